/* @brief The debug-view pass, an example of how a pass plugs in: when the frame asks for a view
 * (fv_quality.debug_view: direct, shadow, cascade, albedo, normal, depth, gaze), it overwrites the linear colour
 * (FV_IMAGE_COLOR) after shading with that quantity — the same one `fovea reference --view` computes on the CPU —
 * which the present pass then encodes. Off otherwise (no work at all). */
#ifndef FV_DEBUG_H
#define FV_DEBUG_H

#include "fv_pass.h"

/** The pass's entry in the renderer's table. */
extern const fv_pass fv_debug_pass;

#endif
