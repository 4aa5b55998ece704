/* @brief The small OpenXR app of tests/xr (see xr_app.h). */
#include "xr_app.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define CHECK_XR XR_APP_CHECK

XrTime xr_app_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts); /* fovea's XrTime is CLOCK_MONOTONIC ns (XR_KHR_convert_timespec_time) */
    return (XrTime)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static XrPath path(xr_app *a, const char *s)
{
    XrPath p = XR_NULL_PATH;
    CHECK_XR(xrStringToPath(a->inst, s, &p));
    return p;
}

void xr_app_open(xr_app *a, const char *manifest, const char *gaze_uri)
{
    memset(a, 0, sizeof *a);
    if (manifest) setenv("XR_RUNTIME_JSON", manifest, 1);
    setenv("XR_ENABLE_API_LAYERS", "XR_APILAYER_LUNARG_core_validation", 1);
    if (gaze_uri && *gaze_uri) setenv("FOVEA_XR_GAZE", gaze_uri, 1);
    else if (gaze_uri) unsetenv("FOVEA_XR_GAZE");
    const char *exts[] = {XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME, XR_MND_HEADLESS_EXTENSION_NAME};
    XrInstanceCreateInfo ci = {.type = XR_TYPE_INSTANCE_CREATE_INFO,
                               .applicationInfo = {.applicationName = "fovea xr_app",
                                                   .apiVersion = XR_CURRENT_API_VERSION},
                               .enabledExtensionCount = 2,
                               .enabledExtensionNames = exts};
    CHECK_XR(xrCreateInstance(&ci, &a->inst));
    XrSystemGetInfo gi = {.type = XR_TYPE_SYSTEM_GET_INFO, .formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY};
    CHECK_XR(xrGetSystem(a->inst, &gi, &a->system));
    XrSystemEyeGazeInteractionPropertiesEXT eg = {.type = XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT};
    XrSystemProperties sp = {.type = XR_TYPE_SYSTEM_PROPERTIES, .next = &eg};
    CHECK_XR(xrGetSystemProperties(a->inst, a->system, &sp));
    a->supports_gaze = eg.supportsEyeGazeInteraction == XR_TRUE;
    XrSessionCreateInfo sci = {.type = XR_TYPE_SESSION_CREATE_INFO, .systemId = a->system};
    CHECK_XR(xrCreateSession(a->inst, &sci, &a->session)); /* headless: no graphics binding */
    XrActionSetCreateInfo asi = {.type = XR_TYPE_ACTION_SET_CREATE_INFO, .actionSetName = "gaze",
                                 .localizedActionSetName = "Gaze"};
    CHECK_XR(xrCreateActionSet(a->inst, &asi, &a->set));
    XrActionCreateInfo aci = {.type = XR_TYPE_ACTION_CREATE_INFO, .actionName = "gaze_pose",
                              .actionType = XR_ACTION_TYPE_POSE_INPUT, .localizedActionName = "Gaze pose"};
    CHECK_XR(xrCreateAction(a->set, &aci, &a->gaze));
    XrActionSuggestedBinding b = {a->gaze, path(a, "/user/eyes_ext/input/gaze_ext/pose")};
    XrInteractionProfileSuggestedBinding sb = {.type = XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING,
                                               .interactionProfile =
                                                   path(a, "/interaction_profiles/ext/eye_gaze_interaction"),
                                               .countSuggestedBindings = 1,
                                               .suggestedBindings = &b};
    CHECK_XR(xrSuggestInteractionProfileBindings(a->inst, &sb));
    XrSessionActionSetsAttachInfo at = {.type = XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO, .countActionSets = 1,
                                        .actionSets = &a->set};
    CHECK_XR(xrAttachSessionActionSets(a->session, &at));
    XrActionSpaceCreateInfo asc = {.type = XR_TYPE_ACTION_SPACE_CREATE_INFO, .action = a->gaze,
                                   .poseInActionSpace = {{0, 0, 0, 1}, {0, 0, 0}}};
    CHECK_XR(xrCreateActionSpace(a->session, &asc, &a->gaze_space));
    XrReferenceSpaceCreateInfo rs = {.type = XR_TYPE_REFERENCE_SPACE_CREATE_INFO,
                                     .referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW,
                                     .poseInReferenceSpace = {{0, 0, 0, 1}, {0, 0, 0}}};
    CHECK_XR(xrCreateReferenceSpace(a->session, &rs, &a->view_space));
    /* IDLE, READY: then begin; a headless session goes to FOCUSED at once */
    bool ready = false, focused = false;
    for (int i = 0; i < 100 && !focused; i++) {
        XrEventDataBuffer ev = {.type = XR_TYPE_EVENT_DATA_BUFFER};
        XrResult r = xrPollEvent(a->inst, &ev);
        CHECK_XR(r);
        if (r == XR_EVENT_UNAVAILABLE) {
            if (ready && !focused) {
                XrSessionBeginInfo bi = {.type = XR_TYPE_SESSION_BEGIN_INFO,
                                         .primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO};
                CHECK_XR(xrBeginSession(a->session, &bi));
                ready = false;
            }
            continue;
        }
        if (ev.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
            XrSessionState s = ((XrEventDataSessionStateChanged *)&ev)->state;
            if (s == XR_SESSION_STATE_READY) ready = true;
            if (s == XR_SESSION_STATE_FOCUSED) focused = true;
        }
    }
    if (!focused) {
        fprintf(stderr, "the session never became FOCUSED\n");
        exit(1);
    }
}

