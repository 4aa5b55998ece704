/* @brief The one driver list of fovea's programs (`fovea` and the OpenXR runtime): the built-in drivers (hardware
 * first: hid, usb, pupil; then trace, fixed, mouse, sim) and the driver plug-ins named in FOVEA_DRIVERS (shared
 * objects, ':'-separated paths, each exporting `fv_driver_plugin`: see below), placed before the virtual drivers.
 * A driver added here, built in or plugged in, is what `fovea devices`, `fovea run --gaze`, `fovea trace record`,
 * `fovea latency` and an OpenXR app's eye gaze (FOVEA_XR_GAZE) all open. Thread-safe (built once). */
#ifndef FV_APP_DRIVERS_H
#define FV_APP_DRIVERS_H

#include <stddef.h>
#include <stdint.h>

#include "fovea/fv_device.h"

/** The plug-in interface version; a plug-in whose fv_driver_plugin is asked for another version returns NULL. */
#define FV_DRIVER_PLUGIN_VERSION 1u
/** What a plug-in exports: `const fv_driver *fv_driver_plugin(uint32_t version)`. */
typedef const fv_driver *(*fv_driver_plugin_fn)(uint32_t version);
/** Plug-ins loaded at most. */
#define FV_APP_MAX_PLUGINS 4

/** The drivers, NULL-terminated, in registry order. Loads FOVEA_DRIVERS's plug-ins on the first call (a path that
 *  cannot be loaded, lacks fv_driver_plugin, refuses the version or names a scheme already taken is skipped with one
 *  error line naming it and the reason). */
const fv_driver *const *fv_app_drivers(void);

/** Open a device by URI ("trace:FILE", "sim:seed=1", "hid:auto") with the driver of its scheme; an unknown scheme is
 *  FV_ERR_NOT_FOUND after one line listing the known schemes. Fits fv_gaze_source_open_fn (user unused). */
FV_MUST_CHECK fv_result fv_app_device_open(const char *uri, const fv_device_open_desc *desc, fv_device **out);
FV_MUST_CHECK fv_result fv_app_device_open_fn(void *user, const char *uri, const fv_device_open_desc *desc,
                                              fv_device **out);

/** The capture-to-receipt latency a URI declares, ms: a sim: URI's latency_ms (its default when not written), else
 *  0 (unknown). The one source of it for every frame loop, so all count the same tracker latency. An error (logged)
 *  when a sim: URI does not parse. */
FV_MUST_CHECK fv_result fv_app_declared_latency_ms(const char *uri, double *out_ms);

#endif
