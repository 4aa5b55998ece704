/* @brief The geometry of shadow maps without a GPU: the practical split scheme against its formula (Zhang et al.
 * 2006) at its extremes, the split count for a depth range, depth ranges, orthographic projections, and crops that
 * stay on the texel grid as the head moves (no shimmering). */
#include <math.h>
#include <string.h>

#include "fv_shadow_math.h"
#include "fv_test.h"

static void splits_follow_the_practical_scheme_at_every_extreme(void **state)
{
    (void)state;
    const double ranges[][2] = {{0.1, 100.0}, {1e-4, 1e6}, {0.5, 0.5000001}, {2.0, 3.0}};
    const double lambdas[] = {0.0, 0.25, 0.5, 0.75, 1.0};
    const uint32_t ms[] = {1, 2, 3, 4, 8};
    for (size_t r = 0; r < sizeof ranges / sizeof ranges[0]; r++)
        for (size_t l = 0; l < sizeof lambdas / sizeof lambdas[0]; l++)
            for (size_t k = 0; k < sizeof ms / sizeof ms[0]; k++) {
                double n = ranges[r][0], f = ranges[r][1], lam = lambdas[l];
                uint32_t m = ms[k];
                double c[FV_SHADOW_SPLITS_MAX + 1];
                assert_int_equal(fv_shadow_split_distances(n, f, m, lam, c), m);
                assert_true(c[0] == n);
                assert_true(c[m] == f);
                for (uint32_t i = 0; i <= m; i++) {
                    assert_true(isfinite(c[i]));
                    if (i) assert_true(c[i] >= c[i - 1]);
                    double s = (double)i / m;
                    double want = lam * n * pow(f / n, s) + (1.0 - lam) * (n + (f - n) * s);
                    if (fabs(c[i] - want) > 1e-12 * want)
                        fail_msg("n %g f %g m %u lambda %g: C_%u = %.17g, formula %.17g", n, f, m, lam, i, c[i], want);
                }
            }
    /* lambda = 1 is the logarithmic split: C_1/C_0 = C_2/C_1 = ... */
    double c[5];
    fv_shadow_split_distances(0.1, 1000.0, 4, 1.0, c);
    for (int i = 1; i < 4; i++) assert_float_equal(c[i + 1] / c[i], c[1] / c[0], 1e-9);
    /* lambda = 0 is the uniform split. */
    fv_shadow_split_distances(1.0, 9.0, 4, 0.0, c);
    for (int i = 0; i <= 4; i++) assert_float_equal(c[i], 1.0 + 2.0 * i, 1e-12);
}

static void split_input_is_sanitised_and_stays_finite(void **state)
{
    (void)state;
    const double ns[] = {0.0, -1.0, NAN, INFINITY, 1e-300, 5.0};
    const double fs[] = {0.0, NAN, INFINITY, 1.0, 1e300};
    const double lambdas[] = {NAN, -1.0, 2.0, INFINITY};
    const uint32_t ms[] = {0, 1, 9, 1000};
    for (size_t a = 0; a < 6; a++)
        for (size_t b = 0; b < 5; b++)
            for (size_t l = 0; l < 4; l++)
                for (size_t k = 0; k < 4; k++) {
                    double c[FV_SHADOW_SPLITS_MAX + 1];
                    uint32_t m = fv_shadow_split_distances(ns[a], fs[b], ms[k], lambdas[l], c);
                    assert_true(m >= 1 && m <= FV_SHADOW_SPLITS_MAX);
                    for (uint32_t i = 0; i <= m; i++) {
                        assert_true(isfinite(c[i]) && c[i] > 0.0);
                        if (i) assert_true(c[i] >= c[i - 1]);
                    }
                    assert_true(c[m] > c[0]);
                }
}

static void a_shallow_depth_range_gets_fewer_splits(void **state)
{
    (void)state;
    assert_int_equal(fv_shadow_splits_for_range(1.0, 1.5, 4), 1);
    assert_int_equal(fv_shadow_splits_for_range(1.0, 4.0, 4), 2);
    assert_int_equal(fv_shadow_splits_for_range(0.4, 2.1, 4), 3);
    assert_int_equal(fv_shadow_splits_for_range(0.1, 400.0, 4), 4);
    assert_int_equal(fv_shadow_splits_for_range(0.1, 400.0, 8), 8);
    assert_int_equal(fv_shadow_splits_for_range(0.1, 400.0, 0), 1);
    assert_int_equal(fv_shadow_splits_for_range(NAN, 1.0, 4), 1);
    assert_int_equal(fv_shadow_splits_for_range(1.0, INFINITY, 4), 1);
}

