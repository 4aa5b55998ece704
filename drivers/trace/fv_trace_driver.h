/* @brief The "trace" driver: replays a recorded gaze file as a device. URI trace:FILE[?speed=S&loop=1&format=NAME
 * &blinks=PATH&min_confidence=C]. Replay is paced by the recorded timestamps on the clock given at open (real time
 * with the monotonic clock; stepped deterministically with a simulated clock). All replay time arithmetic saturates,
 * so no timestamps in a file can overflow it. */
#ifndef FV_TRACE_DRIVER_H
#define FV_TRACE_DRIVER_H

#include "fovea/fv_device.h"
#include "fv_trace.h"

/** Scheme "trace". probe lists nothing (files are opened by URI, not discovered). */
extern const fv_driver fv_trace_driver;

/** How to replay (the URI's speed and loop). Zero means default. */
typedef struct fv_trace_replay_desc {
    double speed;          /* playback speed in (0, 1000]; 0 = 1 */
    int loop;              /* 1: start over at the end, the timeline carried on */
    const fv_clock *clock; /* pacing clock and t_host_ns; NULL = monotonic. A simulated clock is borrowed mutable */
    const char *uri;       /* shown in the device info; NULL = the reader's name */
} fv_trace_replay_desc;

/** Replay an open reader (a file or memory) as a device: what the URI open does once it has made the reader; tests
 *  and fuzzers use it on memory input. Takes ownership of reader: it is destroyed at close, or here on failure.
 *  Reads up to 64 samples ahead to learn the rate. One owner; not thread-safe. */
FV_MUST_CHECK fv_result fv_trace_replay_open(fv_trace_reader *reader, const fv_trace_replay_desc *desc,
                                             fv_device **out_dev);

/** The source blink events a trace device's reader has met so far (as `fovea trace info` counts them: Pupil's
 *  blinks.csv events that covered a sample); 0 for any other device or a format without blink events. */
uint64_t fv_trace_device_blink_events(const fv_device *dev);
/** The counters of a trace device's reader so far (impossible gaze repaired and dropped, bad rows, ...); NULL for
 *  any other device. Valid until the device is closed. */
const fv_trace_reader_stats *fv_trace_device_reader_stats(const fv_device *dev);

#endif
