/* @brief The hidden-area mask and the distortion pass in the renderer (cornell, lavapipe, validation on): the mask
 * leaves the displayed (distorted) image bit-identical to a frame without it, every pixel it removes from the
 * G-buffer is one no panel pixel shows (fv_lens_tan_visible, runtime/hmd), the fraction it removes is the one the
 * G-buffer pass reports, the masked pixels' linear colour is 0 (shading skipped them as nothing drawn), and
 * `distort.enabled=off` (or no lens) gives the undistorted image exactly. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_hmd.h"
#include "fv_test.h"
#include "gpu_test.h"

#define W 160u
#define H 176u

FV_GPU_TEST_GROUP(W, H)

static fv_scene *g_scene;

static void load_cornell(void)
{
    if (g_scene) return;
    assert_int_equal(fv_scene_builtin("cornell", &g_scene), FV_OK);
    assert_int_equal(fv_renderer_load_scene(g_r, g_scene), FV_OK);
}

typedef struct frame_out {
    uint8_t *rgba;     /* both eyes side by side */
    uint16_t *material[2];
    float *depth[2];
    float *linear[2];
} frame_out;

static void draw(const fv_quality *q, const fv_hmd_profile *p, frame_out *out)
{
    assert_int_equal(fv_renderer_set_quality(g_r, q), FV_OK);
    fv_frame_input in;
    assert_int_equal(fv_renderer_frame_input(g_r, &g_scene->head, 0, 0.0, &in), FV_OK);
    in.quality.fovea.enabled = false; /* full resolution (foveation has its own tests) */
    float fov[8];
    for (int e = 0; e < 2; e++) {
        fov[4 * e + 0] = p->fov[e].tan_left;
        fov[4 * e + 1] = p->fov[e].tan_right;
        fov[4 * e + 2] = p->fov[e].tan_up;
        fov[4 * e + 3] = p->fov[e].tan_down;
    }
    fv_eye_views_build_fov(&in.head, in.eye[0].near_m, in.eye[0].far_m, fov, in.eye);
    in.quality = *q;
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    assert_int_equal(fv_renderer_finish(g_r), FV_OK);
    out->rgba = malloc((size_t)2 * W * H * 4);
    assert_int_equal(fv_renderer_read_rgba8(g_r, true, 0, out->rgba, (size_t)2 * W * H * 4), FV_OK);
    for (int e = 0; e < 2; e++) {
        out->material[e] = malloc((size_t)W * H * 2);
        assert_int_equal(fv_renderer_read_image(g_r, "gbuffer material id", e, out->material[e], (size_t)W * H * 2, 2),
                         FV_OK);
        out->depth[e] = malloc((size_t)W * H * 4);
        assert_int_equal(fv_renderer_read_image(g_r, "gbuffer depth", e, out->depth[e], (size_t)W * H * 4, 4), FV_OK);
        out->linear[e] = malloc((size_t)W * H * 4 * sizeof(float));
        assert_int_equal(fv_renderer_read_linear(g_r, e, out->linear[e], (size_t)W * H * 4), FV_OK);
    }
}

static void release(frame_out *f)
{
    free(f->rgba);
    for (int e = 0; e < 2; e++) {
        free(f->material[e]);
        free(f->depth[e]);
        free(f->linear[e]);
    }
}

static fv_hmd_profile profile(const char *name)
{
    fv_hmd_profile p;
    char err[256];
    if (fv_hmd_profile_load(name, &p, err, sizeof err) != FV_OK) fail_msg("%s", err);
    return p;
}

