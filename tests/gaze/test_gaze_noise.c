/* @brief Online noise and rate estimation (fv_gaze_noise.h): converges on synthetic white noise of known SD at
 * several rates, ignores microsaccade steps, follows a noise that rises, and derives finite 1€ parameters at the
 * extremes; the pipeline set from it filters a very noisy tracker instead of reading its noise as saccades. */
#include <math.h>
#include <stdint.h>

#include "fv_clock.h"
#include "fv_gaze_noise.h"
#include "fv_gaze_pipeline.h"
#include "fv_test.h"

static uint64_t g_rng = 12345;
static double normal(void) { return fv_test_normal(&g_rng); }

/* seconds of a fixation at (3, -2) deg with white noise sigma per axis at rate_hz */
static void feed(fv_gaze_noise *n, double sigma, double rate_hz, double seconds, int64_t *t_ns)
{
    int64_t dt = (int64_t)llround(1e9 / rate_hz);
    for (int i = 0; i < (int)(seconds * rate_hz); i++) {
        double p[2] = {3.0 + sigma * normal(), -2.0 + sigma * normal()};
        fv_gaze_noise_push(n, *t_ns, p, true);
        *t_ns += dt;
    }
}

static void gaze_noise_converges_on_known_sigma_at_several_rates(void **state)
{
    (void)state;
    const double rates[] = {30.0, 90.0, 120.0, 250.0, 1000.0};
    const double sigmas[] = {0.02, 0.15, 1.0, 5.0};
    for (size_t r = 0; r < sizeof rates / sizeof rates[0]; r++) {
        for (size_t k = 0; k < sizeof sigmas / sizeof sigmas[0]; k++) {
            fv_gaze_noise n;
            fv_gaze_noise_init(&n);
            assert_true(isnan(fv_gaze_noise_sigma_deg(&n)));
            int64_t t = 1000;
            feed(&n, sigmas[k], rates[r], 10.0, &t);
            double est = fv_gaze_noise_sigma_deg(&n), rate = fv_gaze_noise_rate_hz(&n);
            if (!(fabs(est / sigmas[k] - 1.0) < 0.15))
                fail_msg("rate %g Hz, sigma %g: estimated %g", rates[r], sigmas[k], est);
            if (!(fabs(rate / rates[r] - 1.0) < 0.01)) fail_msg("rate %g Hz: estimated %g", rates[r], rate);
        }
    }
}

static void gaze_noise_ignores_microsaccades_and_non_fixations(void **state)
{
    (void)state;
    fv_gaze_noise n;
    fv_gaze_noise_init(&n);
    int64_t t = 0, dt = 8333333;
    double off = 0.0;
    for (int i = 0; i < 1200; i++) {
        if (i % 120 == 60) off += 0.6; /* a 0.6 deg microsaccade every second: 6 noise SDs in one step */
        double p[2] = {off + 0.1 * normal(), 0.1 * normal()};
        fv_gaze_noise_push(&n, t, p, true);
        t += dt;
    }
    assert_true(fabs(fv_gaze_noise_sigma_deg(&n) / 0.1 - 1.0) < 0.15);
    /* samples outside fixations (a pursuit at 20 deg/s) measure the rate but not the noise */
    double before = fv_gaze_noise_sigma_deg(&n);
    for (int i = 0; i < 600; i++) {
        double p[2] = {off + 20.0 * (double)i * 8.333e-3 + 0.1 * normal(), 0.0};
        fv_gaze_noise_push(&n, t, p, false);
        t += dt;
    }
    assert_true(fv_gaze_noise_sigma_deg(&n) == before);
    /* a gap breaks the chain: no difference across it */
    fv_gaze_noise_break(&n);
    fv_gaze_noise_push(&n, t, (double[2]){40.0, 40.0}, true);
    assert_true(fv_gaze_noise_sigma_deg(&n) == before);
}

static void gaze_noise_follows_a_rise(void **state)
{
    (void)state;
    fv_gaze_noise n;
    fv_gaze_noise_init(&n);
    int64_t t = 0;
    feed(&n, 0.1, 120.0, 5.0, &t);
    feed(&n, 0.5, 120.0, 8.0, &t); /* the tracker gets 5x noisier (a poorly fitted headset) */
    assert_true(fabs(fv_gaze_noise_sigma_deg(&n) / 0.5 - 1.0) < 0.2);
}

