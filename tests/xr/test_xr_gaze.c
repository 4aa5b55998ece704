/* @brief An OpenXR app of our own reading eye gaze from fovea's runtime through the OpenXR loader (XR_RUNTIME_JSON,
 * the core-validation layer on): XR_EXT_eye_gaze_interaction in a headless session (XR_MND_headless), the gaze pose
 * action bound to /user/eyes_ext/input/gaze_ext/pose, its action space located against VIEW.
 *  - fixed: the pose comes back as the fixed direction, tracked, at any requested time;
 *  - sim: the pose is fovea's prediction to the requested time (later times are further along the eye's motion);
 *    blinks clear the TRACKED bits;
 *  - no FOVEA_XR_GAZE: supportsEyeGazeInteraction is false and the action space is not located.
 * argv[1] = the runtime manifest. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <openxr/openxr.h>

#include "fv_test.h"

static const char *g_manifest;

#define CHECK_XR(call)                                                                                                 \
    do {                                                                                                               \
        XrResult r_ = (call);                                                                                          \
        if (XR_FAILED(r_)) fail_msg("%s failed: %d", #call, (int)r_);                                                 \
    } while (0)

typedef struct app {
    XrInstance inst;
    XrSystemId system;
    XrSession session;
    XrActionSet set;
    XrAction gaze;
    XrSpace gaze_space, view_space;
    bool supports_gaze;
} app;

static XrTime now_xr(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts); /* fovea's XrTime is CLOCK_MONOTONIC ns (XR_KHR_convert_timespec_time) */
    return (XrTime)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static XrPath path(app *a, const char *s)
{
    XrPath p = XR_NULL_PATH;
    CHECK_XR(xrStringToPath(a->inst, s, &p));
    return p;
}

static void app_open(app *a, const char *gaze_uri)
{
    memset(a, 0, sizeof *a);
    setenv("XR_RUNTIME_JSON", g_manifest, 1);
    setenv("XR_ENABLE_API_LAYERS", "XR_APILAYER_LUNARG_core_validation", 1);
    if (gaze_uri) setenv("FOVEA_XR_GAZE", gaze_uri, 1);
    else unsetenv("FOVEA_XR_GAZE");
    const char *exts[] = {XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME, XR_MND_HEADLESS_EXTENSION_NAME};
    XrInstanceCreateInfo ci = {.type = XR_TYPE_INSTANCE_CREATE_INFO,
                               .applicationInfo = {.applicationName = "test_xr_gaze",
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
    assert_true(focused);
}

static void app_close(app *a)
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
static XrSpaceLocationFlags locate(app *a, XrTime t, double dir[3])
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

static double angle_deg(const double a[3], const double b[3])
{
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    double na = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), nb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double c = d / (na * nb);
    return acos(c > 1 ? 1 : c < -1 ? -1 : c) * 180.0 / M_PI;
}

#define ALL_BITS                                                                                                       \
    (XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT |                                \
     XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT)
#define TRACKED_BITS (XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT)

static void fixed_gaze_comes_back_as_the_same_pose(void **state)
{
    (void)state;
    app a;
    app_open(&a, "fixed:yaw_deg=10,pitch_deg=-5,rate_hz=250");
    assert_true(a.supports_gaze);
    XrActionStateGetInfo gi = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = a.gaze};
    /* the pipeline needs a few samples: wait until the pose is tracked */
    double dir[3];
    XrSpaceLocationFlags f = 0;
    for (int i = 0; i < 200 && (f & ALL_BITS) != ALL_BITS; i++) {
        usleep(10000);
        f = locate(&a, now_xr(), dir);
    }
    assert_int_equal(f & ALL_BITS, ALL_BITS);
    XrActionStatePose ps = {.type = XR_TYPE_ACTION_STATE_POSE};
    CHECK_XR(xrGetActionStatePose(a.session, &gi, &ps));
    assert_true(ps.isActive);
    /* yaw right-positive, pitch up-positive, (0, 0) = -z */
    double y = 10 * M_PI / 180, p = -5 * M_PI / 180;
    double want[3] = {sin(y) * cos(p), sin(p), -cos(y) * cos(p)};
    for (int k = 0; k < 3; k++) {
        XrTime t = now_xr() + (XrTime)k * 40000000; /* now, +40 ms, +80 ms: a fixed gaze does not move */
        f = locate(&a, t, dir);
        double err = angle_deg(dir, want);
        print_message("fixed: t+%d ms: error %.5f deg, flags 0x%llx\n", 40 * k, err, (unsigned long long)f);
        assert_true(err < 0.01);
        assert_int_equal(f & ALL_BITS, ALL_BITS);
    }
    app_close(&a);
}

