/* @brief The foveation passes (see fovea.h). */
#include "fovea.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "compact_comp.spv.h"
#include "fovea_comp.spv.h"
#include "fovea_interface.h"
#include "reconstruct_comp.spv.h"

#define MOD "fovea"

_Static_assert(sizeof(struct fv_fovea_push) == 32, "fv_fovea_push layout");
_Static_assert(FV_FOVEA_SRGB_TABLE >= FV_FOVEA_BLOCK_MAX * FV_FOVEA_BLOCK_MAX, "the sRGB table follows the ranks");
_Static_assert(FV_KNOB_MIN_fovea_block == 2 && FV_KNOB_MAX_fovea_block == FV_FOVEA_BLOCK_MAX, "fovea.block's range");
_Static_assert(sizeof(struct fv_compact_push) == 32, "fv_compact_push layout");
_Static_assert(sizeof(struct fv_recon_push) == 48, "fv_recon_push layout");
_Static_assert(FV_COMPACT_TILE_SIZE == FV_GPU_LIST_GROUP_SIZE, "masked lists: one list workgroup per tile");
_Static_assert(FV_SCENE_SET == 0 && FV_FOVEA_SET == 1 && FV_COMPACT_SET == 1 && FV_RECON_SET == 1,
               "the foveation passes' set order");
_Static_assert(FV_FOVEA_COMPACTION_TILES == FV_COMPACT_MODE_TILES && FV_FOVEA_COMPACTION_ROWS == FV_COMPACT_MODE_ROWS &&
                   FV_FOVEA_COMPACTION_MASKED == FV_COMPACT_MODE_MASKED,
               "the knob's values are the shader's modes");

static const VkPipelineStageFlags CS = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
static const VkAccessFlags RW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;

static const char *const COMPACTION_NAME[] = {"tiles", "rows", "masked"};

/* ---- shared helpers ------------------------------------------------------------------------------------------- */

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

double fv_fovea_r2(uint32_t x, uint32_t y)
{
    /* as fovea.comp's pattern(): fract(0.5 + x a1 + y a2), in float there */
    float v = 0.5f + (float)x * 0.75487766625f + (float)y * 0.56984029101f;
    return (double)(v - (float)(int)v);
}

void fv_fovea_block_ranks(uint32_t block, uint32_t *out_ranks)
{
    uint32_t n = block * block;
    for (uint32_t i = 0; i < n; i++) {
        double mine = fv_fovea_r2(i % block, i / block);
        uint32_t r = 0;
        for (uint32_t k = 0; k < n; k++) {
            double o = fv_fovea_r2(k % block, k / block);
            r += o < mine || (o == mine && k < i);
        }
        out_ranks[i] = r;
    }
}

/* Every stage's pipeline uses all of its buffers statically: each dispatch is declared as reading and writing
 * them, so each waits for the one before (the image table inserts the image barriers; buffers get this one). */
static void buffers_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags src_access,
                            VkPipelineStageFlags dst, VkAccessFlags dst_access)
{
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = src_access,
                          .dstAccessMask = dst_access};
    vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &mb, 0, NULL, 0, NULL);
}

uint32_t fv_fovea_add_detail(fv_pass_detail *out, uint32_t n, uint32_t cap, const char *key, uint32_t count, double a,
                           double b, double c)
{
    if (n >= cap) return n;
    memset(&out[n], 0, sizeof out[n]);
    snprintf(out[n].key, sizeof out[n].key, "%s", key);
    out[n].value[0] = a;
    out[n].value[1] = b;
    out[n].value[2] = c;
    out[n].count = count;
    return n + 1;
}

static fv_result scratch(fv_images *im, const char *name, VkFormat format, fv_image_id *out)
{
    fv_vk_image_desc d = {.layers = 2, .format = format,
                          .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, .name = name};
    return fv_images_scratch(im, &d, out);
}

static uint32_t block_words(uint32_t block) { return (block * block + 31u) / 32u; }

static const char *compaction_name(uint32_t c) { return c <= FV_FOVEA_COMPACTION_LAST ? COMPACTION_NAME[c] : "?"; }

/* ---- plans ---------------------------------------------------------------------------------------------------- */

/* All three passes take the block as their variant: the sampling map makes its rank table for the block at init,
 * and the passes after it keep views of its images, so they are made again together. */
static bool plan_off(const fv_plan_context *ctx, fv_plan_entry *out)
{
    out->enabled = ctx->quality->fovea.enabled;
    out->variant = ctx->quality->fovea.block;
    if (!out->enabled) snprintf(out->reason, sizeof out->reason, "off — fovea.enabled is false");
    return !out->enabled;
}

static void fovea_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    if (plan_off(ctx, out)) return;
    const fv_quality_fovea *f = &ctx->quality->fovea;
    snprintf(out->reason, sizeof out->reason,
             "sampling map from the predicted gaze (MAR %.4g°/° + %.4g°, ξ %.3g, %ux%u blocks%s%s%s)",
             (double)f->mar_slope, (double)f->mar_w0_deg, (double)f->min_prob, f->block, f->block,
             f->uncertainty ? ", +uncertainty" : "", f->saliency > 0.0f ? ", +saliency" : "", f->dof ? ", +DoF" : "");
}

static void compact_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    if (plan_off(ctx, out)) return;
    const char *how[] = {"8x8 tiles, one atomic per tile for its list offset",
                         "row-wise (CSR) reorder: row counts, a prefix sum over the rows, rows in order",
                         "masked full dispatch: every pixel listed, unsampled ones skipped by the shading"};
    uint32_t c = ctx->quality->fovea.compaction;
    snprintf(out->reason, sizeof out->reason, "the samples as the shading's list (%s: %s)", compaction_name(c),
             c <= FV_FOVEA_COMPACTION_LAST ? how[c] : "?");
}

