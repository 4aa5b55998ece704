/* @brief The gaze pipeline: device clock → host clock → validity → 1€ filter → classification → prediction with an
 * uncertainty radius (see fv_gaze_pipeline.h). Angles are (yaw, pitch) in degrees: yaw positive to the right,
 * pitch positive up, (0, 0) straight ahead (-z). */
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

const char *fv_gaze_event_str(fv_gaze_event e)
{
    switch (e) {
    case FV_GAZE_EVENT_NONE: return "none";
    case FV_GAZE_EVENT_FIXATION: return "fixation";
    case FV_GAZE_EVENT_SACCADE: return "saccade";
    case FV_GAZE_EVENT_PURSUIT: return "pursuit";
    case FV_GAZE_EVENT_BLINK: return "blink";
    case FV_GAZE_EVENT_LOST: return "lost";
    }
    return "unknown";
}

static float pos_or(float v, float dflt) { return isfinite(v) && v > 0.0f ? v : dflt; }

const char *const fv_gaze_tuning_names[] = {"select_ses",      "onset2_sds",     "onset_sds",
                                            "shrink_sds",      "mid_window_ms",  "score_memory",
                                            "score_min",       "speed_bin_scale", "slow_saccade_deg_s",
                                            "blend",           "fallback_min",   "fallback_memory",
                                            "fallback",        NULL};

static double *tuning_field(fv_gaze_tuning *t, int i)
{
    double *f[] = {&t->select_ses,   &t->onset2_sds, &t->onset_sds,       &t->shrink_sds,         &t->mid_window_ms,
                   &t->score_memory, &t->score_min,  &t->speed_bin_scale, &t->slow_saccade_deg_s, &t->blend,
                   &t->fallback_min, &t->fallback_memory, &t->fallback};
    _Static_assert(sizeof f / sizeof f[0] + 1 == sizeof fv_gaze_tuning_names / sizeof fv_gaze_tuning_names[0],
                   "one name per field");
    return f[i];
}

fv_gaze_tuning fv_gaze_tuning_defaults(void)
{
    return (fv_gaze_tuning){.select_ses = 1.25, .onset2_sds = 6.0, .onset_sds = 4.0, .shrink_sds = 2.0,
                            .mid_window_ms = 50.0, .score_memory = 512.0, .score_min = 8.0, .speed_bin_scale = 1.0,
                            .slow_saccade_deg_s = 20.0, .blend = 1.0, .fallback_min = 64.0,
                            .fallback_memory = 2048.0, .fallback = 1.0};
}

fv_result fv_gaze_tuning_set(fv_gaze_tuning *t, const char *name, double v)
{
    if (!t || !name) return FV_ERR_INVALID_ARG;
    for (int i = 0; fv_gaze_tuning_names[i]; i++) {
        if (strcmp(name, fv_gaze_tuning_names[i]) != 0) continue;
        bool is_blend = strcmp(name, "blend") == 0 || strcmp(name, "fallback") == 0; /* switches: 1 on, -1 off */
        if (is_blend ? !(v == 1.0 || v == -1.0) : !(isfinite(v) && v > 0.0 && v < 1e6)) return FV_ERR_RANGE;
        *tuning_field(t, i) = v;
        return FV_OK;
    }
    return FV_ERR_NOT_FOUND;
}

/* desc's tuning with zero (or invalid) fields replaced by the defaults */
static fv_gaze_tuning tuning_filled(const fv_gaze_tuning *given)
{
    fv_gaze_tuning t = fv_gaze_tuning_defaults(), g = *given;
    for (int i = 0; fv_gaze_tuning_names[i]; i++) {
        double v = *tuning_field(&g, i);
        bool is_switch = strcmp(fv_gaze_tuning_names[i], "blend") == 0 || strcmp(fv_gaze_tuning_names[i], "fallback") == 0;
        if (isfinite(v) && v != 0.0 && (is_switch ? fabs(v) == 1.0 : v > 0.0 && v < 1e6)) *tuning_field(&t, i) = v;
    }
    if (t.mid_window_ms < 5.0) t.mid_window_ms = 5.0;
    if (t.score_memory < 1.0) t.score_memory = 1.0;
    if (t.fallback_memory < 1.0) t.fallback_memory = 1.0;
    return t;
}

fv_result fv_gaze_pipeline_create(const fv_gaze_pipeline_desc *desc, fv_gaze_pipeline **out)
{
    if (!out) return FV_ERR_INVALID_ARG;
    *out = NULL;
    fv_gaze_pipeline_desc d = {0};
    if (desc) d = *desc;
    bool adaptive = !(isfinite(d.filter_min_cutoff_hz) && d.filter_min_cutoff_hz > 0.0f) &&
                    !(isfinite(d.filter_beta) && d.filter_beta > 0.0f);
    d.accuracy_deg = pos_or(d.accuracy_deg, 0.5f);
    d.filter_min_cutoff_hz = pos_or(d.filter_min_cutoff_hz, 1.0f);
    d.filter_beta = pos_or(d.filter_beta, 0.3f);
    d.saccade_on_deg_s = pos_or(d.saccade_on_deg_s, 70.0f);
    d.saccade_off_deg_s = pos_or(d.saccade_off_deg_s, 35.0f);
    d.min_confidence = pos_or(d.min_confidence, 0.5f);
    d.max_eccentricity_deg = pos_or(d.max_eccentricity_deg, 60.0f);
    d.main_sequence_vmax_deg_s = pos_or(d.main_sequence_vmax_deg_s, 600.0f);
    d.main_sequence_c_deg = pos_or(d.main_sequence_c_deg, 9.0f);
    if (d.saccade_off_deg_s > d.saccade_on_deg_s) {
        FV_ERROR("gaze", "saccade_off_deg_s (%g) must not exceed saccade_on_deg_s (%g)", (double)d.saccade_off_deg_s,
                 (double)d.saccade_on_deg_s);
        return FV_ERR_INVALID_ARG;
    }
    if (d.max_eccentricity_deg > 90.0f || d.min_confidence > 1.0f) {
        FV_ERROR("gaze", "max_eccentricity_deg %g (<= 90) or min_confidence %g (<= 1) out of range",
                 (double)d.max_eccentricity_deg, (double)d.min_confidence);
        return FV_ERR_RANGE;
    }
    fv_gaze_pipeline *p = calloc(1, sizeof *p);
    if (!p) return FV_ERR_NO_MEMORY;
    p->desc = d;
    p->tun = tuning_filled(&d.tuning);
    p->adaptive_filter = adaptive;
    fv_gaze_noise_init(&p->noise);
    p->sacc_on = d.saccade_on_deg_s;
    p->sacc_on2 = INFINITY;
    p->sacc_off = d.saccade_off_deg_s;
    p->ms.vmax_deg_s = d.main_sequence_vmax_deg_s;
    p->ms.c_deg = d.main_sequence_c_deg;
    fv_gaze_clock_map_init(&p->clock, 0, 0);
    for (int c = 0; c < 3; c++) fv_gaze_one_euro_init(&p->ch[c].filter, d.filter_min_cutoff_hz, d.filter_beta, 1.0f);
    p->state = FV_GAZE_EVENT_NONE;
    p->pupil_mm = NAN;
    *out = p;
    return FV_OK;
}

