/* @brief GPU tests of foveation (render/fovea) on lavapipe with validation on: the sampling probability against a
 * CPU evaluation in double for a grid of gazes (incl. the image corner, off-screen, NaN, pupils 0 and 12 mm), one
 * sample per block at least, the sample count against the sum of p, the jump-flooding Voronoi against a
 * brute-force nearest-seed search; the three compaction orders shade the same pixels into the same image; the
 * Sibson fill against a brute-force discrete natural-neighbour interpolation; the fovea following fixed: gazes left
 * and right; the foveal band (0-5 degrees) of a foveated frame against full-resolution shading. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_fixed_driver.h"
#include "fv_metrics.h"
#include "fv_renderer.h"
#include "fv_scene.h"
#include "fv_test.h"
#include "fovea_interface.h"
#include "gpu_test.h"

#define W 96
#define H 80
#define NPIX ((size_t)W * H)
#define DEG (FV_PI / 180.0)
#define P_TOL 1e-4
#define NONE 0xffffffffu

FV_GPU_TEST_GROUP_MOTION(W, H) /* the tests read the motion vectors back */
static uint64_t g_frame_id = 1;

/* p in double: e between the pixel ray and the gaze (invalid: straight ahead, widened 15 deg), e' = max(0, e - u),
 * w = m e' + w0, p = clamp(1 - (w - w_min) / w_far, xi, 1), w_min = max(w0, w_px), w_far = 3 w_px, w_px the angle
 * of the centre pixel (fovea_interface.h). */
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
    double dtx = fabs((double)v->tan_right - v->tan_left) / W, dty = fabs((double)v->tan_down - v->tan_up) / H;
    double w_px = 2.0 * atan(0.5 * fmin(dtx, dty)) / DEG;
    double m = q->mar_slope, w0 = q->mar_w0_deg;
    double w = m * ep / DEG + w0, w_min = fmax(w0, w_px), w_far = 3.0 * w_px;
    return fmin(1.0, fmax((double)q->min_prob, 1.0 - (w - w_min) / w_far));
}

typedef struct gaze_case {
    const char *name;
    fv_vec3 dir;
    bool valid;
    float pupil_mm, unc_deg;
} gaze_case;

static void load(const char *scene, fv_scene **s)
{
    assert_int_equal(fv_scene_load(scene, s), FV_OK);
    assert_int_equal(fv_renderer_load_scene(g_r, *s), FV_OK);
}

static fv_frame_input frame_in(void)
{
    fv_frame_input in;
    assert_int_equal(fv_renderer_frame_input(g_r, NULL, g_frame_id++, 0.0, &in), FV_OK);
    in.quality.fovea.enabled = true;
    in.quality.fovea.saliency = 0.0f; /* the plain MAR map unless a test asks (its own test below) */
    in.quality.fovea.dof = false;
    return in;
}

static void set_gaze(fv_frame_input *in, fv_vec3 dir, float unc_deg)
{
    for (int e = 0; e < 2; e++) {
        in->gaze[e].valid = true;
        in->gaze[e].dir_eye = dir;
        in->gaze[e].uncertainty_deg = unc_deg;
    }
}

/* The exact nearest sample of every pixel (ties: the smaller packed x | y << 16, as the GPU) by brute force. */
static void brute_nearest(const uint32_t *mask, uint32_t *out)
{
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            long best = -1;
            uint32_t bs = NONE;
            for (int yy = 0; yy < H; yy++)
                for (int xx = 0; xx < W; xx++) {
                    if (!mask[(size_t)yy * W + xx]) continue;
                    long dd = (long)(xx - x) * (xx - x) + (long)(yy - y) * (yy - y);
                    uint32_t s = (uint32_t)xx | ((uint32_t)yy << 16);
                    if (best < 0 || dd < best || (dd == best && s < bs)) best = dd, bs = s;
                }
            out[(size_t)y * W + x] = bs;
        }
}

static long dist2(uint32_t s, int x, int y)
{
    long dx = (long)(s & 0xffffu) - x, dy = (long)(s >> 16) - y;
    return dx * dx + dy * dy;
}

static void sampling_map_matches_cpu_and_every_block_holds_a_sample(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    fv_frame_input in = frame_in();
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
    float *prob = malloc(NPIX * 4);
    uint32_t *mask = malloc(NPIX * 4), *vor = malloc(NPIX * 4), *exact_seed = malloc(NPIX * 4);
    assert_true(prob && mask && vor && exact_seed);
    double worst = 0, exact = 0, total = 0;
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const gaze_case *c = &cases[k];
        in = frame_in();
        in.pupil_mm = c->pupil_mm;
        set_gaze(&in, c->dir, c->unc_deg);
        for (int e = 0; e < 2; e++) in.gaze[e].valid = c->valid;
        in.quality.fovea.mar_slope = 0.2f; /* a fovea that fits the small test image */
        in.quality.fovea.block = 3 + (uint32_t)(k % 3); /* 3, 4, 5: blocks cut by the 96x80 image's edges too */
        in.quality.fovea.recon = FV_FOVEA_RECON_NEAREST; /* its Voronoi (soft, the default, makes none) */
        in.quality.fovea.voronoi = FV_FOVEA_VORONOI_JFA; /* the paper's; the block search is checked below */
        in.quality.debug_view = FV_DEBUG_VIEW_PROB; /* p is stored for its readers only */
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
                    count += mask[(size_t)y * W + x] == 1; /* shaded (2: reused from history) */
                }
            uint32_t B = in.quality.fovea.block, blocks = 0;
            double expect = 0; /* per block: its sum of p, but one sample at least */
            for (uint32_t by = 0; by < H; by += B)
                for (uint32_t bx = 0; bx < W; bx += B) {
                    int n = 0;
                    double bp = 0;
                    for (uint32_t y = by; y < by + B && y < H; y++)
                        for (uint32_t x = bx; x < bx + B && x < W; x++) {
                            n += mask[(size_t)y * W + x] == 1;
                            bp += ref_p(&in, e, (int)x, (int)y, c->unc_deg * DEG, valid);
                        }
                    if (n < 1) fail_msg("%s eye %d: block (%u, %u) holds no sample", c->name, e, bx, by);
                    expect += fmax(1.0, bp);
                    blocks++;
                }
            /* Per block the count is round(p n) for the block's ranks (each in [p n - 0.5, p n + 0.5]), or the one
             * forced sample: |count - expected| <= 0.5 per block bounds it, and in practice it averages out. */
            print_message("%s eye %d (B %u): %.0f samples, sum p %.1f, expected %.1f (%+.2f%%), %u blocks\n", c->name,
                          e, B, count, sum_p, expect, 100.0 * (count - expect) / expect, blocks);
            assert_true(fabs(count - expect) <= 0.5 * blocks + 1.0);
            assert_true(fabs(count - expect) <= 0.1 * expect);

            /* the Voronoi of 1+JFA against the exact nearest sample */
            assert_int_equal(fv_renderer_read_image(g_r, "fovea voronoi", e, vor, NPIX * 4, 4), FV_OK);
            brute_nearest(mask, exact_seed);
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    uint32_t sd = vor[(size_t)y * W + x], want = exact_seed[(size_t)y * W + x];
                    assert_true(sd != NONE);
                    assert_true(mask[(size_t)(sd >> 16) * W + (sd & 0xffffu)] != 0); /* a seed is a sample */
                    exact += dist2(sd, x, y) == dist2(want, x, y);
                    total++;
                }
        }
        assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    }
    print_message("worst p error %.2e; 1+JFA exact nearest seed for %.4f%% of %.0f pixels\n", worst,
                  100.0 * exact / total, total);
    assert_true(exact / total >= 0.995);

    /* the block search (fovea.voronoi=blocks, sibson needs every pixel's seed) is exact, with B = 4 and 7 */
    for (uint32_t B = 4; B <= 7; B += 3) {
        in = frame_in();
        set_gaze(&in, fv_v3_normalize_or(fv_v3(0.2f, 0.2f, -1.0f), fv_v3(0, 0, -1)), 0.5f);
        in.quality.fovea.mar_slope = 0.2f;
        in.quality.fovea.block = B;
        in.quality.fovea.voronoi = FV_FOVEA_VORONOI_BLOCKS;
        in.quality.fovea.recon = FV_FOVEA_RECON_SIBSON;
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        for (int e = 0; e < 2; e++) {
            assert_int_equal(fv_renderer_read_image(g_r, "fovea mask", e, mask, NPIX * 4, 4), FV_OK);
            assert_int_equal(fv_renderer_read_image(g_r, "fovea voronoi", e, vor, NPIX * 4, 4), FV_OK);
            brute_nearest(mask, exact_seed);
            for (size_t i = 0; i < NPIX; i++)
                if (vor[i] != exact_seed[i]) fail_msg("B %u eye %d pixel %zu: seed %x, exact %x", B, e, i, vor[i], exact_seed[i]);
        }
    }

    /* the plan and the counters: shade shades the list the GPU made; the stats report the fraction per eye */
    assert_int_equal(fv_renderer_finish(g_r), FV_OK);
    fv_render_stats st;
    assert_int_equal(fv_renderer_stats(g_r, &st), FV_OK);
    bool saw[3] = {false};
    for (uint32_t i = 0; i < st.pass_count; i++) {
        saw[0] |= strcmp(st.pass_name[i], "fovea") == 0;
        saw[1] |= strcmp(st.pass_name[i], "compact") == 0;
        saw[2] |= strcmp(st.pass_name[i], "reconstruct") == 0;
        if (strcmp(st.pass_name[i], "shade") == 0) {
            print_message("shade: %llu of %zu pixels\n", (unsigned long long)st.pass_counters[i].pixels_shaded,
                          2 * NPIX);
            assert_true(st.pass_counters[i].pixels_shaded > 0 && st.pass_counters[i].pixels_shaded < 2 * NPIX);
        }
    }
    assert_true(saw[0] && saw[1] && saw[2]);
    /* the per-eye counts are taken when a slot comes round again (its fence passed): two more frames */
    for (int i = 0; i < 3; i++) {
        fv_frame_input again = in;
        again.frame_id = g_frame_id++;
        assert_int_equal(fv_renderer_draw(g_r, &again), FV_OK);
    }
    fv_pass_detail d[4];
    uint32_t nd = fv_renderer_pass_details(g_r, "compact", d, 4);
    assert_true(nd >= 1);
    assert_string_equal(d[0].key, "sampled_fraction");
    assert_true(d[0].value[0] > 0.0 && d[0].value[0] < 1.0 && d[0].value[1] > 0.0 && d[0].value[1] < 1.0);
    const fv_plan_entry *pe = fv_frame_plan_find(fv_renderer_plan(g_r), "fovea");
    assert_non_null(pe);
    assert_true(pe->enabled);
    assert_non_null(strstr(pe->reason, "sampling map"));
    free(prob);
    free(mask);
    free(vor);
    free(exact_seed);
    fv_scene_destroy(&s);
}

