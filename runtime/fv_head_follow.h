/* @brief Following a tracker's recorded head pose (FV_GAZE_HEAD_VALID samples: head position and forward in the
 * tracker's world) relative to the first pose it reported: the one head source of `fovea run --head trace` and the
 * OpenXR runtime's head (issue 23: head pose moves the eyes' views, never the gaze relative to them). Pure: no I/O. */
#ifndef FV_HEAD_FOLLOW_H
#define FV_HEAD_FOLLOW_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_gaze_sample.h"
#include "fv_math.h"

/** Head travel beyond this from the first pose is a broken pose (mm). */
#define FV_HEAD_FOLLOW_LIMIT_MM 1.0e5

typedef struct fv_head_follow {
    bool have_ref;      /* the first usable pose has been seen */
    fv_vec3 ref_pos_mm; /* the first pose: where the head is when following starts */
    fv_quat ref_q;
    uint64_t ref_seq;   /* its sample's sequence number */
} fv_head_follow;

/** The head of sample s relative to the first usable pose, in that pose's frame: rotation *out_dq and translation
 *  *out_dp_m (metres); the first usable sample becomes the reference (identity). false (outs untouched) when s is
 *  NULL, carries no head, or its head is not finite, has no forward, or lies beyond FV_HEAD_FOLLOW_LIMIT_MM. The
 *  recorded forward gives yaw and pitch; roll is not recorded and stays 0. */
bool fv_head_follow_delta(fv_head_follow *h, const fv_gaze_sample *s, fv_quat *out_dq, fv_vec3 *out_dp_m);

#endif
