/* @brief Foveation passes' interface shared by C and GLSL (render/fovea): "fovea" makes the sampling map and the
 * sample mask (fovea.comp), "compact" turns the mask into the frame sample list (compact.comp), "reconstruct" fills
 * the unshaded pixels (reconstruct.comp). Bindings of their own sets (set 1, after the scene's), workgroup sizes,
 * stages (specialization constant 0), push constants. */
#ifndef FV_FOVEA_INTERFACE_H
#define FV_FOVEA_INTERFACE_H

#if defined(GL_core_profile) || defined(VULKAN) || defined(GL_SPIRV)
#define FV_FOVEA_UINT uint
#else
#include <stdint.h>
#define FV_FOVEA_UINT uint32_t
#endif

#include "fv_sample_mask_interface.h" /* the mask's values and block bits, shared with interpolation */

/* ---- "fovea": the sampling map (fovea.comp) ---- */
#define FV_FOVEA_SET 1
#define FV_FOVEA_BINDING_PROB 0  /* image2DArray r32f: sampling probability p per pixel (written) */
#define FV_FOVEA_BINDING_MASK 1  /* uimage2DArray r32ui: the sample mask (fv_sample_mask_interface.h): SHADED =
                                  * shade this pixel, UNKNOWN = reconstruct it (written) */
#define FV_FOVEA_BINDING_RANKS 2 /* storage uint[B * B]: rank of each pixel of a block in the R2 order (no turn);
                                  * from FV_FOVEA_SRGB_TABLE on, 256 floats (as bits): 8-bit sRGB -> linear */
#define FV_FOVEA_SRGB_TABLE 256u
#define FV_FOVEA_BINDING_BLOCKS 3 /* uimage2DArray r32ui, (blocks_x * words) x blocks_y: each block's samples as
                                   * bits (bit k = its pixel k, row-major, B as the row length), cleared, then
                                   * OR-ed in (atomics) */
#define FV_FOVEA_BINDING_DEPTH 4  /* G-buffer depth, normal, albedo, material: combined samplers 4..7 (saliency, DoF) */
#define FV_FOVEA_BINDING_MOTION 8 /* image2DArray rgba32f: the G-buffer's surface target, motion in rg (storage loads) */
#define FV_FOVEA_BINDING_COUNT 9
#define FV_FOVEA_BLOCK_WORDS_MAX 8u /* ceil(16 * 16 / 32) */
#define FV_FOVEA_GROUP 8 /* 8 x 8 pixels per workgroup, z = the eye */
#define FV_FOVEA_BLOCK_MAX 16u

/* No valid gaze: the fovea is the view centre (straight ahead), widened by this angle as if it were the gaze's
 * uncertainty (with or without fovea.uncertainty). */
#define FV_FOVEA_LOST_WIDEN_RAD 0.2617993877991494 /* 15 degrees */

#define FV_FOVEA_FLAG_UNCERTAINTY 1u /* e' = max(0, e - u) */
#define FV_FOVEA_FLAG_SALIENCY 2u    /* p = max(p, saliency S) (fovea.saliency > 0) */
#define FV_FOVEA_FLAG_DOF 4u         /* the eye's defocus blur widens the MAR (fovea.dof, and a pupil size known) */

/* Saliency S = max(S_albedo, S_normal, S_motion) in [0, 1] (papers/README.md section 3), each over the 8
 * neighbours: S_albedo = max CIELAB (D65) Delta E*ab of the linear albedo / FV_FOVEA_SAL_DELTA_E; S_normal = max
 * (1 - n.n') / FV_FOVEA_SAL_NORMAL, 1 where a neighbour is on the other side of a silhouette (drawn / not drawn);
 * S_motion = the object's own motion (the G-buffer's motion less what the head's motion alone makes of the pixel's
 * point), px per frame / FV_FOVEA_SAL_MOTION_PX; each clamped to 1. */
#define FV_FOVEA_SAL_DELTA_E 25.0
#define FV_FOVEA_SAL_NORMAL 0.5
#define FV_FOVEA_SAL_MOTION_PX 4.0
/* Depth of field: an eye of pupil A focused at d_f (the surface at the gaze) blurs a point at d over the angle
 * c = A |1/d - 1/d_f| (radians; 1/d = 0 where nothing is drawn); it resolves no finer than that, so w' = max(w, c)
 * and the saliency term is scaled by clamp(1 - (c - w_min) / w_far, 0, 1). No pupil (0), no valid gaze, or a gaze
 * off the image or on nothing drawn: no DoF. Distances below FV_FOVEA_DOF_MIN_M count as that. */
