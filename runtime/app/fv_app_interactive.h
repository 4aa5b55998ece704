/* @brief Where an interactive run starts on a software (CPU) Vulkan device: a window, or a run following a gaze
 * tracker, is only interactive when a frame takes a fraction of a second, and a software rasteriser at the default
 * 720x800 per eye takes seconds (the gaze prediction then spans seconds and foveation stops following the eye). When
 * the user left the size and the budget to fovea, such a run starts at a size whose pixels the device's CPU cores can
 * shade in about FV_APP_SOFT_FRAME_MS, with the frame budget on at that period, and says so in one line with the
 * options that override it. Pure: no I/O. */
#ifndef FV_APP_INTERACTIVE_H
#define FV_APP_INTERACTIVE_H

#include <stdbool.h>
#include <stdint.h>

/** The frame time an interactive software run is budgeted for (ms). */
#define FV_APP_SOFT_FRAME_MS 100.0
/** Eye pixels (both eyes) a CPU core shades per such frame at the balanced preset (measured on lavapipe, Mesa 22,
 *  a contended 2-core machine: 16k pixels per core and 100 ms; docs/frame-time.md). */
#define FV_APP_SOFT_PIXELS_PER_CORE 16000.0
/** The smallest eye side it picks. */
#define FV_APP_SOFT_MIN_SIDE 64u

typedef struct fv_app_interactive_in {
    bool software;        /* the chosen Vulkan device is a CPU (VK_PHYSICAL_DEVICE_TYPE_CPU: lavapipe) */
    bool interactive;     /* a window, or a --gaze run */
    bool size_given;      /* --eye-size (or a size a named HMD fixes) */
    bool budget_given;    /* --budget or --budget-scale */
    uint32_t eye_w, eye_h; /* the size the run would have */
    double hz;            /* the display's refresh rate the budget scales from (> 0) */
    uint32_t cpu_cores;   /* online cores (>= 1) */
} fv_app_interactive_in;

typedef struct fv_app_interactive {
    bool applied;         /* false: the run starts as the user asked */
    uint32_t eye_w, eye_h;
    bool budget;          /* --budget auto */
    double budget_scale;  /* the budget's period / the display's (FV_APP_SOFT_FRAME_MS at hz) */
    char line[320];       /* the one start-up line (applied only) */
} fv_app_interactive;

/** The start of a run (see above). Keeps the aspect ratio; never grows the size; sides rounded down to even. */
void fv_app_interactive_start(const fv_app_interactive_in *in, fv_app_interactive *out);

#endif
