/* @brief GPU tests of the debug-view pass and the per-pass counters on lavapipe (or any Vulkan device) with the
 * validation layer forced on: the frame's per-eye gaze and pupil read back from the gaze view against a CPU
 * reference computed in double from the frame input (peak where the gaze ray pierces the image, falloff
 * exp(-a^2 / (2 s^2)), green = pupil mm / 10, blue = valid), the fallbacks for missing or broken gaze, the normal
 * view of the G-buffer, the plan's "debug" entry, and the counters each pass reports. Without a Vulkan device the
 * tests skip with a message, except under CI=true where that is a failure. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_renderer.h"
#include "fv_scene.h"
#include "fv_test.h"
#include "gpu_test.h"

/* Not square, so that a swapped x/y would show. */
#define W 96
#define H 80
#define NPIX ((size_t)W * H)
#define DEG (FV_PI / 180.0)
#define FALLOFF_TOL 1e-4 /* red vs the double-precision formula */
#define GREEN_TOL 1e-6   /* pupil mm / 10 */
#define NORMAL_TOL 1e-3  /* G-buffer normal * 0.5 + 0.5 */
#define SQUARE_HALF_M 0.5

FV_GPU_TEST_GROUP(W, H)
static uint64_t g_frame_id = 1; /* rising over the whole run: frame ids must be distinct and rising */

#define NEED_GPU() FV_NEED_GPU(g_r)

/* ---- scene and frame ------------------------------------------------------------------------------------------ */

/* One reddish square (normal +y) at the origin lit by a point light, seen from 1 m up and 1 m back, looking 45 deg
 * down at its centre. */
static fv_scene *square_scene(void)
{
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("debug-square", &s), FV_OK);
    fv_material mat = fv_material_default();
    mat.base_color = fv_v3(0.9f, 0.2f, 0.1f);
    uint32_t mi;
    assert_int_equal(fv_scene_add_material(s, &mat, &mi), FV_OK);
    fv_mesh m = fv_gpu_test_square_mesh("square", SQUARE_HALF_M, mi);
    uint32_t mesh;
    assert_int_equal(fv_scene_add_mesh(s, &m, &mesh), FV_OK);
    fv_node node = fv_node_default();
    node.mesh = (int32_t)mesh;
    assert_int_equal(fv_scene_add_node(s, &node, NULL), FV_OK);
    fv_light l;
    memset(&l, 0, sizeof l);
    l.type = FV_LIGHT_POINT;
    l.position_m = fv_v3(0.2f, 1.5f, 0.3f);
    l.color = fv_v3(1, 1, 1);
    l.intensity = 4.0f;
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    s->head.position_m = fv_v3(0.0f, 1.0f, 1.0f);
    s->head.orientation = fv_quat_axis_angle(fv_v3(1, 0, 0), (float)(-FV_PI / 4));
    return s;
}

static void frame_for(const fv_scene *s, fv_debug_view view, fv_frame_input *out)
{
    fv_frame_input_from_head(&s->head, 0.1f, 10.0f, W, H, g_frame_id++, 0.0, out);
    out->quality.debug_view = view;
    out->quality.fovea.enabled = false; /* full resolution: the views are compared pixel by pixel */
}

static void draw(const fv_frame_input *in) { assert_int_equal(fv_renderer_draw(g_r, in), FV_OK); }

static float *read_eye(int eye)
{
    float *img = malloc(NPIX * 4 * sizeof *img);
    assert_non_null(img);
    assert_int_equal(fv_renderer_read_linear(g_r, eye, img, NPIX * 4), FV_OK);
    return img;
}

/* ---- the CPU reference (double) ------------------------------------------------------------------------------- */

/* Unit direction in eye view space (-z forward): yaw_deg to the right, then pitch_deg up. */
static fv_vec3 dir_deg(double yaw_deg, double pitch_deg)
{
    double a = yaw_deg * DEG, b = pitch_deg * DEG;
    return fv_v3((float)(sin(a) * cos(b)), (float)sin(b), (float)(-cos(a) * cos(b)));
}

/* The view-space ray through (x, y) in pixel-centre coordinates (pixel (x, y) has its centre at (x, y); debug.comp
 * pixel_ray: (mix(left, right, u), mix(up, down, v), -1)), unit. */
