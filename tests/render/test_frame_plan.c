/* @brief Pure tests (no GPU) of the frame plan and the stereo views: which passes run and why, eye placement, the
 * asymmetric mirrored field of view, near/far from bounds, and finite output for extreme input. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fv_knobs.h"
#include "fv_passes.h"
#include "fv_renderer.h"
#include "fv_scene.h"
#include "fv_test.h"

static void plan_for_cornell_runs_gbuffer_shade_present_and_explains_the_rest(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("cornell", &s), FV_OK);
    fv_frame_plan p;
    fv_frame_plan_build(s, &p);
    const char *on[] = {"gbuffer", "shade", "present"};
    for (int i = 0; i < 3; i++) {
        const fv_plan_entry *e = fv_frame_plan_find(&p, on[i]);
        assert_non_null(e);
        assert_true(e->enabled);
        assert_true(strlen(e->reason) > 0);
    }
    assert_non_null(strstr(fv_frame_plan_find(&p, "shade")->reason, "direct lighting from 1 light (0 point, 1 spot"));
    assert_non_null(strstr(fv_frame_plan_find(&p, "sss")->reason, "off — no translucent material"));
    assert_false(fv_frame_plan_find(&p, "sss")->enabled);
    assert_non_null(strstr(fv_frame_plan_find(&p, "motion")->reason, "static scene"));
    /* cornell's one spot light gets a perspective shadow map (balanced preset: on). */
    assert_true(fv_frame_plan_find(&p, "shadow")->enabled);
    assert_non_null(strstr(fv_frame_plan_find(&p, "shadow")->reason, "1 spot: one perspective map"));
    assert_null(fv_frame_plan_find(&p, "nope"));
    fv_scene_destroy(&s);

    assert_int_equal(fv_scene_load("pillars", &s), FV_OK);
    fv_frame_plan_build(s, &p);
    assert_true(fv_frame_plan_find(&p, "shadow")->enabled);
    assert_non_null(strstr(fv_frame_plan_find(&p, "shadow")->reason, "1 directional: 4 splits (lambda 0.5) shared by both eyes"));
    fv_scene_destroy(&s);

    /* A sun over the Cornell box: a shallow depth range from the head, so fewer splits, and the plan says why. */
    assert_int_equal(fv_scene_load("cornell", &s), FV_OK);
    fv_light sun;
    memset(&sun, 0, sizeof sun);
    sun.type = FV_LIGHT_DIRECTIONAL;
    sun.direction = fv_v3(0.2f, -1.0f, 0.1f);
    sun.color = fv_v3(1, 1, 1);
    sun.intensity = 1.0f;
    assert_int_equal(fv_scene_add_light(s, &sun, NULL), FV_OK);
    fv_frame_plan_build(s, &p);
    const char *why = fv_frame_plan_find(&p, "shadow")->reason;
    if (!strstr(why, "of 4 splits (depth") || !strstr(why, "is shallow")) fail_msg("shadow reason: %s", why);
    fv_scene_destroy(&s);

    assert_int_equal(fv_scene_load("cornell-translucent", &s), FV_OK);
    fv_frame_plan_build(s, &p);
    assert_true(fv_frame_plan_find(&p, "sss")->enabled);
    assert_non_null(strstr(fv_frame_plan_find(&p, "sss")->reason, "1 translucent material: 1 light-view map of"));
    fv_scene_destroy(&s);
}

static void plan_for_an_empty_scene_says_nothing_emits_light(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("empty", &s), FV_OK);
    fv_frame_plan p;
    fv_frame_plan_build(s, &p);
    assert_non_null(strstr(fv_frame_plan_find(&p, "shade")->reason, "nothing emits light"));
    assert_non_null(strstr(fv_frame_plan_find(&p, "shadow")->reason, "off — no lights"));
    assert_non_null(strstr(fv_frame_plan_find(&p, "gbuffer")->reason, "0 triangles"));
    fv_scene_destroy(&s);
    fv_frame_plan_build(NULL, &p);
    assert_true(p.count >= 3);
}

