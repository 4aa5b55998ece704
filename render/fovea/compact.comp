#version 450
// @brief The sample mask as the frame sample list (fovea_interface.h FV_COMPACT_*), in one of three orders:
// tiles: each 8x8 tile's samples in tile order, one subgroup per tile, its offset taken by one atomic per tile and
// its samples ordered by subgroup scans; rows: the paper's row-wise (CSR) reorder, a count per image row, an
// exclusive prefix sum of the rows, each row's samples in order at its offset; masked: every pixel in the full-frame
// tile order, unsampled ones marked so the shading skips them. No barriers outside the one finishing workgroup. Counts per eye go to the
// stats buffer; the finishing workgroup writes the count and the indirect dispatch.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fovea_interface.h"

layout(local_size_x_id = 1, local_size_y = 1, local_size_z = 1) in;
layout(constant_id = 0) const uint STAGE = FV_COMPACT_STAGE_TILES;

FV_SCENE_SET_DECLARE
layout(set = FV_COMPACT_SET, binding = FV_COMPACT_BINDING_MASK, r32ui) uniform readonly uimage2DArray mask_img;
layout(std430, set = FV_COMPACT_SET, binding = FV_COMPACT_BINDING_SUMS) buffer Sums { uint sums[]; };
layout(std430, set = FV_COMPACT_SET, binding = FV_COMPACT_BINDING_LIST) buffer List {
    uint count;
    uint pad0, pad1, pad2;
    uint pixels[];
} list;
layout(std430, set = FV_COMPACT_SET, binding = FV_COMPACT_BINDING_INDIRECT) buffer Indirect { uint args[4]; } ind;
layout(std430, set = FV_COMPACT_SET, binding = FV_COMPACT_BINDING_STATS) buffer Stats { uint eye_samples[4]; } stats;
layout(push_constant) uniform Push { fv_compact_push pc; };

shared uint sh_sub[FV_COMPACT_FINISH_SIZE]; // the finishing workgroup's per-thread totals
shared uint sh_base;

