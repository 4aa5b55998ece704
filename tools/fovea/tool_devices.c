/* @brief The drivers of the fovea tool (all of them). Each driver library exports one `fv_driver` object. */
#include "tool_devices.h"

#include <math.h>
#include <string.h>

#include "fv_log.h"

#include "fv_fixed_driver.h" /* fv_fixed_driver */
#include "fv_hid_driver.h"   /* fv_hid_driver */
#include "fv_mouse_driver.h" /* fv_mouse_driver */
#include "fv_pupil_driver.h" /* fv_pupil_driver */
#include "fv_sim_driver.h"   /* fv_sim_driver */
#include "fv_trace_driver.h" /* fv_trace_driver */
#include "fv_usb_driver.h"   /* fv_usb_driver */

/* Hardware first; the recorded and simulated drivers register last. */
static const fv_driver *const g_drivers[] = {
    &fv_hid_driver,
    &fv_usb_driver,
    &fv_pupil_driver,
    &fv_trace_driver,
    &fv_fixed_driver,
    &fv_mouse_driver,
    &fv_sim_driver,
    NULL,
};

const fv_driver *const *fv_tool_drivers(void) { return g_drivers; }

fv_result fv_tool_declared_latency_ms(const char *uri, double *out_ms)
{
    *out_ms = 0.0;
    if (strncmp(uri, "sim:", 4) != 0) return FV_OK;
    fv_sim_eye_desc d;
    FV_TRY(fv_sim_driver_parse_uri(uri, &d, NULL));
    if (isfinite(d.latency_ms) && d.latency_ms >= 0) *out_ms = d.latency_ms;
    return FV_OK;
}

fv_result fv_tool_device_open(const char *uri, const fv_device_open_desc *desc, fv_device **out)
{
    const char *colon = strchr(uri, ':');
    size_t n = colon ? (size_t)(colon - uri) : strlen(uri);
    for (size_t i = 0; g_drivers[i]; i++) {
        if (strlen(g_drivers[i]->scheme) == n && strncmp(g_drivers[i]->scheme, uri, n) == 0)
            return g_drivers[i]->open(uri, desc, out);
    }
    char known[128] = "";
    for (size_t i = 0; g_drivers[i]; i++) {
        strncat(known, g_drivers[i]->scheme, sizeof known - strlen(known) - 3);
        if (g_drivers[i + 1]) strncat(known, ", ", sizeof known - strlen(known) - 1);
    }
    FV_ERROR("devices", "'%s': unknown URI scheme '%.*s' (this build knows: %s)", uri, (int)n, uri,
             known[0] ? known : "none");
    return FV_ERR_NOT_FOUND;
}
