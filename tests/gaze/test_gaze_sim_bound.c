/* @brief Where the simulated eye's p95 error at 20 ms comes from, and what bounds it: the gaze pipeline run on
 * fv_sim_eye directly (as `fovea gaze eval --gaze sim:seed=N` runs it: target = receipt + 20 ms, truth = the true
 * cyclopean gaze there, latest sample = the newest valid raw sample; a target at which the eye is closed has no
 * truth and is not scored, as on a recording), each sample labelled from the truth (a blink at its capture; a
 * saccade that starts between capture and target; a saccade in flight at capture, by its age), and ORACLES that
 * replace the prediction on one group with what no causal predictor can beat:
 *   - in flight from onset + k ms: the true gaze at the target (a perfect landing-and-timing predictor that needs
 *     k ms of the saccade), for k = 0, 8, 17, 25 ms;
 *   - the true landing point (the saccade's end position) from onset + k ms;
 *   - captures in a blink (the target is after it): the true gaze (what a predictor that saw through closed
 *     lids would give).
 * The figures are printed (docs/gaze.md quotes them). What they showed: the saccades not yet begun and the blinks
 * do NOT bound the gain below 30%; a predictor that knew the gaze in flight from one sample period after onset
 * would gain 65-69%, from two periods 33-41%. The loss is in the first one or two samples of each saccade, where every
 * candidate (the landing fit included) is still far off: one displacement at an unknown phase of the saccade leaves
 * its amplitude uncertain by a factor of several.
 * The asserts pin what the figures rest on: the oracles are never worse than the pipeline; the pipeline beats the
 * latest sample on every seed (by 22% on average over seeds 1-5: 23.4% measured, what `fovea gaze eval` reports);
 * the candidate predict() reports as chosen is the one it predicts; and the in-flight oracle from onset + 8 ms
 * reaches 30% on average (the target is not bounded by what the tracker cannot see). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_clock.h"
#include "fv_gaze_pipeline.h"
#include "fv_math.h"
#include "fv_sim_eye.h"
#include "fv_stats.h"
#include "fv_test.h"

#define SECONDS 60.0
#define H_NS (20 * FV_NS_PER_MS)

enum { G_FIX = 0, G_ONSET_AHEAD, G_INFLIGHT_EARLY, G_INFLIGHT, G_BLINK, GROUPS };
static const char *g_group_names[GROUPS] = {"fixation/pursuit", "saccade starts after capture",
                                            "in flight < 1 sample", "in flight >= 1 sample", "blink at capture"};
enum { O_NONE = 0, O_FLIGHT_0, O_FLIGHT_8, O_FLIGHT_17, O_FLIGHT_25, O_LAND_8, O_LAND_17, O_BLINK, O_FLIGHT_8_BLINK,
       O_ALL_VISIBLE, ORACLES };
static const char *g_oracle_names[ORACLES] = {
    "pipeline", "true gaze in flight from onset", "true gaze in flight from onset+8 ms",
    "true gaze in flight from onset+17 ms", "true gaze in flight from onset+25 ms", "true landing from onset+8 ms",
    "true landing from onset+17 ms", "true gaze in blinks", "in flight from onset+8 ms and blinks",
    "all but saccades not yet begun"};

typedef struct sacc {
    int64_t t0, t1;
    fv_vec3 end;
} sacc;

static double angle_deg(fv_vec3 a, fv_vec3 b)
{
    double ax = a.x, ay = a.y, az = a.z, bx = b.x, by = b.y, bz = b.z;
    double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
    return fv_rad_to_deg(atan2(sqrt(cx * cx + cy * cy + cz * cz), ax * bx + ay * by + az * bz));
}

static bool raw_dir(const fv_gaze_sample *s, fv_vec3 *out)
{
    if ((s->combined.flags & FV_EYE_DIRECTION_VALID) && !(s->combined.flags & FV_EYE_BLINK)) {
        *out = fv_v3_normalize_or(s->combined.direction, fv_v3(0, 0, -1));
        return true;
    }
    fv_vec3 sum = fv_v3(0, 0, 0);
    int n = 0;
    for (int e = 0; e < 2; e++)
        if ((s->eye[e].flags & FV_EYE_DIRECTION_VALID) && !(s->eye[e].flags & FV_EYE_BLINK)) {
            sum = fv_v3_add(sum, fv_v3_normalize_or(s->eye[e].direction, fv_v3(0, 0, -1)));
            n++;
        }
    if (n == 0) return false;
    *out = fv_v3_normalize_or(sum, fv_v3(0, 0, -1));
    return true;
}

#define AGES 5 /* in-flight samples by how many sample periods of the saccade were seen: 1, 2, 3, 4, 5+ */
typedef struct bound {
    double p95_latest, p95[ORACLES];
    uint64_t n, tail_latest[GROUPS], tail_pred[GROUPS], group_n[GROUPS];
    /* in flight >= 1 sample, per age and whether the pipeline labels it a saccade yet: samples, and above the
     * threshold: the latest sample, the pipeline, each candidate; and which candidate it chose */
    uint64_t age_n[2][AGES], age_tail_latest[2][AGES], age_tail_pred[2][AGES],
        age_tail_cand[2][AGES][FV_GAZE_CANDIDATES], age_chosen[2][AGES][FV_GAZE_CANDIDATES];
} bound;

