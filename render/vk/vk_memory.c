/* @brief Vulkan memory: per-resource allocations with a budget check and current/peak counters; buffers, 2D and
 * array images, samplers, one-shot command buffers, staging upload and image readback. */
#include <stdio.h>
#include <string.h>

#include "fv_vk.h"

#define MOD "vk"

static int find_memory_type(const fv_vk *vk, uint32_t type_bits, VkMemoryPropertyFlags want,
                            VkMemoryPropertyFlags nice)
{
    int fallback = -1;
    for (uint32_t i = 0; i < vk->mem_props.memoryTypeCount; i++) {
        if (!(type_bits & (1u << i))) continue;
        VkMemoryPropertyFlags f = vk->mem_props.memoryTypes[i].propertyFlags;
        if ((f & want) != want) continue;
        if ((f & nice) == nice) return (int)i;
        if (fallback < 0) fallback = (int)i;
    }
    return fallback;
}

/* Allocate with a budget check; counts bytes and allocations. */
static fv_result allocate(fv_vk *vk, VkMemoryRequirements req, fv_vk_mem_kind kind, const char *name,
                          VkDeviceMemory *out, bool *out_coherent)
{
    VkMemoryPropertyFlags want = 0, nice = 0;
    switch (kind) {
    case FV_VK_MEM_DEVICE: want = 0; nice = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT; break;
    case FV_VK_MEM_UPLOAD:
        want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        break;
    case FV_VK_MEM_READBACK:
        want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
        nice = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
        break;
    }
    int type = find_memory_type(vk, req.memoryTypeBits, want, nice);
    if (type < 0) {
        FV_ERROR(MOD, "%s: no memory type for kind %d (type bits 0x%x)", name, (int)kind, req.memoryTypeBits);
        return FV_ERR_UNSUPPORTED;
    }
    if (vk->memory_bytes + req.size > vk->memory_budget_bytes) {
        FV_ERROR(MOD, "%s: allocating %llu bytes would exceed the device memory budget (%llu of %llu bytes in use)",
                 name, (unsigned long long)req.size, (unsigned long long)vk->memory_bytes,
                 (unsigned long long)vk->memory_budget_bytes);
        return FV_ERR_NO_MEMORY;
    }
    VkMemoryAllocateInfo ai = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .allocationSize = req.size,
        .memoryTypeIndex = (uint32_t)type,
    };
    FV_VK_CHECK(vkAllocateMemory(vk->device, &ai, NULL, out));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_DEVICE_MEMORY, *out, "%s memory", name);
    vk->memory_bytes += req.size;
    if (vk->memory_bytes > vk->memory_peak_bytes) vk->memory_peak_bytes = vk->memory_bytes;
    vk->allocation_count++;
    if (out_coherent)
        *out_coherent = vk->mem_props.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    return FV_OK;
}

static void release(fv_vk *vk, VkDeviceMemory mem, VkDeviceSize size)
{
    if (!mem) return;
    vkFreeMemory(vk->device, mem, NULL);
    vk->memory_bytes -= size <= vk->memory_bytes ? size : vk->memory_bytes;
    if (vk->allocation_count) vk->allocation_count--;
}

/* ---- buffers ------------------------------------------------------------------------------------------------- */

fv_result fv_vk_buffer_create(fv_vk *vk, VkDeviceSize size, VkBufferUsageFlags usage, fv_vk_mem_kind kind,
                              const char *name, fv_vk_buffer *out)
{
    if (!vk || !out || size == 0) return FV_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    fv_result res = FV_OK;
    VkBufferCreateInfo bi = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
        .size = size,
        .usage = usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
    };
    FV_VK_CHECK_GOTO(vkCreateBuffer(vk->device, &bi, NULL, &out->buffer), res, fail);
    FV_VK_NAME(vk, VK_OBJECT_TYPE_BUFFER, out->buffer, "%s", name);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(vk->device, out->buffer, &req);
    res = allocate(vk, req, kind, name, &out->memory, &out->coherent);
    if (res != FV_OK) goto fail;
    out->size = size;
    FV_VK_CHECK_GOTO(vkBindBufferMemory(vk->device, out->buffer, out->memory, 0), res, fail);
    if (kind != FV_VK_MEM_DEVICE) FV_VK_CHECK_GOTO(vkMapMemory(vk->device, out->memory, 0, VK_WHOLE_SIZE, 0, &out->mapped), res, fail);
    return FV_OK;
