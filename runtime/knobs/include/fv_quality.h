/* @brief fv_quality, the settings a frame is drawn with, as the knobs room defines it: its fields and
 * fv_quality_default() (the `balanced` preset) are generated from the one knob list (fv_knob_list.h), beside the
 * view settings (exposure, debug view, overlay) and the HMD lens. The runtime carries it in fv_frame_input without
 * defining it; the knob table, presets, parsing and validation are fv_knobs.h's. Plain data, header-only. */
#ifndef FV_QUALITY_H
#define FV_QUALITY_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_lens.h"
#include "fv_knob_list.h"

/** Debug views (fv_quality.debug_view): replace the shaded image with a view of the frame's data. */
typedef enum fv_debug_view {
    FV_DEBUG_VIEW_NONE = 0,
    FV_DEBUG_VIEW_NORMAL = 1, /* the G-buffer's world normal, n * 0.5 + 0.5 */
    FV_DEBUG_VIEW_GAZE = 2,   /* the predicted gaze: red peaks on the gaze ray, green = pupil mm / 10, blue = valid */
    FV_DEBUG_VIEW_DIRECT = 3, /* direct light only: visibility x irradiance x BRDF, no emission or ambient */
    FV_DEBUG_VIEW_SHADOW = 4, /* the visibility of light 0, 0..1 */
    FV_DEBUG_VIEW_CASCADE = 5, /* which of light 0's shadow maps (cascade split) holds each pixel, as colours */
    FV_DEBUG_VIEW_ALBEDO = 6, /* the G-buffer's linear albedo */
    FV_DEBUG_VIEW_DEPTH = 7,  /* the G-buffer's depth 0..1 */
    FV_DEBUG_VIEW_SAMPLES = 8, /* foveation's sample mask: white = shaded, black = filled in; blue ring = the gaze */
    FV_DEBUG_VIEW_PROB = 9,    /* foveation's sampling probability p, grey 0..1 */
    FV_DEBUG_VIEW_VORONOI = 10,  /* foveation's reconstruction: each pixel coloured by the sample it was filled from */
    FV_DEBUG_VIEW_GI = 11,       /* indirect light only (one-bounce GI from the light quad-tree) */
    FV_DEBUG_VIEW_CLUSTERS = 12, /* the GI cut drawn over the reflective shadow map, coloured by level */
    FV_DEBUG_VIEW_SSS = 13,      /* the subsurface term alone (dipole over the light hierarchy) */
    FV_DEBUG_VIEW_INTERP = 14,   /* hierarchical interpolation: the level each pixel was shaded or filled at */
    FV_DEBUG_VIEW_COUNT = 15
} fv_debug_view;

/** The name of a view ("color" for FV_DEBUG_VIEW_NONE, "normal", "gaze", "direct", "shadow", "cascade", "albedo",
 *  "depth", "samples", "prob", "voronoi", "gi", "clusters", "sss", "interp"); "?" when out of range. */
static inline const char *fv_debug_view_name(fv_debug_view v)
{
    static const char *const names[FV_DEBUG_VIEW_COUNT] = {"color",  "normal",  "gaze",   "direct",
                                                           "shadow", "cascade", "albedo", "depth",
                                                           "samples", "prob",    "voronoi", "gi",
                                                           "clusters", "sss",    "interp"};
    return (unsigned)v < FV_DEBUG_VIEW_COUNT ? names[v] : "?";
}

/** Shadow-map filters (fv_quality.shadow.filter, knob `shadow.filter`): percentage-closer filtering over an N x N
 *  texel footprint of the shadow map. */
typedef enum fv_shadow_filter {
    FV_SHADOW_FILTER_NONE = 0, /* "none": one tap, binary visibility (hard shadows) */
    FV_SHADOW_FILTER_PCF3 = 1, /* "pcf3": 3 x 3 PCF */
    FV_SHADOW_FILTER_PCF5 = 2, /* "pcf5": 5 x 5 PCF */
} fv_shadow_filter;

