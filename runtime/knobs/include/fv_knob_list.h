/* @brief THE knob list: every speed/accuracy knob of fovea, one entry each. Everything else is derived from it: the
 * fields of fv_quality and fv_quality_default() (fv_quality.h), the knob table with its presets, parsing, formatting,
 * validation and sanitising (runtime/knobs/knobs.c), equality per group (fv_quality_<group>_equal, e.g. the GI pass's
 * cache key) and `fovea knobs`, --help, --set, --quality and the JSON summaries. docs/knobs.md: how to add a knob.
 *
 * One entry per knob, in the order of --help, `fovea knobs` and the JSON summaries (the struct's field order too):
 *   X(group, field, name, TYPE, ctype, min, max, pow2, unit, choices,
 *     fast, balanced, high, exact,
 *     doc, exact_note)
 * group      the fv_quality member and the name's prefix: shadow, fovea, distort, gi, sss, interp
 * field      the C field in fv_quality.<group>
 * name       the dotted name's second part: "<group>.<name>" (`--set shadow.splits=4`)
 * TYPE       BOOL (bool), INT (uint32_t), FLOAT (float) or ENUM (a 4-byte C enum with values 0..choices-1)
 * ctype      the field's C type: bool, uint32_t, float, or the enum's type
 * min, max   the inclusive range (0, 1 for BOOL; 0, choices-1 for ENUM); pow2: INT values must be powers of two
 * unit       "px", "texels", ... ; "" for counts and unitless values
 * choices    ENUM: the names of the values 0..n-1 in parentheses, ("none", "pcf3", "pcf5"); () otherwise
 * fast .. exact  the value under each preset (`--quality`); balanced is the default, fv_quality_default()
 * doc        one line; exact_note: why the exact version is not possible on the GPU and what `exact` uses instead
 *            (NULL when exact is simply every shortcut off)
 * A new group needs its FV_KNOBS_<GROUP> list, its member in fv_quality (fv_quality.h) and its place in
 * FV_KNOB_LIST below. Pure preprocessor data: no include guard needed, but it has one. */
#ifndef FV_KNOB_LIST_H
#define FV_KNOB_LIST_H

/* shadow.*: parallel-split shadow maps (render/shadow; Zhang et al. 2006, ../shared/papers/README.md §2). */
#define FV_KNOBS_SHADOW(X) \
    X(shadow, enabled, enabled, BOOL, bool, 0, 1, false, "", (), \
      true, true, true, true, \
      "draw the shadow pass: each light's visibility from shadow maps (off: nothing is shadowed)", NULL) \
    X(shadow, splits, splits, INT, uint32_t, 1, 8, false, "", (), \
      2, 4, 4, 8, \
      "splits of the view frustum along depth, one shadow map each (PSSM): more splits, less aliasing, more " \
      "draws", \
      "a shadow texel per screen pixel is out of reach of a few maps; the most splits, 8") \
    X(shadow, lambda, lambda, FLOAT, float, 0, 1, false, "", (), \
      0.5f, 0.5f, 0.5f, 0.75f, \
      "split scheme: lambda * logarithmic + (1 - lambda) * uniform split depths (PSSM)", \
      "the logarithmic scheme (1) evens out perspective aliasing but makes the nearest splits uselessly thin;" \
      " leans towards it with 0.75") \
    X(shadow, resolution_px, resolution, INT, uint32_t, 256, 4096, true, "px", (), \
      1024, 2048, 4096, 4096, \
      "side of each split's square shadow map", \
      "a shadow texel per screen pixel is out of reach of a fixed map; the largest, 4096 px") \
    X(shadow, filter, filter, ENUM, fv_shadow_filter, 0, 2, false, "", ("none", "pcf3", "pcf5"), \
      FV_SHADOW_FILTER_NONE, FV_SHADOW_FILTER_PCF3, FV_SHADOW_FILTER_PCF5, FV_SHADOW_FILTER_NONE, \
      "percentage-closer filter of the shadow test: none (one tap), pcf3 (3x3), pcf5 (5x5) texels", \
      "visibility is binary (lit or not) and a filter blurs it, so none") \
    X(shadow, bias_texels, bias, FLOAT, float, 0, 10, false, "texels", (), \
      1.5f, 1.5f, 1.5f, 1.0f, \
      "slope-scaled depth bias against shadow acne; too much detaches shadows from their casters", \
      "exact visibility needs no bias, but a depth map of finite texels shadows itself without one; a smaller" \
      " 1 texel") \
    X(shadow, constant_bias, constant_bias, FLOAT, float, 0, 16, false, "steps", (), \
      1.0f, 1.0f, 1.0f, 1.0f, \
      "constant depth bias of the shadow maps in the depth format's smallest resolvable steps, added to " \
      "shadow.bias", \
      "exact visibility needs no bias, but a depth map of finite precision shadows itself without one; one step") \
    X(shadow, stereo_shared, stereo_shared, BOOL, bool, 0, 1, false, "", (), \
      true, true, true, false, \
      "one set of splits for both eyes, fitted to the union of their frusta (off: one set per eye, twice the " \
      "shadow draws)", NULL)

