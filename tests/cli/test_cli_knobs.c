/* @brief The knob table as a user meets it: `fovea knobs [--json]`, `fovea run --quality PRESET --set NAME=VALUE`
 * (one-line errors naming the knob, the value and the range; exit 2), and the quality in the run's JSON summary. */
#include <cjson/cJSON.h>
#include <stdbool.h>
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

static void knobs_lists_every_knob_with_its_presets(void **state)
{
    (void)state;
    fv_test_cmd *r = run(NULL, "knobs");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    const char *header[] = {"knob", "type", "range", "unit", "fast", "balanced", "high", "exact"};
    for (size_t i = 0; i < sizeof header / sizeof header[0]; i++)
        fv_assert_contains(fv_test_first_line(r->out), header[i]);
    const char *rows[] = {"shadow.enabled", "shadow.splits", "shadow.lambda", "shadow.resolution", "shadow.filter",
                          "shadow.bias", "shadow.stereo_shared", "256..4096, powers of two", "none|pcf3|pcf5",
                          "texels", "exact: "};
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) fv_assert_contains(r->out, rows[i]);
    r = run(NULL, "knobs --help");
    assert_int_equal(r->exit_code, 0);
    fv_assert_contains(r->out, "usage: fovea knobs");
    r = run(NULL, "knobs --bogus");
    assert_int_equal(r->exit_code, 2);
    fv_assert_contains(fv_test_first_line(r->err), "fovea knobs: unknown option '--bogus'");
    r = run(NULL, "--help");
    fv_assert_contains(r->out, "knobs");
}

static void knobs_json_lists_every_knob_with_4_presets_each(void **state)
{
    (void)state;
    fv_test_cmd *r = run(NULL, "knobs --json");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    cJSON *j = cJSON_Parse(r->out);
    if (!j) fail_msg("stdout is not JSON:\n%s", r->out);
    cJSON *presets = cJSON_GetObjectItem(j, "presets"), *knobs = cJSON_GetObjectItem(j, "knobs");
    assert_int_equal(cJSON_GetArraySize(presets), 4);
    assert_string_equal(cJSON_GetObjectItem(j, "default_preset")->valuestring, "balanced");
    /* The JSON lists exactly the knobs of the text listing (one unindented row each, after the header), each name
     * once, and every pass's group is there. */
    fv_test_cmd *t = run(NULL, "knobs");
    int rows = -1;
    for (const char *l = t->out; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL)
        if (*l != ' ' && *l != '\n') rows++;
    assert_true(rows > 0);
    assert_int_equal(cJSON_GetArraySize(knobs), rows);
    static const char *const groups[] = {"shadow.", "fovea.", "gi.", "sss.", "distort."};
    for (size_t g = 0; g < sizeof groups / sizeof groups[0]; g++) {
        int n = 0;
        const cJSON *e;
        cJSON_ArrayForEach(e, knobs) n += strncmp(cJSON_GetObjectItem(e, "name")->valuestring, groups[g],
                                                  strlen(groups[g])) == 0;
        if (n == 0) fail_msg("no %s* knob in the table", groups[g]);
    }
    const cJSON *k, *k2;
    cJSON_ArrayForEach(k, knobs) cJSON_ArrayForEach(k2, knobs) if (k != k2 &&
        strcmp(cJSON_GetObjectItem(k, "name")->valuestring, cJSON_GetObjectItem(k2, "name")->valuestring) == 0)
        fail_msg("knob %s listed twice", cJSON_GetObjectItem(k, "name")->valuestring);
    cJSON_ArrayForEach(k, knobs)
    {
        const char *name = cJSON_GetObjectItem(k, "name")->valuestring;
        assert_true(cJSON_IsString(cJSON_GetObjectItem(k, "type")));
        assert_true(cJSON_IsString(cJSON_GetObjectItem(k, "range")));
        assert_true(cJSON_IsString(cJSON_GetObjectItem(k, "unit")));
        assert_true(cJSON_IsString(cJSON_GetObjectItem(k, "doc")));
        cJSON *pv = cJSON_GetObjectItem(k, "presets");
        if (cJSON_GetArraySize(pv) != 4) fail_msg("%s: %d presets", name, cJSON_GetArraySize(pv));
        const cJSON *p;
        cJSON_ArrayForEach(p, presets) if (!cJSON_GetObjectItem(pv, p->valuestring))
            fail_msg("%s has no value for preset %s", name, p->valuestring);
        if (strcmp(name, "shadow.splits") == 0) {
            assert_int_equal((int)cJSON_GetObjectItem(pv, "fast")->valuedouble, 2);
            assert_int_equal((int)cJSON_GetObjectItem(pv, "exact")->valuedouble, 8);
            assert_int_equal((int)cJSON_GetObjectItem(k, "min")->valuedouble, 1);
            assert_int_equal((int)cJSON_GetObjectItem(k, "max")->valuedouble, 8);
        }
        if (strcmp(name, "shadow.filter") == 0) {
            assert_string_equal(cJSON_GetObjectItem(pv, "balanced")->valuestring, "pcf3");
            assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(k, "choices")), 3);
            assert_true(cJSON_IsString(cJSON_GetObjectItem(k, "exact_note")));
        }
        if (strcmp(name, "shadow.stereo_shared") == 0) assert_true(cJSON_IsFalse(cJSON_GetObjectItem(pv, "exact")));
    }
    cJSON_Delete(j);
}

