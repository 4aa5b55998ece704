/* @brief A test-only driver plug-in (FOVEA_DRIVERS=path/to/this.so): scheme "probe", a fixed gaze (the fixed driver's
 * parameters after "probe:"), no devices listed (so "auto" never picks it). Loaded by the one driver list of the
 * application layer (runtime/app/fv_app_drivers.h), it must be visible to `fovea devices`, `fovea run --gaze` and an
 * OpenXR app's eye gaze alike (tests/runtime/test_cli_app.c, tests/xr/test_xr_gaze.c). */
#include <stdio.h>
#include <string.h>

#include "fv_app_drivers.h"
#include "fv_fixed_driver.h"

static fv_result probe_probe(fv_device_info *out, size_t cap, size_t *out_count)
{
    (void)out;
    (void)cap;
    *out_count = 0;
    return FV_OK;
}

static fv_result probe_open(const char *uri, const fv_device_open_desc *desc, fv_device **out)
{
    char fixed[512];
    const char *rest = strchr(uri, ':');
    snprintf(fixed, sizeof fixed, "fixed:%s", rest ? rest + 1 : "");
    return fv_fixed_driver.open(fixed, desc, out);
}

static const fv_driver g_probe = {.scheme = "probe", .summary = "test-only plug-in (a fixed gaze)",
                                  .probe = probe_probe, .open = probe_open};

__attribute__((visibility("default"))) const fv_driver *fv_driver_plugin(uint32_t version);
const fv_driver *fv_driver_plugin(uint32_t version)
{
    return version == FV_DRIVER_PLUGIN_VERSION ? &g_probe : NULL;
}
