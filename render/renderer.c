/* @brief The renderer object: the device, frames in flight, the plan and the loop over the pass table. Every pass is
 * reached through the table (fv_passes.h); the scene lives in fv_scene_gpu, the images in fv_images. The frame
 * constants (renderer_frame.c), the scene's load (renderer_scene.c) and readback (renderer_readback.c) are beside. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_knobs.h"
#include "renderer_internal.h"

/* Each recorded pass takes one timed range a frame: the timer table holds every pass the table can hold. */
_Static_assert(FV_VK_TIMER_MAX_PASSES >= FV_MAX_PASSES, "a timer range for every pass of the table");

/* ---- the plan ----------------------------------------------------------------------------------------------- */

/* Out-of-range settings fall back to the defaults, field by field, as the knob table says (a zeroed fv_quality
 * becomes the default). */
static fv_quality quality_sanitized(const fv_quality *q)
{
    fv_quality o = q ? *q : fv_quality_default();
    fv_quality_sanitize(&o);
    return o;
}

/* Whether the plan must be decided again: any setting a pass's plan looks at (every knob and view setting). */
static bool plan_differs(const fv_quality *a, const fv_quality *b) { return !fv_quality_equal(a, b); }

static void pass_env(fv_renderer *r, uint32_t i, fv_pass_env *env)
{
    *env = (fv_pass_env){.vk = r->vk, .scene = &r->scene, .images = &r->images, .shade_inputs = &r->shade_inputs,
                         .width = r->desc.eye_width,
                         .height = r->desc.eye_height, .slots = r->slot_count, .multiview = r->multiview,
                         .plan = &r->plan.entries[i], .samples = &r->samples,
                         .scene_model = r->scene_loaded ? &r->plan_scene : NULL};
}

static void fini_pass(fv_renderer *r, uint32_t i)
{
    if (!r->pass_state[i]) return;
    r->table[i]->fini(r->pass_state[i]);
    r->pass_state[i] = NULL;
}

/* Decide the plan from the scene, the device and the quality, then bring the passes in line with it: init what
 * is newly on (or asks for another variant), fini what is off. Waits for the GPU before anything is freed. */
fv_result fv_renderer_plan_apply(fv_renderer *r, const fv_quality *quality)
{
    fv_plan_context ctx = {.scene = r->scene_loaded ? &r->plan_scene : NULL, .device = &r->vk->info,
                           .multiview = r->multiview, .multiview_why = r->multiview ? NULL : r->multiview_why,
                           .quality = quality,
                           .target = r->target && r->target->ops ? r->target->ops->name : "headless",
                           .motion_target = r->desc.motion_target};
    fv_frame_plan plan;
    fv_frame_plan_build_table(r->table, r->pass_count, &ctx, &plan);
    char why[256];
    if (fv_frame_plan_check(r->table, r->pass_count, &plan, why, sizeof why) != FV_OK) {
        FV_ERROR(MOD, "the frame plan does not hold together: %s", why);
        return FV_ERR_STATE;
    }
    uint32_t timed = 0;
    for (uint32_t i = 0; i < r->pass_count; i++) timed += plan.entries[i].enabled && r->table[i]->record;
    if (timed > FV_VK_TIMER_MAX_PASSES) { /* the compile-time assertion makes this unreachable with fv_pass_table */
        FV_ERROR(MOD, "the plan records %u passes; the timer table holds %u (FV_VK_TIMER_MAX_PASSES)", timed,
                 FV_VK_TIMER_MAX_PASSES);
        return FV_ERR_RANGE;
    }
    /* Which passes start, stop or start again (another variant). A pass that reads another's images keeps views of
     * them: it starts again with its maker (e.g. a debug view of foveation's images when the fovea block changes). */
    bool change = false, restart[FV_MAX_PASSES] = {false};
    for (uint32_t i = 0; i < r->pass_count; i++) {
        bool want = plan.entries[i].enabled && r->table[i]->init, had = r->pass_state[i] != NULL;
        restart[i] = want != had || (want && r->pass_variant[i] != plan.entries[i].variant);
        for (uint32_t j = 0; j < i && want && had && !restart[i]; j++)
            restart[i] = restart[j] && fv_frame_plan_reads_from(r->table, i, j);
        change = change || restart[i];
    }
    /* Passes write descriptor sets shared with frames in flight when they start or stop: wait for the GPU first. */
    if (change) {
        FV_TRY(fv_renderer_finish(r));
        VkResult vr = vkDeviceWaitIdle(r->vk->device);
        if (vr < 0) return fv_vk_fail(vr, "vkDeviceWaitIdle", __FILE__, __LINE__);
    }
    for (uint32_t i = 0; i < r->pass_count; i++) {
        if (r->pass_state[i] && restart[i]) fini_pass(r, i);
    }
    r->plan = plan;
    r->plan_quality = *quality;
    for (uint32_t i = 0; i < r->pass_count; i++) {
        if (!plan.entries[i].enabled || !r->table[i]->init || r->pass_state[i]) continue;
        fv_pass_env env;
        pass_env(r, i, &env);
        const fv_pass *p = r->table[i];
        r->images.starting = p->id; /* its images are the ones it declared (fv_images.h) */
        r->images.declared[0] = p->makes;
        r->images.declared[1] = p->needs;
        r->images.declared[2] = p->uses_if_made;
        fv_result res = p->init(&env, &r->pass_state[i]);
        r->images.starting = NULL;
        if (res != FV_OK) {
            FV_ERROR(MOD, "pass %s could not start: %s", r->table[i]->id, fv_result_str(res));
            r->pass_state[i] = NULL;
            return res;
        }
        r->pass_variant[i] = plan.entries[i].variant;
    }
    return FV_OK;
}

