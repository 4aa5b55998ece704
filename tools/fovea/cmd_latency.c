/* @brief `fovea latency --gaze URI [--hz 90] [--render-ms X] [--frames N] [--json]`: runs the frame loop on a
 * simulated clock with a simulated display and a stand-in renderer, reading the gaze device inline (deterministic),
 * and reports gaze-to-photon percentiles, missed refreshes and the share of latency per stage. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "fv_frame_loop.h"
#include "fv_log.h"
#include "fv_sim_display.h"
#include "fv_standin_render.h"
#include "run_frame_log.h"
#include "fv_stats.h"
#include "fv_app_drivers.h"

static const char *g_usage =
    "usage: fovea latency --gaze URI [--hz HZ] [--render-ms MS] [--frames N] [--json] [options]\n"
    "       fovea latency --frame-log FILE.csv [--json]\n"
    "  Run the frame loop on a simulated clock: a simulated display, the gaze device read each frame, the gaze\n"
    "  pipeline predicting to photon time, and a stand-in renderer of the given cost. Reports gaze-to-photon\n"
    "  p50/p95/p99, missed refreshes and the share of each stage.\n"
    "  --gaze URI             sim:seed=1, trace:FILE, ... (required)\n"
    "  --hz HZ                display refresh rate, 1..1000 (default 90)\n"
    "  --render-ms MS         stand-in render cost per frame, 0..1000 (default 5)\n"
    "  --cpu-share F          part of the render cost spent on the CPU before submit, 0..1 (default 0.25)\n"
    "  --render-jitter-ms MS  render cost varies by up to ±MS/2 (default 0)\n"
    "  --frames N             frames to run, 1..1000000 (default 900)\n"
    "  --tracker-ms MS        the tracker's capture-to-receipt latency, counted in gaze-to-photon\n"
    "                         (default: the sim: URI's latency_ms, else 0 = unknown)\n"
    "  --vsync-jitter-us US   display vsync jitter, ± (default 0)\n"
    "  --persistence-ms MS    panel persistence (default 2, at most the period)\n"
    "  --global               global (strobed) panel instead of a rolling scan-out\n"
    "  --seed N               seed for the jitters (default 1)\n"
    "  --json                 machine-readable output\n"
    "  --frame-log FILE.csv   instead of simulating: the statistics of a real run's per-frame record\n"
    "                         (fovea run --frame-log FILE.csv): gaze-to-photon percentiles, missed refreshes,\n"
    "                         stages, GPU time and uncertainty per frame\n";

typedef struct options {
    const char *uri;
    const char *frame_log;
    const char *sim_option; /* the first simulation option given (refused with --frame-log) */
    double hz, render_ms, cpu_share, render_jitter_ms, tracker_ms, vsync_jitter_us, persistence_ms;
    bool tracker_given, global, json;
    int64_t frames, seed;
} options;

