/* @brief The display-clock interface: when the display's vertical syncs happen, which vsync a frame presented at a
 * given time will be shown at, and when that frame's photons reach the eye. Implemented by a swapchain (real timing)
 * and by sim/display (a simulated panel on an injected fv_clock). All times are ns on the host clock.
 *
 * Photon time: the representative moment the frame's light reaches the eye — for a rolling scan-out, the middle row
 * of the image lit at the middle of its persistence; for a global (strobed) panel, the middle of the flash. */
#ifndef FV_DISPLAY_H
#define FV_DISPLAY_H

#include <stddef.h>
#include <stdint.h>

#include "fv_result.h"

/** One vertical sync: its index on the display's timeline and when it happens. */
typedef struct fv_vsync {
    uint64_t index;
    int64_t t_ns;
} fv_vsync;

typedef struct fv_display fv_display;

/** Operations of a display clock. Called from the frame-loop thread only. */
typedef struct fv_display_ops {
    /** The first vsync with t_ns >= t_ns_min. */
    fv_result (*vsync_at_or_after)(fv_display *d, int64_t t_ns_min, fv_vsync *out_vsync);
    /** Photon time of a frame whose scan-out starts at vsync v. */
    int64_t (*photon_ns)(fv_display *d, const fv_vsync *v);
    /** A frame finished at t_present_ns, meant for vsync `target_index`: which vsync shows it (never earlier than the
     *  target; later when presented after the target's latch deadline, i.e. the frame missed it). */
    fv_result (*present)(fv_display *d, int64_t t_present_ns, uint64_t target_index, fv_vsync *out_shown);
    /** Free everything, the display object included. */
    void (*destroy)(fv_display *d);
} fv_display_ops;

/** Base of every display clock; implementations embed it as their first member. */
struct fv_display {
    const fv_display_ops *ops;
    double refresh_hz;          /* nominal refresh rate */
    int64_t period_ns;          /* nominal refresh period */
    int64_t present_margin_ns;  /* a frame must be presented this long before a vsync to be shown at it */
};

FV_MUST_CHECK static inline fv_result fv_display_vsync_at_or_after(fv_display *d, int64_t t_ns_min,
                                                                   fv_vsync *out_vsync)
{
    return d->ops->vsync_at_or_after(d, t_ns_min, out_vsync);
}

static inline int64_t fv_display_photon_ns(fv_display *d, const fv_vsync *v) { return d->ops->photon_ns(d, v); }

FV_MUST_CHECK static inline fv_result fv_display_present(fv_display *d, int64_t t_present_ns,
                                                         uint64_t target_index, fv_vsync *out_shown)
{
    return d->ops->present(d, t_present_ns, target_index, out_shown);
}

/** Destroy and set *d to NULL; safe on NULL. */
static inline void fv_display_destroy(fv_display **d)
{
    if (d && *d) {
        (*d)->ops->destroy(*d);
        *d = NULL;
    }
}

#endif
