#version 450
// @brief Temporal reuse of foveated frames (papers/README.md section 3; Nehab et al. 2007's reverse reprojection
// cache): every pixel is reprojected into the previous frame through the G-buffer's motion vector (a pixel where
// nothing was drawn: through its far-plane point and the previous view-projection) and reads the previous
// history bilinearly, each of the four taps kept only when it is a cache hit: its stored distance from the previous
// eye equals |pos_t - eye_{t-1}| within FV_TEMPORAL_DEPTH_EPS (relative) plus the slope allowance, and it is
// younger than fovea.temporal frames. One pass writes this frame's history and the colour: a shaded pixel is its
// radiance blended (FV_TEMPORAL_SAMPLE_WEIGHT) with a hit's history clamped to within FV_TEMPORAL_CLAMP_REL of it
// (stale history cannot ghost); an unshaded pixel with a hit reuses the history (age + 1), is marked
// FV_TEMPORAL_MASK_REUSED in the mask and its block's bit set, so reconstruction takes it as a sample; a miss is
// unknown (0). Pixels interpolation shaded or interpolated (fv_sample_mask_interface.h) are known like shaded ones.
// A known pixel's colour carries in its alpha what the next frame needs (distance and age, fovea_interface.h); the
// history is the previous frame's colour. Each pixel reads and writes only itself in the colour and the mask. Per eye the hits and reuses are
// counted. No value is ever NaN or Inf: non-finite history or positions are misses.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fv_common.glsl"
#include "fovea_interface.h"

layout(local_size_x = FV_TEMPORAL_GROUP, local_size_y = FV_TEMPORAL_GROUP, local_size_z = 1) in;

FV_SCENE_SET_DECLARE
#define FV_GBUFFER_SET FV_TEMPORAL_SET
#define FV_GBUFFER_BINDING_DEPTH FV_TEMPORAL_BINDING_DEPTH
#define FV_GBUFFER_BINDING_NORMAL (FV_TEMPORAL_BINDING_DEPTH + 1)
#define FV_GBUFFER_BINDING_ALBEDO (FV_TEMPORAL_BINDING_DEPTH + 2)
#define FV_GBUFFER_BINDING_MATERIAL (FV_TEMPORAL_BINDING_DEPTH + 3)
#include "fv_gbuffer_decode.glsl"
layout(set = FV_TEMPORAL_SET, binding = FV_TEMPORAL_BINDING_MOTION, rgba32f) uniform readonly image2DArray g_motion;
layout(set = FV_TEMPORAL_SET, binding = FV_TEMPORAL_BINDING_MASK, r32ui) uniform uimage2DArray mask_img;
layout(set = FV_TEMPORAL_SET, binding = FV_TEMPORAL_BINDING_BLOCKS, r32ui) uniform coherent uimage2DArray blocks_img;
layout(set = FV_TEMPORAL_SET, binding = FV_TEMPORAL_BINDING_COLOR, rgba32f) uniform image2DArray color_img;
layout(set = FV_TEMPORAL_SET, binding = FV_TEMPORAL_BINDING_PREV, rgba32f) uniform readonly image2DArray prev_img;
layout(std430, set = FV_TEMPORAL_SET, binding = FV_TEMPORAL_BINDING_STATS) buffer Stats { uint stats[]; };
layout(push_constant) uniform Push { fv_temporal_push pc; };

const uint AGE_MASK = (1u << FV_TEMPORAL_AGE_BITS) - 1u;

// The history's alpha: a distance (> 0, finite) with the age in its lowest mantissa bits; 0 = nothing known.
float pack_info(float dist, uint age)
{
    return uintBitsToFloat((floatBitsToUint(max(dist, 1e-6)) & ~AGE_MASK) | min(age, AGE_MASK));
}

bool all_finite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

