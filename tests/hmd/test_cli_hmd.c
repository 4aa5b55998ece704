/* @brief `fovea run --hmd` and `--budget` as a user meets them: a named profile's lens, mask and field of view in the
 * JSON summary (validation clean), the budget's ladder and counts, every bad profile or option refused with one line
 * naming the file, the field or the value. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <string.h>

#include "fv_test.h"

static const char *g_fovea;

static fv_test_cmd *run(const char *env, const char *args)
{
    static fv_test_cmd res;
    fv_test_run_cmd(&res, env, g_fovea, args);
    return &res;
}

static void a_named_profile_distorts_masks_and_is_in_the_summary(void **state)
{
    (void)state;
    fv_test_cmd *r = run("FOVEA_VALIDATION=1", "run --hmd htc-vive --eye-size 64x72 --frames 2 --explain --json");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    cJSON *j = cJSON_Parse(r->out);
    if (!j) fail_msg("not JSON:\n%s", r->out);
    cJSON *h = cJSON_GetObjectItem(j, "hmd");
    assert_string_equal(cJSON_GetObjectItem(h, "name")->valuestring, "htc-vive");
    assert_true(cJSON_IsTrue(cJSON_GetObjectItem(h, "fov_applied")));
    assert_int_equal(cJSON_GetObjectItem(h, "refresh_hz")->valuedouble, 90);
    cJSON *m = cJSON_GetObjectItem(h, "masked_fraction");
    assert_int_equal(cJSON_GetArraySize(m), 2);
    assert_true(cJSON_GetArrayItem(m, 0)->valuedouble > 0.0 && cJSON_GetArrayItem(m, 0)->valuedouble < 0.2);
    assert_string_equal(cJSON_GetObjectItem(cJSON_GetObjectItem(j, "budget"), "mode")->valuestring, "off");
    assert_int_equal(cJSON_GetObjectItem(j, "validation_messages")->valueint, 0);
    fv_assert_contains(r->err, "distort      lens pre-distortion");
    fv_assert_contains(r->err, "hidden-area mask of the HMD lens");
    cJSON_Delete(j);
    /* off: the plan says why */
    r = run(NULL, "run --hmd none --eye-size 32x32 --explain");
    assert_int_equal(r->exit_code, 0);
    fv_assert_contains(r->out, "off — no HMD lens in the frame");
    r = run(NULL, "run --set distort.enabled=off --eye-size 32x32 --explain");
    assert_int_equal(r->exit_code, 0);
    fv_assert_contains(r->out, "off — distort.enabled is off");
}

static void the_budget_reports_its_ladder_and_changes(void **state)
{
    (void)state;
    /* a budget no frame can meet: every rung is applied, one change per window, each counted */
    fv_test_cmd *r = run(NULL, "run --quality high --set gi.enabled=off --eye-size 32x32 --frames 40 --budget auto "
                               "--budget-scale 0.01 --json");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    cJSON *j = cJSON_Parse(r->out);
    if (!j) fail_msg("not JSON:\n%s", r->out);
    cJSON *b = cJSON_GetObjectItem(j, "budget");
    assert_string_equal(cJSON_GetObjectItem(b, "mode")->valuestring, "auto");
    int rungs = cJSON_GetArraySize(cJSON_GetObjectItem(b, "rungs"));
    assert_true(rungs >= 3);
    assert_string_equal(cJSON_GetArrayItem(cJSON_GetObjectItem(b, "rungs"), 0)->valuestring, "shadow.resolution=2048");
    int level = cJSON_GetObjectItem(b, "level")->valueint;
    assert_true(level >= 1 && level <= rungs);
    assert_int_equal(cJSON_GetObjectItem(b, "changes")->valueint, level);
    assert_int_equal(cJSON_GetObjectItem(b, "ups")->valueint, 0);
    assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(b, "log")), level);
    assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(b, "applied")), level);
    cJSON_Delete(j);
}

static void bad_profiles_and_options_are_refused_with_one_line(void **state)
{
    (void)state;
    fv_test_cmd *r = run(NULL, "run --hmd /nonexistent/x.json --eye-size 32x32");
    assert_int_equal(r->exit_code, 1);
    fv_assert_contains(fv_test_first_line(r->err), "fovea run: --hmd: /nonexistent/x.json: no such HMD profile");
    const char *folding = "{\"format\": \"fovea-hmd 1\", \"name\": \"fold\", \"description\": \"d\", \"sources\": {"
                          "\"panel\": \"x\", \"refresh_hz\": \"x\", \"lens_geometry\": \"x\", \"eye_to_screen\": \"x\", "
                          "\"k\": \"x\", \"aberration\": \"x\", \"visible_radius\": \"x\", \"fov\": \"x\"}, "
                          "\"panel\": {\"width_px\": 2160, \"height_px\": 1200, \"width_m\": 0.12, \"height_m\": 0.068, "
                          "\"refresh_hz\": 90}, \"lens\": {\"separation_m\": 0.056, \"vertical_position_m\": 0.032, "
                          "\"eye_to_screen_m\": 0.023, \"k\": [1, 0, -1.2, 0], \"aberration\": [1, 1, 1], "
                          "\"visible_radius\": 0}, \"fov\": {}}";
    const char *path = fv_test_write_file("fold.json", folding, strlen(folding));
    char args[1200];
    snprintf(args, sizeof args, "run --hmd %s --eye-size 32x32", path);
    r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    fv_assert_contains(r->err, "fold.json: lens.k: the radial mapping");
    fv_assert_contains(r->err, "folds");
    r = run(NULL, "run --budget sometimes");
    assert_int_equal(r->exit_code, 2);
    fv_assert_contains(fv_test_first_line(r->err), "--budget: 'sometimes' is not one of auto, off");
    r = run(NULL, "run --budget-scale 2");
    assert_int_equal(r->exit_code, 2);
    r = run(NULL, "run --budget auto --budget-scale 0");
    assert_int_equal(r->exit_code, 2);
    fv_assert_contains(fv_test_first_line(r->err), "--budget-scale: '0'");
    r = run(NULL, "bench --hmd nope --sweep shadow.splits=1");
    assert_int_equal(r->exit_code, 1);
    fv_assert_contains(r->err, "fovea bench: --hmd: nope: no such HMD profile");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_cli_hmd PATH-TO-FOVEA\n");
        return 2;
    }
    g_fovea = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_named_profile_distorts_masks_and_is_in_the_summary),
        cmocka_unit_test(the_budget_reports_its_ladder_and_changes),
        cmocka_unit_test(bad_profiles_and_options_are_refused_with_one_line),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
