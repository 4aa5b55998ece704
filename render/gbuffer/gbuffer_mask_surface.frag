#version 450
// @brief Hidden-area mask with the surface target (gbuffer_mask.frag without it): the G-buffer's cleared values
// (material 0 = nothing drawn), so later passes skip the pixel
// as they skip the background.
#extension GL_GOOGLE_include_directive : require
#define FV_GBUFFER_SURFACE 1
#include "gbuffer_mask_body.glsl"
