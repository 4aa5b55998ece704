/* @brief Latency budgets of the frame loop on a simulated clock (deterministic, no sleeps): a 90 Hz display, a
 * 250 Hz tracker with 4 ms latency, the real gaze pipeline and a stand-in renderer.
 * - a render that fits: gaze-to-photon p99 <= two refresh periods + tracker latency, no missed refreshes;
 * - a render over budget: frames are reported missed, latency stays bounded and does not grow (no queueing);
 * - a tracker that stalls, one that disappears and comes back, and one whose read hangs: the loop keeps its pace,
 *   reports the device lost (wider uncertainty) and picks the gaze up again when it returns;
 * - a first frame that stalls (shader compiles: a software device's first frame) does not pace the frames after the
 *   warm-up: their prediction horizon and the gaze's uncertainty are those of the steady frames, not of the stall. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fake_tracker.h"
#include "fv_frame_loop.h"
#include "fv_sim_display.h"
#include "fv_standin_render.h"
#include "fv_test.h"

#define HZ 90.0
#define TRACKER_LATENCY_NS (4 * FV_NS_PER_MS)
#define TRACKER_HZ 250.0

typedef struct rig {
    fv_clock clk;
    fake_tracker tracker;
    fv_display *display;
    fv_gaze_pipeline *pipeline;
    fv_gaze_source *source;
    fv_standin_render standin;
    fv_frame_loop *loop;
    fv_latency_record *rec;
    size_t n;
    /* what the renderer was given, per frame */
    int64_t *in_photon_ns;
    bool *in_gaze_valid;
} rig;

static fv_result spy_render(void *user, fv_frame_input *in, fv_frame_render_times *out)
{
    rig *r = user;
    r->in_photon_ns[in->frame_id] = in->t_photon_ns;
    r->in_gaze_valid[in->frame_id] = in->gaze[0].valid && in->gaze[1].valid;
    assert_true(isfinite(in->gaze[0].uncertainty_deg) && isfinite(in->gaze[1].uncertainty_deg));
    assert_true(fv_v3_isfinite(in->gaze[0].dir_eye) && fv_v3_isfinite(in->gaze[1].dir_eye));
    return fv_standin_render_frame(&r->standin, in, out);
}

/* threaded: use a thread-mode source (the tracker must then not read the simulated clock) */
static void rig_init(rig *r, int64_t render_ns, size_t max_frames, bool threaded)
{
    memset(r, 0, sizeof *r);
    fv_clock_sim_init(&r->clk, 10 * FV_NS_PER_S);
    fake_tracker_init(&r->tracker, threaded ? NULL : &r->clk, TRACKER_HZ, TRACKER_LATENCY_NS);
    r->tracker.hang = threaded; /* threaded rigs test a read that hangs from the start */
    fv_sim_display_desc dd = {.clock = &r->clk, .refresh_hz = HZ};
    assert_int_equal(fv_sim_display_create(&dd, &r->display), FV_OK);
    fv_gaze_pipeline_desc pd = {0};
    assert_int_equal(fv_gaze_pipeline_create(&pd, &r->pipeline), FV_OK);
    fv_gaze_source_desc sd = {.uri = "fake:tracker", .open = fake_tracker_open, .open_user = &r->tracker,
                              .mode = threaded ? FV_GAZE_SOURCE_THREAD : FV_GAZE_SOURCE_INLINE, .clock = &r->clk,
                              .read_timeout_ms = 1, .retry_min_ns = 20 * FV_NS_PER_MS,
                              .retry_max_ns = 160 * FV_NS_PER_MS};
    assert_int_equal(fv_gaze_source_create(&sd, &r->source), FV_OK);
    assert_int_equal(fv_standin_render_init(&r->standin, &r->clk, render_ns, 0.25, 0, 1), FV_OK);
    fv_frame_loop_desc ld = {.clock = &r->clk, .display = r->display, .render = spy_render, .render_user = r,
                             .gaze = r->source, .pipeline = r->pipeline, .tracker_latency_ns = TRACKER_LATENCY_NS};
    assert_int_equal(fv_frame_loop_create(&ld, &r->loop), FV_OK);
    r->rec = calloc(max_frames, sizeof *r->rec);
    r->in_photon_ns = calloc(max_frames, sizeof *r->in_photon_ns);
    r->in_gaze_valid = calloc(max_frames, sizeof *r->in_gaze_valid);
    assert_non_null(r->rec);
    assert_non_null(r->in_photon_ns);
    assert_non_null(r->in_gaze_valid);
}

