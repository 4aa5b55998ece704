/* @brief libusb HID transport (HID 1.11 §7: GET_DESCRIPTOR(Report), interrupt-IN, GET/SET_REPORT) and the `usb`
 * driver that finds HID-class eye trackers with it. */
#include "fv_usb_driver.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libusb.h>

#include "fv_hid_device.h"
#include "fv_hid_driver.h"
#include "fv_hid_eyetracker.h"
#include "fv_log.h"

#define MOD "usb"
#define CTRL_TIMEOUT_MS 1000
#define HID_DT_REPORT 0x22
#define HID_GET_REPORT 0x01
#define HID_SET_REPORT 0x09
#define HID_FEATURE 0x03

typedef struct usb_transport {
    fv_hid_transport base;
    libusb_context *ctx;
    libusb_device_handle *h;
    int iface;
    uint8_t ep_in;
    uint16_t report_desc_len;
    bool claimed, lost;
} usb_transport;

static fv_result map_err(usb_transport *u, int rc, const char *what)
{
    if (rc == LIBUSB_ERROR_NO_DEVICE) {
        if (!u->lost) FV_ERROR(MOD, "%s: %s: device lost (unplugged)", u->base.path, what);
        u->lost = true;
        return FV_ERR_DEVICE_LOST;
    }
    /* once per transfer (each interrupt-IN read): a failing device would repeat it at its full rate */
    static fv_log_ratelimit rl = FV_LOG_RATELIMIT_INIT(5, 30);
    FV_ERROR_RL(&rl, MOD, "%s: %s failed: %s", u->base.path, what, libusb_error_name(rc));
    return FV_ERR_IO;
}

static fv_result usb_get_descriptor(fv_hid_transport *t, uint8_t *buf, size_t cap, size_t *out_len)
{
    usb_transport *u = (usb_transport *)t;
    size_t want = u->report_desc_len ? u->report_desc_len : 4096;
    if (want > cap) want = cap;
    int rc = libusb_control_transfer(u->h, LIBUSB_ENDPOINT_IN | LIBUSB_REQUEST_TYPE_STANDARD | LIBUSB_RECIPIENT_INTERFACE,
                                     LIBUSB_REQUEST_GET_DESCRIPTOR, (uint16_t)(HID_DT_REPORT << 8), (uint16_t)u->iface,
                                     buf, (uint16_t)(want > 0xFFFF ? 0xFFFF : want), CTRL_TIMEOUT_MS);
    if (rc < 0) return map_err(u, rc, "GET_DESCRIPTOR(Report)");
    *out_len = (size_t)rc;
    return FV_OK;
}

static fv_result usb_read(fv_hid_transport *t, uint8_t *buf, size_t cap, size_t *out_len, int timeout_ms)
{
    usb_transport *u = (usb_transport *)t;
    *out_len = 0;
    if (u->lost) return FV_ERR_DEVICE_LOST;
    int got = 0;
    /* libusb reads timeout 0 as "wait forever": a poll becomes the shortest wait instead. */
    unsigned to = timeout_ms > 0 ? (unsigned)timeout_ms : 1u;
    int rc = libusb_interrupt_transfer(u->h, u->ep_in, buf, (int)(cap > 65536 ? 65536 : cap), &got, to);
    if (rc == LIBUSB_ERROR_TIMEOUT && got == 0) return FV_TIMEOUT;
    if (rc != 0 && rc != LIBUSB_ERROR_TIMEOUT) return map_err(u, rc, "interrupt-IN read");
    *out_len = (size_t)got;
    return got > 0 ? FV_OK : FV_TIMEOUT;
}

static fv_result usb_get_feature(fv_hid_transport *t, uint8_t id, uint8_t *buf, size_t cap, size_t *out_len)
{
    usb_transport *u = (usb_transport *)t;
    int rc = libusb_control_transfer(u->h, LIBUSB_ENDPOINT_IN | LIBUSB_REQUEST_TYPE_CLASS | LIBUSB_RECIPIENT_INTERFACE,
                                     HID_GET_REPORT, (uint16_t)(HID_FEATURE << 8 | id), (uint16_t)u->iface, buf,
                                     (uint16_t)(cap > 0xFFFF ? 0xFFFF : cap), CTRL_TIMEOUT_MS);
    if (rc < 0) return map_err(u, rc, "GET_REPORT(Feature)");
    *out_len = (size_t)rc;
    return FV_OK;
}

