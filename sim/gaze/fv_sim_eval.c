/* @brief Gaze pipeline evaluation against the simulated eye's truth or a recording's own later samples
 * (see fv_sim_eval.h). */
#include "fv_sim_eval.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_sim_driver.h"
#include "fv_gaze_validity.h"
#include "fv_stats.h"

static const int g_horizons_ms[FV_SIM_EVAL_HORIZONS] = {0, 10, 20, 40, 60};

const char *fv_sim_eval_truth_name(fv_sim_eval_truth t)
{
    switch (t) {
    case FV_SIM_EVAL_TRUTH_RAW: return "raw";
    case FV_SIM_EVAL_TRUTH_SMOOTHED: return "smoothed";
    case FV_SIM_EVAL_TRUTH_TRUE: return "true";
    case FV_SIM_EVAL_TRUTHS: break;
    }
    return "unknown";
}

const char *fv_sim_eval_method_name(fv_sim_eval_method m)
{
    switch (m) {
    case FV_SIM_EVAL_PREDICTED: return "predicted";
    case FV_SIM_EVAL_LATEST_FILTERED: return "latest_filtered";
    case FV_SIM_EVAL_LATEST_SAMPLE: return "latest_sample";
    case FV_SIM_EVAL_METHODS: break;
    }
    return "unknown";
}

typedef struct rec {
    fv_gaze_sample s;
    fv_sim_truth truth;
    bool has_truth;
    bool raw_valid;     /* a usable combined direction in the raw sample */
    fv_vec3 raw_dir;
    fv_vec3 smooth_dir; /* zero-phase smoothing of the valid raw directions (when raw_valid) */
    int64_t t_ns;       /* the sample's time on the evaluation timeline (receipt, host clock) */
} rec;

typedef struct interval {
    int64_t t0, t1;
    bool used, excluded;
} interval;

/* angle between two directions in degrees, accurate for small angles */
static double angle_deg(fv_vec3 a, fv_vec3 b)
{
    double ax = a.x, ay = a.y, az = a.z, bx = b.x, by = b.y, bz = b.z;
    double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
    double cr = sqrt(cx * cx + cy * cy + cz * cz), dt = ax * bx + ay * by + az * bz;
    return fv_rad_to_deg(atan2(cr, dt));
}

/* The truth obeys the same validity rules as the readers and the pipeline (fv_gaze_validity.h): a ray no eye can
 * make is no truth. */
static bool raw_combined(const fv_gaze_sample *s, fv_vec3 *out) { return fv_gaze_sample_direction(s, out); }

static fv_sim_eval_error summarize(double *v, uint64_t n)
{
    fv_sim_eval_error e = {0.0, 0.0, n, NAN};
    if (n == 0) return e;
    double sum = 0.0;
    for (uint64_t i = 0; i < n; i++) sum += v[i];
    e.mean_deg = sum / (double)n;
    e.p95_deg = fv_percentile_f64(v, (size_t)n, 95.0); /* nearest rank */
    return e;
}

/* ---- reading ---- */

