/* @brief The frame-budget controller (runtime/budget) on the simulated display (sim/display, a simulated clock) with
 * synthetic GPU costs: a cost spike, a slow ramp, an oscillating cost and an overload no rung can fix — quality never
 * oscillates (bounded reversals, settled at the end), misses stay bounded and it returns to full quality when the
 * cost does; and its ladder from the knob table (runtime/app/app_ladder.c): each rung one knob one preset cheaper, in
 * preset steps, least noticeable first, bounded by the presets, never the lens. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fv_budget.h"
#include "fv_sim_display.h"
#include "fv_test.h"
#include "fv_app_ladder.h"

#define HZ 90.0
#define RUNGS 6u
#define SAVE 0.85 /* each rung makes a frame 15% cheaper */

typedef double (*cost_fn)(uint64_t frame); /* the scene's cost at level 0, ms */

typedef struct sim_result {
    uint64_t misses;     /* frames the display showed later than their vsync */
    uint32_t max_level;
    uint32_t level_at[8192];
    uint64_t frames;
} sim_result;

/* Frames on a simulated 90 Hz display: each starts at a vsync, takes cost(level) of GPU time, is presented when done
 * and shown at the first vsync whose latch deadline it met; the next frame starts at that vsync. */
static void simulate(cost_fn cost, uint64_t frames, fv_budget *b, sim_result *out)
{
    memset(out, 0, sizeof *out);
    fv_clock clock;
    fv_clock_sim_init(&clock, 1000000000);
    fv_display *d = NULL;
    fv_sim_display_desc dd = {.clock = &clock, .refresh_hz = HZ};
    assert_int_equal(fv_sim_display_create(&dd, &d), FV_OK);
    fv_budget_desc bd = {.period_ns = d->period_ns, .rungs = RUNGS};
    assert_int_equal(fv_budget_init(b, &bd), FV_OK);
    fv_vsync v;
    assert_int_equal(fv_display_vsync_at_or_after(d, fv_clock_now_ns(&clock), &v), FV_OK);
    for (uint64_t f = 0; f < frames; f++) {
        clock.sleep_until_ns(&clock, v.t_ns);
        double ms = cost(f) * pow(SAVE, b->level);
        int64_t gpu_ns = (int64_t)(ms * 1e6);
        fv_vsync shown;
        assert_int_equal(fv_display_present(d, v.t_ns + gpu_ns, v.index + 1, &shown), FV_OK);
        out->misses += shown.index > v.index + 1;
        fv_budget_push(b, gpu_ns);
        if (b->level > out->max_level) out->max_level = b->level;
        if (f < 8192) out->level_at[f] = b->level;
        v = shown;
    }
    out->frames = frames;
    fv_display_destroy(&d);
    assert_int_equal(b->misses <= b->frames, 1);
}

static uint32_t changes_between(const sim_result *r, uint64_t a, uint64_t z)
{
    uint32_t n = 0;
    for (uint64_t f = a + 1; f < z && f < 8192; f++) n += r->level_at[f] != r->level_at[f - 1];
    return n;
}

static double spike(uint64_t f) { return f >= 200 && f < 260 ? 16.0 : 8.0; }

static void a_cost_spike_steps_down_then_back_up_once(void **state)
{
    (void)state;
    fv_budget b;
    sim_result r;
    simulate(spike, 1200, &b, &r);
    print_message("spike: max level %u, misses %llu, downs %llu, ups %llu, reversals %llu, final %u\n", r.max_level,
                  (unsigned long long)r.misses, (unsigned long long)b.downs, (unsigned long long)b.ups,
                  (unsigned long long)b.reversals, b.level);
    /* 16 ms needs 0.85^3 = 0.61 of the cost to fit 10 ms: three rungs, not more than one past that */
    assert_true(r.max_level >= 3 && r.max_level <= 4);
    assert_int_equal(r.level_at[199], 0);
    assert_int_equal(b.level, 0);           /* back to full quality */
    assert_true(b.reversals <= 1);
    assert_true(changes_between(&r, 700, 1200) == 0);
    /* each rung takes a window (8 frames) to measure: the first ~3 windows of the spike miss, nothing else */
    assert_true(r.misses <= 32);
}

static double ramp(uint64_t f) { return f < 1000 ? 6.0 + 8.0 * (double)f / 1000.0 : 14.0; }

static void a_slow_ramp_only_ever_steps_down(void **state)
{
    (void)state;
    fv_budget b;
    sim_result r;
    simulate(ramp, 1400, &b, &r);
    print_message("ramp: final level %u, misses %llu, downs %llu, ups %llu\n", b.level, (unsigned long long)r.misses,
                  (unsigned long long)b.downs, (unsigned long long)b.ups);
    assert_int_equal(b.ups, 0);
    for (uint64_t f = 1; f < 1400; f++) assert_true(r.level_at[f] >= r.level_at[f - 1]);
    /* 14 ms fits 10 ms at 0.85^3 (8.6 ms): three rungs, and it steps before frames miss */
    assert_int_equal(b.level, 3);
    assert_true(r.misses <= 2);
    assert_true(changes_between(&r, 1000, 1400) == 0);
}

