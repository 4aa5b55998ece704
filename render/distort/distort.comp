#version 450
// @brief Lens pre-distortion with chromatic aberration (fv_lens.h): each display pixel of an eye is a point of its
// panel viewport; each colour channel looks up the undistorted ray its lens shows there (radial polynomial around
// the lens centre times the channel's scale) in the rendered eye image, bilinearly, black outside it and beyond the
// lens's visible radius. The evaluation mirrors fv_lens_panel_to_tan (runtime/hmd/hmd_lens.c), checked by
// test_render_distort against it.
#extension GL_GOOGLE_include_directive : require
#include "fv_common.glsl"
#include "distort_interface.h"

layout(local_size_x = FV_DISTORT_GROUP_X, local_size_y = FV_DISTORT_GROUP_Y, local_size_z = 1) in;

layout(set = 0, binding = FV_DISTORT_BINDING_SOURCE) uniform sampler2DArray source;
layout(set = 0, binding = FV_DISTORT_BINDING_OUTPUT, rgba8) uniform writeonly image2DArray out_display;
layout(push_constant) uniform Push { fv_distort_push pc; };

void main()
{
    uvec3 p = gl_GlobalInvocationID;
    if (p.x >= pc.width || p.y >= pc.height || p.z > 1u) return;
    uint eye = p.z;
    vec2 uv = (vec2(p.xy) + 0.5) / vec2(pc.width, pc.height);
    vec2 centre = eye == 0u ? pc.centre_m.xy : pc.centre_m.zw;
    vec2 q = uv * pc.geometry.xy - centre; // metres from the lens centre, y down
    float r = length(q) / pc.geometry.z;
    vec3 c = vec3(0.0);
    if (pc.aberration.w <= 0.0 || r <= pc.aberration.w) {
        float d = pc.k.x + r * (pc.k.y + r * (pc.k.z + r * pc.k.w));
        vec4 f = pc.frustum[eye]; // tan left, right, up, down
        for (int ch = 0; ch < 3; ch++) {
            vec2 t = q * (d * pc.aberration[ch] * pc.geometry.w); // tangent x right, y down
            vec2 src = vec2((t.x + f.x) / (f.x + f.y), (t.y + f.z) / (f.z + f.w));
            if (all(greaterThanEqual(src, vec2(0.0))) && all(lessThanEqual(src, vec2(1.0))))
                c[ch] = textureLod(source, vec3(src, float(eye)), 0.0)[ch];
        }
    }
    imageStore(out_display, ivec3(p), vec4(fv_srgb_encode(c), 1.0));
}
