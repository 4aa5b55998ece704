/* @brief The loader's entry into fovea's OpenXR runtime: xrNegotiateLoaderRuntimeInterface (the one exported symbol),
 * xrGetInstanceProcAddr (core functions, and extension functions only when the extension is enabled), the table of
 * live handles, the event queue and small shared helpers. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "xr_internal.h"

#define FV_XR_EXPORT __attribute__((visibility("default")))

/* ---- live handles: a handle is valid while it is in this table (so a stale or foreign pointer is never read) ---- */
static pthread_mutex_t g_handles_lock = PTHREAD_MUTEX_INITIALIZER;
static void **g_handles;
static size_t g_handle_count, g_handle_cap;

void fv_xr_handle_add(void *h)
{
    pthread_mutex_lock(&g_handles_lock);
    if (g_handle_count == g_handle_cap) {
        size_t cap = g_handle_cap ? g_handle_cap * 2 : 64;
        void **n = realloc(g_handles, cap * sizeof *n);
        if (!n) {
            pthread_mutex_unlock(&g_handles_lock);
            return; /* the handle then reads invalid: callers check fv_xr_handle_live right after */
        }
        g_handles = n;
        g_handle_cap = cap;
    }
    g_handles[g_handle_count++] = h;
    pthread_mutex_unlock(&g_handles_lock);
}

void fv_xr_handle_remove(void *h)
{
    pthread_mutex_lock(&g_handles_lock);
    for (size_t i = 0; i < g_handle_count; i++)
        if (g_handles[i] == h) {
            g_handles[i] = g_handles[--g_handle_count];
            break;
        }
    if (g_handle_count == 0) {
        free(g_handles);
        g_handles = NULL;
        g_handle_cap = 0;
    }
    pthread_mutex_unlock(&g_handles_lock);
}

bool fv_xr_handle_live(const void *h, uint32_t magic)
{
    if (!h) return false;
    bool live = false;
    pthread_mutex_lock(&g_handles_lock);
    for (size_t i = 0; i < g_handle_count && !live; i++)
        if (g_handles[i] == h) live = *(const uint32_t *)h == magic;
    pthread_mutex_unlock(&g_handles_lock);
    return live;
}

XrInstance fv_xr_instance_check(XrInstance instance)
{
    return fv_xr_handle_live(instance, FV_XR_MAGIC_INSTANCE) ? instance : XR_NULL_HANDLE;
}

XrSession fv_xr_session_check(XrSession session)
{
    return fv_xr_handle_live(session, FV_XR_MAGIC_SESSION) ? session : XR_NULL_HANDLE;
}

int64_t fv_xr_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

XrResult fv_xr_chain_find(const void *next, XrStructureType type, const char *what, const void **out)
{
    const void *found = NULL;
    int links = 0;
    for (const XrBaseInStructure *b = next; b; b = b->next) {
        if (++links > FV_XR_MAX_CHAIN) {
            FV_ERROR(FV_XR_LOG, "%s: the next chain has more than %d structures (or loops)", what, FV_XR_MAX_CHAIN);
            if (out) *out = NULL;
            return XR_ERROR_VALIDATION_FAILURE;
        }
        if (!found && type != XR_TYPE_UNKNOWN && b->type == type) found = b;
    }
    if (out) *out = found;
    return XR_SUCCESS;
}

XrResult fv_xr_chain_check(const void *next, const char *what)
{
    return fv_xr_chain_find(next, XR_TYPE_UNKNOWN, what, NULL);
}

bool fv_xr_pose_valid(const XrPosef *p)
{
    const float v[7] = {p->orientation.x, p->orientation.y, p->orientation.z, p->orientation.w,
                        p->position.x,    p->position.y,    p->position.z};
    for (int i = 0; i < 7; i++)
        if (!isfinite(v[i])) return false;
    double n = (double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2] + (double)v[3] * v[3];
    return fabs(n - 1.0) <= 1e-2; /* the spec: unit length within a practical tolerance */
}

/* ---- events ---------------------------------------------------------------------------------------------------- */
void fv_xr_event_push(struct XrInstance_T *inst, const void *event, size_t size)
{
    if (size > sizeof(XrEventDataBuffer)) return;
    if (inst->event_count == FV_XR_EVENT_CAP) {
        /* full: drop the oldest and tell the app how many it lost (XrEventDataEventsLost is queued next) */
        inst->event_head = (inst->event_head + 1) % FV_XR_EVENT_CAP;
        inst->event_count--;
        inst->events_dropped++;
    }
    XrEventDataBuffer *slot = &inst->events[(inst->event_head + inst->event_count) % FV_XR_EVENT_CAP];
    memset(slot, 0, sizeof *slot);
    memcpy(slot, event, size);
    inst->event_count++;
}

