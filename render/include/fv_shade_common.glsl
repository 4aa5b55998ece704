// @brief The shading function every pass shares (fv_shade_surface): light evaluation and the BRDF, with named hooks
// for visibility, indirect light and subsurface light (fv_shade_hooks.glsl). Direct lighting (Lambert; point, spot,
// directional), emission and ambient today. Requires fv_gpu.h, fv_common.glsl, the scene set (FV_SCENE_SET_DECLARE)
// and fv_gbuffer_decode.glsl. The CPU reference in tests/render/test_render.c mirrors these formulas.
#ifndef FV_SHADE_COMMON_GLSL
#define FV_SHADE_COMMON_GLSL

#include "fv_shade_hooks.glsl"

// Irradiance (per channel, W/m^2) that one light delivers to a surface point `pos` with unit normal `n`:
//   point/spot: E = I * falloff * max(n.l, 0) / d^2   (inverse square; d clamped to 1e-4 m so E stays finite)
//   spot falloff: smoothstep between the outer cone (0) and the inner cone (1) on cos(angle to the axis)
//   range window (glTF KHR_lights_punctual): (clamp(1 - (d/range)^4, 0, 1))^2 when range > 0
//   directional: E = E0 * max(n.l, 0)
vec3 fv_light_irradiance(fv_gpu_light L, vec3 pos, vec3 n)
{
    uint type = uint(L.direction_type.w + 0.5);
    vec3 dir = L.direction_type.xyz;
    if (type == FV_GPU_LIGHT_DIRECTIONAL) {
        return L.intensity.rgb * max(dot(n, -dir), 0.0);
    }
    vec3 to_light = L.position_range.xyz - pos;
    float d2 = max(dot(to_light, to_light), 1e-8);
    float d = sqrt(d2);
    vec3 l = to_light / d;
    float cos_surface = max(dot(n, l), 0.0);
    float falloff = 1.0;
    if (type == FV_GPU_LIGHT_SPOT) {
        float cos_axis = dot(-l, dir);
        float cos_inner = L.cone.x, cos_outer = L.cone.y;
        float t = clamp((cos_axis - cos_outer) / max(cos_inner - cos_outer, 1e-6), 0.0, 1.0);
        falloff = t * t * (3.0 - 2.0 * t);
    }
    float range = L.position_range.w;
    if (range > 0.0) {
        float q = d / range;
        float w = clamp(1.0 - q * q * q * q, 0.0, 1.0);
        falloff *= w * w;
    }
    return L.intensity.rgb * (falloff * cos_surface / d2);
}

// Lambertian BRDF: albedo / pi.
vec3 fv_brdf_lambert(vec3 albedo)
{
    return albedo * (1.0 / FV_PI);
}

// Outgoing radiance for a given summed irradiance, emitted radiance and ambient radiance.
vec3 fv_shade_combine(vec3 albedo, vec3 irradiance, vec3 emissive, vec3 ambient)
{
    return fv_brdf_lambert(albedo) * irradiance + emissive + albedo * ambient;
}

// Outgoing radiance of a decoded surface toward the eye: every light's irradiance times its visibility, the indirect
// irradiance, through the Lambertian BRDF; plus emission, ambient and subsurface light. Finite for any input.
// Direct irradiance at a decoded surface: every light's irradiance times its visibility (W/m^2 per channel).
vec3 fv_shade_direct_irradiance(fv_surface s)
{
    vec3 irradiance = vec3(0.0);
    uint nl = min(frame.counts.x, uint(lights.length()));
    for (uint i = 0u; i < nl; i++) irradiance += fv_hook_visibility(i, s) * fv_light_irradiance(lights[i], s.pos_world, s.normal);
    return irradiance;
}

vec3 fv_shade_surface(fv_surface s)
{
    if (!s.hit) return vec3(0.0);
    vec3 irradiance = fv_shade_direct_irradiance(s);
    irradiance += fv_hook_indirect_irradiance(s);
    vec3 color = fv_shade_combine(s.albedo, irradiance, materials[s.material].emissive.rgb, frame.ambient.rgb);
    color += fv_hook_subsurface_radiance(s);
    // Keep the output finite whatever the inputs.
    if (any(isnan(color))) color = vec3(0.0);
    return clamp(color, vec3(0.0), vec3(1e30));
}

#endif