bool mask_at(uvec3 p) { return imageLoad(mask_img, ivec3(p)).x != 0u; }

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
    uint W = frame.counts.y, H = frame.counts.z;
    if (STAGE == FV_COMPACT_STAGE_FINISH) {
        if (pc.pass == 0u) { // before the list is made: no samples yet
            if (li == 0u) list.count = 0u;
            if (li < 4u) stats.eye_samples[li] = 0u;
            return;
        }
        if (pc.mode != FV_COMPACT_MODE_ROWS) {
            if (li == 0u) write_args(pc.mode == FV_COMPACT_MODE_MASKED ? pc.entries * FV_COMPACT_TILE_SIZE : list.count);
            return;
        }
        // exclusive prefix sum of the 2H row counts: a chunk per thread, then the chunk totals
        uint rows = 2u * H;
        uint chunk = (rows + FV_COMPACT_FINISH_SIZE - 1u) / FV_COMPACT_FINISH_SIZE;
        uint begin = min(li * chunk, rows), end = min(begin + chunk, rows);
        uint total = 0u;
        for (uint k = begin; k < end; k++) total += sums[k];
        sh_sub[li] = total;
        barrier();
        if (li == 0u) {
            uint run = 0u;
            for (uint s = 0u; s < FV_COMPACT_FINISH_SIZE; s++) {
                uint c = sh_sub[s];
                sh_sub[s] = run;
                run += c;
            }
            sh_base = run;
        }
        barrier();
        uint base = sh_sub[li];
        for (uint k = begin; k < end; k++) {
            uint c = sums[k];
            sums[k] = base;
            base += c;
        }
        if (li == 0u) write_args(sh_base);
        return;
    }
    // Tiles and rows: one subgroup per tile or row, no barriers. Its lanes walk the pixels in runs of the subgroup
    // size (row-major in a tile: one tile row per run at subgroup size 8), a subgroup scan orders each run.
    uint unit = (gl_WorkGroupID.x + gl_WorkGroupID.y * pc.groups_x) * gl_NumSubgroups + gl_SubgroupID;
    uint lane = gl_SubgroupInvocationID, step = gl_SubgroupSize;
    if (STAGE == FV_COMPACT_STAGE_ROWS) {
        uint row = unit; // rows of eye 0, then eye 1
        if (row >= 2u * H) return;
        uint layer = row / H, y = row % H;
        if (pc.pass == 0u) {
            uint v = 0u;
            for (uint x = lane; x < W; x += step) v += mask_at(uvec3(x, y, layer)) ? 1u : 0u;
            uint total = subgroupAdd(v);
            if (subgroupElect()) {
                sums[row] = total;
                if (total > 0u) atomicAdd(stats.eye_samples[layer], total);
            }
            return;
        }
        uint at = sums[row];
        for (uint x0 = 0u; x0 < W; x0 += step) {
            uint x = x0 + lane;
            bool s = x < W && mask_at(uvec3(x, y, layer));
            uint v = s ? 1u : 0u;
            uint before = subgroupExclusiveAdd(v);
            if (s) list.pixels[at + before] = FV_GPU_PIXEL_PACK(x, y, layer);
            at += subgroupAdd(v);
        }
        return;
    }
    // FV_COMPACT_STAGE_TILES
    if (unit >= pc.entries) return;
    uint tile = (unit % FV_COMPACT_STRIPES) * pc.tiles_per_stripe + unit / FV_COMPACT_STRIPES;
    uint per_eye = pc.tiles_x * pc.tiles_y;
    uint layer = tile / per_eye, t = tile % per_eye;
    uvec2 origin = uvec2(t % pc.tiles_x, t / pc.tiles_x) * FV_COMPACT_TILE;
    bool real = tile < pc.tile_count;
    if (pc.mode == FV_COMPACT_MODE_MASKED) {
        // the shade pass's full-frame tile layout, one list workgroup per tile; unsampled entries skipped there
        uint n = 0u;
        for (uint k = lane; k < FV_COMPACT_TILE_SIZE; k += step) {
            uvec3 p = uvec3(origin + uvec2(k % FV_COMPACT_TILE, k / FV_COMPACT_TILE), layer);
            bool s = real && p.x < W && p.y < H && mask_at(p);
            n += s ? 1u : 0u;
            list.pixels[unit * FV_COMPACT_TILE_SIZE + k] = FV_GPU_PIXEL_PACK(p.x, p.y, s ? layer : FV_COMPACT_MASKED_LAYER);
        }
        uint total = subgroupAdd(n);
        if (subgroupElect() && total > 0u) atomicAdd(stats.eye_samples[layer], total);
        return;
    }
    if (!real) return;
    // count, one atomic for the tile's place in the list, then the samples in tile order
    uint bits = 0u, n = 0u; // this lane's pixels k = lane + i * step, i < 64 / step <= 32
    for (uint i = 0u, k = lane; k < FV_COMPACT_TILE_SIZE; i++, k += step) {
        uvec3 p = uvec3(origin + uvec2(k % FV_COMPACT_TILE, k / FV_COMPACT_TILE), layer);
        if (p.x < W && p.y < H && mask_at(p)) {
            bits |= 1u << i;
            n++;
        }
    }
    uint total = subgroupAdd(n);
    if (total == 0u) return;
    uint base = 0u;
    if (subgroupElect()) {
        base = atomicAdd(list.count, total);
        atomicAdd(stats.eye_samples[layer], total);
    }
    uint at = subgroupBroadcastFirst(base);
    for (uint i = 0u, k = lane; k < FV_COMPACT_TILE_SIZE; i++, k += step) {
        uint v = (bits >> i) & 1u;
        uint before = subgroupExclusiveAdd(v);
        if (v != 0u) list.pixels[at + before] = FV_GPU_PIXEL_PACK(origin.x + k % FV_COMPACT_TILE,
                                                                  origin.y + k / FV_COMPACT_TILE, layer);
        at += subgroupAdd(v);
    }
}
