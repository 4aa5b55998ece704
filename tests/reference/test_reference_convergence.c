/* @brief Path mode converges as Monte Carlo should: on a floor with a box under an emissive square (an area light)
 * and one bounce, the RMS error against a high-spp result halves when the samples per pixel grow fourfold. (The
 * Cornell box is a poor case: its two-sided lamp hangs 1 mm under the ceiling, whose points beside the lamp's edge
 * see its top at millimetres, a heavy-tailed estimate that makes a 20% tolerance flaky.) */
#include <math.h>
#include <stdlib.h>

#include "fv_reference.h"
#include "fv_scene.h"
#include "fv_test.h"
#include "reference_test.h"

#define W 24
#define H 24

static double rmse(const float *a, const float *b, size_t n)
{
    double sum = 0;
    for (size_t i = 0; i < n; i++) sum += ((double)a[i] - b[i]) * ((double)a[i] - b[i]);
    return sqrt(sum / (double)n);
}

static void path_error_halves_when_spp_quadruples(void **state)
{
    (void)state;
    fv_scene *s = rt_plane_scene(fv_v3(0.8f, 0.8f, 0.8f), 3.0);
    rt_add_box(s, fv_v3(-0.2f, 0.15f, 0.1f), 0.15, 0);
    uint32_t lamp = rt_material(s, fv_v3(0.5f, 0.5f, 0.5f), fv_v3(4, 3, 2));
    rt_add_square(s, "lamp", fv_v3(0.5f, 0.8f, 0.0f), 0.2, lamp);
    fv_frame_input in = rt_views(&s->head, W, H);
    size_t n = (size_t)W * H * 3;
    float *ref[2] = {rt_image(W, H), rt_image(W, H)}, *lo[2] = {rt_image(W, H), rt_image(W, H)};
    float *hi[2] = {rt_image(W, H), rt_image(W, H)};
    /* independent seeds: the estimates share no samples with the reference */
    fv_reference_desc d = {.mode = FV_REFERENCE_PATH, .bounces = 1, .eye_width = W, .eye_height = H};
    d.spp = 256, d.seed = 1000;
    fv_reference_stats st;
    assert_int_equal(fv_reference_render(s, &in, &d, ref[0], ref[1], &st), FV_OK);
    assert_true(st.emissive_triangles >= 2);
    d.spp = 4, d.seed = 1;
    assert_int_equal(fv_reference_render(s, &in, &d, lo[0], lo[1], NULL), FV_OK);
    d.spp = 16, d.seed = 2;
    assert_int_equal(fv_reference_render(s, &in, &d, hi[0], hi[1], NULL), FV_OK);
    double e4 = sqrt(0.5 * (pow(rmse(lo[0], ref[0], n), 2) + pow(rmse(lo[1], ref[1], n), 2)));
    double e16 = sqrt(0.5 * (pow(rmse(hi[0], ref[0], n), 2) + pow(rmse(hi[1], ref[1], n), 2)));
    /* the reference's own noise (1/64 of the 4-spp variance) lowers the ratio from 2 to about 1.96 */
    double ratio = e4 / e16;
    print_message("RMSE 4 spp %.4g, 16 spp %.4g: ratio %.3f (2 expected)\n", e4, e16, ratio);
    assert_true(e16 > 0);
    assert_true(ratio > 2.0 * 0.8 && ratio < 2.0 * 1.2);
    for (int e = 0; e < 2; e++) {
        free(ref[e]);
        free(lo[e]);
        free(hi[e]);
    }
    fv_scene_destroy(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(path_error_halves_when_spp_quadruples),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
