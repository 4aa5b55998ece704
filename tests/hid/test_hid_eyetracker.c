/* @brief Page-0x12 decoding: tracking data into head-frame rays, INT32_MAX as "no data", status/configuration/control
 * reports, and malformed reports (short, wrong ID). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_hid_descriptor.h"
#include "fv_hid_eyetracker.h"
#include "fv_test.h"
#include "hid_test_util.h"

typedef struct ctx {
    fv_hid_descriptor desc;
    fv_hid_eyetracker_map map;
    fv_hid_screen_config screen;
} ctx;

static int setup_file(void **state, const char *file)
{
    ctx *c = calloc(1, sizeof *c);
    uint8_t bytes[1024];
    size_t n = hid_test_load_hex(file, bytes, sizeof bytes);
    if (fv_hid_descriptor_parse(bytes, n, &c->desc) != FV_OK) return -1;
    if (fv_hid_eyetracker_map_init(&c->desc, NULL, &c->map) != FV_OK) return -1;
    fv_hid_screen_config_defaults(&c->screen);
    c->screen.width_mm = 527.0f;
    c->screen.height_mm = 296.0f;
    *state = c;
    return 0;
}
static int setup_gazehid(void **state) { return setup_file(state, "ms-gazehid-vhidmini-eye-tracker.rdesc.hex"); }
static int setup_dmf(void **state) { return setup_file(state, "ms-dmf-virtualeyegaze.rdesc.hex"); }
static int teardown(void **state)
{
    free(*state);
    return 0;
}

static void assert_near(double a, double b, double tol)
{
    if (!(fabs(a - b) <= tol)) fail_msg("%.9g is not within %.3g of %.9g", a, tol, b);
}

static void tracking_report_becomes_head_frame_rays(void **state)
{
    ctx *c = *state;
    uint8_t rep[128];
    size_t n = hid_test_synthetic("gazehid_input_0x10_valid_t1", rep, sizeof rep);
    assert_int_equal(n, 65);
    fv_gaze_sample s;
    assert_int_equal(fv_hid_eyetracker_decode_tracking(&c->desc, &c->map, &c->screen, rep, n, &s), FV_OK);
    assert_int_equal(s.t_device_ns, INT64_C(1000000000)); /* 1 000 000 µs */
    assert_true(s.flags & FV_GAZE_SCREEN_POINT_VALID);
    assert_near(s.screen_point_mm.x, 263.5, 1e-4);
    assert_near(s.screen_point_mm.y, 148.25, 1e-4);
    /* Left eye at (-31, 12, 620) mm in the tracker frame; the screen centre 650 mm ahead of the head */
    assert_true(s.eye[FV_EYE_LEFT].flags & FV_EYE_ORIGIN_VALID);
    assert_near(s.eye[FV_EYE_LEFT].origin_mm.x, -31.0, 1e-4);
    assert_near(s.eye[FV_EYE_LEFT].origin_mm.y, 12.0, 1e-4);
    assert_near(s.eye[FV_EYE_LEFT].origin_mm.z, -30.0, 1e-3);
    /* Gaze point (263.5, 148.25) is (0, -0.25) from the centre of a 527 x 296 mm screen */
    double dx = 31.0, dy = -12.25, dz = -620.0, len = sqrt(dx * dx + dy * dy + dz * dz);
    assert_true(s.eye[FV_EYE_LEFT].flags & FV_EYE_DIRECTION_VALID);
    assert_near(s.eye[FV_EYE_LEFT].direction.x, dx / len, 1e-5);
    assert_near(s.eye[FV_EYE_LEFT].direction.y, dy / len, 1e-5);
    assert_near(s.eye[FV_EYE_LEFT].direction.z, dz / len, 1e-5);
    assert_near(s.eye[FV_EYE_RIGHT].direction.x, -dx / len, 1e-5);
    assert_true(s.combined.flags & FV_EYE_DIRECTION_VALID);
    assert_near(s.combined.direction.x, 0.0, 1e-6);
    /* No pupil in Microsoft's descriptor, no head pose in GazeHid's: invalid, NaN */
    assert_false(s.eye[0].flags & FV_EYE_PUPIL_VALID);
    assert_true(isnan(s.eye[0].pupil_mm));
    assert_false(s.flags & FV_GAZE_HEAD_VALID);
    assert_true(isnan(s.head_pos_mm.x));

    /* The next report: 8333 µs later */
    n = hid_test_synthetic("gazehid_input_0x10_valid_t2_plus_8333us", rep, sizeof rep);
    fv_gaze_sample s2;
    assert_int_equal(fv_hid_eyetracker_decode_tracking(&c->desc, &c->map, &c->screen, rep, n, &s2), FV_OK);
    assert_int_equal(s2.t_device_ns - s.t_device_ns, INT64_C(8333000));
}

