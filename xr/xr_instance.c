/* @brief Instance and system: extensions, API version checks, the HMD system (stereo; properties from fovea's HMD
 * profile, FOVEA_XR_HMD), view configurations, blend modes, result and structure names, time conversion. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <openxr/openxr_reflection.h>

#include "xr_internal.h"

/* Every instance extension fovea implements. */
static const XrExtensionProperties g_extensions[] = {
    {XR_TYPE_EXTENSION_PROPERTIES, NULL, XR_KHR_VULKAN_ENABLE_EXTENSION_NAME, XR_KHR_vulkan_enable_SPEC_VERSION},
    {XR_TYPE_EXTENSION_PROPERTIES, NULL, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME, XR_KHR_vulkan_enable2_SPEC_VERSION},
    {XR_TYPE_EXTENSION_PROPERTIES, NULL, XR_MND_HEADLESS_EXTENSION_NAME, XR_MND_headless_SPEC_VERSION},
    {XR_TYPE_EXTENSION_PROPERTIES, NULL, XR_KHR_OPENGL_ENABLE_EXTENSION_NAME, XR_KHR_opengl_enable_SPEC_VERSION},
    {XR_TYPE_EXTENSION_PROPERTIES, NULL, XR_KHR_OPENGL_ES_ENABLE_EXTENSION_NAME, XR_KHR_opengl_es_enable_SPEC_VERSION},
    {XR_TYPE_EXTENSION_PROPERTIES, NULL, XR_MNDX_EGL_ENABLE_EXTENSION_NAME, XR_MNDX_egl_enable_SPEC_VERSION},
    {XR_TYPE_EXTENSION_PROPERTIES, NULL, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME,
     XR_EXT_eye_gaze_interaction_SPEC_VERSION},
    {XR_TYPE_EXTENSION_PROPERTIES, NULL, XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME,
     XR_KHR_convert_timespec_time_SPEC_VERSION},
    {XR_TYPE_EXTENSION_PROPERTIES, NULL, XR_EXT_LOCAL_FLOOR_EXTENSION_NAME, XR_EXT_local_floor_SPEC_VERSION},
    {XR_TYPE_EXTENSION_PROPERTIES, NULL, XR_VARJO_QUAD_VIEWS_EXTENSION_NAME, XR_VARJO_quad_views_SPEC_VERSION},
    {XR_TYPE_EXTENSION_PROPERTIES, NULL, XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME,
     XR_VARJO_foveated_rendering_SPEC_VERSION},
};
#define EXTENSION_COUNT (uint32_t)(sizeof g_extensions / sizeof g_extensions[0])

