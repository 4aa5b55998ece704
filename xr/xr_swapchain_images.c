/* @brief Swapchain images of fovea's OpenXR runtime: created on fovea's device (fv_vk) with exportable memory
 * (VK_KHR_external_memory_fd) and imported into the app's device, so both see one image; the formats both can share;
 * the hand-overs of xrAcquire/Wait/ReleaseSwapchainImage on the app's queue (app family -> VK_QUEUE_FAMILY_EXTERNAL ->
 * compositor family and back, each release paired with an acquire of the same layouts, fenced). The compositor
 * (xr_compositor.c) reads them. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "xr_compositor_internal.h"
/* ---- formats ------------------------------------------------------------------------------------------------- */
bool fv_xr_format_is_depth(int64_t f)
{
    return f == VK_FORMAT_D16_UNORM || f == VK_FORMAT_D32_SFLOAT || f == VK_FORMAT_D24_UNORM_S8_UINT ||
           f == VK_FORMAT_D32_SFLOAT_S8_UINT;
}

/* Whether an image of this format and usage can be created exportable (opaque fd) on fovea's device. */
static bool shareable(fv_xr_compositor *c, VkFormat f, VkImageUsageFlags usage)
{
    VkPhysicalDeviceExternalImageFormatInfo ext = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_IMAGE_FORMAT_INFO,
                                                   .handleType = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT};
    VkPhysicalDeviceImageFormatInfo2 fi = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_IMAGE_FORMAT_INFO_2,
                                           .pNext = &ext,
                                           .format = f,
                                           .type = VK_IMAGE_TYPE_2D,
                                           .tiling = VK_IMAGE_TILING_OPTIMAL,
                                           .usage = usage};
    VkExternalImageFormatProperties ep = {.sType = VK_STRUCTURE_TYPE_EXTERNAL_IMAGE_FORMAT_PROPERTIES};
    VkImageFormatProperties2 fp = {.sType = VK_STRUCTURE_TYPE_IMAGE_FORMAT_PROPERTIES_2, .pNext = &ep};
    if (vkGetPhysicalDeviceImageFormatProperties2(c->vk->phys, &fi, &fp) != VK_SUCCESS) return false;
    VkExternalMemoryFeatureFlags need =
        VK_EXTERNAL_MEMORY_FEATURE_EXPORTABLE_BIT | VK_EXTERNAL_MEMORY_FEATURE_IMPORTABLE_BIT;
    return (ep.externalMemoryProperties.externalMemoryFeatures & need) == need;
}

uint32_t fv_xr_compositor_formats(fv_xr_compositor *c, int64_t *out, uint32_t cap)
{
    /* colour formats first, sRGB preferred (the spec's recommendation); then depth for depth layers */
    static const VkFormat colour[] = {VK_FORMAT_R8G8B8A8_SRGB, VK_FORMAT_B8G8R8A8_SRGB, VK_FORMAT_R8G8B8A8_UNORM,
                                      VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R16G16B16A16_SFLOAT,
                                      VK_FORMAT_A2B10G10R10_UNORM_PACK32};
    static const VkFormat depth[] = {VK_FORMAT_D32_SFLOAT, VK_FORMAT_D16_UNORM, VK_FORMAT_D24_UNORM_S8_UINT,
                                     VK_FORMAT_D32_SFLOAT_S8_UINT};
    uint32_t n = 0;
    for (size_t i = 0; i < sizeof colour / sizeof colour[0]; i++) {
        VkImageUsageFlags u = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                              VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        if (!fv_vk_format_supports(c->vk, colour[i], VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT |
                                                         VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT))
            continue;
        if (!shareable(c, colour[i], u)) continue;
        if (out && n < cap) out[n] = colour[i];
        n++;
    }
    for (size_t i = 0; i < sizeof depth / sizeof depth[0]; i++) {
        if (!fv_vk_format_supports(c->vk, depth[i], VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT)) continue;
        if (out && n < cap) out[n] = depth[i];
        n++;
    }
    return n;
}

_Static_assert(FV_XR_COMPOSE_MAX_LAYERS >= 2 * FV_XR_MAX_LAYERS, "every layer of a frame, each with its inset");

