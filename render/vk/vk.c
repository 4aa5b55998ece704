/* @brief Vulkan core: instance, validation messenger, device listing and selection, queue, pool, debug names. */
#include "fv_vk.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MOD "vk"
#define VALIDATION_LAYER "VK_LAYER_KHRONOS_validation"
#define MAX_DEVICES 16

const char *fv_vk_result_str(VkResult r)
{
    switch (r) {
#define C(x) case x: return #x;
        C(VK_SUCCESS) C(VK_NOT_READY) C(VK_TIMEOUT) C(VK_EVENT_SET) C(VK_EVENT_RESET) C(VK_INCOMPLETE)
        C(VK_ERROR_OUT_OF_HOST_MEMORY) C(VK_ERROR_OUT_OF_DEVICE_MEMORY) C(VK_ERROR_INITIALIZATION_FAILED)
        C(VK_ERROR_DEVICE_LOST) C(VK_ERROR_MEMORY_MAP_FAILED) C(VK_ERROR_LAYER_NOT_PRESENT)
        C(VK_ERROR_EXTENSION_NOT_PRESENT) C(VK_ERROR_FEATURE_NOT_PRESENT) C(VK_ERROR_INCOMPATIBLE_DRIVER)
        C(VK_ERROR_TOO_MANY_OBJECTS) C(VK_ERROR_FORMAT_NOT_SUPPORTED) C(VK_ERROR_FRAGMENTED_POOL)
        C(VK_ERROR_UNKNOWN) C(VK_ERROR_OUT_OF_POOL_MEMORY) C(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        C(VK_ERROR_FRAGMENTATION) C(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS) C(VK_PIPELINE_COMPILE_REQUIRED)
        C(VK_ERROR_SURFACE_LOST_KHR) C(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR) C(VK_SUBOPTIMAL_KHR)
        C(VK_ERROR_OUT_OF_DATE_KHR) C(VK_ERROR_VALIDATION_FAILED_EXT)
#undef C
    default: return "VK_RESULT_UNKNOWN";
    }
}

fv_result fv_vk_fail(VkResult r, const char *call, const char *file, int line)
{
    fv_log_write(FV_LOG_LEVEL_ERROR, MOD, file, line, "%s failed: %s (%d) at %s:%d", call, fv_vk_result_str(r),
                 (int)r, file, line);
    if (r == VK_ERROR_DEVICE_LOST) return FV_ERR_DEVICE_LOST;
    if (r == VK_ERROR_OUT_OF_HOST_MEMORY || r == VK_ERROR_OUT_OF_DEVICE_MEMORY) return FV_ERR_NO_MEMORY;
    if (r == VK_ERROR_FEATURE_NOT_PRESENT || r == VK_ERROR_EXTENSION_NOT_PRESENT ||
        r == VK_ERROR_FORMAT_NOT_SUPPORTED || r == VK_ERROR_INCOMPATIBLE_DRIVER)
        return FV_ERR_UNSUPPORTED;
    return FV_ERR_VULKAN;
}

const char *fv_vk_device_type_str(VkPhysicalDeviceType t)
{
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
    }
}

/* ---- validation messenger ------------------------------------------------------------------------------------ */

static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                 VkDebugUtilsMessageTypeFlagsEXT types,
                                                 const VkDebugUtilsMessengerCallbackDataEXT *data, void *user)
{
    fv_vk *vk = user;
    const char *msg = (data && data->pMessage) ? data->pMessage : "(no message)";
    const char *kind = (types & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT)    ? "validation"
                       : (types & VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT) ? "performance"
                                                                                    : "general";
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        if (vk) atomic_fetch_add(&vk->validation_messages, 1u);
        FV_ERROR(MOD, "%s error: %s", kind, msg);
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        if (vk) atomic_fetch_add(&vk->validation_messages, 1u);
        FV_WARN(MOD, "%s warning: %s", kind, msg);
    } else {
        FV_DEBUG(MOD, "%s: %s", kind, msg);
    }
    return VK_FALSE;
}

