/* @brief The Vulkan side of the xr test apps (see xr_app_vk.h). */
#include "xr_app_vk.h"

#include <stdio.h>
#include <string.h>
#include <stdlib.h>

#define VK_APP_CHECK(call, ok)                                                                                         \
    do {                                                                                                               \
        long long r_ = (long long)(call);                                                                              \
        if (r_ != (ok)) {                                                                                              \
            fprintf(stderr, "%s failed: %lld\n", #call, r_);                                                           \
            exit(1);                                                                                                   \
        }                                                                                                              \
    } while (0)
#define XR(call) VK_APP_CHECK(call, XR_SUCCESS)
#define VK(call) VK_APP_CHECK(call, VK_SUCCESS)

void xr_app_vk_create(XrInstance inst, XrSystemId system, const VkInstanceCreateInfo *ici, xr_app_vk *out)
{
    PFN_xrGetVulkanGraphicsRequirements2KHR get_req = NULL;
    PFN_xrCreateVulkanInstanceKHR create_inst = NULL;
    PFN_xrGetVulkanGraphicsDevice2KHR get_dev = NULL;
    PFN_xrCreateVulkanDeviceKHR create_dev = NULL;
    XR(xrGetInstanceProcAddr(inst, "xrGetVulkanGraphicsRequirements2KHR", (PFN_xrVoidFunction *)&get_req));
    XR(xrGetInstanceProcAddr(inst, "xrCreateVulkanInstanceKHR", (PFN_xrVoidFunction *)&create_inst));
    XR(xrGetInstanceProcAddr(inst, "xrGetVulkanGraphicsDevice2KHR", (PFN_xrVoidFunction *)&get_dev));
    XR(xrGetInstanceProcAddr(inst, "xrCreateVulkanDeviceKHR", (PFN_xrVoidFunction *)&create_dev));
    XrGraphicsRequirementsVulkan2KHR req = {.type = XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN2_KHR};
    XR(get_req(inst, system, &req));
    XrVulkanInstanceCreateInfoKHR xi = {.type = XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR,
                                        .systemId = system,
                                        .pfnGetInstanceProcAddr = vkGetInstanceProcAddr,
                                        .vulkanCreateInfo = ici};
    VkResult vr = VK_SUCCESS;
    XR(create_inst(inst, &xi, &out->instance, &vr));
    VK(vr);
    XrVulkanGraphicsDeviceGetInfoKHR dgi = {.type = XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR,
                                            .systemId = system,
                                            .vulkanInstance = out->instance};
    XR(get_dev(inst, &dgi, &out->phys));
    uint32_t nf = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(out->phys, &nf, NULL);
    VkQueueFamilyProperties qf[16];
    if (nf > 16) nf = 16;
    vkGetPhysicalDeviceQueueFamilyProperties(out->phys, &nf, qf);
    out->family = UINT32_MAX;
    for (uint32_t i = 0; i < nf && out->family == UINT32_MAX; i++)
        if (qf[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) out->family = i;
    if (out->family == UINT32_MAX) {
        fprintf(stderr, "xr_app_vk: the runtime's physical device has no graphics queue\n");
        exit(1);
    }
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
                                  .queueFamilyIndex = out->family,
                                  .queueCount = 1,
                                  .pQueuePriorities = &prio};
    VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, .queueCreateInfoCount = 1,
                              .pQueueCreateInfos = &qi};
    XrVulkanDeviceCreateInfoKHR xd = {.type = XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR,
                                      .systemId = system,
                                      .pfnGetInstanceProcAddr = vkGetInstanceProcAddr,
                                      .vulkanPhysicalDevice = out->phys,
                                      .vulkanCreateInfo = &dci};
    XR(create_dev(inst, &xd, &out->device, &vr));
    VK(vr);
}

XrGraphicsBindingVulkanKHR xr_app_vk_binding(const xr_app_vk *vk)
{
    return (XrGraphicsBindingVulkanKHR){.type = XR_TYPE_GRAPHICS_BINDING_VULKAN_KHR,
                                        .instance = vk->instance,
                                        .physicalDevice = vk->phys,
                                        .device = vk->device,
                                        .queueFamilyIndex = vk->family,
                                        .queueIndex = 0};
}

