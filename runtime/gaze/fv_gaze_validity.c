/* @brief Physically possible gaze (see fv_gaze_validity.h): the rules every reader, the pipeline and the evaluation
 * truth apply. */
#include "fv_gaze_validity.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>

#include "fv_math.h"

const char *fv_gaze_fault_str(fv_gaze_fault f)
{
    switch (f) {
    case FV_GAZE_FAULT_POINT_BEHIND: return "gaze point behind the head";
    case FV_GAZE_FAULT_BACKWARD: return "direction pointing backwards";
    case FV_GAZE_FAULT_DIVERGENT: return "eyes diverging";
    case FV_GAZE_FAULT_CONVERGENT: return "eyes converging";
    case FV_GAZE_FAULT_VERTICAL: return "eyes misaligned vertically";
    case FV_GAZE_FAULTS: break;
    }
    return "unknown";
}

bool fv_gaze_direction_possible(fv_vec3 d)
{
    if (!fv_v3_isfinite(d)) return false;
    double x = d.x, y = d.y, z = d.z, n = sqrt(x * x + y * y + z * z);
    return n > 1e-6 && isfinite(n) && z / n < -1e-6; /* strictly forward of the head's frontal plane */
}

bool fv_gaze_eye_usable(const fv_eye_sample *e)
{
    return (e->flags & FV_EYE_DIRECTION_VALID) && !(e->flags & FV_EYE_BLINK) && fv_gaze_direction_possible(e->direction);
}

int fv_gaze_vergence_fault(fv_vec3 l, fv_vec3 r)
{
    if (!fv_gaze_direction_possible(l) || !fv_gaze_direction_possible(r)) return -1;
    double yl = fv_rad_to_deg(atan2((double)l.x, -(double)l.z)), yr = fv_rad_to_deg(atan2((double)r.x, -(double)r.z));
    double pl = fv_rad_to_deg(atan2((double)l.y, sqrt((double)l.x * l.x + (double)l.z * l.z)));
    double pr = fv_rad_to_deg(atan2((double)r.y, sqrt((double)r.x * r.x + (double)r.z * r.z)));
    double verg = yl - yr; /* the left eye turned right of the right eye: converging */
    if (verg < -FV_GAZE_MAX_DIVERGENCE_DEG) return FV_GAZE_FAULT_DIVERGENT;
    if (verg > FV_GAZE_MAX_CONVERGENCE_DEG) return FV_GAZE_FAULT_CONVERGENT;
    if (fabs(pl - pr) > FV_GAZE_MAX_VERTICAL_VERGENCE_DEG) return FV_GAZE_FAULT_VERTICAL;
    return -1;
}

static void clear_direction(fv_eye_sample *e)
{
    e->direction = fv_v3(NAN, NAN, NAN);
    e->flags &= ~(uint32_t)FV_EYE_DIRECTION_VALID;
}

uint32_t fv_gaze_sample_enforce(fv_gaze_sample *s)
{
    uint32_t faults = 0;
    fv_eye_sample *rays[3] = {&s->eye[FV_EYE_LEFT], &s->eye[FV_EYE_RIGHT], &s->combined};
    for (int i = 0; i < 3; i++) {
        fv_eye_sample *e = rays[i];
        if (!(e->flags & FV_EYE_DIRECTION_VALID) || fv_gaze_direction_possible(e->direction)) continue;
        /* a non-finite or zero vector under a valid flag is a broken value, not a direction: cleared, not counted */
        if (fv_v3_isfinite(e->direction) && fv_v3_len(e->direction) > 1e-6f) faults |= 1u << FV_GAZE_FAULT_BACKWARD;
        clear_direction(e);
    }
    const fv_eye_sample *l = rays[0], *r = rays[1];
    if (fv_gaze_eye_usable(l) && fv_gaze_eye_usable(r)) {
        int f = fv_gaze_vergence_fault(l->direction, r->direction);
        if (f >= 0) {
            faults |= 1u << f;
            for (int i = 0; i < 3; i++) clear_direction(rays[i]);
        }
    }
    return faults;
}

bool fv_gaze_sample_direction(const fv_gaze_sample *s, fv_vec3 *out)
{
    fv_gaze_sample c = *s;
    (void)fv_gaze_sample_enforce(&c);
    if (fv_gaze_eye_usable(&c.combined)) {
        *out = fv_v3_normalize_or(c.combined.direction, fv_v3(0, 0, -1));
        return true;
    }
    int n = 0;
    fv_vec3 sum = fv_v3(0, 0, 0);
    for (int e = 0; e < 2; e++)
        if (fv_gaze_eye_usable(&c.eye[e])) {
            sum = fv_v3_add(sum, fv_v3_normalize_or(c.eye[e].direction, fv_v3(0, 0, -1)));
            n++;
        }
    if (n == 0 || !(fv_v3_len(sum) > 1e-6f)) return false;
    *out = fv_v3_normalize_or(sum, fv_v3(0, 0, -1));
    return true;
}

void fv_gaze_validity_count(fv_gaze_validity_counts *c, uint32_t repaired_bits, uint32_t dropped_bits)
{
    for (int k = 0; k < FV_GAZE_FAULTS; k++) {
        if (repaired_bits & (1u << k)) c->repaired[k]++;
        if (dropped_bits & (1u << k)) c->dropped[k]++;
    }
}

uint64_t fv_gaze_validity_total(const fv_gaze_validity_counts *c, bool repaired)
{
    uint64_t n = 0;
    for (int k = 0; k < FV_GAZE_FAULTS; k++) n += repaired ? c->repaired[k] : c->dropped[k];
    return n;
}

/* Append to buf (NUL-terminated, truncated at cap). */
static void append(char *buf, size_t cap, size_t *n, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static void append(char *buf, size_t cap, size_t *n, const char *fmt, ...)
{
    if (*n + 1 >= cap) return;
    va_list ap;
    va_start(ap, fmt);
    int w = vsnprintf(buf + *n, cap - *n, fmt, ap);
    va_end(ap);
    if (w > 0) *n = *n + (size_t)w < cap ? *n + (size_t)w : cap - 1;
}

static void list_kinds(char *buf, size_t cap, size_t *n, uint64_t total, const uint64_t *v, const char *what)
{
    append(buf, cap, n, "%s%llu %s", *n ? ", " : "", (unsigned long long)total, what);
    if (!total) return;
    const char *sep = " (";
    for (int k = 0; k < FV_GAZE_FAULTS; k++) {
        if (!v[k]) continue;
        append(buf, cap, n, "%s%s: %llu", sep, fv_gaze_fault_str((fv_gaze_fault)k), (unsigned long long)v[k]);
        sep = ", ";
    }
    append(buf, cap, n, ")");
}

void fv_gaze_validity_describe(const fv_gaze_validity_counts *c, char *buf, size_t cap)
{
    if (!cap) return;
    buf[0] = '\0';
    uint64_t rep = fv_gaze_validity_total(c, true), drop = fv_gaze_validity_total(c, false);
    size_t n = 0;
    if (!rep && !drop) {
        append(buf, cap, &n, "none");
        return;
    }
    list_kinds(buf, cap, &n, rep, c->repaired, "repaired");
    list_kinds(buf, cap, &n, drop, c->dropped, "dropped");
}
