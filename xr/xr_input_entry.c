/* @brief The action system's OpenXR entry points (xrStringToPath ... xrStopHapticFeedback), each a thin wrapper that
 * checks the handle, takes the instance's lock and calls xr/input (fv_xr_input.h); the runtime's part: the devices
 * fovea has (the gaze source), FOCUSED-only syncs, the interaction-profile-changed event, action-space pose sources. */
#include <string.h>

#include "xr_internal.h"

#if FV_XR_HAVE_INPUT

XrResult fv_xr_input_instance_init(struct XrInstance_T *inst)
{
    fv_xr_input_desc d = {.eye_gaze_ext_enabled = inst->ext.eye_gaze};
    return fv_xr_input_create(&d, &inst->input);
}

void fv_xr_input_instance_fini(struct XrInstance_T *inst) { fv_xr_input_destroy(&inst->input); }

XrResult fv_xr_input_session_init(struct XrSession_T *s) { return fv_xr_input_session_create(s->inst->input, &s->input); }

void fv_xr_input_session_fini(struct XrSession_T *s) { fv_xr_input_session_destroy(&s->input); }

/* What fovea's devices give now: the gaze source (no controllers in fovea). */
static void devices_now(struct XrSession_T *s, fv_xr_input_devices *dev)
{
    memset(dev, 0, sizeof *dev);
    struct XrInstance_T *inst = s->inst;
    dev->time = fv_xr_now_ns();
    if (inst->gaze && inst->ext.eye_gaze && fv_xr_gaze_present(inst->gaze)) {
        dev->eye_gaze_present = true;
        dev->eye_gaze_tracked = fv_xr_gaze_tracked(inst->gaze, dev->time);
    }
}

static void queue_profile_changed(struct XrSession_T *s)
{
    if (!fv_xr_input_take_profile_changed(s->input)) return;
    XrEventDataInteractionProfileChanged ev = {XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED, NULL, s};
    fv_xr_event_push(s->inst, &ev, sizeof ev);
}

void fv_xr_input_focus(struct XrSession_T *s)
{
    fv_xr_input_devices dev;
    devices_now(s, &dev);
    fv_xr_input_update_profiles(s->input, &dev);
}

int fv_xr_input_space_source(struct XrSpace_T *sp)
{
    return (int)fv_xr_input_pose_source(sp->session->input, sp->action, sp->subaction_path);
}

XrResult fv_xr_input_check_space(struct XrSession_T *s, const XrActionSpaceCreateInfo *info)
{
    return fv_xr_input_check_action_space(s->inst->input, info);
}

/* ---- instance-level entry points ---------------------------------------------------------------------------- */
#define INST_CALL(instance, call)                                                                                      \
    struct XrInstance_T *inst = fv_xr_instance_check(instance);                                                        \
    if (!inst) return XR_ERROR_HANDLE_INVALID;                                                                         \
    pthread_mutex_lock(&inst->lock);                                                                                   \
    XrResult r = (call);                                                                                               \
    pthread_mutex_unlock(&inst->lock);                                                                                 \
    return r

#define SESSION_CALL(session, call)                                                                                    \
    struct XrSession_T *s = fv_xr_session_check(session);                                                              \
    if (!s) return XR_ERROR_HANDLE_INVALID;                                                                            \
    pthread_mutex_lock(&s->inst->lock);                                                                                \
    XrResult r = s->loss_pending ? XR_ERROR_SESSION_LOST : (call);                                                     \
    pthread_mutex_unlock(&s->inst->lock);                                                                              \
    return r

static XRAPI_ATTR XrResult XRAPI_CALL string_to_path(XrInstance instance, const char *str, XrPath *out)
{
    INST_CALL(instance, fv_xr_input_string_to_path(inst->input, str, out));
}

static XRAPI_ATTR XrResult XRAPI_CALL path_to_string(XrInstance instance, XrPath path, uint32_t cap, uint32_t *count,
                                                     char *buf)
{
    INST_CALL(instance, fv_xr_input_path_to_string(inst->input, path, cap, count, buf));
}

static XRAPI_ATTR XrResult XRAPI_CALL create_action_set(XrInstance instance, const XrActionSetCreateInfo *info,
                                                        XrActionSet *out)
{
    INST_CALL(instance, fv_xr_input_create_action_set(inst->input, info, out));
}

/* Action sets and actions: the input library validates the handles; every live instance is asked (one today). */

static XRAPI_ATTR XrResult XRAPI_CALL suggest_bindings(XrInstance instance, const XrInteractionProfileSuggestedBinding *b)
{
    INST_CALL(instance, fv_xr_input_suggest_bindings(inst->input, b));
}

static XRAPI_ATTR XrResult XRAPI_CALL attach(XrSession session, const XrSessionActionSetsAttachInfo *info)
{
    SESSION_CALL(session, fv_xr_input_attach(s->input, info));
}

