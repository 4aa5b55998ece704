/* @brief The "trace" driver: a recorded gaze file replayed as a device. Samples come out when the injected clock
 * reaches their recorded time (relative to the first read), divided by the speed; with a simulated clock the
 * replay is stepped deterministically (a read with a timeout jumps the clock to the next sample). t_host_ns is the
 * sample's due time on that clock; t_device_ns is the recorded time, scaled by the speed and continued across loops
 * so that it never goes back. Every time difference and sum saturates (fv_stats.h): a file can put its timestamps
 * anywhere in int64, and a replay clock can be anywhere too. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_stats.h"
#include "fv_trace.h"
#include "fv_trace_driver.h"

#define PRE_N 64 /* samples read ahead at open to estimate the nominal rate */

typedef struct trace_device {
    fv_device base; /* first member */
    fv_trace_reader *reader;
    const fv_clock *clock;
    double speed;
    bool loop;
    bool started, ended, have_first;
    int64_t t0_host_ns;    /* host time of the first read */
    int64_t first_file_ns; /* file time of the first sample */
    int64_t last_file_ns;  /* file time of the latest sample read from the file */
    int64_t loop_offset_ns;
    int64_t period_ns;     /* median interval of the first samples: the pause between two loops */
    fv_gaze_sample pre[PRE_N];
    size_t pre_n, pre_i;
    fv_gaze_sample pending;
    bool have_pending;
    int64_t pending_due_ns;
    int64_t last_rel_ns;   /* replay time of the latest sample: never goes back */
    int64_t last_device_ns; /* t_device_ns handed out last: never goes back */
} trace_device;

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* Next sample from the read-ahead, then the file; loops when asked. */
static fv_result next_file_sample(trace_device *d, fv_gaze_sample *out)
{
    if (d->pre_i < d->pre_n) {
        *out = d->pre[d->pre_i++];
        return FV_OK;
    }
    fv_result r = fv_trace_reader_next(d->reader, out);
    if (r == FV_END_OF_STREAM && d->loop && d->have_first) {
        FV_TRY(fv_trace_reader_rewind(d->reader));
        d->loop_offset_ns = fv_i64_add_sat(
            d->loop_offset_ns, fv_i64_add_sat(fv_i64_sub_sat(d->last_file_ns, d->first_file_ns), d->period_ns));
        r = fv_trace_reader_next(d->reader, out); /* file time; fetch() applies the loop offset */
    }
    return r;
}

static fv_result fetch(trace_device *d)
{
    fv_gaze_sample s;
    fv_result r = next_file_sample(d, &s);
    if (r != FV_OK) return r;
    if (!d->have_first) {
        d->first_file_ns = s.t_device_ns;
        d->have_first = true;
    }
    d->last_file_ns = s.t_device_ns;
    /* file time since the first sample, across loops, at the replay speed */
    int64_t rel = fv_i64_add_sat(fv_i64_sub_sat(s.t_device_ns, d->first_file_ns), d->loop_offset_ns);
    if (d->speed != 1.0) {
        double scaled = (double)rel / d->speed;
        rel = scaled >= 9.2e18 ? INT64_MAX : (scaled <= -9.2e18 ? INT64_MIN : (int64_t)llround(scaled));
    }
    if (rel < d->last_rel_ns) rel = d->last_rel_ns; /* the reader never goes back; nor does the replay */
    d->last_rel_ns = rel;
    /* at speed 1 the file's own time (plus the loops): exact even where rel saturated */
    int64_t dev = d->speed == 1.0 ? fv_i64_add_sat(s.t_device_ns, d->loop_offset_ns)
                                  : fv_i64_add_sat(d->first_file_ns, rel);
    if (dev < d->last_device_ns) dev = d->last_device_ns;
    d->last_device_ns = dev;
    s.t_device_ns = dev;
    d->pending = s;
    d->pending_due_ns = fv_i64_add_sat(d->t0_host_ns, rel);
    d->have_pending = true;
    return FV_OK;
}