FV_XR_DECL(xrPollEvent)(XrInstance instance, XrEventDataBuffer *event)
{
    struct XrInstance_T *inst = fv_xr_instance_check(instance);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!event || event->type != XR_TYPE_EVENT_DATA_BUFFER) return XR_ERROR_VALIDATION_FAILURE;
    pthread_mutex_lock(&inst->lock);
    XrResult r = XR_EVENT_UNAVAILABLE;
    if (inst->events_dropped) {
        XrEventDataEventsLost lost = {XR_TYPE_EVENT_DATA_EVENTS_LOST, NULL, (uint32_t)inst->events_dropped};
        memset(event, 0, sizeof *event);
        memcpy(event, &lost, sizeof lost);
        inst->events_dropped = 0;
        r = XR_SUCCESS;
    } else if (inst->event_count) {
        *event = inst->events[inst->event_head];
        inst->event_head = (inst->event_head + 1) % FV_XR_EVENT_CAP;
        inst->event_count--;
        r = XR_SUCCESS;
    }
    pthread_mutex_unlock(&inst->lock);
    return r;
}

void fv_xr_session_set_state(struct XrSession_T *s, XrSessionState state)
{
    if (s->state == state) return;
    s->state = state;
    XrEventDataSessionStateChanged ev = {XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED, NULL, s, state, fv_xr_now_ns()};
    fv_xr_event_push(s->inst, &ev, sizeof ev);
    FV_INFO(FV_XR_LOG, "session state %d", (int)state);
}

/* ---- xrGetInstanceProcAddr --------------------------------------------------------------------------------------- */
typedef enum proc_need { NEED_NONE = 0, NEED_INSTANCE, NEED_VULKAN, NEED_VULKAN2, NEED_TIMESPEC, NEED_OPENGL,
                         NEED_OPENGL_ES } proc_need;

typedef struct proc_entry {
    const char *name;
    PFN_xrVoidFunction fn;
    proc_need need;
} proc_entry;

static XRAPI_ATTR XrResult XRAPI_CALL get_instance_proc_addr(XrInstance instance, const char *name,
                                                             PFN_xrVoidFunction *function);

#define P(name, need) {#name, (PFN_xrVoidFunction)fv_##name, need}
static const proc_entry g_procs[] = {
    {"xrGetInstanceProcAddr", (PFN_xrVoidFunction)get_instance_proc_addr, NEED_NONE},
    P(xrEnumerateInstanceExtensionProperties, NEED_NONE),
    P(xrEnumerateApiLayerProperties, NEED_NONE),
    P(xrCreateInstance, NEED_NONE),
    P(xrDestroyInstance, NEED_INSTANCE),
    P(xrGetInstanceProperties, NEED_INSTANCE),
    P(xrPollEvent, NEED_INSTANCE),
    P(xrResultToString, NEED_INSTANCE),
    P(xrStructureTypeToString, NEED_INSTANCE),
    P(xrGetSystem, NEED_INSTANCE),
    P(xrGetSystemProperties, NEED_INSTANCE),
    P(xrEnumerateEnvironmentBlendModes, NEED_INSTANCE),
    P(xrEnumerateViewConfigurations, NEED_INSTANCE),
    P(xrGetViewConfigurationProperties, NEED_INSTANCE),
    P(xrEnumerateViewConfigurationViews, NEED_INSTANCE),
    P(xrCreateSession, NEED_INSTANCE),
    P(xrDestroySession, NEED_INSTANCE),
    P(xrBeginSession, NEED_INSTANCE),
    P(xrEndSession, NEED_INSTANCE),
    P(xrRequestExitSession, NEED_INSTANCE),
    P(xrWaitFrame, NEED_INSTANCE),
    P(xrBeginFrame, NEED_INSTANCE),
    P(xrEndFrame, NEED_INSTANCE),
    P(xrEnumerateReferenceSpaces, NEED_INSTANCE),
    P(xrCreateReferenceSpace, NEED_INSTANCE),
    P(xrGetReferenceSpaceBoundsRect, NEED_INSTANCE),
    P(xrCreateActionSpace, NEED_INSTANCE),
    P(xrLocateSpace, NEED_INSTANCE),
    P(xrDestroySpace, NEED_INSTANCE),
    P(xrLocateViews, NEED_INSTANCE),
    P(xrEnumerateSwapchainFormats, NEED_INSTANCE),
    P(xrCreateSwapchain, NEED_INSTANCE),
    P(xrDestroySwapchain, NEED_INSTANCE),
    P(xrEnumerateSwapchainImages, NEED_INSTANCE),
    P(xrAcquireSwapchainImage, NEED_INSTANCE),
    P(xrWaitSwapchainImage, NEED_INSTANCE),
    P(xrReleaseSwapchainImage, NEED_INSTANCE),
    P(xrGetVulkanInstanceExtensionsKHR, NEED_VULKAN),
    P(xrGetVulkanDeviceExtensionsKHR, NEED_VULKAN),
    P(xrGetVulkanGraphicsDeviceKHR, NEED_VULKAN),
    P(xrGetVulkanGraphicsRequirementsKHR, NEED_VULKAN),
    P(xrCreateVulkanInstanceKHR, NEED_VULKAN2),
    P(xrCreateVulkanDeviceKHR, NEED_VULKAN2),
    P(xrGetVulkanGraphicsDevice2KHR, NEED_VULKAN2),
    {"xrGetVulkanGraphicsRequirements2KHR", (PFN_xrVoidFunction)fv_xrGetVulkanGraphicsRequirementsKHR, NEED_VULKAN2},
    P(xrGetOpenGLGraphicsRequirementsKHR, NEED_OPENGL),
    P(xrGetOpenGLESGraphicsRequirementsKHR, NEED_OPENGL_ES),
    P(xrConvertTimespecTimeToTimeKHR, NEED_TIMESPEC),
    P(xrConvertTimeToTimespecTimeKHR, NEED_TIMESPEC),
};
#undef P