/* tiles, rows and masked lists shade the same pixels by the same function: the same image, bit for bit; the shade
 * counter is the list's size (every pixel for masked). */
static void compaction_orders_shade_the_same_image(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    float *img[3][2];
    uint64_t shaded[3] = {0};
    uint32_t *mask = malloc(NPIX * 4);
    double samples = 0;
    for (int m = 0; m < 3; m++) {
        fv_frame_input in = frame_in();
        in.frame_id = 77; /* the same pattern each time */
        set_gaze(&in, fv_v3_normalize_or(fv_v3(-0.2f, 0.1f, -1.0f), fv_v3(0, 0, -1)), 1.0f);
        in.quality.fovea.mar_slope = 0.2f;
        in.quality.fovea.compaction = (fv_fovea_compaction)m;
        in.quality.fovea.temporal = 0; /* the same known pixels each time: no history */
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        assert_int_equal(fv_renderer_finish(g_r), FV_OK);
        for (int e = 0; e < 2; e++) {
            img[m][e] = malloc(NPIX * 16);
            assert_int_equal(fv_renderer_read_linear(g_r, e, img[m][e], NPIX * 4), FV_OK);
            if (m == 0) {
                assert_int_equal(fv_renderer_read_image(g_r, "fovea mask", e, mask, NPIX * 4, 4), FV_OK);
                for (size_t i = 0; i < NPIX; i++) samples += mask[i] == 1;
            }
        }
        fv_render_stats st;
        assert_int_equal(fv_renderer_stats(g_r, &st), FV_OK);
        for (uint32_t i = 0; i < st.pass_count; i++)
            if (strcmp(st.pass_name[i], "shade") == 0) shaded[m] = st.pass_counters[i].pixels_shaded;
    }
    print_message("samples %.0f; shaded: tiles %llu, rows %llu, masked %llu\n", samples,
                  (unsigned long long)shaded[0], (unsigned long long)shaded[1], (unsigned long long)shaded[2]);
    assert_true(shaded[0] == (uint64_t)samples && shaded[1] == (uint64_t)samples);
    assert_true(shaded[2] >= 2 * NPIX); /* every tile slot listed */
    for (int m = 1; m < 3; m++)
        for (int e = 0; e < 2; e++)
            if (memcmp(img[0][e], img[m][e], NPIX * 16) != 0) fail_msg("compaction %d eye %d: another image", m, e);
    for (int m = 0; m < 3; m++) free(img[m][0]), free(img[m][1]);
    free(mask);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    fv_scene_destroy(&s);
}

/* The discrete natural-neighbour colour of pixel (x, y): the mean of the seed colours of every q with
 * |p - q| <= d(q) (q's nearest seed no nearer than p), over a window of half side R (R < 0: the whole image). */
static void natural_neighbour(const uint32_t *seed, const float *rgba, int x, int y, int R, double out[3])
{
    double sum[3] = {0, 0, 0}, n = 0;
    int y0 = R < 0 ? 0 : y - R, y1 = R < 0 ? H - 1 : y + R, x0 = R < 0 ? 0 : x - R, x1 = R < 0 ? W - 1 : x + R;
    for (int qy = y0; qy <= y1; qy++)
        for (int qx = x0; qx <= x1; qx++) {
            if (qx < 0 || qy < 0 || qx >= W || qy >= H) continue;
            uint32_t s = seed[(size_t)qy * W + qx];
            long pq = (long)(qx - x) * (qx - x) + (long)(qy - y) * (qy - y);
            if (pq > dist2(s, qx, qy)) continue;
            const float *c = &rgba[((size_t)(s >> 16) * W + (s & 0xffffu)) * 4];
            for (int k = 0; k < 3; k++) sum[k] += c[k];
            n++;
        }
    for (int k = 0; k < 3; k++) out[k] = sum[k] / (n > 0 ? n : 1);
}

static void sibson_matches_brute_force_natural_neighbours(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    fv_frame_input in = frame_in();
    set_gaze(&in, fv_v3_normalize_or(fv_v3(0.3f, -0.1f, -1.0f), fv_v3(0, 0, -1)), 0.5f);
    in.quality.fovea.mar_slope = 0.3f;
    in.quality.fovea.block = 4;
    in.quality.fovea.recon = FV_FOVEA_RECON_SIBSON;
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    float *rgba = malloc(NPIX * 16);
    uint32_t *mask = malloc(NPIX * 4), *vor = malloc(NPIX * 4), *exact_seed = malloc(NPIX * 4);
    assert_true(rgba && mask && vor && exact_seed);
    double same_window = 0, same_full = 0, filled = 0, worst_window = 0, sum_full = 0;
    for (int e = 0; e < 2; e++) {
        assert_int_equal(fv_renderer_read_linear(g_r, e, rgba, NPIX * 4), FV_OK);
        assert_int_equal(fv_renderer_read_image(g_r, "fovea mask", e, mask, NPIX * 4, 4), FV_OK);
        assert_int_equal(fv_renderer_read_image(g_r, "fovea voronoi", e, vor, NPIX * 4, 4), FV_OK);
        brute_nearest(mask, exact_seed);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                const float *got = &rgba[((size_t)y * W + x) * 4];
                for (int k = 0; k < 3; k++) assert_true(isfinite(got[k]));
                if (mask[(size_t)y * W + x]) continue; /* samples keep their shaded colour */
                filled++;
                /* the GPU's rule on the GPU's Voronoi: equal but for float summation order */
                double want[3], full[3];
                natural_neighbour(vor, rgba, x, y, 4, want);
                double err = 0;
                for (int k = 0; k < 3; k++) err = fmax(err, fabs(got[k] - want[k]) / fmax(1e-3, fabs(want[k])));
                worst_window = fmax(worst_window, err);
                same_window += err <= 1e-4;
                /* the exact discrete natural neighbours: the exact Voronoi, no window */
                natural_neighbour(exact_seed, rgba, x, y, -1, full);
                double ef = 0;
                for (int k = 0; k < 3; k++) ef = fmax(ef, fabs(got[k] - full[k]) / fmax(1e-3, fabs(full[k])));
                same_full += ef <= 1e-4;
                sum_full += ef;
            }
    }
    print_message("sibson: %.0f filled pixels; windowed rule on the GPU's Voronoi: %.3f%% equal (worst rel %.2e); "
                  "exact natural neighbours without window: %.3f%% equal, mean rel error %.2e\n",
                  filled, 100.0 * same_window / filled, worst_window, 100.0 * same_full / filled, sum_full / filled);
    assert_true(filled > 0);
    assert_true(same_window == filled);
    assert_true(same_full / filled >= 0.95);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    free(rgba);
    free(mask);
    free(vor);
    free(exact_seed);
    fv_scene_destroy(&s);
}

/* fixed: gazes 20 degrees left and right (the driver's own sample): the sampled fraction per column peaks on the
 * gaze's side, and the disc around the gaze is sampled more densely than its mirror image. */
static void fovea_follows_fixed_gazes(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    uint32_t *mask = malloc(NPIX * 4);
    for (int side = -1; side <= 1; side += 2) {
        char uri[64];
        snprintf(uri, sizeof uri, "fixed:yaw_deg=%d,pitch_deg=0", side * 20);
        fv_fixed_desc fd;
        assert_int_equal(fv_fixed_parse_uri(uri, &fd), FV_OK);
        fv_gaze_sample gs;
        fv_fixed_sample(&fd, &gs);
        fv_frame_input in = frame_in();
        for (int e = 0; e < 2; e++) {
            in.gaze[e].valid = true;
            in.gaze[e].dir_eye = gs.eye[e].direction; /* the head is not turned: eye space = head frame */
            in.gaze[e].uncertainty_deg = 0.5f;
        }
        in.quality.fovea.mar_slope = 0.2f;
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        for (int e = 0; e < 2; e++) {
            assert_int_equal(fv_renderer_read_image(g_r, "fovea mask", e, mask, NPIX * 4, 4), FV_OK);
            const fv_eye_view *v = &in.eye[e];
            fv_vec3 d = in.gaze[e].dir_eye;
            double gx = ((d.x / -d.z) - v->tan_left) / ((double)v->tan_right - v->tan_left) * W;
            double gy = ((d.y / -d.z) - v->tan_up) / ((double)v->tan_down - v->tan_up) * H;
            int best_col = 0;
            double best = -1;
            for (int x = 0; x < W; x++) {
                double n = 0;
                for (int y = 0; y < H; y++) n += mask[(size_t)y * W + x] == 1; /* shaded, not reused */
                if (n > best) best = n, best_col = x;
            }
            double at = 0, mirror = 0, na = 0, nm = 0, mx = W - gx;
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    bool m = mask[(size_t)y * W + x] == 1;
                    if (hypot(x + 0.5 - gx, y + 0.5 - gy) < 10) at += m, na++;
                    if (hypot(x + 0.5 - mx, y + 0.5 - gy) < 10) mirror += m, nm++;
                }
            print_message("%s eye %d: gaze at (%.1f, %.1f) px, densest column %d; disc %.3f, mirror %.3f\n", uri, e,
                          gx, gy, best_col, at / na, mirror / nm);
            assert_true(side < 0 ? best_col < W / 2 : best_col >= W / 2);
            assert_true(fabs(best_col + 0.5 - gx) < 12);
            assert_true(at / na > mirror / nm + 0.2);
        }
    }
    free(mask);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    fv_scene_destroy(&s);
}

/* A static scene and a fixed gaze: within 5 degrees of the gaze the foveated frame is the full-resolution frame
 * (PSNR >= 40 dB on sRGB values), with both reconstructions. */
