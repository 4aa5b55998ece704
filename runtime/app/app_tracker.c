/* @brief The gaze tracker of a run (see fv_app_tracker.h). */
#include "fv_app_tracker.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_app_drivers.h"
#include "fv_log.h"
#include "fv_usb_hotplug.h"

struct fv_app_tracker {
    char uri[256];
    const fv_clock *clock;
    fv_gaze_source *source;
    fv_gaze_pipeline *pipeline;
    fv_gaze_drain drain;
    int64_t latency_ns;
    fv_usb_hotplug *hotplug;
    uint64_t reprobes;
    fv_head_follow follow;
    bool have_head;
    fv_quat head_dq;
    fv_vec3 head_dp_m;
    fv_app_head_report head_report;
};

/* Each accepted sample: its head pose relative to the first. */
static void on_sample(void *user, const fv_gaze_sample *s)
{
    fv_app_tracker *t = user;
    if (!(s->flags & FV_GAZE_HEAD_VALID)) return;
    t->head_report.flagged++;
    fv_quat dq;
    fv_vec3 dp;
    if (!fv_head_follow_delta(&t->follow, s, &dq, &dp)) return;
    t->head_report.usable++;
    if (fabsf(dq.x) + fabsf(dq.y) + fabsf(dq.z) > 1e-6f || fabsf(dp.x) + fabsf(dp.y) + fabsf(dp.z) > 1e-6f)
        t->head_report.moved++;
    t->head_dq = dq;
    t->head_dp_m = dp;
    t->have_head = true;
}

fv_result fv_app_tracker_open(const fv_app_tracker_desc *desc, fv_app_tracker **out)
{
    *out = NULL;
    const char *who = desc->who ? desc->who : "gaze";
    if (!desc->uri || !desc->uri[0]) {
        FV_ERROR(who, "no gaze source URI");
        return FV_ERR_INVALID_ARG;
    }
    fv_app_tracker *t = calloc(1, sizeof *t);
    if (!t) return FV_ERR_NO_MEMORY;
    snprintf(t->uri, sizeof t->uri, "%s", desc->uri);
    t->clock = desc->clock ? desc->clock : fv_clock_monotonic();
    double ms = 0.0;
    fv_result r = fv_app_declared_latency_ms(desc->uri, &ms);
    t->latency_ns = (int64_t)llround(ms * 1e6);
    fv_gaze_source_desc sd = {
        .uri = desc->uri,
        .open = fv_app_device_open_fn,
        .open_desc = {.clock = t->clock},
        .mode = desc->mode,
        .clock = t->clock,
        .ring_capacity = desc->ring_capacity,
    };
    if (r == FV_OK) r = fv_gaze_source_create(&sd, &t->source);
    if (FV_FAILED(r)) {
        FV_ERROR(who, "cannot open gaze source '%s' (the reason is above); nothing was started", desc->uri);
        fv_app_tracker_close(&t);
        return r;
    }
    fv_gaze_pipeline_desc pd = {.disable_prediction = desc->no_predict};
    r = fv_gaze_pipeline_create(&pd, &t->pipeline);
    if (FV_FAILED(r)) {
        fv_app_tracker_close(&t);
        return r;
    }
    fv_gaze_drain_init(&t->drain, t->source, t->pipeline, desc->stall_timeout_ns, fv_clock_now_ns(t->clock));
    t->drain.on_sample = on_sample;
    t->drain.user = t;
    /* A hardware tracker that is unplugged and plugged back is re-opened as soon as it arrives. Without hotplug
     * support (no udev, no permission) the source still re-opens on its backoff. */
    if (desc->mode == FV_GAZE_SOURCE_THREAD && (!strncmp(desc->uri, "hid:", 4) || !strncmp(desc->uri, "usb:", 4)) &&
        FV_FAILED(fv_usb_hotplug_start(&t->hotplug)))
        FV_INFO(who, "%s: no USB hotplug events; a lost tracker is re-opened on a backoff", desc->uri);
    *out = t;
    return FV_OK;
}

void fv_app_tracker_close(fv_app_tracker **pt)
{
    if (!pt || !*pt) return;
    fv_app_tracker *t = *pt;
    fv_usb_hotplug_stop(&t->hotplug);
    fv_gaze_pipeline_destroy(&t->pipeline);
    fv_gaze_source_destroy(&t->source);
    free(t);
    *pt = NULL;
}

void fv_app_tracker_hotplug(fv_app_tracker *t)
{
    if (t->hotplug && fv_usb_hotplug_take_reprobe(t->hotplug)) {
        t->reprobes++;
        fv_gaze_source_reprobe(t->source);
    }
}

bool fv_app_tracker_drain(fv_app_tracker *t)
{
    fv_app_tracker_hotplug(t);
    return fv_gaze_drain_step(&t->drain, fv_clock_now_ns(t->clock));
}

void fv_app_tracker_predict(fv_app_tracker *t, int64_t t_target_ns, fv_gaze_prediction *out)
{
    fv_app_tracker_drain(t);
    fv_gaze_pipeline_predict(t->pipeline, t_target_ns, out);
}

bool fv_app_tracker_head(const fv_app_tracker *t, fv_quat *out_dq, fv_vec3 *out_dp_m)
{
    if (!t->have_head) return false;
    *out_dq = t->head_dq;
    *out_dp_m = t->head_dp_m;
    return true;
}

void fv_app_tracker_head_report(const fv_app_tracker *t, fv_app_head_report *out) { *out = t->head_report; }
fv_gaze_drain *fv_app_tracker_drain_state(fv_app_tracker *t) { return &t->drain; }
fv_gaze_source *fv_app_tracker_source(const fv_app_tracker *t) { return t->source; }
fv_gaze_pipeline *fv_app_tracker_pipeline(const fv_app_tracker *t) { return t->pipeline; }
const char *fv_app_tracker_uri(const fv_app_tracker *t) { return t->uri; }
int64_t fv_app_tracker_latency_ns(const fv_app_tracker *t) { return t->latency_ns; }
uint64_t fv_app_tracker_reprobes(const fv_app_tracker *t) { return t->reprobes; }
