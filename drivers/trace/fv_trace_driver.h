/* @brief The "trace" driver: replays a recorded gaze file as a device. URI trace:FILE[?speed=S&loop=1&format=NAME
 * &blinks=PATH&min_confidence=C]. Replay is paced by the recorded timestamps on the clock given at open (real time
 * with the monotonic clock; stepped deterministically with a simulated clock). */
#ifndef FV_TRACE_DRIVER_H
#define FV_TRACE_DRIVER_H

#include "fovea/fv_device.h"

/** Scheme "trace". probe lists nothing (files are opened by URI, not discovered). */
extern const fv_driver fv_trace_driver;

#endif
