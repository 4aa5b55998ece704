/* @brief N-bit timestamp unwrapping: 32-bit and 24-bit µs counters through wraps and small reordering. */
#include <stdint.h>

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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gaze_unwrap_32bit_us_survives_two_wraps),
        cmocka_unit_test(gaze_unwrap_24bit_counter_wraps_every_16s),
        cmocka_unit_test(gaze_unwrap_reordered_value_across_wrap_maps_to_its_earlier_time),
        cmocka_unit_test(gaze_unwrap_64bit_and_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