static double oscillating(uint64_t f) { return 9.0 + 2.5 * sin(2.0 * M_PI * (double)f / 90.0); }

static void an_oscillating_cost_does_not_make_quality_oscillate(void **state)
{
    (void)state;
    fv_budget b;
    sim_result r;
    simulate(oscillating, 4000, &b, &r);
    uint32_t late = changes_between(&r, 1000, 4000);
    print_message("oscillating: level %u, changes %llu (%u after frame 1000), reversals %llu, misses %llu\n", b.level,
                  (unsigned long long)(b.downs + b.ups), late, (unsigned long long)b.reversals,
                  (unsigned long long)r.misses);
    assert_true(b.reversals <= 2);
    assert_int_equal(late, 0);
    assert_int_equal(b.level, 1); /* the peaks (11.5 ms) fit at one rung (9.8 ms) */
    assert_true(r.misses <= 40);
}

static double overload(uint64_t f)
{
    (void)f;
    return 40.0;
}

static void an_overload_no_rung_fixes_stops_at_the_last_rung(void **state)
{
    (void)state;
    fv_budget b;
    sim_result r;
    simulate(overload, 300, &b, &r);
    assert_int_equal(b.level, RUNGS);
    assert_int_equal(b.ups, 0);
    assert_int_equal(r.max_level, RUNGS);
}

static void bad_descriptions_and_times_are_refused_or_clamped(void **state)
{
    (void)state;
    fv_budget b;
    assert_int_equal(fv_budget_init(&b, &(fv_budget_desc){.period_ns = 0, .rungs = 1}), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_budget_init(&b, &(fv_budget_desc){.period_ns = -5, .rungs = 1}), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_budget_init(&b, &(fv_budget_desc){.period_ns = 1000, .rungs = FV_BUDGET_MAX_RUNGS + 1}),
                     FV_ERR_INVALID_ARG);
    assert_int_equal(fv_budget_init(&b, &(fv_budget_desc){.period_ns = 1000, .target = 1.5f}), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_budget_init(&b, &(fv_budget_desc){.period_ns = 1000, .window = 1}), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_budget_init(&b, &(fv_budget_desc){.period_ns = 1000, .window = 16, .up_hold = 8}),
                     FV_ERR_INVALID_ARG);
    assert_int_equal(fv_budget_init(&b, NULL), FV_ERR_INVALID_ARG);
    /* no rungs: never changes; absurd times are clamped and counted */
    assert_int_equal(fv_budget_init(&b, &(fv_budget_desc){.period_ns = INT64_MAX / 2}), FV_OK);
    for (int i = 0; i < 100; i++) assert_int_equal(fv_budget_push(&b, i & 1 ? INT64_MAX : -INT64_MAX), FV_BUDGET_KEEP);
    assert_int_equal(b.level, 0);
    assert_int_equal(b.misses, 50);
    assert_true(fv_budget_target_ns(&b) > 0);
}

/* ---- the ladder from the knob table ---------------------------------------------------------------------------- */