void fv_gaze_pipeline_destroy(fv_gaze_pipeline **p)
{
    if (!p || !*p) return;
    free(*p);
    *p = NULL;
}

/* ---- angles ---- */

bool fv_gaze_dir_to_angles(fv_vec3 d, double max_ecc_deg, double out[2])
{
    if (!fv_v3_isfinite(d)) return false;
    double x = d.x, y = d.y, z = d.z;
    double len = sqrt(x * x + y * y + z * z);
    if (!(len > 1e-6) || !isfinite(len)) return false;
    x /= len;
    y /= len;
    z /= len;
    double ecc = fv_rad_to_deg(acos(fmax(-1.0, fmin(1.0, -z))));
    if (ecc > max_ecc_deg) return false;
    out[0] = fv_rad_to_deg(atan2(x, -z));
    out[1] = fv_rad_to_deg(atan2(y, sqrt(x * x + z * z)));
    return isfinite(out[0]) && isfinite(out[1]);
}

fv_vec3 fv_gaze_angles_to_dir(const double a[2])
{
    double yaw = isfinite(a[0]) ? fmax(-179.0, fmin(179.0, a[0])) : 0.0;
    double pitch = isfinite(a[1]) ? fmax(-89.0, fmin(89.0, a[1])) : 0.0;
    double cy = cos(fv_deg_to_rad(yaw)), sy = sin(fv_deg_to_rad(yaw));
    double cp = cos(fv_deg_to_rad(pitch)), sp = sin(fv_deg_to_rad(pitch));
    return fv_v3((float)(sy * cp), (float)sp, (float)(-cy * cp));
}

/* angular distance in degrees for small differences of (yaw, pitch) */
static double ang_norm(const double d[2], double pitch_deg)
{
    double c = cos(fv_deg_to_rad(fmax(-89.0, fmin(89.0, pitch_deg))));
    return sqrt(d[0] * c * d[0] * c + d[1] * d[1]);
}

/* ---- history ---- */

static void hist_clear(fv_gaze_pipeline *p) { p->h_count = 0; }

static void hist_push(fv_gaze_pipeline *p, int64_t t, const double pos[2])
{
    p->h_t[p->h_head] = t;
    p->h_p[p->h_head][0] = pos[0];
    p->h_p[p->h_head][1] = pos[1];
    p->h_head = (p->h_head + 1) % HIST;
    if (p->h_count < HIST) p->h_count++;
}

/* i = 0 is the newest */
static int hist_index(const fv_gaze_pipeline *p, int i) { return ((p->h_head - 1 - i) % HIST + HIST) % HIST; }

/* Least-squares line through the newest samples within window_ns (at least min_n when available, only samples at
 * or after from_ns). Returns the number used; slope in deg/s, intercept at the newest time. */
static int regress(const fv_gaze_pipeline *p, int64_t window_ns, int min_n, int64_t from_ns, double slope[2],
                   double icept[2])
{
    if (p->h_count == 0) return 0;
    int64_t t_new = p->h_t[hist_index(p, 0)];
    int n = 0;
    double st = 0, stt = 0, sp[2] = {0, 0}, stp[2] = {0, 0};
    for (int i = 0; i < p->h_count; i++) {
        int k = hist_index(p, i);
        int64_t dt_ns = fv_i64_sub_sat(t_new, p->h_t[k]);
        if (p->h_t[k] < from_ns) break;
        if (dt_ns > window_ns && n >= min_n) break;
        double t = (double)(-dt_ns) * 1e-9;
        st += t;
        stt += t * t;
        for (int a = 0; a < 2; a++) {
            sp[a] += p->h_p[k][a];
            stp[a] += t * p->h_p[k][a];
        }
        n++;
    }
    double den = n * stt - st * st;
    for (int a = 0; a < 2; a++) {
        if (n >= 2 && den > 1e-15) {
            slope[a] = (n * stp[a] - st * sp[a]) / den;
            icept[a] = (sp[a] - slope[a] * st) / n;
        } else {
            slope[a] = 0.0;
            icept[a] = n > 0 ? sp[a] / n : 0.0;
        }
        if (!isfinite(slope[a])) slope[a] = 0.0;
    }
    return n;
}

/* How many standard errors the fitted velocity of the newest n samples is away from zero (a t statistic on the
 * 2-D slope; the noise is estimated from the residuals). 0 when n < 4. */
static double slope_significance(const fv_gaze_pipeline *p, int n, const double slope[2], const double icept[2])
{
    if (n < 4) return 0.0;
    int64_t t_new = p->h_t[hist_index(p, 0)];
    double ss = 0.0, st = 0.0, stt = 0.0;
    for (int i = 0; i < n; i++) {
        int k = hist_index(p, i);
        double t = (double)(p->h_t[k] - t_new) * 1e-9;
        for (int a = 0; a < 2; a++) {
            double r = p->h_p[k][a] - (icept[a] + slope[a] * t);
            ss += r * r;
        }
        st += t;
        stt += t * t;
    }
    double sxx = stt - st * st / n;
    double var = ss / (2.0 * (n - 2));
    if (!(sxx > 0.0)) return 0.0;
    double se = sqrt(fmax(var, 1e-12) / sxx);
    double v = sqrt(slope[0] * slope[0] + slope[1] * slope[1]);
    double z = v / se;
    return isfinite(z) ? z : 0.0;
}

#define FIT_MAX_SAMPLES 16 /* samples of a saccade used by the landing fit (evenly thinned when more) */

