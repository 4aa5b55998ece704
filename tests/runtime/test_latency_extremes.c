/* @brief Latency records with any times (a frame log is outside data): every difference saturates through
 * fv_i64_sub_sat, so no input is undefined behaviour (UBSan aborts the sanitizer build on one) and no overflow turns
 * a huge latency into a negative one: gaze-to-photon, each stage, and the frame interval of the summary. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "fv_latency.h"
#include "fv_test.h"

static fv_latency_record rec(int64_t capture, int64_t photon)
{
    fv_latency_record r;
    memset(&r, 0, sizeof r);
    r.has_gaze = true;
    r.fresh_gaze = true;
    r.t_sample_capture_ns = capture;
    r.t_photon_ns = photon;
    return r;
}

static void gaze_to_photon_and_stages_saturate(void **state)
{
    (void)state;
    fv_latency_record r = rec(INT64_MIN, INT64_MAX);
    assert_true(fv_latency_gaze_to_photon_ns(&r) == INT64_MAX);
    r = rec(INT64_MAX, INT64_MIN);
    assert_true(fv_latency_gaze_to_photon_ns(&r) == INT64_MIN);
    /* every stage: the later time at INT64_MAX, the earlier at INT64_MIN */
    memset(&r, 0, sizeof r);
    int64_t *t[] = {&r.t_sample_capture_ns, &r.t_sample_received_ns, &r.t_latch_ns, &r.t_cpu_begin_ns,
                    &r.t_submit_ns,         &r.t_gpu_end_ns,         &r.t_vsync_ns, &r.t_photon_ns};
    for (int s = 0; s < FV_LATENCY_STAGE_COUNT; s++) {
        for (int k = 0; k < 8; k++) *t[k] = 0;
        *t[s] = INT64_MIN;
        *t[s + 1] = INT64_MAX;
        if (fv_latency_stage_ns(&r, (fv_latency_stage)s) != INT64_MAX)
            fail_msg("stage %s does not saturate", fv_latency_stage_str((fv_latency_stage)s));
    }
}

static void a_summary_of_extreme_records_is_never_negative_from_overflow(void **state)
{
    (void)state;
    fv_latency_record r[3] = {rec(-9000000000000000000, 9000000000000000000), rec(0, 5000000),
                              rec(INT64_MIN, INT64_MAX)};
    r[0].t_vsync_ns = INT64_MIN;
    r[2].t_vsync_ns = INT64_MAX;
    fv_latency_summary s;
    assert_int_equal(fv_latency_summarize(r, 3, &s), FV_OK);
    assert_int_equal(s.frames_with_gaze, 3);
    assert_true(s.g2p_min_ms == 5.0);
    assert_true(s.g2p_p50_ms > 0 && s.g2p_p95_ms > 0 && s.g2p_p99_ms > 0 && s.g2p_max_ms > 0 && s.g2p_mean_ms > 0);
    assert_true(s.g2p_max_ms == (double)INT64_MAX / 1e6);
    assert_true(s.frame_interval_mean_ms > 0 && isfinite(s.frame_interval_mean_ms));
    for (int k = 0; k < FV_LATENCY_STAGE_COUNT; k++) assert_true(isfinite(s.stage_mean_ms[k]));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gaze_to_photon_and_stages_saturate),
        cmocka_unit_test(a_summary_of_extreme_records_is_never_negative_from_overflow),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
