/* @brief The Vulkan side of a small OpenXR app through the loader (XR_KHR_vulkan_enable2): the app's VkInstance and
 * VkDevice made by the runtime, on the physical device it names, with one graphics queue. Shared by xr_quad_app and
 * test_xr_misuse. Any failed call prints the call and its result and exits (status 1). */
#ifndef FV_XR_APP_VK_H
#define FV_XR_APP_VK_H

#include <stdint.h>

#include <vulkan/vulkan.h>
#define XR_USE_GRAPHICS_API_VULKAN 1
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

typedef struct xr_app_vk {
    VkInstance instance;
    VkPhysicalDevice phys;
    VkDevice device;
    uint32_t family; /* the graphics queue family (queue 0 of it) */
} xr_app_vk;

/** The instance from `ici` (the app's layers and extensions) and a device with one graphics queue, through
 *  xrCreateVulkanInstanceKHR / xrGetVulkanGraphicsDevice2KHR / xrCreateVulkanDeviceKHR (the graphics requirements
 *  queried first). */
void xr_app_vk_create(XrInstance inst, XrSystemId system, const VkInstanceCreateInfo *ici, xr_app_vk *out);
/** Clear mip 0, layer 0 of an image in `layout` (left in it) to rgba on queue 0, waited for (the image needs
 *  TRANSFER_DST usage). */
void xr_app_vk_clear(const xr_app_vk *vk, VkImage image, VkImageLayout layout, const float rgba[4]);
/** Fill mip 0, layer 0 of an image in `layout` (left in it) with w x h RGBA8 texels (rows top down) on queue 0,
 *  waited for (the image needs TRANSFER_DST usage and a 4-byte texel format). */
void xr_app_vk_upload(const xr_app_vk *vk, VkImage image, VkImageLayout layout, uint32_t w, uint32_t h,
                      const uint8_t *rgba8);
/** The binding for xrCreateSession. */
XrGraphicsBindingVulkanKHR xr_app_vk_binding(const xr_app_vk *vk);

#endif