static void ortho_maps_the_box_to_vulkan_clip(void **state)
{
    (void)state;
    fv_mat4 o = fv_shadow_ortho(-2, 6, -1, 3, 0.5, 10.5);
    fv_vec4 a = fv_mat4_mul_v4(&o, (fv_vec4){-2, -1, -0.5f, 1}), b = fv_mat4_mul_v4(&o, (fv_vec4){6, 3, -10.5f, 1});
    assert_float_equal(a.x, -1, 1e-6);
    assert_float_equal(a.y, 1, 1e-6); /* Vulkan y down: bottom -> +1 */
    assert_float_equal(a.z, 0, 1e-6);
    assert_float_equal(b.x, 1, 1e-6);
    assert_float_equal(b.y, -1, 1e-6);
    assert_float_equal(b.z, 1, 1e-6);
    fv_mat4 inv;
    assert_true(fv_mat4_invert(&o, &inv));
    fv_mat4 d = fv_shadow_ortho(1, 1, 2, 2, 3, 3); /* degenerate: widened, still invertible */
    assert_true(fv_mat4_invert(&d, &inv));
}

static void depth_range_holds_the_box_and_the_clip_planes(void **state)
{
    (void)state;
    fv_mat4 view = fv_mat4_look_at(fv_v3(0, 0, 10), fv_v3(0, 0, 0), fv_v3(0, 1, 0));
    double n, f;
    assert_true(fv_shadow_depth_range(&view, fv_v3(-1, -1, -1), fv_v3(1, 1, 1), 0.05f, 100.0f, &n, &f));
    assert_float_equal(n, 9.0, 1e-5);
    assert_float_equal(f, 11.0, 1e-5);
    assert_true(fv_shadow_depth_range(&view, fv_v3(-1, -1, -1), fv_v3(1, 1, 1), 10.0f, 10.5f, &n, &f));
    assert_float_equal(n, 10.0, 1e-6);
    assert_float_equal(f, 10.5, 1e-6);
    /* behind the eye: nothing */
    assert_false(fv_shadow_depth_range(&view, fv_v3(-1, -1, 20), fv_v3(1, 1, 30), 0.05f, 100.0f, &n, &f));
}

/* Where a world point falls inside its texel (0..1 in x and y). */
static void texel_phase(const fv_mat4 *vp, fv_vec3 p, uint32_t res, double out[2])
{
    fv_vec4 c = fv_mat4_mul_v4(vp, (fv_vec4){p.x, p.y, p.z, 1.0f});
    double u = (c.x / c.w * 0.5 + 0.5) * res, v = (c.y / c.w * 0.5 + 0.5) * res;
    out[0] = u - floor(u);
    out[1] = v - floor(v);
}

static void crops_stay_on_the_texel_grid_as_the_head_moves(void **state)
{
    (void)state;
    fv_mat4 lv = fv_shadow_light_view(fv_v3(0.3f, -1.0f, 0.2f));
    const uint32_t res = 1024;
    fv_eye_view eye;
    fv_head_pose head = {.position_m = fv_v3(0, 1.7f, 0), .orientation = fv_quat_identity(), .ipd_mm = 63};
    fv_eye_view views[2];
    fv_eye_views_build(&head, 0.1f, 200.0f, 720, 800, views);
    eye = views[0];
    fv_vec3 pts[8];
    fv_shadow_slice_corners(&eye, 5.0, 25.0, pts);
    double texel0 = 0, phase0[2];
    fv_vec3 probe = fv_v3(1.234f, 0.0f, -12.5f);
    fv_mat4 vp0 = fv_shadow_crop_directional(&lv, pts, 8, fv_v3(-50, 0, -300), fv_v3(50, 10, 10), res, &texel0);
    texel_phase(&vp0, probe, res, phase0);
    for (int step = 1; step <= 20; step++) {
        /* The head walks and turns a little: the slice moves, the map must only shift by whole texels. */
        head.position_m = fv_v3(0.013f * step, 1.7f, -0.021f * step);
        head.orientation = fv_quat_axis_angle(fv_v3(0, 1, 0), 0.002f * step);
        fv_eye_views_build(&head, 0.1f, 200.0f, 720, 800, views);
        fv_shadow_slice_corners(&views[0], 5.0, 25.0, pts);
        double texel, phase[2];
        fv_mat4 vp = fv_shadow_crop_directional(&lv, pts, 8, fv_v3(-50, 0, -300), fv_v3(50, 10, 10), res, &texel);
        assert_float_equal(texel, texel0, 1e-12); /* the map's size does not breathe */
        texel_phase(&vp, probe, res, phase);
        for (int k = 0; k < 2; k++) {
            double d = fabs(phase[k] - phase0[k]);
            d = d > 0.5 ? 1.0 - d : d;
            if (d > 2e-3) fail_msg("step %d: the probe moved %.4f of a texel inside its texel", step, d);
        }
        /* the slice is inside the map */
        for (int i = 0; i < 8; i++) {
            fv_vec4 c = fv_mat4_mul_v4(&vp, (fv_vec4){pts[i].x, pts[i].y, pts[i].z, 1.0f});
            assert_true(fabs(c.x) <= 1.0001f && fabs(c.y) <= 1.0001f && c.z >= 0.0f && c.z <= 1.0f);
        }
    }
}