/** How the foveated frame fills the pixels it did not shade (fv_quality.fovea.recon, knob `fovea.recon`). */
typedef enum fv_fovea_recon {
    FV_FOVEA_RECON_NEAREST = 0, /* "nearest": the colour of the nearest shaded pixel (jump flooding, 1+JFA) */
    FV_FOVEA_RECON_SIBSON = 1,  /* "sibson": approximate discrete Sibson (natural-neighbour) interpolation over the
                                 * Voronoi diagram, window = the block */
    FV_FOVEA_RECON_IDW = 2,     /* "idw": inverse-distance-squared (Shepard) weights of the samples of the
                                 * neighbouring blocks (no Voronoi diagram needed) */
    FV_FOVEA_RECON_SOFT = 3,    /* "soft": an edge-aware (G-buffer plane and normal) Gaussian of the known pixels of
                                 * the 3x3 blocks around, as wide as the local sample spacing (one pass) */
    FV_FOVEA_RECON_LAST = FV_FOVEA_RECON_SOFT
} fv_fovea_recon;

/** How the Voronoi diagram of the samples is found (knob `fovea.voronoi`). */
typedef enum fv_fovea_voronoi {
    FV_FOVEA_VORONOI_JFA = 0,    /* "jfa": jump flooding, 1+JFA from the block size (the paper) */
    FV_FOVEA_VORONOI_BLOCKS = 1, /* "blocks": exact, a search of the samples of the neighbouring blocks (every
                                  * block holds one, so the nearest is at most one block away for B <= 5, two above) */
    FV_FOVEA_VORONOI_LAST = FV_FOVEA_VORONOI_BLOCKS
} fv_fovea_voronoi;

/** How the sampled pixels become the list the shading dispatches over (knob `fovea.compaction`). */
typedef enum fv_fovea_compaction {
    FV_FOVEA_COMPACTION_TILES = 0,  /* "tiles": per 8x8 tile, one atomic per tile for its offset */
    FV_FOVEA_COMPACTION_ROWS = 1,   /* "rows": the paper's row-wise (CSR) reorder, a prefix sum over the rows */
    FV_FOVEA_COMPACTION_MASKED = 2, /* "masked": a full dispatch over every pixel, unsampled ones skipped */
    FV_FOVEA_COMPACTION_LAST = FV_FOVEA_COMPACTION_MASKED
} fv_fovea_compaction;

/** How the GI pass gathers indirect light per pixel (fv_quality.gi.mode, knob `gi.mode`). */
typedef enum fv_gi_mode {
    FV_GI_CUT = 0,          /* "cut": the flat cut list of the light quad-tree, extracted once per tree update */
    FV_GI_TRAVERSE = 1,     /* "traverse": the paper's per-pixel top-down traversal (the same clusters, per pixel) */
    FV_GI_BOUND = 2,        /* "bound": refine a cluster while its bound exceeds gi.bound_fraction of the total */
    FV_GI_RSM_SAMPLING = 3, /* "rsm_sampling": gi.samples RSM texels around the pixel (Dachsbacher & Stamminger 2005) */
    FV_GI_EXACT = 4,        /* "exact": every VPL of the RSM */
} fv_gi_mode;

/** The light quad-tree's limit level (fv_quality.gi.limit_level, knob `gi.limit_level`): nodes per side. */
typedef enum fv_gi_limit {
    FV_GI_LIMIT_16 = 0,   /* "16": 16 x 16 nodes, at most 256 clusters */
    FV_GI_LIMIT_32 = 1,   /* "32" */
    FV_GI_LIMIT_64 = 2,   /* "64" */
    FV_GI_LIMIT_LEAF = 3, /* "leaf": no limit, a cluster is cut only where it is valid */
} fv_gi_limit;

