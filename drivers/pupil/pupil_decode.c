/* @brief Pure decoding of Pupil Capture gaze datums (msgpack maps) into fv_gaze_sample, head frame. Field names and
 * meanings are Pupil Capture's network API: timestamp (s, Pupil time), confidence (0..1), norm_pos (scene image,
 * origin bottom-left), gaze_point_3d (mm, scene camera frame), binocular eye_centers_3d / gaze_normals_3d (maps keyed
 * by eye id 0/1), monocular eye_center_3d / gaze_normal_3d, base_data (the pupil datums, with id and diameter_3d). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <msgpack.h>

#include "fv_gaze_validity.h"
#include "fv_pupil_driver.h"

/* Plausible bounds: beyond them a value is broken, not a measurement. */
#define ORIGIN_LIMIT_MM 1.0e4
#define PUPIL_MAX_MM 20.0
#define PUPIL_TIME_MAX_S 9.0e9 /* Pupil time fits int64 ns up to 9.2e9 s */

typedef struct dec {
    char *why;
    size_t cap;
} dec;

static fv_result fail(dec *d, const char *fmt, ...) FV_PRINTF(2, 3);
static fv_result fail(dec *d, const char *fmt, ...)
{
    if (d->why && d->cap) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(d->why, d->cap, fmt, ap);
        va_end(ap);
    }
    return FV_ERR_PARSE;
}

static const char *type_name(msgpack_object_type t)
{
    switch (t) {
    case MSGPACK_OBJECT_NIL: return "nil";
    case MSGPACK_OBJECT_BOOLEAN: return "a boolean";
    case MSGPACK_OBJECT_POSITIVE_INTEGER:
    case MSGPACK_OBJECT_NEGATIVE_INTEGER: return "an integer";
    case MSGPACK_OBJECT_FLOAT32:
    case MSGPACK_OBJECT_FLOAT64: return "a number";
    case MSGPACK_OBJECT_STR: return "a string";
    case MSGPACK_OBJECT_ARRAY: return "an array";
    case MSGPACK_OBJECT_MAP: return "a map";
    case MSGPACK_OBJECT_BIN: return "binary";
    case MSGPACK_OBJECT_EXT: return "an extension";
    }
    return "unknown";
}

static bool key_is(const msgpack_object *k, const char *name)
{
    size_t n = strlen(name);
    return k->type == MSGPACK_OBJECT_STR && k->via.str.size == n && memcmp(k->via.str.ptr, name, n) == 0;
}

static const msgpack_object *map_get(const msgpack_object *map, const char *name)
{
    for (uint32_t i = 0; i < map->via.map.size; i++)
        if (key_is(&map->via.map.ptr[i].key, name)) return &map->via.map.ptr[i].val;
    return NULL;
}

/* Eye id of a map key: the integer 0/1 (msgpack of a Python dict keyed by int) or the string "0"/"1". -1 else. */
static int eye_key(const msgpack_object *k)
{
    if (k->type == MSGPACK_OBJECT_POSITIVE_INTEGER && k->via.u64 <= 1) return (int)k->via.u64;
    if (k->type == MSGPACK_OBJECT_STR && k->via.str.size == 1 && (k->via.str.ptr[0] == '0' || k->via.str.ptr[0] == '1'))
        return k->via.str.ptr[0] - '0';
    return -1;
}

/* A finite number. field names the value in the reason. */
static fv_result num(dec *d, const msgpack_object *o, const char *field, double *out)
{
    switch (o->type) {
    case MSGPACK_OBJECT_FLOAT32:
    case MSGPACK_OBJECT_FLOAT64: *out = o->via.f64; break;
    case MSGPACK_OBJECT_POSITIVE_INTEGER: *out = (double)o->via.u64; break;
    case MSGPACK_OBJECT_NEGATIVE_INTEGER: *out = (double)o->via.i64; break;
    default: return fail(d, "field '%s' is %s, not a number", field, type_name(o->type));
    }
    if (!isfinite(*out)) return fail(d, "field '%s' is %s", field, isnan(*out) ? "NaN" : "infinite");
    return FV_OK;
}

static fv_result vec(dec *d, const msgpack_object *o, const char *field, uint32_t n, double *out)
{
    if (o->type != MSGPACK_OBJECT_ARRAY)
        return fail(d, "field '%s' is %s, not an array of %u numbers", field, type_name(o->type), n);
    if (o->via.array.size != n)
        return fail(d, "field '%s' has %u values, not %u", field, o->via.array.size, n);
    for (uint32_t i = 0; i < n; i++) {
        char name[64];
        snprintf(name, sizeof name, "%s[%u]", field, i);
        fv_result r = num(d, &o->via.array.ptr[i], name, &out[i]);
        if (r != FV_OK) return r;
    }
    return FV_OK;
}

