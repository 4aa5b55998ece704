/* @brief The refresh divisor of fovea's OpenXR runtime (xr/pace, fv_xr_pace.h): the window's estimate (none before
 * FV_XR_PACE_MIN_FRAMES frames, its 75th percentile after: a one-off slow frame does not count), the divisor raised
 * at once to the smallest k whose k refreshes hold the need, kept at the boundary (no flapping), lowered with
 * headroom, back to 1 when the compositor is fast again; bad input never gives a k outside 1..FV_XR_PACE_MAX. */
#include <math.h>

#include "fv_test.h"
#include "fv_xr_pace.h"

static void window_needs_min_frames_and_ignores_a_one_off(void **state)
{
    (void)state;
    fv_xr_pace_window w = {0};
    double need = -1;
    fv_xr_pace_window_add(&w, 400.0); /* the first frame: pipelines made on first use */
    for (int i = 0; i < FV_XR_PACE_MIN_FRAMES - 2; i++) fv_xr_pace_window_add(&w, 5.0);
    assert_false(fv_xr_pace_window_need(&w, &need));
    assert_true(need == -1);
    fv_xr_pace_window_add(&w, 5.0);
    assert_true(fv_xr_pace_window_need(&w, &need));
    assert_true(need == 5.0);
    fv_xr_pace_window_add(&w, NAN); /* not counted */
    fv_xr_pace_window_add(&w, -1.0);
    assert_int_equal(w.count, FV_XR_PACE_MIN_FRAMES);
    /* the window slides: 16 frames of 30 ms replace everything */
    for (int i = 0; i < FV_XR_PACE_WINDOW; i++) fv_xr_pace_window_add(&w, 30.0);
    assert_true(fv_xr_pace_window_need(&w, &need) && need == 30.0);
    /* the 75th percentile: 12 of 16 at 10 ms, 4 at 50 ms -> 50 (the slow quarter counts); 13 at 10 -> 10 */
    for (int i = 0; i < FV_XR_PACE_WINDOW; i++) fv_xr_pace_window_add(&w, i < 12 ? 10.0 : 50.0);
    assert_true(fv_xr_pace_window_need(&w, &need) && need == 50.0);
    for (int i = 0; i < FV_XR_PACE_WINDOW; i++) fv_xr_pace_window_add(&w, i < 13 ? 10.0 : 50.0);
    assert_true(fv_xr_pace_window_need(&w, &need) && need == 10.0);
}

static void divisor_rises_holds_and_falls_back(void **state)
{
    (void)state;
    const double r = 1000.0 / 90.0; /* 11.1 ms */
    assert_int_equal(fv_xr_pace_divisor(1, 5.0, r), 1);
    assert_int_equal(fv_xr_pace_divisor(1, r, r), 1);         /* exactly one refresh holds it */
    assert_int_equal(fv_xr_pace_divisor(1, 26.4, r), 3);      /* 26.4 ms: three refreshes (33.3 ms) */
    assert_int_equal(fv_xr_pace_divisor(3, 23.0, r), 3);      /* 2 refreshes would hold 23 ms, not with 20% spare */
    assert_int_equal(fv_xr_pace_divisor(3, 17.0, r), 2);      /* 17 <= 0.8 * 22.2 */
    assert_int_equal(fv_xr_pace_divisor(2, 21.0, r), 2);      /* at the boundary: stays */
    assert_int_equal(fv_xr_pace_divisor(2, 23.0, r), 3);      /* over it: up at once */
    assert_int_equal(fv_xr_pace_divisor(3, 8.0, r), 1);       /* fast again: every refresh */
    assert_int_equal(fv_xr_pace_divisor(2, 0.0, r), 1);
    assert_int_equal(fv_xr_pace_divisor(1, 1e9, r), FV_XR_PACE_MAX);
}

static void divisor_of_bad_input_stays_in_range(void **state)
{
    (void)state;
    const double r = 1000.0 / 90.0;
    assert_int_equal(fv_xr_pace_divisor(0, 5.0, r), 1);
    assert_int_equal(fv_xr_pace_divisor(1000, 5.0, r), 1);
    assert_int_equal(fv_xr_pace_divisor(4, NAN, r), 1);
    assert_int_equal(fv_xr_pace_divisor(4, INFINITY, r), 1);
    assert_int_equal(fv_xr_pace_divisor(4, 50.0, 0.0), 1);
    assert_int_equal(fv_xr_pace_divisor(4, 50.0, -r), 1);
    assert_int_equal(fv_xr_pace_divisor(4, 50.0, NAN), 1);
    assert_int_equal(fv_xr_pace_divisor(4, -3.0, r), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(window_needs_min_frames_and_ignores_a_one_off),
        cmocka_unit_test(divisor_rises_holds_and_falls_back),
        cmocka_unit_test(divisor_of_bad_input_stays_in_range),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
