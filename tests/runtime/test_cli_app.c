/* @brief The application layer as a user meets it through `fovea` (label cli: the release build):
 * - a driver plugged into the one driver list (FOVEA_DRIVERS: the test-only probe plug-in) is listed by
 *   `fovea devices` and followed by `fovea run --gaze`; paths that are no plug-ins are skipped with one line each (tests/xr/test_xr_gaze.c: the same plug-in in an OpenXR app);
 * - `fovea run --gaze pupil:` with no Pupil Capture fails before any rendering work, naming the source;
 * - a progress line (frames completed and submitted, GPU ms so far, time left) for long runs, `reference` and
 *   `bench`, its baselines (the exact preset, the CPU reference) included (FOVEA_PROGRESS=0 shows it at once, as a
 *   terminal would after 2 s);
 * - a --gaze run on a software device starts at the interactive size with the budget on, saying so in one line, and
 *   not when the size is given;
 * - --head trace with a recording whose head pose is all zero, or never changes, says so;
 * - `fovea latency --frame-log` books a software device's GPU time as GPU even in a log whose run booked it as CPU.
 * argv[1] = fovea, argv[2] = the probe plug-in, argv[3] = a shared object that is no plug-in. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_test.h"

static const char *g_fovea, *g_plugin, *g_not_plugin;

#define assert_contains fv_assert_contains

static void run_env(fv_test_cmd *res, const char *env, const char *args) { fv_test_run_cmd(res, env, g_fovea, args); }

static const cJSON *item(const cJSON *o, const char *key)
{
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!x) fail_msg("JSON has no \"%s\"", key);
    return x;
}

static void plugged_in_driver_is_listed_and_followed_by_run(void **state)
{
    (void)state;
    static fv_test_cmd dev, run;
    char env[1200];
    snprintf(env, sizeof env, "FOVEA_DRIVERS='%s'", g_plugin);
    run_env(&dev, env, "devices");
    assert_int_equal(dev.exit_code, 0);
    assert_contains(dev.out, "probe");
    /* paths that are no plug-ins are skipped, one line each, and the rest still load */
    static fv_test_cmd bad;
    char benv[2600];
    snprintf(benv, sizeof benv, "FOVEA_DRIVERS='/nonexistent/x.so:%s:%s:%s'", g_not_plugin, g_plugin, g_plugin);
    run_env(&bad, benv, "devices");
    print_message("%s", bad.err);
    assert_int_equal(bad.exit_code, 0);
    assert_contains(bad.err, "'/nonexistent/x.so': cannot load");
    assert_contains(bad.err, "no symbol fv_driver_plugin"); /* a shared object, not a plug-in */
    assert_contains(bad.err, "its scheme is already taken: probe"); /* the same plug-in twice */
    assert_contains(bad.out, "probe");
        run_env(&run, env, "run --gaze probe:yaw_deg=9,pitch_deg=2,rate_hz=500 --frames 2 --eye-size 16x16 --json");
    if (run.exit_code != 0) fail_msg("run failed:\n%s", run.err);
    cJSON *j = cJSON_Parse(run.out);
    assert_non_null(j);
    const cJSON *g = item(j, "gaze");
    assert_string_equal(item(g, "uri")->valuestring, "probe:yaw_deg=9,pitch_deg=2,rate_hz=500");
    assert_string_equal(item(g, "state")->valuestring, "connected");
    assert_true(item(g, "delivered")->valuedouble > 0);
    assert_true(item(item(j, "latency"), "frames_with_gaze")->valuedouble >= 1);
    cJSON_Delete(j);
}

static void missing_pupil_capture_fails_before_rendering(void **state)
{
    (void)state;
    static fv_test_cmd r;
    /* a port nothing listens on; info level: the renderer would log its device */
    run_env(&r, "FOVEA_LOG='*=info'", "run --gaze pupil:127.0.0.1:9 --frames 2 --eye-size 16x16");
    print_message("%s", r.err);
    assert_int_equal(r.exit_code, 1);
    assert_contains(r.err, "cannot open gaze source 'pupil:127.0.0.1:9'");
    assert_null(strstr(r.err, "vk: device")); /* no Vulkan device was made */
    assert_null(strstr(r.err, "uploaded"));   /* no scene was loaded into a renderer */
}

