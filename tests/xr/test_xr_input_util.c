/* @brief Helpers shared by the fv_xr_input tests (see test_xr_input_util.h). */
#include "fv_test.h"
#include "test_xr_input_util.h"

#include <stdio.h>

XrPath xri_test_path(fv_xr_input *in, const char *s)
{
    XrPath p = XR_NULL_PATH;
    XrResult r = fv_xr_input_string_to_path(in, s, &p);
    if (r != XR_SUCCESS) fail_msg("xrStringToPath(\"%s\") = %d", s, r);
    return p;
}

XrResult xri_test_try_set(fv_xr_input *in, const char *name, const char *lname, uint32_t priority, XrActionSet *out)
{
    XrActionSetCreateInfo si = {.type = XR_TYPE_ACTION_SET_CREATE_INFO, .priority = priority};
    snprintf(si.actionSetName, sizeof si.actionSetName, "%s", name);
    snprintf(si.localizedActionSetName, sizeof si.localizedActionSetName, "%s", lname);
    return fv_xr_input_create_action_set(in, &si, out);
}

XrActionSet xri_test_set(fv_xr_input *in, const char *name, uint32_t priority)
{
    char l[128];
    snprintf(l, sizeof l, "Set %s", name);
    XrActionSet s = XR_NULL_HANDLE;
    XrResult r = xri_test_try_set(in, name, l, priority, &s);
    if (r != XR_SUCCESS) fail_msg("xrCreateActionSet(%s) = %d", name, r);
    return s;
}

XrResult xri_test_try_action(fv_xr_input *in, XrActionSet set, const char *name, const char *lname, XrActionType t,
                             uint32_t nsub, const XrPath *sub, XrAction *out)
{
    XrActionCreateInfo ai = {.type = XR_TYPE_ACTION_CREATE_INFO, .actionType = t, .countSubactionPaths = nsub,
                             .subactionPaths = sub};
    snprintf(ai.actionName, sizeof ai.actionName, "%s", name);
    snprintf(ai.localizedActionName, sizeof ai.localizedActionName, "%s", lname);
    return fv_xr_input_create_action(in, set, &ai, out);
}

XrAction xri_test_action(fv_xr_input *in, XrActionSet set, const char *name, XrActionType t, uint32_t nsub,
                         const XrPath *sub)
{
    char l[128];
    snprintf(l, sizeof l, "Action %s", name);
    XrAction a = XR_NULL_HANDLE;
    XrResult r = xri_test_try_action(in, set, name, l, t, nsub, sub, &a);
    if (r != XR_SUCCESS) fail_msg("xrCreateAction(%s) = %d", name, r);
    return a;
}

XrResult xri_test_suggest(fv_xr_input *in, const char *profile, uint32_t n, const XrAction *acts,
                          const char *const *paths)
{
    XrActionSuggestedBinding b[32];
    assert_true(n <= 32);
    for (uint32_t i = 0; i < n; i++) {
        b[i].action = acts[i];
        b[i].binding = xri_test_path(in, paths[i]);
    }
    XrInteractionProfileSuggestedBinding sb = {.type = XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING,
                                               .interactionProfile = xri_test_path(in, profile),
                                               .countSuggestedBindings = n,
                                               .suggestedBindings = b};
    return fv_xr_input_suggest_bindings(in, &sb);
}

void xri_test_suggest_one(fv_xr_input *in, const char *profile, XrAction a, const char *path)
{
    const char *paths[1] = {path};
    XrResult r = xri_test_suggest(in, profile, 1, &a, paths);
    if (r != XR_SUCCESS) fail_msg("suggest %s %s = %d", profile, path, r);
}