/** How the light quad-tree averages a node's position, depth and normal over its children (fv_quality.gi.average,
 *  knob `gi.average`). */
typedef enum fv_gi_average {
    FV_GI_AVERAGE_FLUX = 0,  /* "flux": weighted by each child's incident power (the cluster's flux centroid) */
    FV_GI_AVERAGE_PLAIN = 1, /* "plain": every child with geometry counts equally (the paper's mip-map mean) */
} fv_gi_average;

/** The rate the one-bounce GI is gathered at (fv_quality.gi.rate, knob `gi.rate`): per pixel, or once per r x r
 *  block of the G-buffer, joint-bilaterally upsampled where the G-buffer is coherent (render/gi_gather). */
typedef enum fv_gi_rate {
    FV_GI_RATE_FULL = 0,    /* "full": every shaded pixel gathers (exact keeps this) */
    FV_GI_RATE_HALF = 1,    /* "half": one gather per 2 x 2 block */
    FV_GI_RATE_QUARTER = 2, /* "quarter": one gather per 4 x 4 block */
    FV_GI_RATE_EIGHTH = 3,  /* "eighth": one gather per 8 x 8 block */
    FV_GI_RATE_LAST = FV_GI_RATE_EIGHTH,
} fv_gi_rate;

/** How subsurface light is summed (fv_quality.sss.mode, knob `sss.mode`). */
typedef enum fv_sss_mode {
    FV_SSS_MODE_HIERARCHY = 0, /* "hierarchy": a per-pixel cut through the quad-tree of light-view samples */
    FV_SSS_MODE_EXACT = 1,     /* "exact": every sample of the light-view maps, no hierarchy (brute force) */
} fv_sss_mode;

/* Each group's struct holds its knobs' fields in list order (fv_knob_list.h). */
#define FV_KNOB_FIELD_(group, field, name, TYPE, ctype, ...) ctype field;

typedef struct fv_quality_shadow {
    FV_KNOBS_SHADOW(FV_KNOB_FIELD_)
} fv_quality_shadow;

typedef struct fv_quality_fovea {
    FV_KNOBS_FOVEA(FV_KNOB_FIELD_)
} fv_quality_fovea;

/** The lens knobs and the lens they apply. `lens` is not a knob: it is the HMD profile's (runtime/hmd, `fovea run
 *  --hmd`); with lens.valid false (fv_quality_default) there is no HMD and nothing is distorted or masked. */
typedef struct fv_quality_distort {
    FV_KNOBS_DISTORT(FV_KNOB_FIELD_)
    fv_lens lens; /* the HMD's lens (fv_lens.h) */
} fv_quality_distort;

typedef struct fv_quality_gi {
    FV_KNOBS_GI(FV_KNOB_FIELD_)
} fv_quality_gi;

typedef struct fv_quality_sss {
    FV_KNOBS_SSS(FV_KNOB_FIELD_)
} fv_quality_sss;

typedef struct fv_quality_interp {
    FV_KNOBS_INTERP(FV_KNOB_FIELD_)
} fv_quality_interp;

/** The settings a frame is drawn with. Zero is not a valid value: start from fv_quality_default() (the `balanced`
 *  preset) or fv_quality_preset() (runtime/knobs/fv_knobs.h).
 *  Every speed/accuracy trade is a knob of the one knob list (fv_knob_list.h; `fovea knobs` lists it). `exposure`,
 *  `debug_view` and `overlay` are view settings, not speed/accuracy trades, and are deliberately not knobs (`fovea
 *  run` sets them with --exposure, --debug-view and --overlay). */
