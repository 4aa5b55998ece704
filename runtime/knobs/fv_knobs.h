/* @brief The knob table: every speed/accuracy knob of fovea (dotted name, type, range, unit, a default per preset,
 * one-line doc, and where it lives in fv_quality), generated from the one knob list (include/fv_knob_list.h), with
 * the presets, parsing of NAME=VALUE, formatting, validation and sanitising built on it. `fovea run --help/--quality/--set`, its JSON summary, `fovea knobs` and `fovea bench`
 * derive from this table. Pure data and functions: no allocation, no logging, thread-safe. */
#ifndef FV_KNOBS_H
#define FV_KNOBS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fovea/fv_frame_input.h"
#include "fv_result.h"

/** What a knob holds, and how it is stored in fv_quality. */
typedef enum fv_knob_type {
    FV_KNOB_BOOL,  /* bool; written on|off, parsed from on|off|true|false|1|0 */
    FV_KNOB_INT,   /* uint32_t; a whole number in [min, max] (powers of two only when pow2) */
    FV_KNOB_FLOAT, /* float; a finite number in [min, max] */
    FV_KNOB_ENUM,  /* a C enum of 4 bytes whose values are 0..choice_count-1, named by choices[] */
} fv_knob_type;

/** The presets, in order of cost. `exact` turns every shortcut of fovea's own off and keeps the same model; where the
 *  exact version is not possible on the GPU, the knob's exact_note says what exact uses instead. */
typedef enum fv_quality_preset_id {
    FV_QUALITY_FAST = 0,
    FV_QUALITY_BALANCED = 1, /* the default: fv_quality_default() */
    FV_QUALITY_HIGH = 2,
    FV_QUALITY_EXACT = 3,
    FV_QUALITY_PRESET_COUNT = 4,
} fv_quality_preset_id;

/** One knob's value: b for bool, i for int and enum (the enum's index), f for float. */
typedef union fv_knob_value {
    bool b;
    int64_t i;
    float f;
} fv_knob_value;

/** One row of the knob table. */
typedef struct fv_knob {
    const char *name;           /* dotted, "<pass>.<knob>": "shadow.splits" */
    fv_knob_type type;
    double min, max;            /* inclusive range of int and float knobs (0..1 for bool, 0..count-1 for enum) */
    bool pow2;                  /* int: only powers of two are allowed */
    const char *unit;           /* "px", "texels", ... ; "" for counts and unitless values */
    const char *const *choices; /* enum: the names of the values 0..choice_count-1; NULL otherwise */
    uint32_t choice_count;
    size_t offset, size;        /* where the value lives: offsetof(fv_quality, ...) and sizeof that field */
    /* The value under each preset (fv_knob_list.h's columns; balanced is also fv_quality_default()'s field). */
    fv_knob_value fast, balanced, high, exact;
    const char *doc;            /* one line */
    const char *exact_note;     /* why the exact version is not possible on the GPU and what `exact` uses instead
                                 * (shown as "exact: <note>"); NULL when exact is simply every shortcut off */
} fv_knob;

/** The whole table, in a stable order (the order of --help, `fovea knobs` and the JSON summaries). Static storage;
 *  *count (non-NULL) receives the number of rows. */
const fv_knob *fv_knobs(size_t *count);

/** The knob with this exact dotted name, or NULL. */
const fv_knob *fv_knob_find(const char *name);

/** The preset's name ("fast", "balanced", "high", "exact"), or NULL for an id out of range. */
const char *fv_quality_preset_name(fv_quality_preset_id id);

/** "fast, balanced, high, exact": the preset names joined by ", " (static storage). */
const char *fv_quality_preset_names(void);

/** Fill *out with the named preset: fv_quality_default() (exposure, debug_view and the balanced knobs) with the
 *  preset's knob values. An unknown name leaves *out alone, returns FV_ERR_NOT_FOUND and, when err is non-NULL,
 *  writes one line naming the allowed presets. */
FV_MUST_CHECK fv_result fv_quality_preset(const char *preset, fv_quality *out, char *err, size_t err_size);

/** Apply one "NAME=VALUE" to *q (e.g. "shadow.splits=3", "shadow.filter=pcf5", "shadow.enabled=off"). On any error
 *  *q is left alone and err (when non-NULL) receives one line naming the knob, the value and the allowed range or
 *  choices. Returns FV_ERR_NOT_FOUND for an unknown name, FV_ERR_RANGE for a number that parses but is out of range
 *  or not a power of two, FV_ERR_PARSE for anything else (no '=', an empty value, junk, NaN/inf, an unknown enum
 *  name), FV_ERR_INVALID_ARG for NULL q or assignment. */
FV_MUST_CHECK fv_result fv_quality_set(fv_quality *q, const char *assignment, char *err, size_t err_size);

/** The knob's value in *q. */
fv_knob_value fv_knob_get(const fv_knob *k, const fv_quality *q);

/** Write the knob's value in *q as fv_quality_set parses it back exactly ("4", "0.75", "pcf3", "on"); returns buf. */
const char *fv_knob_format(const fv_knob *k, const fv_quality *q, char *buf, size_t size);

/** Write the knob's allowed values: "1..8", "256..4096, powers of two", "0..1", "none|pcf3|pcf5", "on|off";
 *  returns buf. */
const char *fv_knob_format_range(const fv_knob *k, char *buf, size_t size);

/** "bool", "int", "float" or "enum". */
const char *fv_knob_type_name(fv_knob_type type);

/** FV_OK when every field of *q is in range: every knob as the table says, exposure finite and > 0, debug_view one of
 *  fv_debug_view. Otherwise FV_ERR_RANGE, and err (when non-NULL) lists each broken rule, "; "-separated, on one
 *  line. Renderer-side sanitising may rely on this. */
FV_MUST_CHECK fv_result fv_quality_validate(const fv_quality *q, char *err, size_t err_size);

/** Bring every field of *q (non-NULL) in range, field by field: a knob the table refuses (out of range, not a power of
 *  two, an enum or bool byte out of its values, a float NaN) takes its balanced value, exposure that is not finite
 *  and > 0 becomes 1, a debug_view out of range none. A zeroed fv_quality becomes valid. The renderer draws with it;
 *  afterwards fv_quality_validate(q) is FV_OK. */
void fv_quality_sanitize(fv_quality *q);

/** True when a and b hold the same value in every knob and in exposure, debug_view and overlay (floats compare with
 *  ==, so a NaN is never equal). */
bool fv_quality_equal(const fv_quality *a, const fv_quality *b);

#endif