/* A render whose first frame stalls (the warm-up: shader compiles) and whose later frames fit the period. */
static fv_result stall_render(void *user, fv_frame_input *in, fv_frame_render_times *out)
{
    rig *r = user;
    r->in_photon_ns[in->frame_id] = in->t_photon_ns;
    int64_t cost = in->frame_id == 0 ? 800 * FV_NS_PER_MS : 4 * FV_NS_PER_MS;
    int64_t begin = fv_clock_now_ns(&r->clk);
    out->t_submit_ns = begin + cost / 4;
    out->t_gpu_begin_ns = out->t_submit_ns;
    out->t_gpu_end_ns = begin + cost;
    fv_clock_sim_advance(&r->clk, cost / 4);
    return FV_OK;
}

static void rig_run(rig *r, size_t frames)
{
    for (size_t i = 0; i < frames; i++) assert_int_equal(fv_frame_loop_step(r->loop, &r->rec[r->n++]), FV_OK);
}

static void rig_fini(rig *r)
{
    fv_frame_loop_destroy(&r->loop);
    fv_gaze_source_destroy(&r->source);
    fv_gaze_pipeline_destroy(&r->pipeline);
    fv_display_destroy(&r->display);
    fake_tracker_fini(&r->tracker);
    free(r->rec);
    free(r->in_photon_ns);
    free(r->in_gaze_valid);
}

static fv_latency_summary summarize(const fv_latency_record *rec, size_t n)
{
    fv_latency_summary s;
    assert_int_equal(fv_latency_summarize(rec, n, &s), FV_OK);
    return s;
}

static double period_ms(void) { return 1000.0 / HZ; }

static void render_that_fits_keeps_p99_within_two_periods_plus_tracker(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, 6 * FV_NS_PER_MS, 900, false);
    rig_run(&r, 900); /* 10 s */
    fv_latency_summary s = summarize(r.rec, r.n);
    print_message("fits: p50 %.2f p95 %.2f p99 %.2f max %.2f ms; missed %zu; budget %.2f ms\n", s.g2p_p50_ms,
                  s.g2p_p95_ms, s.g2p_p99_ms, s.g2p_max_ms, s.missed, 2 * period_ms() + 4.0);
    assert_int_equal(s.frames_with_gaze, 900);
    assert_true(s.g2p_p99_ms <= 2.0 * period_ms() + TRACKER_LATENCY_NS / 1e6);
    assert_int_equal(s.missed, 0);
    assert_int_equal(s.lost_frames, 0);
    assert_int_equal(s.stale_frames, 0); /* 250 Hz tracker, 90 Hz frames: every frame has a new sample */
    assert_true(fabs(s.frame_interval_mean_ms - period_ms()) < 1e-3);
    for (size_t i = 0; i < r.n; i++) {
        const fv_latency_record *x = &r.rec[i];
        /* the fake's device clock is the host clock: capture time = device timestamp */
        assert_int_equal(x->t_sample_capture_ns, x->t_sample_device_ns);
        int64_t sum = 0;
        for (int st = 0; st < FV_LATENCY_STAGE_COUNT; st++) {
            int64_t d = fv_latency_stage_ns(x, (fv_latency_stage)st);
            assert_true(d >= 0);
            sum += d;
        }
        assert_int_equal(sum, fv_latency_gaze_to_photon_ns(x));
        if (i) assert_int_equal(x->shown_vsync, r.rec[i - 1].shown_vsync + 1); /* one new frame per refresh */
        assert_int_equal(r.in_photon_ns[i], x->t_photon_ns); /* predicted for the photon time it really got */
        assert_true(r.in_gaze_valid[i]);
        /* the sample is the newest the tracker had delivered at latch */
        int64_t next_capture = x->t_sample_capture_ns + (int64_t)llround(1e9 / TRACKER_HZ);
        assert_true(next_capture + TRACKER_LATENCY_NS > x->t_latch_ns);
    }
    rig_fini(&r);
}

static void runs_are_deterministic(void **state)
{
    (void)state;
    rig a, b;
    rig_init(&a, 7 * FV_NS_PER_MS, 300, false);
    rig_init(&b, 7 * FV_NS_PER_MS, 300, false);
    rig_run(&a, 300);
    rig_run(&b, 300);
    for (size_t i = 0; i < 300; i++) {
        assert_int_equal(a.rec[i].t_photon_ns, b.rec[i].t_photon_ns);
        assert_int_equal(a.rec[i].t_sample_device_ns, b.rec[i].t_sample_device_ns);
        assert_int_equal(a.rec[i].t_latch_ns, b.rec[i].t_latch_ns);
        assert_true(a.rec[i].uncertainty_deg == b.rec[i].uncertainty_deg);
    }
    rig_fini(&a);
    rig_fini(&b);
}