static fv_result collect(fv_device *dev, fv_clock *clock, double seconds, rec **out_recs, size_t *out_n,
                          bool *out_whole)
{
    size_t cap = 4096, n = 0;
    rec *recs = malloc(cap * sizeof *recs);
    if (!recs) return FV_ERR_NO_MEMORY;
    fv_gaze_sample buf[64];
    bool have_first = false;
    int64_t first_dev = 0;
    int idle = 0;
    fv_result r = FV_OK;
    for (;;) {
        size_t got = 0;
        r = fv_device_read(dev, buf, 64, &got, 100);
        if (r == FV_END_OF_STREAM) {
            *out_whole = true;
            r = FV_OK;
            break;
        }
        if (r == FV_TIMEOUT) {
            /* a paced source with nothing due: move the simulated clock on (bounded) */
            if (++idle > 36000) {
                FV_ERROR("gaze", "%s: no sample in an hour of simulated time", dev->info.uri);
                r = FV_ERR_DEVICE_LOST;
                goto fail;
            }
            clock->sleep_until_ns(clock, fv_clock_now_ns(clock) + 100 * FV_NS_PER_MS);
            continue;
        }
        if (FV_FAILED(r)) {
            FV_ERROR("gaze", "%s: read failed: %s", dev->info.uri, fv_result_str(r));
            goto fail;
        }
        idle = 0;
        bool done = false;
        for (size_t i = 0; i < got && !done; i++) {
            if (!have_first) {
                have_first = true;
                first_dev = buf[i].t_device_ns;
            }
            if ((double)buf[i].t_device_ns - (double)first_dev >= seconds * 1e9 || n >= FV_SIM_EVAL_MAX_SAMPLES) {
                done = true;
                break;
            }
            if (n == cap) {
                rec *bigger = realloc(recs, 2 * cap * sizeof *recs);
                if (!bigger) {
                    r = FV_ERR_NO_MEMORY;
                    goto fail;
                }
                recs = bigger;
                cap *= 2;
            }
            rec *rc = &recs[n++];
            memset(rc, 0, sizeof *rc);
            rc->s = buf[i];
            rc->has_truth = fv_sim_device_truth(dev, buf[i].seq, &rc->truth);
            rc->raw_valid = raw_combined(&buf[i], &rc->raw_dir);
            rc->t_ns = (buf[i].flags & FV_GAZE_HOST_TIME_VALID) ? buf[i].t_host_ns : buf[i].t_device_ns;
        }
        if (done) break;
    }
    *out_recs = recs;
    *out_n = n;
    return FV_OK;
fail:
    free(recs);
    return r;
}

#define REF_MAX_GAP_NS (50 * FV_NS_PER_MS) /* the truth is never interpolated across a longer hole */

/* The recording itself at time t: the raw (or smoothed) gaze interpolated between the valid neighbours of t (at
 * most 50 ms apart). */
static bool reference_from_samples(const rec *recs, size_t n, size_t from, int64_t t, bool smoothed, fv_vec3 *out)
{
    size_t j = from;
    while (j + 1 < n && recs[j + 1].t_ns <= t) j++;
    if (j + 1 >= n || recs[j].t_ns > t) return false;
    const rec *a = &recs[j], *b = &recs[j + 1];
    if (!a->raw_valid || !b->raw_valid || fv_i64_sub_sat(b->t_ns, a->t_ns) > REF_MAX_GAP_NS || b->t_ns <= a->t_ns)
        return false;
    fv_vec3 da = smoothed ? a->smooth_dir : a->raw_dir, db = smoothed ? b->smooth_dir : b->raw_dir;
    float w = (float)((double)fv_i64_sub_sat(t, a->t_ns) / (double)fv_i64_sub_sat(b->t_ns, a->t_ns));
    *out = fv_v3_normalize_or(fv_v3_add(fv_v3_scale(da, 1.0f - w), fv_v3_scale(db, w)), da);
    return true;
}

/* Median interval between consecutive samples (ns); 0 with fewer than 2. */
static int64_t median_interval_ns(const rec *recs, size_t n)
{
    if (n < 2) return 0;
    double *dt = malloc((n - 1) * sizeof *dt);
    if (!dt) return 0;
    for (size_t i = 1; i < n; i++) dt[i - 1] = (double)fv_i64_sub_sat(recs[i].t_ns, recs[i - 1].t_ns);
    double m = fv_percentile_f64(dt, n - 1, 50.0);
    free(dt);
    return m > 0.0 && isfinite(m) ? (int64_t)m : 0;
}

/* Zero-phase smoothing of the valid raw directions: per sample, a least-squares quadratic in time (yaw and pitch)
 * through the valid samples within +-half_ns of the same valid run (no hole > 50 ms), evaluated at the sample's
 * time (a Savitzky-Golay filter on an irregular time axis). Fewer than 5 samples in reach: the local mean of those
 * there; the samples themselves when fewer than 3. */