/* Fit the saccade under way (main sequence, minimum jerk) to the samples since its onset; cache the result. */
static void fit_saccade(fv_gaze_pipeline *p)
{
    double t_s[FIT_MAX_SAMPLES], d[FIT_MAX_SAMPLES];
    p->fit_ok = false;
    const double *now = p->h_p[hist_index(p, 0)];
    double dir[2] = {now[0] - p->sacc_start_pos[0], now[1] - p->sacc_start_pos[1]};
    double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1]);
    if (!(len > 1e-6) || !isfinite(len)) return;
    dir[0] /= len;
    dir[1] /= len;
    int64_t t_new = p->h_t[hist_index(p, 0)];
    int count = 0;
    while (count < p->h_count && p->h_t[hist_index(p, count)] >= p->sacc_from_ns) count++;
    int n = count < FIT_MAX_SAMPLES ? count : FIT_MAX_SAMPLES;
    for (int j = 0; j < n; j++) {
        /* oldest first; with more samples than slots, an even selection that keeps the oldest and the newest */
        int i = n > 1 ? (int)((int64_t)(count - 1) * (n - 1 - j) / (n - 1)) : 0;
        int k = hist_index(p, i);
        t_s[j] = (double)(p->h_t[k] - t_new) * 1e-9;
        d[j] = (p->h_p[k][0] - p->sacc_start_pos[0]) * dir[0] + (p->h_p[k][1] - p->sacc_start_pos[1]) * dir[1];
    }
    fv_gaze_saccade_fit fit;
    if (!fv_gaze_saccade_fit_landing(&p->ms, t_s, d, n, &fit)) return;
    p->fit_ok = true;
    p->fit_confident = n >= 3 && fit.rms_deg < 0.5;
    p->fit_amp_deg = fit.amplitude_deg;
    p->fit_dur_s = fit.duration_s;
    p->fit_onset_ns = fv_i64_add_sat(t_new, (int64_t)llround(fit.t_onset_s * 1e9));
    p->fit_dir[0] = dir[0];
    p->fit_dir[1] = dir[1];
    p->fit_d_now = d[n - 1];
}

/* Where the saccade under way will be at t_target_ns (from the cached fit). */
static bool predict_saccade(const fv_gaze_pipeline *p, int64_t t_target_ns, double out[2], double *out_remaining_deg)
{
    if (!p->fit_ok) return false;
    double u = ((double)t_target_ns - (double)p->fit_onset_ns) * 1e-9 / p->fit_dur_s;
    double disp = p->fit_amp_deg * fv_gaze_minjerk(u);
    if (disp < p->fit_d_now) disp = p->fit_d_now; /* a saccade does not turn back */
    /* never beyond the plausible range of eye rotation */
    double lim = p->desc.max_eccentricity_deg;
    out[0] = fmax(-lim, fmin(lim, p->sacc_start_pos[0] + p->fit_dir[0] * disp));
    out[1] = fmax(-lim, fmin(lim, p->sacc_start_pos[1] + p->fit_dir[1] * disp));
    *out_remaining_deg = fabs(p->fit_amp_deg - disp);
    return isfinite(out[0]) && isfinite(out[1]);
}

/* ---- push ---- */

static bool eye_usable(const fv_gaze_pipeline *p, const fv_eye_sample *e, double out[2])
{
    if (!fv_gaze_eye_usable(e)) return false; /* the rules every reader and the evaluation truth obey */
    return fv_gaze_dir_to_angles(e->direction, p->desc.max_eccentricity_deg, out);
}

static void reset_motion(fv_gaze_pipeline *p, int64_t t)
{
    hist_clear(p);
    fv_gaze_noise_break(&p->noise);
    p->pend_count = 0; /* predictions across a hole are not scored */
    p->have_prev_raw = false;
    p->state = FV_GAZE_EVENT_FIXATION;
    p->segment_start_ns = t;
    p->long_ok = false;
    p->v_mid_sig = 0.0;
    p->v_short[0] = p->v_short[1] = p->v_long[0] = p->v_long[1] = 0.0;
    for (int c = 0; c < 3; c++) p->ch[c].filter.started = false;
}

static void restart_timeline(fv_gaze_pipeline *p)
{
    p->stats.clock_resets += (uint64_t)p->clock.resets + 1u;
    fv_gaze_clock_map_reset(&p->clock);
    p->clock.resets = 0;
    p->have_dev = false;
}

static int64_t map_time(fv_gaze_pipeline *p, const fv_gaze_sample *s)
{
    int64_t t;
    if (s->flags & FV_GAZE_HOST_TIME_VALID) {
        (void)fv_gaze_clock_map_observe(&p->clock, s->t_device_ns, s->t_host_ns); /* counted in clock.resets */
        if (!fv_gaze_clock_map_to_host(&p->clock, s->t_device_ns, &t)) t = s->t_host_ns;
        if (t > s->t_host_ns) t = s->t_host_ns; /* never newer than its receipt */
    } else if (!fv_gaze_clock_map_to_host(&p->clock, s->t_device_ns, &t)) {
        t = s->t_device_ns; /* no mapping yet: the device clock is taken as the host clock */
    }
    return t;
}

static void update_pupil(fv_gaze_pipeline *p, const fv_gaze_sample *s, int64_t t)
{
    double sum = 0.0;
    int n = 0;
    for (int e = 0; e < 2; e++) {
        const fv_eye_sample *es = &s->eye[e];
        if ((es->flags & FV_EYE_PUPIL_VALID) && !(es->flags & FV_EYE_BLINK) && isfinite(es->pupil_mm) &&
            es->pupil_mm >= PUPIL_MIN_MM && es->pupil_mm <= PUPIL_MAX_MM) {
            sum += es->pupil_mm;
            n++;
        }
    }
    if (n == 0 && (s->combined.flags & FV_EYE_PUPIL_VALID) && isfinite(s->combined.pupil_mm) &&
        s->combined.pupil_mm >= PUPIL_MIN_MM && s->combined.pupil_mm <= PUPIL_MAX_MM) {
        sum = s->combined.pupil_mm;
        n = 1;
    }
    if (n == 0) return;
    double v = sum / n;
    if (!p->pupil_valid || fv_i64_sub_sat(t, p->pupil_ns) > MAX_BLINK_NS) {
        p->pupil_mm = v;
    } else {
        double dt = (double)fv_i64_sub_sat(t, p->pupil_ns) * 1e-9;
        double a = dt > 0.0 ? 1.0 - exp(-dt / PUPIL_TAU_S) : 0.0;
        p->pupil_mm += a * (v - p->pupil_mm);
    }
    p->pupil_valid = true;
    p->pupil_ns = t;
}