static void render_over_budget_is_reported_missed_and_latency_stays_bounded(void **state)
{
    (void)state;
    const int64_t render_ns = 15 * FV_NS_PER_MS; /* > 11.1 ms period */
    rig r;
    rig_init(&r, render_ns, 600, false);
    rig_run(&r, 600);
    fv_latency_summary s = summarize(r.rec, r.n);
    print_message("over budget: p50 %.2f p99 %.2f max %.2f ms; late %zu, repeated refreshes %zu of %zu frames\n",
                  s.g2p_p50_ms, s.g2p_p99_ms, s.g2p_max_ms, s.late_frames, s.repeated_vsyncs, s.frames);
    assert_true(s.missed >= 590); /* every frame needs two refreshes: about one repeat per frame */
    assert_true(s.repeated_vsyncs >= 590);
    const int64_t photon_offset = fv_sim_display_photon_offset_ns(r.display);
    const int64_t period = r.display->period_ns;
    /* bound: tracker + one sample interval + render + margins + one period (waiting for the refresh) + scan-out */
    const int64_t bound = TRACKER_LATENCY_NS + (int64_t)(1e9 / TRACKER_HZ) + render_ns + FV_NS_PER_MS +
                          r.display->present_margin_ns + period + photon_offset;
    for (size_t i = 0; i < r.n; i++) {
        assert_true(fv_latency_gaze_to_photon_ns(&r.rec[i]) <= bound);
        /* no queue: each frame reaches the display within one period of being presented */
        assert_true(r.rec[i].t_vsync_ns - r.rec[i].t_present_ns <= period + r.display->present_margin_ns);
    }
    /* and it does not creep up over time */
    fv_latency_summary early = summarize(r.rec + 20, 100), late = summarize(r.rec + r.n - 100, 100);
    assert_true(late.g2p_mean_ms <= early.g2p_mean_ms + 0.5);
    assert_true(late.g2p_max_ms <= early.g2p_max_ms + 0.5);
    rig_fini(&r);
}

static double mean_uncertainty(const rig *r, size_t from, size_t to)
{
    double sum = 0;
    for (size_t i = from; i < to; i++) sum += r->rec[i].uncertainty_deg;
    return sum / (double)(to - from);
}

/* index of the first frame latched at or after t */
static size_t frame_at(const rig *r, int64_t t)
{
    for (size_t i = 0; i < r->n; i++)
        if (r->rec[i].t_latch_ns >= t) return i;
    return r->n;
}

static void stalled_tracker_is_reported_lost_without_slowing_the_loop(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, 6 * FV_NS_PER_MS, 450, false);
    const int64_t t0 = r.tracker.first_capture_ns;
    r.tracker.stall_from_ns = t0 + 2 * FV_NS_PER_S;
    r.tracker.stall_to_ns = t0 + 3 * FV_NS_PER_S;
    fv_test_log_capture_begin();
    rig_run(&r, 450); /* 5 s */
    fv_test_log_capture_end();
    fv_latency_summary s = summarize(r.rec, r.n);
    assert_int_equal(s.missed, 0); /* pace kept through the stall */
    size_t before = frame_at(&r, t0 + 2 * FV_NS_PER_S), during = frame_at(&r, t0 + 2300 * FV_NS_PER_MS),
           during_end = frame_at(&r, t0 + 2950 * FV_NS_PER_MS), after = frame_at(&r, t0 + 3100 * FV_NS_PER_MS);
    for (size_t i = 0; i < before; i++) assert_false(r.rec[i].device_lost);
    for (size_t i = during; i < during_end; i++) {
        assert_true(r.rec[i].device_lost);
        assert_false(r.rec[i].fresh_gaze);
    }
    for (size_t i = after; i < r.n; i++) {
        assert_false(r.rec[i].device_lost);
        assert_true(r.rec[i].fresh_gaze);
    }
    double u_before = mean_uncertainty(&r, before - 50, before), u_during = mean_uncertainty(&r, during, during_end);
    print_message("stall: uncertainty %.2f deg before, %.2f deg while stalled\n", u_before, u_during);
    assert_true(u_during > u_before);
    fv_assert_log_contains("fake:tracker: no gaze (connected, stalled)");
    fv_assert_log_contains("fake:tracker: gaze back");
    rig_fini(&r);
}

