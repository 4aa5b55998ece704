/* @brief The renderer object: Vulkan core + G-buffer + shading + present, frames in flight, per-pass timings. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_gpu.h"
#include "fv_renderer.h"
#include "fv_vk.h"
#include "gbuffer.h"
#include "present.h"
#include "shade.h"

#define MOD "render"
#define MAX_SLOTS 8

/* Per frame in flight: what the CPU writes or the GPU may still be using while the next frame is recorded. */
typedef struct frame_slot {
    VkCommandPool pool;
    VkCommandBuffer cmd;
    VkFence fence;
    fv_vk_buffer upload; /* frame block | lights | draw records, host-written each frame */
    bool pending;        /* submitted, fence not yet waited for */
    uint64_t seq;        /* submission number (caller frame ids need not increase) */
    uint64_t frame_id;
    uint64_t pixels_shaded;
} frame_slot;

struct fv_renderer {
    fv_renderer_desc desc;
    fv_vk *vk;
    fv_gbuffer gb;
    fv_shade shade;
    fv_present present;
    fv_vk_timer timer;
    frame_slot slots[MAX_SLOTS];
    uint32_t slot_count, next_slot;
    /* the loaded scene: only what per-frame work needs (the renderer keeps no pointer to the caller's scene) */
    bool scene_loaded;
    fv_scene anim;            /* nodes only, for fv_scene_node_world */
    fv_gbuffer_draw *draws;   /* one per drawn node */
    uint32_t *draw_nodes;
    uint32_t *draw_materials;
    uint32_t draw_count;
    fv_gpu_light *lights;
    uint32_t light_count;
    fv_vec3 ambient;
    fv_head head;
    fv_vec3 bounds_min, bounds_max;
    bool has_bounds;
    VkDeviceSize lights_offset, draws_offset, upload_size;
    fv_frame_plan plan;
    /* previous frame, for motion vectors */
    bool have_prev;
    double prev_time_s;
    fv_mat4 prev_view_proj[2];
    /* results */
    bool have_frame;
    uint32_t last_slot;
    fv_render_stats stats;
    bool have_stats;
    fv_render_stats history[FV_RENDERER_STATS_HISTORY]; /* the last retired frames, by frame_id % N */
    bool history_valid[FV_RENDERER_STATS_HISTORY];
    uint64_t stats_seq, submitted;
    bool multiview;
    char multiview_why[96];
};

/* The plan's G-buffer entry also says how the eyes are drawn on this device. */
static void plan_build(fv_renderer *r, const fv_scene *scene)
{
    fv_frame_plan_build(scene, &r->plan);
    if (r->multiview) return;
    for (uint32_t i = 0; i < r->plan.count; i++) {
        fv_plan_entry *e = &r->plan.entries[i];
        if (strcmp(e->pass, "gbuffer") != 0) continue;
        char *m = strstr(e->reason, "both eyes in one multiview pass");
        if (!m) continue;
        char tail[160];
        snprintf(tail, sizeof tail, "%s", m + strlen("both eyes in one multiview pass"));
        snprintf(m, sizeof e->reason - (size_t)(m - e->reason), "%s%s", r->multiview_why, tail);
    }
}

static VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }

static fv_gpu_mat4 to_gpu(const fv_mat4 *m)
{
    fv_gpu_mat4 g;
    memcpy(g.m, m->m, sizeof g.m);
    return g;
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
    if (desc.frames_in_flight > MAX_SLOTS) {
        FV_ERROR(MOD, "frames_in_flight %u exceeds %u", desc.frames_in_flight, MAX_SLOTS);
        return FV_ERR_RANGE;
    }
    fv_renderer *r = calloc(1, sizeof *r);
    if (!r) return FV_ERR_NO_MEMORY;
    r->desc = desc;
    r->slot_count = desc.frames_in_flight;
    fv_vk_desc vd = {.device = desc.device,
                     .validation = desc.validation > 0 ? 1 : (desc.validation < 0 ? -1 : 0),
                     .memory_budget_bytes = desc.memory_budget_bytes,
                     .app_name = "fovea"};
    fv_result res = fv_vk_create(&vd, &r->vk);
    if (res != FV_OK) goto fail;
    r->multiview = fv_vk_multiview_trusted(&r->vk->info, r->multiview_why, sizeof r->multiview_why);
    fv_gbuffer_desc gd = {.width = desc.eye_width, .height = desc.eye_height, .frames_in_flight = r->slot_count,
                          .multiview = r->multiview};
    res = fv_gbuffer_init(&r->gb, r->vk, &gd);
    if (res == FV_OK) res = fv_shade_init(&r->shade, r->vk, &r->gb, r->slot_count);
    if (res == FV_OK) res = fv_present_init(&r->present, r->vk, &r->shade.color, FV_TONEMAP_CLAMP);
    if (res == FV_OK) res = fv_vk_timer_init(&r->timer, r->vk, r->slot_count);
    if (res == FV_OK) res = create_slots(r);
    if (res != FV_OK) goto fail;
    plan_build(r, NULL);
    *out_renderer = r;
    return FV_OK;
fail:
    FV_ERROR(MOD, "renderer (%ux%u per eye) could not be created: %s", desc.eye_width, desc.eye_height,
             fv_result_str(res));
    fv_renderer_destroy(&r);
    return res;
}

