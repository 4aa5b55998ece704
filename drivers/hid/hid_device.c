/* @brief The HID eye-tracker device on a transport: open sequence (descriptor, features, mode request, drain) and the
 * read loop (timeout vs hang-up, tracking vs status reports, malformed reports skipped with a reason). */
#include "fv_hid_device.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_gaze_unwrap.h"
#include "fv_log.h"

#define MOD "hid"
#define REPORT_BUF 4097
#define DRAIN_MAX 65536 /* stale reports discarded at most at open (a flood never hangs the open) */
#define MALFORMED_LINES 5 /* malformed reports reported per window, then one summary (fv_log_ratelimit) */
#define MALFORMED_WINDOW_NS (30 * FV_NS_PER_S)

typedef struct hid_device {
    fv_device base; /* first: fv_device_close frees through ops */
    fv_hid_transport *transport;
    const fv_clock *clock;
    fv_hid_descriptor *desc;
    fv_hid_eyetracker_map map;
    fv_hid_screen_config screen;
    fv_gaze_unwrap unwrap;
    bool unwrap_on;
    fv_hid_device_stats stats;
    fv_log_ratelimit rl_malformed;
    uint64_t seq;
    bool lost;
    uint8_t buf[REPORT_BUF];
} hid_device;

static const fv_device_ops g_hid_device_ops;

static void log_malformed(hid_device *h, const char *why)
{
    /* Rate-limited over time, so a flood of bad reports cannot flood the log. */
    FV_WARN_RL(&h->rl_malformed, MOD, "%s: skipped report #%llu (%s); %llu skipped so far", h->base.info.uri,
               (unsigned long long)h->stats.reports, why, (unsigned long long)h->stats.malformed);
}

/* One input report → 0 or 1 sample. */
static bool handle_report(hid_device *h, const uint8_t *rep, size_t len, fv_gaze_sample *out)
{
    h->stats.reports++;
    uint8_t id = h->desc->uses_report_ids && len ? rep[0] : 0;
    if (id == h->map.tracking_id) {
        fv_result r = fv_hid_eyetracker_decode_tracking(h->desc, &h->map, &h->screen, rep, len, out);
        if (r != FV_OK) {
            h->stats.malformed++;
            log_malformed(h, "tracking report did not decode");
            return false;
        }
        out->t_host_ns = fv_clock_now_ns(h->clock);
        if (h->unwrap_on) {
            /* A timestamp narrower than 64 bits wraps: unwrap the raw count (decode gave raw * tick), checked
             * against the receipt time so a counter that wraps between reports is detected, not misread. */
            int64_t tick = h->unwrap.tick_ns > 0 ? h->unwrap.tick_ns : 1;
            out->t_device_ns =
                fv_gaze_unwrap_push_host(&h->unwrap, (uint64_t)(out->t_device_ns / tick), out->t_host_ns);
        }
        out->flags |= FV_GAZE_HOST_TIME_VALID;
        out->seq = ++h->seq;
        h->stats.samples++;
        return true;
    }
    if (h->map.status_config[1].field >= 0 && id == h->desc->fields[h->map.status_config[1].field].report_id) {
        fv_hid_status st;
        if (fv_hid_eyetracker_decode_status(h->desc, &h->map, FV_HID_REPORT_INPUT, rep, len, &st) == FV_OK) {
            h->stats.status_reports++;
            if (isfinite(st.sampling_frequency_hz) && st.sampling_frequency_hz > 0)
                h->base.nominal_rate_hz = st.sampling_frequency_hz;
            if (st.configuration_status != FV_HID_STATUS_READY && st.configuration_status >= 0)
                FV_INFO(MOD, "%s: tracker status %d (not ready)", h->base.info.uri, st.configuration_status);
            return false;
        }
    }
    h->stats.malformed++;
    char why[96];
    snprintf(why, sizeof why, "input report ID 0x%02x, %zu bytes, is neither tracking data nor status", id, len);
    log_malformed(h, why);
    return false;
}

