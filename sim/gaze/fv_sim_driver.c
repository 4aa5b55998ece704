/* @brief The "sim" driver (see fv_sim_driver.h). */
#include "fv_sim_driver.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_gaze_unwrap.h"
#include "fv_log.h"

#define TRUTH_CAP 4096

typedef struct sim_device {
    fv_device base; /* first member */
    fv_sim_eye *eye;
    const fv_clock *clock;
    int64_t host_origin_ns;
    bool have_pending;
    fv_gaze_sample pending;
    fv_sim_truth pending_truth;
    unsigned ts_bits;
    fv_gaze_unwrap unwrap;
    fv_sim_truth truth[TRUTH_CAP];
    uint64_t truth_seq[TRUTH_CAP];
    bool truth_used[TRUTH_CAP];
} sim_device;

static const fv_device_ops g_sim_ops;

/* ---- URI ---- */

typedef enum kind { K_F64, K_U64, K_BOOL, K_BITS } kind;
typedef struct key {
    const char *name;
    kind k;
    size_t off;
} key;

#define F(name) {#name, K_F64, offsetof(fv_sim_eye_desc, name)}
static const key g_keys[] = {
    {"seed", K_U64, offsetof(fv_sim_eye_desc, seed)},
    F(rate_hz), F(jitter_us), F(latency_ms), F(transport_jitter_ms), F(dropout), F(eye_loss), F(precision_deg),
    F(accuracy_deg), F(blink_per_min), F(pursuit_prob),
    {"microsaccades", K_BOOL, offsetof(fv_sim_eye_desc, microsaccades)},
    F(skew_ppm), F(device_offset_s), F(ipd_mm), F(vmax_deg_s), F(c_deg), F(main_seq_spread),
    {"ts_bits", K_BITS, 0},
};
#undef F

static void known_keys(char *buf, size_t n)
{
    buf[0] = '\0';
    for (size_t i = 0; i < sizeof g_keys / sizeof g_keys[0]; i++) {
        if (i) strncat(buf, ",", n - strlen(buf) - 1);
        strncat(buf, g_keys[i].name, n - strlen(buf) - 1);
    }
}

fv_result fv_sim_driver_parse_uri(const char *uri, fv_sim_eye_desc *out, unsigned *out_ts_bits)
{
    fv_sim_eye_desc d;
    fv_sim_eye_desc_defaults(&d);
    unsigned bits = 0;
    if (!uri || strncmp(uri, "sim:", 4) != 0) {
        FV_ERROR("sim", "'%s': not a sim: URI", uri ? uri : "(null)");
        return FV_ERR_PARSE;
    }
    char buf[512];
    if (strlen(uri + 4) >= sizeof buf) {
        FV_ERROR("sim", "'%.40s...': URI longer than %zu characters", uri, sizeof buf - 1);
        return FV_ERR_PARSE;
    }
    strcpy(buf, uri + 4);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",&?", &save); tok; tok = strtok_r(NULL, ",&?", &save)) {
        char *eq = strchr(tok, '=');
        if (!eq) {
            FV_ERROR("sim", "'%s': option '%s' is not key=value", uri, tok);
            return FV_ERR_PARSE;
        }
        *eq = '\0';
        const char *val = eq + 1;
        const key *k = NULL;
        for (size_t i = 0; i < sizeof g_keys / sizeof g_keys[0]; i++)
            if (strcmp(g_keys[i].name, tok) == 0) k = &g_keys[i];
        if (!k) {
            char known[400];
            known_keys(known, sizeof known);
            FV_ERROR("sim", "'%s': unknown key '%s' (known: %s)", uri, tok, known);
            return FV_ERR_PARSE;
        }
        char *end = NULL;
        errno = 0;
        if (k->k == K_F64) {
            double v = strtod(val, &end);
            if (!*val || *end || errno || !isfinite(v)) {
                FV_ERROR("sim", "'%s': %s='%s' is not a number", uri, tok, val);
                return FV_ERR_PARSE;
            }
            memcpy((char *)&d + k->off, &v, sizeof v);
        } else if (k->k == K_U64 || k->k == K_BITS) {
            unsigned long long v = strtoull(val, &end, 10);
            if (!*val || *end || errno || val[0] == '-') {
                FV_ERROR("sim", "'%s': %s='%s' is not a non-negative integer", uri, tok, val);
                return FV_ERR_PARSE;
            }
            if (k->k == K_U64) {
                d.seed = (uint64_t)v;
            } else {
                if (v != 0 && (v < 8 || v > 63)) {
                    FV_ERROR("sim", "'%s': ts_bits=%llu must be 0 (64-bit ns) or 8..63", uri, v);
                    return FV_ERR_RANGE;
                }
                bits = (unsigned)v;
            }
        } else {
            bool b;
            if (strcmp(val, "1") == 0 || strcmp(val, "true") == 0 || strcmp(val, "on") == 0) b = true;
            else if (strcmp(val, "0") == 0 || strcmp(val, "false") == 0 || strcmp(val, "off") == 0) b = false;
            else {
                FV_ERROR("sim", "'%s': %s='%s' is not a boolean (0/1/true/false/on/off)", uri, tok, val);
                return FV_ERR_PARSE;
            }
            memcpy((char *)&d + k->off, &b, sizeof b);
        }
    }
    *out = d;
    if (out_ts_bits) *out_ts_bits = bits;
    return FV_OK;
}