static void run_bound(const fv_sim_eye_desc *d, bound *out)
{
    fv_sim_eye *eye = NULL, *truth_eye = NULL;
    assert_int_equal(fv_sim_eye_create(d, &eye), FV_OK);
    assert_int_equal(fv_sim_eye_create(d, &truth_eye), FV_OK); /* the same eye, queried ahead for events */
    int64_t end_ns = (int64_t)(SECONDS * 1e9);
    fv_sim_eye_generate_until(truth_eye, end_ns + FV_NS_PER_S);
    size_t ne = fv_sim_eye_event_count(truth_eye), ns = 0;
    sacc *sv = calloc(ne + 1, sizeof *sv);
    assert_non_null(sv);
    for (size_t i = 0; i < ne; i++) {
        fv_sim_event ev;
        if (!fv_sim_eye_event_get(truth_eye, i, &ev) || ev.label != FV_SIM_SACCADE) continue;
        fv_sim_truth te;
        assert_true(fv_sim_eye_truth_at(truth_eye, ev.t_end_ns, &te));
        sv[ns++] = (sacc){ev.t_start_ns, ev.t_end_ns, te.dir_cyc};
    }
    fv_gaze_pipeline *p = NULL;
    assert_int_equal(fv_gaze_pipeline_create(NULL, &p), FV_OK);
    size_t cap = (size_t)(SECONDS * d->rate_hz * 1.1) + 16, n = 0;
    double *e_lat = malloc(cap * sizeof *e_lat), *e_or[ORACLES];
    int *grp = malloc(cap * sizeof *grp);
    assert_non_null(e_lat);
    assert_non_null(grp);
    for (int o = 0; o < ORACLES; o++) {
        e_or[o] = malloc(cap * sizeof **e_or);
        assert_non_null(e_or[o]);
    }
    bool have_latest = false;
    fv_vec3 latest = fv_v3(0, 0, -1);
    int *age_k = malloc(cap * sizeof *age_k);
    int *chosen = malloc(cap * sizeof *chosen);
    unsigned char *detected = malloc(cap);
    double (*e_cand)[FV_GAZE_CANDIDATES] = malloc(cap * sizeof *e_cand);
    assert_non_null(age_k);
    assert_non_null(chosen);
    assert_non_null(detected);
    assert_non_null(e_cand);
    size_t si = 0;
    for (;;) {
        fv_gaze_sample s;
        fv_sim_truth tc;
        assert_int_equal(fv_sim_eye_next(eye, &s, &tc), FV_OK);
        if (tc.t_ns >= end_ns || n == cap) break;
        fv_result r = fv_gaze_pipeline_push(p, &s);
        if (r == FV_NO_NEW_DATA) continue;
        assert_int_equal(r, FV_OK);
        fv_vec3 rd;
        if (raw_dir(&s, &rd)) latest = rd, have_latest = true;
        if (!have_latest) continue;
        int64_t target = s.t_host_ns + H_NS;
        fv_gaze_prediction pr;
        fv_gaze_pipeline_predict(p, target, &pr);
        fv_sim_truth tt;
        /* a target in a blink has no truth and is not scored (as the eval does, as on a recording) */
        if (!pr.combined_valid || !fv_sim_eye_truth_at(truth_eye, target, &tt) || tt.blink) continue;
        /* the group, from the truth */
        while (si < ns && sv[si].t1 < tc.t_ns) si++;
        int g = G_FIX;
        const sacc *in = NULL;
        for (size_t k = si; k < ns && sv[k].t0 <= target; k++) {
            if (sv[k].t0 <= tc.t_ns && sv[k].t1 >= tc.t_ns) in = &sv[k];
            else if (sv[k].t0 > tc.t_ns && g == G_FIX) g = G_ONSET_AHEAD;
        }
        double age_ms = in ? (double)(tc.t_ns - in->t0) * 1e-6 : -1.0;
        if (in) g = age_ms < 1000.0 / d->rate_hz ? G_INFLIGHT_EARLY : G_INFLIGHT;
        if (tc.blink) g = G_BLINK;
        grp[n] = g;
        age_k[n] = in ? (int)fmin(AGES - 1, floor(age_ms * 1e-3 * d->rate_hz) - 1.0) : -1;
        detected[n] = fv_gaze_pipeline_event(p) == FV_GAZE_EVENT_SACCADE;
        double cand[FV_GAZE_CANDIDATES][2];
        chosen[n] = fv_gaze_pipeline_candidates(p, target, cand);
        if (chosen[n] >= 0) /* the diagnostics report what predict() did */
            assert_true(angle_deg(fv_gaze_angles_to_dir(cand[chosen[n]]), pr.combined_dir_head) < 1e-3);
        for (int c = 0; c < FV_GAZE_CANDIDATES; c++)
            e_cand[n][c] = chosen[n] >= 0 ? angle_deg(fv_gaze_angles_to_dir(cand[c]), tt.dir_cyc) : NAN;
        e_lat[n] = angle_deg(latest, tt.dir_cyc);
        double ep = angle_deg(pr.combined_dir_head, tt.dir_cyc);
        static const double flight_k[ORACLES] = {-1, 0, 8, 17, 25, -1, -1, -1, 8, 0};
        for (int o = 0; o < ORACLES; o++) {
            double e = ep;
            bool blink_perfect = o == O_BLINK || o == O_FLIGHT_8_BLINK || o == O_ALL_VISIBLE;
            if (g == G_BLINK && blink_perfect) e = 0.0;
            if (g != G_BLINK && in && flight_k[o] >= 0.0 && age_ms >= flight_k[o]) e = 0.0;
            if (g != G_BLINK && in && ((o == O_LAND_8 && age_ms >= 8.0) || (o == O_LAND_17 && age_ms >= 17.0)))
                e = fmin(ep, angle_deg(in->end, tt.dir_cyc));
            e_or[o][n] = e;
        }
        n++;
    }
    memset(out, 0, sizeof *out);
    out->n = n;
    double *tmp = malloc(n * sizeof *tmp);
    assert_non_null(tmp);
    memcpy(tmp, e_lat, n * sizeof *tmp);
    out->p95_latest = fv_percentile_f64(tmp, n, 95.0);
    double thr = 0.7 * out->p95_latest; /* what a 30% gain needs every sample but 5% to be within */
    for (int o = 0; o < ORACLES; o++) {
        memcpy(tmp, e_or[o], n * sizeof *tmp);
        out->p95[o] = fv_percentile_f64(tmp, n, 95.0);
    }
    for (size_t i = 0; i < n; i++) {
        out->group_n[grp[i]]++;
        if (e_lat[i] > thr) out->tail_latest[grp[i]]++;
        if (e_or[O_NONE][i] > thr) out->tail_pred[grp[i]]++;
        if (grp[i] != G_INFLIGHT || age_k[i] < 0) continue;
        int a = age_k[i], dt = detected[i] ? 1 : 0;
        out->age_n[dt][a]++;
        out->age_tail_latest[dt][a] += e_lat[i] > thr;
        out->age_tail_pred[dt][a] += e_or[O_NONE][i] > thr;
        for (int c = 0; c < FV_GAZE_CANDIDATES; c++) out->age_tail_cand[dt][a][c] += e_cand[i][c] > thr;
        if (chosen[i] >= 0) out->age_chosen[dt][a][chosen[i]]++;
    }
    free(age_k);
    free(chosen);
    free(detected);
    free(e_cand);
    free(tmp);
    for (int o = 0; o < ORACLES; o++) free(e_or[o]);
    free(e_lat);
    free(grp);
    free(sv);
    fv_gaze_pipeline_destroy(&p);
    fv_sim_eye_destroy(&eye);
    fv_sim_eye_destroy(&truth_eye);
}

