/* @brief The application layer (runtime/app) that `fovea` and the OpenXR runtime share:
 * - the one driver list: every built-in driver once, hardware first, and a plug-in from FOVEA_DRIVERS joining it
 *   (argv[1]: the test-only "probe" plug-in) before the virtual drivers; a tracker opened on it delivers its gaze;
 * - a frame's GPU time booked as GPU when the draw call waited for a software device's GPU inside it (the CPU stage
 *   ends where the GPU's own timestamps say it began; `fovea latency --frame-log` of a lavapipe run said cpu 1770 ms,
 *   gpu 0.23 ms);
 * - where an interactive run starts on a software device (its size from the CPU cores, never larger, the aspect
 *   kept, the budget on), and only there;
 * - each budget change is one line at the default log level; a budget kept to some knobs (the OpenXR runtime's). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fv_app_budget.h"
#include "fv_app_drivers.h"
#include "fv_app_interactive.h"
#include "fv_app_tracker.h"
#include "fv_frame_loop.h"
#include "fv_knobs.h"
#include "fv_test.h"

static const char *g_plugin;

#define MS FV_NS_PER_MS

static void gpu_time_is_gpu_when_the_draw_waited_for_it(void **state)
{
    (void)state;
    int64_t t0 = 1000 * MS;
    fv_frame_render_times t;
    /* lavapipe behind a window: the draw's present waited for the frame, the fence was signalled 0.23 ms after it
     * returned, and the GPU's timestamps span 1769 ms */
    fv_frame_times_from_fence(t0, t0 + 1770 * MS, t0 + 1770 * MS + 230000, 1769 * MS, &t);
    double cpu_ms = (double)(t.t_submit_ns - t0) / 1e6, gpu_ms = (double)(t.t_gpu_end_ns - t.t_submit_ns) / 1e6;
    print_message("software device: cpu %.2f ms, gpu %.2f ms\n", cpu_ms, gpu_ms);
    assert_true(cpu_ms < 2.0);
    assert_true(fabs(gpu_ms - 1769.0) < 0.01);
    assert_true(t.t_gpu_begin_ns >= t.t_submit_ns && t.t_gpu_end_ns >= t.t_gpu_begin_ns);
    /* a GPU that ran after the draw returned: submit at the return, the queue wait counted in the GPU stage */
    fv_frame_times_from_fence(t0, t0 + 5 * MS, t0 + 25 * MS, 18 * MS, &t);
    assert_true(t.t_submit_ns == t0 + 5 * MS && t.t_gpu_begin_ns == t0 + 7 * MS && t.t_gpu_end_ns == t0 + 25 * MS);
    /* unknown GPU time: the GPU from the return to the fence */
    fv_frame_times_from_fence(t0, t0 + 5 * MS, t0 + 25 * MS, 0, &t);
    assert_true(t.t_submit_ns == t0 + 5 * MS && t.t_gpu_begin_ns == t0 + 5 * MS);
    /* timestamps claiming more than elapsed since the CPU began: everything after the CPU began is the GPU's */
    fv_frame_times_from_fence(t0, t0 + 5 * MS, t0 + 25 * MS, 5000 * MS, &t);
    assert_true(t.t_submit_ns == t0 && t.t_gpu_begin_ns == t0 && t.t_gpu_end_ns == t0 + 25 * MS);
    /* times out of order: a fence before the return, a return before the begin */
    fv_frame_times_from_fence(t0, t0 - MS, t0 - 2 * MS, 3 * MS, &t);
    assert_true(t.t_submit_ns >= t0 && t.t_gpu_begin_ns >= t.t_submit_ns && t.t_gpu_end_ns >= t.t_gpu_begin_ns);
}

