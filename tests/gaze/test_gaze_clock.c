/* @brief Device-to-host clock mapping: recovers a known offset and skew under transport jitter; restarts on device
 * clock discontinuities. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "fv_gaze_clock.h"
#include "fv_test.h"

static uint64_t g_rng = 12345;
static double uniform(void)
{
    g_rng = g_rng * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(g_rng >> 11) * (1.0 / 9007199254740992.0);
}

/* host(capture) = offset + dev * (1 + skew) ; receipt = host(capture) + 2 ms + exponential jitter (mean 1 ms) with
 * 2% spikes of 5..30 ms (a busy USB bus / scheduler). */
static void run_jitter(double skew_ppm, int64_t offset_ns, double seconds, double *out_max_err_ns, double *out_skew)
{
    fv_gaze_clock_map m;
    fv_gaze_clock_map_init(&m, 0, 0);
    const double latency_ns = 2.0e6;
    double max_err = 0.0;
    int64_t dev0 = INT64_C(5000000000000); /* the device has been up for ~83 min */
    for (int i = 0; i < (int)(seconds * 120.0); i++) {
        int64_t dev = dev0 + (int64_t)i * 8333333;
        double host_cap = (double)offset_ns + (double)(dev - dev0) * (1.0 + skew_ppm * 1e-6);
        double jitter = -1.0e6 * log(1.0 - uniform());
        if (uniform() < 0.02) jitter += 5.0e6 + 25.0e6 * uniform();
        int64_t receipt = (int64_t)(host_cap + latency_ns + jitter);
        fv_gaze_clock_map_observe(&m, dev, receipt);
        int64_t mapped;
        assert_true(fv_gaze_clock_map_to_host(&m, dev, &mapped));
        if (i > 120 * 20) { /* after 20 s the estimate has settled */
            double err = fabs((double)mapped - (host_cap + latency_ns));
            if (err > max_err) max_err = err;
        }
    }
    *out_max_err_ns = max_err;
    *out_skew = fv_gaze_clock_map_skew_ppm(&m);
}

static void gaze_clock_recovers_offset_and_skew_under_jitter(void **state)
{
    (void)state;
    double err, skew;
    run_jitter(50.0, INT64_C(123456789012), 120.0, &err, &skew);
    /* the mapped time sits on the lower envelope: within 0.3 ms of capture + minimum latency */
    assert_true(err < 0.3e6);
    assert_true(fabs(skew - 50.0) < 10.0);
    run_jitter(-80.0, -INT64_C(999999999), 120.0, &err, &skew);
    assert_true(err < 0.3e6);
    assert_true(fabs(skew + 80.0) < 10.0);
    /* a naive mapping (receipt as is) would be off by the jitter: mean 1 ms, spikes to 30 ms */
}

static void gaze_clock_without_skew_keeps_offset(void **state)
{
    (void)state;
    double err, skew;
    run_jitter(0.0, 0, 60.0, &err, &skew);
    assert_true(err < 0.3e6);
    assert_true(fabs(skew) < 10.0);
}

static void gaze_clock_restarts_when_the_device_clock_jumps(void **state)
{
    (void)state;
    fv_gaze_clock_map m;
    fv_gaze_clock_map_init(&m, 0, 0);
    for (int i = 0; i < 600; i++) fv_gaze_clock_map_observe(&m, (int64_t)i * 8333333, (int64_t)i * 8333333 + 1000000);
    int64_t mapped;
    assert_true(fv_gaze_clock_map_to_host(&m, 100 * 8333333, &mapped));
    assert_int_equal(mapped, 100 * 8333333 + 1000000);
    /* the device restarts at 0 while the host goes on */
    int64_t host = 600 * INT64_C(8333333) + 1000000;
    assert_true(fv_gaze_clock_map_observe(&m, 0, host));
    assert_true(fv_gaze_clock_map_to_host(&m, 0, &mapped));
    assert_int_equal(mapped, host);
    /* a jump forward of an hour: far below the envelope, restart again */
    assert_true(fv_gaze_clock_map_observe(&m, INT64_C(3600000000000), host + 8333333));
    assert_true(fv_gaze_clock_map_to_host(&m, INT64_C(3600000000000), &mapped));
    assert_int_equal(mapped, host + 8333333);
    assert_int_equal(m.resets, 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gaze_clock_recovers_offset_and_skew_under_jitter),
        cmocka_unit_test(gaze_clock_without_skew_keeps_offset),
        cmocka_unit_test(gaze_clock_restarts_when_the_device_clock_jumps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
