/* @brief The reduced-rate GI gather (see gi_gather.h). */
#include "gi_gather.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_gi_interface.glsl"
#include "gi_gather_comp.spv.h"
#include "gi_gather_interface.h"

#define MOD "gi_gather"
#define OUTPUTS 1

_Static_assert(FV_GI_GATHER_BINDING_NORMAL == FV_GI_GATHER_BINDING_DEPTH + 1 &&
                   FV_GI_GATHER_BINDING_ALBEDO == FV_GI_GATHER_BINDING_DEPTH + 2 &&
                   FV_GI_GATHER_BINDING_MATERIAL == FV_GI_GATHER_BINDING_DEPTH + 3,
               "fv_images_bind_gbuffer writes depth, normal, albedo, material in a row");
_Static_assert(FV_SHADE_INPUTS_SLOT_IMAGES >= OUTPUTS, "the GI slot holds the image");

typedef struct gi_gather {
    fv_vk *vk;
    fv_shade_inputs *inputs;
    uint32_t width, height, rate, low_w, low_h;
    fv_vk_compute cs;
    VkSampler nearest;
    fv_images *images;
    fv_image_id out[OUTPUTS];
    bool bound;
} gi_gather;

/* GI runs (the GI pass's own conditions: a spot or directional light, gi.enabled) and the rate is reduced. The
 * variant: the rate and the gather mode the pipeline is specialised for. */
static void gi_gather_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    const fv_scene *s = ctx->scene;
    const fv_quality_gi *q = &ctx->quality->gi;
    uint32_t r = fv_gi_rate_factor((uint32_t)q->rate);
    uint32_t lit = 0;
    for (uint32_t l = 0; s && l < s->light_count; l++) lit += s->lights[l].type != FV_LIGHT_POINT;
    out->enabled = false;
    if (!q->enabled || !lit) {
        snprintf(out->reason, sizeof out->reason, "off — no GI this frame (%s)",
                 !q->enabled ? "gi.enabled is false" : "no spot or directional light");
        return;
    }
    if (r == 1) {
        snprintf(out->reason, sizeof out->reason, "off — gi.rate is full: every shaded pixel gathers its own");
        return;
    }
    out->enabled = true;
    out->variant = r | ((uint32_t)q->mode << 8);
    snprintf(out->reason, sizeof out->reason,
             "GI gathered once per %ux%u block (1/%u of the pixels), joint-bilateral upsample in shading (depth "
             "and normal guided; unmatched pixels gather their own)",
             r, r, r * r);
}

static void gi_gather_fini(void *state)
{
    gi_gather *g = state;
    if (!g) return;
    /* the GPU is idle: the upsample reads the dummies again (which match no pixel: every pixel gathers) */
    if (g->bound)
        for (uint32_t i = 0; i < OUTPUTS; i++)
            if (fv_shade_inputs_bind_image(g->inputs, g->images, FV_GI_BINDING_LOW_IRRADIANCE + i, FV_IMAGE_MAX,
                                           false) != FV_OK)
                FV_ERROR(MOD, "the GI image slot %u could not be reset to the dummy", i);
    for (uint32_t i = 0; i < OUTPUTS; i++)
        if (g->out[i] != FV_IMAGE_MAX) fv_images_release(g->images, g->out[i]);
    fv_vk_compute_fini(g->vk, &g->cs);
    if (g->nearest) vkDestroySampler(g->vk->device, g->nearest, NULL);
    free(g);
}