static void pixel_ray(const fv_eye_view *v, double x, double y, double out[3])
{
    double u = (x + 0.5) / W, t = (y + 0.5) / H;
    double r[3] = {v->tan_left + u * ((double)v->tan_right - v->tan_left),
                   v->tan_up + t * ((double)v->tan_down - v->tan_up), -1.0};
    double len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    for (int k = 0; k < 3; k++) out[k] = r[k] / len;
}

/* Where a view-space direction pierces the image, in pixel-centre coordinates (pixel (x, y) has its centre at
 * (x, y)): the inverse of pixel_ray. */
static void pierce(const fv_eye_view *v, fv_vec3 d, double *out_x, double *out_y)
{
    double tx = (double)d.x / -(double)d.z, ty = (double)d.y / -(double)d.z;
    double u = (tx - v->tan_left) / ((double)v->tan_right - v->tan_left);
    double t = (ty - v->tan_up) / ((double)v->tan_down - v->tan_up);
    *out_x = u * W - 0.5;
    *out_y = t * H - 0.5;
}

/* red = exp(-a^2 / (2 s^2)), a the angle between the pixel's ray and the gaze ray, s = max(1 deg, uncertainty). */
static double ref_red(const fv_eye_view *v, int x, int y, fv_vec3 gaze, double uncertainty_rad)
{
    double r[3], g[3] = {gaze.x, gaze.y, gaze.z};
    pixel_ray(v, x, y, r);
    double gl = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    double c[3] = {r[1] * g[2] - r[2] * g[1], r[2] * g[0] - r[0] * g[2], r[0] * g[1] - r[1] * g[0]};
    double a = atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / gl, (r[0] * g[0] + r[1] * g[1] + r[2] * g[2]) / gl);
    double s = fmax(1.0 * DEG, uncertainty_rad);
    return exp(-(a * a) / (2.0 * s * s));
}

static void peak(const float *img, int *out_x, int *out_y)
{
    float best = -1.0f;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            if (img[((size_t)y * W + x) * 4] > best) {
                best = img[((size_t)y * W + x) * 4];
                *out_x = x;
                *out_y = y;
            }
}

/* The peak of red is within 1 px of where `d` pierces the image. */
static void check_peak(const float *img, const fv_eye_view *v, fv_vec3 d, const char *what, int eye)
{
    int px = -1, py = -1;
    peak(img, &px, &py);
    double ex, ey;
    pierce(v, d, &ex, &ey);
    print_message("%s eye %d: red peak at (%d, %d), gaze pierces (%.2f, %.2f)\n", what, eye, px, py, ex, ey);
    if (!(fabs(px - ex) <= 1.0 && fabs(py - ey) <= 1.0))
        fail_msg("%s eye %d: red peak at (%d, %d), expected within 1 px of (%.2f, %.2f)", what, eye, px, py, ex, ey);
}

/* Every pixel finite; green and blue constant. */
static void check_green_blue(const float *img, double green, double blue, const char *what, int eye)
{
    for (size_t p = 0; p < NPIX; p++) {
        for (int c = 0; c < 4; c++)
            if (!isfinite(img[p * 4 + c])) fail_msg("%s eye %d pixel %zu ch %d not finite", what, eye, p, c);
        if (fabs(img[p * 4 + 1] - green) > GREEN_TOL)
            fail_msg("%s eye %d pixel %zu: green %.8f, expected %.8f", what, eye, p, img[p * 4 + 1], green);
        if (img[p * 4 + 2] != (float)blue)
            fail_msg("%s eye %d pixel %zu: blue %g, expected %g", what, eye, p, img[p * 4 + 2], blue);
    }
}

/* The falloff at every pixel against the double formula: the worst error (the caller asserts on it, after the
 * other checks). */