/* ---- device ---- */

static fv_result probe(fv_device_info *out, size_t cap, size_t *out_count)
{
    if (cap >= 1 && out) {
        memset(&out[0], 0, sizeof out[0]);
        snprintf(out[0].uri, sizeof out[0].uri, "sim:seed=1");
        snprintf(out[0].name, sizeof out[0].name, "fovea simulated eye");
        snprintf(out[0].driver, sizeof out[0].driver, "sim");
        snprintf(out[0].detail, sizeof out[0].detail,
                 "always available; 120 Hz, 4 ms latency, blinks, saccades, pursuit (keys: see 'fovea gaze --help')");
    }
    *out_count = 1;
    return FV_OK;
}

static fv_result sim_open(const char *uri, const fv_device_open_desc *desc, fv_device **out_dev)
{
    if (!out_dev) return FV_ERR_INVALID_ARG;
    *out_dev = NULL;
    fv_sim_eye_desc ed;
    unsigned bits = 0;
    fv_result r = fv_sim_driver_parse_uri(uri, &ed, &bits);
    if (r != FV_OK) return r;
    sim_device *d = calloc(1, sizeof *d);
    if (!d) return FV_ERR_NO_MEMORY;
    r = fv_sim_eye_create(&ed, &d->eye);
    if (r != FV_OK) {
        FV_ERROR("sim", "'%s': cannot create the simulated eye (%s)", uri, fv_result_str(r));
        goto fail;
    }
    d->ts_bits = bits;
    if (bits) {
        /* A counter that wraps before two samples have passed leaves the number of wraps between samples to guess:
         * refuse it rather than invent a timeline (real devices are checked against the host clock instead). */
        double wrap_ms = ldexp(1.0, (int)bits) / 1000.0, interval_ms = 1000.0 / ed.rate_hz;
        if (wrap_ms < 2.0 * interval_ms) {
            unsigned need = bits;
            while (ldexp(1.0, (int)need) / 1000.0 < 2.0 * interval_ms) need++;
            FV_ERROR("sim", "'%s': ts_bits=%u (a microsecond counter) wraps every %.3f ms, faster than twice the "
                     "sample interval at rate_hz=%g (2 x %.3f ms), so its timestamps cannot be unwrapped; use "
                     "ts_bits=%u or more, or 0", uri, bits, wrap_ms, ed.rate_hz, interval_ms, need);
            r = FV_ERR_RANGE;
            goto fail;
        }
        r = fv_gaze_unwrap_init(&d->unwrap, bits, 1000);
        if (r != FV_OK) goto fail;
    }
    d->base.ops = &g_sim_ops;
    snprintf(d->base.info.uri, sizeof d->base.info.uri, "%s", uri);
    d->unwrap.label = d->base.info.uri;
    snprintf(d->base.info.name, sizeof d->base.info.name, "fovea simulated eye (seed %llu)",
             (unsigned long long)ed.seed);
    snprintf(d->base.info.driver, sizeof d->base.info.driver, "sim");
    snprintf(d->base.info.detail, sizeof d->base.info.detail, "%.0f Hz, latency %.1f ms, ts_bits %u", ed.rate_hz,
             ed.latency_ms, bits);
    d->base.nominal_rate_hz = ed.rate_hz;
    d->clock = desc && desc->clock ? desc->clock : fv_clock_monotonic();
    d->host_origin_ns = fv_clock_now_ns(d->clock);
    *out_dev = &d->base;
    return FV_OK;
fail:
    fv_sim_eye_destroy(&d->eye);
    free(d);
    return r;
}

