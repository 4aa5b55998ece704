/* @brief The present pass (see present.h). */
#include "present.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "present_comp.spv.h"
#include "fv_tone_curve.h"
#include "present_interface.h"

#define MOD "present"

_Static_assert(sizeof(struct fv_present_push) == 16, "fv_present_push layout");

typedef struct present {
    fv_vk *vk;
    uint32_t width, height;
    fv_vk_compute cs;
} present;

/* The tone curve is for radiance (colour, and the direct, gi and sss views); the data views (normal, depth, albedo,
 * visibility, ids...) keep their [0,1] values as they are (clamp). */
static bool radiance_view(fv_debug_view v)
{
    return v == FV_DEBUG_VIEW_NONE || v == FV_DEBUG_VIEW_DIRECT || v == FV_DEBUG_VIEW_GI || v == FV_DEBUG_VIEW_SSS;
}

static void present_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    out->enabled = true;
    out->variant = FV_TONEMAP_REINHARD_EXT;
    float exposure = ctx->quality->exposure;
    char ex[48] = "";
    if (exposure != 1.0f && isfinite(exposure) && exposure > 0.0f)
        snprintf(ex, sizeof ex, "exposure %g, ", (double)exposure);
    char tone[64];
    if (radiance_view(ctx->quality->debug_view)) snprintf(tone, sizeof tone, "tone curve (Reinhard extended, white %g)", FV_TONE_WHITE);
    else snprintf(tone, sizeof tone, "clamp (a data view)");
    snprintf(out->reason, sizeof out->reason, "%s%s + sRGB encode into a %s target", ex, tone,
             ctx->target ? ctx->target : "headless");
}

static void present_fini(void *state)
{
    present *pr = state;
    if (!pr) return;
    fv_vk_compute_fini(pr->vk, &pr->cs);
    free(pr);
}

static fv_result present_init(const fv_pass_env *env, void **out_state)
{
    present *pr = calloc(1, sizeof *pr);
    if (!pr) return FV_ERR_NO_MEMORY;
    pr->vk = env->vk;
    pr->width = env->width;
    pr->height = env->height;
    const fv_vk_image *linear, *display;
    fv_result res = fv_images_get(env->images, FV_IMAGE_COLOR, &linear);
    if (res == FV_OK) res = fv_images_get(env->images, FV_IMAGE_DISPLAY, &display);
    VkDescriptorSetLayoutBinding b[2] = {
        {FV_PRESENT_BINDING_LINEAR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {FV_PRESENT_BINDING_OUTPUT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    uint32_t tonemap = env->plan ? env->plan->variant : FV_TONEMAP_REINHARD_EXT;
    fv_vk_compute_desc cd = {.name = "present (tonemap + sRGB)", .code = fv_spv_present_comp,
                             .code_size = sizeof fv_spv_present_comp, .bindings = b, .binding_count = 2,
                             .set_count = 1, .push_bytes = sizeof(struct fv_present_push), .spec = &tonemap,
                             .spec_count = 1};
    if (res == FV_OK) res = fv_vk_compute_init(env->vk, &cd, &pr->cs);
    if (res != FV_OK) {
        FV_ERROR(MOD, "present pass could not be created: %s", fv_result_str(res));
        present_fini(pr);
        return res;
    }
    fv_vk_write_image(env->vk, pr->cs.sets[0], FV_PRESENT_BINDING_LINEAR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                      linear->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    fv_vk_write_image(env->vk, pr->cs.sets[0], FV_PRESENT_BINDING_OUTPUT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                      display->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    *out_state = pr;
    return FV_OK;
}

static void present_record(void *state, const fv_pass_frame *f)
{
    present *pr = state;
    VkCommandBuffer cmd = f->cmd;
    fv_vk_label_begin(pr->vk, cmd, "present (tonemap + sRGB)");
    VkPipelineStageFlags cs = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    fv_images_use(f->images, cmd, FV_IMAGE_COLOR, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, cs, VK_ACCESS_SHADER_READ_BIT});
    fv_images_use(f->images, cmd, FV_IMAGE_DISPLAY,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, cs, VK_ACCESS_SHADER_WRITE_BIT});
    float exposure = f->input ? f->input->quality.exposure : 1.0f;
    if (!(isfinite(exposure) && exposure > 0.0f)) exposure = 1.0f;
    bool radiance = radiance_view(f->input ? f->input->quality.debug_view : FV_DEBUG_VIEW_NONE);
    struct fv_present_push pc = {.exposure = exposure, .width = pr->width, .height = pr->height,
                                 .tone = radiance ? 1u : 0u};
    fv_vk_compute_bind(&pr->cs, cmd, 0, NULL, 0, 0, &pc);
    vkCmdDispatch(cmd, (pr->width + FV_PRESENT_GROUP_X - 1) / FV_PRESENT_GROUP_X,
                  (pr->height + FV_PRESENT_GROUP_Y - 1) / FV_PRESENT_GROUP_Y, 2);
    f->counters->dispatches++;
    fv_vk_label_end(pr->vk, cmd);
}

const fv_pass fv_present_pass = {
    .id = "present",
    .flags = FV_PASS_REPLAYS_ON_PIXELS,
    .plan = present_plan,
    .init = present_init,
    .record = present_record,
    .fini = present_fini,
};
