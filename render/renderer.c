/* @brief The renderer object: the device, frames in flight, the plan loop over the pass table, and readback. Every
 * pass is reached through the table (fv_passes.h); the scene lives in fv_scene_gpu, the images in fv_images. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_gpu.h"
#include "fv_images.h"
#include "fv_knobs.h"
#include "fv_passes.h"
#include "fv_renderer.h"
#include "fv_scene_gpu.h"
#include "fv_shade_inputs.h"
#include "fv_target.h"
#include "fv_vk.h"

#define MOD "render"

/* Per frame in flight: what the CPU writes or the GPU may still be using while the next frame is recorded. */
typedef struct frame_slot {
    VkCommandPool pool;
    VkCommandBuffer cmd;
    VkFence fence;
    VkSemaphore image_ready, frame_done; /* binary semaphores for the target's hand-overs */
    bool pending;                        /* submitted, fence not yet waited for */
    uint64_t seq;                        /* submission number (caller frame ids need not increase) */
    uint64_t frame_id;
    fv_pass_counters counters[FV_MAX_PASSES]; /* per timed pass, in timer order */
    bool sampled;                        /* a pass filled the frame sample list: its count is read back at retire */
    uint32_t counter_count;
} frame_slot;

struct fv_renderer {
    fv_renderer_desc desc;
    fv_vk *vk;
    fv_images images;
    fv_scene_gpu scene;
    fv_shade_inputs shade_inputs;
    fv_frame_samples samples; /* the frame sample list (fv_frame_samples.h) */
    fv_vk_timer timer;
    fv_target *target;
    frame_slot slots[FV_MAX_FRAMES_IN_FLIGHT];
    uint32_t slot_count, next_slot;
    /* the pass table, its plan and each enabled pass's state */
    const fv_pass *const *table;
    uint32_t pass_count;
    void *pass_state[FV_MAX_PASSES];
    uint32_t pass_variant[FV_MAX_PASSES]; /* the variant each live state was made for */
    fv_frame_plan plan;
    fv_quality plan_quality;
    bool multiview;
    char multiview_why[96];
    /* the loaded scene, as planning needs it (no vertex data, no textures) */
    bool scene_loaded;
    fv_scene plan_scene;
    fv_head head;
    fv_vec3 bounds_min, bounds_max;
    bool has_bounds;
    /* previous frame, for motion vectors */
    bool have_prev;
    double prev_time_s;
    fv_mat4 prev_view_proj[2];
    /* results */
    bool have_frame;
    uint32_t last_slot;
    fv_frame_input last_input;
    fv_render_stats stats;
    bool have_stats;
    fv_render_stats history[FV_RENDERER_STATS_HISTORY]; /* the last retired frames, by frame_id % N */
    bool history_valid[FV_RENDERER_STATS_HISTORY];
    uint64_t stats_seq, submitted;
};

