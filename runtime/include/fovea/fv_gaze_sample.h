/* @brief One gaze sample: both eyes and a combined ray in the head frame, with validity flags.
 * Head frame: right-handed, +x right (wearer's right), +y up, -z forward, millimetres. Times in nanoseconds.
 * Unknown values are NaN and their valid flag is clear. Plain data; no ownership. */
#ifndef FV_GAZE_SAMPLE_H
#define FV_GAZE_SAMPLE_H

#include <stdint.h>

#include "fv_math.h"

enum {
    FV_EYE_LEFT = 0,
    FV_EYE_RIGHT = 1,
};

/** Per-eye validity and state flags (fv_eye_sample.flags). */
enum fv_eye_flags {
    FV_EYE_ORIGIN_VALID = 1u << 0,    /* origin_mm holds a measured eye position */
    FV_EYE_DIRECTION_VALID = 1u << 1, /* direction holds a unit gaze direction */
    FV_EYE_PUPIL_VALID = 1u << 2,     /* pupil_mm holds a measured diameter */
    FV_EYE_OPENNESS_VALID = 1u << 3,  /* openness holds a value in [0,1] */
    FV_EYE_BLINK = 1u << 4,           /* the source marks this sample as inside a blink */
};

typedef struct fv_eye_sample {
    fv_vec3 origin_mm; /* eye (cornea/pupil centre) position, head frame, mm */
    fv_vec3 direction; /* unit gaze direction, head frame */
    float pupil_mm;    /* pupil diameter, mm; NaN when unknown */
    float openness;    /* eyelid openness 0 (closed) .. 1 (open); NaN when unknown */
    uint32_t flags;    /* fv_eye_flags */
} fv_eye_sample;

/** Whole-sample flags (fv_gaze_sample.flags). */
enum fv_gaze_flags {
    FV_GAZE_HOST_TIME_VALID = 1u << 0, /* t_host_ns was set (by the transport or the clock mapper) */
    FV_GAZE_HEAD_VALID = 1u << 1,      /* head_pos_mm / head_dir hold tracker-reported head pose */
    FV_GAZE_SCREEN_POINT_VALID = 1u << 2, /* screen_point_mm holds the gaze point on the calibrated screen plane */
};

typedef struct fv_gaze_sample {
    int64_t t_device_ns;     /* device timestamp (unwrapped), ns on the device's own timeline */
    int64_t t_host_ns;       /* host monotonic time of receipt (or mapped), ns */
    fv_eye_sample eye[2];    /* FV_EYE_LEFT, FV_EYE_RIGHT */
    fv_eye_sample combined;  /* cyclopean ray (origin between the eyes) */
    float confidence;        /* 0..1; NaN when the source gives none */
    uint32_t flags;          /* fv_gaze_flags */
    fv_vec2 screen_point_mm; /* gaze point on the tracker's calibrated screen plane, when given */
    fv_vec3 head_pos_mm;     /* head position in the tracker frame, when given */
    fv_vec3 head_dir;        /* head forward direction in the tracker frame, when given */
    uint64_t seq;            /* source sequence number (row or report index), for diagnostics */
} fv_gaze_sample;

/** A sample with every value NaN/invalid and the given times. */
void fv_gaze_sample_init_invalid(fv_gaze_sample *s, int64_t t_device_ns, int64_t t_host_ns);

#endif