/* fovea.*: foveated rendering (render/fovea: the sampling map from the predicted gaze, compaction,
 * reconstruction; ../shared/papers/README.md section 3). */
#define FV_KNOBS_FOVEA(X) \
    X(fovea, enabled, enabled, BOOL, bool, 0, 1, false, "", (), \
      true, true, true, false, \
      "foveated rendering: shade a gaze-driven subset of the pixels, reuse the previous frame's, reconstruct " \
      "the rest (off: every pixel shaded)", NULL) \
    X(fovea, mar_slope, mar_slope, FLOAT, float, 0, 1, false, "deg/deg", (), \
      0.03f, 0.022f, 0.016f, 0.022f, \
      "slope m of the linear minimum angle of resolution w = m e + w0 (e: eccentricity from the gaze)", NULL) \
    X(fovea, mar_w0_deg, mar_w0_deg, FLOAT, float, 0.001, 1, false, "deg", (), \
      1.0f / 40.0f, 1.0f / 48.0f, 1.0f / 60.0f, 1.0f / 48.0f, \
      "w0, the minimum angle of resolution at the gaze (also w_min of the sampling probability)", NULL) \
    X(fovea, min_prob, min_prob, FLOAT, float, 0.01, 1, false, "", (), \
      0.03f, 0.05f, 0.1f, 1.0f, \
      "xi, the smallest sampling probability (the far periphery); 1 samples every pixel", NULL) \
    X(fovea, block, block, INT, uint32_t, 2, 16, false, "px", (), \
      5, 5, 4, 2, \
      "side of the square blocks that each hold at least one sample (bounds the gap reconstruction fills)", NULL) \
    X(fovea, uncertainty, uncertainty, BOOL, bool, 0, 1, false, "", (), \
      false, true, true, true, \
      "widen the fovea by the predicted gaze's uncertainty (eccentricity e' = max(0, e - u))", NULL) \
    X(fovea, recon, recon, ENUM, fv_fovea_recon, 0, FV_FOVEA_RECON_LAST, false, "", ("nearest", "sibson", "idw", "soft"), \
      FV_FOVEA_RECON_SOFT, FV_FOVEA_RECON_SOFT, FV_FOVEA_RECON_SOFT, FV_FOVEA_RECON_NEAREST, \
      "how unshaded pixels are filled: nearest (the nearest sample's colour), sibson (approximate discrete " \
      "natural-neighbour interpolation over the Voronoi diagram, window = the block), idw " \
      "(inverse-distance-squared weights of the neighbouring blocks' samples), soft (an edge-aware Gaussian, G-buffer " \
      "plane and normal guided, of the 2x2 nearest blocks' samples, as wide as the local sample spacing: soft edges, " \
      "one pass)", NULL) \
    X(fovea, voronoi, voronoi, ENUM, fv_fovea_voronoi, 0, FV_FOVEA_VORONOI_LAST, false, "", ("jfa", "blocks"), \
      FV_FOVEA_VORONOI_BLOCKS, FV_FOVEA_VORONOI_BLOCKS, FV_FOVEA_VORONOI_BLOCKS, FV_FOVEA_VORONOI_BLOCKS, \
      "how the nearest sample of every pixel is found: jfa (jump flooding, 1+JFA from the block size) or " \
      "blocks (exact: a search of the neighbouring blocks' samples, one pass)", NULL) \
    X(fovea, compaction, compaction, ENUM, fv_fovea_compaction, 0, FV_FOVEA_COMPACTION_LAST, false, "", \
      ("tiles", "rows", "masked"), \
      FV_FOVEA_COMPACTION_TILES, FV_FOVEA_COMPACTION_TILES, FV_FOVEA_COMPACTION_TILES, FV_FOVEA_COMPACTION_TILES, \
      "how the samples become the shading's list: tiles (8x8 tiles, one atomic each), rows (the paper's " \
      "row-wise CSR reorder), masked (a full dispatch that skips unsampled pixels)", NULL) \
    X(fovea, temporal, temporal, INT, uint32_t, 0, 15, false, "frames", (), \
      12, 8, 4, 0, \
      "temporal reuse: the previous frame reprojected through the motion vectors (depth test), blended into " \
      "shaded pixels and reused for unshaded ones until they are this many frames older than their last " \
      "shading (0: none)", NULL) \
    X(fovea, saliency, saliency, FLOAT, float, 0, 1, false, "", (), \
      0.0f, 0.0f, 0.5f, 0.0f, \
      "weight of the saliency (CIELAB albedo gradient, normal gradient, object motion) that raises the " \
      "sampling probability at edges and moving objects (0: off)", NULL) \
    X(fovea, dof, dof, BOOL, bool, 0, 1, false, "", (), \
      true, true, true, false, \
      "depth of field: the eye's defocus blur (pupil diameter, focus at the surface under the gaze) widens " \
      "the minimum angle of resolution off the focal plane; no pupil from the tracker: no effect", NULL)

