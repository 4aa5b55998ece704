/* @brief One small transport interface for HID trackers (report descriptor, read with timeout, get/set feature), with
 * three implementations: hidapi over hidraw (here), libusb (drivers/usb) and a fake that replays bytes (tests: CI
 * has no /dev/hidraw and no USB devices). The hid device (fv_hid_device.h) sits on top of any of them. */
#ifndef FV_HID_TRANSPORT_H
#define FV_HID_TRANSPORT_H

#include <stddef.h>
#include <stdint.h>

#include "fv_result.h"

typedef struct fv_hid_transport fv_hid_transport;

/** Operations. One thread uses a transport at a time (the device's reader); report buffers start with the report ID
 *  when the descriptor uses IDs, exactly as hidraw delivers them. */
typedef struct fv_hid_transport_ops {
    /** The report descriptor. */
    fv_result (*get_descriptor)(fv_hid_transport *t, uint8_t *buf, size_t cap, size_t *out_len);
    /** One input report, waiting at most timeout_ms (0 = poll). FV_OK with *out_len > 0; FV_TIMEOUT when nothing came;
     *  FV_ERR_DEVICE_LOST when the device hung up (unplugged); FV_ERR_IO for other failures. */
    fv_result (*read)(fv_hid_transport *t, uint8_t *buf, size_t cap, size_t *out_len, int timeout_ms);
    /** GET_REPORT(Feature, report_id) into buf (buf[0] = the ID). */
    fv_result (*get_feature)(fv_hid_transport *t, uint8_t report_id, uint8_t *buf, size_t cap, size_t *out_len);
    /** SET_REPORT(Feature); buf[0] is the report ID. */
    fv_result (*set_feature)(fv_hid_transport *t, const uint8_t *buf, size_t len);
    /** Close and free. */
    void (*destroy)(fv_hid_transport *t);
} fv_hid_transport_ops;

/** Base of every transport (implementations embed it first). */
struct fv_hid_transport {
    const fv_hid_transport_ops *ops;
    uint16_t vid, pid;
    char path[256];   /* "/dev/hidraw3", "usb:1-4:1.0", "fake" */
    char name[128];   /* product string when known */
    char serial[64];
};

/** Destroy and set *t to NULL; safe on NULL. */
void fv_hid_transport_destroy(fv_hid_transport **t);

/* ---- hidapi (hidraw) ---- */

/** Open a hidraw node through hidapi. The report descriptor is read with the HIDIOCGRDESC ioctl on the same node
 *  (hidapi 0.13 has no hid_get_report_descriptor). FV_ERR_NOT_FOUND / FV_ERR_IO (logged with errno text; permission
 *  problems name the udev rule fix). */
FV_MUST_CHECK fv_result fv_hid_hidapi_open_path(const char *path, fv_hid_transport **out);

/* ---- fake (replays bytes) ---- */

typedef struct fv_hid_fake fv_hid_fake;

/** A fake transport: a descriptor, a queue of input reports, feature replies by ID and a record of feature writes.
 *  When `gate_on_mode_request` is set, queued input reports flow only after a Control (set_feature) report whose
 *  first byte is `mode_report_id` and second byte is nonzero was written, as a real page-0x12 tracker behaves;
 *  inputs pushed before that are "stale" and stay buffered. */
typedef struct fv_hid_fake_desc {
    const uint8_t *descriptor;
    size_t descriptor_len;
    uint16_t vid, pid;
    int gate_on_mode_request;
    uint8_t mode_report_id;
} fv_hid_fake_desc;

/** Create; the transport owns copies of all bytes. `out_fake` (optional) is a handle to feed it; it stays valid until
 *  the transport is destroyed. */
FV_MUST_CHECK fv_result fv_hid_fake_create(const fv_hid_fake_desc *desc, fv_hid_transport **out,
                                           fv_hid_fake **out_fake);
/** Queue one input report. Thread-safe against the reader. */
FV_MUST_CHECK fv_result fv_hid_fake_push_input(fv_hid_fake *f, const uint8_t *report, size_t len);
/** Set the reply to GET_REPORT(Feature, report[0]). */
FV_MUST_CHECK fv_result fv_hid_fake_set_feature_reply(fv_hid_fake *f, const uint8_t *report, size_t len);
/** From now on, once the queue is empty, reads fail with FV_ERR_DEVICE_LOST (an unplug). */
void fv_hid_fake_unplug(fv_hid_fake *f);
/** Number of set_feature calls so far and the last one written (copied into buf). */
size_t fv_hid_fake_feature_writes(fv_hid_fake *f, uint8_t *last, size_t cap, size_t *out_len);
/** Input reports still queued. */
size_t fv_hid_fake_pending(fv_hid_fake *f);

#endif
