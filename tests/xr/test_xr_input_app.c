/* @brief A small OpenXR app of our own on fovea's runtime through the OpenXR loader (XR_RUNTIME_JSON = the generated
 * manifest), headless (XR_MND_headless) with XR_EXT_eye_gaze_interaction and a fixed: gaze source
 * (FOVEA_XR_GAZE): the action system's rules as an app meets them — paths, sets, actions, suggested bindings,
 * attach, XR_SESSION_NOT_FOCUSED before the session is focused, the interaction-profile-changed event, the eye-gaze
 * pose action, bound sources and localized names, stale handles. Run twice: once with the error cases (no layer,
 * the runtime must answer them), once with only valid calls under the OpenXR core-validation layer, asserting it
 * reports nothing. argv[1] = the runtime manifest. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openxr/openxr.h>

#include "fv_test.h"

static const char *g_manifest;

#define CHK(call)                                                                                                      \
    do {                                                                                                               \
        XrResult r_ = (call);                                                                                          \
        if (r_ != XR_SUCCESS) fail_msg("%s = %d", #call, (int)r_);                                                     \
    } while (0)

typedef struct app {
    XrInstance inst;
    XrSystemId sys;
    XrSession sess;
    XrSessionState state;
    int profile_events;
} app;

static XrPath path(app *a, const char *s)
{
    XrPath p = XR_NULL_PATH;
    CHK(xrStringToPath(a->inst, s, &p));
    return p;
}

static void poll_events(app *a)
{
    for (;;) {
        XrEventDataBuffer ev = {.type = XR_TYPE_EVENT_DATA_BUFFER};
        XrResult r = xrPollEvent(a->inst, &ev);
        if (r == XR_EVENT_UNAVAILABLE) return;
        assert_int_equal(r, XR_SUCCESS);
        if (ev.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED)
            a->state = ((XrEventDataSessionStateChanged *)&ev)->state;
        if (ev.type == XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED) {
            assert_ptr_equal(((XrEventDataInteractionProfileChanged *)&ev)->session, a->sess);
            a->profile_events++;
        }
    }
}

static void start(app *a, bool layer, const char *validation_file)
{
    memset(a, 0, sizeof *a);
    setenv("XR_RUNTIME_JSON", g_manifest, 1);
    setenv("FOVEA_XR_GAZE", "fixed:yaw_deg=10,pitch_deg=-5", 1);
    if (layer) {
        setenv("XR_ENABLE_API_LAYERS", "XR_APILAYER_LUNARG_core_validation", 1);
        setenv("XR_CORE_VALIDATION_EXPORT_TYPE", "text", 1);
        setenv("XR_CORE_VALIDATION_FILE_NAME", validation_file, 1);
    } else {
        unsetenv("XR_ENABLE_API_LAYERS");
    }
    const char *exts[] = {XR_MND_HEADLESS_EXTENSION_NAME, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME};
    XrInstanceCreateInfo ci = {.type = XR_TYPE_INSTANCE_CREATE_INFO,
                               .enabledExtensionCount = 2,
                               .enabledExtensionNames = exts,
                               .applicationInfo = {.applicationName = "test_xr_input_app",
                                                   .apiVersion = XR_MAKE_VERSION(1, 0, 0)}};
    CHK(xrCreateInstance(&ci, &a->inst));
    XrSystemGetInfo sg = {.type = XR_TYPE_SYSTEM_GET_INFO, .formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY};
    CHK(xrGetSystem(a->inst, &sg, &a->sys));
    XrSystemEyeGazeInteractionPropertiesEXT gp = {.type = XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT};
    XrSystemProperties sp = {.type = XR_TYPE_SYSTEM_PROPERTIES, .next = &gp};
    CHK(xrGetSystemProperties(a->inst, a->sys, &sp));
    assert_true(gp.supportsEyeGazeInteraction); /* the fixed: source is open */
}

static void create_session(app *a)
{
    XrSessionCreateInfo sc = {.type = XR_TYPE_SESSION_CREATE_INFO, .systemId = a->sys}; /* headless: no binding */
    CHK(xrCreateSession(a->inst, &sc, &a->sess));
    poll_events(a);
    assert_int_equal(a->state, XR_SESSION_STATE_READY);
}

static void finish(app *a)
{
    CHK(xrRequestExitSession(a->sess));
    poll_events(a);
    if (a->state == XR_SESSION_STATE_STOPPING) CHK(xrEndSession(a->sess));
    CHK(xrDestroySession(a->sess));
    CHK(xrDestroyInstance(a->inst));
}