/* ---- create / destroy ----------------------------------------------------------------------------------------- */

static fv_result create_slots(fv_renderer *r)
{
    fv_vk *vk = r->vk;
    for (uint32_t i = 0; i < r->slot_count; i++) {
        frame_slot *s = &r->slots[i];
        VkCommandPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                       .flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT,
                                       .queueFamilyIndex = vk->queue_family};
        FV_VK_CHECK(vkCreateCommandPool(vk->device, &pci, NULL, &s->pool));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_COMMAND_POOL, s->pool, "frame slot %u pool", i);
        VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                          .commandPool = s->pool,
                                          .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                          .commandBufferCount = 1};
        FV_VK_CHECK(vkAllocateCommandBuffers(vk->device, &ai, &s->cmd));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_COMMAND_BUFFER, s->cmd, "frame slot %u commands", i);
        VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        FV_VK_CHECK(vkCreateFence(vk->device, &fci, NULL, &s->fence));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_FENCE, s->fence, "frame slot %u fence", i);
        VkSemaphoreCreateInfo sci = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        FV_VK_CHECK(vkCreateSemaphore(vk->device, &sci, NULL, &s->image_ready));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_SEMAPHORE, s->image_ready, "frame slot %u image ready", i);
        FV_VK_CHECK(vkCreateSemaphore(vk->device, &sci, NULL, &s->frame_done));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_SEMAPHORE, s->frame_done, "frame slot %u frame done", i);
    }
    return FV_OK;
}

