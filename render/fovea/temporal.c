/* @brief The "temporal" pass of foveation (see fovea.h, temporal.comp): the previous frame's known pixels
 * reprojected into this one, blended into the shaded pixels and reused for unshaded ones before reconstruction. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fovea.h"
#include "fovea_interface.h"
#include "temporal_comp.spv.h"

#define MOD "fovea"

_Static_assert(sizeof(struct fv_temporal_push) == 64, "fv_temporal_push layout");
_Static_assert(FV_TEMPORAL_AGE_MAX == (1u << FV_TEMPORAL_AGE_BITS) - 1u, "the age fits its bits");

static const VkPipelineStageFlags CS = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
static const VkAccessFlags RW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;

typedef struct temporal {
    fv_vk *vk;
    uint32_t width, height, block, slots;
    fv_vk_compute cs;
    fv_image_id mask, blocks;
    VkSampler nearest;
    fv_vk_buffer stats; /* 4 words per slot, host-read after the slot's fence */
    bool recorded[FV_MAX_FRAMES_IN_FLIGHT];
    /* the previous recorded frame: its eyes and the scene it showed */
    bool have_prev;
    fv_vec3 prev_eye[2];
    fv_mat4 prev_view[2];
    uint64_t prev_load;
    uint64_t resets;         /* history resets: first frame, scene load, head jump */
    double last_hits[2], last_reused[2]; /* of the newest retired frame, per eye (fractions) */
    bool have_last;
    uint32_t max_age;
} temporal;

bool fv_fovea_head_jumped(const fv_mat4 *prev_view, const fv_vec3 *prev_eye, const fv_mat4 *view,
                          const fv_vec3 *eye)
{
    double dx = (double)eye->x - prev_eye->x, dy = (double)eye->y - prev_eye->y, dz = (double)eye->z - prev_eye->z;
    double moved = sqrt(dx * dx + dy * dy + dz * dz);
    /* the rotation between the views: trace of R_cur R_prev^T = sum over i, j of R_cur[j][i] R_prev[j][i] */
    double tr = 0;
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++) tr += (double)view->m[c][r] * prev_view->m[c][r];
    double cosang = (tr - 1.0) / 2.0;
    cosang = cosang > 1.0 ? 1.0 : cosang < -1.0 ? -1.0 : cosang;
    double deg = acos(cosang) * 180.0 / FV_PI;
    /* NaN anywhere counts as a jump: nothing about the previous frame can be trusted */
    return !(moved <= FV_TEMPORAL_JUMP_M) || !(deg <= FV_TEMPORAL_JUMP_DEG);
}

static void temporal_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    const fv_quality_fovea *f = &ctx->quality->fovea;
    out->enabled = f->enabled && f->temporal > 0;
    out->variant = f->block;
    if (!f->enabled) snprintf(out->reason, sizeof out->reason, "off — fovea.enabled is false");
    else if (!f->temporal) snprintf(out->reason, sizeof out->reason, "off — fovea.temporal is 0");
    else
        snprintf(out->reason, sizeof out->reason,
                 "previous frame reprojected by the motion vectors (depth test %g%% + slope): blended into shaded "
                 "pixels, reused for unshaded ones up to %u frames",
                 100.0 * FV_TEMPORAL_DEPTH_EPS, f->temporal);
}

static void temporal_fini(void *state)
{
    temporal *t = state;
    if (!t) return;
    fv_vk_compute_fini(t->vk, &t->cs);
    fv_vk_buffer_destroy(t->vk, &t->stats);
    if (t->nearest) vkDestroySampler(t->vk->device, t->nearest, NULL);
    free(t);
}

