/* @brief Eye gaze for XR_EXT_eye_gaze_interaction: the application layer's gaze tracker (runtime/app: a reader thread
 * per device, re-opened with backoff when lost, the one drain, fovea's gaze pipeline) on the URI in FOVEA_XR_GAZE,
 * opened through the one driver list that `fovea run --gaze` opens (fv_app_drivers.h: hid, usb, pupil, trace, fixed,
 * mouse, sim and FOVEA_DRIVERS plug-ins). A pose located at time T is the pipeline's prediction to T; a blink or a
 * lost device reads as not tracked. And the frame budget of the session's frames (fv_app_budget.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_app_budget.h"
#include "fv_app_tracker.h"
#include "fv_clock.h"
#include "fv_stats.h"
#include "xr_internal.h"

struct fv_xr_gaze {
    pthread_mutex_t lock;
    fv_app_tracker *tracker;
    bool lost;
    fv_xr_gaze_stats stats;
};

fv_result fv_xr_gaze_create(const char *uri, fv_xr_gaze **out)
{
    fv_xr_gaze *g = calloc(1, sizeof *g);
    if (!g) return FV_ERR_NO_MEMORY;
    pthread_mutex_init(&g->lock, NULL);
    fv_app_tracker_desc td = {.uri = uri, .mode = FV_GAZE_SOURCE_THREAD, .clock = fv_clock_monotonic(),
                              .who = FV_XR_LOG};
    fv_result res = fv_app_tracker_open(&td, &g->tracker);
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
    fv_app_tracker_close(&g->tracker);
    pthread_mutex_destroy(&g->lock);
    free(g);
    *pg = NULL;
}

/* Drain the source into the pipeline (the application layer's one drain). Lock held. */
static void drain(fv_xr_gaze *g) { g->lost = fv_app_tracker_drain(g->tracker); }

bool fv_xr_gaze_head(fv_xr_gaze *g, float out_q[4], float out_p_m[3])
{
    pthread_mutex_lock(&g->lock);
    drain(g);
    fv_quat dq;
    fv_vec3 dp;
    bool have = fv_app_tracker_head(g->tracker, &dq, &dp);
    if (have) {
        out_q[0] = dq.x, out_q[1] = dq.y, out_q[2] = dq.z, out_q[3] = dq.w;
        out_p_m[0] = dp.x, out_p_m[1] = dp.y, out_p_m[2] = dp.z;
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
    fv_gaze_source_get_status(fv_app_tracker_source(g->tracker), &st);
    return st.state == FV_GAZE_SOURCE_CONNECTED || st.state == FV_GAZE_SOURCE_LOST;
}

static bool predict(fv_xr_gaze *g, int64_t t_ns, float out_origin_m[3], float out_dir[3], bool record,
                    float *out_uncertainty_deg)
{
    pthread_mutex_lock(&g->lock);
    fv_gaze_prediction p;
    fv_app_tracker_predict(g->tracker, t_ns, &p);
    g->lost = fv_app_tracker_drain_state(g->tracker)->lost;
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
    fv_gaze_prediction p;
    fv_app_tracker_predict(g->tracker, fv_xr_now_ns(), &p);
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

/* ---- the frame budget of a session (the application layer's, as `fovea run --budget auto` has it) ---------------- */

struct fv_xr_budget {
    fv_app_budget b;
    fv_quality q;     /* the level's quality: what the foveated insets are sized from */
    uint64_t frames;
};

/* The knobs the runtime's own work reads: the insets' MAR model (fv_xr_quad_inset_radius_deg). The ladder's other
 * rungs would save nothing here. */
static const char *const g_xr_knobs[] = {"fovea.mar_slope", "fovea.mar_w0_deg", NULL};

fv_xr_budget *fv_xr_budget_create(fv_app_run *run, double refresh_hz)
{
    const char *env = getenv("FOVEA_XR_BUDGET");
    char err[128];
    if (FV_FAILED(fv_app_run_budget_parse(run, env, err, sizeof err))) {
        FV_ERROR(FV_XR_LOG, "FOVEA_XR_BUDGET='%s': %s; using auto", env, err);
        (void)fv_app_run_budget_parse(run, "auto", err, sizeof err);
    }
    if (!run->budget) return NULL;
    fv_xr_budget *xb = calloc(1, sizeof *xb);
    if (!xb) return NULL;
    int failed;
    if (FV_FAILED(fv_app_run_quality(run, &xb->q, &failed, err, sizeof err))) {
        FV_ERROR(FV_XR_LOG, "the session's quality: %s; no frame budget", err);
        free(xb);
        return NULL;
    }
    if (fv_app_budget_start(&xb->b, FV_XR_LOG, &xb->q, fv_app_quality_choice_preset(&run->quality), refresh_hz,
                            run->budget_scale > 0 ? run->budget_scale : 1.0, NULL) != FV_OK ||
        fv_app_budget_keep_knobs(&xb->b, g_xr_knobs) != FV_OK) {
        free(xb);
        return NULL;
    }
    return xb;
}

void fv_xr_budget_destroy(fv_xr_budget **pb)
{
    if (!pb || !*pb) return;
    free(*pb);
    *pb = NULL;
}

void fv_xr_budget_frame(fv_xr_budget *xb, double frame_ms)
{
    if (!xb) return;
    xb->frames++;
    (void)fv_app_budget_push(&xb->b, xb->frames, frame_ms, &xb->q);
}

void fv_xr_budget_quality(const fv_xr_budget *xb, fv_quality *out) { *out = xb ? xb->q : fv_quality_default(); }

void fv_xr_budget_write_stats(const fv_xr_budget *xb, FILE *f)
{
    if (!xb) {
        fprintf(f, "  \"budget\": null,\n");
        return;
    }
    fprintf(f, "  \"budget\": {\"budget_ms\": %.4f, \"level\": %u, \"rungs\": %zu, \"changes\": %llu, "
               "\"frames\": %llu, \"misses\": %llu},\n", fv_app_budget_target_ms(&xb->b), xb->b.ctl.level,
            xb->b.rung_count, (unsigned long long)xb->b.changes, (unsigned long long)xb->b.ctl.frames,
            (unsigned long long)xb->b.ctl.misses);
}
