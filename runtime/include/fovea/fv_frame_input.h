/* @brief What the runtime hands the renderer each frame: time, per-eye view/projection, per-eye gaze, pupil and
 * quality. Plain data, shared by runtime/ and render/ (the seam between them). */
#ifndef FV_FRAME_INPUT_H
#define FV_FRAME_INPUT_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_math.h"
#include "fv_lens.h"
#include "fv_quality.h" /* fv_quality: defined by the knobs room (runtime/knobs), carried here */

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

/** The head in the world: where it is, which way it looks (its local -z), and the distance between the eyes. */
typedef struct fv_head_pose {
    fv_vec3 position_m;
    fv_quat orientation;
    float ipd_mm;
} fv_head_pose;

typedef struct fv_frame_input {
    uint64_t frame_id;
    double time_s;            /* scene time for animations */
    fv_head_pose head;        /* the head the eye views were built from */
    fv_eye_view eye[2];       /* 0 = left, 1 = right */
    fv_eye_gaze gaze[2];
    float pupil_mm;           /* NaN when unknown */
    int64_t t_photon_ns;      /* when this frame's photons are due (host clock), 0 if unknown */
    fv_quality quality;       /* what this frame is drawn with */
} fv_frame_input;

/** Build both eyes' views from a head pose (NULL = at the origin looking down -z, IPD 63 mm): eyes at +-IPD/2
 *  along the head's x axis (IPD clamped to [0, FV_MAX_IPD_MM]; NaN = 63 mm), the HMD default asymmetric field of
 *  view (vertical extent FV_HMD_FOV_UP/DOWN; horizontal extent from the image aspect, square pixels, split
 *  outer:inner as FV_HMD_FOV_OUTER:INNER, mirrored per eye, eye 0 = left, outer = left), near/far clamped so the
 *  projection stays finite (<= 0 or non-finite: 0.05 m / 100 m). Finite for any input (NaN poses: identity). */
void fv_eye_views_build(const fv_head_pose *head, float near_m, float far_m, uint32_t eye_width, uint32_t eye_height,
                        fv_eye_view out[2]);

/** The same with each eye's field of view given (an HMD profile's): fov[4 eye + i] = the tangents of its left,
 *  right, up and down half-angles (i = 0..3), all > 0 (eye 0 = left). A tangent that is not finite or outside
 *  [1e-3, 100] takes the default's. */
void fv_eye_views_build_fov(const fv_head_pose *head, float near_m, float far_m, const float fov[8],
                            fv_eye_view out[2]);

/** Clamp near/far planes to what keeps a projection finite: near <= 0 or non-finite -> 0.05 m, near in
 *  [1e-5, 5e8] m; far <= 0 or non-finite -> max(100 m, 1000 near), far <= 1e9 m and > 1.001 near. */
void fv_near_far_sanitize(float *near_m, float *far_m);

/** Near/far planes that hold the bounding sphere of [bounds_min, bounds_max] seen from the head (both eyes), with a
 *  margin; finite and far > near for any input (NULL head or NaN bounds: 0.05 / 100 m). */
void fv_near_far_from_bounds(const fv_head_pose *head, fv_vec3 bounds_min, fv_vec3 bounds_max, float *out_near_m,
                             float *out_far_m);

/** An eye's pose in the head frame (+x right, +y up, -z forward; metres): where the eye sits and how its view is
 *  turned against the head. The head's pose in the world moves the eyes' views and never enters here: gaze, which
 *  trackers give in the head frame, meets the views only through this pose (fv_eye_gaze_from_head). */
typedef struct fv_eye_in_head {
    fv_vec3 offset_m;    /* the eye's centre in the head frame */
    fv_quat orientation; /* head frame -> this eye's view frame turned by this (identity: parallel displays) */
} fv_eye_in_head;

/** The eyes of fovea's views (fv_eye_views_build*): at -+IPD/2 on the head's x axis (IPD sanitised as there), not
 *  turned (both views look down the head's -z). */
void fv_eyes_in_head(float ipd_mm, fv_eye_in_head out[2]);

/** THE seam between gaze and views: a gaze direction in the head frame as the eye's gaze in its own view space
 *  (rotated by the inverse of the eye's orientation in the head; the head's world pose plays no part). Invalid
 *  (dir_eye -z, uncertainty 180) when dir_head is not a finite non-zero vector; the uncertainty is clamped to
 *  0..180 (NaN: 180). Used by the frame loop (every tracker), `fovea bench --gaze-deg`, the OpenXR runtime, and,
 *  inverted, by the window's mouse: driver. */
fv_eye_gaze fv_eye_gaze_from_head(const fv_eye_in_head *eye, fv_vec3 dir_head, float uncertainty_deg);
/** The inverse for directions: a direction in the eye's view space, in the head frame. */
fv_vec3 fv_eye_dir_to_head(const fv_eye_in_head *eye, fv_vec3 dir_eye);
/** A point in the eye's view space (metres), in the head frame. */
fv_vec3 fv_eye_point_to_head(const fv_eye_in_head *eye, fv_vec3 p_eye);

/** The largest IPD fv_eye_views_build accepts (mm). */
#define FV_MAX_IPD_MM 100.0f
/** The IPD used when none is known (mm). */
#define FV_DEFAULT_IPD_MM 63.0f

/** HMD-like default field of view per eye (degrees): outer, inner, up, down. Asymmetric: the outer side is wider. */
#define FV_HMD_FOV_OUTER_DEG 50.0f
#define FV_HMD_FOV_INNER_DEG 42.0f
#define FV_HMD_FOV_UP_DEG 45.0f
#define FV_HMD_FOV_DOWN_DEG 48.0f

#endif
