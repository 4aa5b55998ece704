/* @brief Pure tests of the CPU reference renderer (render/reference): model mode against closed forms in double
 * (a spot-lit plane, exact shadows of a blocker, the depth and normal views, textures), path mode's direct light
 * equal to model mode, determinism for a seed whatever the thread count, and finite output for extreme scenes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_reference.h"
#include "fv_scene.h"
#include "fv_test.h"
#include "reference_test.h"

#define W 40
#define H 36

/* ---- closed forms (fv_shade_common.glsl in double, written out again here) ----------------------------------- */

typedef struct light_d {
    int type;
    double pos[3], dir[3], intensity[3], range, cos_inner, cos_outer;
} light_d;

static light_d light_double(const fv_light *l)
{
    light_d o;
    memset(&o, 0, sizeof o);
    o.type = (int)l->type;
    double dl = sqrt((double)l->direction.x * l->direction.x + (double)l->direction.y * l->direction.y +
                     (double)l->direction.z * l->direction.z);
    double p[3] = {l->position_m.x, l->position_m.y, l->position_m.z};
    double d[3] = {l->direction.x / dl, l->direction.y / dl, l->direction.z / dl};
    double c[3] = {l->color.x, l->color.y, l->color.z};
    for (int k = 0; k < 3; k++) o.pos[k] = p[k], o.dir[k] = d[k], o.intensity[k] = c[k] * (double)l->intensity;
    o.range = l->range_m;
    o.cos_inner = cos((double)l->inner_cone_rad);
    o.cos_outer = cos((double)l->outer_cone_rad);
    return o;
}

/* Irradiance factor (without the colour) of light l at p with normal n. */
static double irradiance(const light_d *l, const double p[3], const double n[3])
{
    if (l->type == FV_LIGHT_DIRECTIONAL) return fmax(-(n[0] * l->dir[0] + n[1] * l->dir[1] + n[2] * l->dir[2]), 0);
    double to[3] = {l->pos[0] - p[0], l->pos[1] - p[1], l->pos[2] - p[2]};
    double d2 = to[0] * to[0] + to[1] * to[1] + to[2] * to[2];
    double d = sqrt(d2);
    double lv[3] = {to[0] / d, to[1] / d, to[2] / d};
    double cs = fmax(n[0] * lv[0] + n[1] * lv[1] + n[2] * lv[2], 0.0);
    double falloff = 1.0;
    if (l->type == FV_LIGHT_SPOT) {
        double ca = -(lv[0] * l->dir[0] + lv[1] * l->dir[1] + lv[2] * l->dir[2]);
        double t = fmin(fmax((ca - l->cos_outer) / (l->cos_inner - l->cos_outer), 0.0), 1.0);
        falloff = t * t * (3.0 - 2.0 * t);
    }
    if (l->range > 0) {
        double q = d / l->range;
        double w = fmin(fmax(1.0 - q * q * q * q, 0.0), 1.0);
        falloff *= w * w;
    }
    return falloff * cs / d2;
}

/* The plane y = 0 seen through pixel (x, y) of an eye: the hit point, false when the ray misses it. */
static bool plane_hit(const fv_eye_view *v, int x, int y, double out_p[3], double *out_t)
{
    double o[3], d[3], t_max;
    assert_true(fv_reference_pixel_ray(v, W, H, x + 0.5, y + 0.5, o, d, &t_max));
    double t = -o[1] / d[1];
    if (!(d[1] < 0) || !(t > 0) || t > t_max) return false;
    for (int k = 0; k < 3; k++) out_p[k] = o[k] + t * d[k];
    if (out_t) *out_t = t;
    return true;
}

static void check_finite_nonnegative(const float *img, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(img[i]) || img[i] < 0) fail_msg("value %zu is %g", i, (double)img[i]);
}

/* ---- model mode against closed forms ------------------------------------------------------------------------- */

