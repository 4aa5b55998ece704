/* @brief sim/display: vsync timing (rate, bounded seeded jitter, first-at-or-after), photon time for rolling and
 * global panels, which vsync a presented frame is shown at, and clear errors for a bad description. */
#include <math.h>
#include <string.h>

#include "fv_sim_display.h"
#include "fv_test.h"

static fv_display *make(fv_clock *clk, const fv_sim_display_desc *extra)
{
    fv_sim_display_desc d = extra ? *extra : (fv_sim_display_desc){0};
    d.clock = clk;
    fv_display *disp = NULL;
    assert_int_equal(fv_sim_display_create(&d, &disp), FV_OK);
    return disp;
}

static void display_refreshes_at_90hz_without_drift(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 5 * FV_NS_PER_S);
    fv_display *d = make(&clk, NULL);
    assert_true(fabs(d->refresh_hz - 90.0) < 1e-9);
    assert_int_equal(d->period_ns, 11111111);
    fv_vsync v0, v900;
    assert_int_equal(fv_display_vsync_at_or_after(d, 0, &v0), FV_OK);
    assert_int_equal(v0.index, 0);
    assert_int_equal(v0.t_ns, 5 * FV_NS_PER_S + d->period_ns); /* vsync 0 one period after create */
    assert_int_equal(fv_display_vsync_at_or_after(d, v0.t_ns + 10 * FV_NS_PER_S, &v900), FV_OK);
    assert_int_equal(v900.index, 900); /* 900 refreshes in 10 s: the period is not rounded to whole ns per frame */
    assert_int_equal(v900.t_ns - v0.t_ns, 10 * FV_NS_PER_S);
    fv_display_destroy(&d);
    assert_null(d);
}

static void vsync_jitter_is_bounded_seeded_and_monotonic(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    const int64_t J = 300000; /* ±0.3 ms */
    fv_sim_display_desc desc = {.vsync_jitter_ns = J, .seed = 42, .refresh_hz = 120.0};
    fv_display *a = make(&clk, &desc), *b = make(&clk, &desc);
    desc.seed = 43;
    fv_display *c = make(&clk, &desc);
    const double period = 1e9 / 120.0;
    const int64_t t0 = (int64_t)llround(period);
    int64_t prev = INT64_MIN;
    int differs_from_nominal = 0, differs_between_seeds = 0;
    int64_t min_j = INT64_MAX, max_j = INT64_MIN;
    for (uint64_t k = 0; k < 2000; k++) {
        int64_t nominal = t0 + (int64_t)llround((double)k * period);
        fv_vsync va, vb, vc;
        /* asking just past the previous vsync must give exactly vsync k */
        assert_int_equal(fv_display_vsync_at_or_after(a, prev == INT64_MIN ? 0 : prev + 1, &va), FV_OK);
        assert_int_equal(va.index, k);
        assert_int_equal(fv_display_vsync_at_or_after(b, prev == INT64_MIN ? 0 : prev + 1, &vb), FV_OK);
        assert_int_equal(vb.t_ns, va.t_ns); /* same seed, same sequence */
        assert_int_equal(fv_display_vsync_at_or_after(c, nominal - J, &vc), FV_OK);
        if (vc.index == k && vc.t_ns != va.t_ns) differs_between_seeds++;
        int64_t j = va.t_ns - nominal;
        assert_true(j >= -J && j <= J);
        if (j < min_j) min_j = j;
        if (j > max_j) max_j = j;
        if (j != 0) differs_from_nominal++;
        assert_true(va.t_ns > prev);
        prev = va.t_ns;
    }
    assert_true(differs_from_nominal > 1900);
    assert_true(differs_between_seeds > 1900);
    assert_true(min_j < -J / 2 && max_j > J / 2); /* spread over the whole band */
    fv_display_destroy(&a);
    fv_display_destroy(&b);
    fv_display_destroy(&c);
}

static void vsync_at_or_after_returns_the_first_one_not_before_t(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fv_sim_display_desc desc = {.vsync_jitter_ns = 1000000, .seed = 7};
    fv_display *d = make(&clk, &desc);
    uint64_t x = 1;
    for (int i = 0; i < 5000; i++) {
        x = x * 6364136223846793005ULL + 1442695040888963407ULL;
        int64_t t = (int64_t)(x >> 34); /* 0 .. ~1 s */
        fv_vsync v, before;
        assert_int_equal(fv_display_vsync_at_or_after(d, t, &v), FV_OK);
        assert_true(v.t_ns >= t);
        if (v.index > 0) {
            assert_int_equal(fv_display_vsync_at_or_after(d, v.t_ns - 1, &before), FV_OK);
            assert_int_equal(before.index, v.index); /* nothing between t and v */
            assert_int_equal(fv_display_vsync_at_or_after(d, v.t_ns - d->period_ns / 2, &before), FV_OK);
            assert_true(before.index == v.index || before.index == v.index - 1);
        }
        /* exactly at a vsync: that vsync */
        fv_vsync same;
        assert_int_equal(fv_display_vsync_at_or_after(d, v.t_ns, &same), FV_OK);
        assert_int_equal(same.index, v.index);
    }
    fv_display_destroy(&d);
}

