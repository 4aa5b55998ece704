/* @brief The overlay pass (--overlay, fv_quality.overlay): draws the predicted gaze point, its uncertainty ring and,
 * with foveation on, the foveal boundary into the display image, after the present pass and before lens distortion
 * (so the lens pre-distorts the marks with the image) and the target. Reads the predicted gaze from the frame input
 * (the same prediction the frame is rendered for) and foveation's probability image ("fovea prob") when the fovea
 * pass runs. Layouts: FV_IMAGE_DISPLAY enters GENERAL (the present pass's) and leaves GENERAL, read and written by
 * compute; "fovea prob" is read in GENERAL. */
#ifndef FV_OVERLAY_H
#define FV_OVERLAY_H

#include "fv_pass.h"

/** The pass's entry in the renderer's table. */
extern const fv_pass fv_overlay_pass;

/** The push constants of one frame (overlay_interface.h) from a frame input: each eye's gaze (invalid, non-finite or
 *  zero directions: no gaze mark), its uncertainty clamped to [0, pi] rad, its frustum. Exposed for tests. */
struct fv_overlay_push;
void fv_overlay_push_from_input(const fv_frame_input *in, uint32_t width, uint32_t height, bool fovea,
                                struct fv_overlay_push *out);

#endif
