/* @brief Reading the renderer's images back (display, linear colour, motion, any named image) and re-shading a
 * list of pixels with the last frame's inputs. Each waits for the frames in flight first. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "renderer_internal.h"

fv_result fv_renderer_need_frame(const fv_renderer *r, const char *what)
{
    if (r->have_frame) return FV_OK;
    FV_ERROR(MOD, "%s before any frame was drawn", what);
    return FV_ERR_STATE;
}

fv_result fv_renderer_read_rgba8(fv_renderer *r, bool sbs, int eye, uint8_t *out, size_t out_size)
{
    if (!r || !out) return FV_ERR_INVALID_ARG;
    FV_TRY(fv_renderer_need_frame(r, "read_rgba8"));
    FV_TRY(fv_renderer_finish(r));
    return fv_target_read_display(&r->images, r->desc.eye_width, r->desc.eye_height, sbs, eye, out, out_size);
}

/* A float readback of `per_pixel` floats per pixel of one eye: a frame was drawn and out_floats holds it. */
static fv_result need_floats(const fv_renderer *r, const char *what, size_t per_pixel, size_t out_floats)
{
    FV_TRY(fv_renderer_need_frame(r, what));
    size_t n = (size_t)r->desc.eye_width * r->desc.eye_height * per_pixel;
    if (out_floats >= n) return FV_OK;
    FV_ERROR(MOD, "%s needs %zu floats, got %zu", what, n, out_floats);
    return FV_ERR_INVALID_ARG;
}

fv_result fv_renderer_read_linear(fv_renderer *r, int eye, float *out_rgba, size_t out_floats)
{
    if (!r || !out_rgba || eye < 0 || eye > 1) return FV_ERR_INVALID_ARG;
    FV_TRY(need_floats(r, "read_linear", 4, out_floats));
    FV_TRY(fv_renderer_finish(r));
    return fv_images_read(&r->images, FV_IMAGE_COLOR, (uint32_t)eye, out_rgba, out_floats * sizeof(float), 0,
                          (size_t)r->desc.eye_width * 16);
}