static int parse(int argc, char **argv, options *o)
{
    *o = (options){.hz = 90.0, .render_ms = 5.0, .cpu_share = 0.25, .frames = 900, .seed = 1, .persistence_ms = -1};
    for (int i = 1; i < argc; i++) {
        const char *v = NULL;
        int m;
#define OPT(name) ((m = fv_cli_option(argc, argv, &i, name, &v)) != 0)
#define NEED(name)                                                                                                     \
    if (m < 0) return fv_cli_usage_error("latency", g_usage, "%s needs a value", name)
#define F64(name, lo, hi, dst)                                                                                         \
    if (OPT(name)) {                                                                                                   \
        NEED(name);                                                                                                    \
        if (!o->sim_option) o->sim_option = name;                                                                      \
        if (!fv_cli_parse_f64(v, lo, hi, dst))                                                                         \
            return fv_cli_usage_error("latency", g_usage, "%s '%s': expected a number in %g..%g", name, v,            \
                                      (double)(lo), (double)(hi));                                                     \
        continue;                                                                                                      \
    }
        if (fv_cli_is_help(argv[i])) {
            fputs(g_usage, stdout);
            return -1;
        }
        if (strcmp(argv[i], "--json") == 0) {
            o->json = true;
            continue;
        }
        if (strcmp(argv[i], "--global") == 0) {
            if (!o->sim_option) o->sim_option = "--global";
            o->global = true;
            continue;
        }
        if (OPT("--gaze")) {
            NEED("--gaze");
            o->uri = v;
            continue;
        }
        if (OPT("--frame-log")) {
            NEED("--frame-log");
            o->frame_log = v;
            continue;
        }
        if (OPT("--frames")) {
            NEED("--frames");
            if (!o->sim_option) o->sim_option = "--frames";
            if (!fv_cli_parse_i64(v, 1, 1000000, &o->frames))
                return fv_cli_usage_error("latency", g_usage, "--frames '%s': expected an integer in 1..1000000", v);
            continue;
        }
        if (OPT("--seed")) {
            NEED("--seed");
            if (!o->sim_option) o->sim_option = "--seed";
            if (!fv_cli_parse_i64(v, 0, INT64_MAX, &o->seed))
                return fv_cli_usage_error("latency", g_usage, "--seed '%s': expected a non-negative integer", v);
            continue;
        }
        F64("--hz", 1.0, 1000.0, &o->hz)
        F64("--render-ms", 0.0, 1000.0, &o->render_ms)
        F64("--cpu-share", 0.0, 1.0, &o->cpu_share)
        F64("--render-jitter-ms", 0.0, 1000.0, &o->render_jitter_ms)
        F64("--vsync-jitter-us", 0.0, 1e6, &o->vsync_jitter_us)
        F64("--persistence-ms", 0.0, 1000.0, &o->persistence_ms)
        if (OPT("--tracker-ms")) {
            NEED("--tracker-ms");
            if (!o->sim_option) o->sim_option = "--tracker-ms";
            if (!fv_cli_parse_f64(v, 0.0, 1000.0, &o->tracker_ms))
                return fv_cli_usage_error("latency", g_usage, "--tracker-ms '%s': expected a number in 0..1000", v);
            o->tracker_given = true;
            continue;
        }
#undef OPT
#undef NEED
#undef F64
        return fv_cli_usage_error("latency", g_usage, "unknown argument '%s'", argv[i]);
    }
    if (o->frame_log && o->uri)
        return fv_cli_usage_error("latency", g_usage, "--frame-log reads a recorded run; --gaze simulates one: give "
                                  "one of them");
    if (o->frame_log && o->sim_option)
        return fv_cli_usage_error("latency", g_usage, "%s sets up the simulation and has no effect with --frame-log",
                                  o->sim_option);
    if (o->frame_log) return 0;
    if (!o->uri) return fv_cli_usage_error("latency", g_usage, "--gaze URI is required");
    if (o->render_jitter_ms > o->render_ms)
        return fv_cli_usage_error("latency", g_usage, "--render-jitter-ms %g exceeds --render-ms %g",
                                  o->render_jitter_ms, o->render_ms);
    double period_ms = 1000.0 / o->hz;
    if (o->persistence_ms < 0) o->persistence_ms = period_ms < 2.0 ? period_ms : 2.0; /* default */
    if (o->persistence_ms > period_ms)
        return fv_cli_usage_error("latency", g_usage, "--persistence-ms %g exceeds the refresh period %.3f ms",
                                  o->persistence_ms, period_ms);
    if (o->vsync_jitter_us / 1000.0 > period_ms / 4)
        return fv_cli_usage_error("latency", g_usage, "--vsync-jitter-us %g exceeds a quarter of the period",
                                  o->vsync_jitter_us);
    return 0;
}

/* The declared tracker latency: --tracker-ms, else what a sim: URI says, else 0 (unknown). A sim: URI that does not
 * parse fails here, once (its error is logged by the parser; opening it again would log it twice). */
