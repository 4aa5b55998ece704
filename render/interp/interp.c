/* @brief The hierarchical screen-space interpolation passes (see interp.h). */
#include "interp.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "interp_comp.spv.h"
#include "interp_fill_comp.spv.h"
#include "interp_fill_mark_comp.spv.h"
#include "fv_shade_inputs_interface.h"
#include "interp_interface.h"

#define MOD "interp"

_Static_assert(sizeof(struct fv_interp_push) == 80, "fv_interp_push layout");
_Static_assert(sizeof(struct fv_interp_fill_push) == 16, "fv_interp_fill_push layout");
_Static_assert(FV_SCENE_SET == 0 && FV_SHADE_INPUTS_SET == 1 && FV_INTERP_SET == 2 && FV_INTERP_FILL_SET == 1,
               "the interp passes' set order");
_Static_assert(FV_INTERP_BINDING_NORMAL == FV_INTERP_BINDING_DEPTH + 1 &&
                   FV_INTERP_BINDING_ALBEDO == FV_INTERP_BINDING_DEPTH + 2 &&
                   FV_INTERP_BINDING_MATERIAL == FV_INTERP_BINDING_DEPTH + 3,
               "fv_images_bind_gbuffer writes depth, normal, albedo, material in a row");
_Static_assert(FV_INTERP_TILE_SIZE == FV_GPU_LIST_GROUP_SIZE, "the given stage takes a list group per workgroup");
_Static_assert(FV_INTERP_MAX_LEVEL < FV_INTERP_CODE_LEVEL_MASK, "a level fits the code's level bits");

static const VkPipelineStageFlags CS = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
static const VkAccessFlags RW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;

uint32_t fv_interp_nodes_along(uint32_t n, uint32_t level)
{
    if (n <= 1 || level >= 31) return 1;
    uint32_t s = 1u << level, c = (n - 1u + s - 1u) / s;
    return c ? c : 1;
}

/* ---- plans ---------------------------------------------------------------------------------------------------- */

static bool plan_off(const fv_plan_context *ctx, fv_plan_entry *out)
{
    const fv_quality_interp *q = &ctx->quality->interp;
    out->enabled = q->enabled;
    out->variant = 0;
    if (!out->enabled) snprintf(out->reason, sizeof out->reason, "off — interp.enabled is false");
    return !out->enabled;
}

static void interp_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    if (plan_off(ctx, out)) return;
    const fv_quality_interp *q = &ctx->quality->interp;
    uint32_t s = 1u << (q->start_level <= FV_INTERP_MAX_LEVEL ? q->start_level : FV_INTERP_MAX_LEVEL);
    snprintf(out->reason, sizeof out->reason,
             "coherent regions (τ %g%s) shaded at their corners, %ux%u px down to 2x2, the rest per pixel%s",
             (double)q->threshold, q->light ? ", light" : "", s, s,
             ctx->quality->fovea.enabled ? "; thinned by foveation" : "");
}

/* Foveation on: the fill also marks the shaded and filled pixels in foveation's sample mask, so that temporal reuse
 * and reconstruction (after it) keep them. The variant is then foveation's block (as its own passes': they keep
 * views of its images, so they are made again together), 0 without. */
static void fill_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    if (plan_off(ctx, out)) return;
    bool mark = ctx->quality->fovea.enabled;
    out->variant = mark ? ctx->quality->fovea.block : 0;
    snprintf(out->reason, sizeof out->reason, "%s%s",
             ctx->quality->debug_view == FV_DEBUG_VIEW_INTERP
                 ? "view 'interp': the level each pixel was shaded or filled at"
                 : "the unshaded pixels of coherent regions, bilinear from their region's four shaded corners",
             mark ? "; marked in foveation's sample mask" : "");
}

/* ---- "interp": pyramid, classification, the list --------------------------------------------------------------- */

