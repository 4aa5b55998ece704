/* @brief The frame loop: pacing to the display clock, late gaze latch, prediction to photon time, render, present,
 * latency records (see fv_frame_loop.h). */
#include "fv_frame_loop.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_stats.h"

#define COST_WINDOW 16                          /* frames the render-time estimate looks back over */
#define MAX_GPU_AHEAD_NS (10 * FV_NS_PER_S)     /* a renderer claiming its GPU ends later than this is wrong */

struct fv_frame_loop {
    fv_frame_loop_desc desc;
    fv_eye_in_head eyes[2]; /* the eyes' poses in the head: how the head-frame gaze reaches each eye's view */
    int64_t stall_timeout_ns, margin_ns, initial_estimate_ns;
    int64_t cost_ns[COST_WINDOW];
    size_t cost_count, cost_next;
    uint64_t frame_id;
    int64_t t_start_ns;
    bool have_shown;
    fv_vsync last_shown;
    /* gaze */
    bool have_sample;
    fv_gaze_sample newest;
    fv_gaze_sample newest_head; /* the newest accepted sample with FV_GAZE_HEAD_VALID (have_head) */
    bool have_head;
    int64_t newest_received_ns; /* receipt time used for the newest sample */
    int64_t last_new_sample_ns; /* when the loop last drained a new sample */
    uint64_t newest_serial, latched_serial;
    bool lost_reported;
    bool warned_future_receipt, warned_push, warned_times;
    fv_gaze_prediction last_prediction;
};

fv_result fv_frame_loop_create(const fv_frame_loop_desc *desc, fv_frame_loop **out)
{
    if (!out) return FV_ERR_INVALID_ARG;
    *out = NULL;
    if (!desc || !desc->clock || !desc->display || !desc->render) {
        FV_ERROR("frame", "frame loop: clock, display and render callback are required");
        return FV_ERR_INVALID_ARG;
    }
    if (desc->gaze && !desc->pipeline) {
        FV_ERROR("frame", "frame loop: a gaze source needs a gaze pipeline");
        return FV_ERR_INVALID_ARG;
    }
    if (desc->display->period_ns <= 0) {
        FV_ERROR("frame", "frame loop: display period %lld ns is not positive", (long long)desc->display->period_ns);
        return FV_ERR_INVALID_ARG;
    }
    if (desc->tracker_latency_ns < 0 || desc->stall_timeout_ns < 0 || desc->initial_render_estimate_ns < 0) {
        FV_ERROR("frame", "frame loop: tracker latency %lld, stall timeout %lld, initial estimate %lld ns: must not be "
                 "negative", (long long)desc->tracker_latency_ns, (long long)desc->stall_timeout_ns,
                 (long long)desc->initial_render_estimate_ns);
        return FV_ERR_RANGE;
    }
    fv_frame_loop *l = calloc(1, sizeof *l);
    if (!l) {
        FV_ERROR("frame", "frame loop: out of memory");
        return FV_ERR_NO_MEMORY;
    }
    l->desc = *desc;
    fv_eyes_in_head(desc->ipd_mm > 0.0f ? desc->ipd_mm : FV_DEFAULT_IPD_MM, l->eyes);
    l->stall_timeout_ns = desc->stall_timeout_ns ? desc->stall_timeout_ns : 100 * FV_NS_PER_MS;
    l->margin_ns = desc->safety_margin_ns == 0 ? FV_NS_PER_MS : (desc->safety_margin_ns < 0 ? 0 : desc->safety_margin_ns);
    l->initial_estimate_ns =
        desc->initial_render_estimate_ns ? desc->initial_render_estimate_ns : desc->display->period_ns / 2;
    l->t_start_ns = fv_clock_now_ns(desc->clock);
    l->last_new_sample_ns = l->t_start_ns;
    *out = l;
    return FV_OK;
}

void fv_frame_loop_destroy(fv_frame_loop **loop)
{
    if (!loop || !*loop) return;
    free(*loop);
    *loop = NULL;
}

void fv_frame_loop_last_prediction(const fv_frame_loop *loop, fv_gaze_prediction *out)
{
    *out = loop->last_prediction;
}