static VkDebugUtilsMessengerCreateInfoEXT messenger_info(fv_vk *vk)
{
    VkDebugUtilsMessengerCreateInfoEXT ci = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = on_message,
        .pUserData = vk,
    };
    if (fv_log_enabled(MOD, FV_LOG_LEVEL_DEBUG))
        ci.messageSeverity |= VK_DEBUG_UTILS_MESSAGE_SEVERITY_INFO_BIT_EXT;
    return ci;
}

/* ---- instance ------------------------------------------------------------------------------------------------ */

static bool has_extension(const VkExtensionProperties *exts, uint32_t n, const char *name)
{
    for (uint32_t i = 0; i < n; i++)
        if (strcmp(exts[i].extensionName, name) == 0) return true;
    return false;
}

static bool layer_present(const char *name)
{
    uint32_t n = 0;
    if (vkEnumerateInstanceLayerProperties(&n, NULL) != VK_SUCCESS || n == 0) return false;
    VkLayerProperties *layers = calloc(n, sizeof *layers);
    if (!layers) return false;
    bool found = false;
    if (vkEnumerateInstanceLayerProperties(&n, layers) >= 0)
        for (uint32_t i = 0; i < n; i++)
            if (strcmp(layers[i].layerName, name) == 0) found = true;
    free(layers);
    return found;
}

