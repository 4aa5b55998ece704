// @brief Small GLSL helpers shared by passes: octahedral normal encoding, sRGB encoding, pixel unpacking.
#ifndef FV_COMMON_GLSL
#define FV_COMMON_GLSL

const float FV_PI = 3.14159265358979323846;

// Octahedral encoding of a unit vector into [-1,1]^2 (Cigolle et al. 2014, "A Survey of Efficient
// Representations for Independent Unit Vectors", sec. 3.1).
vec2 fv_oct_wrap(vec2 v)
{
    return (1.0 - abs(v.yx)) * vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
}

vec2 fv_oct_encode(vec3 n)
{
    n /= max(abs(n.x) + abs(n.y) + abs(n.z), 1e-20);
    return n.z >= 0.0 ? n.xy : fv_oct_wrap(n.xy);
}

vec3 fv_oct_decode(vec2 e)
{
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = fv_oct_wrap(n.xy);
    float len2 = dot(n, n);
    return len2 > 1e-30 ? n * inversesqrt(len2) : vec3(0.0, 0.0, 1.0);
}

// Linear -> sRGB transfer (IEC 61966-2-1).
vec3 fv_srgb_encode(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    vec3 lo = c * 12.92;
    vec3 hi = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
    return mix(lo, hi, greaterThan(c, vec3(0.0031308)));
}

// Inverse of FV_GPU_PIXEL_PACK: (x, y, layer).
uvec3 fv_pixel_unpack(uint p)
{
    return uvec3(p & 0x7fffu, (p >> 15) & 0x7fffu, p >> 30);
}

#endif