static fv_result tracker_latency_ms(const options *o, double *out_ms, const char **out_origin)
{
    *out_ms = 0.0;
    *out_origin = "unknown, counted as 0 (use --tracker-ms)";
    if (strncmp(o->uri, "sim:", 4) == 0) {
        double ms;
        FV_TRY(fv_app_declared_latency_ms(o->uri, &ms)); /* the same as `fovea run` counts */
        if (!o->tracker_given) {
            *out_origin = "the simulated eye's latency_ms";
            *out_ms = ms;
        }
    }
    if (o->tracker_given) {
        *out_origin = "declared with --tracker-ms";
        *out_ms = o->tracker_ms;
    }
    return FV_OK;
}

static const char *stage_what(fv_latency_stage s)
{
    switch (s) {
    case FV_LATENCY_TRACKER: return "capture -> host receipt";
    case FV_LATENCY_SAMPLE_AGE: return "receipt -> latch";
    case FV_LATENCY_LATCH: return "latch -> render (predict, frame input)";
    case FV_LATENCY_CPU: return "CPU render";
    case FV_LATENCY_GPU: return "GPU render";
    case FV_LATENCY_PRESENT: return "GPU end -> vsync";
    case FV_LATENCY_DISPLAY: return "vsync -> photon (scan-out, persistence)";
    case FV_LATENCY_STAGE_COUNT: break;
    }
    return "";
}

static void print_text(const options *o, const fv_latency_summary *s, const fv_gaze_source_status *st,
                       double tracker_ms, const char *tracker_origin, const fv_standin_render *standin)
{
    printf("fovea latency: %s -> %.3g Hz simulated display, stand-in render %.2f ms (CPU %.2f + GPU %.2f), "
           "%zu frames on a simulated clock\n",
           o->uri, o->hz, o->render_ms, (double)standin->cpu_ns / 1e6, (double)standin->gpu_ns / 1e6, s->frames);
    if (s->frames_with_gaze)
        printf("gaze-to-photon  p50 %.2f ms  p95 %.2f ms  p99 %.2f ms  (min %.2f, mean %.2f, max %.2f; %zu frames "
               "with gaze)\n",
               s->g2p_p50_ms, s->g2p_p95_ms, s->g2p_p99_ms, s->g2p_min_ms, s->g2p_mean_ms, s->g2p_max_ms,
               s->frames_with_gaze);
    else
        printf("gaze-to-photon  no gaze sample reached any frame\n");
    printf("missed          %zu (%zu late frames, %zu repeated refreshes) in %zu frames; refresh period %.3f ms, "
           "mean frame interval %.3f ms\n",
           s->missed, s->late_frames, s->repeated_vsyncs, s->frames, 1000.0 / o->hz, s->frame_interval_mean_ms);
    printf("device          %s; %llu samples: %llu delivered, %llu overruns (dropped as stale, newest kept: ring of "
           "%zu); %llu losses, %llu re-opens; %zu frames without gaze or stalled, %zu reused an old sample\n",
           fv_gaze_source_state_str(st->state), (unsigned long long)st->samples, (unsigned long long)st->delivered,
           (unsigned long long)st->overruns, st->ring_capacity, (unsigned long long)st->losses,
           (unsigned long long)st->reopens, s->lost_frames, s->stale_frames);
    if (st->poll_limited)
        printf("                %llu polls stopped with the device still delivering (it never ran dry)\n",
               (unsigned long long)st->poll_limited);
    printf("tracker latency %.2f ms (%s)\n", tracker_ms, tracker_origin);
    if (!s->frames_with_gaze) return;
    printf("stages (mean, share of gaze-to-photon):\n");
    for (int i = 0; i < FV_LATENCY_STAGE_COUNT; i++)
        printf("  %-11s %7.2f ms  %5.1f%%  %s\n", fv_latency_stage_str((fv_latency_stage)i), s->stage_mean_ms[i],
               100.0 * s->stage_share[i], stage_what((fv_latency_stage)i));
}

