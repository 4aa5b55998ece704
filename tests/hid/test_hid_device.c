/* @brief The hid device end to end: simulated eye → virtual HID tracker → fake transport → parser → decoder →
 * fv_gaze_sample, plus the open sequence (features, mode request, stale drain), timeout vs hang-up, malformed reports
 * in the stream, URIs, and a descriptor that is not an eye tracker. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_hid_device.h"
#include "fv_hid_driver.h"
#include "fv_sim_eye.h"
#include "fv_test.h"
#include "fv_vhid.h"
#include "hid_test_util.h"

static double angle_between(fv_vec3 a, fv_vec3 b)
{
    double d = fv_v3_dot(a, b) / (fv_v3_len(a) * fv_v3_len(b));
    return acos(d > 1.0 ? 1.0 : (d < -1.0 ? -1.0 : d));
}

static void simulated_eye_runs_end_to_end_through_the_virtual_tracker(void **state)
{
    (void)state;
    fv_vhid *v;
    assert_int_equal(fv_vhid_create(NULL, &v), FV_OK);
    fv_hid_transport *t;
    fv_hid_fake *fake;
    assert_int_equal(fv_vhid_transport_create(v, &t, &fake), FV_OK);

    fv_sim_eye_desc ed;
    fv_sim_eye_desc_defaults(&ed);
    ed.seed = 1;
    ed.rate_hz = 120;
    fv_sim_eye *eye;
    assert_int_equal(fv_sim_eye_create(&ed, &eye), FV_OK);

    /* Three reports are buffered before the host opens the device: stale. */
    uint8_t rep[128];
    size_t n;
    fv_gaze_sample s;
    fv_sim_truth truth;
    for (int i = 0; i < 3; i++) {
        assert_int_equal(fv_sim_eye_next(eye, &s, &truth), FV_OK);
        assert_int_equal(fv_vhid_encode_sample(v, &s, rep, sizeof rep, &n), FV_OK);
        assert_int_equal(fv_hid_fake_push_input(fake, rep, n), FV_OK);
    }
    fv_clock clock;
    fv_clock_sim_init(&clock, 5 * FV_NS_PER_S);
    fv_hid_device_desc dd = {.clock = &clock, .uri = "hid:vhid"};
    fv_device *dev;
    assert_int_equal(fv_hid_device_open_transport(t, &dd, &dev), FV_OK);

    /* The host wrote the Device Mode Request (all modes), read the features, drained the stale reports. */
    uint8_t last[8];
    size_t last_len;
    assert_int_equal(fv_hid_fake_feature_writes(fake, last, sizeof last, &last_len), 1);
    assert_int_equal(last_len, 2);
    assert_int_equal(last[0], 0x14);
    assert_int_equal(last[1], FV_HID_MODE_ALL);
    fv_hid_device_stats st;
    fv_hid_device_get_stats(dev, &st);
    assert_int_equal(st.drained_at_open, 3);
    assert_int_equal(st.tracker_quality, 1);
    assert_true(fabs(st.calibrated_width_mm - 527.0) < 1e-9);
    assert_true(dev->nominal_rate_hz == 120.0);

    /* 2 s of samples (blinks, saccades, one-eye losses included), read in chunks */
    enum { N = 240 };
    static fv_gaze_sample sent[N], got[N];
    for (int i = 0; i < N; i++) {
        assert_int_equal(fv_sim_eye_next(eye, &sent[i], &truth), FV_OK);
        assert_int_equal(fv_vhid_encode_sample(v, &sent[i], rep, sizeof rep, &n), FV_OK);
        assert_int_equal(fv_hid_fake_push_input(fake, rep, n), FV_OK);
    }
    size_t total = 0;
    while (total < N) {
        size_t count = 0;
        fv_clock_sim_advance(&clock, FV_NS_PER_MS);
        fv_result r = fv_device_read(dev, got + total, 32, &count, 10);
        assert_int_equal(r, FV_OK);
        assert_true(count >= 1 && count <= 32);
        for (size_t k = 0; k < count; k++) assert_int_equal(got[total + k].t_host_ns, fv_clock_now_ns(&clock));
        total += count;
    }
    int invalid = 0, compared = 0;
    double worst_dir = 0, worst_pupil = 0, worst_origin = 0;
    for (int i = 0; i < N; i++) {
        const fv_gaze_sample *a = &sent[i], *b = &got[i];
        assert_int_equal(b->seq, (uint64_t)i + 1);
        assert_true(b->flags & FV_GAZE_HOST_TIME_VALID);
        assert_int_equal(b->t_device_ns, a->t_device_ns / 1000 * 1000); /* µs on the wire */
        bool any = (a->combined.flags | a->eye[0].flags | a->eye[1].flags) & FV_EYE_DIRECTION_VALID;
        assert_int_equal(!!(b->combined.flags & FV_EYE_DIRECTION_VALID), !!any);
        if (!any) {
            invalid++;
            assert_true(isnan(b->combined.direction.x));
            assert_true(isnan(b->eye[0].pupil_mm) && isnan(b->eye[1].pupil_mm));
            continue;
        }
        for (int e = 0; e < 2; e++) {
            assert_int_equal(!!(b->eye[e].flags & FV_EYE_ORIGIN_VALID), !!(a->eye[e].flags & FV_EYE_ORIGIN_VALID));
            assert_int_equal(!!(b->eye[e].flags & FV_EYE_PUPIL_VALID), !!(a->eye[e].flags & FV_EYE_PUPIL_VALID));
            if (a->eye[e].flags & FV_EYE_PUPIL_VALID)
                worst_pupil = fmax(worst_pupil, fabs(b->eye[e].pupil_mm - a->eye[e].pupil_mm));
            if (a->eye[e].flags & FV_EYE_ORIGIN_VALID)
                worst_origin = fmax(worst_origin, fv_v3_len(fv_v3_sub(b->eye[e].origin_mm, a->eye[e].origin_mm)));
        }
        if (a->combined.flags & FV_EYE_DIRECTION_VALID) {
            worst_dir = fmax(worst_dir, angle_between(a->combined.direction, b->combined.direction));
            compared++;
        }
    }
    /* µm quantization at 650 mm is ~1.5e-6 rad; pupils to 1 µm; origins to 1 µm (float head frame) */
    if (worst_dir > 1e-5 || worst_pupil > 1.01e-3 || worst_origin > 2e-3)
        fail_msg("round trip error: dir %.3g rad, pupil %.3g mm, origin %.3g mm", worst_dir, worst_pupil, worst_origin);
    assert_true(compared > N / 2);
    fv_hid_device_get_stats(dev, &st);
    assert_int_equal(st.samples, N);
    assert_int_equal(st.malformed, 0);

    /* Nothing queued: a timeout, not an error */
    size_t count = 99;
    assert_int_equal(fv_device_read(dev, got, 8, &count, 5), FV_TIMEOUT);
    assert_int_equal(count, 0);

    /* Unplug with one report still queued: it is delivered, then the device is lost for good */
    assert_int_equal(fv_sim_eye_next(eye, &s, &truth), FV_OK);
    assert_int_equal(fv_vhid_encode_sample(v, &s, rep, sizeof rep, &n), FV_OK);
    assert_int_equal(fv_hid_fake_push_input(fake, rep, n), FV_OK);
    fv_hid_fake_unplug(fake);
    fv_test_log_capture_begin();
    assert_int_equal(fv_device_read(dev, got, 8, &count, 5), FV_OK);
    assert_int_equal(count, 1);
    assert_int_equal(fv_device_read(dev, got, 8, &count, 5), FV_ERR_DEVICE_LOST);
    assert_int_equal(fv_device_read(dev, got, 8, &count, 5), FV_ERR_DEVICE_LOST);
    fv_test_log_capture_end();
    fv_assert_log_contains("device lost");
    fv_device_close(&dev);
    assert_null(dev);
    fv_sim_eye_destroy(&eye);
    fv_vhid_destroy(&v);
}