static void foveal_band_equals_full_resolution(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    float *full[2], *fov = malloc(NPIX * 16), *ecc = malloc(NPIX * 4);
    fv_vec3 gaze = fv_metrics_gaze_dir_from_deg(-8.0, 4.0);
    fv_frame_input in = frame_in();
    in.quality.fovea.enabled = false;
    set_gaze(&in, gaze, 0.5f);
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    for (int e = 0; e < 2; e++) {
        full[e] = malloc(NPIX * 16);
        assert_int_equal(fv_renderer_read_linear(g_r, e, full[e], NPIX * 4), FV_OK);
    }
    for (int r = 0; r <= FV_FOVEA_RECON_LAST; r++) {
        in = frame_in();
        set_gaze(&in, gaze, 0.5f);
        in.quality.fovea.mar_slope = 0.2f;
        in.quality.fovea.recon = (fv_fovea_recon)r;
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        double se_band = 0, n_band = 0, se_all = 0;
        for (int e = 0; e < 2; e++) {
            assert_int_equal(fv_renderer_read_linear(g_r, e, fov, NPIX * 4), FV_OK);
            fv_metrics_eccentricity_deg(&in.eye[e], gaze, W, H, ecc, W);
            for (size_t i = 0; i < NPIX; i++)
                for (int k = 0; k < 3; k++) {
                    double a = fv_metrics_linear_to_srgb(fov[i * 4 + k]), b = fv_metrics_linear_to_srgb(full[e][i * 4 + k]);
                    assert_true(isfinite(fov[i * 4 + k]));
                    se_all += (a - b) * (a - b);
                    if (ecc[i] < 5.0f) se_band += (a - b) * (a - b), n_band++;
                }
        }
        double band_db = fv_metrics_psnr_db(n_band ? se_band / n_band : NAN);
        double all_db = fv_metrics_psnr_db(se_all / (2.0 * NPIX * 3));
        print_message("recon %d: foveal band (0-5 deg, %.0f values) PSNR %.1f dB, whole image %.1f dB\n", r, n_band,
                      band_db, all_db);
        assert_true(n_band > 0);
        assert_true(band_db >= 40.0);
        assert_true(all_db > 15.0 && all_db < INFINITY); /* the periphery is reconstructed, not shaded */
    }
    free(full[0]);
    free(full[1]);
    free(fov);
    free(ecc);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    fv_scene_destroy(&s);
}

/* A moving head (yaw 0.5 degrees and 3 mm sideways per frame) and a gaze held at the centre: with temporal reuse
 * (fovea.temporal=8) the periphery (> 5 degrees from the gaze) is closer to full-resolution shading of the same
 * frames, and its error flickers less from frame to frame, than without (fovea.temporal=0); the pass reports its
 * cache hits, and a head jump and a scene load reset the history. */
#define T_FRAMES 10
#define T_SKIP 3 /* frames before the history has filled */
static fv_head head_at(const fv_scene *s, int k, double yaw_deg)
{
    fv_head h = s->head;
    h.orientation = fv_quat_normalize(
        fv_quat_mul(h.orientation, fv_quat_axis_angle(fv_v3(0, 1, 0), (float)(yaw_deg * k * DEG))));
    h.position_m = fv_v3_add(h.position_m, fv_quat_rotate(s->head.orientation, fv_v3(0.003f * (float)k, 0, 0)));
    return h;
}

static void temporal_reuse_lowers_periphery_error_and_flicker(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    enum { FULL = 0, NO_REUSE = 1, REUSE = 2 };
    float *img[3][T_FRAMES][2];
    float *ecc = malloc(NPIX * 4);
    assert_non_null(ecc);
    fv_vec3 gaze = fv_v3(0, 0, -1);
    double hits = 0, reused = 0;
    for (int mode = 0; mode < 3; mode++)
        for (int k = 0; k < T_FRAMES; k++) {
            fv_head h = head_at(s, k, 0.5);
            fv_frame_input in;
            assert_int_equal(fv_renderer_frame_input(g_r, &h, g_frame_id++, 0.0, &in), FV_OK);
            in.quality.fovea.enabled = mode != FULL;
            in.quality.fovea.mar_slope = 0.2f;
            in.quality.fovea.temporal = mode == REUSE ? 8u : 0u;
            set_gaze(&in, gaze, 0.5f);
            assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
            assert_int_equal(fv_renderer_finish(g_r), FV_OK);
            for (int e = 0; e < 2; e++) {
                img[mode][k][e] = malloc(NPIX * 16);
                assert_non_null(img[mode][k][e]);
                assert_int_equal(fv_renderer_read_linear(g_r, e, img[mode][k][e], NPIX * 4), FV_OK);
                for (size_t i = 0; i < NPIX * 4; i++) assert_true(isfinite(img[mode][k][e][i]));
            }
            if (mode == REUSE && k == T_FRAMES - 1) {
                /* the counts of a frame are read when its slot comes round: draw the last pose again */
                for (int again = 0; again < 3; again++) {
                    in.frame_id = g_frame_id++;
                    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
                }
                fv_pass_detail d[4];
                uint32_t nd = fv_renderer_pass_details(g_r, "temporal", d, 4);
                for (uint32_t i = 0; i < nd; i++) {
                    if (strcmp(d[i].key, "cache_hit_fraction") == 0) hits = d[i].value[0];
                    if (strcmp(d[i].key, "reused_fraction") == 0) reused = d[i].value[0];
                }
            }
        }
    double mse[3] = {0}, flicker[3] = {0}, n = 0, nf = 0;
    for (int e = 0; e < 2; e++) {
        fv_frame_input in0;
        fv_head h0 = head_at(s, 0, 0.5);
        assert_int_equal(fv_renderer_frame_input(g_r, &h0, 1, 0.0, &in0), FV_OK);
        fv_metrics_eccentricity_deg(&in0.eye[e], gaze, W, H, ecc, W); /* the gaze is fixed in the eye */
        for (int k = T_SKIP; k < T_FRAMES; k++)
            for (size_t i = 0; i < NPIX; i++) {
                if (!(ecc[i] > 5.0f)) continue;
                for (int c = 0; c < 3; c++) {
                    double full = fv_metrics_linear_to_srgb(img[FULL][k][e][i * 4 + c]);
                    double full_prev = fv_metrics_linear_to_srgb(img[FULL][k - 1][e][i * 4 + c]);
                    for (int m = NO_REUSE; m <= REUSE; m++) {
                        double err = fv_metrics_linear_to_srgb(img[m][k][e][i * 4 + c]) - full;
                        double err_prev = fv_metrics_linear_to_srgb(img[m][k - 1][e][i * 4 + c]) - full_prev;
                        mse[m] += err * err;
                        flicker[m] += (err - err_prev) * (err - err_prev);
                    }
                    n++;
                    nf++;
                }
            }
    }
    for (int m = NO_REUSE; m <= REUSE; m++) mse[m] /= n, flicker[m] /= nf;
    print_message("moving head, periphery (> 5 deg): PSNR %.2f dB without reuse, %.2f dB with; flicker (mean squared "
                  "frame-to-frame change of the error) %.3e without, %.3e with; cache hits %.1f%%, reused %.1f%% of "
                  "eye 0's pixels\n",
                  fv_metrics_psnr_db(mse[NO_REUSE]), fv_metrics_psnr_db(mse[REUSE]), flicker[NO_REUSE],
                  flicker[REUSE], 100.0 * hits, 100.0 * reused);
    assert_true(mse[REUSE] < mse[NO_REUSE]);
    assert_true(flicker[REUSE] < flicker[NO_REUSE]);
    assert_true(hits > 0.2 && hits <= 1.0);
    assert_true(reused > 0.05 && reused < hits);
    for (int m = 0; m < 3; m++)
        for (int k = 0; k < T_FRAMES; k++) free(img[m][k][0]), free(img[m][k][1]);

    /* resets: a head jump of 40 degrees, and a scene load, each reset the history (no pixel reused) */
    fv_pass_detail d[4];
    double resets0 = -1, resets1 = -1, resets2 = -1;
    uint32_t nd = fv_renderer_pass_details(g_r, "temporal", d, 4);
    for (uint32_t i = 0; i < nd; i++)
        if (strcmp(d[i].key, "resets_max_age") == 0) resets0 = d[i].value[0];
    fv_head jump = head_at(s, 80, 0.5);
    fv_frame_input in;
    assert_int_equal(fv_renderer_frame_input(g_r, &jump, g_frame_id++, 0.0, &in), FV_OK);
    in.quality.fovea.enabled = true;
    in.quality.fovea.mar_slope = 0.2f;
    in.quality.fovea.temporal = 8u;
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    nd = fv_renderer_pass_details(g_r, "temporal", d, 4);
    for (uint32_t i = 0; i < nd; i++)
        if (strcmp(d[i].key, "resets_max_age") == 0) resets1 = d[i].value[0];
    assert_true(resets0 >= 1 && resets1 == resets0 + 1);
    assert_int_equal(fv_renderer_finish(g_r), FV_OK);
    uint32_t *mask = malloc(NPIX * 4);
    assert_non_null(mask);
    assert_int_equal(fv_renderer_read_image(g_r, "fovea mask", 0, mask, NPIX * 4, 4), FV_OK);
    for (size_t i = 0; i < NPIX; i++) assert_true(mask[i] <= 1u); /* nothing reused after the jump */
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    in.frame_id = g_frame_id++;
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    nd = fv_renderer_pass_details(g_r, "temporal", d, 4);
    for (uint32_t i = 0; i < nd; i++)
        if (strcmp(d[i].key, "resets_max_age") == 0) resets2 = d[i].value[0];
    assert_true(resets2 == resets1 + 1);
    assert_int_equal(fv_renderer_finish(g_r), FV_OK);
    assert_int_equal(fv_renderer_read_image(g_r, "fovea mask", 1, mask, NPIX * 4, 4), FV_OK);
    for (size_t i = 0; i < NPIX; i++) assert_true(mask[i] <= 1u);
    free(mask);
    free(ecc);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    fv_scene_destroy(&s);
}

/* ---- saliency and depth of field against the CPU in double ------------------------------------------------------ */

typedef struct gbuf {
    float depth[NPIX];
    int16_t normal[NPIX][2];
    uint8_t albedo[NPIX][4];
    uint16_t material[NPIX];
    float motion[NPIX * 2];
} gbuf;