static void int32_max_marks_the_field_invalid(void **state)
{
    ctx *c = *state;
    uint8_t rep[128];
    size_t n = hid_test_synthetic("gazehid_input_0x10_gaze_invalid_int32max", rep, sizeof rep);
    fv_gaze_sample s;
    assert_int_equal(fv_hid_eyetracker_decode_tracking(&c->desc, &c->map, &c->screen, rep, n, &s), FV_OK);
    assert_false(s.flags & FV_GAZE_SCREEN_POINT_VALID);
    assert_true(isnan(s.screen_point_mm.x));
    for (int e = 0; e < 2; e++) {
        assert_true(s.eye[e].flags & FV_EYE_ORIGIN_VALID); /* eyes still seen */
        assert_false(s.eye[e].flags & FV_EYE_DIRECTION_VALID);
        assert_true(isnan(s.eye[e].direction.x));
    }
    assert_false(s.combined.flags & FV_EYE_DIRECTION_VALID);
}

static void unknown_screen_size_leaves_rays_invalid_but_finite(void **state)
{
    ctx *c = *state;
    c->screen.width_mm = 0.0f;
    uint8_t rep[128];
    size_t n = hid_test_synthetic("gazehid_input_0x10_valid_t1", rep, sizeof rep);
    fv_gaze_sample s;
    assert_int_equal(fv_hid_eyetracker_decode_tracking(&c->desc, &c->map, &c->screen, rep, n, &s), FV_OK);
    assert_true(s.flags & FV_GAZE_SCREEN_POINT_VALID);
    assert_false(s.eye[0].flags & FV_EYE_DIRECTION_VALID);
    /* extremes: every position at the logical limits stays finite */
    for (int i = 9; i < 41; i += 4) {
        rep[i] = 0x80; rep[i + 1] = 0x84; rep[i + 2] = 0x1e; rep[i + 3] = 0x00; /* +2 000 000 */
    }
    c->screen.width_mm = 1e-3f;
    c->screen.height_mm = 1e-3f;
    assert_int_equal(fv_hid_eyetracker_decode_tracking(&c->desc, &c->map, &c->screen, rep, n, &s), FV_OK);
    for (int e = 0; e < 2; e++) {
        if (s.eye[e].flags & FV_EYE_DIRECTION_VALID) assert_true(fv_v3_isfinite(s.eye[e].direction));
        assert_true(fv_v3_isfinite(s.eye[e].origin_mm));
    }
}

static void dmf_head_pose_int32_max_is_invalid(void **state)
{
    ctx *c = *state;
    uint8_t rep[128];
    size_t n = hid_test_synthetic("dmf_input_0x10_head_unavailable_int32max", rep, sizeof rep);
    fv_gaze_sample s;
    assert_int_equal(fv_hid_eyetracker_decode_tracking(&c->desc, &c->map, &c->screen, rep, n, &s), FV_OK);
    assert_true(s.flags & FV_GAZE_SCREEN_POINT_VALID);
    assert_false(s.flags & FV_GAZE_HEAD_VALID);
    assert_true(isnan(s.head_dir.x));
    /* Head in range: position and a direction facing the screen */
    memset(rep + 41, 0, 24);
    rep[41 + 8] = 0x20; /* z = 0x20 00 00 00? little endian: byte 0 → 32 µm */
    assert_int_equal(fv_hid_eyetracker_decode_tracking(&c->desc, &c->map, &c->screen, rep, n, &s), FV_OK);
    assert_true(s.flags & FV_GAZE_HEAD_VALID);
    assert_near(s.head_pos_mm.z, 0.032, 1e-6);
    assert_near(s.head_dir.z, -1.0, 1e-6);
}

