/* @brief fv_xr_input: skeleton (every call fails with XR_ERROR_RUNTIME_FAILURE until implemented). */
#include "fv_xr_input.h"

XrResult fv_xr_input_create(const fv_xr_input_desc *desc, fv_xr_input **out)
{
    (void)desc;
    (void)out;
    return XR_ERROR_RUNTIME_FAILURE;
}

void fv_xr_input_destroy(fv_xr_input **in)
{
    (void)in;
}

XrResult fv_xr_input_string_to_path(fv_xr_input *in, const char *str, XrPath *out)
{
    (void)in;
    (void)str;
    (void)out;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_path_to_string(fv_xr_input *in, XrPath path, uint32_t capacity, uint32_t *count_out, char *buf)
{
    (void)in;
    (void)path;
    (void)capacity;
    (void)count_out;
    (void)buf;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_create_action_set(fv_xr_input *in, const XrActionSetCreateInfo *info, XrActionSet *out)
{
    (void)in;
    (void)info;
    (void)out;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_destroy_action_set(fv_xr_input *in, XrActionSet set)
{
    (void)in;
    (void)set;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_create_action(fv_xr_input *in, XrActionSet set, const XrActionCreateInfo *info, XrAction *out)
{
    (void)in;
    (void)set;
    (void)info;
    (void)out;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_destroy_action(fv_xr_input *in, XrAction action)
{
    (void)in;
    (void)action;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_suggest_bindings(fv_xr_input *in, const XrInteractionProfileSuggestedBinding *b)
{
    (void)in;
    (void)b;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_session_create(fv_xr_input *in, fv_xr_input_session **out)
{
    (void)in;
    (void)out;
    return XR_ERROR_RUNTIME_FAILURE;
}

void fv_xr_input_session_destroy(fv_xr_input_session **s)
{
    (void)s;
}

XrResult fv_xr_input_attach(fv_xr_input_session *s, const XrSessionActionSetsAttachInfo *info)
{
    (void)s;
    (void)info;
    return XR_ERROR_RUNTIME_FAILURE;
}

void fv_xr_input_update_profiles(fv_xr_input_session *s, const fv_xr_input_devices *dev)
{
    (void)s;
    (void)dev;
}

XrResult fv_xr_input_get_current_interaction_profile(fv_xr_input_session *s, XrPath top_level_user_path, XrInteractionProfileState *out)
{
    (void)s;
    (void)top_level_user_path;
    (void)out;
    return XR_ERROR_RUNTIME_FAILURE;
}

bool fv_xr_input_take_profile_changed(fv_xr_input_session *s)
{
    (void)s;
    return false;
}

XrResult fv_xr_input_sync(fv_xr_input_session *s, const XrActionsSyncInfo *info, const fv_xr_input_devices *dev)
{
    (void)s;
    (void)info;
    (void)dev;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_get_boolean(fv_xr_input_session *s, const XrActionStateGetInfo *g, XrActionStateBoolean *out)
{
    (void)s;
    (void)g;
    (void)out;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_get_float(fv_xr_input_session *s, const XrActionStateGetInfo *g, XrActionStateFloat *out)
{
    (void)s;
    (void)g;
    (void)out;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_get_vector2f(fv_xr_input_session *s, const XrActionStateGetInfo *g, XrActionStateVector2f *out)
{
    (void)s;
    (void)g;
    (void)out;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_get_pose(fv_xr_input_session *s, const XrActionStateGetInfo *g, XrActionStatePose *out)
{
    (void)s;
    (void)g;
    (void)out;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_enumerate_bound_sources(fv_xr_input_session *s, const XrBoundSourcesForActionEnumerateInfo *e, uint32_t capacity, uint32_t *count_out, XrPath *sources)
{
    (void)s;
    (void)e;
    (void)capacity;
    (void)count_out;
    (void)sources;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_get_localized_name(fv_xr_input_session *s, const XrInputSourceLocalizedNameGetInfo *g, uint32_t capacity, uint32_t *count_out, char *buf)
{
    (void)s;
    (void)g;
    (void)capacity;
    (void)count_out;
    (void)buf;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_apply_haptic(fv_xr_input_session *s, const XrHapticActionInfo *h, const XrHapticBaseHeader *fb)
{
    (void)s;
    (void)h;
    (void)fb;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_stop_haptic(fv_xr_input_session *s, const XrHapticActionInfo *h)
{
    (void)s;
    (void)h;
    return XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_input_check_action_space(fv_xr_input *in, const XrActionSpaceCreateInfo *info)
{
    (void)in;
    (void)info;
    return XR_ERROR_RUNTIME_FAILURE;
}

fv_xr_pose_source fv_xr_input_pose_source(fv_xr_input_session *s, XrAction action, XrPath subaction_path)
{
    (void)s;
    (void)action;
    (void)subaction_path;
    return FV_XR_POSE_NONE;
}

XrResult fv_xr_input_sync_unfocused(fv_xr_input_session *s, const XrActionsSyncInfo *info)
{
    (void)s;
    (void)info;
    return XR_ERROR_RUNTIME_FAILURE;
}

bool fv_xr_input_is_attached(const fv_xr_input_session *s)
{
    (void)s;
    return false;
}
