/* @brief The drivers compiled into the fovea tool. Each driver library exports one `fv_driver` object. */
#include "tool_devices.h"

#include <string.h>

#include "fv_log.h"

#ifdef FV_HAVE_LIB_FV_HID
#include "fv_hid_driver.h" /* fv_hid_driver */
#endif
#ifdef FV_HAVE_LIB_FV_USB
#include "fv_usb_driver.h" /* fv_usb_driver */
#endif
#ifdef FV_HAVE_LIB_FV_TRACE
#include "fv_trace_driver.h" /* fv_trace_driver */
#endif
#ifdef FV_HAVE_LIB_FV_SIM
#include "fv_sim_driver.h" /* fv_sim_driver */
#endif

static const fv_driver *const g_drivers[] = {
#ifdef FV_HAVE_LIB_FV_HID
    &fv_hid_driver,
#endif
#ifdef FV_HAVE_LIB_FV_USB
    &fv_usb_driver,
#endif
#ifdef FV_HAVE_LIB_FV_TRACE
    &fv_trace_driver,
#endif
#ifdef FV_HAVE_LIB_FV_SIM
    &fv_sim_driver,
#endif
    NULL,
};

const fv_driver *const *fv_tool_drivers(void) { return g_drivers; }

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
