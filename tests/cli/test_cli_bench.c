/* @brief `fovea bench` as a user runs it: a small sweep on the Cornell box writes bench.json (also on stdout with
 * --json), bench.csv and a PNG plot per swept knob; the exact preset's own point is identical to exact; sweeping the
 * presets; bad sweeps exit 2 with one line naming the knob. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_test.h"

static const char *g_fovea;
static fv_test_cmd g_res; /* the last command's result */

static fv_test_cmd *run(const char *args)
{
    fv_test_run_cmd(&g_res, NULL, g_fovea, args);
    return &g_res;
}

static const cJSON *item(const cJSON *o, const char *key)
{
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!x) fail_msg("JSON has no \"%s\"", key);
    return x;
}

/* Run a bench with --json into a fresh out dir; the parsed stdout, which must equal the bench.json written there. */
static cJSON *bench_json(const char *out_name, const char *args, const char **out_dir)
{
    const char *dir = fv_test_tmp(out_name);
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "bench %s --out %s --json", args, dir);
    fv_test_cmd *r = run(cmd);
    if (r->exit_code != 0) fail_msg("'%s' exited %d; stderr:\n%s", cmd, r->exit_code, r->err);
    cJSON *j = cJSON_Parse(r->out);
    if (!j) fail_msg("stdout is not one JSON object:\n%s", r->out);
    char path[1200];
    snprintf(path, sizeof path, "%s/bench.json", dir);
    char *text = fv_test_read_file(path, NULL);
    cJSON *file = cJSON_Parse(text);
    free(text);
    if (!file || !cJSON_Compare(j, file, true)) fail_msg("%s differs from stdout", path);
    cJSON_Delete(file);
    *out_dir = dir;
    return j;
}

/* psnr_db finite or null, ssim in [-1, 1], rel_mean >= 0; bands (5 of them) exactly when a gaze was given. */
static void check_error(const cJSON *e, bool bands)
{
    const cJSON *psnr = item(e, "psnr_db");
    assert_true(cJSON_IsNull(psnr) || (cJSON_IsNumber(psnr) && isfinite(psnr->valuedouble)));
    double ssim = item(e, "ssim")->valuedouble;
    if (!(ssim >= -1.0 && ssim <= 1.0)) fail_msg("ssim %g", ssim);
    assert_true(item(e, "rel_mean")->valuedouble >= 0.0);
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(e, "bands");
    if (!bands) {
        assert_null(b);
        return;
    }
    assert_int_equal(cJSON_GetArraySize(b), 5);
    const cJSON *band;
    cJSON_ArrayForEach(band, b)
    {
        assert_true(cJSON_IsNumber(item(band, "from_deg")) && cJSON_IsNumber(item(band, "to_deg")));
        (void)item(band, "psnr_db"), (void)item(band, "ssim"), (void)item(band, "rel_mean");
    }
}

/* Timings: every pass and the frame with median_ms > 0 and p95_ms >= median_ms. */
static void check_ms(const cJSON *ms)
{
    double med = item(ms, "median_ms")->valuedouble, p95 = item(ms, "p95_ms")->valuedouble;
    if (!(med > 0 && p95 >= med)) fail_msg("median %g, p95 %g", med, p95);
}

static void check_point(const cJSON *p, const char *const *knobs, size_t knob_count, bool reference, bool bands)
{
    const cJSON *k = item(p, "knobs");
    assert_int_equal(cJSON_GetArraySize(k), (int)knob_count);
    for (size_t i = 0; i < knob_count; i++) (void)item(k, knobs[i]);
    const cJSON *passes = item(p, "passes"), *pass;
    assert_true(cJSON_GetArraySize(passes) >= 2);
    (void)item(passes, "gbuffer"), (void)item(passes, "shade");
    cJSON_ArrayForEach(pass, passes) check_ms(pass);
    check_ms(item(p, "frame_ms"));
    check_error(item(p, "vs_exact"), bands);
    if (reference) check_error(item(p, "vs_reference"), bands);
    else assert_true(cJSON_IsNull(item(p, "vs_reference")));
}

static bool is_png(const char *path)
{
    FILE *f = fopen(path, "rb");
    unsigned char sig[8] = {0};
    bool ok = f && fread(sig, 1, 8, f) == 8 && memcmp(sig, "\x89PNG\r\n\x1a\n", 8) == 0;
    if (f) fclose(f);
    return ok;
}

