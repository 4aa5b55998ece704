/* @brief The "trace" driver: replay paced by the recorded timestamps on a simulated clock (deterministic), speed,
 * loop, end of stream, real-time replay on the monotonic clock, URI errors, and record -> read back equal. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_test.h"
#include "fv_trace.h"
#include "fv_trace_driver.h"
#include "trace_test.h"

#define MS FV_NS_PER_MS

/* A fovea trace of n samples, 10 ms apart, starting at t = 1000 ns. */
static const char *make_trace(const char *name, int n)
{
    const char *path = fv_test_tmp(name);
    fv_trace_writer *w = NULL;
    assert_int_equal(fv_trace_writer_create(path, NULL, &w), FV_OK);
    for (int i = 0; i < n; i++) {
        fv_gaze_sample s;
        fv_gaze_sample_init_invalid(&s, 1000 + i * 10 * MS, 0);
        s.combined.direction = fv_v3(0, 0, -1);
        s.combined.flags = FV_EYE_DIRECTION_VALID;
        s.seq = (uint64_t)i;
        assert_int_equal(fv_trace_writer_write(w, &s), FV_OK);
    }
    assert_int_equal(fv_trace_writer_finish(&w), FV_OK);
    return path;
}

static void replay_is_paced_by_recorded_time_on_a_simulated_clock(void **state)
{
    (void)state;
    const char *path = make_trace("paced.fvt", 10);
    fv_clock clock;
    const int64_t t0 = 5 * FV_NS_PER_S;
    fv_clock_sim_init(&clock, t0);
    fv_device *dev = trace_test_open_uri("trace:%s", path, &clock);
    assert_true(fabs(dev->nominal_rate_hz - 100.0) < 1e-6);
    assert_string_equal(dev->info.driver, "trace");
    fv_gaze_sample buf[16];
    size_t n = 0;
    assert_int_equal(fv_device_read(dev, buf, 16, &n, 0), FV_OK);
    assert_int_equal(n, 1);
    assert_int_equal(buf[0].t_host_ns, t0);
    assert_int_equal(buf[0].t_device_ns, 1000);
    assert_true(buf[0].flags & FV_GAZE_HOST_TIME_VALID);
    assert_int_equal(fv_device_read(dev, buf, 16, &n, 0), FV_TIMEOUT); /* next one is due at +10 ms */
    assert_int_equal(n, 0);
    assert_int_equal(clock.sim_now_ns, t0); /* a poll does not move the clock */
    fv_clock_sim_advance(&clock, 25 * MS);
    assert_int_equal(fv_device_read(dev, buf, 16, &n, 0), FV_OK);
    assert_int_equal(n, 2);
    assert_int_equal(buf[0].t_host_ns, t0 + 10 * MS);
    assert_int_equal(buf[1].t_host_ns, t0 + 20 * MS);
    assert_int_equal(buf[1].seq, 2);
    /* a read with a timeout steps the simulated clock to the next sample */
    assert_int_equal(fv_device_read(dev, buf, 16, &n, 100), FV_OK);
    assert_int_equal(n, 1);
    assert_int_equal(buf[0].t_host_ns, t0 + 30 * MS);
    assert_int_equal(clock.sim_now_ns, t0 + 30 * MS);
    /* a timeout shorter than the wait: FV_TIMEOUT, the clock moves by the timeout */
    assert_int_equal(fv_device_read(dev, buf, 16, &n, 4), FV_TIMEOUT);
    assert_int_equal(clock.sim_now_ns, t0 + 34 * MS);
    /* cap is honoured */
    fv_clock_sim_advance(&clock, 1000 * MS);
    assert_int_equal(fv_device_read(dev, buf, 3, &n, 0), FV_OK);
    assert_int_equal(n, 3);
    assert_int_equal(fv_device_read(dev, buf, 16, &n, 0), FV_OK);
    assert_int_equal(n, 3);
    assert_int_equal(buf[2].seq, 9);
    assert_int_equal(fv_device_read(dev, buf, 16, &n, 0), FV_END_OF_STREAM);
    assert_int_equal(n, 0);
    assert_int_equal(fv_device_read(dev, buf, 16, &n, 100), FV_END_OF_STREAM);
    fv_device_close(&dev);
    assert_null(dev);
}