static void set_origin(fv_eye_sample *e, double x, double y, double z)
{
    if (fabs(x) > ORIGIN_LIMIT_MM || fabs(y) > ORIGIN_LIMIT_MM || fabs(z) > ORIGIN_LIMIT_MM) return;
    e->origin_mm = fv_v3((float)x, (float)y, (float)z);
    e->flags |= FV_EYE_ORIGIN_VALID;
}

/* Normalised in double; a zero-length vector stays invalid. */
static void set_direction(fv_eye_sample *e, double x, double y, double z)
{
    double n = sqrt(x * x + y * y + z * z);
    if (!isfinite(n) || n < 1e-6) return;
    e->direction = fv_v3((float)(x / n), (float)(y / n), (float)(z / n));
    e->flags |= FV_EYE_DIRECTION_VALID;
}

/* camera frame (x right, y down, z forward) -> head frame (x, -y, -z); eye 0 is the right eye */
static fv_eye_sample *eye_of(fv_gaze_sample *s, int id) { return &s->eye[id == 0 ? FV_EYE_RIGHT : FV_EYE_LEFT]; }

/* One per-eye 3D vector field: binocular (a map by eye id) or monocular (an array, for the topic's eye). */
static fv_result eye_vectors(dec *d, fv_gaze_sample *s, const msgpack_object *o, const char *field, int mono_eye,
                             bool origin)
{
    double v[3];
    if (o->type == MSGPACK_OBJECT_MAP) {
        for (uint32_t i = 0; i < o->via.map.size; i++) {
            int id = eye_key(&o->via.map.ptr[i].key);
            if (id < 0) return fail(d, "field '%s' has a key that is not eye 0 or 1", field);
            char name[64];
            snprintf(name, sizeof name, "%s.%d", field, id);
            fv_result r = vec(d, &o->via.map.ptr[i].val, name, 3, v);
            if (r != FV_OK) return r;
            if (origin) set_origin(eye_of(s, id), v[0], -v[1], -v[2]);
            else set_direction(eye_of(s, id), v[0], -v[1], -v[2]);
        }
        return FV_OK;
    }
    fv_result r = vec(d, o, field, 3, v);
    if (r != FV_OK) return r;
    if (mono_eye < 0) return fail(d, "field '%s' is for one eye but the topic names no eye", field);
    if (origin) set_origin(eye_of(s, mono_eye), v[0], -v[1], -v[2]);
    else set_direction(eye_of(s, mono_eye), v[0], -v[1], -v[2]);
    return FV_OK;
}

/* Eye of a monocular topic ("gaze.3d.1.", "gaze.2d.0."): 0/1, or -1 for binocular ("01") or none. */
static int topic_eye(const char *topic, size_t len)
{
    /* gaze.<method>.<eyes>. */
    size_t dots = 0, start = 0, end = 0;
    for (size_t i = 0; i < len; i++) {
        if (topic[i] != '.') continue;
        dots++;
        if (dots == 2) start = i + 1;
        if (dots == 3) {
            end = i;
            break;
        }
    }
    if (dots < 3 || end != start + 1) return -1;
    return (topic[start] == '0' || topic[start] == '1') ? topic[start] - '0' : -1;
}

