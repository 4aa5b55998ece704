#version 450
// @brief Reconstruction of the pixels foveation did not shade, from the shaded pixels (the seeds): nearest (the
// colour of the nearest seed) or sibson (approximate discrete natural-neighbour interpolation), both over the
// Voronoi diagram of the seeds found by jump flooding (Rong & Tan 2006) in its 1+JFA form: one step of size 1, then steps from the
// block size down to 1 (every block holds a seed, so no seed is farther than two blocks). Seeds ping-pong between
// two R32UI images; distances are exact integer squared distances, ties go to the smaller packed seed. idw and the
// nearest with blocks search the neighbouring blocks' samples instead. The soft fill (FV_RECON_STAGE_SOFT, see
// fovea_interface.h): per block its representatives, then per pixel a bounded edge-aware Gaussian of those of the
// blocks around.
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fovea_interface.h"

layout(local_size_x = FV_RECON_GROUP, local_size_y = FV_RECON_GROUP, local_size_z = 1) in;
layout(constant_id = 0) const uint STAGE = FV_RECON_STAGE_INIT;

FV_SCENE_SET_DECLARE
layout(set = FV_RECON_SET, binding = FV_RECON_BINDING_MASK, r32ui) uniform readonly uimage2DArray mask_img;
layout(std430, set = FV_RECON_SET, binding = FV_RECON_BINDING_SEEDS_A) buffer SeedsA { uint seeds_a[]; };
layout(std430, set = FV_RECON_SET, binding = FV_RECON_BINDING_SEEDS_B) buffer SeedsB { uint seeds_b[]; };
layout(set = FV_RECON_SET, binding = FV_RECON_BINDING_COLOR, rgba32f) uniform image2DArray color_img;
layout(set = FV_RECON_SET, binding = FV_RECON_BINDING_VORONOI, r32ui) uniform writeonly uimage2DArray voronoi_img;
layout(set = FV_RECON_SET, binding = FV_RECON_BINDING_BLOCKS, r32ui) uniform readonly uimage2DArray blocks_img;
#define FV_GBUFFER_SET FV_RECON_SET
#define FV_GBUFFER_BINDING_DEPTH FV_RECON_BINDING_DEPTH
#define FV_GBUFFER_BINDING_NORMAL (FV_RECON_BINDING_DEPTH + 1)
#define FV_GBUFFER_BINDING_ALBEDO (FV_RECON_BINDING_DEPTH + 2)
#define FV_GBUFFER_BINDING_MATERIAL (FV_RECON_BINDING_DEPTH + 3)
#include "fv_common.glsl"
#include "fv_gbuffer_decode.glsl"
layout(push_constant) uniform Push { fv_recon_push pc; };

uint at(ivec3 c) { return (uint(c.z) * frame.counts.z + uint(c.y)) * frame.counts.y + uint(c.x); }
uint read_seed(ivec3 c) { return pc.src == 0u ? seeds_a[at(c)] : seeds_b[at(c)]; }

uint dist2(uint s, ivec2 p)
{
    ivec2 d = ivec2(int(s & 0xffffu), int(s >> 16)) - p;
    return uint(d.x * d.x + d.y * d.y);
}

// Every sample of the blocks within pc.reach blocks of p's own: the nearest (ties: the smaller packed seed) and,
// with `idw`, the sums of Shepard weights (1 - d / r)^2 / d^2 (r = the radius the neighbourhood always covers, so a
// sample's weight is 0 before it leaves the neighbourhood: no seams at block edges) and weighted colours.
// The block masks around this workgroup's 8x8 pixels (and pc.reach blocks beyond), loaded once per workgroup:
// a pixel's gather reads up to 25 blocks, and storage-image loads are the cost on some devices (lavapipe).
const int TILE_BLOCKS = FV_RECON_GROUP / 2 + 2 + 2 * 2; // per side: B >= 2, reach <= 2, plus misalignment
shared uint sh_blocks[TILE_BLOCKS * TILE_BLOCKS * int(FV_FOVEA_BLOCK_WORDS_MAX)];
shared ivec2 sh_origin; // the tile's first block

