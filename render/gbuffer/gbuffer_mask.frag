#version 450
// @brief Hidden-area mask: the G-buffer's cleared values (material 0 = nothing drawn), so later passes skip the pixel
// as they skip the background.
#extension GL_GOOGLE_include_directive : require
#include "gbuffer_interface.h"

layout(location = FV_GBUFFER_OUT_NORMAL) out vec2 out_normal;
layout(location = FV_GBUFFER_OUT_ALBEDO) out vec4 out_albedo;
layout(location = FV_GBUFFER_OUT_MATERIAL) out uint out_material;
layout(location = FV_GBUFFER_OUT_MOTION) out vec4 out_motion;

void main()
{
    out_normal = vec2(0.0);
    out_albedo = vec4(0.0);
    out_material = 0u;
    out_motion = vec4(0.0);
}