static fv_result device_read(fv_device *dev, fv_gaze_sample *out, size_t cap, size_t *out_count, int timeout_ms)
{
    hid_device *h = (hid_device *)dev;
    *out_count = 0;
    if (h->lost) return FV_ERR_DEVICE_LOST;
    if (cap == 0) return FV_ERR_INVALID_ARG;
    size_t count = 0;
    int wait_ms = timeout_ms < 0 ? 0 : timeout_ms;
    /* The first read waits; then everything already queued is taken without waiting, up to cap. */
    for (int reads = 0; count < cap && reads < 4096; reads++) {
        size_t len = 0;
        fv_result r = h->transport->ops->read(h->transport, h->buf, sizeof h->buf, &len, reads == 0 ? wait_ms : 0);
        if (r == FV_TIMEOUT) break;
        if (r == FV_ERR_DEVICE_LOST) {
            h->lost = true;
            FV_WARN(MOD, "%s: device lost (hung up) after %llu samples", dev->info.uri,
                    (unsigned long long)h->stats.samples);
            if (count > 0) break; /* hand over what arrived; the next read reports the loss */
            return FV_ERR_DEVICE_LOST;
        }
        if (FV_FAILED(r)) {
            if (count > 0) break;
            return r;
        }
        if (len > 0 && handle_report(h, h->buf, len, &out[count])) count++;
    }
    *out_count = count;
    return count > 0 ? FV_OK : FV_TIMEOUT;
}

static void device_close(fv_device *dev)
{
    hid_device *h = (hid_device *)dev;
    if (!h) return;
    fv_log_ratelimit_flush(&h->rl_malformed);
    fv_hid_transport_destroy(&h->transport);
    free(h->desc);
    free(h);
}

static const fv_device_ops g_hid_device_ops = {device_read, device_close};

void fv_hid_device_get_stats(const fv_device *dev, fv_hid_device_stats *out)
{
    memset(out, 0, sizeof *out);
    if (!dev || dev->ops != &g_hid_device_ops) return;
    *out = ((const hid_device *)dev)->stats;
}

/* Features at open: all optional (a tracker may not answer them); each failure is logged at debug level. */
static void read_features(hid_device *h, bool size_configured)
{
    uint8_t buf[256];
    size_t len;
    fv_hid_transport *t = h->transport;
    h->stats.tracker_quality = -1;
    h->stats.calibrated_width_mm = NAN;
    h->stats.calibrated_height_mm = NAN;
    if (h->map.quality.field >= 0 &&
        t->ops->get_feature(t, h->desc->fields[h->map.quality.field].report_id, buf, sizeof buf, &len) == FV_OK) {
        fv_hid_capabilities caps;
        if (fv_hid_eyetracker_decode_capabilities(h->desc, &h->map, buf, len, &caps) == FV_OK)
            h->stats.tracker_quality = caps.tracker_quality;
    }
    if (h->map.calibrated_width.field >= 0 &&
        t->ops->get_feature(t, h->desc->fields[h->map.calibrated_width.field].report_id, buf, sizeof buf, &len) ==
            FV_OK) {
        fv_hid_configuration cfg;
        if (fv_hid_eyetracker_decode_configuration(h->desc, &h->map, buf, len, &cfg) == FV_OK) {
            h->stats.calibrated_width_mm = cfg.calibrated_width_mm;
            h->stats.calibrated_height_mm = cfg.calibrated_height_mm;
            if (!size_configured && isfinite(cfg.calibrated_width_mm) && isfinite(cfg.calibrated_height_mm) &&
                cfg.calibrated_width_mm > 0 && cfg.calibrated_height_mm > 0) {
                h->screen.width_mm = (float)cfg.calibrated_width_mm;
                h->screen.height_mm = (float)cfg.calibrated_height_mm;
            }
        }
    }
    if (h->map.status_frequency[0].field >= 0 &&
        t->ops->get_feature(t, h->desc->fields[h->map.status_frequency[0].field].report_id, buf, sizeof buf, &len) ==
            FV_OK) {
        fv_hid_status st;
        if (fv_hid_eyetracker_decode_status(h->desc, &h->map, FV_HID_REPORT_FEATURE, buf, len, &st) == FV_OK &&
            isfinite(st.sampling_frequency_hz) && st.sampling_frequency_hz > 0)
            h->base.nominal_rate_hz = st.sampling_frequency_hz;
    }
}

