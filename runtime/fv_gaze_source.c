/* @brief Gaze source: device reader (thread or inline), SPSC ring, loss detection and re-open with backoff. */
#include "fv_gaze_source.h"

#include <errno.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fv_log.h"

#define MAX_BATCH 256

struct fv_gaze_source {
    char *uri;
    fv_gaze_source_open_fn open;
    void *open_user;
    fv_device_open_desc open_desc;
    fv_gaze_source_mode mode;
    const fv_clock *clock; /* inline: injected; thread: monotonic */
    size_t batch;
    size_t poll_max;
    int timeout_ms;
    int64_t retry_min_ns, retry_max_ns;

    fv_ring *ring;
    fv_gaze_sample *buf; /* read buffer, reader side only */

    /* reader side only (the thread, or the consumer in inline mode) */
    fv_device *dev;
    int64_t backoff_ns;
    int64_t next_retry_ns;

    /* shared: written by the reader side, read by anyone */
    _Atomic int state;
    _Atomic uint64_t samples, losses, reopens, open_failures, poll_limited;
    _Atomic uint64_t delivered; /* written by the consumer */
    bool warned_poll_limit;      /* reader side */
    /* a device that comes and goes at its own pace (a flapping cable, a hostile device): "lost" and "back" through
     * rate limits over time */
    fv_log_ratelimit rl_lost, rl_back;
    _Atomic int last_error;

    /* thread mode */
    bool thread_started;
    pthread_t thread;
    pthread_mutex_t lock; /* only for the stop condition variable */
    pthread_cond_t wake;
    bool sync_inited;
    _Atomic bool stop;
    _Atomic bool reprobe; /* a hotplug arrival (or the user) asked for a re-open now, skipping the backoff */
};

const char *fv_gaze_source_state_str(fv_gaze_source_state s)
{
    switch (s) {
    case FV_GAZE_SOURCE_CONNECTED: return "connected";
    case FV_GAZE_SOURCE_LOST: return "lost";
    case FV_GAZE_SOURCE_ENDED: return "ended";
    case FV_GAZE_SOURCE_FAILED: return "failed";
    }
    return "unknown";
}

/* Errors that re-opening the same URI cannot fix. */
static bool permanent(fv_result r)
{
    return r == FV_ERR_INVALID_ARG || r == FV_ERR_PARSE || r == FV_ERR_UNSUPPORTED || r == FV_ERR_RANGE;
}

static void set_state(fv_gaze_source *s, fv_gaze_source_state st)
{
    atomic_store_explicit(&s->state, (int)st, memory_order_release);
}

static fv_gaze_source_state get_state(const fv_gaze_source *s)
{
    return (fv_gaze_source_state)atomic_load_explicit(&((fv_gaze_source *)s)->state, memory_order_acquire);
}

static void schedule_retry(fv_gaze_source *s, int64_t now_ns)
{
    s->next_retry_ns = now_ns + s->backoff_ns;
    s->backoff_ns = s->backoff_ns > s->retry_max_ns / 2 ? s->retry_max_ns : s->backoff_ns * 2;
}

/* The device failed or went away: close it, report it lost, and plan the first re-open. */
static void device_lost(fv_gaze_source *s, fv_result why, int64_t now_ns)
{
    FV_WARN_RL(&s->rl_lost, "devices", "%s: device lost (%s); re-opening with backoff", s->uri, fv_result_str(why));
    fv_device_close(&s->dev);
    atomic_store(&s->last_error, (int)why);
    atomic_fetch_add(&s->losses, 1);
    s->backoff_ns = s->retry_min_ns;
    schedule_retry(s, now_ns);
    set_state(s, FV_GAZE_SOURCE_LOST);
}

/* LOST and due: try to open the URI again. */
static void try_reopen(fv_gaze_source *s, int64_t now_ns)
{
    if (!s->open) {
        FV_ERROR("devices", "%s: lost and no way to re-open it", s->uri);
        set_state(s, FV_GAZE_SOURCE_FAILED);
        return;
    }
    fv_device *dev = NULL;
    fv_result r = s->open(s->open_user, s->uri, &s->open_desc, &dev);
    if (r == FV_OK && dev) {
        s->dev = dev;
        atomic_fetch_add(&s->reopens, 1);
        FV_WARN_RL(&s->rl_back, "devices", "%s: device back (%llu failed re-opens so far)", s->uri,
                   (unsigned long long)atomic_load(&s->open_failures)); /* pairs with the "lost" warning */
        set_state(s, FV_GAZE_SOURCE_CONNECTED);
        return;
    }
    if (r == FV_OK) r = FV_ERR_PROTOCOL; /* success without a device: a driver bug */
    atomic_fetch_add(&s->open_failures, 1);
    atomic_store(&s->last_error, (int)r);
    if (permanent(r)) {
        FV_ERROR("devices", "%s: cannot be re-opened (%s); giving up", s->uri, fv_result_str(r));
        set_state(s, FV_GAZE_SOURCE_FAILED);
        return;
    }
    FV_DEBUG("devices", "%s: re-open failed (%s); next try in %lld ms", s->uri, fv_result_str(r),
             (long long)(s->backoff_ns / FV_NS_PER_MS));
    schedule_retry(s, now_ns);
}