static fv_light spot_light(void)
{
    /* the direction is not unit: the renderer normalises it, as the GPU upload does */
    fv_light l = rt_light(FV_LIGHT_SPOT, fv_v3(0.2f, 1.6f, -0.3f), fv_v3(-0.2f, -1.0f, 0.1f), fv_v3(1.0f, 0.8f, 0.6f),
                          3.0f);
    l.range_m = 2.5f;
    return l;
}

static void model_spot_lit_plane_matches_the_closed_form_to_1e9(void **state)
{
    (void)state;
    fv_vec3 albedo = fv_v3(0.9f, 0.7f, 0.5f);
    fv_scene *s = rt_plane_scene(albedo, 6.0);
    fv_light l = spot_light();
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    fv_frame_input in = rt_views(&s->head, W, H);
    double *img[2] = {rt_image_f64(W, H), rt_image_f64(W, H)};
    fv_reference_desc d = {.mode = FV_REFERENCE_MODEL, .eye_width = W, .eye_height = H, .threads = 2};
    fv_reference_stats st;
    assert_int_equal(fv_reference_render_f64(s, &in, &d, img[0], img[1], &st), FV_OK);
    assert_int_equal(st.primary_rays, 2 * W * H);
    assert_int_equal(st.threads, 2);
    light_d ld = light_double(&l);
    double a[3] = {albedo.x, albedo.y, albedo.z};
    const double n[3] = {0, 1, 0};
    int lit = 0, fringe = 0;
    double worst = 0;
    for (int eye = 0; eye < 2; eye++)
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                double p[3];
                assert_true(plane_hit(&in.eye[eye], x, y, p, NULL));
                double e = irradiance(&ld, p, n);
                for (int c = 0; c < 3; c++) {
                    double want = a[c] / FV_PI * ld.intensity[c] * e;
                    double got = img[eye][((size_t)y * W + x) * 3 + c];
                    if (want > 0) {
                        double rel = fabs(got - want) / want;
                        if (rel > worst) worst = rel;
                        if (rel > 1e-9) fail_msg("eye %d (%d,%d) ch %d: %.17g, closed form %.17g", eye, x, y, c, got, want);
                        lit++;
                        if (e < 0.5 * ld.intensity[0]) fringe++;
                    } else {
                        assert_true(got == 0.0);
                    }
                }
            }
    assert_true(lit > W * H / 4);
    assert_true(fringe > 10); /* the smoothstep and the range window are exercised, not only the plateau */
    print_message("spot-lit plane: worst relative difference to the closed form %.3g\n", worst);
    free(img[0]);
    free(img[1]);
    fv_scene_destroy(&s);
}

static void shadow_ray_blocker_gives_zero_in_its_shadow_and_the_closed_form_elsewhere(void **state)
{
    (void)state;
    fv_scene *s = rt_plane_scene(fv_v3(1, 1, 1), 6.0);
    /* a 0.4 m square blocker at y = 0.5 under a point light at y = 1: its shadow is the 0.8 m square at y = 0 */
    uint32_t mat = rt_material(s, fv_v3(1, 1, 1), fv_v3(0, 0, 0));
    rt_add_square(s, "blocker", fv_v3(0, 0.5f, 0), 0.2, mat);
    fv_light l = rt_light(FV_LIGHT_POINT, fv_v3(0, 1.0f, 0), fv_v3(0, -1, 0), fv_v3(1, 1, 1), 1.0f);
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    s->head.position_m = fv_v3(0.9f, 1.4f, 0.1f); /* off the light's axis: sees the shadow beside the blocker */
    fv_frame_input in = rt_views(&s->head, W, H);
    float *img = rt_image(W, H), *vis = rt_image(W, H);
    fv_reference_desc d = {.eye_width = W, .eye_height = H};
    assert_int_equal(fv_reference_render(s, &in, &d, img, NULL, NULL), FV_OK);
    d.view = FV_REFERENCE_VIEW_SHADOW;
    assert_int_equal(fv_reference_render(s, &in, &d, vis, NULL, NULL), FV_OK);
    light_d ld = light_double(&l);
    const double n[3] = {0, 1, 0};
    int shadowed = 0, lit = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double p[3], o[3], dir[3], t_max;
            assert_true(plane_hit(&in.eye[0], x, y, p, NULL));
            /* skip pixels that see the blocker itself, and those within 2 mm of the shadow's edge */
            assert_true(fv_reference_pixel_ray(&in.eye[0], W, H, x + 0.5, y + 0.5, o, dir, &t_max));
            double tb = (0.5 - o[1]) / dir[1];
            double bx = o[0] + tb * dir[0], bz = o[2] + tb * dir[2];
            if (tb > 0 && fabs(bx) < 0.2 + 1e-3 && fabs(bz) < 0.2 + 1e-3) continue;
            double m = fmax(fabs(p[0]), fabs(p[2]));
            if (fabs(m - 0.4) < 2e-3) continue;
            const float *px = &img[((size_t)y * W + x) * 3];
            float v = vis[((size_t)y * W + x) * 3];
            if (m < 0.4) {
                shadowed++;
                assert_true(px[0] == 0.0f && px[1] == 0.0f && px[2] == 0.0f);
                assert_true(v == 0.0f);
            } else {
                lit++;
                double want = irradiance(&ld, p, n) / FV_PI;
                assert_true(fabs(px[0] - want) <= 1e-6 * want);
                assert_true(v == 1.0f);
            }
        }
    assert_true(shadowed > 20);
    assert_true(lit > 200);
    free(img);
    free(vis);
    fv_scene_destroy(&s);
}