static void release_scene(fv_renderer *r)
{
    free(r->anim.nodes);
    memset(&r->anim, 0, sizeof r->anim);
    free(r->draws);
    free(r->draw_nodes);
    free(r->draw_materials);
    free(r->lights);
    r->draws = NULL;
    r->draw_nodes = NULL;
    r->draw_materials = NULL;
    r->lights = NULL;
    r->draw_count = r->light_count = 0;
    r->scene_loaded = false;
    r->have_prev = false;
    r->have_frame = false;
    memset(r->history_valid, 0, sizeof r->history_valid); /* frame ids may start over with the next scene */
    for (uint32_t i = 0; i < r->slot_count; i++) fv_vk_buffer_destroy(r->vk, &r->slots[i].upload);
}

void fv_renderer_destroy(fv_renderer **pr)
{
    if (!pr || !*pr) return;
    fv_renderer *r = *pr;
    if (r->vk) {
        vkDeviceWaitIdle(r->vk->device);
        release_scene(r);
        for (uint32_t i = 0; i < r->slot_count; i++) {
            frame_slot *s = &r->slots[i];
            if (s->fence) vkDestroyFence(r->vk->device, s->fence, NULL);
            if (s->pool) vkDestroyCommandPool(r->vk->device, s->pool, NULL);
        }
        fv_vk_timer_fini(&r->timer, r->vk);
        fv_present_fini(&r->present);
        fv_shade_fini(&r->shade);
        fv_gbuffer_fini(&r->gb);
        fv_vk_destroy(&r->vk);
    }
    free(r);
    *pr = NULL;
}

/* ---- frames in flight ---------------------------------------------------------------------------------------- */

/* Wait for a slot's frame and take its timings. */
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
    for (uint32_t i = 0; i < st->pass_count; i++) {
        memcpy(st->pass_name[i], names[i], sizeof st->pass_name[i]); /* both FV_VK_TIMER_NAME_MAX, terminated */
        st->pass_name[i][sizeof st->pass_name[i] - 1] = '\0';
        st->pass_gpu_ms[i] = ms[i];
    }
    st->frame_id = s->frame_id;
    st->pixels_shaded = s->pixels_shaded;
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

static fv_gpu_light to_gpu_light(const fv_light *l)
{
    fv_gpu_light g;
    memset(&g, 0, sizeof g);
    fv_vec3 p = fv_v3_isfinite(l->position_m) ? l->position_m : fv_v3(0, 0, 0);
    fv_vec3 d = fv_v3_normalize_or(l->direction, fv_v3(0, -1, 0));
    float range = isfinite(l->range_m) && l->range_m > 0 ? l->range_m : 0.0f;
    float intensity = isfinite(l->intensity) && l->intensity > 0 ? l->intensity : 0.0f;
    fv_vec3 c = l->color;
    c = fv_v3(isfinite(c.x) && c.x > 0 ? c.x : 0, isfinite(c.y) && c.y > 0 ? c.y : 0, isfinite(c.z) && c.z > 0 ? c.z : 0);
    uint32_t type = (unsigned)l->type <= FV_LIGHT_DIRECTIONAL ? (uint32_t)l->type : FV_GPU_LIGHT_POINT;
    float outer = isfinite(l->outer_cone_rad) ? fv_clampf(l->outer_cone_rad, 0.0f, (float)FV_PI / 2) : (float)FV_PI / 4;
    float inner = isfinite(l->inner_cone_rad) ? fv_clampf(l->inner_cone_rad, 0.0f, outer) : 0.0f;
    g.position_range = (fv_gpu_vec4){p.x, p.y, p.z, range};
    g.direction_type = (fv_gpu_vec4){d.x, d.y, d.z, (float)type};
    g.intensity = (fv_gpu_vec4){c.x * intensity, c.y * intensity, c.z * intensity, 0.0f};
    g.cone = (fv_gpu_vec4){cosf(inner), cosf(outer), 0.0f, 0.0f};
    return g;
}