fail:
    fv_vk_buffer_destroy(vk, out);
    return res;
}

void fv_vk_buffer_destroy(fv_vk *vk, fv_vk_buffer *b)
{
    if (!vk || !b) return;
    if (b->buffer) {
        VkMemoryRequirements req = {0};
        vkGetBufferMemoryRequirements(vk->device, b->buffer, &req);
        if (b->mapped) vkUnmapMemory(vk->device, b->memory);
        vkDestroyBuffer(vk->device, b->buffer, NULL);
        release(vk, b->memory, req.size);
    } else if (b->memory) {
        release(vk, b->memory, 0);
    }
    memset(b, 0, sizeof *b);
}

fv_result fv_vk_buffer_flush(fv_vk *vk, fv_vk_buffer *b)
{
    if (b->coherent || !b->mapped) return FV_OK;
    VkMappedMemoryRange r = {.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, .memory = b->memory, .size = VK_WHOLE_SIZE};
    FV_VK_CHECK(vkFlushMappedMemoryRanges(vk->device, 1, &r));
    return FV_OK;
}

fv_result fv_vk_buffer_invalidate(fv_vk *vk, fv_vk_buffer *b)
{
    if (b->coherent || !b->mapped) return FV_OK;
    VkMappedMemoryRange r = {.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, .memory = b->memory, .size = VK_WHOLE_SIZE};
    FV_VK_CHECK(vkInvalidateMappedMemoryRanges(vk->device, 1, &r));
    return FV_OK;
}

/* ---- images -------------------------------------------------------------------------------------------------- */

uint32_t fv_vk_format_size(VkFormat f)
{
    switch (f) {
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_R16G16_SFLOAT:
    case VK_FORMAT_R16G16_SNORM:
    case VK_FORMAT_R16G16_UNORM: return 4;
    case VK_FORMAT_R16_UINT: return 2;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R32G32_SFLOAT: return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT: return 16;
    default: return 0;
    }
}

bool fv_vk_format_supports(const fv_vk *vk, VkFormat f, VkFormatFeatureFlags features)
{
    VkFormatProperties p;
    vkGetPhysicalDeviceFormatProperties(vk->phys, f, &p);
    return (p.optimalTilingFeatures & features) == features;
}

static bool is_depth(VkFormat f)
{
    return f == VK_FORMAT_D32_SFLOAT || f == VK_FORMAT_D16_UNORM || f == VK_FORMAT_X8_D24_UNORM_PACK32;
}

fv_result fv_vk_image_create(fv_vk *vk, const fv_vk_image_desc *d, fv_vk_image *out)
{
    if (!vk || !d || !out || !d->width || !d->height || !d->layers) return FV_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    const char *name = d->name ? d->name : "image";
    if (d->width > vk->props.limits.maxImageDimension2D || d->height > vk->props.limits.maxImageDimension2D ||
        d->layers > vk->props.limits.maxImageArrayLayers) {
        FV_ERROR(MOD, "%s: %ux%u x%u layers exceeds the device limits (%u px, %u layers)", name, d->width, d->height,
                 d->layers, vk->props.limits.maxImageDimension2D, vk->props.limits.maxImageArrayLayers);
        return FV_ERR_RANGE;
    }
    fv_result res = FV_OK;
    VkImageCreateInfo ii = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
        .imageType = VK_IMAGE_TYPE_2D,
        .format = d->format,
        .extent = {d->width, d->height, 1},
        .mipLevels = 1,
        .arrayLayers = d->layers,
        .samples = VK_SAMPLE_COUNT_1_BIT,
        .tiling = VK_IMAGE_TILING_OPTIMAL,
        .usage = d->usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
        .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
    };
    FV_VK_CHECK_GOTO(vkCreateImage(vk->device, &ii, NULL, &out->image), res, fail);
    FV_VK_NAME(vk, VK_OBJECT_TYPE_IMAGE, out->image, "%s", name);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(vk->device, out->image, &req);
    res = allocate(vk, req, FV_VK_MEM_DEVICE, name, &out->memory, NULL);
    if (res != FV_OK) goto fail;
    FV_VK_CHECK_GOTO(vkBindImageMemory(vk->device, out->image, out->memory, 0), res, fail);
    out->format = d->format;
    out->aspect = is_depth(d->format) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
    out->width = d->width;
    out->height = d->height;
    out->layers = d->layers;
    VkImageViewCreateInfo vi = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
        .image = out->image,
        .viewType = d->layers > 1 || d->array ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D,
        .format = d->format,
        .subresourceRange = {out->aspect, 0, 1, 0, d->layers},
    };
    FV_VK_CHECK_GOTO(vkCreateImageView(vk->device, &vi, NULL, &out->view), res, fail);
    FV_VK_NAME(vk, VK_OBJECT_TYPE_IMAGE_VIEW, out->view, "%s view", name);
    return FV_OK;