static fv_result usb_set_feature(fv_hid_transport *t, const uint8_t *buf, size_t len)
{
    usb_transport *u = (usb_transport *)t;
    if (len == 0) return FV_ERR_INVALID_ARG;
    uint8_t id = buf[0];
    /* Report ID 0 means "no IDs": the ID byte is not sent (the hidapi convention). */
    const uint8_t *data = id ? buf : buf + 1;
    size_t n = id ? len : len - 1;
    int rc = libusb_control_transfer(u->h, LIBUSB_ENDPOINT_OUT | LIBUSB_REQUEST_TYPE_CLASS | LIBUSB_RECIPIENT_INTERFACE,
                                     HID_SET_REPORT, (uint16_t)(HID_FEATURE << 8 | id), (uint16_t)u->iface,
                                     (unsigned char *)(uintptr_t)data, (uint16_t)n, CTRL_TIMEOUT_MS);
    if (rc < 0) return map_err(u, rc, "SET_REPORT(Feature)");
    return FV_OK;
}

static void usb_destroy(fv_hid_transport *t)
{
    usb_transport *u = (usb_transport *)t;
    if (u->claimed) libusb_release_interface(u->h, u->iface);
    if (u->h) libusb_close(u->h);
    if (u->ctx) libusb_exit(u->ctx);
    free(u);
}

static const fv_hid_transport_ops g_usb_ops = {usb_get_descriptor, usb_read, usb_get_feature, usb_set_feature,
                                               usb_destroy};

/* The first HID interface with an interrupt-IN endpoint; its report descriptor length from the HID class
 * descriptor (bDescriptorType 0x21) in the interface's extra bytes. */
static bool find_hid_interface(libusb_device *dev, int *out_iface, uint8_t *out_ep, uint16_t *out_len)
{
    struct libusb_config_descriptor *cfg;
    if (libusb_get_active_config_descriptor(dev, &cfg) != 0 && libusb_get_config_descriptor(dev, 0, &cfg) != 0)
        return false;
    bool found = false;
    for (int i = 0; i < cfg->bNumInterfaces && !found; i++) {
        const struct libusb_interface *itf = &cfg->interface[i];
        for (int a = 0; a < itf->num_altsetting && !found; a++) {
            const struct libusb_interface_descriptor *d = &itf->altsetting[a];
            if (d->bInterfaceClass != LIBUSB_CLASS_HID) continue;
            for (int e = 0; e < d->bNumEndpoints; e++) {
                const struct libusb_endpoint_descriptor *ep = &d->endpoint[e];
                if ((ep->bEndpointAddress & LIBUSB_ENDPOINT_IN) &&
                    (ep->bmAttributes & 3) == LIBUSB_TRANSFER_TYPE_INTERRUPT) {
                    *out_iface = d->bInterfaceNumber;
                    *out_ep = ep->bEndpointAddress;
                    found = true;
                    break;
                }
            }
            *out_len = 0;
            for (int k = 0; found && k + 9 <= d->extra_length; k += d->extra[k] ? d->extra[k] : 1) {
                const unsigned char *x = d->extra + k;
                if (x[1] != 0x21 || x[0] < 9) continue;
                for (int n = 0; n < x[5] && 6 + 3 * n + 2 < x[0]; n++)
                    if (x[6 + 3 * n] == HID_DT_REPORT) *out_len = (uint16_t)(x[7 + 3 * n] | x[8 + 3 * n] << 8);
            }
        }
    }
    libusb_free_config_descriptor(cfg);
    return found;
}

static bool serial_of(libusb_device_handle *h, const struct libusb_device_descriptor *dd, char *out, size_t cap)
{
    out[0] = '\0';
    if (!dd->iSerialNumber) return false;
    return libusb_get_string_descriptor_ascii(h, dd->iSerialNumber, (unsigned char *)out, (int)cap) > 0;
}