static fv_result fill_pending(sim_device *d)
{
    if (d->have_pending) return FV_OK;
    fv_result r = fv_sim_eye_next(d->eye, &d->pending, &d->pending_truth);
    if (r != FV_OK) return r;
    /* simulation time → host clock */
    d->pending.t_host_ns += d->host_origin_ns;
    if (d->ts_bits) {
        /* the device sends a ts_bits-wide µs counter; unwrap it as a real driver would, against the receipt */
        uint64_t raw = (uint64_t)(d->pending.t_device_ns / 1000);
        d->pending.t_device_ns = fv_gaze_unwrap_push_host(&d->unwrap, raw, d->pending.t_host_ns);
    }
    d->have_pending = true;
    return FV_OK;
}

static fv_result sim_read(fv_device *dev, fv_gaze_sample *out, size_t cap, size_t *out_count, int timeout_ms)
{
    sim_device *d = (sim_device *)dev;
    *out_count = 0;
    if (!out || cap == 0) return FV_ERR_INVALID_ARG;
    bool waited = false;
    for (;;) {
        int64_t now = fv_clock_now_ns(d->clock);
        while (*out_count < cap) {
            FV_TRY(fill_pending(d));
            if (d->pending.t_host_ns > now) break;
            out[*out_count] = d->pending;
            size_t slot = (size_t)(d->pending.seq % TRUTH_CAP);
            d->truth[slot] = d->pending_truth;
            d->truth_seq[slot] = d->pending.seq;
            d->truth_used[slot] = true;
            d->have_pending = false;
            (*out_count)++;
        }
        if (*out_count > 0) return FV_OK;
        if (waited || timeout_ms <= 0) return FV_TIMEOUT;
        int64_t until = now + (int64_t)timeout_ms * FV_NS_PER_MS;
        if (d->pending.t_host_ns < until) until = d->pending.t_host_ns;
        d->clock->sleep_until_ns(d->clock, until);
        waited = true;
    }
}

static void sim_close(fv_device *dev)
{
    sim_device *d = (sim_device *)dev;
    if (!d) return;
    fv_sim_eye_destroy(&d->eye);
    free(d);
}

static const fv_device_ops g_sim_ops = {sim_read, sim_close};

const fv_driver fv_sim_driver = {
    .scheme = "sim",
    .summary = "simulated eye (seeded; saccades, pursuit, blinks, noise, latency)",
    .probe = probe,
    .open = sim_open,
};

fv_sim_eye *fv_sim_device_eye(fv_device *dev)
{
    if (!dev || dev->ops != &g_sim_ops) return NULL;
    return ((sim_device *)dev)->eye;
}

int64_t fv_sim_device_host_origin_ns(const fv_device *dev)
{
    if (!dev || dev->ops != &g_sim_ops) return 0;
    return ((const sim_device *)dev)->host_origin_ns;
}

bool fv_sim_device_truth(const fv_device *dev, uint64_t seq, fv_sim_truth *out)
{
    if (!dev || dev->ops != &g_sim_ops) return false;
    const sim_device *d = (const sim_device *)dev;
    size_t slot = (size_t)(seq % TRUTH_CAP);
    if (!d->truth_used[slot] || d->truth_seq[slot] != seq) return false;
    *out = d->truth[slot];
    return true;
}