static double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }

static void lab_of(const uint8_t *rgba, double out[3])
{
    double c[3];
    for (int k = 0; k < 3; k++) c[k] = srgb_to_linear(rgba[k] / 255.0);
    double x = 0.4124564 * c[0] + 0.3575761 * c[1] + 0.1804375 * c[2];
    double y = 0.2126729 * c[0] + 0.7151522 * c[1] + 0.0721750 * c[2];
    double z = 0.0193339 * c[0] + 0.1191920 * c[1] + 0.9503041 * c[2];
    double t[3] = {x / 0.95047, y, z / 1.08883}, f[3];
    for (int k = 0; k < 3; k++) {
        double d = 6.0 / 29.0;
        f[k] = t[k] > d * d * d ? cbrt(t[k]) : t[k] / (3.0 * d * d) + 4.0 / 29.0;
    }
    out[0] = 116.0 * f[1] - 16.0, out[1] = 500.0 * (f[0] - f[1]), out[2] = 200.0 * (f[1] - f[2]);
}

static void normal_of(const int16_t *e16, double out[3])
{
    double ex = fmax(e16[0] / 32767.0, -1.0), ey = fmax(e16[1] / 32767.0, -1.0);
    double n[3] = {ex, ey, 1.0 - fabs(ex) - fabs(ey)};
    if (n[2] < 0) {
        double wx = (1.0 - fabs(ey)) * (ex >= 0 ? 1 : -1), wy = (1.0 - fabs(ex)) * (ey >= 0 ? 1 : -1);
        n[0] = wx, n[1] = wy;
    }
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++) out[k] = len > 1e-15 ? n[k] / len : (k == 2);
}

/* The distance from the eye to the surface drawn at (x, y): view z from the depth and the projection, along the
 * pixel centre's ray. */
static double dist_of(const fv_frame_input *in, int e, const gbuf *g, int x, int y)
{
    const fv_eye_view *v = &in->eye[e];
    double d = g->depth[(size_t)y * W + x], m22 = v->proj.m[2][2], m32 = v->proj.m[3][2];
    double z = -m32 / (d + m22);
    double tx = v->tan_left + (x + 0.5) / W * ((double)v->tan_right - v->tan_left);
    double ty = v->tan_up + (y + 0.5) / H * ((double)v->tan_down - v->tan_up);
    return fabs(z) * sqrt(tx * tx + ty * ty + 1.0);
}

/* The history is the frame's colour (fovea_interface.h): after reconstruction, with temporal reuse on and a moving
 * head, every pixel a fill wrote (mask UNKNOWN) has alpha 0 whatever the method (the next frame must not reuse a
 * guess), and every known pixel (shaded or reused) holds its distance from the eye, the G-buffer's to 1e-5, and an
 * age within fovea.temporal; the G-buffer's surface target carries that distance (the depth's, along the pixel
 * centre's ray, to 1e-4: the fragment's interpolated position against D32) and the normal target's bits, which foveation reads in one fetch (fv_gbuffer_fovea). */
static void the_history_in_the_colour_is_known_pixels_only(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    gbuf *g = malloc(sizeof *g);
    float *rgba = malloc(NPIX * 16), *surf = malloc(NPIX * 16);
    uint32_t *mask = malloc(NPIX * 4);
    assert_true(g && rgba && surf && mask);
    const fv_fovea_recon methods[4] = {FV_FOVEA_RECON_NEAREST, FV_FOVEA_RECON_SIBSON, FV_FOVEA_RECON_IDW,
                                       FV_FOVEA_RECON_SOFT};
    const char *const name[4] = {"nearest", "sibson", "idw", "soft"};
    for (int mi = 0; mi < 4; mi++) {
        fv_frame_input in;
        for (int k = 0; k < 3; k++) { /* each method from a history reset: 100 steps of 0.5 degrees away */
            fv_head h = head_at(s, 100 * mi + k, 0.5);
            assert_int_equal(fv_renderer_frame_input(g_r, &h, g_frame_id++, 0.0, &in), FV_OK);
            in.quality.fovea.enabled = true;
            in.quality.fovea.mar_slope = 0.2f;
            in.quality.fovea.temporal = 8u;
            in.quality.fovea.recon = methods[mi];
            set_gaze(&in, fv_v3(0, 0, -1), 0.5f);
            assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        }
        assert_int_equal(fv_renderer_finish(g_r), FV_OK);
        size_t filled = 0, known = 0, reused = 0;
        for (int e = 0; e < 2; e++) {
            assert_int_equal(fv_renderer_read_linear(g_r, e, rgba, NPIX * 4), FV_OK);
            assert_int_equal(fv_renderer_read_image(g_r, "fovea mask", e, mask, NPIX * 4, 4), FV_OK);
            assert_int_equal(fv_renderer_read_image(g_r, "gbuffer fovea surface", e, surf, NPIX * 16, 16), FV_OK);
            assert_int_equal(fv_renderer_read_image(g_r, "gbuffer depth", e, g->depth, sizeof g->depth, 4), FV_OK);
            assert_int_equal(fv_renderer_read_image(g_r, "gbuffer normal (oct)", e, g->normal, sizeof g->normal, 4),
                             FV_OK);
            assert_int_equal(fv_renderer_read_image(g_r, "gbuffer material id", e, g->material, sizeof g->material, 2),
                             FV_OK);
            assert_int_equal(fv_renderer_read_motion(g_r, e, g->motion, NPIX * 2), FV_OK);
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    size_t i = (size_t)y * W + x;
                    uint32_t bits;
                    memcpy(&bits, &rgba[i * 4 + 3], 4);
                    bool drawn = g->material[i] != 0;
                    /* the surface target: motion, distance (0 = nothing drawn) and the normal's bits */
                    for (int c = 0; c < 2; c++) /* the motion target holds the same as a half float */
                        assert_true(fabs(surf[i * 4 + c] - g->motion[2 * i + c]) <= 1e-3 * fabs(surf[i * 4 + c]) + 1e-7);
                    if (!drawn) {
                        assert_true(surf[i * 4 + 2] == 0.0f);
                    } else {
                        double want = dist_of(&in, e, g, x, y);
                        if (!(fabs(surf[i * 4 + 2] - want) <= 1e-4 * want))
                            fail_msg("%s eye %d (%d,%d): surface target's distance %.9g, from the depth %.9g",
                                     name[mi], e, x, y, surf[i * 4 + 2], want);
                        uint32_t nb;
                        memcpy(&nb, &surf[i * 4 + 3], 4);
                        assert_int_equal((int16_t)(nb & 0xffffu), g->normal[i][0]);
                        assert_int_equal((int16_t)(nb >> 16), g->normal[i][1]);
                    }
                    if (mask[i] == FV_SAMPLE_MASK_UNKNOWN) { /* filled: nothing known */
                        if (bits != 0u)
                            fail_msg("%s eye %d (%d,%d): filled pixel's alpha 0x%08x, not 0",
                                     name[mi], e, x, y, bits);
                        filled++;
                        continue;
                    }
                    known++;
                    reused += mask[i] == FV_SAMPLE_MASK_REUSED;
                    assert_true(bits != 0u);
                    assert_true((bits & FV_TEMPORAL_AGE_MAX) <= 8u);
                    float d;
                    uint32_t db = bits & ~FV_TEMPORAL_AGE_MAX;
                    memcpy(&d, &db, 4);
                    if (!drawn) {
                        assert_true(d >= 0.5f * (float)FV_TEMPORAL_SKY);
                    } else if (!(fabs(d - surf[i * 4 + 2]) <= 1e-5 * surf[i * 4 + 2])) {
                        fail_msg("%s eye %d (%d,%d): known pixel's distance %.9g, the G-buffer's %.9g",
                                 name[mi], e, x, y, d, surf[i * 4 + 2]);
                    }
                }
        }
        printf("%s: %zu filled (alpha 0), %zu known (%zu reused) with their distance and age\n",
               name[mi], filled, known, reused);
        assert_true(filled > 1000 && reused > 1000);
    }
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    free(g), free(rgba), free(surf), free(mask);
    fv_scene_destroy(&s);
}

/* p with saliency (weight sal) and DoF (fovea_interface.h), in double; the focus pixel is picked with the GPU's
 * float arithmetic (a discrete choice). */
