/* @brief render/window's swapchain display clock (fv_present_clock): the refresh period from vsync evidence (steady,
 * with missed refreshes, jitter, a wrong nominal rate), no evidence (the nominal rate, flagged as not measured),
 * which vsync a present is shown at, and the extremes (equal, earlier and far-future times, absurd rates): indices
 * never go back and every time stays finite. Pure computation: no GPU, no window. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fv_clock.h"

#include "fv_present_clock.h"
#include "fv_test.h"

#define T0 1000000000LL

/* A splitmix-style hash for deterministic jitter in [-j, j] ns. */
static int64_t jitter(uint64_t k, int64_t j)
{
    uint64_t x = k * 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 31)) * 0xBF58476D1CE4E5B9ull;
    x ^= x >> 29;
    return j ? (int64_t)(x % (uint64_t)(2 * j + 1)) - j : 0;
}

static void period_of_a_steady_60hz_display_is_measured_within_0p1_percent(void **state)
{
    (void)state;
    fv_present_clock c;
    fv_present_clock_init(&c, FV_PRESENT_CLOCK_CADENCE, 0.0, T0); /* unknown nominal rate */
    assert_false(c.period_measured);
    const double T = 1e9 / 60.0;
    for (uint64_t k = 1; k <= 120; k++) fv_present_clock_vsync(&c, T0 + (int64_t)llround(k * T) + jitter(k, 300000));
    assert_true(c.period_measured);
    assert_true(fabs(c.period_exact_ns / T - 1.0) < 1e-3);
    assert_true(fabs(c.base.refresh_hz - 60.0) < 0.06);
    /* the next vsync is predicted within the jitter plus the period's error over one period */
    fv_vsync v;
    int64_t last = T0 + (int64_t)llround(120 * T);
    assert_int_equal(fv_display_vsync_at_or_after(&c.base, last + 1000000, &v), FV_OK);
    assert_true(llabs(v.t_ns - (last + (int64_t)llround(T))) < 700000);
    assert_true(v.t_ns >= last + 1000000);
}

static void missed_refreshes_count_as_whole_periods_not_a_slower_display(void **state)
{
    (void)state;
    fv_present_clock c;
    fv_present_clock_init(&c, FV_PRESENT_CLOCK_CADENCE, 0.0, T0);
    const double T = 1e9 / 90.0;
    uint64_t k = 0;
    uint64_t idx_before = c.anchor_index;
    for (int i = 0; i < 200; i++) {
        k += 1 + (uint64_t)(i % 7 == 3) + 2u * (uint64_t)(i % 11 == 5); /* skip 1 or 2 refreshes now and then */
        fv_present_clock_vsync(&c, T0 + (int64_t)llround((double)k * T) + jitter(k, 200000));
    }
    assert_true(fabs(c.period_exact_ns / T - 1.0) < 2e-3);
    /* the first event anchors the grid; every later one advances the index by its whole periods */
    assert_true(c.anchor_index - idx_before >= k - 1);
}

static void a_wrong_nominal_rate_gives_way_to_the_measured_one(void **state)
{
    (void)state;
    fv_present_clock c;
    fv_present_clock_init(&c, FV_PRESENT_CLOCK_CADENCE, 60.0, T0); /* the monitor says 60, the panel runs at 75 */
    assert_int_equal(c.base.period_ns, 16666667);
    const double T = 1e9 / 75.0;
    for (uint64_t k = 1; k <= 64; k++) fv_present_clock_vsync(&c, T0 + (int64_t)llround(k * T));
    assert_true(fabs(c.base.refresh_hz - 75.0) < 0.1);
}

static void without_vsync_evidence_the_nominal_rate_holds_and_is_flagged(void **state)
{
    (void)state;
    fv_present_clock c;
    fv_present_clock_init(&c, FV_PRESENT_CLOCK_CADENCE, 90.0, T0);
    fv_vsync shown;
    /* presents at a render-bound 22 Hz say nothing about the refresh */
    for (int i = 1; i <= 50; i++)
        assert_int_equal(fv_display_present(&c.base, T0 + i * 45000000LL, 0, &shown), FV_OK);
    assert_false(c.period_measured);
    assert_int_equal(c.base.period_ns, 11111111);
    fv_present_clock_init(&c, FV_PRESENT_CLOCK_CADENCE, 0.0, T0);
    assert_true(fabs(c.base.refresh_hz - 60.0) < 1e-9); /* unknown: 60 Hz until shown otherwise */
    /* acquires that blocked at a steady 5 Hz (a software presenter under load) are not a 5 Hz display */
    for (int i = 1; i <= 40; i++) fv_present_clock_vsync(&c, T0 + i * 200000000LL);
    assert_false(c.period_measured);
    assert_true(fabs(c.base.refresh_hz - 60.0) < 1e-9);
}

