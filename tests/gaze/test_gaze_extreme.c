/* @brief Numerical extremes through the gaze pipeline: NaN/Inf gaze, off-screen and zero directions, pupil 0 and
 * 12 mm, huge time jumps, zero dt, absurd confidences. Nothing may come out NaN or Inf. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "fv_gaze_pipeline.h"
#include "fv_gaze_saccade.h"
#include "fv_test.h"

static void assert_finite_prediction(const fv_gaze_prediction *pr)
{
    for (int e = 0; e < 2; e++) {
        assert_true(fv_v3_isfinite(pr->dir_head[e]));
        assert_true(fabsf(fv_v3_len(pr->dir_head[e]) - 1.0f) < 1e-3f);
    }
    assert_true(fv_v3_isfinite(pr->combined_dir_head));
    assert_true(fabsf(fv_v3_len(pr->combined_dir_head) - 1.0f) < 1e-3f);
    assert_true(isfinite(pr->uncertainty_deg) && pr->uncertainty_deg > 0.0f && pr->uncertainty_deg <= 90.0f);
    assert_true(isnan(pr->pupil_mm) || (isfinite(pr->pupil_mm) && pr->pupil_mm > 0.0f && pr->pupil_mm <= 10.0f));
}

static fv_gaze_sample valid_sample(int64_t t, fv_vec3 d0, fv_vec3 d1, float pupil)
{
    fv_gaze_sample s;
    fv_gaze_sample_init_invalid(&s, t, t);
    s.flags = FV_GAZE_HOST_TIME_VALID;
    s.eye[0].direction = d0;
    s.eye[1].direction = d1;
    s.eye[0].pupil_mm = s.eye[1].pupil_mm = pupil;
    s.eye[0].flags = s.eye[1].flags = FV_EYE_DIRECTION_VALID | FV_EYE_PUPIL_VALID;
    s.confidence = 1.0f;
    return s;
}

static void gaze_extremes_never_produce_nan_or_inf(void **state)
{
    (void)state;
    const float inf = INFINITY, nan = NAN;
    const fv_vec3 dirs[] = {
        {0, 0, -1}, {nan, 0, -1}, {inf, 0, -1}, {-inf, inf, nan}, {0, 0, 0}, {0, 0, 1} /* backwards */,
        {1, 0, 0} /* 90 deg off */, {1e-30f, 0, -1e-30f}, {3e38f, 3e38f, -3e38f}, {0, 1, 0}, {0.5f, 0.2f, -1},
        {-0.3f, -0.9f, -0.2f},
    };
    const float pupils[] = {0.0f, 12.0f, -1.0f, nan, inf, 4.0f, 1e30f};
    const float confs[] = {1.0f, nan, inf, -inf, 0.0f, 0.49f, 2.0f};
    const int64_t times[] = {0, 1, 1, 2, INT64_C(8333333), INT64_C(3600000000000), INT64_C(3600000000001),
                             INT64_MAX / 2, INT64_MAX - 10, INT64_MAX - 9, INT64_MIN + 5};
    for (int desc_i = 0; desc_i < 2; desc_i++) {
        fv_gaze_pipeline_desc d = {0};
        d.disable_prediction = desc_i == 1;
        fv_gaze_pipeline *p = NULL;
        assert_int_equal(fv_gaze_pipeline_create(&d, &p), FV_OK);
        int64_t t = 0;
        unsigned k = 0;
        for (int step = 0; step < 3000; step++) {
            k = k * 1103515245u + 12345u;
            size_t nd = sizeof dirs / sizeof dirs[0];
            fv_gaze_sample s = valid_sample(t, dirs[(k >> 4) % nd], dirs[(k >> 9) % nd],
                                            pupils[(k >> 14) % (sizeof pupils / sizeof pupils[0])]);
            s.confidence = confs[(k >> 18) % (sizeof confs / sizeof confs[0])];
            if ((k >> 22) % 7 == 0) {
                s.combined.direction = dirs[(k >> 25) % nd];
                s.combined.flags = FV_EYE_DIRECTION_VALID;
            }
            if ((k >> 27) % 11 == 0) s.flags = 0; /* no host time */
            if (step % 50 == 0) s.t_device_ns = s.t_host_ns = times[(size_t)(step / 50) % (sizeof times / sizeof times[0])];
            else if ((k >> 3) % 5 == 0) t += 0; /* zero dt: a duplicate */
            else t += (int64_t)((k >> 5) % 20000000);
            if (step % 50 != 0) s.t_device_ns = s.t_host_ns = t;
            fv_result r = fv_gaze_pipeline_push(p, &s);
            assert_true(r == FV_OK || r == FV_NO_NEW_DATA);
            fv_gaze_prediction pr;
            const int64_t soon = s.t_host_ns > INT64_MAX - 20000000 ? INT64_MAX : s.t_host_ns + 20000000;
            const int64_t targets[] = {s.t_host_ns, soon, INT64_MAX, INT64_MIN, 0};
            for (size_t j = 0; j < sizeof targets / sizeof targets[0]; j++) {
                fv_gaze_pipeline_predict(p, targets[j], &pr);
                assert_finite_prediction(&pr);
            }
        }
        fv_gaze_pipeline_set_device_lost(p, true, 0);
        fv_gaze_prediction pr;
        fv_gaze_pipeline_predict(p, 0, &pr);
        assert_finite_prediction(&pr);
        fv_gaze_pipeline_destroy(&p);
    }
}

