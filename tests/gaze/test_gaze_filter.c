/* @brief 1€ filter on gaze angles: holds a noisy fixation, follows a gaze shift, ignores bad time steps. */
#include <math.h>
#include <stdint.h>

#include "fv_gaze_filter.h"
#include "fv_test.h"

static uint64_t g_rng = 777;
static double normal(void) { return fv_test_normal(&g_rng); }

static void gaze_filter_holds_fixation_within_0p1_deg(void **state)
{
    (void)state;
    fv_gaze_one_euro f;
    fv_gaze_one_euro_init(&f, 0, 0, 0); /* defaults */
    const double truth[2] = {5.0, -3.0}, sigma = 0.1; /* 0.1 deg SD per axis: a typical VR tracker */
    double raw_max = 0.0, filt_max = 0.0;
    for (int i = 0; i < 120 * 10; i++) {
        double in[2] = {truth[0] + sigma * normal(), truth[1] + sigma * normal()}, out[2];
        fv_gaze_one_euro_push(&f, (int64_t)i * 8333333, in, out);
        if (i < 60) continue; /* half a second to settle */
        double re = hypot(in[0] - truth[0], in[1] - truth[1]), fe = hypot(out[0] - truth[0], out[1] - truth[1]);
        raw_max = fmax(raw_max, re);
        filt_max = fmax(filt_max, fe);
    }
    assert_true(raw_max > 0.25);  /* the input really is noisy */
    assert_true(filt_max < 0.1);  /* the output holds within 0.1 deg at every sample */
}

static void gaze_filter_follows_a_gaze_shift_quickly(void **state)
{
    (void)state;
    fv_gaze_one_euro f;
    fv_gaze_one_euro_init(&f, 0, 0, 0);
    double out[2];
    for (int i = 0; i < 120; i++) fv_gaze_one_euro_push(&f, (int64_t)i * 8333333, (double[2]){0, 0}, out);
    /* a 10 deg step: the speed term raises the cutoff, so the output gets there within 150 ms */
    for (int i = 120; i < 138; i++) fv_gaze_one_euro_push(&f, (int64_t)i * 8333333, (double[2]){10, 0}, out);
    assert_true(fabs(out[0] - 10.0) < 0.5);
}

static void gaze_filter_ignores_zero_dt_and_nan(void **state)
{
    (void)state;
    fv_gaze_one_euro f;
    fv_gaze_one_euro_init(&f, NAN, -1.0f, INFINITY); /* bad parameters fall back to defaults */
    assert_true(f.min_cutoff_hz > 0.0f && isfinite(f.beta) && isfinite(f.d_cutoff_hz));
    double out[2];
    fv_gaze_one_euro_push(&f, 1000, (double[2]){NAN, 1}, out); /* not started by NaN */
    assert_false(f.started);
    fv_gaze_one_euro_push(&f, 1000, (double[2]){1, 2}, out);
    assert_true(out[0] == 1.0 && out[1] == 2.0);
    fv_gaze_one_euro_push(&f, 1000, (double[2]){50, 50}, out); /* zero dt: no change */
    assert_true(out[0] == 1.0 && out[1] == 2.0);
    fv_gaze_one_euro_push(&f, 900, (double[2]){50, 50}, out); /* time going back: no change */
    assert_true(out[0] == 1.0 && out[1] == 2.0);
    fv_gaze_one_euro_push(&f, 2000, (double[2]){INFINITY, 0}, out);
    assert_true(out[0] == 1.0 && out[1] == 2.0);
    fv_gaze_one_euro_push(&f, 2001, (double[2]){1e30, -1e30}, out); /* 1 ns later, absurd values: finite */
    assert_true(isfinite(out[0]) && isfinite(out[1]));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gaze_filter_holds_fixation_within_0p1_deg),
        cmocka_unit_test(gaze_filter_follows_a_gaze_shift_quickly),
        cmocka_unit_test(gaze_filter_ignores_zero_dt_and_nan),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
