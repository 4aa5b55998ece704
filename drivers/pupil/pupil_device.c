/* @brief The `pupil` driver's I/O: Pupil Remote requests (REQ, one fresh socket per exchange so a lost reply never
 * wedges the REQ state machine), the gaze subscription (SUB, topic "gaze."), clock synchronisation with Pupil time
 * (the `t` request; offset from the exchange with the shortest round trip, host = pupil + offset, redone every
 * 10 s), and reconnection when Capture goes away or restarts on a new SUB port. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <zmq.h>

#include "fv_log.h"
#include "fv_pupil_driver.h"

#define MOD "pupil"
#define SYNC_EXCHANGES 6
#define RESYNC_NS (10 * FV_NS_PER_S)
#define MIN_RESYNC_NS FV_NS_PER_S /* a clock jump resynchronises at most this often */
#define JUMP_NS FV_NS_PER_S       /* a sample mapped further than this from its receipt: the Pupil clock jumped */
#define SILENCE_CHECK_NS FV_NS_PER_S /* ask Pupil Remote after this long without gaze */
#define CHECK_TIMEOUT_MS 300
#define PROBE_TIMEOUT_MS 200
/* Gaze messages queued unread at most: 5 s of Capture's 200 Hz binocular stream. With frames of FV_PUPIL_MAX_PAYLOAD
 * at most, two-frame messages fill it with 128 MiB at worst (1 GiB at 8192). libzmq bounds neither the frames of one
 * multipart message nor their total: a peer sending endless parts of one message is not bounded here. */
#define RCV_HWM 1024
#define SKIP_PER_READ 256 /* malformed messages one read skips at most beyond cap: a flood cannot hold the reader */
/* Rate limits of the repeated warnings (fv_log_ratelimit): lines per window, then one summary per window. */
#define MALFORMED_LINES 20
#define JUMP_LINES 3
#define SYNC_LINES 3
#define WARN_WINDOW_NS (30 * FV_NS_PER_S)
#define ECHO_BYTES 32 /* bytes of a peer's answer or topic quoted in a log line */

typedef struct pupil_dev {
    fv_device base;
    fv_pupil_uri uri;
    const fv_clock *clock;
    void *ctx, *sub;
    int sub_port;
    bool synced;
    int64_t offset_ns; /* host = pupil + offset */
    int64_t last_msg_ns, last_check_ns, last_sync_ns;
    bool lost_warned, silent_warned, resubscribed, jumped;
    uint64_t malformed, seq;
    fv_log_ratelimit rl_malformed, rl_jump, rl_sync, rl_offset;
} pupil_dev;

/* Bytes from the peer for a log line: printable ASCII as it is, anything else as \xNN, at most ECHO_BYTES of them,
 * "..." when there were more (total: the length the peer sent; n: the bytes at hand). */
static const char *quote(const char *p, size_t n, size_t total, char *out, size_t cap)
{
    size_t o = 0;
    for (size_t i = 0; i < n && i < ECHO_BYTES && o + 5 < cap; i++) {
        unsigned char c = (unsigned char)p[i];
        if (c >= 0x20 && c < 0x7f && c != '\\') out[o++] = (char)c;
        else o += (size_t)snprintf(out + o, cap - o, "\\x%02x", c);
    }
    if (total > ECHO_BYTES && o + 4 < cap) memcpy(out + o, "...", 3), o += 3;
    out[o] = '\0';
    return out;
}

/* Every socket: no linger, and no frame from the peer larger than a gaze payload: libzmq drops the connection at
 * such a frame's header instead of allocating what the peer says (for good: check_capture subscribes again). */
static void set_common(void *s)
{
    int zero = 0;
    int64_t max = FV_PUPIL_MAX_PAYLOAD;
    zmq_setsockopt(s, ZMQ_LINGER, &zero, sizeof zero);
    zmq_setsockopt(s, ZMQ_MAXMSGSIZE, &max, sizeof max);
}

/* One request/reply exchange on a REQ socket that is already connected. The reply is cut to cap - 1 bytes;
 * *reply_len (optional) is the length Pupil Remote sent. */
