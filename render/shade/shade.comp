#version 450
// @brief Direct lighting from the G-buffer (Lambert; point, spot and directional lights; emissive; ambient), into
// linear RGBA32F per eye layer. Either every pixel (tiles interleaved over the dispatch) or a list of pixels.
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_common.glsl"
#include "fv_shade_common.glsl"
#include "shade_interface.h"

layout(local_size_x = FV_SHADE_GROUP_X, local_size_y = FV_SHADE_GROUP_Y, local_size_z = 1) in;
layout(constant_id = 0) const uint SHADE_MODE = FV_SHADE_MODE_ALL;

layout(std140, set = 0, binding = FV_SHADE_BINDING_FRAME) uniform Frame { fv_gpu_frame frame; };
layout(std430, set = 0, binding = FV_SHADE_BINDING_LIGHTS) readonly buffer Lights { fv_gpu_light lights[]; };
layout(std430, set = 0, binding = FV_SHADE_BINDING_MATERIALS) readonly buffer Materials { fv_gpu_material materials[]; };
layout(set = 0, binding = FV_SHADE_BINDING_DEPTH) uniform sampler2DArray g_depth;
layout(set = 0, binding = FV_SHADE_BINDING_NORMAL) uniform sampler2DArray g_normal;
layout(set = 0, binding = FV_SHADE_BINDING_ALBEDO) uniform sampler2DArray g_albedo;
layout(set = 0, binding = FV_SHADE_BINDING_MATERIAL) uniform usampler2DArray g_material;
layout(set = 0, binding = FV_SHADE_BINDING_COLOR, rgba32f) uniform writeonly image2DArray out_color;
layout(std430, set = 0, binding = FV_SHADE_BINDING_PIXELS) readonly buffer Pixels {
    uint count;
    uint pad0, pad1, pad2;
    uint pixels[];
} list;
layout(push_constant) uniform Push { fv_shade_push pc; };

// Shade one pixel of one eye: reconstruct the world position from depth at the pixel centre, then light it.
void shade_pixel(uvec3 p)
{
    uint w = frame.counts.y, h = frame.counts.z;
    if (p.x >= w || p.y >= h || p.z > 1u) return;
    ivec3 c = ivec3(p);
    uint id = texelFetch(g_material, c, 0).r;
    vec3 color = vec3(0.0);
    if (id != 0u) {
        uint mat = min(id - 1u, uint(materials.length()) - 1u);
        float depth = texelFetch(g_depth, c, 0).r;
        vec2 ndc = (vec2(p.xy) + 0.5) / vec2(w, h) * 2.0 - 1.0;
        vec4 wp = frame.inv_view_proj[p.z] * vec4(ndc, depth, 1.0);
        vec3 pos = wp.xyz / (abs(wp.w) > 1e-30 ? wp.w : 1e-30);
        vec3 n = fv_oct_decode(texelFetch(g_normal, c, 0).rg);
        vec3 albedo = texelFetch(g_albedo, c, 0).rgb;
        vec3 irradiance = vec3(0.0);
        uint nl = min(frame.counts.x, uint(lights.length()));
        for (uint i = 0u; i < nl; i++) irradiance += fv_light_irradiance(lights[i], pos, n);
        color = fv_shade_combine(albedo, irradiance, materials[mat].emissive.rgb, frame.ambient.rgb);
        // Keep the output finite whatever the inputs.
        if (any(isnan(color))) color = vec3(0.0);
        color = clamp(color, vec3(0.0), vec3(1e30));
    }
    imageStore(out_color, c, vec4(color, 1.0));
}

void main()
{
    uint group = gl_WorkGroupID.x + gl_WorkGroupID.y * (SHADE_MODE == FV_SHADE_MODE_LIST ? FV_SHADE_LIST_GROUPS_X : pc.groups_x);
    if (SHADE_MODE == FV_SHADE_MODE_LIST) {
        uint i = group * FV_SHADE_GROUP_SIZE + gl_LocalInvocationIndex;
        if (i >= list.count || i >= uint(list.pixels.length())) return;
        shade_pixel(fv_pixel_unpack(list.pixels[i]));
        return;
    }
    uint stripe = group % FV_SHADE_STRIPES;
    uint tile = stripe * pc.tiles_per_stripe + group / FV_SHADE_STRIPES;
    if (group / FV_SHADE_STRIPES >= pc.tiles_per_stripe || tile >= pc.tile_count) return;
    uint per_eye = pc.tiles_x * pc.tiles_y;
    uint layer = tile / per_eye;
    uint t = tile % per_eye;
    uvec2 origin = uvec2(t % pc.tiles_x, t / pc.tiles_x) * uvec2(FV_SHADE_GROUP_X, FV_SHADE_GROUP_Y);
    shade_pixel(uvec3(origin + gl_LocalInvocationID.xy, layer));
}
