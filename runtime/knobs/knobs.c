/* @brief The knob table (every speed/accuracy knob: name, type, range, unit, a value per preset, doc), generated from
 * the one knob list (fv_knob_list.h), and the presets, NAME=VALUE parsing, formatting, validation and sanitising
 * built on it. */
#include "fv_knobs.h"

#include <assert.h>
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Storage: bools are one byte, ints uint32_t, enums 4-byte C enums read as uint32_t. */
_Static_assert(sizeof(bool) == 1, "bool knobs are stored in one byte");
_Static_assert(sizeof(fv_shadow_filter) == sizeof(uint32_t), "enum knobs are stored in 4 bytes");

static const char *const g_presets[FV_QUALITY_PRESET_COUNT] = {"fast", "balanced", "high", "exact"};
/* ---- the table, generated from the one knob list (fv_knob_list.h) ------------------------------------------- */

#define UNPAREN_(...) __VA_ARGS__
#define VALUE_BOOL(x) {.b = (x)}
#define VALUE_INT(x) {.i = (x)}
#define VALUE_ENUM(x) {.i = (x)}
#define VALUE_FLOAT(x) {.f = (x)}
#define CHOICES_BOOL(c) .choices = NULL, .choice_count = 0
#define CHOICES_INT(c) .choices = NULL, .choice_count = 0
#define CHOICES_FLOAT(c) .choices = NULL, .choice_count = 0
#define CHOICES_ENUM(c)                                                                                                \
    .choices = (const char *const[]){UNPAREN_ c},                                                                      \
    .choice_count = (uint32_t)(sizeof((const char *const[]){UNPAREN_ c}) / sizeof(const char *))
#define FIELD_(group, field) ((fv_quality *)0)->group.field

