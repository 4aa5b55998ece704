/* @brief The display tone curve (render/present/fv_tone_curve.h, the one definition the present shader compiles):
 * Reinhard extended with white point 4. Fails if the curve came back as a clamp (bright surfaces flat white), if
 * mid-grey moved from where the header documents it, or if any input (NaN, +-Inf, negative, huge, denormal) gave a
 * value that is not finite and in range. The shader's use of it is checked on the GPU by test_render_golden. */
#include <float.h>
#include <math.h>

#include "fv_metrics.h"
#include "fv_test.h"
#include "fv_tone_curve.h"

static float display(float x) { return fv_tone_reinhard_ext(fv_tone_sanitize(x)); }
static int code8(float x) { return (int)(fv_metrics_linear_to_srgb(display(x)) * 255.0 + 0.5); }

static void tone_curve_keeps_bright_surfaces_graded(void **state)
{
    (void)state;
    /* surfaces from display white (1.0) up to the white point keep distinct 8-bit codes (a clamp gives 255 to all) */
    int prev = code8(1.0f);
    assert_true(prev < 200);
    for (float x = 1.25f; x <= 3.76f; x += 0.25f) {
        int c = code8(x);
        assert_true(c > prev);
        assert_true(c < 255);
        prev = c;
    }
    assert_int_equal(code8((float)FV_TONE_WHITE), 255);
    assert_true(fabsf(display((float)FV_TONE_WHITE) - 1.0f) < 1e-6f);
    /* strictly increasing on [0, W], and never above 1 there */
    float last = -1.0f;
    for (int i = 0; i <= 4000; i++) {
        float x = (float)FV_TONE_WHITE * (float)i / 4000.0f, y = display(x);
        assert_true(y > last && y <= 1.0f + 1e-6f);
        last = y;
    }
}

static void tone_curve_maps_mid_grey_where_documented(void **state)
{
    (void)state;
    /* the header: 0.18 -> 0.1543 (sRGB code 109), 1.0 -> 0.531 (193), 2.0 -> 0.75 (225), 4.0 -> 1.0 (255) */
    assert_true(fabsf(display(0.18f) - 0.1543f) < 2e-4f);
    assert_int_equal(code8(0.18f), 109);
    assert_true(fabsf(display(1.0f) - 0.53125f) < 1e-5f);
    assert_int_equal(code8(1.0f), 193);
    assert_true(fabsf(display(2.0f) - 0.75f) < 1e-5f);
    assert_int_equal(code8(2.0f), 225);
    /* slope 1 at black: shadows are neither crushed nor lifted */
    assert_true(fabsf(display(1e-4f) / 1e-4f - 1.0f) < 1e-3f);
}

static void tone_curve_is_finite_for_any_input(void **state)
{
    (void)state;
    const float bad[] = {NAN, -NAN, INFINITY, -INFINITY, -1.0f, -FLT_MIN, 0.0f, -0.0f, FLT_MIN, 1e-45f, FLT_MAX,
                         (float)FV_TONE_MAX_INPUT, 1e30f};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        float s = fv_tone_sanitize(bad[i]), y = fv_tone_reinhard_ext(s);
        assert_true(isfinite(s) && s >= 0.0f && s <= (float)FV_TONE_MAX_INPUT);
        assert_true(isfinite(y) && y >= 0.0f);
        int c = code8(bad[i]);
        assert_true(c >= 0 && c <= 255);
    }
    assert_int_equal(code8(NAN), 0);
    assert_int_equal(code8(-INFINITY), 0);
    assert_int_equal(code8(-5.0f), 0);
    assert_int_equal(code8(INFINITY), 255); /* an infinite highlight is white, not black */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(tone_curve_keeps_bright_surfaces_graded),
        cmocka_unit_test(tone_curve_maps_mid_grey_where_documented),
        cmocka_unit_test(tone_curve_is_finite_for_any_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
