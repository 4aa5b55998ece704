/* @brief Eye gaze for XR_EXT_eye_gaze_interaction: fovea's gaze source (a reader thread per device, re-opened with
 * backoff when lost) on the URI in FOVEA_XR_GAZE, opened through the device registry of fovea's drivers (hid, usb,
 * pupil, trace, fixed, mouse, sim), feeding fovea's gaze pipeline (filter, saccade detection, prediction). A pose
 * located at time T is the pipeline's prediction to T; a blink or a lost device reads as not tracked. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_clock.h"
#include "fv_fixed_driver.h"
#include "fv_gaze_pipeline.h"
#include "fv_gaze_source.h"
#include "fv_head_follow.h"
#include "fv_hid_driver.h"
#include "fv_mouse_driver.h"
#include "fv_pupil_driver.h"
#include "fv_registry.h"
#include "fv_sim_driver.h"
#include "fv_stats.h"
#include "fv_trace_driver.h"
#include "fv_usb_driver.h"
#include "xr_internal.h"

/* Hardware first; the recorded and simulated drivers last (the registry's order). */
static const fv_driver *const g_drivers[] = {
    &fv_hid_driver, &fv_usb_driver, &fv_pupil_driver, &fv_trace_driver, &fv_fixed_driver, &fv_mouse_driver,
    &fv_sim_driver, NULL,
};

struct fv_xr_gaze {
    pthread_mutex_t lock;
    fv_registry registry;
    fv_gaze_source *source;
    fv_gaze_pipeline *pipeline;
    bool lost;
    fv_xr_gaze_stats stats;
    fv_head_follow head;     /* the tracker's recorded head pose, relative to its first (fv_head_follow.h) */
    bool have_head;
    fv_quat head_dq;         /* the newest head sample's pose relative to the first */
    fv_vec3 head_dp_m;
};

fv_result fv_xr_gaze_create(const char *uri, fv_xr_gaze **out)
{
    fv_xr_gaze *g = calloc(1, sizeof *g);
    if (!g) return FV_ERR_NO_MEMORY;
    pthread_mutex_init(&g->lock, NULL);
    fv_result res = fv_registry_init(&g->registry, g_drivers);
    fv_gaze_source_desc sd = {.uri = uri,
                              .open = fv_registry_open_fn,
                              .open_user = &g->registry,
                              .open_desc = {.clock = fv_clock_monotonic()},
                              .mode = FV_GAZE_SOURCE_THREAD};
    if (res == FV_OK) res = fv_gaze_source_create(&sd, &g->source);
    fv_gaze_pipeline_desc pd = {0};
    if (res == FV_OK) res = fv_gaze_pipeline_create(&pd, &g->pipeline);
    if (res != FV_OK) {
        fv_xr_gaze_destroy(&g);
        return res;
    }
    *out = g;
    return FV_OK;
}

void fv_xr_gaze_destroy(fv_xr_gaze **pg)
{
    if (!pg || !*pg) return;
    fv_xr_gaze *g = *pg;
    fv_gaze_source_destroy(&g->source);
    fv_gaze_pipeline_destroy(&g->pipeline);
    pthread_mutex_destroy(&g->lock);
    free(g);
    *pg = NULL;
}

/* Drain the source into the pipeline. Lock held. */
static void drain(fv_xr_gaze *g)
{
    fv_gaze_sample s;
    while (fv_gaze_source_pop(g->source, &s) == FV_OK) {
        fv_result r = fv_gaze_pipeline_push(g->pipeline, &s);
        (void)r; /* duplicates and out-of-order samples are the pipeline's to drop (FV_NO_NEW_DATA) */
        if (fv_head_follow_delta(&g->head, &s, &g->head_dq, &g->head_dp_m)) g->have_head = true;
    }
    fv_gaze_source_status st;
    fv_gaze_source_get_status(g->source, &st);
    bool lost = st.state != FV_GAZE_SOURCE_CONNECTED;
    if (lost != g->lost) {
        fv_gaze_pipeline_set_device_lost(g->pipeline, lost, fv_xr_now_ns());
        g->lost = lost;
    }
}