static void long_work_shows_progress_with_gpu_time_and_time_left(void **state)
{
    (void)state;
    static fv_test_cmd r;
    run_env(&r, "FOVEA_PROGRESS=0", "run --frames 3 --eye-size 16x16");
    print_message("%s", r.err);
    assert_int_equal(r.exit_code, 0);
    assert_contains(r.err, "fovea run: 0/3 frames done");
    assert_contains(r.err, "fovea run: 3/3 frames done, GPU ");
    assert_contains(r.err, " ms so far");
    /* the summary labels what it measures: the loop's submit time and the completed frames' wall time */
    assert_contains(r.out, "loop per frame");
    assert_contains(r.out, "wall per frame");
    assert_contains(r.out, "(completed:");
    /* reference and bench: the same line, in their units */
    static fv_test_cmd ref, bench;
    char args[1200];
    snprintf(args, sizeof args, "reference --eye-size 16x16 --out '%s'", fv_test_tmp("ref"));
    run_env(&ref, "FOVEA_PROGRESS=0", args);
    assert_int_equal(ref.exit_code, 0);
    assert_contains(ref.err, "fovea reference: ");
    assert_contains(ref.err, " tiles done");
    snprintf(args, sizeof args, "bench --sweep shadow.splits=1,2 --frames 3 --eye-size 16x16 --reference none "
             "--exact off --out '%s'", fv_test_tmp("bench"));
    run_env(&bench, "FOVEA_PROGRESS=0", args);
    assert_int_equal(bench.exit_code, 0);
    assert_contains(bench.err, "fovea bench: 2/2 points done, GPU ");
    assert_contains(bench.err, "point 2/2 shadow.splits=2");
    /* the baselines a bench renders before its points (often most of its time) are on the line too */
    static fv_test_cmd base;
    snprintf(args, sizeof args, "bench --sweep shadow.splits=1,2 --frames 3 --eye-size 16x16 --out '%s'",
             fv_test_tmp("bench_base"));
    run_env(&base, "FOVEA_PROGRESS=0", args);
    print_message("%s", base.err);
    assert_int_equal(base.exit_code, 0);
    assert_contains(base.err, "fovea bench: 0/2 points done, 0.0 s, time left known after the first point; the exact "
                              "preset (the baseline)");
    assert_contains(base.err, "; the CPU reference");
    /* not a terminal and not asked for: no progress */
    static fv_test_cmd q;
    run_env(&q, NULL, "run --frames 2 --eye-size 16x16");
    assert_null(strstr(q.err, "frames done"));
}

static void software_device_starts_gaze_runs_interactive(void **state)
{
    (void)state;
    static fv_test_cmd r, given;
    run_env(&r, NULL, "run --gaze sim:seed=1 --frames 2 --json");
    if (r.exit_code != 0) fail_msg("run failed:\n%s", r.err);
    cJSON *j = cJSON_Parse(r.out);
    assert_non_null(j);
    const char *device = item(j, "device")->valuestring;
    bool software = strstr(device, "llvmpipe") != NULL;
    print_message("device %s: %s", device, r.err);
    if (software) {
        assert_contains(r.err, "is a software Vulkan device");
        assert_contains(r.err, "override: --eye-size");
        assert_true(item(j, "eye_width")->valuedouble < 720 && item(j, "eye_height")->valuedouble < 800);
        assert_string_equal(item(item(j, "budget"), "mode")->valuestring, "auto");
    } else {
        assert_null(strstr(r.err, "software Vulkan device"));
        assert_true(item(j, "eye_width")->valuedouble == 720);
    }
    cJSON_Delete(j);
    run_env(&given, NULL, "run --gaze sim:seed=1 --frames 1 --eye-size 16x16 --json");
    assert_int_equal(given.exit_code, 0);
    assert_null(strstr(given.err, "software Vulkan device"));
}

/* A fovea trace of 200 samples at 250 Hz (gaze ahead) whose head columns are `head` on every row. */
static const char *trace_with_head(const char *name, const char *head)
{
    static char text[65536];
    size_t n = (size_t)snprintf(text, sizeof text, "fovea-trace 1\nt_device_ns,flags,seq,c_flags,c_dir_x,c_dir_y,"
                                "c_dir_z,head_x_mm,head_y_mm,head_z_mm,head_dir_x,head_dir_y,head_dir_z\n");
    for (int i = 0; i < 200 && n < sizeof text; i++)
        n += (size_t)snprintf(text + n, sizeof text - n, "%lld,2,%d,2,0,0,-1,%s\n", (long long)i * 4000000, i, head);
    return fv_test_write_file(name, text, n);
}

static void head_trace_that_never_moves_says_so(void **state)
{
    (void)state;
    static fv_test_cmd zero, same, scene;
    char args[1200];
    snprintf(args, sizeof args, "run --gaze trace:%s --frames 2 --eye-size 16x16", trace_with_head("zero.fvt", "0,0,0,0,0,0"));
    run_env(&zero, NULL, args);
    print_message("%s", zero.err);
    assert_int_equal(zero.exit_code, 0);
    assert_contains(zero.err, "has no head pose");
    assert_contains(zero.err, "all zero");
    snprintf(args, sizeof args, "run --gaze trace:%s --frames 2 --eye-size 16x16", trace_with_head("same.fvt", "10,20,30,0,0,-1"));
    run_env(&same, NULL, args);
    assert_int_equal(same.exit_code, 0);
    assert_contains(same.err, "are all the same");
    /* --head scene: the user chose not to follow; nothing to say */
    snprintf(args, sizeof args, "run --gaze trace:%s --head scene --frames 2 --eye-size 16x16", fv_test_tmp("zero.fvt"));
    run_env(&scene, NULL, args);
    assert_int_equal(scene.exit_code, 0);
    assert_null(strstr(scene.err, "head pose"));
}