static double ref_p_sal_dof(const fv_frame_input *in, int e, const gbuf *g, int x, int y, double u_rad, bool valid,
                            double sal, bool dof)
{
    const fv_eye_view *v = &in->eye[e];
    const fv_quality_fovea *q = &in->quality.fovea;
    double uu = (x + 0.5) / W, tt = (y + 0.5) / H;
    double r[3] = {v->tan_left + uu * ((double)v->tan_right - v->tan_left),
                   v->tan_up + tt * ((double)v->tan_down - v->tan_up), -1.0};
    double gd[3] = {0, 0, -1};
    if (valid) {
        fv_vec3 d = in->gaze[e].dir_eye;
        double len = sqrt((double)d.x * d.x + (double)d.y * d.y + (double)d.z * d.z);
        gd[0] = d.x / len, gd[1] = d.y / len, gd[2] = d.z / len;
    }
    double c[3] = {r[1] * gd[2] - r[2] * gd[1], r[2] * gd[0] - r[0] * gd[2], r[0] * gd[1] - r[1] * gd[0]};
    double ecc = atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), r[0] * gd[0] + r[1] * gd[1] + r[2] * gd[2]);
    double ep = fmax(0.0, ecc - (valid ? u_rad : 15.0 * DEG));
    double dtx = fabs((double)v->tan_right - v->tan_left) / W, dty = fabs((double)v->tan_down - v->tan_up) / H;
    double w_px = 2.0 * atan(0.5 * fmin(dtx, dty)) / DEG;
    double w0 = q->mar_w0_deg, w = q->mar_slope * ep / DEG + w0, w_min = fmax(w0, w_px), w_far = 3.0 * w_px;
    size_t i = (size_t)y * W + x;
    bool hit = g->material[i] != 0;
    double blur = 0;
    if (dof && in->pupil_mm > 0 && in->pupil_mm <= 20 && valid && gd[2] < 0) {
        fv_vec3 d = in->gaze[e].dir_eye;
        float len = sqrtf(d.x * d.x + d.y * d.y + d.z * d.z);
        float dx = d.x / len, dy = d.y / len, dz = d.z / len;
        float fu = (dx / -dz - v->tan_left) / (v->tan_right - v->tan_left);
        float fv = (dy / -dz - v->tan_up) / (v->tan_down - v->tan_up);
        if (fu >= 0 && fv >= 0 && fu < 1 && fv < 1) {
            int fx = (int)(fu * W), fy = (int)(fv * H);
            fx = fx < W - 1 ? fx : W - 1, fy = fy < H - 1 ? fy : H - 1;
            if (g->material[(size_t)fy * W + fx]) {
                double df = fmax(dist_of(in, e, g, fx, fy), 1e-3);
                double inv = hit ? 1.0 / fmax(dist_of(in, e, g, x, y), 1e-3) : 0.0;
                blur = fmin(in->pupil_mm * 1e-3 * fabs(inv - 1.0 / df) / DEG, 180.0);
            }
        }
    }
    double pm = 1.0 - (fmax(w, blur) - w_min) / w_far;
    if (sal > 0) {
        double sa = 0, sn = 0, lp[3], np[3];
        lab_of(g->albedo[i], lp);
        normal_of(g->normal[i], np);
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                int qx = x + dx, qy = y + dy;
                if ((!dx && !dy) || qx < 0 || qy < 0 || qx >= W || qy >= H) continue;
                size_t k = (size_t)qy * W + qx;
                bool qhit = g->material[k] != 0;
                if (qhit != hit) {
                    sn = 1.0;
                    continue;
                }
                if (!hit) continue;
                double lq[3], nq[3];
                lab_of(g->albedo[k], lq);
                normal_of(g->normal[k], nq);
                sa = fmax(sa, sqrt((lp[0] - lq[0]) * (lp[0] - lq[0]) + (lp[1] - lq[1]) * (lp[1] - lq[1]) +
                                   (lp[2] - lq[2]) * (lp[2] - lq[2])));
                sn = fmax(sn, 1.0 - (np[0] * nq[0] + np[1] * nq[1] + np[2] * nq[2]));
            }
        /* a static scene drawn again with the same views: all motion is the head's (none) */
        double sv = hit ? hypot(g->motion[2 * i] * W, g->motion[2 * i + 1] * H) / 4.0 : 0.0;
        double sal_s = fmin(1.0, fmax(fmax(sa / 25.0, sn / 0.5), sv));
        double seen = fmin(1.0, fmax(0.0, 1.0 - (blur - w_min) / w_far));
        pm = fmax(pm, sal * sal_s * seen);
    }
    return fmin(1.0, fmax((double)q->min_prob, pm));
}

static void saliency_and_dof_match_cpu(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    gbuf *g = malloc(sizeof *g);
    float *prob = malloc(NPIX * 4);
    assert_true(g && prob);
    fv_frame_input in = frame_in();
    fv_vec3 corner = fv_v3_normalize_or(fv_v3(in.eye[0].tan_left, in.eye[0].tan_up, -1.0f), fv_v3(0, 0, -1));
    const gaze_case cases[] = {
        {"left 10 deg", fv_v3_normalize_or(fv_v3(-0.17f, 0.05f, -1.0f), fv_v3(0, 0, -1)), true, 12.0f, 0.5f},
        {"centre, no pupil", fv_v3(0, 0, -1), true, 0.0f, 0.5f},
        {"low right", fv_v3_normalize_or(fv_v3(0.2f, -0.3f, -1.0f), fv_v3(0, 0, -1)), true, 12.0f, 0.0f},
        {"image corner", corner, true, 12.0f, 0.0f},
        {"off-screen", fv_v3_normalize_or(fv_v3(3.0f, -2.0f, -1.0f), fv_v3(0, 0, -1)), true, 12.0f, 1.0f},
        {"NaN", fv_v3(NAN, 0, -1), true, 12.0f, 1.0f},
        {"lost", fv_v3(0, 0, -1), false, 12.0f, 1.0f},
    };
    const double sal_w[] = {1.0, 0.5, 0.0};
    double worst = 0, raised = 0, lowered = 0;
    /* Then with a telephoto view (tangents x 0.06, 0.07 degrees a pixel), where a 12 mm pupil's defocus blur exceeds
     * the MAR off the focal plane, as it does at headset resolutions: gazes on the near box and on the back wall. */
    const gaze_case tele[] = {
        {"tele centre", fv_v3(0, 0, -1), true, 12.0f, 0.0f},
        {"tele lower left", fv_v3_normalize_or(fv_v3(-0.03f, -0.03f, -1.0f), fv_v3(0, 0, -1)), true, 12.0f, 0.0f},
        {"tele no pupil", fv_v3(0, 0, -1), true, 0.0f, 0.0f},
    };
    size_t nc = sizeof cases / sizeof cases[0], nt = sizeof tele / sizeof tele[0];
    for (size_t k = 0; k < nc + nt; k++)
        for (int sw = 0; sw < 3; sw++) {
            const gaze_case *c = k < nc ? &cases[k] : &tele[k - nc];
            for (int rep = 0; rep < 2; rep++) { /* twice: the second frame's motion is that of the same views */
                in = frame_in();
                for (int e = 0; e < 2 && k >= nc; e++) {
                    fv_eye_view *v = &in.eye[e];
                    v->tan_left *= 0.06f, v->tan_right *= 0.06f, v->tan_up *= 0.06f, v->tan_down *= 0.06f;
                    v->proj = fv_mat4_perspective_tan(v->tan_left, v->tan_right, v->tan_up, v->tan_down, v->near_m,
                                                      v->far_m);
                }
                in.pupil_mm = c->pupil_mm;
                set_gaze(&in, c->dir, c->unc_deg);
                for (int e = 0; e < 2; e++) in.gaze[e].valid = c->valid;
                in.quality.fovea.mar_slope = 0.2f;
                in.quality.fovea.saliency = (float)sal_w[sw];
                in.quality.fovea.dof = sw != 2 || k % 2 == 0;
                if (k >= nc) in.quality.fovea.mar_slope = 0.022f;
                in.quality.debug_view = FV_DEBUG_VIEW_PROB; /* p is stored for its readers only */
                assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
            }
            bool valid = c->valid && isfinite(c->dir.x);
            for (int e = 0; e < 2; e++) {
                assert_int_equal(fv_renderer_read_image(g_r, "fovea prob", e, prob, NPIX * 4, 4), FV_OK);
                assert_int_equal(fv_renderer_read_image(g_r, "gbuffer depth", e, g->depth, sizeof g->depth, 4), FV_OK);
                assert_int_equal(fv_renderer_read_image(g_r, "gbuffer normal (oct)", e, g->normal, sizeof g->normal, 4),
                                 FV_OK);
                assert_int_equal(fv_renderer_read_image(g_r, "gbuffer albedo", e, g->albedo, sizeof g->albedo, 4), FV_OK);
                assert_int_equal(fv_renderer_read_image(g_r, "gbuffer material id", e, g->material, sizeof g->material, 2),
                                 FV_OK);
                assert_int_equal(fv_renderer_read_motion(g_r, e, g->motion, NPIX * 2), FV_OK);
                for (int y = 0; y < H; y++)
                    for (int x = 0; x < W; x++) {
                        float got = prob[(size_t)y * W + x];
                        if (!isfinite(got)) fail_msg("%s eye %d (%d, %d): p %f", c->name, e, x, y, got);
                        double want = ref_p_sal_dof(&in, e, g, x, y, c->unc_deg * DEG, valid, sal_w[sw],
                                                    in.quality.fovea.dof);
                        double plain = ref_p(&in, e, x, y, c->unc_deg * DEG, valid);
                        raised += want > plain + 1e-3;
                        lowered += want < plain - 1e-3;
                        double err = fabs(got - want);
                        worst = fmax(worst, err);
                        if (!(err <= P_TOL))
                            fail_msg("%s, saliency %.1f, dof %d, eye %d (%d, %d): p gpu %.6f cpu %.6f (without: %.6f)",
                                     c->name, sal_w[sw], in.quality.fovea.dof, e, x, y, got, want, plain);
                    }
            }
        }
    print_message("saliency + DoF: worst p error %.2e; pixels raised by saliency %.0f, lowered by DoF %.0f\n", worst,
                  raised, lowered);
    assert_true(raised > 100 && lowered > 100); /* both terms act on this scene */
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    free(g);
    free(prob);
    fv_scene_destroy(&s);
}


/* ---- the soft fill (fovea.recon=soft) ---------------------------------------------------------------------------- */

/* The inverse of a 4x4 column-major matrix (m[c][r]) in double, by Gauss-Jordan with partial pivoting. */
static bool inverse4(double a[4][4], double out[4][4])
{
    double m[4][8];
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 8; c++) m[r][c] = c < 4 ? a[c][r] : (c - 4 == r);
    for (int c = 0; c < 4; c++) {
        int piv = c;
        for (int r = c + 1; r < 4; r++)
            if (fabs(m[r][c]) > fabs(m[piv][c])) piv = r;
        if (fabs(m[piv][c]) < 1e-300) return false;
        for (int k = 0; k < 8; k++) {
            double t = m[c][k];
            m[c][k] = m[piv][k], m[piv][k] = t;
        }
        double d = m[c][c];
        for (int k = 0; k < 8; k++) m[c][k] /= d;
        for (int r = 0; r < 4; r++)
            if (r != c) {
                double f = m[r][c];
                for (int k = 0; k < 8; k++) m[r][k] -= f * m[c][k];
            }
    }
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) out[c][r] = m[r][c + 4];
    return true;
}

/* What the soft fill reads of one eye: the frame's known colours, the mask, the G-buffer as world positions and
 * normals (double). */
typedef struct soft_in {
    int w, h, B;
    const float *rgba;
    const uint32_t *mask;
    double (*pos)[3], (*nrm)[3];
    bool *hit;
    const uint16_t *material; /* the G-buffer's material id: index + 1, 0 nothing drawn */
    double eye[3], w_px;
} soft_in;

