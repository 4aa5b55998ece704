/* @brief N-bit timestamp unwrapping: 32-bit and 24-bit µs counters through wraps and small reordering; checked
 * against the host clock, a gap over half a wrap and a counter that wraps faster than samples arrive. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fv_gaze_unwrap.h"
#include "fv_test.h"

static void gaze_unwrap_32bit_us_survives_two_wraps(void **state)
{
    (void)state;
    fv_gaze_unwrap u;
    assert_int_equal(fv_gaze_unwrap_init(&u, 32, 1000), FV_OK);
    /* start 1 s before the wrap, step 8333 µs (120 Hz) for 2.5 wrap periods (~179 min) in big strides */
    uint64_t t_us = UINT64_C(4294967296) - 1000000u;
    int64_t first = fv_gaze_unwrap_push(&u, t_us & 0xFFFFFFFFu);
    assert_int_equal(first, (int64_t)t_us * 1000);
    int64_t prev = first;
    for (int i = 0; i < 1300000; i++) {
        t_us += 8333;
        int64_t ns = fv_gaze_unwrap_push(&u, t_us & 0xFFFFFFFFu);
        assert_true(ns > prev);
        prev = ns;
    }
    assert_int_equal(prev, (int64_t)t_us * 1000);
    assert_true(t_us > UINT64_C(3) * UINT64_C(4294967296)); /* went through two wraps */
}

static void gaze_unwrap_24bit_counter_wraps_every_16s(void **state)
{
    (void)state;
    fv_gaze_unwrap u;
    assert_int_equal(fv_gaze_unwrap_init(&u, 24, 1000), FV_OK);
    uint64_t t_us = 0;
    for (int i = 0; i < 120 * 60; i++) { /* one minute at 120 Hz: 3.6 wraps */
        int64_t ns = fv_gaze_unwrap_push(&u, t_us & 0xFFFFFFu);
        assert_int_equal(ns, (int64_t)t_us * 1000);
        t_us += 8333;
    }
}

static void gaze_unwrap_reordered_value_across_wrap_maps_to_its_earlier_time(void **state)
{
    (void)state;
    fv_gaze_unwrap u;
    assert_int_equal(fv_gaze_unwrap_init(&u, 24, 1000), FV_OK);
    const uint64_t wrap = UINT64_C(1) << 24;
    uint64_t a = wrap - 3000, b = wrap - 1000, c = wrap + 1000, d = wrap + 3000;
    assert_int_equal(fv_gaze_unwrap_push(&u, a & (wrap - 1)), (int64_t)a * 1000);
    assert_int_equal(fv_gaze_unwrap_push(&u, c & (wrap - 1)), (int64_t)c * 1000); /* b arrives late */
    assert_int_equal(fv_gaze_unwrap_push(&u, b & (wrap - 1)), (int64_t)b * 1000); /* before the wrap */
    assert_int_equal(fv_gaze_unwrap_push(&u, d & (wrap - 1)), (int64_t)d * 1000); /* reference not disturbed */
    /* an exact duplicate maps to the same time */
    assert_int_equal(fv_gaze_unwrap_push(&u, d & (wrap - 1)), (int64_t)d * 1000);
}

static void gaze_unwrap_64bit_and_bad_arguments(void **state)
{
    (void)state;
    fv_gaze_unwrap u;
    assert_int_equal(fv_gaze_unwrap_init(&u, 0, 1000), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_gaze_unwrap_init(&u, 65, 1000), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_gaze_unwrap_init(&u, 32, 0), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_gaze_unwrap_init(&u, 64, 1), FV_OK);
    assert_int_equal(fv_gaze_unwrap_push(&u, 100), 100);
    assert_int_equal(fv_gaze_unwrap_push(&u, 50), 50); /* small reorder in 64-bit */
    assert_int_equal(fv_gaze_unwrap_push(&u, 200), 200);
    /* a huge µs counter saturates instead of overflowing */
    assert_int_equal(fv_gaze_unwrap_init(&u, 64, 1000), FV_OK);
    assert_int_equal(fv_gaze_unwrap_push(&u, UINT64_MAX), INT64_MAX);
    assert_int_equal(fv_gaze_unwrap_push(&u, UINT64_MAX - 5), INT64_MAX);
    /* 63-bit: the half-range boundary */
    assert_int_equal(fv_gaze_unwrap_init(&u, 63, 1), FV_OK);
    assert_int_equal(fv_gaze_unwrap_push(&u, 10), 10);
    assert_int_equal(fv_gaze_unwrap_push(&u, (UINT64_C(1) << 63) - 10), -10); /* 20 ticks back through the wrap */
    fv_gaze_unwrap_reset(&u);
    assert_int_equal(fv_gaze_unwrap_push(&u, 7), 7);
}

/* A 24-bit µs counter (16.8 s) and a device quiet for 10 s, over half the wrap: alone, the counter reads the gap as
 * 6.8 s back; with the receipt times the timeline continues exactly. */