/* Creates the instance; vk may be NULL (device listing): then no validation and no messenger. */
static fv_result create_instance(fv_vk *vk, bool validation, const char *app_name, const fv_vk_desc *want,
                                 VkInstance *out, bool *out_debug_utils)
{
    uint32_t api = 0;
    FV_VK_CHECK(vkEnumerateInstanceVersion(&api));
    if (api < VK_API_VERSION_1_2) {
        FV_ERROR(MOD, "the Vulkan loader offers %u.%u; fovea needs 1.2 or newer", VK_API_VERSION_MAJOR(api),
                 VK_API_VERSION_MINOR(api));
        return FV_ERR_UNSUPPORTED;
    }
    uint32_t n = 0;
    FV_VK_CHECK(vkEnumerateInstanceExtensionProperties(NULL, &n, NULL));
    VkExtensionProperties *exts = calloc(n ? n : 1, sizeof *exts);
    if (!exts) return FV_ERR_NO_MEMORY;
    VkResult vr = vkEnumerateInstanceExtensionProperties(NULL, &n, exts);
    if (vr < 0) {
        free(exts);
        return fv_vk_fail(vr, "vkEnumerateInstanceExtensionProperties", __FILE__, __LINE__);
    }
    const char *enabled[FV_VK_MAX_EXTENSIONS + 3];
    uint32_t count = 0;
    bool debug_utils = has_extension(exts, n, VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    bool portability = has_extension(exts, n, "VK_KHR_portability_enumeration");
    if (debug_utils) enabled[count++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    if (portability) enabled[count++] = "VK_KHR_portability_enumeration";
    /* What a surface target asks for (VK_KHR_surface implied), each checked before the instance is made. */
    const char *asked[FV_VK_MAX_EXTENSIONS + 1];
    uint32_t asked_count = 0;
    if (want && want->create_surface) asked[asked_count++] = VK_KHR_SURFACE_EXTENSION_NAME;
    for (uint32_t i = 0; want && i < want->instance_extension_count && asked_count < FV_VK_MAX_EXTENSIONS; i++)
        asked[asked_count++] = want->instance_extensions[i];
    for (uint32_t i = 0; i < asked_count; i++) {
        bool dup = false;
        for (uint32_t k = 0; k < count; k++) dup = dup || strcmp(enabled[k], asked[i]) == 0;
        if (dup) continue;
        if (!has_extension(exts, n, asked[i])) {
            FV_ERROR(MOD, "the Vulkan loader lacks instance extension %s (needed to present to a window)", asked[i]);
            free(exts);
            return FV_ERR_UNSUPPORTED;
        }
        enabled[count++] = asked[i];
    }
    free(exts);

    const char *layers[1] = {VALIDATION_LAYER};
    if (validation && !layer_present(VALIDATION_LAYER)) {
        FV_ERROR(MOD, "validation requested but %s is not installed (Debian: vulkan-validationlayers)",
                 VALIDATION_LAYER);
        return FV_ERR_UNSUPPORTED;
    }
    if (validation && !debug_utils) {
        FV_ERROR(MOD, "validation requested but %s is missing: messages could not be counted",
                 VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
        return FV_ERR_UNSUPPORTED;
    }

    VkApplicationInfo app = {
        .sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
        .pApplicationName = app_name ? app_name : "fovea",
        .applicationVersion = VK_MAKE_API_VERSION(0, 0, 1, 0),
        .pEngineName = "fovea",
        .engineVersion = VK_MAKE_API_VERSION(0, 0, 1, 0),
        .apiVersion = VK_API_VERSION_1_2,
    };
    /* Synchronization validation catches missing barriers that serial CPU execution would hide. */
    VkValidationFeatureEnableEXT features[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT vf = {
        .sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT,
        .enabledValidationFeatureCount = 1,
        .pEnabledValidationFeatures = features,
    };
    VkDebugUtilsMessengerCreateInfoEXT mi;
    VkInstanceCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
        .pApplicationInfo = &app,
        .enabledExtensionCount = count,
        .ppEnabledExtensionNames = enabled,
        .flags = portability ? 0x00000001 /* VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR */ : 0,
    };
    if (validation) {
        ci.enabledLayerCount = 1;
        ci.ppEnabledLayerNames = layers;
        mi = messenger_info(vk);
        const char *sync = getenv("FOVEA_VALIDATION_SYNC");
        if (!sync || strcmp(sync, "0") != 0) mi.pNext = &vf;
        ci.pNext = &mi; /* messages during vkCreateInstance itself */
    }
    FV_VK_CHECK(vkCreateInstance(&ci, NULL, out));
    *out_debug_utils = debug_utils;
    return FV_OK;
}

/* ---- device description -------------------------------------------------------------------------------------- */

static int find_queue_family(VkPhysicalDevice pd, bool *out_timestamps)
{
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, NULL);
    if (n == 0 || n > 64) return -1;
    VkQueueFamilyProperties q[64];
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, q);
    for (uint32_t i = 0; i < n; i++) {
        VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
        if ((q[i].queueFlags & need) == need && q[i].queueCount > 0) {
            *out_timestamps = q[i].timestampValidBits > 0;
            return (int)i;
        }
    }
    return -1;
}

static void describe(VkPhysicalDevice pd, uint32_t index, fv_vk_device_info *d)
{
    memset(d, 0, sizeof *d);
    d->index = index;
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(pd, &p);
    snprintf(d->name, sizeof d->name, "%s", p.deviceName);
    d->type = p.deviceType;
    d->api_version = p.apiVersion;
    d->driver_version = p.driverVersion;
    d->max_image_dimension_2d = p.limits.maxImageDimension2D;
    d->max_compute_workgroup_invocations = p.limits.maxComputeWorkGroupInvocations;
    d->timestamp_period_ns = p.limits.timestampPeriod;
    if (p.apiVersion < VK_API_VERSION_1_2) {
        snprintf(d->why_not, sizeof d->why_not, "Vulkan %u.%u (fovea needs 1.2)", VK_API_VERSION_MAJOR(p.apiVersion),
                 VK_API_VERSION_MINOR(p.apiVersion));
        return;
    }
    VkPhysicalDeviceDriverProperties drv = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceMultiviewProperties mvp = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MULTIVIEW_PROPERTIES,
                                               .pNext = &drv};
    VkPhysicalDeviceSubgroupProperties sg = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES,
                                             .pNext = &mvp};
    VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &sg};
    vkGetPhysicalDeviceProperties2(pd, &p2);
    snprintf(d->driver_name, sizeof d->driver_name, "%s", drv.driverName);
    snprintf(d->driver_info, sizeof d->driver_info, "%s", drv.driverInfo);
    d->subgroup_size = sg.subgroupSize;
    d->max_multiview_views = mvp.maxMultiviewViewCount;
    d->shader_loop_limit = fv_vk_is_llvmpipe(d) ? FV_VK_LLVMPIPE_LOOP_LIMIT : 0u;

    VkPhysicalDeviceVulkan12Features f12 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceVulkan11Features f11 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES,
                                            .pNext = &f12};
    VkPhysicalDeviceFeatures2 f2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &f11};
    vkGetPhysicalDeviceFeatures2(pd, &f2);
    d->multiview = f11.multiview;
    d->descriptor_indexing = f12.descriptorIndexing && f12.runtimeDescriptorArray;
    d->storage_image_write_without_format = f2.features.shaderStorageImageWriteWithoutFormat;

    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(pd, &mp);
    for (uint32_t i = 0; i < mp.memoryHeapCount; i++)
        if ((mp.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) && mp.memoryHeaps[i].size > d->device_local_bytes)
            d->device_local_bytes = mp.memoryHeaps[i].size;

    bool ts = false;
    int qf = find_queue_family(pd, &ts);
    d->timestamps = ts && p.limits.timestampComputeAndGraphics;
    if (qf < 0) snprintf(d->why_not, sizeof d->why_not, "no queue family with graphics and compute");
    else if (!d->multiview || d->max_multiview_views < 2)
        snprintf(d->why_not, sizeof d->why_not, "no multiview (stereo needs 2 views)");
    else d->usable = true;
}

