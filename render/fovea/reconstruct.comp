#version 450
// @brief Reconstruction of the pixels foveation did not shade, from the shaded pixels (the seeds), each filled pixel's
// alpha 0 (not known: the history's, fovea_interface.h): nearest (the
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
layout(set = FV_RECON_SET, binding = FV_RECON_BINDING_MOTION, rgba32f) uniform readonly image2DArray g_motion;
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
// the representatives: FV_RECON_SOFT_REP_UVEC4S texels per block in a row (an image: cheaper loads than a buffer on
// some devices, lavapipe)
layout(set = FV_RECON_SET, binding = FV_RECON_BINDING_REPS, rgba32ui) uniform uimage2DArray reps_img;
layout(std430, set = FV_RECON_SET, binding = FV_RECON_BINDING_LISTS) buffer Lists { uint lists[]; };

uint list_base(uint l) { return l * (FV_RECON_LIST_HEADER + pc.list_pixels); }
// Pixel p as entry i of list l (its count, then the packed pixels); past the capacity, nothing.
void list_store(uint l, uint i, ivec3 p)
{
    if (i < pc.list_pixels) lists[list_base(l) + FV_RECON_LIST_HEADER + i] = FV_GPU_PIXEL_PACK(uint(p.x), uint(p.y), uint(p.z));
}
// Append pixel p to list l.
void list_append(uint l, ivec3 p) { list_store(l, atomicAdd(lists[list_base(l)], 1u), p); }
// This invocation's entry of list l (a dispatch of FV_RECON_GROUP^2 per workgroup, FV_GPU_LIST_GROUPS_X wide), or
// false past its end.
bool list_entry(uint l, out ivec3 p)
{
    uint i = (gl_WorkGroupID.x + gl_WorkGroupID.y * FV_GPU_LIST_GROUPS_X) * uint(FV_RECON_GROUP * FV_RECON_GROUP) +
             gl_LocalInvocationIndex;
    p = ivec3(0);
    if (i >= min(lists[list_base(l)], pc.list_pixels)) return false;
    p = ivec3(fv_pixel_unpack(lists[list_base(l) + FV_RECON_LIST_HEADER + i]));
    return true;
}

ivec3 rep_at(ivec2 b, int layer, uint j) { return ivec3(b.x * FV_RECON_SOFT_REP_UVEC4S + int(j), b.y, layer); }

uint block_count(ivec2 b, int layer)
{
    int words = int(pc.block_words);
    uint k = 0u;
    for (int w = 0; w < words; w++) k += uint(bitCount(imageLoad(blocks_img, ivec3(b.x * words + w, b.y, layer)).x));
    return k;
}

