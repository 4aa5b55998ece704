#version 450
// @brief Hierarchical screen-space interpolation, before shading (interp_interface.h has the rules): the pyramid of
// the G-buffer's position, normal and albedo with each node's coherence, the classification of every pixel (shaded,
// filled or left), and the list of the shaded pixels by an exclusive prefix sum over the tiles in an interleaved
// order. One shader; each stage is a pipeline of its own (specialization constant 0).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fv_shade_inputs_interface.h"
#include "fv_common.glsl"
#include "interp_interface.h"

layout(local_size_x = FV_INTERP_GROUP, local_size_y = FV_INTERP_GROUP, local_size_z = 1) in;
// The stage (FV_INTERP_STAGE_*) as a specialization constant: each stage is its own pipeline, so the stages without
// barriers compile without them (a CPU driver runs a workgroup that has barriers far more slowly).
layout(constant_id = 0) const uint STAGE = FV_INTERP_STAGE_COUNT;

FV_SCENE_SET_DECLARE
FV_SHADE_INPUTS_DECLARE
#define FV_GBUFFER_SET FV_INTERP_SET
#define FV_GBUFFER_BINDING_DEPTH FV_INTERP_BINDING_DEPTH
#define FV_GBUFFER_BINDING_NORMAL FV_INTERP_BINDING_NORMAL
#define FV_GBUFFER_BINDING_ALBEDO FV_INTERP_BINDING_ALBEDO
#define FV_GBUFFER_BINDING_MATERIAL FV_INTERP_BINDING_MATERIAL
#include "fv_gbuffer_decode.glsl"
#include "fv_shade_common.glsl"

layout(std430, set = FV_INTERP_SET, binding = FV_INTERP_BINDING_NODES) buffer Nodes { vec4 nodes[]; };
layout(set = FV_INTERP_SET, binding = FV_INTERP_BINDING_LEVEL, r32ui) uniform uimage2DArray level_img;
layout(std430, set = FV_INTERP_SET, binding = FV_INTERP_BINDING_TILES) buffer Tiles { uint tiles[]; };
layout(std430, set = FV_INTERP_SET, binding = FV_INTERP_BINDING_LIST) buffer List {
    uint count;
    uint pad0, pad1, pad2;
    uint pixels[];
} list;
layout(std430, set = FV_INTERP_SET, binding = FV_INTERP_BINDING_INDIRECT) buffer Indirect { uint args[4]; } ind;
layout(std430, set = FV_INTERP_SET, binding = FV_INTERP_BINDING_GIVEN) buffer Given { uint given[]; };
layout(std430, set = FV_INTERP_SET, binding = FV_INTERP_BINDING_STATS) buffer Stats { uint counts[4]; } stats;
layout(push_constant) uniform Push { fv_interp_push pc; };

shared uint sh_sum[FV_INTERP_TILE_SIZE]; // the scan's per-thread totals

bool all_finite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

uint W() { return frame.counts.y; }
uint H() { return frame.counts.z; }

// Nodes per row (x) and column (y) of level k: max(1, ceil((n - 1) / 2^k)).
uint nodes_along(uint n, uint k) { return max(1u, ((n - 1u) + (1u << k) - 1u) >> k); }

// Index of the first node of level k (1..MAX) in nodes[] / 2 (the host sums 2 nx_l ny_l over l < k).
uint level_base(uint k) { return pc.level_base[min(k, FV_INTERP_MAX_LEVEL)]; }

uint node_index(uint k, uint eye, uvec2 ij)
{
    uint nx = nodes_along(W(), k), ny = nodes_along(H(), k);
    ij = min(ij, uvec2(nx - 1u, ny - 1u));
    return level_base(k) + (eye * ny + ij.y) * nx + ij.x;
}

uint node_flags(uint index) { return floatBitsToUint(nodes[FV_INTERP_NODE_VEC4 * index].w); }
bool node_coherent(uint k, uint eye, uvec2 ij) { return (node_flags(node_index(k, eye, ij)) & FV_INTERP_NODE_COHERENT) != 0u; }

float max3(vec3 v) { return max(v.x, max(v.y, v.z)); }