/* ---- swapchain images ------------------------------------------------------------------------------------------ */
static VkImageUsageFlags usage_of(XrSwapchainUsageFlags u, bool depth)
{
    VkImageUsageFlags v = 0;
    if (u & XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT) v |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    if (u & XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT) v |= VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    if (u & XR_SWAPCHAIN_USAGE_UNORDERED_ACCESS_BIT) v |= VK_IMAGE_USAGE_STORAGE_BIT;
    if (u & XR_SWAPCHAIN_USAGE_TRANSFER_SRC_BIT) v |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    if (u & XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT) v |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    if (u & XR_SWAPCHAIN_USAGE_SAMPLED_BIT) v |= VK_IMAGE_USAGE_SAMPLED_BIT;
    if (u & XR_SWAPCHAIN_USAGE_INPUT_ATTACHMENT_BIT_MND) v |= VK_IMAGE_USAGE_INPUT_ATTACHMENT_BIT;
    if (!depth) v |= VK_IMAGE_USAGE_SAMPLED_BIT; /* the compositor samples every colour image */
    if (!v) v = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT; /* a depth image with no usage named: what it is for */
    return v;
}

static uint32_t memory_type(const VkPhysicalDeviceMemoryProperties *mp, uint32_t bits, VkMemoryPropertyFlags want)
{
    for (uint32_t i = 0; i < mp->memoryTypeCount; i++)
        if ((bits & (1u << i)) && (mp->memoryTypes[i].propertyFlags & want) == want) return i;
    for (uint32_t i = 0; i < mp->memoryTypeCount; i++)
        if (bits & (1u << i)) return i;
    return UINT32_MAX;
}

static void image_fini(fv_xr_compositor *c, struct XrSession_T *s, fv_xr_swapchain_image *im)
{
    VkDevice ad = s->vk.device;
    if (im->app_fence) {
        vkWaitForFences(ad, 1, &im->app_fence, VK_TRUE, FV_XR_FENCE_TIMEOUT_NS);
        vkDestroyFence(ad, im->app_fence, NULL);
    }
    if (im->app_cmd) vkFreeCommandBuffers(ad, s->vk.pool, 1, &im->app_cmd);
    if (im->app_image) vkDestroyImage(ad, im->app_image, NULL);
    if (im->app_mem) vkFreeMemory(ad, im->app_mem, NULL);
    if (im->comp_view) vkDestroyImageView(c->vk->device, im->comp_view, NULL);
    if (im->comp_image) vkDestroyImage(c->vk->device, im->comp_image, NULL);
    if (im->comp_mem) vkFreeMemory(c->vk->device, im->comp_mem, NULL);
    memset(im, 0, sizeof *im);
}

/* The Vulkan image of a swapchain's images (ext: the external-memory info it chains for a colour image). */
static VkImageCreateInfo image_create_info(const struct XrSwapchain_T *sc, VkExternalMemoryImageCreateInfo *ext)
{
    const XrSwapchainCreateInfo *ci = &sc->info;
    *ext = (VkExternalMemoryImageCreateInfo){.sType = VK_STRUCTURE_TYPE_EXTERNAL_MEMORY_IMAGE_CREATE_INFO,
                                             .handleTypes = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT};
    VkImageCreateInfo ic = {.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
                            .pNext = sc->depth ? NULL : ext,
                            .flags = (ci->usageFlags & XR_SWAPCHAIN_USAGE_MUTABLE_FORMAT_BIT)
                                         ? VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT
                                         : 0,
                            .imageType = VK_IMAGE_TYPE_2D,
                            .format = sc->format,
                            .extent = {ci->width, ci->height, 1},
                            .mipLevels = ci->mipCount,
                            .arrayLayers = ci->arraySize * ci->faceCount,
                            .samples = VK_SAMPLE_COUNT_1_BIT,
                            .tiling = VK_IMAGE_TILING_OPTIMAL,
                            .usage = usage_of(ci->usageFlags, sc->depth),
                            .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
                            .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED};
    if (ci->faceCount == 6) ic.flags |= VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT;
    /* an EGL session (xr_egl.c): GL textures on the app's side, copied into the compositor's image */
    if (sc->session->egl) ic.usage |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    return ic;
}