/* distort.*: the HMD lens (render/distort, the hidden-area mask in render/gbuffer). Not speed/accuracy trades of
 * the image but what the panel needs: on in every preset, exact included (an undistorted frame on an HMD panel is
 * wrong, not more exact; the mask removes only pixels no one can see). They act only with an HMD lens. */
#define FV_KNOBS_DISTORT(X) \
    X(distort, enabled, enabled, BOOL, bool, 0, 1, false, "", (), \
      true, true, true, true, \
      "pre-distort each eye for its HMD lens (radial polynomial, per-channel scale for chromatic aberration);" \
      " off: the undistorted eye images reach the target", NULL) \
    X(distort, mask, mask, BOOL, bool, 0, 1, false, "", (), \
      true, true, true, true, \
      "hidden-area mask: the pixels the lens never shows are never shaded (depth pre-fill in the G-buffer; " \
      "later passes skip them as nothing drawn)", NULL)

/* gi.*: one-bounce GI from the light quad-tree (render/gi; Ki & Oh 2007, ../shared/papers/README.md §1). The
 * threshold pairs of the paper: (0.45, 0.3), (0.25, 0.6), (0.05, 0.9). */
#define FV_KNOBS_GI(X) \
    X(gi, enabled, enabled, BOOL, bool, 0, 1, false, "", (), \
      true, true, true, true, \
      "one-bounce indirect light: a reflective shadow map per spot or directional light, clustered in a light" \
      " quad-tree (off: direct light only)", NULL) \
    X(gi, mode, mode, ENUM, fv_gi_mode, 0, 4, false, "", ("cut", "traverse", "bound", "rsm_sampling", "exact"), \
      FV_GI_CUT, FV_GI_CUT, FV_GI_CUT, FV_GI_EXACT, \
      "gather: cut (the flat cut list), traverse (the paper's per-pixel traversal), bound (refine while a " \
      "cluster's bound is large), rsm_sampling (Dachsbacher & Stamminger 2005), exact (every VPL)", NULL) \
    X(gi, rsm_size, rsm_size, INT, uint32_t, 1, 1024, true, "px", (), \
      128, 256, 512, 64, \
      "side of each light's reflective shadow map: one VPL per texel", \
      "the exact sum visits every VPL at every pixel (N^2 each); 64 px (4096 VPLs) keeps a frame within " \
      "seconds on lavapipe — exact for that RSM") \
    X(gi, start_level, start_level, INT, uint32_t, 1, 64, true, "nodes", (), \
      16, 8, 8, 8, \
      "nodes per side of the level the traversal and the cut start from (coarser nodes are never one light)", NULL) \
    X(gi, limit_level, limit_level, ENUM, fv_gi_limit, 0, 3, false, "nodes", ("16", "32", "64", "leaf"), \
      FV_GI_LIMIT_16, FV_GI_LIMIT_32, FV_GI_LIMIT_64, FV_GI_LIMIT_LEAF, \
      "nodes per side of the level always taken as valid: bounds the clusters per pixel (16: 256, 32: 1024, " \
      "64: 4096), leaf: no bound", NULL) \
    X(gi, depth_threshold, depth_threshold, FLOAT, float, 0, 1, false, "", (), \
      0.45f, 0.25f, 0.05f, 0.05f, \
      "a cluster is valid when each child's depth from the light is within this of the mean (a fraction of " \
      "the scene's size)", NULL) \
    X(gi, normal_threshold, normal_threshold, FLOAT, float, -1, 1, false, "", (), \
      0.3f, 0.6f, 0.9f, 0.9f, \
      "a cluster is valid when each child's normal has a dot product above this with the mean normal", NULL) \
    X(gi, samples, samples, INT, uint32_t, 1, 65536, false, "", (), \
      128, 256, 1024, 4096, \
      "RSM samples per pixel of gi.mode=rsm_sampling", NULL) \
    X(gi, bound_fraction, bound_fraction, FLOAT, float, 0.00001, 1, false, "", (), \
      0.05f, 0.01f, 0.002f, 0.0001f, \
      "gi.mode=bound: a cluster is one light when its bound is at most this fraction of the start level's " \
      "estimate", NULL) \
    X(gi, average, average, ENUM, fv_gi_average, 0, 1, false, "", ("flux", "plain"), \
      FV_GI_AVERAGE_FLUX, FV_GI_AVERAGE_FLUX, FV_GI_AVERAGE_FLUX, FV_GI_AVERAGE_FLUX, \
      "how a tree node averages its children's position, depth and normal: flux (weighted by their power, the" \
      " cluster's flux centroid; measured closer to exact, BENCHMARKS.md) or plain (equal weights)", NULL) \
    X(gi, refine, refine, FLOAT, float, 0, 1, false, "", (), \
      0.0f, 0.0f, 0.0f, 0.0f, \
      "gi.mode=cut: a cut cluster whose extent is more than this times its distance from the pixel is " \
      "replaced, for that pixel, by its children (recursively; the near field), 0: the flat cut alone", NULL) \
    X(gi, rate, rate, ENUM, fv_gi_rate, 0, FV_GI_RATE_LAST, false, "", ("full", "half", "quarter", "eighth"), \
      FV_GI_RATE_EIGHTH, FV_GI_RATE_QUARTER, FV_GI_RATE_QUARTER, FV_GI_RATE_FULL, \
      "where the indirect light is gathered: full (every shaded pixel), half, quarter or eighth (once per 2x2, 4x4 " \
      "or 8x8 block of the G-buffer, then a joint-bilateral upsample guided by depth and normal; a pixel no block " \
      "sample matches gathers itself)", NULL)