static void eyes_sit_at_half_ipd_along_the_head_x_axis(void **state)
{
    (void)state;
    fv_head h = {.position_m = {1, 2, 3}, .orientation = fv_quat_axis_angle(fv_v3(0, 1, 0), (float)(FV_PI / 2)),
                 .ipd_mm = 64};
    fv_frame_input in;
    fv_frame_input_from_head(&h, 0.1f, 50.0f, 720, 800, 9, 1.5, &in);
    /* head x axis rotated 90 deg about y points to -z */
    assert_float_equal(in.eye[0].pos_world.x, 1.0f, 1e-6);
    assert_float_equal(in.eye[0].pos_world.z, 3.0f + 0.032f, 1e-6);
    assert_float_equal(in.eye[1].pos_world.z, 3.0f - 0.032f, 1e-6);
    assert_int_equal(in.frame_id, 9);
    /* the view matrix maps the eye to the origin and the head's forward (-x in world) to -z */
    for (int e = 0; e < 2; e++) {
        fv_vec3 o = fv_mat4_mul_point(&in.eye[e].view, in.eye[e].pos_world);
        assert_float_equal(fv_v3_len(o), 0.0f, 1e-5);
        fv_vec3 f = fv_mat4_mul_dir(&in.eye[e].view, fv_v3(-1, 0, 0));
        assert_float_equal(f.z, -1.0f, 1e-5);
        assert_true(in.gaze[e].valid);
    }
}

static void fov_is_asymmetric_outer_wider_and_mirrored(void **state)
{
    (void)state;
    fv_head h = {.orientation = {0, 0, 0, 1}, .ipd_mm = 63};
    fv_frame_input in;
    fv_frame_input_from_head(&h, 0.1f, 50.0f, 720, 800, 0, 0, &in);
    const fv_eye_view *l = &in.eye[0], *r = &in.eye[1];
    assert_true(-l->tan_left > l->tan_right);  /* left eye: outer (left) wider */
    assert_true(r->tan_right > -r->tan_left); /* right eye: outer (right) wider */
    assert_float_equal(l->tan_left, -r->tan_right, 1e-6);
    assert_float_equal(l->tan_right, -r->tan_left, 1e-6);
    assert_float_equal(l->tan_up, tan(fv_deg_to_rad(FV_HMD_FOV_UP_DEG)), 1e-6);
    assert_float_equal(l->tan_down, -tan(fv_deg_to_rad(FV_HMD_FOV_DOWN_DEG)), 1e-6);
    /* square pixels: horizontal span / width == vertical span / height */
    assert_float_equal((l->tan_right - l->tan_left) / 720.0f, (l->tan_up - l->tan_down) / 800.0f, 1e-6);
    /* outer:inner as the HMD constants */
    double ratio = -l->tan_left / l->tan_right;
    assert_float_equal(ratio, tan(fv_deg_to_rad(FV_HMD_FOV_OUTER_DEG)) / tan(fv_deg_to_rad(FV_HMD_FOV_INNER_DEG)),
                       1e-5);
}

static bool mat_finite(const fv_mat4 *m)
{
    for (int c = 0; c < 4; c++)
        for (int k = 0; k < 4; k++)
            if (!isfinite(m->m[c][k])) return false;
    return true;
}

static void extreme_inputs_give_finite_views(void **state)
{
    (void)state;
    const float nears[] = {0.0f, -1.0f, NAN, 1e-30f, 1e-4f, 1e6f, INFINITY};
    const float fars[] = {0.0f, NAN, 1e6f, 1e30f, 1e-4f, INFINITY};
    fv_head h = {.position_m = {NAN, 0, 0}, .orientation = {0, 0, 0, 0}, .ipd_mm = NAN};
    for (size_t i = 0; i < sizeof nears / sizeof nears[0]; i++)
        for (size_t j = 0; j < sizeof fars / sizeof fars[0]; j++) {
            fv_frame_input in;
            fv_frame_input_from_head(&h, nears[i], fars[j], 0, 0, 0, NAN, &in);
            for (int e = 0; e < 2; e++) {
                assert_true(mat_finite(&in.eye[e].view));
                assert_true(mat_finite(&in.eye[e].proj));
                assert_true(in.eye[e].far_m > in.eye[e].near_m && in.eye[e].near_m > 0);
                fv_mat4 vp = fv_mat4_mul(&in.eye[e].proj, &in.eye[e].view), inv;
                assert_true(fv_mat4_invert(&vp, &inv));
            }
            assert_float_equal(in.eye[1].pos_world.x - in.eye[0].pos_world.x, 0.063f, 1e-6); /* NaN IPD: 63 mm */
        }
    h.ipd_mm = 1e9f;
    fv_frame_input in;
    fv_frame_input_from_head(&h, 1e-4f, 1e6f, 64, 64, 0, 0, &in);
    assert_float_equal(in.eye[1].pos_world.x - in.eye[0].pos_world.x, FV_SCENE_MAX_IPD_MM * 1e-3f, 1e-6);
}

