/* @brief Device registry: sim and trace are ordered last, every driver is probed (a failing one is listed with its
 * result), open goes by URI scheme, unknown schemes and "auto" without hardware say so plainly. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_registry.h"
#include "fv_test.h"

static int g_open_calls;
static char g_last_uri[256];

typedef struct fake_dev {
    fv_device base;
} fake_dev;

static fv_result dev_read(fv_device *d, fv_gaze_sample *out, size_t cap, size_t *n, int timeout_ms)
{
    (void)d, (void)out, (void)cap, (void)timeout_ms;
    *n = 0;
    return FV_TIMEOUT;
}
static void dev_close(fv_device *d) { free(d); }
static const fv_device_ops g_ops = {.read = dev_read, .close = dev_close};

static fv_result open_ok(const char *uri, const fv_device_open_desc *desc, fv_device **out)
{
    (void)desc;
    g_open_calls++;
    snprintf(g_last_uri, sizeof g_last_uri, "%s", uri);
    fake_dev *d = calloc(1, sizeof *d);
    if (!d) return FV_ERR_NO_MEMORY;
    d->base.ops = &g_ops;
    *out = &d->base;
    return FV_OK;
}

static fv_result open_broken(const char *uri, const fv_device_open_desc *desc, fv_device **out)
{
    (void)uri, (void)desc;
    *out = NULL; /* claims success, hands back nothing */
    return FV_OK;
}

static fv_result probe_none(fv_device_info *out, size_t cap, size_t *count)
{
    (void)out, (void)cap;
    *count = 0;
    return FV_OK;
}

static fv_result probe_fails(fv_device_info *out, size_t cap, size_t *count)
{
    (void)out, (void)cap;
    *count = 0;
    return FV_ERR_IO;
}

static fv_result probe_sim(fv_device_info *out, size_t cap, size_t *count)
{
    *count = 1;
    if (cap >= 1) {
        memset(&out[0], 0, sizeof out[0]);
        snprintf(out[0].uri, sizeof out[0].uri, "sim:seed=1");
        snprintf(out[0].name, sizeof out[0].name, "simulated eye");
        snprintf(out[0].driver, sizeof out[0].driver, "sim");
    }
    return FV_OK;
}

/* 20 devices, and no NUL in the name: the registry asks again with room and terminates the strings */
static fv_result probe_many(fv_device_info *out, size_t cap, size_t *count)
{
    *count = 20;
    for (size_t i = 0; i < cap && i < 20; i++) {
        memset(&out[i], 'x', sizeof out[i]);
        snprintf(out[i].uri, sizeof out[i].uri, "hid:/dev/hidraw%zu", i);
        out[i].driver[0] = '\0';
    }
    return FV_OK;
}

static const fv_driver d_sim = {"sim", "simulated eye", probe_sim, open_ok};
static const fv_driver d_trace = {"trace", "recordings", probe_none, open_ok};
static const fv_driver d_hid = {"hid", "HID trackers", probe_none, open_ok};
static const fv_driver d_usb = {"usb", "USB trackers", probe_fails, open_ok};
static const fv_driver d_many = {"hid", "HID trackers", probe_many, open_ok};
static const fv_driver d_broken = {"usb", "broken", probe_none, open_broken};

static void sim_and_trace_are_ordered_last(void **state)
{
    (void)state;
    const fv_driver *list[] = {&d_sim, &d_hid, &d_trace, &d_usb, NULL};
    fv_registry reg;
    assert_int_equal(fv_registry_init(&reg, list), FV_OK);
    assert_int_equal(reg.count, 4);
    assert_string_equal(reg.drivers[0]->scheme, "hid");
    assert_string_equal(reg.drivers[1]->scheme, "usb");
    assert_string_equal(reg.drivers[2]->scheme, "trace");
    assert_string_equal(reg.drivers[3]->scheme, "sim");
    assert_true(fv_registry_is_virtual(&d_sim));
    assert_false(fv_registry_is_virtual(&d_usb));
}

static void duplicate_or_incomplete_drivers_are_refused(void **state)
{
    (void)state;
    const fv_driver nameless = {NULL, "?", probe_none, open_ok};
    const fv_driver *dup[] = {&d_hid, &d_many, NULL};
    const fv_driver *bad[] = {&nameless, NULL};
    fv_registry reg;
    fv_test_log_capture_begin();
    assert_int_equal(fv_registry_init(&reg, dup), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_registry_init(&reg, bad), FV_ERR_INVALID_ARG);
    fv_test_log_capture_end();
    fv_assert_log_contains("two drivers answer the scheme 'hid'");
    fv_assert_log_contains("lacks a scheme, probe or open");
}

