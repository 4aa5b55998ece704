// @brief The hidden-area mask's fragment shader body, included by gbuffer_mask.frag and (FV_GBUFFER_SURFACE defined)
// gbuffer_mask_surface.frag.
#include "gbuffer_interface.h"

#include "gbuffer_outputs.glsl"

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
