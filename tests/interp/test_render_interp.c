/* @brief GPU tests of hierarchical screen-space interpolation (render/interp) on lavapipe with validation on: a flat
 * wall is filled from the start level, its shaded pixels are bit-identical to full-resolution shading and the list
 * holds exactly them; across a depth edge no region is interpolated; SSIM against full-resolution shading at the
 * default threshold; 1x1 and odd sizes, threshold 0 and huge: finite, and every filled pixel's corners shaded;
 * composed with foveation; the plan. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_knobs.h"
#include "fv_metrics.h"
#include "fv_passes.h"
#include "fv_renderer.h"
#include "fv_scene.h"
#include "fv_test.h"
#include "gpu_test.h"
#include "fv_sample_mask_interface.h"
#include "interp_interface.h"

#define W 96
#define H 80
#define NPIX ((size_t)W * H)

FV_GPU_TEST_GROUP(W, H)
static uint64_t g_frame_id = 1;

/* ---- scenes -------------------------------------------------------------------------------------------------- */

/* A wall (square, normal +y, half size `half` m) seen straight from 1 m above, lit by a point light; with `step`,
 * a second square of the same material 0.3 m in front of it, a third of the way in. */
static fv_scene *wall_scene(double half, bool step)
{
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("interp-wall", &s), FV_OK);
    fv_material mat = fv_material_default();
    mat.base_color = fv_v3(0.7f, 0.6f, 0.5f);
    uint32_t mi;
    assert_int_equal(fv_scene_add_material(s, &mat, &mi), FV_OK);
    fv_mesh m = fv_gpu_test_square_mesh("wall", half, mi);
    uint32_t mesh;
    assert_int_equal(fv_scene_add_mesh(s, &m, &mesh), FV_OK);
    fv_node node = fv_node_default();
    node.mesh = (int32_t)mesh;
    assert_int_equal(fv_scene_add_node(s, &node, NULL), FV_OK);
    if (step) {
        fv_mesh m2 = fv_gpu_test_square_mesh("step", 0.25, mi);
        uint32_t mesh2;
        assert_int_equal(fv_scene_add_mesh(s, &m2, &mesh2), FV_OK);
        fv_node n2 = fv_node_default();
        n2.mesh = (int32_t)mesh2;
        n2.translation_m = fv_v3(0.15f, 0.3f, 0.1f);
        assert_int_equal(fv_scene_add_node(s, &n2, NULL), FV_OK);
    }
    fv_light l;
    memset(&l, 0, sizeof l);
    l.type = FV_LIGHT_POINT;
    l.position_m = fv_v3(0.3f, 3.0f, -0.2f);
    l.color = fv_v3(1, 1, 1);
    l.intensity = 20.0f;
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    s->head.position_m = fv_v3(0.0f, 1.0f, 0.0f);
    s->head.orientation = fv_quat_axis_angle(fv_v3(1, 0, 0), (float)(-FV_PI / 2));
    return s;
}

static fv_frame_input frame_for(fv_renderer *r, const fv_scene *s, bool interp)
{
    uint32_t w, h;
    fv_renderer_size(r, &w, &h);
    fv_frame_input in;
    fv_frame_input_from_head(&s->head, 0.05f, 10.0f, w, h, g_frame_id++, 0.0, &in);
    in.quality.interp.enabled = interp;
    in.quality.fovea.enabled = false;
    return in;
}

/* ---- reading back --------------------------------------------------------------------------------------------- */

typedef struct frame_read {
    uint32_t w, h;
    float *rgba[2];
    uint32_t *code[2]; /* NULL when interpolation was off */
} frame_read;

static void read_frame(fv_renderer *r, bool codes, frame_read *out)
{
    fv_renderer_size(r, &out->w, &out->h);
    size_t n = (size_t)out->w * out->h;
    for (int e = 0; e < 2; e++) {
        out->rgba[e] = malloc(n * 4 * sizeof(float));
        assert_non_null(out->rgba[e]);
        assert_int_equal(fv_renderer_read_linear(r, e, out->rgba[e], n * 4), FV_OK);
        out->code[e] = NULL;
        if (!codes) continue;
        out->code[e] = malloc(n * 4);
        assert_non_null(out->code[e]);
        assert_int_equal(fv_renderer_read_image(r, "interp level", e, out->code[e], n * 4, 4), FV_OK);
    }
}