static void depth_and_normal_views_match_the_projection_and_the_facing_normal(void **state)
{
    (void)state;
    fv_scene *s = rt_plane_scene(fv_v3(0.3f, 0.6f, 0.9f), 6.0);
    s->meshes[0].normals[0] = fv_v3(0, -1, 0); /* a flipped normal: the G-buffer turns it toward the eye */
    for (uint32_t i = 1; i < s->meshes[0].vertex_count; i++) s->meshes[0].normals[i] = fv_v3(0, -1, 0);
    fv_frame_input in = rt_views(&s->head, W, H);
    float *depth = rt_image(W, H), *normal = rt_image(W, H), *albedo = rt_image(W, H);
    fv_reference_desc d = {.eye_width = W, .eye_height = H, .view = FV_REFERENCE_VIEW_DEPTH};
    assert_int_equal(fv_reference_render(s, &in, &d, NULL, depth, NULL), FV_OK);
    d.view = FV_REFERENCE_VIEW_NORMAL;
    assert_int_equal(fv_reference_render(s, &in, &d, NULL, normal, NULL), FV_OK);
    d.view = FV_REFERENCE_VIEW_ALBEDO;
    assert_int_equal(fv_reference_render(s, &in, &d, NULL, albedo, NULL), FV_OK);
    fv_mat4 vp = fv_mat4_mul(&in.eye[1].proj, &in.eye[1].view);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double p[3];
            assert_true(plane_hit(&in.eye[1], x, y, p, NULL));
            double z = 0, wc = 0;
            for (int c = 0; c < 3; c++) z += (double)vp.m[c][2] * p[c], wc += (double)vp.m[c][3] * p[c];
            z += vp.m[3][2], wc += vp.m[3][3];
            size_t i = ((size_t)y * W + x) * 3;
            assert_true(fabs(depth[i] - z / wc) < 1e-7);
            assert_true(depth[i] > 0 && depth[i] < 1);
            assert_true(normal[i] == 0.5f && normal[i + 1] == 1.0f && normal[i + 2] == 0.5f);
            assert_true(albedo[i] == 0.3f && albedo[i + 1] == 0.6f && albedo[i + 2] == 0.9f);
        }
    free(depth);
    free(normal);
    free(albedo);
    fv_scene_destroy(&s);
}

