/* @brief Foveation passes' interface shared by C and GLSL (render/fovea: "fovea" makes the sampling map and the
 * compacted sample list, "reconstruct" fills the unshaded pixels): bindings of their own sets (set 1, after the
 * scene's), workgroup sizes, stages (specialization constant 0), push constants. */
#ifndef FV_FOVEA_INTERFACE_H
#define FV_FOVEA_INTERFACE_H

/* ---- "fovea": sampling map and compaction (fovea.comp) ---- */
#define FV_FOVEA_SET 1
#define FV_FOVEA_BINDING_PROB 0     /* image2DArray r32f: sampling probability p per pixel (written) */
#define FV_FOVEA_BINDING_MASK 1     /* uimage2DArray r32ui: 1 = shade this pixel, 0 = reconstruct it */
#define FV_FOVEA_BINDING_SUMS 2     /* storage uint[entries]: samples per tile, then (scan) each tile's list offset */
#define FV_FOVEA_BINDING_LIST 3     /* storage pixel list (fv_gpu.h FV_GPU_LIST_*): the frame sample list */
#define FV_FOVEA_BINDING_INDIRECT 4 /* storage uint[4]: the list's VkDispatchIndirectCommand */
#define FV_FOVEA_BINDING_COUNT 5

#define FV_FOVEA_STAGE_MAP 0     /* per 8x8 tile: p, the mask, the tile's sample count */
#define FV_FOVEA_STAGE_SCAN 1    /* one workgroup: exclusive prefix sum of the tile counts, list count, dispatch */
#define FV_FOVEA_STAGE_SCATTER 2 /* per 8x8 tile: write the tile's samples at its offset (local scan) */

#define FV_FOVEA_TILE 8                                /* tiles of 8 x 8 pixels, one workgroup each */
#define FV_FOVEA_TILE_SIZE (FV_FOVEA_TILE * FV_FOVEA_TILE)
#define FV_FOVEA_SCAN_SIZE 256                         /* threads of the scan workgroup */
/* The list is in tile order g -> tile (g % stripes) * tiles_per_stripe + g / stripes (as the shade pass's full
 * frame), so any contiguous half of the list (one lavapipe thread's share of its dispatch) covers both eyes and
 * the whole image: each half gets its share of the fovea. */
#define FV_FOVEA_STRIPES 32u

/* No valid gaze: the fovea is the view centre (straight ahead), widened by this angle as if it were the gaze's
 * uncertainty (with or without fovea.uncertainty). */
#define FV_FOVEA_LOST_WIDEN_RAD 0.2617993877991494 /* 15 degrees */

#if defined(GL_core_profile) || defined(VULKAN) || defined(GL_SPIRV)
#define FV_FOVEA_UINT uint
#else
#include <stdint.h>
#define FV_FOVEA_UINT uint32_t
#endif

#define FV_FOVEA_FLAG_UNCERTAINTY 1u /* e' = max(0, e - u) */

struct fv_fovea_push {
    FV_FOVEA_UINT tiles_x, tiles_y; /* per eye */
    FV_FOVEA_UINT tile_count;       /* tiles_x * tiles_y * 2 */
    FV_FOVEA_UINT tiles_per_stripe; /* ceil(tile_count / FV_FOVEA_STRIPES) */
    FV_FOVEA_UINT entries;          /* tiles_per_stripe * FV_FOVEA_STRIPES: tile-order slots (some empty) */
    FV_FOVEA_UINT groups_x;         /* dispatch width (workgroups are linearised as x + y * groups_x) */
    FV_FOVEA_UINT block;            /* fovea.block, px */
    FV_FOVEA_UINT flags;            /* FV_FOVEA_FLAG_* */
    float mar_slope;                /* fovea.mar_slope, deg / deg */
    float mar_w0_deg;               /* fovea.mar_w0_deg */
    float min_prob;                 /* fovea.min_prob (xi) */
    float pad;
};

/* ---- "reconstruct": nearest sample by jump flooding (reconstruct.comp) ---- */
#define FV_RECON_SET 1
#define FV_RECON_BINDING_MASK 0    /* uimage2DArray r32ui (read) */
#define FV_RECON_BINDING_SEEDS_A 1 /* uimage2DArray r32ui: nearest seed so far, x | y << 16, or FV_RECON_NONE */
#define FV_RECON_BINDING_SEEDS_B 2 /* its ping-pong partner */
#define FV_RECON_BINDING_COLOR 3   /* image2DArray rgba32f: linear colour (unsampled pixels written) */
#define FV_RECON_BINDING_COUNT 4
#define FV_RECON_NONE 0xffffffffu

#define FV_RECON_STAGE_INIT 0    /* seeds A = the sampled pixels */
#define FV_RECON_STAGE_STEP 1    /* one jump-flooding step of size `step` from seeds[src] to the other */
#define FV_RECON_STAGE_RESOLVE 2 /* unsampled pixels take their seed's colour from seeds[src] */
#define FV_RECON_GROUP 8

struct fv_recon_push {
    FV_FOVEA_UINT step; /* px */
    FV_FOVEA_UINT src;  /* 0: read seeds A (write B), 1: read B (write A) */
    FV_FOVEA_UINT pad[2];
};

#endif
