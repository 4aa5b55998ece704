/* @brief An OpenXR app of our own reading eye gaze from fovea's runtime through the OpenXR loader (XR_RUNTIME_JSON,
 * the core-validation layer on): XR_EXT_eye_gaze_interaction in a headless session (XR_MND_headless), the gaze pose
 * action bound to /user/eyes_ext/input/gaze_ext/pose, its action space located against VIEW.
 *  - fixed: the pose comes back as the fixed direction, tracked, at any requested time;
 *  - sim: the pose is fovea's prediction to the requested time (later times are further along the eye's motion);
 *    blinks clear the TRACKED bits;
 *  - trace: a real recording replayed: gaze at each frame's predicted display time of a headless frame loop;
 *  - no FOVEA_XR_GAZE: supportsEyeGazeInteraction is false and the action space is not located;
 *  - a driver plugged into the one driver list (FOVEA_DRIVERS: the test-only probe plug-in) gives eye gaze as
 *    `fovea run --gaze` sees it (tests/runtime/test_cli_app.c runs the same plug-in through `fovea run`).
 * argv[1] = the runtime manifest, argv[2] = the probe plug-in. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <openxr/openxr.h>

#include "fv_test.h"
#include "xr_app.h"

static const char *g_manifest;
static const char *g_plugin;

#define CHECK_XR(call) assert_int_equal((int)(call), (int)XR_SUCCESS)
#define ALL_BITS XR_APP_ALL_BITS
#define TRACKED_BITS XR_APP_TRACKED_BITS

static void fixed_gaze_comes_back_as_the_same_pose(void **state)
{
    (void)state;
    xr_app a;
    xr_app_open(&a, g_manifest, "fixed:yaw_deg=10,pitch_deg=-5,rate_hz=250");
    assert_true(a.supports_gaze);
    XrActionStateGetInfo gi = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = a.gaze};
    /* the pipeline needs a few samples: wait until the pose is tracked */
    double dir[3];
    XrSpaceLocationFlags f = 0;
    for (int i = 0; i < 200 && (f & ALL_BITS) != ALL_BITS; i++) {
        usleep(10000);
        f = xr_app_locate(&a, xr_app_now(), dir);
    }
    assert_int_equal(f & ALL_BITS, ALL_BITS);
    XrActionStatePose ps = {.type = XR_TYPE_ACTION_STATE_POSE};
    CHECK_XR(xrGetActionStatePose(a.session, &gi, &ps));
    assert_true(ps.isActive);
    /* yaw right-positive, pitch up-positive, (0, 0) = -z */
    double y = 10 * M_PI / 180, p = -5 * M_PI / 180;
    double want[3] = {sin(y) * cos(p), sin(p), -cos(y) * cos(p)};
    for (int k = 0; k < 3; k++) {
        XrTime t = xr_app_now() + (XrTime)k * 40000000; /* now, +40 ms, +80 ms: a fixed gaze does not move */
        f = xr_app_locate(&a, t, dir);
        double err = xr_app_angle_deg(dir, want);
        print_message("fixed: t+%d ms: error %.5f deg, flags 0x%llx\n", 40 * k, err, (unsigned long long)f);
        assert_true(err < 0.01);
        assert_int_equal(f & ALL_BITS, ALL_BITS);
    }
    xr_app_close(&a);
}