fv_result fv_usb_transport_open(uint16_t vid, uint16_t pid, const char *serial, fv_hid_transport **out)
{
    fv_result r = FV_ERR_NOT_FOUND;
    usb_transport *u = calloc(1, sizeof *u);
    libusb_device **list = NULL;
    if (!u) return FV_ERR_NO_MEMORY;
    u->base.ops = &g_usb_ops;
    int rc = libusb_init(&u->ctx);
    if (rc != 0) {
        FV_ERROR(MOD, "libusb unavailable: %s", libusb_error_name(rc));
        u->ctx = NULL;
        r = FV_ERR_IO;
        goto fail;
    }
    ssize_t n = libusb_get_device_list(u->ctx, &list);
    for (ssize_t i = 0; i < n && !u->h; i++) {
        struct libusb_device_descriptor dd;
        if (libusb_get_device_descriptor(list[i], &dd) != 0 || dd.idVendor != vid || dd.idProduct != pid) continue;
        if (!find_hid_interface(list[i], &u->iface, &u->ep_in, &u->report_desc_len)) continue;
        rc = libusb_open(list[i], &u->h);
        if (rc != 0) {
            FV_ERROR(MOD, "usb %04x:%04x (bus %u address %u): cannot open: %s%s", vid, pid,
                     libusb_get_bus_number(list[i]), libusb_get_device_address(list[i]), libusb_error_name(rc),
                     rc == LIBUSB_ERROR_ACCESS ? " (add a udev rule for this VID:PID, see docs/hid.md)" : "");
            u->h = NULL;
            r = FV_ERR_IO;
            continue;
        }
        if (serial && serial[0] && (!serial_of(u->h, &dd, u->base.serial, sizeof u->base.serial) ||
                                    strcmp(u->base.serial, serial) != 0)) {
            libusb_close(u->h);
            u->h = NULL;
            continue;
        }
        snprintf(u->base.path, sizeof u->base.path, "usb:%u-%u:%d", libusb_get_bus_number(list[i]),
                 libusb_get_device_address(list[i]), u->iface);
        if (dd.iProduct)
            libusb_get_string_descriptor_ascii(u->h, dd.iProduct, (unsigned char *)u->base.name,
                                               (int)sizeof u->base.name);
    }
    if (list) libusb_free_device_list(list, 1);
    list = NULL;
    if (!u->h) {
        if (r == FV_ERR_NOT_FOUND)
            FV_ERROR(MOD, "usb %04x:%04x%s%s: no such HID device is attached", vid, pid,
                     serial && serial[0] ? " serial " : "", serial && serial[0] ? serial : "");
        goto fail;
    }
    u->base.vid = vid;
    u->base.pid = pid;
    /* Detach the kernel's usbhid for the time we hold the interface (reattached on release). */
    libusb_set_auto_detach_kernel_driver(u->h, 1);
    rc = libusb_claim_interface(u->h, u->iface);
    if (rc != 0) {
        r = map_err(u, rc, "claim interface");
        goto fail;
    }
    u->claimed = true;
    *out = &u->base;
    return FV_OK;
fail:
    if (list) libusb_free_device_list(list, 1);
    usb_destroy(&u->base);
    return r;
}

static fv_result usb_probe(fv_device_info *out, size_t cap, size_t *out_count)
{
    *out_count = 0;
    libusb_context *ctx;
    int rc = libusb_init(&ctx);
    if (rc != 0) {
        FV_INFO(MOD, "libusb unavailable (%s): no USB devices listed", libusb_error_name(rc));
        return FV_OK;
    }
    libusb_device **list = NULL;
    ssize_t n = libusb_get_device_list(ctx, &list);
    size_t found = 0;
    for (ssize_t i = 0; i < n; i++) {
        struct libusb_device_descriptor dd;
        int iface;
        uint8_t ep;
        uint16_t dlen;
        if (libusb_get_device_descriptor(list[i], &dd) != 0) continue;
        const fv_hid_quirk *q = fv_hid_quirk_find(dd.idVendor, dd.idProduct);
        if (!q || !q->eye_tracker || !find_hid_interface(list[i], &iface, &ep, &dlen)) continue;
        if (found < cap) {
            fv_device_info *info = &out[found];
            memset(info, 0, sizeof *info);
            snprintf(info->uri, sizeof info->uri, "usb:%04x:%04x", dd.idVendor, dd.idProduct);
            snprintf(info->name, sizeof info->name, "%s", q->name);
            snprintf(info->driver, sizeof info->driver, "usb");
            snprintf(info->detail, sizeof info->detail, "bus %u address %u interface %d, quirks table",
                     libusb_get_bus_number(list[i]), libusb_get_device_address(list[i]), iface);
        }
        found++;
    }
    if (n >= 0 && list) libusb_free_device_list(list, 1);
    libusb_exit(ctx);
    *out_count = found;
    return FV_OK;
}

static fv_result usb_open(const char *uri, const fv_device_open_desc *desc, fv_device **out)
{
    fv_hid_uri u;
    FV_TRY(fv_hid_uri_parse(uri, "usb", &u));
    if (u.kind == FV_HID_URI_PATH) {
        FV_ERROR(MOD, "'%s': usb: URIs take auto or VID:PID[:serial], not a path", uri);
        return FV_ERR_PARSE;
    }
    if (u.kind == FV_HID_URI_AUTO) {
        fv_device_info info[1];
        size_t count = 0;
        FV_TRY(usb_probe(info, 1, &count));
        if (count == 0) {
            FV_ERROR(MOD, "'%s': no known USB eye tracker is attached", uri);
            return FV_ERR_NOT_FOUND;
        }
        FV_TRY(fv_hid_uri_parse(info[0].uri, "usb", &u));
    }
    fv_hid_transport *t = NULL;
    FV_TRY(fv_usb_transport_open(u.vid, u.pid, u.serial, &t));
    fv_hid_device_desc hd = {.clock = desc ? desc->clock : NULL, .uri = uri};
    return fv_hid_device_open_transport(t, &hd, out);
}

const fv_driver fv_usb_driver = {
    .scheme = "usb",
    .summary = "HID-class eye trackers through libusb (when hidraw is not usable)",
    .probe = usb_probe,
    .open = usb_open,
};