static void photon_time_follows_scanout_and_persistence(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fv_sim_display_desc rolling = {.scanout_ns = 10 * FV_NS_PER_MS, .persistence_ns = 2 * FV_NS_PER_MS};
    fv_sim_display_desc global = rolling;
    global.scan = FV_SIM_DISPLAY_GLOBAL;
    fv_display *r = make(&clk, &rolling), *g = make(&clk, &global), *def = make(&clk, NULL);
    fv_vsync v = {.index = 3, .t_ns = 1000000000};
    assert_int_equal(fv_display_photon_ns(r, &v) - v.t_ns, 5 * FV_NS_PER_MS + 1 * FV_NS_PER_MS);
    assert_int_equal(fv_display_photon_ns(g, &v) - v.t_ns, 10 * FV_NS_PER_MS + 1 * FV_NS_PER_MS);
    assert_int_equal(fv_sim_display_photon_offset_ns(g), 11 * FV_NS_PER_MS);
    /* defaults: 95% of 11.111 ms scan-out, 2 ms persistence, rolling */
    assert_int_equal(fv_display_photon_ns(def, &v) - v.t_ns, 10555556 / 2 + 1 * FV_NS_PER_MS);
    fv_display_destroy(&r);
    fv_display_destroy(&g);
    fv_display_destroy(&def);
}

static void present_shows_on_target_or_at_the_next_vsync_after_the_deadline(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fv_display *d = make(&clk, NULL);
    const int64_t margin = d->present_margin_ns;
    assert_int_equal(margin, FV_NS_PER_MS / 2);
    fv_vsync v10, v11, shown;
    assert_int_equal(fv_display_vsync_at_or_after(d, 10 * d->period_ns, &v10), FV_OK);
    assert_int_equal(fv_display_vsync_at_or_after(d, v10.t_ns + 1, &v11), FV_OK);
    assert_int_equal(v11.index, v10.index + 1);
    /* just in time */
    assert_int_equal(fv_display_present(d, v10.t_ns - margin, v10.index, &shown), FV_OK);
    assert_int_equal(shown.index, v10.index);
    assert_int_equal(shown.t_ns, v10.t_ns);
    /* one ns late: the next refresh */
    assert_int_equal(fv_display_present(d, v10.t_ns - margin + 1, v10.index, &shown), FV_OK);
    assert_int_equal(shown.index, v11.index);
    /* early: waits for its target */
    assert_int_equal(fv_display_present(d, v10.t_ns - 5 * d->period_ns, v10.index, &shown), FV_OK);
    assert_int_equal(shown.index, v10.index);
    /* very late: several refreshes later */
    assert_int_equal(fv_display_present(d, v10.t_ns + 3 * d->period_ns, v10.index, &shown), FV_OK);
    assert_true(shown.index >= v10.index + 3);
    assert_true(shown.t_ns - margin >= v10.t_ns + 3 * d->period_ns);
    fv_display_destroy(&d);
}

static void bad_descriptions_are_refused_with_the_field_and_value(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fv_display *d = (fv_display *)&d;
    fv_test_log_capture_begin();
    fv_sim_display_desc desc = {.clock = &clk, .refresh_hz = NAN};
    assert_int_equal(fv_sim_display_create(&desc, &d), FV_ERR_RANGE);
    assert_null(d);
    desc.refresh_hz = 5000;
    assert_int_equal(fv_sim_display_create(&desc, &d), FV_ERR_RANGE);
    desc = (fv_sim_display_desc){.clock = &clk, .vsync_jitter_ns = 5 * FV_NS_PER_MS, .persistence_ns = -1,
                                 .scanout_ns = 20 * FV_NS_PER_MS, .present_margin_ns = 9 * FV_NS_PER_MS,
                                 .scan = (fv_sim_display_scan)9};
    assert_int_equal(fv_sim_display_create(&desc, &d), FV_ERR_RANGE);
    desc = (fv_sim_display_desc){0};
    assert_int_equal(fv_sim_display_create(&desc, &d), FV_ERR_INVALID_ARG);
    fv_test_log_capture_end();
    fv_assert_log_contains("refresh_hz nan outside 1..1000");
    fv_assert_log_contains("refresh_hz 5000 outside");
    fv_assert_log_contains("vsync_jitter_ns 5000000 outside 0..2777777");
    fv_assert_log_contains("persistence_ns -1 outside");
    fv_assert_log_contains("scanout_ns 20000000 outside");
    fv_assert_log_contains("present_margin_ns 9000000 outside");
    fv_assert_log_contains("unknown scan mode 9");
    fv_assert_log_contains("a clock is required");
}

static void far_future_times_are_refused_not_wrapped(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fv_display *d = make(&clk, NULL);
    fv_vsync v;
    fv_test_log_capture_begin();
    assert_int_equal(fv_display_vsync_at_or_after(d, INT64_MAX - FV_NS_PER_S, &v), FV_ERR_RANGE);
    fv_test_log_capture_end();
    fv_assert_log_contains("beyond the simulated display's timeline");
    /* a year ahead is fine */
    assert_int_equal(fv_display_vsync_at_or_after(d, 365LL * 86400 * FV_NS_PER_S, &v), FV_OK);
    assert_true(v.t_ns >= 365LL * 86400 * FV_NS_PER_S);
    fv_display_destroy(&d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(display_refreshes_at_90hz_without_drift),
        cmocka_unit_test(vsync_jitter_is_bounded_seeded_and_monotonic),
        cmocka_unit_test(vsync_at_or_after_returns_the_first_one_not_before_t),
        cmocka_unit_test(photon_time_follows_scanout_and_persistence),
        cmocka_unit_test(present_shows_on_target_or_at_the_next_vsync_after_the_deadline),
        cmocka_unit_test(bad_descriptions_are_refused_with_the_field_and_value),
        cmocka_unit_test(far_future_times_are_refused_not_wrapped),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
