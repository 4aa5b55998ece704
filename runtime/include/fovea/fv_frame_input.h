/* @brief What the runtime hands the renderer each frame: time, per-eye view/projection, per-eye gaze, pupil and
 * quality. Plain data, shared by runtime/ and render/ (the seam between them). */
#ifndef FV_FRAME_INPUT_H
#define FV_FRAME_INPUT_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_math.h"
#include "fv_lens.h"

typedef struct fv_eye_view {
    fv_mat4 view;        /* world -> eye view space (-z forward) */
    fv_mat4 proj;        /* eye view -> Vulkan clip */
    fv_vec3 pos_world;   /* eye position, metres */
    float tan_left, tan_right, tan_up, tan_down; /* the frustum the projection was built from */
    float near_m, far_m;
} fv_eye_view;

typedef struct fv_eye_gaze {
    bool valid;               /* false: no gaze (blink, lost): the renderer treats the whole view as the fovea */
    fv_vec3 dir_eye;          /* predicted unit gaze direction in eye view space (-z forward) */
    float uncertainty_deg;    /* radius by which the fovea must be widened */
} fv_eye_gaze;

/** The head in the world: where it is, which way it looks (its local -z), and the distance between the eyes. */
typedef struct fv_head_pose {
    fv_vec3 position_m;
    fv_quat orientation;
    float ipd_mm;
} fv_head_pose;

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

/** The shadow pass's knobs (render/shadow/: parallel-split shadow maps, Zhang et al. 2006). Each field is one knob
 *  of the table in render/knobs/ (its name in quotes); ranges are inclusive. */
typedef struct fv_quality_shadow {
    bool enabled;            /* "shadow.enabled": draw shadow maps at all (off: every light is unoccluded) */
    uint32_t splits;         /* "shadow.splits": splits of the view frustum along view depth, a count in 1..8 */
    float lambda;            /* "shadow.lambda": the split scheme's blend, 0 = uniform, 1 = logarithmic; 0..1,
                              * unitless (PSSM: C_i = lambda * log_i + (1 - lambda) * uniform_i) */
    uint32_t resolution_px;  /* "shadow.resolution": px per side of each split's square map, a power of two in
                              * 256..4096 */
    fv_shadow_filter filter; /* "shadow.filter": none | pcf3 | pcf5 */
    float bias_texels;       /* "shadow.bias": slope-scaled depth bias in shadow-map texels, 0..10 */
    bool stereo_shared;      /* "shadow.stereo_shared": true = one set of splits for both eyes, fitted to the union of
                              * the two frusta; false = one set per eye */
} fv_quality_shadow;

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

/** The foveated-rendering knobs (render/fovea/: sampling map from the predicted gaze, compaction, reconstruction;
 *  papers/README.md section 3). Each field is one knob of the table in render/knobs/. */
typedef struct fv_quality_fovea {
    bool enabled;          /* "fovea.enabled": shade a gaze-driven subset of the pixels (off: every pixel) */
    float mar_slope;       /* "fovea.mar_slope": m of the linear MAR w = m e + w0, degrees per degree, 0..1 */
    float mar_w0_deg;      /* "fovea.mar_w0_deg": w0, the MAR at the gaze, degrees, 0.001..1 */
    float min_prob;        /* "fovea.min_prob": xi, the smallest sampling probability, 0.01..1 */
    uint32_t block;        /* "fovea.block": side of the blocks that each hold at least one sample, px, 2..16 */
    bool uncertainty;      /* "fovea.uncertainty": widen the fovea by the gaze uncertainty (e' = max(0, e - u)) */
    fv_fovea_recon recon;  /* "fovea.recon": nearest | sibson | idw */
    fv_fovea_voronoi voronoi; /* "fovea.voronoi": jfa | blocks */
    fv_fovea_compaction compaction; /* "fovea.compaction": tiles | rows | masked */
    uint32_t temporal;     /* "fovea.temporal": temporal reuse, the frames an unshaded pixel may take a reprojected
                            * history value since it was last shaded, 0..15 (0: no temporal reuse) */
    float saliency;        /* "fovea.saliency": p raised to this weight times the saliency (albedo and normal
                            * gradients, object motion), 0..1 (0: off) */
    bool dof;              /* "fovea.dof": the eye's defocus blur (pupil, focus at the gaze) lowers p */
} fv_quality_fovea;

