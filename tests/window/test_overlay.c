/* @brief render/overlay on the GPU (headless, validation on): the gaze dot lands on the pixel the predicted gaze
 * points at in each eye, the uncertainty ring at its angular radius, the foveal boundary exactly on the edge of
 * foveation's full-rate region (read back from the fovea pass), nothing for an invalid gaze, and any gaze or
 * uncertainty (NaN, zero, huge) draws without a validation message. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_test.h"
#include "gpu_test.h"

#define W 192
#define H 192

FV_GPU_TEST_GROUP(W, H)

static fv_scene *g_scene;

static void load(void)
{
    if (!g_scene) {
        assert_int_equal(fv_scene_load("cornell", &g_scene), FV_OK);
        assert_int_equal(fv_renderer_load_scene(g_r, g_scene), FV_OK);
    }
}

/* Gaze of both eyes towards pixel (px, py) of each eye's image (pixel centres), uncertainty u_deg. */
static void aim(fv_frame_input *in, double px, double py, float u_deg)
{
    for (int e = 0; e < 2; e++) {
        const fv_eye_view *v = &in->eye[e];
        double x = v->tan_left + (v->tan_right - v->tan_left) * (px + 0.5) / W;
        double y = v->tan_up + (v->tan_down - v->tan_up) * (py + 0.5) / H;
        in->gaze[e] = (fv_eye_gaze){.valid = true, .dir_eye = fv_v3_normalize_or(fv_v3((float)x, (float)y, -1.0f),
                                                                                  fv_v3(0, 0, -1)),
                                    .uncertainty_deg = u_deg};
    }
}

static uint8_t *draw(fv_frame_input *in, int eye)
{
    assert_int_equal(fv_renderer_draw(g_r, in), FV_OK);
    uint8_t *px = malloc((size_t)W * H * 4);
    assert_non_null(px);
    assert_int_equal(fv_renderer_read_rgba8(g_r, false, eye, px, (size_t)W * H * 4), FV_OK);
    return px;
}

typedef bool (*pick_fn)(const uint8_t *p);
static bool yellow(const uint8_t *p) { return p[0] > 200 && p[1] > 170 && p[2] < 90; }
static bool cyan(const uint8_t *p) { return p[0] < 70 && p[1] > 180 && p[2] > 200; }
static bool magenta(const uint8_t *p) { return p[0] > 200 && p[1] < 90 && p[2] > 180; }

static int centroid(const uint8_t *img, pick_fn pick, double *cx, double *cy)
{
    double sx = 0, sy = 0;
    int n = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            if (pick(img + ((size_t)y * W + x) * 4)) {
                sx += x;
                sy += y;
                n++;
            }
    if (n) {
        *cx = sx / n;
        *cy = sy / n;
    }
    return n;
}

static fv_frame_input input(uint64_t id, bool fovea)
{
    fv_frame_input in;
    assert_int_equal(fv_renderer_frame_input(g_r, NULL, id, 0.0, &in), FV_OK);
    in.quality.overlay = true;
    in.quality.fovea.enabled = fovea;
    return in;
}

static void the_dot_and_ring_land_where_the_gaze_points_in_each_eye(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    load();
    const double pts[2][2] = {{50, 120}, {140, 60}};
    for (int k = 0; k < 2; k++)
        for (int eye = 0; eye < 2; eye++) {
            fv_frame_input in = input(1 + (uint64_t)k, false);
            aim(&in, pts[k][0], pts[k][1], 6.0f);
            uint8_t *img = draw(&in, eye);
            double x = 0, y = 0;
            assert_true(centroid(img, yellow, &x, &y) >= 5);
            if (fabs(x - pts[k][0]) > 0.75 || fabs(y - pts[k][1]) > 0.75)
                fail_msg("eye %d: dot at (%.2f, %.2f), gaze at (%.0f, %.0f)", eye, x, y, pts[k][0], pts[k][1]);
            /* the ring: every cyan pixel about 6 degrees from the gaze (pixels of ~0.48 deg near the centre) */
            const fv_eye_view *v = &in.eye[eye];
            fv_vec3 g = in.gaze[eye].dir_eye;
            int n = 0;
            for (int py = 0; py < H; py++)
                for (int px = 0; px < W; px++) {
                    if (!cyan(img + ((size_t)py * W + px) * 4)) continue;
                    n++;
                    double rx = v->tan_left + (v->tan_right - v->tan_left) * (px + 0.5) / W;
                    double ry = v->tan_up + (v->tan_down - v->tan_up) * (py + 0.5) / H;
                    double rn = sqrt(rx * rx + ry * ry + 1.0);
                    double e = acos(fmin(1.0, (rx * g.x + ry * g.y - g.z) / rn)) * 180.0 / FV_PI;
                    if (fabs(e - 6.0) > 0.6) fail_msg("ring pixel (%d, %d) is %.2f deg from the gaze", px, py, e);
                }
            assert_true(n > 40);
            free(img);
        }
}

