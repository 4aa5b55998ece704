/* @brief The "sim" driver: serves the simulated eye (fv_sim_eye.h) as a device, paced by the injected clock.
 * URI: sim:[key=value[,key=value...]] with the fields of fv_sim_eye_desc (seed, rate_hz, jitter_us, latency_ms,
 * transport_jitter_ms, dropout, eye_loss, precision_deg, accuracy_deg, blink_per_min, pursuit_prob, microsaccades,
 * skew_ppm, device_offset_s, ipd_mm, vmax_deg_s, c_deg, main_seq_spread) plus ts_bits (0 = 64-bit ns device
 * timestamps; 8..63 = a µs counter of that width, wrapped by the device and unwrapped by the driver with
 * fv_gaze_unwrap_push_host; open refuses a counter that wraps faster than twice the sample interval). Simulation time 0 is the host time at open; samples are delivered when the clock passes their
 * arrival time, with t_host_ns = that arrival time. */
#ifndef FV_SIM_DRIVER_H
#define FV_SIM_DRIVER_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_device.h"
#include "fv_sim_eye.h"

extern const fv_driver fv_sim_driver;

/** Parse a "sim:..." URI into a desc (starting from the defaults); out_ts_bits may be NULL. Logs the key and the
 *  reason on error (FV_ERR_PARSE for unknown keys or junk, FV_ERR_RANGE for values out of range). */
FV_MUST_CHECK fv_result fv_sim_driver_parse_uri(const char *uri, fv_sim_eye_desc *out, unsigned *out_ts_bits);
/** The simulated eye behind a device opened by the sim driver; NULL for any other device. */
fv_sim_eye *fv_sim_device_eye(fv_device *dev);
/** Host time at simulation time 0 (the open time on the device's clock); 0 for other devices. */
int64_t fv_sim_device_host_origin_ns(const fv_device *dev);
/** Truth of a recently delivered sample by its seq (the last 4096 are kept); false when unknown. */
bool fv_sim_device_truth(const fv_device *dev, uint64_t seq, fv_sim_truth *out);

#endif