static void probe_lists_every_driver_and_counts_only_hardware(void **state)
{
    (void)state;
    const fv_driver *list[] = {&d_sim, &d_trace, &d_hid, &d_usb, NULL};
    fv_registry reg;
    assert_int_equal(fv_registry_init(&reg, list), FV_OK);
    fv_registry_listing l;
    assert_int_equal(fv_registry_probe(&reg, &l), FV_OK);
    assert_int_equal(l.driver_count, 4);
    assert_int_equal(l.hardware_devices, 0); /* the simulated eye is not an eye tracker */
    assert_int_equal(l.drivers[1].result, FV_ERR_IO); /* usb could not look; still listed */
    assert_int_equal(l.drivers[3].count, 1);
    assert_string_equal(l.drivers[3].devices[0].uri, "sim:seed=1");
    fv_registry_listing_fini(&l);
    fv_registry_listing_fini(&l); /* twice is fine */
}

static void probe_asks_again_when_a_driver_has_more_and_terminates_strings(void **state)
{
    (void)state;
    const fv_driver *list[] = {&d_many, NULL};
    fv_registry reg;
    assert_int_equal(fv_registry_init(&reg, list), FV_OK);
    fv_registry_listing l;
    assert_int_equal(fv_registry_probe(&reg, &l), FV_OK);
    assert_int_equal(l.drivers[0].count, 20);
    assert_false(l.drivers[0].truncated);
    assert_int_equal(l.hardware_devices, 20);
    assert_string_equal(l.drivers[0].devices[19].uri, "hid:/dev/hidraw19");
    assert_string_equal(l.drivers[0].devices[19].driver, "hid"); /* filled in for the driver */
    assert_int_equal(strlen(l.drivers[0].devices[19].name), sizeof l.drivers[0].devices[19].name - 1);
    fv_registry_listing_fini(&l);
}

static void open_goes_by_scheme_and_names_unknown_ones(void **state)
{
    (void)state;
    const fv_driver *list[] = {&d_hid, &d_sim, &d_broken, NULL};
    fv_registry reg;
    assert_int_equal(fv_registry_init(&reg, list), FV_OK);
    fv_device *dev = NULL;
    g_open_calls = 0;
    assert_int_equal(fv_registry_open(&reg, "sim:seed=3", NULL, &dev), FV_OK);
    assert_non_null(dev);
    assert_string_equal(g_last_uri, "sim:seed=3");
    fv_device_close(&dev);
    assert_null(dev);
    fv_test_log_capture_begin();
    assert_int_equal(fv_registry_open(&reg, "bluetooth:aa:bb", NULL, &dev), FV_ERR_NOT_FOUND);
    assert_int_equal(fv_registry_open(&reg, "usb:1234:5678", NULL, &dev), FV_ERR_PROTOCOL);
    assert_null(dev);
    fv_test_log_capture_end();
    fv_assert_log_contains("unknown URI scheme 'bluetooth' (known: hid, usb, sim)");
    fv_assert_log_contains("driver 'usb' reported success without a usable device");
    assert_int_equal(g_open_calls, 1);
}

static void auto_opens_the_first_hardware_device_or_says_none_attached(void **state)
{
    (void)state;
    const fv_driver *none[] = {&d_sim, &d_hid, NULL};
    const fv_driver *some[] = {&d_sim, &d_many, NULL};
    fv_registry reg;
    fv_device *dev = NULL;
    assert_int_equal(fv_registry_init(&reg, none), FV_OK);
    fv_test_log_capture_begin();
    assert_int_equal(fv_registry_open(&reg, "auto", NULL, &dev), FV_ERR_NOT_FOUND);
    fv_test_log_capture_end();
    fv_assert_log_contains("no eye trackers attached");
    assert_int_equal(fv_registry_init(&reg, some), FV_OK);
    assert_int_equal(fv_registry_open_fn(&reg, "auto", NULL, &dev), FV_OK);
    assert_string_equal(g_last_uri, "hid:/dev/hidraw0"); /* not the simulated eye */
    fv_device_close(&dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sim_and_trace_are_ordered_last),
        cmocka_unit_test(duplicate_or_incomplete_drivers_are_refused),
        cmocka_unit_test(probe_lists_every_driver_and_counts_only_hardware),
        cmocka_unit_test(probe_asks_again_when_a_driver_has_more_and_terminates_strings),
        cmocka_unit_test(open_goes_by_scheme_and_names_unknown_ones),
        cmocka_unit_test(auto_opens_the_first_hardware_device_or_says_none_attached),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
