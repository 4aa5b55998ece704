/* @brief Logging: the replaceable sink, module levels, FOVEA_LOG parsing, the per-load budget and the rate limit
 * over time. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_clock.h"
#include "fv_log.h"
#include "fv_test.h"

static void sink_receives_errors_and_warnings_with_module(void **state)
{
    (void)state;
    fv_test_log_capture_begin();
    FV_ERROR("scene", "file %s: bad", "x.json");
    FV_WARN("hid", "odd report");
    FV_DEBUG("hid", "hidden at default level");
    fv_test_log_capture_end();
    fv_assert_log_contains("error scene: file x.json: bad");
    fv_assert_log_contains("warn hid: odd report");
    assert_null(strstr(fv_test_log_text(), "hidden"));
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_WARN), 2);
}

static void module_level_enables_debug_for_that_module_only(void **state)
{
    (void)state;
    fv_log_set_level("gi", FV_LOG_LEVEL_DEBUG);
    assert_true(fv_log_enabled("gi", FV_LOG_LEVEL_DEBUG));
    assert_false(fv_log_enabled("hid", FV_LOG_LEVEL_DEBUG));
    assert_true(fv_log_enabled("hid", FV_LOG_LEVEL_ERROR));
}

static void emit_many(int n)
{
    for (int i = 0; i < n; i++) FV_ERROR("scene", "a.json: objects[%d]: bad", i); /* one call site: one kind */
}

static void a_load_budget_shows_a_few_of_each_kind_then_one_summary(void **state)
{
    (void)state;
    fv_log_budget outer, inner;
    fv_test_log_capture_begin();
    fv_log_budget_begin(&outer, "a.json", 3);
    emit_many(100000);
    fv_log_budget_begin(&inner, "model.ply", 0); /* nested: the outer budget counts */
    emit_many(2);
    FV_WARN("scene", "another kind");
    fv_log_budget_end(&inner);
    assert_int_equal(fv_log_budget_suppressed(&outer), 100002 - 3);
    fv_log_budget_end(&outer);
    FV_ERROR("scene", "after the budget"); /* shown: no budget is active */
    fv_test_log_capture_end();
    fv_assert_log_contains("objects[2]: bad");
    assert_null(strstr(fv_test_log_text(), "objects[3]: bad"));
    fv_assert_log_contains("error scene: a.json: ... and 99,999 more like: a.json: objects[0]: bad");
    fv_assert_log_contains("warn scene: another kind");
    fv_assert_log_contains("after the budget");
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_WARN), 3 + 1 + 1 + 1);
}

/* 10,000 warnings over 4 simulated seconds through a limit of 10 lines per second: 10 shown per window, then one
 * summary per window with the exact count of the rest, and nothing lost. */
static void a_rate_limit_bounds_lines_per_window_and_counts_the_rest(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 1000 * FV_NS_PER_S);
    fv_log_ratelimit rl;
    fv_log_ratelimit_init(&rl, 10, FV_NS_PER_S, &clk);
    fv_test_log_capture_begin();
    for (int i = 0; i < 10000; i++) {
        FV_WARN_RL(&rl, "pupil", "message %d: not msgpack; skipped", i);
        fv_clock_sim_advance(&clk, 400 * 1000); /* 0.4 ms: 2500 per second */
    }
    fv_log_ratelimit_flush(&rl);
    fv_test_log_capture_end();
    unsigned long long summarised = 0;
    int summaries = fv_test_log_lines("more like this in the last", &summarised);
    int shown = fv_test_log_lines("; skipped", NULL) - summaries; /* a summary quotes its first message */
    assert_int_equal(shown, 4 * 10);
    assert_int_equal(summaries, 4);
    assert_true(shown + summarised == 10000);
    assert_true(fv_log_ratelimit_suppressed(&rl) == 10000 - 40);
    /* each window: 10 shown, the 11th is the first counted; the summary names it */
    fv_assert_log_contains("message 9: not msgpack; skipped");
    fv_assert_log_contains("warn pupil: ... 2490 more like this in the last 1.0 s; the first: message 10: not "
                           "msgpack; skipped");
    fv_assert_log_contains("the first: message 2510: not msgpack");
    assert_null(strstr(fv_test_log_text(), "warn pupil: message 10: not msgpack"));
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_WARN), 44);
}

/* A window that ends with no further message: tick gives its summary; a quiet limit says nothing; after a window
 * the next message is shown again. */
