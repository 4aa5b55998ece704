/* @brief The "fixed" driver: a gaze that does not move, for tests, demos and headsets without an eye tracker.
 * URI: fixed:yaw_deg=Y,pitch_deg=P[,vergence_m=D][,rate_hz=R][,ipd_mm=I][,pupil_mm=M], keys in any order, each at
 * most once (',', '&' or '?' separate them). The gaze is in the head frame (+x right, +y up, -z forward): yaw
 * positive to the right, pitch positive up, both in [-89, 89] degrees (default 0). Without vergence_m both eyes
 * look parallel (a point at infinity); with it each eye looks at the point vergence_m metres along the cyclopean
 * ray from the midpoint between the eyes (0.05..1000 m). The eyes sit at -+ipd/2 on x (default 63 mm, 40..90).
 * Samples come at rate_hz (default 120, 1..2000) on the host clock from the moment it opens, pupil_mm (default 4,
 * 1..9) as the measured pupil, confidence 1. */
#ifndef FV_FIXED_DRIVER_H
#define FV_FIXED_DRIVER_H

#include <stdbool.h>

#include "fovea/fv_device.h"

typedef struct fv_fixed_desc {
    double yaw_deg, pitch_deg;
    double vergence_m; /* 0: parallel (infinity) */
    double rate_hz;
    double ipd_mm;
    double pupil_mm;
} fv_fixed_desc;

extern const fv_driver fv_fixed_driver;

/** Parse a fixed: URI (defaults for keys not given). FV_ERR_PARSE / FV_ERR_RANGE with the URI, the key and the
 *  reason in the log. */
FV_MUST_CHECK fv_result fv_fixed_parse_uri(const char *uri, fv_fixed_desc *out);
/** The sample the device reports (both eyes' origins and unit directions, combined ray, pupil), times 0. */
void fv_fixed_sample(const fv_fixed_desc *d, fv_gaze_sample *out);

#endif