/* One read from the device and its consequences. Returns the number of samples pushed, or -1 when the caller
 * should stop reading for now (timeout, end, loss). */
static long read_once(fv_gaze_source *s, int timeout_ms, int64_t now_ns)
{
    size_t n = 0;
    fv_result r = fv_device_read(s->dev, s->buf, s->batch, &n, timeout_ms);
    if (r == FV_OK) {
        if (n > s->batch) {
            FV_ERROR("devices", "%s: driver returned %zu samples for a buffer of %zu; keeping %zu", s->uri, n,
                     s->batch, s->batch);
            n = s->batch;
        }
        for (size_t i = 0; i < n; i++) {
            fv_result pr = fv_ring_push(s->ring, &s->buf[i]);
            (void)pr; /* a full ring drops (and counts) the oldest: the frame loop wants the newest */
        }
        atomic_fetch_add_explicit(&s->samples, n, memory_order_relaxed);
        return n ? (long)n : -1;
    }
    if (r == FV_TIMEOUT || r == FV_NO_NEW_DATA) return -1;
    if (r == FV_END_OF_STREAM) {
        FV_INFO("devices", "%s: end of stream", s->uri);
        fv_device_close(&s->dev);
        set_state(s, FV_GAZE_SOURCE_ENDED);
        return -1;
    }
    device_lost(s, FV_FAILED(r) ? r : FV_ERR_PROTOCOL, now_ns);
    return -1;
}

/* ---- thread mode ---- */

static struct timespec abs_time(int64_t t_ns)
{
    struct timespec ts = {.tv_sec = (time_t)(t_ns / FV_NS_PER_S), .tv_nsec = (long)(t_ns % FV_NS_PER_S)};
    return ts;
}

/* Wait until t_ns on the monotonic clock or until stop is requested. */
static void wait_until(fv_gaze_source *s, int64_t t_ns)
{
    struct timespec ts = abs_time(t_ns);
    pthread_mutex_lock(&s->lock);
    while (!atomic_load(&s->stop) && !atomic_load(&s->reprobe) && fv_clock_now_ns(s->clock) < t_ns) {
        if (pthread_cond_timedwait(&s->wake, &s->lock, &ts) == ETIMEDOUT) break;
    }
    pthread_mutex_unlock(&s->lock);
}

static void *reader_main(void *arg)
{
    fv_gaze_source *s = arg;
    while (!atomic_load_explicit(&s->stop, memory_order_acquire)) {
        fv_gaze_source_state st = get_state(s);
        if (st == FV_GAZE_SOURCE_CONNECTED) {
            (void)read_once(s, s->timeout_ms, fv_clock_now_ns(s->clock));
        } else if (st == FV_GAZE_SOURCE_LOST) {
            wait_until(s, s->next_retry_ns);
            if (atomic_exchange(&s->reprobe, false)) s->backoff_ns = s->retry_min_ns; /* a fresh start */
            if (!atomic_load(&s->stop)) try_reopen(s, fv_clock_now_ns(s->clock));
        } else {
            break; /* ended or failed: nothing more to read */
        }
    }
    return NULL;
}

/* ---- public ---- */

