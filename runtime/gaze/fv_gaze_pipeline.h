/* @brief The gaze pipeline: samples in (device clock) → host clock → validity → 1€ filter → classification →
 * prediction to a target time (the frame's photon time) with an uncertainty radius. One owner; not thread-safe.
 * The frame loop pushes every sample it drains from a device ring, then asks for a prediction per frame.
 * Time: samples are ordered by t_device_ns (it must advance); with FV_GAZE_HOST_TIME_VALID the pipeline maps the
 * device clock onto the host clock from the receipt times (lower envelope: the mapped time is the capture time plus
 * the smallest transport delay, free of jitter). The 1€ parameters and the saccade threshold follow the tracker's
 * noise, measured online during fixations; each candidate prediction (latest sample, filtered, model, ...) is scored
 * on the tracker's own later samples and used only where it has done best. Details, defaults and measured figures:
 * docs/gaze.md. */
#ifndef FV_GAZE_PIPELINE_H
#define FV_GAZE_PIPELINE_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_gaze_sample.h"
#include "fv_result.h"

typedef enum fv_gaze_event {
    FV_GAZE_EVENT_NONE = 0, /* no valid data yet */
    FV_GAZE_EVENT_FIXATION = 1,
    FV_GAZE_EVENT_SACCADE = 2,
    FV_GAZE_EVENT_PURSUIT = 3,
    FV_GAZE_EVENT_BLINK = 4, /* both eyes invalid for a blink-length gap: last fixation held */
    FV_GAZE_EVENT_LOST = 5,  /* no valid sample for longer than a blink, or the device is lost */
} fv_gaze_event;

const char *fv_gaze_event_str(fv_gaze_event e);

/** (yaw, pitch) in degrees of a head-frame direction (yaw right, pitch up, (0, 0) = -z). false when the direction
 *  is not finite, zero, or further than max_ecc_deg from straight ahead. */
bool fv_gaze_dir_to_angles(fv_vec3 d, double max_ecc_deg, double out_deg[2]);
/** The unit direction of (yaw, pitch) degrees (clamped to +-179 / +-89; non-finite = 0). */
fv_vec3 fv_gaze_angles_to_dir(const double a_deg[2]);

typedef struct fv_gaze_prediction {
    int64_t t_target_ns;         /* host time the prediction is for */
    int64_t t_sample_ns;         /* host time of the newest sample used */
    bool eye_valid[2];           /* per eye: a direction is available (possibly held through a blink) */
    fv_vec3 dir_head[2];         /* predicted unit gaze direction per eye, head frame (-z forward) */
    bool combined_valid;
    fv_vec3 combined_dir_head;   /* predicted cyclopean direction */
    float uncertainty_deg;       /* radius the renderer widens the fovea by (>= tracker accuracy); finite */
    float pupil_mm;              /* filtered pupil diameter, NaN when unknown */
    fv_gaze_event event;         /* current classification */
    bool predicted;              /* false when prediction is disabled and the latest sample was used as is */
} fv_gaze_prediction;

/* The predictor's tuned constants: every number that was chosen by looking at recordings (not derived from the
 * noise, the rate or physiology). Zero = the default; `fovea gaze eval --tune KEY=VALUE` sets them, and
 * tools/gaze_loro.py cross-validates each (leave one recording out, leave one device out: docs/gaze.md). */
typedef struct fv_gaze_tuning {
    double select_ses;        /* a candidate replaces the newest sample when it leads by this many SE; 1.25 */
    double onset2_sds;        /* two-sample saccade onset: SDs of the speed between the two newest samples; 6 */
    double onset_sds;         /* 20 ms slope onset: SEs of the slope; 4 */
    double shrink_sds;        /* James-Stein threshold of the extrapolated velocity (SE); 2 */
    double mid_window_ms;     /* the extrapolated velocity's regression window; 50 */
    double score_memory;      /* the running scores average over about this many; 512 */
    double score_min;         /* scores a context needs before its own figures are used; 8 */
    double speed_bin_scale;   /* the context speed bins 5 / 20 / 60 deg/s times this; 1 */
    double slow_saccade_deg_s; /* a saccade from slower motion is binned by the samples seen of it; 20 */
    double blend;             /* 1: the blend candidate takes part; -1: it does not; 0 = 1 */
    double fallback_min;      /* scored predictions before the device-level fallback may start; 64 */
    double fallback_memory;   /* the device-level check averages over about this many; 2048 */
    double fallback;          /* 1: the device-level fallback is on (it starts fallen back until fallback_min
                               * scores); -1: off; 0 = 1 */
} fv_gaze_tuning;

/** The defaults of every tuned constant (what zero means). */
fv_gaze_tuning fv_gaze_tuning_defaults(void);
/** Set one constant by name ("select_ses", ...); FV_ERR_NOT_FOUND for an unknown name, FV_ERR_RANGE for a value
 *  that is not finite and positive (the switches blend and fallback: 1 or -1). */
FV_MUST_CHECK fv_result fv_gaze_tuning_set(fv_gaze_tuning *t, const char *name, double value);
/** The names, NULL-terminated. */
extern const char *const fv_gaze_tuning_names[];