static void sim_gaze_is_predicted_to_the_requested_time(void **state)
{
    (void)state;
    app a;
    /* smooth pursuits after every gaze shift, no blinks, little noise: the eye keeps moving */
    app_open(&a, "sim:seed=7,rate_hz=250,pursuit_prob=1,blink_per_min=0,dropout=0,eye_loss=0,precision_deg=0.02");
    assert_true(a.supports_gaze);
    int moving = 0, consistent = 0, samples = 0;
    for (int i = 0; i < 150; i++) {
        usleep(10000);
        XrTime t = now_xr();
        double d0[3], d1[3], d2[3];
        XrSpaceLocationFlags f0 = locate(&a, t, d0);
        XrSpaceLocationFlags f1 = locate(&a, t + 25000000, d1);
        XrSpaceLocationFlags f2 = locate(&a, t + 50000000, d2);
        if ((f0 & f1 & f2 & ALL_BITS) != ALL_BITS) continue;
        samples++;
        double a01 = angle_deg(d0, d1), a02 = angle_deg(d0, d2);
        if (a02 > 0.05) {
            moving++;
            /* further in time is further along the motion */
            if (a02 > a01) consistent++;
        }
    }
    print_message("sim: %d tracked instants, %d with the gaze predicted to move, %d further at +50 than at +25 ms\n",
                  samples, moving, consistent);
    assert_true(samples > 100);
    assert_true(moving > 10);              /* the requested time changes the answer while the eye moves */
    assert_true(consistent >= moving * 8 / 10);
    app_close(&a);
}

static void sim_blinks_clear_the_tracked_bits(void **state)
{
    (void)state;
    app a;
    app_open(&a, "sim:seed=11,rate_hz=250,blink_per_min=60");
    int tracked = 0, untracked_valid = 0, total = 0;
    for (int i = 0; i < 300; i++) {
        usleep(10000);
        double d[3];
        XrSpaceLocationFlags f = locate(&a, now_xr(), d);
        if (!(f & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT)) continue;
        total++;
        if ((f & TRACKED_BITS) == TRACKED_BITS) tracked++;
        else if ((f & TRACKED_BITS) == 0) untracked_valid++;
        else fail_msg("orientation and position tracked bits disagree: 0x%llx", (unsigned long long)f);
    }
    print_message("blinks: %d located, %d tracked, %d untracked (blink)\n", total, tracked, untracked_valid);
    assert_true(tracked > 0);
    assert_true(untracked_valid > 0); /* 1 blink a second over 3 s: some instants are inside one */
    app_close(&a);
}

static void no_gaze_source_no_eye_gaze(void **state)
{
    (void)state;
    app a;
    app_open(&a, NULL);
    assert_false(a.supports_gaze);
    double d[3];
    XrSpaceLocationFlags f = locate(&a, now_xr(), d);
    assert_int_equal(f & ALL_BITS, 0);
    app_close(&a);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s MANIFEST\n", argv[0]);
        return 2;
    }
    g_manifest = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fixed_gaze_comes_back_as_the_same_pose),
        cmocka_unit_test(sim_gaze_is_predicted_to_the_requested_time),
        cmocka_unit_test(sim_blinks_clear_the_tracked_bits),
        cmocka_unit_test(no_gaze_source_no_eye_gaze),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