static void recon_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    if (plan_off(ctx, out)) return;
    const fv_quality_fovea *f = &ctx->quality->fovea;
    uint32_t steps[8], n = fv_fovea_jfa_steps(f->block, steps, 8);
    char list[48] = "";
    size_t at = 0;
    for (uint32_t i = 0; i < n && at < sizeof list; i++)
        at += (size_t)snprintf(list + at, sizeof list - at, "%s%u", i ? ", " : "", steps[i]);
    char vor[80];
    if (f->voronoi == FV_FOVEA_VORONOI_BLOCKS)
        snprintf(vor, sizeof vor, "the exact Voronoi from the neighbouring blocks' samples");
    else
        snprintf(vor, sizeof vor, "the 1+JFA Voronoi, steps %s px", list);
    if (f->recon == FV_FOVEA_RECON_SOFT)
        snprintf(out->reason, sizeof out->reason,
                 "unshaded pixels by an edge-aware Gaussian (G-buffer plane, normal) of the 2x2 nearest blocks' "
                 "known pixels, bilinear over the blocks (soft)");
    else if (f->recon == FV_FOVEA_RECON_IDW)
        snprintf(out->reason, sizeof out->reason,
                 "unshaded pixels by inverse-distance weights of the samples of the neighbouring blocks (idw)");
    else if (f->recon == FV_FOVEA_RECON_SIBSON)
        snprintf(out->reason, sizeof out->reason,
                 "unshaded pixels by discrete Sibson interpolation (%ux%u window) over %s", 2 * f->block + 1,
                 2 * f->block + 1, vor);
    else
        snprintf(out->reason, sizeof out->reason, "unshaded pixels take their nearest sample's colour, by %s", vor);
}

/* ---- "fovea": the sampling map ---------------------------------------------------------------------------------- */

/* The map's variants, made on first use: bit 0 with the G-buffer's reads (fovea.comp USE_GBUFFER), bit 1 with p
 * stored (WRITE_PROB). */
#define MAP_VARIANTS 4u
static const uint32_t MAP_SPEC[MAP_VARIANTS * 2] = {0u, 0u, 1u, 0u, 0u, 1u, 1u, 1u};

typedef struct fovea {
    fv_vk *vk;
    uint32_t width, height, block;
    fv_vk_compute cs;
    fv_images *images;
    fv_image_id prob, mask, blocks; /* FV_IMAGE_MAX until made */
    fv_vk_buffer ranks;
    VkSampler nearest; /* the G-buffer's reads (saliency, DoF) */
    struct fv_fovea_push pc;
    uint32_t variant; /* of the last recorded frame: bit 0 reads the G-buffer (saliency, DoF with a pupil), bit 1
                       * stores p ("fovea prob") */
} fovea;

static void fovea_fini(void *state)
{
    fovea *fv = state;
    if (!fv) return;
    fv_vk_compute_fini(fv->vk, &fv->cs);
    fv_vk_buffer_destroy(fv->vk, &fv->ranks);
    if (fv->nearest) vkDestroySampler(fv->vk->device, fv->nearest, NULL);
    /* the scratch images go with the pass (a plan that turns it on again makes new ones); the GPU is idle */
    if (fv->prob != FV_IMAGE_MAX) fv_images_release(fv->images, fv->prob);
    if (fv->mask != FV_IMAGE_MAX) fv_images_release(fv->images, fv->mask);
    if (fv->blocks != FV_IMAGE_MAX) fv_images_release(fv->images, fv->blocks);
    free(fv);
}

