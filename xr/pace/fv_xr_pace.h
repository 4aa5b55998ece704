/* @brief The display period fovea's OpenXR runtime paces apps at: the refresh period, or an integer multiple k of it
 * when the compositor cannot finish a frame within one refresh (as SteamVR's motion smoothing and Oculus's ASW drop
 * an app to 45 of 90 Hz). The compositor's own time per frame (without waiting for the app's GPU or for a window's
 * acquire and present, which wait for its display) goes into a window of the last FV_XR_PACE_WINDOW frames; its 75th
 * percentile (a one-off, such as a pipeline made on first use, does not count) is what a frame needs; k is the smallest integer whose k refreshes hold it, raised at once, lowered only
 * when the lower k holds it with FV_XR_PACE_HEADROOM to spare (no flapping between two k at the boundary).
 * xrWaitFrame then plans vsyncs k refreshes apart and reports predictedDisplayPeriod = k refreshes. */
#ifndef FV_XR_PACE_H
#define FV_XR_PACE_H

#include <stdbool.h>
#include <stdint.h>

#define FV_XR_PACE_WINDOW 16      /* frames in the window */
#define FV_XR_PACE_MIN_FRAMES 8   /* no estimate (k stays) before this many frames */
#define FV_XR_PACE_MAX 255        /* the largest divisor (2.8 s at 90 Hz; lavapipe needs 0.7 s a frame for the generic
                                   * HMD's whole panel: a lower ceiling made the period reported a lie there) */
#define FV_XR_PACE_HEADROOM 0.8   /* k is lowered when k - 1 refreshes hold the need with 20% to spare */

typedef struct fv_xr_pace_window {
    double ms[FV_XR_PACE_WINDOW];
    uint32_t count, next;
} fv_xr_pace_window;

/** Add one frame's time (ms; a negative or non-finite value is not counted). */
void fv_xr_pace_window_add(fv_xr_pace_window *w, double ms);
/** The time a frame needs (the window's 75th percentile, ms) into *out_ms; false (nothing written) while the window
 *  holds fewer than FV_XR_PACE_MIN_FRAMES frames. */
bool fv_xr_pace_window_need(const fv_xr_pace_window *w, double *out_ms);
/** The divisor after `k` (1..FV_XR_PACE_MAX; anything else counts as 1) for a frame that needs need_ms on a display
 *  refreshing every refresh_ms (> 0; else 1 is returned): raised at once to the smallest k with need_ms <= k
 *  refreshes, lowered to the smallest k with need_ms <= HEADROOM * k refreshes when that is below the current one. */
uint32_t fv_xr_pace_divisor(uint32_t k, double need_ms, double refresh_ms);

#endif
