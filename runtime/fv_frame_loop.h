/* @brief The frame loop: wait for the frame → latch the newest gaze → predict to photon time → render → present →
 * one latency record per frame id.
 *
 * Pacing: each frame targets the earliest refresh that leaves room for the expected render time (the longest of the
 * recent frames) plus a safety margin and the display's latch margin, and never a refresh already used; the loop
 * sleeps (on the injected clock) until that deadline minus the expected cost, so the gaze is latched as late as
 * possible. One frame at a time: a render over budget makes that frame late (shown a refresh later) and later frames
 * are paced further ahead — refreshes repeat, latency stays bounded, nothing queues. The gaze device is only ever
 * drained (lock-free ring), never waited for; a device that is lost, has ended, or has sent nothing for
 * stall_timeout_ns is reported to the pipeline (fv_gaze_pipeline_set_device_lost), which widens the uncertainty.
 * One owner thread; not thread-safe. */
#ifndef FV_FRAME_LOOP_H
#define FV_FRAME_LOOP_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_display.h"
#include "fovea/fv_frame_input.h"
#include "fv_gaze_drain.h"
#include "fv_gaze_pipeline.h"
#include "fv_gaze_source.h"
#include "fv_latency.h"

/** What the renderer reports about one frame, on the loop's host clock. Zero = unknown: submit defaults to when the
 *  callback returned, GPU begin/end to submit (no separate GPU timeline). */
typedef struct fv_frame_render_times {
    int64_t t_submit_ns;    /* CPU work handed to the GPU */
    int64_t t_gpu_begin_ns; /* GPU started this frame's work */
    int64_t t_gpu_end_ns;   /* GPU finished (the frame may be presented from then on) */
} fv_frame_render_times;

/** A frame's times from what a renderer observes on the host: the callback began at t_cpu_begin_ns, its draw call
 *  returned at t_returned_ns, the frame's fence was seen signalled at t_fence_ns (>= t_returned_ns), and the GPU's
 *  own timestamps span gpu_ns from the frame's first command to its last. The GPU's interval ends at the fence and
 *  lasts gpu_ns. When it began before the draw returned (a draw that waited for the GPU inside it: a software
 *  device's present or image acquire, which would otherwise book the GPU's time as CPU time), the work was submitted
 *  when the GPU began: the CPU stage ends there. gpu_ns <= 0 (unknown): the GPU from the return to the fence. */
void fv_frame_times_from_fence(int64_t t_cpu_begin_ns, int64_t t_returned_ns, int64_t t_fence_ns, int64_t gpu_ns,
                               fv_frame_render_times *out);

/** Render one frame. The loop fills the time, the gaze (already in each eye's view space, from the head-frame
 *  prediction through the eyes' poses in the head: fv_eye_gaze_from_head) and pupil; the callback places the head
 *  (in->head) and builds the eye views (in->eye, zero on entry) for it, once: the head's pose moves the views and
 *  never the gaze relative to them. An error stops the loop's step. */
typedef fv_result (*fv_frame_render_fn)(void *user, fv_frame_input *in, fv_frame_render_times *out_times);

/** Zero means default. */
typedef struct fv_frame_loop_desc {
    const fv_clock *clock;          /* required: the host clock (the one the display and the device use) */
    fv_display *display;            /* required; borrowed */
    fv_frame_render_fn render;      /* required */
    void *render_user;
    fv_gaze_source *gaze;           /* optional; borrowed. Without it (and without drain) every frame has no gaze */
    fv_gaze_pipeline *pipeline;     /* required with gaze; borrowed */
    fv_gaze_drain *drain;           /* optional, instead of gaze + pipeline: the caller's drain (the application
                                       layer's tracker, fv_app_tracker.h), borrowed; its stall timeout applies */
    int64_t tracker_latency_ns;     /* the tracker's capture → host receipt latency, if known (0: counted as 0) */
    int64_t stall_timeout_ns;       /* no new sample for this long: treated as lost; 0 = 100 ms */
    int64_t safety_margin_ns;       /* slack added to the expected render time; 0 = 1 ms; negative = none */
    int64_t initial_render_estimate_ns; /* expected render time before any frame ran; 0 = half a period */
    float ipd_mm;                   /* the eyes' distance in the head (in->head.ipd_mm); 0 = 63 */
    int32_t warmup_frames;          /* the first frames (shader compiles, first uploads) whose render cost leaves the
                                       estimate as soon as a later frame was measured, so that their stall does not
                                       pace the next frames (and widen the prediction horizon); 0 = 2, < 0 = none */
} fv_frame_loop_desc;

typedef struct fv_frame_loop fv_frame_loop;

FV_MUST_CHECK fv_result fv_frame_loop_create(const fv_frame_loop_desc *desc, fv_frame_loop **out_loop);
void fv_frame_loop_destroy(fv_frame_loop **loop);

/** Run one frame and fill its latency record (optional). Returns the render callback's or the display's error as is
 *  (logged). */
FV_MUST_CHECK fv_result fv_frame_loop_step(fv_frame_loop *loop, fv_latency_record *out_record);

/** The prediction used by the most recent frame. */
void fv_frame_loop_last_prediction(const fv_frame_loop *loop, fv_gaze_prediction *out_prediction);
/** The newest sample drained so far that carried a head pose (FV_GAZE_HEAD_VALID: head_pos_mm, head_dir in the
 *  tracker's frame), as the device gave it (not predicted). false (out untouched) until one has come. */
bool fv_frame_loop_newest_head(const fv_frame_loop *loop, fv_gaze_sample *out_sample);


#endif
