/* @brief CSV splitting, whole-field number parsing and validated sample setters shared by the trace readers
 * (see trace_util.h: pure, no reader). */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "trace_util.h"
#include "fv_gaze_validity.h"

int trace_csv_split(char *line, char sep, char **fields, int cap)
{
    int n = 0;
    char *p = line;
    for (;;) {
        char *out = p, *start = p;
        if (*p == '"') { /* quoted: "" is a literal quote; text after the closing quote is kept (lenient) */
            p++;
            for (;;) {
                if (*p == '\0') return -1;
                if (*p == '"') {
                    if (p[1] == '"') {
                        *out++ = '"';
                        p += 2;
                        continue;
                    }
                    p++;
                    break;
                }
                *out++ = *p++;
            }
            while (*p && *p != sep) *out++ = *p++;
        } else {
            while (*p && *p != sep) p++;
            out = p;
        }
        char end = *p;
        *out = '\0';
        if (n < cap) fields[n++] = start;
        if (end != sep) break;
        p++;
    }
    return n;
}

static const char *trim_name(const char *s, size_t *out_len)
{
    if ((unsigned char)s[0] == 0xEF && (unsigned char)s[1] == 0xBB && (unsigned char)s[2] == 0xBF) s += 3;
    while (*s == ' ' || *s == '\t') s++;
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r')) n--;
    *out_len = n;
    return s;
}

int trace_csv_find(char *const *fields, int n, const char *name)
{
    size_t want = strlen(name);
    for (int i = 0; i < n; i++) {
        size_t len;
        const char *f = trim_name(fields[i], &len);
        if (len == want && memcmp(f, name, len) == 0) return i;
    }
    return -1;
}

bool trace_field_empty(const char *s)
{
    if (!s) return true;
    while (*s == ' ' || *s == '\t') s++;
    return *s == '\0';
}

static bool only_space(const char *s)
{
    while (*s == ' ' || *s == '\t') s++;
    return *s == '\0';
}

bool trace_parse_f64(const char *s, double *out)
{
    if (trace_field_empty(s)) return false;
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || !only_space(end)) return false;
    if (errno == ERANGE && isinf(v)) return false;
    *out = v;
    return true;
}

bool trace_parse_i64(const char *s, int64_t *out)
{
    if (trace_field_empty(s)) return false;
    char *end = NULL;
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (end == s || !only_space(end) || errno == ERANGE) return false;
    *out = (int64_t)v;
    return true;
}

bool trace_seconds_to_ns(double s, int64_t *out_ns)
{
    if (!isfinite(s) || fabs(s) >= 9.2e9) return false;
    *out_ns = llround(s * 1e9);
    return true;
}

float trace_f32(double v)
{
    if (!isfinite(v) || fabs(v) > (double)FLT_MAX) return NAN;
    return (float)v;
}

/* Plausible bounds: an eye position beyond 10 m of the tracker is a broken value, not a measurement. */
#define ORIGIN_LIMIT_MM 1.0e4
#define PUPIL_MAX_MM 20.0

void trace_eye_set_origin(fv_eye_sample *e, double x, double y, double z)
{
    if (!isfinite(x) || !isfinite(y) || !isfinite(z) || fabs(x) > ORIGIN_LIMIT_MM || fabs(y) > ORIGIN_LIMIT_MM ||
        fabs(z) > ORIGIN_LIMIT_MM) {
        e->origin_mm = fv_v3(NAN, NAN, NAN);
        e->flags &= ~(uint32_t)FV_EYE_ORIGIN_VALID;
        return;
    }
    e->origin_mm = fv_v3((float)x, (float)y, (float)z);
    e->flags |= FV_EYE_ORIGIN_VALID;
}

void trace_eye_set_direction(fv_eye_sample *e, double x, double y, double z)
{
    double n = (isfinite(x) && isfinite(y) && isfinite(z)) ? sqrt(x * x + y * y + z * z) : NAN;
    /* Sources give unit vectors; anything with a usable length is renormalised. A zero vector is the sources'
     * "invalid" marker. Components up to 1e154 cannot overflow the sum of squares; beyond, n is inf and rejected. */
    if (!isfinite(n) || n < 1e-6) {
        e->direction = fv_v3(NAN, NAN, NAN);
        e->flags &= ~(uint32_t)FV_EYE_DIRECTION_VALID;
        return;
    }
    e->direction = fv_v3((float)(x / n), (float)(y / n), (float)(z / n));
    e->flags |= FV_EYE_DIRECTION_VALID;
}

void trace_eye_set_pupil(fv_eye_sample *e, double mm)
{
    if (!isfinite(mm) || mm <= 0.0 || mm > PUPIL_MAX_MM) {
        e->pupil_mm = NAN;
        e->flags &= ~(uint32_t)FV_EYE_PUPIL_VALID;
        return;
    }
    e->pupil_mm = (float)mm;
    e->flags |= FV_EYE_PUPIL_VALID;
}

void trace_eye_set_openness(fv_eye_sample *e, double v)
{
    if (!isfinite(v) || v < 0.0 || v > 1.0) {
        e->openness = NAN;
        e->flags &= ~(uint32_t)FV_EYE_OPENNESS_VALID;
        return;
    }
    e->openness = (float)v;
    e->flags |= FV_EYE_OPENNESS_VALID;
}

void trace_eye_invalidate(fv_eye_sample *e)
{
    e->origin_mm = fv_v3(NAN, NAN, NAN);
    e->direction = fv_v3(NAN, NAN, NAN);
    e->pupil_mm = NAN;
    e->openness = NAN;
    e->flags &= FV_EYE_BLINK;
}