/* What a transfer writes into mip 0, layer 0 of an image in TRANSFER_DST_OPTIMAL: a clear colour or a buffer. */
typedef struct transfer_src {
    const float *rgba;
    VkBuffer buffer;
    uint32_t w, h;
} transfer_src;

/* One transfer into `image` (in `layout`, left in it) on queue 0, waited for. */
static void transfer(const xr_app_vk *vk, VkImage image, VkImageLayout layout, const transfer_src *src)
{
    VkQueue q;
    vkGetDeviceQueue(vk->device, vk->family, 0, &q);
    VkCommandPoolCreateInfo pi = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO, .queueFamilyIndex = vk->family};
    VkCommandPool pool;
    VK(vkCreateCommandPool(vk->device, &pi, NULL, &pool));
    VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, .commandPool = pool,
                                      .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY, .commandBufferCount = 1};
    VkCommandBuffer cmd;
    VK(vkAllocateCommandBuffers(vk->device, &ai, &cmd));
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    VK(vkBeginCommandBuffer(cmd, &bi));
    VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkImageMemoryBarrier b = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT,
                              .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .oldLayout = layout, .newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                              .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                              .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED, .image = image,
                              .subresourceRange = range};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0, NULL,
                         1, &b);
    if (src->rgba) {
        VkClearColorValue c = {.float32 = {src->rgba[0], src->rgba[1], src->rgba[2], src->rgba[3]}};
        vkCmdClearColorImage(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &c, 1, &range);
    } else {
        VkBufferImageCopy r = {.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                               .imageExtent = {src->w, src->h, 1}};
        vkCmdCopyBufferToImage(cmd, src->buffer, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &r);
    }
    b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    b.newLayout = layout;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, NULL, 0, NULL,
                         1, &b);
    VK(vkEndCommandBuffer(cmd));
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &cmd};
    VK(vkQueueSubmit(q, 1, &si, VK_NULL_HANDLE));
    VK(vkQueueWaitIdle(q));
    vkDestroyCommandPool(vk->device, pool, NULL);
}

void xr_app_vk_clear(const xr_app_vk *vk, VkImage image, VkImageLayout layout, const float rgba[4])
{
    transfer(vk, image, layout, &(transfer_src){.rgba = rgba});
}

void xr_app_vk_upload(const xr_app_vk *vk, VkImage image, VkImageLayout layout, uint32_t w, uint32_t h,
                      const uint8_t *rgba8)
{
    VkDeviceSize size = (VkDeviceSize)w * h * 4;
    VkBufferCreateInfo bci = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO, .size = size,
                              .usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT};
    VkBuffer buf;
    VK(vkCreateBuffer(vk->device, &bci, NULL, &buf));
    VkMemoryRequirements mr;
    vkGetBufferMemoryRequirements(vk->device, buf, &mr);
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(vk->phys, &mp);
    const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    uint32_t type = 0;
    while (type < mp.memoryTypeCount &&
           !((mr.memoryTypeBits & (1u << type)) && (mp.memoryTypes[type].propertyFlags & want) == want))
        type++;
    if (type == mp.memoryTypeCount) {
        fprintf(stderr, "xr_app_vk: no host-visible coherent memory for the upload\n");
        exit(1);
    }
    VkMemoryAllocateInfo mai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, .allocationSize = mr.size,
                                .memoryTypeIndex = type};
    VkDeviceMemory mem;
    VK(vkAllocateMemory(vk->device, &mai, NULL, &mem));
    VK(vkBindBufferMemory(vk->device, buf, mem, 0));
    void *p;
    VK(vkMapMemory(vk->device, mem, 0, size, 0, &p));
    memcpy(p, rgba8, (size_t)size);
    vkUnmapMemory(vk->device, mem);
    transfer(vk, image, layout, &(transfer_src){.buffer = buf, .w = w, .h = h});
    vkDestroyBuffer(vk->device, buf, NULL);
    vkFreeMemory(vk->device, mem, NULL);
}
