/* @brief The "mouse" driver: in a window, the cursor is the gaze point of both eyes, so anyone can see foveation
 * without an eye tracker. The program that owns the window tells the driver where the cursor is (fv_mouse_pointer_*,
 * from its event loop); the device turns that into gaze samples through the same pipeline as a tracker.
 * URI: mouse:[vergence_m=D][,rate_hz=R] — the cursor over one eye's image is the point on that eye's ray through
 * the pixel at D metres in front of the eyes (default 1.5, 0.05..1000); both eyes look at it (their vergence follows
 * from the IPD); samples at R Hz (default 250, 1..2000) on the host clock. The pupil is unknown. While the cursor is
 * outside both images the last point is held (a mouse does not blink). Without a window, open fails with a clear
 * error. The pointer state is process-wide and thread-safe (the window's thread writes, the reader thread reads). */
#ifndef FV_MOUSE_DRIVER_H
#define FV_MOUSE_DRIVER_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_device.h"

extern const fv_driver fv_mouse_driver;

/** The eyes the window shows: per eye the signed frustum tangents of its image (left < right, down < up, as
 *  fv_eye_view: tan_left, tan_right, tan_up, tan_down), and the IPD. Eye frames are the head frame moved by
 *  -+ipd/2 on x (no toe-in), as fv_eye_views_build makes them. */
typedef struct fv_mouse_views {
    float tan_left[2], tan_right[2], tan_up[2], tan_down[2];
    float ipd_mm;
} fv_mouse_views;

/** A window with these eyes exists: mouse: devices may open. */
void fv_mouse_pointer_attach(const fv_mouse_views *views);
/** The window is gone: open devices report the device lost, new opens fail. */
void fv_mouse_pointer_detach(void);
/** The cursor is over eye `eye`'s image (0 left, 1 right) at u (right), v (down) in 0..1, at host time t_ns. */
void fv_mouse_pointer_move(int eye, float u, float v, int64_t t_ns);

/** Options of a mouse: URI. */
typedef struct fv_mouse_desc {
    double vergence_m;
    double rate_hz;
} fv_mouse_desc;

/** Parse a mouse: URI (defaults for keys not given); FV_ERR_PARSE / FV_ERR_RANGE with the key and reason logged. */
FV_MUST_CHECK fv_result fv_mouse_parse_uri(const char *uri, fv_mouse_desc *out);
/** The gaze of a cursor at (u, v) over eye `eye`'s image (clamped to the image; NaN = its centre) with the point
 *  vergence_m ahead: both eyes' origins and unit directions, and the cyclopean ray, head frame; times 0, pupil
 *  unknown. Finite for any input. */
void fv_mouse_gaze(const fv_mouse_views *views, int eye, float u, float v, double vergence_m, fv_gaze_sample *out);

#endif
