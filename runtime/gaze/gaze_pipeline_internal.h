/* @brief The gaze pipeline's state, shared by the files that do its jobs: fv_gaze_pipeline.c (time, validity,
 * filtering, classification, the saccade fit, push and predict) and fv_gaze_candidates.c (the candidate predictors,
 * their online scoring per context and the choice among them). Not a public header. */
#ifndef GAZE_PIPELINE_INTERNAL_H
#define GAZE_PIPELINE_INTERNAL_H

#include "fv_gaze_pipeline.h"
#include "fv_gaze_validity.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_clock.h"
#include "fv_gaze_clock.h"
#include "fv_gaze_filter.h"
#include "fv_gaze_noise.h"
#include "fv_gaze_saccade.h"
#include "fv_log.h"
#include "fv_stats.h"

#define HIST 64                                   /* combined-gaze history (power of two not required) */
#define SHORT_WINDOW_NS (20 * FV_NS_PER_MS)       /* saccade velocity: regression over 20 ms (>= 2 samples) */
#define LONG_WINDOW_NS (150 * FV_NS_PER_MS)       /* pursuit velocity: regression over up to 150 ms */
#define LONG_MIN_SPAN_NS (60 * FV_NS_PER_MS)      /* pursuit needs at least this much of a segment */
#define GAP_RESET_NS (75 * FV_NS_PER_MS)          /* a hole this long breaks the velocity history */
#define MAX_BLINK_NS (500 * FV_NS_PER_MS)         /* longer without valid gaze: lost */
#define MAX_SACCADE_NS (200 * FV_NS_PER_MS)       /* no saccade lasts longer */
#define DEVICE_RESET_NS INT64_C(1000000000)       /* device time going back > 1 s: the device restarted */
#define MAX_EXTRAPOLATION_S 0.2                   /* never extrapolate a velocity further than this */
#define PURSUIT_ON_DEG_S 4.0
#define PURSUIT_OFF_DEG_S 2.5
#define PURSUIT_MIN_SIGNIFICANCE 3.0
#define SCORE_HORIZON_NS (20 * FV_NS_PER_MS)      /* candidates are scored at this horizon */
/* the tuned constants (fv_gaze_tuning): scores needed before a candidate other than the model is used; the
 * running scores' memory; a candidate replaces the newest sample only when its mean error stays below the sample's
 * by SELECT_SES standard errors */
#define SCORE_MIN (p->tun.score_min)
#define SCORE_MEMORY (p->tun.score_memory)
#define SELECT_SES (p->tun.select_ses)
#define PEND_SLOTS 32
#define RADIUS_PER_MEAN_ERROR 1.72                /* Rayleigh: P(r < 1.72 mean) = 0.90 */
#define MID_WINDOW_NS ((int64_t)(p->tun.mid_window_ms * 1e6)) /* extrapolated velocity: regression window (50 ms) */
#define SHRINK_SDS (p->tun.shrink_sds)            /* velocity shrinkage: nothing of a velocity within 2 SE */
#define VERGENCE_TAU_S 0.2
#define PUPIL_TAU_S 0.15
#define PUPIL_MIN_MM 0.5
#define PUPIL_MAX_MM 10.0
#define MAX_UNCERTAINTY_DEG 90.0
#define LOST_UNCERTAINTY_DEG 30.0
#define BLINK_GROWTH_DEG_S 30.0
#define FIXATION_GROWTH_DEG_S 2.0

enum { CH_LEFT = 0, CH_RIGHT = 1, CH_COMBINED = 2 };
/* the candidate predictions (see candidates()): the newest sample, the filtered position, the model, the newest
 * sample moved by the shrunk velocity, and by half of it (inside a saccade: by the 20 ms velocity) */
enum { CAND_SAMPLE = 0, CAND_FILTERED = 1, CAND_MODEL = 2, CAND_SAMPLE_VEL = 3, CAND_SAMPLE_HALF = 4, CAND_BLEND = 5,
       CANDS = 6 };
/* scoring contexts: the motion state x the speed of the newest 50 ms (4 bins); a saccade that began from slow
 * motion (< 20 deg/s) instead by the samples seen of it (1, 2, 3+: bins 0, 4, 5) -- see context() */
enum { STATES = FV_GAZE_EVENT_LOST + 1, SPEED_BINS = 6, CONTEXTS = STATES * SPEED_BINS };

typedef struct channel {
    fv_gaze_one_euro filter;
    bool have;       /* pos holds an estimate */
    double pos[2];   /* current estimate (filtered; raw inside a saccade), deg */
    int64_t t_ns;    /* time of the last valid sample of this channel */
} channel;

