/* @brief Hierarchical screen-space interpolation's interface shared by C and GLSL (render/interp): "interp" builds
 * the pyramid, classifies every pixel and makes the frame sample list (interp.comp, one pipeline per stage by
 * specialization constant 0); "interp_fill" fills the interpolated pixels after shading and draws `--view interp`
 * (interp_fill.comp). Bindings of their own sets (interp: set 2, after the scene's and the shading inputs'; fill:
 * set 1), workgroup sizes, push constants.
 *
 * The pyramid. A node of level k (1..FV_INTERP_MAX_LEVEL, spacing s = 2^k px) of an eye is the CLOSED square of
 * pixels [i s, min((i+1) s, W-1)] x [j s, min((j+1) s, H-1)]: its four corner pixels lie on the grid of spacing s,
 * so neighbouring nodes share their corners and the union of a node's four children (level k-1) is the node.
 * Level 1 is built from the 3x3 pixels of the G-buffer, level k from the four children at k-1. Nodes per row:
 * nx_k = max(1, ceil((W-1) / s)), per column likewise. A node stores the mean world position, the mean normal, the
 * mean albedo, the material seen (or "nothing drawn") and whether it is coherent: every member (pixel at level 1,
 * child node above) has the node's material, and with τ = interp.threshold (dimensionless)
 *     1 − n_i · n̄ ≤ τ                 (normal: one minus the cosine of the angle to the mean normal n̄, unit)
 *     |(p_i − p̄) · n̄| ≤ τ · w_k        (position: distance off the mean tangent plane, in node widths: w_k = 2^k
 *                                       pixels at the eye distance |p̄ − eye|, from the frustum's pixel step)
 *     max_c |a_i,c − ā_c| ≤ τ          (albedo, linear, per channel: texture edges are not blurred)
 *     max_c |E_i,c − Ē_c| ≤ τ max_c Ē_c (with interp.light: the direct irradiance, shadows included, so shadow edges
 *                                       and spot-light cones are not interpolated across; the paper has no such test)
 * and at level k ≥ 2 every child is coherent itself. A node where nothing is drawn throughout is coherent.
 *
 * Classification (coarse to fine, as the paper): a pixel belongs to the node (x >> k, y >> k) of each level; its
 * level is the coarsest k <= interp.start_level whose node is coherent (0: none), and that node is ACCEPTED (coherent,
 * with a parent that is not, or at the start level). A pixel is SHADED when it is a corner of any accepted node (it
 * lies on that node's grid: a multiple of s, or the clamped last column or row), when its level is 0, or when its
 * level is >= 1 and it lies on the image's last column or row (those W + H pixels keep the rule simple); every other
 * pixel (level k >= 1) is FILLED by bilinear interpolation of its accepted node's four corners, all of them shaded.
 * With a sample list already made for the frame (foveation), a level-0 pixel that is no corner is shaded only when
 * that list holds it, and otherwise LEFT to the pass that made the list (reconstruct) to fill; corners are shaded
 * whatever that list says, so every filled pixel's corners exist. Interpolation decides which pixels must be shaded,
 * foveation thins the per-pixel rest; after shading, interp_fill_mark marks the shaded pixels and the filled ones in
 * the frame's sample mask (fv_sample_mask_interface.h), so temporal reuse and reconstruction keep both. */
#ifndef FV_INTERP_INTERFACE_H
#define FV_INTERP_INTERFACE_H

#if defined(GL_core_profile) || defined(VULKAN) || defined(GL_SPIRV)
#define FV_INTERP_UINT uint
#else
#include <stdint.h>
#define FV_INTERP_UINT uint32_t
#endif

#define FV_INTERP_MAX_LEVEL 7u /* 128 x 128 px nodes at most */

/* ---- "interp" (interp.comp) ---- */
#define FV_INTERP_SET 2 /* after the scene set (0) and the shading inputs (1): the light test shades directly */
#define FV_INTERP_BINDING_DEPTH 0    /* sampler2DArray: the G-buffer (fv_images_bind_gbuffer writes 0..3) */
#define FV_INTERP_BINDING_NORMAL 1
#define FV_INTERP_BINDING_ALBEDO 2
#define FV_INTERP_BINDING_MATERIAL 3
#define FV_INTERP_BINDING_NODES 4    /* storage vec4[3 per node]: levels 1..MAX, eye 0 then eye 1, row-major */
#define FV_INTERP_NODE_VEC4 3u
#define FV_INTERP_BINDING_LEVEL 5    /* uimage2DArray r32ui "interp level": each pixel's code (FV_INTERP_CODE_*) */
#define FV_INTERP_BINDING_TILES 6    /* storage uint[tile_count]: shaded pixels per tile, then each tile's offset */
#define FV_INTERP_BINDING_LIST 7     /* storage pixel list (fv_gpu.h FV_GPU_LIST_*): the frame sample list */
#define FV_INTERP_BINDING_INDIRECT 8 /* storage uint[4]: the list's VkDispatchIndirectCommand */
#define FV_INTERP_BINDING_GIVEN 9    /* storage uint[2 W H]: 1 where the frame's earlier list holds the pixel */
#define FV_INTERP_BINDING_STATS 10   /* storage uint[4]: shaded, filled, left pixels (host-read after the fence) */
#define FV_INTERP_BINDING_COUNT 11