/* The flow both runs share; errors = also make the calls that must fail. */
static void flow(app *a, bool errors)
{
    XrActionSetCreateInfo si = {.type = XR_TYPE_ACTION_SET_CREATE_INFO, .actionSetName = "gameplay",
                                .localizedActionSetName = "Gameplay"};
    XrActionSet set;
    CHK(xrCreateActionSet(a->inst, &si, &set));
    XrPath hands[2] = {path(a, "/user/hand/left"), path(a, "/user/hand/right")};
    XrPath eyes = path(a, "/user/eyes_ext");
    XrActionCreateInfo ai = {.type = XR_TYPE_ACTION_CREATE_INFO, .actionName = "grab", .actionType =
                             XR_ACTION_TYPE_FLOAT_INPUT, .countSubactionPaths = 2, .subactionPaths = hands,
                             .localizedActionName = "Grab"};
    XrAction grab, gaze, quit;
    CHK(xrCreateAction(set, &ai, &grab));
    XrActionCreateInfo gi = {.type = XR_TYPE_ACTION_CREATE_INFO, .actionName = "gaze", .actionType =
                             XR_ACTION_TYPE_POSE_INPUT, .countSubactionPaths = 1, .subactionPaths = &eyes,
                             .localizedActionName = "Gaze"};
    CHK(xrCreateAction(set, &gi, &gaze));
    XrActionCreateInfo qi = {.type = XR_TYPE_ACTION_CREATE_INFO, .actionName = "quit", .actionType =
                             XR_ACTION_TYPE_BOOLEAN_INPUT, .localizedActionName = "Quit"};
    CHK(xrCreateAction(set, &qi, &quit));
    if (errors) {
        XrPath p;
        assert_int_equal(xrStringToPath(a->inst, "/user//hand", &p), XR_ERROR_PATH_FORMAT_INVALID);
        XrAction dup;
        assert_int_equal(xrCreateAction(set, &ai, &dup), XR_ERROR_NAME_DUPLICATED);
        XrActionCreateInfo bad = qi;
        strcpy(bad.actionName, "quit2");
        strcpy(bad.localizedActionName, "Quit 2");
        XrPath tread = path(a, "/user/treadmill");
        bad.countSubactionPaths = 1;
        bad.subactionPaths = &tread;
        assert_int_equal(xrCreateAction(set, &bad, &dup), XR_ERROR_PATH_UNSUPPORTED);
    }
    XrActionSuggestedBinding simple[3] = {{grab, path(a, "/user/hand/left/input/select/click")},
                                          {grab, path(a, "/user/hand/right/input/select/click")},
                                          {quit, path(a, "/user/hand/left/input/menu/click")}};
    XrInteractionProfileSuggestedBinding sb = {.type = XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING,
                                               .interactionProfile =
                                                   path(a, "/interaction_profiles/khr/simple_controller"),
                                               .countSuggestedBindings = 3,
                                               .suggestedBindings = simple};
    CHK(xrSuggestInteractionProfileBindings(a->inst, &sb));
    XrActionSuggestedBinding gb = {gaze, path(a, "/user/eyes_ext/input/gaze_ext/pose")};
    XrInteractionProfileSuggestedBinding gsb = {.type = XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING,
                                                .interactionProfile =
                                                    path(a, "/interaction_profiles/ext/eye_gaze_interaction"),
                                                .countSuggestedBindings = 1,
                                                .suggestedBindings = &gb};
    CHK(xrSuggestInteractionProfileBindings(a->inst, &gsb));
    if (errors) {
        XrActionSuggestedBinding wrong = {grab, path(a, "/user/hand/left/input/trigger/value")};
        sb.suggestedBindings = &wrong;
        sb.countSuggestedBindings = 1;
        assert_int_equal(xrSuggestInteractionProfileBindings(a->inst, &sb), XR_ERROR_PATH_UNSUPPORTED);
    }

    create_session(a);
    XrActiveActionSet active = {set, XR_NULL_PATH};
    XrActionsSyncInfo sync = {.type = XR_TYPE_ACTIONS_SYNC_INFO, .countActiveActionSets = 1,
                              .activeActionSets = &active};
    if (errors) {
        XrInteractionProfileState ps = {.type = XR_TYPE_INTERACTION_PROFILE_STATE};
        assert_int_equal(xrGetCurrentInteractionProfile(a->sess, eyes, &ps), XR_ERROR_ACTIONSET_NOT_ATTACHED);
        assert_int_equal(xrSyncActions(a->sess, &sync), XR_ERROR_ACTIONSET_NOT_ATTACHED);
    }
    XrActionSpaceCreateInfo asi = {.type = XR_TYPE_ACTION_SPACE_CREATE_INFO, .action = gaze,
                                   .poseInActionSpace = {.orientation = {0, 0, 0, 1}}};
    XrSpace gaze_space;
    CHK(xrCreateActionSpace(a->sess, &asi, &gaze_space));
    if (errors) {
        XrSpace bad;
        asi.action = grab;
        assert_int_equal(xrCreateActionSpace(a->sess, &asi, &bad), XR_ERROR_ACTION_TYPE_MISMATCH);
        asi.action = gaze;
        asi.subactionPath = hands[0];
        assert_int_equal(xrCreateActionSpace(a->sess, &asi, &bad), XR_ERROR_PATH_UNSUPPORTED);
    }
    XrSessionActionSetsAttachInfo at = {.type = XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO, .countActionSets = 1,
                                        .actionSets = &set};
    CHK(xrAttachSessionActionSets(a->sess, &at));
    if (errors) {
        assert_int_equal(xrAttachSessionActionSets(a->sess, &at), XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
        XrAction late;
        XrActionCreateInfo li = qi;
        strcpy(li.actionName, "late");
        strcpy(li.localizedActionName, "Late");
        assert_int_equal(xrCreateAction(set, &li, &late), XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
    }
    /* READY, not focused: the sync says so and every action reads inactive */
    assert_int_equal(xrSyncActions(a->sess, &sync), XR_SESSION_NOT_FOCUSED);
    XrActionStateGetInfo gg = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = gaze};
    XrActionStatePose pose = {.type = XR_TYPE_ACTION_STATE_POSE};
    CHK(xrGetActionStatePose(a->sess, &gg, &pose));
    assert_false(pose.isActive);

    XrSessionBeginInfo bi = {.type = XR_TYPE_SESSION_BEGIN_INFO,
                             .primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO};
    CHK(xrBeginSession(a->sess, &bi));
    poll_events(a);
    assert_int_equal(a->state, XR_SESSION_STATE_FOCUSED);
    CHK(xrSyncActions(a->sess, &sync));
    poll_events(a);
    assert_int_equal(a->profile_events, 1); /* /user/eyes_ext got its profile */
    XrInteractionProfileState ps = {.type = XR_TYPE_INTERACTION_PROFILE_STATE};
    CHK(xrGetCurrentInteractionProfile(a->sess, eyes, &ps));
    assert_int_equal(ps.interactionProfile, path(a, "/interaction_profiles/ext/eye_gaze_interaction"));
    CHK(xrGetCurrentInteractionProfile(a->sess, hands[0], &ps));
    assert_int_equal(ps.interactionProfile, XR_NULL_PATH); /* fovea has no controllers */
    CHK(xrGetActionStatePose(a->sess, &gg, &pose));
    assert_true(pose.isActive);
    XrActionStateGetInfo fg = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = grab, .subactionPath = hands[1]};
    XrActionStateFloat fs = {.type = XR_TYPE_ACTION_STATE_FLOAT};
    CHK(xrGetActionStateFloat(a->sess, &fg, &fs));
    assert_false(fs.isActive);
    assert_true(fs.currentState == 0.0f);
    XrBoundSourcesForActionEnumerateInfo be = {.type = XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO, .action = gaze};
    uint32_t n = 0;
    CHK(xrEnumerateBoundSourcesForAction(a->sess, &be, 0, &n, NULL));
    assert_int_equal(n, 1);
    XrPath src = XR_NULL_PATH;
    CHK(xrEnumerateBoundSourcesForAction(a->sess, &be, 1, &n, &src));
    assert_int_equal(src, path(a, "/user/eyes_ext/input/gaze_ext/pose"));
    XrInputSourceLocalizedNameGetInfo ln = {.type = XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO, .sourcePath = src,
                                            .whichComponents = XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT |
                                                               XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT};
    char name[64];
    CHK(xrGetInputSourceLocalizedName(a->sess, &ln, 0, &n, NULL));
    assert_true(n <= sizeof name);
    CHK(xrGetInputSourceLocalizedName(a->sess, &ln, n, &n, name));
    assert_string_equal(name, "Eyes Eye Gaze Pose");
    /* a second sync with nothing new: no second event */
    CHK(xrSyncActions(a->sess, &sync));
    poll_events(a);
    assert_int_equal(a->profile_events, 1);
    if (errors) {
        XrActionStateBoolean bs = {.type = XR_TYPE_ACTION_STATE_BOOLEAN};
        assert_int_equal(xrGetActionStateBoolean(a->sess, &fg, &bs), XR_ERROR_ACTION_TYPE_MISMATCH);
        CHK(xrDestroyAction(grab));
        assert_int_equal(xrGetActionStateFloat(a->sess, &fg, &fs), XR_ERROR_HANDLE_INVALID);
    }
    CHK(xrDestroySpace(gaze_space));
    CHK(xrDestroyActionSet(set));
}

static void action_rules_hold_through_the_loader_and_runtime(void **st)
{
    (void)st;
    app a;
    start(&a, false, NULL);
    flow(&a, true);
    finish(&a);
}

static void valid_action_use_is_clean_under_core_validation(void **st)
{
    (void)st;
    const char *out = fv_test_tmp("core_validation.txt");
    remove(out);
    app a;
    start(&a, true, out);
    flow(&a, false);
    finish(&a);
    FILE *f = fopen(out, "r");
    if (!f) return; /* the layer writes the file only when it has something to say */
    char line[1024];
    while (fgets(line, sizeof line, f)) {
        if (strstr(line, "VUID-") || strstr(line, "Error") || strstr(line, "error"))
            fail_msg("core validation: %s", line);
    }
    fclose(f);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s RUNTIME_MANIFEST\n", argv[0]);
        return 2;
    }
    g_manifest = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(action_rules_hold_through_the_loader_and_runtime),
        cmocka_unit_test(valid_action_use_is_clean_under_core_validation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