fv_result fv_gaze_source_create(const fv_gaze_source_desc *desc, fv_gaze_source **out)
{
    if (!out) return FV_ERR_INVALID_ARG;
    *out = NULL;
    fv_device *given = desc ? desc->device : NULL;
    fv_result r = FV_ERR_INVALID_ARG;
    fv_gaze_source *s = NULL;
    if (!desc || !desc->uri || !desc->uri[0]) {
        FV_ERROR("devices", "gaze source: a URI is required");
        goto fail;
    }
    if (!desc->open && !given) {
        FV_ERROR("devices", "gaze source %s: neither an open function nor an open device", desc->uri);
        goto fail;
    }
    if (desc->mode != FV_GAZE_SOURCE_THREAD && desc->mode != FV_GAZE_SOURCE_INLINE) {
        FV_ERROR("devices", "gaze source %s: unknown mode %d", desc->uri, (int)desc->mode);
        goto fail;
    }
    if (desc->mode == FV_GAZE_SOURCE_INLINE && !desc->clock) {
        FV_ERROR("devices", "gaze source %s: inline mode needs a clock", desc->uri);
        goto fail;
    }
    if (desc->read_batch > MAX_BATCH || desc->read_timeout_ms < 0 || desc->retry_min_ns < 0 ||
        desc->retry_max_ns < 0) {
        FV_ERROR("devices", "gaze source %s: read_batch %zu (max %d), read_timeout_ms %d, retry %lld..%lld ns: out of range",
                 desc->uri, desc->read_batch, MAX_BATCH, desc->read_timeout_ms, (long long)desc->retry_min_ns,
                 (long long)desc->retry_max_ns);
        r = FV_ERR_RANGE;
        goto fail;
    }
    r = FV_ERR_NO_MEMORY;
    s = calloc(1, sizeof *s);
    if (!s) goto fail;
    s->clock = desc->mode == FV_GAZE_SOURCE_INLINE ? desc->clock : fv_clock_monotonic();
    fv_log_ratelimit_init(&s->rl_lost, 5, 30 * FV_NS_PER_S, s->clock);
    fv_log_ratelimit_init(&s->rl_back, 5, 30 * FV_NS_PER_S, s->clock);
    s->uri = strdup(desc->uri);
    s->batch = desc->read_batch ? desc->read_batch : 32;
    s->buf = calloc(s->batch, sizeof *s->buf);
    if (!s->uri || !s->buf) goto fail;
    s->open = desc->open;
    s->open_user = desc->open_user;
    s->open_desc = desc->open_desc;
    s->mode = desc->mode;
    s->timeout_ms = desc->read_timeout_ms ? desc->read_timeout_ms : 10;
    s->poll_max = desc->poll_max_samples;
    s->retry_min_ns = desc->retry_min_ns ? desc->retry_min_ns : 50 * FV_NS_PER_MS;
    s->retry_max_ns = desc->retry_max_ns ? desc->retry_max_ns : 2 * FV_NS_PER_S;
    if (s->retry_max_ns < s->retry_min_ns) s->retry_max_ns = s->retry_min_ns;
    atomic_init(&s->state, FV_GAZE_SOURCE_CONNECTED);
    atomic_init(&s->samples, 0);
    atomic_init(&s->losses, 0);
    atomic_init(&s->reopens, 0);
    atomic_init(&s->open_failures, 0);
    atomic_init(&s->poll_limited, 0);
    atomic_init(&s->delivered, 0);
    atomic_init(&s->last_error, FV_OK);
    atomic_init(&s->stop, false);
    r = fv_ring_create(sizeof(fv_gaze_sample), desc->ring_capacity ? desc->ring_capacity : 512,
                       desc->overrun_policy, &s->ring);
    if (FV_FAILED(r)) goto fail;
    if (!s->poll_max) s->poll_max = 64 * fv_ring_capacity(s->ring);

    if (given) {
        s->dev = given;
        given = NULL;
    } else {
        r = s->open(s->open_user, s->uri, &s->open_desc, &s->dev);
        if (r == FV_OK && !s->dev) r = FV_ERR_PROTOCOL;
        if (FV_FAILED(r)) {
            s->dev = NULL;
            if (!desc->start_lost || permanent(r)) goto fail; /* the driver logged why */
            FV_WARN("devices", "%s: not available yet (%s); will keep trying", s->uri, fv_result_str(r));
            atomic_store(&s->last_error, (int)r);
            s->backoff_ns = s->retry_min_ns;
            schedule_retry(s, fv_clock_now_ns(s->clock));
            set_state(s, FV_GAZE_SOURCE_LOST);
        }
    }

    if (s->mode == FV_GAZE_SOURCE_THREAD) {
        pthread_condattr_t attr;
        pthread_condattr_init(&attr);
        pthread_condattr_setclock(&attr, CLOCK_MONOTONIC); /* waits are on the monotonic clock, like s->clock */
        int e1 = pthread_mutex_init(&s->lock, NULL);
        int e2 = pthread_cond_init(&s->wake, &attr);
        pthread_condattr_destroy(&attr);
        if (e1 || e2) {
            if (!e1) pthread_mutex_destroy(&s->lock);
            if (!e2) pthread_cond_destroy(&s->wake);
            FV_ERROR("devices", "%s: cannot create the reader's synchronisation objects", s->uri);
            r = FV_ERR_IO;
            goto fail;
        }
        s->sync_inited = true;
        if (pthread_create(&s->thread, NULL, reader_main, s) != 0) {
            FV_ERROR("devices", "%s: cannot start the reader thread", s->uri);
            r = FV_ERR_IO;
            goto fail;
        }
        s->thread_started = true;
    }
    *out = s;
    return FV_OK;
fail:
    if (r == FV_ERR_NO_MEMORY) FV_ERROR("devices", "gaze source: out of memory");
    fv_device_close(&given);
    fv_gaze_source_destroy(&s);
    return r;
}