static void classify(fv_gaze_pipeline *p, int64_t t)
{
    double icept[2];
    int ns = regress(p, SHORT_WINDOW_NS, 2, INT64_MIN, p->v_short, icept);
    double pitch = p->h_p[hist_index(p, 0)][1];
    double speed = ns >= 2 ? ang_norm(p->v_short, pitch) : 0.0;
    if (p->state != FV_GAZE_EVENT_SACCADE) {
        double speed2 = 0.0;
        if (p->h_count >= 2) {
            int k0 = hist_index(p, 0), k1 = hist_index(p, 1);
            double dt = (double)(p->h_t[k0] - p->h_t[k1]) * 1e-9;
            if (dt > 0.0) {
                double dv[2] = {(p->h_p[k0][0] - p->h_p[k1][0]) / dt, (p->h_p[k0][1] - p->h_p[k1][1]) / dt};
                speed2 = ang_norm(dv, pitch);
            }
        }
        if (speed > p->sacc_on || speed2 > p->sacc_on2) {
            p->state = FV_GAZE_EVENT_SACCADE;
            p->stats.saccades++;
            p->sacc_start_ns = t;
            /* the fit uses the samples of the velocity window (the onset is inside it) */
            p->sacc_from_ns = p->h_t[hist_index(p, ns - 1)];
            const channel *c = &p->ch[CH_COMBINED];
            const double *first = p->h_p[hist_index(p, ns - 1)];
            p->sacc_start_pos[0] = c->have ? c->pos[0] : first[0];
            p->sacc_start_pos[1] = c->have ? c->pos[1] : first[1];
            p->long_ok = false;
            return;
        }
    } else {
        if (speed < p->sacc_off || fv_i64_sub_sat(t, p->sacc_start_ns) > MAX_SACCADE_NS) {
            p->state = FV_GAZE_EVENT_FIXATION;
            p->segment_start_ns = t;
        } else {
            return;
        }
    }
    /* fixation or pursuit: the longer window, within this segment only */
    int nl = regress(p, LONG_WINDOW_NS, 3, p->segment_start_ns, p->v_long, p->reg_pos);
    int64_t span = nl > 0 ? fv_i64_sub_sat(t, p->h_t[hist_index(p, nl - 1)]) : 0;
    p->long_ok = nl >= 3 && span >= LONG_MIN_SPAN_NS;
    double vl = p->long_ok ? ang_norm(p->v_long, pitch) : 0.0;
    /* a pursuit velocity must stand out of the noise (3 standard errors), or extrapolating it only adds error */
    p->v_long_sig = p->long_ok ? slope_significance(p, nl, p->v_long, p->reg_pos) : 0.0;
    /* the extrapolated velocity: over the newest 50 ms of the segment (>= 4 samples), and how far it stands out */
    int nm = regress(p, MID_WINDOW_NS, 4, p->segment_start_ns, p->v_mid, p->mid_pos);
    p->v_mid_sig = slope_significance(p, nm, p->v_mid, p->mid_pos);
    if (p->state == FV_GAZE_EVENT_PURSUIT) {
        /* hysteresis on the significance too: a noisy tracker's fitted velocity is rarely below 2.5 deg/s */
        if (!p->long_ok || vl < PURSUIT_OFF_DEG_S || p->v_long_sig < 0.5 * PURSUIT_MIN_SIGNIFICANCE)
            p->state = FV_GAZE_EVENT_FIXATION;
    } else if (p->long_ok && vl > PURSUIT_ON_DEG_S && p->v_long_sig > PURSUIT_MIN_SIGNIFICANCE) {
        p->state = FV_GAZE_EVENT_PURSUIT;
    }
}

/* The candidate predictions at horizon h_s (clamped) after the newest valid sample for motion state ev:
 * the newest raw sample, the filtered position, and the model (fixation and pursuit: the filtered position moved
 * toward the line through the newest 50 ms, extrapolated by the share of its velocity that stands out of the noise,
 * g = 1 - (k/z)^2 for a velocity z standard errors from zero (James-Stein shrinkage; 0 below k): a fixation's drift
 * is within the noise, g = 0, the filtered position; a pursuit's velocity is not, g -> 1, the line free of the
 * filter's lag. Saccade: the main-sequence landing once the fit is confident, else the newest position).
 * *extra_unc: what the model adds to the uncertainty beyond the fixation growth. */
static int context(const fv_gaze_pipeline *p, fv_gaze_event ev);

/* The blend: the newest sample moved by the share lambda of the model's step from it that has paid off in this
 * context (least squares on the scored samples: lambda = E[(truth - sample).(model - sample)] / E[|model -
 * sample|^2], clamped to [0, 1]) -- shrinkage of the predicted displacement toward zero by its measured benefit. */
static void blend(const fv_gaze_pipeline *p, fv_gaze_event ev, double cand[CANDS][2])
{
    int cx = context(p, ev), st = cx / SPEED_BINS;
    double num = 0.0, den = 0.0;
    if (p->scored[cx] >= SCORE_MIN) num = p->lam_num[cx], den = p->lam_den[cx];
    else if (p->scored_state[st] >= SCORE_MIN) num = p->lam_num_state[st], den = p->lam_den_state[st];
    double lam = den > 1e-12 ? fmax(0.0, fmin(1.0, num / den)) : 0.0;
    if (!isfinite(lam) || p->tun.blend < 0.0) lam = 0.0; /* without the blend: the newest sample, never chosen */
    for (int a = 0; a < 2; a++)
        cand[CAND_BLEND][a] = cand[CAND_SAMPLE][a] + lam * (cand[CAND_MODEL][a] - cand[CAND_SAMPLE][a]);
}

static void candidates(const fv_gaze_pipeline *p, fv_gaze_event ev, double h_s, double cand[CANDS][2],
                       double *extra_unc)
{
    const double *raw = p->h_p[hist_index(p, 0)];
    const channel *cc = &p->ch[CH_COMBINED];
    double hpos = fmax(0.0, h_s);
    for (int a = 0; a < 2; a++) {
        cand[CAND_SAMPLE][a] = p->h_count > 0 ? raw[a] : cc->pos[a];
        cand[CAND_FILTERED][a] = cc->pos[a];
        cand[CAND_MODEL][a] = cc->pos[a];
        cand[CAND_SAMPLE_VEL][a] = cand[CAND_SAMPLE][a];
        cand[CAND_SAMPLE_HALF][a] = cand[CAND_SAMPLE][a];
        cand[CAND_BLEND][a] = cand[CAND_SAMPLE][a];
    }
    if (ev == FV_GAZE_EVENT_SACCADE) {
        double remaining = 0.0;
        int64_t target = fv_i64_add_sat(p->last_valid_ns, (int64_t)(h_s * 1e9));
        if (!p->fit_confident || !predict_saccade(p, target, cand[CAND_MODEL], &remaining)) {
            /* no trustworthy landing yet: the newest position (the saccade's extent is unknown) */
            cand[CAND_MODEL][0] = cc->pos[0];
            cand[CAND_MODEL][1] = cc->pos[1];
            remaining = ang_norm(p->v_short, cc->pos[1]) * hpos;
        }
        *extra_unc = 0.5 + 0.25 * remaining;
        /* the velocity slot: the landing fit even before it is confident (from its first two samples, the
         * amplitude prior decides); the scorer keeps it only where it pays */
        double r2;
        if (p->fit_ok && !predict_saccade(p, target, cand[CAND_SAMPLE_VEL], &r2)) {
            cand[CAND_SAMPLE_VEL][0] = cand[CAND_SAMPLE][0];
            cand[CAND_SAMPLE_VEL][1] = cand[CAND_SAMPLE][1];
        }
        /* inside a saccade the half-velocity slot holds the newest sample moved by the 20 ms velocity (a head
         * movement read as a saccade continues; the velocity slot stays the sample) */
        double lim = p->desc.max_eccentricity_deg;
        for (int a = 0; a < 2; a++)
            cand[CAND_SAMPLE_HALF][a] = fmax(-lim, fmin(lim, cand[CAND_SAMPLE_HALF][a] + p->v_short[a] * hpos));
        blend(p, ev, cand);
        return;
    }
    double z = p->v_mid_sig, k = SHRINK_SDS, g = z > k ? 1.0 - (k / z) * (k / z) : 0.0;
    for (int a = 0; a < 2; a++) {
        cand[CAND_MODEL][a] += g * (p->mid_pos[a] + p->v_mid[a] * h_s - cc->pos[a]);
        cand[CAND_SAMPLE_VEL][a] += g * p->v_mid[a] * h_s;
        cand[CAND_SAMPLE_HALF][a] += 0.5 * g * p->v_mid[a] * h_s;
    }
    *extra_unc = 0.25 * g * ang_norm(p->v_mid, cc->pos[1]) * hpos;
    blend(p, ev, cand);
}

