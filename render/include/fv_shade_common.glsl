// @brief The shading function every pass shares (fv_shade_surface): light evaluation and the BRDF, with named hooks
// for visibility, indirect light and subsurface light (fv_shade_hooks.glsl). Direct lighting (Lambert; point, spot,
// directional), emission and ambient today. Requires fv_gpu.h, fv_common.glsl, the scene set (FV_SCENE_SET_DECLARE)
// and fv_gbuffer_decode.glsl. The CPU reference in tests/render/test_render.c mirrors these formulas.
#ifndef FV_SHADE_COMMON_GLSL
#define FV_SHADE_COMMON_GLSL

#include "fv_shade_hooks.glsl"

#include "fv_light.glsl"

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
    // Translucent with SSS on: the dipole carries the direct light (fv_hook_subsurface_radiance); smooth indirect
    // light still enters through the diffuse term.
    vec3 irradiance = fv_hook_subsurface_replaces_diffuse(s) ? vec3(0.0) : fv_shade_direct_irradiance(s);
    irradiance += fv_hook_indirect_irradiance(s);
    vec3 color = fv_shade_combine(s.albedo, irradiance, materials[s.material].emissive.rgb, frame.ambient.rgb);
    color += fv_hook_subsurface_radiance(s);
    // Keep the output finite whatever the inputs.
    if (any(isnan(color))) color = vec3(0.0);
    return clamp(color, vec3(0.0), vec3(1e30));
}

#endif