static XRAPI_ATTR XrResult XRAPI_CALL get_instance_proc_addr(XrInstance instance, const char *name,
                                                             PFN_xrVoidFunction *function)
{
    if (!function) return XR_ERROR_VALIDATION_FAILURE;
    *function = NULL;
    if (!name) return XR_ERROR_VALIDATION_FAILURE;
    struct XrInstance_T *inst = NULL;
    if (instance != XR_NULL_HANDLE) {
        inst = fv_xr_instance_check(instance);
        if (!inst) return XR_ERROR_HANDLE_INVALID;
    }
    const proc_entry *e = NULL;
    for (size_t i = 0; i < sizeof g_procs / sizeof g_procs[0] && !e; i++)
        if (strcmp(g_procs[i].name, name) == 0) e = &g_procs[i];
    PFN_xrVoidFunction input_fn = e ? NULL : fv_xr_input_proc(name);
    if (!e && !input_fn) return XR_ERROR_FUNCTION_UNSUPPORTED;
    if (input_fn) {
        if (!inst) return XR_ERROR_HANDLE_INVALID;
        *function = input_fn;
        return XR_SUCCESS;
    }
    if (e->need != NEED_NONE && !inst) return XR_ERROR_HANDLE_INVALID;
    if ((e->need == NEED_VULKAN && !inst->ext.vulkan) || (e->need == NEED_VULKAN2 && !inst->ext.vulkan2) ||
        (e->need == NEED_TIMESPEC && !inst->ext.convert_timespec) || (e->need == NEED_OPENGL && !inst->ext.opengl) ||
        (e->need == NEED_OPENGL_ES && !inst->ext.opengl_es))
        return XR_ERROR_FUNCTION_UNSUPPORTED; /* the extension is not enabled */
    *function = e->fn;
    return XR_SUCCESS;
}

FV_XR_EXPORT XRAPI_ATTR XrResult XRAPI_CALL xrNegotiateLoaderRuntimeInterface(const XrNegotiateLoaderInfo *info,
                                                                              XrNegotiateRuntimeRequest *req)
{
    if (!info || !req) return XR_ERROR_INITIALIZATION_FAILED;
    if (info->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO ||
        info->structVersion != XR_LOADER_INFO_STRUCT_VERSION || info->structSize != sizeof *info)
        return XR_ERROR_INITIALIZATION_FAILED;
    if (req->structType != XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST ||
        req->structVersion != XR_RUNTIME_INFO_STRUCT_VERSION || req->structSize != sizeof *req)
        return XR_ERROR_INITIALIZATION_FAILED;
    if (info->minInterfaceVersion > XR_CURRENT_LOADER_RUNTIME_VERSION ||
        info->maxInterfaceVersion < XR_CURRENT_LOADER_RUNTIME_VERSION)
        return XR_ERROR_INITIALIZATION_FAILED;
    /* The runtime implements OpenXR 1.0 (patch level of the headers it is built with). */
    if (XR_VERSION_MAJOR(info->minApiVersion) > 1 || XR_VERSION_MAJOR(info->maxApiVersion) < 1)
        return XR_ERROR_INITIALIZATION_FAILED;
    req->runtimeInterfaceVersion = XR_CURRENT_LOADER_RUNTIME_VERSION;
    req->runtimeApiVersion = XR_CURRENT_API_VERSION;
    req->getInstanceProcAddr = get_instance_proc_addr;
    return XR_SUCCESS;
}