/** The lens knobs (render/distort/: pre-distortion with chromatic aberration; the hidden-area mask in render/gbuffer)
 *  and the lens they apply. `lens` is not a knob: it is the HMD profile's (runtime/hmd, `fovea run --hmd`); with
 *  lens.valid false (fv_quality_default) there is no HMD and nothing is distorted or masked. */
typedef struct fv_quality_distort {
    bool enabled; /* "distort.enabled": pre-distort each eye for its lens (off: the undistorted eye images) */
    bool mask;    /* "distort.mask": never shade the pixels the lens cannot show (G-buffer and every later pass) */
    fv_lens lens; /* the HMD's lens (fv_lens.h) */
} fv_quality_distort;

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

/** The one-bounce GI knobs (render/gi/: reflective shadow maps, light quad-tree, Ki & Oh 2007; papers/README.md
 *  section 1). Each field is one knob of the table in render/knobs/. */
typedef struct fv_quality_gi {
    bool enabled;            /* "gi.enabled": one-bounce indirect light from spot and directional lights */
    fv_gi_mode mode;         /* "gi.mode": cut | traverse | bound | rsm_sampling | exact */
    uint32_t rsm_size;       /* "gi.rsm_size": px per side of each light's reflective shadow map, power of two 1..1024 */
    uint32_t start_level;    /* "gi.start_level": nodes per side where the traversal starts, power of two 1..64 */
    fv_gi_limit limit_level; /* "gi.limit_level": 16 | 32 | 64 | leaf */
    float depth_threshold;   /* "gi.depth_threshold": children's depth within this of the mean (fraction of the scene
                              * size), 0..1 */
    float normal_threshold;  /* "gi.normal_threshold": children's normals' dot product with the mean above this, -1..1 */
    uint32_t samples;        /* "gi.samples": RSM samples per pixel for rsm_sampling, 1..8192 */
    float bound_fraction;    /* "gi.bound_fraction": bound mode's refinement tolerance, 0.00001..1 */
    fv_gi_average average;   /* "gi.average": flux | plain weights of the pyramid's means */
    float refine;            /* "gi.refine": cut mode splits, per pixel, a cluster whose extent over its distance
                              * exceeds this (0: the flat cut alone), 0..1 */
} fv_quality_gi;

/** How subsurface light is summed (fv_quality.sss.mode, knob `sss.mode`). */
typedef enum fv_sss_mode {
    FV_SSS_MODE_HIERARCHY = 0, /* "hierarchy": a per-pixel cut through the quad-tree of light-view samples */
    FV_SSS_MODE_EXACT = 1,     /* "exact": every sample of the light-view maps, no hierarchy (brute force) */
} fv_sss_mode;

/** The subsurface-scattering knobs (render/sss/: dipole diffusion over a light hierarchy, papers/README.md section
 *  4). Levels count from the root: level k has 2^k x 2^k clusters, the leaves are level log2(map_size). */
typedef struct fv_quality_sss {
    bool enabled;           /* "sss.enabled": subsurface light on translucent materials (off: shaded as opaque) */
    uint32_t map_size_px;   /* "sss.map_size": side of each light-view sample map, a power of two in 16..512 */
    uint32_t start_level;   /* "sss.start_level": the level the cut starts from, 0..9 (0 = the root; 3 = 8 x 8) */
    uint32_t limit_level;   /* "sss.limit_level": the finest level the cut reaches (its clusters are always
                             * accepted), 0..9, clamped to the leaves */
    float distance_scale;   /* "sss.distance_scale": a cluster of radius r at distance d from the pixel is accepted
                             * when r <= distance_scale * (eye distance, m) * similarity * d; per metre, 0..100 */
    fv_sss_mode mode;       /* "sss.mode": hierarchy | exact */
    float cutoff;           /* "sss.cutoff": the hierarchy drops clusters wholly farther from the pixel than the radius
                             * outside which this fraction of a point source's diffuse reflectance leaves; 0..0.5,
                             * 0 = no cutoff */
} fv_quality_sss;

/** The hierarchical screen-space interpolation knobs (render/interp/: Ki & Oh, papers/README.md section 4): coherent
 *  screen regions are shaded at their corners and filled by interpolation. Each field is one knob of the table in
 *  render/knobs/. */
