/* @brief The virtual HID eye tracker: builds its descriptor item by item and encodes samples into reports with the
 * generic field writer, so it exercises the same layout code the decoder reads with. */
#include "fv_vhid.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"

#define MOD "vhid"
#define DESC_CAP 512
#define POS_LIMIT_UM 2000000 /* logical range of positions: ±2 m in µm */
#define PUPIL_MAX_UM 20000

struct fv_vhid {
    uint8_t bytes[DESC_CAP];
    size_t len;
    fv_hid_descriptor desc;
    fv_hid_eyetracker_map map;
    fv_hid_screen_config screen;
    unsigned hz;
};

typedef struct builder {
    uint8_t *b;
    size_t len, cap;
} builder;

/* One short item: prefix = tag << 4 | type << 2 | size code (HID 1.11 §6.2.2.2). */
static void item(builder *w, unsigned type, unsigned tag, uint32_t value, unsigned nbytes)
{
    unsigned code = nbytes == 4 ? 3u : nbytes;
    if (w->len + 1 + nbytes > w->cap) {
        w->len = w->cap + 1; /* marks overflow; checked once at the end */
        return;
    }
    w->b[w->len++] = (uint8_t)(tag << 4 | type << 2 | code);
    for (unsigned i = 0; i < nbytes; i++) w->b[w->len++] = (uint8_t)(value >> (8 * i));
}

enum { MAIN = 0, GLOBAL = 1, LOCAL = 2 };
#define USAGE_PAGE(p, n) item(&w, GLOBAL, 0x0, (p), (n))
#define USAGE(u) item(&w, LOCAL, 0x0, (u), (u) > 0xFF ? 2 : 1)
#define COLLECTION(t) item(&w, MAIN, 0xA, (t), 1)
#define END_COLLECTION() item(&w, MAIN, 0xC, 0, 0)
#define REPORT_ID(id) item(&w, GLOBAL, 0x8, (id), 1)
#define REPORT_SIZE(n) item(&w, GLOBAL, 0x7, (n), 1)
#define REPORT_COUNT(n) item(&w, GLOBAL, 0x9, (n), 1)
#define LOGICAL_MIN(v, n) item(&w, GLOBAL, 0x1, (uint32_t)(v), (n))
#define LOGICAL_MAX(v, n) item(&w, GLOBAL, 0x2, (uint32_t)(v), (n))
#define UNIT(u, n) item(&w, GLOBAL, 0x6, (u), (n))
#define UNIT_EXPONENT(e) item(&w, GLOBAL, 0x5, (uint32_t)(e) & 0xFu, 1)
#define INPUT(f) item(&w, MAIN, 0x8, (f), 1)
#define FEATURE(f) item(&w, MAIN, 0xB, (f), 1)
#define DATA_VAR_ABS 0x02u