void fv_gaze_source_destroy(fv_gaze_source **source)
{
    if (!source || !*source) return;
    fv_gaze_source *s = *source;
    if (s->thread_started) {
        atomic_store_explicit(&s->stop, true, memory_order_release);
        pthread_mutex_lock(&s->lock);
        pthread_cond_broadcast(&s->wake);
        pthread_mutex_unlock(&s->lock);
        pthread_join(s->thread, NULL);
    }
    if (s->sync_inited) {
        pthread_cond_destroy(&s->wake);
        pthread_mutex_destroy(&s->lock);
    }
    fv_device_close(&s->dev);
    fv_log_ratelimit_flush(&s->rl_lost);
    fv_log_ratelimit_flush(&s->rl_back);
    fv_ring_destroy(&s->ring);
    free(s->buf);
    free(s->uri);
    free(s);
    *source = NULL;
}

void fv_gaze_source_poll(fv_gaze_source *s)
{
    if (!s || s->mode != FV_GAZE_SOURCE_INLINE) return;
    int64_t now = fv_clock_now_ns(s->clock);
    if (get_state(s) == FV_GAZE_SOURCE_LOST && atomic_exchange(&s->reprobe, false)) {
        s->backoff_ns = s->retry_min_ns;
        try_reopen(s, now);
    } else if (get_state(s) == FV_GAZE_SOURCE_LOST && now >= s->next_retry_ns) {
        try_reopen(s, now);
    }
    /* Read until the device has nothing more: what stays in the driver would reach a later frame older and older
     * (a source faster than a ring per frame backs up without bound). The ring keeps the newest and counts what it
     * drops. A device that never runs dry cannot keep the frame loop here: the poll stops at poll_max. */
    size_t got = 0;
    while (get_state(s) == FV_GAZE_SOURCE_CONNECTED) {
        if (got >= s->poll_max) {
            atomic_fetch_add_explicit(&s->poll_limited, 1, memory_order_relaxed);
            if (!s->warned_poll_limit) {
                FV_WARN("devices", "%s: still delivering after %zu samples in one poll; the rest waits for the next "
                        "frame (counted as poll_limited; reported once)", s->uri, got);
                s->warned_poll_limit = true;
            }
            break;
        }
        long n = read_once(s, 0, now);
        if (n < 0) break;
        got += (size_t)n;
    }
}

void fv_gaze_source_reprobe(fv_gaze_source *s)
{
    if (!s || get_state(s) != FV_GAZE_SOURCE_LOST) return;
    atomic_store(&s->reprobe, true);
    pthread_mutex_lock(&s->lock);
    pthread_cond_broadcast(&s->wake); /* the reader thread may be sleeping out its backoff */
    pthread_mutex_unlock(&s->lock);
}

fv_result fv_gaze_source_pop(fv_gaze_source *s, fv_gaze_sample *out_sample)
{
    fv_result r = fv_ring_pop(s->ring, out_sample);
    if (r == FV_OK) atomic_fetch_add_explicit(&s->delivered, 1, memory_order_relaxed);
    return r;
}

void fv_gaze_source_get_status(const fv_gaze_source *source, fv_gaze_source_status *out)
{
    fv_gaze_source *s = (fv_gaze_source *)source; /* atomic loads need non-const objects */
    memset(out, 0, sizeof *out);
    out->state = get_state(s);
    out->samples = atomic_load_explicit(&s->samples, memory_order_relaxed);
    out->delivered = atomic_load_explicit(&s->delivered, memory_order_relaxed);
    out->overruns = fv_ring_overruns(s->ring);
    out->queued = fv_ring_count(s->ring);
    out->poll_limited = atomic_load_explicit(&s->poll_limited, memory_order_relaxed);
    out->losses = atomic_load(&s->losses);
    out->reopens = atomic_load(&s->reopens);
    out->open_failures = atomic_load(&s->open_failures);
    out->last_error = (fv_result)atomic_load(&s->last_error);
    out->ring_capacity = fv_ring_capacity(s->ring);
}

const char *fv_gaze_source_uri(const fv_gaze_source *source) { return source->uri; }