static void smooth_recording(rec *recs, size_t n, int64_t half_ns)
{
    int64_t *run = malloc(n * sizeof *run);
    if (!run) {
        for (size_t i = 0; i < n; i++) recs[i].smooth_dir = recs[i].raw_dir;
        return;
    }
    int64_t id = 0, last_valid_t = INT64_MIN;
    for (size_t i = 0; i < n; i++) {
        if (!recs[i].raw_valid) continue;
        if (last_valid_t == INT64_MIN || fv_i64_sub_sat(recs[i].t_ns, last_valid_t) > REF_MAX_GAP_NS) id++;
        run[i] = id;
        last_valid_t = recs[i].t_ns;
    }
    double hs = (double)half_ns * 1e-9;
    for (size_t i = 0; i < n; i++) {
        rec *ri = &recs[i];
        if (!ri->raw_valid) continue;
        ri->smooth_dir = ri->raw_dir;
        double a0[2];
        if (!fv_gaze_dir_to_angles(ri->raw_dir, 90.0, a0)) continue;
        /* normal equations in u = (t_j - t_i) / half: sums of u^k (k = 0..4) and of u^k * angle (k = 0..2) */
        double su[5] = {0}, sy[2][3] = {{0}};
        size_t lo = i, hi = i;
        while (lo > 0 && fv_i64_sub_sat(ri->t_ns, recs[lo - 1].t_ns) <= half_ns) lo--;
        while (hi + 1 < n && fv_i64_sub_sat(recs[hi + 1].t_ns, ri->t_ns) <= half_ns) hi++;
        for (size_t j = lo; j <= hi; j++) {
            double aj[2];
            if (!recs[j].raw_valid || run[j] != run[i] || !fv_gaze_dir_to_angles(recs[j].raw_dir, 90.0, aj)) continue;
            double u = (double)fv_i64_sub_sat(recs[j].t_ns, ri->t_ns) * 1e-9 / hs, uk = 1.0;
            for (int k = 0; k < 5; k++, uk *= u) su[k] += uk;
            for (int c = 0; c < 2; c++) {
                double d = aj[c] - a0[c];
                sy[c][0] += d, sy[c][1] += u * d, sy[c][2] += u * u * d;
            }
        }
        double cnt = su[0], out[2];
        if (cnt < 3.0) continue;
        /* 3x3 solve by Cramer's rule for c0 (the value at u = 0); a degenerate layout falls back to the mean */
        double m[3][3] = {{su[0], su[1], su[2]}, {su[1], su[2], su[3]}, {su[2], su[3], su[4]}};
        double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        for (int c = 0; c < 2; c++) {
            double b0 = sy[c][0], b1 = sy[c][1], b2 = sy[c][2];
            double c0 = b0 / cnt;
            if (cnt >= 5.0 && fabs(det) > 1e-9 * cnt * cnt * cnt) {
                double d0 = b0 * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (b1 * m[2][2] - m[1][2] * b2) +
                            m[0][2] * (b1 * m[2][1] - m[1][1] * b2);
                c0 = d0 / det;
            }
            out[c] = a0[c] + (isfinite(c0) ? c0 : 0.0);
        }
        ri->smooth_dir = fv_gaze_angles_to_dir(out);
    }
    free(run);
}

static bool overlaps_blink(const interval *blinks, size_t nb, int64_t t0, int64_t t1)
{
    for (size_t i = 0; i < nb; i++)
        if (t0 < blinks[i].t1 && t1 > blinks[i].t0) return true;
    return false;
}