// Whether a member (position p, normal n, albedo a, direct irradiance e) is close enough to the mean (pm, unit nm,
// am, em): see the header.
bool similar(vec3 p, vec3 n, vec3 a, vec3 e, vec3 pm, vec3 nm, vec3 am, vec3 em, float width_m)
{
    float t = pc.threshold;
    bool light = (pc.flags & FV_INTERP_FLAG_LIGHT) == 0u || max3(abs(e - em)) <= t * max3(em);
    return 1.0 - dot(n, nm) <= t && abs(dot(p - pm, nm)) <= t * width_m && max3(abs(a - am)) <= t && light;
}

// A node's width on a surface facing the eye at the mean position: its 2^k pixels at the eye distance (the larger
// tangent step of a pixel of the eye's frustum), metres; finite and >= 0.
float node_width_m(uint k, uint eye, vec3 pm)
{
    vec4 t = frame.eye_tan[min(eye, 1u)];
    float step = max(abs(t.y - t.x) / float(W()), abs(t.w - t.z) / float(H()));
    float w = float(1u << k) * step * length(pm - frame.eye_pos[min(eye, 1u)].xyz);
    return w < 3.4e38 ? w : 0.0; // NaN and Inf: 0, nothing but exact agreement
}

// The direct irradiance the light test compares (0 without it): finite, >= 0.
vec3 direct_light(fv_surface s)
{
    if ((pc.flags & FV_INTERP_FLAG_LIGHT) == 0u || !s.hit) return vec3(0);
    vec3 e = fv_shade_direct_irradiance(s);
    return all_finite(e) ? max(e, vec3(0)) : vec3(0);
}

// Write node (k, eye, ij): members' sums and whether they agree so far; `ok` false: already incoherent.
void store_node(uint k, uint eye, uvec2 ij, vec3 p_mean, vec3 n_sum, vec3 a_mean, vec3 e_mean, uint material, bool coh)
{
    uint flags = (coh ? FV_INTERP_NODE_COHERENT : 0u) | (material << FV_INTERP_NODE_MATERIAL_SHIFT);
    uint i = FV_INTERP_NODE_VEC4 * node_index(k, eye, ij);
    nodes[i] = vec4(p_mean, uintBitsToFloat(flags));
    nodes[i + 1u] = vec4(n_sum, uintBitsToFloat(packUnorm4x8(vec4(clamp(a_mean, 0.0, 1.0), 0.0))));
    nodes[i + 2u] = vec4(e_mean, 0.0);
}

// Level 1: the closed 3 x 3 pixels [2i, 2i+2] x [2j, 2j+2] (clamped to the image), decoded from the G-buffer by
// each node (2.25 decodes per pixel: measured cheaper on lavapipe than decoding each once into shared memory behind
// a barrier).
#define LEAF_SIDE (2 * FV_INTERP_GROUP + 1)
shared vec4 sh_a[LEAF_SIDE * LEAF_SIDE]; // LEAF_SHARED: position, material + 1 (bits)
shared vec4 sh_b[LEAF_SIDE * LEAF_SIDE]; // normal, albedo (unorm4x8 bits)
shared vec3 sh_e[LEAF_SIDE * LEAF_SIDE]; // direct irradiance

