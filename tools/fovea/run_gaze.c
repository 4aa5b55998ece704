/* @brief Gaze-driven runs of `fovea run` (see run_gaze.h). */
#include "run_gaze.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "fv_log.h"
#include "fv_sim_display.h"

fv_result run_gaze_open(run_gaze *g, const char *uri, bool no_predict)
{
    memset(g, 0, sizeof *g);
    snprintf(g->uri, sizeof g->uri, "%s", uri);
    fv_app_tracker_desc td = {.uri = uri, .mode = FV_GAZE_SOURCE_THREAD, .no_predict = no_predict, .who = "run"};
    return fv_app_tracker_open(&td, &g->tracker);
}

fv_result run_gaze_start(run_gaze *g, fv_display *display, double refresh_hz, size_t frames, fv_frame_render_fn render,
                         void *render_user, float ipd_mm)
{
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
    fv_frame_loop_desc ld = {
        .tracker_latency_ns = fv_app_tracker_latency_ns(g->tracker), /* as `fovea latency` counts it */
        .clock = clock,
        .display = g->display,
        .render = render,
        .render_user = render_user,
        .drain = fv_app_tracker_drain_state(g->tracker),
        .ipd_mm = ipd_mm,
    };
    return fv_frame_loop_create(&ld, &g->loop);
}

fv_result run_gaze_step(run_gaze *g)
{
    if (g->count >= g->cap) return FV_ERR_STATE;
    fv_app_tracker_hotplug(g->tracker); /* a tracker that came back is re-opened; the loop drains at its latch */
    FV_TRY(fv_frame_loop_step(g->loop, &g->records[g->count]));
    g->count++;
    return FV_OK;
}

static void summarize(const run_gaze *g, fv_latency_summary *s, fv_gaze_source_status *st)
{
    if (FV_FAILED(fv_latency_summarize(g->records, g->count, s))) memset(s, 0, sizeof *s);
    fv_gaze_source_get_status(fv_app_tracker_source(g->tracker), st);
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
    fv_frame_loop_destroy(&g->loop);
    fv_app_tracker_close(&g->tracker);
    if (!g->display_borrowed) fv_display_destroy(&g->display);
    g->display = NULL;
    free(g->records);
    g->records = NULL;
}
