/* @brief The Vulkan side of the xr test apps (see xr_app_vk.h). */
#include "xr_app_vk.h"

#include <stdio.h>
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
