/* @brief The `hid` driver object: URI parsing, probing through hidapi enumeration, opening a hidraw node. */
#include "fv_hid_driver.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <wchar.h>

#include <hidapi.h>

#include "fv_hid_device.h"
#include "fv_hid_eyetracker.h"
#include "fv_log.h"

#define MOD "hid"

static bool parse_hex16(const char *s, size_t n, uint16_t *out)
{
    if (n >= 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
        s += 2;
        n -= 2;
    }
    if (n == 0 || n > 4) return false;
    unsigned v = 0;
    for (size_t i = 0; i < n; i++) {
        char c = s[i];
        int d = (c >= '0' && c <= '9') ? c - '0' : (c >= 'a' && c <= 'f') ? c - 'a' + 10 : (c >= 'A' && c <= 'F') ? c - 'A' + 10 : -1;
        if (d < 0) return false;
        v = v * 16u + (unsigned)d;
    }
    *out = (uint16_t)v;
    return true;
}

fv_result fv_hid_uri_parse(const char *uri, const char *scheme, fv_hid_uri *out)
{
    memset(out, 0, sizeof *out);
    size_t sl = strlen(scheme);
    if (!uri || strncmp(uri, scheme, sl) != 0 || uri[sl] != ':') {
        FV_ERROR(MOD, "'%s': not a %s: URI", uri ? uri : "(null)", scheme);
        return FV_ERR_PARSE;
    }
    const char *rest = uri + sl + 1;
    if (*rest == '\0' || strcmp(rest, "auto") == 0) {
        out->kind = FV_HID_URI_AUTO;
        return FV_OK;
    }
    if (rest[0] == '/') {
        if (strlen(rest) >= sizeof out->path) {
            FV_ERROR(MOD, "'%s': path too long", uri);
            return FV_ERR_PARSE;
        }
        out->kind = FV_HID_URI_PATH;
        snprintf(out->path, sizeof out->path, "%s", rest);
        return FV_OK;
    }
    const char *c1 = strchr(rest, ':');
    const char *c2 = c1 ? strchr(c1 + 1, ':') : NULL;
    size_t pid_len = c1 ? (c2 ? (size_t)(c2 - c1 - 1) : strlen(c1 + 1)) : 0;
    if (!c1 || !parse_hex16(rest, (size_t)(c1 - rest), &out->vid) || !parse_hex16(c1 + 1, pid_len, &out->pid)) {
        FV_ERROR(MOD, "'%s': expected %s:auto, %s:/dev/hidrawN or %s:VID:PID[:serial] with hex VID and PID", uri,
                 scheme, scheme, scheme);
        return FV_ERR_PARSE;
    }
    if (c2) {
        if (c2[1] == '\0' || strlen(c2 + 1) >= sizeof out->serial) {
            FV_ERROR(MOD, "'%s': empty or too long serial", uri);
            return FV_ERR_PARSE;
        }
        snprintf(out->serial, sizeof out->serial, "%s", c2 + 1);
    }
    out->kind = FV_HID_URI_VIDPID;
    return FV_OK;
}

static void narrow(const wchar_t *w, char *out, size_t cap)
{
    size_t i = 0;
    for (; w && w[i] && i + 1 < cap; i++) out[i] = (w[i] >= 32 && w[i] < 127) ? (char)w[i] : '?';
    out[i] = '\0';
}

/* Why a hidapi device entry is an eye tracker (NULL when it is not). */
static const char *eye_tracker_reason(const struct hid_device_info *d)
{
    if (d->usage_page == FV_HID_PAGE_EYE_HEAD_TRACKERS && d->usage == 0x01) return "usage page 0x12 (Eye Tracker)";
    const fv_hid_quirk *q = fv_hid_quirk_find(d->vendor_id, d->product_id);
    if (q && q->eye_tracker) return "quirks table";
    return NULL;
}

static bool serial_matches(const struct hid_device_info *d, const char *serial)
{
    if (!serial[0]) return true;
    char s[64];
    narrow(d->serial_number, s, sizeof s);
    return strcmp(s, serial) == 0;
}

static fv_result driver_probe(fv_device_info *out, size_t cap, size_t *out_count)
{
    *out_count = 0;
    if (hid_init() != 0) {
        FV_ERROR(MOD, "hidapi initialisation failed");
        return FV_ERR_IO;
    }
    struct hid_device_info *list = hid_enumerate(0, 0);
    size_t n = 0;
    for (struct hid_device_info *d = list; d; d = d->next) {
        const char *why = eye_tracker_reason(d);
        if (!why) continue;
        if (n < cap) {
            fv_device_info *info = &out[n];
            memset(info, 0, sizeof *info);
            snprintf(info->uri, sizeof info->uri, "hid:%s", d->path);
            narrow(d->product_string, info->name, sizeof info->name);
            if (!info->name[0]) snprintf(info->name, sizeof info->name, "HID eye tracker");
            snprintf(info->driver, sizeof info->driver, "hid");
            char serial[64];
            narrow(d->serial_number, serial, sizeof serial);
            snprintf(info->detail, sizeof info->detail, "%04x:%04x%s%s, %s", d->vendor_id, d->product_id,
                     serial[0] ? " serial " : "", serial, why);
        }
        n++;
    }
    hid_free_enumeration(list);
    *out_count = n;
    return FV_OK;
}

/* The hidraw path a URI names (auto: the first eye tracker; VID:PID[:serial]: the first such tracker). */
static fv_result resolve_path(const char *uri, const fv_hid_uri *u, char *path, size_t cap)
{
    if (u->kind == FV_HID_URI_PATH) {
        snprintf(path, cap, "%s", u->path);
        return FV_OK;
    }
    if (hid_init() != 0) {
        FV_ERROR(MOD, "hidapi initialisation failed");
        return FV_ERR_IO;
    }
    struct hid_device_info *list = hid_enumerate(u->kind == FV_HID_URI_VIDPID ? u->vid : 0,
                                                 u->kind == FV_HID_URI_VIDPID ? u->pid : 0);
    fv_result r = FV_ERR_NOT_FOUND;
    for (struct hid_device_info *d = list; d && r != FV_OK; d = d->next) {
        bool ok = u->kind == FV_HID_URI_VIDPID ? serial_matches(d, u->serial) : eye_tracker_reason(d) != NULL;
        if (ok) {
            snprintf(path, cap, "%s", d->path);
            r = FV_OK;
        }
    }
    hid_free_enumeration(list);
    if (r != FV_OK)
        FV_ERROR(MOD, "'%s': no %s is attached (hidraw sees none; try `fovea devices`)", uri,
                 u->kind == FV_HID_URI_AUTO ? "HID eye tracker" : "such HID device");
    return r;
}

static fv_result driver_open(const char *uri, const fv_device_open_desc *desc, fv_device **out)
{
    fv_hid_uri u;
    FV_TRY(fv_hid_uri_parse(uri, "hid", &u));
    char path[256];
    FV_TRY(resolve_path(uri, &u, path, sizeof path));
    fv_hid_transport *t = NULL;
    FV_TRY(fv_hid_hidapi_open_path(path, &t));
    char full[300];
    snprintf(full, sizeof full, "hid:%s", path);
    fv_hid_device_desc hd = {.clock = desc ? desc->clock : NULL, .uri = full};
    return fv_hid_device_open_transport(t, &hd, out);
}

const fv_driver fv_hid_driver = {
    .scheme = "hid",
    .summary = "HID eye trackers (usage page 0x12) on hidraw via hidapi",
    .probe = driver_probe,
    .open = driver_open,
};
