/* @brief The present pass: exposure, tonemap and sRGB encoding of the linear colour (FV_IMAGE_COLOR, read as a
 * storage image in GENERAL) into the display image (FV_IMAGE_DISPLAY, RGBA8 holding sRGB-encoded values, GENERAL),
 * which the renderer's target then shows (headless: kept on the GPU and read back; a window: copied to its
 * swapchain image). */
#ifndef FV_PRESENT_H
#define FV_PRESENT_H

#include "fv_pass.h"

/** The pass's entry in the renderer's table. */
extern const fv_pass fv_present_pass;

#endif
