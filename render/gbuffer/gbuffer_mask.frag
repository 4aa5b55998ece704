#version 450
// @brief Hidden-area mask: the G-buffer's cleared values (material 0 = nothing drawn), so later passes skip the pixel
// as they skip the background.
#extension GL_GOOGLE_include_directive : require
#include "gbuffer_mask_body.glsl"