/* A queue family of pd that can present to surface: `prefer` when it can, else the first that can; -1 if none. */
static int present_family(VkPhysicalDevice pd, VkSurfaceKHR surface, uint32_t prefer)
{
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, NULL);
    int first = -1;
    for (uint32_t i = 0; i < n && i < 64; i++) {
        VkBool32 ok = VK_FALSE;
        if (vkGetPhysicalDeviceSurfaceSupportKHR(pd, i, surface, &ok) != VK_SUCCESS || !ok) continue;
        if (i == prefer) return (int)i;
        if (first < 0) first = (int)i;
    }
    return first;
}

/* A device that cannot serve the asked-for presentation (device extensions, a family presenting to the surface)
 * is not usable; why_not says what it lacks. */
static void require_presentation(VkPhysicalDevice pd, fv_vk_device_info *d, const fv_vk_desc *want,
                                 VkSurfaceKHR surface)
{
    if (!d->usable) return;
    uint32_t n = 0;
    if (vkEnumerateDeviceExtensionProperties(pd, NULL, &n, NULL) < 0) n = 0;
    VkExtensionProperties *exts = calloc(n ? n : 1, sizeof *exts);
    if (!exts) return;
    if (vkEnumerateDeviceExtensionProperties(pd, NULL, &n, exts) < 0) n = 0;
    const char *missing = NULL;
    if (surface && !has_extension(exts, n, VK_KHR_SWAPCHAIN_EXTENSION_NAME)) missing = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
    for (uint32_t i = 0; !missing && i < want->device_extension_count; i++)
        if (!has_extension(exts, n, want->device_extensions[i])) missing = want->device_extensions[i];
    free(exts);
    if (missing) {
        d->usable = false;
        snprintf(d->why_not, sizeof d->why_not, "lacks device extension %s", missing);
    } else if (surface && present_family(pd, surface, 0) < 0) {
        d->usable = false;
        snprintf(d->why_not, sizeof d->why_not, "no queue family can present to the window's surface");
    }
}

static int type_rank(VkPhysicalDeviceType t)
{
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
    }
}

static bool contains_nocase(const char *hay, const char *needle)
{
    size_t n = strlen(needle);
    for (const char *h = hay; *h; h++) {
        size_t i = 0;
        while (i < n && h[i] && tolower((unsigned char)h[i]) == tolower((unsigned char)needle[i])) i++;
        if (i == n) return true;
    }
    return n == 0;
}

