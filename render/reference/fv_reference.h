/* @brief The CPU reference renderer: both eyes of an fv_scene, ray cast with Intel Embree 3 and shaded in double.
 * `model` mode evaluates fovea's own shading (render/include/fv_shade_common.glsl) per pixel centre with exact
 * visibility (shadow rays): what the GPU computes, minus its approximations. `path` mode is a path-traced ground
 * truth (Lambert, next-event estimation of the punctual lights and of emissive triangles with MIS, cosine bounces,
 * Russian roulette). Deterministic for a seed whatever the thread count. No clock, no I/O: the caller times it and
 * writes the images. */
#ifndef FV_REFERENCE_H
#define FV_REFERENCE_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_frame_input.h"
#include "fv_result.h"
#include "fv_scene.h"

typedef enum fv_reference_mode {
    /** fovea's shading formulas at each pixel centre (one primary ray, no antialiasing unless `aa`), every light's
     *  irradiance times its exact visibility, Lambert BRDF, plus emission and ambient: the GPU's image without its
     *  shadow-map approximation. Deterministic: spp only matters with `aa`. */
    FV_REFERENCE_MODEL = 0,
    /** Path-traced ground truth. Punctual lights: the same irradiance as model mode (same units, spot smoothstep,
     *  range window) through shadow rays. Emissive triangles are area lights, sampled uniformly by area and
     *  combined with BSDF sampling by the power heuristic (Veach 1997, eq. 9.13); emission is two-sided, as the
     *  GPU draws it. Cosine-weighted Lambert bounces; Russian roulette after FV_REFERENCE_RR_BOUNCES bounces.
     *  Rays that leave the scene after a bounce see the scene's ambient radiance (as a uniform sky); primary rays
     *  that miss are black, as on the GPU. */
    FV_REFERENCE_PATH = 1,
} fv_reference_mode;

/** What the image shows (the GPU's debug views where it has them). */
typedef enum fv_reference_view {
    FV_REFERENCE_VIEW_COLOR = 0,  /* outgoing radiance toward the eye (linear) */
    FV_REFERENCE_VIEW_DIRECT = 1, /* model: color without emission and ambient; path: direct light of the first hit
                                   * (punctual and area lights), no emission seen, no bounce */
    FV_REFERENCE_VIEW_SHADOW = 2, /* visibility of light `shadow_light` at the first hit, 0..1 (grey; 0 on a miss) */
    FV_REFERENCE_VIEW_ALBEDO = 3, /* linear albedo as the G-buffer stores it (0 on a miss) */
    FV_REFERENCE_VIEW_NORMAL = 4, /* n * 0.5 + 0.5 of the eye-facing shading normal (0 on a miss), as --debug-view */
    FV_REFERENCE_VIEW_DEPTH = 5,  /* Vulkan depth of the eye's projection, 0 (near) .. 1 (far; 1 on a miss), grey */
    FV_REFERENCE_VIEW_GI = 6,     /* model: indirect light only, albedo / pi x the exact VPL sum (0 without desc.gi) */
    FV_REFERENCE_VIEW_SSS = 7,    /* model: the subsurface term alone, the exact dipole sum (0 on opaque surfaces) */
    FV_REFERENCE_VIEW_COUNT
} fv_reference_view;

/** Bounces after which path mode starts Russian roulette (survival = max throughput component, at most 0.95). */
#define FV_REFERENCE_RR_BOUNCES 3u
/** Largest accepted `spp`, `bounces` and per-eye size. */
#define FV_REFERENCE_MAX_SPP 1048576u
#define FV_REFERENCE_MAX_BOUNCES 1024u
#define FV_REFERENCE_MAX_DIM 16384u

/** Progress callback: called from the worker threads (one at a time, under a lock) after each finished tile.
 *  Must be quick; it may not call back into the reference renderer. */
typedef void (*fv_reference_progress_fn)(void *user, uint64_t tiles_done, uint64_t tiles_total);