static fv_result exchange(void *req, const char *msg, char *reply, size_t cap, size_t *reply_len, int timeout_ms)
{
    if (zmq_send(req, msg, strlen(msg), 0) < 0) return FV_ERR_IO;
    zmq_pollitem_t it = {req, 0, ZMQ_POLLIN, 0};
    int rc = zmq_poll(&it, 1, timeout_ms);
    if (rc < 0) return errno == EINTR ? FV_TIMEOUT : FV_ERR_IO;
    if (rc == 0) return FV_TIMEOUT;
    int n = zmq_recv(req, reply, cap - 1, ZMQ_DONTWAIT);
    if (n < 0) return FV_ERR_IO;
    reply[(size_t)n < cap - 1 ? (size_t)n : cap - 1] = '\0';
    if (reply_len) *reply_len = (size_t)n;
    return FV_OK;
}

static void *req_open(void *ctx, const char *host, int port)
{
    void *req = zmq_socket(ctx, ZMQ_REQ);
    if (!req) return NULL;
    set_common(req);
    char ep[300];
    snprintf(ep, sizeof ep, strchr(host, ':') ? "tcp://[%s]:%d" : "tcp://%s:%d", host, port);
    if (strchr(host, ':')) {
        int one = 1;
        zmq_setsockopt(req, ZMQ_IPV6, &one, sizeof one);
    }
    if (zmq_connect(req, ep) != 0) {
        zmq_close(req);
        return NULL;
    }
    return req;
}

/* Ask Pupil Remote one thing on a fresh socket. */
static fv_result remote_ask(void *ctx, const char *host, int port, const char *msg, char *reply, size_t cap,
                            int timeout_ms)
{
    void *req = req_open(ctx, host, port);
    if (!req) return FV_ERR_IO;
    fv_result r = exchange(req, msg, reply, cap, NULL, timeout_ms);
    zmq_close(req);
    return r;
}

static fv_result parse_port(const char *s, int *out)
{
    char *end = NULL;
    long v = strtol(s, &end, 10);
    if (end == s || *end || v < 1 || v > 65535) return FV_ERR_PROTOCOL;
    *out = (int)v;
    return FV_OK;
}

/* Clock offset from `t` exchanges: each gives the Pupil time at the host midpoint of its round trip; the shortest
 * round trip bounds the error best (its half). On failure, why says what happened: no answer in time, or what came
 * back instead of a time (quoted), or the socket's error. */
static fv_result sync_clock(pupil_dev *d, int timeout_ms, char *why, size_t why_cap)
{
    void *req = req_open(d->ctx, d->uri.host, d->uri.port);
    if (!req) {
        snprintf(why, why_cap, "no socket for 't': %s", zmq_strerror(errno));
        return FV_ERR_IO;
    }
    int64_t best_rtt = INT64_MAX, best_off = 0;
    fv_result r = FV_OK;
    for (int i = 0; i < SYNC_EXCHANGES; i++) {
        char reply[64], q[4 * ECHO_BYTES + 8];
        size_t n = 0;
        int64_t h0 = fv_clock_now_ns(d->clock);
        r = exchange(req, "t", reply, sizeof reply, &n, timeout_ms);
        int64_t h1 = fv_clock_now_ns(d->clock);
        if (r == FV_TIMEOUT) {
            snprintf(why, why_cap, "'t' got no answer within %d ms", timeout_ms);
            break;
        }
        if (r != FV_OK) {
            snprintf(why, why_cap, "'t' failed: %s", zmq_strerror(errno));
            break;
        }
        char *end = NULL;
        double t = strtod(reply, &end);
        if (n == 0 || n >= sizeof reply || strlen(reply) != n || end == reply || *end || !isfinite(t) || t < 0.0 ||
            t > 9.0e9) {
            snprintf(why, why_cap, "Pupil Remote answered 't' with '%s' (%zu bytes), not a time in seconds",
                     quote(reply, n < sizeof reply ? n : sizeof reply - 1, n, q, sizeof q), n);
            r = FV_ERR_PROTOCOL;
            break;
        }
        if (i == 0) continue; /* the first exchange carries the connection set-up */
        if (h1 - h0 < best_rtt) {
            best_rtt = h1 - h0;
            best_off = h0 + (h1 - h0) / 2 - (int64_t)llround(t * 1e9);
        }
    }
    zmq_close(req);
    if (best_rtt == INT64_MAX) return r != FV_OK ? r : FV_TIMEOUT; /* a later failure keeps the earlier answers */
    d->offset_ns = best_off;
    d->synced = true;
    d->last_sync_ns = fv_clock_now_ns(d->clock);
    FV_LOG_RL(&d->rl_offset, FV_LOG_LEVEL_DEBUG, MOD, "%s:%d: Pupil clock offset %.6f s (round trip %.3f ms)",
              d->uri.host, d->uri.port, (double)best_off * 1e-9, (double)best_rtt * 1e-6);
    return FV_OK;
}

