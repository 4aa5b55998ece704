/* @brief The debug-view pass (see debug.h). */
#include "debug.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "debug_comp.spv.h"
#include "debug_fovea_comp.spv.h"
#include "debug_interface.h"
#include "fv_shade_inputs_interface.h"

#define MOD "debug"

typedef struct debug {
    fv_vk *vk;
    uint32_t width, height;
    fv_vk_compute cs;
    VkSampler nearest;
    bool fovea;                 /* a foveation view (debug_fovea.comp) */
    fv_image_id prob, mask;     /* its images, made by the fovea pass */
    fv_image_id voronoi;        /* the reconstruct pass's (FV_IMAGE_MAX for the other views) */
} debug;

static void debug_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    static const char *const what[FV_DEBUG_VIEW_COUNT] = {
        "", "the G-buffer normal", "the predicted gaze", "direct light only", "light 0's visibility",
        "which of light 0's shadow maps holds each pixel", "the G-buffer albedo", "the G-buffer depth",
        "foveation's sample mask (blue ring: the gaze)", "foveation's sampling probability",
        "the sample each pixel was filled from", "indirect light only", "the GI cut over the reflective shadow map",
        "the subsurface term alone", "the level each pixel was shaded or filled at"};
    fv_debug_view v = ctx->quality->debug_view;
    if (v == FV_DEBUG_VIEW_NONE || (unsigned)v >= FV_DEBUG_VIEW_COUNT) {
        out->enabled = false;
        snprintf(out->reason, sizeof out->reason, "off — no debug view asked for");
        return;
    }
    _Static_assert(FV_DEBUG_VIEW_DEPTH == FV_GPU_DEBUG_VIEW_DEPTH && FV_DEBUG_VIEW_GAZE == FV_GPU_DEBUG_VIEW_GAZE &&
                       FV_DEBUG_VIEW_SAMPLES == FV_GPU_DEBUG_VIEW_SAMPLES && FV_DEBUG_VIEW_PROB == FV_GPU_DEBUG_VIEW_PROB,
                   "view numbers agree between C and GLSL");
    if (v == FV_DEBUG_VIEW_INTERP) { /* drawn by the interp_fill pass, which holds each pixel's level */
        out->enabled = false;
        snprintf(out->reason, sizeof out->reason, "off — view 'interp' is drawn by the interp_fill pass%s",
                 ctx->quality->interp.enabled ? "" : " (needs interp.enabled)");
        return;
    }
    if (v > FV_DEBUG_VIEW_VORONOI && v != FV_DEBUG_VIEW_GI && v != FV_DEBUG_VIEW_CLUSTERS && v != FV_DEBUG_VIEW_SSS) { /* views of passes still being built; each owner replaces its line here */
        out->enabled = false;
        snprintf(out->reason, sizeof out->reason, "off — debug view '%s' is not implemented yet", fv_debug_view_name(v));
        return;
    }
    if ((v == FV_DEBUG_VIEW_GI || v == FV_DEBUG_VIEW_CLUSTERS) && !ctx->quality->gi.enabled) {
        out->enabled = false;
        snprintf(out->reason, sizeof out->reason, "off — debug view '%s' needs gi.enabled", fv_debug_view_name(v));
        return;
    }
    if ((v == FV_DEBUG_VIEW_SAMPLES || v == FV_DEBUG_VIEW_PROB || v == FV_DEBUG_VIEW_VORONOI) &&
        !ctx->quality->fovea.enabled) {
        out->enabled = false;
        snprintf(out->reason, sizeof out->reason, "off — debug view '%s' needs fovea.enabled", fv_debug_view_name(v));
        return;
    }
    out->enabled = true;
    out->variant = (uint32_t)v;
    snprintf(out->reason, sizeof out->reason, "debug view '%s': %s replaces the shading", fv_debug_view_name(v), what[v]);
}

