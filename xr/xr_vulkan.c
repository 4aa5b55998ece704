/* @brief XR_KHR_vulkan_enable and XR_KHR_vulkan_enable2: the app's Vulkan instance and device must be able to import
 * the swapchain memory fovea's device exports (VK_KHR_external_memory_fd) and must run on fovea's physical device
 * (matched by device UUID). The compositor's device is created on the first graphics call. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "xr_internal.h"

static const char *const g_instance_exts[] = {VK_KHR_EXTERNAL_MEMORY_CAPABILITIES_EXTENSION_NAME,
                                              VK_KHR_GET_PHYSICAL_DEVICE_PROPERTIES_2_EXTENSION_NAME};
static const char *const g_device_exts[] = {VK_KHR_EXTERNAL_MEMORY_EXTENSION_NAME,
                                            VK_KHR_EXTERNAL_MEMORY_FD_EXTENSION_NAME,
                                            VK_KHR_DEDICATED_ALLOCATION_EXTENSION_NAME,
                                            VK_KHR_GET_MEMORY_REQUIREMENTS_2_EXTENSION_NAME};
#define N_INSTANCE_EXTS 2u
#define N_DEVICE_EXTS 4u

/* The compositor's device (created once per instance). Instance lock held. */
static XrResult ensure_compositor(struct XrInstance_T *inst)
{
    if (inst->comp) return XR_SUCCESS;
    fv_result res = fv_xr_compositor_create(inst, &inst->comp);
    if (res != FV_OK) {
        FV_ERROR(FV_XR_LOG, "no Vulkan device for the compositor: %s", fv_result_str(res));
        return XR_ERROR_RUNTIME_FAILURE;
    }
    return XR_SUCCESS;
}

/* A space-separated list with the two-call idiom (count includes the terminating NUL). */
static XrResult ext_string(const char *const *names, uint32_t n, uint32_t cap, uint32_t *count, char *buffer)
{
    if (!count || (cap && !buffer)) return XR_ERROR_VALIDATION_FAILURE;
    size_t len = 0;
    for (uint32_t i = 0; i < n; i++) len += strlen(names[i]) + 1;
    *count = (uint32_t)len;
    if (cap == 0) return XR_SUCCESS;
    if (cap < len) return XR_ERROR_SIZE_INSUFFICIENT;
    buffer[0] = 0;
    for (uint32_t i = 0; i < n; i++) {
        strcat(buffer, names[i]);
        if (i + 1 < n) strcat(buffer, " ");
    }
    return XR_SUCCESS;
}

static XrResult check(XrInstance instance, XrSystemId system, struct XrInstance_T **out)
{
    struct XrInstance_T *inst = fv_xr_instance_check(instance);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (system != FV_XR_SYSTEM_ID) return XR_ERROR_SYSTEM_INVALID;
    *out = inst;
    return XR_SUCCESS;
}

FV_XR_DECL(xrGetVulkanInstanceExtensionsKHR)(XrInstance instance, XrSystemId system, uint32_t cap, uint32_t *count,
                                             char *buffer)
{
    struct XrInstance_T *inst;
    XrResult r = check(instance, system, &inst);
    return r != XR_SUCCESS ? r : ext_string(g_instance_exts, N_INSTANCE_EXTS, cap, count, buffer);
}

FV_XR_DECL(xrGetVulkanDeviceExtensionsKHR)(XrInstance instance, XrSystemId system, uint32_t cap, uint32_t *count,
                                           char *buffer)
{
    struct XrInstance_T *inst;
    XrResult r = check(instance, system, &inst);
    return r != XR_SUCCESS ? r : ext_string(g_device_exts, N_DEVICE_EXTS, cap, count, buffer);
}

FV_XR_DECL(xrGetVulkanGraphicsRequirementsKHR)(XrInstance instance, XrSystemId system,
                                               XrGraphicsRequirementsVulkanKHR *req)
{
    struct XrInstance_T *inst;
    XrResult r = check(instance, system, &inst);
    if (r != XR_SUCCESS) return r;
    if (!req || req->type != XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN_KHR) return XR_ERROR_VALIDATION_FAILURE;
    pthread_mutex_lock(&inst->lock);
    r = ensure_compositor(inst);
    if (r == XR_SUCCESS) {
        uint32_t v = fv_xr_compositor_api_version(inst->comp);
        /* Vulkan 1.0 apps work (with the extensions listed); the device's own version is the most they may use */
        req->minApiVersionSupported = XR_MAKE_VERSION(1, 0, 0);
        req->maxApiVersionSupported = XR_MAKE_VERSION(VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v), 0);
        inst->graphics_requirements_queried = true;
    }
    pthread_mutex_unlock(&inst->lock);
    return r;
}