static fv_result decode_map(dec *d, const msgpack_object *m, int mono_eye, const fv_pupil_camera *cam,
                            double min_confidence, fv_gaze_sample *s)
{
    const msgpack_object *o;
    double ts, conf, v[3];
    if (!(o = map_get(m, "timestamp"))) return fail(d, "missing field 'timestamp'");
    FV_TRY(num(d, o, "timestamp", &ts));
    if (ts < 0.0 || ts > PUPIL_TIME_MAX_S) return fail(d, "field 'timestamp' %.17g s is outside [0, 9e9] s", ts);
    s->t_device_ns = (int64_t)llround(ts * 1e9);
    if (!(o = map_get(m, "confidence"))) return fail(d, "missing field 'confidence'");
    FV_TRY(num(d, o, "confidence", &conf));
    if (conf < 0.0 || conf > 1.0) return fail(d, "field 'confidence' %g is outside [0, 1]", conf);
    s->confidence = (float)conf;

    /* 3D pipeline: per-eye centres and normals */
    const char *cn = NULL, *nn = NULL;
    const msgpack_object *centres = NULL, *normals = NULL;
    if ((centres = map_get(m, "eye_centers_3d"))) cn = "eye_centers_3d";
    else if ((centres = map_get(m, "eye_center_3d"))) cn = "eye_center_3d";
    if ((normals = map_get(m, "gaze_normals_3d"))) nn = "gaze_normals_3d";
    else if ((normals = map_get(m, "gaze_normal_3d"))) nn = "gaze_normal_3d";
    if (centres) FV_TRY(eye_vectors(d, s, centres, cn, mono_eye, true));
    if (normals) FV_TRY(eye_vectors(d, s, normals, nn, mono_eye, false));

    fv_eye_sample *cb = &s->combined;
    if ((o = map_get(m, "gaze_point_3d"))) {
        FV_TRY(vec(d, o, "gaze_point_3d", 3, v));
        const fv_eye_sample *l = &s->eye[FV_EYE_LEFT], *r = &s->eye[FV_EYE_RIGHT];
        bool lo = l->flags & FV_EYE_ORIGIN_VALID, ro = r->flags & FV_EYE_ORIGIN_VALID;
        if (lo && ro)
            set_origin(cb, 0.5 * ((double)l->origin_mm.x + r->origin_mm.x),
                       0.5 * ((double)l->origin_mm.y + r->origin_mm.y), 0.5 * ((double)l->origin_mm.z + r->origin_mm.z));
        else if (lo || ro)
            set_origin(cb, (lo ? l : r)->origin_mm.x, (lo ? l : r)->origin_mm.y, (lo ? l : r)->origin_mm.z);
        /* from the eye(s) to the gaze point; from the scene camera when no eye centre is known. The point is
         * rounded to float first, as the recorded reader does, so live and recorded data decode alike. */
        fv_vec3 p = fv_v3((float)v[0], (float)-v[1], (float)-v[2]);
        fv_vec3 c = (cb->flags & FV_EYE_ORIGIN_VALID) ? cb->origin_mm : fv_v3(0, 0, 0);
        fv_vec3 eyes;
        fv_gaze_sample only_eyes = *s;
        only_eyes.combined.flags &= ~(uint32_t)FV_EYE_DIRECTION_VALID;
        if (v[2] < 0.0 && isfinite(v[0]) && isfinite(v[1])) {
            /* the lines of sight met behind the head (a quirk Pupil Labs documents): their repair, as the recorded
             * reader makes it (trace_fmt_pupil.c): the eyes' possible gaze normals averaged, else the point flipped */
            if (fv_gaze_sample_direction(&only_eyes, &eyes)) set_direction(cb, eyes.x, eyes.y, eyes.z);
            else set_direction(cb, -v[0], v[1], v[2]);
        } else if (fv_v3_isfinite(p)) {
            set_direction(cb, (double)p.x - c.x, (double)p.y - c.y, (double)p.z - c.z);
        }
    }
    if ((o = map_get(m, "norm_pos"))) {
        FV_TRY(vec(d, o, "norm_pos", 2, v));
        if (!(cb->flags & FV_EYE_DIRECTION_VALID)) {
            /* norm_pos: (0,0) bottom-left, (1,1) top-right; pixel y grows down */
            double px = v[0] * cam->width_px, py = (1.0 - v[1]) * cam->height_px;
            set_direction(cb, (px - cam->cx_px) / cam->fx_px, (cam->cy_px - py) / cam->fy_px, -1.0);
        }
    } else if (!(cb->flags & FV_EYE_DIRECTION_VALID) && !(s->eye[0].flags & FV_EYE_DIRECTION_VALID) &&
               !(s->eye[1].flags & FV_EYE_DIRECTION_VALID)) {
        return fail(d, "no gaze: none of 'norm_pos', 'gaze_point_3d', 'gaze_normals_3d' or 'gaze_normal_3d'");
    }
    /* One eye's ray without gaze_point_3d: the combined ray is that eye's */
    if (!(cb->flags & FV_EYE_DIRECTION_VALID)) {
        for (int k = 0; k < 2; k++)
            if (s->eye[k].flags & FV_EYE_DIRECTION_VALID)
                set_direction(cb, s->eye[k].direction.x, s->eye[k].direction.y, s->eye[k].direction.z);
    }

    /* base_data: the pupil datums this gaze came from; diameter_3d is the pupil's diameter in mm (3D model) */
    if ((o = map_get(m, "base_data"))) {
        if (o->type != MSGPACK_OBJECT_ARRAY)
            return fail(d, "field 'base_data' is %s, not an array of pupil datums", type_name(o->type));
        for (uint32_t i = 0; i < o->via.array.size; i++) {
            const msgpack_object *p = &o->via.array.ptr[i], *f;
            if (p->type != MSGPACK_OBJECT_MAP)
                return fail(d, "field 'base_data[%u]' is %s, not a pupil datum (a map)", i, type_name(p->type));
            double id, dia;
            char name[64];
            snprintf(name, sizeof name, "base_data[%u].id", i);
            if (!(f = map_get(p, "id"))) return fail(d, "missing field '%s'", name);
            FV_TRY(num(d, f, name, &id));
            if (id != 0.0 && id != 1.0) return fail(d, "field '%s' is %g, not eye 0 or 1", name, id);
            if (!(f = map_get(p, "diameter_3d"))) continue; /* 2D pupil detection: a diameter in eye-image px only */
            snprintf(name, sizeof name, "base_data[%u].diameter_3d", i);
            FV_TRY(num(d, f, name, &dia));
            fv_eye_sample *e = eye_of(s, (int)id);
            if (dia > 0.0 && dia <= PUPIL_MAX_MM) {
                e->pupil_mm = (float)dia;
                e->flags |= FV_EYE_PUPIL_VALID;
            }
        }
    }

    if (min_confidence >= 0.0 && !(conf >= min_confidence)) { /* kept, as an invalid sample */
        fv_gaze_sample inv;
        fv_gaze_sample_init_invalid(&inv, s->t_device_ns, 0);
        s->eye[0] = inv.eye[0];
        s->eye[1] = inv.eye[1];
        s->combined = inv.combined;
    }
    (void)fv_gaze_sample_enforce(s); /* physically impossible gaze: the rules every reader applies */
    return FV_OK;
}