static fv_result fovea_init(const fv_pass_env *env, void **out_state)
{
    fovea *fv = calloc(1, sizeof *fv);
    if (!fv) return FV_ERR_NO_MEMORY;
    fv->vk = env->vk;
    fv->width = env->width;
    fv->height = env->height;
    fv->images = env->images;
    fv->prob = fv->mask = fv->blocks = FV_IMAGE_MAX;
    fv->block = env->plan->variant;
    fv_result res = fv->block >= 2 && fv->block <= FV_FOVEA_BLOCK_MAX ? FV_OK : FV_ERR_INVALID_ARG;
    if (res == FV_OK) res = scratch(env->images, "fovea prob", VK_FORMAT_R32_SFLOAT, &fv->prob);
    if (res == FV_OK) res = scratch(env->images, "fovea mask", VK_FORMAT_R32_UINT, &fv->mask);
    if (res == FV_OK) {
        fv_vk_image_desc d = {.width = (env->width + fv->block - 1) / fv->block * block_words(fv->block),
                              .height = (env->height + fv->block - 1) / fv->block, .layers = 2,
                              .format = VK_FORMAT_R32_UINT,
                              .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                                       VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                              .name = "fovea blocks"};
        res = fv_images_scratch(env->images, &d, &fv->blocks);
    }
    if (res == FV_OK)
        res = fv_vk_buffer_create(env->vk, (VkDeviceSize)(FV_FOVEA_SRGB_TABLE + 256u) * 4u,
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, FV_VK_MEM_UPLOAD, "fovea block ranks",
                                  &fv->ranks);
    if (res == FV_OK) {
        fv_fovea_block_ranks(fv->block, fv->ranks.mapped);
        float *srgb = (float *)fv->ranks.mapped + FV_FOVEA_SRGB_TABLE; /* the IEC 61966-2-1 decode, in double */
        for (int i = 0; i < 256; i++) {
            double c = i / 255.0;
            srgb[i] = (float)(c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
        }
        res = fv_vk_buffer_flush(env->vk, &fv->ranks);
    }
    const fv_vk_image *motion;
    if (res == FV_OK) res = fv_images_get_gbuffer(env->images);
    if (res == FV_OK) res = fv_images_get(env->images, FV_IMAGE_SURFACE, &motion);
    if (res == FV_OK) res = fv_vk_sampler_create(env->vk, false, false, "fovea nearest sampler", &fv->nearest);
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorType cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    VkDescriptorSetLayoutBinding b[FV_FOVEA_BINDING_COUNT] = {
        {FV_FOVEA_BINDING_PROB, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        {FV_FOVEA_BINDING_MASK, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        {FV_FOVEA_BINDING_RANKS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
        {FV_FOVEA_BINDING_BLOCKS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        {FV_FOVEA_BINDING_DEPTH, cis, 1, cs, NULL},
        {FV_FOVEA_BINDING_DEPTH + 1, cis, 1, cs, NULL},
        {FV_FOVEA_BINDING_DEPTH + 2, cis, 1, cs, NULL},
        {FV_FOVEA_BINDING_DEPTH + 3, cis, 1, cs, NULL},
        {FV_FOVEA_BINDING_MOTION, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
    };
    VkDescriptorSetLayout shared[1] = {env->scene->set_layout};
    fv_vk_compute_desc cd = {.name = "fovea", .code = fv_spv_fovea_comp, .code_size = sizeof fv_spv_fovea_comp,
                             .shared_sets = shared, .shared_set_count = 1, .bindings = b,
                             .binding_count = FV_FOVEA_BINDING_COUNT, .set_count = 1,
                             .push_bytes = sizeof(struct fv_fovea_push), .spec = MAP_SPEC, .spec_count = 2,
                             .variant_count = MAP_VARIANTS, .lazy = true};
    if (res == FV_OK) res = fv_vk_compute_init(env->vk, &cd, &fv->cs);
    if (res == FV_OK) {
        VkDescriptorSet set = fv->cs.sets[0];
        fv_vk_write_image(env->vk, set, FV_FOVEA_BINDING_PROB, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                          fv_images_image(env->images, fv->prob)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_image(env->vk, set, FV_FOVEA_BINDING_MASK, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                          fv_images_image(env->images, fv->mask)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_buffer(env->vk, set, FV_FOVEA_BINDING_RANKS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, fv->ranks.buffer,
                           0, VK_WHOLE_SIZE);
        fv_vk_write_image(env->vk, set, FV_FOVEA_BINDING_BLOCKS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                          fv_images_image(env->images, fv->blocks)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_images_bind_gbuffer(env->images, set, FV_FOVEA_BINDING_DEPTH, fv->nearest);
        fv_vk_write_image(env->vk, set, FV_FOVEA_BINDING_MOTION, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, motion->view,
                          VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    }
    if (res != FV_OK) {
        FV_ERROR(MOD, "sampling-map pass could not be created: %s", fv_result_str(res));
        fovea_fini(fv);
        return res;
    }
    *out_state = fv;
    return FV_OK;
}

static void fovea_record(void *state, const fv_pass_frame *f)
{
    fovea *fv = state;
    VkCommandBuffer cmd = f->cmd;
    if (!f->samples) return; /* only whole frames make a sample list */
    const fv_quality_fovea *q = &f->input->quality.fovea;
    /* DoF acts only with a pupil size (the renderer passes 0 for an unknown one: no blur); without it and without
     * saliency the map runs the variant that reads no G-buffer */
    float pupil = f->input->pupil_mm;
    bool dof = q->dof && isfinite(pupil) && pupil > 0.0f && pupil <= FV_GPU_PUPIL_MAX_MM;
    uint32_t flags = (q->uncertainty ? FV_FOVEA_FLAG_UNCERTAINTY : 0u) | (dof ? FV_FOVEA_FLAG_DOF : 0u) |
                     (q->saliency > 0.0f ? FV_FOVEA_FLAG_SALIENCY : 0u);
    /* p is stored only for its readers: the views of foveation and the overlay's foveal boundary */
    fv_debug_view view = f->input->quality.debug_view;
    bool prob = f->input->quality.overlay || view == FV_DEBUG_VIEW_SAMPLES || view == FV_DEBUG_VIEW_PROB ||
                view == FV_DEBUG_VIEW_VORONOI;
    uint32_t variant = (flags & (FV_FOVEA_FLAG_DOF | FV_FOVEA_FLAG_SALIENCY) ? 1u : 0u) | (prob ? 2u : 0u);
    VkPipeline pipe = fv_vk_compute_lazy(fv->vk, &fv->cs, variant);
    if (!pipe) return; /* said once */
    fv->pc = (struct fv_fovea_push){.block = fv->block, .flags = flags, .mar_slope = q->mar_slope,
                                    .mar_w0_deg = q->mar_w0_deg, .min_prob = q->min_prob,
                                    .block_words = block_words(fv->block), .saliency = q->saliency};
    fv_vk_label_begin(fv->vk, cmd, "fovea (sampling map)");
    /* the block masks start empty; the map ORs each sample's bit in */
    fv_images_use(f->images, cmd, fv->blocks,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT});
    VkClearColorValue zero = {.uint32 = {0, 0, 0, 0}};
    VkImageSubresourceRange all = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 2};
    vkCmdClearColorImage(cmd, fv_images_image(f->images, fv->blocks)->image, VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &all);
    fv_images_use(f->images, cmd, fv->blocks, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    /* the previous frame's compaction and debug views read the mask and the probability: the table orders it */
    fv_images_use(f->images, cmd, fv->prob, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, VK_ACCESS_SHADER_WRITE_BIT});
    fv_images_use(f->images, cmd, fv->mask, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, VK_ACCESS_SHADER_WRITE_BIT});
    fv_images_use_gbuffer(f->images, cmd, CS);
    fv_images_use(f->images, cmd, FV_IMAGE_SURFACE, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, VK_ACCESS_SHADER_READ_BIT});
    fv->variant = variant;
    fv_vk_compute_bind_pipeline(&fv->cs, cmd, pipe, &f->scene_set, 1, 0, &fv->pc);
    vkCmdDispatch(cmd, (fv->width + FV_FOVEA_GROUP - 1) / FV_FOVEA_GROUP,
                  (fv->height + FV_FOVEA_GROUP - 1) / FV_FOVEA_GROUP, 2);
    f->counters->dispatches++;
    fv_vk_label_end(fv->vk, cmd);
}

static uint32_t fovea_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    fovea *fv = state;
    uint32_t n = fv_fovea_add_detail(out, 0, cap, "block_mar_slope_min_prob", 3, fv->block, fv->pc.mar_slope,
                                     fv->pc.min_prob);
    n = fv_fovea_add_detail(out, n, cap, "reads_gbuffer", 1, fv->variant & 1u, 0, 0);
    return fv_fovea_add_detail(out, n, cap, "stores_p", 1, fv->variant >> 1, 0, 0);
}

const fv_pass fv_fovea_pass = {
    .id = "fovea",
    .plan = fovea_plan,
    .init = fovea_init,
    .record = fovea_record,
    .fini = fovea_fini,
    .details = fovea_details,
    .makes = FV_PASS_NAMES("fovea prob", "fovea mask", "fovea blocks"),
};

/* ---- "compact": the mask as the frame sample list ---------------------------------------------------------------- */

enum { CSTAGE_TILES = 0, CSTAGE_ROWS = 1, CSTAGE_FINISH = 2 };

typedef struct compact {
    fv_vk *vk;
    uint32_t width, height, slots;
    fv_vk_compute cs;
    fv_image_id mask;
    fv_vk_buffer sums;                             /* per image row (rows mode) */
    fv_vk_buffer stats[FV_MAX_FRAMES_IN_FLIGHT];   /* per slot: samples per eye (host-read after the fence) */
    bool recorded[FV_MAX_FRAMES_IN_FLIGHT];
    struct fv_compact_push pc;
    uint32_t units_per_group; /* tiles or rows per workgroup: one per subgroup */
    uint32_t mode;
    uint64_t last_samples[2]; /* of the newest retired frame */
    bool have_last;
} compact;

static void compact_fini(void *state)
{
    compact *c = state;
    if (!c) return;
    fv_vk_compute_fini(c->vk, &c->cs);
    fv_vk_buffer_destroy(c->vk, &c->sums);
    for (uint32_t i = 0; i < FV_MAX_FRAMES_IN_FLIGHT; i++) fv_vk_buffer_destroy(c->vk, &c->stats[i]);
    free(c);
}

static fv_result compact_init(const fv_pass_env *env, void **out_state)
{
    compact *c = calloc(1, sizeof *c);
    if (!c) return FV_ERR_NO_MEMORY;
    c->vk = env->vk;
    c->width = env->width;
    c->height = env->height;
    c->slots = env->slots;
    struct fv_compact_push *pc = &c->pc;
    pc->tiles_x = (env->width + FV_COMPACT_TILE - 1) / FV_COMPACT_TILE;
    pc->tiles_y = (env->height + FV_COMPACT_TILE - 1) / FV_COMPACT_TILE;
    pc->tile_count = pc->tiles_x * pc->tiles_y * 2u;
    pc->tiles_per_stripe = (pc->tile_count + FV_COMPACT_STRIPES - 1) / FV_COMPACT_STRIPES;
    pc->entries = pc->tiles_per_stripe * FV_COMPACT_STRIPES;
    uint32_t max_x = env->vk->props.limits.maxComputeWorkGroupCount[0];
    pc->groups_x = pc->entries < max_x ? pc->entries : max_x;
    /* A masked list holds every tile-order slot; the renderer sized the list for the image's pixels. The buffers
     * are made at the first reserve, by this pass only (the one producer), so the capacity is raised before. */
    uint32_t masked = pc->entries * FV_COMPACT_TILE_SIZE;
    if (!env->samples->list[0].buffer && env->samples->capacity < masked) env->samples->capacity = masked;
    fv_result res = env->samples->capacity >= masked ? FV_OK : FV_ERR_STATE;
    if (res == FV_OK) res = fv_images_find(env->images, "fovea mask", &c->mask); /* the fovea pass made it */
    if (res == FV_OK) res = fv_frame_samples_reserve(env->samples);
    if (res == FV_OK)
        res = fv_vk_buffer_create(env->vk, (VkDeviceSize)env->height * 2u * 4u, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                  FV_VK_MEM_DEVICE, "fovea row sums", &c->sums);
    for (uint32_t i = 0; res == FV_OK && i < env->slots; i++)
        res = fv_vk_buffer_create(env->vk, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, FV_VK_MEM_READBACK,
                                  "fovea sample stats", &c->stats[i]);
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorType sb = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    VkDescriptorSetLayoutBinding b[FV_COMPACT_BINDING_COUNT] = {
        {FV_COMPACT_BINDING_MASK, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        {FV_COMPACT_BINDING_SUMS, sb, 1, cs, NULL},
        {FV_COMPACT_BINDING_LIST, sb, 1, cs, NULL},
        {FV_COMPACT_BINDING_INDIRECT, sb, 1, cs, NULL},
        {FV_COMPACT_BINDING_STATS, sb, 1, cs, NULL},
    };
    /* constant 0: the stage, constant 1: the workgroup size */
    const uint32_t spec[3][2] = {{FV_COMPACT_STAGE_TILES, FV_COMPACT_GROUP},
                                 {FV_COMPACT_STAGE_ROWS, FV_COMPACT_GROUP},
                                 {FV_COMPACT_STAGE_FINISH, FV_COMPACT_FINISH_SIZE}};
    VkDescriptorSetLayout shared[1] = {env->scene->set_layout};
    fv_vk_compute_desc cd = {.name = "compact", .code = fv_spv_compact_comp, .code_size = sizeof fv_spv_compact_comp,
                             .shared_sets = shared, .shared_set_count = 1, .bindings = b,
                             .binding_count = FV_COMPACT_BINDING_COUNT, .set_count = env->slots,
                             .push_bytes = sizeof(struct fv_compact_push), .spec = &spec[0][0], .spec_count = 2,
                             .variant_count = 3};
    /* the subgroup scan needs arithmetic subgroup operations in compute shaders */
    VkPhysicalDeviceSubgroupProperties sg = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &sg};
    vkGetPhysicalDeviceProperties2(env->vk->phys, &p2);
    if (res == FV_OK && (!(sg.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) ||
                         !(sg.supportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT) ||
                         !(sg.supportedOperations & VK_SUBGROUP_FEATURE_BALLOT_BIT) || sg.subgroupSize < 2 ||
                         sg.subgroupSize > FV_COMPACT_GROUP || FV_COMPACT_GROUP % sg.subgroupSize)) {
        FV_ERROR(MOD, "compaction needs arithmetic and ballot subgroup operations in compute shaders, subgroups of "
                 "2..%u (this device: %u)", FV_COMPACT_GROUP, sg.subgroupSize);
        res = FV_ERR_UNSUPPORTED;
    }
    c->units_per_group = sg.subgroupSize ? FV_COMPACT_GROUP / sg.subgroupSize : 1;
    if (res == FV_OK) res = fv_vk_compute_init(env->vk, &cd, &c->cs);
    for (uint32_t i = 0; res == FV_OK && i < env->slots; i++) {
        VkDescriptorSet set = c->cs.sets[i];
        fv_vk_write_image(env->vk, set, FV_COMPACT_BINDING_MASK, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                          fv_images_image(env->images, c->mask)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_buffer(env->vk, set, FV_COMPACT_BINDING_SUMS, sb, c->sums.buffer, 0, VK_WHOLE_SIZE);
        fv_vk_write_buffer(env->vk, set, FV_COMPACT_BINDING_LIST, sb, env->samples->list[i].buffer, 0, VK_WHOLE_SIZE);
        fv_vk_write_buffer(env->vk, set, FV_COMPACT_BINDING_INDIRECT, sb, env->samples->indirect[i].buffer, 0,
                           VK_WHOLE_SIZE);
        fv_vk_write_buffer(env->vk, set, FV_COMPACT_BINDING_STATS, sb, c->stats[i].buffer, 0, VK_WHOLE_SIZE);
    }
    if (res != FV_OK) {
        FV_ERROR(MOD, "compaction pass could not be created: %s", fv_result_str(res));
        compact_fini(c);
        return res;
    }
    *out_state = c;
    return FV_OK;
}

/* The slot's frame is done (prepare): its per-eye sample counts are the newest retired ones. */
static void compact_prepare(void *state, const fv_pass_frame *f)
{
    compact *c = state;
    if (f->slot >= c->slots || !c->recorded[f->slot]) return;
    if (fv_vk_buffer_invalidate(c->vk, &c->stats[f->slot]) != FV_OK) return;
    const uint32_t *s = c->stats[f->slot].mapped;
    c->last_samples[0] = s[0];
    c->last_samples[1] = s[1];
    c->have_last = true;
}

static void compact_stage(compact *c, const fv_pass_frame *f, uint32_t stage, uint32_t pass, uint32_t groups)
{
    VkCommandBuffer cmd = f->cmd;
    fv_images_use(f->images, cmd, c->mask, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, VK_ACCESS_SHADER_READ_BIT});
    c->pc.pass = pass;
    fv_vk_compute_bind(&c->cs, cmd, stage, &f->scene_set, 1, f->slot, &c->pc);
    uint32_t gx = groups < c->pc.groups_x ? groups : c->pc.groups_x;
    vkCmdDispatch(cmd, gx, (groups + gx - 1) / gx, 1);
    f->counters->dispatches++;
}

static void compact_record(void *state, const fv_pass_frame *f)
{
    compact *c = state;
    VkCommandBuffer cmd = f->cmd;
    if (!f->samples) return;
    c->mode = f->input->quality.fovea.compaction;
    c->pc.mode = c->mode <= FV_COMPACT_MODE_MASKED ? c->mode : FV_COMPACT_MODE_TILES;
    fv_vk_label_begin(c->vk, cmd, "compact (sample list)");
    /* Earlier frames' shading read a sample list (another slot's, but the row sums are shared) and the host read
     * this slot's stats after its fence: those reads and this pass's earlier writes come before this frame's. */
    buffers_barrier(cmd, CS | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, RW | VK_ACCESS_INDIRECT_COMMAND_READ_BIT, CS, RW);
    compact_stage(c, f, CSTAGE_FINISH, 0, 1); /* reset the count and the stats */
    buffers_barrier(cmd, CS, RW, CS, RW);
    if (c->pc.mode == FV_COMPACT_MODE_ROWS) {
        uint32_t rows = (2u * c->height + c->units_per_group - 1) / c->units_per_group;
        compact_stage(c, f, CSTAGE_ROWS, 0, rows); /* row counts */
        buffers_barrier(cmd, CS, RW, CS, RW);
        compact_stage(c, f, CSTAGE_FINISH, 1, 1); /* row offsets, count, dispatch */
        buffers_barrier(cmd, CS, RW, CS, RW);
        compact_stage(c, f, CSTAGE_ROWS, 1, rows); /* scatter */
    } else {
        compact_stage(c, f, CSTAGE_TILES, 0, (c->pc.entries + c->units_per_group - 1) / c->units_per_group);
        buffers_barrier(cmd, CS, RW, CS, RW);
        compact_stage(c, f, CSTAGE_FINISH, 1, 1); /* count, dispatch */
    }
    /* The list, its count and its dispatch arguments -> the shade pass's indirect dispatch and reads, and the
     * host's reads of the count and the stats after the fence. */
    buffers_barrier(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT,
                    CS | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                    VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_HOST_READ_BIT);
    f->samples->active = true;
    c->recorded[f->slot] = true;
    fv_vk_label_end(c->vk, cmd);
}

static uint32_t compact_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    compact *c = state;
    uint32_t n = 0;
    double per_eye = (double)c->width * c->height, s0 = (double)c->last_samples[0], s1 = (double)c->last_samples[1];
    if (c->have_last) {
        n = fv_fovea_add_detail(out, n, cap, "sampled_fraction", 2, s0 / per_eye, s1 / per_eye, 0);
        n = fv_fovea_add_detail(out, n, cap, "samples", 2, s0, s1, 0);
    }
    return fv_fovea_add_detail(out, n, cap, "compaction_mode", 1, c->mode, 0, 0);
}

const fv_pass fv_compact_pass = {
    .id = "compact",
    .plan = compact_plan,
    .init = compact_init,
    .prepare = compact_prepare,
    .record = compact_record,
    .fini = compact_fini,
    .details = compact_details,
    .needs = FV_PASS_NAMES("fovea mask"),
};

/* ---- "reconstruct" ------------------------------------------------------------------------------------------- */

/* the stages of rc->cs; the soft fill's two are rc->soft's (a compute holds at most 4 variants) */
enum { RSTAGE_INIT = 0, RSTAGE_STEP = 1, RSTAGE_RESOLVE = 2, RSTAGE_BLOCKS = 3, RSTAGE_SOFT_REPS = 4, RSTAGE_SOFT_FILL = 5,
       RSTAGE_SOFT_ARGS = 6, RSTAGE_SOFT_EDGE = 7 };

typedef struct recon {
    fv_vk *vk;
    uint32_t width, height, block;
    fv_vk_compute cs, soft;
    fv_images *images;
    fv_image_id mask, blocks, voronoi, reps; /* voronoi, reps: FV_IMAGE_MAX until made (mask, blocks: the fovea pass's) */
    VkSampler nearest;                 /* the G-buffer's reads (soft) */
    fv_vk_buffer seeds[2];
    fv_vk_buffer lists;               /* soft: its two pixel lists and their dispatch arguments (FV_RECON_LIST_*) */
    uint32_t list_pixels;             /* each list's capacity: 2 W H */
    uint32_t slots;
    fv_vk_timer timer;             /* its stages: "voronoi" (1+JFA or the block search), "fill" */
    bool recorded[FV_MAX_FRAMES_IN_FLIGHT];
    double stage_ms[2];            /* of the newest retired frame */
    bool have_stage_ms;
    uint32_t last_steps, last_final, last_method;
} recon;

static void recon_fini(void *state)
{
    recon *rc = state;
    if (!rc) return;
    fv_vk_compute_fini(rc->vk, &rc->cs);
    fv_vk_compute_fini(rc->vk, &rc->soft);
    fv_vk_timer_fini(&rc->timer, rc->vk);
    for (int i = 0; i < 2; i++) fv_vk_buffer_destroy(rc->vk, &rc->seeds[i]);
    fv_vk_buffer_destroy(rc->vk, &rc->lists);
    if (rc->nearest) vkDestroySampler(rc->vk->device, rc->nearest, NULL);
    if (rc->voronoi != FV_IMAGE_MAX) fv_images_release(rc->images, rc->voronoi);
    if (rc->reps != FV_IMAGE_MAX) fv_images_release(rc->images, rc->reps);
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
    rc->voronoi = rc->reps = FV_IMAGE_MAX;
    rc->slots = env->slots;
    const fv_vk_image *color;
    fv_result res = fv_images_find(env->images, "fovea mask", &rc->mask); /* the fovea pass (earlier) made it */
    if (res == FV_OK) res = fv_images_find(env->images, "fovea blocks", &rc->blocks);
    if (res == FV_OK) res = scratch(env->images, "fovea voronoi", VK_FORMAT_R32_UINT, &rc->voronoi);
    VkDeviceSize seed_bytes = (VkDeviceSize)env->width * env->height * 2u * 4u;
    for (int i = 0; i < 2 && res == FV_OK; i++)
        res = fv_vk_buffer_create(env->vk, seed_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, FV_VK_MEM_DEVICE,
                                  i ? "fovea seeds b" : "fovea seeds a", &rc->seeds[i]);
    rc->list_pixels = env->width * env->height * 2u;
    if (res == FV_OK)
        res = fv_vk_buffer_create(env->vk, ((VkDeviceSize)2u * (FV_RECON_LIST_HEADER + rc->list_pixels) + 8u) * 4u,
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                                      VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                  FV_VK_MEM_DEVICE, "fovea fill lists", &rc->lists);
    uint32_t B = env->plan->variant >= 2 ? env->plan->variant : 2; /* the block (the fovea pass checks it) */
    rc->block = B;
    if (res == FV_OK) { /* the soft fill's representatives: FV_RECON_SOFT_REP_UVEC4S texels per block in a row */
        fv_vk_image_desc d = {.width = (env->width + B - 1) / B * FV_RECON_SOFT_REP_UVEC4S,
                              .height = (env->height + B - 1) / B, .layers = 2, .format = VK_FORMAT_R32G32B32A32_UINT,
                              .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                              .name = "fovea soft reps"};
        res = fv_images_scratch(env->images, &d, &rc->reps);
    }
    if (res == FV_OK) res = fv_images_get(env->images, FV_IMAGE_COLOR, &color);
    if (res == FV_OK) res = fv_vk_timer_init(&rc->timer, env->vk, env->slots);
    if (res == FV_OK) res = fv_images_get_gbuffer(env->images);
    const fv_vk_image *motion;
    if (res == FV_OK) res = fv_images_get(env->images, FV_IMAGE_SURFACE, &motion);
    if (res == FV_OK) res = fv_vk_sampler_create(env->vk, false, false, "reconstruct nearest sampler", &rc->nearest);
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorType si = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    VkDescriptorSetLayoutBinding b[FV_RECON_BINDING_COUNT] = {
        {FV_RECON_BINDING_MASK, si, 1, cs, NULL},
        {FV_RECON_BINDING_SEEDS_A, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
        {FV_RECON_BINDING_SEEDS_B, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
        {FV_RECON_BINDING_COLOR, si, 1, cs, NULL},
        {FV_RECON_BINDING_VORONOI, si, 1, cs, NULL},
        {FV_RECON_BINDING_BLOCKS, si, 1, cs, NULL},
        {FV_RECON_BINDING_DEPTH, cis, 1, cs, NULL},
        {FV_RECON_BINDING_DEPTH + 1, cis, 1, cs, NULL},
        {FV_RECON_BINDING_DEPTH + 2, cis, 1, cs, NULL},
        {FV_RECON_BINDING_DEPTH + 3, cis, 1, cs, NULL},
        {FV_RECON_BINDING_REPS, si, 1, cs, NULL},
        {FV_RECON_BINDING_MOTION, si, 1, cs, NULL},
        {FV_RECON_BINDING_LISTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
    };
    const uint32_t spec[4] = {FV_RECON_STAGE_INIT, FV_RECON_STAGE_STEP, FV_RECON_STAGE_RESOLVE, FV_RECON_STAGE_BLOCKS};
    const uint32_t soft_spec[4] = {FV_RECON_STAGE_SOFT_REPS, FV_RECON_STAGE_SOFT_FILL, FV_RECON_STAGE_SOFT_ARGS,
                                   FV_RECON_STAGE_SOFT_EDGE};
    VkDescriptorSetLayout shared[1] = {env->scene->set_layout};
    fv_vk_compute_desc cd = {.name = "reconstruct", .code = fv_spv_reconstruct_comp,
                             .code_size = sizeof fv_spv_reconstruct_comp, .shared_sets = shared,
                             .shared_set_count = 1, .bindings = b, .binding_count = FV_RECON_BINDING_COUNT,
                             .set_count = 1, .push_bytes = sizeof(struct fv_recon_push), .spec = spec,
                             .spec_count = 1, .variant_count = 4};
    if (res == FV_OK) res = fv_vk_compute_init(env->vk, &cd, &rc->cs);
    cd.name = "reconstruct soft";
    cd.spec = soft_spec;
    cd.variant_count = 4;
    if (res == FV_OK) res = fv_vk_compute_init(env->vk, &cd, &rc->soft);
    if (res != FV_OK) {
        FV_ERROR(MOD, "reconstruction pass could not be created: %s", fv_result_str(res));
        recon_fini(rc);
        return res;
    }
    for (int c = 0; c < 2; c++) { /* the same bindings in both pipelines' sets */
        VkDescriptorSet set = c ? rc->soft.sets[0] : rc->cs.sets[0];
        fv_vk_write_image(env->vk, set, FV_RECON_BINDING_MASK, si, fv_images_image(env->images, rc->mask)->view,
                          VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        for (int i = 0; i < 2; i++)
            fv_vk_write_buffer(env->vk, set, i ? FV_RECON_BINDING_SEEDS_B : FV_RECON_BINDING_SEEDS_A,
                               VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, rc->seeds[i].buffer, 0, VK_WHOLE_SIZE);
        fv_vk_write_buffer(env->vk, set, FV_RECON_BINDING_LISTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, rc->lists.buffer, 0,
                           VK_WHOLE_SIZE);
        fv_vk_write_image(env->vk, set, FV_RECON_BINDING_COLOR, si, color->view, VK_NULL_HANDLE,
                          VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_image(env->vk, set, FV_RECON_BINDING_VORONOI, si,
                          fv_images_image(env->images, rc->voronoi)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_image(env->vk, set, FV_RECON_BINDING_BLOCKS, si, fv_images_image(env->images, rc->blocks)->view,
                          VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_images_bind_gbuffer(env->images, set, FV_RECON_BINDING_DEPTH, rc->nearest);
        fv_vk_write_image(env->vk, set, FV_RECON_BINDING_REPS, si, fv_images_image(env->images, rc->reps)->view,
                          VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_image(env->vk, set, FV_RECON_BINDING_MOTION, si,
                          fv_images_image(env->images, FV_IMAGE_SURFACE)->view, VK_NULL_HANDLE,
                          VK_IMAGE_LAYOUT_GENERAL);
    }
    *out_state = rc;
    return FV_OK;
}

static void recon_stage(recon *rc, const fv_pass_frame *f, uint32_t stage, const struct fv_recon_push *pc)
{
    VkCommandBuffer cmd = f->cmd;
    /* Every stage's pipeline uses all its images and buffers statically: declare them all, so each dispatch waits
     * for the one before (and the first for the shading that wrote the colour and the fovea pass that wrote the
     * mask); the seed buffers get a barrier of their own (the first: the previous frame's reads and writes). */
    fv_images_use(f->images, cmd, rc->mask,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, VK_ACCESS_SHADER_READ_BIT});
    fv_images_use(f->images, cmd, FV_IMAGE_COLOR, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    fv_images_use(f->images, cmd, rc->voronoi, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    fv_images_use(f->images, cmd, rc->reps, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    fv_images_use(f->images, cmd, rc->blocks, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, VK_ACCESS_SHADER_READ_BIT});
    fv_images_use_gbuffer(f->images, cmd, CS);
    fv_images_use(f->images, cmd, FV_IMAGE_SURFACE, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, VK_ACCESS_SHADER_READ_BIT});
    /* the buffers (seeds, the soft fill's lists): written by the stage before, their arguments read indirectly */
    buffers_barrier(cmd, CS, RW, CS | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, RW | VK_ACCESS_INDIRECT_COMMAND_READ_BIT);
    if (stage >= RSTAGE_SOFT_REPS) fv_vk_compute_bind(&rc->soft, cmd, stage - RSTAGE_SOFT_REPS, &f->scene_set, 1, 0, pc);
    else fv_vk_compute_bind(&rc->cs, cmd, stage, &f->scene_set, 1, 0, pc);
    if (stage == RSTAGE_SOFT_FILL || stage == RSTAGE_SOFT_EDGE) { /* over a list: its arguments (SOFT_ARGS) */
        uint32_t l = stage == RSTAGE_SOFT_EDGE ? FV_RECON_LIST_EDGE : FV_RECON_LIST_FILL;
        vkCmdDispatchIndirect(cmd, rc->lists.buffer, ((VkDeviceSize)2u * (FV_RECON_LIST_HEADER + rc->list_pixels) + 4u * l) * 4u);
    } else if (stage == RSTAGE_SOFT_ARGS) {
        vkCmdDispatch(cmd, 1, 1, 1);
    } else { /* SOFT_REPS: a thread per block; the rest a thread per pixel */
        uint32_t w = stage == RSTAGE_SOFT_REPS ? (rc->width + rc->block - 1) / rc->block : rc->width;
        uint32_t h = stage == RSTAGE_SOFT_REPS ? (rc->height + rc->block - 1) / rc->block : rc->height;
        vkCmdDispatch(cmd, (w + FV_RECON_GROUP - 1) / FV_RECON_GROUP, (h + FV_RECON_GROUP - 1) / FV_RECON_GROUP, 2);
    }
    f->counters->dispatches++;
}

/* The slot's frame is done: its stage timings are the newest retired ones. */
static void recon_prepare(void *state, const fv_pass_frame *f)
{
    recon *rc = state;
    if (f->slot >= rc->slots || !rc->recorded[f->slot]) return;
    double ms[2], total;
    char names[2][FV_VK_TIMER_NAME_MAX];
    if (fv_vk_timer_collect(&rc->timer, rc->vk, f->slot, ms, names, 2, &total) == 2) {
        rc->stage_ms[0] = ms[0];
        rc->stage_ms[1] = ms[1];
        rc->have_stage_ms = true;
    }
}

/* With temporal reuse (fovea.temporal > 0, its pass made the history): the frame's colour, every pixel known or
 * filled, becomes the next frame's history (fovea_interface.h): one copy. */
static void keep_history(const fv_pass_frame *f)
{
    const fv_vk_image *src = fv_images_image(f->images, FV_IMAGE_COLOR);
    const fv_vk_image *dst = fv_images_image(f->images, FV_IMAGE_HISTORY);
    if (f->input->quality.fovea.temporal == 0 || !src || !dst) return;
    VkPipelineStageFlags tr = VK_PIPELINE_STAGE_TRANSFER_BIT;
    fv_images_use(f->images, f->cmd, FV_IMAGE_COLOR,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, tr, VK_ACCESS_TRANSFER_READ_BIT});
    fv_images_use(f->images, f->cmd, FV_IMAGE_HISTORY,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, tr, VK_ACCESS_TRANSFER_WRITE_BIT});
    VkImageCopy region = {.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 2},
                          .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 2},
                          .extent = {src->width, src->height, 1}};
    vkCmdCopyImage(f->cmd, src->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst->image,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
}

/* The fill stage closes the "voronoi" timer range t and is timed as "fill"; what was recorded is kept for the details. */
static void recon_fill(recon *rc, const fv_pass_frame *f, int t, uint32_t stage, const struct fv_recon_push *pc,
                       uint32_t steps, uint32_t src, uint32_t method)
{
    if (t >= 0) fv_vk_timer_end(&rc->timer, f->cmd, f->slot, t);
    t = fv_vk_timer_begin(&rc->timer, f->cmd, f->slot, "fill");
    recon_stage(rc, f, stage, pc);
    if (stage == RSTAGE_SOFT_FILL) { /* list 1: the edges */
        struct fv_recon_push edge = *pc;
        edge.step = FV_RECON_LIST_EDGE;
        recon_stage(rc, f, RSTAGE_SOFT_ARGS, &edge);
        recon_stage(rc, f, RSTAGE_SOFT_EDGE, &edge);
    }
    if (t >= 0) fv_vk_timer_end(&rc->timer, f->cmd, f->slot, t);
    keep_history(f);
    rc->recorded[f->slot] = true;
    rc->last_steps = steps;
    rc->last_final = src;
    rc->last_method = method;
    fv_vk_label_end(rc->vk, f->cmd);
}

static void recon_record(void *state, const fv_pass_frame *f)
{
    recon *rc = state;
    if (!f->samples) return;
    fv_vk_timer_reset(&rc->timer, f->cmd, f->slot);
    const fv_quality_fovea *q = &f->input->quality.fovea;
    uint32_t method = q->recon == FV_FOVEA_RECON_SIBSON ? FV_RECON_METHOD_SIBSON
                      : q->recon == FV_FOVEA_RECON_IDW  ? FV_RECON_METHOD_IDW
                      : q->recon == FV_FOVEA_RECON_SOFT ? FV_RECON_METHOD_SOFT
                                                        : FV_RECON_METHOD_NEAREST;
    bool jfa = q->voronoi != FV_FOVEA_VORONOI_BLOCKS;
    fv_vk_label_begin(rc->vk, f->cmd, "reconstruct");
    uint32_t steps[8], n = jfa ? fv_fovea_jfa_steps(q->block, steps, 8) : 0, src = 0;
    /* the nearest sample is at most (B - 1) sqrt 2 away (every block holds one): one block around for B <= 5 */
    struct fv_recon_push pc = {.method = method, .window = q->block, .block = q->block,
                               .block_words = block_words(q->block), .reach = q->block <= 5 ? 1u : 2u};
    /* the voronoi stage: 1+JFA, or the block search for every pixel (sibson); nearest and idw with blocks need no
     * stage of their own (the fill finds each unsampled pixel's nearest itself) */
    int t = fv_vk_timer_begin(&rc->timer, f->cmd, f->slot, "voronoi");
    if (method == FV_RECON_METHOD_SOFT) {
        /* no Voronoi: the representatives of the blocks (timed as its "voronoi" stage), then the fill; the nearest
         * representative goes to "fovea voronoi" only for the voronoi debug view */
        n = 0;
        src = FV_RECON_SRC_SEARCH;
        pc.flags = f->input->quality.debug_view == FV_DEBUG_VIEW_VORONOI ? FV_RECON_FLAG_VORONOI : 0u;
        pc.list_pixels = rc->list_pixels;
        /* both lists start empty (the previous frame's stages are done with them: the barrier in recon_stage) */
        buffers_barrier(f->cmd, CS | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, RW | VK_ACCESS_INDIRECT_COMMAND_READ_BIT,
                        VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
        for (uint32_t l = 0; l < 2; l++)
            vkCmdFillBuffer(f->cmd, rc->lists.buffer, (VkDeviceSize)l * (FV_RECON_LIST_HEADER + rc->list_pixels) * 4u,
                            16u, 0u);
        buffers_barrier(f->cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, CS, RW);
        recon_stage(rc, f, RSTAGE_SOFT_REPS, &pc); /* the slots, and list 0: the unknown pixels */
        pc.step = FV_RECON_LIST_FILL;
        recon_stage(rc, f, RSTAGE_SOFT_ARGS, &pc);
        recon_fill(rc, f, t, RSTAGE_SOFT_FILL, &pc, n, src, method); /* list 0; its edges to list 1 */
        return;
    }
    if (method != FV_RECON_METHOD_IDW && jfa) {
        recon_stage(rc, f, RSTAGE_INIT, &pc);
        for (uint32_t i = 0; i < n; i++, src ^= 1u) {
            pc.step = steps[i];
            pc.src = src;
            recon_stage(rc, f, RSTAGE_STEP, &pc);
        }
    } else if (method == FV_RECON_METHOD_SIBSON) {
        recon_stage(rc, f, RSTAGE_BLOCKS, &pc); /* every pixel's nearest, for the window's d(q) */
    } else {
        src = FV_RECON_SRC_SEARCH; /* nearest or idw: the fill searches the blocks itself, one pass */
    }
    pc.step = 0;
    pc.src = src;
    recon_fill(rc, f, t, RSTAGE_RESOLVE, &pc, n, src, method);
}

static uint32_t recon_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    recon *rc = state;
    /* final seeds: 0 a, 1 b, FV_RECON_SRC_SEARCH none (the "fovea voronoi" image always holds the result) */
    uint32_t n = fv_fovea_add_detail(out, 0, cap, "jfa_steps_final_seeds_method", 3, rc->last_steps, rc->last_final,
                            rc->last_method);
    if (rc->have_stage_ms) n = fv_fovea_add_detail(out, n, cap, "stage_gpu_ms_voronoi_fill", 2, rc->stage_ms[0], rc->stage_ms[1], 0);
    return n;
}

const fv_pass fv_reconstruct_pass = {
    .id = "reconstruct",
    .plan = recon_plan,
    .init = recon_init,
    .prepare = recon_prepare,
    .record = recon_record,
    .fini = recon_fini,
    .details = recon_details,
    .makes = FV_PASS_NAMES("fovea voronoi", "fovea soft reps"),
    .needs = FV_PASS_NAMES("fovea mask", "fovea blocks"),
};