static XRAPI_ATTR XrResult XRAPI_CALL current_profile(XrSession session, XrPath top, XrInteractionProfileState *out)
{
    SESSION_CALL(session, fv_xr_input_get_current_interaction_profile(s->input, top, out));
}

static XrResult sync_locked(struct XrSession_T *s, const XrActionsSyncInfo *info)
{
    if (s->state != XR_SESSION_STATE_FOCUSED) return fv_xr_input_sync_unfocused(s->input, info);
    fv_xr_input_devices dev;
    devices_now(s, &dev);
    XrResult r = fv_xr_input_sync(s->input, info, &dev);
    queue_profile_changed(s);
    return r;
}

static XRAPI_ATTR XrResult XRAPI_CALL sync_actions(XrSession session, const XrActionsSyncInfo *info)
{
    SESSION_CALL(session, sync_locked(s, info));
}

static XRAPI_ATTR XrResult XRAPI_CALL get_boolean(XrSession session, const XrActionStateGetInfo *g,
                                                  XrActionStateBoolean *out)
{
    SESSION_CALL(session, fv_xr_input_get_boolean(s->input, g, out));
}

static XRAPI_ATTR XrResult XRAPI_CALL get_float(XrSession session, const XrActionStateGetInfo *g,
                                                XrActionStateFloat *out)
{
    SESSION_CALL(session, fv_xr_input_get_float(s->input, g, out));
}

static XRAPI_ATTR XrResult XRAPI_CALL get_vector2f(XrSession session, const XrActionStateGetInfo *g,
                                                   XrActionStateVector2f *out)
{
    SESSION_CALL(session, fv_xr_input_get_vector2f(s->input, g, out));
}

static XRAPI_ATTR XrResult XRAPI_CALL get_pose(XrSession session, const XrActionStateGetInfo *g,
                                               XrActionStatePose *out)
{
    SESSION_CALL(session, fv_xr_input_get_pose(s->input, g, out));
}

static XRAPI_ATTR XrResult XRAPI_CALL bound_sources(XrSession session, const XrBoundSourcesForActionEnumerateInfo *e,
                                                    uint32_t cap, uint32_t *count, XrPath *sources)
{
    SESSION_CALL(session, fv_xr_input_enumerate_bound_sources(s->input, e, cap, count, sources));
}

static XRAPI_ATTR XrResult XRAPI_CALL localized_name(XrSession session, const XrInputSourceLocalizedNameGetInfo *g,
                                                     uint32_t cap, uint32_t *count, char *buf)
{
    SESSION_CALL(session, fv_xr_input_get_localized_name(s->input, g, cap, count, buf));
}

static XRAPI_ATTR XrResult XRAPI_CALL apply_haptic(XrSession session, const XrHapticActionInfo *h,
                                                   const XrHapticBaseHeader *fb)
{
    SESSION_CALL(session, fv_xr_input_apply_haptic(s->input, h, fb));
}

static XRAPI_ATTR XrResult XRAPI_CALL stop_haptic(XrSession session, const XrHapticActionInfo *h)
{
    SESSION_CALL(session, fv_xr_input_stop_haptic(s->input, h));
}

/* xrCreateAction / xrDestroyAction / xrDestroyActionSet take no instance: the action set / action handle belongs
 * to one instance's input library, which validates it. The instances that made action sets are remembered here, and
 * a handle goes to the live one whose library owns it (none: XR_ERROR_HANDLE_INVALID). Returns with that instance's
 * lock held. */
#define MAX_INPUT_INSTANCES 16
static pthread_mutex_t g_any_lock = PTHREAD_MUTEX_INITIALIZER;
static struct XrInstance_T *g_instances[MAX_INPUT_INSTANCES];

static struct XrInstance_T *lock_instance_owning(uint64_t handle)
{
    pthread_mutex_lock(&g_any_lock);
    struct XrInstance_T *found = NULL;
    for (int i = 0; i < MAX_INPUT_INSTANCES && !found; i++) {
        struct XrInstance_T *inst = g_instances[i];
        if (!inst) continue;
        if (!fv_xr_handle_live(inst, FV_XR_MAGIC_INSTANCE)) { /* destroyed since: forget it */
            g_instances[i] = NULL;
            continue;
        }
        pthread_mutex_lock(&inst->lock);
        if (fv_xr_input_owns_handle(inst->input, handle)) found = inst; /* keeps its lock */
        else pthread_mutex_unlock(&inst->lock);
    }
    pthread_mutex_unlock(&g_any_lock);
    return found;
}

