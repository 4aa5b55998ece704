/* @brief N-bit device timestamp unwrapper: turns a wrapping counter (32-bit µs wraps every ~71.6 min, 24-bit
 * counters every ~16.8 s at 1 µs) into a 64-bit nanosecond timeline. Survives wraps and small reordering; checked
 * against the host clock, it also survives gaps longer than half a wrap and counters that wrap faster than samples
 * arrive (reported once), without inventing samples. */
#ifndef FV_GAZE_UNWRAP_H
#define FV_GAZE_UNWRAP_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_result.h"

/** Unwrapper state; the caller embeds it. One owner; not thread-safe. */
typedef struct fv_gaze_unwrap {
    unsigned bits;        /* counter width, 1..64 */
    uint64_t mask;        /* 2^bits - 1 */
    int64_t tick_ns;      /* nanoseconds per counter tick (1000 for a µs counter) */
    bool started;
    uint64_t last_raw;    /* newest raw value seen (the reference for the next difference) */
    int64_t last_ticks;   /* unwrapped tick count of last_raw */
    bool have_host;       /* host_offset_ticks holds an estimate (push_host) */
    int64_t host_offset_ticks; /* host receipt − unwrapped device time, in ticks, smoothed (1/32 per value) */
    int64_t last_host_ns; /* the newest receipt time seen */
    uint64_t host_corrections; /* values whose counter difference disagreed with the host clock by half a wrap or
                                  more, resolved from the host clock (push_host) */
    const char *label;    /* optional, borrowed, set by the caller after init: names the device in the warning */
    bool warned;
} fv_gaze_unwrap;

/** Set up for a counter of `bits` bits (1..64) ticking every tick_ns (>0) nanoseconds. */
FV_MUST_CHECK fv_result fv_gaze_unwrap_init(fv_gaze_unwrap *u, unsigned bits, int64_t tick_ns);
/** Forget the history (the next value starts the timeline at raw * tick_ns). Keeps the label and the counters. */
void fv_gaze_unwrap_reset(fv_gaze_unwrap *u);
/** Unwrap one raw counter value into nanoseconds. The difference to the newest value is read as a signed number of
 *  half the counter's range, so a forward wrap continues the timeline and a value that arrives slightly late
 *  (reordered) maps to its earlier time without moving the reference. Bits above `bits` are ignored. Returns the
 *  unwrapped time in ns (saturating at INT64 limits). */
int64_t fv_gaze_unwrap_push(fv_gaze_unwrap *u, uint64_t raw);
/** As fv_gaze_unwrap_push, checked against host_ns, the value's receipt time on the host clock (ns; only differences
 *  matter). The counter alone cannot tell how many wraps passed between two values. The host time predicts the
 *  device time (receipt minus the smoothed receipt − device offset, which follows skew and averages the transport
 *  jitter); when the counter's reading lands half a wrap or more from that prediction (the counter wraps faster than
 *  twice the sample interval, or the device went quiet for over half a wrap), the value congruent to the counter,
 *  modulo the wrap, that is closest to the prediction is taken instead: the timeline keeps the host's pace and no
 *  samples are invented. Exact while the transport jitter stays under half a wrap; a counter that wraps faster than
 *  the jitter carries no information beyond the host clock, and then follows it. Counted in host_corrections and
 *  reported once (a warning naming label). A receipt time that goes back (another clock, a broken driver), or a
 *  counter of 62 bits or more, falls back to fv_gaze_unwrap_push. */
int64_t fv_gaze_unwrap_push_host(fv_gaze_unwrap *u, uint64_t raw, int64_t host_ns);
/** The counter's wrap period in ns (saturating; INT64_MAX for 63 bits and more). */
int64_t fv_gaze_unwrap_wrap_ns(const fv_gaze_unwrap *u);

#endif