static void debug_fini(void *state)
{
    debug *d = state;
    if (!d) return;
    fv_vk_compute_fini(d->vk, &d->cs);
    if (d->nearest) vkDestroySampler(d->vk->device, d->nearest, NULL);
    free(d);
}

static fv_result debug_init(const fv_pass_env *env, void **out_state)
{
    debug *d = calloc(1, sizeof *d);
    if (!d) return FV_ERR_NO_MEMORY;
    d->vk = env->vk;
    d->width = env->width;
    d->height = env->height;
    const fv_vk_image *color;
    fv_result res = fv_images_get_gbuffer(env->images);
    if (res == FV_OK) res = fv_images_get(env->images, FV_IMAGE_COLOR, &color);
    if (res == FV_OK) res = fv_vk_sampler_create(env->vk, false, false, "debug nearest sampler", &d->nearest);
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorType cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    VkDescriptorSetLayoutBinding b[FV_DEBUG_BINDING_COUNT] = {
        {FV_DEBUG_BINDING_DEPTH, cis, 1, cs, NULL},
        {FV_DEBUG_BINDING_NORMAL, cis, 1, cs, NULL},
        {FV_DEBUG_BINDING_ALBEDO, cis, 1, cs, NULL},
        {FV_DEBUG_BINDING_MATERIAL, cis, 1, cs, NULL},
        {FV_DEBUG_BINDING_COLOR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
    };
    uint32_t view = env->plan ? env->plan->variant : FV_GPU_DEBUG_VIEW_NORMAL;
    if (view == FV_GPU_DEBUG_VIEW_SAMPLES || view == FV_GPU_DEBUG_VIEW_PROB || view == FV_GPU_DEBUG_VIEW_VORONOI) {
        d->fovea = true;
        if (res == FV_OK) res = fv_images_find(env->images, "fovea prob", &d->prob); /* the fovea pass runs earlier */
        if (res == FV_OK) res = fv_images_find(env->images, "fovea mask", &d->mask);
        if (res == FV_OK) res = fv_images_find(env->images, "fovea voronoi", &d->voronoi); /* reconstruct, earlier */
        VkDescriptorSetLayoutBinding fb[FV_DEBUG_FOVEA_BINDING_COUNT] = {
            {FV_DEBUG_FOVEA_BINDING_PROB, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
            {FV_DEBUG_FOVEA_BINDING_MASK, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
            {FV_DEBUG_FOVEA_BINDING_COLOR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
            {FV_DEBUG_FOVEA_BINDING_VORONOI, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        };
        VkDescriptorSetLayout scene_only[1] = {env->scene->set_layout};
        fv_vk_compute_desc fd = {.name = "debug view (fovea)", .code = fv_spv_debug_fovea_comp,
                                 .code_size = sizeof fv_spv_debug_fovea_comp, .shared_sets = scene_only,
                                 .shared_set_count = 1, .bindings = fb, .binding_count = FV_DEBUG_FOVEA_BINDING_COUNT,
                                 .set_count = 1, .spec = &view, .spec_count = 1};
        if (res == FV_OK) res = fv_vk_compute_init(env->vk, &fd, &d->cs);
        if (res != FV_OK) {
            FV_ERROR(MOD, "debug view pass could not be created: %s", fv_result_str(res));
            debug_fini(d);
            return res;
        }
        VkDescriptorType si = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        fv_vk_write_image(env->vk, d->cs.sets[0], FV_DEBUG_FOVEA_BINDING_PROB, si,
                          fv_images_image(env->images, d->prob)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_image(env->vk, d->cs.sets[0], FV_DEBUG_FOVEA_BINDING_MASK, si,
                          fv_images_image(env->images, d->mask)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_image(env->vk, d->cs.sets[0], FV_DEBUG_FOVEA_BINDING_COLOR, si, color->view, VK_NULL_HANDLE,
                          VK_IMAGE_LAYOUT_GENERAL);
        fv_vk_write_image(env->vk, d->cs.sets[0], FV_DEBUG_FOVEA_BINDING_VORONOI, si,
                          fv_images_image(env->images, d->voronoi)->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        *out_state = d;
        return FV_OK;
    }
    VkDescriptorSetLayout shared[2] = {env->scene->set_layout, env->shade_inputs->layout};
    _Static_assert(FV_SCENE_SET == 0 && FV_SHADE_INPUTS_SET == 1 && FV_DEBUG_SET == 2, "debug's set order");
    fv_vk_compute_desc cd = {.name = "debug view", .code = fv_spv_debug_comp, .code_size = sizeof fv_spv_debug_comp,
                             .shared_sets = shared, .shared_set_count = 2, .bindings = b,
                             .binding_count = FV_DEBUG_BINDING_COUNT, .set_count = 1, .spec = &view, .spec_count = 1};
    if (res == FV_OK) res = fv_vk_compute_init(env->vk, &cd, &d->cs);
    if (res != FV_OK) {
        FV_ERROR(MOD, "debug view pass could not be created: %s", fv_result_str(res));
        debug_fini(d);
        return res;
    }
    fv_images_bind_gbuffer(env->images, d->cs.sets[0], FV_DEBUG_BINDING_DEPTH, d->nearest);
    fv_vk_write_image(env->vk, d->cs.sets[0], FV_DEBUG_BINDING_COLOR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, color->view,
                      VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    *out_state = d;
    return FV_OK;
}

static void debug_record(void *state, const fv_pass_frame *f)
{
    debug *d = state;
    VkCommandBuffer cmd = f->cmd;
    fv_vk_label_begin(d->vk, cmd, "debug view");
    VkPipelineStageFlags cs = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    if (d->fovea) {
        fv_images_use(f->images, cmd, d->prob, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, cs, VK_ACCESS_SHADER_READ_BIT});
        fv_images_use(f->images, cmd, d->mask, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, cs, VK_ACCESS_SHADER_READ_BIT});
        fv_images_use(f->images, cmd, d->voronoi,
                      (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, cs, VK_ACCESS_SHADER_READ_BIT});
        fv_images_use(f->images, cmd, FV_IMAGE_COLOR,
                      (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, cs, VK_ACCESS_SHADER_WRITE_BIT});
        fv_vk_compute_bind(&d->cs, cmd, 0, &f->scene_set, 1, 0, NULL);
        vkCmdDispatch(cmd, (d->width + FV_DEBUG_GROUP_X - 1) / FV_DEBUG_GROUP_X,
                      (d->height + FV_DEBUG_GROUP_Y - 1) / FV_DEBUG_GROUP_Y, 2);
        f->counters->dispatches++;
        fv_vk_label_end(d->vk, cmd);
        return;
    }
    fv_images_use_gbuffer(f->images, cmd, cs);
    fv_shade_inputs_use(f->shade_inputs, f->images, cmd, cs);
    fv_images_use(f->images, cmd, FV_IMAGE_COLOR, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, cs, VK_ACCESS_SHADER_WRITE_BIT});
    /* Its own set binds only images that stay put; the scene's and the shading inputs' sets are the slot's. */
    VkDescriptorSet shared[2] = {f->scene_set, fv_shade_inputs_set(f->shade_inputs, f->slot)};
    fv_vk_compute_bind(&d->cs, cmd, 0, shared, 2, 0, NULL);
    vkCmdDispatch(cmd, (d->width + FV_DEBUG_GROUP_X - 1) / FV_DEBUG_GROUP_X,
                  (d->height + FV_DEBUG_GROUP_Y - 1) / FV_DEBUG_GROUP_Y, 2);
    f->counters->dispatches++;
    fv_vk_label_end(d->vk, cmd);
}

const fv_pass fv_debug_pass = {
    .id = "debug",
    .flags = FV_PASS_REPLAYS_ON_PIXELS,
    .plan = debug_plan,
    .init = debug_init,
    .record = debug_record,
    .fini = debug_fini,
    .uses_if_made = FV_PASS_NAMES("fovea prob", "fovea mask", "fovea voronoi"), /* its fovea views */
};