typedef struct fv_quality_interp {
    bool enabled;         /* "interp.enabled": shade coherent regions once and interpolate them (off: every pixel) */
    float threshold;      /* "interp.threshold": tau, dimensionless, 0..1000: a region is coherent when every member
                           * has 1 - cos(normal, mean normal) <= tau, distance off the mean tangent plane <= tau x the
                           * region's width (its 2^k pixels at the eye distance), and each linear albedo channel
                           * within tau of the mean (and one material) */
    uint32_t start_level; /* "interp.start_level": the coarsest regions, 2^k x 2^k px, k in 1..7 */
    bool light;           /* "interp.light": also require each member's direct irradiance (shadows included) within
                           * tau of the mean, relative to the mean's largest channel */
} fv_quality_interp;

/** The settings a frame is drawn with. Zero is not a valid value: start from fv_quality_default() (the `balanced`
 *  preset) or fv_quality_preset() (render/knobs/fv_knobs.h).
 *  Every speed/accuracy trade is a knob of the one knob table (render/knobs/: name, type, range, unit, a default per
 *  preset, doc; `fovea knobs` lists it), which reads and writes these fields by offset. `exposure` and `debug_view`
 *  are view settings, not speed/accuracy trades, and are deliberately not in the knob table (`fovea run` sets them
 *  with --exposure and --debug-view). */
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

/** The `balanced` preset, and the one source of its values: the knob table's balanced column reads this (a unit
 *  test checks it). Inline so that runtime code needs no extra library. */
static inline fv_quality fv_quality_default(void)
{
    fv_quality q = {.exposure = 1.0f,
                    .debug_view = FV_DEBUG_VIEW_NONE,
                    .shadow = {.enabled = true,
                               .splits = 4,
                               .lambda = 0.5f,
                               .resolution_px = 2048,
                               .filter = FV_SHADOW_FILTER_PCF3,
                               .bias_texels = 1.5f,
                               .stereo_shared = true},
                    .fovea = {.enabled = true, /* BENCHMARKS.md: foveated sparse shading */
                              .mar_slope = 0.022f,
                              .mar_w0_deg = 1.0f / 48.0f,
                              .min_prob = 0.05f,
                              .block = 5,
                              .uncertainty = true,
                              .recon = FV_FOVEA_RECON_SOFT, /* BENCHMARKS.md: issue 25 */
                              .compaction = FV_FOVEA_COMPACTION_TILES,
                              .voronoi = FV_FOVEA_VORONOI_BLOCKS,
                              .temporal = 8,
                              .saliency = 0.0f,
                              .dof = true},
                    .distort = {.enabled = true, .mask = true},
                    .gi = {.enabled = true, /* scenes without a spot or directional light skip the pass */
                           .mode = FV_GI_CUT,
                           .rsm_size = 256,
                           .start_level = 8,
                           .limit_level = FV_GI_LIMIT_32,
                           .depth_threshold = 0.25f,
                           .normal_threshold = 0.6f,
                           .samples = 256,
                           .bound_fraction = 0.01f,
                           .average = FV_GI_AVERAGE_FLUX,
                           .refine = 0.0f},
                    .sss = {.enabled = true,
                            .map_size_px = 128,
                            .start_level = 0,
                            .limit_level = 7,
                            .distance_scale = 1.5f,
                            .mode = FV_SSS_MODE_HIERARCHY,
                            .cutoff = 0.005f},
                    .interp = {.enabled = false, .threshold = 0.2f, .start_level = 2, .light = true}};
    return q;
}

typedef struct fv_frame_input {
    uint64_t frame_id;
    double time_s;            /* scene time for animations */
    fv_head_pose head;        /* the head the eye views were built from */
    fv_eye_view eye[2];       /* 0 = left, 1 = right */
    fv_eye_gaze gaze[2];
    float pupil_mm;           /* NaN when unknown */
    int64_t t_photon_ns;      /* when this frame's photons are due (host clock), 0 if unknown */
    fv_quality quality;       /* what this frame is drawn with */
} fv_frame_input;

