/* @brief Gaze-driven runs of `fovea run --gaze URI`: the runtime's frame loop (fv_frame_loop) paced by a display
 * (a simulated display on the monotonic clock: the headless target has no swapchain), latching from the application
 * layer's gaze tracker (runtime/app: source, pipeline, drain, loss; the one the OpenXR runtime reads), the renderer as
 * the loop's render callback, and one latency record per frame (gaze sampled → photons due). */
#ifndef FV_RUN_GAZE_H
#define FV_RUN_GAZE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "fv_app_tracker.h"
#include "fv_frame_loop.h"

typedef struct cJSON cJSON;

typedef struct run_gaze {
    char uri[256];
    double refresh_hz;
    fv_display *display;
    bool display_borrowed;          /* a presenter's display clock (run_gaze_open_on), not ours to destroy */
    char clock[64];                 /* which clock paces the frames, for the summary */
    fv_app_tracker *tracker;        /* the application layer's tracker (hotplug re-opens included) */
    fv_frame_loop *loop;
    fv_latency_record *records; /* one per frame stepped */
    size_t count, cap;
} run_gaze;

/** Open the gaze device by URI (the application layer's tracker), before anything else of the run is made: a
 *  source that cannot be opened fails the run at once, with one line naming it. no_predict: the latest filtered
 *  sample instead of the prediction (fv_gaze_pipeline_desc.disable_prediction). */
FV_MUST_CHECK fv_result run_gaze_open(run_gaze *g, const char *uri, bool no_predict);
/** Build the loop around `render` (called once per frame with the frame input: gaze (in each eye's view space,
 *  fv_eye_gaze_from_head) and photon time filled by the loop, head and views to be set by the callback), paced by a
 *  given display clock (a window's swapchain; borrowed, outlives g), or by a simulated display at refresh_hz when
 *  display is NULL. ipd_mm: the eyes' distance in the head (0 = 63). */
FV_MUST_CHECK fv_result run_gaze_start(run_gaze *g, fv_display *display, double refresh_hz, size_t frames,
                                       fv_frame_render_fn render, void *render_user, float ipd_mm);
/** One frame through the loop (waits for its refresh on the real clock). */
FV_MUST_CHECK fv_result run_gaze_step(run_gaze *g);
void run_gaze_print(const run_gaze *g, FILE *f);
void run_gaze_add_json(const run_gaze *g, cJSON *obj);
void run_gaze_close(run_gaze *g);

#endif
