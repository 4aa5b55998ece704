/* @brief Gaze for `fovea run` (see run_gaze.h). */
#include "run_gaze.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <string.h>

#include "fv_log.h"
#include "tool_devices.h"

static fv_result open_uri(void *user, const char *uri, const fv_device_open_desc *desc, fv_device **out)
{
    (void)user;
    return fv_tool_device_open(uri, desc, out);
}

fv_result run_gaze_open(run_gaze *g, const char *uri)
{
    memset(g, 0, sizeof *g);
    snprintf(g->uri, sizeof g->uri, "%s", uri);
    fv_gaze_source_desc sd = {
        .uri = uri,
        .open = open_uri,
        .open_desc = {.clock = fv_clock_monotonic()},
        .mode = FV_GAZE_SOURCE_THREAD,
    };
    FV_TRY(fv_gaze_source_create(&sd, &g->source));
    fv_gaze_pipeline_desc pd = {0};
    fv_result r = fv_gaze_pipeline_create(&pd, &g->pipeline);
    if (FV_FAILED(r)) fv_gaze_source_destroy(&g->source);
    return r;
}

void run_gaze_latch(run_gaze *g, int64_t t_photon_ns, fv_frame_input *in)
{
    g->frames++;
    /* Drain what the reader thread has queued; the ring is bounded, so this is too. */
    fv_gaze_sample s;
    while (fv_gaze_source_pop(g->source, &s) == FV_OK) {
        if (fv_gaze_pipeline_push(g->pipeline, &s) == FV_OK) g->samples++;
        else g->rejected++;
    }
    fv_gaze_source_get_status(g->source, &g->status);
    bool lost = g->status.state == FV_GAZE_SOURCE_LOST || g->status.state == FV_GAZE_SOURCE_FAILED;
    if (lost != g->lost) {
        if (lost) FV_WARN("run", "%s: gaze device lost; rendering on with widened uncertainty", g->uri);
        fv_gaze_pipeline_set_device_lost(g->pipeline, lost, fv_time_monotonic_ns());
        g->lost = lost;
    }
    g->ended = g->status.state == FV_GAZE_SOURCE_ENDED;
    fv_gaze_pipeline_predict(g->pipeline, t_photon_ns, &g->last);
    bool any = false;
    for (int e = 0; e < 2; e++) {
        in->gaze[e].valid = g->last.eye_valid[e];
        if (g->last.eye_valid[e]) in->gaze[e].dir_eye = g->last.dir_head[e];
        in->gaze[e].uncertainty_deg = g->last.uncertainty_deg;
        any |= g->last.eye_valid[e];
    }
    in->pupil_mm = g->last.pupil_mm;
    in->t_photon_ns = t_photon_ns;
    if (any) g->frames_with_gaze++;
}

void run_gaze_print(const run_gaze *g, FILE *f)
{
    fprintf(f, "  gaze: %s: %llu samples (%llu rejected), gaze on %llu of %llu frames, last event %s, "
               "uncertainty %.2f deg%s\n",
            g->uri, (unsigned long long)g->samples, (unsigned long long)g->rejected,
            (unsigned long long)g->frames_with_gaze, (unsigned long long)g->frames, fv_gaze_event_str(g->last.event),
            g->last.uncertainty_deg, g->ended ? ", source ended" : (g->lost ? ", device lost" : ""));
}

void run_gaze_add_json(const run_gaze *g, cJSON *obj)
{
    cJSON *j = cJSON_AddObjectToObject(obj, "gaze");
    cJSON_AddStringToObject(j, "uri", g->uri);
    cJSON_AddNumberToObject(j, "samples", (double)g->samples);
    cJSON_AddNumberToObject(j, "rejected", (double)g->rejected);
    cJSON_AddNumberToObject(j, "frames_with_gaze", (double)g->frames_with_gaze);
    cJSON_AddStringToObject(j, "last_event", fv_gaze_event_str(g->last.event));
    cJSON_AddNumberToObject(j, "last_uncertainty_deg", g->last.uncertainty_deg);
    cJSON_AddBoolToObject(j, "source_ended", g->ended);
    cJSON_AddBoolToObject(j, "device_lost", g->lost);
    cJSON_AddNumberToObject(j, "overruns", (double)g->status.overruns);
    cJSON_AddNumberToObject(j, "losses", (double)g->status.losses);
}

void run_gaze_close(run_gaze *g)
{
    fv_gaze_pipeline_destroy(&g->pipeline);
    fv_gaze_source_destroy(&g->source);
}