static void software_device_starts_interactive_runs_where_the_budget_holds(void **state)
{
    (void)state;
    fv_app_interactive_in in = {.software = true, .interactive = true, .eye_w = 720, .eye_h = 800, .hz = 90,
                                .cpu_cores = 2};
    fv_app_interactive o;
    fv_app_interactive_start(&in, &o);
    print_message("2 cores: %ux%u, scale %.2f: %s\n", o.eye_w, o.eye_h, o.budget_scale, o.line);
    assert_true(o.applied && o.budget);
    assert_true((double)o.eye_w * o.eye_h <= FV_APP_SOFT_PIXELS_PER_CORE * 2 / 2);
    assert_true(o.eye_w >= FV_APP_SOFT_MIN_SIDE && o.eye_h >= FV_APP_SOFT_MIN_SIDE);
    assert_true(fabs((double)o.eye_w / o.eye_h - 720.0 / 800.0) < 0.03);
    assert_true(fabs(o.budget_scale - 9.0) < 1e-9); /* 100 ms at 90 Hz */
    fv_assert_contains(o.line, "--eye-size");
    fv_assert_contains(o.line, "--budget off");
    /* more cores, a larger start; never larger than the size asked for */
    uint32_t w2 = o.eye_w;
    in.cpu_cores = 16;
    fv_app_interactive_start(&in, &o);
    assert_true(o.applied && o.eye_w > w2 && o.eye_w < 720);
    in.cpu_cores = 256;
    fv_app_interactive_start(&in, &o);
    assert_true(o.applied && o.eye_w == 720 && o.eye_h == 800);
    /* a tiny size stays as it is */
    in = (fv_app_interactive_in){.software = true, .interactive = true, .eye_w = 16, .eye_h = 16, .hz = 90,
                                 .cpu_cores = 1};
    fv_app_interactive_start(&in, &o);
    assert_true(o.eye_w == 16 && o.eye_h == 16);
    /* not applied: a GPU, a run that is not interactive, a size or a budget the user chose */
    fv_app_interactive_in base = {.software = true, .interactive = true, .eye_w = 720, .eye_h = 800, .hz = 90,
                                  .cpu_cores = 2};
    in = base;
    in.software = false;
    fv_app_interactive_start(&in, &o);
    assert_false(o.applied);
    assert_true(o.eye_w == 720 && o.eye_h == 800 && !o.budget);
    in = base;
    in.interactive = false;
    fv_app_interactive_start(&in, &o);
    assert_false(o.applied);
    in = base;
    in.size_given = true;
    fv_app_interactive_start(&in, &o);
    assert_false(o.applied);
    in = base;
    in.budget_given = true;
    fv_app_interactive_start(&in, &o);
    assert_false(o.applied);
}

static void budget_changes_are_one_line_each_at_the_default_level(void **state)
{
    (void)state;
    fv_log_set_level("*", FV_LOG_LEVEL_WARN); /* the default */
    fv_quality q = fv_quality_default();
    q.exposure = 2.0f;
    fv_app_budget b;
    fv_test_log_capture_begin();
    assert_int_equal(fv_app_budget_start(&b, "run", &q, "balanced", 90.0, 1.0, NULL), FV_OK);
    assert_true(b.rung_count > 2);
    for (uint64_t f = 0; f < 200; f++) (void)fv_app_budget_push(&b, f + 1, 40.0, &q); /* far over 11.1 ms */
    fv_test_log_capture_end();
    print_message("%llu changes, level %u; log:\n%s", (unsigned long long)b.changes, b.ctl.level, fv_test_log_text());
    assert_true(b.changes >= 2);
    assert_int_equal(fv_test_log_lines("budget: frame", NULL), (int)b.changes);
    assert_true(b.ctl.level > 0);
    assert_true(q.exposure == 2.0f); /* the view settings stay the run's */
    assert_int_equal(b.log_n, (size_t)b.changes);
    assert_true(b.log[0].down);
    /* the OpenXR runtime's budget: only the knobs its own work reads (the insets' MAR model) */
    fv_quality base = fv_quality_default();
    assert_int_equal(fv_app_budget_start(&b, "xr", &base, "balanced", 90.0, 1.0, NULL), FV_OK);
    const char *const mar[] = {"fovea.mar_slope", "fovea.mar_w0_deg", NULL};
    assert_int_equal(fv_app_budget_keep_knobs(&b, mar), FV_OK);
    assert_int_equal(b.rung_count, 2);
    assert_true(!strcmp(b.rungs[0].knob->name, mar[0]) || !strcmp(b.rungs[0].knob->name, mar[1]));
    fv_log_set_level("*", FV_LOG_LEVEL_ERROR); /* quiet: the steps were checked above */
    for (uint64_t f = 0; f < 100; f++) (void)fv_app_budget_push(&b, f + 1, 40.0, &base);
    fv_log_set_level("*", FV_LOG_LEVEL_WARN);
    assert_int_equal(b.ctl.level, 2);
    assert_true(base.fovea.mar_slope > fv_quality_default().fovea.mar_slope); /* coarser periphery: smaller insets */
    /* a period that cannot be budgeted: one line naming it */
    fv_test_log_capture_begin();
    assert_int_equal(fv_app_budget_start(&b, "run", &q, "balanced", 0.0, 1.0, NULL), FV_ERR_INVALID_ARG);
    fv_test_log_capture_end();
    fv_assert_log_contains("cannot be budgeted");
}

