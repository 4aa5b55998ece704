/* @brief The usb driver without hardware: URIs, a clean "nothing attached", hotplug start/stop, and the hotplug
 * callback flagging re-probes only for possible trackers. */
#include <string.h>

#include "fv_hid_driver.h"
#include "fv_test.h"
#include "fv_usb_driver.h"
#include "fv_usb_hotplug.h"

static void usb_uris_and_missing_devices_fail_clearly(void **state)
{
    (void)state;
    assert_string_equal(fv_usb_driver.scheme, "usb");
    fv_device *dev = NULL;
    fv_test_log_capture_begin();
    assert_int_equal(fv_usb_driver.open("usb:/dev/bus/usb/001/002", NULL, &dev), FV_ERR_PARSE);
    fv_test_log_capture_end();
    fv_assert_log_contains("not a path");
    fv_test_log_capture_begin();
    fv_result r = fv_usb_driver.open("usb:dead:beef", NULL, &dev);
    fv_test_log_capture_end();
    assert_true(r == FV_ERR_NOT_FOUND || r == FV_ERR_IO); /* IO: no usbfs in this sandbox */
    assert_null(dev);
    assert_true(strstr(fv_test_log_text(), "dead:beef") || strstr(fv_test_log_text(), "libusb unavailable"));
    fv_device_info infos[4];
    size_t count = 99;
    assert_int_equal(fv_usb_driver.probe(infos, 4, &count), FV_OK);
    assert_true(count <= 4 || count < 1000);
}

static void hotplug_flags_reprobe_for_possible_trackers_only(void **state)
{
    (void)state;
    fv_usb_hotplug *h = NULL;
    fv_result r = fv_usb_hotplug_start(&h);
    if (r == FV_ERR_UNSUPPORTED) {
        assert_null(h);
        return; /* no libusb hotplug in this environment: start refused cleanly */
    }
    assert_int_equal(r, FV_OK);
    assert_false(fv_usb_hotplug_take_reprobe(h));
    fv_usb_hotplug_note(h, 0x046D, 0xC077, 0x09, true); /* a hub-class device: ignored */
    assert_false(fv_usb_hotplug_take_reprobe(h));
    fv_usb_hotplug_note(h, 0x1209, 0x0001, 0xEF, true); /* in the quirks table */
    fv_usb_hotplug_note(h, 0x1234, 0x5678, 0x00, false); /* class per interface: may be HID */
    assert_true(fv_usb_hotplug_take_reprobe(h));
    assert_false(fv_usb_hotplug_take_reprobe(h));
    assert_int_equal(fv_usb_hotplug_events(h), 2);
    fv_usb_hotplug_stop(&h);
    assert_null(h);
    fv_usb_hotplug_stop(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(usb_uris_and_missing_devices_fail_clearly),
        cmocka_unit_test(hotplug_flags_reprobe_for_possible_trackers_only),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