static void sub_close(pupil_dev *d)
{
    if (d->sub) zmq_close(d->sub);
    d->sub = NULL;
}

/* Ask for the SUB port, subscribe to gaze, synchronise the clock. */
static fv_result connect_capture(pupil_dev *d, int timeout_ms)
{
    char reply[64];
    fv_result r = remote_ask(d->ctx, d->uri.host, d->uri.port, "SUB_PORT", reply, sizeof reply, timeout_ms);
    if (r != FV_OK) return r;
    int port;
    if (parse_port(reply, &port) != FV_OK) {
        FV_ERROR(MOD, "%s:%d: Pupil Remote answered '%.32s' to SUB_PORT, not a port number", d->uri.host,
                 d->uri.port, reply);
        return FV_ERR_PROTOCOL;
    }
    sub_close(d);
    d->sub = zmq_socket(d->ctx, ZMQ_SUB);
    if (!d->sub) return FV_ERR_IO;
    set_common(d->sub);
    int hwm = RCV_HWM;
    zmq_setsockopt(d->sub, ZMQ_RCVHWM, &hwm, sizeof hwm);
    char ep[300];
    bool v6 = strchr(d->uri.host, ':') != NULL;
    if (v6) {
        int one = 1;
        zmq_setsockopt(d->sub, ZMQ_IPV6, &one, sizeof one);
    }
    snprintf(ep, sizeof ep, v6 ? "tcp://[%s]:%d" : "tcp://%s:%d", d->uri.host, port);
    if (zmq_connect(d->sub, ep) != 0 || zmq_setsockopt(d->sub, ZMQ_SUBSCRIBE, "gaze.", 5) != 0) {
        FV_ERROR(MOD, "%s: cannot subscribe: %s", ep, zmq_strerror(errno));
        sub_close(d);
        return FV_ERR_IO;
    }
    d->sub_port = port;
    char why[200];
    if (sync_clock(d, timeout_ms, why, sizeof why) != FV_OK) {
        d->synced = false;
        FV_WARN_RL(&d->rl_sync, MOD, "%s:%d: no clock synchronisation with Pupil time (%s): samples carry their "
                   "receipt time", d->uri.host, d->uri.port, why);
    }
    int64_t now = fv_clock_now_ns(d->clock);
    d->last_msg_ns = d->last_check_ns = now;
    return FV_OK;
}

/* tlen: the topic's bytes at hand; sent: its length as sent (the topic at hand may be cut). */
static void warn_malformed(pupil_dev *d, const char *topic, size_t tlen, size_t sent, const char *why)
{
    d->malformed++;
    char q[4 * ECHO_BYTES + 8];
    FV_WARN_RL(&d->rl_malformed, MOD, "%s:%d: message %llu (topic '%s'): %s; skipped", d->uri.host, d->uri.port,
               (unsigned long long)(d->seq + 1), quote(topic, tlen, sent, q, sizeof q), why);
}

