/* @brief `fovea xr`: fovea as an OpenXR runtime (xr/). `fovea xr manifest` prints the path of the runtime manifest
 * generated into the build tree, which XR_RUNTIME_JSON (or the user's active_runtime.json) points the OpenXR loader
 * at. */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "fovea_config.h"

static const char *const USAGE =
    "usage: fovea xr manifest\n"
    "\n"
    "fovea is an OpenXR runtime (libfovea_xr.so). 'fovea xr manifest' prints the path of its runtime manifest.\n"
    "Make fovea the active runtime for one app:\n"
    "  XR_RUNTIME_JSON=$(fovea xr manifest) hello_xr -g Vulkan2\n"
    "or for the user: ln -sf $(fovea xr manifest) ~/.config/openxr/1/active_runtime.json\n"
    "Environment read by the runtime: FOVEA_XR_GAZE (a --gaze URI: eye gaze for XR_EXT_eye_gaze_interaction and\n"
    "the quad-view insets of XR_VARJO_foveated_rendering), FOVEA_XR_HMD (HMD profile), FOVEA_XR_SCALE (render\n"
    "scale), FOVEA_XR_OUT (PNG of the last frame; FOVEA_XR_OUT_ALL=1: of every frame), FOVEA_XR_DISTORT=0 (no lens\n"
    "pass), FOVEA_XR_FRAMES (end the session after N frames), FOVEA_XR_STATS (frame statistics JSON),\n"
    "FOVEA_XR_PRESENT=auto|window|headless (auto: a window when there is a display), FOVEA_XR_PRESENT_MODE=\n"
    "fifo|mailbox|immediate (the window's present mode), FOVEA_XR_EGL_COPY=1 (OpenGL apps through EGL: copy the\n"
    "images to the compositor even where GL can share its memory).\n";

int fv_cmd_xr(int argc, char **argv)
{
    if (argc < 2 || fv_cli_is_help(argv[1])) {
        fputs(USAGE, argc < 2 ? stderr : stdout);
        return argc < 2 ? FV_EXIT_USAGE : FV_EXIT_OK;
    }
    if (strcmp(argv[1], "manifest") != 0)
        return fv_cli_usage_error("xr", USAGE, "unknown subcommand '%s' (there is: manifest)", argv[1]);
    if (argc > 2) return fv_cli_usage_error("xr", USAGE, "manifest takes no arguments ('%s')", argv[2]);
    struct stat st;
    if (stat(FV_XR_MANIFEST_PATH, &st) != 0) {
        fprintf(stderr, "fovea xr manifest: %s does not exist (build the fovea_xr target)\n", FV_XR_MANIFEST_PATH);
        return FV_EXIT_FAIL;
    }
    printf("%s\n", FV_XR_MANIFEST_PATH);
    return FV_EXIT_OK;
}