static double srgb_decode(int code)
{
    double c = code / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

static void albedo_is_base_colour_times_the_srgb_decoded_bilinear_texture(void **state)
{
    (void)state;
    fv_scene *s = rt_plane_scene(fv_v3(0.5f, 1.0f, 1.0f), 6.0);
    /* a 2x1 texture: codes 64 and 200 (red), 128 (green, both), 255 (blue); texcoords repeat 3 times */
    fv_texture t;
    memset(&t, 0, sizeof t);
    snprintf(t.source, sizeof t.source, "test");
    t.width = 2;
    t.height = 1;
    t.rgba8 = malloc(8);
    assert_non_null(t.rgba8);
    const uint8_t px[8] = {64, 128, 255, 255, 200, 128, 255, 255};
    memcpy(t.rgba8, px, 8);
    uint32_t ti;
    assert_int_equal(fv_scene_add_texture(s, &t, &ti), FV_OK);
    s->materials[0].base_color_texture = (int32_t)ti;
    fv_mesh *m = &s->meshes[0];
    m->texcoords = malloc(m->vertex_count * sizeof *m->texcoords);
    assert_non_null(m->texcoords);
    for (uint32_t v = 0; v < m->vertex_count; v++)
        m->texcoords[v] = (fv_vec2){m->positions[v].x * 3.0f, m->positions[v].z * 3.0f};
    fv_frame_input in = rt_views(&s->head, W, H);
    float *img = rt_image(W, H);
    fv_reference_desc d = {.eye_width = W, .eye_height = H, .view = FV_REFERENCE_VIEW_ALBEDO};
    assert_int_equal(fv_reference_render(s, &in, &d, img, NULL, NULL), FV_OK);
    double lo = srgb_decode(64), hi = srgb_decode(200);
    double r_min = 1, r_max = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double p[3];
            assert_true(plane_hit(&in.eye[0], x, y, p, NULL));
            /* u = 3 x (repeat), blended between texel centres 0.25 and 0.75 with wrap-around */
            double u = p[0] * 3.0 - floor(p[0] * 3.0);
            double xx = u * 2.0 - 0.5;
            double f = xx - floor(xx);
            int i0 = ((int)floor(xx) % 2 + 2) % 2;
            double c0 = i0 == 0 ? lo : hi, c1 = i0 == 0 ? hi : lo;
            double want_r = 0.5 * ((1 - f) * c0 + f * c1);
            const float *q = &img[((size_t)y * W + x) * 3];
            /* texcoords are interpolated from float vertices: allow for that, not for a different filter */
            assert_true(fabs(q[0] - want_r) < 2e-5);
            assert_true(fabs(q[1] - srgb_decode(128)) < 1e-6);
            assert_true(fabs(q[2] - 1.0) < 1e-6);
            r_min = fmin(r_min, q[0]), r_max = fmax(r_max, q[0]);
        }
    assert_true(r_max - r_min > 0.3 * (hi - lo)); /* the texture varies across the image */
    free(img);
    fv_scene_destroy(&s);
}

/* ---- path mode ----------------------------------------------------------------------------------------------- */

static fv_scene *cornell_without_emission(void)
{
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("cornell", &s), FV_OK);
    for (uint32_t i = 0; i < s->material_count; i++) s->materials[i].emissive = fv_v3(0, 0, 0);
    /* every light type, so that all three go through both modes */
    fv_light l = rt_light(FV_LIGHT_POINT, fv_v3(0.1f, 0.3f, -0.1f), fv_v3(0, -1, 0), fv_v3(0.3f, 0.5f, 1.0f), 0.05f);
    l.range_m = 1.0f;
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    l.type = FV_LIGHT_DIRECTIONAL;
    l.direction = fv_v3(0.3f, -1.0f, 0.6f);
    l.intensity = 0.4f;
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    return s;
}