void trace_sample_invalidate(fv_gaze_sample *s, bool blink)
{
    fv_eye_sample *eyes[3] = {&s->eye[0], &s->eye[1], &s->combined};
    for (int i = 0; i < 3; i++) {
        trace_eye_invalidate(eyes[i]);
        if (blink) eyes[i]->flags |= FV_EYE_BLINK;
    }
}

void trace_combined_origin(fv_gaze_sample *s, bool one_ok)
{
    const fv_eye_sample *l = &s->eye[FV_EYE_LEFT], *r = &s->eye[FV_EYE_RIGHT];
    bool lo = (l->flags & FV_EYE_ORIGIN_VALID) != 0, ro = (r->flags & FV_EYE_ORIGIN_VALID) != 0;
    if (lo && ro)
        trace_eye_set_origin(&s->combined, 0.5 * ((double)l->origin_mm.x + r->origin_mm.x),
                             0.5 * ((double)l->origin_mm.y + r->origin_mm.y),
                             0.5 * ((double)l->origin_mm.z + r->origin_mm.z));
    else if (one_ok && (lo || ro))
        trace_eye_set_origin(&s->combined, (lo ? l : r)->origin_mm.x, (lo ? l : r)->origin_mm.y,
                             (lo ? l : r)->origin_mm.z);
}

void trace_combine_eyes(fv_gaze_sample *s)
{
    const fv_eye_sample *l = &s->eye[FV_EYE_LEFT], *r = &s->eye[FV_EYE_RIGHT];
    /* an eye pointing backwards is left out here (the reader's validity rules clear and count it); a mean with it
     * would be a ray neither eye made */
    bool lv = (l->flags & FV_EYE_DIRECTION_VALID) && fv_gaze_direction_possible(l->direction);
    bool rv = (r->flags & FV_EYE_DIRECTION_VALID) && fv_gaze_direction_possible(r->direction);
    fv_eye_sample *c = &s->combined;
    if (lv && rv) {
        trace_eye_set_direction(c, (double)l->direction.x + r->direction.x, (double)l->direction.y + r->direction.y,
                                (double)l->direction.z + r->direction.z);
        trace_combined_origin(s, false);
    } else if (lv || rv) {
        const fv_eye_sample *e = lv ? l : r;
        trace_eye_set_direction(c, e->direction.x, e->direction.y, e->direction.z);
    }
}

/* sin and cos of an angle in degrees, exact (0, ±1) at multiples of 90°: the angle is reduced to [−45°, 45°] around
 * its nearest quadrant first, so 90° gives a forward of exactly (1, 0, 0) rather than cos(π/2) ≈ 6e−17. */
static void sincos_deg(double deg, double *out_s, double *out_c)
{
    double q = nearbyint(deg / 90.0);
    double rad = (deg - q * 90.0) * (3.14159265358979323846 / 180.0);
    double sn = sin(rad), cs = cos(rad);
    switch (((long)fmod(q, 4.0) + 4) % 4) {
    case 0: *out_s = sn, *out_c = cs; break;
    case 1: *out_s = cs, *out_c = -sn; break;
    case 2: *out_s = -sn, *out_c = -cs; break;
    default: *out_s = -cs, *out_c = sn; break;
    }
}

#define HEAD_POS_LIMIT_M 1.0e3 /* a world position beyond 1 km is a broken value */
#define HEAD_ANGLE_LIMIT_DEG 720.0

void trace_set_head_unity(fv_gaze_sample *s, const char *const pos_m[3], const char *const euler_deg[3])
{
    s->head_pos_mm = fv_v3(NAN, NAN, NAN);
    s->head_dir = fv_v3(NAN, NAN, NAN);
    s->flags &= ~(uint32_t)FV_GAZE_HEAD_VALID;
    double p[3], a[3];
    bool all_zero = true;
    for (int k = 0; k < 3; k++) {
        if (!trace_parse_f64(pos_m[k], &p[k]) || !isfinite(p[k]) || fabs(p[k]) > HEAD_POS_LIMIT_M) return;
        if (!trace_parse_f64(euler_deg[k], &a[k]) || !isfinite(a[k]) || fabs(a[k]) > HEAD_ANGLE_LIMIT_DEG) return;
        all_zero = all_zero && p[k] == 0.0 && a[k] == 0.0;
    }
    if (all_zero) return; /* a logger that has no head pose writes zeros */
    /* Unity forward (0,0,1) through R = Ry(a1)·Rx(a0)·Rz(a2): Rz keeps the z axis, Rx(a0) gives (0, −sin a0, cos a0)
     * (a positive pitch looks down), Ry(a1) then gives (cos a0·sin a1, −sin a0, cos a0·cos a1). Roll has no effect. */
    double sx, cx, sy, cy;
    sincos_deg(a[0], &sx, &cx);
    sincos_deg(a[1], &sy, &cy);
    double fx = cx * sy, fy = -sx, fz = cx * cy;
    double n = sqrt(fx * fx + fy * fy + fz * fz); /* 1 up to rounding */
    s->head_pos_mm = fv_v3((float)(p[0] * 1000.0), (float)(p[1] * 1000.0), (float)(-p[2] * 1000.0));
    s->head_dir = fv_v3((float)(fx / n), (float)(fy / n), (float)(-fz / n));
    s->flags |= FV_GAZE_HEAD_VALID;
}
