/* @brief `fovea devices` and `fovea latency` as a user runs them: plain "no eye trackers attached", JSON that matches
 * the text, the latency budget on the simulated eye, missed frames when the render is over budget, deterministic
 * output, replay of a real recording, a source that outruns the display (latency bounded, stale samples dropped and
 * counted), a sim counter too narrow for its rate refused, and exit codes 2 (bad command line) and 1 (device cannot
 * open); frame logs that are no frame logs (a FIFO, a directory, a device, an over-long header, out-of-range or
 * overflowing values) refused with file:line and the reason. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fv_test.h"

static const char *g_fovea;

typedef fv_test_cmd run_result;

static void run(run_result *res, const char *args) { fv_test_run_cmd(res, NULL, g_fovea, args); }

#define assert_contains fv_assert_contains

static double num(const cJSON *o, const char *key)
{
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!cJSON_IsNumber(x)) fail_msg("JSON has no number \"%s\"", key);
    return x->valuedouble;
}

static void devices_lists_drivers_and_says_when_no_tracker_is_attached(void **state)
{
    (void)state;
    static run_result text, json;
    run(&text, "devices");
    assert_int_equal(text.exit_code, 0);
    run(&json, "devices --json");
    assert_int_equal(json.exit_code, 0);
    cJSON *root = cJSON_Parse(json.out);
    assert_non_null(root);
    const cJSON *drivers = cJSON_GetObjectItemCaseSensitive(root, "drivers");
    assert_true(cJSON_IsArray(drivers));
    int n = cJSON_GetArraySize(drivers);
    assert_true(n >= 1);
    /* virtual drivers come last */
    bool seen_virtual = false;
    for (int i = 0; i < n; i++) {
        const cJSON *d = cJSON_GetArrayItem(drivers, i);
        bool hw = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(d, "hardware"));
        if (!hw) seen_virtual = true;
        else assert_false(seen_virtual);
        assert_contains(text.out, cJSON_GetObjectItemCaseSensitive(d, "scheme")->valuestring);
    }
    if (num(root, "eye_trackers") == 0) {
        assert_false(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(root, "eye_trackers_attached")));
        assert_contains(text.out, "no eye trackers attached");
    } else {
        assert_contains(text.out, "attached");
    }
    cJSON_Delete(root);
}

static void devices_refuses_unknown_arguments(void **state)
{
    (void)state;
    static run_result r;
    run(&r, "devices --list");
    assert_int_equal(r.exit_code, 2);
    assert_contains(r.err, "fovea devices: unknown argument '--list'");
    assert_contains(r.err, "usage: fovea devices");
}

static void latency_on_the_simulated_eye_meets_the_budget(void **state)
{
    (void)state;
    static run_result r, again;
    run(&r, "latency --gaze sim:seed=1,rate_hz=250,latency_ms=4 --hz 90 --render-ms 5 --frames 600 --json");
    assert_int_equal(r.exit_code, 0);
    cJSON *root = cJSON_Parse(r.out);
    assert_non_null(root);
    const cJSON *g = cJSON_GetObjectItemCaseSensitive(root, "gaze_to_photon_ms");
    double p50 = num(g, "p50"), p95 = num(g, "p95"), p99 = num(g, "p99");
    print_message("sim:seed=1 at 90 Hz, 5 ms render: p50 %.2f p95 %.2f p99 %.2f ms\n", p50, p95, p99);
    assert_true(p50 > 0 && p50 <= p95 && p95 <= p99);
    assert_true(p99 <= 2 * 1000.0 / 90.0 + 4.0);
    assert_true(num(root, "tracker_latency_ms") == 4.0);
    assert_true(num(root, "missed") == 0);
    assert_true(num(root, "frames") == 600);
    assert_true(num(root, "frames_with_gaze") >= 590);
    /* the stage shares cover the whole latency */
    const cJSON *stages = cJSON_GetObjectItemCaseSensitive(root, "stages"), *st;
    double share = 0, mean = 0;
    cJSON_ArrayForEach(st, stages)
    {
        share += num(st, "share");
        mean += num(st, "mean_ms");
    }
    assert_true(fabs(share - 1.0) < 1e-9);
    assert_true(fabs(mean - num(g, "mean")) < 1e-6);
    cJSON_Delete(root);
    run(&again, "latency --gaze sim:seed=1,rate_hz=250,latency_ms=4 --hz 90 --render-ms 5 --frames 600 --json");
    assert_string_equal(again.out, r.out); /* simulated clock: the same numbers every run */
}