/* sss.*: subsurface scattering, dipole diffusion over a quad-tree of light-view samples (render/sss; Ki & Oh,
 * ../shared/papers/README.md section 4). Levels count from the root (level k: 2^k x 2^k clusters). */
#define FV_KNOBS_SSS(X) \
    X(sss, enabled, enabled, BOOL, bool, 0, 1, false, "", (), \
      true, true, true, true, \
      "subsurface light on translucent materials (dipole, Jensen et al. 2001); off: shaded as opaque", NULL) \
    X(sss, map_size_px, map_size, INT, uint32_t, 16, 512, true, "px", (), \
      64, 128, 256, 128, \
      "side of each light-view sample map (one per light and translucent material): map_size^2 samples", \
      "the exact sum is over every sample, so its cost grows with map_size^2; 128 keeps it measurable") \
    X(sss, start_level, start_level, INT, uint32_t, 0, 9, false, "", (), \
      0, 0, 0, 0, \
      "the level the per-pixel cut starts from (the paper's 3 = 8 x 8 clusters; 0, the root, lets the cutoff " \
      "drop far halves whole: 1.5x faster, the same image, see BENCHMARKS.md)", NULL) \
    X(sss, limit_level, limit_level, INT, uint32_t, 0, 9, false, "", (), \
      5, 7, 8, 9, \
      "the finest level the cut reaches; its clusters are always accepted (the paper's 4 = 16 x 16 bounds the" \
      " work at 4^limit clusters per pixel but blurs: see BENCHMARKS.md); at the leaves only the distance " \
      "rule refines", NULL) \
    X(sss, distance_scale, distance_scale, FLOAT, float, 0, 100, false, "1/m", (), \
      2.0f, 1.5f, 1.0f, 0.0f, \
      "a cluster of radius r at distance d is accepted when r <= distance_scale x eye distance (m) x " \
      "similarity x d: coarser clusters farther from the eye; 0 refines to the limit level", NULL) \
    X(sss, mode, mode, ENUM, fv_sss_mode, 0, 1, false, "", ("hierarchy", "exact"), \
      FV_SSS_MODE_HIERARCHY, FV_SSS_MODE_HIERARCHY, FV_SSS_MODE_HIERARCHY, FV_SSS_MODE_EXACT, \
      "hierarchy: a cut through the quad-tree per pixel; exact: every sample (brute force)", NULL) \
    X(sss, cutoff, cutoff, FLOAT, float, 0, 0.5, false, "", (), \
      0.01f, 0.005f, 0.001f, 0.0f, \
      "the hierarchy skips clusters wholly beyond the radius outside which this fraction of a point source's " \
      "diffuse reflectance leaves (on a uniformly lit plane: the fraction of subsurface light dropped); 0: " \
      "none", NULL)