void load_block_tile(ivec2 size, int layer)
{
    int B = int(pc.block), R = int(pc.reach), words = int(pc.block_words);
    ivec2 nb = (size + B - 1) / B;
    ivec2 first = ivec2(gl_WorkGroupID.xy) * FV_RECON_GROUP / B - R;
    ivec2 last = (ivec2(gl_WorkGroupID.xy) * FV_RECON_GROUP + FV_RECON_GROUP - 1) / B + R;
    ivec2 n = last - first + 1;
    int total = n.x * n.y * words;
    for (int i = int(gl_LocalInvocationIndex); i < total; i += FV_RECON_GROUP * FV_RECON_GROUP) {
        int w = i % words, bi = i / words;
        ivec2 bb = first + ivec2(bi % n.x, bi / n.x);
        bool in_image = all(greaterThanEqual(bb, ivec2(0))) && all(lessThan(bb, nb));
        uint v = in_image ? imageLoad(blocks_img, ivec3(bb.x * words + w, bb.y, layer)).x : 0u;
        sh_blocks[((bb.y - first.y) * TILE_BLOCKS + (bb.x - first.x)) * words + w] = v;
    }
    if (gl_LocalInvocationIndex == 0u) sh_origin = first;
}

void gather(ivec3 p, ivec2 size, bool idw, inout uint best, inout uint bd, inout vec3 sum, inout float wsum)
{
    int B = int(pc.block), R = int(pc.reach), words = int(pc.block_words);
    ivec2 nb = (size + B - 1) / B, b = p.xy / B;
    float r = float(B * R) + 0.5;
    for (int by = max(b.y - R, 0); by <= min(b.y + R, nb.y - 1); by++)
        for (int bx = max(b.x - R, 0); bx <= min(b.x + R, nb.x - 1); bx++)
            for (int w = 0; w < words; w++) {
                uint bits = sh_blocks[((by - sh_origin.y) * TILE_BLOCKS + (bx - sh_origin.x)) * words + w];
                while (bits != 0u) {
                    int k = w * 32 + findLSB(bits);
                    bits &= bits - 1u;
                    ivec2 q = ivec2(bx * B + k % B, by * B + k / B);
                    ivec2 dq = q - p.xy;
                    uint d = uint(dq.x * dq.x + dq.y * dq.y), packed = uint(q.x) | (uint(q.y) << 16);
                    if (d < bd || (d == bd && packed < best)) {
                        best = packed;
                        bd = d;
                    }
                    if (idw) {
                        float dist = sqrt(float(d)), f = max(0.0, 1.0 - dist / r);
                        float wt = f * f / float(d);
                        sum += wt * imageLoad(color_img, ivec3(q, p.z)).rgb;
                        wsum += wt;
                    }
                }
            }
}


// ---- the soft fill (fovea_interface.h) ---------------------------------------------------------------------------
layout(std430, set = FV_RECON_SET, binding = FV_RECON_BINDING_REPS) buffer Reps { uvec4 reps[]; };

uint rep_base(ivec2 b, int layer, ivec2 nb) { return uint((layer * nb.y + b.y) * nb.x + b.x) * FV_RECON_SOFT_REP_UVEC4S; }

uint block_count(ivec2 b, int layer)
{
    int words = int(pc.block_words);
    uint k = 0u;
    for (int w = 0; w < words; w++) k += uint(bitCount(imageLoad(blocks_img, ivec3(b.x * words + w, b.y, layer)).x));
    return k;
}