static double check_falloff(const float *img, const fv_eye_view *v, fv_vec3 d, double uncertainty_rad,
                            const char *what, int eye)
{
    double worst = 0;
    int wx = 0, wy = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double e = fabs(img[((size_t)y * W + x) * 4] - ref_red(v, x, y, d, uncertainty_rad));
            if (e > worst) {
                worst = e;
                wx = x;
                wy = y;
            }
        }
    print_message("%s eye %d (s = %.2f deg): worst red error %.2e at (%d, %d): gpu %.7f cpu %.7f\n", what, eye,
                  fmax(1.0, uncertainty_rad / DEG), worst, wx, wy, img[((size_t)wy * W + wx) * 4],
                  ref_red(v, wx, wy, d, uncertainty_rad));
    if (worst > FALLOFF_TOL)
        print_error("%s eye %d: red at (%d, %d) is %.7f, formula %.7f (error %.2e > %.0e)\n", what, eye, wx, wy,
                    img[((size_t)wy * W + wx) * 4], ref_red(v, wx, wy, d, uncertainty_rad), worst, FALLOFF_TOL);
    return worst;
}

/* ---- (1) the frame's gaze reaches the GPU --------------------------------------------------------------------- */

typedef struct gaze_case {
    const char *name;
    fv_vec3 dir[2];
    double uncertainty_deg[2];
    float pupil_mm;
} gaze_case;

