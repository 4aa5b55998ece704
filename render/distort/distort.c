/* @brief The distortion pass (see distort.h). */
#include "distort.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "distort_comp.spv.h"
#include "distort_interface.h"

#define MOD "distort"

_Static_assert(sizeof(struct fv_distort_push) == 112, "fv_distort_push layout");
_Static_assert(offsetof(struct fv_distort_push, frustum) == 64, "fv_distort_push frustum offset");
_Static_assert(offsetof(struct fv_distort_push, width) == 96, "fv_distort_push width offset");

typedef struct distort {
    fv_vk *vk;
    uint32_t width, height;
    fv_vk_compute cs;
    VkSampler sampler;
    fv_images *images;
    fv_image_id source; /* the sampled copy of the display image */
    bool have_source;
} distort;

static void distort_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    const fv_quality_distort *d = &ctx->quality->distort;
    if (!d->enabled) {
        snprintf(out->reason, sizeof out->reason, "off — distort.enabled is off: the undistorted eye images");
        out->enabled = false;
        return;
    }
    if (!d->lens.valid) {
        snprintf(out->reason, sizeof out->reason, "off — no HMD lens in the frame (fovea run --hmd PROFILE)");
        out->enabled = false;
        return;
    }
    const fv_lens *l = &d->lens;
    double ca = fmax(fabs(l->aberration[0] - 1.0), fabs(l->aberration[2] - 1.0)) * 100.0;
    out->enabled = true;
    char buf[2 * FV_PASS_REASON_MAX];
    snprintf(buf, sizeof buf, "lens pre-distortion: d(r) = %.3g + %.3g r + %.3g r^2 + %.3g r^3, chromatic +-%.2g%%, "
             "bilinear%s", (double)l->k[0], (double)l->k[1], (double)l->k[2], (double)l->k[3], ca,
             l->visible_r > 0 ? ", black past the visible radius" : "");
    memcpy(out->reason, buf, sizeof out->reason - 1);
    out->reason[sizeof out->reason - 1] = 0;
}

static void distort_fini(void *state)
{
    distort *ds = state;
    if (!ds) return;
    fv_vk_compute_fini(ds->vk, &ds->cs);
    if (ds->sampler) vkDestroySampler(ds->vk->device, ds->sampler, NULL);
    if (ds->have_source) fv_images_release(ds->images, ds->source);
    free(ds);
}