static void latency_reports_missed_frames_when_the_render_is_over_budget(void **state)
{
    (void)state;
    static run_result r;
    run(&r, "latency --gaze sim:seed=2 --hz 90 --render-ms 20 --frames 300 --json");
    assert_int_equal(r.exit_code, 0);
    cJSON *root = cJSON_Parse(r.out);
    assert_non_null(root);
    assert_true(num(root, "missed") >= 290);
    assert_true(fabs(num(root, "frame_interval_mean_ms") - 2 * 1000.0 / 90.0) < 0.1); /* every other refresh */
    const cJSON *g = cJSON_GetObjectItemCaseSensitive(root, "gaze_to_photon_ms");
    assert_true(num(g, "max") < 20.0 + 3 * 1000.0 / 90.0 + 10.0); /* bounded: no queue builds up */
    cJSON_Delete(root);
    static run_result text;
    run(&text, "latency --gaze sim:seed=2 --hz 90 --render-ms 20 --frames 300");
    assert_int_equal(text.exit_code, 0);
    assert_contains(text.out, "repeated refreshes");
    assert_contains(text.out, "gaze-to-photon  p50");
}

static void latency_replays_a_real_recording(void **state)
{
    (void)state;
    static run_result r;
    char args[1024];
    snprintf(args, sizeof args, "latency --gaze trace:%s --frames 200 --json",
             fv_test_data("gaze/pupil_invisible/gaze.csv"));
    run(&r, args);
    assert_int_equal(r.exit_code, 0);
    cJSON *root = cJSON_Parse(r.out);
    assert_non_null(root);
    assert_true(num(root, "frames_with_gaze") >= 190);
    cJSON_Delete(root);
}

/* The device object of `fovea latency --json`: read = delivered + dropped (overruns), and some were dropped. */
static void assert_drops_counted(const cJSON *root)
{
    const cJSON *dev = cJSON_GetObjectItemCaseSensitive(root, "device");
    assert_non_null(dev);
    assert_true(num(dev, "overruns") > 0);
    assert_true(num(dev, "samples") == num(dev, "delivered") + num(dev, "overruns"));
    assert_true(num(dev, "poll_limited") == 0);
}

static void latency_stays_bounded_when_the_source_outruns_the_display(void **state)
{
    (void)state;
    /* 1200 Hz into a 1 Hz display: 1200 samples a frame, 512 fit the ring. Bound: 4 ms tracker + one sample + the
     * lead (half a period on the first frame) + mid-scan-out (475 ms) + persistence. */
    static run_result r;
    run(&r, "latency --gaze sim:seed=1,rate_hz=1200 --hz 1 --frames 30 --json");
    assert_int_equal(r.exit_code, 0);
    cJSON *root = cJSON_Parse(r.out);
    assert_non_null(root);
    const cJSON *g = cJSON_GetObjectItemCaseSensitive(root, "gaze_to_photon_ms");
    assert_true(num(g, "max") < 1000.0);
    assert_true(num(g, "p50") < 500.0);
    assert_drops_counted(root);
    cJSON_Delete(root);
    /* a 200 Hz recording replayed 1000 times faster: 2200 samples a frame at 90 Hz */
    char args[1024];
    snprintf(args, sizeof args, "latency --gaze 'trace:%s?speed=1000&loop=1' --frames 200 --json",
             fv_test_data("gaze/pupil_invisible/gaze.csv"));
    run(&r, args);
    assert_int_equal(r.exit_code, 0);
    root = cJSON_Parse(r.out);
    assert_non_null(root);
    g = cJSON_GetObjectItemCaseSensitive(root, "gaze_to_photon_ms");
    assert_true(num(g, "max") < 2 * 1000.0 / 90.0 + 5.0);
    assert_drops_counted(root);
    cJSON_Delete(root);
    static run_result text;
    run(&text, "latency --gaze sim:seed=1,rate_hz=1200 --hz 1 --frames 5");
    assert_int_equal(text.exit_code, 0);
    assert_contains(text.out, "overruns (dropped as stale, newest kept: ring of 512)");
}

static void latency_refuses_a_sim_counter_that_wraps_faster_than_twice_the_sample_interval(void **state)
{
    (void)state;
    static run_result r;
    run(&r, "latency --gaze sim:ts_bits=8 --frames 10");
    assert_int_equal(r.exit_code, 1);
    assert_contains(r.err, "ts_bits=8 (a microsecond counter) wraps every 0.256 ms, faster than twice the sample "
                           "interval at rate_hz=120");
    assert_contains(r.err, "fovea latency: cannot open 'sim:ts_bits=8'");
    assert_null(strstr(strstr(r.err, "wraps every") + 1, "wraps every")); /* said once */
}

static void latency_command_line_errors_exit_2_and_device_errors_exit_1(void **state)
{
    (void)state;
    static run_result r;
    run(&r, "latency --hz 90");
    assert_int_equal(r.exit_code, 2);
    assert_contains(r.err, "--gaze URI is required");
    run(&r, "latency --gaze sim:seed=1 --hz fast");
    assert_int_equal(r.exit_code, 2);
    assert_contains(r.err, "--hz 'fast': expected a number in 1..1000");
    run(&r, "latency --gaze sim:seed=1 --frames 0");
    assert_int_equal(r.exit_code, 2);
    run(&r, "latency --gaze sim:seed=1 --warp 9");
    assert_int_equal(r.exit_code, 2);
    assert_contains(r.err, "unknown argument '--warp'");
    run(&r, "latency --gaze bluetooth:00:11 --frames 10");
    assert_int_equal(r.exit_code, 1);
    assert_contains(r.err, "unknown URI scheme 'bluetooth'");
    assert_contains(r.err, "fovea latency: cannot open 'bluetooth:00:11'");
    run(&r, "latency --gaze trace:/nonexistent/rec.csv --frames 10");
    assert_int_equal(r.exit_code, 1);
    assert_contains(r.err, "/nonexistent/rec.csv");
}

