/* @brief The distortion pass: pre-distorts each eye of the display image for its HMD lens (fv_lens.h, the frame's
 * quality.distort.lens) with chromatic aberration, after the present pass and before the target. It copies the
 * display image (FV_IMAGE_DISPLAY, sRGB-encoded RGBA8) into its own sampled copy of sRGB format (so bilinear
 * filtering happens on linear values), then writes every display pixel from it.
 * Layouts: FV_IMAGE_DISPLAY enters as the present pass left it (GENERAL) and leaves GENERAL, written by compute;
 * the copy ("distort source") is TRANSFER_DST while copied and SHADER_READ_ONLY while sampled. On only when
 * distort.enabled and the frame has a lens. */
#ifndef FV_DISTORT_H
#define FV_DISTORT_H

#include "fv_pass.h"

/** The pass's entry in the renderer's table. */
extern const fv_pass fv_distort_pass;

#endif