static void near_far_hold_the_scene_bounds(void **state)
{
    (void)state;
    fv_head h = {.position_m = {0, 0, 5}, .orientation = {0, 0, 0, 1}, .ipd_mm = 63};
    float n, f;
    fv_frame_near_far_from_bounds(&h, fv_v3(-1, -1, -1), fv_v3(1, 1, 1), &n, &f);
    double r = sqrt(3.0);
    assert_true(n > 0 && n < 5 - r);
    assert_true(f > 5 + r && f < 2 * (5 + r));
    /* inside the bounds: a small positive near */
    h.position_m = fv_v3(0, 0, 0);
    fv_frame_near_far_from_bounds(&h, fv_v3(-1, -1, -1), fv_v3(1, 1, 1), &n, &f);
    assert_true(n > 0 && n < 0.05f && f > r);
    /* garbage bounds: defaults, finite */
    fv_frame_near_far_from_bounds(&h, fv_v3(NAN, 0, 0), fv_v3(1, 1, 1), &n, &f);
    assert_true(isfinite(n) && isfinite(f) && f > n && n > 0);
    fv_frame_near_far_from_bounds(&h, fv_v3(-1e30f, -1e30f, -1e30f), fv_v3(1e30f, 1e30f, 1e30f), &n, &f);
    assert_true(isfinite(n) && isfinite(f) && f > n && n > 0);
}

/* ---- declared images (fv_pass makes / needs / uses_if_made, fv_frame_plan_check) ------------------------------- */

/* The built-in table holds together in every preset, with interpolation, every debug view and the overlay, for a
 * scene with and without translucency: no pass needs an image no earlier enabled pass makes. */
static void the_built_in_table_holds_together_in_every_plan(void **state)
{
    (void)state;
    uint32_t n = 0;
    const fv_pass *const *t = fv_pass_table(&n);
    const char *scenes[] = {"cornell", "cornell-translucent"};
    const char *presets[] = {"fast", "balanced", "high", "exact"};
    for (size_t sc = 0; sc < 2; sc++) {
        fv_scene *s = NULL;
        assert_int_equal(fv_scene_load(scenes[sc], &s), FV_OK);
        for (size_t p = 0; p < 4; p++)
            for (int v = 0; v < FV_DEBUG_VIEW_COUNT; v++)
                for (int variant = 0; variant < 4; variant++) {
                    fv_quality q;
                    assert_int_equal(fv_quality_preset(presets[p], &q, NULL, 0), FV_OK);
                    q.debug_view = (fv_debug_view)v;
                    q.interp.enabled = variant & 1;
                    q.overlay = variant & 2;
                    fv_plan_context ctx = {.scene = s, .multiview = true, .quality = &q};
                    fv_frame_plan plan;
                    fv_frame_plan_build_table(t, n, &ctx, &plan);
                    char err[256];
                    if (fv_frame_plan_check(t, n, &plan, err, sizeof err) != FV_OK)
                        fail_msg("%s, %s, view %s, variant %d: %s", scenes[sc], presets[p],
                                 fv_debug_view_name((fv_debug_view)v), variant, err);
                }
        fv_scene_destroy(&s);
    }
    /* --explain's graph: each reader names the image's maker */
    fv_frame_plan plan;
    fv_frame_plan_build(NULL, &plan);
    assert_string_equal(fv_frame_plan_find(&plan, "compact")->io, "needs fovea mask (fovea)");
    assert_string_equal(fv_frame_plan_find(&plan, "reconstruct")->io,
                        "makes fovea voronoi, fovea soft reps; needs fovea mask (fovea), fovea blocks (fovea)");
    assert_string_equal(fv_frame_plan_find(&plan, "gbuffer")->io, "");
}