static void soft_in_fill(soft_in *si, const fv_frame_input *in, int e, const float *depth, int16_t (*oct)[2],
                         const uint16_t *material)
{
    const fv_eye_view *v = &in->eye[e];
    double vp[4][4], inv[4][4];
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            vp[c][r] = 0;
            for (int k = 0; k < 4; k++) vp[c][r] += (double)v->proj.m[k][r] * v->view.m[c][k];
        }
    assert_true(inverse4(vp, inv));
    for (int y = 0; y < si->h; y++)
        for (int x = 0; x < si->w; x++) {
            size_t i = (size_t)y * si->w + x;
            double ndc[4] = {(x + 0.5) / si->w * 2.0 - 1.0, (y + 0.5) / si->h * 2.0 - 1.0, depth[i], 1.0}, wp[4];
            for (int r = 0; r < 4; r++) {
                wp[r] = 0;
                for (int c = 0; c < 4; c++) wp[r] += inv[c][r] * ndc[c];
            }
            for (int k = 0; k < 3; k++) si->pos[i][k] = wp[k] / wp[3];
            si->hit[i] = material[i] != 0;
            normal_of(oct[i], si->nrm[i]);
        }
    si->material = material;
    si->eye[0] = v->pos_world.x, si->eye[1] = v->pos_world.y, si->eye[2] = v->pos_world.z;
    double dtx = fabs((double)v->tan_right - v->tan_left) / si->w, dty = fabs((double)v->tan_down - v->tan_up) / si->h;
    si->w_px = 2.0 * atan(0.5 * fmin(dtx, dty));
}

/* The slots of block (bx, by) (fovea_interface.h SOFT_REPS): per quadrant the known pixel nearest its centre (of the
 * whole block; ties: the first in row order), as pixel indices; returns the block's known pixels. */
static int soft_slots_of(const soft_in *si, int bx, int by, size_t out[FV_RECON_SOFT_SLOTS])
{
    int B = si->B, sx = si->w - bx * B < B ? si->w - bx * B : B, sy = si->h - by * B < B ? si->h - by * B : B;
    int count = 0, bestd[FV_RECON_SOFT_SLOTS];
    for (int q = 0; q < FV_RECON_SOFT_SLOTS; q++) out[q] = SIZE_MAX, bestd[q] = 1 << 30;
    for (int ly = 0; ly < sy; ly++)
        for (int lx = 0; lx < sx; lx++) {
            size_t i = (size_t)(by * B + ly) * si->w + bx * B + lx;
            if (!si->mask[i]) continue;
            count++;
            for (int q = 0; q < FV_RECON_SOFT_SLOTS; q++) {
                int dx = 4 * lx + 2 - (2 * (q & 1) + 1) * sx, dy = 4 * ly + 2 - (2 * (q >> 1) + 1) * sy;
                if (dx * dx + dy * dy < bestd[q]) bestd[q] = dx * dx + dy * dy, out[q] = i;
            }
        }
    return count;
}

/* sigma of block (bx, by) (fovea_interface.h SOFT_REPS): FV_RECON_SOFT_SIGMA times sqrt(area / known pixels) of the
 * 3x3 blocks around it, at least FV_RECON_SOFT_SIGMA_MIN. */
static double soft_sigma_of(const soft_in *si, int bx0, int by0)
{
    int B = si->B, nbx = (si->w + B - 1) / B, nby = (si->h + B - 1) / B;
    double known = 0, area = 0;
    for (int by = by0 - 1; by <= by0 + 1; by++)
        for (int bx = bx0 - 1; bx <= bx0 + 1; bx++) {
            if (bx < 0 || by < 0 || bx >= nbx || by >= nby) continue;
            int sx = si->w - bx * B < B ? si->w - bx * B : B, sy = si->h - by * B < B ? si->h - by * B : B;
            size_t idx[FV_RECON_SOFT_SLOTS];
            known += soft_slots_of(si, bx, by, idx);
            area += sx * sy;
        }
    return fmax(FV_RECON_SOFT_SIGMA * sqrt(area / fmax(known, 1.0)), FV_RECON_SOFT_SIGMA_MIN);
}

/* One tap of the soft fill at pixel pi (fovea_interface.h SOFT_FILL): adds its weight (tent, Gaussian of
 * 1 / (2 sigma^2) = inv2s2, edge weight) and weighted colour, keeps the nearest tap; returns the edge exponent. */
static double soft_tap_ref(const soft_in *si, size_t pi, size_t qi, double tent, double inv2s2, double sum[3],
                           double *wsum, long *bd, uint32_t *best)
{
    int x = (int)(pi % (size_t)si->w), y = (int)(pi / (size_t)si->w);
    int xx = (int)(qi % (size_t)si->w), yy = (int)(qi / (size_t)si->w);
    long d2 = (long)(xx - x) * (xx - x) + (long)(yy - y) * (yy - y);
    uint32_t packed = (uint32_t)xx | ((uint32_t)yy << 16);
    if (*bd < 0 || d2 < *bd || (d2 == *bd && packed < *best)) *bd = d2, *best = packed;
    double g, cap = -log(FV_RECON_SOFT_EDGE_FLOOR);
    const double *pp = si->pos[pi], *pn = si->nrm[pi];
    if (si->hit[pi] != si->hit[qi] || si->material[pi] != si->material[qi]) g = cap; /* nothing, another material */
    else if (!si->hit[pi]) g = 0;
    else {
        double dist = sqrt((pp[0] - si->eye[0]) * (pp[0] - si->eye[0]) + (pp[1] - si->eye[1]) * (pp[1] - si->eye[1]) +
                           (pp[2] - si->eye[2]) * (pp[2] - si->eye[2]));
        double foot = dist * si->w_px;
        const double *qp = si->pos[qi], *qn = si->nrm[qi];
        double pl = fabs(qn[0] * (pp[0] - qp[0]) + qn[1] * (pp[1] - qp[1]) + qn[2] * (pp[2] - qp[2]));
        double e = pl / (foot * sqrt(fmax((double)d2, 1.0)) * FV_RECON_SOFT_PLANE); /* off the tap's tangent plane */
        g = fmin(e * e + (1.0 - (pn[0] * qn[0] + pn[1] * qn[1] + pn[2] * qn[2])) / FV_RECON_SOFT_NORMAL, cap);
    }
    double wt = tent * exp(-(double)d2 * inv2s2 - g);
    for (int c = 0; c < 3; c++) sum[c] += wt * si->rgba[qi * 4 + c];
    *wsum += wt;
    return g;
}

/* The soft fill of unknown pixel (x, y) in double (fovea_interface.h SOFT_FILL): the 2x2 blocks whose centres
 * surround the pixel, each by its bilinear tent; of each its slot facing the pixel (sigma at least
 * FV_RECON_SOFT_SIGMA times half a block), or, when one of those has an edge exponent over FV_RECON_SOFT_EDGE_SPLIT,
 * all its distinct slots (sigma: the tents' blend of the blocks' sigmas). */
static void soft_ref(const soft_in *si, int x, int y, double out[3])
{
    int B = si->B, nbx = (si->w + B - 1) / B, nby = (si->h + B - 1) / B;
    double gx = (x + 0.5) / B - 0.5, gy = (y + 0.5) / B - 0.5;
    int bx0 = (int)floor(gx), by0 = (int)floor(gy);
    double fx = gx - bx0, fy = gy - by0, tent[4], ssum = 0, tsum = 0;
    size_t slots[4][FV_RECON_SOFT_SLOTS];
    for (int k = 0; k < 4; k++) {
        int bx = bx0 + (k & 1), by = by0 + (k >> 1);
        tent[k] = ((k & 1) ? fx : 1.0 - fx) * ((k >> 1) ? fy : 1.0 - fy);
        if (bx < 0 || by < 0 || bx >= nbx || by >= nby || tent[k] <= 0) {
            tent[k] = 0;
            continue;
        }
        soft_slots_of(si, bx, by, slots[k]);
        ssum += tent[k] * soft_sigma_of(si, bx, by);
        tsum += tent[k];
    }
    assert_true(tsum > 0);
    double sigma_d = ssum / tsum, sf = fmax(sigma_d, FV_RECON_SOFT_SIGMA * 0.5 * B), emax = 0;
    size_t pi = (size_t)y * si->w + x;
    double sum[3] = {0, 0, 0}, wsum = 0;
    long bd = -1;
    uint32_t best = NONE;
    for (int k = 0; k < 4; k++) {
        if (tent[k] <= 0) continue;
        size_t qi = slots[k][(1 - (k & 1)) + 2 * (1 - (k >> 1))]; /* the quadrant facing the pixel */
        assert_true(qi != SIZE_MAX);                               /* every block holds a sample */
        emax = fmax(emax, soft_tap_ref(si, pi, qi, tent[k], 0.5 / (sf * sf), sum, &wsum, &bd, &best));
    }
    if (emax > FV_RECON_SOFT_EDGE_SPLIT) {
        sum[0] = sum[1] = sum[2] = wsum = 0;
        for (int k = 0; k < 4; k++) {
            if (tent[k] <= 0) continue;
            for (int q = 0; q < FV_RECON_SOFT_SLOTS; q++) {
                bool dup = false;
                for (int r = 0; r < q; r++) dup = dup || slots[k][r] == slots[k][q];
                if (!dup) soft_tap_ref(si, pi, slots[k][q], tent[k], 0.5 / (sigma_d * sigma_d), sum, &wsum, &bd, &best);
            }
        }
    }
    assert_true(best != NONE);
    for (int k = 0; k < 3; k++)
        out[k] = wsum > 1e-30 ? sum[k] / wsum : si->rgba[((size_t)(best >> 16) * si->w + (best & 0xffffu)) * 4 + k];
}

/* The soft fill on the GPU against soft_ref in double, both eyes, blocks of 4, 5 and 7 (reach 1 and 2; blocks cut
 * by the image edge at 5 and 7: 96 x 80 px), gazes at the centre and off to the side. */