/* The app instance's physical device that is fovea's (same device UUID). */
static XrResult match_device(struct XrInstance_T *inst, VkInstance vi, PFN_vkGetInstanceProcAddr gipa,
                             VkPhysicalDevice *out)
{
    if (vi == VK_NULL_HANDLE) return XR_ERROR_VALIDATION_FAILURE;
    XrResult r = ensure_compositor(inst);
    if (r != XR_SUCCESS) return r;
    PFN_vkEnumeratePhysicalDevices enumerate = (PFN_vkEnumeratePhysicalDevices)gipa(vi, "vkEnumeratePhysicalDevices");
    PFN_vkGetPhysicalDeviceProperties2 props2 =
        (PFN_vkGetPhysicalDeviceProperties2)gipa(vi, "vkGetPhysicalDeviceProperties2");
    if (!props2) props2 = (PFN_vkGetPhysicalDeviceProperties2)gipa(vi, "vkGetPhysicalDeviceProperties2KHR");
    if (!enumerate || !props2) {
        FV_ERROR(FV_XR_LOG, "the app's Vulkan instance lacks vkGetPhysicalDeviceProperties2 (enable "
                            "VK_KHR_get_physical_device_properties2 as xrGetVulkanInstanceExtensionsKHR says)");
        return XR_ERROR_RUNTIME_FAILURE;
    }
    uint32_t n = 0;
    if (enumerate(vi, &n, NULL) != VK_SUCCESS || n == 0) return XR_ERROR_RUNTIME_FAILURE;
    VkPhysicalDevice *pd = calloc(n, sizeof *pd);
    if (!pd) return XR_ERROR_OUT_OF_MEMORY;
    enumerate(vi, &n, pd);
    uint8_t uuid[VK_UUID_SIZE];
    fv_xr_compositor_device_uuid(inst->comp, uuid);
    r = XR_ERROR_RUNTIME_FAILURE;
    for (uint32_t i = 0; i < n && r != XR_SUCCESS; i++) {
        VkPhysicalDeviceIDProperties id = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES};
        VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &id};
        props2(pd[i], &p2);
        if (memcmp(id.deviceUUID, uuid, VK_UUID_SIZE) == 0) {
            *out = pd[i];
            r = XR_SUCCESS;
        }
    }
    free(pd);
    if (r != XR_SUCCESS) FV_ERROR(FV_XR_LOG, "the app's Vulkan instance does not see fovea's device");
    return r;
}

FV_XR_DECL(xrGetVulkanGraphicsDeviceKHR)(XrInstance instance, XrSystemId system, VkInstance vk_instance,
                                         VkPhysicalDevice *out)
{
    struct XrInstance_T *inst;
    XrResult r = check(instance, system, &inst);
    if (r != XR_SUCCESS) return r;
    if (!out) return XR_ERROR_VALIDATION_FAILURE;
    pthread_mutex_lock(&inst->lock);
    r = match_device(inst, vk_instance, vkGetInstanceProcAddr, out);
    pthread_mutex_unlock(&inst->lock);
    return r;
}

FV_XR_DECL(xrGetVulkanGraphicsDevice2KHR)(XrInstance instance, const XrVulkanGraphicsDeviceGetInfoKHR *info,
                                          VkPhysicalDevice *out)
{
    if (!info || info->type != XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR || !out)
        return fv_xr_instance_check(instance) ? XR_ERROR_VALIDATION_FAILURE : XR_ERROR_HANDLE_INVALID;
    struct XrInstance_T *inst;
    XrResult r = check(instance, info->systemId, &inst);
    if (r != XR_SUCCESS) return r;
    pthread_mutex_lock(&inst->lock);
    r = match_device(inst, info->vulkanInstance, vkGetInstanceProcAddr, out);
    pthread_mutex_unlock(&inst->lock);
    return r;
}