static void speed_scales_pacing_and_device_time(void **state)
{
    (void)state;
    const char *path = make_trace("speed.fvt", 10);
    fv_clock clock;
    fv_clock_sim_init(&clock, 0);
    fv_device *dev = trace_test_open_uri("trace:%s?speed=2", path, &clock);
    assert_true(fabs(dev->nominal_rate_hz - 200.0) < 1e-6);
    fv_gaze_sample s;
    size_t n;
    for (int i = 0; i < 10; i++) {
        assert_int_equal(fv_device_read(dev, &s, 1, &n, 1000), FV_OK);
        assert_int_equal(s.t_host_ns, i * 5 * MS);
        assert_int_equal(s.t_device_ns, 1000 + i * 5 * MS);
    }
    fv_device_close(&dev);
}

static void loop_continues_the_timeline(void **state)
{
    (void)state;
    const char *path = make_trace("loop.fvt", 3);
    fv_clock clock;
    fv_clock_sim_init(&clock, 0);
    fv_device *dev = trace_test_open_uri("trace:%s?loop=1", path, &clock);
    fv_gaze_sample s;
    size_t n;
    int64_t prev = INT64_MIN;
    for (int i = 0; i < 9; i++) {
        assert_int_equal(fv_device_read(dev, &s, 1, &n, 1000), FV_OK);
        assert_int_equal(n, 1);
        assert_true(s.t_device_ns > prev);
        assert_int_equal(s.t_device_ns, 1000 + i * 10 * MS); /* one median interval between loops */
        assert_int_equal(s.seq, (uint64_t)(i % 3));
        prev = s.t_device_ns;
    }
    fv_device_close(&dev);
}

static void real_time_replay_on_the_monotonic_clock(void **state)
{
    (void)state;
    /* 6.93 s of Pupil Core at 100x: about 70 ms of wall time */
    fv_device *dev =
        trace_test_open_uri("trace:%s?speed=100", fv_test_data("gaze/pupil_core/gaze_positions.csv"), NULL);
    fv_gaze_sample buf[64];
    size_t n, total = 0;
    int64_t start = fv_time_monotonic_ns(), max_late = 0;
    fv_result r;
    while ((r = fv_device_read(dev, buf, 64, &n, 20)) != FV_END_OF_STREAM) {
        assert_true(r == FV_OK || r == FV_TIMEOUT);
        int64_t now = fv_time_monotonic_ns();
        for (size_t i = 0; i < n; i++) {
            assert_true(buf[i].t_host_ns <= now); /* never handed out before its time */
            if (now - buf[i].t_host_ns > max_late) max_late = now - buf[i].t_host_ns;
        }
        total += n;
        assert_true(now - start < 5 * FV_NS_PER_S);
    }
    int64_t wall = fv_time_monotonic_ns() - start;
    assert_int_equal(total, 2054);
    assert_true(wall >= 65 * MS);
    fv_device_close(&dev);
}

static void bad_uris_are_clear_errors(void **state)
{
    (void)state;
    const char *path = make_trace("uri.fvt", 3);
    const char *bad[] = {"trace:%s?speed=0", "trace:%s?speed=abc", "trace:%s?loop=2", "trace:%s?bogus=1",
                         "trace:%s?format=nope"};
    const char *why[] = {"speed '0'", "speed 'abc'", "loop '2'", "unknown option 'bogus'", "unknown format 'nope'"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char uri[1200];
        snprintf(uri, sizeof uri, bad[i], path);
        fv_device *dev = NULL;
        fv_test_log_capture_begin();
        assert_int_equal(fv_trace_driver.open(uri, NULL, &dev), FV_ERR_INVALID_ARG);
        fv_test_log_capture_end();
        assert_null(dev);
        fv_assert_log_contains(why[i]);
    }
    fv_device *dev = NULL;
    fv_test_log_capture_begin();
    assert_int_equal(fv_trace_driver.open("trace:/nonexistent/x.csv", NULL, &dev), FV_ERR_NOT_FOUND);
    assert_int_equal(fv_trace_driver.open("trace:", NULL, &dev), FV_ERR_INVALID_ARG);
    fv_test_log_capture_end();
    fv_assert_log_contains("/nonexistent/x.csv: cannot open");
    /* forcing the format works through the URI */
    char uri[1200];
    snprintf(uri, sizeof uri, "trace:%s?format=fovea&loop=0&speed=1.5", path);
    assert_int_equal(fv_trace_driver.open(uri, NULL, &dev), FV_OK);
    fv_device_close(&dev);
    size_t count = 99;
    assert_int_equal(fv_trace_driver.probe(NULL, 0, &count), FV_OK);
    assert_int_equal(count, 0);
    assert_string_equal(fv_trace_driver.scheme, "trace");
}

