/* @brief The frame image table and its barrier tracking (see fv_images.h). */
#include "fv_images.h"

#include <stdio.h>
#include <string.h>

#define MOD "images"

#define WRITE_ACCESS                                                                                                   \
    (VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | \
     VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_HOST_WRITE_BIT | VK_ACCESS_MEMORY_WRITE_BIT)

static void describe(fv_image_slot *s, const char *name, VkFormat format, VkImageUsageFlags usage)
{
    snprintf(s->name, sizeof s->name, "%s", name);
    s->format = format;
    s->usage = usage;
    s->layout = VK_IMAGE_LAYOUT_UNDEFINED;
}

fv_result fv_images_init(fv_images *t, fv_vk *vk, uint32_t width, uint32_t height)
{
    memset(t, 0, sizeof *t);
    if (!vk || !width || !height) return FV_ERR_INVALID_ARG;
    t->vk = vk;
    t->width = width;
    t->height = height;
    VkImageUsageFlags target = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                               VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    VkImageUsageFlags linear = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                               VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    /* Octahedral normals: 16-bit snorm keeps ~3e-5 per component (half floats would give ~5e-4 near +-1). */
    VkFormat normal_format = VK_FORMAT_R16G16_SNORM;
    if (!fv_vk_format_supports(vk, normal_format,
                               VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT))
        normal_format = VK_FORMAT_R32G32_SFLOAT;
    describe(&t->slot[FV_IMAGE_DEPTH], "gbuffer depth", VK_FORMAT_D32_SFLOAT,
             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    describe(&t->slot[FV_IMAGE_NORMAL], "gbuffer normal (oct)", normal_format, target);
    describe(&t->slot[FV_IMAGE_ALBEDO], "gbuffer albedo", VK_FORMAT_R8G8B8A8_SRGB, target);
    describe(&t->slot[FV_IMAGE_MATERIAL], "gbuffer material id", VK_FORMAT_R16_UINT, target);
    describe(&t->slot[FV_IMAGE_MOTION], "gbuffer motion", VK_FORMAT_R16G16_SFLOAT, target);
    /* Motion, distance and normal bits (gbuffer_interface.h FV_GBUFFER_OUT_SURFACE): one fetch for foveation. */
    describe(&t->slot[FV_IMAGE_SURFACE], "gbuffer fovea surface", VK_FORMAT_R32G32B32A32_SFLOAT,
             target | VK_IMAGE_USAGE_STORAGE_BIT);
    /* Full float linear colour: 16-bit storage would cost up to 1e-3 relative error. */
    describe(&t->slot[FV_IMAGE_COLOR], "linear colour (rgba32f)", VK_FORMAT_R32G32B32A32_SFLOAT, linear);
    describe(&t->slot[FV_IMAGE_HISTORY], "history (rgba32f)", VK_FORMAT_R32G32B32A32_SFLOAT, linear);
    describe(&t->slot[FV_IMAGE_DISPLAY], "display output (sRGB rgba8)", VK_FORMAT_R8G8B8A8_UNORM,
             VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
    t->count = FV_IMAGE_BUILTIN_COUNT;
    return FV_OK;
}

void fv_images_fini(fv_images *t)
{
    if (!t || !t->vk) return;
    for (uint32_t i = 0; i < t->count; i++)
        if (t->slot[i].created) fv_vk_image_destroy(t->vk, &t->slot[i].img);
    memset(t, 0, sizeof *t);
}

static fv_result create(fv_images *t, fv_image_slot *s, uint32_t width, uint32_t height, uint32_t layers)
{
    fv_vk_image_desc d = {.width = width, .height = height, .layers = layers, .array = true, .format = s->format,
                          .usage = s->usage, .name = s->name};
    FV_TRY(fv_vk_image_create(t->vk, &d, &s->img));
    s->created = true;
    s->layout = VK_IMAGE_LAYOUT_UNDEFINED;
    s->write_stage = s->visible = s->readers = 0;
    s->write_access = 0;
    return FV_OK;
}

fv_result fv_images_get(fv_images *t, fv_image_id id, const fv_vk_image **out)
{
    if (!t || !t->vk || (uint32_t)id >= t->count || !out) return FV_ERR_INVALID_ARG;
    fv_image_slot *s = &t->slot[id];
    if (!s->created) FV_TRY(create(t, s, t->width, t->height, 2));
    *out = &s->img;
    return FV_OK;
}

/* While a pass starts: whether it declared `name` in any of lists first..last of t->declared (0 makes, 1 needs,
 * 2 uses_if_made); an error naming the pass when not. */
static fv_result declared(const fv_images *t, const char *name, int first, int last, const char *doing)
{
    if (!t->starting) return FV_OK;
    for (int l = first; l <= last; l++)
        for (const char *const *n = t->declared[l]; n && *n; n++)
            if (strcmp(*n, name) == 0) return FV_OK;
    FV_ERROR(MOD, "pass %s %s image '%s', which its table entry does not declare (fv_pass %s)", t->starting, doing,
             name, first == 0 && last == 0 ? "makes" : "makes, needs or uses_if_made");
    return FV_ERR_STATE;
}

fv_result fv_images_scratch(fv_images *t, const fv_vk_image_desc *desc, fv_image_id *out_id)
{
    if (!t || !t->vk || !desc || !out_id || !desc->format || !desc->usage) return FV_ERR_INVALID_ARG;
    FV_TRY(declared(t, desc->name ? desc->name : "scratch", 0, 0, "makes"));
    uint32_t k = FV_IMAGE_BUILTIN_COUNT;
    while (k < t->count && t->slot[k].created) k++; /* a released slot is taken again */
    if (k >= FV_IMAGE_MAX) {
        FV_ERROR(MOD, "scratch image %s: the table holds %d scratch images, all taken (FV_IMAGE_SCRATCH_MAX)",
                 desc->name ? desc->name : "?", FV_IMAGE_SCRATCH_MAX);
        return FV_ERR_RANGE;
    }
    fv_image_slot *s = &t->slot[k];
    memset(s, 0, sizeof *s);
    describe(s, desc->name ? desc->name : "scratch", desc->format, desc->usage);
    FV_TRY(create(t, s, desc->width ? desc->width : t->width, desc->height ? desc->height : t->height,
                  desc->layers ? desc->layers : 2));
    *out_id = (fv_image_id)k;
    if (k == t->count) t->count++;
    return FV_OK;
}

void fv_images_release(fv_images *t, fv_image_id id)
{
    if (!t || !t->vk || (uint32_t)id < FV_IMAGE_BUILTIN_COUNT || (uint32_t)id >= t->count) return;
    fv_image_slot *s = &t->slot[id];
    if (s->created) fv_vk_image_destroy(t->vk, &s->img);
    memset(s, 0, sizeof *s);
}

fv_result fv_images_find(const fv_images *t, const char *name, fv_image_id *out_id)
{
    if (!t || !name || !out_id) return FV_ERR_INVALID_ARG;
    FV_TRY(declared(t, name, 0, 2, "looks for"));
    for (uint32_t k = 0; k < t->count; k++)
        if (t->slot[k].created && strcmp(t->slot[k].name, name) == 0) {
            *out_id = (fv_image_id)k;
            return FV_OK;
        }
    return FV_ERR_NOT_FOUND;
}

const fv_vk_image *fv_images_image(const fv_images *t, fv_image_id id)
{
    return t && (uint32_t)id < t->count && t->slot[id].created ? &t->slot[id].img : NULL;
}

VkImageLayout fv_images_layout(const fv_images *t, fv_image_id id)
{
    return t && (uint32_t)id < t->count ? t->slot[id].layout : VK_IMAGE_LAYOUT_UNDEFINED;
}

void fv_images_use(fv_images *t, VkCommandBuffer cmd, fv_image_id id, fv_vk_image_use use)
{
    if (!t || (uint32_t)id >= t->count || !t->slot[id].created) return;
    fv_image_slot *s = &t->slot[id];
    bool writes = (use.access & WRITE_ACCESS) != 0;
    bool relayout = use.layout != s->layout;
    if (writes || relayout) {
        /* Write-after-write and write-after-read (and a layout change, which is a write): wait for the last
         * writer and every reader since; make the last write available. */
        VkPipelineStageFlags src = s->write_stage | s->readers;
        fv_vk_image_use from = {s->layout, src, s->write_access};
        if (src || relayout) fv_vk_barrier_image(cmd, &s->img, from, use);
        s->layout = use.layout;
        s->write_stage = use.stage;
        s->write_access = use.access & WRITE_ACCESS;
        /* A write is visible to nobody yet; a layout change for a read was made visible to that read's stages. */
        s->visible = writes ? 0 : use.stage;
        s->readers = writes ? 0 : use.stage;
        return;
    }
    /* Read-after-write: make the last write visible to stages that have not seen it yet. */
    VkPipelineStageFlags unseen = use.stage & ~s->visible;
    if (s->write_stage && unseen) {
        fv_vk_image_use from = {s->layout, s->write_stage, s->write_access};
        fv_vk_barrier_image(cmd, &s->img, from, use);
        s->visible |= use.stage;
    }
    s->readers |= use.stage;
}

void fv_images_render_pass(fv_images *t, VkCommandBuffer cmd, fv_image_id id, VkPipelineStageFlags waits_for,
                           fv_vk_image_use done, VkPipelineStageFlags visible_to)
{
    if (!t || (uint32_t)id >= t->count || !t->slot[id].created) return;
    fv_image_slot *s = &t->slot[id];
    VkPipelineStageFlags uncovered = (s->write_stage | s->readers) & ~waits_for;
    if (uncovered && s->layout != VK_IMAGE_LAYOUT_UNDEFINED) {
        /* Earlier users the render pass's own dependency does not wait for: an execution (and memory) dependency
         * before it begins; the layout stays, the render pass discards it. */
        fv_vk_image_use from = {s->layout, uncovered, s->write_access};
        fv_vk_image_use to = {s->layout, waits_for, 0};
        fv_vk_barrier_image(cmd, &s->img, from, to);
    }
    s->layout = done.layout;
    s->write_stage = done.stage;
    s->write_access = done.access & WRITE_ACCESS;
    s->visible = visible_to;
    s->readers = 0;
}

static const fv_image_id gbuffer_read[4] = {FV_IMAGE_DEPTH, FV_IMAGE_NORMAL, FV_IMAGE_ALBEDO, FV_IMAGE_MATERIAL};

static VkImageLayout read_layout(fv_image_id id)
{
    return id == FV_IMAGE_DEPTH ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
}

void fv_images_use_gbuffer(fv_images *t, VkCommandBuffer cmd, VkPipelineStageFlags stage)
{
    for (int i = 0; i < 4; i++)
        fv_images_use(t, cmd, gbuffer_read[i], (fv_vk_image_use){read_layout(gbuffer_read[i]), stage, VK_ACCESS_SHADER_READ_BIT});
}

void fv_images_bind_gbuffer(const fv_images *t, VkDescriptorSet set, uint32_t first_binding, VkSampler sampler)
{
    for (uint32_t i = 0; i < 4; i++) {
        const fv_vk_image *img = fv_images_image(t, gbuffer_read[i]);
        if (img)
            fv_vk_write_image(t->vk, set, first_binding + i, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, img->view,
                              sampler, read_layout(gbuffer_read[i]));
    }
}

fv_result fv_images_get_gbuffer(fv_images *t)
{
    const fv_vk_image *img;
    for (int i = 0; i < 4; i++) FV_TRY(fv_images_get(t, gbuffer_read[i], &img));
    return FV_OK;
}

fv_result fv_images_read(fv_images *t, fv_image_id id, uint32_t layer, void *out, size_t out_size, size_t out_offset,
                         size_t out_row_pitch)
{
    if (!t || (uint32_t)id >= t->count) return FV_ERR_INVALID_ARG;
    fv_image_slot *s = &t->slot[id];
    if (!s->created || s->layout == VK_IMAGE_LAYOUT_UNDEFINED) {
        FV_ERROR(MOD, "%s: read back before anything wrote it", s->name);
        return FV_ERR_STATE;
    }
    /* The copy's layout change is a write: it waits for the last writer and for every reader since. */
    VkPipelineStageFlags src = s->write_stage | s->readers;
    FV_TRY(fv_vk_read_image(t->vk, &s->img, layer, s->layout, src ? src : VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                            s->write_access, out, out_size, out_offset, out_row_pitch));
    s->readers |= VK_PIPELINE_STAGE_TRANSFER_BIT;
    s->visible |= VK_PIPELINE_STAGE_TRANSFER_BIT;
    return FV_OK;
}