// SOFT_REPS: block b (inside the image) of layer z.
void soft_reps(ivec3 b, ivec2 size)
{
    int B = int(pc.block), words = int(pc.block_words);
    ivec2 nb = (size + B - 1) / B;
    ivec2 o = b.xy * B, bs = min(ivec2(B), size - o);
    uint wv[FV_FOVEA_BLOCK_WORDS_MAX];
    uint count = 0u;
    for (int w = 0; w < words; w++) {
        wv[w] = imageLoad(blocks_img, ivec3(b.x * words + w, b.y, b.z)).x;
        count += uint(bitCount(wv[w]));
    }
    // the local sampling rate: the known pixels of the 3x3 blocks over their area (every block holds one)
    float known = 0.0, area = 0.0;
    for (int by = max(b.y - 1, 0); by <= min(b.y + 1, nb.y - 1); by++)
        for (int bx = max(b.x - 1, 0); bx <= min(b.x + 1, nb.x - 1); bx++) {
            ivec2 cs = min(ivec2(B), size - ivec2(bx, by) * B);
            known += float(bx == b.x && by == b.y ? count : block_count(ivec2(bx, by), b.z));
            area += float(cs.x * cs.y);
        }
    float sigma = max(float(FV_RECON_SOFT_SIGMA) * sqrt(area / max(known, 1.0)), float(FV_RECON_SOFT_SIGMA_MIN));
    // the slots: every known pixel when there are few, else per quadrant the one nearest its centre
    int pick[FV_RECON_SOFT_SLOTS];
    int bestd[FV_RECON_SOFT_SLOTS];
    for (int k = 0; k < FV_RECON_SOFT_SLOTS; k++) pick[k] = -1, bestd[k] = 0x7fffffff;
    uint n = 0u;
    for (int w = 0; w < words; w++) {
        uint bits = wv[w];
        while (bits != 0u) {
            int k = w * 32 + findLSB(bits);
            bits &= bits - 1u;
            ivec2 l = ivec2(k % B, k / B);
            if (count <= uint(FV_RECON_SOFT_SLOTS)) {
                pick[n++] = k;
                continue;
            }
            ivec2 h = ivec2(greaterThanEqual(l * 2, bs)); // the quadrant; its centre at (2 h + 1) bs / 4
            int qd = h.x + 2 * h.y;
            ivec2 dc = l * 4 + 2 - (2 * h + 1) * bs; // 4 (l + 0.5) - (2 h + 1) bs, in quarter pixels
            int d = dc.x * dc.x + dc.y * dc.y;
            if (d < bestd[qd]) bestd[qd] = d, pick[qd] = k; // bits rise: ties keep the first
        }
    }
    uint base = rep_base(b.xy, b.z, nb);
    uint m = 0u;
    for (int s = 0; s < FV_RECON_SOFT_SLOTS; s++) {
        if (pick[s] < 0) continue;
        ivec3 q = ivec3(o + ivec2(pick[s] % B, pick[s] / B), b.z);
        bool hit = texelFetch(g_material, q, 0).r != 0u;
        vec3 pos = fv_gbuffer_position(uvec3(q), texelFetch(g_depth, q, 0).r);
        vec3 nrm = hit ? fv_oct_decode(texelFetch(g_normal, q, 0).rg) : vec3(0.0);
        vec3 c = imageLoad(color_img, q).rgb;
        uint packed = uint(q.x) | (uint(q.y) << 16) | (hit ? 0u : FV_RECON_SOFT_NOTHING);
        reps[base + 1u + 2u * m] = uvec4(floatBitsToUint(c), packed);
        reps[base + 2u + 2u * m] = uvec4(floatBitsToUint(nrm), floatBitsToUint(dot(nrm, pos)));
        m++;
    }
    reps[base] = uvec4(count, m, floatBitsToUint(sigma), 0u);
}

