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

/** The head in the world: where it is, which way it looks (its local -z), and the distance between the eyes. */
typedef struct fv_head_pose {
    fv_vec3 position_m;
    fv_quat orientation;
    float ipd_mm;
} fv_head_pose;

/** Debug views (fv_quality.debug_view): replace the shaded image with a view of the frame's data. */
typedef enum fv_debug_view {
    FV_DEBUG_VIEW_NONE = 0,
    FV_DEBUG_VIEW_NORMAL = 1, /* the G-buffer's world normal, n * 0.5 + 0.5 */
    FV_DEBUG_VIEW_GAZE = 2,   /* the predicted gaze: red peaks on the gaze ray, green = pupil mm / 10, blue = valid */
} fv_debug_view;

/** The speed/accuracy settings a frame is drawn with. Zero is not a valid value: start from fv_quality_default().
 *  (The knob table, its presets and `--set` come with the measuring work; each pass reads its fields here.) */
typedef struct fv_quality {
    float exposure;          /* present: linear scale before tonemapping, > 0 (default 1) */
    fv_debug_view debug_view; /* default FV_DEBUG_VIEW_NONE */
} fv_quality;

/** The defaults every preset starts from. */
static inline fv_quality fv_quality_default(void)
{
    fv_quality q = {.exposure = 1.0f, .debug_view = FV_DEBUG_VIEW_NONE};
    return q;
}

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

/** Clamp near/far planes to what keeps a projection finite: near <= 0 or non-finite -> 0.05 m, near in
 *  [1e-5, 5e8] m; far <= 0 or non-finite -> max(100 m, 1000 near), far <= 1e9 m and > 1.001 near. */
void fv_near_far_sanitize(float *near_m, float *far_m);

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
