/* @brief Pure helpers of drivers/trace (trace_util.c): CSV field splitting, whole-field number parsing and validated
 * sample setters. They work on strings and samples only — no reader, no I/O, no logging — so the dependency points
 * one way: the reader and the format parsers (trace_internal.h) use these, never the reverse. Not a public header. */
#ifndef FV_TRACE_UTIL_H
#define FV_TRACE_UTIL_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_gaze_sample.h"

/* ---- CSV ---- */

/** Split a line in place on sep; double-quoted fields ("a,b", "" for a quote) are unquoted. Returns the field count
 *  (at most cap; the rest are dropped). Returns -1 for an unterminated quote. */
int trace_csv_split(char *line, char sep, char **fields, int cap);
/** Index of column name (exact match after trimming spaces and a UTF-8 BOM) or -1. */
int trace_csv_find(char *const *fields, int n, const char *name);

/* ---- numbers ---- */

/** Whole-field parses; false on empty, junk, overflow. Spaces around the number are allowed. */
bool trace_parse_f64(const char *s, double *out);
bool trace_parse_i64(const char *s, int64_t *out);
bool trace_field_empty(const char *s);
/** Seconds (finite, |s| < 9.2e9) to ns. */
bool trace_seconds_to_ns(double s, int64_t *out_ns);
/** A float from a double; non-finite or beyond FLT_MAX → NaN. */
float trace_f32(double v);

/* ---- sample helpers ---- */

/** Validated setters: a value outside its plausible range leaves the field invalid (NaN, flag clear). */
void trace_eye_set_origin(fv_eye_sample *e, double x, double y, double z);
/** Normalises; a zero, tiny or non-finite vector leaves the direction invalid. */
void trace_eye_set_direction(fv_eye_sample *e, double x, double y, double z);
void trace_eye_set_pupil(fv_eye_sample *e, double mm);
void trace_eye_set_openness(fv_eye_sample *e, double v);
/** Clear every value of an eye (NaN) and its validity flags; FV_EYE_BLINK is kept. */
void trace_eye_invalidate(fv_eye_sample *e);
/** Invalidate both eyes and the combined ray (trace_eye_invalidate); with blink, also set FV_EYE_BLINK on all three. */
void trace_sample_invalidate(fv_gaze_sample *s, bool blink);
/** The combined ray's origin from the eyes': both origins valid → their midpoint; only one (and one_ok) → that
 *  eye's; else left unset. */
void trace_combined_origin(fv_gaze_sample *s, bool one_ok);
/** Combined ray from the eyes when the source gives none: both valid and possible (fv_gaze_direction_possible) →
 *  mean origin and normalised sum of directions; one → that eye's direction, origin unknown. */
void trace_combine_eyes(fv_gaze_sample *s);
/** Head pose from a Unity log (Pico, SRanipal): pos_m is the position in metres and euler_deg the Euler angles in
 *  degrees (x, y, z; Unity applies Z, then X, then Y: R = Ry·Rx·Rz), both in Unity's left-handed world (+x right,
 *  +y up, +z forward). Sets head_pos_mm = (x, y, −z)·1000, head_dir = R·(0,0,1) mapped the same way (x, y, −z), and
 *  FV_GAZE_HEAD_VALID. A value that is NULL (column absent or row short), not a number, non-finite, a position beyond
 *  1 km or an angle beyond ±720°, or an all-zero pose (position and angles all exactly 0: the head was not logged),
 *  leaves the head invalid (NaN, flag clear); the sample itself is kept. */
void trace_set_head_unity(fv_gaze_sample *s, const char *const pos_m[3], const char *const euler_deg[3]);

#endif
