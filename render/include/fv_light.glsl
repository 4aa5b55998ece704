// @brief One light's irradiance at a point (fv_light_irradiance), shared by the shading function (fv_shade_common.glsl)
// and passes that light surfaces from the light's side (render/sss's light-view maps). Requires fv_gpu.h.
#ifndef FV_LIGHT_GLSL
#define FV_LIGHT_GLSL

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

#endif
