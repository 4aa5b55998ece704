/* @brief Shared setup of the GPU tests (see gpu_test.h). */
#include "gpu_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_test.h"

int fv_gpu_test_setup(uint32_t w, uint32_t h, fv_renderer **r) { return fv_gpu_test_setup_with(w, h, false, r); }

int fv_gpu_test_setup_with(uint32_t w, uint32_t h, bool motion, fv_renderer **r)
{
    fv_renderer_desc d = {.eye_width = w, .eye_height = h, .validation = 1, .frames_in_flight = 2,
                          .motion_target = motion};
    fv_result res = fv_renderer_create(&d, r);
    if (res == FV_OK) return 0;
    *r = NULL;
    const char *ci = getenv("CI");
    if (ci && strcmp(ci, "true") == 0) {
        fprintf(stderr, "no usable Vulkan device (%s) and CI=true: failing\n", fv_result_str(res));
        return -1;
    }
    fprintf(stderr, "SKIP: no usable Vulkan device (%s); set CI=true to make this a failure\n", fv_result_str(res));
    return 0;
}

int fv_gpu_test_teardown(fv_renderer **r)
{
    uint32_t n = fv_renderer_validation_messages(*r);
    fv_renderer_destroy(r);
    if (n) fprintf(stderr, "%u validation messages\n", n);
    return n ? -1 : 0;
}

fv_mesh fv_gpu_test_square_mesh(const char *name, double half, uint32_t material)
{
    fv_mesh m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%s", name);
    m.vertex_count = 4;
    m.index_count = 6;
    m.positions = malloc(4 * sizeof *m.positions);
    m.normals = malloc(4 * sizeof *m.normals);
    m.indices = malloc(6 * sizeof *m.indices);
    float h = (float)half;
    fv_vec3 p[4] = {{-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}};
    uint32_t idx[6] = {0, 2, 1, 0, 3, 2};
    if (m.positions && m.normals && m.indices) {
        for (int i = 0; i < 4; i++) {
            m.positions[i] = p[i];
            m.normals[i] = fv_v3(0, 1, 0);
        }
        memcpy(m.indices, idx, sizeof idx);
    }
    m.material = material;
    m.bounds_min = fv_v3(-h, 0, -h);
    m.bounds_max = fv_v3(h, 0, h);
    return m;
}

fv_scene *fv_gpu_test_load_scene(fv_renderer *r, const char *name_or_path)
{
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load(name_or_path, &s), FV_OK);
    assert_int_equal(fv_renderer_load_scene(r, s), FV_OK);
    return s;
}

fv_frame_input fv_gpu_test_frame_input(fv_renderer *r, uint64_t *frame, const fv_quality *q)
{
    fv_frame_input in;
    assert_int_equal(fv_renderer_frame_input(r, NULL, (*frame)++, 0.0, &in), FV_OK);
    in.quality = *q;
    in.quality.fovea.enabled = false;
    return in;
}

void fv_gpu_test_draw_sbs(fv_renderer *r, const fv_frame_input *in, uint32_t w, uint32_t h, float *out_sbs)
{
    assert_int_equal(fv_renderer_draw(r, in), FV_OK);
    size_t npix = (size_t)w * h, w2 = 2 * (size_t)w;
    float *rgba = malloc(npix * 4 * sizeof *rgba);
    assert_non_null(rgba);
    for (uint32_t eye = 0; eye < 2; eye++) {
        assert_int_equal(fv_renderer_read_linear(r, eye, rgba, npix * 4), FV_OK);
        for (size_t y = 0; y < h; y++)
            for (size_t x = 0; x < w; x++)
                for (int c = 0; c < 3; c++) {
                    float v = rgba[(y * w + x) * 4 + c];
                    if (!isfinite(v)) fail_msg("GPU eye %u pixel (%zu, %zu) channel %d is %g", eye, x, y, c, (double)v);
                    out_sbs[(y * w2 + (size_t)eye * w + x) * 3 + c] = v;
                }
    }
    free(rgba);
}
