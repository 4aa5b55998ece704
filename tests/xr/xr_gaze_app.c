/* @brief xr_gaze_app: an OpenXR app that reads predicted eye gaze from fovea's runtime. A headless session
 * (XR_MND_headless) runs a frame loop on fovea's display clock; every frame it locates the gaze action space at the
 * frame's predictedDisplayTime, as a renderer would for foveated rendering, and prints one CSV row per frame
 * (frame, predicted display time, tracked, yaw and pitch in degrees) and a summary on stderr.
 *   XR_RUNTIME_JSON=$(fovea xr manifest) FOVEA_XR_GAZE=trace:RECORDING xr_gaze_app [--frames N]
 * The runtime's statistics (FOVEA_XR_STATS=FILE) give the gaze-to-photon horizon the app saw. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "xr_app.h"

int main(int argc, char **argv)
{
    long frames = 300;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--frames") && i + 1 < argc) {
            char *end = NULL;
            frames = strtol(argv[++i], &end, 10);
            if (!end || *end || frames < 1 || frames > 10000000) {
                fprintf(stderr, "xr_gaze_app: --frames: expected 1..10000000, got '%s'\n", argv[i]);
                return 2;
            }
        } else {
            fprintf(stderr, "usage: xr_gaze_app [--frames N]   (FOVEA_XR_GAZE names the gaze source)\n");
            return 2;
        }
    }
    xr_app a;
    xr_app_open(&a, NULL, NULL);
    if (!a.supports_gaze) {
        fprintf(stderr, "xr_gaze_app: the runtime has no eye gaze (set FOVEA_XR_GAZE to a --gaze URI)\n");
        xr_app_close(&a);
        return 1;
    }
    printf("frame,predicted_display_time_ns,tracked,yaw_deg,pitch_deg\n");
    long tracked = 0;
    for (long f = 0; f < frames; f++) {
        XrTime t = xr_app_frame(&a);
        double d[3];
        XrSpaceLocationFlags fl = xr_app_locate(&a, t, d);
        bool tr = (fl & XR_APP_ALL_BITS) == XR_APP_ALL_BITS;
        tracked += tr;
        double yaw = atan2(d[0], -d[2]) * 180.0 / M_PI, pitch = asin(fmax(-1.0, fmin(1.0, d[1]))) * 180.0 / M_PI;
        if (fl & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT)
            printf("%ld,%lld,%d,%.4f,%.4f\n", f, (long long)t, tr, yaw, pitch);
        else
            printf("%ld,%lld,0,,\n", f, (long long)t);
    }
    fprintf(stderr, "xr_gaze_app: %ld frames, gaze tracked in %ld (%.1f%%)\n", frames, tracked,
            100.0 * (double)tracked / (double)frames);
    xr_app_close(&a);
    return 0;
}
