/* @brief Gaze-driven runs of `fovea run` (see run_gaze.h). */
#include "run_gaze.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "fv_log.h"
#include "fv_sim_display.h"
#include "fv_usb_hotplug.h"
#include "tool_devices.h"

static fv_result open_uri(void *user, const char *uri, const fv_device_open_desc *desc, fv_device **out)
{
    (void)user;
    return fv_tool_device_open(uri, desc, out);
}

fv_result run_gaze_open_on(run_gaze *g, const char *uri, fv_display *display, double refresh_hz, size_t frames,
                           fv_frame_render_fn render, void *render_user, float ipd_mm, bool no_predict)
{
    memset(g, 0, sizeof *g);
    snprintf(g->uri, sizeof g->uri, "%s", uri);
    g->refresh_hz = refresh_hz;
    g->records = calloc(frames ? frames : 1, sizeof *g->records);
    if (!g->records) return FV_ERR_NO_MEMORY;
    g->cap = frames;
    const fv_clock *clock = fv_clock_monotonic();
    if (display) {
        g->display = display;
        g->display_borrowed = true;
        g->refresh_hz = display->refresh_hz;
        snprintf(g->clock, sizeof g->clock, "swapchain");
    } else {
        fv_sim_display_desc dd = {.clock = clock, .refresh_hz = refresh_hz};
        FV_TRY(fv_sim_display_create(&dd, &g->display));
        snprintf(g->clock, sizeof g->clock, "simulated display");
    }
    fv_gaze_source_desc sd = {
        .uri = uri,
        .open = open_uri,
        .open_desc = {.clock = clock},
        .mode = FV_GAZE_SOURCE_THREAD,
    };
    FV_TRY(fv_gaze_source_create(&sd, &g->source));
    fv_gaze_pipeline_desc pd = {.disable_prediction = no_predict};
    FV_TRY(fv_gaze_pipeline_create(&pd, &g->pipeline));
    /* A hardware tracker that is unplugged and plugged back is re-opened as soon as it arrives. Without hotplug
     * support (no udev, no permission) the source still re-opens on its backoff. */
    if (strncmp(uri, "hid:", 4) == 0 || strncmp(uri, "usb:", 4) == 0) {
        if (FV_FAILED(fv_usb_hotplug_start(&g->hotplug)))
            FV_INFO("run", "%s: no USB hotplug events; a lost tracker is re-opened on a backoff", uri);
    }
    double tracker_ms = 0.0; /* what the URI declares (a sim: eye's latency_ms), as `fovea latency` counts it */
    FV_TRY(fv_tool_declared_latency_ms(uri, &tracker_ms));
    fv_frame_loop_desc ld = {
        .tracker_latency_ns = (int64_t)llround(tracker_ms * 1e6),
        .clock = clock,
        .display = g->display,
        .render = render,
        .render_user = render_user,
        .gaze = g->source,
        .pipeline = g->pipeline,
        .ipd_mm = ipd_mm,
    };
    return fv_frame_loop_create(&ld, &g->loop);
}

fv_result run_gaze_step(run_gaze *g)
{
    if (g->count >= g->cap) return FV_ERR_STATE;
    if (g->hotplug && fv_usb_hotplug_take_reprobe(g->hotplug)) {
        g->reprobes++;
        fv_gaze_source_reprobe(g->source);
    }
    FV_TRY(fv_frame_loop_step(g->loop, &g->records[g->count]));
    g->count++;
    return FV_OK;
}

static void summarize(const run_gaze *g, fv_latency_summary *s, fv_gaze_source_status *st)
{
    if (FV_FAILED(fv_latency_summarize(g->records, g->count, s))) memset(s, 0, sizeof *s);
    fv_gaze_source_get_status(g->source, st);
}