typedef struct fv_reference_desc {
    fv_reference_mode mode;
    fv_reference_view view;
    uint32_t spp;          /* samples per pixel; 0 = 1 (model) or 16 (path) */
    uint32_t bounces;      /* path: indirect bounces after the first hit. 0 is a value, not a default: direct light
                            * only (1 = one bounce). Russian roulette may end a path earlier */
    uint64_t seed;         /* per-pixel random streams derive from (seed, eye, x, y, sample) */
    uint32_t threads;      /* worker threads; 0 = the online CPUs */
    uint32_t eye_width, eye_height; /* pixels per eye; 0 = 720 x 800, as fv_renderer_desc */
    bool aa;               /* jitter each sample uniformly inside its pixel (box filter); false = pixel centres */
    uint32_t shadow_light; /* the light FV_REFERENCE_VIEW_SHADOW shows (default 0) */
    bool gi;               /* model mode: add the exact one-bounce VPL sum of in->quality.gi (render/gi's model, when
                            * gi.enabled); false = direct light only, as before GI existed */
    fv_reference_progress_fn progress; /* NULL = none */
    void *progress_user;
    bool (*cancelled)(void); /* polled between tiles (NULL = never): true stops the render, FV_ERR_CANCELLED */
} fv_reference_desc;

/** What one render did. */
typedef struct fv_reference_stats {
    uint64_t primary_rays, shadow_rays, bounce_rays;
    uint64_t rays;              /* the sum: every Embree query */
    uint64_t samples;           /* pixel samples over both eyes */
    uint64_t nonfinite_samples; /* samples whose value was not finite and counted as 0 (should stay 0) */
    uint32_t threads;           /* threads that rendered */
    uint32_t eye_width, eye_height;
    uint32_t triangles;         /* triangles handed to Embree (non-finite and zero-area ones are left out) */
    uint32_t skipped_triangles; /* left out: a non-finite or out-of-range vertex, or zero area */
    uint32_t emissive_triangles; /* area lights of path mode */
    double emissive_area_m2;
} fv_reference_stats;

/** The desc with every zero replaced by its default (spp depends on the mode). */
fv_reference_desc fv_reference_desc_defaults(const fv_reference_desc *desc);

/** Render both eyes of `scene` from `in->eye[0]` (left) and `in->eye[1]` (right) at scene time `in->time_s` (node
 *  transforms from fv_scene_node_world, as the GPU). out_rgb_left / out_rgb_right (either may be NULL to skip that
 *  eye) receive eye_width * eye_height linear RGB float triples, rows top to bottom (y down, as Vulkan's image).
 *  The scene and input are only read; they must not change during the call. Blocks until done; safe to call from
 *  several threads at once (each call has its own Embree scene). Every output value is finite and >= 0.
 *  Errors: FV_ERR_INVALID_ARG (NULL scene/input, a broken desc: each rule logged; an eye position or a scene
 *  position that is not finite or beyond FV_SCENE_MAX_COORD_M, see fv_scene_check_extent), FV_ERR_NO_MEMORY,
 *  FV_ERR_CANCELLED (desc->cancelled said stop: the outputs are partly written),
 *  FV_ERR_UNSUPPORTED (Embree could not start). stats may be NULL. */
FV_MUST_CHECK fv_result fv_reference_render(const fv_scene *scene, const fv_frame_input *in,
                                            const fv_reference_desc *desc, float *out_rgb_left, float *out_rgb_right,
                                            fv_reference_stats *out_stats);

/** fv_reference_render with the values in double, before they are rounded to float: for comparisons against closed
 *  forms (agreement to 1e-9 and better). Same contract otherwise. */
FV_MUST_CHECK fv_result fv_reference_render_f64(const fv_scene *scene, const fv_frame_input *in,
                                                const fv_reference_desc *desc, double *out_rgb_left,
                                                double *out_rgb_right, fv_reference_stats *out_stats);

/** The primary ray of the image point (px, py) in pixels (x right, y down; a pixel centre is (x + 0.5, y + 0.5))
 *  of a `width` x `height` view, computed in double from the inverse of proj * view (the matrices as floats, as the
 *  GPU has them): it starts on the near plane and ends on the far plane. out_dir_world is unit; *out_t_max is the
 *  distance from the near plane to the far plane along it. False (outputs zeroed) for a singular view. */
bool fv_reference_pixel_ray(const fv_eye_view *view, uint32_t width, uint32_t height, double px, double py,
                            double out_origin_world[3], double out_dir_world[3], double *out_t_max);

/** Names ("model", "path"; "color", "direct", "shadow", "albedo", "normal", "depth") and their parsers: false for
 *  an unknown name. */
const char *fv_reference_mode_name(fv_reference_mode mode);
const char *fv_reference_view_name(fv_reference_view view);
bool fv_reference_mode_parse(const char *name, fv_reference_mode *out_mode);
bool fv_reference_view_parse(const char *name, fv_reference_view *out_view);

#endif
