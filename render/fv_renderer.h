/* @brief The renderer: one object with a small surface. Create from a description, load a scene, draw frames from
 * fv_frame_input, read statistics and images back, destroy. Owns the Vulkan device. One thread at a time. */
#ifndef FV_RENDERER_H
#define FV_RENDERER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fovea/fv_frame_input.h"
#include "fv_plan.h"
#include "fv_result.h"
#include "fv_scene.h"

typedef struct fv_target fv_target;

typedef struct fv_renderer fv_renderer;

struct fv_pass;

typedef struct fv_renderer_desc {
    uint32_t eye_width, eye_height; /* per-eye render size; 0 = 720x800 */
    const char *device;             /* index or name substring; NULL = $FOVEA_DEVICE, else prefer a discrete GPU */
    int validation;                 /* 1 on, 0 = from $FOVEA_VALIDATION */
    uint32_t frames_in_flight;      /* 0 = 2, at most FV_MAX_FRAMES_IN_FLIGHT (8) */
    uint64_t memory_budget_bytes;   /* 0 = 80% of the largest device-local heap */
    fv_target *target;              /* where frames are shown (fv_target.h; borrowed, outlives the renderer);
                                     * NULL = headless */
    const struct fv_pass *const *pass_table; /* the passes in frame order (fv_pass.h; borrowed, outlives the
                                     * renderer); NULL = the built-in table (render/frame_plan.c). Tests add a pass
                                     * of their own this way: its folder and one line of a table */
    uint32_t pass_count;            /* entries of pass_table, at most FV_MAX_PASSES */
    bool motion_target;             /* draw the G-buffer's motion vectors for fv_renderer_read_motion (no pass reads
                                     * them: off, the target is not drawn) */
} fv_renderer_desc;

/** Per-pass GPU time and counters of one completed frame (the passes that ran, in order). */
typedef struct fv_render_stats {
    uint64_t frame_id;               /* frame these timings belong to */
    uint32_t pass_count;
    char pass_name[FV_MAX_PASSES][FV_PASS_ID_MAX];
    double pass_gpu_ms[FV_MAX_PASSES];
    fv_pass_counters pass_counters[FV_MAX_PASSES]; /* what each pass did (draws, triangles, pixels, dispatches) */
    double frame_gpu_ms;             /* first timestamp to last */
    uint64_t pixels_shaded;          /* sum over the passes */
    uint64_t device_memory_bytes;    /* currently allocated device memory */
    uint64_t peak_device_memory_bytes;
} fv_render_stats;

FV_MUST_CHECK fv_result fv_renderer_create(const fv_renderer_desc *desc, fv_renderer **out_renderer);
/** Wait for the GPU, free everything, set *r to NULL. Safe on NULL. */
void fv_renderer_destroy(fv_renderer **r);
/** Upload a scene (the renderer keeps no pointer to it) and rebuild the frame plan. */
FV_MUST_CHECK fv_result fv_renderer_load_scene(fv_renderer *r, const fv_scene *scene);
const fv_frame_plan *fv_renderer_plan(const fv_renderer *r);
/** Plan for these quality settings now (a frame drawn with other settings re-plans by itself): passes switched on
 *  start, passes switched off stop (waiting for the GPU first). Out-of-range values fall back to the defaults. */
FV_MUST_CHECK fv_result fv_renderer_set_quality(fv_renderer *r, const fv_quality *quality);
/** Record and submit one frame. Returns once submitted (frames in flight overlap). */
FV_MUST_CHECK fv_result fv_renderer_draw(fv_renderer *r, const fv_frame_input *in);
/** Wait for all submitted frames; stats then describe the last one. */
FV_MUST_CHECK fv_result fv_renderer_finish(fv_renderer *r);
/** How many recently completed frames keep their timings for fv_renderer_frame_stats. */
#define FV_RENDERER_STATS_HISTORY 16
/** Timings of one recently completed frame by id: FV_OK, or FV_NO_NEW_DATA when that frame has not completed yet
 *  or is older than the last FV_RENDERER_STATS_HISTORY completed frames (frame ids must be distinct and rising). */
FV_MUST_CHECK fv_result fv_renderer_frame_stats(const fv_renderer *r, uint64_t frame_id, fv_render_stats *out_stats);
/** Timings of the most recently completed frame (FV_NO_NEW_DATA before the first completes). */
FV_MUST_CHECK fv_result fv_renderer_stats(const fv_renderer *r, fv_render_stats *out_stats);
/** Read the last drawn frame's final colour as 8-bit sRGB RGBA. sbs: both eyes side by side (2W x H), else one eye
 *  (eye 0/1, W x H). out must hold the stated size. Waits for the GPU. */
