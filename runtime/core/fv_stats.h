/* @brief Saturating int64 arithmetic (time in ns from devices and files may be anything) and nearest-rank
 * percentiles. Pure functions: no allocation, no clock, no global state; thread-safe on distinct arrays. */
#ifndef FV_STATS_H
#define FV_STATS_H

#include <stddef.h>
#include <stdint.h>

/** a + b, saturated to [INT64_MIN, INT64_MAX] instead of overflowing (no undefined behaviour for any input). */
static inline int64_t fv_i64_add_sat(int64_t a, int64_t b)
{
    int64_t r;
    if (__builtin_add_overflow(a, b, &r)) return b > 0 ? INT64_MAX : INT64_MIN;
    return r;
}

/** a - b, saturated to [INT64_MIN, INT64_MAX] instead of overflowing (no undefined behaviour for any input). */
static inline int64_t fv_i64_sub_sat(int64_t a, int64_t b)
{
    int64_t r;
    if (__builtin_sub_overflow(a, b, &r)) return b < 0 ? INT64_MAX : INT64_MIN;
    return r;
}

/** a * b, saturated to [INT64_MIN, INT64_MAX] by the sign of the exact product (no undefined behaviour). */
static inline int64_t fv_i64_mul_sat(int64_t a, int64_t b)
{
    int64_t r;
    if (__builtin_mul_overflow(a, b, &r)) return (a < 0) != (b < 0) ? INT64_MIN : INT64_MAX;
    return r;
}

/** Nearest-rank percentile: the value of 1-based rank ceil(p/100 · n) (at least 1) after sorting. Sorts `values`
 *  (n of them, owned by the caller) in place, ascending, NaN last; NaN when n == 0. p is in percent, clamped to
 *  [0, 100]; a NaN p counts as 0 (the minimum). */
double fv_percentile_f64(double *values, size_t n, double p);

/** The same nearest-rank percentile for int64 (e.g. durations in ns): sorts `values` in place, ascending; 0 when
 *  n == 0; p clamped to [0, 100], NaN as 0. */
int64_t fv_percentile_i64(int64_t *values, size_t n, double p);

#endif