/* Pick a device: the selector (index or name substring) or the best-ranked usable device. */
static int choose(const fv_vk_device_info *d, uint32_t n, const char *selector, char *why, size_t why_size)
{
    const char *env = getenv("FOVEA_DEVICE");
    const char *src = selector ? "device selector" : "FOVEA_DEVICE";
    if (!selector && env && *env) selector = env;
    if (selector && *selector) {
        char *end = NULL;
        long idx = strtol(selector, &end, 10);
        bool numeric = end && *end == '\0';
        for (uint32_t i = 0; i < n; i++) {
            bool match = numeric ? (long)d[i].index == idx : contains_nocase(d[i].name, selector);
            if (!match) continue;
            if (!d[i].usable) {
                snprintf(why, why_size, "%s='%s' selects device %u (%s), which is unusable: %s", src, selector, i,
                         d[i].name, d[i].why_not);
                return -1;
            }
            snprintf(why, why_size, "selected by %s='%s'", src, selector);
            return (int)i;
        }
        snprintf(why, why_size, "%s='%s' matches no device (%u listed)", src, selector, n);
        return -1;
    }
    int best = -1;
    for (uint32_t i = 0; i < n; i++)
        if (d[i].usable && (best < 0 || type_rank(d[i].type) > type_rank(d[best].type))) best = (int)i;
    if (best < 0) snprintf(why, why_size, "no device meets the requirements (Vulkan 1.2, multiview, graphics+compute)");
    else if (d[best].type == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU) snprintf(why, why_size, "preferred: discrete GPU");
    else snprintf(why, why_size, "no discrete GPU; best available is a %s", fv_vk_device_type_str(d[best].type));
    return best;
}

static fv_result enumerate(VkInstance inst, VkPhysicalDevice *pds, fv_vk_device_info *infos, uint32_t *out_n)
{
    uint32_t n = MAX_DEVICES;
    VkResult r = vkEnumeratePhysicalDevices(inst, &n, pds);
    if (r < 0) return fv_vk_fail(r, "vkEnumeratePhysicalDevices", __FILE__, __LINE__);
    for (uint32_t i = 0; i < n; i++) describe(pds[i], i, &infos[i]);
    *out_n = n;
    return FV_OK;
}

fv_result fv_vk_list_devices(const char *selector, fv_vk_device_info *out, uint32_t cap, uint32_t *out_count,
                             int *out_chosen, char *why, size_t why_size)
{
    if (!out_count || !out_chosen || (!out && cap)) return FV_ERR_INVALID_ARG;
    char tmp_why[8];
    if (!why || !why_size) {
        why = tmp_why;
        why_size = sizeof tmp_why;
    }
    *out_count = 0;
    *out_chosen = -1;
    VkInstance inst = VK_NULL_HANDLE;
    bool du = false;
    FV_TRY(create_instance(NULL, false, "fovea-info", NULL, &inst, &du));
    VkPhysicalDevice pds[MAX_DEVICES];
    fv_vk_device_info infos[MAX_DEVICES];
    uint32_t n = 0;
    fv_result res = enumerate(inst, pds, infos, &n);
    if (res == FV_OK) {
        *out_chosen = choose(infos, n, selector, why, why_size);
        for (uint32_t i = 0; i < n && i < cap; i++) out[i] = infos[i];
        *out_count = n < cap ? n : cap;
        if (*out_chosen >= (int)cap) *out_chosen = -1;
    }
    vkDestroyInstance(inst, NULL);
    return res;
}

/* ---- create / destroy ----------------------------------------------------------------------------------------- */

static bool env_on(const char *name)
{
    const char *v = getenv(name);
    return v && *v && strcmp(v, "0") != 0 && strcmp(v, "false") != 0;
}

