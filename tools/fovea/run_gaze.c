/* @brief Gaze for `fovea run` (see run_gaze.h). */
#include "run_gaze.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <string.h>

#include "fv_log.h"
#include "tool_devices.h"

fv_result run_gaze_open(run_gaze *g, const char *uri)
{
    memset(g, 0, sizeof *g);
    snprintf(g->uri, sizeof g->uri, "%s", uri);
    fv_device_open_desc desc = {.clock = fv_clock_monotonic()};
    FV_TRY(fv_tool_device_open(uri, &desc, &g->dev));
    fv_gaze_pipeline_desc pd = {0};
    fv_result r = fv_gaze_pipeline_create(&pd, &g->pipeline);
    if (FV_FAILED(r)) fv_device_close(&g->dev);
    return r;
}

void run_gaze_latch(run_gaze *g, int64_t t_photon_ns, fv_frame_input *in)
{
    g->frames++;
    fv_gaze_sample buf[64];
    /* Drain what has arrived; bounded so a flooding device cannot hold the frame. */
    for (int round = 0; g->dev && !g->ended && round < 64; round++) {
        size_t n = 0;
        fv_result r = fv_device_read(g->dev, buf, 64, &n, 0);
        for (size_t i = 0; i < n; i++) {
            if (fv_gaze_pipeline_push(g->pipeline, &buf[i]) == FV_OK) g->samples++;
            else g->rejected++;
        }
        if (r == FV_END_OF_STREAM) {
            g->ended = true;
            break;
        }
        if (r == FV_ERR_DEVICE_LOST) {
            if (!g->lost) FV_WARN("run", "%s: gaze device lost; rendering on with widened uncertainty", g->uri);
            g->lost = true;
            fv_gaze_pipeline_set_device_lost(g->pipeline, true, t_photon_ns);
            break;
        }
        if (r != FV_OK || n == 0) break;
    }
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
}

void run_gaze_close(run_gaze *g)
{
    fv_gaze_pipeline_destroy(&g->pipeline);
    fv_device_close(&g->dev);
}