fail:
    fv_vk_image_destroy(vk, out);
    return res;
}

void fv_vk_image_destroy(fv_vk *vk, fv_vk_image *img)
{
    if (!vk || !img) return;
    if (img->view) vkDestroyImageView(vk->device, img->view, NULL);
    VkMemoryRequirements req = {0};
    if (img->image) {
        vkGetImageMemoryRequirements(vk->device, img->image, &req);
        vkDestroyImage(vk->device, img->image, NULL);
    }
    release(vk, img->memory, req.size);
    memset(img, 0, sizeof *img);
}

fv_result fv_vk_sampler_create(fv_vk *vk, bool linear, bool repeat, const char *name, VkSampler *out)
{
    VkFilter f = linear ? VK_FILTER_LINEAR : VK_FILTER_NEAREST;
    VkSamplerAddressMode m = repeat ? VK_SAMPLER_ADDRESS_MODE_REPEAT : VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSamplerCreateInfo si = {
        .sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
        .magFilter = f,
        .minFilter = f,
        .mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST,
        .addressModeU = m,
        .addressModeV = m,
        .addressModeW = m,
        .maxLod = 0.0f,
    };
    FV_VK_CHECK(vkCreateSampler(vk->device, &si, NULL, out));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_SAMPLER, *out, "%s", name);
    return FV_OK;
}

/* ---- one-shot commands --------------------------------------------------------------------------------------- */

fv_result fv_vk_oneshot_begin(fv_vk *vk, const char *label, VkCommandBuffer *out_cmd)
{
    VkCommandBufferAllocateInfo ai = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
        .commandPool = vk->pool,
        .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
        .commandBufferCount = 1,
    };
    FV_VK_CHECK(vkAllocateCommandBuffers(vk->device, &ai, out_cmd));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_COMMAND_BUFFER, *out_cmd, "one-shot: %s", label);
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    VkResult r = vkBeginCommandBuffer(*out_cmd, &bi);
    if (r < 0) {
        vkFreeCommandBuffers(vk->device, vk->pool, 1, out_cmd);
        return fv_vk_fail(r, "vkBeginCommandBuffer", __FILE__, __LINE__);
    }
    fv_vk_label_begin(vk, *out_cmd, label);
    return FV_OK;
}

fv_result fv_vk_oneshot_end(fv_vk *vk, VkCommandBuffer cmd)
{
    fv_result res = FV_OK;
    fv_vk_label_end(vk, cmd);
    FV_VK_CHECK_GOTO(vkEndCommandBuffer(cmd), res, done);
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &cmd};
    FV_VK_CHECK_GOTO(vkResetFences(vk->device, 1, &vk->oneshot_fence), res, done);
    FV_VK_CHECK_GOTO(vkQueueSubmit(vk->queue, 1, &si, vk->oneshot_fence), res, done);
    FV_VK_CHECK_GOTO(vkWaitForFences(vk->device, 1, &vk->oneshot_fence, VK_TRUE, UINT64_MAX), res, done);
