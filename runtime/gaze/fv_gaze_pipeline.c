/* @brief The gaze pipeline: device clock → host clock → validity → 1€ filter → classification → prediction with an
 * uncertainty radius (see fv_gaze_pipeline.h). Angles are (yaw, pitch) in degrees: yaw positive to the right,
 * pitch positive up, (0, 0) straight ahead (-z). */
#include "gaze_pipeline_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

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
bool fv_gaze_predict_saccade(const fv_gaze_pipeline *p, int64_t t_target_ns, double out[2], double *out_remaining_deg)
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
    int choice = fv_gaze_choose_candidate(p, p->state);
    if (!sacc || choice != CAND_MODEL || !p->fit_confident || !fv_gaze_predict_saccade(p, INT64_MAX / 2, p->hold_pos, &rem)) {
        /* the candidate that has earned its place in this state, at the newest sample */
        bool raw = choice == CAND_SAMPLE && p->h_count > 0;
        p->hold_pos[0] = raw ? a[CH_COMBINED][0] : p->ch[CH_COMBINED].pos[0];
        p->hold_pos[1] = raw ? a[CH_COMBINED][1] : p->ch[CH_COMBINED].pos[1];
    }
    p->have_valid = true;
    p->last_sample_valid = true;
    p->last_valid_ns = t;
    fv_gaze_score_candidates(p, t, a[CH_COMBINED]);
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
        fv_gaze_candidates(p, ev, h_s, cand, &extra);
        int c = fv_gaze_choose_candidate(p, ev);
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
        int cx = fv_gaze_context(p, ev);
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
    fv_gaze_candidates(p, p->state, h_s, out, &extra);
    return fv_gaze_choose_candidate(p, p->state);
}