static fv_result temporal_init(const fv_pass_env *env, void **out_state)
{
    temporal *t = calloc(1, sizeof *t);
    if (!t) return FV_ERR_NO_MEMORY;
    t->vk = env->vk;
    t->width = env->width;
    t->height = env->height;
    t->slots = env->slots;
    t->block = env->plan->variant;
    const fv_vk_image *img;
    fv_result res = t->block >= 2 && t->block <= FV_FOVEA_BLOCK_MAX ? FV_OK : FV_ERR_INVALID_ARG;
    if (res == FV_OK) res = fv_images_find(env->images, "fovea mask", &t->mask); /* the fovea pass (earlier) */
    if (res == FV_OK) res = fv_images_find(env->images, "fovea blocks", &t->blocks);
    if (res == FV_OK) res = fv_images_get_gbuffer(env->images);
    if (res == FV_OK) res = fv_images_get(env->images, FV_IMAGE_SURFACE, &img);
    if (res == FV_OK) res = fv_images_get(env->images, FV_IMAGE_COLOR, &img);
    if (res == FV_OK) res = fv_images_get(env->images, FV_IMAGE_HISTORY, &img);
    if (res == FV_OK) res = fv_vk_sampler_create(env->vk, false, false, "temporal nearest sampler", &t->nearest);
    if (res == FV_OK)
        res = fv_vk_buffer_create(env->vk, (VkDeviceSize)env->slots * 16u,
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                  FV_VK_MEM_READBACK, "fovea temporal stats", &t->stats);
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorType cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, si = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    VkDescriptorSetLayoutBinding b[FV_TEMPORAL_BINDING_COUNT] = {
        {FV_TEMPORAL_BINDING_DEPTH, cis, 1, cs, NULL},
        {FV_TEMPORAL_BINDING_DEPTH + 1, cis, 1, cs, NULL},
        {FV_TEMPORAL_BINDING_DEPTH + 2, cis, 1, cs, NULL},
        {FV_TEMPORAL_BINDING_DEPTH + 3, cis, 1, cs, NULL},
        {FV_TEMPORAL_BINDING_MOTION, si, 1, cs, NULL},
        {FV_TEMPORAL_BINDING_MASK, si, 1, cs, NULL},
        {FV_TEMPORAL_BINDING_BLOCKS, si, 1, cs, NULL},
        {FV_TEMPORAL_BINDING_COLOR, si, 1, cs, NULL},
        {FV_TEMPORAL_BINDING_PREV, si, 1, cs, NULL},
        {FV_TEMPORAL_BINDING_STATS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
    };
    VkDescriptorSetLayout shared[1] = {env->scene->set_layout};
    fv_vk_compute_desc cd = {.name = "temporal", .code = fv_spv_temporal_comp, .code_size = sizeof fv_spv_temporal_comp,
                             .shared_sets = shared, .shared_set_count = 1, .bindings = b,
                             .binding_count = FV_TEMPORAL_BINDING_COUNT, .set_count = 1,
                             .push_bytes = sizeof(struct fv_temporal_push)};
    if (res == FV_OK) res = fv_vk_compute_init(env->vk, &cd, &t->cs);
    if (res != FV_OK) {
        FV_ERROR(MOD, "temporal reuse pass could not be created: %s", fv_result_str(res));
        temporal_fini(t);
        return res;
    }
    {
        VkDescriptorSet set = t->cs.sets[0];
        fv_images_bind_gbuffer(env->images, set, FV_TEMPORAL_BINDING_DEPTH, t->nearest);
        fv_vk_write_image(env->vk, set, FV_TEMPORAL_BINDING_MOTION, si,
                          fv_images_image(env->images, FV_IMAGE_SURFACE)->view, VK_NULL_HANDLE,
                          VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_image(env->vk, set, FV_TEMPORAL_BINDING_MASK, si, fv_images_image(env->images, t->mask)->view,
                          VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_image(env->vk, set, FV_TEMPORAL_BINDING_BLOCKS, si, fv_images_image(env->images, t->blocks)->view,
                          VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_image(env->vk, set, FV_TEMPORAL_BINDING_COLOR, si,
                          fv_images_image(env->images, FV_IMAGE_COLOR)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_image(env->vk, set, FV_TEMPORAL_BINDING_PREV, si,
                          fv_images_image(env->images, FV_IMAGE_HISTORY)->view, VK_NULL_HANDLE,
                          VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_buffer(env->vk, set, FV_TEMPORAL_BINDING_STATS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                           t->stats.buffer, 0, VK_WHOLE_SIZE);
    }
    *out_state = t;
    return FV_OK;
}

/* The slot's frame is done: its hit and reuse counts are the newest retired ones. */
static void temporal_prepare(void *state, const fv_pass_frame *f)
{
    temporal *t = state;
    if (f->slot >= t->slots || !t->recorded[f->slot]) return;
    if (fv_vk_buffer_invalidate(t->vk, &t->stats) != FV_OK) return;
    const uint32_t *s = (const uint32_t *)t->stats.mapped + 4u * f->slot;
    double per_eye = (double)t->width * t->height;
    for (int e = 0; e < 2; e++) {
        t->last_hits[e] = s[e] / per_eye;
        t->last_reused[e] = s[2 + e] / per_eye;
    }
    t->have_last = true;
}

static void dispatch(temporal *t, const fv_pass_frame *f, uint32_t set, const struct fv_temporal_push *pc)
{
    fv_vk_compute_bind(&t->cs, f->cmd, 0, &f->scene_set, 1, set, pc);
    vkCmdDispatch(f->cmd, (t->width + FV_TEMPORAL_GROUP - 1) / FV_TEMPORAL_GROUP,
                  (t->height + FV_TEMPORAL_GROUP - 1) / FV_TEMPORAL_GROUP, 2);
    f->counters->dispatches++;
}

static void temporal_record(void *state, const fv_pass_frame *f)
{
    temporal *t = state;
    VkCommandBuffer cmd = f->cmd;
    if (!f->samples || f->slot >= t->slots) return; /* whole frames only */
    const fv_frame_input *in = f->input;
    struct fv_temporal_push pc = {.max_age = in->quality.fovea.temporal, .stats_base = 4u * f->slot,
                                  .block = t->block, .block_words = (t->block * t->block + 31u) / 32u};
    if (pc.max_age > FV_TEMPORAL_AGE_MAX) pc.max_age = FV_TEMPORAL_AGE_MAX;
    t->max_age = pc.max_age;
    /* the previous frame's history counts unless this is the first frame, another scene, or the head jumped */
    bool valid = t->have_prev;
    const char *why = "first frame";
    if (valid && t->prev_load != f->scene->load_count) valid = false, why = "scene loaded";
    for (int e = 0; e < 2 && valid; e++)
        if (fv_fovea_head_jumped(&t->prev_view[e], &t->prev_eye[e], &in->eye[e].view, &in->eye[e].pos_world))
            valid = false, why = "head jump";
    if (!valid) {
        t->resets++;
        if (t->have_prev) FV_INFO(MOD, "frame %llu: temporal history reset (%s)", (unsigned long long)in->frame_id, why);
    }
    pc.flags = valid ? FV_TEMPORAL_FLAG_HISTORY : 0u;
    for (int e = 0; e < 2; e++) {
        fv_vec3 p = t->have_prev ? t->prev_eye[e] : in->eye[e].pos_world;
        pc.prev_eye[e][0] = p.x, pc.prev_eye[e][1] = p.y, pc.prev_eye[e][2] = p.z, pc.prev_eye[e][3] = 1.0f;
    }

    fv_vk_label_begin(t->vk, cmd, "temporal (reprojection)");
    /* this slot's counts start at 0 (the host read them after the fence) */
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = VK_ACCESS_HOST_READ_BIT | RW,
                          .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_HOST_BIT | CS, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, NULL, 0,
                         NULL);
    vkCmdFillBuffer(cmd, t->stats.buffer, 16u * f->slot, 16u, 0u);
    mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    mb.dstAccessMask = RW;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, CS, 0, 1, &mb, 0, NULL, 0, NULL);

    fv_images_use_gbuffer(f->images, cmd, CS);
    fv_images_use(f->images, cmd, FV_IMAGE_SURFACE, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, VK_ACCESS_SHADER_READ_BIT});
    fv_images_use(f->images, cmd, t->mask, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    fv_images_use(f->images, cmd, t->blocks, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    fv_images_use(f->images, cmd, FV_IMAGE_COLOR, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    fv_images_use(f->images, cmd, FV_IMAGE_HISTORY,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, VK_ACCESS_SHADER_READ_BIT});
    dispatch(t, f, 0, &pc);
    /* the counts -> the host after the fence */
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, CS, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, NULL, 0, NULL);
    fv_vk_label_end(t->vk, cmd);

    t->recorded[f->slot] = true;
    t->have_prev = true;
    t->prev_load = f->scene->load_count;
    for (int e = 0; e < 2; e++) {
        t->prev_eye[e] = in->eye[e].pos_world;
        t->prev_view[e] = in->eye[e].view;
    }
}

static uint32_t temporal_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    temporal *t = state;
    uint32_t n = 0;
    if (t->have_last) {
        n = fv_fovea_add_detail(out, n, cap, "cache_hit_fraction", 2, t->last_hits[0], t->last_hits[1], 0);
        n = fv_fovea_add_detail(out, n, cap, "reused_fraction", 2, t->last_reused[0], t->last_reused[1], 0);
    }
    return fv_fovea_add_detail(out, n, cap, "resets_max_age", 2, (double)t->resets, t->max_age, 0);
}

const fv_pass fv_temporal_pass = {
    .id = "temporal",
    .plan = temporal_plan,
    .init = temporal_init,
    .prepare = temporal_prepare,
    .record = temporal_record,
    .fini = temporal_fini,
    .details = temporal_details,
    .needs = FV_PASS_NAMES("fovea mask", "fovea blocks"),
};
