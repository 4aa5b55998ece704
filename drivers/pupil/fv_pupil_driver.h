/* @brief The `pupil` driver: live gaze from Pupil Capture (Pupil Labs Core) over its network API. Pupil Remote (a
 * ZeroMQ REQ/REP socket, default port 50020) names the subscription port (`SUB_PORT`) and the Pupil clock (`t`);
 * gaze datums arrive on a SUB socket as two-frame messages (topic "gaze.3d.01." etc., then a msgpack map). URI:
 * "pupil:HOST[:PORT][?fx=&fy=&cx=&cy=&width=&height=&min_confidence=&timeout_ms=]" (default 127.0.0.1:50020).
 * The decoder is a pure function on bytes (no I/O, no clock); pupil_device.c owns the sockets. */
#ifndef FV_PUPIL_DRIVER_H
#define FV_PUPIL_DRIVER_H

#include <stddef.h>

#include "fovea/fv_device.h"

extern const fv_driver fv_pupil_driver;

#define FV_PUPIL_DEFAULT_PORT 50020
/** Largest gaze payload decoded (Capture's binocular 3D datum with its two pupil datums is about 2 KiB). */
#define FV_PUPIL_MAX_PAYLOAD 65536
/** Deepest nesting of arrays and maps decoded (Capture's gaze datum nests 5: datum, base_data, pupil datum, its
 *  ellipse, the ellipse's centre). */
#define FV_PUPIL_MAX_DEPTH 16

/** Pinhole model of the scene (world) camera, used to turn the 2D pipeline's norm_pos into a direction. Pixels,
 *  origin top-left. Default: Pupil Core's world camera at 1280x720 with an 800 px focal length, principal point at
 *  the image centre (the same model as the recorded Pupil Core reader). */
typedef struct fv_pupil_camera {
    double width_px, height_px, fx_px, fy_px, cx_px, cy_px;
} fv_pupil_camera;

/** A parsed pupil: URI. */
typedef struct fv_pupil_uri {
    char host[256];         /* "127.0.0.1", "capture.local", "::1" (written [::1] in the URI) */
    int port;               /* Pupil Remote port */
    fv_pupil_camera camera; /* for norm_pos */
    double min_confidence;  /* below it a sample is kept but invalid; default 0.6 (Pupil Labs' recommendation) */
    int timeout_ms;         /* how long open waits for Pupil Remote; default 1000 */
} fv_pupil_uri;

/** The default camera model (see fv_pupil_camera). */
fv_pupil_camera fv_pupil_camera_default(void);

/** Parse "pupil:HOST[:PORT][?k=v&...]". Logs what is wrong (the option, the value and the allowed range) and
 *  returns FV_ERR_INVALID_ARG. */
FV_MUST_CHECK fv_result fv_pupil_uri_parse(const char *uri, fv_pupil_uri *out);

/** Decode one gaze message: its topic frame ("gaze.3d.01.", "gaze.3d.1.", "gaze.2d.0.", ...) and its msgpack
 *  payload, into a sample in fovea's head frame (camera x right, y down, z forward -> head x, -y, -z; eye 0 is the
 *  right eye). 3D datums give per-eye origins and directions and the combined ray to gaze_point_3d; 2D datums give
 *  the combined direction from norm_pos through the camera model. The pupil diameter comes from base_data's
 *  diameter_3d (mm). Sets t_device_ns (Pupil time, ns) and seq = 0; t_host_ns is left 0. A datum below
 *  min_confidence is FV_OK with every eye invalid. FV_ERR_PARSE for a malformed message, with the reason (the field
 *  and what is wrong with it) in why. Before anything is unpacked the payload is walked once: a count or size
 *  larger than the bytes left, nesting deeper than FV_PUPIL_MAX_DEPTH, a truncated or trailing value is refused, so
 *  what is allocated is bounded by the payload's length. Pure: no I/O, no clock, no logging. */
FV_MUST_CHECK fv_result fv_pupil_decode_gaze(const char *topic, size_t topic_len, const void *payload, size_t len,
                                             const fv_pupil_camera *camera, double min_confidence,
                                             fv_gaze_sample *out, char *why, size_t why_cap);

#endif