#define FV_FOVEA_DOF_MIN_M 1e-3

/* p = clamp(1 - (w - w_min) / w_far, xi, 1), w = m e' + w0 (degrees): w_min = max(w0, w_px), the display's
 * smallest resolvable angle (p = 1 while the eye resolves a pixel), and w_far = (FV_FOVEA_FAR_PX - 1) w_px, so p
 * reaches 0 where the eye's MAR spans FV_FOVEA_FAR_PX pixels (one sample per 4 x 4 pixels is all it resolves
 * there); w_px is the angle of the view's centre pixel, 2 atan(dt / 2), dt the smaller of its tangent steps. */
#define FV_FOVEA_FAR_PX 4.0
struct fv_fovea_push {
    FV_FOVEA_UINT block;    /* fovea.block, px */
    FV_FOVEA_UINT flags;    /* FV_FOVEA_FLAG_* */
    float mar_slope;        /* fovea.mar_slope, deg / deg */
    float mar_w0_deg;       /* fovea.mar_w0_deg */
    float min_prob;         /* fovea.min_prob (xi) */
    FV_FOVEA_UINT block_words; /* ceil(B * B / 32): words per block in the block masks */
    float saliency;         /* fovea.saliency: the weight of S (FV_FOVEA_FLAG_SALIENCY) */
    FV_FOVEA_UINT pad;
};

/* ---- "compact": the sample mask as the frame sample list (compact.comp) ---- */
#define FV_COMPACT_SET 1
#define FV_COMPACT_BINDING_MASK 0     /* uimage2DArray r32ui (read) */
#define FV_COMPACT_BINDING_SUMS 1     /* storage uint[rows]: rows mode: samples per row, then each row's offset */
#define FV_COMPACT_BINDING_LIST 2     /* storage pixel list (fv_gpu.h FV_GPU_LIST_*): the frame sample list */
#define FV_COMPACT_BINDING_INDIRECT 3 /* storage uint[4]: the list's VkDispatchIndirectCommand */
#define FV_COMPACT_BINDING_STATS 4    /* storage uint[4]: samples of eye 0, eye 1 (host-read after the fence) */
#define FV_COMPACT_BINDING_COUNT 5

#define FV_COMPACT_STAGE_TILES 0  /* per 8x8 tile (64 threads): append its samples, one atomic per tile */
#define FV_COMPACT_STAGE_ROWS 1   /* per image row (64 threads): count (pass 0) or scatter at its offset (pass 1) */
#define FV_COMPACT_STAGE_FINISH 2 /* one workgroup: rows: scan of the row counts; all: count, dispatch arguments */
#define FV_COMPACT_TILE 8
#define FV_COMPACT_TILE_SIZE (FV_COMPACT_TILE * FV_COMPACT_TILE)
#define FV_COMPACT_GROUP 64u      /* threads of the tile and row workgroups */
#define FV_COMPACT_FINISH_SIZE 256u

/* push.mode: how the list is made (knob fovea.compaction, fv_fovea_compaction) */
#define FV_COMPACT_MODE_TILES 0u  /* per tile, appended by one atomic per tile (tile order within, any order across) */
#define FV_COMPACT_MODE_ROWS 1u   /* the paper's row-wise (CSR) reorder: row counts, a prefix sum, rows in order */
#define FV_COMPACT_MODE_MASKED 2u /* every pixel in the full-frame tile order, unsampled ones masked out */
/* A masked list entry: layer 3, which the shading skips (it shades layers 0 and 1 only). */
#define FV_COMPACT_MASKED_LAYER 3u

/* Tiles are visited in an interleaved order (as the shade pass's full frame): workgroup g takes tile
 * (g % stripes) * tiles_per_stripe + g / stripes, so any contiguous half of a dispatch (one lavapipe thread's share)
 * covers both eyes and the whole image. In masked mode the list is in this order, so each half of the shading
 * dispatch gets its share of the fovea; the other modes' lists are dense, and any half of them holds half the
 * samples. */
#define FV_COMPACT_STRIPES 32u