/* The driver on a virtual tracker's fake transport; fake feeds it. */
static fv_device *open_virtual(fv_vhid **v, fv_hid_fake **fake)
{
    assert_int_equal(fv_vhid_create(NULL, v), FV_OK);
    fv_hid_transport *t;
    assert_int_equal(fv_vhid_transport_create(*v, &t, fake), FV_OK);
    fv_device *dev;
    assert_int_equal(fv_hid_device_open_transport(t, NULL, &dev), FV_OK);
    return dev;
}

static void malformed_and_status_reports_in_the_stream_are_skipped(void **state)
{
    (void)state;
    fv_vhid *v;
    fv_hid_fake *fake;
    fv_device *dev = open_virtual(&v, &fake);

    fv_gaze_sample s;
    fv_gaze_sample_init_invalid(&s, 1000000, 0);
    s.combined.direction = fv_v3(0, 0, -1);
    s.combined.origin_mm = fv_v3(0, 0, 0);
    s.combined.flags = FV_EYE_DIRECTION_VALID | FV_EYE_ORIGIN_VALID;
    uint8_t rep[128];
    size_t n;
    assert_int_equal(fv_vhid_encode_sample(v, &s, rep, sizeof rep, &n), FV_OK);
    assert_int_equal(fv_hid_fake_push_input(fake, rep, n - 3), FV_OK); /* short */
    uint8_t wrong[4] = {0x42, 1, 2, 3};
    assert_int_equal(fv_hid_fake_push_input(fake, wrong, sizeof wrong), FV_OK); /* unknown ID */
    uint8_t status[8];
    size_t sn;
    assert_int_equal(fv_vhid_status_input(v, FV_HID_STATUS_READY, 90, status, sizeof status, &sn), FV_OK);
    assert_int_equal(fv_hid_fake_push_input(fake, status, sn), FV_OK);
    assert_int_equal(fv_hid_fake_push_input(fake, rep, n), FV_OK); /* a good one */

    fv_gaze_sample out[8];
    size_t count = 0;
    fv_test_log_capture_begin();
    assert_int_equal(fv_device_read(dev, out, 8, &count, 0), FV_OK);
    fv_test_log_capture_end();
    assert_int_equal(count, 1);
    fv_assert_log_contains("is 42 bytes, the descriptor declares 45");
    fv_assert_log_contains("ID 0x42");
    /* The gaze point straight ahead is the screen centre */
    assert_true(fabs(out[0].screen_point_mm.x - 263.5) < 1e-3);
    assert_true(fabs(out[0].combined.direction.z + 1.0) < 1e-6);
    assert_int_equal(out[0].t_device_ns, 1000000);
    fv_hid_device_stats st;
    fv_hid_device_get_stats(dev, &st);
    assert_int_equal(st.malformed, 2);
    assert_int_equal(st.status_reports, 1);
    assert_true(dev->nominal_rate_hz == 90.0);
    fv_device_close(&dev);
    fv_vhid_destroy(&v);
}