FV_XR_DECL(xrEnumerateInstanceExtensionProperties)(const char *layer, uint32_t cap, uint32_t *count,
                                                   XrExtensionProperties *props)
{
    if (layer && layer[0]) return XR_ERROR_API_LAYER_NOT_PRESENT; /* the runtime has no layers of its own */
    if (!count || (cap && !props)) return XR_ERROR_VALIDATION_FAILURE;
    *count = EXTENSION_COUNT;
    if (cap == 0) return XR_SUCCESS;
    if (cap < EXTENSION_COUNT) return XR_ERROR_SIZE_INSUFFICIENT;
    for (uint32_t i = 0; i < EXTENSION_COUNT; i++) {
        if (props[i].type != XR_TYPE_EXTENSION_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
        void *next = props[i].next;
        props[i] = g_extensions[i];
        props[i].next = next;
    }
    return XR_SUCCESS;
}

FV_XR_DECL(xrEnumerateApiLayerProperties)(uint32_t cap, uint32_t *count, XrApiLayerProperties *props)
{
    if (!count) return XR_ERROR_VALIDATION_FAILURE;
    *count = 0; /* the loader lists layers; the runtime has none */
    return XR_SUCCESS;
}

/* A positive float from the environment, or def; a bad value is reported and ignored. */
static float env_float(const char *name, float def, float lo, float hi)
{
    const char *s = getenv(name);
    if (!s || !*s) return def;
    char *end = NULL;
    double v = strtod(s, &end);
    if (!end || *end || !isfinite(v) || v < lo || v > hi) {
        FV_ERROR(FV_XR_LOG, "%s='%s': expected a number in [%g, %g]; using %g", name, s, (double)lo, (double)hi,
                 (double)def);
        return def;
    }
    return (float)v;
}

FV_XR_DECL(xrCreateInstance)(const XrInstanceCreateInfo *info, XrInstance *out)
{
    if (!info || !out || info->type != XR_TYPE_INSTANCE_CREATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    if (info->createFlags != 0) return XR_ERROR_VALIDATION_FAILURE;
    const XrApplicationInfo *app = &info->applicationInfo;
    if (!memchr(app->applicationName, 0, sizeof app->applicationName) || app->applicationName[0] == 0)
        return XR_ERROR_NAME_INVALID;
    if (!memchr(app->engineName, 0, sizeof app->engineName)) return XR_ERROR_NAME_INVALID;
    /* OpenXR 1.0 (any patch): a 1.x with x > 0 or another major is a version this runtime does not implement. */
    if (XR_VERSION_MAJOR(app->apiVersion) != 1 || XR_VERSION_MINOR(app->apiVersion) != 0) {
        FV_ERROR(FV_XR_LOG, "application asks for OpenXR %u.%u.%u; fovea implements 1.0",
                 (unsigned)XR_VERSION_MAJOR(app->apiVersion), (unsigned)XR_VERSION_MINOR(app->apiVersion),
                 (unsigned)XR_VERSION_PATCH(app->apiVersion));
        return XR_ERROR_API_VERSION_UNSUPPORTED;
    }
    if (fv_xr_chain_check(info->next, "xrCreateInstance") != XR_SUCCESS) return XR_ERROR_VALIDATION_FAILURE;
    /* enabledApiLayerNames: the loader has loaded the layers named there and passes the list on unchanged; they are
     * not the runtime's business (a runtime has no layers of its own), so the names are ignored */
    if (info->enabledExtensionCount && !info->enabledExtensionNames) return XR_ERROR_VALIDATION_FAILURE;
    fv_xr_exts ext = {0};
    for (uint32_t i = 0; i < info->enabledExtensionCount; i++) {
        const char *n = info->enabledExtensionNames[i];
        if (!n) return XR_ERROR_VALIDATION_FAILURE;
        if (!strcmp(n, XR_KHR_VULKAN_ENABLE_EXTENSION_NAME)) ext.vulkan = true;
        else if (!strcmp(n, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME)) ext.vulkan2 = true;
        else if (!strcmp(n, XR_MND_HEADLESS_EXTENSION_NAME)) ext.headless = true;
        else if (!strcmp(n, XR_KHR_OPENGL_ENABLE_EXTENSION_NAME)) ext.opengl = true;
        else if (!strcmp(n, XR_KHR_OPENGL_ES_ENABLE_EXTENSION_NAME)) ext.opengl_es = true;
        else if (!strcmp(n, XR_MNDX_EGL_ENABLE_EXTENSION_NAME)) ext.egl = true;
        else if (!strcmp(n, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME)) ext.eye_gaze = true;
        else if (!strcmp(n, XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME)) ext.convert_timespec = true;
        else if (!strcmp(n, XR_EXT_LOCAL_FLOOR_EXTENSION_NAME)) ext.local_floor = true;
        else if (!strcmp(n, XR_VARJO_QUAD_VIEWS_EXTENSION_NAME)) ext.quad_views = true;
        else if (!strcmp(n, XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME)) ext.foveated = true;
        else {
            FV_ERROR(FV_XR_LOG, "extension %s is not supported by fovea", n);
            return XR_ERROR_EXTENSION_NOT_PRESENT;
        }
    }
    if (ext.foveated && !ext.quad_views) { /* XR_VARJO_foveated_rendering requires XR_VARJO_quad_views */
        FV_ERROR(FV_XR_LOG, "%s requires %s to be enabled", XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME,
                 XR_VARJO_QUAD_VIEWS_EXTENSION_NAME);
        return XR_ERROR_VALIDATION_FAILURE;
    }
    struct XrInstance_T *inst = calloc(1, sizeof *inst);
    if (!inst) return XR_ERROR_OUT_OF_MEMORY;
    inst->magic = FV_XR_MAGIC_INSTANCE;
    pthread_mutex_init(&inst->lock, NULL);
    snprintf(inst->app_name, sizeof inst->app_name, "%s", app->applicationName);
    inst->api_version = app->apiVersion;
    inst->ext = ext;
    /* The description of the session's runs (runtime/app's, as `fovea run` fills it from its options): the HMD
     * (FOVEA_XR_HMD: a built-in name or a JSON file; default generic), the per-eye size from it, the gaze source. */
    fv_app_run_defaults(&inst->run);
    const char *hmd = getenv("FOVEA_XR_HMD");
    inst->run.hmd = hmd && *hmd ? hmd : "generic";
    char err[256];
    if (fv_hmd_profile_load(inst->run.hmd, &inst->hmd, err, sizeof err) != FV_OK) {
        FV_ERROR(FV_XR_LOG, "FOVEA_XR_HMD: %s", err);
        pthread_mutex_destroy(&inst->lock);
        free(inst);
        return XR_ERROR_RUNTIME_FAILURE;
    }
    inst->render_scale = env_float("FOVEA_XR_SCALE", 1.0f, 0.02f, 2.0f);
    double w = (double)inst->hmd.panel_width_px * 0.5 * inst->render_scale;
    double h = (double)inst->hmd.panel_height_px * inst->render_scale;
    if (w > FV_XR_MAX_IMAGE_SIZE || h > FV_XR_MAX_IMAGE_SIZE) {
        /* no app could make a swapchain of that size: the largest it can, the aspect ratio kept */
        double k = FV_XR_MAX_IMAGE_SIZE / fmax(w, h);
        FV_WARN(FV_XR_LOG, "HMD %s: %.0fx%.0f per eye (panel %ux%u, FOVEA_XR_SCALE %g) exceeds the largest swapchain "
                "image (%u); recommending %.0fx%.0f", inst->hmd.name, w, h, inst->hmd.panel_width_px,
                inst->hmd.panel_height_px, (double)inst->render_scale, FV_XR_MAX_IMAGE_SIZE, fmin(round(w * k),
                FV_XR_MAX_IMAGE_SIZE), fmin(round(h * k), FV_XR_MAX_IMAGE_SIZE));
        w *= k;
        h *= k;
    }
    inst->run.eye_w = w < 16.0 ? 16u : (uint32_t)fmin(round(w), FV_XR_MAX_IMAGE_SIZE);
    inst->run.eye_h = h < 16.0 ? 16u : (uint32_t)fmin(round(h), FV_XR_MAX_IMAGE_SIZE);
    XrResult r = fv_xr_input_instance_init(inst);
    if (r != XR_SUCCESS) {
        pthread_mutex_destroy(&inst->lock);
        free(inst);
        return r;
    }
    /* Eye gaze: fovea's gaze pipeline on the source named by FOVEA_XR_GAZE (any --gaze URI). A source that fails to
     * open is reported; the system then says it has no eye-gaze interaction. */
    const char *gaze = getenv("FOVEA_XR_GAZE");
    inst->run.gaze_uri = gaze && *gaze ? gaze : NULL;
    if (inst->run.gaze_uri && fv_xr_gaze_create(inst->run.gaze_uri, &inst->gaze) != FV_OK)
        FV_ERROR(FV_XR_LOG, "FOVEA_XR_GAZE='%s' could not be opened: no eye gaze", inst->run.gaze_uri);
    fv_xr_handle_add(inst);
    if (!fv_xr_handle_live(inst, FV_XR_MAGIC_INSTANCE)) {
        fv_xr_gaze_destroy(&inst->gaze);
        fv_xr_input_instance_fini(inst);
        free(inst);
        return XR_ERROR_OUT_OF_MEMORY;
    }
    FV_INFO(FV_XR_LOG, "instance for '%s': HMD %s, %ux%u per eye, gaze %s", inst->app_name, inst->hmd.name,
            inst->run.eye_w, inst->run.eye_h, inst->gaze ? inst->run.gaze_uri : "none");
    *out = inst;
    return XR_SUCCESS;
}

FV_XR_DECL(xrDestroyInstance)(XrInstance instance)
{
    struct XrInstance_T *inst = fv_xr_instance_check(instance);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (inst->session) fv_xrDestroySession(inst->session); /* child handles go with their parent */
    fv_xr_handle_remove(inst);
    fv_xr_compositor_destroy(&inst->comp);
    fv_xr_gaze_destroy(&inst->gaze);
    fv_xr_input_instance_fini(inst);
    inst->magic = 0;
    pthread_mutex_destroy(&inst->lock);
    free(inst);
    return XR_SUCCESS;
}

FV_XR_DECL(xrGetInstanceProperties)(XrInstance instance, XrInstanceProperties *props)
{
    if (!fv_xr_instance_check(instance)) return XR_ERROR_HANDLE_INVALID;
    if (!props || props->type != XR_TYPE_INSTANCE_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
    props->runtimeVersion = XR_MAKE_VERSION(0, 1, 0);
    snprintf(props->runtimeName, sizeof props->runtimeName, "fovea");
    return XR_SUCCESS;
}

FV_XR_DECL(xrResultToString)(XrInstance instance, XrResult value, char buffer[XR_MAX_RESULT_STRING_SIZE])
{
    if (!fv_xr_instance_check(instance)) return XR_ERROR_HANDLE_INVALID;
    if (!buffer) return XR_ERROR_VALIDATION_FAILURE;
#define CASE(name, val)                                                                                                \
    case name: snprintf(buffer, XR_MAX_RESULT_STRING_SIZE, "%s", #name); return XR_SUCCESS;
    switch (value) {
        XR_LIST_ENUM_XrResult(CASE) default : break;
    }
#undef CASE
    snprintf(buffer, XR_MAX_RESULT_STRING_SIZE, "XR_UNKNOWN_%s_%d", value >= 0 ? "SUCCESS" : "FAILURE", (int)value);
    return XR_SUCCESS;
}

FV_XR_DECL(xrStructureTypeToString)(XrInstance instance, XrStructureType value,
                                    char buffer[XR_MAX_STRUCTURE_NAME_SIZE])
{
    if (!fv_xr_instance_check(instance)) return XR_ERROR_HANDLE_INVALID;
    if (!buffer) return XR_ERROR_VALIDATION_FAILURE;
#define CASE(name, val)                                                                                                \
    case name: snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "%s", #name); return XR_SUCCESS;
    switch (value) {
        XR_LIST_ENUM_XrStructureType(CASE) default : break;
    }
#undef CASE
    snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "XR_UNKNOWN_STRUCTURE_TYPE_%d", (int)value);
    return XR_SUCCESS;
}

FV_XR_DECL(xrGetSystem)(XrInstance instance, const XrSystemGetInfo *info, XrSystemId *out)
{
    if (!fv_xr_instance_check(instance)) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_SYSTEM_GET_INFO ||
        fv_xr_chain_check(info->next, "xrGetSystem") != XR_SUCCESS)
        return XR_ERROR_VALIDATION_FAILURE;
    /* a head-mounted display only: any other form factor, known or not (the conformance suite asks it) */
    if (info->formFactor != XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY) return XR_ERROR_FORM_FACTOR_UNSUPPORTED;
    *out = FV_XR_SYSTEM_ID;
    return XR_SUCCESS;
}

FV_XR_DECL(xrGetSystemProperties)(XrInstance instance, XrSystemId system, XrSystemProperties *props)
{
    struct XrInstance_T *inst = fv_xr_instance_check(instance);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (system != FV_XR_SYSTEM_ID) return XR_ERROR_SYSTEM_INVALID;
    if (!props || props->type != XR_TYPE_SYSTEM_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
    /* the extensions' structures, each filled only when its extension is enabled (else ignored, like any structure
     * the runtime does not recognise) */
    XrSystemEyeGazeInteractionPropertiesEXT *gaze = NULL;
    XrSystemFoveatedRenderingPropertiesVARJO *fov = NULL;
    if (fv_xr_chain_find(props->next, inst->ext.eye_gaze ? XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT
                                                         : XR_TYPE_UNKNOWN,
                         "xrGetSystemProperties", (const void **)&gaze) != XR_SUCCESS ||
        fv_xr_chain_find(props->next, inst->ext.foveated ? XR_TYPE_SYSTEM_FOVEATED_RENDERING_PROPERTIES_VARJO
                                                         : XR_TYPE_UNKNOWN,
                         "xrGetSystemProperties", (const void **)&fov) != XR_SUCCESS)
        return XR_ERROR_VALIDATION_FAILURE;
    props->systemId = system;
    props->vendorId = FV_XR_VENDOR_ID;
    snprintf(props->systemName, sizeof props->systemName, "fovea (%s)", inst->hmd.name);
    props->graphicsProperties.maxSwapchainImageWidth = FV_XR_MAX_IMAGE_SIZE;
    props->graphicsProperties.maxSwapchainImageHeight = FV_XR_MAX_IMAGE_SIZE;
    props->graphicsProperties.maxLayerCount = FV_XR_MAX_LAYERS;
    /* No head tracker in fovea today: the head pose is given (static), not tracked. */
    props->trackingProperties.orientationTracking = XR_FALSE;
    props->trackingProperties.positionTracking = XR_FALSE;
    bool gaze_present = inst->gaze && fv_xr_gaze_present(inst->gaze);
    if (gaze) gaze->supportsEyeGazeInteraction = gaze_present ? XR_TRUE : XR_FALSE;
    /* rendering gaze: fovea's gaze pipeline on an open source */
    if (fov) fov->supportsFoveatedRendering = gaze_present ? XR_TRUE : XR_FALSE;
    return XR_SUCCESS;
}

XrResult fv_xr_check_view_config(struct XrInstance_T *inst, XrViewConfigurationType type, uint32_t *out_views)
{
    if (type == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) {
        if (out_views) *out_views = 2;
        return XR_SUCCESS;
    }
    if (type == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO && inst->ext.quad_views) {
        if (out_views) *out_views = 4; /* wide left, wide right, inset left, inset right (xr_quad.c) */
        return XR_SUCCESS;
    }
    return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED; /* any other, known or not (as the conformance suite asks) */
}

FV_XR_DECL(xrEnumerateViewConfigurations)(XrInstance instance, XrSystemId system, uint32_t cap, uint32_t *count,
                                          XrViewConfigurationType *types)
{
    struct XrInstance_T *inst = fv_xr_instance_check(instance);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (system != FV_XR_SYSTEM_ID) return XR_ERROR_SYSTEM_INVALID;
    if (!count || (cap && !types)) return XR_ERROR_VALIDATION_FAILURE;
    /* quad views only for an app that enabled XR_VARJO_quad_views; preferred then (the insets at the display's
     * density, the rest at less) */
    uint32_t n = inst->ext.quad_views ? 2 : 1;
    *count = n;
    if (cap == 0) return XR_SUCCESS;
    if (cap < n) return XR_ERROR_SIZE_INSUFFICIENT;
    if (n == 2) types[0] = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO;
    types[n - 1] = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    return XR_SUCCESS;
}

FV_XR_DECL(xrGetViewConfigurationProperties)(XrInstance instance, XrSystemId system, XrViewConfigurationType type,
                                             XrViewConfigurationProperties *props)
{
    struct XrInstance_T *inst = fv_xr_instance_check(instance);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (system != FV_XR_SYSTEM_ID) return XR_ERROR_SYSTEM_INVALID;
    if (!props || props->type != XR_TYPE_VIEW_CONFIGURATION_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
    XrResult r = fv_xr_check_view_config(inst, type, NULL);
    if (r != XR_SUCCESS) return r;
    props->viewConfigurationType = type;
    props->fovMutable = XR_TRUE; /* the compositor maps each layer's own fov onto the display's */
    return XR_SUCCESS;
}

FV_XR_DECL(xrEnumerateViewConfigurationViews)(XrInstance instance, XrSystemId system, XrViewConfigurationType type,
                                              uint32_t cap, uint32_t *count, XrViewConfigurationView *views)
{
    struct XrInstance_T *inst = fv_xr_instance_check(instance);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (system != FV_XR_SYSTEM_ID) return XR_ERROR_SYSTEM_INVALID;
    if (!count || (cap && !views)) return XR_ERROR_VALIDATION_FAILURE;
    uint32_t n = 0;
    XrResult r = fv_xr_check_view_config(inst, type, &n);
    if (r != XR_SUCCESS) return r;
    *count = n;
    if (cap == 0) return XR_SUCCESS;
    if (cap < n) return XR_ERROR_SIZE_INSUFFICIENT;
    for (uint32_t i = 0; i < n; i++) {
        const XrFoveatedViewConfigurationViewVARJO *fv = NULL; /* ignored unless XR_VARJO_foveated_rendering */
        if (views[i].type != XR_TYPE_VIEW_CONFIGURATION_VIEW ||
            fv_xr_chain_find(views[i].next, inst->ext.foveated ? XR_TYPE_FOVEATED_VIEW_CONFIGURATION_VIEW_VARJO
                                                                : XR_TYPE_UNKNOWN,
                             "xrEnumerateViewConfigurationViews", (const void **)&fv) != XR_SUCCESS)
            return XR_ERROR_VALIDATION_FAILURE;
        views[i].recommendedImageRectWidth = inst->run.eye_w;
        views[i].recommendedImageRectHeight = inst->run.eye_h;
        if (n == 4) {
            fv_xr_quad_view_size(inst, i, fv && fv->foveatedRenderingActive, &views[i].recommendedImageRectWidth,
                                 &views[i].recommendedImageRectHeight);
        }
        views[i].maxImageRectWidth = FV_XR_MAX_IMAGE_SIZE;
        views[i].maxImageRectHeight = FV_XR_MAX_IMAGE_SIZE;
        views[i].recommendedSwapchainSampleCount = 1;
        views[i].maxSwapchainSampleCount = FV_XR_MAX_SAMPLES;
    }
    return XR_SUCCESS;
}

FV_XR_DECL(xrEnumerateEnvironmentBlendModes)(XrInstance instance, XrSystemId system, XrViewConfigurationType type,
                                             uint32_t cap, uint32_t *count, XrEnvironmentBlendMode *modes)
{
    struct XrInstance_T *inst = fv_xr_instance_check(instance);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (system != FV_XR_SYSTEM_ID) return XR_ERROR_SYSTEM_INVALID;
    if (!count || (cap && !modes)) return XR_ERROR_VALIDATION_FAILURE;
    XrResult r = fv_xr_check_view_config(inst, type, NULL);
    if (r != XR_SUCCESS) return r;
    *count = 1;
    if (cap == 0) return XR_SUCCESS;
    modes[0] = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    return XR_SUCCESS;
}

FV_XR_DECL(xrConvertTimespecTimeToTimeKHR)(XrInstance instance, const struct timespec *ts, XrTime *out)
{
    if (!fv_xr_instance_check(instance)) return XR_ERROR_HANDLE_INVALID;
    if (!ts || !out) return XR_ERROR_VALIDATION_FAILURE;
    if (ts->tv_sec < 0 || ts->tv_nsec < 0 || ts->tv_nsec >= 1000000000 || ts->tv_sec > INT64_MAX / 1000000000 - 1)
        return XR_ERROR_TIME_INVALID;
    *out = (XrTime)ts->tv_sec * 1000000000 + ts->tv_nsec; /* XrTime is CLOCK_MONOTONIC in ns */
    return XR_SUCCESS;
}

FV_XR_DECL(xrConvertTimeToTimespecTimeKHR)(XrInstance instance, XrTime t, struct timespec *out)
{
    if (!fv_xr_instance_check(instance)) return XR_ERROR_HANDLE_INVALID;
    if (!out) return XR_ERROR_VALIDATION_FAILURE;
    if (t <= 0) return XR_ERROR_TIME_INVALID;
    out->tv_sec = (time_t)(t / 1000000000);
    out->tv_nsec = (long)(t % 1000000000);
    return XR_SUCCESS;
}