static void tracker_that_disappears_is_reopened_and_the_loop_keeps_going(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, 6 * FV_NS_PER_MS, 450, false);
    const int64_t t0 = r.tracker.first_capture_ns;
    r.tracker.lost_at_ns = t0 + 2 * FV_NS_PER_S;
    r.tracker.back_at_ns = t0 + 2500 * FV_NS_PER_MS;
    fv_test_log_capture_begin();
    rig_run(&r, 450);
    fv_test_log_capture_end();
    fv_latency_summary s = summarize(r.rec, r.n);
    assert_int_equal(s.missed, 0);
    fv_gaze_source_status st;
    fv_gaze_source_get_status(r.source, &st);
    assert_int_equal(st.losses, 1);
    assert_int_equal(st.reopens, 1);
    assert_true(st.open_failures >= 2);
    size_t lost = frame_at(&r, t0 + 2 * FV_NS_PER_S + 20 * FV_NS_PER_MS);
    size_t gone_end = frame_at(&r, t0 + 2500 * FV_NS_PER_MS);
    size_t after = frame_at(&r, t0 + 2700 * FV_NS_PER_MS); /* back at the first retry after 2.5 s */
    for (size_t i = lost; i < gone_end; i++) assert_true(r.rec[i].device_lost);
    for (size_t i = after; i < r.n; i++) {
        assert_false(r.rec[i].device_lost);
        assert_true(r.rec[i].fresh_gaze);
    }
    assert_true(mean_uncertainty(&r, lost, gone_end) > mean_uncertainty(&r, lost - 50, lost));
    fv_assert_log_contains("fake:tracker: device lost");
    fv_assert_log_contains("fake:tracker: device back");
    rig_fini(&r);
}

static void hung_tracker_read_never_blocks_the_frame_loop(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, 6 * FV_NS_PER_MS, 300, true); /* reader thread, stuck in its first read */
    fv_test_log_capture_begin();
    rig_run(&r, 300); /* the reader thread is stuck in the driver the whole time */
    fv_test_log_capture_end();
    fv_latency_summary s = summarize(r.rec, r.n);
    assert_int_equal(s.frames, 300);
    assert_int_equal(s.missed, 0);
    assert_int_equal(s.frames_with_gaze, 0);
    size_t stalled = frame_at(&r, r.rec[0].t_latch_ns + 110 * FV_NS_PER_MS);
    for (size_t i = stalled; i < r.n; i++) {
        assert_true(r.rec[i].device_lost);
        assert_false(r.in_gaze_valid[i]); /* no gaze: the renderer is told so (whole view foveal) */
    }
    fake_tracker_set_hang(&r.tracker, false);
    rig_fini(&r);
}

static void warmup_stall_does_not_pace_or_widen_later_frames(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, 4 * FV_NS_PER_MS, 64, false);
    fv_frame_loop_destroy(&r.loop);
    fv_frame_loop_desc ld = {.clock = &r.clk, .display = r.display, .render = stall_render, .render_user = &r,
                             .gaze = r.source, .pipeline = r.pipeline, .tracker_latency_ns = TRACKER_LATENCY_NS};
    assert_int_equal(fv_frame_loop_create(&ld, &r.loop), FV_OK);
    rig_run(&r, 12);
    /* frame 0 stalled 800 ms; from the third frame (the default two warm-up frames measured) the loop paces by the
     * steady 4 ms frames: the gaze latched is predicted at most a few periods ahead, not past the stall */
    for (size_t i = 3; i < 12; i++) {
        double horizon_ms = (double)(r.rec[i].t_photon_ns - r.rec[i].t_latch_ns) / 1e6;
        print_message("frame %zu: latch to photon %.2f ms, uncertainty %.2f deg, event %d\n", i, horizon_ms,
                      (double)r.rec[i].uncertainty_deg, r.rec[i].gaze_event);
        assert_true(horizon_ms < 4 * period_ms());
        assert_true(r.rec[i].has_gaze);
        assert_true(r.rec[i].uncertainty_deg < 5.0f); /* not the lost gaze's 30 deg cap */
        assert_int_not_equal(r.rec[i].gaze_event, FV_GAZE_EVENT_LOST);
    }
    /* warm-up frames counted in (-1 = none): the stall paces the frames that follow it for the cost window */
    rig_fini(&r);
    rig_init(&r, 4 * FV_NS_PER_MS, 64, false);
    fv_frame_loop_destroy(&r.loop);
    ld = (fv_frame_loop_desc){.clock = &r.clk, .display = r.display, .render = stall_render, .render_user = &r,
                              .gaze = r.source, .pipeline = r.pipeline, .tracker_latency_ns = TRACKER_LATENCY_NS,
                              .warmup_frames = -1};
    assert_int_equal(fv_frame_loop_create(&ld, &r.loop), FV_OK);
    rig_run(&r, 6);
    assert_true((double)(r.rec[4].t_photon_ns - r.rec[4].t_latch_ns) / 1e6 > 500.0);
    rig_fini(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(render_that_fits_keeps_p99_within_two_periods_plus_tracker),
        cmocka_unit_test(runs_are_deterministic),
        cmocka_unit_test(render_over_budget_is_reported_missed_and_latency_stays_bounded),
        cmocka_unit_test(stalled_tracker_is_reported_lost_without_slowing_the_loop),
        cmocka_unit_test(tracker_that_disappears_is_reopened_and_the_loop_keeps_going),
        cmocka_unit_test(hung_tracker_read_never_blocks_the_frame_loop),
        cmocka_unit_test(warmup_stall_does_not_pace_or_widen_later_frames),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