// SOFT_REPS: block b (inside the image) of layer z. Per quadrant slot the known pixel nearest the quadrant's centre
// (of the whole block: in a sparse block one sample fills every slot), with its colour, position, surface (unit
// normal, tangent plane's offset n.x) and the block's sigma.
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
    // each slot: the known pixel nearest its quadrant's centre, (2 h + 1) bs / 4 (ties: the first in row order)
    int pick[FV_RECON_SOFT_SLOTS];
    int bestd[FV_RECON_SOFT_SLOTS];
    for (int k = 0; k < FV_RECON_SOFT_SLOTS; k++) pick[k] = -1, bestd[k] = 0x7fffffff;
    for (int w = 0; w < words; w++) {
        uint bits = wv[w];
        while (bits != 0u) {
            int k = w * 32 + findLSB(bits);
            bits &= bits - 1u;
            ivec2 l = ivec2(k % B, k / B);
            for (int qd = 0; qd < FV_RECON_SOFT_SLOTS; qd++) {
                ivec2 h = ivec2(qd & 1, qd >> 1);
                ivec2 dc = l * 4 + 2 - (2 * h + 1) * bs; // 4 (l + 0.5) - (2 h + 1) bs, in quarter pixels
                int d = dc.x * dc.x + dc.y * dc.y;
                if (d < bestd[qd]) bestd[qd] = d, pick[qd] = k; // bits rise: ties keep the first
            }
        }
    }
    // the block's unknown pixels go to the fill's list, one atomic per block (the known ones are kept; the voronoi
    // view: their own)
    uint at = atomicAdd(lists[list_base(FV_RECON_LIST_FILL)], uint(bs.x * bs.y) - count);
    for (int k = 0; k < bs.x * bs.y; k++) {
        ivec2 l = ivec2(k % bs.x, k / bs.x);
        int kb = l.y * B + l.x;
        bool known = (wv[kb / 32] & (1u << uint(kb % 32))) != 0u;
        ivec3 q = ivec3(o + l, b.z);
        if (!known) {
            list_store(FV_RECON_LIST_FILL, at++, q);
        } else if ((pc.flags & FV_RECON_FLAG_VORONOI) != 0u) {
            imageStore(voronoi_img, q, uvec4(uint(q.x) | (uint(q.y) << 16)));
        }
    }
    for (int s = 0; s < FV_RECON_SOFT_SLOTS; s++) {
        if (pick[s] < 0) { // no known pixel (cannot happen: every block holds a sample): not a tap
            imageStore(reps_img, rep_at(b.xy, b.z, 2u * uint(s)), uvec4(0u, 0u, 0u, FV_RECON_NONE));
            continue;
        }
        ivec3 q = ivec3(o + ivec2(pick[s] % B, pick[s] / B), b.z);
        vec4 m = imageLoad(g_motion, q);
        fv_gbuffer_fovea_surf gs = fv_gbuffer_fovea(uvec3(q), m);
        bool hit = gs.hit;
        vec3 pos = gs.pos;
        vec2 oct = unpackSnorm2x16(floatBitsToUint(m.a));
        vec3 nrm = hit ? gs.normal : vec3(0.0);
        vec3 c = imageLoad(color_img, q).rgb;
        uint packed = uint(q.x) | (uint(q.y) << 16) | (hit ? 0u : FV_RECON_SOFT_NOTHING);
        imageStore(reps_img, rep_at(b.xy, b.z, 2u * uint(s)), uvec4(floatBitsToUint(c), packed));
        imageStore(reps_img, rep_at(b.xy, b.z, 2u * uint(s) + 1u),
                   uvec4(packSnorm2x16(oct), floatBitsToUint(dot(nrm, pos)), floatBitsToUint(sigma),
                         texelFetch(g_material, q, 0).r));
    }
}

// The squared distance of pixel p from the slot's pixel.
float soft_d2(uvec4 qa, ivec3 p)
{
    uint packed = qa.w & ~FV_RECON_SOFT_NOTHING;
    ivec2 dq = ivec2(int(packed & 0xffffu), int(packed >> 16)) - p.xy;
    return float(dq.x * dq.x + dq.y * dq.y);
}

// -log of the edge weight of pixel p (drawn: hit, at pos with normal nrm) against a slot (qa, qb), capped; the
// nearest slot so far (ties: the smaller packed position) updated.
float soft_tap(uvec4 qa, uvec4 qb, ivec3 p, bool hit, uint mat, vec3 pos, vec3 nrm, float kplane, float cap,
               inout uint best, inout uint bd, inout vec3 best_col)
{
    uint packed = qa.w & ~FV_RECON_SOFT_NOTHING;
    bool qhit = (qa.w & FV_RECON_SOFT_NOTHING) == 0u;
    float fd2 = soft_d2(qa, p);
    uint d2 = uint(fd2);
    if (d2 < bd || (d2 == bd && packed < best)) best = packed, bd = d2, best_col = uintBitsToFloat(qa.xyz);
    float e2;
    if (hit != qhit || (hit && qb.w != mat)) { // drawn against nothing, or another material
        e2 = cap;
    } else if (!hit) {
        e2 = 0.0;
    } else {
        vec3 qn = fv_oct_decode(unpackSnorm2x16(qb.x));
        float t = dot(qn, pos) - uintBitsToFloat(qb.y); // p's distance from the tap's tangent plane
        e2 = t * t * kplane / max(fd2, 1.0) + (1.0 - dot(nrm, qn)) * float(1.0 / FV_RECON_SOFT_NORMAL);
    }
    return isnan(e2) ? cap : min(e2, cap);
}