/* Column index of name in a CSV header line. */
static int column(const char *header, const char *name)
{
    int k = 0;
    for (const char *p = header; *p && *p != '\n'; k++) {
        size_t len = strcspn(p, ",\n");
        if (len == strlen(name) && !strncmp(p, name, len)) return k;
        p += len;
        if (*p == ',') p++;
    }
    fail_msg("no column %s", name);
    return -1;
}

static void latency_books_a_software_devices_gpu_time_as_gpu(void **state)
{
    (void)state;
    static fv_test_cmd r, lat;
    const char *log = fv_test_tmp("frames.csv");
    char args[1200];
    snprintf(args, sizeof args, "run --gaze sim:seed=1 --frames 3 --eye-size 16x16 --frame-log %s", log);
    run_env(&r, NULL, args);
    assert_int_equal(r.exit_code, 0);
    /* rewrite it as a run whose draw waited for the GPU inside it wrote it: submit 0.23 ms before the fence, all
     * but 1 ms of the frame in the GPU's own timestamps */
    char *text = fv_test_read_file(log, NULL);
    char *nl = strchr(text, '\n');
    assert_non_null(nl);
    int c_cpu = column(text, "t_cpu_begin_ns"), c_sub = column(text, "t_submit_ns"),
        c_gb = column(text, "t_gpu_begin_ns"), c_ge = column(text, "t_gpu_end_ns"), c_gpu = column(text, "gpu_ms");
    static char out[1 << 16];
    size_t n = (size_t)(nl + 1 - text);
    memcpy(out, text, n);
    double want_gpu = 0;
    int rows = 0;
    for (char *line = nl + 1; *line; rows++) {
        char *end = strchr(line, '\n');
        if (end) *end = '\0';
        char *f[64];
        int nf = 0;
        for (char *p = line; nf < 64;) {
            f[nf++] = p;
            char *c = strchr(p, ',');
            if (!c) break;
            *c = '\0';
            p = c + 1;
        }
        long long cpu = atoll(f[c_cpu]), ge = atoll(f[c_ge]);
        char sub[32], gpu[32];
        snprintf(sub, sizeof sub, "%lld", ge - 230000);
        snprintf(gpu, sizeof gpu, "%.6f", (double)(ge - cpu) / 1e6 - 1.0);
        want_gpu += (double)(ge - cpu) / 1e6 - 1.0;
        f[c_sub] = sub;
        f[c_gb] = sub;
        f[c_gpu] = gpu;
        for (int k = 0; k < nf; k++) n += (size_t)snprintf(out + n, sizeof out - n, "%s%s", k ? "," : "", f[k]);
        n += (size_t)snprintf(out + n, sizeof out - n, "\n");
        if (!end) break;
        line = end + 1;
    }
    free(text);
    const char *bad = fv_test_write_file("frames_cpu.csv", out, n);
    snprintf(args, sizeof args, "latency --frame-log %s --json", bad);
    run_env(&lat, NULL, args);
    if (lat.exit_code != 0) fail_msg("latency failed:\n%s", lat.err);
    cJSON *j = cJSON_Parse(lat.out);
    assert_non_null(j);
    const cJSON *st = item(j, "stages");
    double cpu = item(item(st, "cpu"), "mean_ms")->valuedouble, gpu = item(item(st, "gpu"), "mean_ms")->valuedouble;
    print_message("rewritten log: cpu %.3f ms, gpu %.3f ms (GPU timestamps %.3f ms mean)\n", cpu, gpu,
                  want_gpu / rows);
    assert_true(cpu < 1.5);
    assert_true(fabs(gpu - want_gpu / rows) < 0.01);
    cJSON_Delete(j);
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: test_cli_app FOVEA PROBE_PLUGIN NOT_A_PLUGIN\n");
        return 2;
    }
    g_fovea = argv[1];
    g_plugin = argv[2];
    g_not_plugin = argv[3];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(plugged_in_driver_is_listed_and_followed_by_run),
        cmocka_unit_test(missing_pupil_capture_fails_before_rendering),
        cmocka_unit_test(long_work_shows_progress_with_gpu_time_and_time_left),
        cmocka_unit_test(software_device_starts_gaze_runs_interactive),
        cmocka_unit_test(head_trace_that_never_moves_says_so),
        cmocka_unit_test(latency_books_a_software_devices_gpu_time_as_gpu),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
