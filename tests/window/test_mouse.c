/* @brief drivers/mouse: the cursor over an eye's image becomes the gaze point of both eyes — the eye under the cursor
 * looks exactly through the cursor's pixel, the other eye at the same point at the vergence distance — finite for any
 * input (NaN or out-of-image cursors, absurd vergence and IPD); the URI's keys and their errors; and the device: no
 * window, no open (a clear error), samples that follow the pointer at the asked rate, lost when the window goes. */
#include <math.h>
#include <string.h>

#include "fovea/fv_frame_input.h"
#include "fv_clock.h"
#include "fv_mouse_driver.h"
#include "fv_test.h"

/* The HMD default views of a 720x800 eye, as the window's owner hands them over. */
static fv_mouse_views views(void)
{
    fv_eye_view ev[2];
    fv_head_pose head = {.orientation = fv_quat_identity(), .ipd_mm = 63.0f};
    fv_eye_views_build(&head, 0.05f, 100.0f, 720, 800, ev);
    fv_mouse_views v = {.ipd_mm = 63.0f};
    for (int e = 0; e < 2; e++) {
        v.tan_left[e] = ev[e].tan_left;
        v.tan_right[e] = ev[e].tan_right;
        v.tan_up[e] = ev[e].tan_up;
        v.tan_down[e] = ev[e].tan_down;
    }
    return v;
}

static void assert_unit_finite(fv_vec3 d)
{
    assert_true(fv_v3_isfinite(d));
    assert_true(fabsf(fv_v3_len(d) - 1.0f) < 1e-5f);
}

static void the_eye_under_the_cursor_looks_through_its_pixel_and_both_meet_at_the_vergence_point(void **state)
{
    (void)state;
    fv_mouse_views v = views();
    const float pts[4][2] = {{0.5f, 0.5f}, {0.1f, 0.2f}, {0.9f, 0.95f}, {0.0f, 1.0f}};
    for (int eye = 0; eye < 2; eye++)
        for (int k = 0; k < 4; k++) {
            fv_gaze_sample s;
            fv_mouse_gaze(&v, eye, pts[k][0], pts[k][1], 1.5, &s);
            const fv_eye_sample *me = &s.eye[eye], *other = &s.eye[1 - eye];
            assert_unit_finite(me->direction);
            assert_unit_finite(other->direction);
            assert_true((me->flags & FV_EYE_DIRECTION_VALID) && !(me->flags & FV_EYE_PUPIL_VALID));
            /* back through the projection: the cursor's uv */
            double tx = me->direction.x / -me->direction.z, ty = me->direction.y / -me->direction.z;
            double u = (tx - v.tan_left[eye]) / (v.tan_right[eye] - v.tan_left[eye]);
            double vv = (v.tan_up[eye] - ty) / (v.tan_up[eye] - v.tan_down[eye]);
            assert_true(fabs(u - pts[k][0]) < 1e-4 && fabs(vv - pts[k][1]) < 1e-4);
            /* the fixation point: where the cursor's eye ray reaches z = -1500 mm; the other eye looks at it */
            double t = 1500.0 / -me->direction.z;
            double P[3] = {me->origin_mm.x + t * me->direction.x, me->origin_mm.y + t * me->direction.y, -1500.0};
            double q[3] = {P[0] - other->origin_mm.x, P[1] - other->origin_mm.y, P[2] - other->origin_mm.z};
            double qn = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
            double dot = (q[0] * other->direction.x + q[1] * other->direction.y + q[2] * other->direction.z) / qn;
            assert_true(dot > 1.0 - 1e-9 * 1000.0); /* within ~0.003 deg */
            assert_true(fabsf(me->origin_mm.x - (eye == 0 ? -31.5f : 31.5f)) < 1e-4f);
        }
}

static void any_input_gives_a_finite_unit_gaze(void **state)
{
    (void)state;
    fv_mouse_views v = views();
    const float us[] = {NAN, INFINITY, -INFINITY, -5.0f, 5.0f, 0.5f};
    const double verg[] = {NAN, 0.0, -1.0, 0.05, 1000.0, 1e30};
    for (size_t i = 0; i < sizeof us / sizeof us[0]; i++)
        for (size_t k = 0; k < sizeof verg / sizeof verg[0]; k++)
            for (int eye = -1; eye <= 2; eye++) {
                fv_gaze_sample s;
                fv_mouse_gaze(&v, eye, us[i], us[(i + 3) % 6], verg[k], &s);
                for (int e = 0; e < 2; e++) assert_unit_finite(s.eye[e].direction);
                assert_unit_finite(s.combined.direction);
            }
    /* absurd views and IPDs */
    fv_mouse_views bad = v;
    bad.ipd_mm = NAN;
    bad.tan_left[0] = NAN;
    bad.tan_up[1] = INFINITY;
    fv_gaze_sample s;
    for (int eye = 0; eye < 2; eye++) {
        fv_mouse_gaze(&bad, eye, 0.3f, 0.7f, 1.5, &s);
        assert_unit_finite(s.eye[0].direction);
        assert_unit_finite(s.eye[1].direction);
    }
    bad.ipd_mm = 1e9f;
    fv_mouse_gaze(&bad, 0, 0.3f, 0.7f, 1.5, &s);
    assert_unit_finite(s.eye[1].direction);
    assert_true(fabsf(s.eye[1].origin_mm.x - 31.5f) < 1e-4f); /* refused: the default IPD */
    fv_mouse_gaze(NULL, 0, 0.5f, 0.5f, 1.5, &s);
    assert_unit_finite(s.eye[0].direction);
    /* the cursor at the image's centre at 1000 m: the two eyes are nearly parallel */
    fv_mouse_gaze(&v, 0, 0.5f, 0.5f, 1000.0, &s);
    assert_true(fv_v3_dot(s.eye[0].direction, s.eye[1].direction) > 0.9999999f);
}