static int print_json(const options *o, const fv_latency_summary *s, const fv_gaze_source_status *st,
                      double tracker_ms)
{
    cJSON *root = cJSON_CreateObject();
    if (!root) return FV_EXIT_FAIL;
    fv_cli_json_add_string(root, "gaze", o->uri);
    cJSON_AddNumberToObject(root, "hz", o->hz);
    cJSON_AddNumberToObject(root, "render_ms", o->render_ms);
    cJSON_AddNumberToObject(root, "frames", (double)s->frames);
    cJSON_AddNumberToObject(root, "frames_with_gaze", (double)s->frames_with_gaze);
    cJSON_AddNumberToObject(root, "tracker_latency_ms", tracker_ms);
    cJSON *g = cJSON_AddObjectToObject(root, "gaze_to_photon_ms");
    cJSON_AddNumberToObject(g, "p50", s->g2p_p50_ms);
    cJSON_AddNumberToObject(g, "p95", s->g2p_p95_ms);
    cJSON_AddNumberToObject(g, "p99", s->g2p_p99_ms);
    cJSON_AddNumberToObject(g, "min", s->g2p_min_ms);
    cJSON_AddNumberToObject(g, "mean", s->g2p_mean_ms);
    cJSON_AddNumberToObject(g, "max", s->g2p_max_ms);
    cJSON_AddNumberToObject(root, "missed", (double)s->missed);
    cJSON_AddNumberToObject(root, "late_frames", (double)s->late_frames);
    cJSON_AddNumberToObject(root, "repeated_vsyncs", (double)s->repeated_vsyncs);
    cJSON_AddNumberToObject(root, "lost_frames", (double)s->lost_frames);
    cJSON_AddNumberToObject(root, "stale_frames", (double)s->stale_frames);
    cJSON_AddNumberToObject(root, "frame_interval_mean_ms", s->frame_interval_mean_ms);
    cJSON *stages = cJSON_AddObjectToObject(root, "stages");
    for (int i = 0; i < FV_LATENCY_STAGE_COUNT; i++) {
        cJSON *x = cJSON_AddObjectToObject(stages, fv_latency_stage_str((fv_latency_stage)i));
        cJSON_AddNumberToObject(x, "mean_ms", s->stage_mean_ms[i]);
        cJSON_AddNumberToObject(x, "share", s->stage_share[i]);
    }
    cJSON *dev = cJSON_AddObjectToObject(root, "device");
    fv_cli_json_add_string(dev, "state", fv_gaze_source_state_str(st->state));
    cJSON_AddNumberToObject(dev, "samples", (double)st->samples);
    cJSON_AddNumberToObject(dev, "delivered", (double)st->delivered);
    cJSON_AddNumberToObject(dev, "overruns", (double)st->overruns); /* dropped as stale, newest kept */
    cJSON_AddNumberToObject(dev, "poll_limited", (double)st->poll_limited);
    cJSON_AddNumberToObject(dev, "losses", (double)st->losses);
    cJSON_AddNumberToObject(dev, "reopens", (double)st->reopens);
    int rc = fv_cli_json_print(root, true);
    cJSON_Delete(root);
    return rc;
}

/* Median and p95 of the finite values (NaN when there are none). */
static void finite_pcts(const double *v, size_t n, double *out_p50, double *out_p95, size_t *out_count)
{
    *out_p50 = *out_p95 = NAN;
    *out_count = 0;
    double *tmp = malloc((n ? n : 1) * sizeof *tmp);
    if (!tmp) return;
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        if (isfinite(v[i])) tmp[k++] = v[i];
    if (k) {
        *out_p50 = fv_percentile_f64(tmp, k, 50);
        *out_p95 = fv_percentile_f64(tmp, k, 95);
    }
    *out_count = k;
    free(tmp);
}