static void soft_matches_cpu_double(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    float *rgba = malloc(NPIX * 16), *depth = malloc(NPIX * 4);
    uint32_t *mask = malloc(NPIX * 4);
    int16_t(*oct)[2] = malloc(NPIX * 4);
    uint16_t *material = malloc(NPIX * 2);
    double(*pos)[3] = malloc(NPIX * sizeof *pos), (*nrm)[3] = malloc(NPIX * sizeof *nrm);
    bool *hit = malloc(NPIX);
    assert_true(rgba && depth && mask && oct && material && pos && nrm && hit);
    const uint32_t blocks[] = {4, 5, 7};
    const fv_vec3 gazes[] = {fv_v3(0, 0, -1), fv_v3_normalize_or(fv_v3(0.3f, -0.1f, -1.0f), fv_v3(0, 0, -1))};
    double filled = 0, close = 0, worst = 0, sum_err = 0;
    for (int bi = 0; bi < 3; bi++)
        for (int gi = 0; gi < 2; gi++) {
            fv_frame_input in = frame_in();
            set_gaze(&in, gazes[gi], 0.5f);
            in.quality.fovea.mar_slope = 0.3f;
            in.quality.fovea.block = blocks[bi];
            in.quality.fovea.temporal = 0;
            in.quality.fovea.recon = FV_FOVEA_RECON_SOFT;
            assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
            for (int e = 0; e < 2; e++) {
                assert_int_equal(fv_renderer_read_linear(g_r, e, rgba, NPIX * 4), FV_OK);
                assert_int_equal(fv_renderer_read_image(g_r, "fovea mask", e, mask, NPIX * 4, 4), FV_OK);
                assert_int_equal(fv_renderer_read_image(g_r, "gbuffer depth", e, depth, NPIX * 4, 4), FV_OK);
                assert_int_equal(fv_renderer_read_image(g_r, "gbuffer normal (oct)", e, oct, NPIX * 4, 4), FV_OK);
                assert_int_equal(fv_renderer_read_image(g_r, "gbuffer material id", e, material, NPIX * 2, 2), FV_OK);
                soft_in si = {.w = W, .h = H, .B = (int)blocks[bi], .rgba = rgba, .mask = mask, .pos = pos,
                              .nrm = nrm, .hit = hit};
                soft_in_fill(&si, &in, e, depth, oct, material);
                for (int y = 0; y < H; y++)
                    for (int x = 0; x < W; x++) {
                        const float *got = &rgba[((size_t)y * W + x) * 4];
                        for (int k = 0; k < 3; k++) assert_true(isfinite(got[k]));
                        if (mask[(size_t)y * W + x]) continue;
                        double want[3], err = 0;
                        soft_ref(&si, x, y, want);
                        for (int k = 0; k < 3; k++) err = fmax(err, fabs(got[k] - want[k]) / fmax(1e-2, fabs(want[k])));
                        filled++;
                        close += err <= 1e-3;
                        sum_err += err;
                        worst = fmax(worst, err);
                    }
            }
        }
    print_message("soft: %.0f filled pixels, %.3f%% within 1e-3 of the CPU in double, mean rel error %.2e, worst "
                  "%.2e\n", filled, 100.0 * close / filled, sum_err / filled, worst);
    assert_true(filled > 1000);
    assert_true(close / filled >= 0.995);
    assert_true(sum_err / filled <= 1e-4);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    free(rgba), free(depth), free(mask), free(oct), free(material), free(pos), free(nrm), free(hit);
    fv_scene_destroy(&s);
}

/* A head turning (yaw 0.5 degrees and 3 mm sideways per frame) with the gaze held at the centre and temporal reuse
 * on (fovea.temporal=8, balanced): the flicker of the periphery (> 5 degrees), the mean squared frame-to-frame
 * change of (reconstructed - full resolution) in sRGB, is under half of nearest's with the soft fill, and its PSNR
 * against full resolution 3 dB higher; every variant's numbers are printed (BENCHMARKS.md quotes them). The fill
 * alone: temporal reuse off. */
#define F_FRAMES 8
static void soft_fill_flickers_less_than_nearest(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    enum { MODES = FV_FOVEA_RECON_LAST + 2, FULL = FV_FOVEA_RECON_LAST + 1 };
    static const char *const name[MODES] = {"nearest", "sibson", "idw", "soft", "full"};
    float *img[MODES][2], *prev[MODES][2], *ecc[2];
    for (int m = 0; m < MODES; m++)
        for (int e = 0; e < 2; e++) {
            img[m][e] = malloc(NPIX * 16), prev[m][e] = malloc(NPIX * 16);
            assert_true(img[m][e] && prev[m][e]);
        }
    ecc[0] = malloc(NPIX * 4), ecc[1] = malloc(NPIX * 4);
    assert_true(ecc[0] && ecc[1]);
    fv_vec3 gaze = fv_v3(0, 0, -1);
    double flicker[MODES] = {0}, mse[MODES] = {0}, n = 0, nf = 0;
    /* each mode's sequence in turn (the temporal history is the mode's own), frame k against full frame k */
    for (int k = 0; k < F_FRAMES; k++) {
        for (int m = MODES - 1; m >= 0; m--) {
            fv_head h = head_at(s, k, 0.5);
            fv_frame_input in;
            assert_int_equal(fv_renderer_frame_input(g_r, &h, g_frame_id++, 0.0, &in), FV_OK);
            in.quality.fovea.enabled = m != FULL;
            in.quality.fovea.recon = m == FULL ? FV_FOVEA_RECON_NEAREST : (fv_fovea_recon)m;
            in.quality.fovea.temporal = 0; /* the fill alone: mixing the modes' frames breaks each one's history */
            in.quality.fovea.mar_slope = 0.1f;
            set_gaze(&in, gaze, 0.5f);
            assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
            assert_int_equal(fv_renderer_finish(g_r), FV_OK);
            for (int e = 0; e < 2; e++) {
                float *t = prev[m][e];
                prev[m][e] = img[m][e], img[m][e] = t;
                assert_int_equal(fv_renderer_read_linear(g_r, e, img[m][e], NPIX * 4), FV_OK);
                if (k == 0) fv_metrics_eccentricity_deg(&in.eye[e], gaze, W, H, ecc[e], W);
            }
        }
        for (int e = 0; e < 2; e++)
            for (size_t i = 0; i < NPIX; i++) {
                if (!(ecc[e][i] > 5.0f)) continue;
                for (int c = 0; c < 3; c++) {
                    double full = fv_metrics_linear_to_srgb(img[FULL][e][i * 4 + c]);
                    double full_prev = fv_metrics_linear_to_srgb(prev[FULL][e][i * 4 + c]);
                    for (int m = 0; m < FULL; m++) {
                        assert_true(isfinite(img[m][e][i * 4 + c]));
                        double err = fv_metrics_linear_to_srgb(img[m][e][i * 4 + c]) - full;
                        mse[m] += err * err;
                        if (k == 0) continue;
                        double err_prev = fv_metrics_linear_to_srgb(prev[m][e][i * 4 + c]) - full_prev;
                        flicker[m] += (err - err_prev) * (err - err_prev);
                    }
                    n++;
                    nf += k > 0;
                }
            }
    }
    for (int m = 0; m < FULL; m++) {
        print_message("turning head, periphery (> 5 deg): %-8s PSNR %.2f dB vs full resolution, flicker %.3e\n",
                      name[m], fv_metrics_psnr_db(mse[m] / n), flicker[m] / nf);
    }
    /* margins far beyond what frame-to-frame pattern changes alone make of the same fill */
    assert_true(flicker[FV_FOVEA_RECON_SOFT] < 0.5 * flicker[FV_FOVEA_RECON_NEAREST]);
    assert_true(fv_metrics_psnr_db(mse[FV_FOVEA_RECON_SOFT] / n) > fv_metrics_psnr_db(mse[FV_FOVEA_RECON_NEAREST] / n) + 3.0);
    for (int m = 0; m < MODES; m++)
        for (int e = 0; e < 2; e++) free(img[m][e]), free(prev[m][e]);
    free(ecc[0]), free(ecc[1]);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    fv_scene_destroy(&s);
}

/* Every fill finite (no NaN or Inf anywhere in the colour) at the extremes: blocks 2 and 16, xi 0.01 and 1 (and 0,
 * which the renderer replaces), gazes at the centre, off the image and lost, at 96 x 80 and on a second renderer of
 * 13 x 7 px (odd, smaller than a block of 16). */
static void check_finite(fv_renderer *r, uint32_t w, uint32_t h, const fv_scene *s, float *rgba)
{
    const uint32_t blocks[] = {2, 16};
    const float xis[] = {0.01f, 1.0f, 0.0f};
    const fv_vec3 gazes[] = {fv_v3(0, 0, -1), fv_v3_normalize_or(fv_v3(3.0f, -2.0f, -1.0f), fv_v3(0, 0, -1)),
                             fv_v3(0, 0, -1)};
    for (int b = 0; b < 2; b++)
        for (int rc = 0; rc <= FV_FOVEA_RECON_LAST; rc++)
            for (int x = 0; x < 3; x++)
                for (int g = 0; g < 3; g++) {
                    fv_frame_input in;
                    assert_int_equal(fv_renderer_frame_input(r, &s->head, g_frame_id++, 0.0, &in), FV_OK);
                    in.quality.fovea.enabled = true;
                    in.quality.fovea.block = blocks[b];
                    in.quality.fovea.recon = (fv_fovea_recon)rc;
                    in.quality.fovea.min_prob = xis[x];
                    set_gaze(&in, gazes[g], 0.5f);
                    if (g == 2) in.gaze[0].valid = in.gaze[1].valid = false;
                    assert_int_equal(fv_renderer_draw(r, &in), FV_OK);
                    for (int e = 0; e < 2; e++) {
                        assert_int_equal(fv_renderer_read_linear(r, e, rgba, (size_t)w * h * 4), FV_OK);
                        for (size_t i = 0; i < (size_t)w * h * 4; i++)
                            if (!isfinite(rgba[i])) fail_msg("%ux%u block %u recon %d xi %g gaze %d eye %d: value %zu "
                                                             "is %g", w, h, blocks[b], rc, (double)xis[x], g, e, i,
                                                             (double)rgba[i]);
                    }
                }
}

static void every_fill_finite_at_extremes(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    float *rgba = malloc(NPIX * 16);
    assert_non_null(rgba);
    check_finite(g_r, W, H, s, rgba);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    fv_renderer *small = NULL;
    assert_int_equal(fv_gpu_test_setup(13, 7, &small), 0);
    assert_non_null(small);
    fv_scene *s2 = fv_gpu_test_load_scene(small, "cornell");
    check_finite(small, 13, 7, s2, rgba);
    assert_int_equal(fv_renderer_validation_messages(small), 0);
    assert_int_equal(fv_gpu_test_teardown(&small), 0);
    fv_scene_destroy(&s2);
    free(rgba);
    fv_scene_destroy(&s);
}