/* A tracker that sends 1000 bad reports: a few lines, then one summary with the exact count of the rest (the log
 * rate limit over time; the original printed 5 lines, then one per 1000, and never said how many it left out). */
static void a_flood_of_bad_reports_is_rate_limited(void **state)
{
    (void)state;
    fv_vhid *v;
    fv_hid_fake *fake;
    fv_device *dev = open_virtual(&v, &fake);
    uint8_t wrong[4] = {0x42, 1, 2, 3};
    for (int i = 0; i < 1000; i++) assert_int_equal(fv_hid_fake_push_input(fake, wrong, sizeof wrong), FV_OK);
    fv_gaze_sample out[8];
    size_t count = 0;
    fv_test_log_capture_begin();
    assert_int_equal(fv_device_read(dev, out, 8, &count, 0), FV_TIMEOUT);
    fv_device_close(&dev); /* the summary of the open window */
    fv_test_log_capture_end();
    unsigned long long summarised = 0;
    int summaries = fv_test_log_lines("more like this in the last", &summarised);
    int shown = fv_test_log_lines("skipped report", NULL) - summaries;
    assert_int_equal(summaries, 1);
    assert_true(shown >= 1 && shown <= 5);
    assert_true((unsigned long long)shown + summarised == 1000);
    fv_vhid_destroy(&v);
}

static void microsoft_descriptor_on_the_fake_transport(void **state)
{
    (void)state;
    uint8_t desc[1024], rep[128];
    size_t dn = hid_test_load_hex("ms-gazehid-vhidmini-eye-tracker.rdesc.hex", desc, sizeof desc);
    fv_hid_fake_desc fd = {.descriptor = desc, .descriptor_len = dn, .vid = 0xDEED, .pid = 0xFEED};
    fv_hid_transport *t;
    fv_hid_fake *fake;
    assert_int_equal(fv_hid_fake_create(&fd, &t, &fake), FV_OK);
    size_t n = hid_test_synthetic("configuration_feature_0x12_527x296mm_display", rep, sizeof rep);
    assert_int_equal(fv_hid_fake_set_feature_reply(fake, rep, n), FV_OK);
    n = hid_test_load_hex("ms-gazehid-capabilities-feature-report.hex", rep, sizeof rep);
    assert_int_equal(fv_hid_fake_set_feature_reply(fake, rep, n), FV_OK);
    fv_device *dev;
    assert_int_equal(fv_hid_device_open_transport(t, NULL, &dev), FV_OK);
    fv_hid_device_stats st;
    fv_hid_device_get_stats(dev, &st);
    assert_int_equal(st.tracker_quality, 1);
    assert_non_null(strstr(dev->info.detail, "Microsoft GazeHid"));
    n = hid_test_synthetic("gazehid_input_0x10_valid_t1", rep, sizeof rep);
    assert_int_equal(fv_hid_fake_push_input(fake, rep, n), FV_OK);
    fv_gaze_sample out[2];
    size_t count;
    assert_int_equal(fv_device_read(dev, out, 2, &count, 0), FV_OK);
    assert_int_equal(count, 1);
    /* The calibrated size came from the Configuration feature: the gaze point is near the centre */
    assert_true(out[0].combined.flags & FV_EYE_DIRECTION_VALID);
    assert_true(fabs(out[0].combined.direction.x) < 1e-6);
    fv_device_close(&dev);
}