fv_result fv_renderer_load_scene(fv_renderer *r, const fv_scene *scene)
{
    if (!r || !scene) return FV_ERR_INVALID_ARG;
    fv_result res = fv_renderer_finish(r);
    if (res != FV_OK) return res;
    VkResult vr = vkDeviceWaitIdle(r->vk->device);
    if (vr < 0) return fv_vk_fail(vr, "vkDeviceWaitIdle", __FILE__, __LINE__);
    release_scene(r);
    res = fv_gbuffer_load_scene(&r->gb, scene);
    if (res != FV_OK) goto fail;

    uint32_t draws = 0;
    for (uint32_t i = 0; i < scene->node_count; i++)
        if (scene->nodes[i].mesh >= 0 && (uint32_t)scene->nodes[i].mesh < scene->mesh_count) draws++;
    r->anim.nodes = malloc((scene->node_count ? scene->node_count : 1) * sizeof *r->anim.nodes);
    r->draws = calloc(draws ? draws : 1, sizeof *r->draws);
    r->draw_nodes = calloc(draws ? draws : 1, sizeof *r->draw_nodes);
    r->draw_materials = calloc(draws ? draws : 1, sizeof *r->draw_materials);
    r->lights = calloc(scene->light_count ? scene->light_count : 1, sizeof *r->lights);
    if (!r->anim.nodes || !r->draws || !r->draw_nodes || !r->draw_materials || !r->lights) {
        res = FV_ERR_NO_MEMORY;
        goto fail;
    }
    memcpy(r->anim.nodes, scene->nodes, scene->node_count * sizeof *scene->nodes);
    r->anim.node_count = scene->node_count;
    for (uint32_t i = 0; i < scene->node_count; i++) {
        const fv_node *n = &scene->nodes[i];
        if (n->mesh < 0 || (uint32_t)n->mesh >= scene->mesh_count) continue;
        uint32_t mat = scene->meshes[n->mesh].material;
        if (mat >= r->gb.material_count) mat = 0;
        int32_t tex = mat < scene->material_count ? scene->materials[mat].base_color_texture : -1;
        r->draws[r->draw_count] = (fv_gbuffer_draw){.mesh = (uint32_t)n->mesh, .texture = tex};
        r->draw_nodes[r->draw_count] = i;
        r->draw_materials[r->draw_count] = mat;
        r->draw_count++;
    }
    for (uint32_t l = 0; l < scene->light_count; l++) r->lights[l] = to_gpu_light(&scene->lights[l]);
    r->light_count = scene->light_count;
    r->ambient = fv_v3_isfinite(scene->ambient) ? fv_v3_max(scene->ambient, fv_v3(0, 0, 0)) : fv_v3(0, 0, 0);
    r->head = scene->head;
    r->has_bounds = fv_scene_world_bounds(scene, 0.0, &r->bounds_min, &r->bounds_max);

    /* Per-frame upload buffers: frame block | lights | draw records, each at the device's offset alignment. */
    VkDeviceSize a = r->vk->props.limits.minUniformBufferOffsetAlignment;
    if (r->vk->props.limits.minStorageBufferOffsetAlignment > a) a = r->vk->props.limits.minStorageBufferOffsetAlignment;
    if (a < 16) a = 16;
    r->lights_offset = align_up(sizeof(fv_gpu_frame), a);
    r->draws_offset = align_up(r->lights_offset + (scene->light_count ? scene->light_count : 1) * sizeof(fv_gpu_light), a);
    r->upload_size = r->draws_offset + (draws ? draws : 1) * sizeof(fv_gpu_draw);
    for (uint32_t i = 0; i < r->slot_count; i++) {
        char name[48];
        snprintf(name, sizeof name, "frame slot %u data", i);
        res = fv_vk_buffer_create(r->vk, r->upload_size,
                                  VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                  FV_VK_MEM_UPLOAD, name, &r->slots[i].upload);
        if (res != FV_OK) goto fail;
        memset(r->slots[i].upload.mapped, 0, r->upload_size);
        VkBuffer b = r->slots[i].upload.buffer;
        fv_gbuffer_bind_frame(&r->gb, i, b, 0, r->draws_offset, (draws ? draws : 1) * sizeof(fv_gpu_draw));
        fv_shade_bind_frame(&r->shade, i, b, 0, r->lights_offset,
                            (scene->light_count ? scene->light_count : 1) * sizeof(fv_gpu_light), r->gb.materials.buffer);
    }
    plan_build(r, scene);
    r->scene_loaded = true;
    FV_INFO(MOD, "%s: %u draws, %u lights, %llu triangles uploaded", scene->source, r->draw_count, r->light_count,
            (unsigned long long)fv_scene_triangle_count(scene));
    return FV_OK;
fail:
    FV_ERROR(MOD, "%s: loading the scene into the renderer failed: %s", scene->source, fv_result_str(res));
    release_scene(r);
    return res;
}