void build_leaf(uvec3 id)
{
    uint nx = nodes_along(W(), 1u), ny = nodes_along(H(), 1u);
    uint eye = id.z;
    if (STAGE == FV_INTERP_STAGE_LEAF_SHARED) {
        uvec2 origin = 2u * gl_WorkGroupID.xy * FV_INTERP_GROUP;
        for (uint q = gl_LocalInvocationIndex; q < LEAF_SIDE * LEAF_SIDE; q += FV_INTERP_TILE_SIZE) {
            uvec3 p = uvec3(min(origin.x + q % LEAF_SIDE, W() - 1u), min(origin.y + q / LEAF_SIDE, H() - 1u), eye);
            fv_surface sf = fv_gbuffer_surface(p);
            sh_a[q] = vec4(sf.hit ? sf.pos_world : vec3(0), uintBitsToFloat(sf.hit ? sf.material + 1u : 0u));
            sh_b[q] = vec4(sf.hit ? sf.normal : vec3(0),
                           uintBitsToFloat(packUnorm4x8(vec4(sf.hit ? sf.albedo : vec3(0), 0.0))));
            sh_e[q] = direct_light(sf);
        }
        barrier();
    }
    if (id.x >= nx || id.y >= ny) return;
    vec3 pos[9], nrm[9], alb[9], lit[9];
    uint mat = 0u, hits = 0u;
    bool same = true;
    vec3 ps = vec3(0), ns = vec3(0), as = vec3(0), es = vec3(0);
    for (uint q = 0u; q < 9u; q++) {
        uint m;
        if (STAGE == FV_INTERP_STAGE_LEAF_SHARED) {
            uint at = (2u * gl_LocalInvocationID.y + q / 3u) * LEAF_SIDE + 2u * gl_LocalInvocationID.x + q % 3u;
            vec4 a = sh_a[at], b = sh_b[at];
            m = floatBitsToUint(a.w);
            pos[q] = a.xyz;
            nrm[q] = b.xyz;
            alb[q] = unpackUnorm4x8(floatBitsToUint(b.w)).rgb;
            lit[q] = sh_e[at];
        } else {
            uvec3 p = uvec3(min(2u * id.x + q % 3u, W() - 1u), min(2u * id.y + q / 3u, H() - 1u), eye);
            fv_surface sf = fv_gbuffer_surface(p);
            m = sf.hit ? sf.material + 1u : 0u;
            pos[q] = sf.hit ? sf.pos_world : vec3(0);
            nrm[q] = sf.hit ? sf.normal : vec3(0);
            alb[q] = sf.hit ? sf.albedo : vec3(0);
            lit[q] = direct_light(sf);
        }
        if (q == 0u) mat = m;
        same = same && m == mat;
        hits += m != 0u ? 1u : 0u;
        ps += pos[q];
        ns += nrm[q];
        as += alb[q];
        es += lit[q];
    }
    vec3 pm = ps / 9.0, am = as / 9.0, em = es / 9.0;
    bool coh = same;
    if (same && hits > 0u) {
        float len = length(ns) / 9.0;
        coh = len >= FV_INTERP_NORMAL_MIN && all_finite(pm);
        vec3 nm = coh ? normalize(ns) : vec3(0, 1, 0);
        float d = node_width_m(1u, eye, pm);
        for (uint q = 0u; q < 9u && coh; q++) coh = similar(pos[q], nrm[q], alb[q], lit[q], pm, nm, am, em, d);
    }
    store_node(1u, eye, id.xy, pm, ns / 9.0, am, em, mat, coh);
}

// Level k >= 2 from its four children at k - 1 (clamped at the last row and column: a duplicate changes nothing).
void build_node(uvec3 id)
{
    uint k = pc.level;
    uint nx = nodes_along(W(), k), ny = nodes_along(H(), k);
    if (id.x >= nx || id.y >= ny) return;
    uint eye = id.z;
    vec3 pos[4], nrm[4], alb[4], lit[4];
    uint mat = 0u;
    bool coh = true;
    vec3 ps = vec3(0), ns = vec3(0), as = vec3(0), es = vec3(0);
    for (uint c = 0u; c < 4u; c++) {
        uint i = FV_INTERP_NODE_VEC4 * node_index(k - 1u, eye, 2u * id.xy + uvec2(c & 1u, c >> 1u));
        vec4 a = nodes[i], b = nodes[i + 1u];
        lit[c] = nodes[i + 2u].xyz;
        es += lit[c];
        uint f = floatBitsToUint(a.w);
        uint m = f >> FV_INTERP_NODE_MATERIAL_SHIFT;
        if (c == 0u) mat = m;
        coh = coh && (f & FV_INTERP_NODE_COHERENT) != 0u && m == mat;
        pos[c] = a.xyz;
        float len = length(b.xyz);
        nrm[c] = len > 1e-20 ? b.xyz / len : vec3(0);
        alb[c] = unpackUnorm4x8(floatBitsToUint(b.w)).rgb;
        ps += a.xyz;
        ns += b.xyz;
        as += alb[c];
    }
    vec3 pm = ps * 0.25, am = as * 0.25, em = es * 0.25;
    if (coh && mat != 0u) {
        float len = length(ns) * 0.25;
        coh = len >= FV_INTERP_NORMAL_MIN && all_finite(pm);
        vec3 nm = coh ? normalize(ns) : vec3(0, 1, 0);
        float d = node_width_m(k, eye, pm);
        for (uint c = 0u; c < 4u && coh; c++) coh = similar(pos[c], nrm[c], alb[c], lit[c], pm, nm, am, em, d);
    }
    store_node(k, eye, id.xy, pm, ns * 0.25, am, em, mat, coh);
}

