/* @brief The debug-view pass, an example of how a pass plugs in: when the quality asks for a debug view
 * (fv_quality.debug_view), it overwrites the linear colour (FV_IMAGE_COLOR) after shading with a view of the frame's
 * data — the G-buffer normal, or the predicted gaze from the frame constants — which the present pass then encodes.
 * Off otherwise (no work at all). */
#ifndef FV_DEBUG_H
#define FV_DEBUG_H

#include "fv_pass.h"

/** The pass's entry in the renderer's table. */
extern const fv_pass fv_debug_pass;

#endif
