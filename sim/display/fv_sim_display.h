/* @brief A simulated display clock: a panel refreshing at a fixed rate with bounded, seeded vsync jitter, a scan-out
 * time and a panel persistence, giving vsync times and photon times on an injected fv_clock's timeline.
 * Deterministic: the same desc gives the same vsync sequence. Implements fv_display (fovea/fv_display.h). */
#ifndef FV_SIM_DISPLAY_H
#define FV_SIM_DISPLAY_H

#include <stdint.h>

#include "fovea/fv_display.h"
#include "fv_clock.h"

typedef enum fv_sim_display_scan {
    FV_SIM_DISPLAY_ROLLING = 0, /* rows light up as they are scanned out (OLED rolling): photons of the middle row */
    FV_SIM_DISPLAY_GLOBAL = 1,  /* the whole panel flashes after scan-out (strobed LCD backlight) */
} fv_sim_display_scan;

/** Zero means default for every field but vsync_jitter_ns and seed (0 = no jitter). */
typedef struct fv_sim_display_desc {
    const fv_clock *clock;      /* required: vsync 0 is at the clock's time at create (plus t0_offset_ns) */
    double refresh_hz;          /* 0 = 90; 1 .. 1000 */
    int64_t vsync_jitter_ns;    /* each vsync lands within ±this of its nominal time; 0 .. period/4 */
    uint64_t seed;              /* the jitter sequence */
    int64_t scanout_ns;         /* time to scan the image out; 0 = 95% of the period; at most the period */
    int64_t persistence_ns;     /* how long a row (or the panel) stays lit; 0 = 2 ms (or the period if shorter) */
    fv_sim_display_scan scan;   /* rolling (default) or global */
    int64_t present_margin_ns;  /* latch deadline before a vsync; 0 = 0.5 ms; at most half the period */
    int64_t t0_offset_ns;       /* vsync 0 relative to the clock's now; 0 = one period ahead */
} fv_sim_display_desc;

/** Create a simulated display. Each broken rule of the desc is logged ("display" module) with the value. */
FV_MUST_CHECK fv_result fv_sim_display_create(const fv_sim_display_desc *desc, fv_display **out_display);

/** Photon time minus vsync time for this display (constant: scan-out and persistence). */
int64_t fv_sim_display_photon_offset_ns(const fv_display *display);

#endif