/* The sampling map compiles the G-buffer's reads in only where they act (fovea.comp USE_GBUFFER; on llvmpipe their
 * presence costs ~10x the rest of the pass): the variant without them runs with saliency 0 and DoF on but no pupil
 * size (or DoF off), the other with saliency or with DoF and a pupil; and it stores p ("fovea prob", WRITE_PROB: a
 * store per pixel) only while a reader of it runs: the views of foveation or the overlay. The pass reports which
 * variant ran. */
static double map_variant(const char *key, float saliency, bool dof, float pupil_mm, fv_debug_view view, bool overlay)
{
    fv_frame_input in = frame_in();
    in.quality.fovea.saliency = saliency;
    in.quality.fovea.dof = dof;
    in.quality.debug_view = view;
    in.quality.overlay = overlay;
    in.pupil_mm = pupil_mm;
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    fv_pass_detail d[8];
    uint32_t n = fv_renderer_pass_details(g_r, "fovea", d, 8);
    for (uint32_t i = 0; i < n; i++)
        if (strcmp(d[i].key, key) == 0) return d[i].value[0];
    fail_msg("the fovea pass reports no %s", key);
    return -1;
}

static double map_reads_gbuffer(float saliency, bool dof, float pupil_mm)
{
    return map_variant("reads_gbuffer", saliency, dof, pupil_mm, FV_DEBUG_VIEW_NONE, false);
}

static double map_stores_p(fv_debug_view view, bool overlay, float saliency)
{
    return map_variant("stores_p", saliency, true, NAN, view, overlay);
}

static void map_reads_gbuffer_only_when_needed(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    assert_true(map_reads_gbuffer(0.0f, true, NAN) == 0);   /* balanced without a tracker: DoF has no pupil */
    assert_true(map_reads_gbuffer(0.0f, true, 0.0f) == 0);
    assert_true(map_reads_gbuffer(0.0f, true, 25.0f) == 0); /* beyond FV_GPU_PUPIL_MAX_MM: unknown */
    assert_true(map_reads_gbuffer(0.0f, false, 4.0f) == 0);
    assert_true(map_reads_gbuffer(0.0f, true, 4.0f) == 1);
    assert_true(map_reads_gbuffer(0.5f, false, NAN) == 1);
    /* p: not stored for the image alone, nor for a view that does not show it; stored for each of its readers, with
     * and without the G-buffer's reads; and not again once they are gone */
    assert_true(map_stores_p(FV_DEBUG_VIEW_NONE, false, 0.0f) == 0);
    assert_true(map_stores_p(FV_DEBUG_VIEW_NORMAL, false, 0.0f) == 0);
    assert_true(map_stores_p(FV_DEBUG_VIEW_PROB, false, 0.0f) == 1);
    assert_true(map_stores_p(FV_DEBUG_VIEW_SAMPLES, false, 0.5f) == 1);
    assert_true(map_stores_p(FV_DEBUG_VIEW_VORONOI, false, 0.0f) == 1);
    assert_true(map_stores_p(FV_DEBUG_VIEW_NONE, true, 0.0f) == 1);
    assert_true(map_stores_p(FV_DEBUG_VIEW_NONE, false, 0.5f) == 0);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    fv_scene_destroy(&s);
}

/* The soft fill respects material edges: an emissive light is in its ceiling's plane with its normal, so plane and
 * normal alone let the light's slots fill the ceiling's unknown pixels beside it (5-px serrations along the light in
 * `make run`'s picture). Unknown ceiling pixels within 3 px of the light, gaze far from it, no history: their
 * colour against full resolution, clamped to 1 as the display shows it. */
static void the_soft_fill_keeps_a_light_off_its_ceiling(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    uint16_t light = 0; /* the G-buffer's id of the emissive material */
    for (uint32_t m = 0; m < s->material_count; m++)
        if (s->materials[m].emissive.x + s->materials[m].emissive.y + s->materials[m].emissive.z > 0.0f)
            light = (uint16_t)(m + 1);
    assert_true(light != 0);
    float *full = malloc(NPIX * 16), *fov = malloc(NPIX * 16);
    uint32_t *mask = malloc(NPIX * 4);
    uint16_t *material = malloc(NPIX * 2);
    assert_true(full && fov && mask && material);
    /* the light's box in the default view, then a view of it and the ceiling around (the light 1/3 of it) */
    fv_frame_input in0 = frame_in();
    in0.quality.fovea.enabled = false;
    assert_int_equal(fv_renderer_draw(g_r, &in0), FV_OK);
    assert_int_equal(fv_renderer_read_image(g_r, "gbuffer material id", 0, material, NPIX * 2, 2), FV_OK);
    int x0 = W, x1 = -1, y0 = H, y1 = -1;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            if (material[(size_t)y * W + x] == light)
                x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1, y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
    assert_true(x1 >= x0 && y1 >= y0);
    const fv_eye_view *v0 = &in0.eye[0];
    double cx = (x0 + x1 + 1) * 0.5 / W, cy = (y0 + y1 + 1) * 0.5 / H; /* the light's centre, uv */
    double hw = 1.5 * (x1 - x0 + 1) / W, hh = 1.5 * (y1 - y0 + 1) / H;  /* 3x its size */
    float tx = (float)(v0->tan_left + (v0->tan_right - v0->tan_left) * cx);
    float ty = (float)(v0->tan_up + (v0->tan_down - v0->tan_up) * cy);
    float sx = (float)((v0->tan_right - v0->tan_left) * hw), sy = (float)((v0->tan_down - v0->tan_up) * hh);
    double err = 0;
    int n = 0, near_light = 0;
    for (int pass = 0; pass < 2; pass++) {
        fv_frame_input in = frame_in();
        for (int e = 0; e < 2; e++) {
            fv_eye_view *v = &in.eye[e];
            v->tan_left = tx - sx, v->tan_right = tx + sx, v->tan_up = ty - sy, v->tan_down = ty + sy;
            v->proj = fv_mat4_perspective_tan(v->tan_left, v->tan_right, v->tan_up, v->tan_down, v->near_m, v->far_m);
        }
        set_gaze(&in, fv_v3_normalize_or(fv_v3(-1.0f, 0.0f, -1.0f), fv_v3(0, 0, -1)), 0.0f); /* far left: periphery */
        in.quality.fovea.enabled = pass == 1;
        in.quality.fovea.temporal = 0;
        in.quality.fovea.recon = FV_FOVEA_RECON_SOFT;
        in.quality.fovea.mar_slope = 0.2f;
        in.quality.gi.enabled = false;
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        assert_int_equal(fv_renderer_read_linear(g_r, 0, pass ? fov : full, NPIX * 4), FV_OK);
        if (pass) {
            assert_int_equal(fv_renderer_read_image(g_r, "fovea mask", 0, mask, NPIX * 4, 4), FV_OK);
            assert_int_equal(fv_renderer_read_image(g_r, "gbuffer material id", 0, material, NPIX * 2, 2), FV_OK);
        }
    }
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            near_light += material[i] == light;
            if (mask[i] || material[i] == 0 || material[i] == light) continue;
            bool beside = false;
            for (int dy = -3; dy <= 3; dy++)
                for (int dx = -3; dx <= 3; dx++) {
                    int xx = x + dx, yy = y + dy;
                    if (xx >= 0 && yy >= 0 && xx < W && yy < H && material[(size_t)yy * W + xx] == light) beside = true;
                }
            if (!beside) continue;
            for (int c = 0; c < 3; c++) /* as the display shows it: linear clamped to 1 (the light is far above) */
                err += fabs(fmin(fov[i * 4 + c], 1.0) - fmin(full[i * 4 + c], 1.0)) / 3.0;
            n++;
        }
    print_message("soft fill beside the light: %d unknown pixels (light %d px), mean error %.4f (of 1)\n", n,
                  near_light, n ? err / n : 0.0);
    assert_true(near_light > 20);
    assert_true(n > 10);
    assert_true(err / n < 0.1); /* 0.515 before, 0.049 now */
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    free(full), free(fov), free(mask), free(material);
    fv_scene_destroy(&s);
}

/* A pass that reads another's images keeps views of them: when foveation starts again with another block (its
 * images made again), a view of them starts again too (it kept the destroyed images' views before: validation
 * errors, then a crash). And p read back is this frame's map. */
static void a_view_of_foveation_follows_a_new_block(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = NULL;
    load("cornell", &s);
    float *prob = malloc(NPIX * 4);
    assert_non_null(prob);
    for (uint32_t B = 3; B <= 6; B += 3)
        for (int v = 0; v < 3; v++) {
            fv_frame_input in = frame_in();
            in.quality.fovea.block = B;
            in.quality.debug_view = (fv_debug_view[]){FV_DEBUG_VIEW_PROB, FV_DEBUG_VIEW_SAMPLES, FV_DEBUG_VIEW_VORONOI}[v];
            assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
            assert_int_equal(fv_renderer_read_image(g_r, "fovea prob", 0, prob, NPIX * 4, 4), FV_OK);
            for (size_t i = 0; i < NPIX; i++)
                if (!(prob[i] >= in.quality.fovea.min_prob && prob[i] <= 1.0f)) fail_msg("p[%zu] = %g", i, prob[i]);
        }
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
    free(prob);
    fv_scene_destroy(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sampling_map_matches_cpu_and_every_block_holds_a_sample),
        cmocka_unit_test(compaction_orders_shade_the_same_image),
        cmocka_unit_test(sibson_matches_brute_force_natural_neighbours),
        cmocka_unit_test(fovea_follows_fixed_gazes),
        cmocka_unit_test(foveal_band_equals_full_resolution),
        cmocka_unit_test(temporal_reuse_lowers_periphery_error_and_flicker),
        cmocka_unit_test(the_history_in_the_colour_is_known_pixels_only),
        cmocka_unit_test(saliency_and_dof_match_cpu),
        cmocka_unit_test(soft_matches_cpu_double),
        cmocka_unit_test(soft_fill_flickers_less_than_nearest),
        cmocka_unit_test(every_fill_finite_at_extremes),
        cmocka_unit_test(map_reads_gbuffer_only_when_needed),
        cmocka_unit_test(a_view_of_foveation_follows_a_new_block),
        cmocka_unit_test(the_soft_fill_keeps_a_light_off_its_ceiling),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