/* Whether the device can make the swapchain's images (its usage for its format, its size, mips, layers, samples):
 * xrCreateSwapchain's checks against fovea's own limits come first; this is the device's word on the rest. */
static XrResult image_supported(fv_xr_compositor *c, const struct XrSwapchain_T *sc)
{
    VkExternalMemoryImageCreateInfo ext;
    VkImageCreateInfo ic = image_create_info(sc, &ext);
    VkPhysicalDeviceExternalImageFormatInfo xi = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_IMAGE_FORMAT_INFO,
                                                  .handleType = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT};
    VkPhysicalDeviceImageFormatInfo2 fi = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_IMAGE_FORMAT_INFO_2,
                                           .pNext = sc->depth ? NULL : &xi,
                                           .format = ic.format,
                                           .type = ic.imageType,
                                           .tiling = ic.tiling,
                                           .usage = ic.usage,
                                           .flags = ic.flags};
    /* the external-memory answer asked for with the external info (Mesa's drivers write it unconditionally) */
    VkExternalImageFormatProperties ep = {.sType = VK_STRUCTURE_TYPE_EXTERNAL_IMAGE_FORMAT_PROPERTIES};
    VkImageFormatProperties2 fp = {.sType = VK_STRUCTURE_TYPE_IMAGE_FORMAT_PROPERTIES_2,
                                   .pNext = sc->depth ? NULL : &ep};
    const XrSwapchainCreateInfo *ci = &sc->info;
    const char *why = NULL;
    if (vkGetPhysicalDeviceImageFormatProperties2(c->vk->phys, &fi, &fp) != VK_SUCCESS)
        why = "the usage flags are not supported for the format";
    else if (ic.extent.width > fp.imageFormatProperties.maxExtent.width ||
             ic.extent.height > fp.imageFormatProperties.maxExtent.height)
        why = "the size exceeds the device's";
    else if (ic.mipLevels > fp.imageFormatProperties.maxMipLevels)
        why = "mipCount exceeds the device's";
    else if (ic.arrayLayers > fp.imageFormatProperties.maxArrayLayers)
        why = "arraySize x faceCount exceeds the device's";
    if (why) {
        FV_ERROR(FV_XR_LOG, "xrCreateSwapchain: format %lld, %ux%u, %u mips, %u layers, usage 0x%llx: %s",
                 (long long)ci->format, ci->width, ci->height, ci->mipCount, ic.arrayLayers,
                 (unsigned long long)ci->usageFlags, why);
        return XR_ERROR_FEATURE_UNSUPPORTED;
    }
    return XR_SUCCESS;
}

