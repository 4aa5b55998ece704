/* @brief The GPU tests' CPU-reference helper (gpu_test_reference.c): for tests that link fv_reference. */
#ifndef FV_GPU_TEST_REFERENCE_H
#define FV_GPU_TEST_REFERENCE_H

#include "fv_reference.h"
#include "gpu_test.h"

/** The CPU reference's model-mode image of `in` (view: colour or one of its debug views) in the layout of
 *  fv_gpu_test_draw_sbs; fails the test on error or on any non-finite sample. */
void fv_gpu_test_reference_sbs(const fv_scene *s, const fv_frame_input *in, fv_reference_view view, uint32_t w,
                               uint32_t h, float *out_sbs);

#endif