static void match_saccades(fv_sim_eye *eye, int64_t span0, int64_t span1, interval *det, size_t nd,
                           fv_sim_eval_result *out)
{
    size_t nev = fv_sim_eye_event_count(eye);
    interval *truth = calloc(nev + 1, sizeof *truth), *blinks = calloc(nev + 1, sizeof *blinks);
    size_t nt = 0, nb = 0;
    if (!truth || !blinks) goto done;
    for (size_t i = 0; i < nev; i++) {
        fv_sim_event ev;
        if (!fv_sim_eye_event_get(eye, i, &ev)) continue;
        if (ev.label == FV_SIM_BLINK) blinks[nb++] = (interval){ev.t_start_ns, ev.t_end_ns, false, false};
    }
    for (size_t i = 0; i < nev; i++) {
        fv_sim_event ev;
        if (!fv_sim_eye_event_get(eye, i, &ev) || ev.label != FV_SIM_SACCADE) continue;
        if (ev.t_start_ns < span0 || ev.t_end_ns > span1) continue;
        bool hidden = overlaps_blink(blinks, nb, ev.t_start_ns, ev.t_end_ns);
        truth[nt++] = (interval){ev.t_start_ns, ev.t_end_ns, false, hidden};
    }
    int64_t tol = (int64_t)(FV_SIM_EVAL_MATCH_TOL_MS * 1e6);
    for (size_t i = 0; i < nt; i++) {
        if (truth[i].excluded) out->true_saccades_hidden++;
        else out->true_saccades++;
    }
    for (size_t d = 0; d < nd; d++) {
        bool in_blink = overlaps_blink(blinks, nb, det[d].t0 - tol, det[d].t1 + tol);
        bool matched = false;
        for (size_t i = 0; i < nt && !matched; i++) {
            if (truth[i].used) continue;
            if (det[d].t0 <= truth[i].t1 + tol && det[d].t1 >= truth[i].t0 - tol) {
                truth[i].used = true;
                matched = true;
                if (truth[i].excluded) out->det_in_blink++;
                else out->tp++;
            }
        }
        if (!matched) {
            if (in_blink) out->det_in_blink++;
            else out->fp++;
        }
    }
    for (size_t i = 0; i < nt; i++)
        if (!truth[i].used && !truth[i].excluded) out->fn++;
done:
    free(truth);
    free(blinks);
    double tp = (double)out->tp;
    out->precision = tp + out->fp > 0 ? tp / (tp + (double)out->fp) : 0.0;
    out->recall = tp + out->fn > 0 ? tp / (tp + (double)out->fn) : 0.0;
    out->f1 = 2 * tp + out->fp + out->fn > 0 ? 2 * tp / (2 * tp + (double)out->fp + (double)out->fn) : 0.0;
}

static void bench(const rec *recs, size_t n, const fv_sim_eval_desc *desc, fv_sim_eval_result *out)
{
    double best = INFINITY;
    for (int rep = 0; rep < desc->bench_repeats; rep++) {
        fv_gaze_pipeline *p = NULL;
        if (fv_gaze_pipeline_create(&desc->pipeline, &p) != FV_OK) return;
        int64_t t0 = fv_time_monotonic_ns();
        fv_gaze_prediction pr;
        float sink = 0.0f;
        for (size_t i = 0; i < n; i++) {
            if (fv_gaze_pipeline_push(p, &recs[i].s) < 0) break;
            fv_gaze_pipeline_predict(p, recs[i].t_ns + 20 * FV_NS_PER_MS, &pr);
            sink += pr.uncertainty_deg;
        }
        int64_t t1 = fv_time_monotonic_ns();
        fv_gaze_pipeline_destroy(&p);
        double per = (double)(t1 - t0) / (double)n + (sink < 0.0f ? 1.0 : 0.0);
        if (per < best) best = per;
    }
    out->ns_per_sample = isfinite(best) ? best : 0.0;
}

static fv_sim_eval_error summarize_with(double *v, const unsigned char *inside, uint64_t n, bool has_radius)
{
    fv_sim_eval_error e = summarize(v, n);
    e.inside_radius = NAN;
    if (has_radius && n > 0) {
        uint64_t k = 0;
        for (uint64_t i = 0; i < n; i++) k += inside[i];
        e.inside_radius = (double)k / (double)n;
    }
    return e;
}

static void csv_angles(FILE *f, bool ok, fv_vec3 d)
{
    double a[2];
    if (ok && fv_gaze_dir_to_angles(d, 90.0, a)) fprintf(f, ",%.4f,%.4f", a[0], a[1]);
    else fputs(",NaN,NaN", f);
}