bool fv_xr_gaze_head(fv_xr_gaze *g, float out_q[4], float out_p_m[3])
{
    pthread_mutex_lock(&g->lock);
    drain(g);
    bool have = g->have_head;
    if (have) {
        out_q[0] = g->head_dq.x, out_q[1] = g->head_dq.y, out_q[2] = g->head_dq.z, out_q[3] = g->head_dq.w;
        out_p_m[0] = g->head_dp_m.x, out_p_m[1] = g->head_dp_m.y, out_p_m[2] = g->head_dp_m.z;
    }
    pthread_mutex_unlock(&g->lock);
    return have;
}

void fv_xr_gaze_update(fv_xr_gaze *g)
{
    pthread_mutex_lock(&g->lock);
    drain(g);
    pthread_mutex_unlock(&g->lock);
}

bool fv_xr_gaze_present(fv_xr_gaze *g)
{
    fv_gaze_source_status st;
    fv_gaze_source_get_status(g->source, &st);
    return st.state == FV_GAZE_SOURCE_CONNECTED || st.state == FV_GAZE_SOURCE_LOST;
}

static bool predict(fv_xr_gaze *g, int64_t t_ns, float out_origin_m[3], float out_dir[3], bool record,
                    float *out_uncertainty_deg)
{
    pthread_mutex_lock(&g->lock);
    drain(g);
    fv_gaze_prediction p;
    fv_gaze_pipeline_predict(g->pipeline, t_ns, &p);
    bool tracked = p.combined_valid && !g->lost && p.event != FV_GAZE_EVENT_BLINK && p.event != FV_GAZE_EVENT_LOST &&
                   p.event != FV_GAZE_EVENT_NONE;
    double horizon_ms = (double)fv_i64_sub_sat(t_ns, p.t_sample_ns) * 1e-6; /* t_ns: any XrTime an app passes */
    if (tracked && record) {
        g->stats.count++;
        g->stats.sum_ms += horizon_ms;
        if (horizon_ms > g->stats.max_ms) g->stats.max_ms = horizon_ms;
    }
    FV_LOG(FV_LOG_LEVEL_DEBUG, FV_XR_LOG, "gaze at %+.1f ms from the newest sample: %s, %s", horizon_ms,
           fv_gaze_event_str(p.event), tracked ? "tracked" : "not tracked");
    pthread_mutex_unlock(&g->lock);
    if (out_uncertainty_deg) *out_uncertainty_deg = p.uncertainty_deg;
    /* the combined (cyclopean) ray starts between the eyes: the head frame's origin */
    out_origin_m[0] = out_origin_m[1] = out_origin_m[2] = 0.0f;
    if (p.combined_valid) {
        out_dir[0] = p.combined_dir_head.x;
        out_dir[1] = p.combined_dir_head.y;
        out_dir[2] = p.combined_dir_head.z;
    } else {
        out_dir[0] = out_dir[1] = out_dir[2] = NAN; /* nothing known: not even a last pose */
    }
    return tracked;
}

int64_t fv_xr_gaze_newest_sample_ns(fv_xr_gaze *g)
{
    pthread_mutex_lock(&g->lock);
    drain(g);
    fv_gaze_prediction p;
    fv_gaze_pipeline_predict(g->pipeline, fv_xr_now_ns(), &p);
    pthread_mutex_unlock(&g->lock);
    return p.combined_valid ? p.t_sample_ns : 0;
}

void fv_xr_gaze_get_stats(fv_xr_gaze *g, fv_xr_gaze_stats *out)
{
    pthread_mutex_lock(&g->lock);
    *out = g->stats;
    pthread_mutex_unlock(&g->lock);
}

bool fv_xr_gaze_predict(fv_xr_gaze *g, int64_t t_ns, float out_origin_m[3], float out_dir[3])
{
    return predict(g, t_ns, out_origin_m, out_dir, true, NULL);
}

bool fv_xr_gaze_predict_uncertainty(fv_xr_gaze *g, int64_t t_ns, float out_origin_m[3], float out_dir[3],
                                    float *out_uncertainty_deg)
{
    return predict(g, t_ns, out_origin_m, out_dir, true, out_uncertainty_deg);
}

bool fv_xr_gaze_tracked(fv_xr_gaze *g, int64_t t_ns)
{
    float o[3], d[3];
    return predict(g, t_ns, o, d, false, NULL);
}