static void mask_hides_only_unseen_pixels_and_changes_nothing_shown(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    load_cornell();
    const char *names[] = {"generic", "htc-vive"};
    for (int n = 0; n < 2; n++) {
        fv_hmd_profile p = profile(names[n]);
        fv_quality q = fv_quality_default();
        q.fovea.enabled = false; /* full resolution (foveation has its own tests) */
        /* the per-pixel gather: a reduced gi.rate samples the G-buffer once per block, and a block sample the mask
         * hides is no sample (its shown neighbours gather their own: the same picture within the upsampling error,
         * not bit for bit) */
        q.gi.rate = FV_GI_RATE_FULL;
        q.distort.lens = p.lens;
        frame_out on, off;
        draw(&q, &p, &on);
        const fv_plan_entry *g = fv_frame_plan_find(fv_renderer_plan(g_r), "gbuffer");
        assert_non_null(strstr(g->reason, "hidden-area mask"));
        fv_pass_detail d[8];
        uint32_t nd = fv_renderer_pass_details(g_r, "gbuffer", d, 8);
        assert_int_equal(nd, 1);
        assert_string_equal(d[0].key, "mask.fraction");
        q.distort.mask = false;
        draw(&q, &p, &off);
        assert_true(memcmp(on.rgba, off.rgba, (size_t)2 * W * H * 4) == 0);
        for (int e = 0; e < 2; e++) {
            const fv_hmd_fov *f = &p.fov[e];
            uint64_t masked = 0, wrong = 0, lit = 0;
            for (uint32_t y = 0; y < H; y++)
                for (uint32_t x = 0; x < W; x++) {
                    size_t i = (size_t)y * W + x;
                    assert_true(off.depth[e][i] > 0.0f); /* without the mask, nothing is at depth 0 */
                    if (on.depth[e][i] != 0.0f) continue; /* the mask writes depth 0 */
                    masked++;
                    assert_int_equal(on.material[e][i], 0); /* nothing drawn */
                    double tx = -f->tan_left + (x + 0.5) / W * ((double)f->tan_left + f->tan_right);
                    double ty = f->tan_up - (y + 0.5) / H * ((double)f->tan_up + f->tan_down);
                    wrong += fv_lens_tan_visible(&p.lens, e, tx, ty);
                    const float *c = on.linear[e] + 4 * i;
                    lit += c[0] != 0.0f || c[1] != 0.0f || c[2] != 0.0f;
                }
            double frac = (double)masked / (W * H);
            print_message("%s eye %d: %.4f of the pixels masked (the pass says %.4f)\n", names[n], e, frac,
                          d[0].value[e]);
            assert_int_equal(wrong, 0);
            assert_int_equal(lit, 0);
            /* the rasterised mask against the pass's own count of the pixel centres its triangles cover */
            assert_true(fabs(frac - d[0].value[e]) < 0.005);
            if (n == 0) assert_true(frac > 0.03);
        }
        release(&on);
        release(&off);
    }
}

static void distortion_off_or_no_lens_is_the_undistorted_image(void **state)
{
    (void)state;
    FV_NEED_GPU(g_r);
    load_cornell();
    fv_hmd_profile p = profile("generic");
    fv_quality q = fv_quality_default(); /* no lens */
    q.fovea.enabled = false; /* full resolution (foveation has its own tests) */
    frame_out plain, off, on;
    draw(&q, &p, &plain);
    assert_false(fv_frame_plan_find(fv_renderer_plan(g_r), "distort")->enabled);
    q.distort.lens = p.lens;
    q.distort.enabled = false;
    draw(&q, &p, &off);
    assert_false(fv_frame_plan_find(fv_renderer_plan(g_r), "distort")->enabled);
    assert_true(memcmp(plain.rgba, off.rgba, (size_t)2 * W * H * 4) == 0);
    q.distort.enabled = true;
    draw(&q, &p, &on);
    assert_true(fv_frame_plan_find(fv_renderer_plan(g_r), "distort")->enabled);
    assert_true(memcmp(plain.rgba, on.rgba, (size_t)2 * W * H * 4) != 0);
    /* the distorted image is black where the lens shows nothing: the generic panel's corners (past its visible
     * radius) */
    const uint8_t *corner = on.rgba;
    assert_true(corner[0] == 0 && corner[1] == 0 && corner[2] == 0);
    release(&plain);
    release(&off);
    release(&on);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(mask_hides_only_unseen_pixels_and_changes_nothing_shown),
        cmocka_unit_test(distortion_off_or_no_lens_is_the_undistorted_image),
    };
    int rc = cmocka_run_group_tests(tests, setup, teardown);
    fv_scene_destroy(&g_scene);
    return rc;
}