#define FV_INTERP_GROUP 8            /* 8 x 8 threads: 8 x 8 nodes or pixels; COUNT and SCATTER: one subgroup per
                                      * tile, gl_NumSubgroups tiles per workgroup (no barriers) */
#define FV_INTERP_TILE 8
#define FV_INTERP_TILE_SIZE (FV_INTERP_TILE * FV_INTERP_TILE)

#define FV_INTERP_STAGE_GIVEN 0  /* scatter the frame's earlier list into `given` (indirect, as its own dispatch) */
#define FV_INTERP_STAGE_LEAF 1   /* level 1 from the G-buffer's 3 x 3 pixels */
#define FV_INTERP_STAGE_NODE 2   /* level pc.level from its children */
#define FV_INTERP_STAGE_COUNT 3  /* classify every pixel of a tile, write its code, count its shaded pixels (one
                                  * subgroup per tile, in runs of the subgroup size) */
#define FV_INTERP_STAGE_SCAN 4   /* one workgroup: exclusive prefix sum of the tile counts in the interleaved order,
                                  * the list's count and its dispatch arguments */
#define FV_INTERP_STAGE_SCATTER 5 /* each tile's shaded pixels at its offset, in row-major order within the tile */
#define FV_INTERP_STAGE_LEAF_SHARED 6 /* LEAF with the light test: the workgroup's 17 x 17 pixels decoded and lit once
                                       * each into shared memory (1.13 evaluations per pixel, not 2.25) */

/* The list is made in an interleaved tile order (as the shade pass visits a full frame): position g of the order
 * is tile (g % STRIPES) * tiles_per_stripe + g / STRIPES, so any contiguous half of the list (one lavapipe thread's
 * share of the indirect dispatch) holds pixels from all over both eyes. Tiles: eye-major, then row-major. */
#define FV_INTERP_STRIPES 32u

#define FV_INTERP_FLAG_GIVEN 1u /* the frame had a sample list before this pass: level-0 pixels follow it */
#define FV_INTERP_FLAG_LIGHT 2u /* interp.light: members' direct light (shadows included) must agree too */

/* A pixel's code in "interp level": bits 0..3 the level, and one of */
#define FV_INTERP_CODE_LEVEL_MASK 15u
#define FV_INTERP_CODE_SHADED 16u /* in the list: shaded by the shading function */
#define FV_INTERP_CODE_FILLED 32u /* interpolated from its level's node's corners (interp_fill) */
#define FV_INTERP_CODE_LEFT 64u   /* level 0 and not in the earlier list: another pass fills it */

/* node flags, the w of a node's first vec4 (as uint) */
#define FV_INTERP_NODE_COHERENT 1u
#define FV_INTERP_NODE_MATERIAL_SHIFT 8u /* material index + 1; 0 = nothing drawn */
#define FV_INTERP_NORMAL_MIN 0.5 /* a mean normal shorter than this (members disagree): not coherent */

struct fv_interp_push {
    FV_INTERP_UINT stage;            /* FV_INTERP_STAGE_* */
    FV_INTERP_UINT level;            /* NODE: the level built (2..MAX) */
    FV_INTERP_UINT start_level;      /* interp.start_level (1..MAX) */
    FV_INTERP_UINT flags;            /* FV_INTERP_FLAG_* */
    float threshold;                 /* interp.threshold, τ */
    FV_INTERP_UINT tiles_x, tiles_y; /* per eye */
    FV_INTERP_UINT tiles_per_stripe; /* ceil(tile_count / STRIPES) */
    FV_INTERP_UINT tile_count;       /* tiles_x * tiles_y * 2 */
    FV_INTERP_UINT groups_x;         /* COUNT, SCATTER: dispatch width (workgroups linearised as x + y * groups_x) */
    FV_INTERP_UINT pad[2];
    FV_INTERP_UINT level_base[FV_INTERP_MAX_LEVEL + 1]; /* index (in nodes) of level k's first node; [0] unused */
};

/* ---- "interp_fill" (interp_fill.comp; interp_fill_mark.comp with the frame's sample mask) ---- */
#define FV_INTERP_FILL_SET 1
#define FV_INTERP_FILL_BINDING_LEVEL 0 /* uimage2DArray r32ui "interp level" (read) */
#define FV_INTERP_FILL_BINDING_COLOR 1 /* image2DArray rgba32f: linear colour (filled pixels written) */
#define FV_INTERP_FILL_BINDING_COUNT 2
/* interp_fill_mark only: the sample mask and block masks (fv_sample_mask_interface.h; foveation's "fovea mask" and
 * "fovea blocks"), shaded and filled pixels marked */
#define FV_INTERP_FILL_BINDING_MASK 2   /* uimage2DArray r32ui (read, written) */
#define FV_INTERP_FILL_BINDING_BLOCKS 3 /* uimage2DArray r32ui (bits OR-ed in) */
#define FV_INTERP_FILL_MARK_BINDING_COUNT 4

#define FV_INTERP_FILL_VIEW 1u /* push.view: write `--view interp`'s colours instead of filling */

struct fv_interp_fill_push {
    FV_INTERP_UINT view;        /* 0: fill; FV_INTERP_FILL_VIEW: the view */
    FV_INTERP_UINT block;       /* interp_fill_mark: the block masks' block side B, px (fovea.block) */
    FV_INTERP_UINT block_words; /* ceil(B * B / 32) */
    FV_INTERP_UINT pad;
};

#endif
