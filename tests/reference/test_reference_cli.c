/* @brief `fovea reference` as a user runs it: images (PFM + PNG, side by side or per eye), the JSON summary, the
 * cache, and usage errors. */
#include <cjson/cJSON.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "fv_test.h"

static const char *g_fovea;

static void run(fv_test_cmd *res, const char *args) { fv_test_run_cmd(res, NULL, g_fovea, args); }

static bool file_exists(const char *dir, const char *name)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    struct stat st;
    return stat(path, &st) == 0 && st.st_size > 0;
}

static cJSON *parse_json(const fv_test_cmd *res)
{
    cJSON *j = cJSON_Parse(res->out);
    if (!j) fail_msg("stdout is not JSON:\n%s\nstderr:\n%s", res->out, res->err);
    return j;
}

static void model_mode_writes_pfm_and_png_side_by_side_and_a_json_summary(void **state)
{
    (void)state;
    static fv_test_cmd res;
    const char *out = fv_test_tmp("sbs");
    char args[1400];
    snprintf(args, sizeof args, "reference --scene cornell --eye-size 24x20 --out %s --json --threads 2", out);
    run(&res, args);
    assert_int_equal(res.exit_code, 0);
    cJSON *j = parse_json(&res);
    assert_string_equal(cJSON_GetObjectItem(j, "mode")->valuestring, "model");
    assert_int_equal(cJSON_GetObjectItem(j, "spp")->valueint, 1);
    assert_int_equal(cJSON_GetObjectItem(j, "threads")->valueint, 2);
    assert_true(cJSON_GetObjectItem(j, "rays")->valuedouble >= 2 * 24 * 20);
    assert_true(cJSON_GetObjectItem(j, "seconds")->valuedouble >= 0);
    assert_non_null(cJSON_GetObjectItem(j, "bounces"));
    assert_non_null(cJSON_GetObjectItem(j, "seed"));
    cJSON_Delete(j);
    assert_true(file_exists(out, "frame_00000.png"));
    char pfm[1200];
    snprintf(pfm, sizeof pfm, "%s/frame_00000.pfm", out);
    size_t len = 0;
    char *data = fv_test_read_file(pfm, &len);
    assert_true(strncmp(data, "PF\n48 20\n-1", 11) == 0);
    free(data);
}

static void path_mode_per_eye_and_the_cache_gives_the_same_result(void **state)
{
    (void)state;
    static fv_test_cmd res;
    const char *out = fv_test_tmp("eyes"), *cache = fv_test_tmp("cache");
    char args[1600];
    snprintf(args, sizeof args,
             "reference --scene cornell --mode path --spp 2 --bounces 1 --eye-size 16x16 --layout eyes --out %s "
             "--cache %s --json",
             out, cache);
    char rm[1200];
    snprintf(rm, sizeof rm, "-rf %s", cache); /* a cache left by an earlier run would answer the first call */
    fv_test_run_cmd(&res, NULL, "rm", rm);
    run(&res, args);
    assert_int_equal(res.exit_code, 0);
    cJSON *j = parse_json(&res);
    assert_false(cJSON_IsTrue(cJSON_GetObjectItem(j, "cached")));
    assert_true(cJSON_GetObjectItem(j, "bounce_rays")->valuedouble > 0);
    cJSON_Delete(j);
    assert_true(file_exists(out, "frame_00000_left.png") && file_exists(out, "frame_00000_right.png"));
    assert_true(file_exists(out, "frame_00000_left.pfm") && file_exists(out, "frame_00000_right.pfm"));
    char path[1200];
    snprintf(path, sizeof path, "%s/frame_00000_left.pfm", out);
    size_t n1 = 0, n2 = 0;
    char *first = fv_test_read_file(path, &n1);
    run(&res, args);
    assert_int_equal(res.exit_code, 0);
    j = parse_json(&res);
    assert_true(cJSON_IsTrue(cJSON_GetObjectItem(j, "cached")));
    cJSON_Delete(j);
    char *second = fv_test_read_file(path, &n2);
    assert_int_equal(n1, n2);
    assert_memory_equal(first, second, n1);
    free(first);
    free(second);
}

static void bad_options_exit_2_and_help_exits_0(void **state)
{
    (void)state;
    static fv_test_cmd res;
    run(&res, "reference --mode nope");
    assert_int_equal(res.exit_code, 2);
    fv_assert_contains(res.err, "--mode: 'nope' is not one of model, path");
    run(&res, "reference --spp 0");
    assert_int_equal(res.exit_code, 2);
    run(&res, "reference --view shiny");
    assert_int_equal(res.exit_code, 2);
    run(&res, "reference --help");
    assert_int_equal(res.exit_code, 0);
    fv_assert_contains(res.out, "usage: fovea reference");
    run(&res, "reference --scene /nonexistent.gltf --eye-size 8x8");
    assert_int_equal(res.exit_code, 1);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_reference_cli PATH_TO_FOVEA\n");
        return 2;
    }
    g_fovea = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(model_mode_writes_pfm_and_png_side_by_side_and_a_json_summary),
        cmocka_unit_test(path_mode_per_eye_and_the_cache_gives_the_same_result),
        cmocka_unit_test(bad_options_exit_2_and_help_exits_0),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
