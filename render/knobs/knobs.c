/* @brief The knob table (every speed/accuracy knob: name, type, range, unit, fast/high/exact values, doc) and the
 * presets, NAME=VALUE parsing, formatting and validation built on it. The balanced column is fv_quality_default(). */
#include "fv_knobs.h"

#include <assert.h>
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Storage: bools are one byte, ints uint32_t, enums 4-byte C enums read as uint32_t. */
_Static_assert(sizeof(bool) == 1, "bool knobs are stored in one byte");
_Static_assert(sizeof(fv_shadow_filter) == sizeof(uint32_t), "enum knobs are stored in 4 bytes");

static const char *const g_presets[FV_QUALITY_PRESET_COUNT] = {"fast", "balanced", "high", "exact"};
static const char *const g_filter_names[] = {"none", "pcf3", "pcf5"};

#define B(x) {.b = (x)}
#define I(x) {.i = (x)}
#define F(x) {.f = (x)}
#define AT(field) .offset = offsetof(fv_quality, field), .size = sizeof(((fv_quality *)0)->field)

/* The table. Presets: fast, high and exact here; balanced is fv_quality_default() (fv_frame_input.h). Split scheme
 * and its lambda: parallel-split shadow maps, ../shared/papers/README.md §2. */
static const char *const g_recon_names[] = {"nearest", "sibson", "idw", "soft"};
static const char *const g_voronoi_names[] = {"jfa", "blocks"};
static const char *const g_compaction_names[] = {"tiles", "rows", "masked"};
static const char *const g_gi_mode_names[] = {"cut", "traverse", "bound", "rsm_sampling", "exact"};
static const char *const g_gi_limit_names[] = {"16", "32", "64", "leaf"};
static const char *const g_gi_average_names[] = {"flux", "plain"};
static const char *const g_sss_mode_names[] = {"hierarchy", "exact"};

