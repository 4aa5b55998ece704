/* @brief The drivers this build of the fovea tool has, in probe order (hid, usb, then trace and sim last), and
 * opening a device by URI through them. */
#ifndef FV_TOOL_DEVICES_H
#define FV_TOOL_DEVICES_H

#include <stddef.h>

#include "fovea/fv_device.h"

/** The drivers compiled into this build, NULL-terminated, in registration order (sim and trace last). */
const fv_driver *const *fv_tool_drivers(void);
/** Open a device by URI ("trace:FILE", "sim:seed=1", "hid:auto") with the driver of its scheme. Logs the reason
 *  (unknown scheme lists the known ones). */
FV_MUST_CHECK fv_result fv_tool_device_open(const char *uri, const fv_device_open_desc *desc, fv_device **out);

/** The capture-to-receipt latency a URI declares, ms: a sim: URI's latency_ms (its default when not written), else
 *  0 (unknown). The one source of it for `fovea run` and `fovea latency`, so both count the same tracker latency.
 *  An error (logged by the parser) when a sim: URI does not parse. */
FV_MUST_CHECK fv_result fv_tool_declared_latency_ms(const char *uri, double *out_ms);

#endif