// SOFT_FILL: pixel p (inside the image). The 2x2 blocks whose centres surround p, each weighted by its bilinear tent
// over the block grid (so a block's weight reaches 0 exactly where it leaves the set: no seams), times per
// representative a Gaussian of its distance and the edge weight; sigma the tents' blend of the blocks' sigmas.
void soft_fill(ivec3 p, ivec2 size)
{
    if (imageLoad(mask_img, p).x != 0u) { // known: kept
        if ((pc.flags & FV_RECON_FLAG_VORONOI) != 0u) imageStore(voronoi_img, p, uvec4(uint(p.x) | (uint(p.y) << 16)));
        return;
    }
    int B = int(pc.block);
    ivec2 nb = (size + B - 1) / B;
    vec2 g = (vec2(p.xy) + 0.5) / float(B) - 0.5; // p in block-centre coordinates
    ivec2 b0 = ivec2(floor(g));
    vec2 f = g - vec2(b0);
    uint base[4];
    float tent[4];
    float ssum = 0.0, tsum = 0.0;
    for (int k = 0; k < 4; k++) {
        ivec2 bb = b0 + ivec2(k & 1, k >> 1);
        float t = ((k & 1) != 0 ? f.x : 1.0 - f.x) * ((k >> 1) != 0 ? f.y : 1.0 - f.y);
        bool in_image = all(greaterThanEqual(bb, ivec2(0))) && all(lessThan(bb, nb)) && t > 0.0;
        base[k] = in_image ? rep_base(bb, p.z, nb) : 0xffffffffu;
        tent[k] = in_image ? t : 0.0;
        if (in_image) ssum += t * uintBitsToFloat(reps[base[k]].z), tsum += t;
    }
    float sigma = ssum / tsum;
    float inv2s2 = 0.5 / (sigma * sigma);
    bool hit = texelFetch(g_material, p, 0).r != 0u;
    vec3 pos = fv_gbuffer_position(uvec3(p), texelFetch(g_depth, p, 0).r);
    vec3 nrm = hit ? fv_oct_decode(texelFetch(g_normal, p, 0).rg) : vec3(0.0);
    vec4 te = frame.eye_tan[p.z];
    vec2 dt = abs(vec2(te.y - te.x, te.w - te.z)) / vec2(size);
    float foot = length(pos - frame.eye_pos[p.z].xyz) * 2.0 * atan(0.5 * min(dt.x, dt.y)); // m per px
    // (t / (foot d PLANE))^2 = t^2 kplane / d^2: no root or division per tap but one
    float kplane = 1.0 / max(foot * foot * float(FV_RECON_SOFT_PLANE * FV_RECON_SOFT_PLANE), 1e-30);
    float cap = -log(float(FV_RECON_SOFT_EDGE_FLOOR));
    vec3 sum = vec3(0.0), best_col = vec3(0.0);
    float wsum = 0.0;
    uint best = FV_RECON_NONE, bd = 0xffffffffu;
    for (int k = 0; k < 4; k++) {
        if (base[k] == 0xffffffffu) continue;
        uint n = min(reps[base[k]].y, uint(FV_RECON_SOFT_SLOTS));
        for (uint i = 0u; i < n; i++) {
            uvec4 qa = reps[base[k] + 1u + 2u * i];
            vec3 qc = uintBitsToFloat(qa.xyz);
            uint packed = qa.w & ~FV_RECON_SOFT_NOTHING;
            bool qhit = (qa.w & FV_RECON_SOFT_NOTHING) == 0u;
            ivec2 dq = ivec2(int(packed & 0xffffu), int(packed >> 16)) - p.xy;
            uint d2 = uint(dq.x * dq.x + dq.y * dq.y);
            if (d2 < bd || (d2 == bd && packed < best)) best = packed, bd = d2, best_col = qc;
            float fd2 = float(d2);
            float e2; // -log of the edge weight
            if (hit != qhit) {
                e2 = cap;
            } else if (!hit) {
                e2 = 0.0;
            } else {
                uvec4 qb = reps[base[k] + 2u + 2u * i];
                vec3 qn = uintBitsToFloat(qb.xyz);
                float t = dot(qn, pos) - uintBitsToFloat(qb.w); // p's distance from the tap's tangent plane
                e2 = t * t * kplane / max(fd2, 1.0) + (1.0 - dot(nrm, qn)) * float(1.0 / FV_RECON_SOFT_NORMAL);
            }
            if (isnan(e2)) e2 = cap;
            float wt = tent[k] * exp(-fd2 * inv2s2 - min(e2, cap));
            sum += wt * qc;
            wsum += wt;
        }
    }
    if ((pc.flags & FV_RECON_FLAG_VORONOI) != 0u) imageStore(voronoi_img, p, uvec4(best));
    if (best == FV_RECON_NONE) return;
    vec3 c = wsum > 1e-30 ? sum / wsum : best_col;
    if (any(isnan(c)) || any(isinf(c))) c = best_col;
    imageStore(color_img, p, vec4(c, 1.0));
}

