/* @brief The overlay pass (see overlay.h). */
#include "overlay.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "overlay_comp.spv.h"
#include "overlay_interface.h"

#define MOD "overlay"

_Static_assert(sizeof(struct fv_overlay_push) == 112, "fv_overlay_push layout");
_Static_assert(sizeof(struct fv_overlay_push) <= 128, "push constants fit the guaranteed 128 bytes");

typedef struct overlay {
    fv_vk *vk;
    uint32_t width, height;
    fv_vk_compute cs;
    bool fovea;          /* the foveal boundary: foveation's probability image is bound */
    fv_image_id prob;
    fv_vk_image dummy;   /* 1x1 stand-in for the probability image when foveation is off */
} overlay;

static void overlay_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    if (!ctx->quality->overlay) {
        out->enabled = false;
        snprintf(out->reason, sizeof out->reason, "off — no overlay asked for (--overlay)");
        return;
    }
    out->enabled = true;
    out->variant = ctx->quality->fovea.enabled ? 1u : 0u;
    snprintf(out->reason, sizeof out->reason, "the predicted gaze point and its uncertainty ring%s, over the display "
             "image", out->variant ? " and the foveal boundary" : "");
}

void fv_overlay_push_from_input(const fv_frame_input *in, uint32_t width, uint32_t height, bool fovea,
                                struct fv_overlay_push *out)
{
    memset(out, 0, sizeof *out);
    out->width = width;
    out->height = height;
    out->flags = fovea ? FV_OVERLAY_FLAG_FOVEA : 0u;
    for (int e = 0; e < 2; e++) {
        const fv_eye_view *v = &in->eye[e];
        bool tans = isfinite(v->tan_left) && isfinite(v->tan_right) && isfinite(v->tan_up) && isfinite(v->tan_down);
        out->tan[e] = tans ? (fv_overlay_vec4){v->tan_left, v->tan_right, v->tan_up, v->tan_down}
                           : (fv_overlay_vec4){-1.0f, 1.0f, 1.0f, -1.0f};
        const fv_eye_gaze *g = &in->gaze[e];
        fv_vec3 d = g->dir_eye;
        /* Scale by the largest component first, so that neither huge nor tiny directions over/underflow. */
        float m = fmaxf(fabsf(d.x), fmaxf(fabsf(d.y), fabsf(d.z)));
        bool valid = g->valid && fv_v3_isfinite(d) && m > 0.0f && isfinite(m);
        if (valid) {
            d = fv_v3_normalize_or(fv_v3_scale(d, 1.0f / m), fv_v3(0, 0, 0));
            valid = fv_v3_len(d) > 0.5f;
        }
        out->gaze[e] = valid ? (fv_overlay_vec4){d.x, d.y, d.z, 1.0f} : (fv_overlay_vec4){0.0f, 0.0f, -1.0f, 0.0f};
        float u = isfinite(g->uncertainty_deg) ? fv_clampf((float)fv_deg_to_rad(g->uncertainty_deg), 0.0f, (float)FV_PI)
                                               : (float)FV_PI;
        out->info[e] = (fv_overlay_vec4){valid ? u : (float)FV_PI, 0.0f, 0.0f, 0.0f};
    }
}

static void overlay_fini(void *state)
{
    overlay *o = state;
    if (!o) return;
    fv_vk_compute_fini(o->vk, &o->cs);
    fv_vk_image_destroy(o->vk, &o->dummy);
    free(o);
}

static fv_result overlay_init(const fv_pass_env *env, void **out_state)
{
    overlay *o = calloc(1, sizeof *o);
    if (!o) return FV_ERR_NO_MEMORY;
    o->vk = env->vk;
    o->width = env->width;
    o->height = env->height;
    const fv_vk_image *display = NULL, *prob = NULL;
    fv_result res = fv_images_get(env->images, FV_IMAGE_DISPLAY, &display);
    /* The fovea pass runs earlier in the table, so its image exists once it started. */
    if (res == FV_OK && env->plan && env->plan->variant == 1 && fv_images_find(env->images, "fovea prob", &o->prob) == FV_OK) {
        o->fovea = true;
        prob = fv_images_image(env->images, o->prob);
    }
    if (res == FV_OK && !o->fovea) {
        fv_vk_image_desc dd = {.width = 1, .height = 1, .layers = 2, .format = VK_FORMAT_R32_SFLOAT,
                               .usage = VK_IMAGE_USAGE_STORAGE_BIT, .name = "overlay: no foveation (dummy)"};
        res = fv_vk_image_create(env->vk, &dd, &o->dummy);
        if (res == FV_OK) res = fv_vk_image_set_layout(env->vk, &o->dummy, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
        prob = &o->dummy;
    }
    VkDescriptorSetLayoutBinding b[2] = {
        {FV_OVERLAY_BINDING_DISPLAY, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {FV_OVERLAY_BINDING_PROB, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    fv_vk_compute_desc cd = {.name = "overlay", .code = fv_spv_overlay_comp, .code_size = sizeof fv_spv_overlay_comp,
                             .bindings = b, .binding_count = 2, .set_count = 1,
                             .push_bytes = sizeof(struct fv_overlay_push)};
    if (res == FV_OK) res = fv_vk_compute_init(env->vk, &cd, &o->cs);
    if (res != FV_OK) {
        FV_ERROR(MOD, "overlay pass could not be created: %s", fv_result_str(res));
        overlay_fini(o);
        return res;
    }
    fv_vk_write_image(env->vk, o->cs.sets[0], FV_OVERLAY_BINDING_DISPLAY, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                      display->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    fv_vk_write_image(env->vk, o->cs.sets[0], FV_OVERLAY_BINDING_PROB, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, prob->view,
                      VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    *out_state = o;
    return FV_OK;
}

static void overlay_record(void *state, const fv_pass_frame *f)
{
    overlay *o = state;
    if (!f->input) return;
    VkCommandBuffer cmd = f->cmd;
    fv_vk_label_begin(o->vk, cmd, "overlay (gaze, uncertainty, foveal boundary)");
    VkPipelineStageFlags cs = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    fv_images_use(f->images, cmd, FV_IMAGE_DISPLAY,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, cs, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT});
    if (o->fovea)
        fv_images_use(f->images, cmd, o->prob, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, cs, VK_ACCESS_SHADER_READ_BIT});
    struct fv_overlay_push pc;
    fv_overlay_push_from_input(f->input, o->width, o->height, o->fovea, &pc);
    fv_vk_compute_bind(&o->cs, cmd, 0, NULL, 0, 0, &pc);
    vkCmdDispatch(cmd, (o->width + FV_OVERLAY_GROUP_X - 1) / FV_OVERLAY_GROUP_X,
                  (o->height + FV_OVERLAY_GROUP_Y - 1) / FV_OVERLAY_GROUP_Y, 2);
    f->counters->dispatches++;
    fv_vk_label_end(o->vk, cmd);
}

const fv_pass fv_overlay_pass = {
    .id = "overlay",
    .flags = FV_PASS_REPLAYS_ON_PIXELS,
    .plan = overlay_plan,
    .init = overlay_init,
    .record = overlay_record,
    .fini = overlay_fini,
    .uses_if_made = FV_PASS_NAMES("fovea prob"), /* the foveal boundary */
};
