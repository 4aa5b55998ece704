#version 450
// @brief G-buffer fragment shader: octahedral normal (facing the eye), albedo (factor x base colour texture),
// material id + 1, motion vector (current uv - previous uv, from this and the previous frame's matrices), and for
// foveation the surface target (gbuffer_interface.h FV_GBUFFER_OUT_SURFACE).
#extension GL_EXT_multiview : require
#extension GL_GOOGLE_include_directive : require
#include "gbuffer_body.glsl"