static void gaze_unwrap_host_time_resolves_a_gap_over_half_the_wrap(void **state)
{
    (void)state;
    fv_gaze_unwrap plain, host;
    assert_int_equal(fv_gaze_unwrap_init(&plain, 24, 1000), FV_OK);
    assert_int_equal(fv_gaze_unwrap_init(&host, 24, 1000), FV_OK);
    host.label = "hid:test";
    const uint64_t wrap = UINT64_C(1) << 24;
    uint64_t t_us = 123456;
    fv_test_log_capture_begin();
    for (int i = 0; i < 300; i++, t_us += i == 150 ? 10000000 : 10000) { /* 100 Hz, then 10 s of silence */
        int64_t host_ns = (int64_t)t_us * 1000 + 3000000 + (i % 7) * 100000; /* receipt: 3 ms + up to 0.6 ms later */
        int64_t a = fv_gaze_unwrap_push(&plain, t_us & (wrap - 1));
        int64_t b = fv_gaze_unwrap_push_host(&host, t_us & (wrap - 1), host_ns);
        assert_int_equal(b, (int64_t)t_us * 1000);
        if (i == 151) assert_true(a < b); /* the plain reading went back (a late value) */
    }
    fv_test_log_capture_end();
    assert_int_equal(host.host_corrections, 1);
    fv_assert_log_contains("hid:test: device timestamps disagree with the host clock");
}

/* An 8-bit µs counter wraps every 0.256 ms, 32 times between two 120 Hz samples. Alone it turns 10 s into ~80 ms
 * (a stream of ~15 kHz); checked against receipt times that jitter by up to 1 ms it keeps the host's pace: no
 * sample invented, one warning. */
static void gaze_unwrap_counter_faster_than_the_samples_keeps_the_host_pace(void **state)
{
    (void)state;
    fv_gaze_unwrap plain, host;
    assert_int_equal(fv_gaze_unwrap_init(&plain, 8, 1000), FV_OK);
    assert_int_equal(fv_gaze_unwrap_init(&host, 8, 1000), FV_OK);
    host.label = "hid:fast";
    uint64_t lcg = 7;
    int64_t first_plain = 0, first_host = 0, prev = INT64_MIN, a = 0, b = 0;
    const int n = 1200;
    fv_test_log_capture_begin();
    for (int i = 0; i < n; i++) {
        int64_t capture_ns = INT64_C(5000000000) + (int64_t)i * 8333333;
        lcg = lcg * 6364136223846793005u + 1442695040888963407u;
        int64_t host_ns = capture_ns + 4000000 + (int64_t)(lcg >> 44) % 1000000; /* 4 ms + [0, 1) ms */
        uint64_t raw = (uint64_t)(capture_ns / 1000);
        a = fv_gaze_unwrap_push(&plain, raw);
        b = fv_gaze_unwrap_push_host(&host, raw, host_ns);
        if (i == 0) {
            first_plain = a;
            first_host = b;
        }
        assert_true(b > prev); /* in order, never a step back */
        prev = b;
        /* within a few wraps (the receipt jitter) of the true elapsed time */
        assert_true(llabs((b - first_host) - (capture_ns - INT64_C(5000000000))) < 3000000);
    }
    fv_test_log_capture_end();
    double span_s = (double)(n - 1) * 8333333e-9;
    print_message("8-bit counter, %d samples over %.2f s: plain %.3f s, checked %.3f s, %llu corrections\n", n,
                  span_s, (double)(a - first_plain) / 1e9, (double)(b - first_host) / 1e9,
                  (unsigned long long)host.host_corrections);
    assert_true((double)(a - first_plain) / 1e9 < 0.2 * span_s);   /* the defect: the plain timeline compresses */
    assert_true(fabs((double)(b - first_host) / 1e9 - span_s) < 0.003); /* 120 Hz stays 120 Hz */
    assert_true(host.host_corrections > (uint64_t)n * 9 / 10);
    const char *needle = "hid:fast: device timestamps disagree with the host clock";
    const char *hit = strstr(fv_test_log_text(), needle);
    assert_non_null(hit);
    assert_null(strstr(hit + strlen(needle), "disagree")); /* reported once */
    fv_assert_log_contains("8-bit counter (wraps every 0.256 ms)");
}

/* A host time that goes back (another clock, a bad driver) is not used: the plain reading applies. */
static void gaze_unwrap_host_time_going_back_falls_back_to_the_counter(void **state)
{
    (void)state;
    fv_gaze_unwrap u;
    assert_int_equal(fv_gaze_unwrap_init(&u, 16, 1000), FV_OK);
    assert_int_equal(fv_gaze_unwrap_push_host(&u, 100, INT64_C(1000000000)), 100000);
    assert_int_equal(fv_gaze_unwrap_push_host(&u, 200, INT64_C(5000)), 200000);
    assert_int_equal(u.host_corrections, 0);
    assert_int_equal(fv_gaze_unwrap_wrap_ns(&u), INT64_C(65536000));
    assert_int_equal(fv_gaze_unwrap_init(&u, 64, 1), FV_OK);
    assert_int_equal(fv_gaze_unwrap_wrap_ns(&u), INT64_MAX);
    assert_int_equal(fv_gaze_unwrap_push_host(&u, 10, 0), 10);
    assert_int_equal(fv_gaze_unwrap_push_host(&u, 20, INT64_MAX), 20); /* 62+ bits: the counter alone */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gaze_unwrap_32bit_us_survives_two_wraps),
        cmocka_unit_test(gaze_unwrap_24bit_counter_wraps_every_16s),
        cmocka_unit_test(gaze_unwrap_reordered_value_across_wrap_maps_to_its_earlier_time),
        cmocka_unit_test(gaze_unwrap_64bit_and_bad_arguments),
        cmocka_unit_test(gaze_unwrap_host_time_resolves_a_gap_over_half_the_wrap),
        cmocka_unit_test(gaze_unwrap_counter_faster_than_the_samples_keeps_the_host_pace),
        cmocka_unit_test(gaze_unwrap_host_time_going_back_falls_back_to_the_counter),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
