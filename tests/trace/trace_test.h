/* @brief Helpers shared by the tests of drivers/trace (header-only: each test is its own executable). */
#ifndef FV_TRACE_TEST_H
#define FV_TRACE_TEST_H

#include <stdio.h>

#include "fv_test.h"
#include "fv_trace_driver.h"

/** Open the trace driver on the URI made from fmt (one %s, the path), paced by clock; fails the test on an error. */
static inline fv_device *trace_test_open_uri(const char *fmt, const char *path, const fv_clock *clock)
{
    char uri[1400];
    snprintf(uri, sizeof uri, fmt, path);
    fv_device_open_desc d = {.clock = clock};
    fv_device *dev = NULL;
    assert_int_equal(fv_trace_driver.open(uri, &d, &dev), FV_OK);
    assert_non_null(dev);
    return dev;
}

#endif