static void the_foveal_boundary_is_the_edge_of_the_full_rate_region(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    load();
    fv_frame_input in = input(10, true);
    aim(&in, 96, 96, 0.0f);
    uint8_t *img = draw(&in, 0);
    float *prob = malloc((size_t)W * H * sizeof *prob);
    assert_non_null(prob);
    assert_int_equal(fv_renderer_read_image(g_r, "fovea prob", 0, prob, (size_t)W * H * sizeof *prob, 4), FV_OK);
    int n = 0;
    for (int y = 1; y < H - 1; y++)
        for (int x = 1; x < W - 1; x++) {
            if (!magenta(img + ((size_t)y * W + x) * 4)) continue;
            n++;
            const float *p = prob + (size_t)y * W + x;
            bool inside = p[0] >= 0.999f;
            bool edge = p[1] < 0.999f || p[-1] < 0.999f || p[W] < 0.999f || p[-W] < 0.999f;
            if (!inside || !edge) fail_msg("boundary pixel (%d, %d): p %.4f, not on the full-rate edge", x, y, p[0]);
        }
    assert_true(n > 20);
    free(prob);
    free(img);
    /* without foveation: no boundary */
    fv_frame_input off = input(11, false);
    aim(&off, 96, 96, 0.0f);
    img = draw(&off, 0);
    double x, y;
    assert_int_equal(centroid(img, magenta, &x, &y), 0);
    free(img);
}

static void no_gaze_no_dot_and_any_gaze_draws_cleanly(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    load();
    fv_frame_input in = input(20, false);
    aim(&in, 50, 50, 3.0f);
    in.gaze[0].valid = in.gaze[1].valid = false;
    uint8_t *img = draw(&in, 0);
    double x, y;
    assert_int_equal(centroid(img, yellow, &x, &y), 0);
    free(img);
    const fv_vec3 dirs[] = {fv_v3(NAN, 0, -1), fv_v3(0, 0, 0), fv_v3(INFINITY, 0, -1), fv_v3(1e30f, 1e30f, -1e30f),
                            fv_v3(1e-30f, 0, -1e-30f), fv_v3(0, 0, 1)};
    const float us[] = {NAN, INFINITY, -1.0f, 1e9f, 0.0f, 180.0f};
    for (size_t i = 0; i < sizeof dirs / sizeof dirs[0]; i++) {
        fv_frame_input q = input(30 + i, i % 2 == 0);
        for (int e = 0; e < 2; e++) q.gaze[e] = (fv_eye_gaze){.valid = true, .dir_eye = dirs[i], .uncertainty_deg = us[i]};
        img = draw(&q, 1);
        int dots = centroid(img, yellow, &x, &y);
        if (i == 0 || i == 1 || i == 2) assert_int_equal(dots, 0); /* no usable direction: no dot */
        free(img);
    }
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

static int teardown_all(void **state)
{
    fv_scene_destroy(&g_scene);
    return teardown(state);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_dot_and_ring_land_where_the_gaze_points_in_each_eye),
        cmocka_unit_test(the_foveal_boundary_is_the_edge_of_the_full_rate_region),
        cmocka_unit_test(no_gaze_no_dot_and_any_gaze_draws_cleanly),
    };
    return cmocka_run_group_tests(tests, setup, teardown_all);
}