void xr_app_close(xr_app *a)
{
    CHECK_XR(xrDestroySpace(a->gaze_space));
    CHECK_XR(xrDestroySpace(a->view_space));
    CHECK_XR(xrRequestExitSession(a->session));
    for (int i = 0; i < 100; i++) {
        XrEventDataBuffer ev = {.type = XR_TYPE_EVENT_DATA_BUFFER};
        if (xrPollEvent(a->inst, &ev) != XR_SUCCESS) break;
        if (ev.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED &&
            ((XrEventDataSessionStateChanged *)&ev)->state == XR_SESSION_STATE_STOPPING)
            CHECK_XR(xrEndSession(a->session));
    }
    CHECK_XR(xrDestroySession(a->session));
    CHECK_XR(xrDestroyInstance(a->inst));
}

/* Sync, then locate the gaze space in VIEW at t: the gaze direction (the pose's -z) and the flags. */
XrSpaceLocationFlags xr_app_locate(xr_app *a, XrTime t, double dir[3])
{
    XrActiveActionSet act = {a->set, XR_NULL_PATH};
    XrActionsSyncInfo si = {.type = XR_TYPE_ACTIONS_SYNC_INFO, .countActiveActionSets = 1, .activeActionSets = &act};
    CHECK_XR(xrSyncActions(a->session, &si));
    XrSpaceLocation loc = {.type = XR_TYPE_SPACE_LOCATION};
    CHECK_XR(xrLocateSpace(a->gaze_space, a->view_space, t, &loc));
    const XrQuaternionf q = loc.pose.orientation;
    /* rotate (0, 0, -1) by q */
    dir[0] = -(2.0 * (q.x * q.z + q.y * q.w));
    dir[1] = -(2.0 * (q.y * q.z - q.x * q.w));
    dir[2] = -(1.0 - 2.0 * (q.x * q.x + q.y * q.y));
    return loc.locationFlags;
}

double xr_app_angle_deg(const double a[3], const double b[3])
{
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    double na = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), nb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double c = d / (na * nb);
    return acos(c > 1 ? 1 : c < -1 ? -1 : c) * 180.0 / M_PI;
}

XrTime xr_app_frame(xr_app *a)
{
    XrFrameWaitInfo wi = {.type = XR_TYPE_FRAME_WAIT_INFO};
    XrFrameState fs = {.type = XR_TYPE_FRAME_STATE};
    CHECK_XR(xrWaitFrame(a->session, &wi, &fs));
    XrFrameBeginInfo bi = {.type = XR_TYPE_FRAME_BEGIN_INFO};
    CHECK_XR(xrBeginFrame(a->session, &bi));
    XrFrameEndInfo ei = {.type = XR_TYPE_FRAME_END_INFO,
                         .displayTime = fs.predictedDisplayTime,
                         .environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE};
    CHECK_XR(xrEndFrame(a->session, &ei));
    return fs.predictedDisplayTime;
}

int xr_app_run_session(XrInstance inst, XrSession session, XrViewConfigurationType config, int frames,
                       void (*frame)(void *ctx, int n, bool visible), void *ctx)
{
    XrSessionState state = XR_SESSION_STATE_UNKNOWN;
    bool running = false, exit_requested = false, done = false;
    int n = 0;
    while (!done) {
        XrEventDataBuffer ev = {.type = XR_TYPE_EVENT_DATA_BUFFER};
        XrResult r;
        while ((r = xrPollEvent(inst, &ev)) == XR_SUCCESS) {
            if (ev.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
                state = ((XrEventDataSessionStateChanged *)&ev)->state;
                if (state == XR_SESSION_STATE_READY) {
                    XrSessionBeginInfo bi = {.type = XR_TYPE_SESSION_BEGIN_INFO, .primaryViewConfigurationType = config};
                    CHECK_XR(xrBeginSession(session, &bi));
                    running = true;
                } else if (state == XR_SESSION_STATE_STOPPING) {
                    CHECK_XR(xrEndSession(session));
                    running = false;
                } else if (state == XR_SESSION_STATE_EXITING || state == XR_SESSION_STATE_LOSS_PENDING) {
                    done = true;
                }
            }
            ev = (XrEventDataBuffer){.type = XR_TYPE_EVENT_DATA_BUFFER};
        }
        CHECK_XR(r);
        if (done) break;
        if (!running) {
            usleep(1000); /* waiting for the runtime's next state */
            continue;
        }
        if (n < frames) {
            frame(ctx, n, state == XR_SESSION_STATE_VISIBLE || state == XR_SESSION_STATE_FOCUSED);
            n++;
        } else if (!exit_requested) {
            CHECK_XR(xrRequestExitSession(session));
            exit_requested = true;
        }
    }
    return n;
}

int xr_app_args(int argc, char **argv, const char *usage, int *frames, const xr_app_flag *flags, int flag_count,
                int (*other)(void *ctx, int argc, char **argv, int *i), void *ctx)
{
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--frames") && i + 1 < argc) {
            *frames = atoi(argv[++i]);
            continue;
        }
        int took = 0;
        for (int f = 0; f < flag_count && !took; f++)
            if (!strcmp(argv[i], flags[f].name)) *flags[f].value = true, took = 1;
        if (!took && other) took = other(ctx, argc, argv, &i);
        if (took == 2) return 2;
        if (!took) {
            fprintf(stderr, "usage: %s %s\n", argv[0], usage);
            return 2;
        }
    }
    if (*frames < 1 || *frames > 100000) {
        const char *name = strrchr(argv[0], '/');
        fprintf(stderr, "%s: --frames %d: expected 1..100000\n", name ? name + 1 : argv[0], *frames);
        return 2;
    }
    return 0;
}
