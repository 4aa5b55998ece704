// @brief Reading the G-buffer, shared by every pass that reads it: the sampler declarations and fv_gbuffer_surface, which decodes one pixel into an fv_surface (world position reconstructed from depth at the
// pixel centre, unit normal, linear albedo, material). Requires fv_gpu.h, fv_common.glsl and the scene set
// (FV_SCENE_SET_DECLARE, for the frame block and the materials).
#ifndef FV_GBUFFER_DECODE_GLSL
#define FV_GBUFFER_DECODE_GLSL

// What shading needs to know about the surface seen at one pixel of one eye.
struct fv_surface {
    uvec3 pixel;     // x, y, eye layer
    bool hit;        // false: nothing drawn there (the rest is undefined)
    uint material;   // index into materials[]
    float depth;     // Vulkan depth 0..1
    vec3 pos_world;  // metres
    vec3 normal;     // unit, world, facing the eye
    vec3 albedo;     // linear
    vec3 view_dir;   // unit, from the surface to the eye
};

// The samplers, in the set and bindings the including shader names before including this file:
// FV_GBUFFER_SET, FV_GBUFFER_BINDING_DEPTH, _NORMAL, _ALBEDO, _MATERIAL (nearest samplers, layer = eye).
layout(set = FV_GBUFFER_SET, binding = FV_GBUFFER_BINDING_DEPTH) uniform sampler2DArray g_depth;
layout(set = FV_GBUFFER_SET, binding = FV_GBUFFER_BINDING_NORMAL) uniform sampler2DArray g_normal;
layout(set = FV_GBUFFER_SET, binding = FV_GBUFFER_BINDING_ALBEDO) uniform sampler2DArray g_albedo;
layout(set = FV_GBUFFER_SET, binding = FV_GBUFFER_BINDING_MATERIAL) uniform usampler2DArray g_material;

// World position of pixel p (its centre) at depth `depth`, from the eye's inverse view-projection.
vec3 fv_gbuffer_position(uvec3 p, float depth)
{
    uint w = frame.counts.y, h = frame.counts.z;
    vec2 ndc = (vec2(p.xy) + 0.5) / vec2(w, h) * 2.0 - 1.0;
    vec4 wp = frame.inv_view_proj[p.z] * vec4(ndc, depth, 1.0);
    return wp.xyz / (abs(wp.w) > 1e-30 ? wp.w : 1e-30);
}

// Decode pixel p (inside the image: the caller checks) of the G-buffer.
fv_surface fv_gbuffer_surface(uvec3 p)
{
    fv_surface s;
    ivec3 c = ivec3(p);
    s.pixel = p;
    uint id = texelFetch(g_material, c, 0).r;
    s.hit = id != 0u;
    s.material = s.hit ? min(id - 1u, uint(materials.length()) - 1u) : 0u;
    s.depth = texelFetch(g_depth, c, 0).r;
    s.pos_world = fv_gbuffer_position(p, s.depth);
    s.normal = fv_oct_decode(texelFetch(g_normal, c, 0).rg);
    s.albedo = texelFetch(g_albedo, c, 0).rgb;
    vec3 to_eye = frame.eye_pos[min(p.z, 1u)].xyz - s.pos_world;
    float len2 = dot(to_eye, to_eye);
    s.view_dir = len2 > 1e-30 ? to_eye * inversesqrt(len2) : s.normal;
    return s;
}

// What foveation's per-pixel passes read of pixel p (inside the image) in one fetch `m` of the surface target
// (gbuffer_interface.h FV_GBUFFER_OUT_SURFACE): drawn, distance from the eye, world position (on the pixel centre's
// ray; undefined where nothing was drawn), unit normal (the normal target's own value) and motion. One fetch instead
// of four (material, depth, normal, motion): on lavapipe each costs about half a present pass per pixel.
struct fv_gbuffer_fovea_surf {
    bool hit;
    float dist;
    vec3 pos, normal;
    vec2 motion;
};
fv_gbuffer_fovea_surf fv_gbuffer_fovea(uvec3 p, vec4 m)
{
    fv_gbuffer_fovea_surf s;
    s.hit = m.b > 0.0;
    s.dist = m.b;
    vec3 eye = frame.eye_pos[min(p.z, 1u)].xyz;
    vec3 ray = fv_gbuffer_position(p, 0.0) - eye; // towards the pixel's near-plane point
    s.pos = eye + ray * (m.b * inversesqrt(max(dot(ray, ray), 1e-30)));
    s.normal = fv_oct_decode(unpackSnorm2x16(floatBitsToUint(m.a)));
    s.motion = m.rg;
    return s;
}

#endif
