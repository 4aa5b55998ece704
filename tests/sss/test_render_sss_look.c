/* @brief What the translucent scenes look like on a device (issue 28). scenes/marble-bunny.scene.json is lit where
 * the head sees it (item 4: its low sun shone from behind the bunny, and the 15 cm body passes none of it through,
 * so all but the ears' rims rendered black). The marble sphere's subsurface light (the sss view) has no concentric
 * rings, in both modes (item 5). The head stands close above cornell-translucent's sphere (it fills the view); along every row and
 * column of the sphere's well-lit pixels (direct light at least 30% of its brightest there, where the irradiance
 * varies slowly) the profile of the subsurface term is counted for significant local extrema (a second difference
 * above 3% of the value at a turning point). The light-view map's texel grid aliasing against the dipole's
 * sub-millimetre peak made them (one disk of the texel's area per sample); footprints matched to each texel
 * (fv_dipole_tile_kernel) leave about half as many. The CPU reference's exact sum is
 * counted the same way and compared (the same model: it rang too). Validation must stay silent. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_reference.h"
#include "fv_test.h"
#include "gpu_test_reference.h"

#define W 64
#define H 64
#define NPIX ((size_t)W * H)
#define MAP 128 /* sss.map_size (balanced): 2.3 mm texels on the sphere, 5 of marble's mean free paths */
/* A significant extremum: a turning point whose second difference exceeds REL of its value (a visible ripple).
 * Per profile pixel, one disk per sample (the rings) left 0.26 of them, the footprints 0.14 (what is left: the
 * irradiance held constant over each texel of the tessellated sphere, docs/rendering.md); measured in BENCHMARKS.md
 * "SSS rings". */
#define REL 0.03
#define EXTREMA_PER_PX_MAX 0.2

FV_GPU_TEST_GROUP(W, H)
#define NEED_GPU() FV_NEED_GPU(g_r)

static uint64_t g_frame = 1;

static void draw(const fv_quality *q, fv_debug_view view, float *rgb)
{
    fv_quality v = *q;
    v.debug_view = view;
    fv_frame_input in = fv_gpu_test_frame_input(g_r, &g_frame, &v);
    fv_gpu_test_draw_sbs(g_r, &in, W, H, rgb);
}

/* Significant local extrema along the rows and columns of the masked runs of at least 8 px; *out_px: the
 * profile pixels looked at. */
static int extrema(const float *rgb, const bool *mask, double rel, size_t *out_px)
{
    int count = 0;
    size_t px = 0;
    const size_t w2 = 2 * W;
    for (int dir = 0; dir < 2; dir++) {
        size_t lines = dir ? w2 : H, len = dir ? H : w2;
        for (size_t a = 0; a < lines; a++) {
            double v[2 * W];
            size_t n = 0;
            for (size_t b = 0; b <= len; b++) {
                size_t i = b < len ? (dir ? b * w2 + a : a * w2 + b) : 0;
                /* a run ends at an unmasked pixel, the line's end or the seam between the eyes */
                bool in = b < len && mask[i] && !(dir == 0 && b == W);
                if (in) {
                    v[n++] = (double)rgb[i * 3] + rgb[i * 3 + 1] + rgb[i * 3 + 2];
                    continue;
                }
                if (n >= 8) {
                    for (size_t k = 1; k + 1 < n; k++) {
                        double d2 = v[k - 1] - 2.0 * v[k] + v[k + 1];
                        if ((v[k] - v[k - 1]) * (v[k + 1] - v[k]) < 0.0 && fabs(d2) > rel * v[k]) count++;
                    }
                    px += n - 2;
                }
                n = 0;
                if (b < len && mask[i] && dir == 0 && b == W) v[n++] = (double)rgb[i * 3] + rgb[i * 3 + 1] + rgb[i * 3 + 2];
            }
        }
    }
    *out_px = px;
    return count;
}