static void path_direct_only_equals_model_without_emission(void **state)
{
    (void)state;
    fv_scene *s = cornell_without_emission();
    fv_frame_input in = rt_views_auto(s, W, H);
    double *model[2] = {rt_image_f64(W, H), rt_image_f64(W, H)}, *path[2] = {rt_image_f64(W, H), rt_image_f64(W, H)};
    fv_reference_desc d = {.mode = FV_REFERENCE_MODEL, .eye_width = W, .eye_height = H};
    assert_int_equal(fv_reference_render_f64(s, &in, &d, model[0], model[1], NULL), FV_OK);
    d.mode = FV_REFERENCE_PATH;
    d.bounces = 0;
    d.spp = 3;
    fv_reference_stats st;
    assert_int_equal(fv_reference_render_f64(s, &in, &d, path[0], path[1], &st), FV_OK);
    assert_int_equal(st.bounce_rays, 0);
    assert_int_equal(st.emissive_triangles, 0);
    double peak = 0;
    for (int e = 0; e < 2; e++)
        for (size_t i = 0; i < (size_t)W * H * 3; i++) {
            double a = model[e][i], b = path[e][i];
            peak = fmax(peak, a);
            if (fabs(a - b) > 1e-9 * fmax(fabs(a), 1e-30)) fail_msg("eye %d value %zu: model %.9g path %.9g", e, i, a, b);
        }
    assert_true(peak > 0.05);
    for (int e = 0; e < 2; e++) {
        free(model[e]);
        free(path[e]);
    }
    fv_scene_destroy(&s);
}

/* A closed box that emits Le = 1 everywhere (two-sided) with albedo 0.5, seen from inside: each bounce adds a
 * factor 0.5, so L = Le (1 + 0.5 + ... + 0.5^bounces), 2 in the limit. Checks area-light sampling, MIS and Russian
 * roulette for bias. Without a bounce (no MIS) uniform area sampling is heavy-tailed near the box's edges (1/r^2),
 * hence the wider tolerance there. */
static void path_mode_sums_the_furnace_series(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("furnace", &s), FV_OK);
    uint32_t m = rt_material(s, fv_v3(0.5f, 0.5f, 0.5f), fv_v3(1, 1, 1));
    rt_add_box(s, fv_v3(0, 0, 0), 1.0, m);
    s->head.position_m = fv_v3(0.1f, 0.2f, 0.3f);
    enum { FW = 16, FH = 16 };
    fv_frame_input in = rt_views(&s->head, FW, FH);
    double *img = rt_image_f64(FW, FH);
    const uint32_t bounces[3] = {0, 1, 64};
    const double want[3] = {1.5, 1.75, 2.0}, tol[3] = {0.08, 0.03, 0.02};
    for (int b = 0; b < 3; b++) {
        fv_reference_desc d = {.mode = FV_REFERENCE_PATH, .spp = 128, .bounces = bounces[b], .seed = 3,
                               .eye_width = FW, .eye_height = FH};
        assert_int_equal(fv_reference_render_f64(s, &in, &d, img, NULL, NULL), FV_OK);
        double sum = 0;
        for (size_t i = 0; i < (size_t)FW * FH * 3; i++) sum += img[i];
        double mean = sum / (FW * FH * 3);
        print_message("furnace, %u bounces: mean %.4f (exact %.4f)\n", bounces[b], mean, want[b]);
        assert_true(fabs(mean - want[b]) < tol[b]);
    }
    free(img);
    fv_scene_destroy(&s);
}

static void same_seed_gives_identical_images_on_1_and_2_threads_and_another_seed_differs(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("cornell", &s), FV_OK); /* the lamp emits: area-light sampling is random */
    enum { SW = 20, SH = 18 };
    fv_frame_input in = rt_views_auto(s, SW, SH);
    float *a[2] = {rt_image(SW, SH), rt_image(SW, SH)}, *b[2] = {rt_image(SW, SH), rt_image(SW, SH)};
    float *c = rt_image(SW, SH);
    fv_reference_desc d = {.mode = FV_REFERENCE_PATH, .spp = 2, .bounces = 4, .seed = 7, .threads = 1,
                           .eye_width = SW, .eye_height = SH, .aa = true};
    assert_int_equal(fv_reference_render(s, &in, &d, a[0], a[1], NULL), FV_OK);
    d.threads = 2;
    assert_int_equal(fv_reference_render(s, &in, &d, b[0], b[1], NULL), FV_OK);
    size_t bytes = (size_t)SW * SH * 3 * sizeof(float);
    assert_memory_equal(a[0], b[0], bytes);
    assert_memory_equal(a[1], b[1], bytes);
    d.seed = 8;
    assert_int_equal(fv_reference_render(s, &in, &d, c, NULL, NULL), FV_OK);
    int differ = 0;
    for (size_t i = 0; i < (size_t)SW * SH * 3; i++) differ += c[i] != a[0][i];
    assert_true(differ > SW * SH / 2);
    /* model mode too */
    d = (fv_reference_desc){.mode = FV_REFERENCE_MODEL, .threads = 1, .eye_width = SW, .eye_height = SH};
    assert_int_equal(fv_reference_render(s, &in, &d, a[0], NULL, NULL), FV_OK);
    d.threads = 2;
    assert_int_equal(fv_reference_render(s, &in, &d, b[0], NULL, NULL), FV_OK);
    assert_memory_equal(a[0], b[0], bytes);
    for (int e = 0; e < 2; e++) {
        free(a[e]);
        free(b[e]);
    }
    free(c);
    fv_scene_destroy(&s);
}

