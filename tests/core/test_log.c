/* @brief Logging: the replaceable sink, module levels, FOVEA_LOG parsing. */
#include <stdlib.h>
#include <string.h>

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
    };
    int rc = cmocka_run_group_tests(tests, NULL, NULL);
    if (!fv_log_enabled("trace_mod", FV_LOG_LEVEL_TRACE)) rc = 1;
    return rc;
}