done:
    vkFreeCommandBuffers(vk->device, vk->pool, 1, &cmd);
    return res;
}

/* ---- upload -------------------------------------------------------------------------------------------------- */

fv_result fv_vk_upload_buffer(fv_vk *vk, fv_vk_buffer *dst, VkDeviceSize offset, const void *data, VkDeviceSize size)
{
    if (!size) return FV_OK;
    if (!dst || !data || offset + size > dst->size) return FV_ERR_INVALID_ARG;
    fv_vk_buffer staging;
    FV_TRY(fv_vk_buffer_create(vk, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, FV_VK_MEM_UPLOAD, "staging upload",
                               &staging));
    memcpy(staging.mapped, data, (size_t)size);
    fv_result res = fv_vk_buffer_flush(vk, &staging);
    VkCommandBuffer cmd;
    if (res == FV_OK) res = fv_vk_oneshot_begin(vk, "upload buffer", &cmd);
    if (res == FV_OK) {
        VkBufferCopy c = {.srcOffset = 0, .dstOffset = offset, .size = size};
        vkCmdCopyBuffer(cmd, staging.buffer, dst->buffer, 1, &c);
        /* The copy must finish before any later vertex/index/shader read of the destination. */
        VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .dstAccessMask = VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT |
                                               VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_UNIFORM_READ_BIT};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                                 VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                             0, 1, &mb, 0, NULL, 0, NULL);
        res = fv_vk_oneshot_end(vk, cmd);
    }
    fv_vk_buffer_destroy(vk, &staging);
    return res;
}

static VkPipelineStageFlags layout_stages(VkImageLayout l, VkAccessFlags *out_access)
{
    switch (l) {
    case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL:
        *out_access = VK_ACCESS_SHADER_READ_BIT;
        return VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    case VK_IMAGE_LAYOUT_GENERAL:
        *out_access = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
        return VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT;
    case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL:
        *out_access = VK_ACCESS_TRANSFER_READ_BIT;
        return VK_PIPELINE_STAGE_TRANSFER_BIT;
    case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL:
        *out_access = VK_ACCESS_TRANSFER_WRITE_BIT;
        return VK_PIPELINE_STAGE_TRANSFER_BIT;
    default:
        *out_access = 0;
        return VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT;
    }
}

fv_result fv_vk_image_set_layout(fv_vk *vk, fv_vk_image *img, VkImageLayout old_layout, VkImageLayout new_layout)
{
    VkCommandBuffer cmd;
    FV_TRY(fv_vk_oneshot_begin(vk, "image layout", &cmd));
    VkAccessFlags src_access, dst_access;
    VkPipelineStageFlags src = layout_stages(old_layout, &src_access);
    VkPipelineStageFlags dst = layout_stages(new_layout, &dst_access);
    if (old_layout == VK_IMAGE_LAYOUT_UNDEFINED) src_access = 0;
    VkImageMemoryBarrier b = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
        .srcAccessMask = src_access,
        .dstAccessMask = dst_access,
        .oldLayout = old_layout,
        .newLayout = new_layout,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = img->image,
        .subresourceRange = {img->aspect, 0, 1, 0, img->layers},
    };
    vkCmdPipelineBarrier(cmd, src, dst, 0, 0, NULL, 0, NULL, 1, &b);
    return fv_vk_oneshot_end(vk, cmd);
}