static void the_sphere_shows_no_rings_in_either_mode(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("cornell-translucent", &s), FV_OK);
    /* Close above the sphere (r 80 mm at (-0.14, 0.08, 0.16)): it fills the upper right of both eyes. */
    fv_scene_head_look_at(&s->head, fv_v3(-0.14f, 0.21f, 0.33f), fv_v3(-0.14f, 0.08f, 0.16f));
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    fv_quality q = fv_quality_default();
    q.fovea.enabled = false;
    q.gi.enabled = false;
    q.sss.map_size_px = MAP;
    float *rgb = malloc(2 * NPIX * 3 * sizeof *rgb), *ref = malloc(2 * NPIX * 3 * sizeof *ref);
    bool *mask = calloc(2 * NPIX, sizeof *mask);
    assert_true(rgb && ref && mask);
    /* The sphere (marble's albedo), then its well-lit part. */
    draw(&q, FV_DEBUG_VIEW_ALBEDO, rgb);
    for (size_t i = 0; i < 2 * NPIX; i++) {
        const float *p = &rgb[i * 3];
        mask[i] = fabsf(p[0] - 0.83f) < 2e-3f && fabsf(p[1] - 0.79f) < 2e-3f && fabsf(p[2] - 0.75f) < 2e-3f;
    }
    fv_quality opaque = q;
    opaque.sss.enabled = false; /* the direct light of the surface as if opaque */
    draw(&opaque, FV_DEBUG_VIEW_DIRECT, rgb);
    double brightest = 0.0;
    for (size_t i = 0; i < 2 * NPIX; i++)
        if (mask[i]) brightest = fmax(brightest, (double)rgb[i * 3] + rgb[i * 3 + 1] + rgb[i * 3 + 2]);
    size_t lit = 0;
    for (size_t i = 0; i < 2 * NPIX; i++) {
        mask[i] = mask[i] && (double)rgb[i * 3] + rgb[i * 3 + 1] + rgb[i * 3 + 2] >= 0.3 * brightest;
        lit += mask[i];
    }
    assert_true(brightest > 0.0 && lit > 150);
    /* The reference's exact sum, counted the same way. */
    fv_quality rq = q;
    rq.sss.mode = FV_SSS_MODE_EXACT;
    fv_frame_input in = fv_gpu_test_frame_input(g_r, &g_frame, &rq);
    fv_gpu_test_reference_sbs(s, &in, FV_REFERENCE_VIEW_SSS, W, H, ref);
    size_t px;
    int ref_ext = extrema(ref, mask, REL, &px);

    print_message("well-lit sphere: %zu px; reference exact sum: %d significant extrema over %zu profile px\n", lit,
                  ref_ext, px);
    for (int mode = 0; mode < 2; mode++) {
        fv_quality m = q;
        m.sss.mode = mode ? FV_SSS_MODE_EXACT : FV_SSS_MODE_HIERARCHY;
        draw(&m, FV_DEBUG_VIEW_SSS, rgb);
        int ext = extrema(rgb, mask, REL, &px);

        double num = 0.0, den = 0.0;
        for (size_t i = 0; i < 2 * NPIX; i++)
            if (mask[i])
                for (int c = 0; c < 3; c++) {
                    num += fabs((double)rgb[i * 3 + c] - ref[i * 3 + c]);
                    den += fabs((double)ref[i * 3 + c]);
                }
        print_message("%s: %d significant extrema over %zu profile px (%.4f per px); mean relative difference from "
                      "the reference %.4f\n", mode ? "exact" : "hierarchy", ext, px, (double)ext / (double)px,
                      num / den);
        if ((double)ext > EXTREMA_PER_PX_MAX * (double)px)
            fail_msg("%s: %d ripples over %zu profile pixels of the sphere's subsurface light (rings)",
                     mode ? "exact" : "hierarchy", ext, px);
        if (mode == 1 && num / den > 0.01) fail_msg("exact against the reference: %.4f", num / den);
    }
    if ((double)ref_ext > EXTREMA_PER_PX_MAX * (double)px)
        fail_msg("the reference's exact sum rings: %d extrema over %zu px", ref_ext, px);
    free(rgb);
    free(ref);
    free(mask);
    fv_scene_destroy(&s);
}

/* The marble bunny's pixels (the G-buffer's albedo is its base colour): most of them lit in the colour image. */
static void the_marble_bunny_is_lit_where_the_head_sees_it(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = fv_gpu_test_load_scene(g_r, FV_SOURCE_DIR "/scenes/marble-bunny.scene.json");
    fv_quality q = fv_quality_default();
    q.fovea.enabled = false;
    float *rgb = malloc(2 * NPIX * 3 * sizeof *rgb);
    bool *mask = calloc(2 * NPIX, sizeof *mask);
    assert_true(rgb && mask);
    draw(&q, FV_DEBUG_VIEW_ALBEDO, rgb);
    size_t bunny = 0, lit = 0;
    for (size_t i = 0; i < 2 * NPIX; i++) {
        const float *p = &rgb[i * 3];
        mask[i] = fabsf(p[0] - 0.83f) < 2e-3f && fabsf(p[1] - 0.79f) < 2e-3f && fabsf(p[2] - 0.75f) < 2e-3f;
        bunny += mask[i];
    }
    assert_true(bunny > 200);
    draw(&q, FV_DEBUG_VIEW_NONE, rgb);
    double sum = 0.0;
    for (size_t i = 0; i < 2 * NPIX; i++) {
        if (!mask[i]) continue;
        /* Rec. 709 luminance, linear */
        double y = 0.2126 * rgb[i * 3] + 0.7152 * rgb[i * 3 + 1] + 0.0722 * rgb[i * 3 + 2];
        sum += y;
        lit += y > 0.05; /* an sRGB value of about 63 of 255 */
    }
    print_message("marble bunny: %zu px, %.3f of them lit (luminance > 0.05), mean luminance %.4f\n", bunny,
                  (double)lit / (double)bunny, sum / (double)bunny);
    if (lit < bunny / 2) fail_msg("the bunny renders dark: %zu of %zu px lit", lit, bunny);
    if (!(sum / (double)bunny > 0.1)) fail_msg("the bunny's mean luminance is %.4f", sum / (double)bunny);
    free(rgb);
    free(mask);
    fv_scene_destroy(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_marble_bunny_is_lit_where_the_head_sees_it),
        cmocka_unit_test(the_sphere_shows_no_rings_in_either_mode),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