/* ---- extremes ------------------------------------------------------------------------------------------------ */

static void render_every_mode_and_view_finite(const fv_scene *s, const fv_frame_input *in)
{
    enum { EW = 12, EH = 10 };
    float *img[2] = {rt_image(EW, EH), rt_image(EW, EH)};
    for (int mode = 0; mode < 2; mode++)
        for (int view = 0; view < FV_REFERENCE_VIEW_COUNT; view++) {
            fv_reference_desc d = {.mode = (fv_reference_mode)mode, .view = (fv_reference_view)view, .spp = 2,
                                   .bounces = 3, .eye_width = EW, .eye_height = EH, .aa = true};
            fv_reference_stats st;
            assert_int_equal(fv_reference_render(s, in, &d, img[0], img[1], &st), FV_OK);
            check_finite_nonnegative(img[0], (size_t)EW * EH * 3);
            check_finite_nonnegative(img[1], (size_t)EW * EH * 3);
            assert_int_equal(st.nonfinite_samples, 0);
        }
    free(img[0]);
    free(img[1]);
}

static void extreme_scenes_give_finite_images(void **state)
{
    (void)state;
    fv_test_log_capture_begin();
    /* empty */
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("empty", &s), FV_OK);
    fv_frame_input in = rt_views(&s->head, 12, 10);
    render_every_mode_and_view_finite(s, &in);
    fv_scene_destroy(&s);

    /* no lights, then a zero-intensity light: black */
    s = rt_plane_scene(fv_v3(1, 1, 1), 6.0);
    in = rt_views(&s->head, 12, 10);
    render_every_mode_and_view_finite(s, &in);
    fv_light l = rt_light(FV_LIGHT_SPOT, fv_v3(0, 1, 0), fv_v3(0, -1, 0), fv_v3(1, 1, 1), 0.0f);
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    float *img = rt_image(12, 10);
    fv_reference_desc d = {.eye_width = 12, .eye_height = 10};
    assert_int_equal(fv_reference_render(s, &in, &d, img, NULL, NULL), FV_OK);
    for (size_t i = 0; i < 12 * 10 * 3; i++) assert_true(img[i] == 0.0f);
    render_every_mode_and_view_finite(s, &in);

    /* a light inside a closed box on the plane, and one exactly on the plane: nothing escapes the box */
    s->lights[0].intensity = 5.0f;
    s->lights[0].type = FV_LIGHT_POINT;
    s->lights[0].position_m = fv_v3(0, 0.2f, 0);
    rt_add_box(s, fv_v3(0, 0.2f, 0), 0.1, 0);
    assert_int_equal(fv_reference_render(s, &in, &d, img, NULL, NULL), FV_OK);
    for (size_t i = 0; i < 12 * 10 * 3; i++) assert_true(img[i] == 0.0f);
    l.type = FV_LIGHT_POINT;
    l.intensity = 1.0f;
    l.position_m = fv_v3(0.5f, 0.0f, 0.3f);
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    render_every_mode_and_view_finite(s, &in);

    /* degenerate triangles (a point, a line), a NaN vertex, NaN normals and texcoords, NaN and huge light values,
     * a NaN ambient, an out-of-range material and an emissive degenerate triangle */
    uint32_t lamp = rt_material(s, fv_v3(1, 1, 1), fv_v3(3, 3, 3));
    fv_vec3 pts[9] = {{0.1f, 0.1f, 0.1f}, {0.1f, 0.1f, 0.1f}, {0.1f, 0.1f, 0.1f},
                      {0, 0.3f, 0},       {0.1f, 0.3f, 0},    {0.2f, 0.3f, 0},
                      {-0.3f, 0.2f, 0},   {0.3f, 0.2f, 0},    {0, 0.2f, 0.3f}};
    uint32_t mesh = rt_add_triangles(s, "degenerate", pts, 9, lamp);
    rt_add_triangles(s, "nan vertex", pts + 6, 3, 0);
    s->meshes[s->mesh_count - 1].positions[1].y = NAN;
    s->meshes[s->mesh_count - 1].normals[0] = fv_v3(NAN, NAN, NAN);
    s->meshes[mesh].normals[4] = fv_v3(0, 0, 0);
    s->meshes[mesh].material = 999;
    l.position_m = fv_v3(NAN, 0, 0);
    l.intensity = INFINITY;
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    l.type = FV_LIGHT_SPOT;
    l.position_m = fv_v3(0, 1e30f, 0);
    l.direction = fv_v3(0, 0, 0);
    l.intensity = 1e30f;
    l.inner_cone_rad = NAN;
    l.outer_cone_rad = -1;
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    s->ambient = fv_v3(NAN, 1, 1);
    fv_reference_stats st;
    /* a NaN light position and one at 1e30 m: refused before any work, naming them (Embree aborted on rays from
     * past 1.8e18 m) */
    assert_int_equal(fv_reference_render(s, &in, &d, img, NULL, &st), FV_ERR_INVALID_ARG);
    fv_assert_log_contains("position (m): nan is beyond the +-1e+06 m bound");
    fv_assert_log_contains("position (m): 1e+30 is beyond the +-1e+06 m bound");
    fv_assert_log_contains("not rendered: positions beyond the bound");
    s->lights[s->light_count - 2].position_m = fv_v3(0, 0.5f, 0); /* its intensity stays infinite */
    s->lights[s->light_count - 1].position_m = fv_v3(0, (float)FV_SCENE_MAX_COORD_M, 0); /* at the bound */
    assert_int_equal(fv_reference_render(s, &in, &d, img, NULL, &st), FV_OK);
    assert_true(st.skipped_triangles >= 3);
    render_every_mode_and_view_finite(s, &in);
    /* an emitter that really emits next to the NaN: path mode samples it */
    rt_add_square(s, "lamp", fv_v3(0, 0.8f, 0), 0.2, lamp);
    render_every_mode_and_view_finite(s, &in);
    /* a NaN head, or one past the bound: refused (the scene's head and the eyes made from it) */
    fv_head head = s->head;
    float far[2] = {NAN, 1e20f};
    for (int k = 0; k < 2; k++) {
        s->head.position_m = fv_v3(0, 0, far[k]);
        fv_frame_input bad = rt_views(&s->head, 12, 10);
        assert_int_equal(fv_reference_render(s, &bad, &d, img, NULL, NULL), FV_ERR_INVALID_ARG);
        fv_assert_log_contains("head: position (m)");
        s->head = head;
        if (k == 0) continue; /* the views of a NaN head fall back to identity */
        /* the eyes alone (the scene's head sane) */
        fv_test_log_capture_end();
        fv_test_log_capture_begin();
        assert_int_equal(fv_reference_render(s, &bad, &d, img, NULL, NULL), FV_ERR_INVALID_ARG);
        fv_assert_log_contains("eye 0 at (-0.0315, 0, 1e+20) m is not finite or beyond the +-1e+06 m bound");
    }
    free(img);
    fv_scene_destroy(&s);
    fv_test_log_capture_end();
}