typedef struct interp {
    fv_vk *vk;
    uint32_t width, height, slots;
    fv_images *images;
    fv_vk_compute cs[2];                          /* [0]: leaf, node, scan (barriers); [1]: given, count, scatter */
    VkSampler nearest;
    fv_image_id level;                            /* "interp level"; FV_IMAGE_MAX until made */
    fv_vk_buffer nodes, tiles, given;
    fv_vk_buffer stats[FV_MAX_FRAMES_IN_FLIGHT];  /* per slot: shaded, filled, left (host-read after the fence) */
    bool recorded[FV_MAX_FRAMES_IN_FLIGHT];
    fv_vk_timer timer;                            /* its stages: "pyramid", "classify", "list" */
    double stage_ms[3];                           /* of the newest retired frame */
    bool have_stage_ms;
    struct fv_interp_push pc;
    uint32_t tiles_per_group;                     /* COUNT, SCATTER: one subgroup per tile */
    uint64_t last[3];                             /* of the newest retired frame */
    bool have_last, last_given;
} interp;

static VkDeviceSize node_bytes(uint32_t w, uint32_t h)
{
    VkDeviceSize n = 0;
    for (uint32_t k = 1; k <= FV_INTERP_MAX_LEVEL; k++)
        n += 2u * (VkDeviceSize)fv_interp_nodes_along(w, k) * fv_interp_nodes_along(h, k);
    return n * 16u * FV_INTERP_NODE_VEC4;
}

static void interp_fini(void *state)
{
    interp *it = state;
    if (!it) return;
    for (int i = 0; i < 2; i++) fv_vk_compute_fini(it->vk, &it->cs[i]);
    fv_vk_timer_fini(&it->timer, it->vk);
    if (it->nearest) vkDestroySampler(it->vk->device, it->nearest, NULL);
    fv_vk_buffer_destroy(it->vk, &it->nodes);
    fv_vk_buffer_destroy(it->vk, &it->tiles);
    fv_vk_buffer_destroy(it->vk, &it->given);
    for (uint32_t i = 0; i < FV_MAX_FRAMES_IN_FLIGHT; i++) fv_vk_buffer_destroy(it->vk, &it->stats[i]);
    if (it->level != FV_IMAGE_MAX) fv_images_release(it->images, it->level);
    free(it);
}