/* One image: on fovea's device (exportable, dedicated), then the same on the app's device from the exported fd. */
static XrResult image_init(fv_xr_compositor *c, struct XrSwapchain_T *sc, uint32_t index, fv_xr_swapchain_image *im)
{
    struct XrSession_T *s = sc->session;
    VkDevice ad = s->vk.device, cd = c->vk->device;
    VkExternalMemoryImageCreateInfo ext;
    VkImageCreateInfo ic = image_create_info(sc, &ext);
    bool egl = s->egl != NULL;
    if (egl && sc->depth) return XR_SUCCESS;
    VkMemoryRequirements req;
    if (sc->depth) {
        /* depth images stay on the app's side: the compositor does not read depth */
        if (vkCreateImage(ad, &ic, NULL, &im->app_image) != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
        vkGetImageMemoryRequirements(ad, im->app_image, &req);
        VkPhysicalDeviceMemoryProperties mp;
        vkGetPhysicalDeviceMemoryProperties(s->vk.phys, &mp);
        VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                   .allocationSize = req.size,
                                   .memoryTypeIndex = memory_type(&mp, req.memoryTypeBits,
                                                                  VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)};
        if (vkAllocateMemory(ad, &ai, NULL, &im->app_mem) != VK_SUCCESS) return XR_ERROR_OUT_OF_MEMORY;
        if (vkBindImageMemory(ad, im->app_image, im->app_mem, 0) != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
    } else {
        if (vkCreateImage(cd, &ic, NULL, &im->comp_image) != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
        FV_VK_NAME(c->vk, VK_OBJECT_TYPE_IMAGE, im->comp_image, "xr swapchain %p image %u", (void *)sc, index);
        vkGetImageMemoryRequirements(cd, im->comp_image, &req);
        uint32_t type = memory_type(&c->vk->mem_props, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        VkMemoryDedicatedAllocateInfo ded = {.sType = VK_STRUCTURE_TYPE_MEMORY_DEDICATED_ALLOCATE_INFO,
                                             .image = im->comp_image};
        VkExportMemoryAllocateInfo exp = {.sType = VK_STRUCTURE_TYPE_EXPORT_MEMORY_ALLOCATE_INFO,
                                          .pNext = &ded,
                                          .handleTypes = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT};
        VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                   .pNext = &exp,
                                   .allocationSize = req.size,
                                   .memoryTypeIndex = type};
        if (type == UINT32_MAX || vkAllocateMemory(cd, &ai, NULL, &im->comp_mem) != VK_SUCCESS)
            return XR_ERROR_OUT_OF_MEMORY;
        if (vkBindImageMemory(cd, im->comp_image, im->comp_mem, 0) != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
        VkImageViewCreateInfo vi = {.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
                                    .image = im->comp_image,
                                    .viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY,
                                    .format = sc->format,
                                    .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, ic.arrayLayers}};
        if (vkCreateImageView(cd, &vi, NULL, &im->comp_view) != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
        if (egl) return XR_SUCCESS;
        int fd = -1;
        VkMemoryGetFdInfoKHR gi = {.sType = VK_STRUCTURE_TYPE_MEMORY_GET_FD_INFO_KHR,
                                   .memory = im->comp_mem,
                                   .handleType = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT};
        if (c->get_memory_fd(cd, &gi, &fd) != VK_SUCCESS || fd < 0) return XR_ERROR_RUNTIME_FAILURE;
        if (vkCreateImage(ad, &ic, NULL, &im->app_image) != VK_SUCCESS) {
            close(fd);
            return XR_ERROR_RUNTIME_FAILURE;
        }
        VkMemoryRequirements areq;
        vkGetImageMemoryRequirements(ad, im->app_image, &areq);
        if (!(areq.memoryTypeBits & (1u << type)) || areq.size > req.size) {
            FV_ERROR(FV_XR_LOG, "the app's device cannot import the swapchain memory (type %u, %llu bytes)", type,
                     (unsigned long long)req.size);
            close(fd);
            return XR_ERROR_RUNTIME_FAILURE;
        }
        VkMemoryDedicatedAllocateInfo aded = {.sType = VK_STRUCTURE_TYPE_MEMORY_DEDICATED_ALLOCATE_INFO,
                                              .image = im->app_image};
        VkImportMemoryFdInfoKHR imp = {.sType = VK_STRUCTURE_TYPE_IMPORT_MEMORY_FD_INFO_KHR,
                                       .pNext = &aded,
                                       .handleType = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT,
                                       .fd = fd};
        VkMemoryAllocateInfo aai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                    .pNext = &imp,
                                    .allocationSize = req.size,
                                    .memoryTypeIndex = type};
        if (vkAllocateMemory(ad, &aai, NULL, &im->app_mem) != VK_SUCCESS) {
            close(fd); /* a failed import leaves the fd with us */
            return XR_ERROR_OUT_OF_MEMORY;
        }
        if (vkBindImageMemory(ad, im->app_image, im->app_mem, 0) != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
    }
    VkCommandBufferAllocateInfo cai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                       .commandPool = s->vk.pool,
                                       .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                       .commandBufferCount = 1};
    if (vkAllocateCommandBuffers(ad, &cai, &im->app_cmd) != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO, .flags = VK_FENCE_CREATE_SIGNALED_BIT};
    if (vkCreateFence(ad, &fci, NULL, &im->app_fence) != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
    im->owner = OWNER_UNINIT;
    return XR_SUCCESS;
}

XrResult fv_xr_swapchain_images_create(fv_xr_compositor *c, struct XrSwapchain_T *sc)
{
    XrResult r = image_supported(c, sc);
    if (r != XR_SUCCESS) return r;
    sc->images = calloc(sc->image_count, sizeof *sc->images);
    if (!sc->images) return XR_ERROR_OUT_OF_MEMORY;
    for (uint32_t i = 0; i < sc->image_count; i++) {
        XrResult r = image_init(c, sc, i, &sc->images[i]);
        if (r != XR_SUCCESS) {
            fv_xr_swapchain_images_destroy(c, sc);
            return r;
        }
    }
    return XR_SUCCESS;
}

void fv_xr_swapchain_images_destroy(fv_xr_compositor *c, struct XrSwapchain_T *sc)
{
    if (!sc->images) return;
    fv_xr_compositor_drain(c); /* nothing queued or running may still read them */
    pthread_mutex_lock(&c->gpu_mu);
    vkDeviceWaitIdle(c->vk->device);
    pthread_mutex_unlock(&c->gpu_mu);
    for (uint32_t i = 0; i < sc->image_count; i++) image_fini(c, sc->session, &sc->images[i]);
    free(sc->images);
    sc->images = NULL;
}

VkImage fv_xr_swapchain_app_image(struct XrSwapchain_T *sc, uint32_t index) { return sc->images[index].app_image; }
VkImage fv_xr_swapchain_comp_image(struct XrSwapchain_T *sc, uint32_t index) { return sc->images[index].comp_image; }
struct fv_vk *fv_xr_compositor_vk(fv_xr_compositor *c) { return c->vk; }
int fv_xr_swapchain_export_fd(fv_xr_compositor *c, struct XrSwapchain_T *sc, uint32_t index, uint64_t *out_size)
{
    fv_xr_swapchain_image *im = &sc->images[index];
    if (!im->comp_mem) return -1;
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(c->vk->device, im->comp_image, &req);
    *out_size = req.size; /* the dedicated allocation's size (image_init allocates exactly this) */
    int fd = -1;
    VkMemoryGetFdInfoKHR gi = {.sType = VK_STRUCTURE_TYPE_MEMORY_GET_FD_INFO_KHR,
                               .memory = im->comp_mem,
                               .handleType = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT};
    return c->get_memory_fd(c->vk->device, &gi, &fd) == VK_SUCCESS ? fd : -1;
}

static VkImageLayout app_layout(const struct XrSwapchain_T *sc)
{
    return sc->depth ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
}

VkImageMemoryBarrier fv_xr_image_barrier(const struct XrSwapchain_T *sc, VkImage image, VkImageLayout from,
                                         VkImageLayout to, uint32_t src_family, uint32_t dst_family, VkAccessFlags src,
                                         VkAccessFlags dst)
{
    VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
    if (sc->depth) {
        aspect = VK_IMAGE_ASPECT_DEPTH_BIT;
        if (sc->format == VK_FORMAT_D24_UNORM_S8_UINT || sc->format == VK_FORMAT_D32_SFLOAT_S8_UINT)
            aspect |= VK_IMAGE_ASPECT_STENCIL_BIT;
    }
    return (VkImageMemoryBarrier){.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                                  .srcAccessMask = src,
                                  .dstAccessMask = dst,
                                  .oldLayout = from,
                                  .newLayout = to,
                                  .srcQueueFamilyIndex = src_family,
                                  .dstQueueFamilyIndex = dst_family,
                                  .image = image,
                                  .subresourceRange = {aspect, 0, VK_REMAINING_MIP_LEVELS, 0,
                                                       VK_REMAINING_ARRAY_LAYERS}};
}

/* Record and submit one hand-over on the app's queue, fenced. The fence's previous use has finished. */
static XrResult app_submit(struct XrSession_T *s, fv_xr_swapchain_image *im, const VkImageMemoryBarrier *b,
                           uint32_t count, VkPipelineStageFlags src, VkPipelineStageFlags dst)
{
    VkDevice ad = s->vk.device;
    if (vkWaitForFences(ad, 1, &im->app_fence, VK_TRUE, FV_XR_FENCE_TIMEOUT_NS) != VK_SUCCESS)
        return XR_ERROR_RUNTIME_FAILURE;
    vkResetFences(ad, 1, &im->app_fence);
    vkResetCommandBuffer(im->app_cmd, 0);
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    if (vkBeginCommandBuffer(im->app_cmd, &bi) != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
    vkCmdPipelineBarrier(im->app_cmd, src, dst, 0, 0, NULL, 0, NULL, count, b);
    if (vkEndCommandBuffer(im->app_cmd) != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &im->app_cmd};
    VkResult vr = vkQueueSubmit(s->vk.queue, 1, &si, im->app_fence);
    if (vr == VK_ERROR_DEVICE_LOST) return XR_ERROR_SESSION_LOST;
    return vr == VK_SUCCESS ? XR_SUCCESS : XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_swapchain_image_acquire(fv_xr_compositor *c, struct XrSwapchain_T *sc, uint32_t index)
{
    (void)c;
    fv_xr_swapchain_image *im = &sc->images[index];
    uint32_t fam = sc->session->vk.queue_family;
    VkImageLayout want = app_layout(sc);
    VkAccessFlags use = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    VkImageMemoryBarrier b[2];
    uint32_t n = 0;
    if (im->owner == OWNER_UNINIT) {
        b[n++] = fv_xr_image_barrier(sc, im->app_image, VK_IMAGE_LAYOUT_UNDEFINED, want, VK_QUEUE_FAMILY_IGNORED,
                         VK_QUEUE_FAMILY_IGNORED, 0, use);
    } else if (im->owner == OWNER_EXTERNAL) {
        /* take it from the external owner with the layouts of the release in flight, then into the app's layout */
        b[n++] = fv_xr_image_barrier(sc, im->app_image, im->ext_old, im->ext_new, VK_QUEUE_FAMILY_EXTERNAL, fam, 0, use);
        if (im->ext_new != want)
            b[n++] = fv_xr_image_barrier(sc, im->app_image, im->ext_new, want, VK_QUEUE_FAMILY_IGNORED, VK_QUEUE_FAMILY_IGNORED,
                             use, use);
    } else {
        return XR_SUCCESS; /* the app holds it already in its layout (depth images never leave) */
    }
    XrResult r = app_submit(sc->session, im, b, n, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                            VK_PIPELINE_STAGE_ALL_COMMANDS_BIT);
    if (r == XR_SUCCESS) {
        im->owner = OWNER_APP;
        im->layout = want;
    }
    return r;
}

XrResult fv_xr_swapchain_image_wait(fv_xr_compositor *c, struct XrSwapchain_T *sc, uint32_t index, XrDuration timeout)
{
    (void)c;
    /* the image is the app's once its acquire hand-over has run on the app's queue: queue order already puts the
     * app's later work after it, so waiting here only bounds how far the CPU runs ahead */
    fv_xr_swapchain_image *im = &sc->images[index];
    uint64_t t = timeout < 0 ? 0 : (uint64_t)timeout;
    VkResult vr = vkWaitForFences(sc->session->vk.device, 1, &im->app_fence, VK_TRUE, t);
    if (vr == VK_TIMEOUT) return XR_TIMEOUT_EXPIRED;
    return vr == VK_SUCCESS ? XR_SUCCESS : XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_swapchain_image_release(fv_xr_compositor *c, struct XrSwapchain_T *sc, uint32_t index)
{
    (void)c;
    fv_xr_swapchain_image *im = &sc->images[index];
    if (sc->depth) return XR_SUCCESS; /* stays with the app */
    uint32_t fam = sc->session->vk.queue_family;
    /* release to the external owner (fovea's device), moving to the layout the compose pass samples */
    VkImageMemoryBarrier b = fv_xr_image_barrier(sc, im->app_image, im->layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, fam,
                                     VK_QUEUE_FAMILY_EXTERNAL, VK_ACCESS_MEMORY_WRITE_BIT, 0);
    XrResult r = app_submit(sc->session, im, &b, 1, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                            VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
    if (r == XR_SUCCESS) {
        im->owner = OWNER_EXTERNAL;
        im->ext_old = im->layout;
        im->ext_new = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    }
    return r;
}
