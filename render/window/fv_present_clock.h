/* @brief The display clock of a real swapchain (implements fv_display, fovea/fv_display.h): vsync times on the host
 * clock estimated from timestamps the presenter feeds it. Two kinds of evidence:
 *  - vsync events: times known to lie on a vsync — VK_GOOGLE_display_timing's actual present times, or the host
 *    time a FIFO acquire returned after it had to wait (a waiting acquire is released by a flip, i.e. a vsync);
 *  Without vsync events (mailbox, immediate, or a renderer too slow for FIFO to ever wait) the period stays the
 *  nominal one (60 Hz when unknown) and period_measured stays false: a render-bound cadence says how fast fovea
 *  draws, not how fast the display refreshes.
 * The refresh period is the robust average of the intervals between recent vsync events, each divided by its whole
 * number of periods (a missed refresh gives an interval of 2 periods, not a slower display), seeded by the nominal
 * refresh rate (the monitor's, when known) and kept within 1..1000 Hz; a measured rate below 20 Hz is not believed
 * (an acquire blocked by a slow software presenter looks like a slow display). A present is shown at the first vsync after
 * its latch (fv_display_present ignores the target: a swapchain present has no target time). The vsync grid is anchored at the newest event;
 * vsync indices only ever increase. Pure computation on given times: no clock reads, no allocation, no Vulkan.
 * One owner thread. */
#ifndef FV_PRESENT_CLOCK_H
#define FV_PRESENT_CLOCK_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_display.h"

/** Where the clock's vsync events come from (what the summary reports). */
typedef enum fv_present_clock_source {
    FV_PRESENT_CLOCK_CADENCE = 0,        /* host timestamps around acquire/present, period from their cadence */
    FV_PRESENT_CLOCK_DISPLAY_TIMING = 1, /* VK_GOOGLE_display_timing: actual present times and the refresh cycle */
} fv_present_clock_source;

#define FV_PRESENT_CLOCK_WINDOW 32 /* vsync intervals the period estimate looks back over */

typedef struct fv_present_clock {
    fv_display base;                 /* first member: ops, refresh_hz, period_ns, present_margin_ns */
    fv_present_clock_source source;
    int64_t nominal_period_ns;       /* from the monitor or the extension; 0 = unknown */
    double period_exact_ns;          /* the current estimate */
    int64_t intervals[FV_PRESENT_CLOCK_WINDOW]; /* between consecutive vsync events, ns */
    uint32_t interval_count, interval_next;
    bool period_measured;            /* the period came from vsync events, not from the nominal rate */
    int64_t anchor_ns;               /* a vsync time: the newest event (or the creation time) */
    uint64_t anchor_index;
    uint64_t vsync_events;           /* events taken */
    uint64_t presents;               /* fv_display_present calls */
} fv_present_clock;

/** Start a clock at host time t0_ns (the first vsync grid is anchored there). nominal_hz: the display's refresh rate
 *  when known (outside 1..1000 or NaN = unknown: 60 Hz until events say otherwise). */
void fv_present_clock_init(fv_present_clock *c, fv_present_clock_source source, double nominal_hz, int64_t t0_ns);
/** A time known to be a vsync (see the header). Times earlier than the anchor are ignored. */
void fv_present_clock_vsync(fv_present_clock *c, int64_t t_ns);
/** "VK_GOOGLE_display_timing" or "host timestamps (acquire/present cadence)". */
const char *fv_present_clock_source_str(fv_present_clock_source source);

#endif