static void gaze_noise_filter_params_extremes_and_trends(void **state)
{
    (void)state;
    const double vals[] = {0.0, -1.0, 1e-12, 1e-3, 0.1, 1.0, 50.0, 1e12, NAN, INFINITY, -INFINITY};
    for (size_t i = 0; i < sizeof vals / sizeof vals[0]; i++) {
        for (size_t j = 0; j < sizeof vals / sizeof vals[0]; j++) {
            float fc = -1.0f, beta = -1.0f;
            fv_gaze_noise_filter_params(vals[i], vals[j] * 1000.0, &fc, &beta);
            assert_true(isfinite(fc) && fc >= 0.05f && fc <= 30.0f);
            assert_true(isfinite(beta) && beta >= 0.005f && beta <= 20.0f);
        }
    }
    /* noisier: smooth more (lower cutoff, lower beta); faster: each sample weighs less, the cutoff rises */
    float fc1, b1, fc2, b2, fc3, b3;
    fv_gaze_noise_filter_params(0.05, 120.0, &fc1, &b1);
    fv_gaze_noise_filter_params(0.5, 120.0, &fc2, &b2);
    fv_gaze_noise_filter_params(0.05, 1000.0, &fc3, &b3);
    assert_true(fc2 < fc1 && b2 < b1);
    assert_true(fc3 > fc1 && b3 == b1);
    /* non-finite input and a time that does not advance leave the estimate finite and unchanged */
    fv_gaze_noise n;
    fv_gaze_noise_init(&n);
    int64_t t = 0;
    feed(&n, 0.2, 200.0, 2.0, &t);
    double s = fv_gaze_noise_sigma_deg(&n);
    fv_gaze_noise_push(&n, t, (double[2]){NAN, 0.0}, true);
    fv_gaze_noise_push(&n, t - 5, (double[2]){1e300, 0.0}, true);
    fv_gaze_noise_push(&n, t + 5000000, (double[2]){INFINITY, -INFINITY}, true);
    assert_true(fv_gaze_noise_sigma_deg(&n) == s && isfinite(s));
    fv_gaze_noise_push(&n, INT64_MAX, (double[2]){1e300, -1e300}, true); /* a huge step after a huge gap */
    assert_true(isfinite(fv_gaze_noise_sigma_deg(&n)) && isfinite(fv_gaze_noise_rate_hz(&n)));
}

static fv_vec3 dir_of(double yaw, double pitch) { return fv_gaze_angles_to_dir((double[2]){yaw, pitch}); }

static double angle_between(fv_vec3 a, fv_vec3 b)
{
    double d = (double)a.x * b.x + (double)a.y * b.y + (double)a.z * b.z;
    return acos(fmax(-1.0, fmin(1.0, d))) * 180.0 / 3.14159265358979;
}

/* A tracker as noisy as the monocular SRanipal recording (about 5 deg per axis): without the noise estimate every
 * sample looks like a saccade and the prediction follows the noise; with it the pipeline filters and wins. */
static void gaze_pipeline_filters_a_very_noisy_tracker(void **state)
{
    (void)state;
    fv_gaze_pipeline *p = NULL;
    assert_int_equal(fv_gaze_pipeline_create(NULL, &p), FV_OK);
    double err_pred = 0.0, err_raw = 0.0;
    int n = 0, fix = 0;
    for (int i = 0; i < 120 * 20; i++) {
        fv_gaze_sample s = {0};
        s.t_device_ns = s.t_host_ns = (int64_t)i * 8333333 + 1000000;
        s.seq = (uint64_t)i;
        double yaw = 10.0 + 5.0 * normal(), pitch = 5.0 * normal();
        s.combined.flags = FV_EYE_DIRECTION_VALID;
        s.combined.direction = dir_of(yaw, pitch);
        s.confidence = NAN;
        assert_int_equal(fv_gaze_pipeline_push(p, &s), FV_OK);
        if (i < 120 * 10) continue; /* 10 s to learn the noise */
        fv_gaze_prediction pr;
        fv_gaze_pipeline_predict(p, s.t_host_ns + 20 * FV_NS_PER_MS, &pr);
        assert_true(isfinite(pr.uncertainty_deg));
        err_pred += angle_between(pr.combined_dir_head, dir_of(10.0, 0.0));
        err_raw += angle_between(s.combined.direction, dir_of(10.0, 0.0));
        fix += fv_gaze_pipeline_event(p) == FV_GAZE_EVENT_FIXATION;
        n++;
    }
    fv_gaze_pipeline_stats st;
    fv_gaze_pipeline_get_stats(p, &st);
    print_message("noise %.2f deg, f_cmin %.2f Hz, beta %.3f; mean error predicted %.2f raw %.2f; fixation %d/%d\n",
                  st.noise_deg, (double)st.filter_min_cutoff_hz, (double)st.filter_beta, err_pred / n, err_raw / n,
                  fix, n);
    assert_true(fabs(st.noise_deg / 5.0 - 1.0) < 0.25);
    assert_true(fix > n * 9 / 10);
    assert_true(err_pred < 0.4 * err_raw);
    fv_gaze_pipeline_destroy(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gaze_noise_converges_on_known_sigma_at_several_rates),
        cmocka_unit_test(gaze_noise_ignores_microsaccades_and_non_fixations),
        cmocka_unit_test(gaze_noise_follows_a_rise),
        cmocka_unit_test(gaze_noise_filter_params_extremes_and_trends),
        cmocka_unit_test(gaze_pipeline_filters_a_very_noisy_tracker),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
