/* @brief An open HID eye tracker on any transport: descriptor → page-0x12 map, features read at open, the Device
 * Mode Request written, stale reports drained, then read() decodes Tracking Data into fv_gaze_sample. */
#ifndef FV_HID_DEVICE_H
#define FV_HID_DEVICE_H

#include <stdint.h>

#include "fovea/fv_device.h"
#include "fv_hid_eyetracker.h"
#include "fv_hid_transport.h"

/** Options for opening. Zero means default. */
typedef struct fv_hid_device_desc {
    const fv_clock *clock;              /* host clock for t_host_ns; NULL = monotonic */
    const fv_hid_screen_config *screen; /* NULL = fv_hid_screen_config_defaults() + the device's calibrated size */
    unsigned mode;                      /* Device Mode Request bits; 0 = FV_HID_MODE_ALL */
    const char *uri;                    /* recorded in the device info; NULL = built from the transport path */
} fv_hid_device_desc;

/** Open an eye tracker on a transport; the device takes ownership of `t` (destroyed on failure too).
 *  FV_ERR_UNSUPPORTED when the descriptor is not an eye tracker; FV_ERR_PARSE for a malformed descriptor; transport
 *  errors as they are. */
FV_MUST_CHECK fv_result fv_hid_device_open_transport(fv_hid_transport *t, const fv_hid_device_desc *desc,
                                                     fv_device **out);

/** Counters of an open hid device (for tests and `fovea devices`). */
typedef struct fv_hid_device_stats {
    uint64_t reports;          /* input reports received after open */
    uint64_t samples;          /* tracking reports decoded into samples */
    uint64_t malformed;        /* reports skipped (wrong ID, short, undecodable) */
    uint64_t status_reports;   /* status inputs seen */
    uint64_t drained_at_open;  /* stale reports discarded at open */
    double calibrated_width_mm, calibrated_height_mm;
    int tracker_quality;       /* -1 unknown */
} fv_hid_device_stats;

/** Counters of a device opened by this library (hid or usb scheme). */
void fv_hid_device_get_stats(const fv_device *dev, fv_hid_device_stats *out);

#endif
