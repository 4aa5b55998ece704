/* @brief GPU tests of foveation (render/fovea) on lavapipe with validation on: the sampling probability against a
 * CPU evaluation in double for a grid of gazes (incl. the image corner, off-screen, NaN, pupils 0 and 12 mm), one
 * sample per block at least, the sample count against the sum of p, the pass list and the shade counter, and the
 * jump-flooding seeds against a brute-force nearest-seed search. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_renderer.h"
#include "fv_scene.h"
#include "fv_test.h"
#include "gpu_test.h"

#define W 96
#define H 80
#define NPIX ((size_t)W * H)
#define DEG (FV_PI / 180.0)
#define P_TOL 1e-4

FV_GPU_TEST_GROUP(W, H)
static uint64_t g_frame_id = 1;

/* p in double: e between the pixel ray and the gaze (invalid: straight ahead, widened 15 deg), e' = max(0, e - u),
 * w = m e' + w0, p = clamp(1 - (w - w0) / (m E + w0), xi, 1), E the view's corner eccentricity. */
static double ref_p(const fv_frame_input *in, int e, int x, int y, double u_rad, bool valid)
{
    const fv_eye_view *v = &in->eye[e];
    const fv_quality_fovea *q = &in->quality.fovea;
    double uu = (x + 0.5) / W, tt = (y + 0.5) / H;
    double r[3] = {v->tan_left + uu * ((double)v->tan_right - v->tan_left),
                   v->tan_up + tt * ((double)v->tan_down - v->tan_up), -1.0};
    double g[3] = {0, 0, -1};
    if (valid) {
        fv_vec3 d = in->gaze[e].dir_eye;
        g[0] = d.x, g[1] = d.y, g[2] = d.z;
    }
    double c[3] = {r[1] * g[2] - r[2] * g[1], r[2] * g[0] - r[0] * g[2], r[0] * g[1] - r[1] * g[0]};
    double ecc = atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), r[0] * g[0] + r[1] * g[1] + r[2] * g[2]);
    double u = valid ? u_rad : 15.0 * DEG;
    double ep = fmax(0.0, ecc - u);
    double tx = fmax(fabs(v->tan_left), fabs(v->tan_right)), ty = fmax(fabs(v->tan_up), fabs(v->tan_down));
    double E = atan(sqrt(tx * tx + ty * ty));
    double m = q->mar_slope, w0 = q->mar_w0_deg;
    double w = m * ep / DEG + w0, wfar = m * E / DEG + w0;
    return fmin(1.0, fmax((double)q->min_prob, 1.0 - (w - w0) / wfar));
}

typedef struct gaze_case {
    const char *name;
    fv_vec3 dir;
    bool valid;
    float pupil_mm, unc_deg;
} gaze_case;