static const fv_knob g_knobs[] = {
    {.name = "shadow.enabled", .type = FV_KNOB_BOOL, .min = 0, .max = 1, .unit = "", AT(shadow.enabled),
     .fast = B(true), .high = B(true), .exact = B(true),
     .doc = "draw the shadow pass: each light's visibility from shadow maps (off: nothing is shadowed)"},
    {.name = "shadow.splits", .type = FV_KNOB_INT, .min = 1, .max = 8, .unit = "", AT(shadow.splits),
     .fast = I(2), .high = I(4), .exact = I(8),
     .doc = "splits of the view frustum along depth, one shadow map each (PSSM): more splits, less aliasing, more draws",
     .exact_note = "a shadow texel per screen pixel is out of reach of a few maps; the most splits, 8"},
    {.name = "shadow.lambda", .type = FV_KNOB_FLOAT, .min = 0, .max = 1, .unit = "", AT(shadow.lambda),
     .fast = F(0.5f), .high = F(0.5f), .exact = F(0.75f),
     .doc = "split scheme: lambda * logarithmic + (1 - lambda) * uniform split depths (PSSM)",
     .exact_note = "the logarithmic scheme (1) evens out perspective aliasing but makes the nearest splits uselessly "
                   "thin; leans towards it with 0.75"},
    {.name = "shadow.resolution", .type = FV_KNOB_INT, .min = 256, .max = 4096, .pow2 = true, .unit = "px",
     AT(shadow.resolution_px), .fast = I(1024), .high = I(4096), .exact = I(4096),
     .doc = "side of each split's square shadow map",
     .exact_note = "a shadow texel per screen pixel is out of reach of a fixed map; the largest, 4096 px"},
    {.name = "shadow.filter", .type = FV_KNOB_ENUM, .min = 0, .max = 2, .unit = "", .choices = g_filter_names,
     .choice_count = 3, AT(shadow.filter), .fast = I(FV_SHADOW_FILTER_NONE), .high = I(FV_SHADOW_FILTER_PCF5),
     .exact = I(FV_SHADOW_FILTER_NONE),
     .doc = "percentage-closer filter of the shadow test: none (one tap), pcf3 (3x3), pcf5 (5x5) texels",
     .exact_note = "visibility is binary (lit or not) and a filter blurs it, so none"},
    {.name = "shadow.bias", .type = FV_KNOB_FLOAT, .min = 0, .max = 10, .unit = "texels", AT(shadow.bias_texels),
     .fast = F(1.5f), .high = F(1.5f), .exact = F(1.0f),
     .doc = "slope-scaled depth bias against shadow acne; too much detaches shadows from their casters",
     .exact_note = "exact visibility needs no bias, but a depth map of finite texels shadows itself without one; "
                   "a smaller 1 texel"},
    {.name = "shadow.stereo_shared", .type = FV_KNOB_BOOL, .min = 0, .max = 1, .unit = "", AT(shadow.stereo_shared),
     .fast = B(true), .high = B(true), .exact = B(false),
     .doc = "one set of splits for both eyes, fitted to the union of their frusta (off: one set per eye, twice the "
            "shadow draws)"},
    {.name = "fovea.enabled", .type = FV_KNOB_BOOL, .min = 0, .max = 1, .unit = "", AT(fovea.enabled),
     .fast = B(true), .high = B(true), .exact = B(false),
     .doc = "foveated rendering: shade a gaze-driven subset of the pixels, reuse the previous frame's, reconstruct the "
            "rest (off: every pixel shaded)"},
    {.name = "fovea.mar_slope", .type = FV_KNOB_FLOAT, .min = 0, .max = 1, .unit = "deg/deg", AT(fovea.mar_slope),
     .fast = F(0.03f), .high = F(0.016f), .exact = F(0.022f),
     .doc = "slope m of the linear minimum angle of resolution w = m e + w0 (e: eccentricity from the gaze)"},
    {.name = "fovea.mar_w0_deg", .type = FV_KNOB_FLOAT, .min = 0.001, .max = 1, .unit = "deg", AT(fovea.mar_w0_deg),
     .fast = F(1.0f / 40.0f), .high = F(1.0f / 60.0f), .exact = F(1.0f / 48.0f),
     .doc = "w0, the minimum angle of resolution at the gaze (also w_min of the sampling probability)"},
    {.name = "fovea.min_prob", .type = FV_KNOB_FLOAT, .min = 0.01, .max = 1, .unit = "", AT(fovea.min_prob),
     .fast = F(0.03f), .high = F(0.1f), .exact = F(1.0f),
     .doc = "xi, the smallest sampling probability (the far periphery); 1 samples every pixel"},
    {.name = "fovea.block", .type = FV_KNOB_INT, .min = 2, .max = 16, .unit = "px", AT(fovea.block),
     .fast = I(5), .high = I(4), .exact = I(2),
     .doc = "side of the square blocks that each hold at least one sample (bounds the gap reconstruction fills)"},
    {.name = "fovea.uncertainty", .type = FV_KNOB_BOOL, .min = 0, .max = 1, .unit = "", AT(fovea.uncertainty),
     .fast = B(false), .high = B(true), .exact = B(true),
     .doc = "widen the fovea by the predicted gaze's uncertainty (eccentricity e' = max(0, e - u))"},
    {.name = "fovea.recon", .type = FV_KNOB_ENUM, .min = 0, .max = FV_FOVEA_RECON_LAST, .unit = "",
     .choices = g_recon_names, .choice_count = 4, AT(fovea.recon), .fast = I(FV_FOVEA_RECON_SOFT),
     .high = I(FV_FOVEA_RECON_SOFT), .exact = I(FV_FOVEA_RECON_NEAREST),
     .doc = "how unshaded pixels are filled: nearest (the nearest sample's colour), sibson (approximate discrete "
            "natural-neighbour interpolation over the Voronoi diagram, window = the block), idw (inverse-distance-"
            "squared weights of the neighbouring blocks' samples), soft (an edge-aware Gaussian, G-buffer plane and "
            "normal guided, of the 3x3 blocks' known pixels, as wide as the local sample spacing: soft edges, one "
            "pass)"},
    {.name = "fovea.voronoi", .type = FV_KNOB_ENUM, .min = 0, .max = FV_FOVEA_VORONOI_LAST, .unit = "",
     .choices = g_voronoi_names, .choice_count = 2, AT(fovea.voronoi), .fast = I(FV_FOVEA_VORONOI_BLOCKS),
     .high = I(FV_FOVEA_VORONOI_BLOCKS), .exact = I(FV_FOVEA_VORONOI_BLOCKS),
     .doc = "how the nearest sample of every pixel is found: jfa (jump flooding, 1+JFA from the block size) or "
            "blocks (exact: a search of the neighbouring blocks' samples, one pass)"},
    {.name = "fovea.compaction", .type = FV_KNOB_ENUM, .min = 0, .max = FV_FOVEA_COMPACTION_LAST, .unit = "",
     .choices = g_compaction_names, .choice_count = 3, AT(fovea.compaction), .fast = I(FV_FOVEA_COMPACTION_TILES),
     .high = I(FV_FOVEA_COMPACTION_TILES), .exact = I(FV_FOVEA_COMPACTION_TILES),
     .doc = "how the samples become the shading's list: tiles (8x8 tiles, one atomic each), rows (the paper's "
            "row-wise CSR reorder), masked (a full dispatch that skips unsampled pixels)"},
    {.name = "fovea.temporal", .type = FV_KNOB_INT, .min = 0, .max = 15, .unit = "frames", AT(fovea.temporal),
     .fast = I(12), .high = I(4), .exact = I(0),
     .doc = "temporal reuse: the previous frame reprojected through the motion vectors (depth test), blended into "
            "shaded pixels and reused for unshaded ones until they are this many frames older than their last "
            "shading (0: none)"},
    {.name = "fovea.saliency", .type = FV_KNOB_FLOAT, .min = 0, .max = 1, .unit = "", AT(fovea.saliency),
     .fast = F(0.0f), .high = F(0.5f), .exact = F(0.0f),
     .doc = "weight of the saliency (CIELAB albedo gradient, normal gradient, object motion) that raises the "
            "sampling probability at edges and moving objects (0: off)"},
    {.name = "fovea.dof", .type = FV_KNOB_BOOL, .min = 0, .max = 1, .unit = "", AT(fovea.dof),
     .fast = B(true), .high = B(true), .exact = B(false),
     .doc = "depth of field: the eye's defocus blur (pupil diameter, focus at the surface under the gaze) widens "
            "the minimum angle of resolution off the focal plane; no pupil from the tracker: no effect"},
    /* distort.*: the HMD lens (render/distort, the hidden-area mask in render/gbuffer). Not speed/accuracy trades of
     * the image but what the panel needs: on in every preset, exact included (an undistorted frame on an HMD panel
     * is wrong, not more exact; the mask removes only pixels no one can see). They act only with an HMD lens. */
    {.name = "distort.enabled", .type = FV_KNOB_BOOL, .min = 0, .max = 1, .unit = "", AT(distort.enabled),
     .fast = B(true), .high = B(true), .exact = B(true),
     .doc = "pre-distort each eye for its HMD lens (radial polynomial, per-channel scale for chromatic aberration); "
            "off: the undistorted eye images reach the target"},
    {.name = "distort.mask", .type = FV_KNOB_BOOL, .min = 0, .max = 1, .unit = "", AT(distort.mask),
     .fast = B(true), .high = B(true), .exact = B(true),
     .doc = "hidden-area mask: the pixels the lens never shows are never shaded (depth pre-fill in the G-buffer; "
            "later passes skip them as nothing drawn)"},
    /* gi.*: one-bounce GI from the light quad-tree (render/gi; Ki & Oh 2007, ../shared/papers/README.md §1). The
     * threshold pairs of the paper: (0.45, 0.3), (0.25, 0.6), (0.05, 0.9). */
    {.name = "gi.enabled", .type = FV_KNOB_BOOL, .min = 0, .max = 1, .unit = "", AT(gi.enabled),
     .fast = B(true), .high = B(true), .exact = B(true),
     .doc = "one-bounce indirect light: a reflective shadow map per spot or directional light, clustered in a light "
            "quad-tree (off: direct light only)"},
    {.name = "gi.mode", .type = FV_KNOB_ENUM, .min = 0, .max = 4, .unit = "", .choices = g_gi_mode_names,
     .choice_count = 5, AT(gi.mode), .fast = I(FV_GI_CUT), .high = I(FV_GI_CUT), .exact = I(FV_GI_EXACT),
     .doc = "gather: cut (the flat cut list), traverse (the paper's per-pixel traversal), bound (refine while a "
            "cluster's bound is large), rsm_sampling (Dachsbacher & Stamminger 2005), exact (every VPL)"},
    {.name = "gi.rsm_size", .type = FV_KNOB_INT, .min = 1, .max = 1024, .pow2 = true, .unit = "px", AT(gi.rsm_size),
     .fast = I(128), .high = I(512), .exact = I(64),
     .doc = "side of each light's reflective shadow map: one VPL per texel",
     .exact_note = "the exact sum visits every VPL at every pixel (N^2 each); 64 px (4096 VPLs) keeps a frame "
                   "within seconds on lavapipe — exact for that RSM"},
    {.name = "gi.start_level", .type = FV_KNOB_INT, .min = 1, .max = 64, .pow2 = true, .unit = "nodes",
     AT(gi.start_level), .fast = I(16), .high = I(8), .exact = I(8),
     .doc = "nodes per side of the level the traversal and the cut start from (coarser nodes are never one light)"},
    {.name = "gi.limit_level", .type = FV_KNOB_ENUM, .min = 0, .max = 3, .unit = "nodes", .choices = g_gi_limit_names,
     .choice_count = 4, AT(gi.limit_level), .fast = I(FV_GI_LIMIT_16), .high = I(FV_GI_LIMIT_64),
     .exact = I(FV_GI_LIMIT_LEAF),
     .doc = "nodes per side of the level always taken as valid: bounds the clusters per pixel (16: 256, 32: 1024, "
            "64: 4096), leaf: no bound"},
    {.name = "gi.depth_threshold", .type = FV_KNOB_FLOAT, .min = 0, .max = 1, .unit = "", AT(gi.depth_threshold),
     .fast = F(0.45f), .high = F(0.05f), .exact = F(0.05f),
     .doc = "a cluster is valid when each child's depth from the light is within this of the mean (a fraction of "
            "the scene's size)"},
    {.name = "gi.normal_threshold", .type = FV_KNOB_FLOAT, .min = -1, .max = 1, .unit = "", AT(gi.normal_threshold),
     .fast = F(0.3f), .high = F(0.9f), .exact = F(0.9f),
     .doc = "a cluster is valid when each child's normal has a dot product above this with the mean normal"},
    {.name = "gi.samples", .type = FV_KNOB_INT, .min = 1, .max = 65536, .unit = "", AT(gi.samples),
     .fast = I(128), .high = I(1024), .exact = I(4096),
     .doc = "RSM samples per pixel of gi.mode=rsm_sampling"},
    {.name = "gi.bound_fraction", .type = FV_KNOB_FLOAT, .min = 0.00001, .max = 1, .unit = "", AT(gi.bound_fraction),
     .fast = F(0.05f), .high = F(0.002f), .exact = F(0.0001f),
     .doc = "gi.mode=bound: a cluster is one light when its bound is at most this fraction of the start level's "
            "estimate"},
    {.name = "gi.average", .type = FV_KNOB_ENUM, .min = 0, .max = 1, .unit = "", .choices = g_gi_average_names,
     .choice_count = 2, AT(gi.average), .fast = I(FV_GI_AVERAGE_FLUX), .high = I(FV_GI_AVERAGE_FLUX),
     .exact = I(FV_GI_AVERAGE_FLUX),
     .doc = "how a tree node averages its children's position, depth and normal: flux (weighted by their power, "
            "the cluster's flux centroid; measured closer to exact, BENCHMARKS.md) or plain (equal weights)"},
    {.name = "gi.refine", .type = FV_KNOB_FLOAT, .min = 0, .max = 1, .unit = "", AT(gi.refine),
     .fast = F(0.0f), .high = F(0.0f), .exact = F(0.0f),
     .doc = "gi.mode=cut: a cut cluster whose extent is more than this times its distance from the pixel is "
            "replaced, for that pixel, by its children (recursively; the near field), 0: the flat cut alone"},
    /* sss.*: subsurface scattering, dipole diffusion over a quad-tree of light-view samples (render/sss; Ki & Oh,
     * ../shared/papers/README.md section 4). Levels count from the root (level k: 2^k x 2^k clusters). */
    {.name = "sss.enabled", .type = FV_KNOB_BOOL, .min = 0, .max = 1, .unit = "", AT(sss.enabled),
     .fast = B(true), .high = B(true), .exact = B(true),
     .doc = "subsurface light on translucent materials (dipole, Jensen et al. 2001); off: shaded as opaque"},
    {.name = "sss.map_size", .type = FV_KNOB_INT, .min = 16, .max = 512, .pow2 = true, .unit = "px",
     AT(sss.map_size_px), .fast = I(64), .high = I(256), .exact = I(128),
     .doc = "side of each light-view sample map (one per light and translucent material): map_size^2 samples",
     .exact_note = "the exact sum is over every sample, so its cost grows with map_size^2; 128 keeps it measurable"},
    {.name = "sss.start_level", .type = FV_KNOB_INT, .min = 0, .max = 9, .unit = "", AT(sss.start_level),
     .fast = I(0), .high = I(0), .exact = I(0),
     .doc = "the level the per-pixel cut starts from (the paper's 3 = 8 x 8 clusters; 0, the root, lets the cutoff "
            "drop far halves whole: 1.5x faster, the same image, see BENCHMARKS.md)"},
    {.name = "sss.limit_level", .type = FV_KNOB_INT, .min = 0, .max = 9, .unit = "", AT(sss.limit_level),
     .fast = I(5), .high = I(8), .exact = I(9),
     .doc = "the finest level the cut reaches; its clusters are always accepted (the paper's 4 = 16 x 16 bounds the "
            "work at 4^limit clusters per pixel but blurs: see BENCHMARKS.md); at the leaves only the distance rule "
            "refines"},
    {.name = "sss.distance_scale", .type = FV_KNOB_FLOAT, .min = 0, .max = 100, .unit = "1/m",
     AT(sss.distance_scale), .fast = F(2.0f), .high = F(1.0f), .exact = F(0.0f),
     .doc = "a cluster of radius r at distance d is accepted when r <= distance_scale x eye distance (m) x "
            "similarity x d: coarser clusters farther from the eye; 0 refines to the limit level"},
    {.name = "sss.mode", .type = FV_KNOB_ENUM, .min = 0, .max = 1, .unit = "", .choices = g_sss_mode_names,
     .choice_count = 2, AT(sss.mode), .fast = I(FV_SSS_MODE_HIERARCHY), .high = I(FV_SSS_MODE_HIERARCHY),
     .exact = I(FV_SSS_MODE_EXACT),
     .doc = "hierarchy: a cut through the quad-tree per pixel; exact: every sample (brute force)"},
    {.name = "sss.cutoff", .type = FV_KNOB_FLOAT, .min = 0, .max = 0.5, .unit = "", AT(sss.cutoff),
     .fast = F(0.01f), .high = F(0.001f), .exact = F(0.0f),
     .doc = "the hierarchy skips clusters wholly beyond the radius outside which this fraction of a point source's "
            "diffuse reflectance leaves (on a uniformly lit plane: the fraction of subsurface light dropped); 0: none"},
    /* interp.*: hierarchical screen-space interpolation (render/interp; Ki & Oh, ../shared/papers/README.md
     * section 4). Level k: regions of 2^k x 2^k px. */
    {.name = "interp.enabled", .type = FV_KNOB_BOOL, .min = 0, .max = 1, .unit = "", AT(interp.enabled),
     .fast = B(false), .high = B(false), .exact = B(false),
     .doc = "shade coherent screen regions at their corners and interpolate the rest (off: every pixel shaded)",
     .exact_note = "interpolated pixels are approximations; every pixel is shaded"},
    {.name = "interp.threshold", .type = FV_KNOB_FLOAT, .min = 0, .max = 1000, .unit = "", AT(interp.threshold),
     .fast = F(0.3f), .high = F(0.05f), .exact = F(0.0f),
     .doc = "tau: a region is coherent when each member's 1 - cos(normal, mean), distance off the mean tangent plane "
            "in region widths (2^k px at the eye distance), and linear albedo difference are all <= tau (one "
            "material; interp.light: the direct light too); 0: exact agreement only. Balanced 0.2: the knee measured "
            "in BENCHMARKS.md"},
    {.name = "interp.start_level", .type = FV_KNOB_INT, .min = 1, .max = 7, .unit = "", AT(interp.start_level),
     .fast = I(3), .high = I(2), .exact = I(1),
     .doc = "the coarsest regions, 2^k x 2^k px: a coherent one is shaded at its 4 corners (the paper: 4x4 px at "
            "512x512)"},
    {.name = "interp.light", .type = FV_KNOB_BOOL, .min = 0, .max = 1, .unit = "", AT(interp.light),
     .fast = B(false), .high = B(true), .exact = B(true),
     .doc = "coherence also needs the members' direct light (shadows included) within tau of the mean: no "
            "interpolation across shadow edges, at one direct-light evaluation per G-buffer read of the pyramid"},
};

