/* @brief hidapi (hidraw backend) transport. The report descriptor comes from the hidraw HIDIOCGRDESC ioctl on the
 * same node, since hidapi 0.13 has no hid_get_report_descriptor. */
#include <errno.h>
#include <fcntl.h>
#include <linux/hidraw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>
#include <wchar.h>

#include <hidapi.h>

#include "fv_hid_transport.h"
#include "fv_log.h"

#define MOD "hid"

typedef struct hidapi_transport {
    fv_hid_transport base;
    hid_device *dev;
    int lost;
} hidapi_transport;

static void wide_to_utf8ish(const wchar_t *w, char *out, size_t cap)
{
    size_t i = 0;
    for (; w && w[i] && i + 1 < cap; i++) out[i] = (w[i] >= 32 && w[i] < 127) ? (char)w[i] : '?';
    out[i] = '\0';
}

static fv_result hidapi_get_descriptor(fv_hid_transport *t, uint8_t *buf, size_t cap, size_t *out_len)
{
    int fd = open(t->path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        FV_ERROR(MOD, "%s: cannot open for HIDIOCGRDESC: %s", t->path, strerror(errno));
        return errno == ENOENT ? FV_ERR_DEVICE_LOST : FV_ERR_IO;
    }
    int size = 0;
    fv_result r = FV_OK;
    struct hidraw_report_descriptor rd;
    memset(&rd, 0, sizeof rd);
    if (ioctl(fd, HIDIOCGRDESCSIZE, &size) < 0 || size <= 0 || size > HID_MAX_DESCRIPTOR_SIZE) {
        FV_ERROR(MOD, "%s: HIDIOCGRDESCSIZE failed: %s", t->path, size <= 0 ? strerror(errno) : "bad size");
        r = FV_ERR_IO;
        goto done;
    }
    rd.size = (uint32_t)size;
    if (ioctl(fd, HIDIOCGRDESC, &rd) < 0) {
        FV_ERROR(MOD, "%s: HIDIOCGRDESC failed: %s", t->path, strerror(errno));
        r = FV_ERR_IO;
        goto done;
    }
    if ((size_t)size > cap) {
        r = FV_ERR_RANGE;
        goto done;
    }
    memcpy(buf, rd.value, (size_t)size);
    *out_len = (size_t)size;
done:
    close(fd);
    return r;
}

static fv_result hidapi_read(fv_hid_transport *t, uint8_t *buf, size_t cap, size_t *out_len, int timeout_ms)
{
    hidapi_transport *h = (hidapi_transport *)t;
    *out_len = 0;
    if (h->lost) return FV_ERR_DEVICE_LOST;
    int n = hid_read_timeout(h->dev, buf, cap, timeout_ms);
    if (n > 0) {
        *out_len = (size_t)n;
        return FV_OK;
    }
    if (n == 0) return FV_TIMEOUT;
    /* hidapi's hidraw backend returns -1 on POLLHUP/POLLERR/ENODEV: the node went away (unplug). */
    char err[128];
    wide_to_utf8ish(hid_error(h->dev), err, sizeof err);
    FV_ERROR(MOD, "%s: read failed (%s): device lost", t->path, err[0] ? err : "unknown error");
    h->lost = 1;
    return FV_ERR_DEVICE_LOST;
}

static fv_result hidapi_get_feature(fv_hid_transport *t, uint8_t id, uint8_t *buf, size_t cap, size_t *out_len)
{
    hidapi_transport *h = (hidapi_transport *)t;
    if (cap == 0) return FV_ERR_INVALID_ARG;
    buf[0] = id;
    int n = hid_get_feature_report(h->dev, buf, cap);
    if (n < 0) {
        char err[128];
        wide_to_utf8ish(hid_error(h->dev), err, sizeof err);
        FV_ERROR(MOD, "%s: GET_REPORT(Feature 0x%02x) failed: %s", t->path, id, err);
        return FV_ERR_IO;
    }
    *out_len = (size_t)n;
    return FV_OK;
}

static fv_result hidapi_set_feature(fv_hid_transport *t, const uint8_t *buf, size_t len)
{
    hidapi_transport *h = (hidapi_transport *)t;
    if (hid_send_feature_report(h->dev, buf, len) < 0) {
        char err[128];
        wide_to_utf8ish(hid_error(h->dev), err, sizeof err);
        FV_ERROR(MOD, "%s: SET_REPORT(Feature 0x%02x) failed: %s", t->path, len ? buf[0] : 0, err);
        return FV_ERR_IO;
    }
    return FV_OK;
}

static void hidapi_destroy(fv_hid_transport *t)
{
    hidapi_transport *h = (hidapi_transport *)t;
    if (h->dev) hid_close(h->dev);
    free(h);
}

static const fv_hid_transport_ops g_hidapi_ops = {
    hidapi_get_descriptor, hidapi_read, hidapi_get_feature, hidapi_set_feature, hidapi_destroy,
};

fv_result fv_hid_hidapi_open_path(const char *path, fv_hid_transport **out)
{
    if (!path || !out) return FV_ERR_INVALID_ARG;
    if (hid_init() != 0) {
        FV_ERROR(MOD, "hidapi initialisation failed");
        return FV_ERR_IO;
    }
    if (access(path, F_OK) != 0) {
        FV_ERROR(MOD, "%s: no such device", path);
        return FV_ERR_NOT_FOUND;
    }
    hidapi_transport *h = calloc(1, sizeof *h);
    if (!h) return FV_ERR_NO_MEMORY;
    h->base.ops = &g_hidapi_ops;
    snprintf(h->base.path, sizeof h->base.path, "%s", path);
    h->dev = hid_open_path(path);
    if (!h->dev) {
        int e = errno;
        FV_ERROR(MOD, "%s: cannot open: %s%s", path, strerror(e),
                 e == EACCES ? " (add a udev rule granting access to the hidraw node, see docs/hid.md)" : "");
        free(h);
        return FV_ERR_IO;
    }
    struct hid_device_info *info = hid_get_device_info(h->dev);
    if (info) {
        h->base.vid = info->vendor_id;
        h->base.pid = info->product_id;
        wide_to_utf8ish(info->product_string, h->base.name, sizeof h->base.name);
        wide_to_utf8ish(info->serial_number, h->base.serial, sizeof h->base.serial);
    }
    *out = &h->base;
    return FV_OK;
}
