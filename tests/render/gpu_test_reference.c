/* @brief The CPU reference's image in the GPU tests' layout (see gpu_test.h; links fv_reference). */
#include <stdlib.h>
#include <string.h>

#include "fv_test.h"
#include "gpu_test_reference.h"

void fv_gpu_test_reference_sbs(const fv_scene *s, const fv_frame_input *in, fv_reference_view view, uint32_t w,
                               uint32_t h, float *out_sbs)
{
    fv_reference_desc d = {.mode = FV_REFERENCE_MODEL, .view = view, .eye_width = w, .eye_height = h};
    size_t npix = (size_t)w * h, w2 = 2 * (size_t)w;
    float *eye[2] = {malloc(npix * 3 * sizeof(float)), malloc(npix * 3 * sizeof(float))};
    assert_true(eye[0] && eye[1]);
    fv_reference_stats st;
    assert_int_equal(fv_reference_render(s, in, &d, eye[0], eye[1], &st), FV_OK);
    assert_int_equal(st.nonfinite_samples, 0);
    for (int e = 0; e < 2; e++)
        for (size_t y = 0; y < h; y++)
            memcpy(&out_sbs[(y * w2 + (size_t)e * w) * 3], &eye[e][y * w * 3], w * 3 * sizeof(float));
    free(eye[0]);
    free(eye[1]);
}
