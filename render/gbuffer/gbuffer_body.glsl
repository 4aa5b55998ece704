// @brief The G-buffer fragment shader's body, included by gbuffer.frag and (FV_GBUFFER_SURFACE defined: the surface
// target too, while foveation runs) gbuffer_surface.frag.
#include "fv_gpu.h"
#include "fv_common.glsl"
#include "fv_scene_set.h"
#include "gbuffer_interface.h"

FV_SCENE_SET_DECLARE
layout(set = FV_SCENE_TEXTURE_SET, binding = FV_SCENE_BINDING_BASE_COLOR) uniform sampler2D base_color_tex;
layout(push_constant) uniform Push { uint draw_index; uint eye; } pc;
// 1: both eyes in one multiview pass (eye = gl_ViewIndex); 0: one pass per eye (eye from the push constant).
layout(constant_id = 0) const uint USE_MULTIVIEW = 1u;

layout(location = 0) in vec3 v_pos_world;
layout(location = 1) in vec3 v_normal_world;
layout(location = 2) in vec2 v_texcoord;
layout(location = 3) in vec4 v_clip;
layout(location = 4) in vec4 v_prev_clip;

#include "gbuffer_outputs.glsl"

void main()
{
    uint eye = USE_MULTIVIEW != 0u ? gl_ViewIndex : pc.eye;
    vec3 n = v_normal_world;
    float len2 = dot(n, n);
    n = len2 > 1e-30 ? n * inversesqrt(len2) : vec3(0.0, 1.0, 0.0);
    // Two-sided: file winding and normals are not trusted; the normal faces the eye that sees the surface.
    if (dot(n, frame.eye_pos[eye].xyz - v_pos_world) < 0.0) n = -n;
    vec2 oct = fv_oct_encode(n);
    out_normal = oct;

    uint material = draws[pc.draw_index].info.x;
    vec4 albedo = materials[material].base_color * texture(base_color_tex, v_texcoord);
    out_albedo = vec4(clamp(albedo.rgb, 0.0, 1.0), 1.0);
    out_material = min(material + 1u, 65535u);

    // Motion in uv units: ndc/2. Guard w so a vertex at the eye plane yields 0, not Inf.
    vec2 cur = v_clip.xy / (abs(v_clip.w) > 1e-20 ? v_clip.w : 1e-20);
    vec2 prev = v_prev_clip.xy / (abs(v_prev_clip.w) > 1e-20 ? v_prev_clip.w : 1e-20);
    vec2 m = (cur - prev) * 0.5;
    out_motion = clamp(m, vec2(-65000.0), vec2(65000.0));
#ifdef FV_GBUFFER_SURFACE
    float dist = length(v_pos_world - frame.eye_pos[eye].xyz);
    // drawn: a distance above 0 (0 is the cleared "nothing drawn")
    out_surface = vec4(out_motion, isnan(dist) || isinf(dist) ? 1e-20 : max(dist, 1e-20),
                       uintBitsToFloat(packSnorm2x16(oct)));
#endif
}