static void gaze_off_screen_and_nan_directions_are_invalid_not_nan(void **state)
{
    (void)state;
    fv_gaze_pipeline *p = NULL;
    assert_int_equal(fv_gaze_pipeline_create(NULL, &p), FV_OK);
    fv_gaze_sample s = valid_sample(1000, fv_v3(0, 0, 1), fv_v3(NAN, 0, -1), 4.0f);
    assert_int_equal(fv_gaze_pipeline_push(p, &s), FV_OK);
    fv_gaze_pipeline_stats st;
    fv_gaze_pipeline_get_stats(p, &st);
    assert_int_equal(st.invalid, 1);
    fv_gaze_prediction pr;
    fv_gaze_pipeline_predict(p, 2000, &pr);
    assert_false(pr.eye_valid[0] || pr.eye_valid[1] || pr.combined_valid);
    assert_finite_prediction(&pr);
    /* pupil 0 and 12 mm are not taken as measurements */
    s = valid_sample(2000, fv_v3(0, 0, -1), fv_v3(0, 0, -1), 0.0f);
    assert_int_equal(fv_gaze_pipeline_push(p, &s), FV_OK);
    s = valid_sample(3000, fv_v3(0, 0, -1), fv_v3(0, 0, -1), 12.0f);
    assert_int_equal(fv_gaze_pipeline_push(p, &s), FV_OK);
    fv_gaze_pipeline_predict(p, 3000, &pr);
    assert_true(pr.combined_valid);
    assert_true(isnan(pr.pupil_mm));
    fv_gaze_pipeline_destroy(&p);
}

static void gaze_main_sequence_and_fit_stay_finite(void **state)
{
    (void)state;
    const double amps[] = {-1.0, 0.0, 1e-12, 0.5, 10.0, 1e6, NAN, INFINITY};
    for (size_t i = 0; i < sizeof amps / sizeof amps[0]; i++) {
        double v = fv_gaze_main_sequence_peak_deg_s(NULL, amps[i]);
        double d = fv_gaze_main_sequence_duration_s(NULL, amps[i]);
        assert_true(isfinite(v) && v > 0.0 && isfinite(d) && d > 0.0);
    }
    double t[3] = {-0.01, -0.005, 0.0}, dd[3] = {0.0, 0.0, 0.0};
    fv_gaze_saccade_fit fit;
    assert_true(fv_gaze_saccade_fit_landing(NULL, t, dd, 3, &fit));
    assert_true(isfinite(fit.amplitude_deg) && isfinite(fit.t_onset_s) && fit.duration_s > 0.0);
    double bad[3] = {0.0, NAN, 1.0};
    assert_false(fv_gaze_saccade_fit_landing(NULL, t, bad, 3, &fit));
    double big[3] = {0.0, 1e9, 1e12};
    assert_true(fv_gaze_saccade_fit_landing(NULL, t, big, 3, &fit));
    assert_true(isfinite(fit.amplitude_deg));
    assert_true(fv_gaze_minjerk_inverse(NAN) == 0.0 && fv_gaze_minjerk(INFINITY) == 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gaze_extremes_never_produce_nan_or_inf),
        cmocka_unit_test(gaze_off_screen_and_nan_directions_are_invalid_not_nan),
        cmocka_unit_test(gaze_main_sequence_and_fit_stay_finite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