fv_result fv_vk_create(const fv_vk_desc *desc_in, fv_vk **out_vk)
{
    if (!out_vk) return FV_ERR_INVALID_ARG;
    *out_vk = NULL;
    fv_vk_desc desc = desc_in ? *desc_in : (fv_vk_desc){0};
    fv_result res = FV_OK;
    fv_vk *vk = calloc(1, sizeof *vk);
    if (!vk) return FV_ERR_NO_MEMORY;
    atomic_init(&vk->validation_messages, 0u);
    vk->validation = desc.validation > 0 || (desc.validation == 0 && env_on("FOVEA_VALIDATION"));

    if (desc.instance_extension_count > FV_VK_MAX_EXTENSIONS || desc.device_extension_count > FV_VK_MAX_EXTENSIONS ||
        desc.optional_device_extension_count > FV_VK_MAX_EXTENSIONS) {
        FV_ERROR(MOD, "more than %d instance or device extensions asked for", FV_VK_MAX_EXTENSIONS);
        res = FV_ERR_RANGE;
        goto fail;
    }
    res = create_instance(vk, vk->validation, desc.app_name, &desc, &vk->instance, &vk->debug_utils);
    if (res != FV_OK) goto fail;
    if (vk->debug_utils) {
        vk->set_object_name =
            (PFN_vkSetDebugUtilsObjectNameEXT)vkGetInstanceProcAddr(vk->instance, "vkSetDebugUtilsObjectNameEXT");
        vk->cmd_label_begin =
            (PFN_vkCmdBeginDebugUtilsLabelEXT)vkGetInstanceProcAddr(vk->instance, "vkCmdBeginDebugUtilsLabelEXT");
        vk->cmd_label_end =
            (PFN_vkCmdEndDebugUtilsLabelEXT)vkGetInstanceProcAddr(vk->instance, "vkCmdEndDebugUtilsLabelEXT");
    }
    if (vk->validation) {
        PFN_vkCreateDebugUtilsMessengerEXT create_messenger =
            (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(vk->instance, "vkCreateDebugUtilsMessengerEXT");
        VkDebugUtilsMessengerCreateInfoEXT mi = messenger_info(vk);
        if (!create_messenger) {
            FV_ERROR(MOD, "vkCreateDebugUtilsMessengerEXT not found");
            res = FV_ERR_UNSUPPORTED;
            goto fail;
        }
        FV_VK_CHECK_GOTO(create_messenger(vk->instance, &mi, NULL, &vk->messenger), res, fail);
    }

    VkPhysicalDevice pds[MAX_DEVICES];
    fv_vk_device_info infos[MAX_DEVICES];
    uint32_t n = 0;
    res = enumerate(vk->instance, pds, infos, &n);
    if (res != FV_OK) goto fail;
    if (desc.create_surface) {
        res = desc.create_surface(vk->instance, desc.surface_user, &vk->surface);
        if (res != FV_OK || !vk->surface) {
            FV_ERROR(MOD, "the presentation surface could not be created: %s", fv_result_str(res ? res : FV_ERR_VULKAN));
            res = res ? res : FV_ERR_VULKAN;
            goto fail;
        }
    }
    for (uint32_t i = 0; i < n; i++) require_presentation(pds[i], &infos[i], &desc, vk->surface);
    int chosen = choose(infos, n, desc.device, vk->choice_reason, sizeof vk->choice_reason);
    if (chosen < 0) {
        FV_ERROR(MOD, "no Vulkan device: %s", vk->choice_reason);
        for (uint32_t i = 0; i < n; i++)
            FV_ERROR(MOD, "  device %u: %s (%s)%s%s", i, infos[i].name, fv_vk_device_type_str(infos[i].type),
                     infos[i].usable ? "" : " unusable: ", infos[i].why_not);
        res = n == 0 ? FV_ERR_NOT_FOUND : (desc.device || getenv("FOVEA_DEVICE") ? FV_ERR_NOT_FOUND : FV_ERR_UNSUPPORTED);
        goto fail;
    }
    vk->phys = pds[chosen];
    vk->info = infos[chosen];
    vkGetPhysicalDeviceProperties(vk->phys, &vk->props);
    vkGetPhysicalDeviceMemoryProperties(vk->phys, &vk->mem_props);
    bool ts = false;
    vk->queue_family = (uint32_t)find_queue_family(vk->phys, &ts);

    uint32_t ne = 0;
    FV_VK_CHECK_GOTO(vkEnumerateDeviceExtensionProperties(vk->phys, NULL, &ne, NULL), res, fail);
    VkExtensionProperties *exts = calloc(ne ? ne : 1, sizeof *exts);
    if (!exts) {
        res = FV_ERR_NO_MEMORY;
        goto fail;
    }
    VkResult er = vkEnumerateDeviceExtensionProperties(vk->phys, NULL, &ne, exts);
    bool portability_subset = er >= 0 && has_extension(exts, ne, "VK_KHR_portability_subset");
    const char *dev_exts[2 * FV_VK_MAX_EXTENSIONS + 2];
    uint32_t dev_ext_count = 0;
    if (portability_subset) dev_exts[dev_ext_count++] = "VK_KHR_portability_subset";
    if (vk->surface) dev_exts[dev_ext_count++] = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
    for (uint32_t i = 0; i < desc.device_extension_count; i++) {
        bool dup = false;
        for (uint32_t k = 0; k < dev_ext_count; k++) dup = dup || strcmp(dev_exts[k], desc.device_extensions[i]) == 0;
        if (!dup) dev_exts[dev_ext_count++] = desc.device_extensions[i];
    }
    /* Optional extensions: enabled when this device has them (e.g. a presenter's display timing). */
    for (uint32_t i = 0; i < desc.optional_device_extension_count && er >= 0; i++) {
        const char *x = desc.optional_device_extensions[i];
        bool dup = false;
        for (uint32_t k = 0; k < dev_ext_count; k++) dup = dup || strcmp(dev_exts[k], x) == 0;
        if (dup || !has_extension(exts, ne, x)) continue;
        dev_exts[dev_ext_count++] = x;
        vk->optional_enabled[vk->optional_enabled_count++] = x;
    }
    free(exts);

    /* Presenting: prefer the rendering family itself; else the first family that can present (then the window's
     * swapchain images are shared concurrently by the two families, so no ownership transfer is needed). */
    vk->present_family = vk->queue_family;
    if (vk->surface) {
        int pf = present_family(vk->phys, vk->surface, vk->queue_family);
        vk->present_family = pf >= 0 ? (uint32_t)pf : vk->queue_family;
    }
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qcis[2] = {{
        .sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
        .queueFamilyIndex = vk->queue_family,
        .queueCount = 1,
        .pQueuePriorities = &prio,
    }};
    qcis[1] = qcis[0];
    qcis[1].queueFamilyIndex = vk->present_family;
    uint32_t queue_infos = vk->present_family == vk->queue_family ? 1u : 2u;
    VkPhysicalDeviceVulkan11Features f11 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES,
                                            .multiview = VK_TRUE};
    VkPhysicalDeviceFeatures2 f2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &f11};
    VkDeviceCreateInfo dci = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
        .pNext = &f2,
        .queueCreateInfoCount = queue_infos,
        .pQueueCreateInfos = qcis,
        .enabledExtensionCount = dev_ext_count,
        .ppEnabledExtensionNames = dev_exts,
    };
    FV_VK_CHECK_GOTO(vkCreateDevice(vk->phys, &dci, NULL, &vk->device), res, fail);
    vkGetDeviceQueue(vk->device, vk->queue_family, 0, &vk->queue);
    vkGetDeviceQueue(vk->device, vk->present_family, 0, &vk->present_queue);
    FV_VK_NAME(vk, VK_OBJECT_TYPE_DEVICE, vk->device, "fovea device (%s)", vk->info.name);
    FV_VK_NAME(vk, VK_OBJECT_TYPE_QUEUE, vk->queue, "fovea queue (family %u)", vk->queue_family);

    VkCommandPoolCreateInfo pci = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
        .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT | VK_COMMAND_POOL_CREATE_TRANSIENT_BIT,
        .queueFamilyIndex = vk->queue_family,
    };
    FV_VK_CHECK_GOTO(vkCreateCommandPool(vk->device, &pci, NULL, &vk->pool), res, fail);
    FV_VK_NAME(vk, VK_OBJECT_TYPE_COMMAND_POOL, vk->pool, "vk one-shot pool");
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    FV_VK_CHECK_GOTO(vkCreateFence(vk->device, &fci, NULL, &vk->oneshot_fence), res, fail);
    FV_VK_NAME(vk, VK_OBJECT_TYPE_FENCE, vk->oneshot_fence, "vk one-shot fence");

    fv_vk_pipeline_cache_open(vk);
    vk->memory_budget_bytes = desc.memory_budget_bytes;
    if (!vk->memory_budget_bytes) {
        uint64_t heap = vk->info.device_local_bytes ? vk->info.device_local_bytes : (uint64_t)1 << 30;
        vk->memory_budget_bytes = heap / 10 * 8;
    }
    FV_INFO(MOD, "device %s (%s, Vulkan %u.%u): %s; validation %s", vk->info.name,
            fv_vk_device_type_str(vk->info.type), VK_API_VERSION_MAJOR(vk->info.api_version),
            VK_API_VERSION_MINOR(vk->info.api_version), vk->choice_reason, vk->validation ? "on" : "off");
    *out_vk = vk;
    return FV_OK;

