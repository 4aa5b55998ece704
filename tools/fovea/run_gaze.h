/* @brief Gaze for `fovea run`: a gaze source (reader thread + lock-free ring, re-open with backoff) on the device
 * a URI names; each frame drains the ring into the gaze pipeline and puts the predicted per-eye gaze (for the
 * frame's photon time) into the frame input. */
#ifndef FV_RUN_GAZE_H
#define FV_RUN_GAZE_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "fovea/fv_device.h"
#include "fovea/fv_frame_input.h"
#include "fv_gaze_pipeline.h"
#include "fv_gaze_source.h"

typedef struct cJSON cJSON;

typedef struct run_gaze {
    fv_gaze_source *source;
    fv_gaze_pipeline *pipeline;
    char uri[256];
    uint64_t samples, rejected, frames_with_gaze, frames;
    bool ended, lost;
    fv_gaze_source_status status;
    fv_gaze_prediction last;
} run_gaze;

FV_MUST_CHECK fv_result run_gaze_open(run_gaze *g, const char *uri);
/** Drain the device without blocking, push into the pipeline, predict to t_photon_ns and fill in->gaze/pupil. */
void run_gaze_latch(run_gaze *g, int64_t t_photon_ns, fv_frame_input *in);
void run_gaze_print(const run_gaze *g, FILE *f);
void run_gaze_add_json(const run_gaze *g, cJSON *obj);
void run_gaze_close(run_gaze *g);

#endif