bool fv_frame_loop_newest_head(const fv_frame_loop *loop, fv_gaze_sample *out_sample)
{
    if (loop->have_head && out_sample) *out_sample = loop->newest_head;
    return loop->have_head;
}

static int64_t now_ns(const fv_frame_loop *l) { return fv_clock_now_ns(l->desc.clock); }

static void sleep_until(const fv_frame_loop *l, int64_t t_ns)
{
    if (t_ns > now_ns(l)) l->desc.clock->sleep_until_ns(l->desc.clock, t_ns);
}

static int64_t render_estimate(const fv_frame_loop *l)
{
    if (l->cost_count == 0) return l->initial_estimate_ns;
    int64_t m = 0;
    for (size_t i = 0; i < l->cost_count; i++)
        if (l->cost_ns[i] > m) m = l->cost_ns[i];
    return m;
}

static void remember_cost(fv_frame_loop *l, int64_t cost_ns)
{
    l->cost_ns[l->cost_next] = cost_ns < 0 ? 0 : cost_ns;
    l->cost_next = (l->cost_next + 1) % COST_WINDOW;
    if (l->cost_count < COST_WINDOW) l->cost_count++;
}

/* Drain the device ring into the pipeline (bounded by the ring's size, so a flooding device cannot hold the loop
 * here) and keep the newest accepted sample. */
static void drain_gaze(fv_frame_loop *l, int64_t t_now)
{
    fv_gaze_source *src = l->desc.gaze;
    fv_gaze_source_poll(src); /* inline sources read here; threaded ones already filled the ring */
    fv_gaze_source_status st;
    fv_gaze_source_get_status(src, &st);
    fv_gaze_sample s;
    for (size_t i = 0; i < st.ring_capacity && fv_gaze_source_pop(src, &s) == FV_OK; i++) {
        fv_result r = fv_gaze_pipeline_push(l->desc.pipeline, &s);
        if (r != FV_OK) {
            if (FV_FAILED(r) && !l->warned_push) {
                FV_WARN("frame", "%s: the gaze pipeline refused sample %llu (%s); further refusals are not logged",
                        fv_gaze_source_uri(src), (unsigned long long)s.seq, fv_result_str(r));
                l->warned_push = true;
            }
            continue; /* duplicates and out-of-order samples are not "newest" */
        }
        int64_t received = (s.flags & FV_GAZE_HOST_TIME_VALID) ? s.t_host_ns : t_now;
        if (received > t_now) {
            if (!l->warned_future_receipt) {
                FV_WARN("frame", "%s: sample received at %lld ns, after the loop's now %lld ns (another clock?); "
                        "using the drain time", fv_gaze_source_uri(src), (long long)received, (long long)t_now);
                l->warned_future_receipt = true;
            }
            received = t_now;
        }
        l->newest = s;
        if (s.flags & FV_GAZE_HEAD_VALID) {
            l->newest_head = s;
            l->have_head = true;
        }
        l->newest_received_ns = received;
        l->have_sample = true;
        l->newest_serial++;
        l->last_new_sample_ns = t_now;
    }
}

static void update_lost(fv_frame_loop *l, int64_t t_now, bool *out_lost)
{
    fv_gaze_source_status st;
    fv_gaze_source_get_status(l->desc.gaze, &st);
    bool lost = st.state != FV_GAZE_SOURCE_CONNECTED || t_now - l->last_new_sample_ns > l->stall_timeout_ns;
    if (lost != l->lost_reported) {
        if (lost)
            FV_WARN("frame", "%s: no gaze (%s%s); widening the uncertainty", fv_gaze_source_uri(l->desc.gaze),
                    fv_gaze_source_state_str(st.state),
                    st.state == FV_GAZE_SOURCE_CONNECTED ? ", stalled" : "");
        else
            FV_WARN("frame", "%s: gaze back", fv_gaze_source_uri(l->desc.gaze)); /* pairs with the warning above */
        fv_gaze_pipeline_set_device_lost(l->desc.pipeline, lost, t_now);
        l->lost_reported = lost;
    }
    *out_lost = lost;
}