static void status_configuration_and_control_reports(void **state)
{
    ctx *c = *state;
    uint8_t rep[64], want[8];
    size_t n = hid_test_synthetic("status_input_0x13_ready_100hz", rep, sizeof rep);
    fv_hid_status st;
    assert_int_equal(fv_hid_eyetracker_decode_status(&c->desc, &c->map, FV_HID_REPORT_INPUT, rep, n, &st), FV_OK);
    assert_int_equal(st.configuration_status, FV_HID_STATUS_READY);
    assert_near(st.sampling_frequency_hz, 100.0, 0.0);
    /* The same ID is also a feature report */
    n = hid_test_synthetic("status_input_0x13_user_calibration_needed_120hz", rep, sizeof rep);
    assert_int_equal(fv_hid_eyetracker_decode_status(&c->desc, &c->map, FV_HID_REPORT_FEATURE, rep, n, &st), FV_OK);
    assert_int_equal(st.configuration_status, FV_HID_STATUS_USER_CALIBRATION_NEEDED);
    assert_near(st.sampling_frequency_hz, 120.0, 0.0);

    n = hid_test_synthetic("configuration_feature_0x12_527x296mm_display", rep, sizeof rep);
    assert_int_equal(n, 19);
    fv_hid_configuration cfg;
    assert_int_equal(fv_hid_eyetracker_decode_configuration(&c->desc, &c->map, rep, n, &cfg), FV_OK);
    assert_near(cfg.calibrated_width_mm, 527.0, 1e-9);
    assert_near(cfg.calibrated_height_mm, 296.0, 1e-9);
    assert_int_equal(cfg.display_manufacturer, 0x10AC);
    assert_int_equal(cfg.display_serial, 1);

    uint8_t buf[8];
    size_t len;
    size_t wn = hid_test_synthetic("control_feature_0x14_set_enable_gaze_point", want, sizeof want);
    assert_int_equal(fv_hid_eyetracker_encode_mode_request(&c->desc, &c->map, FV_HID_MODE_GAZE_POINT, buf, sizeof buf,
                                                           &len),
                     FV_OK);
    assert_int_equal(len, wn);
    assert_memory_equal(buf, want, wn);
    wn = hid_test_synthetic("control_feature_0x14_set_enable_all_modes", want, sizeof want);
    assert_int_equal(fv_hid_eyetracker_encode_mode_request(&c->desc, &c->map, FV_HID_MODE_ALL, buf, sizeof buf, &len),
                     FV_OK);
    assert_memory_equal(buf, want, wn);
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_eyetracker_encode_mode_request(&c->desc, &c->map, 8, buf, sizeof buf, &len), FV_ERR_RANGE);
    fv_test_log_capture_end();
    fv_assert_log_contains("outside the declared range 0..7");
}

static void malformed_reports_are_protocol_errors(void **state)
{
    ctx *c = *state;
    uint8_t rep[128];
    size_t n = hid_test_synthetic("gazehid_input_0x10_valid_t1", rep, sizeof rep);
    fv_gaze_sample s;
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_eyetracker_decode_tracking(&c->desc, &c->map, &c->screen, rep, n - 1, &s),
                     FV_ERR_PROTOCOL);
    fv_test_log_capture_end();
    fv_assert_log_contains("input report 0x10 is 64 bytes, the descriptor declares 65");

    rep[0] = 0x99;
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_eyetracker_decode_tracking(&c->desc, &c->map, &c->screen, rep, n, &s), FV_ERR_PROTOCOL);
    fv_test_log_capture_end();
    fv_assert_log_contains("ID 0x99");

    rep[0] = 0x13; /* a status input is not tracking data */
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_eyetracker_decode_tracking(&c->desc, &c->map, &c->screen, rep, 4, &s), FV_ERR_PROTOCOL);
    fv_test_log_capture_end();
    fv_assert_log_contains("not Tracking Data");

    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_eyetracker_decode_tracking(&c->desc, &c->map, &c->screen, rep, 0, &s), FV_ERR_PROTOCOL);
    fv_test_log_capture_end();

    uint8_t caps[22] = {0x12};
    fv_hid_capabilities cp;
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_eyetracker_decode_capabilities(&c->desc, &c->map, caps, sizeof caps, &cp),
                     FV_ERR_PROTOCOL);
    fv_test_log_capture_end();
    fv_assert_log_contains("not the Capabilities report (0x11)");
}

static void quirks_table_knows_the_virtual_trackers(void **state)
{
    (void)state;
    const fv_hid_quirk *q = fv_hid_quirk_find(0x1209, 0x0001);
    assert_non_null(q);
    assert_int_equal(q->pupil_usage[0], FV_HID_FOVEA_USAGE_PUPIL_LEFT);
    assert_non_null(fv_hid_quirk_find(0xDEED, 0xFEED));
    assert_null(fv_hid_quirk_find(0x046D, 0xC52B));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(tracking_report_becomes_head_frame_rays, setup_gazehid, teardown),
        cmocka_unit_test_setup_teardown(int32_max_marks_the_field_invalid, setup_gazehid, teardown),
        cmocka_unit_test_setup_teardown(unknown_screen_size_leaves_rays_invalid_but_finite, setup_gazehid, teardown),
        cmocka_unit_test_setup_teardown(dmf_head_pose_int32_max_is_invalid, setup_dmf, teardown),
        cmocka_unit_test_setup_teardown(status_configuration_and_control_reports, setup_gazehid, teardown),
        cmocka_unit_test_setup_teardown(malformed_reports_are_protocol_errors, setup_gazehid, teardown),
        cmocka_unit_test(quirks_table_knows_the_virtual_trackers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
