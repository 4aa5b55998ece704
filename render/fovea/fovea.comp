#version 450
// @brief The sampling map (papers/README.md section 3; linear MAR): per pixel the eccentricity e from the predicted
// gaze ray, e' = max(0, e - u), w = m e' + w0, p = clamp(1 - (w - w_min) / w_far, xi, 1) (w_min, w_far: see
// fovea_interface.h); per B x B block a sample mask from the ranks of a low-discrepancy (R2) pattern, turned by a
// cyclic shift each frame: a pixel is sampled when its rank r has r == 0 or r + 0.5 < p n (n pixels in the block),
// so every block holds at least one sample. One thread per pixel, no barriers.
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fovea_interface.h"

layout(local_size_x = FV_FOVEA_GROUP, local_size_y = FV_FOVEA_GROUP, local_size_z = 1) in;

FV_SCENE_SET_DECLARE
layout(set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_PROB, r32f) uniform writeonly image2DArray prob_img;
layout(set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_MASK, r32ui) uniform writeonly uimage2DArray mask_img;
layout(std430, set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_RANKS) readonly buffer Ranks { uint ranks[]; };
layout(set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_BLOCKS, r32ui) uniform coherent uimage2DArray blocks_img;
layout(push_constant) uniform Push { fv_fovea_push pc; };

const float RAD_TO_DEG = 57.295779513082323;

float sampling_prob(uvec3 p)
{
    vec4 t = frame.eye_tan[p.z];
    vec2 size = vec2(frame.counts.y, frame.counts.z);
    vec2 uv = (vec2(p.xy) + 0.5) / size;
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
    vec2 dt = abs(vec2(t.y - t.x, t.w - t.z)) / size;
    float w_px = 2.0 * atan(0.5 * min(dt.x, dt.y)) * RAD_TO_DEG;
    float w_min = max(pc.mar_w0_deg, w_px);
    float w_far = (float(FV_FOVEA_FAR_PX) - 1.0) * w_px;
    float w = pc.mar_slope * ep * RAD_TO_DEG + pc.mar_w0_deg;
    return clamp(1.0 - (w - w_min) / w_far, pc.min_prob, 1.0);
}

// The R2 value of a pixel of its block.
float pattern(uvec2 l) { return fract(0.5 + float(l.x) * 0.75487766625 + float(l.y) * 0.56984029101); }

// The frame's cyclic shift of the ranks of an n-pixel block (golden-ratio sequence over the frames).
uint frame_shift(uint n) { return uint(fract(float(frame.counts.w & 1023u) * 0.61803398875) * float(n)) % n; }

bool sampled(uvec3 p, float prob)
{
    uint B = pc.block;
    uvec2 size = uvec2(frame.counts.y, frame.counts.z);
    uvec2 b0 = (p.xy / B) * B;
    uvec2 bs = min(uvec2(B), size - b0);
    uint n = bs.x * bs.y;
    uvec2 l = p.xy - b0;
    uint rank;
    if (n == B * B) {
        rank = ranks[l.y * B + l.x]; // a whole block: the table the host made for B
    } else {
        // a block cut by the image edge: rank among its own pixels (R2 value, ties by index)
        uint me = l.y * bs.x + l.x;
        float mine = pattern(l);
        rank = 0u;
        for (uint k = 0u; k < n; k++) {
            float o = pattern(uvec2(k % bs.x, k / bs.x));
            rank += (o < mine || (o == mine && k < me)) ? 1u : 0u;
        }
    }
    rank = (rank + frame_shift(n)) % n;
    return rank == 0u || float(rank) + 0.5 < prob * float(n);
}

void main()
{
    uvec3 p = gl_GlobalInvocationID;
    if (p.x >= frame.counts.y || p.y >= frame.counts.z || p.z > 1u) return;
    float prob = sampling_prob(p);
    bool s = sampled(p, prob);
    imageStore(prob_img, ivec3(p), vec4(prob));
    imageStore(mask_img, ivec3(p), uvec4(s ? 1u : 0u));
    if (s) {
        uint B = pc.block, k = (p.y % B) * B + p.x % B;
        imageAtomicOr(blocks_img, ivec3(int((p.x / B) * pc.block_words + k / 32u), int(p.y / B), int(p.z)),
                      1u << (k % 32u));
    }
}