static void sampling_map_matches_cpu_and_every_block_holds_a_sample(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("cornell", &s), FV_OK);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    fv_frame_input in;
    assert_int_equal(fv_renderer_frame_input(g_r, NULL, g_frame_id, 0.0, &in), FV_OK);
    /* the image corner of eye 0 (top left) and beyond the frustum */
    fv_vec3 corner = fv_v3_normalize_or(fv_v3(in.eye[0].tan_left, in.eye[0].tan_up, -1.0f), fv_v3(0, 0, -1));
    const gaze_case cases[] = {
        {"centre", fv_v3(0, 0, -1), true, 4.0f, 1.0f},
        {"right 20 deg", fv_v3(0.342f, 0.0f, -0.940f), true, 0.0f, 0.5f},
        {"image corner", corner, true, 12.0f, 0.0f},
        {"off-screen", fv_v3_normalize_or(fv_v3(3.0f, -2.0f, -1.0f), fv_v3(0, 0, -1)), true, 4.0f, 2.0f},
        {"NaN", fv_v3(NAN, 0, -1), true, 12.0f, 1.0f},
        {"invalid", fv_v3(0, 0, -1), false, 0.0f, 1.0f},
    };
    float *prob = malloc(NPIX * 4), *rgba = malloc(NPIX * 16);
    uint32_t *mask = malloc(NPIX * 4), *seeds = malloc(NPIX * 4);
    assert_true(prob && mask && rgba && seeds);
    double worst = 0, exact = 0, total = 0;
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const gaze_case *c = &cases[k];
        assert_int_equal(fv_renderer_frame_input(g_r, NULL, g_frame_id++, 0.0, &in), FV_OK);
        in.pupil_mm = c->pupil_mm;
        for (int e = 0; e < 2; e++) {
            in.gaze[e].valid = c->valid;
            in.gaze[e].dir_eye = c->dir;
            in.gaze[e].uncertainty_deg = c->unc_deg;
        }
        in.quality.fovea.enabled = true; /* experimental: off in every preset */
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        bool valid = c->valid && isfinite(c->dir.x);
        for (int e = 0; e < 2; e++) {
            assert_int_equal(fv_renderer_read_image(g_r, "fovea prob", e, prob, NPIX * 4, 4), FV_OK);
            assert_int_equal(fv_renderer_read_image(g_r, "fovea mask", e, mask, NPIX * 4, 4), FV_OK);
            double sum_p = 0, count = 0;
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    float got = prob[(size_t)y * W + x];
                    assert_true(isfinite(got));
                    double want = ref_p(&in, e, x, y, c->unc_deg * DEG, valid);
                    double err = fabs(got - want);
                    if (err > worst) worst = err;
                    if (!(err <= P_TOL)) fail_msg("%s eye %d (%d, %d): p gpu %.6f cpu %.6f", c->name, e, x, y, got, want);
                    sum_p += want;
                    count += mask[(size_t)y * W + x] != 0;
                }
            uint32_t B = in.quality.fovea.block, blocks = 0;
            for (uint32_t by = 0; by < H; by += B)
                for (uint32_t bx = 0; bx < W; bx += B) {
                    int n = 0;
                    for (uint32_t y = by; y < by + B && y < H; y++)
                        for (uint32_t x = bx; x < bx + B && x < W; x++) n += mask[(size_t)y * W + x] != 0;
                    if (n < 1) fail_msg("%s eye %d: block (%u, %u) holds no sample", c->name, e, bx, by);
                    blocks++;
                }
            /* Per block the count is round(p n) for the block's ranks (each in [p n - 0.5, p n + 0.5]) or the one
             * forced sample: |count - sum p| <= 0.5 per block bounds it; in practice it averages out. */
            print_message("%s eye %d: %.0f samples, sum p %.1f (%.2f%%), %u blocks\n", c->name, e, count, sum_p,
                          100.0 * (count - sum_p) / sum_p, blocks);
            assert_true(fabs(count - sum_p) <= 0.5 * blocks + 1.0);

            /* JFA (the reconstruction's final seeds) against a brute-force nearest sample */
            fv_pass_detail d;
            assert_int_equal(fv_renderer_pass_details(g_r, "reconstruct", &d, 1), 1);
            const char *final = d.value[1] == 0 ? "fovea seeds a" : "fovea seeds b";
            assert_int_equal(fv_renderer_read_image(g_r, final, e, seeds, NPIX * 4, 4), FV_OK);
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    uint32_t sd = seeds[(size_t)y * W + x];
                    long best = -1;
                    for (int yy = 0; yy < H; yy++)
                        for (int xx = 0; xx < W; xx++)
                            if (mask[(size_t)yy * W + xx]) {
                                long dd = (long)(xx - x) * (xx - x) + (long)(yy - y) * (yy - y);
                                if (best < 0 || dd < best) best = dd;
                            }
                    long sx = (long)(sd & 0xffffu), sy = (long)(sd >> 16);
                    long got = sd == 0xffffffffu ? -1 : (sx - x) * (sx - x) + (sy - y) * (sy - y);
                    exact += got == best && mask[(size_t)sy * W + sx] != 0;
                    total++;
                }
        }
        assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    }
    print_message("worst p error %.2e; JFA exact nearest seed for %.4f%% of %.0f pixels\n", worst,
                  100.0 * exact / total, total);
    assert_true(exact / total >= 0.99);

    /* the plan and the counters: shade shades the list the GPU made */
    assert_int_equal(fv_renderer_finish(g_r), FV_OK);
    fv_render_stats st;
    assert_int_equal(fv_renderer_stats(g_r, &st), FV_OK);
    bool saw_fovea = false, saw_recon = false;
    for (uint32_t i = 0; i < st.pass_count; i++) {
        saw_fovea |= strcmp(st.pass_name[i], "fovea") == 0;
        saw_recon |= strcmp(st.pass_name[i], "reconstruct") == 0;
        if (strcmp(st.pass_name[i], "shade") == 0) {
            print_message("shade: %llu of %zu pixels\n", (unsigned long long)st.pass_counters[i].pixels_shaded,
                          2 * NPIX);
            assert_true(st.pass_counters[i].pixels_shaded > 0 && st.pass_counters[i].pixels_shaded <= 2 * NPIX);
        }
    }
    assert_true(saw_fovea && saw_recon);
    const fv_plan_entry *pe = fv_frame_plan_find(fv_renderer_plan(g_r), "fovea");
    assert_non_null(pe);
    assert_true(pe->enabled);
    assert_non_null(strstr(pe->reason, "sampling map"));
    free(prob);
    free(mask);
    free(rgba);
    free(seeds);
    fv_scene_destroy(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sampling_map_matches_cpu_and_every_block_holds_a_sample),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