// Node (k, eye, ij) holds pixels at level k: coh, and its parent is not (or k is the start level).
bool accepted(uint k, uint eye, uvec2 ij)
{
    if (!node_coherent(k, eye, ij)) return false;
    return k >= pc.start_level || !node_coherent(k + 1u, eye, ij >> 1u);
}

// The node columns (or rows) of level k that have pixel column x as a corner column, as a range [lo, hi] (lo > hi:
// none): x = i s is the left corner of node i and the right corner of node i - 1; the last pixel is the (clamped)
// right corner of the last node.
uvec2 corner_nodes(uint x, uint n, uint k)
{
    uint count = nodes_along(n, k);
    uint lo = 1u, hi = 0u;
    if ((x & ((1u << k) - 1u)) == 0u) {
        uint i = x >> k;
        lo = i > 0u ? i - 1u : 0u;
        hi = min(i, count - 1u);
    }
    if (x == n - 1u) {
        lo = min(lo, count - 1u);
        hi = lo > hi ? count - 1u : max(hi, count - 1u);
    }
    return uvec2(lo, hi);
}

// Is pixel p a corner of any accepted node?
bool corner_of_accepted(uvec3 p)
{
    for (uint k = 1u; k <= pc.start_level; k++) {
        uvec2 cx = corner_nodes(p.x, W(), k), cy = corner_nodes(p.y, H(), k);
        if (cx.x > cx.y || cy.x > cy.y) break; // off the grid of level k, so off every coarser one too
        for (uint j = cy.x; j <= cy.y; j++)
            for (uint i = cx.x; i <= cx.y; i++)
                if (accepted(k, p.z, uvec2(i, j))) return true;
    }
    return false;
}

// A pixel's code (FV_INTERP_CODE_*).
uint classify(uvec3 p)
{
    uint level = 0u;
    for (uint k = pc.start_level; k >= 1u; k--)
        if (node_coherent(k, p.z, p.xy >> k)) {
            level = k;
            break;
        }
    // the last column and row: the node index is clamped, the pixel is a corner (shaded below)
    if (level > 0u && (p.x == W() - 1u || p.y == H() - 1u || ((p.x | p.y) & ((1u << level) - 1u)) == 0u))
        return level | FV_INTERP_CODE_SHADED;
    if (corner_of_accepted(p)) return level | FV_INTERP_CODE_SHADED;
    if (level > 0u) return level | FV_INTERP_CODE_FILLED;
    bool listed = (pc.flags & FV_INTERP_FLAG_GIVEN) == 0u || given[(p.z * H() + p.y) * W() + p.x] != 0u;
    return listed ? FV_INTERP_CODE_SHADED : FV_INTERP_CODE_LEFT;
}

// The tile's first pixel and eye (the divisions once per tile, not per pixel: they are slow on a CPU's vectors).
uvec3 tile_origin(uint tile)
{
    uint per_eye = pc.tiles_x * pc.tiles_y;
    uint t = tile % per_eye;
    return uvec3(uvec2(t % pc.tiles_x, t / pc.tiles_x) * FV_INTERP_TILE, tile / per_eye);
}

void write_args(uint count)
{
    list.count = count;
    uint groups = (count + FV_GPU_LIST_GROUP_SIZE - 1u) / FV_GPU_LIST_GROUP_SIZE;
    ind.args[0] = groups == 0u ? 0u : min(groups, FV_GPU_LIST_GROUPS_X);
    ind.args[1] = groups == 0u ? 0u : (groups + FV_GPU_LIST_GROUPS_X - 1u) / FV_GPU_LIST_GROUPS_X;
    ind.args[2] = 1u;
    ind.args[3] = 0u;
}