static void one_driver_list_with_the_plugin_and_a_tracker_on_it(void **state)
{
    (void)state;
    const fv_driver *const *list = fv_app_drivers();
    const char *want[] = {"hid", "usb", "pupil", "probe", "trace", "fixed", "mouse", "sim"};
    size_t n = 0;
    for (; list[n]; n++) {
        print_message("driver %zu: %s (%s)\n", n, list[n]->scheme, list[n]->summary);
        assert_true(n < sizeof want / sizeof want[0]);
        assert_string_equal(list[n]->scheme, want[n]); /* each once, the plug-in before the virtual drivers */
    }
    assert_int_equal(n, sizeof want / sizeof want[0]);
    assert_true(fv_app_drivers() == list); /* built once */
    fv_device *dev = NULL;
    fv_test_log_capture_begin();
    assert_int_equal(fv_app_device_open("nope:x", &(fv_device_open_desc){.clock = fv_clock_monotonic()}, &dev),
                     FV_ERR_NOT_FOUND);
    fv_test_log_capture_end();
    fv_assert_log_contains("probe"); /* the known schemes listed include the plug-in's */
    /* the tracker of `fovea run --gaze` and the OpenXR runtime on the plug-in's device */
    fv_app_tracker *t = NULL;
    fv_app_tracker_desc td = {.uri = "probe:yaw_deg=12,pitch_deg=-4,rate_hz=500", .who = "test"};
    assert_int_equal(fv_app_tracker_open(&td, &t), FV_OK);
    fv_gaze_prediction p = {0};
    for (int i = 0; i < 300 && !(p.combined_valid && p.event != FV_GAZE_EVENT_NONE); i++) {
        usleep(5000);
        fv_app_tracker_predict(t, fv_clock_now_ns(fv_clock_monotonic()), &p);
    }
    assert_true(p.combined_valid);
    double yaw = atan2(p.combined_dir_head.x, -p.combined_dir_head.z) * 180.0 / M_PI;
    print_message("probe: yaw %.3f deg, event %d, uncertainty %.2f\n", yaw, p.event, (double)p.uncertainty_deg);
    assert_true(fabs(yaw - 12.0) < 0.05);
    assert_false(fv_app_tracker_drain(t)); /* connected and delivering: not lost */
    fv_app_head_report hr;
    fv_app_tracker_head_report(t, &hr);
    assert_true(hr.flagged == 0 && hr.moved == 0); /* a fixed gaze carries no head pose */
    fv_app_tracker_close(&t);
    assert_null(t);
    /* a source that cannot be opened fails at once, naming it */
    fv_test_log_capture_begin();
    td.uri = "probe:yaw_deg=oops";
    assert_true(FV_FAILED(fv_app_tracker_open(&td, &t)));
    fv_test_log_capture_end();
    assert_null(t);
    fv_assert_log_contains("cannot open gaze source 'probe:yaw_deg=oops'");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_app PROBE_PLUGIN.so\n");
        return 2;
    }
    g_plugin = argv[1];
    setenv("FOVEA_DRIVERS", g_plugin, 1); /* before the list is built (its first use) */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gpu_time_is_gpu_when_the_draw_waited_for_it),
        cmocka_unit_test(software_device_starts_interactive_runs_where_the_budget_holds),
        cmocka_unit_test(budget_changes_are_one_line_each_at_the_default_level),
        cmocka_unit_test(one_driver_list_with_the_plugin_and_a_tracker_on_it),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