fv_result fv_renderer_create(const fv_renderer_desc *desc_in, fv_renderer **out_renderer)
{
    if (!out_renderer) return FV_ERR_INVALID_ARG;
    *out_renderer = NULL;
    fv_renderer_desc desc = desc_in ? *desc_in : (fv_renderer_desc){0};
    if (!desc.eye_width || !desc.eye_height) {
        if (desc.eye_width || desc.eye_height) {
            FV_ERROR(MOD, "eye size %ux%u: both or neither must be 0", desc.eye_width, desc.eye_height);
            return FV_ERR_INVALID_ARG;
        }
        desc.eye_width = 720;
        desc.eye_height = 800;
    }
    if (desc.eye_width > FV_GPU_PIXEL_MAX_DIM || desc.eye_height > FV_GPU_PIXEL_MAX_DIM) {
        FV_ERROR(MOD, "eye size %ux%u exceeds %u px", desc.eye_width, desc.eye_height, FV_GPU_PIXEL_MAX_DIM);
        return FV_ERR_RANGE;
    }
    if (!desc.frames_in_flight) desc.frames_in_flight = 2;
    if (desc.frames_in_flight > FV_MAX_FRAMES_IN_FLIGHT) {
        FV_ERROR(MOD, "frames_in_flight %u exceeds %u", desc.frames_in_flight, FV_MAX_FRAMES_IN_FLIGHT);
        return FV_ERR_RANGE;
    }
    if (desc.pass_table && (desc.pass_count > FV_MAX_PASSES || !desc.pass_count)) {
        FV_ERROR(MOD, "a pass table of %u entries: the renderer holds 1..%d (FV_MAX_PASSES)", desc.pass_count,
                 FV_MAX_PASSES);
        return FV_ERR_RANGE;
    }
    fv_renderer *r = calloc(1, sizeof *r);
    if (!r) return FV_ERR_NO_MEMORY;
    r->desc = desc;
    r->slot_count = desc.frames_in_flight;
    r->target = desc.target ? desc.target : fv_target_headless();
    r->table = desc.pass_table ? desc.pass_table : fv_pass_table(&r->pass_count);
    if (desc.pass_table) r->pass_count = desc.pass_count;
    fv_vk_desc vd = {.device = desc.device,
                     .validation = desc.validation > 0 ? 1 : (desc.validation < 0 ? -1 : 0),
                     .memory_budget_bytes = desc.memory_budget_bytes,
                     .app_name = "fovea"};
    if (r->target->ops && r->target->ops->configure_vk) r->target->ops->configure_vk(r->target, &vd);
    fv_result res = fv_vk_create(&vd, &r->vk);
    if (res != FV_OK) goto fail;
    r->multiview = fv_vk_multiview_trusted(&r->vk->info, r->multiview_why, sizeof r->multiview_why);
    res = fv_images_init(&r->images, r->vk, desc.eye_width, desc.eye_height);
    if (res == FV_OK) fv_frame_samples_init(&r->samples, r->vk, r->slot_count, 2u * desc.eye_width * desc.eye_height);
    if (res == FV_OK) res = fv_scene_gpu_init(&r->scene, r->vk, r->slot_count);
    if (res == FV_OK) res = fv_shade_inputs_init(&r->shade_inputs, r->vk, r->slot_count);
    if (res == FV_OK) res = fv_vk_timer_init(&r->timer, r->vk, r->slot_count);
    if (res == FV_OK) res = create_slots(r);
    fv_quality q = fv_quality_default();
    if (res == FV_OK) res = fv_renderer_plan_apply(r, &q);
    if (res != FV_OK) goto fail;
    *out_renderer = r;
    return FV_OK;
fail:
    FV_ERROR(MOD, "renderer (%ux%u per eye) could not be created: %s", desc.eye_width, desc.eye_height,
             fv_result_str(res));
    fv_renderer_destroy(&r);
    return res;
}

void fv_renderer_destroy(fv_renderer **pr)
{
    if (!pr || !*pr) return;
    fv_renderer *r = *pr;
    if (r->vk) {
        vkDeviceWaitIdle(r->vk->device);
        for (uint32_t i = 0; i < r->pass_count; i++) fini_pass(r, i);
        fv_renderer_release_scene(r);
        for (uint32_t i = 0; i < r->slot_count; i++) {
            frame_slot *s = &r->slots[i];
            if (s->fence) vkDestroyFence(r->vk->device, s->fence, NULL);
            if (s->image_ready) vkDestroySemaphore(r->vk->device, s->image_ready, NULL);
            if (s->frame_done) vkDestroySemaphore(r->vk->device, s->frame_done, NULL);
            if (s->pool) vkDestroyCommandPool(r->vk->device, s->pool, NULL);
        }
        fv_vk_timer_fini(&r->timer, r->vk);
        fv_scene_gpu_fini(&r->scene);
        fv_shade_inputs_fini(&r->shade_inputs);
        fv_frame_samples_fini(&r->samples);
        fv_images_fini(&r->images);
        if (r->target && r->target->ops && r->target->ops->detach) r->target->ops->detach(r->target, r->vk);
        fv_vk_destroy(&r->vk);
    }
    free(r);
    *pr = NULL;
}

/* ---- frames in flight ---------------------------------------------------------------------------------------- */

