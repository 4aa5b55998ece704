/* @brief An OpenXR app of our own reading eye gaze from fovea's runtime through the OpenXR loader (XR_RUNTIME_JSON,
 * the core-validation layer on): XR_EXT_eye_gaze_interaction in a headless session (XR_MND_headless), the gaze pose
 * action bound to /user/eyes_ext/input/gaze_ext/pose, its action space located against VIEW.
 *  - fixed: the pose comes back as the fixed direction, tracked, at any requested time;
 *  - sim: the pose is fovea's prediction to the requested time (later times are further along the eye's motion);
 *    blinks clear the TRACKED bits;
 *  - trace: a real recording replayed: gaze at each frame's predicted display time of a headless frame loop;
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
#include "xr_app.h"

static const char *g_manifest;

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
        cmocka_unit_test(replayed_recording_gives_predicted_gaze_per_frame),
        cmocka_unit_test(no_gaze_source_no_eye_gaze),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
