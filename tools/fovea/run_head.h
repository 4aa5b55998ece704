/* @brief `fovea run --head`: which head the stereo camera follows in a gaze-driven run. `trace` (the default with
 * --gaze): the scene's head moved by the tracker's recorded head pose relative to the first pose it reported (a
 * recording from SRanipal, Pico or fovea's own format); `scene`: the scene's head, the tracker's pose ignored;
 * `fixed`: the scene's head as it is at time 0, held for the whole run. Pure: no I/O. */
#ifndef FV_RUN_HEAD_H
#define FV_RUN_HEAD_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_app_run.h"
#include "fv_math.h"
#include "fv_scene.h"

typedef struct run_head {
    fv_app_head mode;     /* the run's (fv_app_run.head: trace, scene, fixed; fv_app_head_parse, fv_app_head_name) */
    bool applied;         /* the last run_head_apply used a recorded pose */
    uint64_t seq;         /* and this sample's sequence number */
    uint64_t frames_moved;
} run_head;

/** The head of a frame: `scene` moved by the tracker's recorded pose relative to its first (dq, dp_m: the application
 *  layer's fv_app_tracker_head; dq NULL: none yet, the scene's head), in trace mode; `scene` as is otherwise. seq:
 *  the head sample's sequence number, for the frame log. Finite for any input. */
void run_head_apply(run_head *h, const fv_quat *dq, const fv_vec3 *dp_m, uint64_t seq, const fv_head *scene,
                    fv_head *out);

#endif
