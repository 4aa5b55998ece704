/* @brief fovea's virtual HID eye tracker: a page-0x12 report descriptor (Tracking Data with fovea's vendor pupil
 * extension, Capabilities, Configuration, Status input+feature, Control) and the reports a real tracker would send,
 * encoded from fv_gaze_sample values (e.g. the simulated eye in sim/gaze). Its transport is the fake HID transport,
 * so samples run end to end through the same parser and decoder as a real device. One owner; not thread-safe. */
#ifndef FV_VHID_H
#define FV_VHID_H

#include <stddef.h>
#include <stdint.h>

#include "fovea/fv_gaze_sample.h"
#include "fv_hid_eyetracker.h"
#include "fv_hid_transport.h"

/** pid.codes' test VID/PID; listed in the quirks table with fovea's pupil extension. */
#define FV_VHID_VID 0x1209
#define FV_VHID_PID 0x0001

typedef struct fv_vhid_desc {
    float screen_width_mm, screen_height_mm; /* calibrated screen (0: 527 x 296 mm) */
    const fv_hid_screen_config *screen;      /* placement used to put rays on the plane (NULL: defaults) */
    unsigned sampling_hz;                    /* reported in Status (0: 120) */
} fv_vhid_desc;

typedef struct fv_vhid fv_vhid;

FV_MUST_CHECK fv_result fv_vhid_create(const fv_vhid_desc *desc, fv_vhid **out);
void fv_vhid_destroy(fv_vhid **v);

/** The report descriptor bytes (owned by v). */
const uint8_t *fv_vhid_descriptor(const fv_vhid *v, size_t *out_len);
/** The screen placement in use (width/height filled). */
const fv_hid_screen_config *fv_vhid_screen(const fv_vhid *v);

/** Encode one sample as a Tracking Data input report: timestamp from t_device_ns (µs), the gaze point where the
 *  combined ray (or a valid eye's ray) meets the screen plane, eye positions and pupils; anything invalid or out of
 *  range is sent as the out-of-range value (INT32_MAX, 0xFFFF) as real trackers do. */
FV_MUST_CHECK fv_result fv_vhid_encode_sample(fv_vhid *v, const fv_gaze_sample *s, uint8_t *buf, size_t cap,
                                              size_t *out_len);
/** A feature report (0x11 capabilities, 0x12 configuration, 0x13 status) as the device answers GET_REPORT. */
FV_MUST_CHECK fv_result fv_vhid_feature(fv_vhid *v, uint8_t report_id, uint8_t *buf, size_t cap, size_t *out_len);
/** A Status input report (0x13). */
FV_MUST_CHECK fv_result fv_vhid_status_input(fv_vhid *v, int status, unsigned hz, uint8_t *buf, size_t cap,
                                             size_t *out_len);

/** A fake transport that speaks as this virtual tracker: its descriptor, VID/PID and feature replies, gated on the
 *  Device Mode Request. Push encoded reports through *out_fake. */
FV_MUST_CHECK fv_result fv_vhid_transport_create(fv_vhid *v, fv_hid_transport **out, fv_hid_fake **out_fake);

#endif