static void spot_map_holds_the_cone_and_the_scene(void **state)
{
    (void)state;
    fv_vec3 pos = fv_v3(0, 2, 0);
    fv_mat4 vp = fv_shadow_spot(pos, fv_v3(0, -1, 0), (float)fv_deg_to_rad(30.0), fv_v3(-3, 0, -3), fv_v3(3, 1, 3));
    fv_vec4 c = fv_mat4_mul_v4(&vp, (fv_vec4){0, 0, 0, 1});
    assert_float_equal(c.x / c.w, 0, 1e-6);
    assert_float_equal(c.y / c.w, 0, 1e-6);
    assert_true(c.z / c.w > 0 && c.z / c.w < 1);
    /* the cone's edge at 30 degrees lies inside the map (the map is 2% wider) */
    double r = 2.0 * tan(fv_deg_to_rad(30.0));
    c = fv_mat4_mul_v4(&vp, (fv_vec4){(float)r, 0, 0, 1});
    double edge = fmax(fabs(c.x / c.w), fabs(c.y / c.w)); /* the map's axes are the light's own */
    assert_true(edge < 1.0 && edge > 0.95);
    /* extremes: a zero direction, a NaN cone: finite */
    fv_mat4 e = fv_shadow_spot(pos, fv_v3(0, 0, 0), NAN, fv_v3(-1, -1, -1), fv_v3(1, 1, 1));
    for (int i = 0; i < 4; i++)
        for (int k = 0; k < 4; k++) assert_true(isfinite(e.m[i][k]));
    assert_true(fv_shadow_spot_texel_per_m((float)fv_deg_to_rad(45.0), 1024) > 0.0);
}

static void cube_faces_cover_every_direction(void **state)
{
    (void)state;
    fv_vec3 pos = fv_v3(0.5f, 1.0f, -0.25f);
    /* Each direction's major axis picks a face; the point must project inside that face, in front of it. */
    for (int i = 0; i < 500; i++) {
        double a = i * 2.399963, z = 1.0 - 2.0 * (i + 0.5) / 500.0, r = sqrt(1.0 - z * z);
        fv_vec3 d = fv_v3((float)(r * cos(a)), (float)z, (float)(r * sin(a)));
        float ax = fabsf(d.x), ay = fabsf(d.y), az = fabsf(d.z);
        uint32_t axis = ax >= ay && ax >= az ? 0u : (ay >= az ? 1u : 2u);
        float comp = axis == 0 ? d.x : (axis == 1 ? d.y : d.z);
        uint32_t face = axis * 2u + (comp < 0 ? 1u : 0u);
        fv_mat4 vp = fv_shadow_cube_face(pos, face, fv_v3(-3, -3, -3), fv_v3(3, 3, 3));
        fv_vec3 p = fv_v3_add(pos, fv_v3_scale(d, 2.0f));
        fv_vec4 c = fv_mat4_mul_v4(&vp, (fv_vec4){p.x, p.y, p.z, 1.0f});
        assert_true(c.w > 0);
        assert_true(fabsf(c.x / c.w) <= 1.0f / 1.02f + 1e-4f && fabsf(c.y / c.w) <= 1.0f / 1.02f + 1e-4f);
        assert_true(c.z / c.w > 0 && c.z / c.w < 1);
    }
    assert_true(fv_shadow_cube_texel_per_m(2048) > 0);
    fv_mat4 e = fv_shadow_cube_face(fv_v3(NAN, 0, 0), 99, fv_v3(-1, -1, -1), fv_v3(1, 1, 1));
    for (int i = 0; i < 4; i++)
        for (int k = 0; k < 4; k++) assert_true(isfinite(e.m[i][k]));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(splits_follow_the_practical_scheme_at_every_extreme),
        cmocka_unit_test(split_input_is_sanitised_and_stays_finite),
        cmocka_unit_test(a_shallow_depth_range_gets_fewer_splits),
        cmocka_unit_test(ortho_maps_the_box_to_vulkan_clip),
        cmocka_unit_test(depth_range_holds_the_box_and_the_clip_planes),
        cmocka_unit_test(crops_stay_on_the_texel_grid_as_the_head_moves),
        cmocka_unit_test(spot_map_holds_the_cone_and_the_scene),
        cmocka_unit_test(cube_faces_cover_every_direction),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
