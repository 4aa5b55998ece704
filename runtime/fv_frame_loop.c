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
    int64_t margin_ns, initial_estimate_ns;
    int64_t cost_ns[COST_WINDOW];
    size_t cost_count, cost_next;
    uint64_t frame_id;
    int64_t t_start_ns;
    bool have_shown;
    fv_vsync last_shown;
    uint32_t warmup_frames;   /* frames whose cost stays out of the estimate once a later frame was measured */
    /* gaze: the one drain (fv_gaze_drain.h), the loop's own or the caller's (desc.drain) */
    fv_gaze_drain own_drain;
    fv_gaze_drain *drain;     /* NULL without gaze */
    uint64_t latched_serial;
    bool warned_times;
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
    if (desc->drain && (!desc->drain->source || !desc->drain->pipeline)) {
        FV_ERROR("frame", "frame loop: a drain needs its gaze source and pipeline");
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
    l->margin_ns = desc->safety_margin_ns == 0 ? FV_NS_PER_MS : (desc->safety_margin_ns < 0 ? 0 : desc->safety_margin_ns);
    l->initial_estimate_ns =
        desc->initial_render_estimate_ns ? desc->initial_render_estimate_ns : desc->display->period_ns / 2;
    l->warmup_frames = desc->warmup_frames < 0 ? 0u : desc->warmup_frames == 0 ? 2u : (uint32_t)desc->warmup_frames;
    l->t_start_ns = fv_clock_now_ns(desc->clock);
    if (desc->drain) {
        l->drain = desc->drain;
        l->desc.gaze = desc->drain->source;
        l->desc.pipeline = desc->drain->pipeline;
    } else if (desc->gaze) {
        fv_gaze_drain_init(&l->own_drain, desc->gaze, desc->pipeline, desc->stall_timeout_ns, l->t_start_ns);
        l->drain = &l->own_drain;
    }
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
    if (!loop->drain || !loop->drain->have_head) return false;
    if (out_sample) *out_sample = loop->drain->newest_head;
    return true;
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

/* A frame's cost enters the estimate. The warm-up frames (shader compiles, first uploads: their cost says nothing
 * about the frames that follow) count only until the first frame after them was measured, which replaces them. */
static void remember_cost(fv_frame_loop *l, int64_t cost_ns)
{
    if (l->frame_id == l->warmup_frames && l->warmup_frames > 0) { /* the first steady frame: forget the warm-up */
        l->cost_count = 0;
        l->cost_next = 0;
    }
    l->cost_ns[l->cost_next] = cost_ns < 0 ? 0 : cost_ns;
    l->cost_next = (l->cost_next + 1) % COST_WINDOW;
    if (l->cost_count < COST_WINDOW) l->cost_count++;
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

void fv_frame_times_from_fence(int64_t t_cpu_begin, int64_t t_returned, int64_t t_fence, int64_t gpu_ns,
                               fv_frame_render_times *out)
{
    if (t_returned < t_cpu_begin) t_returned = t_cpu_begin;
    if (t_fence < t_returned) t_fence = t_returned;
    out->t_gpu_end_ns = t_fence;
    int64_t begin = gpu_ns > 0 ? fv_i64_sub_sat(t_fence, gpu_ns) : t_returned;
    if (begin >= t_returned) { /* the GPU ran after the draw returned (waiting in its queue counts as GPU time) */
        out->t_submit_ns = t_returned;
        out->t_gpu_begin_ns = begin;
    } else { /* the draw returned after the GPU began: it was submitted when the GPU began */
        out->t_submit_ns = begin > t_cpu_begin ? begin : t_cpu_begin;
        out->t_gpu_begin_ns = out->t_submit_ns;
    }
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
    bool lost = l->drain ? fv_gaze_drain_step(l->drain, rec.t_wake_ns) : false;
    rec.t_latch_ns = now_ns(l);
    rec.device_lost = lost;
    if (l->drain && l->drain->have_sample) {
        const fv_gaze_drain *d = l->drain;
        /* a stale sample from a lost device says nothing about this frame's latency: kept for diagnostics, but
         * not counted as gaze */
        rec.has_gaze = !lost;
        rec.fresh_gaze = d->serial != l->latched_serial;
        l->latched_serial = d->serial;
        rec.sample_seq = d->newest.seq;
        rec.t_sample_device_ns = d->newest.t_device_ns;
        rec.t_sample_received_ns = d->newest_received_ns;
        rec.t_sample_capture_ns = fv_i64_sub_sat(d->newest_received_ns, l->desc.tracker_latency_ns);
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