typedef struct fv_gaze_pipeline_desc {
    float accuracy_deg;          /* tracker accuracy floor for the uncertainty; 0 = 0.5 */
    float filter_min_cutoff_hz;  /* 1€ filter f_cmin; both 0 = set from the tracker's noise, measured online */
    float filter_beta;           /* 1€ filter β; (one given: the other 1 Hz / 0.3 per deg, fixed) */
    float saccade_on_deg_s;      /* velocity threshold to enter a saccade; 0 = default */
    float saccade_off_deg_s;     /* hysteresis: velocity to leave it; 0 = default */
    bool disable_prediction;     /* true: predict() returns the latest filtered sample (the baseline) */
    /* Extensions (zero = default): */
    float min_confidence;        /* samples with a finite confidence below this are invalid; 0 = 0.5 */
    float max_eccentricity_deg;  /* directions further than this from straight ahead are invalid; 0 = 60, <= 90 */
    float main_sequence_vmax_deg_s; /* main sequence Vp = Vmax (1 - e^(-A/C)) for landing prediction; 0 = 600 */
    float main_sequence_c_deg;   /* 0 = 9 */
    fv_gaze_tuning tuning;       /* the predictor's tuned constants; zero fields = defaults */
} fv_gaze_pipeline_desc;

typedef struct fv_gaze_pipeline fv_gaze_pipeline;

FV_MUST_CHECK fv_result fv_gaze_pipeline_create(const fv_gaze_pipeline_desc *desc, fv_gaze_pipeline **out);
void fv_gaze_pipeline_destroy(fv_gaze_pipeline **p);
/** Push one sample. t_host_ns must be set (receipt time, or mapped from the device clock by the pipeline's clock
 *  mapper when FV_GAZE_HOST_TIME_VALID is clear). Duplicates and out-of-order samples are rejected with
 *  FV_NO_NEW_DATA; invalid values are kept as invalid (a blink), never as NaN directions. */
FV_MUST_CHECK fv_result fv_gaze_pipeline_push(fv_gaze_pipeline *p, const fv_gaze_sample *s);
/** Predict to host time t_target_ns. Always fills *out with finite values (eye_valid false when nothing known). */
void fv_gaze_pipeline_predict(fv_gaze_pipeline *p, int64_t t_target_ns, fv_gaze_prediction *out);
/** Counters for diagnostics and evaluation. */
typedef struct fv_gaze_pipeline_stats {
    uint64_t pushed;         /* samples given to push() */
    uint64_t rejected;       /* duplicates / out of order (FV_NO_NEW_DATA) */
    uint64_t invalid;        /* accepted samples with no usable eye (blink, NaN, low confidence, implausible) */
    uint64_t one_eye;        /* accepted samples with exactly one usable eye */
    uint64_t impossible;     /* accepted samples with a physically impossible ray dropped (fv_gaze_validity.h) */
    uint64_t saccades;       /* saccade onsets detected */
    uint64_t clock_resets;   /* device clock discontinuities (mapper restarted) */
    double clock_skew_ppm;   /* current device-to-host skew estimate */
    double noise_deg;        /* online tracker noise estimate (deg RMS per axis, from fixations); NaN before one */
    double rate_hz;          /* online sample-rate estimate; 0 before one */
    double filter_min_cutoff_hz, filter_beta; /* the 1€ parameters in use */
    /* Prediction's device-level check: predict() calls (outside blinks), those that fell back to the newest sample
     * because the selection's choices have not beaten it on this device's own later samples, the switches, the
     * state now, and the running mean of (chosen - newest sample) error in deg (negative: prediction pays). */
    uint64_t predictions, fallback_predictions, fallback_switches;
    bool fallback;
    double fallback_margin_deg;
} fv_gaze_pipeline_stats;

void fv_gaze_pipeline_get_stats(const fv_gaze_pipeline *p, fv_gaze_pipeline_stats *out);
/** The classification after the newest sample (FIXATION/SACCADE/PURSUIT; BLINK while invalid; NONE before data). */
fv_gaze_event fv_gaze_pipeline_event(const fv_gaze_pipeline *p);
/** Host time the pipeline assigned to the newest accepted sample (mapped from the device clock); 0 before any. */
int64_t fv_gaze_pipeline_last_sample_ns(const fv_gaze_pipeline *p);
/** Diagnostics for evaluation tools: the candidate predictions (yaw, pitch deg) predict() chooses from at
 *  t_target_ns in the current motion state, in the order sample, filtered, model, sample + velocity (saccade: the
 *  landing fit), sample + half velocity (saccade: + the 20 ms velocity), blend; returns the index predict() would
 *  choose, or -1 when it would not choose among them (blink, lost, no data, prediction disabled). */
#define FV_GAZE_CANDIDATES 6
int fv_gaze_pipeline_candidates(const fv_gaze_pipeline *p, int64_t t_target_ns, double out[FV_GAZE_CANDIDATES][2]);
/** Tell the pipeline the device is lost (or back): uncertainty widens while lost. */
void fv_gaze_pipeline_set_device_lost(fv_gaze_pipeline *p, bool lost, int64_t now_ns);

#endif