/* `fovea latency --frame-log F` with what is no frame log: each refused with exit 1 and one clear reason naming the
 * file (and line, column, limit where they apply), never a hang on a FIFO without a writer (run under timeout:
 * exit 124 would be the hang), never a negative or overflowed gaze-to-photon percentile. */
static void latency_frame_log_refuses_bad_files_with_file_line_and_reason(void **state)
{
    (void)state;
    static run_result r;
    char prog[1200], args[1400], fifo[1024], dir[1024];
    snprintf(prog, sizeof prog, "timeout -k 5 20 '%s'", g_fovea);
    snprintf(fifo, sizeof fifo, "%s", fv_test_tmp("nowriter.csv"));
    unlink(fifo);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    snprintf(dir, sizeof dir, "%s", fv_test_tmp("logdir.csv"));
    mkdir(dir, 0700);
    static const char head[] = "frame_id,has_gaze,fresh_gaze,late,device_lost,t_sample_capture_ns,t_photon_ns,"
                               "t_vsync_ns,repeated_vsyncs\n";
    char text[8192];
    snprintf(text, sizeof text, "%s0,1,1,0,0,100,200,150,0\n1,1,1,0,0,100,200,150,4294967296\n", head);
    char rep[1024], ovf[1024], neg[1024], longh[1024]; /* fv_test_tmp's buffers are reused: copies */
    snprintf(rep, sizeof rep, "%s", fv_test_write_file("rep.csv", text, strlen(text)));
    snprintf(text, sizeof text, "%s0,1,1,0,0,-9223372036854775000,9223372036854775000,5,0\n", head);
    snprintf(ovf, sizeof ovf, "%s", fv_test_write_file("ovf.csv", text, strlen(text)));
    snprintf(text, sizeof text, "%s0,1,1,0,0,300,200,150,0\n", head);
    snprintf(neg, sizeof neg, "%s", fv_test_write_file("neg.csv", text, strlen(text)));
    memset(text, 'x', 5000);
    memcpy(text, "frame_id,", 9);
    text[5000] = '\n';
    snprintf(longh, sizeof longh, "%s", fv_test_write_file("longhead.csv", text, 5001));
    struct {
        const char *path, *why;
    } cases[] = {
        {fifo, "nowriter.csv: not a regular file: it is a FIFO"},
        {dir, "logdir.csv: not a regular file: it is a directory"},
        {"/dev/zero", "/dev/zero: not a regular file: it is a character device"},
        {longh, "longhead.csv:1: the header line is 5000 bytes, longer than the limit of 4094"},
        {rep, "rep.csv:3:9: column 'repeated_vsyncs' is 4294967296, outside 0..4294967295"},
        {ovf, "ovf.csv:2: a gaze-to-photon latency past the 64-bit ns range (t_photon_ns 9223372036854775000, "
              "t_sample_capture_ns -9223372036854775000)"},
        {neg, "neg.csv:2: photons before the sample was captured: a negative gaze-to-photon latency"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(args, sizeof args, "latency --frame-log '%s' --json", cases[i].path);
        fv_test_run_cmd(&r, NULL, prog, args);
        if (r.exit_code != 1) fail_msg("case %zu exited %d, not 1:\n%s", i, r.exit_code, r.err);
        assert_contains(r.err, cases[i].why);
        assert_null(strstr(r.err, "runtime error"));
        assert_int_equal(r.out[0], '\0');
    }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s PATH_TO_FOVEA\n", argv[0]);
        return 2;
    }
    g_fovea = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(devices_lists_drivers_and_says_when_no_tracker_is_attached),
        cmocka_unit_test(devices_refuses_unknown_arguments),
        cmocka_unit_test(latency_on_the_simulated_eye_meets_the_budget),
        cmocka_unit_test(latency_reports_missed_frames_when_the_render_is_over_budget),
        cmocka_unit_test(latency_replays_a_real_recording),
        cmocka_unit_test(latency_stays_bounded_when_the_source_outruns_the_display),
        cmocka_unit_test(latency_refuses_a_sim_counter_that_wraps_faster_than_twice_the_sample_interval),
        cmocka_unit_test(latency_command_line_errors_exit_2_and_device_errors_exit_1),
        cmocka_unit_test(latency_frame_log_refuses_bad_files_with_file_line_and_reason),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