void main()
{
    ivec3 p = ivec3(gl_GlobalInvocationID);
    ivec2 size = ivec2(frame.counts.y, frame.counts.z);
    bool inside = p.x < size.x && p.y < size.y && p.z <= 1;
    bool hit = false, reused = false;
    if (inside) {
        uint m = imageLoad(mask_img, p).x;
        bool shaded = m != 0u;
        fv_gbuffer_fovea_surf gs = fv_gbuffer_fovea(uvec3(p), imageLoad(g_motion, p));
        bool surf = gs.hit;
        vec3 pos = surf ? gs.pos : fv_gbuffer_position(uvec3(p), 1.0);
        vec3 eye = frame.eye_pos[p.z].xyz, prev_eye = vec3(pc.prev_eye[p.z][0], pc.prev_eye[p.z][1],
                                                           pc.prev_eye[p.z][2]);
        float dist = surf ? gs.dist : float(FV_TEMPORAL_SKY);
        float expect = surf ? length(pos - prev_eye) : float(FV_TEMPORAL_SKY);
        // here: what the next frame needs of this pixel is finite; ok: its history can be looked up as well
        bool here = all_finite(pos) && !isnan(dist) && !isinf(dist);
        bool ok = here && !isnan(expect) && !isinf(expect);
        // where this pixel was in the previous frame, in pixels (continuous, centres at + 0.5)
        vec2 uv = (vec2(p.xy) + 0.5) / vec2(size);
        vec2 prev_uv;
        if (surf) {
            prev_uv = uv - gs.motion;
        } else {
            vec4 c = frame.prev_view_proj[p.z] * vec4(pos, 1.0);
            prev_uv = c.w > 1e-30 ? c.xy / c.w * 0.5 + 0.5 : vec2(-1.0);
        }
        vec2 f = prev_uv * vec2(size) - 0.5;
        ok = ok && !any(isnan(f)) && !any(isinf(f)) && all(greaterThan(f, vec2(-1.0))) &&
             all(lessThan(f, vec2(size)));
        // the slope allowance: how much the distance varies over one pixel on this surface, as seen from the eye
        float w_px = frame.pixel_angle[p.z];
        vec3 to_eye = eye - pos;
        float cos_t = surf ? abs(dot(gs.normal, normalize(to_eye))) : 1.0;
        float tan_t = min(sqrt(max(0.0, 1.0 - cos_t * cos_t)) / max(cos_t, 1e-6), float(FV_TEMPORAL_SLOPE_TAN_MAX));
        vec3 hsum = vec3(0.0);
        float wsum = 0.0;
        uint age = 0u;
        if (ok && (pc.flags & FV_TEMPORAL_FLAG_HISTORY) != 0u && pc.max_age > 0u) {
            ivec2 i0 = ivec2(floor(f));
            vec2 fr = f - vec2(i0);
            for (int k = 0; k < 4; k++) {
                ivec2 o = ivec2(k & 1, k >> 1);
                ivec2 q = i0 + o;
                float w = (o.x == 1 ? fr.x : 1.0 - fr.x) * (o.y == 1 ? fr.y : 1.0 - fr.y);
                if (w <= 0.0 || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
                vec4 h = imageLoad(prev_img, ivec3(q, p.z));
                uint bits = floatBitsToUint(h.a);
                if (bits == 0u || !all_finite(h.rgb) || isnan(h.a) || isinf(h.a)) continue;
                uint hage = bits & AGE_MASK;
                if (hage >= pc.max_age && !shaded) continue; // too old to be reused again
                float hd = uintBitsToFloat(bits & ~AGE_MASK);
                bool same;
                if (!surf) {
                    same = hd >= 0.5 * float(FV_TEMPORAL_SKY);
                } else {
                    float off = length(vec2(q) - f) + 0.5;
                    float tol = float(FV_TEMPORAL_DEPTH_EPS) * expect + expect * w_px * off * tan_t;
                    same = hd < 0.5 * float(FV_TEMPORAL_SKY) && abs(hd - expect) < tol;
                }
                if (!same) continue;
                hsum += w * h.rgb;
                wsum += w;
                age = max(age, hage);
            }
        }
        hit = wsum > 1e-4;
        vec3 h = hit ? hsum / wsum : vec3(0.0);
        if (shaded) {
            vec3 c = imageLoad(color_img, p).rgb;
            if (!all_finite(c)) c = vec3(0.0);
            if (hit) {
                // history that differs from the new shading by more than the clamp is stale (ghosting): clamped
                vec3 tol = float(FV_TEMPORAL_CLAMP_REL) * c + vec3(float(FV_TEMPORAL_CLAMP_ABS));
                c = mix(clamp(h, c - tol, c + tol), c, float(FV_TEMPORAL_SAMPLE_WEIGHT));
            }
            imageStore(color_img, p, vec4(c, here ? pack_info(dist, 0u) : 0.0)); // known next frame
        } else if (hit) {
            reused = true;
            imageStore(color_img, p, vec4(h, pack_info(dist, age + 1u)));
            imageStore(mask_img, p, uvec4(FV_TEMPORAL_MASK_REUSED));
            imageAtomicOr(blocks_img, fv_sample_block_word(uvec3(p), pc.block, pc.block_words),
                          fv_sample_block_bit(uvec3(p), pc.block));
        }
    }
    // counts per eye: one atomic per subgroup (a workgroup is one eye: z)
    uint nh = subgroupAdd(hit ? 1u : 0u), nr = subgroupAdd(reused ? 1u : 0u);
    if (subgroupElect() && p.z <= 1) {
        if (nh > 0u) atomicAdd(stats[pc.stats_base + uint(p.z)], nh);
        if (nr > 0u) atomicAdd(stats[pc.stats_base + 2u + uint(p.z)], nr);
    }
}