fv_result fv_sim_eval_run(fv_device *dev, fv_clock *clock, const fv_sim_eval_desc *desc, fv_sim_eval_result *out)
{
    if (!dev || !clock || !desc || !out) return FV_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    for (int h = 0; h < FV_SIM_EVAL_HORIZONS; h++) out->horizon_ms[h] = g_horizons_ms[h];
    fv_sim_eye *eye = fv_sim_device_eye(dev);
    double seconds = desc->seconds > 0.0 ? desc->seconds : eye ? 60.0 : FV_SIM_EVAL_MAX_SECONDS;
    int64_t origin = fv_sim_device_host_origin_ns(dev);
    out->has_truth = eye != NULL;

    rec *recs = NULL;
    size_t n = 0;
    double *err = NULL;
    unsigned char *inside = NULL;
    interval *det = NULL;
    FILE *tl = NULL;
    fv_gaze_pipeline *pp = NULL, *pb = NULL;
    fv_result r = collect(dev, clock, seconds, &recs, &n, &out->whole);
    if (r != FV_OK) return r;
    if (n < 2) {
        FV_ERROR("gaze", "%s: only %zu samples: nothing to evaluate", dev->info.uri, n);
        r = FV_ERR_NOT_FOUND;
        goto fail;
    }
    int64_t med = median_interval_ns(recs, n);
    int64_t half = (int64_t)fmax(FV_SIM_EVAL_SMOOTH_HALF_MS * 1e6, FV_SIM_EVAL_SMOOTH_HALF_SAMPLES * (double)med);
    out->smooth_half_ms = (double)half * 1e-6;
    smooth_recording(recs, n, half);
    /* blinks as `fovea trace info` counts them: runs of samples the source flags as a blink */
    bool in_rec_blink = false;
    for (size_t i = 0; i < n; i++) {
        const fv_gaze_sample *g = &recs[i].s;
        bool b = ((g->eye[0].flags | g->eye[1].flags | g->combined.flags) & FV_EYE_BLINK) != 0;
        if (b && !in_rec_blink) out->recorded_blinks++;
        in_rec_blink = b;
    }
    fv_gaze_pipeline_desc base = desc->pipeline;
    base.disable_prediction = true;
    fv_gaze_pipeline_desc pred = desc->pipeline;
    pred.disable_prediction = false;
    r = fv_gaze_pipeline_create(&pred, &pp);
    if (r != FV_OK) goto fail;
    r = fv_gaze_pipeline_create(&base, &pb);
    if (r != FV_OK) goto fail;
    size_t slots = (size_t)FV_SIM_EVAL_TRUTHS * FV_SIM_EVAL_METHODS * FV_SIM_EVAL_HORIZONS;
    err = malloc(sizeof *err * n * slots);
    inside = malloc(n * slots);
    size_t det_cap = n / 2 + 2;
    det = malloc(sizeof *det * det_cap);
    if (!err || !det || !inside) {
        r = FV_ERR_NO_MEMORY;
        goto fail;
    }
    if (desc->timeline_csv) {
        tl = fopen(desc->timeline_csv, "w");
        if (!tl) {
            FV_ERROR("gaze", "%s: cannot write the timeline: %s", desc->timeline_csv, strerror(errno));
            r = FV_ERR_IO;
            goto fail;
        }
        fprintf(tl, "t_s,raw_yaw,raw_pitch,pred_yaw,pred_pitch,truth_yaw,truth_pitch,event,saccade,uncertainty_deg\n");
    }
    int tl_h = desc->timeline_horizon_ms > 0 ? desc->timeline_horizon_ms : 20;
    uint64_t cnt[FV_SIM_EVAL_TRUTHS][FV_SIM_EVAL_METHODS][FV_SIM_EVAL_HORIZONS];
    memset(cnt, 0, sizeof cnt);
#define SLOT(t, m, h) (((size_t)(t) * FV_SIM_EVAL_METHODS + (size_t)(m)) * FV_SIM_EVAL_HORIZONS + (size_t)(h))
#define ERR(t, m, h) (err + SLOT(t, m, h) * n)
#define INS(t, m, h) (inside + SLOT(t, m, h) * n)
    size_t nd = 0;
    bool in_sacc = false;
    fv_gaze_event prev_ev = FV_GAZE_EVENT_NONE;
    bool have_latest = false;
    fv_vec3 latest = fv_v3(0, 0, -1);
    double unc_sum = 0.0;
    uint64_t unc_n = 0;
    for (size_t i = 0; i < n; i++) {
        const rec *rc = &recs[i];
        fv_result a = fv_gaze_pipeline_push(pp, &rc->s);
        fv_result b = fv_gaze_pipeline_push(pb, &rc->s);
        if (a == FV_NO_NEW_DATA || b == FV_NO_NEW_DATA) {
            out->rejected++;
            continue;
        }
        if (FV_FAILED(a) || FV_FAILED(b)) {
            r = FV_FAILED(a) ? a : b;
            goto fail;
        }
        out->samples++;
        if (rc->raw_valid) {
            latest = rc->raw_dir;
            have_latest = true;
        }
        /* events: onsets, and saccade intervals on the capture timeline (a blink inside a saccade continues it) */
        fv_gaze_event ev = fv_gaze_pipeline_event(pp);
        int64_t t_cap = rc->has_truth ? rc->truth.t_ns : rc->t_ns;
        if (ev != prev_ev) {
            if (ev == FV_GAZE_EVENT_PURSUIT) out->det_pursuits++;
            if (ev == FV_GAZE_EVENT_BLINK) out->det_blinks++;
        }
        if (ev == FV_GAZE_EVENT_SACCADE) {
            if (!in_sacc && nd < det_cap) det[nd++] = (interval){t_cap, t_cap, false, false};
            else if (nd > 0) det[nd - 1].t1 = t_cap;
            in_sacc = true;
        } else if (ev != FV_GAZE_EVENT_BLINK || !in_sacc) {
            in_sacc = false;
        }
        prev_ev = ev;
        /* errors at photon time = receipt + horizon, against each truth */
        for (int h = 0; h < FV_SIM_EVAL_HORIZONS; h++) {
            int64_t target = rc->t_ns + (int64_t)g_horizons_ms[h] * FV_NS_PER_MS;
            fv_vec3 ref[FV_SIM_EVAL_TRUTHS];
            bool ok[FV_SIM_EVAL_TRUTHS];
            ok[FV_SIM_EVAL_TRUTH_RAW] = reference_from_samples(recs, n, i, target, false, &ref[FV_SIM_EVAL_TRUTH_RAW]);
            ok[FV_SIM_EVAL_TRUTH_SMOOTHED] =
                reference_from_samples(recs, n, i, target, true, &ref[FV_SIM_EVAL_TRUTH_SMOOTHED]);
            ok[FV_SIM_EVAL_TRUTH_TRUE] = false;
            /* Blinks are treated as on a recording: a target at which the eye is closed has no truth (a
             * recording has no valid sample there; the simulated eye's direction behind closed lids is no gaze
             * anyone sees), so it is not scored. A capture inside a blink is scored when its target is not. */
            if (eye) {
                fv_sim_truth tr;
                ok[FV_SIM_EVAL_TRUTH_TRUE] = fv_sim_eye_truth_at(eye, target - origin, &tr) && !tr.blink;
                ref[FV_SIM_EVAL_TRUTH_TRUE] = tr.dir_cyc;
            }
            if (!have_latest) continue;
            fv_gaze_prediction pa, pbp;
            fv_gaze_pipeline_predict(pp, target, &pa);
            fv_gaze_pipeline_predict(pb, target, &pbp);
            if (!pa.combined_valid || !pbp.combined_valid) continue;
            if (g_horizons_ms[h] == 20) {
                unc_sum += pa.uncertainty_deg;
                unc_n++;
            }
            for (int t = 0; t < FV_SIM_EVAL_TRUTHS; t++) {
                if (!ok[t]) continue;
                fv_vec3 dirs[FV_SIM_EVAL_METHODS] = {pa.combined_dir_head, pbp.combined_dir_head, latest};
                float radius[FV_SIM_EVAL_METHODS] = {pa.uncertainty_deg, pbp.uncertainty_deg, 0.0f};
                for (int m = 0; m < FV_SIM_EVAL_METHODS; m++) {
                    double e = angle_deg(dirs[m], ref[t]);
                    uint64_t k = cnt[t][m][h]++;
                    ERR(t, m, h)[k] = e;
                    INS(t, m, h)[k] = e <= (double)radius[m];
                }
            }
        }
        if (tl) {
            int64_t target = fv_i64_add_sat(rc->t_ns, (int64_t)tl_h * FV_NS_PER_MS);
            fv_gaze_prediction pa;
            fv_gaze_pipeline_predict(pp, target, &pa);
            fv_vec3 ref = fv_v3(0, 0, -1);
            bool ok;
            if (eye) {
                fv_sim_truth tr;
                ok = fv_sim_eye_truth_at(eye, target - origin, &tr) && !tr.blink; /* no truth in a blink */
                ref = tr.dir_cyc;
            } else {
                ok = reference_from_samples(recs, n, i, target, true, &ref);
            }
            fprintf(tl, "%.6f", (double)fv_i64_sub_sat(rc->t_ns, recs[0].t_ns) * 1e-9);
            csv_angles(tl, rc->raw_valid, rc->raw_dir);
            csv_angles(tl, pa.combined_valid, pa.combined_dir_head);
            csv_angles(tl, ok, ref);
            fprintf(tl, ",%s,%d,%.4f\n", fv_gaze_event_str(ev), ev == FV_GAZE_EVENT_SACCADE, (double)pa.uncertainty_deg);
        }
    }
    for (int t = 0; t < FV_SIM_EVAL_TRUTHS; t++)
        for (int m = 0; m < FV_SIM_EVAL_METHODS; m++)
            for (int h = 0; h < FV_SIM_EVAL_HORIZONS; h++)
                out->err[t][m][h] = summarize_with(ERR(t, m, h), INS(t, m, h), cnt[t][m][h], m != FV_SIM_EVAL_LATEST_SAMPLE);
#undef ERR
#undef INS
#undef SLOT
    fv_sim_eval_truth primary = eye ? FV_SIM_EVAL_TRUTH_TRUE : FV_SIM_EVAL_TRUTH_RAW;
    for (int h = 0; h < FV_SIM_EVAL_HORIZONS; h++) {
        out->predicted[h] = out->err[primary][FV_SIM_EVAL_PREDICTED][h];
        out->filtered[h] = out->err[primary][FV_SIM_EVAL_LATEST_FILTERED][h];
        out->latest[h] = out->err[primary][FV_SIM_EVAL_LATEST_SAMPLE][h];
    }
    out->mean_uncertainty_deg = unc_n ? unc_sum / (double)unc_n : 0.0;
    fv_gaze_pipeline_stats st;
    fv_gaze_pipeline_get_stats(pp, &st);
    out->invalid = st.invalid;
    out->one_eye = st.one_eye;
    out->skew_ppm = st.clock_skew_ppm;
    out->noise_deg = st.noise_deg;
    out->filter_min_cutoff_hz = st.filter_min_cutoff_hz;
    out->filter_beta = st.filter_beta;
    out->pipeline = st; /* the predicting pipeline's counters (its device-level fallback among them) */
    out->seconds = ((double)recs[n - 1].s.t_device_ns - (double)recs[0].s.t_device_ns) * 1e-9;
    out->rate_hz = out->seconds > 0.0 ? (double)(n - 1) / out->seconds : 0.0;
    if (eye) {
        int64_t span0 = recs[0].has_truth ? recs[0].truth.t_ns : 0;
        int64_t span1 = recs[n - 1].has_truth ? recs[n - 1].truth.t_ns : 0;
        match_saccades(eye, span0, span1, det, nd, out);
        out->det_saccades = out->tp + out->fp; /* the scored detections; det_in_blink more */
    } else {
        out->det_saccades = nd;
    }
    if (desc->bench_repeats > 0) bench(recs, n, desc, out);
    r = FV_OK;
fail:
    if (tl && fclose(tl) != 0 && r == FV_OK) {
        FV_ERROR("gaze", "%s: cannot write the timeline", desc->timeline_csv);
        r = FV_ERR_IO;
    }
    fv_gaze_pipeline_destroy(&pp);
    fv_gaze_pipeline_destroy(&pb);
    free(err);
    free(inside);
    free(det);
    free(recs);
    return r;
}