static void print_bound(const char *name, const bound *b)
{
    print_message("%s: %llu samples, latest sample p95 %.3f deg; a 30%% gain needs p95 <= %.3f\n", name,
                  (unsigned long long)b->n, b->p95_latest, 0.7 * b->p95_latest);
    for (int o = 0; o < ORACLES; o++)
        print_message("  %-40s p95 %.3f  gain %5.1f%%\n", g_oracle_names[o], b->p95[o],
                      100.0 * (1.0 - b->p95[o] / b->p95_latest));
    print_message("  samples above %.3f deg (latest sample / pipeline), per group:\n", 0.7 * b->p95_latest);
    for (int g = 0; g < GROUPS; g++)
        print_message("    %-32s %5llu samples: %4llu / %4llu\n", g_group_names[g], (unsigned long long)b->group_n[g],
                      (unsigned long long)b->tail_latest[g], (unsigned long long)b->tail_pred[g]);
    print_message("  in flight, by sample periods seen and saccade detected (D) or not (-): n, above the threshold "
                  "(latest, pipeline; candidates sample/filtered/model/fit/vel20/blend), chosen\n");
    for (int dt = 1; dt >= 0; dt--)
        for (int a = 0; a < AGES; a++) {
            if (!b->age_n[dt][a]) continue;
            print_message("    %d%s %c: %4llu  %4llu %4llu ;", a + 1, a == AGES - 1 ? "+" : " ", dt ? 'D' : '-',
                          (unsigned long long)b->age_n[dt][a], (unsigned long long)b->age_tail_latest[dt][a],
                          (unsigned long long)b->age_tail_pred[dt][a]);
            for (int c = 0; c < FV_GAZE_CANDIDATES; c++)
                print_message(" %4llu", (unsigned long long)b->age_tail_cand[dt][a][c]);
            print_message(" ;");
            for (int c = 0; c < FV_GAZE_CANDIDATES; c++)
                print_message(" %4llu", (unsigned long long)b->age_chosen[dt][a][c]);
            print_message("\n");
        }
}

