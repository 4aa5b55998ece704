// @brief The named places in the shared shading function where later techniques plug in. Each hook has a neutral
// body here (what fovea computes without that technique); the pass that brings the technique replaces that body
// with a lookup into the images it produced (bound in a shared set the renderer hands to every shading pass), so
// full-resolution, listed-pixel and foveated shading all get it at once. Requires fv_gbuffer_decode.glsl.
#ifndef FV_SHADE_HOOKS_GLSL
#define FV_SHADE_HOOKS_GLSL

// Visibility of light `light` from the surface, in [0, 1] (shadows: parallel-split shadow maps). 1 = unshadowed.
float fv_hook_visibility(uint light, fv_surface s)
{
    return 1.0;
}

// Indirect irradiance reaching the surface, W/m^2 per channel (one-bounce GI from the light quad-tree). 0 = none.
vec3 fv_hook_indirect_irradiance(fv_surface s)
{
    return vec3(0.0);
}

// Outgoing radiance from light that entered elsewhere below the surface (subsurface scattering, dipole over the
// light hierarchy), W/(m^2 sr) per channel. 0 = opaque.
vec3 fv_hook_subsurface_radiance(fv_surface s)
{
    return vec3(0.0);
}

#endif