static void small_sweep_writes_json_csv_and_plots(void **state)
{
    (void)state;
    const char *dir;
    cJSON *j = bench_json("bench_small",
                          "--scene cornell --eye-size 48x48 --frames 3 --sweep shadow.splits=1,2,2,01 "
                          "--sweep shadow.filter=none,pcf3 --reference model",
                          &dir);
    /* 2 and 01 repeat 2 and 1 once parsed: dropped with one warning line, not benched again */
    fv_assert_contains(g_res.err, "fovea bench: warning: --sweep shadow.splits: 2 values repeat an earlier one and "
                                  "are benched once: 2 (as 2), 01 (as 1)\n");
    assert_string_equal(item(j, "scene")->valuestring, "cornell");
    assert_true(cJSON_IsString(item(j, "device")));
    assert_int_equal((int)item(j, "eye_width")->valuedouble, 48);
    assert_int_equal((int)item(j, "eye_height")->valuedouble, 48);
    assert_string_equal(item(j, "preset")->valuestring, "balanced");
    const cJSON *ref = item(j, "reference");
    assert_string_equal(item(ref, "mode")->valuestring, "model");
    assert_true(item(ref, "seconds")->valuedouble >= 0);
    assert_true(cJSON_IsNumber(item(ref, "spp")));
    check_ms(item(item(j, "exact"), "frame_ms"));
    check_error(item(item(j, "exact"), "vs_reference"), false); /* how far exact itself is from the reference */
    const cJSON *points = item(j, "points");
    assert_int_equal(cJSON_GetArraySize(points), 4);
    const char *knobs[] = {"shadow.splits", "shadow.filter"};
    const cJSON *p;
    int i = 0;
    cJSON_ArrayForEach(p, points)
    {
        check_point(p, knobs, 2, true, false);
        /* The cross product, the last sweep fastest. */
        assert_int_equal((int)item(item(p, "knobs"), "shadow.splits")->valuedouble, i < 2 ? 1 : 2);
        assert_string_equal(item(item(p, "knobs"), "shadow.filter")->valuestring, i % 2 ? "pcf3" : "none");
        assert_true(cJSON_IsFalse(item(p, "is_preset"))); /* balanced has 4 splits */
        i++;
    }
    cJSON_Delete(j);

    char path[1200];
    snprintf(path, sizeof path, "%s/bench.csv", dir);
    char *csv = fv_test_read_file(path, NULL);
    int lines = 0;
    for (const char *c = csv; *c; c++) lines += *c == '\n';
    assert_int_equal(lines, 5);
    const char *cols[] = {"shadow.splits,shadow.filter,frame_ms_median,frame_ms_p95", "shade_median_ms",
                          "exact_psnr_db", "exact_ssim", "exact_rel_mean", "reference_psnr_db", "reference_ssim",
                          "reference_rel_mean"};
    for (size_t c = 0; c < sizeof cols / sizeof cols[0]; c++) fv_assert_contains(fv_test_first_line(csv), cols[c]);
    fv_assert_contains(csv, "\n1,none,");
    fv_assert_contains(csv, "\n2,pcf3,");
    free(csv);
    /* gnuplot is installed by the set-up (gnuplot-nox): a missing plot is a failure, not a skip. */
    const char *plots[] = {"pareto_shadow.splits.png", "pareto_shadow.filter.png"};
    for (size_t k = 0; k < 2; k++) {
        snprintf(path, sizeof path, "%s/%s", dir, plots[k]);
        if (!is_png(path)) fail_msg("%s is not a PNG (is gnuplot installed? make install-deps)", path);
    }
}

static void exact_base_point_is_identical_to_exact_and_bands_follow_the_gaze(void **state)
{
    (void)state;
    const char *dir;
    cJSON *j = bench_json("bench_exact",
                          "--scene cornell --eye-size 48x48 --frames 3 --quality exact --sweep shadow.splits=2,8 "
                          "--reference none --gaze-deg 5,-3",
                          &dir);
    assert_string_equal(item(j, "preset")->valuestring, "exact");
    assert_string_equal(item(item(j, "reference"), "mode")->valuestring, "none");
    assert_float_equal(item(item(j, "gaze"), "yaw_deg")->valuedouble, 5.0, 1e-9);
    const cJSON *points = item(j, "points");
    assert_int_equal(cJSON_GetArraySize(points), 2);
    const char *knobs[] = {"shadow.splits"};
    const cJSON *p;
    cJSON_ArrayForEach(p, points) check_point(p, knobs, 1, false, true);
    const cJSON *p8 = cJSON_GetArrayItem(points, 1);
    assert_int_equal((int)item(item(p8, "knobs"), "shadow.splits")->valuedouble, 8);
    /* Exact's own settings: the same image as the exact render (PSNR infinite, JSON null) or very close. */
    assert_true(cJSON_IsTrue(item(p8, "is_preset")));
    const cJSON *psnr = item(item(p8, "vs_exact"), "psnr_db");
    if (!cJSON_IsNull(psnr) && !(psnr->valuedouble > 60))
        fail_msg("exact's own point: %g dB vs exact", psnr->valuedouble);
    assert_true(cJSON_IsFalse(item(cJSON_GetArrayItem(points, 0), "is_preset")));
    cJSON_Delete(j);
}

