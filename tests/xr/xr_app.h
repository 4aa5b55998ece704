/* @brief A small OpenXR app through the loader (XR_RUNTIME_JSON = fovea's manifest), shared by test_xr_gaze and
 * xr_gaze_app: a headless session (XR_MND_headless) with XR_EXT_eye_gaze_interaction, the gaze pose action bound to
 * /user/eyes_ext/input/gaze_ext/pose, its action space and a VIEW space; the session begun and FOCUSED. Any failed
 * call prints the call and its XrResult and exits (status 1). */
#ifndef FV_XR_APP_H
#define FV_XR_APP_H

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>

#include <openxr/openxr.h>

/** A failed call prints the call and its XrResult and exits (status 1). */
#define XR_APP_CHECK(call)                                                                                             \
    do {                                                                                                               \
        XrResult r_ = (call);                                                                                          \
        if (XR_FAILED(r_)) {                                                                                           \
            fprintf(stderr, "%s failed: %d\n", #call, (int)r_);                                                        \
            exit(1);                                                                                                   \
        }                                                                                                              \
    } while (0)

typedef struct xr_app {
    XrInstance inst;
    XrSystemId system;
    XrSession session;
    XrActionSet set;
    XrAction gaze;
    XrSpace gaze_space, view_space;
    bool supports_gaze; /* XrSystemEyeGazeInteractionPropertiesEXT */
} xr_app;

/** Open everything (gaze_uri: FOVEA_XR_GAZE, "" = none, NULL = the environment's; manifest: XR_RUNTIME_JSON, NULL = the environment's). */
void xr_app_open(xr_app *a, const char *manifest, const char *gaze_uri);
/** Request exit, end the session when STOPPING, destroy everything. */
void xr_app_close(xr_app *a);
/** CLOCK_MONOTONIC now as XrTime (fovea's XrTime). */
XrTime xr_app_now(void);
/** Sync the action set, then locate the gaze space in VIEW at t: the gaze direction (the pose's -z); the flags. */
XrSpaceLocationFlags xr_app_locate(xr_app *a, XrTime t, double out_dir[3]);
/** Angle between two directions, degrees. */
double xr_app_angle_deg(const double a[3], const double b[3]);
/** One headless frame: xrWaitFrame, xrBeginFrame, xrEndFrame with no layers; the predicted display time. */
XrTime xr_app_frame(xr_app *a);

/** The session's life cycle for an app with a frame loop: begin at READY, end at STOPPING, done at EXITING or
 *  LOSS_PENDING; `frame(ctx, n, visible)` runs frames 0..frames-1 while the session runs (visible: VISIBLE or
 *  FOCUSED), then the app requests exit. Returns the frames run. */
int xr_app_run_session(XrInstance inst, XrSession session, XrViewConfigurationType config, int frames,
                       void (*frame)(void *ctx, int n, bool visible), void *ctx);

/** A flag of an app's command line: `name` (e.g. "--gl") sets *value. */
typedef struct xr_app_flag {
    const char *name;
    bool *value;
} xr_app_flag;
/** An app's command line: `--frames N` into *frames (checked to be in 1..100000 at the end), the `flag_count` flags,
 *  and for any other argument `other` (may be NULL), called with *i at it: 1 when it took it (and moved *i past its
 *  values), 0 when it is not its, 2 when it refused it (after printing why). Returns 0, or the exit status 2 after
 *  printing "usage: ARGV0 USAGE" or the reason. */
int xr_app_args(int argc, char **argv, const char *usage, int *frames, const xr_app_flag *flags, int flag_count,
                int (*other)(void *ctx, int argc, char **argv, int *i), void *ctx);

#define XR_APP_ALL_BITS                                                                                                \
    (XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT |                                \
     XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT)
#define XR_APP_TRACKED_BITS (XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT)

#endif