static XRAPI_ATTR XrResult XRAPI_CALL create_action_set_tracked(XrInstance instance, const XrActionSetCreateInfo *info,
                                                                XrActionSet *out)
{
    struct XrInstance_T *inst = fv_xr_instance_check(instance);
    if (inst) {
        pthread_mutex_lock(&g_any_lock);
        int free_slot = -1, have = 0;
        for (int i = 0; i < MAX_INPUT_INSTANCES; i++) {
            if (g_instances[i] == inst) have = 1;
            else if (g_instances[i] && !fv_xr_handle_live(g_instances[i], FV_XR_MAGIC_INSTANCE)) g_instances[i] = NULL;
            if (!g_instances[i] && free_slot < 0) free_slot = i;
        }
        bool full = !have && free_slot < 0;
        if (!have && free_slot >= 0) g_instances[free_slot] = inst;
        pthread_mutex_unlock(&g_any_lock);
        if (full) {
            FV_WARN(FV_XR_LOG, "xrCreateActionSet: more than %d instances with action sets at once", MAX_INPUT_INSTANCES);
            return XR_ERROR_LIMIT_REACHED;
        }
    }
    return create_action_set(instance, info, out);
}

static XRAPI_ATTR XrResult XRAPI_CALL destroy_action_set(XrActionSet set)
{
    struct XrInstance_T *inst = lock_instance_owning((uint64_t)(uintptr_t)set);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    XrResult r = fv_xr_input_destroy_action_set(inst->input, set);
    pthread_mutex_unlock(&inst->lock);
    return r;
}

static XRAPI_ATTR XrResult XRAPI_CALL create_action(XrActionSet set, const XrActionCreateInfo *info, XrAction *out)
{
    struct XrInstance_T *inst = lock_instance_owning((uint64_t)(uintptr_t)set);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    XrResult r = fv_xr_input_create_action(inst->input, set, info, out);
    pthread_mutex_unlock(&inst->lock);
    return r;
}

static XRAPI_ATTR XrResult XRAPI_CALL destroy_action(XrAction action)
{
    struct XrInstance_T *inst = lock_instance_owning((uint64_t)(uintptr_t)action);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    XrResult r = fv_xr_input_destroy_action(inst->input, action);
    pthread_mutex_unlock(&inst->lock);
    return r;
}

PFN_xrVoidFunction fv_xr_input_proc(const char *name)
{
    static const struct {
        const char *name;
        PFN_xrVoidFunction fn;
    } t[] = {
        {"xrStringToPath", (PFN_xrVoidFunction)string_to_path},
        {"xrPathToString", (PFN_xrVoidFunction)path_to_string},
        {"xrCreateActionSet", (PFN_xrVoidFunction)create_action_set_tracked},
        {"xrDestroyActionSet", (PFN_xrVoidFunction)destroy_action_set},
        {"xrCreateAction", (PFN_xrVoidFunction)create_action},
        {"xrDestroyAction", (PFN_xrVoidFunction)destroy_action},
        {"xrSuggestInteractionProfileBindings", (PFN_xrVoidFunction)suggest_bindings},
        {"xrAttachSessionActionSets", (PFN_xrVoidFunction)attach},
        {"xrGetCurrentInteractionProfile", (PFN_xrVoidFunction)current_profile},
        {"xrSyncActions", (PFN_xrVoidFunction)sync_actions},
        {"xrGetActionStateBoolean", (PFN_xrVoidFunction)get_boolean},
        {"xrGetActionStateFloat", (PFN_xrVoidFunction)get_float},
        {"xrGetActionStateVector2f", (PFN_xrVoidFunction)get_vector2f},
        {"xrGetActionStatePose", (PFN_xrVoidFunction)get_pose},
        {"xrEnumerateBoundSourcesForAction", (PFN_xrVoidFunction)bound_sources},
        {"xrGetInputSourceLocalizedName", (PFN_xrVoidFunction)localized_name},
        {"xrApplyHapticFeedback", (PFN_xrVoidFunction)apply_haptic},
        {"xrStopHapticFeedback", (PFN_xrVoidFunction)stop_haptic},
    };
    for (size_t i = 0; i < sizeof t / sizeof t[0]; i++)
        if (strcmp(t[i].name, name) == 0) return t[i].fn;
    return NULL;
}

#else /* built without xr/input: no action system */

XrResult fv_xr_input_instance_init(struct XrInstance_T *inst) { (void)inst; return XR_SUCCESS; }
void fv_xr_input_instance_fini(struct XrInstance_T *inst) { (void)inst; }
XrResult fv_xr_input_session_init(struct XrSession_T *s) { (void)s; return XR_SUCCESS; }
void fv_xr_input_session_fini(struct XrSession_T *s) { (void)s; }
void fv_xr_input_focus(struct XrSession_T *s) { (void)s; }
int fv_xr_input_space_source(struct XrSpace_T *sp) { (void)sp; return 0; }
XrResult fv_xr_input_check_space(struct XrSession_T *s, const XrActionSpaceCreateInfo *info)
{
    (void)s;
    (void)info;
    return XR_ERROR_HANDLE_INVALID;
}
PFN_xrVoidFunction fv_xr_input_proc(const char *name)
{
    (void)name;
    return NULL;
}
#endif