static void free_frame(frame_read *f)
{
    for (int e = 0; e < 2; e++) {
        free(f->rgba[e]);
        free(f->code[e]);
    }
}

typedef struct census {
    uint64_t shaded, filled, left, bad;
    uint64_t at_level[FV_INTERP_MAX_LEVEL + 1];
} census;

/* Every pixel is finite, its code one of shaded / filled / left at a level <= start, and every filled pixel's four
 * corners (its level's node, clamped to the image) are shaded. */
static census check_codes(const frame_read *f, uint32_t start, bool left_allowed)
{
    census c;
    memset(&c, 0, sizeof c);
    uint32_t w = f->w, h = f->h;
    for (int e = 0; e < 2; e++)
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                size_t i = (size_t)y * w + x;
                const float *p = &f->rgba[e][4 * i];
                if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
                    fail_msg("eye %d pixel (%u, %u): colour not finite", e, x, y);
                uint32_t code = f->code[e][i], k = code & FV_INTERP_CODE_LEVEL_MASK;
                uint32_t kind = code & (FV_INTERP_CODE_SHADED | FV_INTERP_CODE_FILLED | FV_INTERP_CODE_LEFT);
                if (k > start || (kind != FV_INTERP_CODE_SHADED && kind != FV_INTERP_CODE_FILLED &&
                                  kind != FV_INTERP_CODE_LEFT))
                    fail_msg("eye %d pixel (%u, %u): code 0x%x", e, x, y, code);
                c.at_level[k]++;
                if (kind == FV_INTERP_CODE_SHADED) c.shaded++;
                if (kind == FV_INTERP_CODE_LEFT) {
                    c.left++;
                    if (!left_allowed || k != 0) fail_msg("eye %d pixel (%u, %u): left unshaded (code 0x%x)", e, x, y, code);
                }
                if (kind != FV_INTERP_CODE_FILLED) continue;
                c.filled++;
                if (k == 0) fail_msg("eye %d pixel (%u, %u): filled at level 0", e, x, y);
                uint32_t s = 1u << k, x0 = (x >> k) << k, y0 = (y >> k) << k;
                uint32_t x1 = x0 + s < w - 1 ? x0 + s : w - 1, y1 = y0 + s < h - 1 ? y0 + s : h - 1;
                uint32_t cx[2] = {x0, x1}, cy[2] = {y0, y1};
                for (int a = 0; a < 4; a++) {
                    uint32_t cc = f->code[e][(size_t)cy[a >> 1] * w + cx[a & 1]];
                    if (!(cc & FV_INTERP_CODE_SHADED))
                        fail_msg("eye %d pixel (%u, %u) filled at level %u: corner (%u, %u) not shaded (0x%x)", e, x, y,
                                 k, cx[a & 1], cy[a >> 1], cc);
                }
            }
    return c;
}

/* Mean SSIM of the two eyes' sRGB luma, a against b. */
static double ssim_of(const frame_read *a, const frame_read *b)
{
    size_t n = (size_t)a->w * a->h;
    double *la = malloc(n * sizeof(double)), *lb = malloc(n * sizeof(double)), *srgb = malloc(n * 3 * sizeof(double));
    assert_true(la && lb && srgb);
    double sum = 0;
    for (int e = 0; e < 2; e++) {
        for (int which = 0; which < 2; which++) {
            const float *src = (which ? b : a)->rgba[e];
            for (size_t i = 0; i < n; i++)
                for (int ch = 0; ch < 3; ch++) srgb[3 * i + ch] = fv_metrics_linear_to_srgb(src[4 * i + ch]);
            fv_metrics_luma(srgb, n, which ? lb : la);
        }
        double s = 0;
        assert_int_equal(fv_metrics_ssim(la, lb, a->w, a->h, &s), FV_OK);
        sum += s;
    }
    free(la);
    free(lb);
    free(srgb);
    return sum / 2;
}

static uint64_t shade_pixels_of_last_frame(fv_renderer *r)
{
    assert_int_equal(fv_renderer_finish(r), FV_OK);
    fv_render_stats st;
    assert_int_equal(fv_renderer_stats(r, &st), FV_OK);
    for (uint32_t i = 0; i < st.pass_count; i++)
        if (strcmp(st.pass_name[i], "shade") == 0) return st.pass_counters[i].pixels_shaded;
    fail_msg("no shade pass in the stats");
    return 0;
}

