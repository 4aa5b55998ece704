/* @brief The `hid` driver: eye trackers on hidraw through hidapi. URIs: "hid:auto", "hid:/dev/hidrawN",
 * "hid:VID:PID[:serial]" (hex VID/PID). Probes by usage page 0x12 and by the quirks table. */
#ifndef FV_HID_DRIVER_H
#define FV_HID_DRIVER_H

#include <stdint.h>

#include "fovea/fv_device.h"

extern const fv_driver fv_hid_driver;

/** A parsed hid/usb URI. */
typedef enum fv_hid_uri_kind {
    FV_HID_URI_AUTO = 0,   /* "hid:auto" or "hid:" */
    FV_HID_URI_PATH = 1,   /* "hid:/dev/hidraw3" */
    FV_HID_URI_VIDPID = 2, /* "hid:deed:feed[:serial]" */
} fv_hid_uri_kind;

typedef struct fv_hid_uri {
    fv_hid_uri_kind kind;
    uint16_t vid, pid;
    char path[256];
    char serial[64]; /* empty: any */
} fv_hid_uri;

/** Parse "<scheme>:..." (scheme "hid" or "usb"). FV_ERR_PARSE (logged with the reason) on a malformed URI. */
FV_MUST_CHECK fv_result fv_hid_uri_parse(const char *uri, const char *scheme, fv_hid_uri *out);

#endif