static void broken_desc_and_null_arguments_are_rejected(void **state)
{
    (void)state;
    fv_test_log_capture_begin();
    fv_scene *s = rt_plane_scene(fv_v3(1, 1, 1), 1.0);
    fv_frame_input in = rt_views(&s->head, 4, 4);
    float img[4 * 4 * 3];
    fv_reference_desc d = {.mode = (fv_reference_mode)7, .view = (fv_reference_view)42, .eye_width = 4,
                           .eye_height = 4, .spp = FV_REFERENCE_MAX_SPP + 1};
    assert_int_equal(fv_reference_render(s, &in, &d, img, NULL, NULL), FV_ERR_INVALID_ARG);
    fv_assert_log_contains("desc.mode 7");
    fv_assert_log_contains("desc.view 42");
    fv_assert_log_contains("desc.spp");
    d = (fv_reference_desc){.eye_width = 4, .eye_height = 4};
    assert_int_equal(fv_reference_render(NULL, &in, &d, img, NULL, NULL), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_reference_render(s, NULL, &d, img, NULL, NULL), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_reference_render(s, &in, &d, NULL, NULL, NULL), FV_OK); /* nothing asked */
    fv_reference_mode m;
    fv_reference_view v;
    assert_true(fv_reference_mode_parse("path", &m) && m == FV_REFERENCE_PATH);
    assert_true(fv_reference_view_parse("depth", &v) && v == FV_REFERENCE_VIEW_DEPTH);
    assert_false(fv_reference_view_parse("nope", &v));
    assert_string_equal(fv_reference_view_name(FV_REFERENCE_VIEW_SHADOW), "shadow");
    fv_reference_desc def = fv_reference_desc_defaults(NULL);
    assert_int_equal(def.spp, 1);
    assert_int_equal(def.eye_width, 720);
    assert_true(def.threads >= 1);
    fv_scene_destroy(&s);
    fv_test_log_capture_end();
}