static void ladder_steps_one_preset_at_a_time_within_the_presets(void **state)
{
    (void)state;
    const char *presets[] = {"exact", "high", "balanced", "fast"};
    for (int p = 0; p < 4; p++) {
        fv_quality base, fast;
        char err[256];
        assert_int_equal(fv_quality_preset(presets[p], &base, err, sizeof err), FV_OK);
        assert_int_equal(fv_quality_preset("fast", &fast, err, sizeof err), FV_OK);
        fv_app_rung rungs[FV_APP_LADDER_MAX];
        size_t n = fv_app_ladder_build(&base, presets[p], rungs, FV_APP_LADDER_MAX);
        print_message("from %s: %zu rungs:", presets[p], n);
        for (size_t i = 0; i < n; i++) print_message(" %s", rungs[i].text);
        print_message("\n");
        if (p == 3) assert_int_equal(n, 0);
        else assert_true(n > 0);
        fv_quality q = base;
        for (size_t i = 0; i < n; i++) {
            const fv_knob *k = rungs[i].knob;
            assert_true(strncmp(k->name, "distort.", 8) != 0);
            /* the rung's value is the value of the preset of its step */
            fv_quality step;
            assert_int_equal(fv_quality_preset(presets[p + 1 + rungs[i].step], &step, err, sizeof err), FV_OK);
            fv_knob_value want = fv_knob_get(k, &step), have = rungs[i].value;
            assert_true(k->type == FV_KNOB_FLOAT ? want.f == have.f : k->type == FV_KNOB_BOOL ? want.b == have.b
                                                                                            : want.i == have.i);
            if (i) assert_true(rungs[i].step >= rungs[i - 1].step);
            /* fv_quality_set checks the value against the knob's range in the table */
            if (fv_quality_set(&q, rungs[i].text, err, sizeof err) != FV_OK) fail_msg("%s: %s", rungs[i].text, err);
        }
        /* all rungs applied: the fast preset on every knob of an effect that is on */
        size_t count;
        const fv_knob *knobs = fv_knobs(&count);
        fv_quality all;
        fv_app_ladder_apply(&base, rungs, n, &all);
        for (size_t i = 0; i < count; i++) {
            const fv_knob *k = &knobs[i];
            char a[48], f[48];
            fv_knob_format(k, &all, a, sizeof a);
            fv_knob_format(k, &fast, f, sizeof f);
            bool laddered = false;
            for (size_t r = 0; r < n; r++) laddered |= rungs[r].knob == k;
            /* a switch is only ever turned off, and an effect switched off keeps its other knobs where they were */
            const char *dot = strchr(k->name, '.');
            bool is_switch = dot && !strcmp(dot, ".enabled");
            char en[64];
            snprintf(en, sizeof en, "%.*s.enabled", dot ? (int)(dot - k->name) : 0, k->name);
            const fv_knob *sw = fv_knob_find(en);
            bool effect_on = !sw || fv_knob_get(sw, &all).b;
            if (laddered && !is_switch && effect_on && strcmp(a, f) != 0)
                fail_msg("from %s: %s ends at %s, fast is %s", presets[p], k->name, a, f);
            if (laddered && is_switch) assert_false(fv_knob_get(k, &all).b);
            if (strncmp(k->name, "distort.", 8) == 0) {
                char b0[48];
                assert_string_equal(fv_knob_format(k, &base, b0, sizeof b0), a); /* the lens is never a rung */
            }
        }
    }
}

static void ladder_puts_the_least_noticeable_knobs_first(void **state)
{
    (void)state;
    fv_quality base;
    char err[256];
    assert_int_equal(fv_quality_preset("high", &base, err, sizeof err), FV_OK);
    fv_app_rung rungs[FV_APP_LADDER_MAX];
    size_t n = fv_app_ladder_build(&base, "high", rungs, FV_APP_LADDER_MAX);
    assert_true(n >= 3);
    /* high -> balanced: shadow resolution before its filter; then balanced -> fast, with fewer splits after both */
    assert_string_equal(rungs[0].text, "shadow.resolution=2048");
    assert_string_equal(rungs[1].text, "shadow.filter=pcf3");
    size_t res2 = n, splits = n;
    for (size_t i = 0; i < n; i++) {
        if (!strcmp(rungs[i].text, "shadow.resolution=1024")) res2 = i;
        if (!strncmp(rungs[i].text, "shadow.splits=", 14)) splits = i;
    }
    assert_true(res2 < n && splits < n && res2 < splits);
    /* a knob of an effect that is off is no rung (foveation turned off); turned on (as in the presets), it is */
    fv_quality no_fovea = base;
    assert_int_equal(fv_quality_set(&no_fovea, "fovea.enabled=off", err, sizeof err), FV_OK);
    size_t nf = fv_app_ladder_build(&no_fovea, "high", rungs, FV_APP_LADDER_MAX);
    for (size_t i = 0; i < nf; i++) assert_true(strncmp(rungs[i].knob->name, "fovea.", 6) != 0);
    assert_int_equal(fv_quality_set(&base, "fovea.enabled=on", err, sizeof err), FV_OK);
    size_t m = fv_app_ladder_build(&base, "high", rungs, FV_APP_LADDER_MAX);
    bool fovea = false;
    for (size_t i = 0; i < m; i++) fovea |= strncmp(rungs[i].knob->name, "fovea.", 6) == 0;
    assert_true(fovea);
    /* the knobs of a pass the plan turned off are no rungs */
    const char *off[] = {"shadow", NULL};
    size_t k = fv_app_ladder_build_for(&base, "high", off, rungs, FV_APP_LADDER_MAX);
    for (size_t i = 0; i < k; i++) assert_true(strncmp(rungs[i].knob->name, "shadow.", 7) != 0);
    /* the capacity is respected */
    assert_int_equal(fv_app_ladder_build(&base, "high", rungs, 2), 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_cost_spike_steps_down_then_back_up_once),
        cmocka_unit_test(a_slow_ramp_only_ever_steps_down),
        cmocka_unit_test(an_oscillating_cost_does_not_make_quality_oscillate),
        cmocka_unit_test(an_overload_no_rung_fixes_stops_at_the_last_rung),
        cmocka_unit_test(bad_descriptions_and_times_are_refused_or_clamped),
        cmocka_unit_test(ladder_steps_one_preset_at_a_time_within_the_presets),
        cmocka_unit_test(ladder_puts_the_least_noticeable_knobs_first),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