static void uri_keys_and_their_errors(void **state)
{
    (void)state;
    fv_mouse_desc d;
    assert_int_equal(fv_mouse_parse_uri("mouse:", &d), FV_OK);
    assert_true(d.vergence_m == 1.5 && d.rate_hz == 250.0);
    assert_int_equal(fv_mouse_parse_uri("mouse:vergence_m=2.5,rate_hz=100", &d), FV_OK);
    assert_true(d.vergence_m == 2.5 && d.rate_hz == 100.0);
    fv_test_log_capture_begin();
    assert_int_equal(fv_mouse_parse_uri("mouse:vergence_m=0", &d), FV_ERR_RANGE);
    fv_assert_log_contains("vergence_m=0 is outside 0.05..1000 m");
    assert_int_equal(fv_mouse_parse_uri("mouse:rate_hz=5000", &d), FV_ERR_RANGE);
    assert_int_equal(fv_mouse_parse_uri("mouse:vergence_m=abc", &d), FV_ERR_PARSE);
    assert_int_equal(fv_mouse_parse_uri("mouse:vergence_m=nan", &d), FV_ERR_PARSE);
    assert_int_equal(fv_mouse_parse_uri("mouse:zoom=2", &d), FV_ERR_PARSE);
    fv_assert_log_contains("unknown key 'zoom'");
    assert_int_equal(fv_mouse_parse_uri("mouse:vergence_m", &d), FV_ERR_PARSE);
    assert_int_equal(fv_mouse_parse_uri("mouse:vergence_m=1,vergence_m=2", &d), FV_ERR_PARSE);
    fv_assert_log_contains("given twice");
    assert_int_equal(fv_mouse_parse_uri("sim:seed=1", &d), FV_ERR_PARSE);
    char longer[400];
    memset(longer, 'a', sizeof longer);
    memcpy(longer, "mouse:", 6);
    longer[sizeof longer - 1] = '\0';
    assert_int_equal(fv_mouse_parse_uri(longer, &d), FV_ERR_RANGE);
    fv_test_log_capture_end();
}

static void the_device_needs_a_window_follows_the_pointer_and_is_lost_with_it(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 10 * FV_NS_PER_S);
    fv_device_open_desc od = {.clock = &clk};
    fv_device *dev = NULL;
    fv_mouse_pointer_detach();
    fv_test_log_capture_begin();
    assert_int_equal(fv_mouse_driver.open("mouse:", &od, &dev), FV_ERR_UNSUPPORTED);
    fv_assert_log_contains("--present window");
    fv_test_log_capture_end();
    assert_null(dev);
    fv_mouse_views v = views();
    fv_mouse_pointer_attach(&v);
    assert_int_equal(fv_mouse_driver.open("mouse:rate_hz=100", &od, &dev), FV_OK);
    fv_gaze_sample s[4];
    size_t n = 0;
    /* before any cursor: straight ahead */
    assert_int_equal(fv_device_read(dev, s, 4, &n, 100), FV_OK);
    assert_int_equal(n, 1);
    assert_true(s[0].combined.direction.z < -0.999f);
    assert_true(s[0].flags & FV_GAZE_HOST_TIME_VALID);
    int64_t t_first = s[0].t_host_ns;
    fv_mouse_pointer_move(0, 0.2f, 0.3f, fv_clock_now_ns(&clk));
    assert_int_equal(fv_device_read(dev, s, 4, &n, 100), FV_OK);
    assert_int_equal(n, 1);
    assert_int_equal(s[0].t_host_ns - t_first, 10 * FV_NS_PER_MS); /* 100 Hz */
    fv_gaze_sample want;
    fv_mouse_gaze(&v, 0, 0.2f, 0.3f, 1.5, &want);
    assert_true(fv_v3_dot(s[0].eye[0].direction, want.eye[0].direction) > 0.999999f);
    /* a poll with no time to wait: nothing yet */
    assert_int_equal(fv_device_read(dev, s, 4, &n, 0), FV_TIMEOUT);
    assert_int_equal(n, 0);
    fv_mouse_pointer_detach();
    fv_test_log_capture_begin();
    assert_int_equal(fv_device_read(dev, s, 4, &n, 100), FV_ERR_DEVICE_LOST);
    fv_test_log_capture_end();
    fv_device_close(&dev);
    /* listed like the other drivers */
    fv_device_info info[2];
    size_t count = 0;
    assert_int_equal(fv_mouse_driver.probe(info, 2, &count), FV_OK);
    assert_int_equal(count, 1);
    fv_assert_contains(info[0].uri, "mouse:");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_eye_under_the_cursor_looks_through_its_pixel_and_both_meet_at_the_vergence_point),
        cmocka_unit_test(any_input_gives_a_finite_unit_gaze),
        cmocka_unit_test(uri_keys_and_their_errors),
        cmocka_unit_test(the_device_needs_a_window_follows_the_pointer_and_is_lost_with_it),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