/* The scoring context of state ev now: the state and a bin of the speed over the newest 50 ms (< 5, < 20, < 60,
 * >= 60 deg/s): the best candidate of a slow pursuit is not that of a fast one. Inside a saccade that speed is the
 * one before it (the 50 ms velocity is not updated in flight). A saccade that began from a fixation or a slow
 * pursuit (< 20 deg/s) is binned by how many of its samples have been seen instead (1: bin 0, 2: bin 4, 3 or more:
 * bin 5): what a candidate is worth depends on how much of the saccade the landing fit has had -- from one
 * displacement its amplitude is uncertain by a factor of several, from three it is not -- and a context mixing
 * the two takes the first samples' choice from the later ones' scores. One that began from fast motion (a head
 * movement on a head-worn tracker, a catch-up saccade in a fast pursuit) keeps its speed bin. */
static int context(const fv_gaze_pipeline *p, fv_gaze_event ev)
{
    int st = (int)ev >= 0 && (int)ev < STATES ? (int)ev : 0;
    double v = ang_norm(p->v_mid, p->h_count > 0 ? p->h_p[hist_index(p, 0)][1] : 0.0);
    double k = p->tun.speed_bin_scale;
    int bin = !(v >= 5.0 * k) ? 0 : v < 20.0 * k ? 1 : v < 60.0 * k ? 2 : 3;
    if (ev == FV_GAZE_EVENT_SACCADE && p->state == FV_GAZE_EVENT_SACCADE && !(v >= p->tun.slow_saccade_deg_s)) {
        int seen = 0;
        while (seen < p->h_count && seen < 3 && p->h_t[hist_index(p, seen)] >= p->sacc_start_ns) seen++;
        bin = seen <= 1 ? 0 : 2 + seen;
    }
    return st * SPEED_BINS + bin;
}

/* Prediction earns its place: every valid sample leaves the candidates' predictions for SCORE_HORIZON ahead; when
 * the samples around that time arrive, each candidate's angular error against the raw gaze interpolated there
 * enters a running mean per context (motion state x speed bin; the state alone until the context has SCORE_MIN).
 * choose_candidate() keeps the newest sample unless another candidate has led it by SELECT_SES standard errors in
 * this context (a tracker whose own filtering leaves nothing to gain, a noisy one where the saccade fit misleads).
 * The raw truth carries the tracker's noise, which is independent of every candidate 20 ms earlier. The mean
 * absolute error, not the mean square, ranks them: a candidate with rare large misses (a landing fit on a head
 * movement) loses less to them, and the 95th percentile followed better on the recordings. */
static int select_candidate(const fv_gaze_pipeline *p, fv_gaze_event ev);

/* Where prediction cannot help on this device (a tracker that filters heavily itself, or one whose motion the eye
 * data do not foretell), the whole device falls back: the selection's choices are scored against the newest sample
 * too, over every context, and while their running mean is not below it (after fallback_min scores) predict()
 * returns the newest sample. The check goes on in the background, so prediction comes back when it pays again. */
static int choose_candidate(const fv_gaze_pipeline *p, fv_gaze_event ev)
{
    return p->fallback ? CAND_SAMPLE : select_candidate(p, ev);
}