/* interp.*: hierarchical screen-space interpolation (render/interp; Ki & Oh, ../shared/papers/README.md section
 * 4). Level k: regions of 2^k x 2^k px. */
#define FV_KNOBS_INTERP(X) \
    X(interp, enabled, enabled, BOOL, bool, 0, 1, false, "", (), \
      false, false, false, false, \
      "shade coherent screen regions at their corners and interpolate the rest (off: every pixel shaded)", \
      "interpolated pixels are approximations; every pixel is shaded") \
    X(interp, threshold, threshold, FLOAT, float, 0, 1000, false, "", (), \
      0.3f, 0.2f, 0.05f, 0.0f, \
      "tau: a region is coherent when each member's 1 - cos(normal, mean), distance off the mean tangent " \
      "plane in region widths (2^k px at the eye distance), and linear albedo difference are all <= tau (one " \
      "material; interp.light: the direct light too); 0: exact agreement only. Balanced 0.2: the knee " \
      "measured in BENCHMARKS.md", NULL) \
    X(interp, start_level, start_level, INT, uint32_t, 1, 7, false, "", (), \
      3, 2, 2, 1, \
      "the coarsest regions, 2^k x 2^k px: a coherent one is shaded at its 4 corners (the paper: 4x4 px at " \
      "512x512)", NULL) \
    X(interp, light, light, BOOL, bool, 0, 1, false, "", (), \
      false, true, true, true, \
      "coherence also needs the members' direct light (shadows included) within tau of the mean: no " \
      "interpolation across shadow edges, at one direct-light evaluation per G-buffer read of the pyramid", NULL)

/* Every knob, in table order. */
#define FV_KNOB_LIST(X)                                                                                              \
    FV_KNOBS_SHADOW(X) FV_KNOBS_FOVEA(X) FV_KNOBS_DISTORT(X) FV_KNOBS_GI(X) FV_KNOBS_SSS(X) FV_KNOBS_INTERP(X)

#endif