/* ---- tests ---------------------------------------------------------------------------------------------------- */

static void flat_wall_is_filled_from_the_start_level_and_its_shaded_pixels_are_exact(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = wall_scene(20.0, false);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    /* full resolution, then a frame from elsewhere (so a pixel the list missed would keep a wrong colour), then
     * the same view interpolated */
    fv_frame_input in = frame_for(g_r, s, false);
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    frame_read full;
    read_frame(g_r, false, &full);
    fv_scene moved = *s;
    moved.head.position_m.x += 0.37f;
    fv_frame_input other = frame_for(g_r, &moved, false);
    assert_int_equal(fv_renderer_draw(g_r, &other), FV_OK);
    in = frame_for(g_r, s, true);
    uint32_t start = in.quality.interp.start_level;
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    uint64_t listed = shade_pixels_of_last_frame(g_r);
    frame_read it;
    read_frame(g_r, true, &it);
    census c = check_codes(&it, start, false);
    /* every pixel at the start level: shaded ones are the grid of 2^start px plus the last row and column */
    assert_int_equal(c.at_level[start], 2 * NPIX);
    uint32_t sp = 1u << start;
    uint64_t grid = 2ull * ((W + sp - 1) / sp) * ((H + sp - 1) / sp);
    uint64_t bound = grid + 2ull * (W + H);
    print_message("flat wall %ux%u, start level %u: %llu shaded (bound %llu), %llu filled\n", W, H, start,
                  (unsigned long long)c.shaded, (unsigned long long)bound, (unsigned long long)c.filled);
    assert_true(c.shaded <= bound);
    assert_int_equal(listed, c.shaded); /* the list holds exactly the shaded pixels */
    double worst_shaded = 0, worst_filled = 0;
    for (int e = 0; e < 2; e++)
        for (size_t i = 0; i < NPIX; i++)
            for (int ch = 0; ch < 3; ch++) {
                double a = it.rgba[e][4 * i + ch], b = full.rgba[e][4 * i + ch];
                double d = fabs(a - b) / fmax(fabs(b), 1e-3);
                if (it.code[e][i] & FV_INTERP_CODE_SHADED) worst_shaded = fmax(worst_shaded, d);
                else worst_filled = fmax(worst_filled, d);
            }
    print_message("flat wall: worst relative difference, shaded %.3g, filled %.3g\n", worst_shaded, worst_filled);
    assert_true(worst_shaded == 0.0); /* the same shading function on the same G-buffer */
    assert_true(worst_filled < 0.01); /* smooth light: bilinear over 4x4 px regions */
    free_frame(&full);
    free_frame(&it);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

static void nothing_is_interpolated_across_a_depth_edge(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_scene *s = wall_scene(20.0, true);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    fv_frame_input in = frame_for(g_r, s, true);
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    frame_read it;
    read_frame(g_r, true, &it);
    census c = check_codes(&it, in.quality.interp.start_level, false);
    /* the G-buffer depth tells the step from the wall: a jump between neighbours of more than 1e-4 in depth */
    uint64_t edges = 0, near_edge_shaded = 0;
    for (int e = 0; e < 2; e++) {
        float *depth = malloc(NPIX * 4);
        assert_non_null(depth);
        assert_int_equal(fv_renderer_read_image(g_r, "gbuffer depth", e, depth, NPIX * 4, 4), FV_OK);
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                uint32_t code = it.code[e][(size_t)y * W + x];
                bool edge = (x + 1 < W && fabsf(depth[y * W + x + 1] - depth[y * W + x]) > 1e-4f) ||
                            (y + 1 < H && fabsf(depth[(y + 1) * W + x] - depth[y * W + x]) > 1e-4f);
                if (edge) {
                    edges++;
                    near_edge_shaded += (code & FV_INTERP_CODE_SHADED) != 0;
                }
                if (!(code & FV_INTERP_CODE_FILLED)) continue;
                /* the filled pixel's region (closed) holds no depth jump between neighbours */
                uint32_t k = code & FV_INTERP_CODE_LEVEL_MASK, sp = 1u << k;
                uint32_t x0 = (x >> k) << k, y0 = (y >> k) << k;
                uint32_t x1 = x0 + sp < W - 1 ? x0 + sp : W - 1, y1 = y0 + sp < H - 1 ? y0 + sp : H - 1;
                for (uint32_t yy = y0; yy <= y1; yy++)
                    for (uint32_t xx = x0; xx <= x1; xx++) {
                        float d = depth[yy * W + xx];
                        if ((xx < x1 && fabsf(depth[yy * W + xx + 1] - d) > 1e-4f) ||
                            (yy < y1 && fabsf(depth[(yy + 1) * W + xx] - d) > 1e-4f))
                            fail_msg("eye %d pixel (%u, %u) filled at level %u across the depth edge at (%u, %u)", e,
                                     x, y, k, xx, yy);
                    }
            }
        free(depth);
    }
    print_message("depth edge: %llu edge pixels, %llu of them shaded; %llu filled, %llu shaded in all\n",
                  (unsigned long long)edges, (unsigned long long)near_edge_shaded, (unsigned long long)c.filled,
                  (unsigned long long)c.shaded);
    assert_true(edges > 2 * 40);          /* the step's outline is in view */
    assert_int_equal(near_edge_shaded, edges); /* pixels on the edge are shaded themselves */
    assert_true(c.filled > NPIX);         /* the wall and the step away from the edge are still filled */
    free_frame(&it);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

/* SSIM of interpolated against full-resolution shading at the default threshold and start level, balanced preset. */
static double ssim_vs_full(fv_renderer *r, const char *scene, double closer, bool light, census *out_census,
                           double *out_shaded)
{
    fv_scene *s = NULL;
    const char *src = strchr(scene, '/') ? fv_test_data(scene) : scene;
    if (fv_scene_load(src, &s) != FV_OK) fail_msg("cannot load scene %s", src);
    fv_vec3 lo, hi;
    if (closer > 0 && fv_scene_world_bounds(s, 0.0, &lo, &hi)) {
        fv_vec3 centre = fv_v3_scale(fv_v3_add(lo, hi), 0.5f), p = s->head.position_m;
        s->head.position_m = fv_v3_add(centre, fv_v3_scale(fv_v3_sub(p, centre), (float)closer));
    }
    assert_int_equal(fv_renderer_load_scene(r, s), FV_OK);
    fv_frame_input in;
    assert_int_equal(fv_renderer_frame_input(r, NULL, g_frame_id++, 0.0, &in), FV_OK);
    in.quality.fovea.enabled = false;
    in.quality.interp.enabled = false;
    assert_int_equal(fv_renderer_draw(r, &in), FV_OK);
    frame_read full;
    read_frame(r, false, &full);
    in.frame_id = g_frame_id++;
    in.quality.interp = fv_quality_default().interp;
    in.quality.interp.enabled = true;
    in.quality.interp.light = light;
    assert_int_equal(fv_renderer_draw(r, &in), FV_OK);
    uint64_t listed = shade_pixels_of_last_frame(r);
    frame_read it;
    read_frame(r, true, &it);
    *out_census = check_codes(&it, in.quality.interp.start_level, false);
    assert_int_equal(listed, out_census->shaded);
    *out_shaded = (double)out_census->shaded / (2.0 * full.w * full.h);
    double ssim = ssim_of(&it, &full);
    free_frame(&full);
    free_frame(&it);
    fv_scene_destroy(&s);
    return ssim;
}

#define SSIM_SIZE 256 /* a 4x4 region is a large part of a 96x80 image; 256 is the top of the test sizes */

static void ssim_against_full_resolution_at_the_default_threshold(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    fv_renderer *r = NULL;
    assert_int_equal(fv_gpu_test_setup(SSIM_SIZE, SSIM_SIZE, &r), 0);
    assert_non_null(r);
    const struct {
        const char *scene;
        double closer;
    } cases[] = {{"cornell", 0}, {"scenes/teapot/teapot_lwjgl.obj", 0.6}, {"scenes/bunny/bun_zipper_res3.ply", 0.8}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        census c;
        double shaded;
        double ssim = ssim_vs_full(r, cases[i].scene, cases[i].closer, true, &c, &shaded);
        print_message("%s %ux%u: SSIM %.5f against full resolution, %.1f%% of the pixels shaded\n", cases[i].scene,
                      SSIM_SIZE, SSIM_SIZE, ssim, 100.0 * shaded);
        assert_true(ssim >= 0.98);
        assert_true(shaded < 0.5); /* it did interpolate */
        if (i > 0) continue;
        /* without the light test (the paper's geometry alone) cornell's shadow edges are interpolated across */
        double shaded_geo;
        double ssim_geo = ssim_vs_full(r, cases[i].scene, cases[i].closer, false, &c, &shaded_geo);
        print_message("%s without interp.light: SSIM %.5f, %.1f%% shaded\n", cases[i].scene, ssim_geo,
                      100.0 * shaded_geo);
        assert_true(ssim_geo < ssim && shaded_geo < shaded);
    }
    assert_int_equal(fv_renderer_validation_messages(r), 0);
    assert_int_equal(fv_gpu_test_teardown(&r), 0);
}

/* 1x1, odd sizes; thresholds 0, NaN-free huge; every start level. */
static void extremes_stay_finite_and_keep_corners_shaded(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    const uint32_t sizes[][2] = {{1, 1}, {37, 23}, {2, 65}};
    const float taus[] = {0.0f, 0.02f, 1000.0f};
    for (size_t z = 0; z < sizeof sizes / sizeof sizes[0]; z++) {
        fv_renderer *r = NULL;
        assert_int_equal(fv_gpu_test_setup(sizes[z][0], sizes[z][1], &r), 0);
        assert_non_null(r);
        for (int step = 0; step < 2; step++) {
            fv_scene *s = wall_scene(step ? 0.6 : 20.0, step == 1);
            assert_int_equal(fv_renderer_load_scene(r, s), FV_OK);
            for (size_t t = 0; t < sizeof taus / sizeof taus[0]; t++)
                for (uint32_t start = 1; start <= FV_INTERP_MAX_LEVEL; start += 3) {
                    fv_frame_input in = frame_for(r, s, true);
                    in.quality.interp.threshold = taus[t];
                    in.quality.interp.start_level = start;
                    assert_int_equal(fv_renderer_draw(r, &in), FV_OK);
                    uint64_t listed = shade_pixels_of_last_frame(r);
                    frame_read f;
                    read_frame(r, true, &f);
                    census c = check_codes(&f, start, false);
                    assert_int_equal(listed, c.shaded);
                    assert_int_equal(c.shaded + c.filled, 2ull * sizes[z][0] * sizes[z][1]);
                    free_frame(&f);
                }
            fv_scene_destroy(&s);
        }
        assert_int_equal(fv_renderer_validation_messages(r), 0);
        assert_int_equal(fv_gpu_test_teardown(&r), 0);
    }
}

/* With foveation: interpolation decides which pixels must be shaded (the corners of coherent regions, whatever
 * foveation says), foveation thins the per-pixel rest (left to reconstruction), and the fill marks what it shaded and
 * filled in foveation's sample mask, so reconstruction keeps both: fewer pixels shaded than by either alone, the
 * mask agrees with the codes, every filled pixel in the final image is still the bilinear of its corners, the shaded
 * ones are full-resolution shading's, and the image is as close to full resolution as foveation alone. */
static void compose_at(float mar_slope, bool small_fovea)
{
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("cornell", &s), FV_OK);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    uint64_t shaded[4];
    frame_read img[4];
    uint32_t *mask[2] = {NULL, NULL};
    uint64_t id = g_frame_id++; /* one frame id: every mode shades the same frame */
    census c;
    memset(&c, 0, sizeof c);
    for (int mode = 0; mode < 4; mode++) { /* fovea only, interp only, both, neither (full resolution) */
        fv_frame_input in;
        assert_int_equal(fv_renderer_frame_input(g_r, NULL, id, 0.0, &in), FV_OK);
        in.quality.fovea.enabled = mode == 0 || mode == 2;
        in.quality.fovea.temporal = 0;
        if (mar_slope > 0) in.quality.fovea.mar_slope = mar_slope;
        in.quality.interp.enabled = mode == 1 || mode == 2;
        for (int e = 0; e < 2; e++) {
            in.gaze[e].valid = true;
            in.gaze[e].dir_eye = fv_v3(0, 0, -1);
            in.gaze[e].uncertainty_deg = 0.5f;
        }
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        shaded[mode] = shade_pixels_of_last_frame(g_r);
        read_frame(g_r, mode == 2, &img[mode]);
        if (mode != 2) continue;
        c = check_codes(&img[2], in.quality.interp.start_level, true);
        assert_int_equal(shaded[mode], c.shaded);
        for (int e = 0; e < 2; e++) {
            mask[e] = malloc(NPIX * 4);
            assert_non_null(mask[e]);
            assert_int_equal(fv_renderer_read_image(g_r, "fovea mask", e, mask[e], NPIX * 4, 4), FV_OK);
        }
    }
    print_message("cornell %ux%u, fovea.mar_slope %s: shaded by fovea %llu, interp %llu, both %llu (%llu filled, %llu left to "
                  "reconstruct)\n", W, H, small_fovea ? "0.2" : "0.05", (unsigned long long)shaded[0], (unsigned long long)shaded[1],
                  (unsigned long long)shaded[2], (unsigned long long)c.filled, (unsigned long long)c.left);
    assert_true(c.filled > 0);
    if (small_fovea) assert_true(c.left > 0);
    /* foveation thins interpolation's per-pixel rest; the corners of coherent regions stay shaded whatever
     * foveation says (every filled pixel needs its four), so where foveation's samples are sparser than the
     * regions' corners (a fovea small against the image) the pair shades more than foveation alone */
    assert_true(shaded[2] < shaded[1]);
    if (!small_fovea) assert_true(shaded[2] < shaded[0]);
    /* the mask: shaded 1, filled 3, left 0 (no temporal reuse); filled pixels kept through reconstruction, shaded
     * ones as full resolution shades them */
    double worst_shaded = 0, worst_filled = 0;
    const frame_read *both = &img[2], *full = &img[3];
    for (int e = 0; e < 2; e++)
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                size_t i = (size_t)y * W + x;
                uint32_t code = both->code[e][i], m = mask[e][i];
                uint32_t want = (code & FV_INTERP_CODE_SHADED)   ? FV_SAMPLE_MASK_SHADED
                                : (code & FV_INTERP_CODE_FILLED) ? FV_SAMPLE_MASK_INTERPOLATED
                                                                 : FV_SAMPLE_MASK_UNKNOWN;
                if (m != want) fail_msg("eye %d pixel (%u, %u): mask %u, code 0x%x", e, x, y, m, code);
                const float *px = &both->rgba[e][4 * i];
                if (code & FV_INTERP_CODE_SHADED)
                    for (int ch = 0; ch < 3; ch++)
                        worst_shaded = fmax(worst_shaded, fabs(px[ch] - full->rgba[e][4 * i + ch]) /
                                                              fmax(fabs(full->rgba[e][4 * i + ch]), 1e-3));
                if (!(code & FV_INTERP_CODE_FILLED)) continue;
                uint32_t k = code & FV_INTERP_CODE_LEVEL_MASK, sp = 1u << k;
                uint32_t x0 = (x >> k) << k, y0 = (y >> k) << k;
                uint32_t x1 = x0 + sp < W - 1 ? x0 + sp : W - 1, y1 = y0 + sp < H - 1 ? y0 + sp : H - 1;
                double tx = (double)(x - x0) / (x1 > x0 ? x1 - x0 : 1), ty = (double)(y - y0) / (y1 > y0 ? y1 - y0 : 1);
                for (int ch = 0; ch < 3; ch++) {
                    const float *im = both->rgba[e];
                    double c00 = im[4 * ((size_t)y0 * W + x0) + ch], c10 = im[4 * ((size_t)y0 * W + x1) + ch];
                    double c01 = im[4 * ((size_t)y1 * W + x0) + ch], c11 = im[4 * ((size_t)y1 * W + x1) + ch];
                    double b = (c00 * (1 - tx) + c10 * tx) * (1 - ty) + (c01 * (1 - tx) + c11 * tx) * ty;
                    worst_filled = fmax(worst_filled, fabs(px[ch] - b) / fmax(fabs(b), 1e-3));
                }
            }
    double ssim_fovea = ssim_of(&img[0], full), ssim_both = ssim_of(both, full), ssim_interp = ssim_of(&img[1], full);
    print_message("worst relative difference: shaded vs full resolution %.3g, filled vs its corners' bilinear %.3g; "
                  "SSIM against full resolution: fovea %.5f, interp %.5f, both %.5f\n", worst_shaded, worst_filled,
                  ssim_fovea, ssim_interp, ssim_both);
    assert_true(worst_shaded < 1e-5);
    assert_true(worst_filled < 1e-4); /* reconstruction replaced no interpolated pixel */
    assert_true(ssim_interp >= 0.98);
    assert_true(ssim_both >= ssim_fovea - 0.01); /* interpolation costs foveation next to nothing in quality */
    for (int m = 0; m < 4; m++) free_frame(&img[m]);
    for (int e = 0; e < 2; e++) free(mask[e]);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