fail:
    fv_vk_destroy(&vk);
    return res;
}

void fv_vk_destroy(fv_vk **pvk)
{
    if (!pvk || !*pvk) return;
    fv_vk *vk = *pvk;
    if (vk->device) {
        vkDeviceWaitIdle(vk->device);
        if (vk->allocation_count)
            FV_WARN(MOD, "%u device allocations (%llu bytes) still live at device destruction", vk->allocation_count,
                    (unsigned long long)vk->memory_bytes);
        fv_vk_pipeline_cache_save(vk);
        if (vk->oneshot_fence) vkDestroyFence(vk->device, vk->oneshot_fence, NULL);
        if (vk->pool) vkDestroyCommandPool(vk->device, vk->pool, NULL);
        vkDestroyDevice(vk->device, NULL);
    }
    if (vk->surface) vkDestroySurfaceKHR(vk->instance, vk->surface, NULL);
    if (vk->messenger) {
        PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger =
            (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(vk->instance, "vkDestroyDebugUtilsMessengerEXT");
        if (destroy_messenger) destroy_messenger(vk->instance, vk->messenger, NULL);
    }
    if (vk->instance) vkDestroyInstance(vk->instance, NULL);
    free(vk);
    *pvk = NULL;
}

bool fv_vk_optional_enabled(const fv_vk *vk, const char *extension)
{
    for (uint32_t i = 0; vk && extension && i < vk->optional_enabled_count; i++)
        if (strcmp(vk->optional_enabled[i], extension) == 0) return true;
    return false;
}

uint32_t fv_vk_validation_messages(const fv_vk *vk)
{
    return vk ? atomic_load(&((fv_vk *)vk)->validation_messages) : 0;
}

void fv_vk_name(fv_vk *vk, VkObjectType type, uint64_t handle, const char *fmt, ...)
{
    if (!vk || !vk->set_object_name || !handle) return;
    char name[128];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(name, sizeof name, fmt, ap);
    va_end(ap);
    VkDebugUtilsObjectNameInfoEXT ni = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT,
        .objectType = type,
        .objectHandle = handle,
        .pObjectName = name,
    };
    (void)vk->set_object_name(vk->device, &ni);
}