/* Receive one multipart message without waiting. 1 = got a sample, 0 = skipped, -1 = nothing queued. */
static int recv_one(pupil_dev *d, fv_gaze_sample *out)
{
    char topic[256];
    int tn = zmq_recv(d->sub, topic, sizeof topic - 1, ZMQ_DONTWAIT);
    if (tn < 0) return -1;
    size_t tlen = (size_t)tn < sizeof topic - 1 ? (size_t)tn : sizeof topic - 1;
    topic[tlen] = '\0';
    int more = 0;
    size_t ms = sizeof more;
    zmq_getsockopt(d->sub, ZMQ_RCVMORE, &more, &ms);
    if (!more) {
        warn_malformed(d, topic, tlen, (size_t)tn, "a topic frame with no payload frame");
        d->seq++;
        return 0;
    }
    zmq_msg_t m;
    zmq_msg_init(&m);
    int pn = zmq_msg_recv(&m, d->sub, 0);
    char why[160] = "";
    fv_result r = FV_ERR_PARSE;
    if (pn < 0) {
        snprintf(why, sizeof why, "payload frame lost (%s)", zmq_strerror(errno));
    } else {
        r = fv_pupil_decode_gaze(topic, tlen, zmq_msg_data(&m), zmq_msg_size(&m), &d->uri.camera,
                                 d->uri.min_confidence, out, why, sizeof why);
    }
    /* Further frames (raw data Capture may attach) are not gaze: drain them. */
    for (;;) {
        more = 0;
        ms = sizeof more;
        zmq_getsockopt(d->sub, ZMQ_RCVMORE, &more, &ms);
        if (!more) break;
        zmq_msg_close(&m);
        zmq_msg_init(&m);
        if (zmq_msg_recv(&m, d->sub, 0) < 0) break;
    }
    zmq_msg_close(&m);
    d->seq++;
    if (r != FV_OK) {
        warn_malformed(d, topic, tlen, (size_t)tn, why);
        return 0;
    }
    out->seq = d->seq;
    return 1;
}

/* Silence: is Capture still there, on the same SUB port? */
static void check_capture(pupil_dev *d, int64_t now)
{
    d->last_check_ns = now;
    char reply[64];
    fv_result r = remote_ask(d->ctx, d->uri.host, d->uri.port, "SUB_PORT", reply, sizeof reply, CHECK_TIMEOUT_MS);
    int port = 0;
    if (r == FV_OK && parse_port(reply, &port) != FV_OK) r = FV_ERR_PROTOCOL;
    if (r != FV_OK) {
        if (!d->lost_warned)
            FV_WARN(MOD, "%s:%d: Pupil Capture stopped answering; reconnecting when it is back", d->uri.host,
                    d->uri.port);
        d->lost_warned = true;
        sub_close(d);
        return;
    }
    if (!d->sub || port != d->sub_port) {
        int old = d->sub_port;
        if (connect_capture(d, CHECK_TIMEOUT_MS) == FV_OK) {
            /* a warning: it pairs with the one that said Capture had gone */
            FV_WARN(MOD, "%s:%d: Pupil Capture is back (SUB port %d -> %d): reconnected", d->uri.host, d->uri.port,
                    old, d->sub_port);
            d->lost_warned = d->silent_warned = d->resubscribed = false;
        }
        return;
    }
    /* Same port, no gaze: the subscription may be gone (libzmq drops a connection for good at a frame over
     * ZMQ_MAXMSGSIZE). Subscribe anew, once per silence, before saying Capture sends nothing. */
    if (!d->resubscribed) {
        d->resubscribed = true;
        FV_INFO(MOD, "%s:%d: no gaze for %.1f s while Pupil Remote answers: subscribing again", d->uri.host,
                d->uri.port, (double)(now - d->last_msg_ns) * 1e-9);
        (void)connect_capture(d, CHECK_TIMEOUT_MS);
        return;
    }
    if (!d->silent_warned)
        FV_WARN(MOD, "%s:%d: Pupil Capture answers but sends no gaze (are the eye processes running, and is it "
                     "calibrated?)", d->uri.host, d->uri.port);
    d->silent_warned = true;
}