/* More lights than FV_SCENE_LIGHTS_WARN: the reference says what a frame costs before it starts (one line). */
static void many_lights_are_announced_before_the_render(void **state)
{
    (void)state;
    fv_scene *s = rt_plane_scene(fv_v3(1, 1, 1), 1.0);
    fv_light l;
    memset(&l, 0, sizeof l);
    l.type = FV_LIGHT_POINT;
    l.color = fv_v3(1, 1, 1);
    l.intensity = 1e-3f;
    l.position_m = fv_v3(0, 0.5f, 0);
    while (s->light_count <= FV_SCENE_LIGHTS_WARN) assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    fv_frame_input in = rt_views(&s->head, 4, 4);
    float img[4 * 4 * 3];
    fv_reference_desc d = {.eye_width = 4, .eye_height = 4, .threads = 1};
    fv_test_log_capture_begin();
    assert_int_equal(fv_reference_render(s, &in, &d, img, NULL, NULL), FV_OK);
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_WARN), 1);
    fv_assert_log_contains("257 lights, and the reference's model mode (a shadow ray per light) sums every light at "
                           "every pixel: about 8.2e+03 light evaluations a frame at 4x4 per eye");
    fv_test_log_capture_end();
    fv_scene_destroy(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(model_spot_lit_plane_matches_the_closed_form_to_1e9),
        cmocka_unit_test(shadow_ray_blocker_gives_zero_in_its_shadow_and_the_closed_form_elsewhere),
        cmocka_unit_test(depth_and_normal_views_match_the_projection_and_the_facing_normal),
        cmocka_unit_test(albedo_is_base_colour_times_the_srgb_decoded_bilinear_texture),
        cmocka_unit_test(path_direct_only_equals_model_without_emission),
        cmocka_unit_test(path_mode_sums_the_furnace_series),
        cmocka_unit_test(same_seed_gives_identical_images_on_1_and_2_threads_and_another_seed_differs),
        cmocka_unit_test(extreme_scenes_give_finite_images),
        cmocka_unit_test(broken_desc_and_null_arguments_are_rejected),
        cmocka_unit_test(many_lights_are_announced_before_the_render),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