const fv_frame_plan *fv_renderer_plan(const fv_renderer *r) { return r ? &r->plan : NULL; }

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

static fv_mat4 normal_matrix(const fv_mat4 *model)
{
    fv_mat4 inv;
    if (!fv_mat4_invert(model, &inv)) return *model;
    return fv_mat4_transpose(&inv);
}

static void write_frame_data(fv_renderer *r, frame_slot *s, const fv_frame_input *in)
{
    uint8_t *base = s->upload.mapped;
    fv_gpu_frame fr;
    memset(&fr, 0, sizeof fr);
    fv_mat4 vp[2];
    for (int e = 0; e < 2; e++) {
        vp[e] = fv_mat4_mul(&in->eye[e].proj, &in->eye[e].view);
        fv_mat4 inv;
        (void)fv_mat4_invert(&vp[e], &inv); /* identity when singular: positions then stay finite */
        fr.view_proj[e] = to_gpu(&vp[e]);
        fr.prev_view_proj[e] = to_gpu(r->have_prev ? &r->prev_view_proj[e] : &vp[e]);
        fr.inv_view_proj[e] = to_gpu(&inv);
        fv_vec3 p = in->eye[e].pos_world;
        fr.eye_pos[e] = (fv_gpu_vec4){p.x, p.y, p.z, 1.0f};
    }
    fr.ambient = (fv_gpu_vec4){r->ambient.x, r->ambient.y, r->ambient.z, 0.0f};
    fr.counts = (fv_gpu_uvec4){r->light_count, r->desc.eye_width, r->desc.eye_height, (uint32_t)in->frame_id};
    memcpy(base, &fr, sizeof fr);
    if (r->light_count) memcpy(base + r->lights_offset, r->lights, r->light_count * sizeof(fv_gpu_light));
    double t = isfinite(in->time_s) ? in->time_s : 0.0;
    double t_prev = r->have_prev ? r->prev_time_s : t;
    fv_gpu_draw *d = (fv_gpu_draw *)(base + r->draws_offset);
    for (uint32_t i = 0; i < r->draw_count; i++) {
        fv_mat4 m = fv_scene_node_world(&r->anim, r->draw_nodes[i], t);
        fv_mat4 pm = fv_scene_node_world(&r->anim, r->draw_nodes[i], t_prev);
        fv_mat4 nm = normal_matrix(&m);
        d[i].model = to_gpu(&m);
        d[i].prev_model = to_gpu(&pm);
        d[i].normal_matrix = to_gpu(&nm);
        d[i].info = (fv_gpu_uvec4){r->draw_materials[i], r->draws[i].texture >= 0 ? (uint32_t)r->draws[i].texture
                                                                                   : 0xffffffffu, 0, 0};
    }
    r->have_prev = true;
    r->prev_time_s = t;
    r->prev_view_proj[0] = vp[0];
    r->prev_view_proj[1] = vp[1];
}

static bool frame_input_ok(const fv_frame_input *in)
{
    for (int e = 0; e < 2; e++)
        for (int c = 0; c < 4; c++)
            for (int k = 0; k < 4; k++)
                if (!isfinite(in->eye[e].view.m[c][k]) || !isfinite(in->eye[e].proj.m[c][k])) return false;
    return fv_v3_isfinite(in->eye[0].pos_world) && fv_v3_isfinite(in->eye[1].pos_world);
}

