#version 450
// @brief Reconstruction of the pixels foveation did not shade: each takes the colour of its nearest shaded pixel
// (the seeds), found by jump flooding (Rong & Tan 2006) in its 1+JFA form: one step of size 1, then steps from the
// block size down to 1 (every block holds a seed, so no seed is farther than two blocks). Seeds ping-pong between
// two R32UI images; distances are exact integer squared distances, ties go to the smaller packed seed.
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fovea_interface.h"

layout(local_size_x = FV_RECON_GROUP, local_size_y = FV_RECON_GROUP, local_size_z = 1) in;
layout(constant_id = 0) const uint STAGE = FV_RECON_STAGE_INIT;

FV_SCENE_SET_DECLARE
layout(set = FV_RECON_SET, binding = FV_RECON_BINDING_MASK, r32ui) uniform readonly uimage2DArray mask_img;
layout(set = FV_RECON_SET, binding = FV_RECON_BINDING_SEEDS_A, r32ui) uniform uimage2DArray seeds_a;
layout(set = FV_RECON_SET, binding = FV_RECON_BINDING_SEEDS_B, r32ui) uniform uimage2DArray seeds_b;
layout(set = FV_RECON_SET, binding = FV_RECON_BINDING_COLOR, rgba32f) uniform image2DArray color_img;
layout(push_constant) uniform Push { fv_recon_push pc; };

uint read_seed(ivec3 c) { return pc.src == 0u ? imageLoad(seeds_a, c).x : imageLoad(seeds_b, c).x; }

uint dist2(uint s, ivec2 p)
{
    ivec2 d = ivec2(int(s & 0xffffu), int(s >> 16)) - p;
    return uint(d.x * d.x + d.y * d.y);
}

void main()
{
    ivec3 p = ivec3(gl_GlobalInvocationID);
    ivec2 size = ivec2(frame.counts.y, frame.counts.z);
    if (p.x >= size.x || p.y >= size.y || p.z > 1) return;
    if (STAGE == FV_RECON_STAGE_INIT) {
        bool s = imageLoad(mask_img, p).x != 0u;
        imageStore(seeds_a, p, uvec4(s ? uint(p.x) | (uint(p.y) << 16) : FV_RECON_NONE));
        return;
    }
    if (STAGE == FV_RECON_STAGE_STEP) {
        uint best = read_seed(p), bd = best == FV_RECON_NONE ? 0xffffffffu : dist2(best, p.xy);
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
        if (pc.src == 0u) imageStore(seeds_b, p, uvec4(best));
        else imageStore(seeds_a, p, uvec4(best));
        return;
    }
    // FV_RECON_STAGE_RESOLVE: only unsampled pixels are written and only sampled ones are read.
    if (imageLoad(mask_img, p).x != 0u) return;
    uint s = read_seed(p);
    if (s == FV_RECON_NONE) return;
    imageStore(color_img, p, imageLoad(color_img, ivec3(int(s & 0xffffu), int(s >> 16), p.z)));
}
