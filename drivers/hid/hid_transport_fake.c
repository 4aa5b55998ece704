/* @brief The fake HID transport: replays queued bytes, answers feature requests, records feature writes. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_hid_transport.h"
#include "fv_log.h"

#define FAKE_MAX_REPORT 256
#define FAKE_MAX_FEATURES 16

typedef struct fake_report {
    struct fake_report *next;
    size_t len;
    uint8_t bytes[];
} fake_report;

struct fv_hid_fake {
    fv_hid_transport base;
    pthread_mutex_t mutex;
    uint8_t *descriptor;
    size_t descriptor_len;
    fake_report *head, *tail;
    size_t pending;
    uint8_t features[FAKE_MAX_FEATURES][FAKE_MAX_REPORT];
    size_t feature_len[FAKE_MAX_FEATURES];
    size_t feature_count;
    uint8_t last_write[FAKE_MAX_REPORT];
    size_t last_write_len, writes;
    int gate, open_gate, unplugged;
    uint8_t mode_id;
};

void fv_hid_transport_destroy(fv_hid_transport **t)
{
    if (t && *t) {
        (*t)->ops->destroy(*t);
        *t = NULL;
    }
}

static fv_result fake_get_descriptor(fv_hid_transport *t, uint8_t *buf, size_t cap, size_t *out_len)
{
    fv_hid_fake *f = (fv_hid_fake *)t;
    if (f->descriptor_len > cap) return FV_ERR_RANGE;
    memcpy(buf, f->descriptor, f->descriptor_len);
    *out_len = f->descriptor_len;
    return FV_OK;
}

static fv_result fake_read(fv_hid_transport *t, uint8_t *buf, size_t cap, size_t *out_len, int timeout_ms)
{
    (void)timeout_ms; /* the fake never waits: an empty queue is a timeout at once */
    fv_hid_fake *f = (fv_hid_fake *)t;
    fv_result r = FV_TIMEOUT;
    *out_len = 0;
    pthread_mutex_lock(&f->mutex);
    if (f->head && (!f->gate || f->open_gate)) {
        fake_report *rep = f->head;
        f->head = rep->next;
        if (!f->head) f->tail = NULL;
        f->pending--;
        size_t n = rep->len < cap ? rep->len : cap;
        memcpy(buf, rep->bytes, n);
        *out_len = n;
        free(rep);
        r = FV_OK;
    } else if (f->unplugged) {
        r = FV_ERR_DEVICE_LOST;
    }
    pthread_mutex_unlock(&f->mutex);
    return r;
}

static fv_result fake_get_feature(fv_hid_transport *t, uint8_t id, uint8_t *buf, size_t cap, size_t *out_len)
{
    fv_hid_fake *f = (fv_hid_fake *)t;
    fv_result r = FV_ERR_PROTOCOL;
    pthread_mutex_lock(&f->mutex);
    if (f->unplugged) r = FV_ERR_DEVICE_LOST;
    for (size_t i = 0; i < f->feature_count && r == FV_ERR_PROTOCOL; i++) {
        if (f->features[i][0] != id) continue;
        if (f->feature_len[i] > cap) {
            r = FV_ERR_RANGE;
            break;
        }
        memcpy(buf, f->features[i], f->feature_len[i]);
        *out_len = f->feature_len[i];
        r = FV_OK;
    }
    pthread_mutex_unlock(&f->mutex);
    return r;
}

static fv_result fake_set_feature(fv_hid_transport *t, const uint8_t *buf, size_t len)
{
    fv_hid_fake *f = (fv_hid_fake *)t;
    if (len == 0 || len > FAKE_MAX_REPORT) return FV_ERR_INVALID_ARG;
    pthread_mutex_lock(&f->mutex);
    fv_result r = f->unplugged ? FV_ERR_DEVICE_LOST : FV_OK;
    if (r == FV_OK) {
        memcpy(f->last_write, buf, len);
        f->last_write_len = len;
        f->writes++;
        if (f->gate && buf[0] == f->mode_id && len >= 2) f->open_gate = buf[1] != 0;
    }
    pthread_mutex_unlock(&f->mutex);
    return r;
}

