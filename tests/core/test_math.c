/* @brief Math: matrices, quaternions and the Vulkan projection, including degenerate and extreme inputs. */
#include <float.h>
#include <math.h>

#include "fv_math.h"
#include "fv_test.h"

static void assert_near(double a, double b, double tol)
{
    if (!(fabs(a - b) <= tol)) fail_msg("%.9g != %.9g (tol %.3g)", a, b, tol);
}

static fv_vec3 project(const fv_mat4 *p, fv_vec3 v)
{
    fv_vec4 c = fv_mat4_mul_v4(p, (fv_vec4){v.x, v.y, v.z, 1});
    return fv_v3(c.x / c.w, c.y / c.w, c.z / c.w);
}

static void perspective_maps_frustum_edges_to_vulkan_ndc(void **state)
{
    (void)state;
    float tl = -1.2f, tr = 0.9f, tu = 1.0f, td = -1.1f;
    fv_mat4 p = fv_mat4_perspective_tan(tl, tr, tu, td, 0.1f, 100.0f);
    fv_vec3 a = project(&p, fv_v3(tr * 5, tu * 5, -5)); /* top right at depth 5 */
    assert_near(a.x, 1, 1e-5);
    assert_near(a.y, -1, 1e-5); /* Vulkan: top is -1 */
    fv_vec3 b = project(&p, fv_v3(tl * 2, td * 2, -2));
    assert_near(b.x, -1, 1e-5);
    assert_near(b.y, 1, 1e-5);
    assert_near(project(&p, fv_v3(0, 0, -0.1f)).z, 0, 1e-6);
    assert_near(project(&p, fv_v3(0, 0, -100)).z, 1, 1e-5);
}

static void perspective_stays_finite_at_extreme_near_far(void **state)
{
    (void)state;
    fv_mat4 p = fv_mat4_perspective_tan(-1, 1, 1, -1, 1e-4f, 1e6f);
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) assert_true(isfinite(p.m[c][r]));
    fv_vec3 n = project(&p, fv_v3(0, 0, -1e-4f)), f = project(&p, fv_v3(0, 0, -1e6f));
    assert_true(isfinite(n.z) && isfinite(f.z));
    assert_true(n.z < f.z);
    assert_near(f.z, 1, 1e-3);
}

static void inverse_times_matrix_is_identity(void **state)
{
    (void)state;
    fv_mat4 m = fv_mat4_trs(fv_v3(1, -2, 3), fv_quat_axis_angle(fv_v3(1, 1, 0), 0.7f), fv_v3(2, 0.5f, 3));
    fv_mat4 inv;
    assert_true(fv_mat4_invert(&m, &inv));
    fv_mat4 id = fv_mat4_mul(&m, &inv);
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) assert_near(id.m[c][r], c == r ? 1 : 0, 1e-5);
}

static void singular_and_nan_matrices_do_not_invert(void **state)
{
    (void)state;
    fv_mat4 z = fv_mat4_scale(fv_v3(1, 0, 1)), inv;
    assert_false(fv_mat4_invert(&z, &inv));
    fv_mat4 n = fv_mat4_identity();
    n.m[1][1] = NAN;
    assert_false(fv_mat4_invert(&n, &inv));
    assert_true(isfinite(inv.m[0][0]));
}

static void normalize_of_zero_and_nan_returns_fallback(void **state)
{
    (void)state;
    fv_vec3 fb = fv_v3(0, 0, -1);
    fv_vec3 a = fv_v3_normalize_or(fv_v3(0, 0, 0), fb);
    assert_true(a.z == -1);
    fv_vec3 b = fv_v3_normalize_or(fv_v3(NAN, 1, 0), fb);
    assert_true(b.z == -1);
    fv_vec3 c = fv_v3_normalize_or(fv_v3(FLT_MAX, FLT_MAX, 0), fb); /* overflow to inf length */
    assert_true(fv_v3_isfinite(c));
    fv_vec3 d = fv_v3_normalize_or(fv_v3(1e-20f, 0, 0), fb); /* tiny but nonzero */
    assert_true(fv_v3_isfinite(d));
}

static void look_at_with_parallel_up_is_still_orthonormal(void **state)
{
    (void)state;
    fv_mat4 v = fv_mat4_look_at(fv_v3(0, 0, 0), fv_v3(0, 5, 0), fv_v3(0, 1, 0));
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) assert_true(isfinite(v.m[c][r]));
    fv_vec3 f = fv_mat4_mul_dir(&v, fv_v3(0, 1, 0)); /* the look direction maps to -z */
    assert_near(f.z, -1, 1e-5);
}

static void quaternion_rotation_matches_matrix(void **state)
{
    (void)state;
    fv_quat q = fv_quat_axis_angle(fv_v3(0, 1, 0), (float)(FV_PI / 2));
    fv_vec3 r = fv_quat_rotate(q, fv_v3(1, 0, 0));
    assert_near(r.z, -1, 1e-6);
    fv_mat4 m = fv_mat4_from_quat(q);
    fv_vec3 r2 = fv_mat4_mul_dir(&m, fv_v3(1, 0, 0));
    assert_near(r2.x, r.x, 1e-6);
    assert_near(r2.z, r.z, 1e-6);
    fv_quat s = fv_quat_slerp(fv_quat_identity(), q, 0.5f);
    fv_vec3 h = fv_quat_rotate(s, fv_v3(1, 0, 0));
    assert_near(h.x, cos(FV_PI / 4), 1e-5);
    fv_quat nq = fv_quat_normalize((fv_quat){0, 0, 0, 0});
    assert_true(nq.w == 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(perspective_maps_frustum_edges_to_vulkan_ndc),
        cmocka_unit_test(perspective_stays_finite_at_extreme_near_far),
        cmocka_unit_test(inverse_times_matrix_is_identity),
        cmocka_unit_test(singular_and_nan_matrices_do_not_invert),
        cmocka_unit_test(normalize_of_zero_and_nan_returns_fallback),
        cmocka_unit_test(look_at_with_parallel_up_is_still_orthonormal),
        cmocka_unit_test(quaternion_rotation_matches_matrix),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
