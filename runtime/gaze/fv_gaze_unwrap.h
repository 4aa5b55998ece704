/* @brief N-bit device timestamp unwrapper: turns a wrapping counter (32-bit µs wraps every ~71.6 min, 24-bit
 * counters every ~16.8 s at 1 µs) into a 64-bit nanosecond timeline. Survives wraps and small reordering. */
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
} fv_gaze_unwrap;

/** Set up for a counter of `bits` bits (1..64) ticking every tick_ns (>0) nanoseconds. */
FV_MUST_CHECK fv_result fv_gaze_unwrap_init(fv_gaze_unwrap *u, unsigned bits, int64_t tick_ns);
/** Forget the history (the next value starts the timeline at raw * tick_ns). */
void fv_gaze_unwrap_reset(fv_gaze_unwrap *u);
/** Unwrap one raw counter value into nanoseconds. The difference to the newest value is read as a signed number of
 *  half the counter's range, so a forward wrap continues the timeline and a value that arrives slightly late
 *  (reordered) maps to its earlier time without moving the reference. Bits above `bits` are ignored. Returns the
 *  unwrapped time in ns (saturating at INT64 limits). */
int64_t fv_gaze_unwrap_push(fv_gaze_unwrap *u, uint64_t raw);

#endif