static void frame_gaze_and_pupil_reach_the_gpu_per_eye(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = square_scene();
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    /* A: eye 0 10 deg right, 5 deg up; eye 1 8 deg left, 3 deg down. B: elsewhere, eye 1 not unit length (the
     * renderer normalises), and an uncertainty under the 1 deg floor. */
    fv_vec3 b1 = dir_deg(15.0, 12.0);
    const gaze_case cases[2] = {
        {"gaze A", {dir_deg(10.0, 5.0), dir_deg(-8.0, -3.0)}, {0.0, 5.0}, 4.2f},
        {"gaze B", {dir_deg(-20.0, -10.0), fv_v3(3 * b1.x, 3 * b1.y, 3 * b1.z)}, {5.0, 0.5}, 6.5f},
    };
    int peaks[2][2][2];
    double worst = 0;
    for (int k = 0; k < 2; k++) {
        const gaze_case *c = &cases[k];
        fv_frame_input in;
        frame_for(s, FV_DEBUG_VIEW_GAZE, &in);
        in.pupil_mm = c->pupil_mm;
        for (int e = 0; e < 2; e++)
            in.gaze[e] = (fv_eye_gaze){.valid = true, .dir_eye = c->dir[e], .uncertainty_deg = (float)c->uncertainty_deg[e]};
        draw(&in);
        const fv_plan_entry *dbg = fv_frame_plan_find(fv_renderer_plan(g_r), "debug");
        assert_non_null(dbg);
        assert_true(dbg->enabled);
        assert_non_null(strstr(dbg->reason, "gaze"));
        for (int e = 0; e < 2; e++) {
            float *img = read_eye(e);
            check_peak(img, &in.eye[e], c->dir[e], c->name, e);
            peak(img, &peaks[k][e][0], &peaks[k][e][1]);
            check_green_blue(img, (double)c->pupil_mm / 10.0, 1.0, c->name, e);
            double w = check_falloff(img, &in.eye[e], c->dir[e], c->uncertainty_deg[e] * DEG, c->name, e);
            if (w > worst) worst = w;
            free(img);
        }
    }
    /* the peaks moved with the gaze (far more than a pixel) */
    for (int e = 0; e < 2; e++)
        assert_true(abs(peaks[0][e][0] - peaks[1][e][0]) + abs(peaks[0][e][1] - peaks[1][e][1]) > 5);
    print_message("worst red error over both frames and eyes: %.2e\n", worst);
    assert_true(worst <= FALLOFF_TOL);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

/* ---- (2) no gaze or a broken gaze -------------------------------------------------------------------------------- */

typedef struct broken_case {
    const char *name;
    fv_eye_gaze gaze;
    float pupil_mm;
    bool valid;     /* expected: blue */
    double green;   /* expected: pupil / 10 as the renderer keeps it */
} broken_case;

static void missing_or_broken_gaze_falls_back_to_straight_ahead_never_nan(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = square_scene();
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    fv_vec3 ok = dir_deg(12.0, -6.0);
    const broken_case cases[] = {
        {"no gaze (valid = false)", {.valid = false, .dir_eye = ok, .uncertainty_deg = 1.0f}, 4.0f, false, 0.4},
        {"NaN direction", {.valid = true, .dir_eye = {NAN, 0.0f, -1.0f}, .uncertainty_deg = 1.0f}, 4.0f, false, 0.4},
        {"infinite direction", {.valid = true, .dir_eye = {INFINITY, 0.0f, -1.0f}, .uncertainty_deg = 1.0f}, 4.0f,
         false, 0.4},
        {"zero direction", {.valid = true, .dir_eye = {0.0f, 0.0f, 0.0f}, .uncertainty_deg = 1.0f}, 4.0f, false, 0.4},
        {"uncertainty NaN", {.valid = true, .dir_eye = ok, .uncertainty_deg = NAN}, 4.0f, true, 0.4},
        {"uncertainty 1e30", {.valid = true, .dir_eye = ok, .uncertainty_deg = 1e30f}, 4.0f, true, 0.4},
        {"uncertainty -inf", {.valid = true, .dir_eye = ok, .uncertainty_deg = -INFINITY}, 4.0f, true, 0.4},
        {"pupil NaN", {.valid = true, .dir_eye = ok, .uncertainty_deg = 1.0f}, NAN, true, 0.0},
        {"pupil 0", {.valid = true, .dir_eye = ok, .uncertainty_deg = 1.0f}, 0.0f, true, 0.0},
        {"pupil -1", {.valid = true, .dir_eye = ok, .uncertainty_deg = 1.0f}, -1.0f, true, 0.0},
        {"pupil 1e9", {.valid = true, .dir_eye = ok, .uncertainty_deg = 1.0f}, 1e9f, true, 0.0 /* not a pupil */},
        {"pupil 21 mm", {.valid = true, .dir_eye = ok, .uncertainty_deg = 1.0f}, 21.0f, true, 0.0},
        {"huge direction", {.valid = true, .dir_eye = {ok.x * 1e30f, ok.y * 1e30f, ok.z * 1e30f}, .uncertainty_deg = 1.0f},
         4.0f, true, 0.4},
        {"tiny direction", {.valid = true, .dir_eye = {ok.x * 1e-30f, ok.y * 1e-30f, ok.z * 1e-30f},
                            .uncertainty_deg = 1.0f}, 4.0f, true, 0.4},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const broken_case *c = &cases[k];
        fv_frame_input in;
        frame_for(s, FV_DEBUG_VIEW_GAZE, &in);
        in.pupil_mm = c->pupil_mm;
        in.gaze[0] = in.gaze[1] = c->gaze;
        draw(&in);
        for (int e = 0; e < 2; e++) {
            float *img = read_eye(e);
            double green = c->green;
            if (green < 0) { /* an absurd pupil: whatever it is kept as, it is finite and not negative */
                green = img[1];
                print_message("%s: green %.6g (pupil kept as %.6g mm)\n", c->name, green, green * 10.0);
                assert_true(isfinite(green) && green >= 0.0);
            }
            check_green_blue(img, green, c->valid ? 1.0 : 0.0, c->name, e);
            check_peak(img, &in.eye[e], c->valid ? ok : fv_v3(0, 0, -1), c->name, e);
            free(img);
        }
        assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    }
    fv_scene_destroy(&s);
}

/* ---- (3) the normal view shows the G-buffer normal ------------------------------------------------------------ */

/* Where the world ray of pixel (x + fx, y + fy) meets the plane y = 0: 1 inside the square, 0 outside or missing. */
static int on_square(const fv_eye_view *v, double x, double y)
{
    double r[3];
    pixel_ray(v, x, y, r);
    /* eye basis in world from the view matrix rows (m[col][row]) */
    double right[3] = {v->view.m[0][0], v->view.m[1][0], v->view.m[2][0]};
    double up[3] = {v->view.m[0][1], v->view.m[1][1], v->view.m[2][1]};
    double back[3] = {v->view.m[0][2], v->view.m[1][2], v->view.m[2][2]};
    double o[3] = {v->pos_world.x, v->pos_world.y, v->pos_world.z}, d[3];
    /* r is (x, y, z) in view space with -z forward: world = x right + y up + z back */
    for (int k = 0; k < 3; k++) d[k] = r[0] * right[k] + r[1] * up[k] + r[2] * back[k];
    if (!(d[1] < 0)) return 0;
    double t = -o[1] / d[1];
    double px = o[0] + t * d[0], pz = o[2] + t * d[2];
    return fabs(px) < SQUARE_HALF_M && fabs(pz) < SQUARE_HALF_M;
}

/* 1: the whole pixel is on the square, 0: the whole pixel is off it, -1: its edge crosses the pixel. */
static int classify(const fv_eye_view *v, int x, int y)
{
    int n = 0;
    for (int k = 0; k < 9; k++) n += on_square(v, x + (k % 3 - 1) * 0.5, y + (k / 3 - 1) * 0.5);
    return n == 9 ? 1 : n == 0 ? 0 : -1;
}

static void normal_debug_view_shows_the_gbuffer_normal_then_turns_off(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = square_scene();
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    fv_frame_input in;
    frame_for(s, FV_DEBUG_VIEW_NORMAL, &in);
    draw(&in);
    const fv_plan_entry *dbg = fv_frame_plan_find(fv_renderer_plan(g_r), "debug");
    assert_non_null(dbg);
    assert_true(dbg->enabled);
    assert_non_null(strstr(dbg->reason, "normal"));
    float *normal[2];
    int on = 0, off = 0;
    double worst = 0;
    for (int e = 0; e < 2; e++) {
        normal[e] = read_eye(e);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                const float *p = &normal[e][((size_t)y * W + x) * 4];
                int where = classify(&in.eye[e], x, y);
                if (where == 1) {
                    const double want[3] = {0.5, 1.0, 0.5};
                    for (int c = 0; c < 3; c++) {
                        double err = fabs(p[c] - want[c]);
                        if (err > worst) worst = err;
                        if (!(err <= NORMAL_TOL))
                            fail_msg("eye %d pixel (%d, %d) on the square: (%.5f, %.5f, %.5f), expected (0.5, 1, 0.5)",
                                     e, x, y, p[0], p[1], p[2]);
                    }
                    on++;
                } else if (where == 0) {
                    if (p[0] != 0.0f || p[1] != 0.0f || p[2] != 0.0f)
                        fail_msg("eye %d pixel (%d, %d) off the square: (%g, %g, %g), expected 0", e, x, y, p[0], p[1],
                                 p[2]);
                    off++;
                }
            }
    }
    print_message("normal view: %d pixels on the square (worst error %.2e), %d off it\n", on, worst, off);
    assert_true(on > (int)NPIX / 10);
    assert_true(off > (int)NPIX / 10);

    /* the next frame without the debug view is shaded again */
    frame_for(s, FV_DEBUG_VIEW_NONE, &in);
    draw(&in);
    dbg = fv_frame_plan_find(fv_renderer_plan(g_r), "debug");
    assert_non_null(dbg);
    assert_false(dbg->enabled);
    assert_non_null(strstr(dbg->reason, "debug view"));
    int differ = 0;
    on = 0;
    for (int e = 0; e < 2; e++) {
        float *shaded = read_eye(e);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                if (classify(&in.eye[e], x, y) != 1) continue;
                const float *a = &shaded[((size_t)y * W + x) * 4], *b = &normal[e][((size_t)y * W + x) * 4];
                double d = fmax(fabs(a[0] - b[0]), fmax(fabs(a[1] - b[1]), fabs(a[2] - b[2])));
                differ += d > 0.05;
                on++;
                assert_true(isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]));
            }
        free(shaded);
        free(normal[e]);
    }
    print_message("shaded again: %d of %d square pixels differ from the normal view by > 0.05\n", differ, on);
    assert_int_equal(differ, on);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