static fv_result interp_init(const fv_pass_env *env, void **out_state)
{
    if (env->width >= FV_GPU_PIXEL_MAX_DIM || env->height >= FV_GPU_PIXEL_MAX_DIM) {
        FV_ERROR(MOD, "an eye of %ux%u px does not fit a packed pixel list (< %u px a side)", env->width, env->height,
                 FV_GPU_PIXEL_MAX_DIM);
        return FV_ERR_RANGE;
    }
    interp *it = calloc(1, sizeof *it);
    if (!it) return FV_ERR_NO_MEMORY;
    fv_vk *vk = env->vk;
    it->vk = vk;
    it->width = env->width;
    it->height = env->height;
    it->slots = env->slots;
    it->images = env->images;
    it->level = FV_IMAGE_MAX;
    struct fv_interp_push *pc = &it->pc;
    pc->tiles_x = (env->width + FV_INTERP_TILE - 1) / FV_INTERP_TILE;
    pc->tiles_y = (env->height + FV_INTERP_TILE - 1) / FV_INTERP_TILE;
    pc->tile_count = pc->tiles_x * pc->tiles_y * 2u;
    pc->tiles_per_stripe = (pc->tile_count + FV_INTERP_STRIPES - 1) / FV_INTERP_STRIPES;
    for (uint32_t k = 1; k < FV_INTERP_MAX_LEVEL; k++)
        pc->level_base[k + 1] = pc->level_base[k] + 2u * fv_interp_nodes_along(env->width, k) *
                                                        fv_interp_nodes_along(env->height, k);
    /* COUNT and SCATTER: a subgroup per tile (arithmetic subgroup operations in compute shaders) */
    VkPhysicalDeviceSubgroupProperties sg = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &sg};
    vkGetPhysicalDeviceProperties2(vk->phys, &p2);
    bool subgroups_ok = (sg.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                        (sg.supportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT) &&
                        (sg.supportedOperations & VK_SUBGROUP_FEATURE_BASIC_BIT) && sg.subgroupSize >= 1 &&
                        sg.subgroupSize <= FV_INTERP_TILE_SIZE && FV_INTERP_TILE_SIZE % sg.subgroupSize == 0;
    it->tiles_per_group = subgroups_ok ? FV_INTERP_TILE_SIZE / sg.subgroupSize : 1;
    uint32_t tile_groups = (pc->tile_count + it->tiles_per_group - 1) / it->tiles_per_group;
    uint32_t max_x = vk->props.limits.maxComputeWorkGroupCount[0];
    pc->groups_x = tile_groups < max_x ? tile_groups : max_x;
    VkDeviceSize pixels = (VkDeviceSize)env->width * env->height * 2u;
    /* Every pixel may be shaded: the list holds both eyes' pixels (the renderer's default capacity). The buffers
     * are made at the first reserve by whichever producer starts first; a producer that lists every slot of whole
     * 8x8 tiles in 32 stripes (foveation's masked compaction) needs the padded count, so it is reserved here too. */
    uint32_t padded = pc->tiles_per_stripe * FV_INTERP_STRIPES * FV_INTERP_TILE_SIZE;
    if (!env->samples->list[0].buffer && env->samples->capacity < padded) env->samples->capacity = padded;
    fv_result res = env->samples->capacity >= pixels ? FV_OK : FV_ERR_STATE;
    if (res == FV_OK && !subgroups_ok) {
        FV_ERROR(MOD, "interpolation needs arithmetic subgroup operations in compute shaders, subgroups of 1..%u "
                 "dividing %u (this device: %u)", FV_INTERP_TILE_SIZE, FV_INTERP_TILE_SIZE, sg.subgroupSize);
        res = FV_ERR_UNSUPPORTED;
    }
    if (res == FV_OK) res = fv_frame_samples_reserve(env->samples);
    if (res == FV_OK) res = fv_images_get_gbuffer(env->images);
    if (res == FV_OK) res = fv_vk_timer_init(&it->timer, vk, env->slots);
    if (res == FV_OK) res = fv_vk_sampler_create(vk, false, false, "interp nearest sampler", &it->nearest);
    if (res == FV_OK) {
        fv_vk_image_desc d = {.layers = 2, .format = VK_FORMAT_R32_UINT,
                              .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                              .name = "interp level"};
        res = fv_images_scratch(env->images, &d, &it->level);
    }
    VkBufferUsageFlags sb = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    if (res == FV_OK)
        res = fv_vk_buffer_create(vk, node_bytes(env->width, env->height), sb, FV_VK_MEM_DEVICE, "interp pyramid",
                                  &it->nodes);
    if (res == FV_OK)
        res = fv_vk_buffer_create(vk, (VkDeviceSize)pc->tile_count * 4u, sb, FV_VK_MEM_DEVICE, "interp tile sums",
                                  &it->tiles);
    if (res == FV_OK) res = fv_vk_buffer_create(vk, pixels * 4u, sb, FV_VK_MEM_DEVICE, "interp given", &it->given);
    for (uint32_t i = 0; res == FV_OK && i < env->slots; i++)
        res = fv_vk_buffer_create(vk, 16, sb, FV_VK_MEM_READBACK, "interp stats", &it->stats[i]);
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorType cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, sbt = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    VkDescriptorSetLayoutBinding b[FV_INTERP_BINDING_COUNT] = {
        {FV_INTERP_BINDING_DEPTH, cis, 1, cs, NULL},
        {FV_INTERP_BINDING_NORMAL, cis, 1, cs, NULL},
        {FV_INTERP_BINDING_ALBEDO, cis, 1, cs, NULL},
        {FV_INTERP_BINDING_MATERIAL, cis, 1, cs, NULL},
        {FV_INTERP_BINDING_NODES, sbt, 1, cs, NULL},
        {FV_INTERP_BINDING_LEVEL, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        {FV_INTERP_BINDING_TILES, sbt, 1, cs, NULL},
        {FV_INTERP_BINDING_LIST, sbt, 1, cs, NULL},
        {FV_INTERP_BINDING_INDIRECT, sbt, 1, cs, NULL},
        {FV_INTERP_BINDING_GIVEN, sbt, 1, cs, NULL},
        {FV_INTERP_BINDING_STATS, sbt, 1, cs, NULL},
    };
    VkDescriptorSetLayout shared[2] = {env->scene->set_layout, env->shade_inputs->layout};
    static const uint32_t stages[2][4] = {
        {FV_INTERP_STAGE_LEAF, FV_INTERP_STAGE_NODE, FV_INTERP_STAGE_SCAN, FV_INTERP_STAGE_LEAF_SHARED},
        {FV_INTERP_STAGE_GIVEN, FV_INTERP_STAGE_COUNT, FV_INTERP_STAGE_SCATTER, FV_INTERP_STAGE_SCATTER}};
    for (int c = 0; c < 2 && res == FV_OK; c++) {
        fv_vk_compute_desc cd = {.name = c ? "interp list" : "interp pyramid", .code = fv_spv_interp_comp,
                                 .code_size = sizeof fv_spv_interp_comp, .shared_sets = shared,
                                 .shared_set_count = 2, .bindings = b, .binding_count = FV_INTERP_BINDING_COUNT,
                                 .set_count = env->slots, .push_bytes = sizeof(struct fv_interp_push),
                                 .spec = stages[c], .spec_count = 1, .variant_count = c ? 3 : 4};
        res = fv_vk_compute_init(vk, &cd, &it->cs[c]);
    }
    for (uint32_t n = 0; res == FV_OK && n < 2u * env->slots; n++) {
        uint32_t i = n % env->slots;
        VkDescriptorSet set = it->cs[n / env->slots].sets[i];
        fv_images_bind_gbuffer(env->images, set, FV_INTERP_BINDING_DEPTH, it->nearest);
        fv_vk_write_buffer(vk, set, FV_INTERP_BINDING_NODES, sbt, it->nodes.buffer, 0, VK_WHOLE_SIZE);
        fv_vk_write_image(vk, set, FV_INTERP_BINDING_LEVEL, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                          fv_images_image(env->images, it->level)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_buffer(vk, set, FV_INTERP_BINDING_TILES, sbt, it->tiles.buffer, 0, VK_WHOLE_SIZE);
        fv_vk_write_buffer(vk, set, FV_INTERP_BINDING_LIST, sbt, env->samples->list[i].buffer, 0, VK_WHOLE_SIZE);
        fv_vk_write_buffer(vk, set, FV_INTERP_BINDING_INDIRECT, sbt, env->samples->indirect[i].buffer, 0,
                           VK_WHOLE_SIZE);
        fv_vk_write_buffer(vk, set, FV_INTERP_BINDING_GIVEN, sbt, it->given.buffer, 0, VK_WHOLE_SIZE);
        fv_vk_write_buffer(vk, set, FV_INTERP_BINDING_STATS, sbt, it->stats[i].buffer, 0, VK_WHOLE_SIZE);
    }
    if (res != FV_OK) {
        FV_ERROR(MOD, "interpolation pass could not be created: %s", fv_result_str(res));
        interp_fini(it);
        return res;
    }
    *out_state = it;
    return FV_OK;
}

/* The slot's frame is done: its counts are the newest retired ones. */
static void interp_prepare(void *state, const fv_pass_frame *f)
{
    interp *it = state;
    if (f->slot >= it->slots || !it->recorded[f->slot]) return;
    if (fv_vk_buffer_invalidate(it->vk, &it->stats[f->slot]) != FV_OK) return;
    const uint32_t *s = it->stats[f->slot].mapped;
    for (int i = 0; i < 3; i++) it->last[i] = s[i];
    it->have_last = true;
    double ms[3], total;
    char names[3][FV_VK_TIMER_NAME_MAX];
    if (fv_vk_timer_collect(&it->timer, it->vk, f->slot, ms, names, 3, &total) == 3) {
        for (int i = 0; i < 3; i++) it->stage_ms[i] = ms[i];
        it->have_stage_ms = true;
    }
}

/* The pipeline of a stage: which compute object, which variant of it. */
static void bind_stage(interp *it, const fv_pass_frame *f, uint32_t which)
{
    static const uint8_t object[7] = {1, 0, 0, 1, 0, 1, 0}, variant[7] = {0, 0, 1, 1, 2, 2, 3};
    _Static_assert(FV_INTERP_STAGE_GIVEN == 0 && FV_INTERP_STAGE_LEAF == 1 && FV_INTERP_STAGE_NODE == 2 &&
                       FV_INTERP_STAGE_COUNT == 3 && FV_INTERP_STAGE_SCAN == 4 && FV_INTERP_STAGE_SCATTER == 5 &&
                       FV_INTERP_STAGE_LEAF_SHARED == 6,
                   "the stage tables follow the stage numbers");
    it->pc.stage = which;
    VkDescriptorSet shared[2] = {f->scene_set, fv_shade_inputs_set(f->shade_inputs, f->slot)};
    fv_vk_compute_bind(&it->cs[object[which]], f->cmd, variant[which], shared, 2, f->slot, &it->pc);
}

static void stage(interp *it, const fv_pass_frame *f, uint32_t which, uint32_t gx, uint32_t gy, uint32_t gz)
{
    bind_stage(it, f, which);
    vkCmdDispatch(f->cmd, gx, gy, gz);
    f->counters->dispatches++;
}

static uint32_t groups(uint32_t n) { return (n + FV_INTERP_GROUP - 1) / FV_INTERP_GROUP; }

static void interp_record(void *state, const fv_pass_frame *f)
{
    interp *it = state;
    VkCommandBuffer cmd = f->cmd;
    if (!f->samples || f->slot >= it->slots) return; /* only whole frames make a list */
    const fv_quality_interp *q = &f->input->quality.interp;
    it->pc.start_level = q->start_level < 1 ? 1 : q->start_level > FV_INTERP_MAX_LEVEL ? FV_INTERP_MAX_LEVEL
                                                                                        : q->start_level;
    it->pc.threshold = q->threshold >= 0.0f ? q->threshold : 0.0f; /* NaN: 0, nothing but exact agreement */
    bool given = f->pixels && f->pixels->indirect; /* an earlier pass (foveation) made the frame's list */
    it->pc.flags = (given ? FV_INTERP_FLAG_GIVEN : 0u) | (q->light ? FV_INTERP_FLAG_LIGHT : 0u);
    it->last_given = given;
    fv_vk_timer_reset(&it->timer, cmd, f->slot);
    fv_vk_label_begin(it->vk, cmd, "interp (pyramid, classification, list)");
    int t = fv_vk_timer_begin(&it->timer, cmd, f->slot, "pyramid");
    /* Earlier frames' shading read a list (another slot's, but the pyramid, tile sums and given are shared) and
     * their fills read the level image; this slot's stats were read by the host after its fence. */
    fv_vk_barrier_memory(cmd, CS | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                    RW | VK_ACCESS_INDIRECT_COMMAND_READ_BIT, CS | VK_PIPELINE_STAGE_TRANSFER_BIT,
                    RW | VK_ACCESS_TRANSFER_WRITE_BIT);
    vkCmdFillBuffer(cmd, it->stats[f->slot].buffer, 0, VK_WHOLE_SIZE, 0);
    if (given) vkCmdFillBuffer(cmd, it->given.buffer, 0, VK_WHOLE_SIZE, 0);
    fv_vk_barrier_memory(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, CS, RW);
    /* Every stage's pipeline holds the level image (one shader): it is in GENERAL before the first dispatch, and the
     * global barriers between the stages order its writes and reads. */
    fv_images_use(f->images, cmd, it->level, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    fv_images_use_gbuffer(f->images, cmd, CS);
    fv_shade_inputs_use(f->shade_inputs, f->images, cmd, CS); /* the light test reads the shadow maps */
    if (given) {
        /* the earlier list, dispatched by its own arguments (already visible to indirect reads) */
        bind_stage(it, f, FV_INTERP_STAGE_GIVEN);
        vkCmdDispatchIndirect(cmd, f->pixels->indirect, f->pixels->indirect_offset);
        f->counters->dispatches++;
        /* every later dispatch's pipeline holds the dispatch arguments as a storage buffer (one shader), and the
         * scan rewrites them: after the indirect read */
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, CS, 0, 0, NULL, 0, NULL, 0, NULL);
    }
    /* with the light test, each pixel is decoded and lit once into shared memory (the light costs) */
    stage(it, f, q->light ? FV_INTERP_STAGE_LEAF_SHARED : FV_INTERP_STAGE_LEAF, groups(fv_interp_nodes_along(it->width, 1)),
          groups(fv_interp_nodes_along(it->height, 1)), 2);
    for (uint32_t k = 2; k <= it->pc.start_level; k++) {
        fv_vk_barrier_memory(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT, CS, RW);
        it->pc.level = k;
        stage(it, f, FV_INTERP_STAGE_NODE, groups(fv_interp_nodes_along(it->width, k)),
              groups(fv_interp_nodes_along(it->height, k)), 2);
    }
    it->pc.level = 0;
    if (t >= 0) fv_vk_timer_end(&it->timer, cmd, f->slot, t);
    t = fv_vk_timer_begin(&it->timer, cmd, f->slot, "classify");
    fv_vk_barrier_memory(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT, CS, RW);
    uint32_t tile_groups = (it->pc.tile_count + it->tiles_per_group - 1) / it->tiles_per_group;
    uint32_t gy = (tile_groups + it->pc.groups_x - 1) / it->pc.groups_x;
    stage(it, f, FV_INTERP_STAGE_COUNT, it->pc.groups_x, gy, 1);
    if (t >= 0) fv_vk_timer_end(&it->timer, cmd, f->slot, t);
    t = fv_vk_timer_begin(&it->timer, cmd, f->slot, "list");
    fv_vk_barrier_memory(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT, CS, RW);
    stage(it, f, FV_INTERP_STAGE_SCAN, 1, 1, 1);
    fv_vk_barrier_memory(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT, CS, RW);
    fv_images_use(f->images, cmd, it->level, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, VK_ACCESS_SHADER_READ_BIT});
    stage(it, f, FV_INTERP_STAGE_SCATTER, it->pc.groups_x, gy, 1);
    if (t >= 0) fv_vk_timer_end(&it->timer, cmd, f->slot, t);
    /* The list, its count and dispatch arguments -> the shade pass's indirect dispatch and reads; the count and
     * the stats -> the host after the fence. */
    fv_vk_barrier_memory(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT,
                    CS | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                    VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_HOST_READ_BIT);
    f->samples->active = true;
    it->recorded[f->slot] = true;
    fv_vk_label_end(it->vk, cmd);
}

static uint32_t interp_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    interp *it = state;
    uint32_t n = 0;
    double all = 2.0 * it->width * it->height;
    if (it->have_last)
        n = fv_pass_detail_add(out, n, cap, "fraction_shaded_filled_left", 3, (double)it->last[0] / all,
                       (double)it->last[1] / all, (double)it->last[2] / all);
    if (it->have_stage_ms)
        n = fv_pass_detail_add(out, n, cap, "stage_gpu_ms_pyramid_classify_list", 3, it->stage_ms[0], it->stage_ms[1],
                       it->stage_ms[2]);
    return fv_pass_detail_add(out, n, cap, "start_level_threshold_given", 3, it->pc.start_level, it->pc.threshold,
                      it->last_given ? 1.0 : 0.0);
}