static void score_candidates(fv_gaze_pipeline *p, int64_t t, const double pos[2])
{
    while (p->pend_count > 0) {
        int i = (p->pend_head - p->pend_count + PEND_SLOTS) % PEND_SLOTS;
        if (p->pend[i].t_ns > t) break;
        p->pend_count--;
        int64_t gap = fv_i64_sub_sat(t, p->prev_raw_ns);
        if (!p->have_prev_raw || p->pend[i].t_ns < p->prev_raw_ns || gap > GAP_RESET_NS) continue;
        double w = gap > 0 ? ((double)p->pend[i].t_ns - (double)p->prev_raw_ns) / (double)gap : 1.0;
        double truth[2] = {p->prev_raw[0] + w * (pos[0] - p->prev_raw[0]), p->prev_raw[1] + w * (pos[1] - p->prev_raw[1])};
        int cx = p->pend[i].context, st = cx / SPEED_BINS;
        double lr = fmax(1.0 / ((double)p->scored[cx] + 1.0), 1.0 / SCORE_MEMORY);
        double ls = fmax(1.0 / ((double)p->scored_state[st] + 1.0), 1.0 / SCORE_MEMORY);
        double e[CANDS];
        for (int c = 0; c < CANDS; c++) {
            double d[2] = {p->pend[i].c[c][0] - truth[0], p->pend[i].c[c][1] - truth[1]};
            e[c] = ang_norm(d, truth[1]);
        }
        if (!isfinite(e[CAND_SAMPLE])) continue;
        {
            const double *s0 = p->pend[i].c[CAND_SAMPLE], *m0 = p->pend[i].c[CAND_MODEL];
            double dm[2] = {m0[0] - s0[0], m0[1] - s0[1]}, dr[2] = {truth[0] - s0[0], truth[1] - s0[1]};
            double num = dm[0] * dr[0] + dm[1] * dr[1], den = dm[0] * dm[0] + dm[1] * dm[1];
            if (isfinite(num) && isfinite(den)) {
                p->lam_num[cx] += lr * (num - p->lam_num[cx]);
                p->lam_den[cx] += lr * (den - p->lam_den[cx]);
                p->lam_num_state[st] += ls * (num - p->lam_num_state[st]);
                p->lam_den_state[st] += ls * (den - p->lam_den_state[st]);
            }
        }
        for (int c = 0; c < CANDS; c++) {
            if (!isfinite(e[c])) e[c] = e[CAND_SAMPLE] + 90.0; /* never chosen */
            double dd = e[c] - e[CAND_SAMPLE];
            p->mae[cx][c] += lr * (e[c] - p->mae[cx][c]);
            p->mae_state[st][c] += ls * (e[c] - p->mae_state[st][c]);
            p->dmean[cx][c] += lr * (dd - p->dmean[cx][c]);
            p->dsq[cx][c] += lr * (dd * dd - p->dsq[cx][c]);
            p->dmean_state[st][c] += ls * (dd - p->dmean_state[st][c]);
            p->dsq_state[st][c] += ls * (dd * dd - p->dsq_state[st][c]);
        }
        if (p->scored[cx] < UINT32_MAX) p->scored[cx]++;
        if (p->scored_state[st] < UINT32_MAX) p->scored_state[st]++;
        {
            /* the mean over every scored prediction (a choice of the sample itself adds 0) */
            int ch = p->pend[i].chosen;
            double dd = ch > CAND_SAMPLE && ch < CANDS ? e[ch] - e[CAND_SAMPLE] : 0.0;
            double lg = fmax(1.0 / ((double)p->dev_scored + 1.0), 1.0 / p->tun.fallback_memory);
            p->dev_dmean += lg * (dd - p->dev_dmean);
            p->dev_scored++;
            bool was = p->fallback;
            p->fallback = p->tun.fallback > 0.0 &&
                          ((double)p->dev_scored < p->tun.fallback_min || !(p->dev_dmean < 0.0));
            if (p->fallback != was) p->stats.fallback_switches++;
        }
    }
    p->have_prev_raw = true;
    p->prev_raw_ns = t;
    p->prev_raw[0] = pos[0];
    p->prev_raw[1] = pos[1];
    if (p->state != FV_GAZE_EVENT_FIXATION && p->state != FV_GAZE_EVENT_PURSUIT && p->state != FV_GAZE_EVENT_SACCADE)
        return;
    int i = p->pend_head;
    if (p->pend_count == PEND_SLOTS) p->pend_count--; /* the oldest gives way */
    p->pend_head = (p->pend_head + 1) % PEND_SLOTS;
    p->pend_count++;
    p->pend[i].t_ns = fv_i64_add_sat(t, SCORE_HORIZON_NS);
    p->pend[i].context = context(p, p->state);
    p->pend[i].chosen = select_candidate(p, p->state);
    double extra;
    candidates(p, p->state, (double)SCORE_HORIZON_NS * 1e-9, p->pend[i].c, &extra);
}

/* The candidate predict() uses in state ev: the model until the context (or its state) has SCORE_MIN scores; then
 * the newest sample unless a candidate's mean error stays below the sample's by SELECT_SES standard errors of the
 * paired difference (the one with the lowest upper bound): a tie, or a gain within the scores' noise, is the latest
 * sample itself, exactly. */
static int select_candidate(const fv_gaze_pipeline *p, fv_gaze_event ev)
{
    int cx = context(p, ev), st = cx / SPEED_BINS;
    const double *dm = NULL, *dq = NULL;
    double n = 0.0;
    if (p->scored[cx] >= SCORE_MIN) dm = p->dmean[cx], dq = p->dsq[cx], n = p->scored[cx];
    else if (p->scored_state[st] >= SCORE_MIN) dm = p->dmean_state[st], dq = p->dsq_state[st], n = p->scored_state[st];
    if (!dm) return CAND_MODEL;
    n = fmin(n, SCORE_MEMORY);
    int best = CAND_SAMPLE;
    double best_ub = 0.0;
    for (int c = 0; c < CANDS; c++) {
        double var = fmax(0.0, dq[c] - dm[c] * dm[c]);
        double ub = dm[c] + SELECT_SES * sqrt(var / n);
        if (ub < best_ub) best = c, best_ub = ub;
    }
    return best;
}

/* The tracker's noise and rate, measured during fixations, set the 1€ parameters (unless the desc fixed them) and
 * raise the saccade thresholds above the speed noise alone produces: SACCADE_NOISE_SDS standard errors of the
 * classifier's speed are needed to start a saccade. */
#define SACCADE_NOISE_SDS (p->tun.onset_sds)
#define SACCADE_ONSET2_SDS (p->tun.onset2_sds) /* the speed between the two newest samples: 6 of its SEs start one */
static void adapt_to_noise(fv_gaze_pipeline *p, int64_t t, const double pos[2], bool fixating)
{
    fv_gaze_noise_push(&p->noise, t, pos, fixating);
    double sigma = fv_gaze_noise_sigma_deg(&p->noise), rate = fv_gaze_noise_rate_hz(&p->noise);
    if (!isfinite(sigma) || !(rate > 0.0)) return;
    if (p->adaptive_filter) {
        float fc, beta;
        fv_gaze_noise_filter_params(sigma, rate, &fc, &beta);
        for (int c = 0; c < 3; c++) {
            p->ch[c].filter.min_cutoff_hz = fc;
            p->ch[c].filter.beta = beta;
        }
    }
    /* the classifier's speed is a least-squares slope over SHORT_WINDOW (n samples, n >= 2): its SE per axis is
     * sigma sqrt(12 / (n (n^2 - 1))) / dt, sqrt(2) sigma / dt for two samples */
    double ns = fmax(2.0, floor((double)SHORT_WINDOW_NS * 1e-9 * rate) + 1.0);
    double noise_speed = SACCADE_NOISE_SDS * sigma * sqrt(12.0 / (ns * (ns * ns - 1.0))) * rate;
    p->sacc_on = fmax((double)p->desc.saccade_on_deg_s, noise_speed);
    p->sacc_on2 = fmax((double)p->desc.saccade_on_deg_s, SACCADE_ONSET2_SDS * sigma * sqrt(2.0) * rate);
    p->sacc_off = p->sacc_on * (double)p->desc.saccade_off_deg_s / (double)p->desc.saccade_on_deg_s;
}