static void preset_pseudo_knob_benches_the_presets(void **state)
{
    (void)state;
    const char *dir;
    cJSON *j = bench_json("bench_presets",
                          "--scene cornell --eye-size 32x32 --frames 3 --sweep preset=fast,balanced,high,exact "
                          "--reference none",
                          &dir);
    const cJSON *points = item(j, "points");
    assert_int_equal(cJSON_GetArraySize(points), 4);
    const char *knobs[] = {"preset"}, *names[] = {"fast", "balanced", "high", "exact"};
    for (int i = 0; i < 4; i++) {
        const cJSON *p = cJSON_GetArrayItem(points, i);
        check_point(p, knobs, 1, false, false);
        assert_string_equal(item(item(p, "knobs"), "preset")->valuestring, names[i]);
        assert_int_equal(cJSON_IsTrue(item(p, "is_preset")), i == 1); /* the base: balanced */
    }
    const cJSON *psnr = item(item(cJSON_GetArrayItem(points, 3), "vs_exact"), "psnr_db");
    assert_true(cJSON_IsNull(psnr) || psnr->valuedouble > 60);
    cJSON_Delete(j);
    char path[1200];
    snprintf(path, sizeof path, "%s/pareto_preset.png", dir);
    assert_true(is_png(path));
}

static void bad_sweeps_exit_2_with_one_line(void **state)
{
    (void)state;
    const char *bad[][3] = {
        {"bench --sweep shadow.splits=0", "shadow.splits", "'0' is not a whole number in 1..8"},
        {"bench --sweep shadow.splits=1,2,x", "shadow.splits", "'x'"},
        {"bench --sweep nope=1", "unknown knob 'nope'", "shadow.splits"},
        {"bench --sweep shadow.splits", "'shadow.splits'", "NAME=V1,V2"},
        {"bench --sweep preset=fast,bogus", "'bogus'", "fast, balanced, high, exact"},
        {"bench --sweep shadow.splits=1 --sweep shadow.splits=2", "shadow.splits", "swept twice"},
        {"bench --sweep shadow.splits=1,2,3,4,5,6,7,8 --sweep shadow.resolution=256,512,1024,2048,4096 "
         "--sweep shadow.filter=none,pcf3,pcf5 --sweep shadow.enabled=on,off --sweep shadow.stereo_shared=on,off",
         "480 points", "more than 256"},
        {"bench --sweep shadow.splits=1 --eye-size 8x8", "--eye-size", "11..8192"},
        {"bench --sweep shadow.splits=1 --frames 2", "--frames", "3..100000"},
        {"bench --sweep shadow.splits=1 --reference exact", "--reference", "model, path, none"},
        {"bench", "needs at least one --sweep", "NAME=V1,V2"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        fv_test_cmd *r = run(bad[i][0]);
        if (r->exit_code != 2) fail_msg("'%s' exited %d, not 2; stderr:\n%s", bad[i][0], r->exit_code, r->err);
        const char *line = fv_test_first_line(r->err);
        if (strncmp(line, "fovea bench: ", 13) != 0) fail_msg("'%s': first line \"%s\"", bad[i][0], line);
        for (int s = 1; s < 3; s++)
            if (!strstr(line, bad[i][s])) fail_msg("'%s': \"%s\" is not in \"%s\"", bad[i][0], bad[i][s], line);
        /* One line, then the usage. */
        assert_true(strncmp(r->err + strlen(line), "\nusage: fovea bench", 19) == 0);
        assert_string_equal(r->out, "");
    }
    fv_test_cmd *r = run("bench --help");
    assert_int_equal(r->exit_code, 0);
    fv_assert_contains(r->out, "usage: fovea bench");
    fv_assert_contains(r->out, "shadow.splits");
    r = run("--help");
    fv_assert_contains(r->out, "bench");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_cli_bench PATH_TO_FOVEA\n");
        return 2;
    }
    g_fovea = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(small_sweep_writes_json_csv_and_plots),
        cmocka_unit_test(exact_base_point_is_identical_to_exact_and_bands_follow_the_gaze),
        cmocka_unit_test(preset_pseudo_knob_benches_the_presets),
        cmocka_unit_test(bad_sweeps_exit_2_with_one_line),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