static void fake_destroy(fv_hid_transport *t)
{
    fv_hid_fake *f = (fv_hid_fake *)t;
    for (fake_report *r = f->head; r;) {
        fake_report *next = r->next;
        free(r);
        r = next;
    }
    pthread_mutex_destroy(&f->mutex);
    free(f->descriptor);
    free(f);
}

static const fv_hid_transport_ops g_fake_ops = {
    fake_get_descriptor, fake_read, fake_get_feature, fake_set_feature, fake_destroy,
};

fv_result fv_hid_fake_create(const fv_hid_fake_desc *desc, fv_hid_transport **out, fv_hid_fake **out_fake)
{
    if (!desc || !out || (!desc->descriptor && desc->descriptor_len)) return FV_ERR_INVALID_ARG;
    fv_hid_fake *f = calloc(1, sizeof *f);
    if (!f) return FV_ERR_NO_MEMORY;
    f->descriptor = malloc(desc->descriptor_len ? desc->descriptor_len : 1);
    if (!f->descriptor) {
        free(f);
        return FV_ERR_NO_MEMORY;
    }
    if (desc->descriptor_len) memcpy(f->descriptor, desc->descriptor, desc->descriptor_len);
    f->descriptor_len = desc->descriptor_len;
    pthread_mutex_init(&f->mutex, NULL);
    f->base.ops = &g_fake_ops;
    f->base.vid = desc->vid;
    f->base.pid = desc->pid;
    snprintf(f->base.path, sizeof f->base.path, "fake");
    snprintf(f->base.name, sizeof f->base.name, "fake HID transport");
    f->gate = desc->gate_on_mode_request;
    f->mode_id = desc->mode_report_id;
    *out = &f->base;
    if (out_fake) *out_fake = f;
    return FV_OK;
}

fv_result fv_hid_fake_push_input(fv_hid_fake *f, const uint8_t *report, size_t len)
{
    if (len == 0 || len > FAKE_MAX_REPORT) return FV_ERR_INVALID_ARG;
    fake_report *r = malloc(sizeof *r + len);
    if (!r) return FV_ERR_NO_MEMORY;
    r->next = NULL;
    r->len = len;
    memcpy(r->bytes, report, len);
    pthread_mutex_lock(&f->mutex);
    if (f->tail) f->tail->next = r;
    else f->head = r;
    f->tail = r;
    f->pending++;
    pthread_mutex_unlock(&f->mutex);
    return FV_OK;
}

fv_result fv_hid_fake_set_feature_reply(fv_hid_fake *f, const uint8_t *report, size_t len)
{
    if (len == 0 || len > FAKE_MAX_REPORT) return FV_ERR_INVALID_ARG;
    fv_result r = FV_OK;
    pthread_mutex_lock(&f->mutex);
    size_t i = 0;
    while (i < f->feature_count && f->features[i][0] != report[0]) i++;
    if (i == FAKE_MAX_FEATURES) r = FV_ERR_NO_MEMORY;
    else {
        memcpy(f->features[i], report, len);
        f->feature_len[i] = len;
        if (i == f->feature_count) f->feature_count++;
    }
    pthread_mutex_unlock(&f->mutex);
    return r;
}

void fv_hid_fake_unplug(fv_hid_fake *f)
{
    pthread_mutex_lock(&f->mutex);
    f->unplugged = 1;
    pthread_mutex_unlock(&f->mutex);
}

size_t fv_hid_fake_feature_writes(fv_hid_fake *f, uint8_t *last, size_t cap, size_t *out_len)
{
    pthread_mutex_lock(&f->mutex);
    size_t n = f->writes;
    size_t len = f->last_write_len < cap ? f->last_write_len : cap;
    if (last && len) memcpy(last, f->last_write, len);
    if (out_len) *out_len = len;
    pthread_mutex_unlock(&f->mutex);
    return n;
}

size_t fv_hid_fake_pending(fv_hid_fake *f)
{
    pthread_mutex_lock(&f->mutex);
    size_t n = f->pending;
    pthread_mutex_unlock(&f->mutex);
    return n;
}
