/* @brief Shared setup of the GPU tests: a renderer with the validation layer forced on, a skip (or, under
 * CI=true, a failure) when no Vulkan device is usable, and a teardown that fails on any validation message. */
#ifndef FV_GPU_TEST_H
#define FV_GPU_TEST_H

#include <stdint.h>

#include "fv_renderer.h"
#include "fv_scene.h"

/** cmocka group setup: create *r at w x h per eye with validation on. 0 on success or skip (*r NULL), -1 on
 *  failure (no device under CI=true). */
int fv_gpu_test_setup(uint32_t w, uint32_t h, fv_renderer **r);
/** The same, with the G-buffer's motion vectors drawn for read-back when `motion` (fv_renderer_desc.motion_target). */
int fv_gpu_test_setup_with(uint32_t w, uint32_t h, bool motion, fv_renderer **r);
/** cmocka group teardown: destroy *r; -1 if the validation layer said anything. */
int fv_gpu_test_teardown(fv_renderer **r);

/** A square of half-size `half` m in the local y = 0 plane, normal +y, two triangles (arrays from malloc, as
 *  fv_scene_add_mesh takes them). */
fv_mesh fv_gpu_test_square_mesh(const char *name, double half, uint32_t material);

/** Load a scene (built-in name or file) and hand it to r; fails the test on error. The caller destroys it. */
fv_scene *fv_gpu_test_load_scene(fv_renderer *r, const char *name_or_path);

/** The frame input r draws for its scene's head with quality q, at frame id *frame (then incremented: ids rise over
 *  a run) and scene time 0; foveation off (full resolution, as the CPU reference shades every pixel). */
fv_frame_input fv_gpu_test_frame_input(fv_renderer *r, uint64_t *frame, const fv_quality *q);

/** Draw `in` and read both eyes' linear colour as one 2w x h RGB image, the eyes side by side (as fv_metrics
 *  compares them); fails the test on any NaN or Inf, naming the pixel. */
void fv_gpu_test_draw_sbs(fv_renderer *r, const fv_frame_input *in, uint32_t w, uint32_t h, float *out_sbs);

/** Define `static fv_renderer *g_r` and the cmocka group `setup` / `teardown` that create it at w x h per eye with
 *  validation on and destroy it (failing on any validation message). FV_GPU_TEST_GROUP_MOTION: a renderer that
 *  draws the G-buffer's motion vectors for fv_renderer_read_motion (fv_renderer_desc.motion_target). */
#define FV_GPU_TEST_GROUP(w, h) FV_GPU_TEST_GROUP_WITH(w, h, false)
#define FV_GPU_TEST_GROUP_MOTION(w, h) FV_GPU_TEST_GROUP_WITH(w, h, true)
#define FV_GPU_TEST_GROUP_WITH(w, h, motion)                                                                           \
    static fv_renderer *g_r;                                                                                           \
    static int setup(void **state)                                                                                     \
    {                                                                                                                  \
        (void)state;                                                                                                   \
        return fv_gpu_test_setup_with((w), (h), (motion), &g_r);                                                       \
    }                                                                                                                  \
    static int teardown(void **state)                                                                                  \
    {                                                                                                                  \
        (void)state;                                                                                                   \
        return fv_gpu_test_teardown(&g_r);                                                                             \
    }

/** Skip the test when no device was available. */
#define FV_NEED_GPU(r)                                                                                                 \
    do {                                                                                                               \
        if (!(r)) skip();                                                                                              \
    } while (0)

#endif