static fv_result distort_init(const fv_pass_env *env, void **out_state)
{
    distort *ds = calloc(1, sizeof *ds);
    if (!ds) return FV_ERR_NO_MEMORY;
    ds->vk = env->vk;
    ds->width = env->width;
    ds->height = env->height;
    ds->images = env->images;
    const fv_vk_image *display, *source = NULL;
    fv_result res = fv_images_get(env->images, FV_IMAGE_DISPLAY, &display);
    /* The copy is of sRGB format: the sampler decodes before filtering, so the bilinear blend is of linear light. */
    fv_vk_image_desc sd = {.format = VK_FORMAT_R8G8B8A8_SRGB, .layers = 2,
                           .usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                           .name = "distort source (sRGB copy of the display)"};
    if (res == FV_OK && !fv_vk_format_supports(env->vk, sd.format, VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT |
                                                                       VK_FORMAT_FEATURE_TRANSFER_DST_BIT)) {
        FV_ERROR(MOD, "the device cannot filter R8G8B8A8_SRGB images linearly");
        res = FV_ERR_UNSUPPORTED;
    }
    if (res == FV_OK) res = fv_images_scratch(env->images, &sd, &ds->source);
    if (res == FV_OK) {
        ds->have_source = true;
        source = fv_images_image(env->images, ds->source);
        res = fv_vk_sampler_create(env->vk, true, false, "distort sampler (linear, clamp)", &ds->sampler);
    }
    VkDescriptorSetLayoutBinding b[2] = {
        {FV_DISTORT_BINDING_SOURCE, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {FV_DISTORT_BINDING_OUTPUT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    fv_vk_compute_desc cd = {.name = "distort (lens + chromatic aberration)", .code = fv_spv_distort_comp,
                             .code_size = sizeof fv_spv_distort_comp, .bindings = b, .binding_count = 2,
                             .set_count = 1, .push_bytes = sizeof(struct fv_distort_push)};
    if (res == FV_OK) res = fv_vk_compute_init(env->vk, &cd, &ds->cs);
    if (res != FV_OK) {
        FV_ERROR(MOD, "distortion pass could not be created: %s", fv_result_str(res));
        distort_fini(ds);
        return res;
    }
    fv_vk_write_image(env->vk, ds->cs.sets[0], FV_DISTORT_BINDING_SOURCE, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                      source->view, ds->sampler, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    fv_vk_write_image(env->vk, ds->cs.sets[0], FV_DISTORT_BINDING_OUTPUT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                      display->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    *out_state = ds;
    return FV_OK;
}

/* A frustum tangent the shader can divide by: finite and > 0, else the HMD default's 1. */
static float tan_or_1(float t) { return isfinite(t) && t > 1e-6f && t < 1e6f ? t : 1.0f; }

static void distort_record(void *state, const fv_pass_frame *f)
{
    distort *ds = state;
    const fv_lens *l = &f->input->quality.distort.lens;
    if (!l->valid) return; /* planned with a lens; a frame without one shows the undistorted image */
    VkCommandBuffer cmd = f->cmd;
    fv_vk_label_begin(ds->vk, cmd, "distort (lens + chromatic aberration)");
    VkPipelineStageFlags tr = VK_PIPELINE_STAGE_TRANSFER_BIT, cs = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    /* The copy reads what the present pass wrote (RAW), then compute writes the display over it (WAR). */
    fv_images_use(f->images, cmd, FV_IMAGE_DISPLAY,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, tr, VK_ACCESS_TRANSFER_READ_BIT});
    fv_images_use(f->images, cmd, ds->source,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, tr, VK_ACCESS_TRANSFER_WRITE_BIT});
    VkImageCopy region = {.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 2},
                          .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 2},
                          .extent = {ds->width, ds->height, 1}};
    vkCmdCopyImage(cmd, fv_images_image(f->images, FV_IMAGE_DISPLAY)->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                   fv_images_image(f->images, ds->source)->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    fv_images_use(f->images, cmd, ds->source,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, cs, VK_ACCESS_SHADER_READ_BIT});
    fv_images_use(f->images, cmd, FV_IMAGE_DISPLAY,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, cs, VK_ACCESS_SHADER_WRITE_BIT});
    struct fv_distort_push pc;
    memset(&pc, 0, sizeof pc);
    pc.centre_m.x = l->centre_m[0][0];
    pc.centre_m.y = l->centre_m[0][1];
    pc.centre_m.z = l->centre_m[1][0];
    pc.centre_m.w = l->centre_m[1][1];
    pc.k.x = l->k[0];
    pc.k.y = l->k[1];
    pc.k.z = l->k[2];
    pc.k.w = l->k[3];
    pc.aberration.x = l->aberration[0];
    pc.aberration.y = l->aberration[1];
    pc.aberration.z = l->aberration[2];
    pc.aberration.w = l->visible_r;
    pc.geometry.x = l->viewport_m[0];
    pc.geometry.y = l->viewport_m[1];
    pc.geometry.z = l->warp_m;
    pc.geometry.w = l->tan_per_m;
    for (int e = 0; e < 2; e++) {
        const fv_eye_view *v = &f->input->eye[e];
        /* fv_eye_view holds signed tangents (left and down negative); the shader takes the four extents */
        pc.frustum[e].x = tan_or_1(-v->tan_left);
        pc.frustum[e].y = tan_or_1(v->tan_right);
        pc.frustum[e].z = tan_or_1(v->tan_up);
        pc.frustum[e].w = tan_or_1(-v->tan_down);
    }
    pc.width = ds->width;
    pc.height = ds->height;
    fv_vk_compute_bind(&ds->cs, cmd, 0, NULL, 0, 0, &pc);
    vkCmdDispatch(cmd, (ds->width + FV_DISTORT_GROUP_X - 1) / FV_DISTORT_GROUP_X,
                  (ds->height + FV_DISTORT_GROUP_Y - 1) / FV_DISTORT_GROUP_Y, 2);
    f->counters->dispatches++;
    fv_vk_label_end(ds->vk, cmd);
}

const fv_pass fv_distort_pass = {
    .id = "distort",
    .flags = FV_PASS_REPLAYS_ON_PIXELS,
    .plan = distort_plan,
    .init = distort_init,
    .record = distort_record,
    .fini = distort_fini,
    .makes = FV_PASS_NAMES("distort source (sRGB copy of the display)"),
};