/* Big-endian unsigned of n bytes at p. */
static uint64_t be(const uint8_t *p, unsigned n)
{
    uint64_t v = 0;
    for (unsigned i = 0; i < n; i++) v = v << 8 | p[i];
    return v;
}

/* One msgpack value must fill the payload exactly. A syntactic walk (no allocation, an explicit stack of
 * FV_PUPIL_MAX_DEPTH levels): each header must be complete, each string/bin/ext size and each array/map count must
 * fit in the bytes left (an element takes at least one byte), the value must end where the payload does. After it,
 * msgpack-c allocates at most one object per payload byte. */
static fv_result precheck(dec *d, const uint8_t *p, size_t len)
{
    uint64_t items[FV_PUPIL_MAX_DEPTH + 1]; /* values still to read at each open level; [0]: the top value */
    int depth = 0;
    items[0] = 1;
    size_t off = 0;
    while (depth >= 0) {
        if (items[depth] == 0) {
            depth--;
            continue;
        }
        items[depth]--;
        if (off >= len) return fail(d, "payload is not msgpack: truncated after %zu bytes (a value is missing)", len);
        size_t at = off;
        uint8_t b = p[off];
        unsigned hdr = 1, lenb = 0; /* header bytes; bytes of its size/count field (after the type byte) */
        uint64_t size = 0, count = 0; /* payload bytes; elements (a map's entries count twice) */
        const char *what = NULL;      /* a container or sized value, for the reason */
        bool map = false;
        if (b <= 0x7f || b >= 0xe0 || b == 0xc0 || b == 0xc2 || b == 0xc3) {
            /* fixint, nil, bool */
        } else if (b <= 0x8f) {
            count = 2u * (b & 0x0fu), what = "a map", map = true;
        } else if (b <= 0x9f) {
            count = b & 0x0fu, what = "an array";
        } else if (b <= 0xbf) {
            size = b & 0x1fu, what = "a string";
        } else if (b == 0xc1) {
            return fail(d, "payload is not msgpack (parse error: byte 0x%02x at offset %zu is never used in msgpack)",
                        b, at);
        } else if (b >= 0xc4 && b <= 0xc6) { /* bin 8/16/32 */
            lenb = 1u << (b - 0xc4), hdr = 1 + lenb, what = "binary data";
        } else if (b >= 0xc7 && b <= 0xc9) { /* ext 8/16/32: size, then the type byte */
            lenb = 1u << (b - 0xc7), hdr = 2 + lenb, what = "an extension";
        } else if (b == 0xca || b == 0xcb) {
            hdr = b == 0xca ? 5 : 9;
        } else if ((b >= 0xcc && b <= 0xcf) || (b >= 0xd0 && b <= 0xd3)) {
            hdr = 1 + (1u << (b & 3u));
        } else if (b >= 0xd4 && b <= 0xd8) { /* fixext 1/2/4/8/16 */
            hdr = 2 + (1u << (b - 0xd4));
        } else if (b >= 0xd9 && b <= 0xdb) { /* str 8/16/32 */
            lenb = 1u << (b - 0xd9), hdr = 1 + lenb, what = "a string";
        } else if (b == 0xdc || b == 0xdd) {
            lenb = b == 0xdc ? 2 : 4, hdr = 1 + lenb, what = "an array";
        } else { /* 0xde, 0xdf */
            lenb = b == 0xde ? 2 : 4, hdr = 1 + lenb, what = "a map", map = true;
        }
        if (len - off < hdr)
            return fail(d, "payload is not msgpack: truncated after %zu bytes (a header of %u bytes at offset %zu)",
                        len, hdr, at);
        if (lenb) {
            uint64_t n = be(p + off + 1, lenb);
            if (b >= 0xdc) count = map ? 2 * n : n;
            else size = n;
        }
        off += hdr;
        size_t left = len - off;
        if (size > left)
            return fail(d, "payload is not msgpack: truncated or corrupt: %s of %llu bytes at offset %zu, %zu bytes "
                        "left", what, (unsigned long long)size, at, left);
        if (count > left)
            return fail(d, "payload is not msgpack: truncated or corrupt: %s of %llu %s at offset %zu, %zu bytes left",
                        what, (unsigned long long)(map ? count / 2 : count), map ? "entries" : "elements", at, left);
        off += (size_t)size;
        if (count) {
            if (depth == FV_PUPIL_MAX_DEPTH)
                return fail(d, "payload nests deeper than %d levels (at offset %zu)", FV_PUPIL_MAX_DEPTH, at);
            items[++depth] = count;
        }
    }
    if (off != len) return fail(d, "payload has %zu bytes after its msgpack value", len - off);
    return FV_OK;
}