/* The app's extension list plus fovea's (no duplicates). The strings are the caller's or static. */
static const char **merge(const char *const *have, uint32_t n, const char *const *add, uint32_t m, uint32_t *out_n)
{
    const char **list = calloc((size_t)n + m, sizeof *list);
    if (!list) return NULL;
    uint32_t k = 0;
    for (uint32_t i = 0; i < n; i++) list[k++] = have[i];
    for (uint32_t j = 0; j < m; j++) {
        bool dup = false;
        for (uint32_t i = 0; i < n && !dup; i++) dup = strcmp(have[i], add[j]) == 0;
        if (!dup) list[k++] = add[j];
    }
    *out_n = k;
    return list;
}

FV_XR_DECL(xrCreateVulkanInstanceKHR)(XrInstance instance, const XrVulkanInstanceCreateInfoKHR *info,
                                      VkInstance *out, VkResult *out_result)
{
    if (!info || info->type != XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR || !out || !out_result)
        return fv_xr_instance_check(instance) ? XR_ERROR_VALIDATION_FAILURE : XR_ERROR_HANDLE_INVALID;
    struct XrInstance_T *inst;
    XrResult r = check(instance, info->systemId, &inst);
    if (r != XR_SUCCESS) return r;
    if (info->createFlags != 0 || !info->pfnGetInstanceProcAddr || !info->vulkanCreateInfo)
        return XR_ERROR_VALIDATION_FAILURE;
    PFN_vkCreateInstance create = (PFN_vkCreateInstance)info->pfnGetInstanceProcAddr(VK_NULL_HANDLE, "vkCreateInstance");
    if (!create) return XR_ERROR_RUNTIME_FAILURE;
    VkInstanceCreateInfo ci = *info->vulkanCreateInfo;
    uint32_t n = 0;
    const char **exts = merge(ci.ppEnabledExtensionNames, ci.enabledExtensionCount, g_instance_exts, N_INSTANCE_EXTS, &n);
    if (!exts) return XR_ERROR_OUT_OF_MEMORY;
    ci.ppEnabledExtensionNames = exts;
    ci.enabledExtensionCount = n;
    *out_result = create(&ci, info->vulkanAllocator, out);
    free(exts);
    return XR_SUCCESS; /* a Vulkan failure is the app's to read in out_result */
}

FV_XR_DECL(xrCreateVulkanDeviceKHR)(XrInstance instance, const XrVulkanDeviceCreateInfoKHR *info, VkDevice *out,
                                    VkResult *out_result)
{
    if (!info || info->type != XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR || !out || !out_result)
        return fv_xr_instance_check(instance) ? XR_ERROR_VALIDATION_FAILURE : XR_ERROR_HANDLE_INVALID;
    struct XrInstance_T *inst;
    XrResult r = check(instance, info->systemId, &inst);
    if (r != XR_SUCCESS) return r;
    if (info->createFlags != 0 || !info->pfnGetInstanceProcAddr || !info->vulkanCreateInfo ||
        info->vulkanPhysicalDevice == VK_NULL_HANDLE)
        return XR_ERROR_VALIDATION_FAILURE;
    pthread_mutex_lock(&inst->lock);
    r = ensure_compositor(inst);
    pthread_mutex_unlock(&inst->lock);
    if (r != XR_SUCCESS) return r;
    /* the physical device must be the one xrGetVulkanGraphicsDevice2KHR named */
    if (!fv_xr_compositor_same_device(inst->comp, info->vulkanPhysicalDevice)) return XR_ERROR_GRAPHICS_DEVICE_INVALID;
    /* vkCreateDevice is a physical-device-level command: the loader's trampoline dispatches it from any instance */
    VkDeviceCreateInfo ci = *info->vulkanCreateInfo;
    uint32_t n = 0;
    const char **exts = merge(ci.ppEnabledExtensionNames, ci.enabledExtensionCount, g_device_exts, N_DEVICE_EXTS, &n);
    if (!exts) return XR_ERROR_OUT_OF_MEMORY;
    ci.ppEnabledExtensionNames = exts;
    ci.enabledExtensionCount = n;
    *out_result = vkCreateDevice(info->vulkanPhysicalDevice, &ci, info->vulkanAllocator, out);
    free(exts);
    return XR_SUCCESS;
}