/* The prediction (head frame) as each eye's gaze in its view space: through the eyes' poses in the head only, so the
 * head's pose (the scene's, a recording's, an OpenXR space) never turns the gaze against the views it moves. */
static void fill_gaze(const fv_frame_loop *l, const fv_gaze_prediction *p, fv_frame_input *in)
{
    for (int e = 0; e < 2; e++) {
        /* one direction for both eyes beats none */
        bool have = p->eye_valid[e] || p->combined_valid;
        fv_vec3 dir_head = p->eye_valid[e] ? p->dir_head[e] : p->combined_dir_head;
        in->gaze[e] = have ? fv_eye_gaze_from_head(&l->eyes[e], dir_head, p->uncertainty_deg)
                           : fv_eye_gaze_from_head(&l->eyes[e], fv_v3(NAN, NAN, NAN), 180.0f);
    }
    in->pupil_mm = isfinite(p->pupil_mm) ? p->pupil_mm : NAN;
}

/* Clamp what the renderer reported into cpu_begin <= submit <= gpu_begin <= gpu_end. */
static void sanitize_times(fv_frame_loop *l, int64_t t_begin, int64_t t_after, fv_frame_render_times *t)
{
    fv_frame_render_times in = *t;
    if (t->t_submit_ns == 0) t->t_submit_ns = t_after;
    if (t->t_submit_ns < t_begin) t->t_submit_ns = t_begin;
    if (t->t_submit_ns > t_after) t->t_submit_ns = t_after;
    if (t->t_gpu_begin_ns == 0 || t->t_gpu_begin_ns < t->t_submit_ns) t->t_gpu_begin_ns = t->t_submit_ns;
    if (t->t_gpu_end_ns == 0 || t->t_gpu_end_ns < t->t_gpu_begin_ns) t->t_gpu_end_ns = t->t_gpu_begin_ns;
    if (t->t_gpu_end_ns > t_after + MAX_GPU_AHEAD_NS) t->t_gpu_end_ns = t_after + MAX_GPU_AHEAD_NS;
    if (t->t_gpu_begin_ns > t->t_gpu_end_ns) t->t_gpu_begin_ns = t->t_gpu_end_ns;
    bool changed = (in.t_submit_ns && in.t_submit_ns != t->t_submit_ns) ||
                   (in.t_gpu_begin_ns && in.t_gpu_begin_ns != t->t_gpu_begin_ns) ||
                   (in.t_gpu_end_ns && in.t_gpu_end_ns != t->t_gpu_end_ns);
    if (changed && !l->warned_times) {
        FV_WARN("frame", "frame %llu: renderer times out of order (submit %lld, gpu %lld..%lld ns; CPU %lld..%lld); "
                "clamped", (unsigned long long)l->frame_id, (long long)in.t_submit_ns, (long long)in.t_gpu_begin_ns,
                (long long)in.t_gpu_end_ns, (long long)t_begin, (long long)t_after);
        l->warned_times = true;
    }
}