/* Test passes: each is on unless its plan says otherwise (t_off), and declares what the test needs. */
static void t_on(const fv_plan_context *ctx, fv_plan_entry *out)
{
    (void)ctx;
    out->enabled = true;
    snprintf(out->reason, sizeof out->reason, "test pass");
}
static void t_off(const fv_plan_context *ctx, fv_plan_entry *out)
{
    (void)ctx;
    out->enabled = false;
    snprintf(out->reason, sizeof out->reason, "off — a test says so");
}
static const fv_pass maker = {.id = "maker", .plan = t_on, .makes = FV_PASS_NAMES("test image")};
static const fv_pass maker_off = {.id = "maker", .plan = t_off, .makes = FV_PASS_NAMES("test image")};
static const fv_pass maker2 = {.id = "maker2", .plan = t_on, .makes = FV_PASS_NAMES("test image")};
static const fv_pass reader = {.id = "reader", .plan = t_on, .needs = FV_PASS_NAMES("test image")};
static const fv_pass reader_off = {.id = "reader", .plan = t_off, .needs = FV_PASS_NAMES("test image")};
static const fv_pass maybe = {.id = "maybe", .plan = t_on, .uses_if_made = FV_PASS_NAMES("test image")};
static const fv_pass stranger = {.id = "stranger", .plan = t_on, .needs = FV_PASS_NAMES("no such image")};

/* One table: its plan's check, and the message when it fails (must contain want; NULL: must pass). */
static void check_table(const fv_pass *const *t, uint32_t n, const char *want)
{
    fv_frame_plan plan;
    fv_plan_context ctx = {.multiview = true};
    fv_frame_plan_build_table(t, n, &ctx, &plan);
    char err[256] = "";
    fv_result r = fv_frame_plan_check(t, n, &plan, err, sizeof err);
    if (!want) {
        if (r != FV_OK) fail_msg("unexpected: %s", err);
        return;
    }
    assert_int_equal(r, FV_ERR_STATE);
    if (!strstr(err, want)) fail_msg("\"%s\" does not say \"%s\"", err, want);
    assert_null(strchr(err, '\n'));
}

/* A pass that reads an image before its maker records, of a maker that is off, or that nobody makes is an error at
 * plan time naming both passes (not a crash in init); an image made twice too; a use-if-made of a maker that is off
 * is not. */
static void a_reader_before_its_maker_is_an_error_at_plan_time(void **state)
{
    (void)state;
    check_table((const fv_pass *const[]){&maker, &reader}, 2, NULL);
    check_table((const fv_pass *const[]){&reader, &maker}, 2,
                "pass reader needs image 'test image' of pass maker, but its maker records after it");
    check_table((const fv_pass *const[]){&maker_off, &reader}, 2,
                "pass reader needs image 'test image' of pass maker, but its maker is off: off — a test says so");
    check_table((const fv_pass *const[]){&maker_off, &reader_off}, 2, NULL); /* nobody reads it */
    check_table((const fv_pass *const[]){&stranger}, 1,
                "pass stranger needs image 'no such image', but no pass of the table makes it");
    check_table((const fv_pass *const[]){&maker, &maker2, &reader}, 3,
                "image 'test image' is made by two passes, maker and maker2");
    check_table((const fv_pass *const[]){&maker_off, &maybe}, 2, NULL);
    check_table((const fv_pass *const[]){&maybe, &maker}, 2,
                "pass maybe uses image 'test image' of pass maker, but its maker records after it");
    fv_frame_plan plan;
    fv_plan_context ctx = {.multiview = true};
    fv_frame_plan_build_table((const fv_pass *const[]){&maker, &reader, &maybe}, 3, &ctx, &plan);
    assert_string_equal(plan.entries[0].io, "makes test image");
    assert_string_equal(plan.entries[1].io, "needs test image (maker)");
    assert_string_equal(plan.entries[2].io, "uses if made test image (maker)");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(plan_for_cornell_runs_gbuffer_shade_present_and_explains_the_rest),
        cmocka_unit_test(plan_for_an_empty_scene_says_nothing_emits_light),
        cmocka_unit_test(eyes_sit_at_half_ipd_along_the_head_x_axis),
        cmocka_unit_test(fov_is_asymmetric_outer_wider_and_mirrored),
        cmocka_unit_test(extreme_inputs_give_finite_views),
        cmocka_unit_test(near_far_hold_the_scene_bounds),
        cmocka_unit_test(the_built_in_table_holds_together_in_every_plan),
        cmocka_unit_test(a_reader_before_its_maker_is_an_error_at_plan_time),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
