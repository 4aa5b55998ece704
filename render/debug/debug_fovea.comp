#version 450
// @brief Debug views of foveation (FV_GPU_DEBUG_VIEW_SAMPLES / _PROB / _VORONOI) over the linear colour (voronoi:
// each pixel's Voronoi cell, i.e. the sample it was filled from, as a hashed colour; samples white): the sample mask
// (r = g = 1 where the pixel was shaded, 0.4 where temporal reuse took it from the history; b = 1 at the point where
// the predicted gaze pierces the image and on a ring of its uncertainty's radius, FV_DEBUG_GAZE_RING_PX at least) or the sampling probability p (grey), from the fovea pass's "fovea mask" / "fovea prob".
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "debug_interface.h"
#include "fv_sample_mask_interface.h"

layout(local_size_x = FV_DEBUG_GROUP_X, local_size_y = FV_DEBUG_GROUP_Y, local_size_z = 1) in;
layout(constant_id = 0) const uint VIEW = FV_GPU_DEBUG_VIEW_SAMPLES;

FV_SCENE_SET_DECLARE
layout(set = FV_DEBUG_FOVEA_SET, binding = FV_DEBUG_FOVEA_BINDING_PROB, r32f) uniform readonly image2DArray prob_img;
layout(set = FV_DEBUG_FOVEA_SET, binding = FV_DEBUG_FOVEA_BINDING_MASK, r32ui) uniform readonly uimage2DArray mask_img;
layout(set = FV_DEBUG_FOVEA_SET, binding = FV_DEBUG_FOVEA_BINDING_COLOR, rgba32f) uniform image2DArray out_color;
layout(set = FV_DEBUG_FOVEA_SET, binding = FV_DEBUG_FOVEA_BINDING_VORONOI, r32ui) uniform readonly uimage2DArray voronoi_img;

// A colour per seed (an integer hash), so neighbouring Voronoi cells differ.
vec3 cell_colour(uint s)
{
    uint h = s * 0x9e3779b9u;
    h ^= h >> 15;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    return vec3(float(h & 255u), float((h >> 8) & 255u), float((h >> 16) & 255u)) / 255.0 * 0.8 + 0.2;
}

void main()
{
    uvec3 p = gl_GlobalInvocationID;
    if (p.x >= frame.counts.y || p.y >= frame.counts.z || p.z > 1u) return;
    vec3 c;
    if (VIEW == FV_GPU_DEBUG_VIEW_PROB) {
        c = vec3(imageLoad(prob_img, ivec3(p)).x);
    } else if (VIEW == FV_GPU_DEBUG_VIEW_VORONOI) {
        // the cell of the sample each pixel was filled from, over the reconstructed colour; samples white
        uint s = imageLoad(voronoi_img, ivec3(p)).x;
        bool self = s == (p.x | (p.y << 16));
        vec3 shade = imageLoad(out_color, ivec3(p)).rgb;
        c = s == 0xffffffffu ? vec3(0.0) : self ? vec3(1.0) : mix(cell_colour(s), shade / (1.0 + shade), 0.35);
    } else {
        // shaded (white), interpolated by interp_fill (light grey), reused from the history by temporal reuse (grey),
        // reconstructed (black): the sample mask's values (fv_sample_mask_interface.h)
        uint mv = imageLoad(mask_img, ivec3(p)).x;
        float m = mv == FV_SAMPLE_MASK_SHADED ? 1.0 : mv == FV_SAMPLE_MASK_INTERPOLATED ? 0.7
                : mv == FV_SAMPLE_MASK_REUSED ? 0.4 : 0.0;
        vec4 g = frame.gaze_dir[p.z];
        vec3 d = g.w > 0.5 ? g.xyz : vec3(0.0, 0.0, -1.0);
        float ring = 0.0;
        if (d.z < 0.0) {
            vec4 t = frame.eye_tan[p.z];
            vec2 uv = vec2((d.x / -d.z - t.x) / (t.y - t.x), (d.y / -d.z - t.z) / (t.w - t.z));
            vec2 at = uv * vec2(frame.counts.y, frame.counts.z) - 0.5;
            float r = length(vec2(p.xy) - at);
            // the gaze point, and its uncertainty as a ring (at least FV_DEBUG_GAZE_RING_PX across)
            vec2 dt = abs(vec2(t.y - t.x, t.w - t.z)) / vec2(frame.counts.y, frame.counts.z);
            float u = clamp(frame.gaze_info[p.z].x, 0.0, 1.5);
            float u_px = g.w > 0.5 ? tan(u) / max(min(dt.x, dt.y), 1e-9) : 0.0;
            float ring_px = min(max(float(FV_DEBUG_GAZE_RING_PX), u_px), 1e5);
            ring = abs(r - ring_px) <= 0.75 || r <= 1.5 ? 1.0 : 0.0;
        }
        c = vec3(m, m, ring);
    }
    imageStore(out_color, ivec3(p), vec4(c, 1.0));
}