static void sim_gaze_is_predicted_to_the_requested_time(void **state)
{
    (void)state;
    xr_app a;
    /* smooth pursuits after every gaze shift, no blinks, little noise: the eye keeps moving */
    xr_app_open(&a, g_manifest, "sim:seed=7,rate_hz=250,pursuit_prob=1,blink_per_min=0,dropout=0,eye_loss=0,precision_deg=0.02");
    assert_true(a.supports_gaze);
    int moving = 0, consistent = 0, samples = 0;
    for (int i = 0; i < 150; i++) {
        usleep(10000);
        XrTime t = xr_app_now();
        double d0[3], d1[3], d2[3];
        XrSpaceLocationFlags f0 = xr_app_locate(&a, t, d0);
        XrSpaceLocationFlags f1 = xr_app_locate(&a, t + 25000000, d1);
        XrSpaceLocationFlags f2 = xr_app_locate(&a, t + 50000000, d2);
        if ((f0 & f1 & f2 & ALL_BITS) != ALL_BITS) continue;
        samples++;
        double a01 = xr_app_angle_deg(d0, d1), a02 = xr_app_angle_deg(d0, d2);
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
    xr_app_close(&a);
}

static void sim_blinks_clear_the_tracked_bits(void **state)
{
    (void)state;
    xr_app a;
    xr_app_open(&a, g_manifest, "sim:seed=11,rate_hz=250,blink_per_min=60");
    int tracked = 0, untracked_valid = 0, total = 0;
    for (int i = 0; i < 300; i++) {
        usleep(10000);
        double d[3];
        XrSpaceLocationFlags f = xr_app_locate(&a, xr_app_now(), d);
        if (!(f & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT)) continue;
        total++;
        if ((f & TRACKED_BITS) == TRACKED_BITS) tracked++;
        else if ((f & TRACKED_BITS) == 0) untracked_valid++;
        else fail_msg("orientation and position tracked bits disagree: 0x%llx", (unsigned long long)f);
    }
    print_message("blinks: %d located, %d tracked, %d untracked (blink)\n", total, tracked, untracked_valid);
    assert_true(tracked > 0);
    assert_true(untracked_valid > 0); /* 1 blink a second over 3 s: some instants are inside one */
    xr_app_close(&a);
}

static void replayed_recording_gives_predicted_gaze_per_frame(void **state)
{
    (void)state;
    /* a real recording (HTC Vive Pro Eye, SRanipal) replayed by the trace driver; the app locates the gaze at each
     * frame's predicted display time, as a foveated renderer would */
    char uri[1200];
    snprintf(uri, sizeof uri, "trace:%s", fv_test_data("gaze/htc_vive_pro_eye_sranipal/TESTNA01_2D_Fist3.csv"));
    xr_app a;
    xr_app_open(&a, g_manifest, uri);
    assert_true(a.supports_gaze);
    int tracked = 0, frames = 90;
    double first[3] = {0, 0, 0}, spread = 0;
    XrTime prev = 0;
    for (int f = 0; f < frames; f++) {
        XrTime t = xr_app_frame(&a);
        assert_true(t > prev); /* predicted display times advance */
        prev = t;
        double d[3];
        XrSpaceLocationFlags fl = xr_app_locate(&a, t, d);
        if ((fl & ALL_BITS) != ALL_BITS) continue;
        for (int k = 0; k < 3; k++) assert_true(isfinite(d[k]));
        if (!tracked) memcpy(first, d, sizeof first);
        else spread = fmax(spread, xr_app_angle_deg(first, d));
        tracked++;
    }
    print_message("trace: %d of %d frames tracked, gaze moved up to %.2f deg\n", tracked, frames, spread);
    assert_true(tracked > frames / 2);
    assert_true(spread > 0.1); /* the recorded eye moves */
    xr_app_close(&a);
}

static void no_gaze_source_no_eye_gaze(void **state)
{
    (void)state;
    xr_app a;
    xr_app_open(&a, g_manifest, "");
    assert_false(a.supports_gaze);
    double d[3];
    XrSpaceLocationFlags f = xr_app_locate(&a, xr_app_now(), d);
    assert_int_equal(f & ALL_BITS, 0);
    xr_app_close(&a);
}

/* Rotate v by the unit quaternion q. */
static void rotate(const XrQuaternionf q, const double v[3], double out[3])
{
    double x = q.x, y = q.y, z = q.z, w = q.w;
    double t[3] = {2 * (y * v[2] - z * v[1]), 2 * (z * v[0] - x * v[2]), 2 * (x * v[1] - y * v[0])};
    out[0] = v[0] + w * t[0] + (y * t[2] - z * t[1]);
    out[1] = v[1] + w * t[1] + (z * t[0] - x * t[2]);
    out[2] = v[2] + w * t[2] + (x * t[1] - y * t[0]);
}

/* A recording whose eyes hold yaw 10 / pitch 5 in the head while the head turns 0 -> 60 degrees (issue 23): the
 * runtime's head (VIEW in LOCAL) follows the recorded head, the gaze located in VIEW stays the head-frame gaze, and
 * the gaze located in LOCAL is the head pose times it. */
static void a_recorded_head_moves_the_views_not_the_gaze_in_them(void **state)
{
    (void)state;
    size_t cap = 1 << 20, n = 0;
    char *trace = malloc(cap);
    n += (size_t)snprintf(trace, cap, "fovea-trace 1\n# rate_hz: 120\nt_device_ns,flags,seq,c_flags,c_dir_x,c_dir_y,"
                                      "c_dir_z,head_x_mm,head_y_mm,head_z_mm,head_dir_x,head_dir_y,head_dir_z\n");
    double y = 10 * M_PI / 180, p = 5 * M_PI / 180;
    const double want[3] = {sin(y) * cos(p), sin(p), -cos(y) * cos(p)};
    for (int i = 0; i < 1200; i++) {
        double hy = 60.0 * i / 1200.0 * M_PI / 180.0;
        n += (size_t)snprintf(trace + n, cap - n, "%lld,2,%d,2,%.9f,%.9f,%.9f,0,0,0,%.9f,0,%.9f\n",
                              (long long)i * 8333333LL, i, want[0], want[1], want[2], sin(hy), -cos(hy));
    }
    const char *path = fv_test_write_file("xr_head.trace", trace, n);
    free(trace);
    char uri[1200];
    snprintf(uri, sizeof uri, "trace:%s?speed=4", path);
    xr_app a;
    xr_app_open(&a, g_manifest, uri);
    assert_true(a.supports_gaze);
    XrReferenceSpaceCreateInfo rs = {.type = XR_TYPE_REFERENCE_SPACE_CREATE_INFO,
                                     .referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL,
                                     .poseInReferenceSpace = {{0, 0, 0, 1}, {0, 0, 0}}};
    XrSpace local;
    CHECK_XR(xrCreateReferenceSpace(a.session, &rs, &local));
    double first_yaw = NAN, last_yaw = NAN, worst_view = 0, worst_local = 0;
    int checked = 0;
    for (int i = 0; i < 250 && checked < 120; i++) {
        usleep(10000);
        XrTime t = xr_app_now();
        double dir[3];
        XrSpaceLocationFlags f = xr_app_locate(&a, t, dir);
        if ((f & ALL_BITS) != ALL_BITS) continue;
        XrSpaceLocation head = {.type = XR_TYPE_SPACE_LOCATION}, gaze = {.type = XR_TYPE_SPACE_LOCATION};
        CHECK_XR(xrLocateSpace(a.view_space, local, t, &head));
        CHECK_XR(xrLocateSpace(a.gaze_space, local, t, &gaze));
        /* the head's forward in LOCAL: its yaw (right positive) */
        const double fwd[3] = {0, 0, -1};
        double hf[3], expect[3], got[3];
        rotate(head.pose.orientation, fwd, hf);
        double hyaw = atan2(hf[0], -hf[2]) * 180 / M_PI;
        if (isnan(first_yaw)) first_yaw = hyaw;
        last_yaw = hyaw;
        rotate(head.pose.orientation, dir, expect); /* head pose x the gaze in VIEW */
        rotate(gaze.pose.orientation, fwd, got);
        double ev = xr_app_angle_deg(dir, want), el = xr_app_angle_deg(got, expect);
        worst_view = ev > worst_view ? ev : worst_view;
        worst_local = el > worst_local ? el : worst_local;
        checked++;
    }
    print_message("recorded head: yaw %.1f -> %.1f deg over %d instants; gaze in VIEW off by at most %.4f deg, in "
                  "LOCAL off the head pose x VIEW gaze by %.4f deg\n", first_yaw, last_yaw, checked, worst_view,
                  worst_local);
    assert_true(checked > 50);
    assert_true(fabs(last_yaw - first_yaw) > 10.0); /* the head moved (it stood still before the head followed) */
    assert_true(worst_view < 0.05);                 /* the gaze in the views never turned with the head */
    assert_true(worst_local < 0.05);
    CHECK_XR(xrDestroySpace(local));
    xr_app_close(&a);
}

/* The application layer's one driver list: a plug-in's scheme opens in the OpenXR runtime as in `fovea run`. */
static void plugged_in_driver_gives_eye_gaze(void **state)
{
    (void)state;
    xr_app a;
    xr_app_open(&a, g_manifest, "probe:yaw_deg=-8,pitch_deg=3,rate_hz=250");
    assert_true(a.supports_gaze);
    double dir[3];
    XrSpaceLocationFlags f = 0;
    for (int i = 0; i < 200 && (f & ALL_BITS) != ALL_BITS; i++) {
        usleep(10000);
        f = xr_app_locate(&a, xr_app_now(), dir);
    }
    assert_int_equal(f & ALL_BITS, ALL_BITS);
    double y = -8 * M_PI / 180, p = 3 * M_PI / 180;
    double want[3] = {sin(y) * cos(p), sin(p), -cos(y) * cos(p)};
    double err = xr_app_angle_deg(dir, want);
    print_message("probe plug-in: error %.5f deg\n", err);
    assert_true(err < 0.01);
    xr_app_close(&a);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: %s MANIFEST PROBE_PLUGIN\n", argv[0]);
        return 2;
    }
    g_manifest = argv[1];
    g_plugin = argv[2];
    setenv("FOVEA_DRIVERS", g_plugin, 1); /* the runtime builds its driver list once, at its first use */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fixed_gaze_comes_back_as_the_same_pose),
        cmocka_unit_test(sim_gaze_is_predicted_to_the_requested_time),
        cmocka_unit_test(sim_blinks_clear_the_tracked_bits),
        cmocka_unit_test(replayed_recording_gives_predicted_gaze_per_frame),
        cmocka_unit_test(no_gaze_source_no_eye_gaze),
        cmocka_unit_test(a_recorded_head_moves_the_views_not_the_gaze_in_them),
        cmocka_unit_test(plugged_in_driver_gives_eye_gaze),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