/* Wait for a slot's frame and take its timings and counters. */
static fv_result retire(fv_renderer *r, uint32_t slot)
{
    frame_slot *s = &r->slots[slot];
    if (!s->pending) return FV_OK;
    FV_VK_CHECK(vkWaitForFences(r->vk->device, 1, &s->fence, VK_TRUE, UINT64_MAX));
    s->pending = false;
    if (r->have_stats && s->seq < r->stats_seq) return FV_OK;
    r->stats_seq = s->seq;
    fv_render_stats *st = &r->stats;
    char names[FV_MAX_PASSES][FV_VK_TIMER_NAME_MAX];
    double ms[FV_MAX_PASSES];
    st->pass_count = fv_vk_timer_collect(&r->timer, r->vk, slot, ms, names, FV_MAX_PASSES, &st->frame_gpu_ms);
    st->pixels_shaded = 0;
    /* A list the GPU made (foveation): its size, read back now that the fence passed, is what its shader shaded. */
    uint64_t gpu_count = s->sampled ? fv_frame_samples_count(&r->samples, slot) : 0;
    for (uint32_t i = 0; i < s->counter_count; i++) s->counters[i].pixels_shaded += s->counters[i].gpu_lists * gpu_count;
    for (uint32_t i = 0; i < st->pass_count; i++) {
        memcpy(st->pass_name[i], names[i], sizeof st->pass_name[i]); /* both 24 bytes, terminated */
        st->pass_name[i][sizeof st->pass_name[i] - 1] = '\0';
        st->pass_gpu_ms[i] = ms[i];
        st->pass_counters[i] = i < s->counter_count ? s->counters[i] : (fv_pass_counters){0};
        st->pixels_shaded += st->pass_counters[i].pixels_shaded;
    }
    st->frame_id = s->frame_id;
    r->have_stats = true;
    r->history[s->frame_id % FV_RENDERER_STATS_HISTORY] = *st;
    r->history_valid[s->frame_id % FV_RENDERER_STATS_HISTORY] = true;
    return FV_OK;
}

fv_result fv_renderer_finish(fv_renderer *r)
{
    if (!r) return FV_ERR_INVALID_ARG;
    /* Oldest first, so the newest frame's timings are the ones left in the stats. */
    for (uint32_t k = 0; k < r->slot_count; k++) FV_TRY(retire(r, (r->next_slot + k) % r->slot_count));
    return FV_OK;
}

const fv_frame_plan *fv_renderer_plan(const fv_renderer *r) { return r ? &r->plan : NULL; }

fv_result fv_renderer_set_quality(fv_renderer *r, const fv_quality *quality)
{
    if (!r || !quality) return FV_ERR_INVALID_ARG;
    fv_quality q = quality_sanitized(quality);
    return plan_differs(&q, &r->plan_quality) ? fv_renderer_plan_apply(r, &q) : FV_OK;
}

/* ---- drawing ------------------------------------------------------------------------------------------------- */

/* Let the enabled passes write the slot's host-side data (the GPU is done with the slot). */
static fv_result prepare_passes(fv_renderer *r, uint32_t slot, const fv_frame_input *in)
{
    fv_shade_inputs_begin_frame(&r->shade_inputs, slot);
    for (uint32_t i = 0; i < r->pass_count; i++) {
        const fv_pass *p = r->table[i];
        if (!r->plan.entries[i].enabled || !r->pass_state[i] || !p->prepare) continue;
        fv_pass_counters unused = {0};
        fv_pass_frame f = {.slot = slot, .input = in, .images = &r->images, .scene = &r->scene,
                           .scene_set = fv_scene_gpu_set(&r->scene, slot), .shade_inputs = &r->shade_inputs,
                           .counters = &unused};
        p->prepare(r->pass_state[i], &f);
    }
    return fv_shade_inputs_end_frame(&r->shade_inputs, slot);
}

/* Record the enabled passes (only those that replay on a pixel list when `replay` is set), each in its own
 * timestamp range when `timed`. A whole frame (replay NULL) hands the frame sample list, once a pass filled it, to
 * the passes after that one as their `pixels`. */
