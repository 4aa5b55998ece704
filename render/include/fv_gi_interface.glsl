/* @brief The light quad-tree's data as the shading function reads it (render/gi, Ki & Oh 2007), shared by C
 * (render/gi/gi.c includes this file) and GLSL (fv_gi_gather.glsl): the tree's nodes, the header with the mode and
 * per-light layout, the flat cut list. Bound in the GI technique slots of the shading-inputs set
 * (fv_shade_inputs_interface.h): buffer 0 = header + cut list, buffer 1 = nodes. With the dummy buffers bound
 * (zeros) counts.x is 0 and the gather returns 0 at the cost of one load. Only vec4/uvec4/mat4 members (std430 ==
 * C layout). */
#ifndef FV_GI_INTERFACE_GLSL
#define FV_GI_INTERFACE_GLSL

#include "fv_gpu.h"
#include "fv_shade_inputs_interface.h"

#define FV_GI_MAX_LIGHTS 2 /* lights with a reflective shadow map (the first spot or directional lights; the header fits
                            * the 256-byte dummy buffer bound while GI is off) */
#define FV_GI_MAX_RSM 1024        /* largest RSM side, px (a power of two) */
#define FV_GI_MAX_LEVELS 11       /* log2(FV_GI_MAX_RSM) + 1 */
#define FV_GI_BINDING_HEADER (FV_SHADE_INPUTS_BINDING_GI_BUFFER0 + 0) /* fv_gi_header + fv_gi_cluster cut[] */
#define FV_GI_BINDING_NODES (FV_SHADE_INPUTS_BINDING_GI_BUFFER0 + 1)  /* fv_gi_node[] */
/* The reduced-rate gather's image (render/gi_gather; a 2D array, layer = eye, ceil(W / r) x ceil(H / r) texels for
 * the rate r of fv_gi_header.rate.x): one texel per r x r block of the G-buffer, gathered at the block's sample pixel
 * (r * i + r / 2, clamped to the image), whose position and normal the upsample reads from the G-buffer itself. The
 * shading function upsamples it (fv_gi_indirect); a 1x1 zero dummy while nothing is bound, which matches no pixel
 * (w = 0), so every pixel gathers itself. */
#define FV_GI_BINDING_LOW_IRRADIANCE (FV_SHADE_INPUTS_BINDING_GI_IMAGE0 + 0) /* rgb irradiance (W/m^2), w 1 = a sample */
#define FV_GI_MAX_RATE 8u /* r is 1, 2, 4 or 8 */

/* fv_gi_stats, one per frame in flight */
#define FV_GI_BINDING_STATS (FV_SHADE_INPUTS_BINDING_GI_BUFFER0 + FV_SHADE_INPUTS_SLOT_STATS)

/* How a shading pass counts the gather's work (FV_GI_STATS, defined before the shading function is included; not
 * defined: no counting, the stats buffer is not declared). */
#define FV_GI_STATS_SUBGROUP 1 /* reduce over the subgroup, then one set of atomics per subgroup */
#define FV_GI_STATS_ATOMIC 2   /* atomics per pixel (devices without arithmetic subgroup operations in compute) */

/* Gather modes (fv_gi_header.counts.y; knob gi.mode). */
#define FV_GI_MODE_CUT 0          /* the flat cut list, the same for every pixel */
#define FV_GI_MODE_TRAVERSE 1     /* the paper's per-pixel top-down traversal from the start level */
#define FV_GI_MODE_BOUND 2        /* per-pixel refinement while a cluster's bound exceeds a fraction of the total */
#define FV_GI_MODE_RSM_SAMPLING 3 /* Dachsbacher & Stamminger 2005: N samples around the pixel's RSM projection */
#define FV_GI_MODE_EXACT 4        /* every VPL (every lit RSM texel) */

/* Light kinds of the RSM (fv_gi_light.info.x). */
#define FV_GI_KIND_NONE 0
#define FV_GI_KIND_SPOT 1        /* perspective over the outer cone */
#define FV_GI_KIND_DIRECTIONAL 2 /* orthographic over the scene's bounding sphere */

/** One node of the quad-tree pyramid (level 0 = the RSM's texels, the VPLs). */
struct fv_gi_node {
    FV_VEC4 flux;   /* rgb reflected flux (W), w incident power (W, luminance): the averaging weight */
    FV_VEC4 pos;    /* xyz flux-weighted mean world position (m), w mean depth from the light / scene size */
    FV_VEC4 normal; /* xyz flux-weighted mean unit normal (|n| <= 1: shorter where the children disagree), w the
                     * cluster's extent: radius (m) of a sphere about pos that holds every texel's disk */
    FV_VEC4 info;   /* x 1 = valid cluster (Ki & Oh's test, children valid), y smallest texel radius below (m),
                     * z 1 = some geometry below, w the slab: every VPL below lies within this distance (m) of the
                     * plane through pos normal to the mean normal (0 for a VPL; the extent without a normal) */
};

