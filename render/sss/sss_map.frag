#version 450
// @brief Light-view sample map, fragments: where the map's material is the nearest surface seen from the light, a
// sample of position, the surface area A the texel covers (fv_sss_texel_area), the flux entering the surface
// E A = Ft(eta, wi) I (n.wi) A (fv_light_irradiance through Schlick's transmittance), the depth along the light,
// the normal facing the light with its cosine to the light, and the texel's footprint on the surface
// (fv_sss_texel_footprint: its edges a, b). The map is the fine map (fv_sss_sub_levels below sss.map_size).
// Every other surface writes depth and an empty sample, so it occludes.
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fv_common.glsl"
#include "fv_sss_interface.h"
#include "fv_light.glsl"

FV_SCENE_SET_DECLARE
layout(push_constant) uniform Push { fv_sss_map_push pc; };
layout(location = 0) in vec3 v_pos_world;
layout(location = 1) in vec3 v_normal_world;
layout(location = FV_SSS_OUT_POS) out vec4 out_pos;
layout(location = FV_SSS_OUT_FLUX) out vec4 out_flux;
layout(location = FV_SSS_OUT_NORMAL) out vec4 out_normal;
layout(location = FV_SSS_OUT_EDGE_A) out vec4 out_edge_a;
layout(location = FV_SSS_OUT_EDGE_B) out vec4 out_edge_b;

void main()
{
    out_pos = vec4(0.0);
    out_flux = vec4(0.0);
    out_normal = vec4(0.0);
    out_edge_a = vec4(0.0);
    out_edge_b = vec4(0.0);
    uint material = draws[pc.ids.x].info.x;
    if (material != pc.ids.z || pc.ids.w >= uint(lights.length())) return;
    fv_gpu_light L = lights[pc.ids.w];
    bool directional = uint(L.direction_type.w + 0.5) == FV_GPU_LIGHT_DIRECTIONAL;
    vec3 to_light = directional ? -L.direction_type.xyz : L.position_range.xyz - v_pos_world;
    float tl2 = dot(to_light, to_light);
    if (!(tl2 > 1e-30)) return;
    vec3 l = to_light * inversesqrt(tl2);
    vec3 n = v_normal_world;
    float len2 = dot(n, n);
    n = len2 > 1e-30 ? n * inversesqrt(len2) : l;
    if (dot(n, l) < 0.0) n = -n; // two-sided, as the G-buffer: the side the light sees
    float cos_i = dot(n, l);
    // The texel's surface area (fv_sss_texel_area).
    float c = clamp(cos_i, float(FV_SSS_GPU_MIN_COS), 1.0);
    float area;
    float depth;
    if (pc.view.x > 0.5) {
        vec3 d = v_pos_world - pc.origin.xyz;
        float dist2 = dot(d, d);
        float cos_axis = dot(d, pc.axis.xyz) * inversesqrt(max(dist2, 1e-30));
        float side = 2.0 * pc.view.y / max(pc.axis.w, 1.0);
        area = cos_axis > 0.0 ? side * side * cos_axis * cos_axis * cos_axis * dist2 / c : 0.0;
        depth = sqrt(dist2);
    } else {
        area = pc.view.y * pc.view.y / c;
        depth = dot(v_pos_world - pc.origin.xyz, pc.axis.xyz);
    }
    float ft = fv_sss_fresnel_t(materials[material].sigma_a.w, cos_i);
    vec3 flux = fv_light_irradiance(L, v_pos_world, n) * (ft * area);
    // The footprint (fv_sss_texel_footprint): the texel's sides across the ray (the map's x and y axes, the first
    // two rows of its view-projection), carried along the ray w onto the plane, tilted toward the light where it
    // grazes so that |a x b| = area.
    vec3 axis = pc.axis.xyz;
    vec3 right = fv_sss_unit_across(vec3(pc.view_proj[0][0], pc.view_proj[1][0], pc.view_proj[2][0]), axis);
    vec3 up = fv_sss_unit_across(vec3(pc.view_proj[0][1], pc.view_proj[1][1], pc.view_proj[2][1]), axis);
    up = fv_sss_unit_across(up, right);
    vec3 w = -l;
    float side = pc.view.x > 0.5 ? 2.0 * pc.view.y / max(pc.axis.w, 1.0) * dot(v_pos_world - pc.origin.xyz, axis)
                                 : pc.view.y;
    vec3 nc = n;
    if (cos_i < c) nc = l * c + fv_sss_unit_across(n, l) * sqrt(1.0 - c * c);
    vec3 ex = right * side, ey = up * side;
    vec3 ea = ex + w * (dot(nc, ex) / c), eb = ey + w * (dot(nc, ey) / c);
    if (!(area > 0.0) || !(side > 0.0) || any(isnan(flux)) || any(isinf(flux)) || any(isnan(ea)) || any(isinf(ea)) ||
        any(isnan(eb)) || any(isinf(eb)))
        return;
    out_pos = vec4(v_pos_world, area);
    out_flux = vec4(flux, depth);
    out_normal = vec4(n, cos_i); // the cosine: whether its nominal texel resolves (fv_sss_texel_resolve)
    out_edge_a = vec4(ea, 0.0);
    out_edge_b = vec4(eb, 0.0);
}
