/* @brief Gaze pipeline evaluation against the simulated eye's truth or a recording's own later samples
 * (see fv_sim_eval.h). */
#include "fv_sim_eval.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_sim_driver.h"
#include "fv_stats.h"

static const int g_horizons_ms[FV_SIM_EVAL_HORIZONS] = {0, 10, 20, 40};

typedef struct rec {
    fv_gaze_sample s;
    fv_sim_truth truth;
    bool has_truth;
    bool raw_valid;     /* a usable combined direction in the raw sample */
    fv_vec3 raw_dir;
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

static bool raw_combined(const fv_gaze_sample *s, fv_vec3 *out)
{
    const fv_eye_sample *c = &s->combined;
    if ((c->flags & FV_EYE_DIRECTION_VALID) && !(c->flags & FV_EYE_BLINK) && fv_v3_isfinite(c->direction) &&
        fv_v3_len(c->direction) > 1e-6f) {
        *out = fv_v3_normalize_or(c->direction, fv_v3(0, 0, -1));
        return true;
    }
    int n = 0;
    fv_vec3 sum = fv_v3(0, 0, 0);
    for (int e = 0; e < 2; e++) {
        const fv_eye_sample *es = &s->eye[e];
        if ((es->flags & FV_EYE_DIRECTION_VALID) && !(es->flags & FV_EYE_BLINK) && fv_v3_isfinite(es->direction) &&
            fv_v3_len(es->direction) > 1e-6f) {
            sum = fv_v3_add(sum, fv_v3_normalize_or(es->direction, fv_v3(0, 0, -1)));
            n++;
        }
    }
    if (n == 0) return false;
    *out = fv_v3_normalize_or(sum, fv_v3(0, 0, -1));
    return fv_v3_len(sum) > 1e-6f;
}

static fv_sim_eval_error summarize(double *v, uint64_t n)
{
    fv_sim_eval_error e = {0.0, 0.0, n};
    if (n == 0) return e;
    double sum = 0.0;
    for (uint64_t i = 0; i < n; i++) sum += v[i];
    e.mean_deg = sum / (double)n;
    e.p95_deg = fv_percentile_f64(v, (size_t)n, 95.0); /* nearest rank */
    return e;
}

/* ---- reading ---- */

static fv_result collect(fv_device *dev, fv_clock *clock, double seconds, rec **out_recs, size_t *out_n)
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

/* the raw gaze interpolated at time t from the recording itself (valid neighbours within 50 ms) */
static bool reference_from_samples(const rec *recs, size_t n, size_t from, int64_t t, fv_vec3 *out)
{
    size_t j = from;
    while (j + 1 < n && recs[j + 1].t_ns <= t) j++;
    if (j + 1 >= n || recs[j].t_ns > t) return false;
    const rec *a = &recs[j], *b = &recs[j + 1];
    if (!a->raw_valid || !b->raw_valid || b->t_ns - a->t_ns > 50 * FV_NS_PER_MS || b->t_ns <= a->t_ns) return false;
    float w = (float)((double)(t - a->t_ns) / (double)(b->t_ns - a->t_ns));
    *out = fv_v3_normalize_or(fv_v3_add(fv_v3_scale(a->raw_dir, 1.0f - w), fv_v3_scale(b->raw_dir, w)), a->raw_dir);
    return true;
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

fv_result fv_sim_eval_run(fv_device *dev, fv_clock *clock, const fv_sim_eval_desc *desc, fv_sim_eval_result *out)
{
    if (!dev || !clock || !desc || !out) return FV_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    for (int h = 0; h < FV_SIM_EVAL_HORIZONS; h++) out->horizon_ms[h] = g_horizons_ms[h];
    double seconds = desc->seconds > 0.0 ? desc->seconds : 60.0;
    fv_sim_eye *eye = fv_sim_device_eye(dev);
    int64_t origin = fv_sim_device_host_origin_ns(dev);
    out->has_truth = eye != NULL;

    rec *recs = NULL;
    size_t n = 0;
    double *err = NULL;
    interval *det = NULL;
    fv_gaze_pipeline *pp = NULL, *pb = NULL;
    fv_result r = collect(dev, clock, seconds, &recs, &n);
    if (r != FV_OK) return r;
    if (n < 2) {
        FV_ERROR("gaze", "%s: only %zu samples: nothing to evaluate", dev->info.uri, n);
        r = FV_ERR_NOT_FOUND;
        goto fail;
    }
    fv_gaze_pipeline_desc base = desc->pipeline;
    base.disable_prediction = true;
    fv_gaze_pipeline_desc pred = desc->pipeline;
    pred.disable_prediction = false;
    r = fv_gaze_pipeline_create(&pred, &pp);
    if (r != FV_OK) goto fail;
    r = fv_gaze_pipeline_create(&base, &pb);
    if (r != FV_OK) goto fail;
    err = malloc(sizeof *err * n * 3 * FV_SIM_EVAL_HORIZONS);
    size_t det_cap = n / 2 + 2;
    det = malloc(sizeof *det * det_cap);
    if (!err || !det) {
        r = FV_ERR_NO_MEMORY;
        goto fail;
    }
    uint64_t cnt[3][FV_SIM_EVAL_HORIZONS] = {{0}};
#define ERR(m, h) (err + ((size_t)(m) * FV_SIM_EVAL_HORIZONS + (size_t)(h)) * n)
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
        /* events: onsets, and saccade intervals on the capture timeline */
        fv_gaze_event ev = fv_gaze_pipeline_event(pp);
        int64_t t_cap = rc->has_truth ? rc->truth.t_ns : rc->t_ns;
        if (ev != prev_ev) {
            if (ev == FV_GAZE_EVENT_SACCADE) out->det_saccades++;
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
        /* errors at photon time = receipt + horizon */
        for (int h = 0; h < FV_SIM_EVAL_HORIZONS; h++) {
            int64_t target = rc->t_ns + (int64_t)g_horizons_ms[h] * FV_NS_PER_MS;
            fv_vec3 ref;
            bool ok;
            if (eye) {
                fv_sim_truth tr;
                ok = fv_sim_eye_truth_at(eye, target - origin, &tr);
                ref = tr.dir_cyc;
            } else {
                ok = reference_from_samples(recs, n, i, target, &ref);
            }
            if (!ok || !have_latest) continue;
            fv_gaze_prediction pa, pbp;
            fv_gaze_pipeline_predict(pp, target, &pa);
            fv_gaze_pipeline_predict(pb, target, &pbp);
            if (!pa.combined_valid || !pbp.combined_valid) continue;
            if (g_horizons_ms[h] == 20) {
                unc_sum += pa.uncertainty_deg;
                unc_n++;
            }
            ERR(0, h)[cnt[0][h]++] = angle_deg(pa.combined_dir_head, ref);
            ERR(1, h)[cnt[1][h]++] = angle_deg(pbp.combined_dir_head, ref);
            ERR(2, h)[cnt[2][h]++] = angle_deg(latest, ref);
        }
    }
    for (int h = 0; h < FV_SIM_EVAL_HORIZONS; h++) {
        out->predicted[h] = summarize(ERR(0, h), cnt[0][h]);
        out->filtered[h] = summarize(ERR(1, h), cnt[1][h]);
        out->latest[h] = summarize(ERR(2, h), cnt[2][h]);
    }
#undef ERR
    out->mean_uncertainty_deg = unc_n ? unc_sum / (double)unc_n : 0.0;
    fv_gaze_pipeline_stats st;
    fv_gaze_pipeline_get_stats(pp, &st);
    out->invalid = st.invalid;
    out->one_eye = st.one_eye;
    out->skew_ppm = st.clock_skew_ppm;
    out->seconds = ((double)recs[n - 1].s.t_device_ns - (double)recs[0].s.t_device_ns) * 1e-9;
    out->rate_hz = out->seconds > 0.0 ? (double)(n - 1) / out->seconds : 0.0;
    if (eye) {
        int64_t span0 = recs[0].has_truth ? recs[0].truth.t_ns : 0;
        int64_t span1 = recs[n - 1].has_truth ? recs[n - 1].truth.t_ns : 0;
        match_saccades(eye, span0, span1, det, nd, out);
    }
    if (desc->bench_repeats > 0) bench(recs, n, desc, out);
    r = FV_OK;
fail:
    fv_gaze_pipeline_destroy(&pp);
    fv_gaze_pipeline_destroy(&pb);
    free(err);
    free(det);
    free(recs);
    return r;
}
