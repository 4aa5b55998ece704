#version 450
// @brief The sampling map and its compaction (papers/README.md section 3; Koskela-style linear MAR): per pixel the
// eccentricity e from the predicted gaze ray, e' = max(0, e - u), w = m e' + w0, p = clamp(1 - (w - w_min) / w_far,
// xi, 1) with w_min = w0 and w_far = m E + w0, E the view's largest eccentricity from its centre (a corner ray);
// per B x B block a sample mask from ranks of a low-discrepancy (R2) pattern turned each frame; then the sampled
// pixels of both eyes as one list by a two-level prefix sum (tiles, then the tile sums) with its dispatch arguments.
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fovea_interface.h"

layout(local_size_x_id = 1, local_size_y = 1, local_size_z = 1) in;
layout(constant_id = 0) const uint STAGE = FV_FOVEA_STAGE_MAP;

FV_SCENE_SET_DECLARE
layout(set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_PROB, r32f) uniform image2DArray prob_img;
layout(set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_MASK, r32ui) uniform uimage2DArray mask_img;
layout(std430, set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_SUMS) buffer Sums { uint sums[]; };
layout(std430, set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_LIST) buffer List {
    uint count;
    uint pad0, pad1, pad2;
    uint pixels[];
} list;
layout(std430, set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_INDIRECT) buffer Indirect { uint args[4]; } ind;
layout(push_constant) uniform Push { fv_fovea_push pc; };

shared uint sh[FV_FOVEA_SCAN_SIZE];

const float RAD_TO_DEG = 57.295779513082323;

float sampling_prob(uvec3 p)
{
    vec4 t = frame.eye_tan[p.z];
    vec2 uv = (vec2(p.xy) + 0.5) / vec2(frame.counts.y, frame.counts.z);
    vec3 r = normalize(vec3(mix(t.x, t.y, uv.x), mix(t.z, t.w, uv.y), -1.0));
    vec4 g = frame.gaze_dir[p.z];
    float glen = length(g.xyz);
    bool valid = g.w > 0.5 && glen > 0.0 && !isnan(glen) && !isinf(glen);
    vec3 d = valid ? g.xyz / glen : vec3(0.0, 0.0, -1.0);
    float u = !valid ? float(FV_FOVEA_LOST_WIDEN_RAD)
                     : ((pc.flags & FV_FOVEA_FLAG_UNCERTAINTY) != 0u ? frame.gaze_info[p.z].x : 0.0);
    if (isnan(u)) u = 3.14159265;
    float e = atan(length(cross(r, d)), dot(r, d)); // exact near 0, unlike acos(dot)
    float ep = max(0.0, e - u);
    vec2 tmax = max(abs(t.xz), abs(t.yw));
    float E = atan(length(tmax));                   // the view's largest eccentricity from its centre
    float w = pc.mar_slope * ep * RAD_TO_DEG + pc.mar_w0_deg;
    float w_far = pc.mar_slope * E * RAD_TO_DEG + pc.mar_w0_deg;
    return clamp(1.0 - (w - pc.mar_w0_deg) / w_far, pc.min_prob, 1.0);
}

// The low-discrepancy value of a pixel of its block (R2 sequence), turned by the frame (golden ratio).
float pattern(uvec2 l)
{
    float phi = fract(float(frame.counts.w & 1023u) * 0.61803398875);
    return fract(0.5 + float(l.x) * 0.75487766625 + float(l.y) * 0.56984029101 + phi);
}

// Sample when the pixel's rank r among its block's n pixels has (r + 0.5) / n < p; rank 0 always (>= 1 per block).
bool sampled(uvec3 p, float prob)
{
    uint B = pc.block;
    uvec2 size = uvec2(frame.counts.y, frame.counts.z);
    uvec2 b0 = (p.xy / B) * B;
    uvec2 bs = min(uvec2(B), size - b0);
    uint n = bs.x * bs.y;
    uvec2 l = p.xy - b0;
    uint me = l.y * bs.x + l.x;
    float mine = pattern(l);
    uint rank = 0u;
    for (uint k = 0u; k < n; k++) {
        float o = pattern(uvec2(k % bs.x, k / bs.x));
        rank += (o < mine || (o == mine && k < me)) ? 1u : 0u;
    }
    return rank == 0u || float(rank) + 0.5 < prob * float(n);
}

