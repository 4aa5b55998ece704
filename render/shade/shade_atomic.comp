#version 450
// @brief The shading pass (shade.glsl) for devices without arithmetic subgroup operations in compute shaders: the GI
// gather's work counted with atomics per pixel.
#extension GL_GOOGLE_include_directive : require
#define FV_GI_STATS FV_GI_STATS_ATOMIC
#include "shade.glsl"
