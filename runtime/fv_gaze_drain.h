/* @brief The one drain of a gaze source into a gaze pipeline, for every consumer (the frame loop, the application
 * layer's tracker that the OpenXR runtime reads): poll (inline sources), pop what the ring holds (bounded by its
 * capacity, so a flooding device cannot hold the caller), push each sample into the pipeline, keep the newest
 * accepted sample and the newest with a head pose, and decide loss: a source that is not connected, or that has sent
 * nothing for stall_timeout_ns, is lost, and the pipeline is told (fv_gaze_pipeline_set_device_lost), once per change,
 * with one warning line. One owner thread (callers serialise). */
#ifndef FV_GAZE_DRAIN_H
#define FV_GAZE_DRAIN_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_gaze_pipeline.h"
#include "fv_gaze_source.h"

typedef struct fv_gaze_drain {
    fv_gaze_source *source;     /* borrowed */
    fv_gaze_pipeline *pipeline; /* borrowed */
    int64_t stall_timeout_ns;
    void (*on_sample)(void *user, const fv_gaze_sample *s); /* optional: each sample the pipeline accepted */
    void *user;
    /* what has been drained */
    bool have_sample;
    fv_gaze_sample newest;       /* the newest accepted sample */
    int64_t newest_received_ns;  /* its receipt time (host; the drain time when it had none or a later one) */
    bool have_head;
    fv_gaze_sample newest_head;  /* the newest accepted sample with FV_GAZE_HEAD_VALID */
    uint64_t serial;             /* accepted samples so far */
    int64_t last_new_sample_ns;  /* when the drain last took a new sample (start: the init time) */
    bool lost;                   /* as last reported to the pipeline */
    bool warned_push, warned_future_receipt;
} fv_gaze_drain;

/** Set up (no I/O). stall_timeout_ns 0 = 100 ms. */
void fv_gaze_drain_init(fv_gaze_drain *d, fv_gaze_source *source, fv_gaze_pipeline *pipeline,
                        int64_t stall_timeout_ns, int64_t t_now_ns);
/** Drain now (t_now_ns on the source's host clock) and update the loss state. Returns whether the source counts as
 *  lost now. */
bool fv_gaze_drain_step(fv_gaze_drain *d, int64_t t_now_ns);

#endif