static void recorded_replay_reads_back_equal(void **state)
{
    (void)state;
    const char *src = fv_test_data("gaze/htc_vive_pro_eye_sranipal/TESTNA01_2D_Fist3.csv");
    fv_clock clock;
    fv_clock_sim_init(&clock, 42 * FV_NS_PER_S);
    fv_device *dev = trace_test_open_uri("trace:%s", src, &clock);
    const char *out = fv_test_tmp("recorded.fvt");
    fv_trace_writer *w = NULL;
    fv_trace_writer_desc wd = {.source = "trace:TESTNA01", .rate_hz = dev->nominal_rate_hz};
    assert_int_equal(fv_trace_writer_create(out, &wd, &w), FV_OK);
    fv_gaze_sample buf[100];
    size_t n, total = 0;
    fv_result r;
    while ((r = fv_device_read(dev, buf, 100, &n, 50)) != FV_END_OF_STREAM) {
        assert_true(r == FV_OK || r == FV_TIMEOUT);
        for (size_t i = 0; i < n; i++) assert_int_equal(fv_trace_writer_write(w, &buf[i]), FV_OK);
        total += n;
    }
    assert_int_equal(fv_trace_writer_finish(&w), FV_OK);
    fv_device_close(&dev);
    assert_int_equal(total, 1518);
    /* the simulated replay took the recording's duration, exactly */
    fv_trace_reader *a = NULL, *b = NULL;
    assert_int_equal(fv_trace_reader_create(src, NULL, &a), FV_OK);
    assert_int_equal(fv_trace_reader_create(out, NULL, &b), FV_OK);
    fv_gaze_sample s, t;
    int64_t first = 0;
    size_t k = 0;
    while (fv_trace_reader_next(a, &s) == FV_OK) {
        assert_int_equal(fv_trace_reader_next(b, &t), FV_OK);
        if (k++ == 0) first = s.t_device_ns;
        assert_int_equal(s.t_device_ns, t.t_device_ns);
        assert_true(t.flags & FV_GAZE_HOST_TIME_VALID);
        assert_int_equal(t.t_host_ns, 42 * FV_NS_PER_S + (s.t_device_ns - first));
        assert_int_equal(s.seq, t.seq);
        assert_int_equal(s.flags, t.flags & ~(uint32_t)FV_GAZE_HOST_TIME_VALID);
        for (int e = 0; e < 2; e++) {
            assert_int_equal(s.eye[e].flags, t.eye[e].flags);
            assert_memory_equal(&s.eye[e].direction, &t.eye[e].direction, sizeof(fv_vec3));
            assert_memory_equal(&s.eye[e].origin_mm, &t.eye[e].origin_mm, sizeof(fv_vec3));
            assert_memory_equal(&s.eye[e].pupil_mm, &t.eye[e].pupil_mm, sizeof(float));
        }
        assert_memory_equal(&s.combined.direction, &t.combined.direction, sizeof(fv_vec3));
    }
    assert_int_equal(fv_trace_reader_next(b, &t), FV_END_OF_STREAM);
    assert_int_equal(k, 1518);
    fv_trace_reader_destroy(&a);
    fv_trace_reader_destroy(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(replay_is_paced_by_recorded_time_on_a_simulated_clock),
        cmocka_unit_test(speed_scales_pacing_and_device_time),
        cmocka_unit_test(loop_continues_the_timeline),
        cmocka_unit_test(real_time_replay_on_the_monotonic_clock),
        cmocka_unit_test(bad_uris_are_clear_errors),
        cmocka_unit_test(recorded_replay_reads_back_equal),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
