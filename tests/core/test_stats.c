/* @brief Saturating int64 arithmetic and nearest-rank percentiles (runtime/core/fv_stats.h), extremes included. */
#include <math.h>

#include "fv_stats.h"
#include "fv_test.h"

static void add_saturates_at_both_limits(void **state)
{
    (void)state;
    assert_true(fv_i64_add_sat(INT64_MAX, 1) == INT64_MAX);
    assert_true(fv_i64_add_sat(INT64_MAX, INT64_MAX) == INT64_MAX);
    assert_true(fv_i64_add_sat(INT64_MIN, -1) == INT64_MIN);
    assert_true(fv_i64_add_sat(INT64_MIN, INT64_MIN) == INT64_MIN);
    assert_true(fv_i64_add_sat(INT64_MAX, INT64_MIN) == -1);
    assert_true(fv_i64_add_sat(INT64_MAX - 1, 1) == INT64_MAX);
    assert_true(fv_i64_add_sat(-5, 3) == -2);
    assert_true(fv_i64_add_sat(0, INT64_MIN) == INT64_MIN);
}

static void sub_saturates_at_both_limits(void **state)
{
    (void)state;
    assert_true(fv_i64_sub_sat(INT64_MIN, 1) == INT64_MIN);
    assert_true(fv_i64_sub_sat(INT64_MAX, -1) == INT64_MAX);
    assert_true(fv_i64_sub_sat(0, INT64_MIN) == INT64_MAX); /* -INT64_MIN does not fit */
    assert_true(fv_i64_sub_sat(-1, INT64_MIN) == INT64_MAX);
    assert_true(fv_i64_sub_sat(INT64_MAX, INT64_MAX) == 0);
    assert_true(fv_i64_sub_sat(INT64_MIN, INT64_MAX) == INT64_MIN);
    assert_true(fv_i64_sub_sat(INT64_MAX, INT64_MIN) == INT64_MAX);
    assert_true(fv_i64_sub_sat(7, 10) == -3);
}

static void mul_saturates_by_the_sign_of_the_product(void **state)
{
    (void)state;
    assert_true(fv_i64_mul_sat(INT64_MAX, 2) == INT64_MAX);
    assert_true(fv_i64_mul_sat(INT64_MAX, -2) == INT64_MIN);
    assert_true(fv_i64_mul_sat(INT64_MIN, -1) == INT64_MAX); /* the one product of two "fitting" factors */
    assert_true(fv_i64_mul_sat(INT64_MIN, 1) == INT64_MIN);
    assert_true(fv_i64_mul_sat(INT64_MIN, INT64_MIN) == INT64_MAX);
    assert_true(fv_i64_mul_sat(-3, INT64_MAX / 2) == INT64_MIN);
    assert_true(fv_i64_mul_sat(0, INT64_MIN) == 0);
    assert_true(fv_i64_mul_sat(INT64_MAX / 1000, 1000) == INT64_MAX / 1000 * 1000);
    assert_true(fv_i64_mul_sat(-4, 5) == -20);
}

static void percentile_of_nothing_is_nan_or_zero(void **state)
{
    (void)state;
    assert_true(isnan(fv_percentile_f64(NULL, 0, 50.0)));
    assert_true(fv_percentile_i64(NULL, 0, 50.0) == 0);
}

static void percentile_of_one_value_is_that_value_for_any_p(void **state)
{
    (void)state;
    const double ps[] = {0.0, 1e-9, 50.0, 100.0, -5.0, 1e300, INFINITY, -INFINITY, NAN};
    for (size_t i = 0; i < sizeof ps / sizeof ps[0]; i++) {
        double d = -2.5;
        int64_t v = INT64_MIN;
        assert_true(fv_percentile_f64(&d, 1, ps[i]) == -2.5);
        assert_true(fv_percentile_i64(&v, 1, ps[i]) == INT64_MIN);
    }
}

static void percentile_is_nearest_rank_and_sorts_in_place(void **state)
{
    (void)state;
    /* 1..10 shuffled: rank ceil(p/10) */
    int64_t v[10] = {7, 3, 10, 1, 9, 2, 8, 4, 6, 5};
    assert_true(fv_percentile_i64(v, 10, 50.0) == 5);
    for (int i = 0; i < 10; i++) assert_true(v[i] == i + 1);
    assert_true(fv_percentile_i64(v, 10, 95.0) == 10);
    assert_true(fv_percentile_i64(v, 10, 90.0) == 9);
    assert_true(fv_percentile_i64(v, 10, 10.0) == 1);
    assert_true(fv_percentile_i64(v, 10, 10.5) == 2);
    double d[5] = {0.5, -1.0, 4.0, 2.0, 3.0};
    assert_true(fv_percentile_f64(d, 5, 50.0) == 2.0); /* rank 3 of 5 */
    assert_true(d[0] == -1.0 && d[4] == 4.0);
    assert_true(fv_percentile_f64(d, 5, 20.0) == -1.0); /* rank 1 */
    assert_true(fv_percentile_f64(d, 5, 20.1) == 0.5);  /* rank 2 */
    /* p = 95 of 20: rank 19 */
    double e[20];
    for (int i = 0; i < 20; i++) e[i] = (double)(19 - i);
    assert_true(fv_percentile_f64(e, 20, 95.0) == 18.0);
}

static void percentile_clamps_p_and_takes_nan_p_as_zero(void **state)
{
    (void)state;
    int64_t v[4] = {INT64_MAX, 0, INT64_MIN, 5};
    assert_true(fv_percentile_i64(v, 4, 0.0) == INT64_MIN);
    assert_true(fv_percentile_i64(v, 4, -1e9) == INT64_MIN);
    assert_true(fv_percentile_i64(v, 4, -INFINITY) == INT64_MIN);
    assert_true(fv_percentile_i64(v, 4, NAN) == INT64_MIN);
    assert_true(fv_percentile_i64(v, 4, 100.0) == INT64_MAX);
    assert_true(fv_percentile_i64(v, 4, 100.0001) == INT64_MAX);
    assert_true(fv_percentile_i64(v, 4, INFINITY) == INT64_MAX);
    double d[3] = {HUGE_VAL, -HUGE_VAL, 1.0};
    assert_true(fv_percentile_f64(d, 3, NAN) == -HUGE_VAL);
    assert_true(fv_percentile_f64(d, 3, 1e308) == HUGE_VAL);
    assert_true(fv_percentile_f64(d, 3, 50.0) == 1.0);
}

static void percentile_orders_nan_values_last(void **state)
{
    (void)state;
    double d[5] = {NAN, 3.0, NAN, 1.0, 2.0};
    assert_true(fv_percentile_f64(d, 5, 0.0) == 1.0);
    assert_true(fv_percentile_f64(d, 5, 60.0) == 3.0);
    assert_true(isnan(fv_percentile_f64(d, 5, 100.0)));
    assert_true(d[0] == 1.0 && d[1] == 2.0 && d[2] == 3.0 && isnan(d[3]) && isnan(d[4]));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(add_saturates_at_both_limits),
        cmocka_unit_test(sub_saturates_at_both_limits),
        cmocka_unit_test(mul_saturates_by_the_sign_of_the_product),
        cmocka_unit_test(percentile_of_nothing_is_nan_or_zero),
        cmocka_unit_test(percentile_of_one_value_is_that_value_for_any_p),
        cmocka_unit_test(percentile_is_nearest_rank_and_sorts_in_place),
        cmocka_unit_test(percentile_clamps_p_and_takes_nan_p_as_zero),
        cmocka_unit_test(percentile_orders_nan_values_last),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