static fv_result trace_read(fv_device *dev, fv_gaze_sample *out, size_t cap, size_t *out_count, int timeout_ms)
{
    trace_device *d = (trace_device *)dev;
    *out_count = 0;
    if (!out || cap == 0) return FV_ERR_INVALID_ARG;
    if (d->ended) return FV_END_OF_STREAM;
    int64_t now = fv_clock_now_ns(d->clock);
    if (!d->started) {
        d->started = true;
        d->t0_host_ns = now;
    }
    int64_t deadline = fv_i64_add_sat(now, timeout_ms > 0 ? (int64_t)timeout_ms * FV_NS_PER_MS : 0);
    size_t n = 0;
    for (;;) {
        if (!d->have_pending) {
            fv_result r = fetch(d);
            if (r == FV_END_OF_STREAM) {
                d->ended = true;
                *out_count = n;
                return n ? FV_OK : FV_END_OF_STREAM;
            }
            if (r != FV_OK) {
                *out_count = n;
                return n ? FV_OK : r; /* report the error on the next read */
            }
        }
        if (d->pending_due_ns <= now) {
            out[n] = d->pending;
            out[n].t_host_ns = d->pending_due_ns;
            out[n].flags |= FV_GAZE_HOST_TIME_VALID;
            d->have_pending = false;
            if (++n == cap) break;
            continue;
        }
        if (n > 0) break;
        if (d->pending_due_ns > deadline) {
            if (deadline > now) d->clock->sleep_until_ns(d->clock, deadline);
            return FV_TIMEOUT;
        }
        d->clock->sleep_until_ns(d->clock, d->pending_due_ns);
        now = fv_clock_now_ns(d->clock);
    }
    *out_count = n;
    return FV_OK;
}

static void trace_close(fv_device *dev)
{
    trace_device *d = (trace_device *)dev;
    if (!d) return;
    fv_trace_reader_destroy(&d->reader);
    free(d);
}

static const fv_device_ops g_ops = {trace_read, trace_close};

static fv_result trace_probe(fv_device_info *out, size_t cap, size_t *out_count)
{
    (void)out;
    (void)cap;
    *out_count = 0; /* recordings are opened by URI, not discovered */
    return FV_OK;
}

/* Parse "FILE[?k=v&k=v]" into the path and options. */
typedef struct trace_uri {
    char path[1024];
    char format[32];
    char blinks[1024];
    bool have_blinks;
    double speed;
    bool loop;
    double min_confidence;
    bool have_min_confidence;
} trace_uri;