const fv_pass fv_interp_pass = {
    .id = "interp",
    .plan = interp_plan,
    .init = interp_init,
    .prepare = interp_prepare,
    .record = interp_record,
    .fini = interp_fini,
    .details = interp_details,
    .makes = FV_PASS_NAMES("interp level"),
};

/* ---- "interp_fill": the interpolated pixels, or the view -------------------------------------------------------- */

typedef struct fill {
    fv_vk *vk;
    uint32_t width, height;
    fv_vk_compute cs;
    fv_image_id level;
    bool mark;               /* interp_fill_mark: the frame has a sample mask (foveation) */
    fv_image_id mask, blocks; /* its sample mask and block masks (mark only) */
    uint32_t block;          /* the block side the block masks were made for, px */
} fill;

static void fill_fini(void *state)
{
    fill *fl = state;
    if (!fl) return;
    fv_vk_compute_fini(fl->vk, &fl->cs);
    free(fl);
}

static fv_result fill_init(const fv_pass_env *env, void **out_state)
{
    fill *fl = calloc(1, sizeof *fl);
    if (!fl) return FV_ERR_NO_MEMORY;
    fl->vk = env->vk;
    fl->width = env->width;
    fl->height = env->height;
    fl->mark = env->plan->variant != 0;
    fl->block = env->plan->variant;
    const fv_vk_image *color = NULL;
    fv_result res = fv_images_find(env->images, "interp level", &fl->level); /* the interp pass (earlier) made it */
    if (res == FV_OK) res = fv_images_get(env->images, FV_IMAGE_COLOR, &color);
    /* the sample mask's owner (foveation, earlier in the frame) made them; the contract is by name and
     * fv_sample_mask_interface.h */
    if (res == FV_OK && fl->mark) res = fv_images_find(env->images, "fovea mask", &fl->mask);
    if (res == FV_OK && fl->mark) res = fv_images_find(env->images, "fovea blocks", &fl->blocks);
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorSetLayoutBinding b[FV_INTERP_FILL_MARK_BINDING_COUNT] = {
        {FV_INTERP_FILL_BINDING_LEVEL, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        {FV_INTERP_FILL_BINDING_COLOR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        {FV_INTERP_FILL_BINDING_MASK, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        {FV_INTERP_FILL_BINDING_BLOCKS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
    };
    VkDescriptorSetLayout shared[1] = {env->scene->set_layout};
    fv_vk_compute_desc cd = {.name = fl->mark ? "interp_fill_mark" : "interp_fill",
                             .code = fl->mark ? fv_spv_interp_fill_mark_comp : fv_spv_interp_fill_comp,
                             .code_size = fl->mark ? sizeof fv_spv_interp_fill_mark_comp : sizeof fv_spv_interp_fill_comp,
                             .shared_sets = shared, .shared_set_count = 1, .bindings = b,
                             .binding_count = fl->mark ? FV_INTERP_FILL_MARK_BINDING_COUNT : FV_INTERP_FILL_BINDING_COUNT,
                             .set_count = 1, .push_bytes = sizeof(struct fv_interp_fill_push)};
    if (res == FV_OK) res = fv_vk_compute_init(env->vk, &cd, &fl->cs);
    if (res != FV_OK) {
        FV_ERROR(MOD, "interpolation fill pass could not be created: %s", fv_result_str(res));
        fill_fini(fl);
        return res;
    }
    VkDescriptorType si = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    VkImageLayout gl = VK_IMAGE_LAYOUT_GENERAL;
    fv_vk_write_image(env->vk, fl->cs.sets[0], FV_INTERP_FILL_BINDING_LEVEL, si,
                      fv_images_image(env->images, fl->level)->view, VK_NULL_HANDLE, gl);
    fv_vk_write_image(env->vk, fl->cs.sets[0], FV_INTERP_FILL_BINDING_COLOR, si, color->view, VK_NULL_HANDLE, gl);
    if (fl->mark) {
        const fv_vk_image *mask = fv_images_image(env->images, fl->mask);
        const fv_vk_image *blocks = fv_images_image(env->images, fl->blocks);
        fv_vk_write_image(env->vk, fl->cs.sets[0], FV_INTERP_FILL_BINDING_MASK, si, mask->view, VK_NULL_HANDLE, gl);
        fv_vk_write_image(env->vk, fl->cs.sets[0], FV_INTERP_FILL_BINDING_BLOCKS, si, blocks->view, VK_NULL_HANDLE,
                          gl);
    }
    *out_state = fl;
    return FV_OK;
}

static void fill_record(void *state, const fv_pass_frame *f)
{
    fill *fl = state;
    if (!f->samples) return; /* a re-shaded pixel list: nothing was classified for it */
    VkCommandBuffer cmd = f->cmd;
    uint32_t B = fl->mark ? fl->block : 1u;
    struct fv_interp_fill_push pc = {
        .view = f->input->quality.debug_view == FV_DEBUG_VIEW_INTERP ? FV_INTERP_FILL_VIEW : 0u,
        .block = B, .block_words = (B * B + 31u) / 32u};
    fv_vk_label_begin(fl->vk, cmd, pc.view ? "interp_fill (view)" : fl->mark ? "interp_fill_mark" : "interp_fill");
    fv_images_use(f->images, cmd, fl->level, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, VK_ACCESS_SHADER_READ_BIT});
    fv_images_use(f->images, cmd, FV_IMAGE_COLOR, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    if (fl->mark) {
        fv_images_use(f->images, cmd, fl->mask, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
        fv_images_use(f->images, cmd, fl->blocks, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, CS, RW});
    }
    fv_vk_compute_bind(&fl->cs, cmd, 0, &f->scene_set, 1, 0, &pc);
    vkCmdDispatch(cmd, groups(fl->width), groups(fl->height), 2);
    f->counters->dispatches++;
    fv_vk_label_end(fl->vk, cmd);
}

const fv_pass fv_interp_fill_pass = {
    .id = "interp_fill",
    .plan = fill_plan,
    .init = fill_init,
    .record = fill_record,
    .fini = fill_fini,
    .needs = FV_PASS_NAMES("interp level"),
    .uses_if_made = FV_PASS_NAMES("fovea mask", "fovea blocks"), /* marks what foveation shaded */
};