static void a_non_eye_tracker_is_refused_at_open(void **state)
{
    (void)state;
    const uint8_t mouse[] = {0x05, 0x01, 0x09, 0x02, 0xA1, 0x01, 0x09, 0x30, 0x75, 0x08,
                             0x95, 0x01, 0x15, 0x81, 0x25, 0x7F, 0x81, 0x06, 0xC0};
    fv_hid_fake_desc fd = {.descriptor = mouse, .descriptor_len = sizeof mouse};
    fv_hid_transport *t;
    assert_int_equal(fv_hid_fake_create(&fd, &t, NULL), FV_OK);
    fv_device *dev = NULL;
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_device_open_transport(t, NULL, &dev), FV_ERR_UNSUPPORTED);
    fv_test_log_capture_end();
    assert_null(dev);
    fv_assert_log_contains("Generic Desktop");
    /* a truncated descriptor: a parse error, transport freed (ASan checks the leak) */
    fd.descriptor_len = 5;
    assert_int_equal(fv_hid_fake_create(&fd, &t, NULL), FV_OK);
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_device_open_transport(t, NULL, &dev), FV_ERR_PARSE);
    fv_test_log_capture_end();
}

static void uris_parse_and_bad_ones_say_why(void **state)
{
    (void)state;
    fv_hid_uri u;
    assert_int_equal(fv_hid_uri_parse("hid:auto", "hid", &u), FV_OK);
    assert_int_equal(u.kind, FV_HID_URI_AUTO);
    assert_int_equal(fv_hid_uri_parse("hid:/dev/hidraw3", "hid", &u), FV_OK);
    assert_int_equal(u.kind, FV_HID_URI_PATH);
    assert_string_equal(u.path, "/dev/hidraw3");
    assert_int_equal(fv_hid_uri_parse("hid:DEED:0xfeed:SN-1", "hid", &u), FV_OK);
    assert_int_equal(u.kind, FV_HID_URI_VIDPID);
    assert_int_equal(u.vid, 0xDEED);
    assert_int_equal(u.pid, 0xFEED);
    assert_string_equal(u.serial, "SN-1");
    assert_int_equal(fv_hid_uri_parse("usb:1209:0001", "usb", &u), FV_OK);
    const char *bad[] = {"hid:xyz", "hid:12345:1", "hid:deed", "hid:deed:feed:", "usb:auto", "hidden:auto"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        fv_test_log_capture_begin();
        assert_int_equal(fv_hid_uri_parse(bad[i], "hid", &u), FV_ERR_PARSE);
        fv_test_log_capture_end();
        fv_assert_log_contains(bad[i]);
    }
    /* No hidraw here: a clear not-found, never a crash */
    fv_device *dev = NULL;
    fv_test_log_capture_begin();
    fv_result r = fv_hid_driver.open("hid:/dev/hidraw-none", NULL, &dev);
    fv_test_log_capture_end();
    assert_int_equal(r, FV_ERR_NOT_FOUND);
    fv_assert_log_contains("/dev/hidraw-none");
    fv_device_info infos[4];
    size_t count = 99;
    r = fv_hid_driver.probe(infos, 4, &count);
    assert_true(r == FV_OK || r == FV_ERR_IO);
    if (r == FV_OK) assert_true(count < 1000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(simulated_eye_runs_end_to_end_through_the_virtual_tracker),
        cmocka_unit_test(malformed_and_status_reports_in_the_stream_are_skipped),
        cmocka_unit_test(a_flood_of_bad_reports_is_rate_limited),
        cmocka_unit_test(microsoft_descriptor_on_the_fake_transport),
        cmocka_unit_test(a_non_eye_tracker_is_refused_at_open),
        cmocka_unit_test(uris_parse_and_bad_ones_say_why),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
