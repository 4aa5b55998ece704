#version 450
// @brief Debug views of the frame's data, written over the linear colour (FV_GPU_DEBUG_VIEW_*): the G-buffer's
// normal (n * 0.5 + 0.5), albedo or depth; direct light only, light 0's visibility or which of its shadow maps holds
// the pixel, through the same shading function as the colour; or the frame constants' predicted gaze (red:
// closeness of each pixel's ray to the gaze ray; green: pupil diameter mm / 10; blue: 1 when the gaze is valid).
// Black where nothing was drawn (depth: 1).
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fv_shade_inputs_interface.h"
#include "fv_common.glsl"
#include "debug_interface.h"

layout(local_size_x = FV_DEBUG_GROUP_X, local_size_y = FV_DEBUG_GROUP_Y, local_size_z = 1) in;
layout(constant_id = 0) const uint VIEW = FV_GPU_DEBUG_VIEW_NORMAL;

FV_SCENE_SET_DECLARE
FV_SHADE_INPUTS_DECLARE
#define FV_GBUFFER_SET FV_DEBUG_SET
#define FV_GBUFFER_BINDING_DEPTH FV_DEBUG_BINDING_DEPTH
#define FV_GBUFFER_BINDING_NORMAL FV_DEBUG_BINDING_NORMAL
#define FV_GBUFFER_BINDING_ALBEDO FV_DEBUG_BINDING_ALBEDO
#define FV_GBUFFER_BINDING_MATERIAL FV_DEBUG_BINDING_MATERIAL
#include "fv_gbuffer_decode.glsl"
layout(set = FV_DEBUG_SET, binding = FV_DEBUG_BINDING_COLOR, rgba32f) uniform writeonly image2DArray out_color;
#include "fv_shade_common.glsl"

// A colour per shadow map (split) index.
vec3 map_colour(int m)
{
    const vec3 c[8] = vec3[8](vec3(1, 0.2, 0.2), vec3(0.2, 1, 0.2), vec3(0.25, 0.4, 1), vec3(1, 1, 0.2),
                              vec3(1, 0.2, 1), vec3(0.2, 1, 1), vec3(1, 0.6, 0.2), vec3(0.7, 0.7, 0.7));
    return c[uint(m) % 8u];
}

// The pixel's ray in the eye's view space (unit).
vec3 pixel_ray(uvec3 p)
{
    vec4 t = frame.eye_tan[p.z];
    vec2 uv = (vec2(p.xy) + 0.5) / vec2(frame.counts.y, frame.counts.z);
    return normalize(vec3(mix(t.x, t.y, uv.x), mix(t.z, t.w, uv.y), -1.0));
}

void main()
{
    uvec3 p = gl_GlobalInvocationID;
    if (p.x >= frame.counts.y || p.y >= frame.counts.z || p.z > 1u) return;
    vec3 c = vec3(0.0);
    if (VIEW == FV_GPU_DEBUG_VIEW_GAZE) {
        vec4 g = frame.gaze_dir[p.z];
        vec3 dir = g.w > 0.5 ? g.xyz : vec3(0.0, 0.0, -1.0);
        // atan2 of |cross| and dot keeps the angle exact near 0, where acos of a dot product loses it.
        vec3 r = pixel_ray(p);
        float a = atan(length(cross(r, dir)), dot(r, dir));
        float s = max(float(FV_DEBUG_GAZE_SIGMA_MIN_RAD), frame.gaze_info[p.z].x);
        c = vec3(exp(-(a * a) / (2.0 * s * s)), frame.gaze_info[p.z].y / 10.0, g.w > 0.5 ? 1.0 : 0.0);
    } else {
        fv_surface s = fv_gbuffer_surface(p);
        if (VIEW == FV_GPU_DEBUG_VIEW_CLUSTERS) {
            c = fv_gi_clusters_colour((vec2(p.xy) + 0.5) / vec2(frame.counts.y, frame.counts.z));
        } else if (VIEW == FV_GPU_DEBUG_VIEW_DEPTH) {
            c = vec3(s.depth);
        } else if (!s.hit) {
            c = vec3(0.0);
        } else if (VIEW == FV_GPU_DEBUG_VIEW_ALBEDO) {
            c = s.albedo;
        } else if (VIEW == FV_GPU_DEBUG_VIEW_DIRECT) {
            c = fv_brdf_lambert(s.albedo) * fv_shade_direct_irradiance(s);
        } else if (VIEW == FV_GPU_DEBUG_VIEW_SHADOW) {
            c = vec3(frame.counts.x > 0u ? fv_hook_visibility(0u, s) : 1.0);
        } else if (VIEW == FV_GPU_DEBUG_VIEW_GI) {
            c = fv_brdf_lambert(s.albedo) * fv_gi_indirect(s); // at the frame's gather rate (gi.rate)
        } else if (VIEW == FV_GPU_DEBUG_VIEW_SSS) {
            c = fv_hook_subsurface_radiance(s); // the subsurface term alone (render/sss)
        } else if (VIEW == FV_GPU_DEBUG_VIEW_CASCADE) {
            uint split;
            int m = fv_shadow_map_of(0u, s, split);
            c = m < 0 ? vec3(0.0) : map_colour(int(split));
        } else {
            c = s.normal * 0.5 + 0.5;
        }
        if (any(isnan(c))) c = vec3(0.0);
    }
    imageStore(out_color, ivec3(p), vec4(c, 1.0));
}