fv_result fv_renderer_draw(fv_renderer *r, const fv_frame_input *in)
{
    if (!r || !in) return FV_ERR_INVALID_ARG;
    if (!r->scene_loaded) {
        FV_ERROR(MOD, "draw before a scene was loaded");
        return FV_ERR_STATE;
    }
    if (!frame_input_ok(in)) {
        FV_ERROR(MOD, "frame %llu: non-finite view or projection matrix", (unsigned long long)in->frame_id);
        return FV_ERR_RANGE;
    }
    uint32_t slot = r->next_slot;
    frame_slot *s = &r->slots[slot];
    FV_TRY(retire(r, slot)); /* the GPU is done with this slot's command buffer, upload data and queries */
    FV_VK_CHECK(vkResetFences(r->vk->device, 1, &s->fence));
    FV_VK_CHECK(vkResetCommandPool(r->vk->device, s->pool, 0));
    write_frame_data(r, s, in);
    FV_TRY(fv_vk_buffer_flush(r->vk, &s->upload));

    VkCommandBuffer cmd = s->cmd;
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    FV_VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
    fv_vk_timer_reset(&r->timer, cmd, slot);

    int t = fv_vk_timer_begin(&r->timer, cmd, slot, "gbuffer");
    fv_gbuffer_inputs gi = {.slot = slot, .draws = r->draws, .draw_count = r->draw_count};
    fv_gbuffer_record(&r->gb, cmd, &gi);
    fv_vk_timer_end(&r->timer, cmd, slot, t);

    t = fv_vk_timer_begin(&r->timer, cmd, slot, "shade");
    fv_shade_inputs si = {.slot = slot, .mode = FV_SHADE_MODE_ALL};
    fv_shade_record(&r->shade, cmd, &si);
    fv_vk_timer_end(&r->timer, cmd, slot, t);

    t = fv_vk_timer_begin(&r->timer, cmd, slot, "present");
    fv_present_record(&r->present, cmd);
    fv_vk_timer_end(&r->timer, cmd, slot, t);

    FV_VK_CHECK(vkEndCommandBuffer(cmd));
    VkSubmitInfo sub = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &cmd};
    FV_VK_CHECK(vkQueueSubmit(r->vk->queue, 1, &sub, s->fence));
    s->pending = true;
    s->frame_id = in->frame_id;
    s->seq = ++r->submitted;
    s->pixels_shaded = fv_shade_pixels_all(&r->shade);
    r->have_frame = true;
    r->last_slot = slot;
    r->next_slot = (slot + 1) % r->slot_count;
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

/* ---- readback and sparse shading ----------------------------------------------------------------------------- */

fv_result fv_renderer_read_rgba8(fv_renderer *r, bool sbs, int eye, uint8_t *out, size_t out_size)
{
    if (!r || !out) return FV_ERR_INVALID_ARG;
    if (!r->have_frame) {
        FV_ERROR(MOD, "read_rgba8 before any frame was drawn");
        return FV_ERR_STATE;
    }
    FV_TRY(fv_renderer_finish(r));
    return fv_present_read_rgba8(&r->present, sbs, eye, out, out_size);
}

fv_result fv_renderer_read_linear(fv_renderer *r, int eye, float *out_rgba, size_t out_floats)
{
    if (!r || !out_rgba || eye < 0 || eye > 1) return FV_ERR_INVALID_ARG;
    if (!r->have_frame) {
        FV_ERROR(MOD, "read_linear before any frame was drawn");
        return FV_ERR_STATE;
    }
    size_t n = (size_t)r->desc.eye_width * r->desc.eye_height * 4;
    if (out_floats < n) {
        FV_ERROR(MOD, "read_linear needs %zu floats, got %zu", n, out_floats);
        return FV_ERR_INVALID_ARG;
    }
    FV_TRY(fv_renderer_finish(r));
    return fv_vk_read_image(r->vk, &r->shade.color, (uint32_t)eye, VK_IMAGE_LAYOUT_GENERAL,
                            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, out_rgba,
                            out_floats * sizeof(float), 0, (size_t)r->desc.eye_width * 16);
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
    if (!r->have_frame) {
        FV_ERROR(MOD, "read_motion before any frame was drawn");
        return FV_ERR_STATE;
    }
    size_t n = (size_t)r->desc.eye_width * r->desc.eye_height * 2;
    if (out_floats < n) {
        FV_ERROR(MOD, "read_motion needs %zu floats, got %zu", n, out_floats);
        return FV_ERR_INVALID_ARG;
    }
    uint16_t *half = malloc(n * sizeof *half);
    if (!half) return FV_ERR_NO_MEMORY;
    fv_result res = fv_renderer_finish(r);
    /* Written by the G-buffer pass (colour attachment) and read by shading (compute): the copy's layout change
     * waits for both (read-after-write and write-after-read). */
    if (res == FV_OK)
        res = fv_vk_read_image(r->vk, &r->gb.motion, (uint32_t)eye, FV_GBUFFER_COLOR_LAYOUT,
                               VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                               VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, half, n * sizeof *half, 0,
                               (size_t)r->desc.eye_width * 2 * sizeof *half);
    if (res == FV_OK)
        for (size_t i = 0; i < n; i++) out_rg[i] = half_to_float(half[i]);
    free(half);
    return res;
}

