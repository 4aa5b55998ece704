/* @brief Evaluation harness for the gaze pipeline: reads a device (simulated or recorded) on a simulated clock,
 * runs the pipeline with and without prediction, and measures
 *  - with the simulated eye's ground truth: the angular error at photon time (receipt of the newest sample +
 *    horizon) of the prediction, of the latest filtered sample (prediction disabled) and of the latest raw sample;
 *    and saccade detection precision/recall/F1 by event matching;
 *  - on recordings (no truth): the same errors measured against the later samples themselves (the raw gaze
 *    interpolated at the target time), and counts of detected events.
 * Blinks are treated alike for every source: a target at which the eye is closed has no truth and is not scored
 * (a recording has no valid sample there; the simulated eye's direction behind closed lids is not scored either).
 * Event matching (documented in docs/gaze.md): a detected saccade is the run of samples the pipeline labels
 * SACCADE (from the capture time of the first to that of the last); it matches a true saccade when the two
 * intervals overlap, allowing FV_SIM_EVAL_MATCH_TOL_MS either side; each true and each detected saccade is used at
 * most once (greedy, in time order). True saccades overlapping a blink, which no tracker can see, and detections
 * overlapping a blink are left out and counted apart. */
#ifndef FV_SIM_EVAL_H
#define FV_SIM_EVAL_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_device.h"
#include "fv_gaze_pipeline.h"

#define FV_SIM_EVAL_HORIZONS 5
#define FV_SIM_EVAL_MATCH_TOL_MS 20.0
#define FV_SIM_EVAL_MAX_SAMPLES 500000
#define FV_SIM_EVAL_MAX_SECONDS 3600.0
/* Zero-phase smoothing of a recording (the "smoothed" truth): a local quadratic least-squares fit (a
 * Savitzky-Golay filter on the time axis, so irregular rates are handled) over the valid samples within
 * +-max(FV_SIM_EVAL_SMOOTH_HALF_MS, FV_SIM_EVAL_SMOOTH_HALF_SAMPLES median intervals) of each sample, never across
 * a hole longer than 50 ms. */
#define FV_SIM_EVAL_SMOOTH_HALF_MS 20.0
#define FV_SIM_EVAL_SMOOTH_HALF_SAMPLES 3.5

/* What an error is measured against. */
typedef enum fv_sim_eval_truth {
    FV_SIM_EVAL_TRUTH_RAW = 0,      /* the raw future sample (interpolated between the later samples) */
    FV_SIM_EVAL_TRUTH_SMOOTHED = 1, /* the zero-phase (non-causal) smoothing of the samples at that time */
    FV_SIM_EVAL_TRUTH_TRUE = 2,     /* the simulated eye's true gaze (sim only) */
    FV_SIM_EVAL_TRUTHS = 3
} fv_sim_eval_truth;

/* What is predicted. */
typedef enum fv_sim_eval_method {
    FV_SIM_EVAL_PREDICTED = 0,       /* the pipeline's prediction */
    FV_SIM_EVAL_LATEST_FILTERED = 1, /* the pipeline with prediction disabled */
    FV_SIM_EVAL_LATEST_SAMPLE = 2,   /* the newest raw sample as is */
    FV_SIM_EVAL_METHODS = 3
} fv_sim_eval_method;

const char *fv_sim_eval_truth_name(fv_sim_eval_truth t);   /* "raw", "smoothed", "true" */
const char *fv_sim_eval_method_name(fv_sim_eval_method m); /* "predicted", "latest_filtered", "latest_sample" */

typedef struct fv_sim_eval_desc {
    double seconds;                       /* how much to read (device time); 0 = 60 s for sim:, else the whole
                                           * recording (at most FV_SIM_EVAL_MAX_SECONDS) */
    fv_gaze_pipeline_desc pipeline;       /* the pipeline under test (the baseline disables prediction) */
    int bench_repeats;                    /* >0: also time push+predict over the samples this many times */
    /* Optional: write a per-sample timeline CSV here (time, raw, predicted at +plot_horizon_ms, truth there,
     * event, uncertainty) for plots. NULL = none. */
    const char *timeline_csv;
    int timeline_horizon_ms;              /* 0 = 20 */
} fv_sim_eval_desc;

typedef struct fv_sim_eval_error {
    double mean_deg, p95_deg;
    uint64_t n;
    double inside_radius;                 /* fraction of truths within the predicted uncertainty radius (NaN when
                                           * the method has none: the latest raw sample) */
} fv_sim_eval_error;

typedef struct fv_sim_eval_result {
    bool has_truth;                       /* the device was the simulated eye */
    double seconds;                       /* device time covered */
    uint64_t samples, invalid, one_eye, rejected;
    double rate_hz;                       /* measured median-free mean rate */
    int horizon_ms[FV_SIM_EVAL_HORIZONS]; /* 0, 10, 20, 40, 60 */
    /* Against the primary truth (sim: the true gaze; recordings: the raw future sample): */
    fv_sim_eval_error predicted[FV_SIM_EVAL_HORIZONS];
    fv_sim_eval_error filtered[FV_SIM_EVAL_HORIZONS]; /* latest filtered sample (prediction disabled) */
    fv_sim_eval_error latest[FV_SIM_EVAL_HORIZONS];   /* latest raw sample */
    /* Every truth: err[truth][method][horizon] (TRUTH_TRUE only when has_truth). */
    fv_sim_eval_error err[FV_SIM_EVAL_TRUTHS][FV_SIM_EVAL_METHODS][FV_SIM_EVAL_HORIZONS];
    double smooth_half_ms;                /* the smoothing's half-width used for the smoothed truth */
    bool whole;                           /* the whole stream was read (not cut at desc->seconds) */
    /* Counts that add up: det_saccades = tp + fp (scored detections); det_in_blink more overlapped a blink and
     * are not scored; true_saccades = tp + fn. Without truth det_saccades counts the detected saccades. */
    uint64_t det_saccades, det_pursuits, det_blinks;  /* det_blinks: invalid runs the pipeline held gaze through */
    uint64_t recorded_blinks;             /* blinks as `fovea trace info` counts them: runs of samples the source
                                           * flags FV_EYE_BLINK */
    uint64_t true_saccades, true_saccades_hidden;     /* with truth: visible and blink-hidden true saccades */
    uint64_t tp, fp, fn, det_in_blink;
    double noise_deg;                     /* the pipeline's online noise estimate at the end (deg RMS per axis) */
    double filter_min_cutoff_hz, filter_beta; /* the 1€ parameters it derived from it */
    double precision, recall, f1;
    double mean_uncertainty_deg;          /* mean predicted uncertainty radius at 20 ms */
    double skew_ppm;                      /* the pipeline's clock skew estimate at the end */
    double ns_per_sample;                 /* bench: push + one predict, per sample (0 when not run) */
    fv_gaze_pipeline_stats pipeline;      /* the predicting pipeline's counters at the end (fallback, ...) */
} fv_sim_eval_result;

/** Read `dev` (pacing its clock: `clock` must be the simulated clock the device was opened with) and evaluate.
 *  Stops after desc->seconds of device time, at the end of a finite stream, or after FV_SIM_EVAL_MAX_SAMPLES. */
FV_MUST_CHECK fv_result fv_sim_eval_run(fv_device *dev, fv_clock *clock, const fv_sim_eval_desc *desc,
                                        fv_sim_eval_result *out);

#endif
