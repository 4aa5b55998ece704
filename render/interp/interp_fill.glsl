// @brief Hierarchical screen-space interpolation's fill after shading, the body shared by interp_fill.comp and
// interp_fill_mark.comp (interp_interface.h): every FILLED pixel gets the bilinear interpolation of its accepted
// node's four corner pixels, which were all shaded; only filled pixels are written and only shaded ones read, so the
// colour is read and written in place. With push.view, `--view interp` instead: each pixel coloured by the level it
// was shaded or filled at. Includers declare nothing of set FV_INTERP_FILL_SET before this file.
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "interp_interface.h"

layout(local_size_x = FV_INTERP_GROUP, local_size_y = FV_INTERP_GROUP, local_size_z = 1) in;

FV_SCENE_SET_DECLARE
layout(set = FV_INTERP_FILL_SET, binding = FV_INTERP_FILL_BINDING_LEVEL, r32ui) uniform readonly uimage2DArray level_img;
layout(set = FV_INTERP_FILL_SET, binding = FV_INTERP_FILL_BINDING_COLOR, rgba32f) uniform image2DArray color;
layout(push_constant) uniform Push { fv_interp_fill_push pc; };

// The view's colour of a level (0 .. MAX): grey at 0, then blue, cyan, green, yellow, orange, red, magenta.
vec3 level_colour(uint k)
{
    const vec3 c[8] = vec3[8](vec3(0.25), vec3(0.1, 0.2, 1.0), vec3(0.0, 0.8, 1.0), vec3(0.1, 0.9, 0.1),
                              vec3(1.0, 0.9, 0.0), vec3(1.0, 0.5, 0.0), vec3(1.0, 0.1, 0.1), vec3(1.0, 0.2, 1.0));
    return c[min(k, 7u)];
}

// Fill (or draw the view at) pixel p; returns its code, FV_INTERP_FILL_OUTSIDE off the image.
const uint FV_INTERP_FILL_OUTSIDE = 0xffffffffu;
uint interp_fill_pixel(uvec3 p)
{
    uint w = frame.counts.y, h = frame.counts.z;
    if (p.x >= w || p.y >= h || p.z > 1u) return FV_INTERP_FILL_OUTSIDE;
    uint code = imageLoad(level_img, ivec3(p)).x;
    uint k = code & FV_INTERP_CODE_LEVEL_MASK;
    if (pc.view == FV_INTERP_FILL_VIEW) {
        // shaded pixels full brightness, filled ones darker, pixels left to another pass black
        vec3 c = level_colour(k);
        c *= (code & FV_INTERP_CODE_SHADED) != 0u ? 1.0 : (code & FV_INTERP_CODE_FILLED) != 0u ? 0.45 : 0.0;
        imageStore(color, ivec3(p), vec4(c, 1.0));
        return code;
    }
    if ((code & FV_INTERP_CODE_FILLED) == 0u || k == 0u || k > FV_INTERP_MAX_LEVEL) return code;
    uint s = 1u << k;
    uvec2 lo = (p.xy >> k) << k;
    uvec2 hi = min(lo + s, uvec2(w, h) - 1u);
    // a filled pixel is neither on the node's grid nor on the last row or column, so lo < p < hi on some axis and
    // lo <= p < hi on both: the weights are finite
    vec2 t = vec2(p.xy - lo) / vec2(max(hi - lo, uvec2(1u)));
    vec4 c00 = imageLoad(color, ivec3(lo.x, lo.y, p.z)), c10 = imageLoad(color, ivec3(hi.x, lo.y, p.z));
    vec4 c01 = imageLoad(color, ivec3(lo.x, hi.y, p.z)), c11 = imageLoad(color, ivec3(hi.x, hi.y, p.z));
    vec4 c = mix(mix(c00, c10, t.x), mix(c01, c11, t.x), t.y);
    imageStore(color, ivec3(p), vec4(c.rgb, 1.0));
    return code;
}