static fv_result parse_uri(const char *uri, trace_uri *u)
{
    memset(u, 0, sizeof *u);
    u->speed = 1.0;
    const char *rest = uri;
    if (strncmp(rest, "trace:", 6) == 0) rest += 6;
    if (strncmp(rest, "//", 2) == 0) rest += 2; /* trace:///abs/path */
    const char *q = strrchr(rest, '?');
    if (q && !strchr(q, '=')) q = NULL; /* a '?' in the file name, not a query */
    size_t plen = q ? (size_t)(q - rest) : strlen(rest);
    if (plen == 0) {
        FV_ERROR("trace", "'%s': no file name (use trace:FILE[?speed=2&loop=1&format=NAME])", uri);
        return FV_ERR_INVALID_ARG;
    }
    if (plen >= sizeof u->path) {
        FV_ERROR("trace", "'%.64s...': file name too long", uri);
        return FV_ERR_INVALID_ARG;
    }
    memcpy(u->path, rest, plen);
    u->path[plen] = '\0';
    if (!q) return FV_OK;
    const char *p = q + 1;
    while (*p) {
        const char *amp = strchr(p, '&');
        size_t len = amp ? (size_t)(amp - p) : strlen(p);
        const char *eq = memchr(p, '=', len);
        char key[32], val[1024];
        size_t klen = eq ? (size_t)(eq - p) : len;
        size_t vlen = eq ? len - klen - 1 : 0;
        if (klen == 0 || klen >= sizeof key || vlen >= sizeof val) {
            FV_ERROR("trace", "'%s': malformed option '%.*s'", uri, (int)len, p);
            return FV_ERR_INVALID_ARG;
        }
        memcpy(key, p, klen);
        key[klen] = '\0';
        if (eq) memcpy(val, eq + 1, vlen);
        val[vlen] = '\0';
        char *end = NULL;
        if (strcmp(key, "speed") == 0) {
            u->speed = strtod(val, &end);
            if (!eq || end == val || *end || !(u->speed > 0.0 && u->speed <= 1000.0)) {
                FV_ERROR("trace", "'%s': speed '%s' must be a number in (0, 1000]", uri, val);
                return FV_ERR_INVALID_ARG;
            }
        } else if (strcmp(key, "loop") == 0) {
            if (!eq || strcmp(val, "1") == 0 || strcmp(val, "true") == 0) u->loop = true;
            else if (strcmp(val, "0") == 0 || strcmp(val, "false") == 0) u->loop = false;
            else {
                FV_ERROR("trace", "'%s': loop '%s' must be 0 or 1", uri, val);
                return FV_ERR_INVALID_ARG;
            }
        } else if (strcmp(key, "format") == 0) {
            snprintf(u->format, sizeof u->format, "%s", val);
        } else if (strcmp(key, "blinks") == 0) {
            snprintf(u->blinks, sizeof u->blinks, "%s", strcmp(val, "none") == 0 ? "" : val);
            u->have_blinks = true;
        } else if (strcmp(key, "min_confidence") == 0) {
            u->min_confidence = strtod(val, &end);
            if (!eq || end == val || *end || !(u->min_confidence >= -1.0 && u->min_confidence <= 1.0)) {
                FV_ERROR("trace", "'%s': min_confidence '%s' must be a number in [-1, 1] (-1 keeps all)", uri, val);
                return FV_ERR_INVALID_ARG;
            }
            u->have_min_confidence = true;
        } else {
            FV_ERROR("trace", "'%s': unknown option '%s' (known: speed, loop, format, blinks, min_confidence)", uri,
                     key);
            return FV_ERR_INVALID_ARG;
        }
        p += len + (amp ? 1 : 0);
    }
    return FV_OK;
}