struct fv_compact_push {
    FV_FOVEA_UINT tiles_x, tiles_y; /* per eye */
    FV_FOVEA_UINT tile_count;       /* tiles_x * tiles_y * 2 */
    FV_FOVEA_UINT tiles_per_stripe; /* ceil(tile_count / FV_COMPACT_STRIPES) */
    FV_FOVEA_UINT entries;          /* tiles_per_stripe * FV_COMPACT_STRIPES: tile-order slots (some empty) */
    FV_FOVEA_UINT groups_x;         /* dispatch width (workgroups are linearised as x + y * groups_x) */
    FV_FOVEA_UINT mode;             /* FV_COMPACT_MODE_* */
    FV_FOVEA_UINT pass;             /* rows stage: 0 count, 1 scatter */
};

/* ---- "reconstruct": the fill of the unknown pixels from the known ones (reconstruct.comp): nearest or sibson
 * over a Voronoi (jump flooding or the block search), idw, or the soft fill ---- */
#define FV_RECON_SET 1
#define FV_RECON_BINDING_MASK 0    /* uimage2DArray r32ui (read) */
#define FV_RECON_BINDING_SEEDS_A 1 /* storage uint[2 W H] (eye, row, column): nearest seed so far, x | y << 16, or
                                    * FV_RECON_NONE (buffers: much cheaper than storage images on lavapipe) */
#define FV_RECON_BINDING_SEEDS_B 2 /* its ping-pong partner */
#define FV_RECON_BINDING_COLOR 3   /* image2DArray rgba32f: linear colour (unsampled pixels written) */
#define FV_RECON_BINDING_VORONOI 4 /* uimage2DArray r32ui: the final nearest seed of every pixel (written by resolve;
                                    * the voronoi view and the tests read it; soft writes its nearest
                                    * representative only for the voronoi view, FV_RECON_FLAG_VORONOI) */
#define FV_RECON_BINDING_BLOCKS 5  /* uimage2DArray r32ui: the fovea pass's block masks (read) */
#define FV_RECON_BINDING_DEPTH 6   /* G-buffer depth, normal, albedo, material: combined samplers 6..9 (soft) */
#define FV_RECON_BINDING_REPS 10   /* uimage2DArray rgba32ui: soft's slots, FV_RECON_SOFT_REP_UVEC4S texels per block
                                    * in a row (an image: cheaper loads than a buffer on lavapipe) */
#define FV_RECON_BINDING_MOTION 11 /* image2DArray rgba32f: the G-buffer's surface target, whose distance and normal the
                                    * soft fill reads (fv_gbuffer_fovea: one fetch) */
#define FV_RECON_BINDING_LISTS 12 /* storage uint[]: the soft fill's two pixel lists (FV_RECON_LIST_*), then the
                                   * indirect dispatch arguments of each (4 uints per list) */
#define FV_RECON_BINDING_COUNT 13
#define FV_RECON_NONE 0xffffffffu

#define FV_RECON_STAGE_INIT 0    /* seeds A and B = the sampled pixels (a seed is its own nearest: steps skip it) */
#define FV_RECON_STAGE_STEP 1    /* one jump-flooding step of size `step` from seeds[src] to the other */
/* Fill the unsampled pixels (push.method): only they are written and only sampled pixels are read, so the colour
 * is read and written in place. */
#define FV_RECON_STAGE_RESOLVE 2
#define FV_RECON_STAGE_BLOCKS 3  /* seeds A = every pixel's exact nearest sample, from the neighbouring block masks */
/* The soft fill (FV_RECON_METHOD_SOFT), two dispatches, no Voronoi, a bounded number of taps per pixel:
 * SOFT_REPS, one thread per block: per quadrant of the block a slot, the block's known pixel nearest the quadrant's
 * centre (in a sparse block one sample fills every slot), with its colour, position, unit normal (octahedral,
 * 2x16 snorm) and tangent plane's offset n.x, and the block's sigma (below), into the "fovea soft reps" image;
 * SOFT_FILL, one thread per unknown pixel (a list, below): every unknown pixel takes the weighted mean of the 2x2 blocks whose centres
 * surround it, of each the slot of its quadrant that faces the pixel (the four facing quadrants tile the square
 * between the four centres, so the choice never changes inside it): 4 taps.
 * w = b_k exp(-d^2 / (2 sigma^2)) max(g, FV_RECON_SOFT_EDGE_FLOOR), b_k the bilinear tent of block k over the block
 * grid (its weight reaches 0 exactly where the 2x2 set changes: no seams at block edges); sigma = the tents' blend
 * of the 4 blocks' sigmas, each FV_RECON_SOFT_SIGMA times the local sample spacing, sqrt(area / known pixels) of the
 * 3x3 blocks around it, at least FV_RECON_SOFT_SIGMA_MIN px (the band limit of the local sampling rate), and for
 * the facing slots at least FV_RECON_SOFT_SIGMA times their spacing, half a block; the edge weight
 * g = exp(-(t / (d foot FV_RECON_SOFT_PLANE))^2 - (1 - n.n') / FV_RECON_SOFT_NORMAL), t the pixel's distance from
 * the tap's tangent plane, foot the pixel's footprint (its distance from the eye times the angle of a pixel), n, n'
 * the normals (G-buffer guided); drawn against nothing drawn, or a tap of another material than the pixel's (the
 * G-buffer's material id: an emissive light on a wall is the wall's plane, not its colour): g = 0, both nothing: 1.
 * At an edge (a facing slot's
 * -log g over FV_RECON_SOFT_EDGE_SPLIT) the pixel takes every distinct slot of the four blocks instead (at most
 * 16 taps, sigma the sample spacing's; SOFT_EDGE): the same surface is found where the facing slots miss it. No weight at all
 * (underflow): the nearest tap's colour. Reads the colour only at known pixels and writes it only at unknown ones. */