void fv_renderer_record_passes(fv_renderer *r, VkCommandBuffer cmd, uint32_t slot, const fv_frame_input *in,
                          const fv_pixel_list *replay, bool timed, frame_slot *s)
{
    if (s) s->counter_count = 0;
    if (s) s->sampled = false;
    r->samples.active = false;
    fv_pixel_list sampled = {0};
    const fv_pixel_list *pixels = replay;
    for (uint32_t i = 0; i < r->pass_count; i++) {
        const fv_pass *p = r->table[i];
        if (!r->plan.entries[i].enabled || !r->pass_state[i] || !p->record) continue;
        if (replay && !(p->flags & FV_PASS_REPLAYS_ON_PIXELS)) continue;
        fv_pass_counters scratch = {0};
        int t = timed ? fv_vk_timer_begin(&r->timer, cmd, slot, p->id) : -1;
        if (timed && t < 0) /* never with plan_apply's check: said, not dropped in silence */
            FV_ERROR(MOD, "pass %s: the timer table is full (FV_VK_TIMER_MAX_PASSES %u): no time or counters", p->id,
                     FV_VK_TIMER_MAX_PASSES);
        fv_pass_counters *counters = s && t >= 0 && (uint32_t)t < FV_MAX_PASSES ? &s->counters[t] : &scratch;
        *counters = (fv_pass_counters){0};
        fv_pass_frame f = {.cmd = cmd, .slot = slot, .input = in, .images = &r->images, .scene = &r->scene,
                           .scene_set = fv_scene_gpu_set(&r->scene, slot), .shade_inputs = &r->shade_inputs,
                           .pixels = pixels, .counters = counters, .samples = replay ? NULL : &r->samples};
        p->record(r->pass_state[i], &f);
        if (!replay && !pixels && r->samples.active) {
            sampled = (fv_pixel_list){.buffer = r->samples.list[slot].buffer, .range = VK_WHOLE_SIZE,
                                      .indirect = r->samples.indirect[slot].buffer, .count_on_gpu = true};
            pixels = &sampled;
            if (s) s->sampled = true;
        }
        if (t >= 0) {
            fv_vk_timer_end(&r->timer, cmd, slot, t);
            if (s && (uint32_t)t + 1 > s->counter_count) s->counter_count = (uint32_t)t + 1;
        }
    }
    for (uint32_t i = 0; !replay && i < r->pass_count; i++) {
        const fv_pass *p = r->table[i];
        if (!r->plan.entries[i].enabled || !r->pass_state[i] || !p->record_end) continue;
        fv_pass_counters unused = {0};
        fv_pass_frame f = {.cmd = cmd, .slot = slot, .input = in, .images = &r->images, .scene = &r->scene,
                           .scene_set = fv_scene_gpu_set(&r->scene, slot), .shade_inputs = &r->shade_inputs,
                           .counters = &unused};
        p->record_end(r->pass_state[i], &f);
    }
}