void main()
{
    uint li = gl_LocalInvocationIndex;
    if (STAGE == FV_INTERP_STAGE_GIVEN) {
        // the earlier list as an indirect dispatch of its own arguments (FV_GPU_LIST_GROUP_SIZE entries a group)
        uint i = (gl_WorkGroupID.x + gl_WorkGroupID.y * FV_GPU_LIST_GROUPS_X) * FV_GPU_LIST_GROUP_SIZE + li;
        if (i >= list.count || i >= uint(list.pixels.length())) return;
        uvec3 p = fv_pixel_unpack(list.pixels[i]);
        if (p.x < W() && p.y < H() && p.z <= 1u) given[(p.z * H() + p.y) * W() + p.x] = 1u;
        return;
    }
    if (STAGE == FV_INTERP_STAGE_LEAF || STAGE == FV_INTERP_STAGE_LEAF_SHARED) {
        build_leaf(gl_GlobalInvocationID);
        return;
    }
    if (STAGE == FV_INTERP_STAGE_NODE) {
        build_node(gl_GlobalInvocationID);
        return;
    }
    if (STAGE == FV_INTERP_STAGE_SCAN) {
        // exclusive prefix sum of the tile counts in the interleaved order: a chunk per thread, then the chunks
        uint entries = pc.tiles_per_stripe * FV_INTERP_STRIPES;
        uint chunk = (entries + FV_INTERP_TILE_SIZE - 1u) / FV_INTERP_TILE_SIZE;
        uint begin = min(li * chunk, entries), end = min(begin + chunk, entries);
        uint total = 0u;
        for (uint g = begin; g < end; g++) {
            uint tile = (g % FV_INTERP_STRIPES) * pc.tiles_per_stripe + g / FV_INTERP_STRIPES;
            if (tile < pc.tile_count) total += tiles[tile];
        }
        sh_sum[li] = total;
        barrier();
        if (li == 0u) {
            uint run = 0u;
            for (uint s = 0u; s < FV_INTERP_TILE_SIZE; s++) {
                uint c = sh_sum[s];
                sh_sum[s] = run;
                run += c;
            }
            write_args(min(run, uint(list.pixels.length())));
        }
        barrier();
        uint base = sh_sum[li];
        for (uint g = begin; g < end; g++) {
            uint tile = (g % FV_INTERP_STRIPES) * pc.tiles_per_stripe + g / FV_INTERP_STRIPES;
            if (tile >= pc.tile_count) continue;
            uint c = tiles[tile];
            tiles[tile] = base;
            base += c;
        }
        return;
    }
    // COUNT and SCATTER: one subgroup per tile, its lanes over the tile's pixels in runs of the subgroup size
    // (row-major), no barriers
    uint tile = (gl_WorkGroupID.x + gl_WorkGroupID.y * pc.groups_x) * gl_NumSubgroups + gl_SubgroupID;
    if (tile >= pc.tile_count) return;
    uint lane = gl_SubgroupInvocationID, step = gl_SubgroupSize;
    uvec3 origin = tile_origin(tile);
    if (STAGE == FV_INTERP_STAGE_COUNT) {
        uvec3 n = uvec3(0u); // shaded, filled, left
        for (uint k = lane; k < FV_INTERP_TILE_SIZE; k += step) {
            uvec3 p = origin + uvec3(k % FV_INTERP_TILE, k / FV_INTERP_TILE, 0u);
            if (p.x >= W() || p.y >= H()) continue;
            uint code = classify(p);
            imageStore(level_img, ivec3(p), uvec4(code));
            n += (code & FV_INTERP_CODE_SHADED) != 0u ? uvec3(1u, 0u, 0u)
                 : (code & FV_INTERP_CODE_FILLED) != 0u ? uvec3(0u, 1u, 0u) : uvec3(0u, 0u, 1u);
        }
        n = subgroupAdd(n);
        if (subgroupElect()) {
            tiles[tile] = n.x;
            for (uint i = 0u; i < 3u; i++)
                if (n[i] > 0u) atomicAdd(stats.counts[i], n[i]);
        }
        return;
    }
    // SCATTER: the tile's shaded pixels at its offset, in row-major order
    uint at = tiles[tile];
    for (uint k0 = 0u; k0 < FV_INTERP_TILE_SIZE; k0 += step) {
        uint k = k0 + lane;
        uvec3 p = origin + uvec3(k % FV_INTERP_TILE, k / FV_INTERP_TILE, 0u);
        bool shaded = k < FV_INTERP_TILE_SIZE && p.x < W() && p.y < H() &&
                      (imageLoad(level_img, ivec3(p)).x & FV_INTERP_CODE_SHADED) != 0u;
        uint v = shaded ? 1u : 0u;
        uint before = subgroupExclusiveAdd(v);
        if (shaded && at + before < uint(list.pixels.length())) list.pixels[at + before] = FV_GPU_PIXEL_PACK(p.x, p.y, p.z);
        at += subgroupAdd(v);
    }
}