static void gaze_sim_bound_of_the_p95_gain(void **state)
{
    (void)state;
    const char *only = getenv("FV_GAZE_BOUND_SEEDS"); /* e.g. "1" to look at one seed */
    int seeds = only && atoi(only) > 0 ? atoi(only) : 5;
    double gain_pipeline = 0.0, gain_flight8 = 0.0;
    for (int sd = 1; sd <= seeds; sd++) {
        fv_sim_eye_desc d;
        fv_sim_eye_desc_defaults(&d);
        d.seed = (uint64_t)sd;
        bound b;
        run_bound(&d, &b);
        char name[32];
        snprintf(name, sizeof name, "seed %d", sd);
        print_bound(name, &b);
        for (int o = 0; o < ORACLES; o++) assert_true(isfinite(b.p95[o]) && b.p95[o] <= b.p95[O_NONE] + 1e-12);
        assert_true(b.p95[O_NONE] < b.p95_latest);
        gain_pipeline += 1.0 - b.p95[O_NONE] / b.p95_latest;
        gain_flight8 += 1.0 - b.p95[O_FLIGHT_8] / b.p95_latest;
    }
    print_message("mean gain over %d seeds: pipeline %.1f%%, perfect in flight from onset+8 ms %.1f%%\n", seeds,
                  100.0 * gain_pipeline / seeds, 100.0 * gain_flight8 / seeds);
    assert_true(gain_flight8 / seeds >= 0.3);
    if (seeds == 5) assert_true(gain_pipeline / seeds >= 0.22); /* 23.4% */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gaze_sim_bound_of_the_p95_gain),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
