/* @brief What test_xr_hello, test_xr_quad and test_xr_egl do in the child of a fork before they exec the app under
 * test: its output to a log file and the environment every xr test runs an app in. */
#ifndef FV_XR_TEST_CHILD_H
#define FV_XR_TEST_CHILD_H

#include <stdbool.h>

/** In the child, before exec: its own process group; stdout and stderr to log_path (_exit(126) when it cannot be opened); XR_RUNTIME_JSON =
 *  manifest; the OpenXR core-validation layer when `layer` (else no API layer); the Vulkan validation layer on
 *  fovea's devices (FOVEA_VALIDATION=1); FOVEA_XR_SCALE = scale; FOVEA_XR_STATS = stats. The caller sets the rest. */
void xr_test_child_env(const char *log_path, const char *manifest, bool layer, const char *scale, const char *stats);

#endif