void fv_vk_label_begin(fv_vk *vk, VkCommandBuffer cmd, const char *name)
{
    if (!vk || !vk->cmd_label_begin) return;
    VkDebugUtilsLabelEXT label = {.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT, .pLabelName = name,
                                  .color = {0.3f, 0.6f, 0.9f, 1.0f}};
    vk->cmd_label_begin(cmd, &label);
}

void fv_vk_label_end(fv_vk *vk, VkCommandBuffer cmd)
{
    if (!vk || !vk->cmd_label_end) return;
    vk->cmd_label_end(cmd);
}

bool fv_vk_is_llvmpipe(const fv_vk_device_info *d)
{
    return d && (strstr(d->driver_name, "llvmpipe") || strstr(d->name, "llvmpipe"));
}

bool fv_vk_multiview_trusted(const fv_vk_device_info *d, char *why, size_t why_size)
{
    char tmp[8];
    if (!why || !why_size) {
        why = tmp;
        why_size = sizeof tmp;
    }
    const char *v = getenv("FOVEA_MULTIVIEW");
    if (v && *v) {
        bool on = strcmp(v, "0") != 0 && strcmp(v, "false") != 0 && strcmp(v, "off") != 0;
        snprintf(why, why_size, "%s (FOVEA_MULTIVIEW=%s)", on ? "both eyes in one multiview pass" : "one pass per eye",
                 v);
        return on && d && d->multiview;
    }
    if (fv_vk_is_llvmpipe(d)) {
        snprintf(why, why_size, "one pass per eye: llvmpipe multiview mis-clips view 1");
        return false;
    }
    snprintf(why, why_size, "both eyes in one multiview pass");
    return d && d->multiview;
}