#define KNOB_COUNT (sizeof g_knobs / sizeof g_knobs[0])

const fv_knob *fv_knobs(size_t *count)
{
    if (count) *count = KNOB_COUNT;
    return g_knobs;
}

const fv_knob *fv_knob_find(const char *name)
{
    if (!name) return NULL;
    for (size_t i = 0; i < KNOB_COUNT; i++)
        if (strcmp(g_knobs[i].name, name) == 0) return &g_knobs[i];
    return NULL;
}

const char *fv_knob_type_name(fv_knob_type type)
{
    switch (type) {
    case FV_KNOB_BOOL: return "bool";
    case FV_KNOB_INT: return "int";
    case FV_KNOB_FLOAT: return "float";
    case FV_KNOB_ENUM: return "enum";
    }
    return "?";
}

const char *fv_quality_preset_name(fv_quality_preset_id id)
{
    return (unsigned)id < FV_QUALITY_PRESET_COUNT ? g_presets[id] : NULL;
}

const char *fv_quality_preset_names(void) { return "fast, balanced, high, exact"; }

/* ---- messages ------------------------------------------------------------------------------------------------ */

/* Append printf output to err at *at, staying NUL-terminated when it does not fit. */
static void say(char *err, size_t size, size_t *at, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static void say(char *err, size_t size, size_t *at, const char *fmt, ...)
{
    if (!err || size == 0 || *at >= size) return;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(err + *at, size - *at, fmt, ap);
    va_end(ap);
    if (n > 0) *at = (size_t)n < size - *at ? *at + (size_t)n : size;
}

/* The shortest text of d that reads back as d (as a float when is_float): fixed point ("10", "0.75") in
 * [1e-4, 1e15), else "%g" ("1e-06"). */
static void fmt_number(double d, bool is_float, char *buf, size_t size)
{
    bool fixed = d == 0.0 || (fabs(d) >= 1e-4 && fabs(d) < 1e15);
    for (int p = fixed ? 0 : 1; p <= 17; p++) {
        snprintf(buf, size, fixed ? "%.*f" : "%.*g", p, d);
        double back = strtod(buf, NULL); /* floats read back as parse_value reads them: strtod, then to float */
        if (is_float ? (float)back == (float)d : back == d) return;
    }
}

/* A float knob holds a float: its bounds as the parser applies them are the table's doubles rounded to float (0.01
 * is 0.00999999977... as a float, below the double 0.01). Every comparison and every printed bound uses these. */
static double bound_lo(const fv_knob *k) { return k->type == FV_KNOB_FLOAT ? (double)(float)k->min : k->min; }
static double bound_hi(const fv_knob *k) { return k->type == FV_KNOB_FLOAT ? (double)(float)k->max : k->max; }

/* The bounds as text that reads back (through parse_value) as exactly the bounds. */
static void format_bounds(const fv_knob *k, char *lo, char *hi, size_t size)
{
    bool is_float = k->type == FV_KNOB_FLOAT;
    fmt_number(bound_lo(k), is_float, lo, size);
    fmt_number(bound_hi(k), is_float, hi, size);
}

const char *fv_knob_format_range(const fv_knob *k, char *buf, size_t size)
{
    if (!buf || size == 0) return buf;
    buf[0] = '\0';
    if (!k) return buf;
    size_t at = 0;
    char lo[32], hi[32];
    switch (k->type) {
    case FV_KNOB_BOOL: say(buf, size, &at, "on|off"); break;
    case FV_KNOB_ENUM:
        for (uint32_t i = 0; i < k->choice_count; i++) say(buf, size, &at, "%s%s", i ? "|" : "", k->choices[i]);
        break;
    case FV_KNOB_INT:
    case FV_KNOB_FLOAT:
        format_bounds(k, lo, hi, sizeof lo);
        say(buf, size, &at, "%s..%s%s", lo, hi, k->pow2 ? ", powers of two" : "");
        break;
    }
    return buf;
}

/* What a value of k must be, for messages: "a whole number in 1..8", "a power of two in 256..4096 px". */
static void expected(const fv_knob *k, char *buf, size_t size)
{
    size_t at = 0;
    char lo[32], hi[32];
    format_bounds(k, lo, hi, sizeof lo);
    switch (k->type) {
    case FV_KNOB_BOOL: say(buf, size, &at, "one of on, off, true, false, 1, 0"); return;
    case FV_KNOB_ENUM:
        say(buf, size, &at, "one of ");
        for (uint32_t i = 0; i < k->choice_count; i++) say(buf, size, &at, "%s%s", i ? ", " : "", k->choices[i]);
        return;
    case FV_KNOB_INT: say(buf, size, &at, "%s in %s..%s", k->pow2 ? "a power of two" : "a whole number", lo, hi); break;
    case FV_KNOB_FLOAT: say(buf, size, &at, "a number in %s..%s", lo, hi); break;
    }
    if (k->unit[0]) say(buf, size, &at, " %s", k->unit);
}

/* ---- values -------------------------------------------------------------------------------------------------- */

/* The bytes a knob of this type takes in fv_quality (the unit test checks every row's size against it). */
#define STORAGE_SIZE(type) ((type) == FV_KNOB_BOOL ? 1u : 4u)

fv_knob_value fv_knob_get(const fv_knob *k, const fv_quality *q)
{
    fv_knob_value v = {.i = 0};
    assert(k && q && k->size == STORAGE_SIZE(k->type));
    const unsigned char *p = (const unsigned char *)q + k->offset;
    uint32_t u = 0;
    switch (k->type) {
    case FV_KNOB_BOOL: v.b = p[0] != 0; break; /* read as a byte: a stray value is not undefined behaviour */
    case FV_KNOB_INT:
    case FV_KNOB_ENUM:
        memcpy(&u, p, sizeof u);
        v.i = u;
        break;
    case FV_KNOB_FLOAT: memcpy(&v.f, p, sizeof v.f); break;
    }
    return v;
}

static void knob_put(const fv_knob *k, fv_quality *q, fv_knob_value v)
{
    assert(k->size == STORAGE_SIZE(k->type));
    unsigned char *p = (unsigned char *)q + k->offset;
    uint32_t u = (uint32_t)v.i;
    switch (k->type) {
    case FV_KNOB_BOOL: memcpy(p, &v.b, 1); break;
    case FV_KNOB_INT:
    case FV_KNOB_ENUM: memcpy(p, &u, sizeof u); break;
    case FV_KNOB_FLOAT: memcpy(p, &v.f, sizeof v.f); break;
    }
}

static bool is_pow2(int64_t x) { return x > 0 && (x & (x - 1)) == 0; }

/* Whether v is allowed for k (bools always are). */
static bool value_ok(const fv_knob *k, fv_knob_value v)
{
    switch (k->type) {
    case FV_KNOB_BOOL: return true;
    case FV_KNOB_ENUM: return v.i >= 0 && v.i < (int64_t)k->choice_count;
    case FV_KNOB_INT: return (double)v.i >= k->min && (double)v.i <= k->max && (!k->pow2 || is_pow2(v.i));
    case FV_KNOB_FLOAT: return isfinite(v.f) && (double)v.f >= bound_lo(k) && (double)v.f <= bound_hi(k);
    }
    return false;
}

const char *fv_knob_format(const fv_knob *k, const fv_quality *q, char *buf, size_t size)
{
    if (!buf || size == 0) return buf;
    buf[0] = '\0';
    if (!k || !q) return buf;
    fv_knob_value v = fv_knob_get(k, q);
    switch (k->type) {
    case FV_KNOB_BOOL: snprintf(buf, size, "%s", v.b ? "on" : "off"); break;
    case FV_KNOB_INT: snprintf(buf, size, "%lld", (long long)v.i); break;
    case FV_KNOB_ENUM:
        if (v.i >= 0 && v.i < (int64_t)k->choice_count) snprintf(buf, size, "%s", k->choices[v.i]);
        else snprintf(buf, size, "%lld", (long long)v.i);
        break;
    case FV_KNOB_FLOAT: fmt_number((double)v.f, true, buf, size); break;
    }
    return buf;
}

/* Parse s as a value of k: FV_OK, FV_ERR_RANGE (a number out of range or not a power of two) or FV_ERR_PARSE. */
static fv_result parse_value(const fv_knob *k, const char *s, fv_knob_value *out)
{
    if (!*s || isspace((unsigned char)s[0])) return FV_ERR_PARSE; /* strto* would skip leading blanks */
    char *end = NULL;
    errno = 0;
    switch (k->type) {
    case FV_KNOB_BOOL: {
        static const char *const yes[] = {"on", "true", "1"}, *const no[] = {"off", "false", "0"};
        for (int i = 0; i < 3; i++) {
            if (strcmp(s, yes[i]) == 0) { out->b = true; return FV_OK; }
            if (strcmp(s, no[i]) == 0) { out->b = false; return FV_OK; }
        }
        return FV_ERR_PARSE;
    }
    case FV_KNOB_ENUM:
        for (uint32_t i = 0; i < k->choice_count; i++)
            if (strcmp(s, k->choices[i]) == 0) { out->i = i; return FV_OK; }
        return FV_ERR_PARSE;
    case FV_KNOB_INT: {
        long long v = strtoll(s, &end, 10);
        if (*end != '\0') return FV_ERR_PARSE;
        if (errno == ERANGE) return FV_ERR_RANGE;
        out->i = v;
        break;
    }
    case FV_KNOB_FLOAT: {
        double d = strtod(s, &end);
        if (*end != '\0' || isnan(d)) return FV_ERR_PARSE;
        /* the value is stored as a float: compare that float with the float bounds (underflow to 0 is fine) */
        if (!isfinite(d) || fabs(d) > FLT_MAX || (float)d < (float)k->min || (float)d > (float)k->max) return FV_ERR_RANGE;
        out->f = (float)d;
        break;
    }
    }
    return value_ok(k, *out) ? FV_OK : FV_ERR_RANGE;
}

/* ---- presets and assignments --------------------------------------------------------------------------------- */

fv_result fv_quality_preset(const char *preset, fv_quality *out, char *err, size_t err_size)
{
    size_t at = 0;
    if (!out) return FV_ERR_INVALID_ARG;
    for (int id = 0; preset && id < FV_QUALITY_PRESET_COUNT; id++) {
        if (strcmp(preset, g_presets[id]) != 0) continue;
        fv_quality q = fv_quality_default();
        for (size_t i = 0; id != FV_QUALITY_BALANCED && i < KNOB_COUNT; i++) {
            const fv_knob *k = &g_knobs[i];
            knob_put(k, &q, id == FV_QUALITY_FAST ? k->fast : id == FV_QUALITY_HIGH ? k->high : k->exact);
        }
        *out = q;
        return FV_OK;
    }
    say(err, err_size, &at, "'%.64s' is not a quality preset (one of %s)", preset ? preset : "(null)",
        fv_quality_preset_names());
    return FV_ERR_NOT_FOUND;
}

fv_result fv_quality_set(fv_quality *q, const char *assignment, char *err, size_t err_size)
{
    size_t at = 0;
    if (err && err_size) err[0] = '\0';
    if (!q || !assignment) return FV_ERR_INVALID_ARG;
    const char *eq = strchr(assignment, '=');
    if (!eq) {
        say(err, err_size, &at, "'%.64s' is not NAME=VALUE (e.g. shadow.splits=4; `fovea knobs` lists the names)",
            assignment);
        return FV_ERR_PARSE;
    }
    size_t n = (size_t)(eq - assignment);
    const fv_knob *k = NULL;
    for (size_t i = 0; i < KNOB_COUNT && !k; i++)
        if (strlen(g_knobs[i].name) == n && strncmp(g_knobs[i].name, assignment, n) == 0) k = &g_knobs[i];
    if (!k) {
        say(err, err_size, &at, "unknown knob '%.*s' (knobs:", n > 64 ? 64 : (int)n, assignment);
        for (size_t i = 0; i < KNOB_COUNT; i++) say(err, err_size, &at, " %s", g_knobs[i].name);
        say(err, err_size, &at, ")");
        return FV_ERR_NOT_FOUND;
    }
    const char *value = eq + 1;
    char want[128] = "";
    fv_knob_value v = {.i = 0};
    fv_result res = parse_value(k, value, &v);
    if (FV_FAILED(res)) {
        expected(k, want, sizeof want);
        if (!*value) say(err, err_size, &at, "%s: empty value (expected %s)", k->name, want);
        else say(err, err_size, &at, "%s: '%.64s' is not %s", k->name, value, want);
        return res;
    }
    knob_put(k, q, v);
    return FV_OK;
}

/* ---- whole qualities ----------------------------------------------------------------------------------------- */

fv_result fv_quality_validate(const fv_quality *q, char *err, size_t err_size)
{
    size_t at = 0;
    if (err && err_size) err[0] = '\0';
    if (!q) {
        say(err, err_size, &at, "no quality");
        return FV_ERR_INVALID_ARG;
    }
    bool ok = true;
    char have[64], want[128];
#define BROKEN(...)                                                                                                    \
    do {                                                                                                               \
        say(err, err_size, &at, "%s", ok ? "" : "; ");                                                                 \
        say(err, err_size, &at, __VA_ARGS__);                                                                          \
        ok = false;                                                                                                    \
    } while (0)
    if (!(isfinite(q->exposure) && q->exposure > 0.0f)) BROKEN("exposure = %g is not finite and > 0", (double)q->exposure);
    uint32_t view;
    memcpy(&view, &q->debug_view, sizeof view);
    if (view >= FV_DEBUG_VIEW_COUNT) BROKEN("debug_view = %u is not a view (0..%d)", view, FV_DEBUG_VIEW_COUNT - 1);
    for (size_t i = 0; i < KNOB_COUNT; i++) {
        const fv_knob *k = &g_knobs[i];
        const unsigned char *p = (const unsigned char *)q + k->offset;
        if (k->type == FV_KNOB_BOOL && p[0] > 1) {
            BROKEN("%s holds byte %u, not a bool", k->name, p[0]);
            continue;
        }
        if (value_ok(k, fv_knob_get(k, q))) continue;
        expected(k, want, sizeof want);
        BROKEN("%s = %s is not %s", k->name, fv_knob_format(k, q, have, sizeof have), want);
    }
#undef BROKEN
    return ok ? FV_OK : FV_ERR_RANGE;
}

bool fv_quality_equal(const fv_quality *a, const fv_quality *b)
{
    if (!a || !b) return a == b;
    if (!(a->exposure == b->exposure) || a->debug_view != b->debug_view) return false;
    if (a->overlay != b->overlay) return false; /* a view setting: the overlay pass runs or not */
    if (!fv_lens_equal(&a->distort.lens, &b->distort.lens)) return false; /* the HMD's lens: not a knob */
    for (size_t i = 0; i < KNOB_COUNT; i++) {
        const fv_knob *k = &g_knobs[i];
        fv_knob_value x = fv_knob_get(k, a), y = fv_knob_get(k, b);
        bool same = k->type == FV_KNOB_BOOL ? x.b == y.b : k->type == FV_KNOB_FLOAT ? x.f == y.f : x.i == y.i;
        if (!same) return false;
    }
    return true;
}