fv_result fv_hid_device_open_transport(fv_hid_transport *t, const fv_hid_device_desc *desc, fv_device **out)
{
    fv_result r = FV_OK;
    hid_device *h = NULL;
    if (!t || !out) {
        r = FV_ERR_INVALID_ARG;
        goto fail;
    }
    h = calloc(1, sizeof *h);
    if (h) fv_log_ratelimit_init(&h->rl_malformed, MALFORMED_LINES, MALFORMED_WINDOW_NS, desc ? desc->clock : NULL);
    if (!h || !(h->desc = calloc(1, sizeof *h->desc))) {
        r = FV_ERR_NO_MEMORY;
        goto fail;
    }
    h->base.ops = &g_hid_device_ops;
    h->transport = t;
    h->clock = desc && desc->clock ? desc->clock : fv_clock_monotonic();
    snprintf(h->base.info.driver, sizeof h->base.info.driver, "hid");
    if (desc && desc->uri) snprintf(h->base.info.uri, sizeof h->base.info.uri, "%s", desc->uri);
    else snprintf(h->base.info.uri, sizeof h->base.info.uri, "hid:%.250s", t->path);
    snprintf(h->base.info.name, sizeof h->base.info.name, "%s", t->name[0] ? t->name : "HID eye tracker");

    size_t dlen = 0;
    r = t->ops->get_descriptor(t, h->buf, sizeof h->buf, &dlen);
    if (FV_FAILED(r)) {
        FV_ERROR(MOD, "%s: cannot read the report descriptor (%s)", h->base.info.uri, fv_result_str(r));
        goto fail;
    }
    r = fv_hid_descriptor_parse(h->buf, dlen, h->desc);
    if (FV_FAILED(r)) goto fail;
    const fv_hid_quirk *quirk = fv_hid_quirk_find(t->vid, t->pid);
    r = fv_hid_eyetracker_map_init(h->desc, quirk, &h->map);
    if (FV_FAILED(r)) goto fail;
    snprintf(h->base.info.detail, sizeof h->base.info.detail, "%04x:%04x%s%s, tracking report 0x%02x%s", t->vid,
             t->pid, quirk ? ", quirk: " : "", quirk ? quirk->name : "", h->map.tracking_id,
             h->map.pupil[0].field >= 0 ? ", vendor pupil" : "");

    if (desc && desc->screen) h->screen = *desc->screen;
    else fv_hid_screen_config_defaults(&h->screen);
    bool size_configured = h->screen.width_mm > 0 && h->screen.height_mm > 0;
    read_features(h, size_configured);

    const fv_hid_field *tf = &h->desc->fields[h->map.timestamp.field];
    uint64_t ts_bits = (tf->usage_total == 1 && tf->count > 1) ? (uint64_t)tf->count * tf->bit_size : tf->bit_size;
    if (ts_bits < 64) {
        double k;
        int64_t tick = fv_hid_unit_time_to_ns(tf->unit, tf->unit_exponent, &k) && k >= 1.0 ? (int64_t)llround(k) : 1000;
        r = fv_gaze_unwrap_init(&h->unwrap, (unsigned)ts_bits, tick);
        if (FV_FAILED(r)) goto fail;
        h->unwrap.label = h->base.info.uri;
        h->unwrap_on = true;
    }

    /* The host must write the Device Mode Request before any gaze flows. */
    if (h->map.mode_request.field >= 0) {
        uint8_t req[64];
        size_t rlen;
        unsigned mode = desc && desc->mode ? desc->mode : FV_HID_MODE_ALL;
        r = fv_hid_eyetracker_encode_mode_request(h->desc, &h->map, mode, req, sizeof req, &rlen);
        if (FV_FAILED(r)) goto fail;
        r = t->ops->set_feature(t, req, rlen);
        if (FV_FAILED(r)) {
            FV_ERROR(MOD, "%s: writing the Device Mode Request failed (%s)", h->base.info.uri, fv_result_str(r));
            goto fail;
        }
    } else {
        FV_WARN(MOD, "%s: no Control report; gaze may not flow", h->base.info.uri);
    }

    /* Drain what was buffered before now: those samples are stale. */
    for (int i = 0; i < DRAIN_MAX; i++) {
        size_t len = 0;
        fv_result rr = t->ops->read(t, h->buf, sizeof h->buf, &len, 0);
        if (rr != FV_OK) {
            if (rr == FV_ERR_DEVICE_LOST) {
                r = rr;
                FV_ERROR(MOD, "%s: device lost while opening", h->base.info.uri);
                goto fail;
            }
            break;
        }
        h->stats.drained_at_open++;
    }
    if (h->stats.drained_at_open)
        FV_DEBUG(MOD, "%s: drained %llu stale reports at open", h->base.info.uri,
                 (unsigned long long)h->stats.drained_at_open);
    *out = &h->base;
    return FV_OK;

fail:
    if (h) {
        device_close(&h->base);
    } else {
        fv_hid_transport_destroy(&t);
    }
    return r;
}
