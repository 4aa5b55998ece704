// @brief The hidden-area mask's fragment shader body, included by gbuffer_mask.frag and (FV_GBUFFER_SURFACE defined)
// gbuffer_mask_surface.frag.
#include "gbuffer_interface.h"

layout(location = FV_GBUFFER_OUT_NORMAL) out vec2 out_normal;
layout(location = FV_GBUFFER_OUT_ALBEDO) out vec4 out_albedo;
layout(location = FV_GBUFFER_OUT_MATERIAL) out uint out_material;
layout(location = FV_GBUFFER_OUT_MOTION) out vec2 out_motion;
#ifdef FV_GBUFFER_SURFACE
layout(location = FV_GBUFFER_OUT_SURFACE) out vec4 out_surface;
#endif

void main()
{
    out_normal = vec2(0.0);
    out_albedo = vec4(0.0);
    out_material = 0u;
    out_motion = vec2(0.0);
#ifdef FV_GBUFFER_SURFACE
    out_surface = vec4(0.0);
#endif
}