static void bad_quality_options_exit_2_with_one_line_naming_the_knob(void **state)
{
    (void)state;
    const char *bad[][4] = {
        {"run --set shadow.splits=0", "shadow.splits", "'0'", "1..8"},
        {"run --set shadow.splits=abc", "shadow.splits", "'abc'", "1..8"},
        {"run --set shadow.resolution=1000", "shadow.resolution", "'1000'", "power of two in 256..4096"},
        {"run --set shadow.filter=gauss", "shadow.filter", "'gauss'", "none, pcf3, pcf5"},
        {"run --set shadow.lambda=nan", "shadow.lambda", "'nan'", "0..1"},
        {"run --set bogus.knob=1", "unknown knob 'bogus.knob'", "shadow.splits", "knobs"},
        {"run --set shadow.splits", "'shadow.splits'", "NAME=VALUE", "--set"},
        {"run --set", "--set", "needs a value", "NAME=VALUE"},
        {"run --quality bogus", "--quality", "'bogus'", "fast, balanced, high, exact"},
        {"run --quality", "--quality", "needs a value", "fast, balanced, high, exact"},
        {"run --quality fast --set shadow.splits=3 --set shadow.bias=11", "shadow.bias", "'11'", "0..10 texels"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        fv_test_cmd *r = run(NULL, bad[i][0]);
        if (r->exit_code != 2) fail_msg("'%s' exited %d, not 2; stderr:\n%s", bad[i][0], r->exit_code, r->err);
        const char *line = fv_test_first_line(r->err);
        if (strncmp(line, "fovea run: ", 11) != 0) fail_msg("'%s': first line \"%s\"", bad[i][0], line);
        for (int s = 1; s < 4; s++)
            if (!strstr(line, bad[i][s])) fail_msg("'%s': \"%s\" is not in \"%s\"", bad[i][0], bad[i][s], line);
        /* One line, then the usage, which lists the presets and points at `fovea knobs`. */
        assert_true(strncmp(r->err + strlen(line), "\nusage: fovea run", 17) == 0);
        fv_assert_contains(r->err, "fast, balanced, high, exact");
        fv_assert_contains(r->err, "`fovea knobs`");
        assert_string_equal(r->out, "");
    }
    /* --help lists the knobs from the table with their ranges and balanced defaults. */
    fv_test_cmd *r = run(NULL, "run --help");
    assert_int_equal(r->exit_code, 0);
    fv_assert_contains(r->out, "--quality");
    fv_assert_contains(r->out, "shadow.resolution");
    fv_assert_contains(r->out, "256..4096, powers of two px");
    fv_assert_contains(r->out, "[2048]");
}

static const cJSON *item(const cJSON *o, const char *key)
{
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!x) fail_msg("JSON has no \"%s\"", key);
    return x;
}

static void run_json_shows_the_preset_and_the_set_knobs(void **state)
{
    (void)state;
    fv_test_cmd *r = run("FOVEA_VALIDATION=1", "run --quality fast --set shadow.splits=3 --json --frames 1 "
                                               "--eye-size 32x32");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    cJSON *j = cJSON_Parse(r->out);
    if (!j) fail_msg("stdout is not JSON:\n%s", r->out);
    const cJSON *q = item(j, "quality");
    assert_string_equal(item(q, "preset")->valuestring, "fast");
    assert_int_equal((int)item(q, "shadow.splits")->valuedouble, 3);
    assert_int_equal((int)item(q, "shadow.resolution")->valuedouble, 1024); /* fast's, untouched by --set */
    assert_string_equal(item(q, "shadow.filter")->valuestring, "none");
    assert_true(cJSON_IsTrue(item(q, "shadow.enabled")));
    assert_float_equal(item(q, "shadow.lambda")->valuedouble, 0.5, 1e-9);
    /* The view settings stay where they were. */
    assert_float_equal(item(q, "exposure")->valuedouble, 1.0, 1e-9);
    assert_string_equal(item(q, "debug_view")->valuestring, "color"); /* the default view */
    assert_int_equal((int)item(j, "validation_messages")->valuedouble, 0);
    cJSON_Delete(j);

    /* --set applies in order after the preset wherever --quality stands; --exposure survives the preset. */
    r = run(NULL, "run --set shadow.filter=pcf5 --exposure 2 --quality exact --set shadow.filter=pcf3 --json "
                  "--frames 1 --eye-size 32x32");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    j = cJSON_Parse(r->out);
    assert_non_null(j);
    q = item(j, "quality");
    assert_string_equal(item(q, "preset")->valuestring, "exact");
    assert_string_equal(item(q, "shadow.filter")->valuestring, "pcf3");
    assert_int_equal((int)item(q, "shadow.splits")->valuedouble, 8);
    assert_true(cJSON_IsFalse(item(q, "shadow.stereo_shared")));
    assert_float_equal(item(q, "exposure")->valuedouble, 2.0, 1e-9);
    cJSON_Delete(j);

    /* Without --quality: balanced; the text summary names the preset and what --set changed. */
    r = run(NULL, "run --frames 1 --eye-size 32x32 --json");
    assert_int_equal(r->exit_code, 0);
    j = cJSON_Parse(r->out);
    assert_non_null(j);
    assert_string_equal(item(item(j, "quality"), "preset")->valuestring, "balanced");
    cJSON_Delete(j);
    r = run(NULL, "run --frames 1 --eye-size 32x32 --quality high --set shadow.splits=6");
    assert_int_equal(r->exit_code, 0);
    fv_assert_contains(r->out, "quality: high; shadow.splits=6");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_cli_knobs PATH_TO_FOVEA\n");
        return 2;
    }
    g_fovea = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(knobs_lists_every_knob_with_its_presets),
        cmocka_unit_test(knobs_json_lists_every_knob_with_4_presets_each),
        cmocka_unit_test(bad_quality_options_exit_2_with_one_line_naming_the_knob),
        cmocka_unit_test(run_json_shows_the_preset_and_the_set_knobs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
