/* @brief `fovea run --head`: which head the stereo camera follows in a gaze-driven run. `trace` (the default with
 * --gaze): the scene's head moved by the tracker's recorded head pose relative to the first pose it reported (a
 * recording from SRanipal, Pico or fovea's own format); `scene`: the scene's head, the tracker's pose ignored;
 * `fixed`: the scene's head as it is at time 0, held for the whole run. Pure: no I/O. */
#ifndef FV_RUN_HEAD_H
#define FV_RUN_HEAD_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_math.h"
#include "fv_scene.h"

typedef enum run_head_mode { RUN_HEAD_TRACE = 0, RUN_HEAD_SCENE, RUN_HEAD_FIXED } run_head_mode;

typedef struct run_head {
    run_head_mode mode;
    bool applied;         /* the last run_head_apply used a recorded pose */
    uint64_t seq;         /* and this sample's sequence number */
    uint64_t frames_moved;
} run_head;

/** "trace", "scene", "fixed"; false for anything else. */
bool run_head_mode_parse(const char *s, run_head_mode *out);
const char *run_head_mode_name(run_head_mode m);
/** The head of a frame: `scene` moved by the tracker's recorded pose relative to its first (dq, dp_m: the application
 *  layer's fv_app_tracker_head; dq NULL: none yet, the scene's head), in trace mode; `scene` as is otherwise. seq:
 *  the head sample's sequence number, for the frame log. Finite for any input. */
void run_head_apply(run_head *h, const fv_quat *dq, const fv_vec3 *dp_m, uint64_t seq, const fv_head *scene,
                    fv_head *out);

#endif