fv_result fv_gaze_pipeline_push(fv_gaze_pipeline *p, const fv_gaze_sample *s)
{
    if (!p || !s) return FV_ERR_INVALID_ARG;
    p->stats.pushed++;
    /* ---- time ---- */
    if (p->have_dev && s->t_device_ns <= p->last_dev_ns) {
        bool restarted = (s->flags & FV_GAZE_HOST_TIME_VALID) && s->t_host_ns > p->last_host_ns &&
                         (double)p->last_dev_ns - (double)s->t_device_ns > (double)DEVICE_RESET_NS;
        if (!restarted) {
            p->stats.rejected++;
            return FV_NO_NEW_DATA;
        }
        FV_WARN("gaze", "device clock went back %.3f s: restarting the clock mapping",
                ((double)p->last_dev_ns - (double)s->t_device_ns) * 1e-9);
        restart_timeline(p);
    }
    int64_t t = map_time(p, s);
    if (p->have_dev && t < p->last_host_ns) t = p->last_host_ns; /* monotonic timeline */
    p->have_dev = true;
    p->last_dev_ns = s->t_device_ns;
    p->last_host_ns = t;

    /* ---- validity ---- */
    bool low_conf = isfinite(s->confidence) && s->confidence < p->desc.min_confidence;
    double a[3][2];
    bool ok[3] = {false, false, false};
    /* a live device's physically impossible rays (fv_gaze_validity.h) are dropped here, as the readers do */
    fv_gaze_sample g = *s;
    if (fv_gaze_sample_enforce(&g)) p->stats.impossible++;
    if (!low_conf) {
        ok[CH_LEFT] = eye_usable(p, &g.eye[0], a[CH_LEFT]);
        ok[CH_RIGHT] = eye_usable(p, &g.eye[1], a[CH_RIGHT]);
        ok[CH_COMBINED] = eye_usable(p, &g.combined, a[CH_COMBINED]);
    }
    if (!ok[CH_COMBINED] && ok[CH_LEFT] && ok[CH_RIGHT]) {
        for (int k = 0; k < 2; k++) a[CH_COMBINED][k] = 0.5 * (a[CH_LEFT][k] + a[CH_RIGHT][k]);
        ok[CH_COMBINED] = true;
    } else if (!ok[CH_COMBINED] && (ok[CH_LEFT] || ok[CH_RIGHT])) {
        int e = ok[CH_LEFT] ? CH_LEFT : CH_RIGHT;
        for (int k = 0; k < 2; k++) a[CH_COMBINED][k] = a[e][k] - (p->verg_valid[e] ? p->verg[e][k] : 0.0);
        ok[CH_COMBINED] = true;
    }
    if (!ok[CH_COMBINED]) {
        p->stats.invalid++;
        p->last_sample_valid = false;
        return FV_OK;
    }
    if (ok[CH_LEFT] != ok[CH_RIGHT]) p->stats.one_eye++;
    /* vergence offsets, from samples where an eye and the combined ray are both seen */
    for (int e = 0; e < 2; e++) {
        if (!ok[e] || !(ok[CH_LEFT] && ok[CH_RIGHT])) continue;
        double off[2] = {a[e][0] - a[CH_COMBINED][0], a[e][1] - a[CH_COMBINED][1]};
        if (!p->verg_valid[e]) {
            p->verg[e][0] = off[0];
            p->verg[e][1] = off[1];
            p->verg_valid[e] = true;
        } else {
            double dt = p->have_valid ? (double)fv_i64_sub_sat(t, p->last_valid_ns) * 1e-9 : 0.0;
            double w = dt > 0.0 ? 1.0 - exp(-dt / VERGENCE_TAU_S) : 0.0;
            for (int k = 0; k < 2; k++) p->verg[e][k] += w * (off[k] - p->verg[e][k]);
        }
    }
    update_pupil(p, s, t);

    /* ---- motion ---- */
    if (!p->have_valid || fv_i64_sub_sat(t, p->last_valid_ns) > GAP_RESET_NS) reset_motion(p, t);
    hist_push(p, t, a[CH_COMBINED]);
    fv_gaze_event was = p->state;
    classify(p, t);
    bool sacc = p->state == FV_GAZE_EVENT_SACCADE;
    /* until the noise is known every difference measures it (the classifier's thresholds depend on it: a tracker
     * noisier than the default saccade threshold would otherwise never show a fixation); then fixations only */
    bool fixating = (was == FV_GAZE_EVENT_FIXATION && p->state == FV_GAZE_EVENT_FIXATION) ||
                    !isfinite(fv_gaze_noise_sigma_deg(&p->noise));
    adapt_to_noise(p, t, a[CH_COMBINED], fixating);
    /* through a saccade the estimate follows the raw signal; the first sample after it starts the fixation afresh
     * (at low rates the filter would otherwise lag the landing by several samples) */
    bool restart = sacc || was == FV_GAZE_EVENT_SACCADE;
    for (int c = 0; c < 3; c++) {
        if (!ok[c]) continue;
        channel *ch = &p->ch[c];
        if (restart) fv_gaze_one_euro_reset(&ch->filter, t, a[c]);
        fv_gaze_one_euro_push(&ch->filter, t, a[c], ch->pos);
        ch->have = true;
        ch->t_ns = t;
    }
    /* what a blink holds: the fixation (or pursuit position) last seen; inside a saccade, its predicted landing */
    double rem;
    if (sacc) fit_saccade(p);
    else p->fit_ok = false;
    int choice = choose_candidate(p, p->state);
    if (!sacc || choice != CAND_MODEL || !p->fit_confident || !predict_saccade(p, INT64_MAX / 2, p->hold_pos, &rem)) {
        /* the candidate that has earned its place in this state, at the newest sample */
        bool raw = choice == CAND_SAMPLE && p->h_count > 0;
        p->hold_pos[0] = raw ? a[CH_COMBINED][0] : p->ch[CH_COMBINED].pos[0];
        p->hold_pos[1] = raw ? a[CH_COMBINED][1] : p->ch[CH_COMBINED].pos[1];
    }
    p->have_valid = true;
    p->last_sample_valid = true;
    p->last_valid_ns = t;
    score_candidates(p, t, a[CH_COMBINED]);
    return FV_OK;
}

/* ---- predict ---- */

static float finite_clamp(double v, double lo, double hi)
{
    if (!(v >= lo)) return (float)lo; /* NaN too */
    return (float)(v > hi ? hi : v);
}