fv_result fv_renderer_draw(fv_renderer *r, const fv_frame_input *in_raw)
{
    if (!r || !in_raw) return FV_ERR_INVALID_ARG;
    if (!r->scene_loaded) {
        FV_ERROR(MOD, "draw before a scene was loaded");
        return FV_ERR_STATE;
    }
    if (!fv_renderer_frame_input_ok(in_raw)) {
        FV_ERROR(MOD, "frame %llu: non-finite view or projection matrix", (unsigned long long)in_raw->frame_id);
        return FV_ERR_RANGE;
    }
    fv_frame_input in = *in_raw;
    in.quality = quality_sanitized(&in_raw->quality);
    if (plan_differs(&in.quality, &r->plan_quality)) FV_TRY(fv_renderer_plan_apply(r, &in.quality));

    uint32_t slot = r->next_slot;
    frame_slot *s = &r->slots[slot];
    FV_TRY(retire(r, slot)); /* the GPU is done with this slot's command buffer, upload data and queries */
    FV_VK_CHECK(vkResetFences(r->vk->device, 1, &s->fence));
    FV_VK_CHECK(vkResetCommandPool(r->vk->device, s->pool, 0));
    fv_gpu_frame fr;
    fv_mat4 vp[2];
    fv_renderer_frame_constants(r, &in, &fr, vp);
    double t = isfinite(in.time_s) ? in.time_s : 0.0;
    FV_TRY(fv_scene_gpu_write_frame(&r->scene, slot, &fr, t, r->have_prev ? r->prev_time_s : t));
    FV_TRY(prepare_passes(r, slot, &in));
    r->have_prev = true;
    r->prev_time_s = t;
    r->prev_view_proj[0] = vp[0];
    r->prev_view_proj[1] = vp[1];

    fv_target_frame tf = {.vk = r->vk, .images = &r->images, .width = r->desc.eye_width,
                          .height = r->desc.eye_height, .slot = slot, .frame_id = in.frame_id, .cmd = s->cmd,
                          .image_ready = s->image_ready, .frame_done = s->frame_done};
    bool wait_ready = false, signal_done = false;
    const fv_target_ops *ops = r->target->ops;
    if (ops->begin) FV_TRY(ops->begin(r->target, &tf, &wait_ready, &signal_done));

    VkCommandBuffer cmd = s->cmd;
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    FV_VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
    fv_vk_timer_reset(&r->timer, cmd, slot);
    fv_renderer_record_passes(r, cmd, slot, &in, NULL, true, s);
    if (ops->record) ops->record(r->target, &tf);
    FV_VK_CHECK(vkEndCommandBuffer(cmd));
    VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    VkSubmitInfo sub = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                        .waitSemaphoreCount = wait_ready ? 1u : 0u,
                        .pWaitSemaphores = &s->image_ready,
                        .pWaitDstStageMask = &wait_stage,
                        .commandBufferCount = 1,
                        .pCommandBuffers = &cmd,
                        .signalSemaphoreCount = signal_done ? 1u : 0u,
                        .pSignalSemaphores = &s->frame_done};
    FV_VK_CHECK(vkQueueSubmit(r->vk->queue, 1, &sub, s->fence));
    s->pending = true;
    s->frame_id = in.frame_id;
    s->seq = ++r->submitted;
    r->have_frame = true;
    r->last_slot = slot;
    r->last_input = in;
    r->next_slot = (slot + 1) % r->slot_count;
    if (ops->end) FV_TRY(ops->end(r->target, &tf));
    return FV_OK;
}

fv_result fv_renderer_frame_stats(const fv_renderer *r, uint64_t frame_id, fv_render_stats *out_stats)
{
    if (!r || !out_stats) return FV_ERR_INVALID_ARG;
    uint32_t k = (uint32_t)(frame_id % FV_RENDERER_STATS_HISTORY);
    if (!r->history_valid[k] || r->history[k].frame_id != frame_id) return FV_NO_NEW_DATA;
    *out_stats = r->history[k];
    out_stats->device_memory_bytes = r->vk->memory_bytes;
    out_stats->peak_device_memory_bytes = r->vk->memory_peak_bytes;
    return FV_OK;
}

fv_result fv_renderer_stats(const fv_renderer *r, fv_render_stats *out_stats)
{
    if (!r || !out_stats) return FV_ERR_INVALID_ARG;
    *out_stats = r->stats;
    out_stats->device_memory_bytes = r->vk->memory_bytes;
    out_stats->peak_device_memory_bytes = r->vk->memory_peak_bytes;
    return r->have_stats ? FV_OK : FV_NO_NEW_DATA;
}

/* ---- small queries ------------------------------------------------------------------------------------------- */

uint32_t fv_renderer_pass_details(const fv_renderer *r, const char *pass, fv_pass_detail *out, uint32_t cap)
{
    if (!r || !pass || !out) return 0;
    for (uint32_t i = 0; i < r->pass_count; i++)
        if (strcmp(r->table[i]->id, pass) == 0 && r->pass_state[i] && r->table[i]->details)
            return r->table[i]->details(r->pass_state[i], out, cap);
    return 0;
}

void *fv_renderer_pass_state(const fv_renderer *r, const char *pass)
{
    for (uint32_t i = 0; r && pass && i < r->pass_count; i++)
        if (strcmp(r->table[i]->id, pass) == 0) return r->pass_state[i];
    return NULL;
}

uint32_t fv_renderer_validation_messages(const fv_renderer *r) { return r ? fv_vk_validation_messages(r->vk) : 0; }

const char *fv_renderer_device_name(const fv_renderer *r) { return r && r->vk ? r->vk->info.name : "(none)"; }

void fv_renderer_size(const fv_renderer *r, uint32_t *out_width, uint32_t *out_height)
{
    if (out_width) *out_width = r ? r->desc.eye_width : 0;
    if (out_height) *out_height = r ? r->desc.eye_height : 0;
}