// Inclusive scan of v over the workgroup's first `n` threads (all threads call it).
uint scan(uint v, uint n)
{
    uint li = gl_LocalInvocationIndex;
    sh[li] = v;
    barrier();
    for (uint off = 1u; off < n; off <<= 1) {
        uint a = li >= off ? sh[li - off] : 0u;
        barrier();
        sh[li] += a;
        barrier();
    }
    return sh[li];
}

void main()
{
    uint li = gl_LocalInvocationIndex;
    if (STAGE == FV_FOVEA_STAGE_SCAN) {
        uint chunk = (pc.entries + FV_FOVEA_SCAN_SIZE - 1u) / FV_FOVEA_SCAN_SIZE;
        uint begin = min(li * chunk, pc.entries), end = min(begin + chunk, pc.entries);
        uint total = 0u;
        for (uint k = begin; k < end; k++) total += sums[k];
        uint incl = scan(total, FV_FOVEA_SCAN_SIZE);
        uint base = incl - total;
        for (uint k = begin; k < end; k++) {
            uint c = sums[k];
            sums[k] = base;
            base += c;
        }
        if (li == FV_FOVEA_SCAN_SIZE - 1u) {
            list.count = incl;
            uint groups = (incl + FV_GPU_LIST_GROUP_SIZE - 1u) / FV_GPU_LIST_GROUP_SIZE;
            ind.args[0] = groups == 0u ? 0u : min(groups, FV_GPU_LIST_GROUPS_X);
            ind.args[1] = groups == 0u ? 0u : (groups + FV_GPU_LIST_GROUPS_X - 1u) / FV_GPU_LIST_GROUPS_X;
            ind.args[2] = 1u;
            ind.args[3] = 0u;
        }
        return;
    }
    uint g = gl_WorkGroupID.x + gl_WorkGroupID.y * pc.groups_x;
    if (g >= pc.entries) return; // the whole workgroup: barriers stay uniform
    uint tile = (g % FV_FOVEA_STRIPES) * pc.tiles_per_stripe + g / FV_FOVEA_STRIPES;
    uint per_eye = pc.tiles_x * pc.tiles_y;
    uint layer = tile / per_eye, t = tile % per_eye;
    uvec3 p = uvec3(uvec2(t % pc.tiles_x, t / pc.tiles_x) * FV_FOVEA_TILE +
                    uvec2(li % FV_FOVEA_TILE, li / FV_FOVEA_TILE), layer);
    bool inside = tile < pc.tile_count && p.x < frame.counts.y && p.y < frame.counts.z;
    uint v = 0u;
    if (STAGE == FV_FOVEA_STAGE_MAP) {
        if (inside) {
            float prob = sampling_prob(p);
            v = sampled(p, prob) ? 1u : 0u;
            imageStore(prob_img, ivec3(p), vec4(prob));
            imageStore(mask_img, ivec3(p), uvec4(v));
        }
        uint incl = scan(v, FV_FOVEA_TILE_SIZE);
        if (li == FV_FOVEA_TILE_SIZE - 1u) sums[g] = incl;
        return;
    }
    // FV_FOVEA_STAGE_SCATTER
    if (inside) v = imageLoad(mask_img, ivec3(p)).x != 0u ? 1u : 0u;
    uint incl = scan(v, FV_FOVEA_TILE_SIZE);
    if (v != 0u) list.pixels[sums[g] + incl - 1u] = FV_GPU_PIXEL_PACK(p.x, p.y, p.z);
}
