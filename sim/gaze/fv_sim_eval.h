/* @brief Evaluation harness for the gaze pipeline: reads a device (simulated or recorded) on a simulated clock,
 * runs the pipeline with and without prediction, and measures
 *  - with the simulated eye's ground truth: the angular error at photon time (receipt of the newest sample +
 *    horizon) of the prediction, of the latest filtered sample (prediction disabled) and of the latest raw sample;
 *    and saccade detection precision/recall/F1 by event matching;
 *  - on recordings (no truth): the same errors measured against the later samples themselves (the raw gaze
 *    interpolated at the target time), and counts of detected events.
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

#define FV_SIM_EVAL_HORIZONS 4
#define FV_SIM_EVAL_MATCH_TOL_MS 20.0
#define FV_SIM_EVAL_MAX_SAMPLES 500000

typedef struct fv_sim_eval_desc {
    double seconds;                       /* how much to read (device time); 0 = 60 */
    fv_gaze_pipeline_desc pipeline;       /* the pipeline under test (the baseline disables prediction) */
    int bench_repeats;                    /* >0: also time push+predict over the samples this many times */
} fv_sim_eval_desc;

typedef struct fv_sim_eval_error {
    double mean_deg, p95_deg;
    uint64_t n;
} fv_sim_eval_error;

typedef struct fv_sim_eval_result {
    bool has_truth;                       /* the device was the simulated eye */
    double seconds;                       /* device time covered */
    uint64_t samples, invalid, one_eye, rejected;
    double rate_hz;                       /* measured median-free mean rate */
    int horizon_ms[FV_SIM_EVAL_HORIZONS]; /* 0, 10, 20, 40 */
    fv_sim_eval_error predicted[FV_SIM_EVAL_HORIZONS];
    fv_sim_eval_error filtered[FV_SIM_EVAL_HORIZONS]; /* latest filtered sample (prediction disabled) */
    fv_sim_eval_error latest[FV_SIM_EVAL_HORIZONS];   /* latest raw sample */
    uint64_t det_saccades, det_pursuits, det_blinks;  /* detected onsets */
    uint64_t true_saccades, true_saccades_hidden;     /* with truth: visible and blink-hidden true saccades */
    uint64_t tp, fp, fn, det_in_blink;
    double precision, recall, f1;
    double mean_uncertainty_deg;          /* mean predicted uncertainty radius at 20 ms */
    double skew_ppm;                      /* the pipeline's clock skew estimate at the end */
    double ns_per_sample;                 /* bench: push + one predict, per sample (0 when not run) */
} fv_sim_eval_result;

/** Read `dev` (pacing its clock: `clock` must be the simulated clock the device was opened with) and evaluate.
 *  Stops after desc->seconds of device time, at the end of a finite stream, or after FV_SIM_EVAL_MAX_SAMPLES. */
FV_MUST_CHECK fv_result fv_sim_eval_run(fv_device *dev, fv_clock *clock, const fv_sim_eval_desc *desc,
                                        fv_sim_eval_result *out);

#endif