static size_t build_descriptor(uint8_t *buf, size_t cap)
{
    builder w = {buf, 0, cap};
    USAGE_PAGE(0x12, 1);
    USAGE(0x01); /* Eye Tracker */
    COLLECTION(1);
    {
        USAGE(0x10); /* Tracking Data */
        COLLECTION(2);
        REPORT_ID(0x10);
        LOGICAL_MIN(0, 1);
        LOGICAL_MAX(255, 2);
        REPORT_SIZE(8);
        USAGE(0x20); /* Sensor Timestamp: 8 x 8 bits, little-endian µs */
        UNIT(0x1001, 2);
        UNIT_EXPONENT(-6);
        REPORT_COUNT(8);
        INPUT(DATA_VAR_ABS);
        REPORT_SIZE(32);
        UNIT(0x11, 1); /* SI linear cm, e-4: µm */
        UNIT_EXPONENT(-4);
        LOGICAL_MIN(-POS_LIMIT_UM, 4);
        LOGICAL_MAX(POS_LIMIT_UM, 4);
        USAGE(0x24); /* Gaze Point */
        COLLECTION(0);
        REPORT_COUNT(2);
        USAGE(0x21);
        USAGE(0x22);
        INPUT(DATA_VAR_ABS);
        END_COLLECTION();
        for (unsigned eye = 0x25; eye <= 0x26; eye++) { /* Left, Right Eye Position */
            USAGE(eye);
            COLLECTION(0);
            REPORT_COUNT(3);
            USAGE(0x21);
            USAGE(0x22);
            USAGE(0x23);
            INPUT(DATA_VAR_ABS);
            END_COLLECTION();
        }
        /* fovea's vendor extension: pupil diameters, µm, 16 bits */
        USAGE_PAGE(FV_HID_FOVEA_VENDOR_PAGE, 2);
        USAGE(FV_HID_FOVEA_USAGE_PUPIL & 0xFFFFu);
        COLLECTION(0);
        REPORT_SIZE(16);
        REPORT_COUNT(2);
        LOGICAL_MIN(0, 1);
        LOGICAL_MAX(PUPIL_MAX_UM, 2);
        USAGE(FV_HID_FOVEA_USAGE_PUPIL_LEFT & 0xFFFFu);
        USAGE(FV_HID_FOVEA_USAGE_PUPIL_RIGHT & 0xFFFFu);
        INPUT(DATA_VAR_ABS);
        END_COLLECTION();
        USAGE_PAGE(0x12, 1);
        END_COLLECTION();
    }
    {
        USAGE(0x11); /* Capabilities */
        COLLECTION(2);
        REPORT_ID(0x11);
        REPORT_SIZE(8);
        REPORT_COUNT(1);
        USAGE(0x100);
        LOGICAL_MIN(0, 1);
        LOGICAL_MAX(1, 1);
        UNIT(0, 1);
        UNIT_EXPONENT(0);
        FEATURE(DATA_VAR_ABS);
        REPORT_COUNT(5);
        REPORT_SIZE(32);
        LOGICAL_MIN(-POS_LIMIT_UM, 4);
        LOGICAL_MAX(POS_LIMIT_UM, 4);
        UNIT(0x11, 1);
        UNIT_EXPONENT(-4);
        for (unsigned u = 0x101; u <= 0x105; u++) USAGE(u);
        FEATURE(DATA_VAR_ABS);
        END_COLLECTION();
    }
    {
        USAGE(0x12); /* Configuration */
        COLLECTION(2);
        REPORT_ID(0x12);
        REPORT_COUNT(1);
        REPORT_SIZE(16);
        LOGICAL_MIN(0, 1);
        LOGICAL_MAX(65535, 4);
        UNIT(0, 1);
        UNIT_EXPONENT(0);
        USAGE(0x200);
        FEATURE(DATA_VAR_ABS);
        USAGE(0x201);
        FEATURE(DATA_VAR_ABS);
        REPORT_SIZE(32);
        LOGICAL_MAX(0x7FFFFFFF, 4);
        USAGE(0x202);
        FEATURE(DATA_VAR_ABS);
        REPORT_SIZE(16);
        LOGICAL_MAX(65535, 4);
        USAGE(0x203);
        FEATURE(DATA_VAR_ABS);
        UNIT(0x11, 1);
        UNIT_EXPONENT(-4);
        LOGICAL_MAX(0x7FFFFFFF, 4);
        REPORT_SIZE(32);
        USAGE(0x204);
        FEATURE(DATA_VAR_ABS);
        USAGE(0x205);
        FEATURE(DATA_VAR_ABS);
        END_COLLECTION();
    }
    for (int pass = 0; pass < 2; pass++) { /* Status: feature, then the same ID as input */
        USAGE(0x13);
        COLLECTION(2);
        REPORT_ID(0x13);
        REPORT_SIZE(8);
        UNIT(0, 1);
        UNIT_EXPONENT(0);
        LOGICAL_MAX(4, 1);
        USAGE(0x301);
        if (pass == 0) FEATURE(DATA_VAR_ABS);
        else INPUT(DATA_VAR_ABS);
        REPORT_SIZE(16);
        LOGICAL_MAX(65535, 4);
        UNIT(0xF001, 2); /* s^-1: Hz */
        USAGE(0x300);
        if (pass == 0) FEATURE(DATA_VAR_ABS);
        else INPUT(DATA_VAR_ABS);
        END_COLLECTION();
    }
    {
        USAGE(0x14); /* Control */
        COLLECTION(2);
        REPORT_ID(0x14);
        REPORT_SIZE(8);
        LOGICAL_MAX(7, 1);
        UNIT(0, 1);
        USAGE(0x400);
        FEATURE(DATA_VAR_ABS);
        END_COLLECTION();
    }
    END_COLLECTION();
    return w.len <= cap ? w.len : 0;
}

