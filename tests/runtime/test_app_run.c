/* @brief The description of a run (runtime/app/fv_app_run.h), the one `fovea run`, `bench`, `reference` and the OpenXR
 * runtime fill: its defaults are the commands' documented ones (cornell, 720x800, side by side, balanced, the generic
 * HMD, no gaze, head trace, budget off); the quality is the preset then each knob in order, and a refused one is
 * named by its index (the preset: -1) with the knob table's reason; the view settings follow the knobs; the head
 * modes and the one-word budget (FOVEA_XR_BUDGET) parse to what the CLI's options mean, and refuse anything else. */
#include <math.h>
#include <string.h>

#include "fv_app_run.h"
#include "fv_knobs.h"
#include "fv_test.h"

static void defaults_are_the_commands(void **state)
{
    (void)state;
    fv_app_run r;
    memset(&r, 0x5a, sizeof r);
    fv_app_run_defaults(&r);
    assert_string_equal(r.scene, "cornell");
    assert_int_equal(r.eye_w, 720);
    assert_int_equal(r.eye_h, 800);
    assert_true(r.sbs);
    assert_null(r.quality.preset);
    assert_int_equal(r.quality.set_count, 0);
    assert_string_equal(fv_app_quality_choice_preset(&r.quality), "balanced");
    assert_null(r.hmd);
    assert_null(r.gaze_uri);
    assert_int_equal(r.head, FV_APP_HEAD_TRACE);
    assert_false(r.budget);
    assert_true(r.budget_scale == 0.0);
    fv_quality q, d = fv_quality_default();
    int failed = 7;
    char err[256];
    assert_int_equal(fv_app_run_quality(&r, &q, &failed, err, sizeof err), FV_OK);
    assert_int_equal(failed, -1);
    assert_true(fv_quality_equal(&q, &d));
}

static void quality_is_the_preset_then_each_knob_in_order(void **state)
{
    (void)state;
    fv_app_run r;
    fv_app_run_defaults(&r);
    r.quality.preset = "fast";
    assert_true(fv_app_quality_choice_add(&r.quality, "shadow.splits=3"));
    assert_true(fv_app_quality_choice_add(&r.quality, "shadow.splits=5")); /* the later one wins */
    r.exposure = 2.0f;
    r.view = FV_DEBUG_VIEW_NORMAL;
    fv_quality q, fast;
    int failed;
    char err[256];
    assert_int_equal(fv_app_run_quality(&r, &q, &failed, err, sizeof err), FV_OK);
    assert_int_equal(fv_quality_preset("fast", &fast, err, sizeof err), FV_OK);
    assert_int_equal(q.shadow.splits, 5);
    assert_true(q.exposure == 2.0f);
    assert_int_equal(q.debug_view, FV_DEBUG_VIEW_NORMAL);
    q.shadow.splits = fast.shadow.splits;
    q.exposure = fast.exposure;
    q.debug_view = fast.debug_view;
    assert_true(fv_quality_equal(&q, &fast)); /* nothing else moved */

    /* a refused knob: its index and the table's reason, naming the knob */
    assert_true(fv_app_quality_choice_add(&r.quality, "shadow.splits=99"));
    err[0] = 0;
    assert_int_not_equal(fv_app_run_quality(&r, &q, &failed, err, sizeof err), FV_OK);
    assert_int_equal(failed, 2);
    assert_non_null(strstr(err, "shadow.splits"));
    /* a refused preset: -1 */
    r.quality.preset = "fastest";
    assert_int_not_equal(fv_app_run_quality(&r, &q, &failed, err, sizeof err), FV_OK);
    assert_int_equal(failed, -1);
    assert_non_null(strstr(err, "fastest"));
}

static void the_knob_list_is_bounded(void **state)
{
    (void)state;
    fv_app_quality_choice c = {0};
    for (int i = 0; i < FV_APP_RUN_MAX_SETS; i++) assert_true(fv_app_quality_choice_add(&c, "shadow.splits=2"));
    assert_false(fv_app_quality_choice_add(&c, "shadow.splits=2"));
    assert_int_equal(c.set_count, FV_APP_RUN_MAX_SETS);
}

static void head_and_sizes(void **state)
{
    (void)state;
    const char *names[] = {"trace", "scene", "fixed"};
    for (int i = 0; i < 3; i++) {
        fv_app_head h = FV_APP_HEAD_TRACE;
        assert_true(fv_app_head_parse(names[i], &h));
        assert_int_equal(h, i);
        assert_string_equal(fv_app_head_name(h), names[i]);
    }
    fv_app_head h = FV_APP_HEAD_SCENE;
    assert_false(fv_app_head_parse("Trace", &h));
    assert_false(fv_app_head_parse("", &h));
    assert_int_equal(h, FV_APP_HEAD_SCENE);
    assert_true(fv_app_run_eye_size_valid(1, 1));
    assert_true(fv_app_run_eye_size_valid(FV_APP_RUN_MAX_EYE_SIZE, FV_APP_RUN_MAX_EYE_SIZE));
    assert_false(fv_app_run_eye_size_valid(0, 16));
    assert_false(fv_app_run_eye_size_valid(16, FV_APP_RUN_MAX_EYE_SIZE + 1));
}

static void budget_word(void **state)
{
    (void)state;
    fv_app_run r;
    fv_app_run_defaults(&r);
    char err[128];
    assert_int_equal(fv_app_run_budget_parse(&r, NULL, err, sizeof err), FV_OK);
    assert_true(r.budget);
    assert_int_equal(fv_app_run_budget_parse(&r, "off", err, sizeof err), FV_OK);
    assert_false(r.budget);
    assert_int_equal(fv_app_run_budget_parse(&r, "auto", err, sizeof err), FV_OK);
    assert_true(r.budget);
    assert_true(r.budget_scale == 0.0);
    assert_int_equal(fv_app_run_budget_parse(&r, "10", err, sizeof err), FV_OK);
    assert_true(r.budget && r.budget_scale == 10.0);
    const char *bad[] = {"0.001", "1001", "nan", "inf", "10x", "on", "-1"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        err[0] = 0;
        assert_int_equal(fv_app_run_budget_parse(&r, bad[i], err, sizeof err), FV_ERR_INVALID_ARG);
        assert_string_equal(err, "expected auto, off or a period scale in 0.01..1000");
        assert_true(r.budget && r.budget_scale == 10.0); /* unchanged */
    }
    assert_true(fv_app_run_budget_scale_valid(FV_APP_RUN_BUDGET_SCALE_MIN));
    assert_true(fv_app_run_budget_scale_valid(FV_APP_RUN_BUDGET_SCALE_MAX));
    assert_false(fv_app_run_budget_scale_valid(NAN));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(defaults_are_the_commands),
        cmocka_unit_test(quality_is_the_preset_then_each_knob_in_order),
        cmocka_unit_test(the_knob_list_is_bounded),
        cmocka_unit_test(head_and_sizes),
        cmocka_unit_test(budget_word),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
