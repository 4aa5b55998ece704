#version 450
// @brief Reflective shadow map, fragment stage (Dachsbacher & Stamminger 2005; Ki & Oh 2007): per texel the flux
// the surface reflects, its world position and depth, its normal (facing the light) and the radius of the disk the
// texel covers on it. The incident power is the light's power through the texel's own solid angle (spot) or area
// (directional), so the RSM's total is the power falling on what the light sees, whatever its size.
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_common.glsl"
#include "fv_scene_set.h"
#include "gi_interface.h"

FV_SCENE_SET_DECLARE
layout(set = FV_SCENE_TEXTURE_SET, binding = FV_SCENE_BINDING_BASE_COLOR) uniform sampler2D base_color_tex;
layout(push_constant) uniform Push { fv_gi_rsm_push pc; };

layout(location = 0) in vec3 v_pos_world;
layout(location = 1) in vec3 v_normal_world;
layout(location = 2) in vec2 v_texcoord;

layout(location = FV_GI_RSM_OUT_FLUX) out vec4 out_flux;
layout(location = FV_GI_RSM_OUT_POS) out vec4 out_pos;
layout(location = FV_GI_RSM_OUT_NORMAL) out vec4 out_normal;

void main()
{
    fv_gpu_light L = lights[pc.ids.z];
    float N = max(pc.params.y, 1.0);
    vec3 n = v_normal_world;
    float len2 = dot(n, n);
    n = len2 > 1e-30 ? n * inversesqrt(len2) : vec3(0.0, 1.0, 0.0);
    vec3 dir;          // unit, from the light to the surface
    float power_share; // solid angle (spot, sr) or area across the beam (directional, m^2) of this texel
    float dist2;       // for the texel's area on the surface
    float depth;
    float window = 1.0;
    if (pc.ids.w == FV_GI_KIND_SPOT) {
        vec3 w = v_pos_world - L.position_range.xyz;
        dist2 = max(dot(w, w), 1e-12);
        float d = sqrt(dist2);
        dir = w / d;
        // The texel's solid angle on a perspective map of half-angle tangent T: (2T/N)^2 / (1 + tx^2 + ty^2)^(3/2)
        // at the texel centre's tangents (tx, ty).
        float T = pc.params.x;
        vec2 t = ((floor(gl_FragCoord.xy) + 0.5) / N * 2.0 - 1.0) * T;
        float q = 1.0 + dot(t, t);
        power_share = (2.0 * T / N) * (2.0 * T / N) / (q * sqrt(q));
        // the same cone and range window as direct light (fv_light_irradiance)
        float cos_axis = dot(dir, L.direction_type.xyz);
        float s = clamp((cos_axis - L.cone.y) / max(L.cone.x - L.cone.y, 1e-6), 0.0, 1.0);
        window = s * s * (3.0 - 2.0 * s);
        float range = L.position_range.w;
        if (range > 0.0) {
            float r4 = (d / range) * (d / range) * (d / range) * (d / range);
            float rw = clamp(1.0 - r4, 0.0, 1.0);
            window *= rw * rw;
        }
        depth = d / max(pc.params.z, 1e-6);
    } else {
        dir = L.direction_type.xyz;
        float texel = 2.0 * pc.params.x / N;
        power_share = texel * texel;
        dist2 = 1.0;
        depth = dot(v_pos_world - pc.origin.xyz, dir) / max(pc.params.z, 1e-6);
    }
    if (dot(n, dir) > 0.0) n = -n; // two-sided: the side the light sees
    float cos_i = max(-dot(n, dir), 0.02); // grazing texels cover at most 50x their beam cross-section
    uint material = draws[pc.ids.x].info.x;
    vec3 albedo = clamp((materials[material].base_color * texture(base_color_tex, v_texcoord)).rgb, 0.0, 1.0);
    vec3 incident = max(L.intensity.rgb, vec3(0.0)) * (window * power_share);
    float area = power_share * dist2 / cos_i;
    out_flux = vec4(albedo * incident, dot(incident, vec3(0.2126, 0.7152, 0.0722)));
    out_pos = vec4(v_pos_world, depth);
    out_normal = vec4(n, max(sqrt(area / FV_PI), 1e-5));
}