fv_result fv_vk_upload_image(fv_vk *vk, fv_vk_image *img, uint32_t layer, const void *data, size_t size,
                             VkImageLayout final_layout)
{
    uint32_t texel = fv_vk_format_size(img->format);
    size_t need = (size_t)img->width * img->height * texel;
    if (!texel || layer >= img->layers || !data || size < need) {
        FV_ERROR(MOD, "upload to image: %zu bytes for %ux%u layer %u of format %d (needs %zu)", size, img->width,
                 img->height, layer, (int)img->format, need);
        return FV_ERR_INVALID_ARG;
    }
    fv_vk_buffer staging;
    FV_TRY(fv_vk_buffer_create(vk, need, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, FV_VK_MEM_UPLOAD, "staging image upload",
                               &staging));
    memcpy(staging.mapped, data, need);
    fv_result res = fv_vk_buffer_flush(vk, &staging);
    VkCommandBuffer cmd;
    if (res == FV_OK) res = fv_vk_oneshot_begin(vk, "upload image", &cmd);
    if (res == FV_OK) {
        VkImageMemoryBarrier b = {
            .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
            .srcAccessMask = 0,
            .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
            .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
            .newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
            .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
            .image = img->image,
            .subresourceRange = {img->aspect, 0, 1, layer, 1},
        };
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0,
                             NULL, 1, &b);
        VkBufferImageCopy c = {
            .imageSubresource = {img->aspect, 0, layer, 1},
            .imageExtent = {img->width, img->height, 1},
        };
        vkCmdCopyBufferToImage(cmd, staging.buffer, img->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
        VkAccessFlags dst_access;
        VkPipelineStageFlags dst = layout_stages(final_layout, &dst_access);
        b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        b.dstAccessMask = dst_access;
        b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        b.newLayout = final_layout;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, dst, 0, 0, NULL, 0, NULL, 1, &b);
        res = fv_vk_oneshot_end(vk, cmd);
    }
    fv_vk_buffer_destroy(vk, &staging);
    return res;
}

/* ---- readback ------------------------------------------------------------------------------------------------ */

fv_result fv_vk_read_image(fv_vk *vk, fv_vk_image *img, uint32_t layer, VkImageLayout layout,
                           VkPipelineStageFlags src_stage, VkAccessFlags src_access, void *out, size_t out_size,
                           size_t out_offset, size_t out_row_pitch)
{
    uint32_t texel = fv_vk_format_size(img->format);
    size_t row = (size_t)img->width * texel;
    if (!texel || layer >= img->layers || !out || out_row_pitch < row ||
        out_offset + out_row_pitch * (img->height - 1) + row > out_size) {
        FV_ERROR(MOD, "read image: bad arguments (layer %u of %u, %zu bytes at offset %zu, pitch %zu)", layer,
                 img->layers, out_size, out_offset, out_row_pitch);
        return FV_ERR_INVALID_ARG;
    }
    size_t bytes = row * img->height;
    fv_vk_buffer rb;
    FV_TRY(fv_vk_buffer_create(vk, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, FV_VK_MEM_READBACK, "readback", &rb));
    VkCommandBuffer cmd;
    fv_result res = fv_vk_oneshot_begin(vk, "readback", &cmd);
    if (res == FV_OK) {
        VkImageLayout copy_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        /* Make the last writer's results available to the copy (and change layout if needed). */
        VkImageMemoryBarrier b = {
            .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
            .srcAccessMask = src_access,
            .dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT,
            .oldLayout = layout,
            .newLayout = copy_layout,
            .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
            .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
            .image = img->image,
            .subresourceRange = {img->aspect, 0, 1, layer, 1},
        };
        vkCmdPipelineBarrier(cmd, src_stage, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0, NULL, 1, &b);
        VkBufferImageCopy c = {
            .imageSubresource = {img->aspect, 0, layer, 1},
            .imageExtent = {img->width, img->height, 1},
        };
        vkCmdCopyImageToBuffer(cmd, img->image, copy_layout, rb.buffer, 1, &c);
        /* Back to the caller's layout; later shader use waits for the copy (write-after-read). */
        if (copy_layout != layout) {
            b.srcAccessMask = 0;
            b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
            b.oldLayout = copy_layout;
            b.newLayout = layout;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, NULL,
                                 0, NULL, 1, &b);
        }
        VkMemoryBarrier hb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &hb, 0, NULL, 0,
                             NULL);
        res = fv_vk_oneshot_end(vk, cmd);
    }
    if (res == FV_OK) res = fv_vk_buffer_invalidate(vk, &rb);
    if (res == FV_OK) {
        const uint8_t *src = rb.mapped;
        uint8_t *dst = (uint8_t *)out + out_offset;
        for (uint32_t y = 0; y < img->height; y++) memcpy(dst + y * out_row_pitch, src + y * row, row);
    }
    fv_vk_buffer_destroy(vk, &rb);
    return res;
}