static fv_gpu_mat4 to_gpu(const fv_mat4 *m)
{
    fv_gpu_mat4 g;
    memcpy(g.m, m->m, sizeof g.m);
    return g;
}

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
static fv_result plan_apply(fv_renderer *r, const fv_quality *quality)
{
    fv_plan_context ctx = {.scene = r->scene_loaded ? &r->plan_scene : NULL, .device = &r->vk->info,
                           .multiview = r->multiview, .multiview_why = r->multiview ? NULL : r->multiview_why,
                           .quality = quality,
                           .target = r->target && r->target->ops ? r->target->ops->name : "headless"};
    fv_frame_plan plan;
    fv_frame_plan_build_ctx(&ctx, &plan);
    /* Passes write descriptor sets shared with frames in flight when they start or stop: wait for the GPU first. */
    bool change = false;
    for (uint32_t i = 0; i < r->pass_count; i++) {
        bool want = plan.entries[i].enabled && r->table[i]->init;
        change = change || (want != (r->pass_state[i] != NULL)) ||
                 (want && r->pass_state[i] && r->pass_variant[i] != plan.entries[i].variant);
    }
    if (change) {
        FV_TRY(fv_renderer_finish(r));
        VkResult vr = vkDeviceWaitIdle(r->vk->device);
        if (vr < 0) return fv_vk_fail(vr, "vkDeviceWaitIdle", __FILE__, __LINE__);
    }
    for (uint32_t i = 0; i < r->pass_count; i++) {
        bool keep = plan.entries[i].enabled && r->table[i]->init && r->pass_variant[i] == plan.entries[i].variant;
        if (r->pass_state[i] && !keep) fini_pass(r, i);
    }
    r->plan = plan;
    r->plan_quality = *quality;
    for (uint32_t i = 0; i < r->pass_count; i++) {
        if (!plan.entries[i].enabled || !r->table[i]->init || r->pass_state[i]) continue;
        fv_pass_env env;
        pass_env(r, i, &env);
        fv_result res = r->table[i]->init(&env, &r->pass_state[i]);
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
    fv_renderer *r = calloc(1, sizeof *r);
    if (!r) return FV_ERR_NO_MEMORY;
    r->desc = desc;
    r->slot_count = desc.frames_in_flight;
    r->target = desc.target ? desc.target : fv_target_headless();
    r->table = fv_pass_table(&r->pass_count);
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
    if (res == FV_OK) res = plan_apply(r, &q);
    if (res != FV_OK) goto fail;
    *out_renderer = r;
    return FV_OK;
fail:
    FV_ERROR(MOD, "renderer (%ux%u per eye) could not be created: %s", desc.eye_width, desc.eye_height,
             fv_result_str(res));
    fv_renderer_destroy(&r);
    return res;
}

static void free_plan_scene(fv_renderer *r)
{
    free(r->plan_scene.nodes);
    free(r->plan_scene.meshes);
    free(r->plan_scene.materials);
    free(r->plan_scene.lights);
    memset(&r->plan_scene, 0, sizeof r->plan_scene);
}

static void release_scene(fv_renderer *r)
{
    fv_scene_gpu_unload(&r->scene);
    free_plan_scene(r);
    r->scene_loaded = false;
    r->have_prev = false;
    r->have_frame = false;
    memset(r->history_valid, 0, sizeof r->history_valid); /* frame ids may start over with the next scene */
}

void fv_renderer_destroy(fv_renderer **pr)
{
    if (!pr || !*pr) return;
    fv_renderer *r = *pr;
    if (r->vk) {
        vkDeviceWaitIdle(r->vk->device);
        for (uint32_t i = 0; i < r->pass_count; i++) fini_pass(r, i);
        release_scene(r);
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

/* ---- scene --------------------------------------------------------------------------------------------------- */

/* What planning looks at: the scene's structure without vertex data or textures. */
static fv_result copy_plan_scene(fv_renderer *r, const fv_scene *s)
{
    fv_scene *p = &r->plan_scene;
    memset(p, 0, sizeof *p);
    snprintf(p->name, sizeof p->name, "%s", s->name);
    snprintf(p->source, sizeof p->source, "%s", s->source);
    p->unit_scale_m = s->unit_scale_m;
    p->head = s->head;
    p->ambient = s->ambient;
    p->nodes = malloc((s->node_count ? s->node_count : 1) * sizeof *p->nodes);
    p->meshes = malloc((s->mesh_count ? s->mesh_count : 1) * sizeof *p->meshes);
    p->materials = malloc((s->material_count ? s->material_count : 1) * sizeof *p->materials);
    p->lights = malloc((s->light_count ? s->light_count : 1) * sizeof *p->lights);
    if (!p->nodes || !p->meshes || !p->materials || !p->lights) return FV_ERR_NO_MEMORY;
    memcpy(p->nodes, s->nodes, s->node_count * sizeof *p->nodes);
    p->node_count = s->node_count;
    for (uint32_t m = 0; m < s->mesh_count; m++) {
        p->meshes[m] = s->meshes[m];
        p->meshes[m].positions = p->meshes[m].normals = NULL;
        p->meshes[m].texcoords = NULL;
        p->meshes[m].indices = NULL;
    }
    p->mesh_count = s->mesh_count;
    memcpy(p->materials, s->materials, s->material_count * sizeof *p->materials);
    p->material_count = s->material_count;
    memcpy(p->lights, s->lights, s->light_count * sizeof *p->lights);
    p->light_count = s->light_count;
    return FV_OK;
}

fv_result fv_renderer_load_scene(fv_renderer *r, const fv_scene *scene)
{
    if (!r || !scene) return FV_ERR_INVALID_ARG;
    fv_result res = fv_renderer_finish(r);
    if (res != FV_OK) return res;
    VkResult vr = vkDeviceWaitIdle(r->vk->device);
    if (vr < 0) return fv_vk_fail(vr, "vkDeviceWaitIdle", __FILE__, __LINE__);
    release_scene(r);
    res = fv_scene_gpu_load(&r->scene, scene);
    if (res == FV_OK) res = copy_plan_scene(r, scene);
    if (res != FV_OK) goto fail;
    r->head = scene->head;
    r->has_bounds = fv_scene_world_bounds(scene, 0.0, &r->bounds_min, &r->bounds_max);
    r->scene_loaded = true;
    res = plan_apply(r, &r->plan_quality);
    if (res != FV_OK) goto fail;
    FV_INFO(MOD, "%s: %u draws, %u lights, %llu triangles uploaded", scene->source, r->scene.draw_count,
            r->scene.light_count, (unsigned long long)fv_scene_triangle_count(scene));
    fv_scene_warn_cost(scene, r->desc.eye_width, r->desc.eye_height, "the shade pass");
    return FV_OK;
fail:
    FV_ERROR(MOD, "%s: loading the scene into the renderer failed: %s", scene->source, fv_result_str(res));
    release_scene(r);
    return res;
}

const fv_frame_plan *fv_renderer_plan(const fv_renderer *r) { return r ? &r->plan : NULL; }

fv_result fv_renderer_set_quality(fv_renderer *r, const fv_quality *quality)
{
    if (!r || !quality) return FV_ERR_INVALID_ARG;
    fv_quality q = quality_sanitized(quality);
    return plan_differs(&q, &r->plan_quality) ? plan_apply(r, &q) : FV_OK;
}

fv_result fv_renderer_frame_input(const fv_renderer *r, const fv_head *head, uint64_t frame_id, double time_s,
                                  fv_frame_input *out)
{
    if (!r || !out) return FV_ERR_INVALID_ARG;
    if (!r->scene_loaded) return FV_ERR_STATE;
    const fv_head *h = head ? head : &r->head;
    float n = 0, f = 0;
    if (r->has_bounds) fv_frame_near_far_from_bounds(h, r->bounds_min, r->bounds_max, &n, &f);
    fv_frame_input_from_head(h, n, f, r->desc.eye_width, r->desc.eye_height, frame_id, time_s, out);
    return FV_OK;
}

/* ---- drawing ------------------------------------------------------------------------------------------------- */

/* The frame constants the runtime's input gives: views, eyes, gaze, pupil, times, quality. */
static void frame_constants(fv_renderer *r, const fv_frame_input *in, fv_gpu_frame *fr, fv_mat4 vp[2])
{
    memset(fr, 0, sizeof *fr);
    for (int e = 0; e < 2; e++) {
        vp[e] = fv_mat4_mul(&in->eye[e].proj, &in->eye[e].view);
        fv_mat4 inv;
        (void)fv_mat4_invert(&vp[e], &inv); /* identity when singular: positions then stay finite */
        fr->view_proj[e] = to_gpu(&vp[e]);
        fr->prev_view_proj[e] = to_gpu(r->have_prev ? &r->prev_view_proj[e] : &vp[e]);
        fr->inv_view_proj[e] = to_gpu(&inv);
        fv_vec3 p = in->eye[e].pos_world;
        fr->eye_pos[e] = (fv_gpu_vec4){p.x, p.y, p.z, 1.0f};
        const fv_eye_view *v = &in->eye[e];
        fr->eye_tan[e] = (fv_gpu_vec4){v->tan_left, v->tan_right, v->tan_up, v->tan_down};
        /* Gaze: a valid, finite, non-zero direction is normalised; anything else is "no gaze" (straight ahead). */
        const fv_eye_gaze *g = &in->gaze[e];
        fv_vec3 d = fv_v3(0, 0, 0);
        if (g->valid && fv_v3_isfinite(g->dir_eye)) {
            /* Scale by the largest component first, so that neither huge nor tiny directions over/underflow. */
            float m = fmaxf(fabsf(g->dir_eye.x), fmaxf(fabsf(g->dir_eye.y), fabsf(g->dir_eye.z)));
            if (m > 0.0f) d = fv_v3_normalize_or(fv_v3_scale(g->dir_eye, 1.0f / m), fv_v3(0, 0, 0));
        }
        bool valid = fv_v3_len(d) > 0.5f;
        if (!valid) d = fv_v3(0, 0, -1);
        fr->gaze_dir[e] = (fv_gpu_vec4){d.x, d.y, d.z, valid ? 1.0f : 0.0f};
        float u = isfinite(g->uncertainty_deg) ? fv_clampf((float)fv_deg_to_rad(g->uncertainty_deg), 0.0f, (float)FV_PI)
                                               : (float)FV_PI;
        /* A human pupil is 1.5 to 9 mm: anything outside (0, FV_GPU_PUPIL_MAX_MM] is unknown (0). */
        float pupil = isfinite(in->pupil_mm) && in->pupil_mm > 0.0f && in->pupil_mm <= FV_GPU_PUPIL_MAX_MM ? in->pupil_mm
                                                                                                         : 0.0f;
        fr->gaze_info[e] = (fv_gpu_vec4){valid ? u : (float)FV_PI, pupil, 0.0f, 0.0f};
    }
    fr->counts = (fv_gpu_uvec4){0, r->desc.eye_width, r->desc.eye_height, (uint32_t)in->frame_id};
    fr->time = (fv_gpu_vec4){(float)(isfinite(in->time_s) ? in->time_s : 0.0), 0.0f, 0.0f, 0.0f};
    uint64_t photon = in->t_photon_ns > 0 ? (uint64_t)in->t_photon_ns : 0u;
    fr->photon = (fv_gpu_uvec4){(uint32_t)photon, (uint32_t)(photon >> 32), (uint32_t)in->quality.debug_view, 0};
    fr->quality = (fv_gpu_vec4){in->quality.exposure, 0.0f, 0.0f, 0.0f};
}

static bool frame_input_ok(const fv_frame_input *in)
{
    for (int e = 0; e < 2; e++)
        for (int c = 0; c < 4; c++)
            for (int k = 0; k < 4; k++)
                if (!isfinite(in->eye[e].view.m[c][k]) || !isfinite(in->eye[e].proj.m[c][k])) return false;
    return fv_v3_isfinite(in->eye[0].pos_world) && fv_v3_isfinite(in->eye[1].pos_world);
}

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
static void record_passes(fv_renderer *r, VkCommandBuffer cmd, uint32_t slot, const fv_frame_input *in,
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
    if (!frame_input_ok(in_raw)) {
        FV_ERROR(MOD, "frame %llu: non-finite view or projection matrix", (unsigned long long)in_raw->frame_id);
        return FV_ERR_RANGE;
    }
    fv_frame_input in = *in_raw;
    in.quality = quality_sanitized(&in_raw->quality);
    if (plan_differs(&in.quality, &r->plan_quality)) FV_TRY(plan_apply(r, &in.quality));

    uint32_t slot = r->next_slot;
    frame_slot *s = &r->slots[slot];
    FV_TRY(retire(r, slot)); /* the GPU is done with this slot's command buffer, upload data and queries */
    FV_VK_CHECK(vkResetFences(r->vk->device, 1, &s->fence));
    FV_VK_CHECK(vkResetCommandPool(r->vk->device, s->pool, 0));
    fv_gpu_frame fr;
    fv_mat4 vp[2];
    frame_constants(r, &in, &fr, vp);
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
    record_passes(r, cmd, slot, &in, NULL, true, s);
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
    fv_images_next_frame(&r->images);
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

/* ---- readback and re-shading --------------------------------------------------------------------------------- */

static fv_result need_frame(const fv_renderer *r, const char *what)
{
    if (r->have_frame) return FV_OK;
    FV_ERROR(MOD, "%s before any frame was drawn", what);
    return FV_ERR_STATE;
}

fv_result fv_renderer_read_rgba8(fv_renderer *r, bool sbs, int eye, uint8_t *out, size_t out_size)
{
    if (!r || !out) return FV_ERR_INVALID_ARG;
    FV_TRY(need_frame(r, "read_rgba8"));
    FV_TRY(fv_renderer_finish(r));
    return fv_target_read_display(&r->images, r->desc.eye_width, r->desc.eye_height, sbs, eye, out, out_size);
}

fv_result fv_renderer_read_linear(fv_renderer *r, int eye, float *out_rgba, size_t out_floats)
{
    if (!r || !out_rgba || eye < 0 || eye > 1) return FV_ERR_INVALID_ARG;
    FV_TRY(need_frame(r, "read_linear"));
    size_t n = (size_t)r->desc.eye_width * r->desc.eye_height * 4;
    if (out_floats < n) {
        FV_ERROR(MOD, "read_linear needs %zu floats, got %zu", n, out_floats);
        return FV_ERR_INVALID_ARG;
    }
    FV_TRY(fv_renderer_finish(r));
    return fv_images_read(&r->images, FV_IMAGE_COLOR, (uint32_t)eye, out_rgba, out_floats * sizeof(float), 0,
                          (size_t)r->desc.eye_width * 16);
}

/* IEEE 754 binary16 -> float (exact: every half is a float). */
static float half_to_float(uint16_t h)
{
    uint32_t sign = (uint32_t)(h >> 15) << 31, exp = (h >> 10) & 0x1fu, mant = h & 0x3ffu, bits;
    if (exp == 0x1fu) {
        bits = sign | 0x7f800000u | (mant << 13); /* Inf / NaN */
    } else if (exp != 0) {
        bits = sign | ((exp + 112u) << 23) | (mant << 13); /* rebias 15 -> 127 */
    } else {
        float f = ldexpf((float)mant, -24); /* zero or subnormal */
        return sign ? -f : f;
    }
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

fv_result fv_renderer_read_motion(fv_renderer *r, int eye, float *out_rg, size_t out_floats)
{
    if (!r || !out_rg || eye < 0 || eye > 1) return FV_ERR_INVALID_ARG;
    FV_TRY(need_frame(r, "read_motion"));
    size_t n = (size_t)r->desc.eye_width * r->desc.eye_height * 2;
    if (out_floats < n) {
        FV_ERROR(MOD, "read_motion needs %zu floats, got %zu", n, out_floats);
        return FV_ERR_INVALID_ARG;
    }
    uint16_t *half = malloc(n * sizeof *half);
    if (!half) return FV_ERR_NO_MEMORY;
    fv_result res = fv_renderer_finish(r);
    if (res == FV_OK)
        res = fv_images_read(&r->images, FV_IMAGE_MOTION, (uint32_t)eye, half, n * sizeof *half, 0,
                             (size_t)r->desc.eye_width * 2 * sizeof *half);
    if (res == FV_OK)
        for (size_t i = 0; i < n; i++) out_rg[i] = half_to_float(half[i]);
    free(half);
    return res;
}

/* Indirect dispatch arguments for a list of `count` pixels (fv_gpu.h FV_GPU_LIST_*). */
static VkDispatchIndirectCommand list_dispatch(uint32_t count)
{
    uint32_t groups = (uint32_t)(((uint64_t)count + FV_GPU_LIST_GROUP_SIZE - 1) / FV_GPU_LIST_GROUP_SIZE);
    VkDispatchIndirectCommand c = {groups < FV_GPU_LIST_GROUPS_X ? groups : FV_GPU_LIST_GROUPS_X,
                                   (groups + FV_GPU_LIST_GROUPS_X - 1) / FV_GPU_LIST_GROUPS_X, 1};
    if (groups == 0) c.x = c.y = 0;
    return c;
}

fv_result fv_renderer_shade_pixels(fv_renderer *r, const uint32_t *packed, uint32_t count, const float *clear_rgba)
{
    if (!r || (!packed && count)) return FV_ERR_INVALID_ARG;
    FV_TRY(need_frame(r, "shade_pixels"));
    for (uint32_t i = 0; i < count; i++) {
        uint32_t x = packed[i] & 0x7fffu, y = (packed[i] >> 15) & 0x7fffu, layer = packed[i] >> 30;
        if (x >= r->desc.eye_width || y >= r->desc.eye_height || layer > 1) {
            FV_ERROR(MOD, "shade_pixels: entry %u is pixel (%u, %u) of eye %u, outside %ux%u x2", i, x, y, layer,
                     r->desc.eye_width, r->desc.eye_height);
            return FV_ERR_RANGE;
        }
    }
    FV_TRY(fv_renderer_finish(r));
    fv_vk *vk = r->vk;
    fv_vk_buffer list = {0}, indirect = {0};
    VkDeviceSize list_size = FV_GPU_LIST_HEADER_BYTES + (VkDeviceSize)(count ? count : 1) * 4;
    fv_result res = fv_vk_buffer_create(vk, list_size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, FV_VK_MEM_UPLOAD,
                                        "shade pixel list", &list);
    if (res == FV_OK)
        res = fv_vk_buffer_create(vk, sizeof(VkDispatchIndirectCommand), VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                                  FV_VK_MEM_UPLOAD, "shade list dispatch", &indirect);
    if (res != FV_OK) goto done;
    uint32_t header[4] = {count, 0, 0, 0};
    memcpy(list.mapped, header, sizeof header);
    if (count) memcpy((uint8_t *)list.mapped + FV_GPU_LIST_HEADER_BYTES, packed, (size_t)count * 4);
    VkDispatchIndirectCommand args = list_dispatch(count);
    memcpy(indirect.mapped, &args, sizeof args);
    if ((res = fv_vk_buffer_flush(vk, &list)) != FV_OK || (res = fv_vk_buffer_flush(vk, &indirect)) != FV_OK) goto done;

    VkCommandBuffer cmd;
    res = fv_vk_oneshot_begin(vk, "shade pixel list", &cmd);
    if (res != FV_OK) goto done;
    if (clear_rgba) {
        fv_images_use(&r->images, cmd, FV_IMAGE_COLOR,
                      (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                        VK_ACCESS_TRANSFER_WRITE_BIT});
        VkClearColorValue cv = {.float32 = {clear_rgba[0], clear_rgba[1], clear_rgba[2], clear_rgba[3]}};
        VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 2};
        vkCmdClearColorImage(cmd, fv_images_image(&r->images, FV_IMAGE_COLOR)->image, VK_IMAGE_LAYOUT_GENERAL, &cv, 1,
                             &range);
    }
    /* The last frame's slot: its frame block and lights describe the frame being re-shaded. */
    fv_pixel_list pl = {.buffer = list.buffer, .offset = 0, .range = VK_WHOLE_SIZE, .indirect = indirect.buffer,
                        .host_count = count};
    record_passes(r, cmd, r->last_slot, &r->last_input, &pl, false, NULL);
    res = fv_vk_oneshot_end(vk, cmd);
done:
    fv_vk_buffer_destroy(vk, &indirect);
    fv_vk_buffer_destroy(vk, &list);
    if (res == FV_OK) r->stats.pixels_shaded = count;
    return res;
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

fv_result fv_renderer_read_image(fv_renderer *r, const char *name, int eye, void *out, size_t out_size,
                                 size_t texel_bytes)
{
    if (!r || !name || !out || eye < 0 || eye > 1 || !texel_bytes) return FV_ERR_INVALID_ARG;
    FV_TRY(need_frame(r, "read_image"));
    fv_image_id id;
    if (fv_images_find(&r->images, name, &id) != FV_OK) {
        FV_ERROR(MOD, "read_image: no image named %s", name);
        return FV_ERR_NOT_FOUND;
    }
    size_t pitch = (size_t)r->desc.eye_width * texel_bytes;
    if (out_size < pitch * r->desc.eye_height) {
        FV_ERROR(MOD, "read_image %s needs %zu bytes, got %zu", name, pitch * r->desc.eye_height, out_size);
        return FV_ERR_INVALID_ARG;
    }
    FV_TRY(fv_renderer_finish(r));
    return fv_images_read(&r->images, id, (uint32_t)eye, out, out_size, 0, pitch);
}

uint32_t fv_renderer_validation_messages(const fv_renderer *r) { return r ? fv_vk_validation_messages(r->vk) : 0; }

const char *fv_renderer_device_name(const fv_renderer *r) { return r && r->vk ? r->vk->info.name : "(none)"; }

void fv_renderer_size(const fv_renderer *r, uint32_t *out_width, uint32_t *out_height)
{
    if (out_width) *out_width = r ? r->desc.eye_width : 0;
    if (out_height) *out_height = r ? r->desc.eye_height : 0;
}
