/* @brief The stamp pass of the test build (stamp_pass.h): a room like render/<pass>/, reached only through a table. */
#include "stamp_pass.h"

#include <stdio.h>
#include <stdlib.h>

typedef struct stamp {
    fv_images *images;
    fv_image_id image, mask;
} stamp;

static void stamp_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    out->enabled = ctx->quality->fovea.enabled;
    out->variant = ctx->quality->fovea.block; /* made again with the fovea pass, whose mask it keeps */
    snprintf(out->reason, sizeof out->reason, out->enabled ? "test pass: stamps its image" : "off — no foveation");
}

static void stamp_fini(void *state)
{
    stamp *s = state;
    if (!s) return;
    if (s->image != FV_IMAGE_MAX) fv_images_release(s->images, s->image);
    free(s);
}

static fv_result init_with(const fv_pass_env *env, void **out, bool sneak)
{
    stamp *s = calloc(1, sizeof *s);
    if (!s) return FV_ERR_NO_MEMORY;
    s->images = env->images;
    s->image = FV_IMAGE_MAX;
    fv_vk_image_desc d = {.format = VK_FORMAT_R32_UINT, .layers = 2, .name = "test stamp",
                          .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                                   VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
    fv_result res = fv_images_find(env->images, "fovea mask", &s->mask); /* the fovea pass (earlier) made it */
    fv_image_id prob;
    if (res == FV_OK && sneak) res = fv_images_find(env->images, "fovea prob", &prob); /* not declared */
    if (res == FV_OK) res = fv_images_scratch(env->images, &d, &s->image);
    if (res != FV_OK) {
        stamp_fini(s);
        return res;
    }
    *out = s;
    return FV_OK;
}

static fv_result stamp_init(const fv_pass_env *env, void **out) { return init_with(env, out, false); }
static fv_result sneak_init(const fv_pass_env *env, void **out) { return init_with(env, out, true); }

static void stamp_record(void *state, const fv_pass_frame *f)
{
    stamp *s = state;
    fv_images_use(f->images, f->cmd, s->image,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                    VK_ACCESS_TRANSFER_WRITE_BIT});
    VkClearColorValue v = {.uint32 = {FV_STAMP_VALUE, 0, 0, 0}};
    VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 2};
    vkCmdClearColorImage(f->cmd, fv_images_image(f->images, s->image)->image, VK_IMAGE_LAYOUT_GENERAL, &v, 1, &range);
    f->counters->draws += 1; /* one clear: seen in the frame's stats */
}

const fv_pass fv_stamp_pass = {
    .id = "stamp",
    .plan = stamp_plan,
    .init = stamp_init,
    .record = stamp_record,
    .fini = stamp_fini,
    .makes = FV_PASS_NAMES("test stamp"),
    .needs = FV_PASS_NAMES("fovea mask"),
};

const fv_pass fv_stamp_sneak_pass = {
    .id = "sneak",
    .plan = stamp_plan,
    .init = sneak_init,
    .record = stamp_record,
    .fini = stamp_fini,
    .makes = FV_PASS_NAMES("test stamp"),
    .needs = FV_PASS_NAMES("fovea mask"),
};