struct fv_gaze_pipeline {
    fv_gaze_pipeline_desc desc;
    fv_gaze_tuning tun;       /* desc.tuning with the defaults filled in */
    fv_gaze_main_sequence ms;
    fv_gaze_clock_map clock;
    fv_gaze_noise noise;      /* the tracker's noise and rate, measured online during fixations */
    bool adaptive_filter;     /* the 1€ parameters follow the noise (none given in the desc) */
    double sacc_on, sacc_off; /* saccade thresholds in use: the desc's, raised above the noise's velocity */
    double sacc_on2;          /* the same for the speed between the two newest samples */
    bool have_dev;
    int64_t last_dev_ns, last_host_ns;
    channel ch[3];
    double verg[2][2]; /* per eye: eye − combined angle, deg */
    bool verg_valid[2];
    /* combined raw history of the current segment (valid samples only), ring, newest at h_head-1 */
    int64_t h_t[HIST];
    double h_p[HIST][2];
    int h_head, h_count;
    fv_gaze_event state;   /* FIXATION / SACCADE / PURSUIT (motion), NONE before data */
    int64_t segment_start_ns;
    int64_t sacc_start_ns, sacc_from_ns;
    double sacc_start_pos[2];
    bool fit_ok;              /* the landing fit of the saccade under way, refreshed at each saccade sample */
    bool fit_confident;       /* >= 3 samples and a small residual: good enough to hold through a blink */
    double fit_amp_deg, fit_dur_s, fit_dir[2], fit_d_now;
    int64_t fit_onset_ns;
    double v_short[2], v_long[2], reg_pos[2];
    double v_long_sig;     /* significance of v_long (standard errors) */
    double v_mid[2], mid_pos[2], v_mid_sig; /* velocity over the newest MID_WINDOW of the segment, its line's
                                             * value at the newest sample, and its significance */
    bool long_ok;
    bool have_valid, last_sample_valid;
    int64_t last_valid_ns;
    double hold_pos[2];    /* the last fixation (held through blinks) */
    /* online scoring of the candidate predictors (see score_candidates) */
    struct {
        int64_t t_ns;
        int context;
        int chosen;           /* the candidate the selection took for this prediction (before the device fallback) */
        double c[CANDS][2];
    } pend[PEND_SLOTS];
    /* the device-level check: the running mean of (chosen candidate's error - newest sample's error) over every
     * scored prediction; prediction falls back to the newest sample while it is not below zero */
    double dev_dmean;
    uint64_t dev_scored;
    bool fallback;
    int pend_head, pend_count;
    double mae[CONTEXTS][CANDS];   /* running mean angular error per context and candidate, deg */
    uint32_t scored[CONTEXTS];
    double mae_state[STATES][CANDS]; /* the same per motion state alone (the fallback of a context not scored yet) */
    uint32_t scored_state[STATES];
    /* the paired difference to the newest sample's error (candidate - sample): running mean and mean square */
    double dmean[CONTEXTS][CANDS], dsq[CONTEXTS][CANDS];
    double dmean_state[STATES][CANDS], dsq_state[STATES][CANDS];
    /* the blend's share of the model's step from the newest sample: running means of (truth - sample).(model -
     * sample) and |model - sample|^2 per context and per state */
    double lam_num[CONTEXTS], lam_den[CONTEXTS], lam_num_state[STATES], lam_den_state[STATES];
    bool have_prev_raw;
    int64_t prev_raw_ns;
    double prev_raw[2];
    bool pupil_valid;
    double pupil_mm;
    int64_t pupil_ns;
    bool device_lost;
    int64_t lost_since_ns;
    fv_gaze_pipeline_stats stats;
};

/* angular distance in degrees for small differences of (yaw, pitch) */
static inline double ang_norm(const double d[2], double pitch_deg)
{
    double c = cos(fv_deg_to_rad(fmax(-89.0, fmin(89.0, pitch_deg))));
    return sqrt(d[0] * c * d[0] * c + d[1] * d[1]);
}

/* i = 0 is the newest */
static inline int hist_index(const fv_gaze_pipeline *p, int i) { return ((p->h_head - 1 - i) % HIST + HIST) % HIST; }

/* ---- between the pipeline's files ---------------------------------------------------------------------------- */

/** Where the saccade under way will be at t_target_ns, from the cached fit (fv_gaze_pipeline.c). */
bool fv_gaze_predict_saccade(const fv_gaze_pipeline *p, int64_t t_target_ns, double out[2], double *out_remaining_deg);
/** The candidate predictions at horizon h_s after the newest valid sample for motion state ev, and what the model
 *  adds to the uncertainty (fv_gaze_candidates.c). */
void fv_gaze_candidates(const fv_gaze_pipeline *p, fv_gaze_event ev, double h_s, double cand[CANDS][2],
                        double *extra_unc);
/** The scoring context of state ev now (fv_gaze_candidates.c). */
int fv_gaze_context(const fv_gaze_pipeline *p, fv_gaze_event ev);
/** The candidate the selection takes now, CAND_SAMPLE while the device falls back (fv_gaze_candidates.c). */
int fv_gaze_choose_candidate(const fv_gaze_pipeline *p, fv_gaze_event ev);
/** The candidate the scores select in state ev's context (fv_gaze_candidates.c). */
int fv_gaze_select_candidate(const fv_gaze_pipeline *p, fv_gaze_event ev);
/** Score the pending predictions whose time the sample at t (position pos) reached (fv_gaze_candidates.c). */
void fv_gaze_score_candidates(fv_gaze_pipeline *p, int64_t t, const double pos[2]);

#endif
