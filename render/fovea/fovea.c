/* @brief The foveation passes (see fovea.h). */
#include "fovea.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fovea_comp.spv.h"
#include "fovea_interface.h"
#include "reconstruct_comp.spv.h"

#define MOD "fovea"

_Static_assert(sizeof(struct fv_fovea_push) == 48, "fv_fovea_push layout");
_Static_assert(sizeof(struct fv_recon_push) == 16, "fv_recon_push layout");
_Static_assert(FV_FOVEA_TILE_SIZE <= FV_FOVEA_SCAN_SIZE, "the scan's shared array holds a tile");
_Static_assert(FV_SCENE_SET == 0 && FV_FOVEA_SET == 1 && FV_RECON_SET == 1, "the foveation passes' set order");

static const VkPipelineStageFlags CS = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
static const VkAccessFlags RW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;

/* ---- plans ---------------------------------------------------------------------------------------------------- */

uint32_t fv_fovea_jfa_steps(uint32_t block, uint32_t *out_steps, uint32_t cap)
{
    uint32_t n = 0;
    if (n < cap) out_steps[n++] = 1;
    for (uint32_t k = block; k >= 1 && n < cap; k = (k + 1) / 2) {
        out_steps[n++] = k;
        if (k == 1) break;
    }
    return n;
}

static void fovea_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    const fv_quality_fovea *f = &ctx->quality->fovea;
    out->enabled = f->enabled;
    if (!f->enabled) {
        snprintf(out->reason, sizeof out->reason, "off — fovea.enabled is false");
        return;
    }
    snprintf(out->reason, sizeof out->reason,
             "sampling map from the predicted gaze (MAR %g°/°, ξ %g, %ux%u blocks), compaction, nearest-sample "
             "reconstruction",
             (double)f->mar_slope, (double)f->min_prob, f->block, f->block);
}

static void recon_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    const fv_quality_fovea *f = &ctx->quality->fovea;
    out->enabled = f->enabled;
    if (!f->enabled) {
        snprintf(out->reason, sizeof out->reason, "off — fovea.enabled is false");
        return;
    }
    uint32_t steps[8], n = fv_fovea_jfa_steps(f->block, steps, 8);
    char list[48] = "";
    size_t at = 0;
    for (uint32_t i = 0; i < n && at < sizeof list; i++)
        at += (size_t)snprintf(list + at, sizeof list - at, "%s%u", i ? ", " : "", steps[i]);
    snprintf(out->reason, sizeof out->reason,
             "unshaded pixels take their nearest sample's colour (nearest; 1+JFA, steps %s px)", list);
}

/* ---- "fovea" ---------------------------------------------------------------------------------------------------- */

enum { STAGE_MAP = 0, STAGE_SCAN = 1, STAGE_SCATTER = 2 };

typedef struct fovea {
    fv_vk *vk;
    uint32_t width, height, slots;
    fv_vk_compute cs;
    fv_images *images;
    fv_image_id prob, mask; /* FV_IMAGE_MAX until made */
    fv_vk_buffer sums;
    struct fv_fovea_push pc;
} fovea;

static void fovea_fini(void *state)
{
    fovea *fv = state;
    if (!fv) return;
    fv_vk_compute_fini(fv->vk, &fv->cs);
    fv_vk_buffer_destroy(fv->vk, &fv->sums);
    /* the scratch images go with the pass (a plan that turns it on again makes new ones); the GPU is idle */
    if (fv->prob != FV_IMAGE_MAX) fv_images_release(fv->images, fv->prob);
    if (fv->mask != FV_IMAGE_MAX) fv_images_release(fv->images, fv->mask);
    free(fv);
}

static fv_result scratch(fv_images *im, const char *name, VkFormat format, fv_image_id *out)
{
    fv_vk_image_desc d = {.layers = 2, .format = format,
                          .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, .name = name};
    return fv_images_scratch(im, &d, out);
}