void run_gaze_print(const run_gaze *g, FILE *f)
{
    fv_latency_summary s;
    fv_gaze_source_status st;
    summarize(g, &s, &st);
    fv_gaze_prediction last;
    fv_frame_loop_last_prediction(g->loop, &last);
    fprintf(f, "  gaze: %s (%s): %llu samples: %llu delivered, %llu overruns (dropped as stale, newest kept); %llu "
               "losses; last event %s, uncertainty %.2f deg\n",
            g->uri, fv_gaze_source_state_str(st.state), (unsigned long long)st.samples,
            (unsigned long long)st.delivered, (unsigned long long)st.overruns, (unsigned long long)st.losses,
            fv_gaze_event_str(last.event), last.uncertainty_deg);
    fprintf(f, "  gaze-to-photon (%.1f Hz %s, %zu of %zu frames with gaze): p50 %.2f ms, p95 %.2f ms, "
               "p99 %.2f ms; %zu late frames, %zu repeated refreshes\n",
            g->display_borrowed ? g->display->refresh_hz : g->refresh_hz, g->clock, s.frames_with_gaze, s.frames, s.g2p_p50_ms, s.g2p_p95_ms, s.g2p_p99_ms, s.late_frames,
            s.repeated_vsyncs);
    fprintf(f, "  stages (mean ms):");
    for (int k = 0; k < FV_LATENCY_STAGE_COUNT; k++)
        fprintf(f, " %s %.2f", fv_latency_stage_str((fv_latency_stage)k), s.stage_mean_ms[k]);
    fprintf(f, "\n");
}

void run_gaze_add_json(const run_gaze *g, cJSON *obj)
{
    fv_latency_summary s;
    fv_gaze_source_status st;
    summarize(g, &s, &st);
    cJSON *j = cJSON_AddObjectToObject(obj, "gaze");
    fv_cli_json_add_string(j, "uri", g->uri);
    fv_cli_json_add_string(j, "state", fv_gaze_source_state_str(st.state));
    cJSON_AddNumberToObject(j, "samples", (double)st.samples);
    cJSON_AddNumberToObject(j, "delivered", (double)st.delivered);
    cJSON_AddNumberToObject(j, "overruns", (double)st.overruns); /* dropped as stale, newest kept */
    cJSON_AddNumberToObject(j, "losses", (double)st.losses);
    cJSON *l = cJSON_AddObjectToObject(obj, "latency");
    cJSON_AddNumberToObject(l, "refresh_hz", g->display_borrowed ? g->display->refresh_hz : g->refresh_hz);
    fv_cli_json_add_string(l, "clock", g->clock);
    cJSON_AddNumberToObject(l, "frames_with_gaze", (double)s.frames_with_gaze);
    cJSON_AddNumberToObject(l, "gaze_to_photon_ms_p50", s.g2p_p50_ms);
    cJSON_AddNumberToObject(l, "gaze_to_photon_ms_p95", s.g2p_p95_ms);
    cJSON_AddNumberToObject(l, "gaze_to_photon_ms_p99", s.g2p_p99_ms);
    cJSON_AddNumberToObject(l, "late_frames", (double)s.late_frames);
    cJSON_AddNumberToObject(l, "repeated_refreshes", (double)s.repeated_vsyncs);
    cJSON *stages = cJSON_AddObjectToObject(l, "stage_mean_ms");
    for (int k = 0; k < FV_LATENCY_STAGE_COUNT; k++)
        cJSON_AddNumberToObject(stages, fv_latency_stage_str((fv_latency_stage)k), s.stage_mean_ms[k]);
}

void run_gaze_close(run_gaze *g)
{
    fv_usb_hotplug_stop(&g->hotplug);
    fv_frame_loop_destroy(&g->loop);
    fv_gaze_pipeline_destroy(&g->pipeline);
    fv_gaze_source_destroy(&g->source);
    if (!g->display_borrowed) fv_display_destroy(&g->display);
    g->display = NULL;
    free(g->records);
    g->records = NULL;
}