#define ROW_(group, field, name_, TYPE, ctype, lo, hi, pow2_, unit_, choices_, fast_, balanced_, high_, exact_,      \
             doc_, exact_note_)                                                                                        \
    {.name = #group "." #name_, .type = FV_KNOB_##TYPE, .min = (lo), .max = (hi), .pow2 = (pow2_), .unit = (unit_),   \
     CHOICES_##TYPE(choices_), .offset = offsetof(fv_quality, group.field), .size = sizeof(FIELD_(group, field)),     \
     .fast = VALUE_##TYPE(fast_), .balanced = VALUE_##TYPE(balanced_), .high = VALUE_##TYPE(high_),                   \
     .exact = VALUE_##TYPE(exact_), .doc = (doc_), .exact_note = (exact_note_)},

static const fv_knob g_knobs[] = {FV_KNOB_LIST(ROW_)};

/* What the list promises, checked by the compiler for every row: the field's storage matches the type (bool: one
 * byte, float: a float, int and enum: 4 bytes), a bool's range is 0..1, an enum's 0..choices-1, an int's min <= max
 * (float bounds are not integer constant expressions: test_knobs checks them). */
#define TYPE_OF_(x) _Generic((x), bool: FV_KNOB_BOOL, float: FV_KNOB_FLOAT, default: FV_KNOB_INT)
#define RANGE_BOOL(lo, hi, c) ((lo) == 0 && (hi) == 1)
#define RANGE_INT(lo, hi, c) ((lo) <= (hi))
#define RANGE_FLOAT(lo, hi, c) 1
#define RANGE_ENUM(lo, hi, c) ((lo) == 0 && (hi) + 1 == sizeof((const char *const[]){UNPAREN_ c}) / sizeof(char *))
#define CHECK_(group, field, name_, TYPE, ctype, lo, hi, pow2_, unit_, choices_, ...)                                 \
    _Static_assert(TYPE_OF_(FIELD_(group, field)) == (FV_KNOB_##TYPE == FV_KNOB_ENUM ? FV_KNOB_INT : FV_KNOB_##TYPE), \
                   #group "." #name_ ": the field's C type is not the knob's type");                                 \
    _Static_assert(sizeof(FIELD_(group, field)) == (FV_KNOB_##TYPE == FV_KNOB_BOOL ? 1u : 4u),                        \
                   #group "." #name_ ": bools take one byte, every other knob four");                                \
    _Static_assert(RANGE_##TYPE(lo, hi, choices_), #group "." #name_ ": the range does not fit the type");
FV_KNOB_LIST(CHECK_)

#define KNOB_COUNT (sizeof g_knobs / sizeof g_knobs[0])

const fv_knob *fv_knobs(size_t *count)
{
    if (count) *count = KNOB_COUNT;
    return g_knobs;
}

const fv_knob *fv_knob_find(const char *name)
{
    if (!name) return NULL;
    for (size_t i = 0; i < KNOB_COUNT; i++)
        if (strcmp(g_knobs[i].name, name) == 0) return &g_knobs[i];
    return NULL;
}

const char *fv_knob_type_name(fv_knob_type type)
{
    switch (type) {
    case FV_KNOB_BOOL: return "bool";
    case FV_KNOB_INT: return "int";
    case FV_KNOB_FLOAT: return "float";
    case FV_KNOB_ENUM: return "enum";
    }
    return "?";
}

const char *fv_quality_preset_name(fv_quality_preset_id id)
{
    return (unsigned)id < FV_QUALITY_PRESET_COUNT ? g_presets[id] : NULL;
}

const char *fv_quality_preset_names(void) { return "fast, balanced, high, exact"; }

/* ---- messages ------------------------------------------------------------------------------------------------ */

/* Append printf output to err at *at, staying NUL-terminated when it does not fit. */
static void say(char *err, size_t size, size_t *at, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static void say(char *err, size_t size, size_t *at, const char *fmt, ...)
{
    if (!err || size == 0 || *at >= size) return;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(err + *at, size - *at, fmt, ap);
    va_end(ap);
    if (n > 0) *at = (size_t)n < size - *at ? *at + (size_t)n : size;
}

/* The shortest text of d that reads back as d (as a float when is_float): fixed point ("10", "0.75") in
 * [1e-4, 1e15), else "%g" ("1e-06"). */
static void fmt_number(double d, bool is_float, char *buf, size_t size)
{
    bool fixed = d == 0.0 || (fabs(d) >= 1e-4 && fabs(d) < 1e15);
    for (int p = fixed ? 0 : 1; p <= 17; p++) {
        snprintf(buf, size, fixed ? "%.*f" : "%.*g", p, d);
        double back = strtod(buf, NULL); /* floats read back as parse_value reads them: strtod, then to float */
        if (is_float ? (float)back == (float)d : back == d) return;
    }
}

/* A float knob holds a float: its bounds as the parser applies them are the table's doubles rounded to float (0.01
 * is 0.00999999977... as a float, below the double 0.01). Every comparison and every printed bound uses these. */
static double bound_lo(const fv_knob *k) { return k->type == FV_KNOB_FLOAT ? (double)(float)k->min : k->min; }
static double bound_hi(const fv_knob *k) { return k->type == FV_KNOB_FLOAT ? (double)(float)k->max : k->max; }

/* The bounds as text that reads back (through parse_value) as exactly the bounds. */
static void format_bounds(const fv_knob *k, char *lo, char *hi, size_t size)
{
    bool is_float = k->type == FV_KNOB_FLOAT;
    fmt_number(bound_lo(k), is_float, lo, size);
    fmt_number(bound_hi(k), is_float, hi, size);
}

const char *fv_knob_format_range(const fv_knob *k, char *buf, size_t size)
{
    if (!buf || size == 0) return buf;
    buf[0] = '\0';
    if (!k) return buf;
    size_t at = 0;
    char lo[32], hi[32];
    switch (k->type) {
    case FV_KNOB_BOOL: say(buf, size, &at, "on|off"); break;
    case FV_KNOB_ENUM:
        for (uint32_t i = 0; i < k->choice_count; i++) say(buf, size, &at, "%s%s", i ? "|" : "", k->choices[i]);
        break;
    case FV_KNOB_INT:
    case FV_KNOB_FLOAT:
        format_bounds(k, lo, hi, sizeof lo);
        say(buf, size, &at, "%s..%s%s", lo, hi, k->pow2 ? ", powers of two" : "");
        break;
    }
    return buf;
}

/* What a value of k must be, for messages: "a whole number in 1..8", "a power of two in 256..4096 px". */
static void expected(const fv_knob *k, char *buf, size_t size)
{
    size_t at = 0;
    char lo[32], hi[32];
    format_bounds(k, lo, hi, sizeof lo);
    switch (k->type) {
    case FV_KNOB_BOOL: say(buf, size, &at, "one of on, off, true, false, 1, 0"); return;
    case FV_KNOB_ENUM:
        say(buf, size, &at, "one of ");
        for (uint32_t i = 0; i < k->choice_count; i++) say(buf, size, &at, "%s%s", i ? ", " : "", k->choices[i]);
        return;
    case FV_KNOB_INT: say(buf, size, &at, "%s in %s..%s", k->pow2 ? "a power of two" : "a whole number", lo, hi); break;
    case FV_KNOB_FLOAT: say(buf, size, &at, "a number in %s..%s", lo, hi); break;
    }
    if (k->unit[0]) say(buf, size, &at, " %s", k->unit);
}

/* ---- values -------------------------------------------------------------------------------------------------- */

/* The bytes a knob of this type takes in fv_quality (the unit test checks every row's size against it). */
#define STORAGE_SIZE(type) ((type) == FV_KNOB_BOOL ? 1u : 4u)

fv_knob_value fv_knob_get(const fv_knob *k, const fv_quality *q)
{
    fv_knob_value v = {.i = 0};
    assert(k && q && k->size == STORAGE_SIZE(k->type));
    const unsigned char *p = (const unsigned char *)q + k->offset;
    uint32_t u = 0;
    switch (k->type) {
    case FV_KNOB_BOOL: v.b = p[0] != 0; break; /* read as a byte: a stray value is not undefined behaviour */
    case FV_KNOB_INT:
    case FV_KNOB_ENUM:
        memcpy(&u, p, sizeof u);
        v.i = u;
        break;
    case FV_KNOB_FLOAT: memcpy(&v.f, p, sizeof v.f); break;
    }
    return v;
}

static void knob_put(const fv_knob *k, fv_quality *q, fv_knob_value v)
{
    assert(k->size == STORAGE_SIZE(k->type));
    unsigned char *p = (unsigned char *)q + k->offset;
    uint32_t u = (uint32_t)v.i;
    switch (k->type) {
    case FV_KNOB_BOOL: memcpy(p, &v.b, 1); break;
    case FV_KNOB_INT:
    case FV_KNOB_ENUM: memcpy(p, &u, sizeof u); break;
    case FV_KNOB_FLOAT: memcpy(p, &v.f, sizeof v.f); break;
    }
}

static bool is_pow2(int64_t x) { return x > 0 && (x & (x - 1)) == 0; }

/* Whether v is allowed for k (bools always are). */
static bool value_ok(const fv_knob *k, fv_knob_value v)
{
    switch (k->type) {
    case FV_KNOB_BOOL: return true;
    case FV_KNOB_ENUM: return v.i >= 0 && v.i < (int64_t)k->choice_count;
    case FV_KNOB_INT: return (double)v.i >= k->min && (double)v.i <= k->max && (!k->pow2 || is_pow2(v.i));
    case FV_KNOB_FLOAT: return isfinite(v.f) && (double)v.f >= bound_lo(k) && (double)v.f <= bound_hi(k);
    }
    return false;
}

const char *fv_knob_format(const fv_knob *k, const fv_quality *q, char *buf, size_t size)
{
    if (!buf || size == 0) return buf;
    buf[0] = '\0';
    if (!k || !q) return buf;
    fv_knob_value v = fv_knob_get(k, q);
    switch (k->type) {
    case FV_KNOB_BOOL: snprintf(buf, size, "%s", v.b ? "on" : "off"); break;
    case FV_KNOB_INT: snprintf(buf, size, "%lld", (long long)v.i); break;
    case FV_KNOB_ENUM:
        if (v.i >= 0 && v.i < (int64_t)k->choice_count) snprintf(buf, size, "%s", k->choices[v.i]);
        else snprintf(buf, size, "%lld", (long long)v.i);
        break;
    case FV_KNOB_FLOAT: fmt_number((double)v.f, true, buf, size); break;
    }
    return buf;
}

/* Parse s as a value of k: FV_OK, FV_ERR_RANGE (a number out of range or not a power of two) or FV_ERR_PARSE. */
static fv_result parse_value(const fv_knob *k, const char *s, fv_knob_value *out)
{
    if (!*s || isspace((unsigned char)s[0])) return FV_ERR_PARSE; /* strto* would skip leading blanks */
    char *end = NULL;
    errno = 0;
    switch (k->type) {
    case FV_KNOB_BOOL: {
        static const char *const yes[] = {"on", "true", "1"}, *const no[] = {"off", "false", "0"};
        for (int i = 0; i < 3; i++) {
            if (strcmp(s, yes[i]) == 0) { out->b = true; return FV_OK; }
            if (strcmp(s, no[i]) == 0) { out->b = false; return FV_OK; }
        }
        return FV_ERR_PARSE;
    }
    case FV_KNOB_ENUM:
        for (uint32_t i = 0; i < k->choice_count; i++)
            if (strcmp(s, k->choices[i]) == 0) { out->i = i; return FV_OK; }
        return FV_ERR_PARSE;
    case FV_KNOB_INT: {
        long long v = strtoll(s, &end, 10);
        if (*end != '\0') return FV_ERR_PARSE;
        if (errno == ERANGE) return FV_ERR_RANGE;
        out->i = v;
        break;
    }
    case FV_KNOB_FLOAT: {
        double d = strtod(s, &end);
        if (*end != '\0' || isnan(d)) return FV_ERR_PARSE;
        /* the value is stored as a float: compare that float with the float bounds (underflow to 0 is fine) */
        if (!isfinite(d) || fabs(d) > FLT_MAX || (float)d < (float)k->min || (float)d > (float)k->max) return FV_ERR_RANGE;
        out->f = (float)d;
        break;
    }
    }
    return value_ok(k, *out) ? FV_OK : FV_ERR_RANGE;
}

/* ---- presets and assignments --------------------------------------------------------------------------------- */

fv_result fv_quality_preset(const char *preset, fv_quality *out, char *err, size_t err_size)
{
    size_t at = 0;
    if (!out) return FV_ERR_INVALID_ARG;
    for (int id = 0; preset && id < FV_QUALITY_PRESET_COUNT; id++) {
        if (strcmp(preset, g_presets[id]) != 0) continue;
        fv_quality q = fv_quality_default();
        for (size_t i = 0; i < KNOB_COUNT; i++) {
            const fv_knob *k = &g_knobs[i];
            knob_put(k, &q, id == FV_QUALITY_FAST       ? k->fast
                            : id == FV_QUALITY_BALANCED ? k->balanced
                            : id == FV_QUALITY_HIGH     ? k->high
                                                        : k->exact);
        }
        *out = q;
        return FV_OK;
    }
    say(err, err_size, &at, "'%.64s' is not a quality preset (one of %s)", preset ? preset : "(null)",
        fv_quality_preset_names());
    return FV_ERR_NOT_FOUND;
}

fv_result fv_quality_set(fv_quality *q, const char *assignment, char *err, size_t err_size)
{
    size_t at = 0;
    if (err && err_size) err[0] = '\0';
    if (!q || !assignment) return FV_ERR_INVALID_ARG;
    const char *eq = strchr(assignment, '=');
    if (!eq) {
        say(err, err_size, &at, "'%.64s' is not NAME=VALUE (e.g. shadow.splits=4; `fovea knobs` lists the names)",
            assignment);
        return FV_ERR_PARSE;
    }
    size_t n = (size_t)(eq - assignment);
    const fv_knob *k = NULL;
    for (size_t i = 0; i < KNOB_COUNT && !k; i++)
        if (strlen(g_knobs[i].name) == n && strncmp(g_knobs[i].name, assignment, n) == 0) k = &g_knobs[i];
    if (!k) {
        say(err, err_size, &at, "unknown knob '%.*s' (knobs:", n > 64 ? 64 : (int)n, assignment);
        for (size_t i = 0; i < KNOB_COUNT; i++) say(err, err_size, &at, " %s", g_knobs[i].name);
        say(err, err_size, &at, ")");
        return FV_ERR_NOT_FOUND;
    }
    const char *value = eq + 1;
    char want[128] = "";
    fv_knob_value v = {.i = 0};
    fv_result res = parse_value(k, value, &v);
    if (FV_FAILED(res)) {
        expected(k, want, sizeof want);
        if (!*value) say(err, err_size, &at, "%s: empty value (expected %s)", k->name, want);
        else say(err, err_size, &at, "%s: '%.64s' is not %s", k->name, value, want);
        return res;
    }
    knob_put(k, q, v);
    return FV_OK;
}

/* ---- whole qualities ----------------------------------------------------------------------------------------- */

fv_result fv_quality_validate(const fv_quality *q, char *err, size_t err_size)
{
    size_t at = 0;
    if (err && err_size) err[0] = '\0';
    if (!q) {
        say(err, err_size, &at, "no quality");
        return FV_ERR_INVALID_ARG;
    }
    bool ok = true;
    char have[64], want[128];
#define BROKEN(...)                                                                                                    \
    do {                                                                                                               \
        say(err, err_size, &at, "%s", ok ? "" : "; ");                                                                 \
        say(err, err_size, &at, __VA_ARGS__);                                                                          \
        ok = false;                                                                                                    \
    } while (0)
    if (!(isfinite(q->exposure) && q->exposure > 0.0f)) BROKEN("exposure = %g is not finite and > 0", (double)q->exposure);
    uint32_t view;
    memcpy(&view, &q->debug_view, sizeof view);
    if (view >= FV_DEBUG_VIEW_COUNT) BROKEN("debug_view = %u is not a view (0..%d)", view, FV_DEBUG_VIEW_COUNT - 1);
    for (size_t i = 0; i < KNOB_COUNT; i++) {
        const fv_knob *k = &g_knobs[i];
        const unsigned char *p = (const unsigned char *)q + k->offset;
        if (k->type == FV_KNOB_BOOL && p[0] > 1) {
            BROKEN("%s holds byte %u, not a bool", k->name, p[0]);
            continue;
        }
        if (value_ok(k, fv_knob_get(k, q))) continue;
        expected(k, want, sizeof want);
        BROKEN("%s = %s is not %s", k->name, fv_knob_format(k, q, have, sizeof have), want);
    }
#undef BROKEN
    return ok ? FV_OK : FV_ERR_RANGE;
}

void fv_quality_sanitize(fv_quality *q)
{
    if (!q) return;
    fv_quality d = fv_quality_default();
    if (!(isfinite(q->exposure) && q->exposure > 0.0f)) q->exposure = d.exposure;
    uint32_t view;
    memcpy(&view, &q->debug_view, sizeof view);
    if (view >= FV_DEBUG_VIEW_COUNT) q->debug_view = d.debug_view;
    for (size_t i = 0; i < KNOB_COUNT; i++) {
        const fv_knob *k = &g_knobs[i];
        const unsigned char *p = (const unsigned char *)q + k->offset;
        bool ok = k->type == FV_KNOB_BOOL ? p[0] <= 1 : value_ok(k, fv_knob_get(k, q));
        if (!ok) knob_put(k, q, k->balanced);
    }
}

bool fv_quality_equal(const fv_quality *a, const fv_quality *b)
{
    if (!a || !b) return a == b;
    if (!(a->exposure == b->exposure) || a->debug_view != b->debug_view) return false;
    if (a->overlay != b->overlay) return false; /* a view setting: the overlay pass runs or not */
    if (!fv_lens_equal(&a->distort.lens, &b->distort.lens)) return false; /* the HMD's lens: not a knob */
    for (size_t i = 0; i < KNOB_COUNT; i++) {
        const fv_knob *k = &g_knobs[i];
        fv_knob_value x = fv_knob_get(k, a), y = fv_knob_get(k, b);
        bool same = k->type == FV_KNOB_BOOL ? x.b == y.b : k->type == FV_KNOB_FLOAT ? x.f == y.f : x.i == y.i;
        if (!same) return false;
    }
    return true;
}