static fv_result pupil_read(fv_device *dev, fv_gaze_sample *out, size_t cap, size_t *out_count, int timeout_ms)
{
    pupil_dev *d = (pupil_dev *)dev;
    *out_count = 0;
    int64_t now = fv_clock_now_ns(d->clock);
    if (!d->sub) {
        if (now - d->last_check_ns >= SILENCE_CHECK_NS) check_capture(d, now);
        if (!d->sub) {
            if (timeout_ms > 0) zmq_poll(NULL, 0, timeout_ms); /* wait as asked; no busy loop */
            return FV_TIMEOUT;
        }
    }
    zmq_pollitem_t it = {d->sub, 0, ZMQ_POLLIN, 0};
    int rc = zmq_poll(&it, 1, timeout_ms < 0 ? 0 : timeout_ms);
    if (rc < 0 && errno != EINTR) {
        FV_ERROR(MOD, "%s:%d: zmq_poll: %s", d->uri.host, d->uri.port, zmq_strerror(errno));
        return FV_ERR_IO;
    }
    size_t n = 0, skipped = 0;
    bool any = false;
    now = fv_clock_now_ns(d->clock);
    fv_log_ratelimit_tick(&d->rl_malformed); /* a window that ended in silence: its summary now */
    fv_log_ratelimit_tick(&d->rl_jump);
    while (n < cap && skipped <= SKIP_PER_READ) {
        int got = recv_one(d, &out[n]);
        if (got < 0) break;
        any = true;
        if (got == 0) {
            skipped++;
            continue;
        }
        fv_gaze_sample *s = &out[n];
        s->t_host_ns = now;
        if (d->synced) {
            int64_t mapped = s->t_device_ns + d->offset_ns, off = mapped - now;
            /* A sample mapped more than a second away from its receipt: Capture's clock jumped (restart, T
             * request by another client). Resynchronise (at most once a second); this sample carries its receipt
             * time. */
            if (off > JUMP_NS || off < -JUMP_NS) {
                d->jumped = true;
                FV_WARN_RL(&d->rl_jump, MOD, "%s:%d: gaze at Pupil time %.6f s maps %+.3f s from its receipt: the "
                           "Pupil clock jumped; resynchronising (the sample carries its receipt time)", d->uri.host,
                           d->uri.port, (double)s->t_device_ns * 1e-9, (double)off * 1e-9);
            } else {
                s->t_host_ns = mapped < now ? mapped : now; /* never newer than its receipt */
            }
        }
        s->flags |= FV_GAZE_HOST_TIME_VALID;
        n++;
    }
    if (any) d->last_msg_ns = now; /* Capture is there and sending, well-formed or not */
    if (n > 0) {
        d->silent_warned = d->resubscribed = false;
        int64_t since = now - d->last_sync_ns;
        if (since >= RESYNC_NS || (d->jumped && since >= MIN_RESYNC_NS)) {
            char why[200];
            d->jumped = false;
            if (sync_clock(d, CHECK_TIMEOUT_MS, why, sizeof why) != FV_OK) {
                FV_WARN_RL(&d->rl_sync, MOD, "%s:%d: clock resynchronisation failed (%s); keeping the last offset",
                           d->uri.host, d->uri.port, why);
                d->last_sync_ns = now; /* try again later */
            }
        }
        *out_count = n;
        return FV_OK;
    }
    if (now - d->last_msg_ns >= SILENCE_CHECK_NS && now - d->last_check_ns >= SILENCE_CHECK_NS) check_capture(d, now);
    return FV_TIMEOUT;
}

static void pupil_close(fv_device *dev)
{
    pupil_dev *d = (pupil_dev *)dev;
    if (!d) return;
    fv_log_ratelimit_flush(&d->rl_malformed);
    fv_log_ratelimit_flush(&d->rl_jump);
    fv_log_ratelimit_flush(&d->rl_sync);
    fv_log_ratelimit_flush(&d->rl_offset);
    if (d->malformed)
        FV_INFO(MOD, "%s:%d: %llu malformed messages were skipped", d->uri.host, d->uri.port,
                (unsigned long long)d->malformed);
    sub_close(d);
    if (d->ctx) zmq_ctx_term(d->ctx);
    free(d);
}

static const fv_device_ops g_ops = {pupil_read, pupil_close};

