/* @brief Where fovea's OpenXR runtime shows the composited frames: in fovea's window presenter (render/window, GLFW)
 * when there is a display, headless otherwise. The choice is made once per compositor (its Vulkan device must be made
 * able to present to the window's surface):
 *   FOVEA_XR_PRESENT=auto (default): a window when DISPLAY or WAYLAND_DISPLAY is set and GLFW opens one, else
 *                    headless; FOVEA_XR_OUT (PNG files) means headless too.
 *   FOVEA_XR_PRESENT=window: a window or an error (no headless fallback).
 *   FOVEA_XR_PRESENT=headless: never a window.
 *   FOVEA_XR_PRESENT_MODE=fifo|mailbox|immediate: the window's present mode (fifo by default).
 * In a window the session's display clock is the window's swapchain clock (xrWaitFrame paces to it and
 * predictedDisplayTime comes from it); closing the window stops the session (STOPPING -> the app ends it ->
 * EXITING); a present that fails for good, or the X server going away, loses the display (LOSS_PENDING). An app that only makes XR_MND_headless
 * sessions (no graphics binding, no graphics calls) never creates the compositor, so never opens a window. GLFW's rule: the thread that calls the graphics
 * functions and xrEndFrame is the one that made the window (an app's main thread, as in hello_xr). */
#ifndef FV_XR_PRESENT_H
#define FV_XR_PRESENT_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "fovea/fv_display.h"
#include "fv_result.h"
#include "fv_target.h"
#include "fv_vk.h"

typedef struct fv_xr_present fv_xr_present;

/** Choose the presenter from the environment and open the window when windowed (eye_w x eye_h per eye, the app's
 *  name in the title). FV_ERR_INVALID_ARG for a bad FOVEA_XR_PRESENT / FOVEA_XR_PRESENT_MODE (logged, naming the
 *  variable); FOVEA_XR_PRESENT=window without a display: FV_ERR_UNSUPPORTED. */
FV_MUST_CHECK fv_result fv_xr_present_create(const char *app_name, uint32_t eye_w, uint32_t eye_h,
                                             fv_xr_present **out);
/** Close the window (after fv_xr_present_detach and after the device is gone). Safe on NULL. */
void fv_xr_present_destroy(fv_xr_present **p);
/** Add what presenting needs to the compositor's device description (the window's surface, its instance extensions,
 *  VK_GOOGLE_display_timing when there), keeping the optional extensions already asked for. Headless: nothing. */
void fv_xr_present_configure_vk(fv_xr_present *p, fv_vk_desc *d);
/** The device is about to go: the window lets go of its swapchain. */
void fv_xr_present_detach(fv_xr_present *p, fv_vk *vk);
/** Whether frames go to a window. */
bool fv_xr_present_windowed(const fv_xr_present *p);
/** The window's target (owned by the window), or NULL when headless. */
fv_target *fv_xr_present_target(fv_xr_present *p);
/** The display clock of the window's swapchain (owned by the window), or NULL when headless. */
fv_display *fv_xr_present_display(fv_xr_present *p);
/** Whether the window's display went away (the X server: Xlib's I/O error, where libX11 lets the app live). */
bool fv_xr_present_lost(const fv_xr_present *p);
/** Handle the window's events; false once it was closed (or Esc pressed). Headless or lost: true. */
bool fv_xr_present_poll(fv_xr_present *p);
/** The presenter's part of the statistics JSON (FOVEA_XR_STATS): lines `  "key": value,`. */
void fv_xr_present_write_stats(const fv_xr_present *p, FILE *f);

#endif