fv_result fv_frame_loop_step(fv_frame_loop *l, fv_latency_record *out_record)
{
    fv_display *disp = l->desc.display;
    fv_latency_record rec;
    memset(&rec, 0, sizeof rec);
    rec.frame_id = l->frame_id;

    /* 1. pace: the earliest refresh the expected work can make, never one already used */
    int64_t est = render_estimate(l);
    int64_t lead = est + l->margin_ns + disp->present_margin_ns;
    fv_vsync target;
    FV_TRY(fv_display_vsync_at_or_after(disp, now_ns(l) + lead, &target));
    if (l->have_shown && target.index <= l->last_shown.index)
        FV_TRY(fv_display_vsync_at_or_after(disp, l->last_shown.t_ns + 1, &target));
    sleep_until(l, target.t_ns - lead);
    rec.t_wake_ns = now_ns(l);
    rec.target_vsync = target.index;

    /* 2. latch the newest gaze */
    bool lost = false;
    if (l->desc.gaze) {
        drain_gaze(l, rec.t_wake_ns);
        update_lost(l, now_ns(l), &lost);
    }
    rec.t_latch_ns = now_ns(l);
    rec.device_lost = lost;
    if (l->have_sample) {
        /* a stale sample from a lost device says nothing about this frame's latency: kept for diagnostics, but
         * not counted as gaze */
        rec.has_gaze = !lost;
        rec.fresh_gaze = l->newest_serial != l->latched_serial;
        l->latched_serial = l->newest_serial;
        rec.sample_seq = l->newest.seq;
        rec.t_sample_device_ns = l->newest.t_device_ns;
        rec.t_sample_received_ns = l->newest_received_ns;
        rec.t_sample_capture_ns = fv_i64_sub_sat(l->newest_received_ns, l->desc.tracker_latency_ns);
    }

    /* 3. predict to the photon time of the target refresh */
    int64_t t_photon_target = fv_display_photon_ns(disp, &target);
    fv_gaze_prediction pred;
    memset(&pred, 0, sizeof pred);
    pred.pupil_mm = NAN;
    if (l->desc.pipeline) fv_gaze_pipeline_predict(l->desc.pipeline, t_photon_target, &pred);
    l->last_prediction = pred;
    rec.gaze_event = (int)pred.event;
    rec.uncertainty_deg = pred.uncertainty_deg;

    fv_frame_input in;
    memset(&in, 0, sizeof in);
    in.frame_id = l->frame_id;
    in.time_s = (double)(t_photon_target - l->t_start_ns) / 1e9;
    /* the head and the eye views are the render callback's to place, once (see fv_frame_render_fn) */
    in.head = (fv_head_pose){.orientation = fv_quat_identity(),
                             .ipd_mm = l->desc.ipd_mm > 0.0f ? l->desc.ipd_mm : FV_DEFAULT_IPD_MM};
    in.t_photon_ns = t_photon_target;
    in.quality = fv_quality_default();
    in.pupil_mm = NAN;
    for (int e = 0; e < 2; e++) {
        in.gaze[e].valid = false;
        in.gaze[e].dir_eye = fv_v3(0.0f, 0.0f, -1.0f);
        in.gaze[e].uncertainty_deg = 180.0f;
    }
    if (l->desc.pipeline) fill_gaze(l, &pred, &in);

    /* 4. render */
    rec.t_cpu_begin_ns = now_ns(l);
    fv_frame_render_times times = {0};
    fv_result r = l->desc.render(l->desc.render_user, &in, &times);
    if (FV_FAILED(r)) {
        FV_ERROR("frame", "frame %llu: render failed (%s)", (unsigned long long)l->frame_id, fv_result_str(r));
        return r;
    }
    int64_t t_after = now_ns(l);
    sanitize_times(l, rec.t_cpu_begin_ns, t_after, &times);
    rec.t_submit_ns = times.t_submit_ns;
    rec.t_gpu_begin_ns = times.t_gpu_begin_ns;
    rec.t_gpu_end_ns = times.t_gpu_end_ns;

    /* 5. present once the GPU is done */
    sleep_until(l, times.t_gpu_end_ns);
    rec.t_present_ns = now_ns(l);
    fv_vsync shown;
    r = fv_display_present(disp, rec.t_present_ns, target.index, &shown);
    if (FV_FAILED(r)) {
        FV_ERROR("frame", "frame %llu: present failed (%s)", (unsigned long long)l->frame_id, fv_result_str(r));
        return r;
    }
    rec.shown_vsync = shown.index;
    rec.t_vsync_ns = shown.t_ns;
    rec.t_photon_ns = fv_display_photon_ns(disp, &shown);
    rec.late = shown.index > target.index;
    if (l->have_shown && shown.index > l->last_shown.index + 1)
        rec.repeated_vsyncs = (uint32_t)(shown.index - l->last_shown.index - 1 > UINT32_MAX
                                             ? UINT32_MAX
                                             : shown.index - l->last_shown.index - 1);
    l->last_shown = shown;
    l->have_shown = true;
    remember_cost(l, times.t_gpu_end_ns - rec.t_cpu_begin_ns);
    l->frame_id++;
    if (out_record) *out_record = rec;
    return FV_OK;
}