fv_result fv_pupil_decode_gaze(const char *topic, size_t topic_len, const void *payload, size_t len,
                               const fv_pupil_camera *camera, double min_confidence, fv_gaze_sample *out, char *why,
                               size_t why_cap)
{
    dec d = {why, why_cap};
    if (why && why_cap) why[0] = '\0';
    fv_gaze_sample_init_invalid(out, 0, 0);
    fv_pupil_camera cam = camera ? *camera : fv_pupil_camera_default();
    if (!topic || topic_len < 5 || memcmp(topic, "gaze.", 5) != 0)
        return fail(&d, "topic '%.*s' is not a gaze topic", (int)(topic && topic_len < 64 ? topic_len : 0),
                    topic ? topic : "");
    if (!payload || len == 0) return fail(&d, "empty payload");
    if (len > FV_PUPIL_MAX_PAYLOAD) return fail(&d, "payload of %zu bytes exceeds %d", len, FV_PUPIL_MAX_PAYLOAD);

    /* msgpack-c allocates each array and map as its header says, before it reads the elements: a 5-byte map32
     * header claiming 2^32 entries is a 192 GiB request. The walk below bounds every count and size by the bytes
     * the message has left, and the depth, before msgpack-c sees the bytes. */
    FV_TRY(precheck(&d, (const uint8_t *)payload, len));
    msgpack_unpacked u;
    msgpack_unpacked_init(&u);
    size_t off = 0;
    fv_result r;
    msgpack_unpack_return ur = msgpack_unpack_next(&u, (const char *)payload, len, &off);
    if (ur != MSGPACK_UNPACK_SUCCESS && ur != MSGPACK_UNPACK_EXTRA_BYTES) /* the walk passed: out of memory */
        r = fail(&d, "payload could not be unpacked (msgpack-c: %d)", (int)ur);
    else if (u.data.type != MSGPACK_OBJECT_MAP) r = fail(&d, "payload is %s, not a map", type_name(u.data.type));
    else r = decode_map(&d, &u.data, topic_eye(topic, topic_len), &cam, min_confidence, out);
    msgpack_unpacked_destroy(&u);
    if (r != FV_OK) fv_gaze_sample_init_invalid(out, 0, 0);
    return r;
}
