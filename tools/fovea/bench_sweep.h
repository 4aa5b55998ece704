/* @brief The points of `fovea bench`: each --sweep NAME=V1,V2,... checked through the knob table (and the pseudo-knob
 * `preset`, which sweeps the presets), and the cross product of the sweeps as one fv_quality per point: the preset
 * (the swept one, else --quality), then each --set, then the point's sweep values. Pure: no allocation, no I/O. */
#ifndef FV_BENCH_SWEEP_H
#define FV_BENCH_SWEEP_H

#include <stdbool.h>
#include <stddef.h>

#include "fv_knobs.h"
#include "tool_knobs.h"

#define FV_BENCH_MAX_SWEEPS 8   /* --sweep options */
#define FV_BENCH_MAX_VALUES 64  /* values of one --sweep */
#define FV_BENCH_MAX_POINTS 256 /* points of the cross product */
#define FV_BENCH_PRESET "preset" /* the pseudo-knob: --sweep preset=fast,balanced,high,exact */

/** One --sweep. */
typedef struct fv_bench_sweep {
    char name[64];                           /* the knob's dotted name, or "preset" */
    const fv_knob *knob;                     /* NULL for the preset pseudo-knob */
    char text[1024];                         /* the values as given, each ended by '\0' */
    const char *values[FV_BENCH_MAX_VALUES]; /* into text */
    size_t value_count;
    size_t dropped_count;                    /* values that repeat an earlier one once parsed ("16,16", "0.5,0.50") */
    char dropped[256];                       /* "16 (as 16), 0.50 (as 0.5)": for the caller's one warning line */
} fv_bench_sweep;

/** Every --sweep, and --quality/--set as given (the base of every point). Zero-initialise. */
typedef struct fv_bench_plan {
    fv_tool_quality tq;
    fv_bench_sweep sweeps[FV_BENCH_MAX_SWEEPS];
    size_t sweep_count;
} fv_bench_plan;

/** Add one --sweep "NAME=V1,V2,...". Each value is checked as fv_quality_set (or fv_quality_preset for `preset`)
 *  checks it. A value that parses to the same setting as an earlier one is dropped (dropped_count, dropped say
 *  which, for the caller to warn). FV_OK, or an error with one line in err: FV_ERR_PARSE (not NAME=V1,...; a bad value),
 *  FV_ERR_NOT_FOUND (unknown knob), FV_ERR_RANGE (a value out of range, too many values or sweeps, a knob swept
 *  twice). */
FV_MUST_CHECK fv_result fv_bench_plan_add(fv_bench_plan *p, const char *arg, char *err, size_t err_size);

/** Points of the cross product (1 without sweeps), saturated at SIZE_MAX. */
size_t fv_bench_plan_points(const fv_bench_plan *p);

/** The value indices of point `index` (0-based): the first sweep varies slowest, the last fastest. */
void fv_bench_point_values(const fv_bench_plan *p, size_t index, size_t out_value_index[FV_BENCH_MAX_SWEEPS]);

/** The quality of point `index` and the name of its preset (static storage). FV_OK, or one line in err (a --quality
 *  or --set that does not apply). */
FV_MUST_CHECK fv_result fv_bench_point_quality(const fv_bench_plan *p, size_t index, fv_quality *out,
                                               const char **out_preset, char *err, size_t err_size);

#endif
