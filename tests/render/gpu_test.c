/* @brief Shared setup of the GPU tests (see gpu_test.h). */
#include "gpu_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int fv_gpu_test_setup(uint32_t w, uint32_t h, fv_renderer **r)
{
    fv_renderer_desc d = {.eye_width = w, .eye_height = h, .validation = 1, .frames_in_flight = 2};
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