void main()
{
    ivec3 p = ivec3(gl_GlobalInvocationID);
    ivec2 size = ivec2(frame.counts.y, frame.counts.z);
    // the stages that gather load the workgroup's block masks first (every invocation reaches the barrier)
    bool gathers = STAGE == FV_RECON_STAGE_BLOCKS ||
                   (STAGE == FV_RECON_STAGE_RESOLVE && (pc.method == FV_RECON_METHOD_IDW || pc.src == FV_RECON_SRC_SEARCH));
    if (gathers) {
        load_block_tile(size, p.z);
        barrier();
    }
    if (STAGE == FV_RECON_STAGE_SOFT_REPS) { // one thread per block
        int B = int(pc.block);
        if (p.x < (size.x + B - 1) / B && p.y < (size.y + B - 1) / B && p.z <= 1) soft_reps(p, size);
        return;
    }
    if (STAGE == FV_RECON_STAGE_SOFT_FILL) {
        if (p.x < size.x && p.y < size.y && p.z <= 1) soft_fill(p, size);
        return;
    }
    if (p.x >= size.x || p.y >= size.y || p.z > 1) return;
    if (STAGE == FV_RECON_STAGE_INIT) {
        bool s = imageLoad(mask_img, p).x != 0u;
        uint v = s ? uint(p.x) | (uint(p.y) << 16) : FV_RECON_NONE;
        seeds_a[at(p)] = v;
        seeds_b[at(p)] = v;
        return;
    }
    if (STAGE == FV_RECON_STAGE_BLOCKS) {
        uint best = FV_RECON_NONE, bd = 0xffffffffu;
        vec3 sum = vec3(0.0);
        float wsum = 0.0;
        if (imageLoad(mask_img, p).x != 0u) best = uint(p.x) | (uint(p.y) << 16);
        else gather(p, size, false, best, bd, sum, wsum);
        seeds_a[at(p)] = best;
        return;
    }
    if (STAGE == FV_RECON_STAGE_STEP) {
        uint best = read_seed(p), bd = best == FV_RECON_NONE ? 0xffffffffu : dist2(best, p.xy);
        if (bd == 0u) return; // a seed: both buffers hold it since INIT
        int k = int(pc.step);
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                ivec2 q = p.xy + ivec2(dx, dy) * k;
                if ((dx == 0 && dy == 0) || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
                uint c = read_seed(ivec3(q, p.z));
                if (c == FV_RECON_NONE) continue;
                uint d = dist2(c, p.xy);
                if (d < bd || (d == bd && c < best)) {
                    best = c;
                    bd = d;
                }
            }
        if (pc.src == 0u) seeds_b[at(p)] = best;
        else seeds_a[at(p)] = best;
        return;
    }
    // FV_RECON_STAGE_RESOLVE: only unsampled pixels are written and only sampled ones are read.
    if (pc.method == FV_RECON_METHOD_IDW || pc.src == FV_RECON_SRC_SEARCH) {
        uint self = uint(p.x) | (uint(p.y) << 16);
        if (imageLoad(mask_img, p).x != 0u) {
            imageStore(voronoi_img, p, uvec4(self));
            return;
        }
        uint best = FV_RECON_NONE, bd = 0xffffffffu;
        vec3 sum = vec3(0.0);
        float wsum = 0.0;
        gather(p, size, pc.method == FV_RECON_METHOD_IDW, best, bd, sum, wsum);
        imageStore(voronoi_img, p, uvec4(best));
        if (best == FV_RECON_NONE) return;
        vec3 c = wsum > 0.0 ? sum / wsum : imageLoad(color_img, ivec3(int(best & 0xffffu), int(best >> 16), p.z)).rgb;
        imageStore(color_img, p, vec4(c, 1.0));
        return;
    }
    uint s = read_seed(p);
    imageStore(voronoi_img, p, uvec4(s));
    if (s == FV_RECON_NONE || s == (uint(p.x) | (uint(p.y) << 16))) return; // a sample keeps its shaded colour
    if (pc.method == FV_RECON_METHOD_SIBSON) {
        // Approximate discrete Sibson interpolation (Park et al. 2006, as the thesis): every pixel q of the window
        // whose nearest seed is at least as far from q as p is (|p - q| <= d(q), q's Voronoi circle holds p) adds
        // its seed's colour; the mean of those is the natural-neighbour weighting of the seeds. q = p always counts.
        int R = int(pc.window);
        vec3 sum = vec3(0.0);
        float n = 0.0;
        for (int dy = -R; dy <= R; dy++)
            for (int dx = -R; dx <= R; dx++) {
                ivec2 q = p.xy + ivec2(dx, dy);
                if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
                uint qs = read_seed(ivec3(q, p.z));
                if (qs == FV_RECON_NONE || uint(dx * dx + dy * dy) > dist2(qs, q)) continue;
                sum += imageLoad(color_img, ivec3(int(qs & 0xffffu), int(qs >> 16), p.z)).rgb;
                n += 1.0;
            }
        imageStore(color_img, p, vec4(sum / max(n, 1.0), 1.0));
        return;
    }
    imageStore(color_img, p, imageLoad(color_img, ivec3(int(s & 0xffffu), int(s >> 16), p.z)));
}