fv_result fv_vhid_create(const fv_vhid_desc *desc, fv_vhid **out)
{
    fv_result r = FV_OK;
    fv_vhid *v = calloc(1, sizeof *v);
    if (!v) return FV_ERR_NO_MEMORY;
    v->len = build_descriptor(v->bytes, sizeof v->bytes);
    if (v->len == 0) {
        r = FV_ERR_NO_MEMORY;
        goto fail;
    }
    r = fv_hid_descriptor_parse(v->bytes, v->len, &v->desc);
    if (FV_FAILED(r)) goto fail;
    r = fv_hid_eyetracker_map_init(&v->desc, fv_hid_quirk_find(FV_VHID_VID, FV_VHID_PID), &v->map);
    if (FV_FAILED(r)) goto fail;
    if (desc && desc->screen) v->screen = *desc->screen;
    else fv_hid_screen_config_defaults(&v->screen);
    v->screen.width_mm = desc && desc->screen_width_mm > 0 ? desc->screen_width_mm : 527.0f;
    v->screen.height_mm = desc && desc->screen_height_mm > 0 ? desc->screen_height_mm : 296.0f;
    v->hz = desc && desc->sampling_hz ? desc->sampling_hz : 120;
    *out = v;
    return FV_OK;
fail:
    FV_ERROR(MOD, "cannot build the virtual tracker's descriptor (%s)", fv_result_str(r));
    free(v);
    return r;
}

void fv_vhid_destroy(fv_vhid **v)
{
    if (v && *v) {
        free(*v);
        *v = NULL;
    }
}

const uint8_t *fv_vhid_descriptor(const fv_vhid *v, size_t *out_len)
{
    *out_len = v->len;
    return v->bytes;
}

const fv_hid_screen_config *fv_vhid_screen(const fv_vhid *v) { return &v->screen; }

static fv_result put(fv_vhid *v, fv_hid_ref ref, int64_t value, uint8_t *payload, size_t plen)
{
    if (ref.field < 0) return FV_OK;
    return fv_hid_field_write(&v->desc.fields[ref.field], ref.index, value, payload, plen);
}

/* mm → µm, or the out-of-range marker when invalid or beyond the logical range. */
static int64_t um_or_invalid(double mm, int64_t limit, int64_t invalid)
{
    if (!isfinite(mm)) return invalid;
    double um = round(mm * 1000.0);
    if (um < (double)-limit || um > (double)limit) return invalid;
    return (int64_t)um;
}

static fv_vec3 head_to_tracker(const fv_hid_screen_config *s, fv_vec3 p_head)
{
    fv_quat inv = {-s->tracker_to_head.x, -s->tracker_to_head.y, -s->tracker_to_head.z, s->tracker_to_head.w};
    return fv_quat_rotate(inv, fv_v3_sub(p_head, s->screen_center_head_mm));
}