static void composes_with_foveation(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    compose_at(0.2f, true); /* a fovea that fits the small image: most of it periphery */
    compose_at(0.05f, false); /* most of the small image foveal */
}

static void plan_says_why(void **state)
{
    (void)state;
    fv_quality q = fv_quality_default();
    q.interp.enabled = false;
    q.fovea.enabled = false;
    fv_frame_plan p;
    fv_plan_context ctx = {.scene = NULL, .multiview = true, .quality = &q};
    fv_frame_plan_build_ctx(&ctx, &p);
    const fv_plan_entry *e = fv_frame_plan_find(&p, "interp"), *f = fv_frame_plan_find(&p, "interp_fill");
    assert_non_null(e);
    assert_non_null(f);
    assert_false(e->enabled);
    assert_non_null(strstr(e->reason, "interp.enabled"));
    q.interp.enabled = true;
    fv_frame_plan_build_ctx(&ctx, &p);
    e = fv_frame_plan_find(&p, "interp");
    f = fv_frame_plan_find(&p, "interp_fill");
    assert_true(e->enabled && f->enabled);
    /* interp before shade, its fill after shade and before reconstruct */
    int order[4] = {-1, -1, -1, -1};
    const char *names[4] = {"interp", "shade", "interp_fill", "reconstruct"};
    for (uint32_t i = 0; i < p.count; i++)
        for (int n = 0; n < 4; n++)
            if (strcmp(p.entries[i].pass, names[n]) == 0) order[n] = (int)i;
    assert_true(order[0] >= 0 && order[0] < order[1] && order[1] < order[2] && order[2] < order[3]);
    /* with foveation: both run, foveation's list before interp's, the fill marks foveation's mask (its block as the
     * variant: made again with foveation's images) before temporal reuse and reconstruction */
    q.fovea.enabled = true;
    fv_frame_plan_build_ctx(&ctx, &p);
    e = fv_frame_plan_find(&p, "interp");
    f = fv_frame_plan_find(&p, "interp_fill");
    assert_true(e->enabled && f->enabled);
    assert_int_equal(f->variant, q.fovea.block);
    assert_non_null(strstr(f->reason, "sample mask"));
    assert_non_null(strstr(e->reason, "foveation"));
    const char *after[3] = {"compact", "temporal", "reconstruct"};
    int pos[3] = {-1, -1, -1};
    for (uint32_t i = 0; i < p.count; i++)
        for (int n = 0; n < 3; n++)
            if (strcmp(p.entries[i].pass, after[n]) == 0) pos[n] = (int)i;
    assert_true(pos[0] >= 0 && pos[0] < order[0] && order[2] < pos[1] && order[2] < pos[2]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(plan_says_why),
        cmocka_unit_test(flat_wall_is_filled_from_the_start_level_and_its_shaded_pixels_are_exact),
        cmocka_unit_test(nothing_is_interpolated_across_a_depth_edge),
        cmocka_unit_test(ssim_against_full_resolution_at_the_default_threshold),
        cmocka_unit_test(extremes_stay_finite_and_keep_corners_shaded),
        cmocka_unit_test(composes_with_foveation),
    };
    const char *only = getenv("FV_TEST_ONLY"); /* a test's name (glob): run only that one, while debugging */
    if (only && *only) cmocka_set_test_filter(only);
    return cmocka_run_group_tests(tests, setup, teardown);
}