/* IEEE 754 binary16 -> float (exact: every half is a float). */
static float half_to_float(uint16_t h)
{
    uint32_t sign = (uint32_t)(h >> 15) << 31, exp = (h >> 10) & 0x1fu, mant = h & 0x3ffu, bits;
    if (exp == 0x1fu) {
        bits = sign | 0x7f800000u | (mant << 13); /* Inf / NaN */
    } else if (exp != 0) {
        bits = sign | ((exp + 112u) << 23) | (mant << 13); /* rebias 15 -> 127 */
    } else {
        float f = ldexpf((float)mant, -24); /* zero or subnormal */
        return sign ? -f : f;
    }
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

fv_result fv_renderer_read_motion(fv_renderer *r, int eye, float *out_rg, size_t out_floats)
{
    if (!r || !out_rg || eye < 0 || eye > 1) return FV_ERR_INVALID_ARG;
    FV_TRY(need_floats(r, "read_motion", 2, out_floats));
    if (!r->desc.motion_target) {
        FV_ERROR(MOD, "read_motion: the G-buffer draws no motion vectors (no pass reads them); create the renderer "
                      "with fv_renderer_desc.motion_target to keep them");
        return FV_ERR_STATE;
    }
    size_t n = (size_t)r->desc.eye_width * r->desc.eye_height * 2;
    uint16_t *half = malloc(n * sizeof *half);
    if (!half) return FV_ERR_NO_MEMORY;
    fv_result res = fv_renderer_finish(r);
    if (res == FV_OK)
        res = fv_images_read(&r->images, FV_IMAGE_MOTION, (uint32_t)eye, half, n * sizeof *half, 0,
                             (size_t)r->desc.eye_width * 2 * sizeof *half);
    if (res == FV_OK)
        for (size_t i = 0; i < n; i++) out_rg[i] = half_to_float(half[i]);
    free(half);
    return res;
}

/* Indirect dispatch arguments for a list of `count` pixels (fv_gpu.h FV_GPU_LIST_*). */
static VkDispatchIndirectCommand list_dispatch(uint32_t count)
{
    uint32_t groups = (uint32_t)(((uint64_t)count + FV_GPU_LIST_GROUP_SIZE - 1) / FV_GPU_LIST_GROUP_SIZE);
    VkDispatchIndirectCommand c = {groups < FV_GPU_LIST_GROUPS_X ? groups : FV_GPU_LIST_GROUPS_X,
                                   (groups + FV_GPU_LIST_GROUPS_X - 1) / FV_GPU_LIST_GROUPS_X, 1};
    if (groups == 0) c.x = c.y = 0;
    return c;
}

fv_result fv_renderer_shade_pixels(fv_renderer *r, const uint32_t *packed, uint32_t count, const float *clear_rgba)
{
    if (!r || (!packed && count)) return FV_ERR_INVALID_ARG;
    FV_TRY(fv_renderer_need_frame(r, "shade_pixels"));
    for (uint32_t i = 0; i < count; i++) {
        uint32_t x = packed[i] & 0x7fffu, y = (packed[i] >> 15) & 0x7fffu, layer = packed[i] >> 30;
        if (x >= r->desc.eye_width || y >= r->desc.eye_height || layer > 1) {
            FV_ERROR(MOD, "shade_pixels: entry %u is pixel (%u, %u) of eye %u, outside %ux%u x2", i, x, y, layer,
                     r->desc.eye_width, r->desc.eye_height);
            return FV_ERR_RANGE;
        }
    }
    FV_TRY(fv_renderer_finish(r));
    fv_vk *vk = r->vk;
    fv_vk_buffer list = {0}, indirect = {0};
    VkDeviceSize list_size = FV_GPU_LIST_HEADER_BYTES + (VkDeviceSize)(count ? count : 1) * 4;
    fv_result res = fv_vk_buffer_create(vk, list_size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, FV_VK_MEM_UPLOAD,
                                        "shade pixel list", &list);
    if (res == FV_OK)
        res = fv_vk_buffer_create(vk, sizeof(VkDispatchIndirectCommand), VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                                  FV_VK_MEM_UPLOAD, "shade list dispatch", &indirect);
    if (res != FV_OK) goto done;
    uint32_t header[4] = {count, 0, 0, 0};
    memcpy(list.mapped, header, sizeof header);
    if (count) memcpy((uint8_t *)list.mapped + FV_GPU_LIST_HEADER_BYTES, packed, (size_t)count * 4);
    VkDispatchIndirectCommand args = list_dispatch(count);
    memcpy(indirect.mapped, &args, sizeof args);
    if ((res = fv_vk_buffer_flush(vk, &list)) != FV_OK || (res = fv_vk_buffer_flush(vk, &indirect)) != FV_OK) goto done;

    VkCommandBuffer cmd;
    res = fv_vk_oneshot_begin(vk, "shade pixel list", &cmd);
    if (res != FV_OK) goto done;
    if (clear_rgba) {
        fv_images_use(&r->images, cmd, FV_IMAGE_COLOR,
                      (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                        VK_ACCESS_TRANSFER_WRITE_BIT});
        VkClearColorValue cv = {.float32 = {clear_rgba[0], clear_rgba[1], clear_rgba[2], clear_rgba[3]}};
        VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 2};
        vkCmdClearColorImage(cmd, fv_images_image(&r->images, FV_IMAGE_COLOR)->image, VK_IMAGE_LAYOUT_GENERAL, &cv, 1,
                             &range);
    }
    /* The last frame's slot: its frame block and lights describe the frame being re-shaded. */
    fv_pixel_list pl = {.buffer = list.buffer, .offset = 0, .range = VK_WHOLE_SIZE, .indirect = indirect.buffer,
                        .host_count = count};
    fv_renderer_record_passes(r, cmd, r->last_slot, &r->last_input, &pl, false, NULL);
    res = fv_vk_oneshot_end(vk, cmd);
done:
    fv_vk_buffer_destroy(vk, &indirect);
    fv_vk_buffer_destroy(vk, &list);
    if (res == FV_OK) r->stats.pixels_shaded = count;
    return res;
}

fv_result fv_renderer_read_image(fv_renderer *r, const char *name, int eye, void *out, size_t out_size,
                                 size_t texel_bytes)
{
    if (!r || !name || !out || eye < 0 || eye > 1 || !texel_bytes) return FV_ERR_INVALID_ARG;
    FV_TRY(fv_renderer_need_frame(r, "read_image"));
    fv_image_id id;
    if (fv_images_find(&r->images, name, &id) != FV_OK) {
        FV_ERROR(MOD, "read_image: no image named %s", name);
        return FV_ERR_NOT_FOUND;
    }
    size_t pitch = (size_t)r->desc.eye_width * texel_bytes;
    if (out_size < pitch * r->desc.eye_height) {
        FV_ERROR(MOD, "read_image %s needs %zu bytes, got %zu", name, pitch * r->desc.eye_height, out_size);
        return FV_ERR_INVALID_ARG;
    }
    FV_TRY(fv_renderer_finish(r));
    return fv_images_read(&r->images, id, (uint32_t)eye, out, out_size, 0, pitch);
}