fv_result fv_renderer_shade_pixels(fv_renderer *r, const uint32_t *packed, uint32_t count, const float *clear_rgba)
{
    if (!r || (!packed && count)) return FV_ERR_INVALID_ARG;
    if (!r->have_frame) {
        FV_ERROR(MOD, "shade_pixels before any frame was drawn");
        return FV_ERR_STATE;
    }
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
    VkDeviceSize list_size = FV_SHADE_LIST_HEADER_BYTES + (VkDeviceSize)(count ? count : 1) * 4;
    fv_result res = fv_vk_buffer_create(vk, list_size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, FV_VK_MEM_UPLOAD,
                                        "shade pixel list", &list);
    if (res == FV_OK)
        res = fv_vk_buffer_create(vk, sizeof(VkDispatchIndirectCommand), VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                                  FV_VK_MEM_UPLOAD, "shade list dispatch", &indirect);
    if (res != FV_OK) goto done;
    uint32_t header[4] = {count, 0, 0, 0};
    memcpy(list.mapped, header, sizeof header);
    if (count) memcpy((uint8_t *)list.mapped + FV_SHADE_LIST_HEADER_BYTES, packed, (size_t)count * 4);
    VkDispatchIndirectCommand args = fv_shade_list_dispatch(count);
    memcpy(indirect.mapped, &args, sizeof args);
    if ((res = fv_vk_buffer_flush(vk, &list)) != FV_OK || (res = fv_vk_buffer_flush(vk, &indirect)) != FV_OK) goto done;

    uint32_t slot = r->last_slot; /* its frame block and lights describe the frame being re-shaded */
    fv_shade_bind_list(&r->shade, slot, list.buffer, 0, VK_WHOLE_SIZE);
    VkCommandBuffer cmd;
    res = fv_vk_oneshot_begin(vk, "shade pixel list", &cmd);
    if (res != FV_OK) goto unbind;
    if (clear_rgba) {
        /* The previous present pass read the colour image: wait for it before clearing (write-after-read). */
        VkImageMemoryBarrier b = {
            .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
            .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
            .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
            .oldLayout = VK_IMAGE_LAYOUT_GENERAL,
            .newLayout = VK_IMAGE_LAYOUT_GENERAL,
            .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
            .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
            .image = r->shade.color.image,
            .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 2},
        };
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0, NULL, 1, &b);
        VkClearColorValue cv = {.float32 = {clear_rgba[0], clear_rgba[1], clear_rgba[2], clear_rgba[3]}};
        VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 2};
        vkCmdClearColorImage(cmd, r->shade.color.image, VK_IMAGE_LAYOUT_GENERAL, &cv, 1, &range);
    }
    fv_shade_inputs si = {.slot = slot, .mode = FV_SHADE_MODE_LIST, .indirect = indirect.buffer};
    fv_shade_record(&r->shade, cmd, &si);
    fv_present_record(&r->present, cmd);
    res = fv_vk_oneshot_end(vk, cmd);
unbind:
    fv_shade_bind_list(&r->shade, slot, VK_NULL_HANDLE, 0, 0);
done:
    fv_vk_buffer_destroy(vk, &indirect);
    fv_vk_buffer_destroy(vk, &list);
    if (res == FV_OK) r->stats.pixels_shaded = count;
    return res;
}

/* ---- small queries ------------------------------------------------------------------------------------------- */

uint32_t fv_renderer_validation_messages(const fv_renderer *r) { return r ? fv_vk_validation_messages(r->vk) : 0; }

const char *fv_renderer_device_name(const fv_renderer *r) { return r && r->vk ? r->vk->info.name : "(none)"; }

void fv_renderer_size(const fv_renderer *r, uint32_t *out_width, uint32_t *out_height)
{
    if (out_width) *out_width = r ? r->desc.eye_width : 0;
    if (out_height) *out_height = r ? r->desc.eye_height : 0;
}