/** Build both eyes' views from a head pose (NULL = at the origin looking down -z, IPD 63 mm): eyes at +-IPD/2
 *  along the head's x axis (IPD clamped to [0, FV_MAX_IPD_MM]; NaN = 63 mm), the HMD default asymmetric field of
 *  view (vertical extent FV_HMD_FOV_UP/DOWN; horizontal extent from the image aspect, square pixels, split
 *  outer:inner as FV_HMD_FOV_OUTER:INNER, mirrored per eye, eye 0 = left, outer = left), near/far clamped so the
 *  projection stays finite (<= 0 or non-finite: 0.05 m / 100 m). Finite for any input (NaN poses: identity). */
void fv_eye_views_build(const fv_head_pose *head, float near_m, float far_m, uint32_t eye_width, uint32_t eye_height,
                        fv_eye_view out[2]);

/** The same with each eye's field of view given (an HMD profile's): fov[4 eye + i] = the tangents of its left,
 *  right, up and down half-angles (i = 0..3), all > 0 (eye 0 = left). A tangent that is not finite or outside
 *  [1e-3, 100] takes the default's. */
void fv_eye_views_build_fov(const fv_head_pose *head, float near_m, float far_m, const float fov[8],
                            fv_eye_view out[2]);

/** Clamp near/far planes to what keeps a projection finite: near <= 0 or non-finite -> 0.05 m, near in
 *  [1e-5, 5e8] m; far <= 0 or non-finite -> max(100 m, 1000 near), far <= 1e9 m and > 1.001 near. */
void fv_near_far_sanitize(float *near_m, float *far_m);

/** Near/far planes that hold the bounding sphere of [bounds_min, bounds_max] seen from the head (both eyes), with a
 *  margin; finite and far > near for any input (NULL head or NaN bounds: 0.05 / 100 m). */
void fv_near_far_from_bounds(const fv_head_pose *head, fv_vec3 bounds_min, fv_vec3 bounds_max, float *out_near_m,
                             float *out_far_m);

/** An eye's pose in the head frame (+x right, +y up, -z forward; metres): where the eye sits and how its view is
 *  turned against the head. The head's pose in the world moves the eyes' views and never enters here: gaze, which
 *  trackers give in the head frame, meets the views only through this pose (fv_eye_gaze_from_head). */
typedef struct fv_eye_in_head {
    fv_vec3 offset_m;    /* the eye's centre in the head frame */
    fv_quat orientation; /* head frame -> this eye's view frame turned by this (identity: parallel displays) */
} fv_eye_in_head;

/** The eyes of fovea's views (fv_eye_views_build*): at -+IPD/2 on the head's x axis (IPD sanitised as there), not
 *  turned (both views look down the head's -z). */
void fv_eyes_in_head(float ipd_mm, fv_eye_in_head out[2]);

/** THE seam between gaze and views: a gaze direction in the head frame as the eye's gaze in its own view space
 *  (rotated by the inverse of the eye's orientation in the head; the head's world pose plays no part). Invalid
 *  (dir_eye -z, uncertainty 180) when dir_head is not a finite non-zero vector; the uncertainty is clamped to
 *  0..180 (NaN: 180). Used by the frame loop (every tracker), `fovea bench --gaze-deg`, the OpenXR runtime, and,
 *  inverted, by the window's mouse: driver. */
fv_eye_gaze fv_eye_gaze_from_head(const fv_eye_in_head *eye, fv_vec3 dir_head, float uncertainty_deg);
/** The inverse for directions: a direction in the eye's view space, in the head frame. */
fv_vec3 fv_eye_dir_to_head(const fv_eye_in_head *eye, fv_vec3 dir_eye);
/** A point in the eye's view space (metres), in the head frame. */
fv_vec3 fv_eye_point_to_head(const fv_eye_in_head *eye, fv_vec3 p_eye);

/** The largest IPD fv_eye_views_build accepts (mm). */
#define FV_MAX_IPD_MM 100.0f
/** The IPD used when none is known (mm). */
#define FV_DEFAULT_IPD_MM 63.0f

/** HMD-like default field of view per eye (degrees): outer, inner, up, down. Asymmetric: the outer side is wider. */
#define FV_HMD_FOV_OUTER_DEG 50.0f
#define FV_HMD_FOV_INNER_DEG 42.0f
#define FV_HMD_FOV_UP_DEG 45.0f
#define FV_HMD_FOV_DOWN_DEG 48.0f

#endif
