/* @brief Nearest-rank percentiles (see fv_stats.h). */
#include "fv_stats.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

/* 0-based index of the nearest-rank percentile p of n >= 1 sorted values: rank ceil(p/100 · n), clamped to 1..n. */
static size_t rank_index(size_t n, double p)
{
    if (!(p > 0.0)) return 0; /* also NaN */
    if (p >= 100.0) return n - 1;
    double rank = ceil(p / 100.0 * (double)n);
    if (!(rank >= 1.0)) return 0;
    if (rank >= (double)n) return n - 1; /* also keeps the conversion below in range */
    return (size_t)rank - 1;
}

/* Ascending with NaN last: a total order, as qsort needs. */
static int cmp_f64(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    bool xn = isnan(x), yn = isnan(y);
    if (xn || yn) return (int)xn - (int)yn;
    return (x > y) - (x < y);
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

double fv_percentile_f64(double *values, size_t n, double p)
{
    if (n == 0) return NAN;
    qsort(values, n, sizeof *values, cmp_f64);
    return values[rank_index(n, p)];
}

int64_t fv_percentile_i64(int64_t *values, size_t n, double p)
{
    if (n == 0) return 0;
    qsort(values, n, sizeof *values, cmp_i64);
    return values[rank_index(n, p)];
}