static fv_result gi_gather_init(const fv_pass_env *env, void **out_state)
{
    gi_gather *g = calloc(1, sizeof *g);
    if (!g) return FV_ERR_NO_MEMORY;
    g->vk = env->vk;
    g->inputs = env->shade_inputs;
    g->images = env->images;
    g->width = env->width;
    g->height = env->height;
    for (uint32_t i = 0; i < OUTPUTS; i++) g->out[i] = FV_IMAGE_MAX;
    uint32_t variant = env->plan ? env->plan->variant : 4u;
    g->rate = variant & 0xffu;
    if (g->rate != 2u && g->rate != 4u && g->rate != 8u) g->rate = 4u;
    int32_t mode = (int32_t)(variant >> 8);
    g->low_w = (g->width + g->rate - 1) / g->rate;
    g->low_h = (g->height + g->rate - 1) / g->rate;
    if (!g->low_w) g->low_w = 1;
    if (!g->low_h) g->low_h = 1;
    fv_vk *vk = env->vk;
    fv_result res = fv_images_get_gbuffer(env->images);
    if (res == FV_OK) res = fv_vk_sampler_create(vk, false, false, "gi gather nearest sampler", &g->nearest);
    static const char *const names[OUTPUTS] = {"gi low irradiance"};
    for (uint32_t i = 0; res == FV_OK && i < OUTPUTS; i++) {
        fv_vk_image_desc d = {.width = g->low_w, .height = g->low_h, .layers = 2, .array = true,
                              .format = VK_FORMAT_R32G32B32A32_SFLOAT,
                              .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                       VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                              .name = names[i]};
        res = fv_images_scratch(env->images, &d, &g->out[i]);
    }
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorType cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, sto = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    VkDescriptorSetLayoutBinding b[FV_GI_GATHER_BINDING_COUNT] = {
        {FV_GI_GATHER_BINDING_DEPTH, cis, 1, cs, NULL},      {FV_GI_GATHER_BINDING_NORMAL, cis, 1, cs, NULL},
        {FV_GI_GATHER_BINDING_ALBEDO, cis, 1, cs, NULL},     {FV_GI_GATHER_BINDING_MATERIAL, cis, 1, cs, NULL},
        {FV_GI_GATHER_BINDING_OUT_E, sto, 1, cs, NULL},
    };
    /* specialised as the shading pass is: this gather mode only, the rate 1 (the gather alone) */
    uint32_t spec[5] = {0};
    spec[FV_SPEC_ID_GI_MODE] = (uint32_t)(mode >= 0 && mode <= FV_GI_EXACT ? mode : FV_SPEC_GI_ANY);
    spec[FV_SPEC_ID_SSS] = 0;
    spec[FV_SPEC_ID_SHADOWS] = 0;
    spec[FV_SPEC_ID_GI_RATE] = 1;
    _Static_assert(FV_SPEC_ID_GI_RATE == 4, "spec[] holds ids 0..4");
    VkDescriptorSetLayout shared[2] = {env->scene->set_layout, env->shade_inputs->layout};
    _Static_assert(FV_SCENE_SET == 0 && FV_SHADE_INPUTS_SET == 1 && FV_GI_GATHER_SET == 2, "gi_gather's set order");
    fv_vk_compute_desc cd = {.name = "gi gather", .code = fv_spv_gi_gather_comp,
                             .code_size = sizeof fv_spv_gi_gather_comp, .shared_sets = shared, .shared_set_count = 2,
                             .bindings = b, .binding_count = FV_GI_GATHER_BINDING_COUNT, .set_count = 1,
                             .push_bytes = sizeof(struct fv_gi_gather_push), .spec = spec, .spec_count = 5};
    if (res == FV_OK) res = fv_vk_compute_init(vk, &cd, &g->cs);
    if (res == FV_OK) {
        fv_images_bind_gbuffer(env->images, g->cs.sets[0], FV_GI_GATHER_BINDING_DEPTH, g->nearest);
        for (uint32_t i = 0; i < OUTPUTS; i++)
            fv_vk_write_image(vk, g->cs.sets[0], FV_GI_GATHER_BINDING_OUT_E + i, sto,
                              fv_images_image(env->images, g->out[i])->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    }
    for (uint32_t i = 0; res == FV_OK && i < OUTPUTS; i++)
        res = fv_shade_inputs_bind_image(env->shade_inputs, env->images, FV_GI_BINDING_LOW_IRRADIANCE + i, g->out[i],
                                         false);
    g->bound = true;
    if (res != FV_OK) {
        FV_ERROR(MOD, "the reduced-rate GI gather could not be created: %s", fv_result_str(res));
        gi_gather_fini(g);
        return res;
    }
    *out_state = g;
    return FV_OK;
}

static void gi_gather_record(void *state, const fv_pass_frame *f)
{
    gi_gather *g = state;
    VkCommandBuffer cmd = f->cmd;
    fv_vk_label_begin(g->vk, cmd, "gi gather (reduced rate)");
    VkPipelineStageFlags cs = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    fv_images_use_gbuffer(f->images, cmd, cs);
    for (uint32_t i = 0; i < OUTPUTS; i++)
        fv_images_use(f->images, cmd, g->out[i],
                      (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, cs, VK_ACCESS_SHADER_WRITE_BIT});
    struct fv_gi_gather_push pc = {.dims = {g->rate, g->low_w, g->low_h, 0}};
    VkDescriptorSet shared[2] = {f->scene_set, fv_shade_inputs_set(f->shade_inputs, f->slot)};
    fv_vk_compute_bind(&g->cs, cmd, 0, shared, 2, 0, &pc);
    vkCmdDispatch(cmd, (g->low_w + FV_GI_GATHER_GROUP_X - 1) / FV_GI_GATHER_GROUP_X,
                  (g->low_h + FV_GI_GATHER_GROUP_Y - 1) / FV_GI_GATHER_GROUP_Y, 2);
    f->counters->dispatches++;
    fv_vk_label_end(g->vk, cmd);
}

static uint32_t gi_gather_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    gi_gather *g = state;
    return fv_pass_detail_add(out, 0, cap, "rate_blocks_per_eye", 3, g->rate, (double)g->low_w, (double)g->low_h);
}

const fv_pass fv_gi_gather_pass = {
    .id = "gi_gather",
    .plan = gi_gather_plan,
    .init = gi_gather_init,
    .record = gi_gather_record,
    .fini = gi_gather_fini,
    .details = gi_gather_details,
    .makes = FV_PASS_NAMES("gi low irradiance"),
};
