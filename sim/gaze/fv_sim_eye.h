/* @brief A seeded, deterministic simulated eye: fixations (log-normal durations), saccades on the main sequence,
 * smooth pursuit of a moving target, microsaccades and drift, per-eye vergence for the fixated depth, blinks,
 * pupil dynamics (light response, hippus), tracker noise (accuracy and precision), sample rate with jitter, device
 * latency, dropouts and one-eye losses. Exports its ground truth: true gaze at any time, the truth of every sample
 * and the event labels with start and end. Pure computation: no clock, no I/O. One owner; not thread-safe. */
#ifndef FV_SIM_EYE_H
#define FV_SIM_EYE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fovea/fv_gaze_sample.h"
#include "fv_result.h"

typedef enum fv_sim_label {
    FV_SIM_NONE = 0,
    FV_SIM_FIXATION = 1,
    FV_SIM_SACCADE = 2,
    FV_SIM_PURSUIT = 3,
    FV_SIM_MICROSACCADE = 4, /* inside a fixation */
    FV_SIM_BLINK = 5,        /* an overlay: the eye keeps its motion, the tracker sees nothing */
} fv_sim_label;

const char *fv_sim_label_str(fv_sim_label l);

/** Knobs of the simulated eye. Unlike most descs, zero is a meaningful value here (no noise, no blinks), so start
 *  from fv_sim_eye_desc_defaults() and change what you need; fv_sim_eye_create validates every field. */
typedef struct fv_sim_eye_desc {
    uint64_t seed;
    double rate_hz;            /* sample rate, 30..1200 (120) */
    double jitter_us;          /* SD of the capture-time jitter (50) */
    double latency_ms;         /* capture → transport, fixed part (4) */
    double transport_jitter_ms;/* mean of the exponential extra transport delay (0.5) */
    double dropout;            /* probability a sample never arrives (0.002) */
    double eye_loss;           /* probability one eye is invalid in a sample (0.003) */
    double precision_deg;      /* tracker noise SD per axis per eye (0.15) */
    double accuracy_deg;       /* constant per-eye offset magnitude (0.5) */
    double blink_per_min;      /* blink rate (15) */
    double pursuit_prob;       /* chance that a gaze shift leads into a smooth pursuit (0.15) */
    bool microsaccades;        /* microsaccades and drift in fixations (true) */
    double skew_ppm;           /* device clock rate error (20) */
    double device_offset_s;    /* device clock reading at simulation time 0 (1000) */
    double ipd_mm;             /* interpupillary distance (63) */
    double vmax_deg_s, c_deg;  /* main sequence Vp = Vmax (1 - e^(-A/C)) (600, 9) */
    double main_seq_spread;    /* log-normal SD of the per-saccade peak velocity factor (0.08) */
} fv_sim_eye_desc;

void fv_sim_eye_desc_defaults(fv_sim_eye_desc *d);

/** Ground truth at one instant. Angles: yaw right-positive, pitch up-positive, (0,0) = -z. */
typedef struct fv_sim_truth {
    int64_t t_ns;             /* simulation time */
    double yaw_deg, pitch_deg;/* cyclopean gaze */
    fv_vec3 dir_cyc;          /* cyclopean unit direction (head frame) */
    fv_vec3 dir_eye[2];       /* per-eye unit direction toward the fixated point */
    double depth_m;           /* fixated depth */
    double pupil_mm;          /* true pupil diameter (sample truths only; NaN from truth_at) */
    fv_sim_label label;       /* motion label (fixation / saccade / pursuit / microsaccade) */
    bool blink;               /* eyes closed */
} fv_sim_truth;

typedef struct fv_sim_event {
    fv_sim_label label;
    int64_t t_start_ns, t_end_ns; /* simulation time */
    double amplitude_deg;         /* saccades/microsaccades: amplitude; pursuit: speed deg/s; else 0 */
    double peak_deg_s;            /* saccades/microsaccades: peak angular velocity */
} fv_sim_event;

typedef struct fv_sim_eye fv_sim_eye;

FV_MUST_CHECK fv_result fv_sim_eye_create(const fv_sim_eye_desc *desc, fv_sim_eye **out);
void fv_sim_eye_destroy(fv_sim_eye **eye);
const fv_sim_eye_desc *fv_sim_eye_get_desc(const fv_sim_eye *eye);
/** The next delivered sample (dropouts skipped). t_device_ns is on the device clock (offset + skew), t_host_ns is
 *  the arrival time in simulation time (capture + latency + transport delay, non-decreasing) with
 *  FV_GAZE_HOST_TIME_VALID; seq is the sample index (gaps are dropouts). *out_truth is the truth at capture. */
FV_MUST_CHECK fv_result fv_sim_eye_next(fv_sim_eye *eye, fv_gaze_sample *out_sample, fv_sim_truth *out_truth);
/** True gaze at simulation time t_ns (generated ahead as needed). false when t_ns is older than the kept history
 *  (about the last 1000 motion segments) or negative. */
bool fv_sim_eye_truth_at(fv_sim_eye *eye, int64_t t_ns, fv_sim_truth *out);
/** Events generated so far, in generation order (blinks are generated on their own timeline, so the list is not
 *  sorted by time; motion events are). Events older than the last 8192 are dropped: get() returns false. */
size_t fv_sim_eye_event_count(const fv_sim_eye *eye);
bool fv_sim_eye_event_get(const fv_sim_eye *eye, size_t index, fv_sim_event *out);
/** Ensure motion and blinks are generated up to t_ns (so every event starting before t_ns is listed). */
void fv_sim_eye_generate_until(fv_sim_eye *eye, int64_t t_ns);

#endif