/** One cluster of the flat cut list, ready to gather (no indirection, the constants folded). The same buffer holds,
 *  after the cut's room (nodes of every light: entries [W, 2W), W = nodes per light * lights), each light's tree again
 *  as walk records in depth-first pre-order (a node, then its four children's subtrees in the order (2x, 2y),
 *  (2x+1, 2y), (2x, 2y+1), (2x+1, 2y+1)), the same 48-byte struct read differently: flux = (rgb flux (W, >= 0),
 *  extent (m)), pos = (xyz, slab), normal = (xyz mean normal, the node's subtree size in records: 1 for a VPL; the
 *  next record after the subtree is this one + that size). An unlit node's record has zero flux and extent. The
 *  refinement (fv_gi_refine) walks it with one index: descend = +1, skip = + subtree size, 3 vec4 loads a node. */
struct fv_gi_cluster {
    FV_VEC4 flux;   /* rgb flux / pi (W), w extent^2 (m^2) */
    FV_VEC4 pos;    /* xyz world (m), w the node's slab (fv_gi_node.info.w) */
    FV_VEC4 normal; /* xyz mean normal (|n| <= 1), w the index of the node's walk record in this buffer's array
                     * (exact as a float) */
};

/** One light's RSM and tree. */
struct fv_gi_light {
    FV_MAT4 view_proj; /* world -> the RSM's clip space (Vulkan: y down, depth 0..1) */
    FV_UVEC4 info;     /* x kind (FV_GI_KIND_*), y first node of its tree, z first cut entry, w cut entries */
};

struct fv_gi_header {
    FV_UVEC4 counts; /* x 1 = GI on, y mode (FV_GI_MODE_*), z lights with a tree, w cut entries over all lights */
    FV_UVEC4 tree;   /* x RSM side N (px), y levels (log2 N + 1), z start level, w limit level (level k has N >> k
                      * nodes per side; start >= limit) */
    FV_UVEC4 opts;   /* x samples (rsm_sampling), y nodes per light's tree, z lit VPLs (counted by the build), w the
                      * bits of the float gi.refine^2 (cut mode: split a cluster whose extent^2 exceeds it times d^2;
                      * 0 = never) */
    FV_VEC4 params;  /* x depth threshold, y normal threshold, z bound fraction, w sampling radius in texels */
    FV_UVEC4 rate;   /* x the gather rate r (gi.rate: 1 per pixel, 2, 4 or 8: per r x r block, upsampled); y, z, w 0 */
#ifdef FV_GLSL
    fv_gi_light light[FV_GI_MAX_LIGHTS];
#else
    struct fv_gi_light light[FV_GI_MAX_LIGHTS];
#endif
};

/** What the gather did in one frame, summed over the shading passes' pixels that ran it (GI on and a surface hit):
 *  written with atomics by shading compiled with FV_GI_STATS, cleared by the GI pass before shading, read back
 *  after. */
struct fv_gi_stats {
    FV_UVEC4 counts; /* x, y: the clusters (tree nodes, samples) summed, low and high 32 bits; z the most at one pixel;
                      * w the pixels that ran the gather */
};

#ifndef FV_GLSL
/** The block side r of a gi.rate knob value (fv_gi_rate: full 0 -> 1, half 1 -> 2, quarter 2 -> 4, eighth 3 -> 8;
 *  out of range: 1, the per-pixel gather): the one mapping the GI pass's header, the reduced-rate gather and shading
 *  use. */
static inline uint32_t fv_gi_rate_factor(uint32_t rate) { return rate <= 3u ? 1u << rate : 1u; }
typedef struct fv_gi_stats fv_gi_stats;
_Static_assert(sizeof(fv_gi_stats) == 16, "fv_gi_stats layout");
typedef struct fv_gi_node fv_gi_node;
typedef struct fv_gi_light fv_gi_light;
typedef struct fv_gi_header fv_gi_header;
_Static_assert(sizeof(fv_gi_node) == 64, "fv_gi_node layout");
_Static_assert(sizeof(fv_gi_light) == 80, "fv_gi_light layout");
typedef struct fv_gi_cluster fv_gi_cluster;
_Static_assert(sizeof(fv_gi_cluster) == 48, "fv_gi_cluster layout");
_Static_assert(sizeof(fv_gi_header) == 80 + 80 * FV_GI_MAX_LIGHTS, "fv_gi_header layout");
#endif

#endif