fv_result fv_vhid_encode_sample(fv_vhid *v, const fv_gaze_sample *s, uint8_t *buf, size_t cap, size_t *out_len)
{
    const fv_hid_report *rep = fv_hid_descriptor_find_report(&v->desc, FV_HID_REPORT_INPUT, v->map.tracking_id);
    size_t n = fv_hid_report_byte_length(&v->desc, rep);
    if (n > cap) return FV_ERR_RANGE;
    if (s->t_device_ns < 0) {
        FV_ERROR(MOD, "sample %llu: negative device time cannot be sent", (unsigned long long)s->seq);
        return FV_ERR_RANGE;
    }
    memset(buf, 0, n);
    buf[0] = v->map.tracking_id;
    uint8_t *p = buf + 1;
    size_t plen = n - 1;
    const int64_t INVALID = INT32_MAX;

    uint64_t us = (uint64_t)(s->t_device_ns / 1000);
    const fv_hid_field *tf = &v->desc.fields[v->map.timestamp.field];
    for (uint32_t i = 0; i < tf->count; i++) FV_TRY(fv_hid_field_write(tf, i, (int64_t)((us >> (8 * i)) & 0xFFu), p, plen));

    /* The gaze point: where the combined ray (else a valid eye's ray) meets the screen plane z = 0 (tracker frame). */
    const fv_eye_sample *src = NULL;
    fv_vec3 origin = fv_v3(0, 0, 0);
    if (s->combined.flags & FV_EYE_DIRECTION_VALID) {
        src = &s->combined;
        origin = (s->combined.flags & FV_EYE_ORIGIN_VALID)
                     ? s->combined.origin_mm
                     : fv_v3_scale(fv_v3_add(v->screen.default_eye_head_mm[0], v->screen.default_eye_head_mm[1]), 0.5f);
    } else {
        for (int e = 0; e < 2 && !src; e++)
            if (s->eye[e].flags & FV_EYE_DIRECTION_VALID) {
                src = &s->eye[e];
                origin = (s->eye[e].flags & FV_EYE_ORIGIN_VALID) ? s->eye[e].origin_mm : v->screen.default_eye_head_mm[e];
            }
    }
    int64_t gx = INVALID, gy = INVALID;
    if (src) {
        fv_vec3 o = head_to_tracker(&v->screen, origin);
        fv_vec3 d = head_to_tracker(&v->screen, fv_v3_add(origin, src->direction));
        d = fv_v3_sub(d, o);
        if (d.z < -1e-6f) { /* heading into the screen */
            double t = -(double)o.z / (double)d.z;
            double x = (double)o.x + t * d.x + 0.5 * v->screen.width_mm;
            double y = 0.5 * v->screen.height_mm - ((double)o.y + t * d.y);
            gx = um_or_invalid(x, POS_LIMIT_UM, INVALID);
            gy = um_or_invalid(y, POS_LIMIT_UM, INVALID);
            if (gx == INVALID || gy == INVALID) gx = gy = INVALID;
        }
    }
    FV_TRY(put(v, v->map.gaze[0], gx, p, plen));
    FV_TRY(put(v, v->map.gaze[1], gy, p, plen));

    for (int e = 0; e < 2; e++) {
        bool ok = (s->eye[e].flags & FV_EYE_ORIGIN_VALID) != 0;
        fv_vec3 t = head_to_tracker(&v->screen, s->eye[e].origin_mm);
        float c[3] = {t.x, t.y, t.z};
        for (int a = 0; a < 3; a++) FV_TRY(put(v, v->map.eye[e][a], ok ? um_or_invalid(c[a], POS_LIMIT_UM, INVALID) : INVALID, p, plen));
        int64_t pupil = (s->eye[e].flags & FV_EYE_PUPIL_VALID) ? um_or_invalid(s->eye[e].pupil_mm, PUPIL_MAX_UM, 0xFFFF)
                                                                : 0xFFFF;
        if (pupil < 0) pupil = 0xFFFF;
        FV_TRY(put(v, v->map.pupil[e], pupil, p, plen));
    }
    *out_len = n;
    return FV_OK;
}

static fv_result feature_buf(fv_vhid *v, fv_hid_report_type type, uint8_t id, uint8_t *buf, size_t cap, size_t *n)
{
    const fv_hid_report *rep = fv_hid_descriptor_find_report(&v->desc, type, id);
    if (!rep) return FV_ERR_NOT_FOUND;
    *n = fv_hid_report_byte_length(&v->desc, rep);
    if (*n > cap) return FV_ERR_RANGE;
    memset(buf, 0, *n);
    buf[0] = id;
    return FV_OK;
}

