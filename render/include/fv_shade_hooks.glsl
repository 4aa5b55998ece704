// @brief The named places in the shared shading function where later techniques plug in. Each hook has a neutral
// body here (what fovea computes without that technique); the pass that brings the technique replaces that body
// with a lookup into the images it produced (bound in a shared set the renderer hands to every shading pass), so
// full-resolution, listed-pixel and foveated shading all get it at once. Requires fv_gbuffer_decode.glsl.
#ifndef FV_SHADE_HOOKS_GLSL
#define FV_SHADE_HOOKS_GLSL

// Visibility of light `light` from the surface, in [0, 1]: its shadow map (render/shadow: parallel-split shadow
// maps for directional lights, Zhang et al. 2006; one perspective map for spot lights), the split that holds the
// pixel's view depth, a depth compare over (2r+1)^2 texels (r = 0: one tap). 1 where the light has no map or the
// point lies outside it. Requires the shading inputs set (FV_SHADE_INPUTS_DECLARE, fv_shade_inputs_interface.h).
// The shadow map of light `light` that holds the surface (its split for cascades), or -1 when the light has none.
layout(constant_id = FV_SPEC_ID_SHADOWS) const bool FV_SPEC_SHADOWS = true;

int fv_shadow_map_of(uint light, fv_surface s, out uint split)
{
    split = 0u;
    if (!FV_SPEC_SHADOWS) return -1; // specialised without shadows: every light is unoccluded, as with no maps
    if (light >= min(shadow.counts.x, uint(FV_SHADOW_MAX_LIGHTS))) return -1;
    fv_gpu_shadow_light L = shadow.light[light];
    if (L.info.x == FV_SHADOW_KIND_NONE) return -1;
    uint eye = min(s.pixel.z, 1u);
    if (L.info.x == FV_SHADOW_KIND_CUBE) {
        // The face the surface lies in: the major axis of surface - light (+x -x +y -y +z -z).
        vec3 v = s.pos_world - lights[light].position_range.xyz;
        vec3 a = abs(v);
        uint axis = a.x >= a.y && a.x >= a.z ? 0u : (a.y >= a.z ? 1u : 2u);
        split = axis * 2u + (v[axis] < 0.0 ? 1u : 0u);
        return int(L.info.y + split);
    }
    if (L.info.x == FV_SHADOW_KIND_CASCADES) {
        float d = (frame.view_proj[eye] * vec4(s.pos_world, 1.0)).w; // clip w = view depth for a perspective eye
        uint n = min(L.info.z, uint(FV_SHADOW_MAX_SPLITS));
        while (split + 1u < n && d > L.split_far[split / 4u][split % 4u]) split++;
    }
    uint map = L.info.y + eye * L.info.w + split;
    return map < min(shadow.counts.y, uint(FV_SHADOW_MAX_MAPS)) ? int(map) : -1;
}

float fv_hook_visibility(uint light, fv_surface s)
{
    uint split;
    int m = fv_shadow_map_of(light, s, split);
    if (m < 0) return 1.0;
    uint map = uint(m);
    fv_gpu_shadow_light L = shadow.light[light];
    // Normal offset: look the receiver up 1.5 texels off its surface, so a surface never shadows itself through
    // the map's finite resolution (the casters' slope-scaled depth bias does the rest).
    float texel = L.info.x == FV_SHADOW_KIND_CASCADES ? L.split_texel[split / 4u][split % 4u]
                                                       : L.params.z * length(s.pos_world - lights[light].position_range.xyz);
    vec4 c = shadow.map_view_proj[map] * vec4(s.pos_world + s.normal * (1.5 * texel), 1.0);
    if (!(c.w > 1e-20)) return 1.0; // behind a spot light
    vec3 p = c.xyz / c.w;
    vec2 uv = p.xy * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || p.z > 1.0 || p.z < 0.0) return 1.0;
    int res = max(int(shadow.counts.z), 1);
    ivec2 t = clamp(ivec2(uv * float(res)), ivec2(0), ivec2(res - 1));
    int r = clamp(int(L.params.x + 0.5), 0, 2);
    float lit = 0.0;
    for (int dy = -r; dy <= r; dy++)
        for (int dx = -r; dx <= r; dx++) {
            ivec2 q = clamp(t + ivec2(dx, dy), ivec2(0), ivec2(res - 1));
            lit += p.z <= texelFetch(shadow_map, ivec3(q, int(map)), 0).r ? 1.0 : 0.0;
        }
    float side = float(2 * r + 1);
    return lit / (side * side);
}

// Indirect irradiance reaching the surface, W/m^2 per channel (one-bounce GI from the light quad-tree, render/gi:
// fv_gi_gather.glsl). 0 while the GI pass is off (its header is the zero dummy: one load). The clusters it summed
// are noted for the GI stats where the shading pass counts (FV_GI_STATS).
#include "fv_gi_gather.glsl"
vec3 fv_hook_indirect_irradiance(fv_surface s)
{
    uint clusters;
    bool gathered;
    vec3 e = fv_gi_indirect(s, clusters, gathered); // at the frame's gather rate (gi.rate): upsampled or gathered
    if (gathered) fv_gi_stats_note(clusters);
    return e;
}

// Outgoing radiance from light that entered elsewhere below the surface (subsurface scattering, dipole over the
// light hierarchy, render/sss: fv_sss_gather.glsl), W/(m^2 sr) per channel. 0 = opaque, or while the SSS pass is
// off (its header is the zero dummy: one load).
#include "fv_sss_gather.glsl"
vec3 fv_hook_subsurface_radiance(fv_surface s)
{
    uint clusters;
    return fv_sss_radiance(s, clusters);
}

// True where the subsurface term is the surface's diffuse reflection of direct light (a translucent material with
// SSS on): the dipole's Rd already holds the light that leaves near where it entered (Jensen et al. 2001), so the
// shading function adds no Lambertian term for the lights there (smooth indirect light still goes through it).
bool fv_hook_subsurface_replaces_diffuse(fv_surface s)
{
    return fv_sss_active(s);
}

#endif