static void a_present_is_shown_at_its_target_or_the_first_vsync_after_its_latch(void **state)
{
    (void)state;
    fv_present_clock c;
    fv_present_clock_init(&c, FV_PRESENT_CLOCK_CADENCE, 100.0, T0); /* 10 ms */
    fv_vsync target, shown;
    assert_int_equal(fv_display_vsync_at_or_after(&c.base, T0 + 25000000, &target), FV_OK);
    assert_int_equal(target.index, 3);
    assert_int_equal(target.t_ns, T0 + 30000000);
    /* early: shown at the next vsync (a swapchain present has no target time; FIFO shows it at the next flip) */
    assert_int_equal(fv_display_present(&c.base, T0 + 11000000, target.index, &shown), FV_OK);
    assert_int_equal(shown.index, 2);
    assert_int_equal(shown.t_ns, T0 + 20000000);
    /* inside the latch margin (0.5 ms): the next one */
    assert_int_equal(fv_display_present(&c.base, T0 + 29800000, target.index, &shown), FV_OK);
    assert_int_equal(shown.index, 4);
    /* photons half a period after the vsync (the middle row of a scan-out) */
    assert_int_equal(fv_display_photon_ns(&c.base, &shown), shown.t_ns + 5000000);
}

static void extremes_keep_indices_rising_and_times_finite(void **state)
{
    (void)state;
    fv_present_clock c;
    const double bad[] = {NAN, INFINITY, -1.0, 0.5, 1e6};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        fv_present_clock_init(&c, FV_PRESENT_CLOCK_CADENCE, bad[i], T0);
        assert_true(fabs(c.base.refresh_hz - 60.0) < 1e-9);
        assert_int_equal(c.nominal_period_ns, 0);
    }
    fv_present_clock_init(&c, FV_PRESENT_CLOCK_DISPLAY_TIMING, 60.0, T0);
    fv_present_clock_vsync(&c, T0 + 16666667);
    uint64_t idx = c.anchor_index;
    fv_present_clock_vsync(&c, T0 + 16666667); /* the same time again */
    fv_present_clock_vsync(&c, T0);            /* earlier */
    fv_present_clock_vsync(&c, INT64_MIN);
    assert_int_equal(c.anchor_index, idx);
    /* a 10 s gap (a suspended machine): one event, the index jumps by the periods in between */
    fv_present_clock_vsync(&c, T0 + 16666667 + 10 * FV_NS_PER_S);
    assert_int_equal(c.anchor_index, idx + 600);
    assert_true(fabs(c.base.refresh_hz - 60.0) < 0.01); /* an interval of 600 periods says nothing: ignored */
    /* intervals shorter than 1 ms (a 10 kHz "display") clamp the period at 1000 Hz */
    fv_present_clock_init(&c, FV_PRESENT_CLOCK_CADENCE, 0.0, T0);
    for (int k = 1; k <= 40; k++) fv_present_clock_vsync(&c, T0 + k * 100000LL);
    assert_true(c.base.refresh_hz <= 1000.0 + 1e-9 && c.base.period_ns >= 1000000);
    /* far future and far past queries */
    fv_vsync v;
    assert_int_equal(fv_display_vsync_at_or_after(&c.base, INT64_MAX / 2, &v), FV_ERR_RANGE);
    assert_int_equal(fv_display_vsync_at_or_after(&c.base, INT64_MIN / 2, &v), FV_OK);
    assert_int_equal(v.index, 0);
    fv_vsync shown;
    assert_int_equal(fv_display_present(&c.base, INT64_MAX, 0, &shown), FV_ERR_RANGE);
    assert_int_equal(fv_display_present(&c.base, T0 + 5000000, UINT64_C(1) << 60, &shown), FV_OK); /* no target */
    assert_true(shown.t_ns >= T0 + 5000000 && shown.t_ns < T0 + 20 * FV_NS_PER_S);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(period_of_a_steady_60hz_display_is_measured_within_0p1_percent),
        cmocka_unit_test(missed_refreshes_count_as_whole_periods_not_a_slower_display),
        cmocka_unit_test(a_wrong_nominal_rate_gives_way_to_the_measured_one),
        cmocka_unit_test(without_vsync_evidence_the_nominal_rate_holds_and_is_flagged),
        cmocka_unit_test(a_present_is_shown_at_its_target_or_the_first_vsync_after_its_latch),
        cmocka_unit_test(extremes_keep_indices_rising_and_times_finite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
