/* @brief What the runtime hands the renderer each frame: time, per-eye view/projection, per-eye gaze, pupil and
 * quality. Plain data, shared by runtime/ and render/ (the seam between them). */
#ifndef FV_FRAME_INPUT_H
#define FV_FRAME_INPUT_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_math.h"

typedef struct fv_eye_view {
    fv_mat4 view;        /* world -> eye view space (-z forward) */
    fv_mat4 proj;        /* eye view -> Vulkan clip */
    fv_vec3 pos_world;   /* eye position, metres */
    float tan_left, tan_right, tan_up, tan_down; /* the frustum the projection was built from */
    float near_m, far_m;
} fv_eye_view;

typedef struct fv_eye_gaze {
    bool valid;               /* false: no gaze (blink, lost): the renderer treats the whole view as the fovea */
    fv_vec3 dir_eye;          /* predicted unit gaze direction in eye view space (-z forward) */
    float uncertainty_deg;    /* radius by which the fovea must be widened */
} fv_eye_gaze;

typedef struct fv_frame_input {
    uint64_t frame_id;
    double time_s;            /* scene time for animations */
    fv_eye_view eye[2];       /* 0 = left, 1 = right */
    fv_eye_gaze gaze[2];
    float pupil_mm;           /* NaN when unknown */
    int64_t t_photon_ns;      /* when this frame's photons are due (host clock), 0 if unknown */
} fv_frame_input;

/** HMD-like default field of view per eye (degrees): outer, inner, up, down. Asymmetric: the outer side is wider. */
#define FV_HMD_FOV_OUTER_DEG 50.0f
#define FV_HMD_FOV_INNER_DEG 42.0f
#define FV_HMD_FOV_UP_DEG 45.0f
#define FV_HMD_FOV_DOWN_DEG 48.0f

#endif