// SOFT_FILL: pixel p (inside the image). The 2x2 blocks whose centres surround p, each weighted by its bilinear tent
// over the block grid (so a block's weight reaches 0 exactly where it leaves the set: no seams), and of each the
// slot of its quadrant that faces p (the four facing quadrants tile the square between the four centres, so the
// choice never changes inside it), times a Gaussian of the distance and the edge weight; sigma the tents' blend of
// the blocks' sigmas.
// SOFT_FILL and SOFT_EDGE: unknown pixel p (from their lists). The fill stage takes the facing slots and leaves a
// pixel at an edge to the edge stage, which takes every distinct slot; each stage's variant compiles only its own
// part (spec constant), so a device that runs every branch for every pixel (llvmpipe) pays for the edges' 16 taps
// only at the edges.
void soft_fill(ivec3 p, ivec2 size)
{
    const bool EDGE = STAGE == FV_RECON_STAGE_SOFT_EDGE;
    int B = int(pc.block);
    ivec2 nb = (size + B - 1) / B;
    vec2 g = (vec2(p.xy) + 0.5) / float(B) - 0.5; // p in block-centre coordinates
    ivec2 b0 = ivec2(floor(g));
    vec2 f = g - vec2(b0);
    uvec4 ta[4], tb[4];
    float tent[4];
    float ssum = 0.0, tsum = 0.0;
    for (int k = 0; k < 4; k++) {
        ivec2 kk = ivec2(k & 1, k >> 1);
        ivec2 bb = b0 + kk;
        float t = (kk.x != 0 ? f.x : 1.0 - f.x) * (kk.y != 0 ? f.y : 1.0 - f.y);
        bool in_image = all(greaterThanEqual(bb, ivec2(0))) && all(lessThan(bb, nb)) && t > 0.0;
        uint slot = 2u * uint((1 - kk.x) + 2 * (1 - kk.y)); // the quadrant facing p
        ta[k] = in_image ? imageLoad(reps_img, rep_at(bb, p.z, slot)) : uvec4(0u, 0u, 0u, FV_RECON_NONE);
        in_image = in_image && ta[k].w != FV_RECON_NONE;
        tb[k] = in_image ? imageLoad(reps_img, rep_at(bb, p.z, slot + 1u)) : uvec4(0u);
        tent[k] = in_image ? t : 0.0;
        if (in_image) ssum += t * uintBitsToFloat(tb[k].z), tsum += t;
    }
    if (!(tsum > 0.0)) { // cannot happen: every block holds a sample
        imageStore(color_img, p, vec4(0.0));
        return;
    }
    float sigma_d = ssum / tsum; // the local sample spacing's
    fv_gbuffer_fovea_surf gs = fv_gbuffer_fovea(uvec3(p), imageLoad(g_motion, p));
    bool hit = gs.hit;
    vec3 pos = gs.pos;
    vec3 nrm = hit ? gs.normal : vec3(0.0);
    uint mat = texelFetch(g_material, p, 0).r;
    float foot = length(pos - frame.eye_pos[p.z].xyz) * frame.pixel_angle[p.z]; // m per px
    // (t / (foot d PLANE))^2 = t^2 kplane / d^2: no root or division per tap but one
    float kplane = 1.0 / max(foot * foot * float(FV_RECON_SOFT_PLANE * FV_RECON_SOFT_PLANE), 1e-30);
    float cap = -log(float(FV_RECON_SOFT_EDGE_FLOOR));
    vec3 sum = vec3(0.0), best_col = vec3(0.0);
    float wsum = 0.0, emax = 0.0;
    uint best = FV_RECON_NONE, bd = 0xffffffffu;
    // the facing slots, as wide as their spacing (half a block) at least
    float inv2s2 = 0.5 / pow(max(sigma_d, float(FV_RECON_SOFT_SIGMA) * 0.5 * float(B)), 2.0);
    if (!EDGE) {
        for (int k = 0; k < 4; k++) {
            if (!(tent[k] > 0.0)) continue;
            float e2 = soft_tap(ta[k], tb[k], p, hit, mat, pos, nrm, kplane, cap, best, bd, best_col);
            emax = max(emax, e2);
            float wt = tent[k] * exp(-soft_d2(ta[k], p) * inv2s2 - e2);
            sum += wt * uintBitsToFloat(ta[k].xyz);
            wsum += wt;
        }
        if (emax > float(FV_RECON_SOFT_EDGE_SPLIT)) { // an edge among the facing slots: the edge stage's
            list_append(FV_RECON_LIST_EDGE, p);
            return;
        }
    } else {
        // an edge among the facing slots: every distinct slot of the four blocks, as wide as the sample spacing
        // (the facing ones among them: the nearest tap is the same)
        inv2s2 = 0.5 / (sigma_d * sigma_d);
        for (int k = 0; k < 4; k++) {
            if (!(tent[k] > 0.0)) continue;
            ivec2 bb = b0 + ivec2(k & 1, k >> 1);
            uint seen[FV_RECON_SOFT_SLOTS];
            for (uint s = 0u; s < uint(FV_RECON_SOFT_SLOTS); s++) {
                uvec4 qa = imageLoad(reps_img, rep_at(bb, p.z, 2u * s));
                seen[s] = qa.w;
                bool dup = qa.w == FV_RECON_NONE;
                for (uint r = 0u; r < s; r++) dup = dup || seen[r] == qa.w;
                if (dup) continue;
                uvec4 qb = imageLoad(reps_img, rep_at(bb, p.z, 2u * s + 1u));
                float e2 = soft_tap(qa, qb, p, hit, mat, pos, nrm, kplane, cap, best, bd, best_col);
                float wt = tent[k] * exp(-soft_d2(qa, p) * inv2s2 - e2);
                sum += wt * uintBitsToFloat(qa.xyz);
                wsum += wt;
            }
        }
    }
    if ((pc.flags & FV_RECON_FLAG_VORONOI) != 0u) imageStore(voronoi_img, p, uvec4(best));
    vec3 c = wsum > 1e-30 ? sum / wsum : best_col;
    if (any(isnan(c)) || any(isinf(c))) c = best_col;
    imageStore(color_img, p, vec4(c, 0.0)); // alpha 0: filled, not known (the history's, fovea_interface.h)
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
    if (STAGE == FV_RECON_STAGE_SOFT_ARGS) { // one thread: list push.step's count as its indirect dispatch
        if (gl_LocalInvocationIndex == 0u) {
            uint l = pc.step, n = min(lists[list_base(l)], pc.list_pixels);
            uint groups = (n + uint(FV_RECON_GROUP * FV_RECON_GROUP) - 1u) / uint(FV_RECON_GROUP * FV_RECON_GROUP);
            uint a = 2u * (FV_RECON_LIST_HEADER + pc.list_pixels) + 4u * l;
            lists[a] = groups == 0u ? 0u : min(groups, FV_GPU_LIST_GROUPS_X);
            lists[a + 1u] = groups == 0u ? 0u : (groups + FV_GPU_LIST_GROUPS_X - 1u) / FV_GPU_LIST_GROUPS_X;
            lists[a + 2u] = groups == 0u ? 0u : 1u;
        }
        return;
    }
    if (STAGE == FV_RECON_STAGE_SOFT_FILL || STAGE == FV_RECON_STAGE_SOFT_EDGE) {
        ivec3 q;
        if (list_entry(STAGE == FV_RECON_STAGE_SOFT_EDGE ? FV_RECON_LIST_EDGE : FV_RECON_LIST_FILL, q)) soft_fill(q, size);
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
        vec3 c = best == FV_RECON_NONE ? vec3(0.0)
                 : wsum > 0.0          ? sum / wsum
                                       : imageLoad(color_img, ivec3(int(best & 0xffffu), int(best >> 16), p.z)).rgb;
        imageStore(color_img, p, vec4(c, 0.0));
        return;
    }
    uint s = read_seed(p);
    imageStore(voronoi_img, p, uvec4(s));
    if (s == (uint(p.x) | (uint(p.y) << 16))) return; // a sample keeps its shaded colour
    if (s == FV_RECON_NONE) { // no sample at all (cannot happen: every block holds one)
        imageStore(color_img, p, vec4(0.0));
        return;
    }
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
        imageStore(color_img, p, vec4(sum / max(n, 1.0), 0.0));
        return;
    }
    imageStore(color_img, p, vec4(imageLoad(color_img, ivec3(int(s & 0xffffu), int(s >> 16), p.z)).rgb, 0.0));
}