static fv_result pupil_open(const char *uri, const fv_device_open_desc *desc, fv_device **out)
{
    *out = NULL;
    pupil_dev *d = calloc(1, sizeof *d);
    if (!d) return FV_ERR_NO_MEMORY;
    d->clock = desc && desc->clock ? desc->clock : fv_clock_monotonic();
    fv_log_ratelimit_init(&d->rl_malformed, MALFORMED_LINES, WARN_WINDOW_NS, d->clock);
    fv_log_ratelimit_init(&d->rl_jump, JUMP_LINES, WARN_WINDOW_NS, d->clock);
    fv_log_ratelimit_init(&d->rl_sync, SYNC_LINES, WARN_WINDOW_NS, d->clock);
    fv_log_ratelimit_init(&d->rl_offset, SYNC_LINES, WARN_WINDOW_NS, d->clock);
    fv_result r = fv_pupil_uri_parse(uri, &d->uri);
    if (r != FV_OK) goto fail;
    d->base.ops = &g_ops;
    d->ctx = zmq_ctx_new();
    if (!d->ctx) {
        r = FV_ERR_IO;
        goto fail;
    }
    r = connect_capture(d, d->uri.timeout_ms);
    if (r == FV_TIMEOUT || r == FV_ERR_IO) {
        FV_ERROR(MOD, "'%s': Pupil Remote at %s:%d did not answer within %d ms (is Pupil Capture running, with its "
                      "Pupil Remote plugin on this port?)", uri, d->uri.host, d->uri.port, d->uri.timeout_ms);
        r = FV_ERR_NOT_FOUND;
    }
    if (r != FV_OK) goto fail;
    snprintf(d->base.info.uri, sizeof d->base.info.uri, "%s", uri);
    snprintf(d->base.info.name, sizeof d->base.info.name, "Pupil Capture at %s:%d", d->uri.host, d->uri.port);
    snprintf(d->base.info.driver, sizeof d->base.info.driver, "pupil");
    snprintf(d->base.info.detail, sizeof d->base.info.detail, "SUB port %d, clock %s", d->sub_port,
             d->synced ? "synchronised" : "not synchronised");
    d->base.nominal_rate_hz = 0.0; /* Capture's rate follows its eye cameras (up to 200 Hz); it does not say */
    FV_INFO(MOD, "%s:%d: subscribed to gaze on SUB port %d", d->uri.host, d->uri.port, d->sub_port);
    *out = &d->base;
    return FV_OK;
fail:
    pupil_close(&d->base);
    return r;
}

/* FOVEA_PUPIL_REMOTE: where `fovea devices` looks ("HOST[:PORT],..."; default 127.0.0.1:50020). */
static fv_result pupil_probe(fv_device_info *out, size_t cap, size_t *out_count)
{
    *out_count = 0;
    const char *env = getenv("FOVEA_PUPIL_REMOTE");
    char list[512];
    snprintf(list, sizeof list, "%s", env && env[0] ? env : "127.0.0.1:50020");
    void *ctx = zmq_ctx_new();
    if (!ctx) return FV_OK;
    size_t found = 0;
    char *save = NULL;
    for (char *tok = strtok_r(list, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        char uri_s[300];
        snprintf(uri_s, sizeof uri_s, "pupil:%s", tok);
        fv_pupil_uri u;
        if (fv_pupil_uri_parse(uri_s, &u) != FV_OK) continue;
        char port_s[64], ver[64] = "";
        int port;
        if (remote_ask(ctx, u.host, u.port, "SUB_PORT", port_s, sizeof port_s, PROBE_TIMEOUT_MS) != FV_OK ||
            parse_port(port_s, &port) != FV_OK)
            continue;
        if (remote_ask(ctx, u.host, u.port, "v", ver, sizeof ver, PROBE_TIMEOUT_MS) != FV_OK) ver[0] = '\0';
        if (found < cap) {
            fv_device_info *info = &out[found];
            memset(info, 0, sizeof *info);
            snprintf(info->uri, sizeof info->uri, "%.250s", uri_s);
            snprintf(info->name, sizeof info->name, "Pupil Capture%s%.60s", ver[0] ? " " : "", ver);
            snprintf(info->driver, sizeof info->driver, "pupil");
            snprintf(info->detail, sizeof info->detail, "Pupil Remote tcp://%.200s:%d, SUB port %d", u.host, u.port,
                     port);
        }
        found++;
    }
    zmq_ctx_term(ctx);
    *out_count = found;
    return FV_OK;
}

const fv_driver fv_pupil_driver = {
    .scheme = "pupil",
    .summary = "Pupil Capture (Pupil Labs Core) over its network API: Pupil Remote, ZeroMQ + msgpack",
    .probe = pupil_probe,
    .open = pupil_open,
};