fv_result fv_trace_replay_open(fv_trace_reader *reader, const fv_trace_replay_desc *desc, fv_device **out_dev)
{
    if (out_dev) *out_dev = NULL;
    if (!reader || !out_dev) {
        fv_trace_reader_destroy(&reader);
        return FV_ERR_INVALID_ARG;
    }
    static const fv_trace_replay_desc zero;
    if (!desc) desc = &zero;
    double speed = desc->speed == 0.0 ? 1.0 : desc->speed;
    if (!(speed > 0.0 && speed <= 1000.0)) {
        FV_ERROR("trace", "%s: speed %g must be in (0, 1000]", fv_trace_reader_name(reader), speed);
        fv_trace_reader_destroy(&reader);
        return FV_ERR_INVALID_ARG;
    }
    fv_result res = FV_OK;
    trace_device *d = calloc(1, sizeof *d);
    if (!d) {
        fv_trace_reader_destroy(&reader);
        return FV_ERR_NO_MEMORY;
    }
    d->base.ops = &g_ops;
    d->reader = reader;
    d->clock = desc->clock ? desc->clock : fv_clock_monotonic();
    d->speed = speed;
    d->loop = desc->loop != 0;
    d->last_device_ns = INT64_MIN;

    /* read ahead to learn the rate (and to fail early on a file with no samples at all) */
    int64_t dts[PRE_N];
    size_t ndt = 0;
    while (d->pre_n < PRE_N) {
        fv_result r = fv_trace_reader_next(d->reader, &d->pre[d->pre_n]);
        if (r == FV_END_OF_STREAM) break;
        if (r != FV_OK) {
            res = r;
            goto fail;
        }
        if (d->pre_n > 0) dts[ndt++] = fv_i64_sub_sat(d->pre[d->pre_n].t_device_ns, d->pre[d->pre_n - 1].t_device_ns);
        d->pre_n++;
    }
    const char *name = fv_trace_reader_name(d->reader);
    if (d->pre_n == 0) FV_WARN("trace", "%s: no samples in the file", name);
    if (ndt > 0) {
        qsort(dts, ndt, sizeof dts[0], cmp_i64);
        d->period_ns = dts[ndt / 2];
    }
    if (d->period_ns <= 0) d->period_ns = FV_NS_PER_MS;
    d->base.nominal_rate_hz = ndt ? 1e9 / (double)d->period_ns * d->speed : 0.0;
    snprintf(d->base.info.uri, sizeof d->base.info.uri, "%.255s", desc->uri ? desc->uri : name);
    const char *base = strrchr(name, '/');
    snprintf(d->base.info.name, sizeof d->base.info.name, "recorded gaze %.100s", base ? base + 1 : name);
    snprintf(d->base.info.driver, sizeof d->base.info.driver, "trace");
    snprintf(d->base.info.detail, sizeof d->base.info.detail, "format %s, speed %g%s",
             fv_trace_format_name(fv_trace_reader_format(d->reader)), d->speed, d->loop ? ", loop" : "");
    *out_dev = &d->base;
    return FV_OK;
fail:
    trace_close(&d->base);
    return res;
}

static fv_result trace_open(const char *uri, const fv_device_open_desc *desc, fv_device **out_dev)
{
    if (!uri || !out_dev) return FV_ERR_INVALID_ARG;
    *out_dev = NULL;
    trace_uri *u = malloc(sizeof *u);
    if (!u) return FV_ERR_NO_MEMORY;
    fv_result res = parse_uri(uri, u);
    if (res != FV_OK) goto done;
    fv_trace_reader_desc rd = {0};
    if (u->format[0] && fv_trace_format_parse(u->format, &rd.format) != FV_OK) {
        FV_ERROR("trace", "'%s': unknown format '%s' (known: fovea, pupil-core, pupil-cloud, sranipal, tobii-g3, "
                          "pico)", uri, u->format);
        res = FV_ERR_INVALID_ARG;
        goto done;
    }
    if (u->have_blinks) rd.blinks_path = u->blinks;
    if (u->have_min_confidence) rd.min_confidence = u->min_confidence == 0.0 ? -1e-9f : (float)u->min_confidence;
    fv_trace_reader *reader = NULL;
    res = fv_trace_reader_create(u->path, &rd, &reader);
    if (res != FV_OK) goto done;
    fv_trace_replay_desc rp = {
        .speed = u->speed, .loop = u->loop, .clock = desc ? desc->clock : NULL, .uri = uri};
    res = fv_trace_replay_open(reader, &rp, out_dev); /* owns the reader from here on */
done:
    free(u);
    return res;
}

uint64_t fv_trace_device_blink_events(const fv_device *dev)
{
    if (!dev || dev->ops != &g_ops) return 0;
    const trace_device *d = (const trace_device *)dev;
    return fv_trace_reader_get_stats(d->reader)->blink_events;
}

const fv_trace_reader_stats *fv_trace_device_reader_stats(const fv_device *dev)
{
    if (!dev || dev->ops != &g_ops) return NULL;
    return fv_trace_reader_get_stats(((const trace_device *)dev)->reader);
}

const fv_driver fv_trace_driver = {
    .scheme = "trace",
    .summary = "recorded gaze files (Pupil Core/Cloud, SRanipal, Tobii Glasses 3, Pico, fovea)",
    .probe = trace_probe,
    .open = trace_open,
};