#define FV_RECON_STAGE_SOFT_REPS 4
#define FV_RECON_STAGE_SOFT_FILL 5
/* On a device that runs every branch of a shader for every invocation (llvmpipe: control flow is masks), the fill
 * pays for its whole code at every pixel, known or not, edge or not. So the fill runs over lists: SOFT_REPS also
 * appends each block's unknown pixels to list 0; SOFT_ARGS (one thread, push.step = the list) turns a list's count
 * into its indirect dispatch; SOFT_FILL, over list 0, fills a pixel from the facing slots or, at an edge, appends it
 * to list 1; SOFT_EDGE, over list 1, fills it from every distinct slot. The same arithmetic as one pass. */
#define FV_RECON_STAGE_SOFT_ARGS 6
#define FV_RECON_STAGE_SOFT_EDGE 7
#define FV_RECON_LIST_FILL 0u
#define FV_RECON_LIST_EDGE 1u
/* The lists' buffer, in uints: list l at l * (FV_RECON_LIST_HEADER + pixels) (its count, 3 spare, then packed
 * pixels, FV_GPU_PIXEL_PACK), the arguments at 2 * (FV_RECON_LIST_HEADER + pixels) + 4 l. */
#define FV_RECON_LIST_HEADER 4u
#define FV_RECON_SOFT_SLOTS 4
#define FV_RECON_SOFT_REP_UVEC4S 8 /* per block, per slot: (colour rgb as bits, x | y << 16 | FV_RECON_SOFT_NOTHING
                                    * where nothing was drawn; FV_RECON_NONE: no slot), (oct normal as 2x16 snorm,
                                    * n . world position as bits, the block's sigma as bits, the slot's material id
                                    * as the G-buffer's) */
#define FV_RECON_SOFT_NOTHING 0x80000000u
#define FV_RECON_SOFT_SIGMA 0.5
#define FV_RECON_SOFT_SIGMA_MIN 0.5
#define FV_RECON_SOFT_PLANE 2.0
#define FV_RECON_SOFT_NORMAL 0.1
#define FV_RECON_SOFT_EDGE_FLOOR 1e-3
#define FV_RECON_SOFT_EDGE_SPLIT 0.69314718 /* a facing slot with an edge weight under 1/2: every slot is read */
#define FV_RECON_GROUP 16

#define FV_RECON_METHOD_NEAREST 0u
#define FV_RECON_METHOD_SIBSON 1u
#define FV_RECON_METHOD_IDW 2u
#define FV_RECON_METHOD_SOFT 3u
#define FV_RECON_FLAG_VORONOI 1u /* soft: also write each pixel's nearest tap to "fovea voronoi" (its debug view) */
/* resolve without a Voronoi: each unsampled pixel searches the neighbouring blocks itself (nearest with blocks) */
#define FV_RECON_SRC_SEARCH 2u

struct fv_recon_push {
    FV_FOVEA_UINT step;   /* px */
    FV_FOVEA_UINT src;    /* 0: read seeds A (write B), 1: read B (write A); resolve: FV_RECON_SRC_SEARCH */
    FV_FOVEA_UINT method; /* FV_RECON_METHOD_* */
    FV_FOVEA_UINT window; /* sibson: the half side of the gather window, px (the jitter block) */
    FV_FOVEA_UINT block;  /* B, px */
    FV_FOVEA_UINT block_words;
    FV_FOVEA_UINT reach;  /* blocks: how many blocks around a pixel's own can hold its nearest sample (1: B <= 5) */
    FV_FOVEA_UINT flags;  /* FV_RECON_FLAG_* */
    FV_FOVEA_UINT list_pixels; /* soft: the capacity of each list, 2 W H */
    FV_FOVEA_UINT pad[3];
};


/* ---- "temporal": reprojection of the previous frame's known pixels (temporal.comp) ---- */
/* The linear colour's alpha, from the temporal pass on, holds per pixel what temporal reuse needs to know of it in
 * the next frame: the distance from the eye to the surface (metres, FV_TEMPORAL_SKY where nothing was drawn) whose 4
 * lowest mantissa bits hold the frames since the pixel was last shaded (its age, 0..15); a = 0: nothing known (a
 * pixel reconstruction filled). Known pixels (shaded, blended with history, or reused) get it from the temporal
 * pass, filled ones 0 from reconstruction, which then copies the frame's colour into the history (the renderer's
 * FV_IMAGE_HISTORY): the next frame's temporal pass reads it. One copy, no full-screen store of a history of its
 * own (on lavapipe a store per pixel costs about 2x a present pass, the copy a fraction of one). */
#define FV_TEMPORAL_SET 1
#define FV_TEMPORAL_BINDING_DEPTH 0    /* G-buffer depth, normal, albedo, material: combined samplers 0..3 */
#define FV_TEMPORAL_BINDING_MOTION 4   /* image2DArray rgba32f: the G-buffer's surface target (fv_gbuffer_fovea) */
#define FV_TEMPORAL_BINDING_MASK 5     /* uimage2DArray r32ui "fovea mask": 1 shaded; written 2 = reused here */
#define FV_TEMPORAL_BINDING_BLOCKS 6   /* uimage2DArray r32ui "fovea blocks": reused pixels' bits OR-ed in */
#define FV_TEMPORAL_BINDING_COLOR 7    /* image2DArray rgba32f: linear colour (known pixels: alpha = the history's) */
#define FV_TEMPORAL_BINDING_PREV 8     /* image2DArray rgba32f: the history, the previous frame's colour (read) */
#define FV_TEMPORAL_BINDING_STATS 9    /* storage uint[4 per frame slot]: hits eye 0, 1, reused eye 0, 1 */
#define FV_TEMPORAL_BINDING_COUNT 10
#define FV_TEMPORAL_GROUP 16


#define FV_TEMPORAL_MASK_REUSED FV_SAMPLE_MASK_REUSED /* a "fovea mask" value (fv_sample_mask_interface.h) */
#define FV_TEMPORAL_AGE_BITS 4u
#define FV_TEMPORAL_AGE_MAX 15u
#define FV_TEMPORAL_SKY 1.0e30      /* the history distance of a pixel where nothing was drawn */
/* The paper's cache test, |d_{t-1}(reprojected) - |pos_t - eye_{t-1}|| < eps, with eps relative to the distance
 * plus what the surface's slope makes one pixel's footprint vary over the bilinear tap's offset. */
#define FV_TEMPORAL_DEPTH_EPS 0.01
#define FV_TEMPORAL_SLOPE_TAN_MAX 8.0
/* A sampled pixel with a history hit: radiance = mix(history clamped to shaded * (1 +- CLAMP_REL) +- CLAMP_ABS,
 * shaded, this weight). */
#define FV_TEMPORAL_SAMPLE_WEIGHT 0.5
#define FV_TEMPORAL_CLAMP_REL 0.1
#define FV_TEMPORAL_CLAMP_ABS 0.001
/* A head jump between two frames that resets the history (faster than a head turns or moves within a frame). */
#define FV_TEMPORAL_JUMP_DEG 20.0
#define FV_TEMPORAL_JUMP_M 0.25

#define FV_TEMPORAL_FLAG_HISTORY 1u /* the previous frame's history is valid (else: every pixel misses) */
struct fv_temporal_push {
    float prev_eye[2][4];        /* the previous frame's eye positions, world metres (xyz) */
    FV_FOVEA_UINT flags;         /* FV_TEMPORAL_FLAG_* */
    FV_FOVEA_UINT max_age;       /* fovea.temporal: frames a pixel may be reused since it was last shaded */
    FV_FOVEA_UINT stats_base;    /* this slot's first stats word */
    FV_FOVEA_UINT block;         /* B, px */
    FV_FOVEA_UINT block_words;
    FV_FOVEA_UINT pad[3];
};

#endif
