/* @brief Scriptable fake eye tracker (see fake_tracker.h). */
#include "fake_tracker.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct fake_device {
    fv_device base;
    fake_tracker *t;
} fake_device;

void fake_tracker_init(fake_tracker *t, const fv_clock *clock, double rate_hz, int64_t latency_ns)
{
    memset(t, 0, sizeof *t);
    t->clock = clock;
    t->rate_hz = rate_hz > 0 ? rate_hz : 250.0;
    t->latency_ns = latency_ns;
    t->first_capture_ns = clock ? fv_clock_now_ns(clock) : 0;
    pthread_mutex_init(&t->lock, NULL);
    pthread_cond_init(&t->cond, NULL);
}

void fake_tracker_fini(fake_tracker *t)
{
    pthread_cond_destroy(&t->cond);
    pthread_mutex_destroy(&t->lock);
}

void fake_tracker_set_hang(fake_tracker *t, bool hang)
{
    pthread_mutex_lock(&t->lock);
    t->hang = hang;
    pthread_cond_broadcast(&t->cond);
    pthread_mutex_unlock(&t->lock);
}

bool fake_tracker_in_read(fake_tracker *t)
{
    pthread_mutex_lock(&t->lock);
    bool r = t->in_read;
    pthread_mutex_unlock(&t->lock);
    return r;
}

int64_t fake_tracker_capture_ns(const fake_tracker *t, uint64_t i)
{
    return t->first_capture_ns + (int64_t)llround((double)i * 1e9 / t->rate_hz);
}

/* A plausible sample: both eyes looking along a slow horizontal sinusoid, 4 mm pupils. */
static void make_sample(const fake_tracker *t, uint64_t i, int64_t capture_ns, int64_t host_ns, fv_gaze_sample *s)
{
    fv_gaze_sample_init_invalid(s, capture_ns, host_ns);
    double ts = (double)(capture_ns - t->first_capture_ns) / 1e9;
    double yaw = fv_deg_to_rad(10.0 * sin(2.0 * FV_PI * 0.5 * ts));
    fv_vec3 dir = fv_v3((float)sin(yaw), 0.0f, (float)-cos(yaw));
    for (int e = 0; e < 2; e++) {
        fv_eye_sample *eye = &s->eye[e];
        eye->origin_mm = fv_v3(e == 0 ? -32.0f : 32.0f, 0.0f, 0.0f);
        eye->direction = dir;
        eye->pupil_mm = 4.0f;
        eye->openness = 1.0f;
        eye->flags = FV_EYE_ORIGIN_VALID | FV_EYE_DIRECTION_VALID | FV_EYE_PUPIL_VALID | FV_EYE_OPENNESS_VALID;
    }
    s->combined = s->eye[0];
    s->combined.origin_mm = fv_v3(0.0f, 0.0f, 0.0f);
    s->confidence = 1.0f;
    s->flags = FV_GAZE_HOST_TIME_VALID;
    s->seq = i;
}

static fv_result fake_read(fv_device *dev, fv_gaze_sample *out, size_t cap, size_t *out_count, int timeout_ms)
{
    fake_tracker *t = ((fake_device *)dev)->t;
    *out_count = 0;
    (void)timeout_ms;
    pthread_mutex_lock(&t->lock);
    t->reads++;
    while (t->hang) { /* a broken driver: ignores its timeout */
        t->in_read = true;
        pthread_cond_wait(&t->cond, &t->lock);
    }
    t->in_read = false;
    pthread_mutex_unlock(&t->lock);
    if (t->flood) {
        for (size_t k = 0; k < cap; k++) {
            uint64_t i = t->next_index++;
            int64_t c = (int64_t)i * 1000; /* 1 MHz: always new, always in order */
            make_sample(t, i, c, c + t->latency_ns, &out[k]);
        }
        *out_count = cap;
        return FV_OK;
    }
    if (!t->clock) return FV_TIMEOUT;
    int64_t now = fv_clock_now_ns(t->clock);
    if (t->lost_at_ns && now >= t->lost_at_ns && !t->lost_fired) {
        t->lost_fired = true;
        return t->end_after_loss ? FV_END_OF_STREAM : FV_ERR_DEVICE_LOST;
    }
    size_t n = 0;
    while (n < cap) {
        int64_t c = fake_tracker_capture_ns(t, t->next_index);
        if (c + t->latency_ns > now) break;
        uint64_t i = t->next_index++;
        if (t->stall_to_ns > t->stall_from_ns && c >= t->stall_from_ns && c < t->stall_to_ns) continue;
        make_sample(t, i, c, c + t->latency_ns, &out[n++]);
    }
    *out_count = n;
    return n ? FV_OK : FV_TIMEOUT;
}

static void fake_close(fv_device *dev)
{
    ((fake_device *)dev)->t->closes++;
    free(dev);
}

static const fv_device_ops g_fake_ops = {.read = fake_read, .close = fake_close};

fv_result fake_tracker_open(void *user, const char *uri, const fv_device_open_desc *desc, fv_device **out_dev)
{
    fake_tracker *t = user;
    (void)desc;
    *out_dev = NULL;
    if (t->lost_fired && t->clock && fv_clock_now_ns(t->clock) < t->back_at_ns) {
        t->open_failures++;
        return FV_ERR_NOT_FOUND;
    }
    fake_device *d = calloc(1, sizeof *d);
    if (!d) return FV_ERR_NO_MEMORY;
    d->base.ops = &g_fake_ops;
    snprintf(d->base.info.uri, sizeof d->base.info.uri, "%s", uri);
    snprintf(d->base.info.name, sizeof d->base.info.name, "fake tracker");
    snprintf(d->base.info.driver, sizeof d->base.info.driver, "fake");
    d->base.nominal_rate_hz = t->rate_hz;
    d->t = t;
    if (t->clock && t->opens > 0) {
        /* the tracker kept running while it was away: what it captured meanwhile is gone */
        int64_t now = fv_clock_now_ns(t->clock);
        while (fake_tracker_capture_ns(t, t->next_index) + t->latency_ns <= now) t->next_index++;
    }
    t->opens++;
    *out_dev = &d->base;
    return FV_OK;
}