/* `fovea latency --frame-log FILE`: the same statistics from a real run's per-frame record. */
static int frame_log_stats(const options *o)
{
    run_frame_log log;
    if (FV_FAILED(run_frame_log_read(o->frame_log, &log))) {
        fprintf(stderr, "fovea latency: cannot read the frame log '%s' (see the message above)\n", o->frame_log);
        return FV_EXIT_FAIL;
    }
    int rc = FV_EXIT_FAIL;
    fv_latency_summary s;
    double gpu50, gpu95, unc50, unc95;
    size_t gpu_n, unc_n;
    /* The GPU stage from the GPU's own time (a log whose run booked it as CPU: a draw that waited for a software
     * device inside it, written before the frame loop's fv_frame_times_from_fence split it) */
    for (size_t i = 0; i < log.n; i++) {
        fv_latency_record *rec = &log.records[i];
        if (!rec->t_cpu_begin_ns || !rec->t_gpu_end_ns || !isfinite(log.gpu_ms[i]) || !(log.gpu_ms[i] > 0)) continue;
        fv_frame_render_times t;
        fv_frame_times_from_fence(rec->t_cpu_begin_ns, rec->t_submit_ns, rec->t_gpu_end_ns,
                                  (int64_t)(log.gpu_ms[i] * 1e6), &t);
        rec->t_submit_ns = t.t_submit_ns;
        rec->t_gpu_begin_ns = t.t_gpu_begin_ns;
    }
    if (FV_FAILED(fv_latency_summarize(log.records, log.n, &s))) goto done;
    finite_pcts(log.gpu_ms, log.n, &gpu50, &gpu95, &gpu_n);
    finite_pcts(log.uncertainty_deg, log.n, &unc50, &unc95, &unc_n);
    if (o->json) {
        cJSON *root = cJSON_CreateObject();
        if (!root) goto done;
        fv_cli_json_add_string(root, "frame_log", o->frame_log);
        cJSON_AddNumberToObject(root, "frames", (double)log.n);
        cJSON_AddNumberToObject(root, "frames_from_gaze_run", (double)log.rows_with_gaze_columns);
        cJSON_AddNumberToObject(root, "frames_with_gaze", (double)s.frames_with_gaze);
        cJSON *g = cJSON_AddObjectToObject(root, "gaze_to_photon_ms");
        fv_cli_json_number(g, "p50", s.frames_with_gaze ? s.g2p_p50_ms : NAN);
        fv_cli_json_number(g, "p95", s.frames_with_gaze ? s.g2p_p95_ms : NAN);
        fv_cli_json_number(g, "p99", s.frames_with_gaze ? s.g2p_p99_ms : NAN);
        fv_cli_json_number(g, "min", s.frames_with_gaze ? s.g2p_min_ms : NAN);
        fv_cli_json_number(g, "mean", s.frames_with_gaze ? s.g2p_mean_ms : NAN);
        fv_cli_json_number(g, "max", s.frames_with_gaze ? s.g2p_max_ms : NAN);
        cJSON_AddNumberToObject(root, "missed", (double)s.missed);
        cJSON_AddNumberToObject(root, "late_frames", (double)s.late_frames);
        cJSON_AddNumberToObject(root, "repeated_vsyncs", (double)s.repeated_vsyncs);
        cJSON_AddNumberToObject(root, "lost_frames", (double)s.lost_frames);
        cJSON_AddNumberToObject(root, "stale_frames", (double)s.stale_frames);
        cJSON *stages = cJSON_AddObjectToObject(root, "stages");
        for (int i = 0; i < FV_LATENCY_STAGE_COUNT; i++) {
            cJSON *x = cJSON_AddObjectToObject(stages, fv_latency_stage_str((fv_latency_stage)i));
            cJSON_AddNumberToObject(x, "mean_ms", s.stage_mean_ms[i]);
            cJSON_AddNumberToObject(x, "share", s.stage_share[i]);
        }
        cJSON *gp = cJSON_AddObjectToObject(root, "gpu_ms");
        cJSON_AddNumberToObject(gp, "frames", (double)gpu_n);
        fv_cli_json_number(gp, "p50", gpu50);
        fv_cli_json_number(gp, "p95", gpu95);
        cJSON *un = cJSON_AddObjectToObject(root, "uncertainty_deg");
        cJSON_AddNumberToObject(un, "frames", (double)unc_n);
        fv_cli_json_number(un, "p50", unc50);
        fv_cli_json_number(un, "p95", unc95);
        rc = fv_cli_json_print(root, true);
        cJSON_Delete(root);
    } else {
        char b1[32], b2[32];
        printf("fovea latency: frame log %s: %zu frames (%zu from a --gaze run)\n", o->frame_log, log.n,
               log.rows_with_gaze_columns);
        if (s.frames_with_gaze)
            printf("gaze-to-photon  p50 %.2f ms  p95 %.2f ms  p99 %.2f ms  (min %.2f, mean %.2f, max %.2f; %zu frames "
                   "with gaze)\n", s.g2p_p50_ms, s.g2p_p95_ms, s.g2p_p99_ms, s.g2p_min_ms, s.g2p_mean_ms,
                   s.g2p_max_ms, s.frames_with_gaze);
        else
            printf("gaze-to-photon  no frame had live gaze%s\n",
                   log.rows_with_gaze_columns ? "" : " (the run had no --gaze)");
        printf("missed          %zu (%zu late frames, %zu repeated refreshes); %zu frames without gaze or stalled, "
               "%zu reused an old sample\n", s.missed, s.late_frames, s.repeated_vsyncs, s.lost_frames,
               s.stale_frames);
        printf("GPU per frame   p50 %s ms  p95 %s ms  (%zu frames timed)\n",
               fv_cli_format_number(b1, sizeof b1, "%.3f", gpu50), fv_cli_format_number(b2, sizeof b2, "%.3f", gpu95),
               gpu_n);
        printf("uncertainty     p50 %s deg  p95 %s deg\n", fv_cli_format_number(b1, sizeof b1, "%.2f", unc50),
               fv_cli_format_number(b2, sizeof b2, "%.2f", unc95));
        if (s.frames_with_gaze) {
            printf("stages (mean, share of gaze-to-photon):\n");
            for (int i = 0; i < FV_LATENCY_STAGE_COUNT; i++)
                printf("  %-11s %7.2f ms  %5.1f%%  %s\n", fv_latency_stage_str((fv_latency_stage)i),
                       s.stage_mean_ms[i], 100.0 * s.stage_share[i], stage_what((fv_latency_stage)i));
        }
        rc = FV_EXIT_OK;
    }
done:
    run_frame_log_fini(&log);
    return rc;
}

