/* @brief The window presenter (GLFW 3 + its Vulkan surface): a window showing both eyes side by side as on an HMD
 * panel, a target (fv_target.h) that copies the display image into a swapchain image each frame and presents it,
 * and the display clock paced by those presents (fv_present_clock.h). The swapchain is made at the first frame and
 * made again when the window is resized, when a present or acquire says it is out of date or suboptimal; a
 * minimised (zero-sized) window waits (its frames are drawn, not shown). Closing the window or pressing Esc asks
 * the program to stop (fv_window_poll). Works wherever GLFW does (X11, Wayland). Main thread only (GLFW's rule). */
#ifndef FV_WINDOW_H
#define FV_WINDOW_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_display.h"
#include "fv_result.h"
#include "fv_target.h"

typedef enum fv_window_present_mode {
    FV_WINDOW_FIFO = 0,      /* "fifo": vsync, never tears (every Vulkan surface has it) */
    FV_WINDOW_MAILBOX = 1,   /* "mailbox": vsync, the newest frame replaces a waiting one */
    FV_WINDOW_IMMEDIATE = 2, /* "immediate": no vsync, may tear */
} fv_window_present_mode;

/** "fifo", "mailbox", "immediate"; NULL out of range. */
const char *fv_window_present_mode_str(fv_window_present_mode m);
/** Parse one of those names; false for anything else. */
bool fv_window_present_mode_parse(const char *s, fv_window_present_mode *out);

/** Zero means default. */
typedef struct fv_window_desc {
    uint32_t width, height;         /* client area, screen px; 0 = both eyes at their size, scaled to fit 90% of the
                                     * screen (both 0 or neither) */
    uint32_t eye_width, eye_height; /* the rendered eye size: the default window size and the aspect kept */
    bool fit_to_screen;             /* scale a given width x height down (aspect kept) to fit 90% of the screen, e.g.
                                     * an HMD panel's size */
    const char *title;              /* NULL = "fovea" */
    fv_window_present_mode present_mode;
} fv_window_desc;

typedef struct fv_window fv_window;

/** Open the window (GLFW initialised here). FV_ERR_UNSUPPORTED with a clear message when there is no display or
 *  GLFW has no Vulkan. */
FV_MUST_CHECK fv_result fv_window_create(const fv_window_desc *desc, fv_window **out_window);
/** Close the window and terminate GLFW; sets *w to NULL; safe on NULL. The renderer using its target must be
 *  destroyed first. */
void fv_window_destroy(fv_window **w);
/** The window's target, for fv_renderer_desc.target (owned by the window). */
fv_target *fv_window_target(fv_window *w);
/** The display clock the window's presents pace (owned by the window; fv_display_destroy on it does nothing). */
fv_display *fv_window_display(fv_window *w);
/** Which clock that is ("VK_GOOGLE_display_timing" or host timestamps), once the first frame made the swapchain. */
const char *fv_window_clock_name(const fv_window *w);

/** Handle window events now. false once the window was closed or Esc pressed. */
bool fv_window_poll(fv_window *w);
/** Ask the window to close, as its close button does (the next frames are not shown, waits for a size end, and
 *  fv_window_poll says false). Only sets a flag: safe from Xlib's error handlers. */
void fv_window_request_close(fv_window *w);
/** The next key pressed since the last call (GLFW_KEY_* codes, e.g. 'F' = 70), 0 when none. Esc is not queued. */
int fv_window_next_key(fv_window *w);
/** Where the cursor is: the eye whose image it is over (0 left, 1 right) and its position in that eye's image,
 *  u right and v down, 0..1. false when the cursor is outside both images (or outside the window). */
bool fv_window_cursor(const fv_window *w, int *out_eye, float *out_u, float *out_v);
/** Set the window title (UTF-8). */
void fv_window_set_title(fv_window *w, const char *title);

/** What the presenter did, for summaries and tests. */
typedef struct fv_window_stats {
    uint64_t presents;           /* frames presented */
    uint64_t skipped;            /* frames drawn while minimised or closing, not shown */
    uint32_t swapchain_creations; /* the first one included */
    uint32_t out_of_date;        /* acquire/present results that asked for a new swapchain */
    uint32_t width, height;      /* current swapchain size */
    const char *present_mode;
    bool separate_present_queue; /* presents on another queue family (images shared concurrently) */
    bool refresh_measured;       /* the display clock's period came from vsyncs, not assumed (fv_present_clock.h) */
    uint64_t vsync_events;       /* vsync times the clock took */
} fv_window_stats;
void fv_window_get_stats(const fv_window *w, fv_window_stats *out);

#endif