FV_MUST_CHECK fv_result fv_renderer_read_rgba8(fv_renderer *r, bool sbs, int eye, uint8_t *out, size_t out_size);
/** Read the last frame's linear colour (RGBA float) of one eye, for tests against a CPU reference. */
FV_MUST_CHECK fv_result fv_renderer_read_linear(fv_renderer *r, int eye, float *out_rgba, size_t out_floats);
/** Read the last frame's G-buffer motion vectors of one eye (eye 0/1 = image layer 0/1), for tests: 2 floats per
 *  pixel (x, y), rows top to bottom, W x H. Units are uv (the image spans [0,1] in x and y, y down; multiply x by
 *  the eye width and y by the eye height for pixels); each vector is current uv - previous uv, i.e. where the
 *  surface at this pixel is now minus where it was in the previously drawn frame (previous view/projection and
 *  previous object transforms). Zero where nothing was drawn, and everywhere in the first frame after a scene load.
 *  Stored as half floats (RG16F) and widened here. out_rg must hold W * H * 2 floats. Waits for the GPU. Only a
 *  renderer made with fv_renderer_desc.motion_target draws them (FV_ERR_STATE otherwise, said in one line). */
FV_MUST_CHECK fv_result fv_renderer_read_motion(fv_renderer *r, int eye, float *out_rg, size_t out_floats);
/** Read one eye of a pass's image of the renderer's table by its name (e.g. "fovea prob": R32F), texel_bytes per
 *  texel, rows tightly packed (waits for the GPU). FV_ERR_NOT_FOUND when no such image exists (the pass is off). */
FV_MUST_CHECK fv_result fv_renderer_read_image(fv_renderer *r, const char *name, int eye, void *out, size_t out_size,
                                               size_t texel_bytes);
/** What a running pass decided for the last frame, as named numbers (e.g. the shadow pass: per shadowed light its
 *  near_m, far_m and splits_m); 0 when the pass is off or has nothing to say. */
uint32_t fv_renderer_pass_details(const fv_renderer *r, const char *pass, fv_pass_detail *out, uint32_t cap);
/** For tests of one pass: the running pass's state (the pointer its init returned; NULL when it is off), to hand to
 *  that pass's own test functions (e.g. fv_gi_read_tree). The GPU must be idle when those use it. */
void *fv_renderer_pass_state(const fv_renderer *r, const char *pass);
/** Count of validation-layer messages seen so far (warnings and errors). */
uint32_t fv_renderer_validation_messages(const fv_renderer *r);
/** Device name, for summaries. */
const char *fv_renderer_device_name(const fv_renderer *r);

/** Re-shade only the listed pixels of the last frame's G-buffer (each packed with FV_GPU_PIXEL_PACK(x, y, eye) from
 *  fv_gpu.h) through the same shading function, then run the passes after shading again (debug view, present). When clear_rgba is not NULL the linear
 *  colour image is first cleared to that value (to see which pixels were written). Waits for the GPU. Errors:
 *  FV_ERR_STATE before the first frame, FV_ERR_RANGE for a pixel outside the image (nothing is shaded then). */
FV_MUST_CHECK fv_result fv_renderer_shade_pixels(fv_renderer *r, const uint32_t *packed, uint32_t count,
                                                 const float *clear_rgba);
/** Per-eye size in pixels. */
void fv_renderer_size(const fv_renderer *r, uint32_t *out_width, uint32_t *out_height);
/** Frame input for the loaded scene's head at time_s: near/far from the scene bounds (see
 *  fv_frame_near_far_from_bounds). head NULL = the scene's head. FV_ERR_STATE without a scene. */
FV_MUST_CHECK fv_result fv_renderer_frame_input(const fv_renderer *r, const fv_head *head, uint64_t frame_id,
                                                double time_s, fv_frame_input *out);

/** Build the frame plan for a scene (no GPU needed; multiview assumed, default quality): every pass, whether it
 *  runs, and why. */
void fv_frame_plan_build(const fv_scene *scene, fv_frame_plan *out);
/** The entry of a pass by name ("gbuffer", "motion", "shadow", "gi", "sss", "fovea", "shade", "debug",
 *  "present"), or NULL. */
const fv_plan_entry *fv_frame_plan_find(const fv_frame_plan *plan, const char *pass);

/** Near/far planes that hold the bounding sphere of [bounds_min, bounds_max] seen from the head (both eyes), with a
 *  margin; finite and far > near for any input (NaN bounds give 0.05 / 100 m). */
void fv_frame_near_far_from_bounds(const fv_head *head, fv_vec3 bounds_min, fv_vec3 bounds_max, float *out_near_m,
                                   float *out_far_m);

/** Frame input for a scene head: the eye views from fv_eye_views_build (fv_frame_input.h: IPD clamped to
 *  [0, FV_SCENE_MAX_IPD_MM], NaN = 63 mm; the HMD default asymmetric field of view with square pixels for this image
 *  size; near/far <= 0 or non-finite: 0.05 m / 100 m — fv_renderer_frame_input uses the scene bounds instead),
 *  the head pose, gaze straight ahead and valid, pupil unknown, default quality. */
void fv_frame_input_from_head(const fv_head *head, float near_m, float far_m, uint32_t eye_width,
                              uint32_t eye_height, uint64_t frame_id, double time_s, fv_frame_input *out);

#endif