typedef struct fv_quality {
    float exposure;           /* view setting, present: linear scale before tonemapping, finite and > 0 (default 1) */
    fv_debug_view debug_view; /* view setting: default FV_DEBUG_VIEW_NONE */
    bool overlay;             /* view setting (render/overlay, --overlay): draw the predicted gaze, its uncertainty ring
                               * and the foveal boundary into the displayed image; default false */
    fv_quality_shadow shadow; /* knobs "shadow.*" */
    fv_quality_fovea fovea;   /* knobs "fovea.*" */
    fv_quality_sss sss;       /* knobs "sss.*" */
    fv_quality_distort distort; /* knobs "distort.*" and the HMD lens */
    fv_quality_gi gi;         /* knobs "gi.*" */
    fv_quality_interp interp; /* knobs "interp.*" */
} fv_quality;

#define FV_KNOB_BALANCED_(group, field, name, TYPE, ctype, min, max, pow2, unit, choices, fast, balanced, ...)     \
    .field = (balanced),

/** The `balanced` preset: every knob's balanced value from the list, exposure 1, no debug view, no overlay, no lens.
 *  Inline so that runtime code needs no extra library. */
static inline fv_quality fv_quality_default(void)
{
    fv_quality q = {.exposure = 1.0f,
                    .debug_view = FV_DEBUG_VIEW_NONE,
                    .shadow = {FV_KNOBS_SHADOW(FV_KNOB_BALANCED_)},
                    .fovea = {FV_KNOBS_FOVEA(FV_KNOB_BALANCED_)},
                    .distort = {FV_KNOBS_DISTORT(FV_KNOB_BALANCED_)},
                    .gi = {FV_KNOBS_GI(FV_KNOB_BALANCED_)},
                    .sss = {FV_KNOBS_SSS(FV_KNOB_BALANCED_)},
                    .interp = {FV_KNOBS_INTERP(FV_KNOB_BALANCED_)}};
    return q;
}

/* Each INT knob's bounds as constants, FV_KNOB_MIN_<group>_<field> and FV_KNOB_MAX_<group>_<field>, so that a pass
 * whose shaders have a limit of their own asserts at compile time that the knob's range fits it (render/fovea:
 * FV_FOVEA_BLOCK_MAX is fovea.block's max). */
#define FV_KNOB_LIMITS_BOOL(group, field, lo, hi)
#define FV_KNOB_LIMITS_FLOAT(group, field, lo, hi)
#define FV_KNOB_LIMITS_ENUM(group, field, lo, hi)
#define FV_KNOB_LIMITS_INT(group, field, lo, hi)                                                                       \
    FV_KNOB_MIN_##group##_##field = (lo), FV_KNOB_MAX_##group##_##field = (hi),
#define FV_KNOB_LIMITS_(group, field, name, TYPE, ctype, lo, hi, ...) FV_KNOB_LIMITS_##TYPE(group, field, lo, hi)
enum fv_knob_int_limits { FV_KNOB_LIST(FV_KNOB_LIMITS_) FV_KNOB_LIMITS_END_ };

/* Equality per group: every knob of the group holds the same value (floats compare with ==, so NaN is never equal;
 * the distort group's lens is not a knob and is not compared). For caches keyed on a group's knobs. */
#define FV_KNOB_SAME_(group, field, ...) &&a->field == b->field
#define FV_QUALITY_GROUP_EQUAL_(group, LIST)                                                                         \
    static inline bool fv_quality_##group##_equal(const fv_quality_##group *a, const fv_quality_##group *b)           \
    {                                                                                                                \
        return true LIST(FV_KNOB_SAME_);                                                                             \
    }
FV_QUALITY_GROUP_EQUAL_(shadow, FV_KNOBS_SHADOW)
FV_QUALITY_GROUP_EQUAL_(fovea, FV_KNOBS_FOVEA)
FV_QUALITY_GROUP_EQUAL_(distort, FV_KNOBS_DISTORT)
FV_QUALITY_GROUP_EQUAL_(gi, FV_KNOBS_GI)
FV_QUALITY_GROUP_EQUAL_(sss, FV_KNOBS_SSS)
FV_QUALITY_GROUP_EQUAL_(interp, FV_KNOBS_INTERP)

#endif