static fv_result fovea_init(const fv_pass_env *env, void **out_state)
{
    fovea *fv = calloc(1, sizeof *fv);
    if (!fv) return FV_ERR_NO_MEMORY;
    fv->vk = env->vk;
    fv->width = env->width;
    fv->height = env->height;
    fv->slots = env->slots;
    fv->images = env->images;
    fv->prob = fv->mask = FV_IMAGE_MAX;
    struct fv_fovea_push *pc = &fv->pc;
    pc->tiles_x = (env->width + FV_FOVEA_TILE - 1) / FV_FOVEA_TILE;
    pc->tiles_y = (env->height + FV_FOVEA_TILE - 1) / FV_FOVEA_TILE;
    pc->tile_count = pc->tiles_x * pc->tiles_y * 2u;
    pc->tiles_per_stripe = (pc->tile_count + FV_FOVEA_STRIPES - 1) / FV_FOVEA_STRIPES;
    pc->entries = pc->tiles_per_stripe * FV_FOVEA_STRIPES;
    uint32_t max_x = env->vk->props.limits.maxComputeWorkGroupCount[0];
    pc->groups_x = pc->entries < max_x ? pc->entries : max_x;
    fv_result res = scratch(env->images, "fovea prob", VK_FORMAT_R32_SFLOAT, &fv->prob);
    if (res == FV_OK) res = scratch(env->images, "fovea mask", VK_FORMAT_R32_UINT, &fv->mask);
    if (res == FV_OK) res = fv_frame_samples_reserve(env->samples);
    if (res == FV_OK)
        res = fv_vk_buffer_create(env->vk, (VkDeviceSize)pc->entries * 4u, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                  FV_VK_MEM_DEVICE, "fovea tile sums", &fv->sums);
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorSetLayoutBinding b[FV_FOVEA_BINDING_COUNT] = {
        {FV_FOVEA_BINDING_PROB, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        {FV_FOVEA_BINDING_MASK, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        {FV_FOVEA_BINDING_SUMS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
        {FV_FOVEA_BINDING_LIST, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
        {FV_FOVEA_BINDING_INDIRECT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
    };
    /* constant 0: the stage, constant 1: the workgroup size */
    const uint32_t spec[3][2] = {{FV_FOVEA_STAGE_MAP, FV_FOVEA_TILE_SIZE},
                                 {FV_FOVEA_STAGE_SCAN, FV_FOVEA_SCAN_SIZE},
                                 {FV_FOVEA_STAGE_SCATTER, FV_FOVEA_TILE_SIZE}};
    VkDescriptorSetLayout shared[1] = {env->scene->set_layout};
    fv_vk_compute_desc cd = {.name = "fovea", .code = fv_spv_fovea_comp, .code_size = sizeof fv_spv_fovea_comp,
                             .shared_sets = shared, .shared_set_count = 1, .bindings = b,
                             .binding_count = FV_FOVEA_BINDING_COUNT, .set_count = env->slots,
                             .push_bytes = sizeof(struct fv_fovea_push), .spec = &spec[0][0], .spec_count = 2,
                             .variant_count = 3};
    if (res == FV_OK) res = fv_vk_compute_init(env->vk, &cd, &fv->cs);
    for (uint32_t i = 0; res == FV_OK && i < env->slots; i++) {
        VkDescriptorSet set = fv->cs.sets[i];
        fv_vk_write_image(env->vk, set, FV_FOVEA_BINDING_PROB, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                          fv_images_image(env->images, fv->prob)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_image(env->vk, set, FV_FOVEA_BINDING_MASK, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                          fv_images_image(env->images, fv->mask)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_buffer(env->vk, set, FV_FOVEA_BINDING_SUMS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, fv->sums.buffer, 0,
                           VK_WHOLE_SIZE);
        fv_vk_write_buffer(env->vk, set, FV_FOVEA_BINDING_LIST, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                           env->samples->list[i].buffer, 0, VK_WHOLE_SIZE);
        fv_vk_write_buffer(env->vk, set, FV_FOVEA_BINDING_INDIRECT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                           env->samples->indirect[i].buffer, 0, VK_WHOLE_SIZE);
    }
    if (res != FV_OK) {
        FV_ERROR(MOD, "foveation pass could not be created: %s", fv_result_str(res));
        fovea_fini(fv);
        return res;
    }
    *out_state = fv;
    return FV_OK;
}

/* Every stage's pipeline uses both images and all buffers statically: each dispatch is declared as reading and
 * writing them, so each waits for the one before (the table inserts the image barriers; buffers get this one). */
static void buffers_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags src_access,
                            VkPipelineStageFlags dst, VkAccessFlags dst_access)
{
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = src_access,
                          .dstAccessMask = dst_access};
    vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &mb, 0, NULL, 0, NULL);
}

static void fovea_stage(fovea *fv, const fv_pass_frame *f, uint32_t stage, uint32_t gx, uint32_t gy)
{
    VkCommandBuffer cmd = f->cmd;
    fv_images_use(f->images, cmd, fv->prob, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    fv_images_use(f->images, cmd, fv->mask, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    fv_vk_compute_bind(&fv->cs, cmd, stage, &f->scene_set, 1, f->slot, &fv->pc);
    vkCmdDispatch(cmd, gx, gy, 1);
    f->counters->dispatches++;
}

static void fovea_record(void *state, const fv_pass_frame *f)
{
    fovea *fv = state;
    VkCommandBuffer cmd = f->cmd;
    if (!f->samples) return; /* only whole frames make a sample list */
    const fv_quality_fovea *q = &f->input->quality.fovea;
    fv->pc.block = q->block;
    fv->pc.flags = q->uncertainty ? FV_FOVEA_FLAG_UNCERTAINTY : 0u;
    fv->pc.mar_slope = q->mar_slope;
    fv->pc.mar_w0_deg = q->mar_w0_deg;
    fv->pc.min_prob = q->min_prob;
    fv_vk_label_begin(fv->vk, cmd, "fovea (sampling map, compaction)");
    /* The previous frame's shading read a sample list (another slot's, but the tile sums are shared): its reads
     * and this pass's earlier writes come before this frame's writes. */
    buffers_barrier(cmd, CS | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                    RW | VK_ACCESS_INDIRECT_COMMAND_READ_BIT, CS, RW);
    uint32_t gy = (fv->pc.entries + fv->pc.groups_x - 1) / fv->pc.groups_x;
    fovea_stage(fv, f, STAGE_MAP, fv->pc.groups_x, gy);
    buffers_barrier(cmd, CS, RW, CS, RW); /* tile counts -> the scan */
    fovea_stage(fv, f, STAGE_SCAN, 1, 1);
    buffers_barrier(cmd, CS, RW, CS, RW); /* tile offsets -> the scatter */
    fovea_stage(fv, f, STAGE_SCATTER, fv->pc.groups_x, gy);
    /* The list, its count and its dispatch arguments -> the shade pass's indirect dispatch and reads, and the
     * renderer's read of the count on the host after the fence. */
    buffers_barrier(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT,
                    CS | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                    VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_HOST_READ_BIT);
    f->samples->active = true;
    fv_vk_label_end(fv->vk, cmd);
}

static uint32_t fovea_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    fovea *fv = state;
    if (cap < 1) return 0;
    memset(out, 0, sizeof *out);
    snprintf(out[0].key, sizeof out[0].key, "block_mar_slope_min_prob");
    out[0].value[0] = fv->pc.block;
    out[0].value[1] = fv->pc.mar_slope;
    out[0].value[2] = fv->pc.min_prob;
    out[0].count = 3;
    return 1;
}

const fv_pass fv_fovea_pass = {
    .id = "fovea",
    .plan = fovea_plan,
    .init = fovea_init,
    .record = fovea_record,
    .fini = fovea_fini,
    .details = fovea_details,
};

/* ---- "reconstruct" ------------------------------------------------------------------------------------------- */

enum { RSTAGE_INIT = 0, RSTAGE_STEP = 1, RSTAGE_RESOLVE = 2 };

typedef struct recon {
    fv_vk *vk;
    uint32_t width, height;
    fv_vk_compute cs;
    fv_images *images;
    fv_image_id mask, seeds[2]; /* seeds: FV_IMAGE_MAX until made (the mask is the fovea pass's) */
    uint32_t last_steps, last_final;
} recon;

static void recon_fini(void *state)
{
    recon *rc = state;
    if (!rc) return;
    fv_vk_compute_fini(rc->vk, &rc->cs);
    for (int i = 0; i < 2; i++)
        if (rc->seeds[i] != FV_IMAGE_MAX) fv_images_release(rc->images, rc->seeds[i]);
    free(rc);
}

static fv_result recon_init(const fv_pass_env *env, void **out_state)
{
    recon *rc = calloc(1, sizeof *rc);
    if (!rc) return FV_ERR_NO_MEMORY;
    rc->vk = env->vk;
    rc->width = env->width;
    rc->height = env->height;
    rc->images = env->images;
    rc->seeds[0] = rc->seeds[1] = FV_IMAGE_MAX;
    const fv_vk_image *color;
    fv_result res = fv_images_find(env->images, "fovea mask", &rc->mask); /* the fovea pass (earlier) made it */
    if (res == FV_OK) res = scratch(env->images, "fovea seeds a", VK_FORMAT_R32_UINT, &rc->seeds[0]);
    if (res == FV_OK) res = scratch(env->images, "fovea seeds b", VK_FORMAT_R32_UINT, &rc->seeds[1]);
    if (res == FV_OK) res = fv_images_get(env->images, FV_IMAGE_COLOR, &color);
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorType si = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    VkDescriptorSetLayoutBinding b[FV_RECON_BINDING_COUNT] = {
        {FV_RECON_BINDING_MASK, si, 1, cs, NULL},
        {FV_RECON_BINDING_SEEDS_A, si, 1, cs, NULL},
        {FV_RECON_BINDING_SEEDS_B, si, 1, cs, NULL},
        {FV_RECON_BINDING_COLOR, si, 1, cs, NULL},
    };
    const uint32_t spec[3] = {FV_RECON_STAGE_INIT, FV_RECON_STAGE_STEP, FV_RECON_STAGE_RESOLVE};
    VkDescriptorSetLayout shared[1] = {env->scene->set_layout};
    fv_vk_compute_desc cd = {.name = "reconstruct", .code = fv_spv_reconstruct_comp,
                             .code_size = sizeof fv_spv_reconstruct_comp, .shared_sets = shared,
                             .shared_set_count = 1, .bindings = b, .binding_count = FV_RECON_BINDING_COUNT,
                             .set_count = 1, .push_bytes = sizeof(struct fv_recon_push), .spec = spec,
                             .spec_count = 1, .variant_count = 3};
    if (res == FV_OK) res = fv_vk_compute_init(env->vk, &cd, &rc->cs);
    if (res != FV_OK) {
        FV_ERROR(MOD, "reconstruction pass could not be created: %s", fv_result_str(res));
        recon_fini(rc);
        return res;
    }
    VkDescriptorSet set = rc->cs.sets[0];
    fv_vk_write_image(env->vk, set, FV_RECON_BINDING_MASK, si, fv_images_image(env->images, rc->mask)->view,
                      VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    fv_vk_write_image(env->vk, set, FV_RECON_BINDING_SEEDS_A, si, fv_images_image(env->images, rc->seeds[0])->view,
                      VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    fv_vk_write_image(env->vk, set, FV_RECON_BINDING_SEEDS_B, si, fv_images_image(env->images, rc->seeds[1])->view,
                      VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    fv_vk_write_image(env->vk, set, FV_RECON_BINDING_COLOR, si, color->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    *out_state = rc;
    return FV_OK;
}

static void recon_stage(recon *rc, const fv_pass_frame *f, uint32_t stage, uint32_t step, uint32_t src)
{
    VkCommandBuffer cmd = f->cmd;
    /* Every stage's pipeline uses all four images statically: declare them all, so each dispatch waits for the
     * one before (and the first for the shading that wrote the colour and the fovea pass that wrote the mask). */
    fv_images_use(f->images, cmd, rc->mask,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, VK_ACCESS_SHADER_READ_BIT});
    fv_images_use(f->images, cmd, rc->seeds[0], (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    fv_images_use(f->images, cmd, rc->seeds[1], (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    fv_images_use(f->images, cmd, FV_IMAGE_COLOR, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    struct fv_recon_push pc = {.step = step, .src = src};
    fv_vk_compute_bind(&rc->cs, cmd, stage, &f->scene_set, 1, 0, &pc);
    vkCmdDispatch(cmd, (rc->width + FV_RECON_GROUP - 1) / FV_RECON_GROUP,
                  (rc->height + FV_RECON_GROUP - 1) / FV_RECON_GROUP, 2);
    f->counters->dispatches++;
}

static void recon_record(void *state, const fv_pass_frame *f)
{
    recon *rc = state;
    if (!f->samples) return;
    fv_vk_label_begin(rc->vk, f->cmd, "reconstruct (nearest sample, 1+JFA)");
    uint32_t steps[8], n = fv_fovea_jfa_steps(f->input->quality.fovea.block, steps, 8), src = 0;
    recon_stage(rc, f, RSTAGE_INIT, 0, 0);
    for (uint32_t i = 0; i < n; i++, src ^= 1u) recon_stage(rc, f, RSTAGE_STEP, steps[i], src);
    recon_stage(rc, f, RSTAGE_RESOLVE, 0, src);
    rc->last_steps = n;
    rc->last_final = src;
    fv_vk_label_end(rc->vk, f->cmd);
}

static uint32_t recon_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    recon *rc = state;
    if (cap < 1) return 0;
    memset(out, 0, sizeof *out);
    snprintf(out[0].key, sizeof out[0].key, "jfa_steps_final_seeds");
    out[0].value[0] = rc->last_steps;
    out[0].value[1] = rc->last_final; /* 0: "fovea seeds a", 1: "fovea seeds b" */
    out[0].count = 2;
    return 1;
}

const fv_pass fv_reconstruct_pass = {
    .id = "reconstruct",
    .plan = recon_plan,
    .init = recon_init,
    .record = recon_record,
    .fini = recon_fini,
    .details = recon_details,
};