void fv_gaze_pipeline_predict(fv_gaze_pipeline *p, int64_t t_target_ns, fv_gaze_prediction *out)
{
    memset(out, 0, sizeof *out);
    out->t_target_ns = t_target_ns;
    out->dir_head[0] = out->dir_head[1] = out->combined_dir_head = fv_v3(0.0f, 0.0f, -1.0f);
    out->pupil_mm = NAN;
    out->uncertainty_deg = (float)MAX_UNCERTAINTY_DEG;
    out->event = FV_GAZE_EVENT_NONE;
    if (!p) return;
    double acc = p->desc.accuracy_deg;
    if (!p->have_valid) {
        out->event = p->device_lost ? FV_GAZE_EVENT_LOST : FV_GAZE_EVENT_NONE;
        return;
    }
    out->t_sample_ns = p->last_valid_ns;
    double since_valid_s = ((double)t_target_ns - (double)p->last_valid_ns) * 1e-9;
    double h_s = fmax(-MAX_EXTRAPOLATION_S, fmin(MAX_EXTRAPOLATION_S, since_valid_s));
    fv_gaze_event ev = p->state;
    if (p->device_lost || since_valid_s * 1e9 > (double)MAX_BLINK_NS) ev = FV_GAZE_EVENT_LOST;
    else if (!p->last_sample_valid) ev = FV_GAZE_EVENT_BLINK;
    out->event = ev;
    out->predicted = !p->desc.disable_prediction;

    const channel *cc = &p->ch[CH_COMBINED];
    double pred[2] = {cc->pos[0], cc->pos[1]};
    double unc = acc;
    double hpos = fmax(0.0, h_s);
    if (ev == FV_GAZE_EVENT_BLINK || ev == FV_GAZE_EVENT_LOST) {
        pred[0] = p->hold_pos[0];
        pred[1] = p->hold_pos[1];
        unc += fmin(20.0, BLINK_GROWTH_DEG_S * fmax(0.0, since_valid_s));
        if (ev == FV_GAZE_EVENT_LOST) unc = fmax(unc, LOST_UNCERTAINTY_DEG);
    } else if (p->desc.disable_prediction) {
        double v = ev == FV_GAZE_EVENT_SACCADE ? ang_norm(p->v_short, pred[1]) : ang_norm(p->v_long, pred[1]);
        unc += FIXATION_GROWTH_DEG_S * hpos + 0.5 * v * hpos;
    } else {
        /* fixation, pursuit, saccade: the candidate that has earned its place in this state (the model at first) */
        double cand[CANDS][2], extra = 0.0;
        candidates(p, ev, h_s, cand, &extra);
        int c = choose_candidate(p, ev);
        p->stats.predictions++;
        if (p->fallback) p->stats.fallback_predictions++;
        pred[0] = cand[c][0];
        pred[1] = cand[c][1];
        unc += FIXATION_GROWTH_DEG_S * hpos + (c == CAND_MODEL ? extra : 0.0);
        if (c != CAND_MODEL) {
            double v = ev == FV_GAZE_EVENT_SACCADE ? ang_norm(p->v_short, pred[1]) : ang_norm(p->v_mid, pred[1]);
            unc += 0.5 * v * hpos;
        }
        /* calibrated by experience: at least the chosen candidate's measured mean error at SCORE_HORIZON times the
         * factor that covers ~90% of a Rayleigh-distributed error (1.72 x its mean), scaled with the horizon */
        int cx = context(p, ev);
        if (p->scored[cx] >= SCORE_MIN) {
            double scale = fmin(3.0, fmax(0.25, hpos / ((double)SCORE_HORIZON_NS * 1e-9)));
            unc = fmax(unc, acc + RADIUS_PER_MEAN_ERROR * p->mae[cx][c] * scale);
        }
    }
    if (!isfinite(pred[0]) || !isfinite(pred[1])) {
        pred[0] = p->hold_pos[0];
        pred[1] = p->hold_pos[1];
    }
    out->combined_valid = true;
    out->combined_dir_head = fv_gaze_angles_to_dir(pred);
    for (int e = 0; e < 2; e++) {
        const channel *ce = &p->ch[e];
        double pe[2];
        bool blinkish = ev == FV_GAZE_EVENT_BLINK || ev == FV_GAZE_EVENT_LOST;
        if (!blinkish && ce->have && ce->t_ns == p->last_valid_ns) {
            /* this eye was seen in the newest sample: its own estimate moved by the predicted change */
            for (int k = 0; k < 2; k++) pe[k] = ce->pos[k] + (pred[k] - cc->pos[k]);
        } else {
            for (int k = 0; k < 2; k++) pe[k] = pred[k] + (p->verg_valid[e] ? p->verg[e][k] : 0.0);
        }
        if (!isfinite(pe[0]) || !isfinite(pe[1])) {
            pe[0] = pred[0];
            pe[1] = pred[1];
        }
        out->eye_valid[e] = true;
        out->dir_head[e] = fv_gaze_angles_to_dir(pe);
    }
    out->uncertainty_deg = finite_clamp(unc, acc, MAX_UNCERTAINTY_DEG);
    if (p->pupil_valid && ev != FV_GAZE_EVENT_LOST && isfinite(p->pupil_mm)) out->pupil_mm = (float)p->pupil_mm;
}

void fv_gaze_pipeline_set_device_lost(fv_gaze_pipeline *p, bool lost, int64_t now_ns)
{
    if (!p) return;
    if (lost && !p->device_lost) p->lost_since_ns = now_ns;
    p->device_lost = lost;
}

void fv_gaze_pipeline_get_stats(const fv_gaze_pipeline *p, fv_gaze_pipeline_stats *out)
{
    *out = p->stats;
    out->clock_resets += (uint64_t)p->clock.resets;
    out->clock_skew_ppm = fv_gaze_clock_map_skew_ppm(&p->clock);
    out->noise_deg = fv_gaze_noise_sigma_deg(&p->noise);
    out->rate_hz = fv_gaze_noise_rate_hz(&p->noise);
    out->filter_min_cutoff_hz = p->ch[CH_COMBINED].filter.min_cutoff_hz;
    out->filter_beta = p->ch[CH_COMBINED].filter.beta;
    out->fallback = p->fallback;
    out->fallback_margin_deg = p->dev_dmean;
}

fv_gaze_event fv_gaze_pipeline_event(const fv_gaze_pipeline *p)
{
    if (!p->have_valid) return FV_GAZE_EVENT_NONE;
    if (!p->last_sample_valid) return FV_GAZE_EVENT_BLINK;
    return p->state;
}

int64_t fv_gaze_pipeline_last_sample_ns(const fv_gaze_pipeline *p) { return p->have_dev ? p->last_host_ns : 0; }

int fv_gaze_pipeline_candidates(const fv_gaze_pipeline *p, int64_t t_target_ns, double out[FV_GAZE_CANDIDATES][2])
{
    _Static_assert(FV_GAZE_CANDIDATES == CANDS, "candidate count");
    if (!p || !out || !p->have_valid || !p->last_sample_valid || p->device_lost || p->desc.disable_prediction)
        return -1;
    double since_valid_s = ((double)t_target_ns - (double)p->last_valid_ns) * 1e-9;
    if (since_valid_s * 1e9 > (double)MAX_BLINK_NS) return -1;
    double h_s = fmax(-MAX_EXTRAPOLATION_S, fmin(MAX_EXTRAPOLATION_S, since_valid_s)), extra = 0.0;
    candidates(p, p->state, h_s, out, &extra);
    return choose_candidate(p, p->state);
}