fv_result fv_vhid_feature(fv_vhid *v, uint8_t id, uint8_t *buf, size_t cap, size_t *out_len)
{
    size_t n;
    FV_TRY(feature_buf(v, FV_HID_REPORT_FEATURE, id, buf, cap, &n));
    uint8_t *p = buf + 1;
    size_t plen = n - 1;
    const fv_hid_eyetracker_map *m = &v->map;
    switch (id) {
    case 0x11:
        FV_TRY(put(v, m->quality, 1, p, plen));
        FV_TRY(put(v, m->min_distance, 0, p, plen)); /* a head-mounted tracker: the eyes are always in range */
        FV_TRY(put(v, m->optimum_distance, 20000, p, plen));
        FV_TRY(put(v, m->max_distance, 60000, p, plen));
        FV_TRY(put(v, m->max_screen_width, (int64_t)llround(v->screen.width_mm * 1000.0), p, plen));
        FV_TRY(put(v, m->max_screen_height, (int64_t)llround(v->screen.height_mm * 1000.0), p, plen));
        break;
    case 0x12:
        FV_TRY(put(v, m->display_manufacturer, 0x1209, p, plen));
        FV_TRY(put(v, m->display_product, 0x0001, p, plen));
        FV_TRY(put(v, m->display_serial, 1, p, plen));
        FV_TRY(put(v, m->display_date, 0, p, plen));
        FV_TRY(put(v, m->calibrated_width, (int64_t)llround(v->screen.width_mm * 1000.0), p, plen));
        FV_TRY(put(v, m->calibrated_height, (int64_t)llround(v->screen.height_mm * 1000.0), p, plen));
        break;
    case 0x13:
        FV_TRY(put(v, m->status_config[0], FV_HID_STATUS_READY, p, plen));
        FV_TRY(put(v, m->status_frequency[0], v->hz, p, plen));
        break;
    default: return FV_ERR_NOT_FOUND;
    }
    *out_len = n;
    return FV_OK;
}

fv_result fv_vhid_status_input(fv_vhid *v, int status, unsigned hz, uint8_t *buf, size_t cap, size_t *out_len)
{
    size_t n;
    FV_TRY(feature_buf(v, FV_HID_REPORT_INPUT, 0x13, buf, cap, &n));
    FV_TRY(put(v, v->map.status_config[1], status, buf + 1, n - 1));
    FV_TRY(put(v, v->map.status_frequency[1], hz, buf + 1, n - 1));
    *out_len = n;
    return FV_OK;
}

fv_result fv_vhid_transport_create(fv_vhid *v, fv_hid_transport **out, fv_hid_fake **out_fake)
{
    fv_hid_fake_desc fd = {
        .descriptor = v->bytes,
        .descriptor_len = v->len,
        .vid = FV_VHID_VID,
        .pid = FV_VHID_PID,
        .gate_on_mode_request = 1,
        .mode_report_id = 0x14,
    };
    fv_hid_fake *fake;
    fv_hid_transport *t;
    FV_TRY(fv_hid_fake_create(&fd, &t, &fake));
    snprintf(t->name, sizeof t->name, "fovea virtual HID eye tracker");
    snprintf(t->path, sizeof t->path, "vhid");
    uint8_t buf[64];
    size_t n;
    static const uint8_t ids[] = {0x11, 0x12, 0x13};
    for (size_t i = 0; i < sizeof ids; i++) {
        fv_result r = fv_vhid_feature(v, ids[i], buf, sizeof buf, &n);
        if (r == FV_OK) r = fv_hid_fake_set_feature_reply(fake, buf, n);
        if (FV_FAILED(r)) {
            fv_hid_transport_destroy(&t);
            return r;
        }
    }
    *out = t;
    if (out_fake) *out_fake = fake;
    return FV_OK;
}