/* ---- (4) per-pass counters ----------------------------------------------------------------------------------- */

static void check_passes(const fv_render_stats *st, const char *const *names, uint32_t count)
{
    if (st->pass_count != count) {
        for (uint32_t i = 0; i < st->pass_count; i++) print_error("pass %u: %s\n", i, st->pass_name[i]);
        fail_msg("%u passes ran, expected %u", st->pass_count, count);
    }
    for (uint32_t i = 0; i < count; i++) assert_string_equal(st->pass_name[i], names[i]);
}

static const fv_pass_counters *counters_of(const fv_render_stats *st, const char *pass)
{
    for (uint32_t i = 0; i < st->pass_count; i++)
        if (strcmp(st->pass_name[i], pass) == 0) return &st->pass_counters[i];
    fail_msg("no pass %s in the stats", pass);
    return NULL;
}

static void passes_report_what_they_did_per_frame(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("cornell", &s), FV_OK);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    uint64_t draws = 0, triangles = 0;
    for (uint32_t i = 0; i < s->node_count; i++) {
        const fv_node *n = &s->nodes[i];
        if (n->mesh < 0 || (uint32_t)n->mesh >= s->mesh_count) continue;
        draws++;
        triangles += s->meshes[n->mesh].index_count / 3;
    }
    assert_true(draws > 1);
    /* Without multiview (llvmpipe: see fv_vk_multiview_trusted) the G-buffer is one render pass per eye, each issuing
     * every draw: the counter counts draw calls. */
    const fv_plan_entry *gbp = fv_frame_plan_find(fv_renderer_plan(g_r), "gbuffer");
    assert_non_null(gbp);
    uint64_t passes_per_frame = strstr(gbp->reason, "one multiview pass") ? 1 : 2;
    print_message("gbuffer plan: %s\n", gbp->reason);
    const fv_debug_view views[2] = {FV_DEBUG_VIEW_NONE, FV_DEBUG_VIEW_GAZE};
    for (int k = 0; k < 2; k++) {
        fv_frame_input in;
        assert_int_equal(fv_renderer_frame_input(g_r, NULL, g_frame_id++, 0.0, &in), FV_OK);
        in.quality.debug_view = views[k];
        /* The full-resolution pass list (foveation, on by default, adds "fovea" and "reconstruct"): its meaning is
         * every pass's counters of a whole frame. test_render_fovea checks the foveated list. */
        in.quality.fovea.enabled = false;
        in.quality.gi.enabled = false; /* and no GI pass (on by default): tests/gi checks it */
        draw(&in);
        assert_int_equal(fv_renderer_finish(g_r), FV_OK);
        fv_render_stats st;
        assert_int_equal(fv_renderer_stats(g_r, &st), FV_OK);
        assert_int_equal(st.frame_id, in.frame_id);
        /* cornell has a spot light: its shadow map is drawn before shading (one map, every draw once). */
        const fv_pass_counters *shadow = NULL;
        if (k == 0) {
            const char *const names[] = {"gbuffer", "shadow", "shade", "present"};
            check_passes(&st, names, 4);
        } else {
            const char *const names[] = {"gbuffer", "shadow", "shade", "debug", "present"};
            check_passes(&st, names, 5);
            const fv_pass_counters *d = counters_of(&st, "debug");
            assert_int_equal(d->dispatches, 1);
            assert_int_equal(d->draws, 0);
            assert_int_equal(d->pixels_shaded, 0);
        }
        const fv_pass_counters *gb = counters_of(&st, "gbuffer"), *sh = counters_of(&st, "shade"),
                               *pr = counters_of(&st, "present");
        print_message("%s: gbuffer %llu draws %llu triangles; shade %llu pixels %llu dispatches; present %llu "
                      "dispatches (scene: %llu draws, %llu triangles)\n",
                      k ? "debug view gaze" : "no debug view", (unsigned long long)gb->draws,
                      (unsigned long long)gb->triangles, (unsigned long long)sh->pixels_shaded,
                      (unsigned long long)sh->dispatches, (unsigned long long)pr->dispatches,
                      (unsigned long long)draws, (unsigned long long)triangles);
        shadow = counters_of(&st, "shadow");
        assert_int_equal(shadow->draws, draws);
        assert_int_equal(shadow->triangles, triangles);
        assert_int_equal(gb->draws, draws * passes_per_frame);
        assert_true(gb->triangles > 0);
        assert_int_equal(gb->triangles, 2 * triangles); /* both eyes */
        assert_int_equal(gb->pixels_shaded, 0);
        assert_int_equal(sh->pixels_shaded, 2u * W * H);
        assert_int_equal(sh->draws, 0);
        assert_int_equal(pr->dispatches, 1);
        assert_int_equal(pr->pixels_shaded, 0);
        assert_int_equal(st.pixels_shaded, 2u * W * H);
    }
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(frame_gaze_and_pupil_reach_the_gpu_per_eye),
        cmocka_unit_test(missing_or_broken_gaze_falls_back_to_straight_ahead_never_nan),
        cmocka_unit_test(normal_debug_view_shows_the_gbuffer_normal_then_turns_off),
        cmocka_unit_test(passes_report_what_they_did_per_frame),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