static void a_rate_limit_summarises_at_tick_and_starts_over(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fv_log_ratelimit rl;
    fv_log_ratelimit_init(&rl, 2, 5 * FV_NS_PER_S, &clk);
    fv_test_log_capture_begin();
    fv_log_ratelimit_tick(&rl); /* nothing yet */
    for (int i = 0; i < 7; i++) FV_ERROR_RL(&rl, "hid", "report %d bad", i);
    fv_clock_sim_advance(&clk, 4 * FV_NS_PER_S);
    fv_log_ratelimit_tick(&rl); /* the window is not over */
    assert_int_equal(fv_test_log_lines("more like this", NULL), 0);
    fv_clock_sim_advance(&clk, FV_NS_PER_S);
    fv_log_ratelimit_tick(&rl);
    fv_assert_log_contains("error hid: ... 5 more like this in the last 5.0 s; the first: report 2 bad");
    fv_log_ratelimit_tick(&rl);
    fv_log_ratelimit_flush(&rl); /* nothing counted since: no second summary */
    assert_int_equal(fv_test_log_lines("more like this", NULL), 1);
    fv_clock_sim_advance(&clk, 60 * FV_NS_PER_S);
    FV_ERROR_RL(&rl, "hid", "report %d bad", 7);
    fv_test_log_capture_end();
    fv_assert_log_contains("report 7 bad");
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_ERROR), 2 + 1 + 1);
    /* below the module's level: neither shown nor counted */
    FV_LOG_RL(&rl, FV_LOG_LEVEL_DEBUG, "hid", "hidden");
    assert_true(fv_log_ratelimit_suppressed(&rl) == 5);
    /* a static limit at a call site */
    static fv_log_ratelimit site = FV_LOG_RATELIMIT_INIT(3, 1);
    fv_test_log_capture_begin();
    for (int i = 0; i < 50; i++) FV_WARN_RL(&site, "usb", "read failed");
    fv_log_ratelimit_flush(&site);
    fv_test_log_capture_end();
    fv_assert_log_contains("... 47 more like this in the last");
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_WARN), 4);
}

/* Shared by threads (a driver's reader thread and another): the counts stay exact. */
typedef struct rl_thread_arg {
    fv_log_ratelimit *rl;
    int n;
} rl_thread_arg;

static void *rl_thread(void *p)
{
    rl_thread_arg *a = p;
    for (int i = 0; i < a->n; i++) FV_WARN_RL(a->rl, "pupil", "from a thread");
    return NULL;
}

static void a_rate_limit_is_exact_across_threads(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fv_log_ratelimit rl;
    fv_log_ratelimit_init(&rl, 5, FV_NS_PER_S, &clk);
    fv_test_log_capture_begin();
    pthread_t th[4];
    rl_thread_arg arg = {&rl, 5000};
    for (int i = 0; i < 4; i++) assert_int_equal(pthread_create(&th[i], NULL, rl_thread, &arg), 0);
    for (int i = 0; i < 4; i++) pthread_join(th[i], NULL);
    fv_log_ratelimit_flush(&rl);
    fv_test_log_capture_end();
    unsigned long long summarised = 0;
    assert_int_equal(fv_test_log_lines("more like this", &summarised), 1);
    assert_true(summarised == 20000 - 5);
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_WARN), 6);
}

static void result_names_are_distinct(void **state)
{
    (void)state;
    assert_string_equal(fv_result_str(FV_ERR_PARSE), "FV_ERR_PARSE");
    assert_string_equal(fv_result_str((fv_result)-999), "FV_RESULT_UNKNOWN");
}

int main(void)
{
    setenv("FOVEA_LOG", "trace_mod=trace,bogus", 1);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sink_receives_errors_and_warnings_with_module),
        cmocka_unit_test(module_level_enables_debug_for_that_module_only),
        cmocka_unit_test(result_names_are_distinct),
        cmocka_unit_test(a_load_budget_shows_a_few_of_each_kind_then_one_summary),
        cmocka_unit_test(a_rate_limit_bounds_lines_per_window_and_counts_the_rest),
        cmocka_unit_test(a_rate_limit_summarises_at_tick_and_starts_over),
        cmocka_unit_test(a_rate_limit_is_exact_across_threads),
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    if (!fv_log_enabled("trace_mod", FV_LOG_LEVEL_TRACE)) rc = 1;
    return rc;
}