int fv_cmd_latency(int argc, char **argv)
{
    options o;
    int pr = parse(argc, argv, &o);
    if (pr < 0) return FV_EXIT_OK; /* --help */
    if (pr > 0) return pr;
    if (o.frame_log) return frame_log_stats(&o);

    int rc = FV_EXIT_FAIL;
    fv_clock clk;
    fv_clock_sim_init(&clk, FV_NS_PER_S);
    fv_display *display = NULL;
    fv_gaze_pipeline *pipeline = NULL;
    fv_gaze_source *source = NULL;
    fv_frame_loop *loop = NULL;
    fv_latency_record *records = NULL;
    fv_standin_render standin;
    const char *tracker_origin = "";
    double tracker_ms = 0.0;
    fv_result r = tracker_latency_ms(&o, &tracker_ms, &tracker_origin);
    if (FV_FAILED(r)) {
        fprintf(stderr, "fovea latency: cannot open '%s' (%s)\n", o.uri, fv_result_str(r));
        return FV_EXIT_FAIL;
    }

    fv_sim_display_desc dd = {.clock = &clk,
                              .refresh_hz = o.hz,
                              .vsync_jitter_ns = (int64_t)llround(o.vsync_jitter_us * 1e3),
                              .seed = (uint64_t)o.seed,
                              .persistence_ns = (int64_t)llround(o.persistence_ms * 1e6),
                              .scan = o.global ? FV_SIM_DISPLAY_GLOBAL : FV_SIM_DISPLAY_ROLLING};
    if (dd.persistence_ns == 0) dd.persistence_ns = 1; /* 0 means "default" to the desc; the user asked for none */
    r = fv_sim_display_create(&dd, &display);
    if (FV_FAILED(r)) goto done;
    fv_gaze_pipeline_desc pd = {0};
    r = fv_gaze_pipeline_create(&pd, &pipeline);
    if (FV_FAILED(r)) goto done;
    fv_gaze_source_desc sd = {.uri = o.uri,
                              .open = fv_app_device_open_fn,
                              .open_desc = {.clock = &clk},
                              .mode = FV_GAZE_SOURCE_INLINE,
                              .clock = &clk};
    r = fv_gaze_source_create(&sd, &source);
    if (FV_FAILED(r)) {
        fprintf(stderr, "fovea latency: cannot open '%s' (%s)\n", o.uri, fv_result_str(r));
        goto done;
    }
    r = fv_standin_render_init(&standin, &clk, (int64_t)llround(o.render_ms * 1e6), o.cpu_share,
                               (int64_t)llround(o.render_jitter_ms * 1e6), (uint64_t)o.seed);
    if (FV_FAILED(r)) goto done;
    fv_frame_loop_desc ld = {.clock = &clk,
                             .display = display,
                             .render = fv_standin_render_frame,
                             .render_user = &standin,
                             .gaze = source,
                             .pipeline = pipeline,
                             .tracker_latency_ns = (int64_t)llround(tracker_ms * 1e6)};
    r = fv_frame_loop_create(&ld, &loop);
    if (FV_FAILED(r)) goto done;
    records = calloc((size_t)o.frames, sizeof *records);
    if (!records) {
        fprintf(stderr, "fovea latency: out of memory for %lld frame records\n", (long long)o.frames);
        goto done;
    }
    for (int64_t i = 0; i < o.frames; i++) {
        r = fv_frame_loop_step(loop, &records[i]);
        if (FV_FAILED(r)) {
            fprintf(stderr, "fovea latency: frame %lld failed (%s)\n", (long long)i, fv_result_str(r));
            goto done;
        }
    }
    fv_latency_summary s;
    r = fv_latency_summarize(records, (size_t)o.frames, &s);
    if (FV_FAILED(r)) goto done;
    fv_gaze_source_status st;
    fv_gaze_source_get_status(source, &st);
    if (o.json) {
        rc = print_json(&o, &s, &st, tracker_ms);
    } else {
        print_text(&o, &s, &st, tracker_ms, tracker_origin, &standin);
        rc = FV_EXIT_OK;
    }
    if (rc == FV_EXIT_OK && s.frames_with_gaze == 0) {
        /* say what happened: nothing came, or samples came but no frame could use them (the device had ended or
         * stalled by the time a frame latched its gaze) */
        if (st.samples == 0)
            fprintf(stderr, "fovea latency: '%s' delivered no gaze sample in %lld frames (device %s)\n", o.uri,
                    (long long)o.frames, fv_gaze_source_state_str(st.state));
        else
            fprintf(stderr, "fovea latency: '%s' delivered %llu gaze sample%s, but none of the %lld frames had live "
                    "gaze (a frame counts gaze only while the device is connected and not stalled; its state: %s)\n",
                    o.uri, (unsigned long long)st.samples, st.samples == 1 ? "" : "s", (long long)o.frames,
                    fv_gaze_source_state_str(st.state));
        rc = FV_EXIT_FAIL;
    }
done:
    free(records);
    fv_frame_loop_destroy(&loop);
    fv_gaze_source_destroy(&source);
    fv_gaze_pipeline_destroy(&pipeline);
    fv_display_destroy(&display);
    return rc;
}
