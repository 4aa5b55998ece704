/* @brief The shading pass: the shared shading function (render/include/fv_shade_common.glsl) over the decoded
 * G-buffer, for every pixel of both eyes, or, when the renderer re-shades a pixel list, only those pixels (the
 * others keep their values). Reads the G-buffer images as the G-buffer pass leaves them; writes FV_IMAGE_COLOR
 * (linear RGBA32F, GENERAL), visible to later compute reads and transfers. */
#ifndef FV_SHADE_H
#define FV_SHADE_H

#include "fv_pass.h"

/** The feature set the shade pass's pipeline is specialised for under quality q in a scene with (translucent) or
 *  without a translucent material (the techniques compiled in: GI mode or off, SSS, shadows), e.g.
 *  "gi=off sss=off shadows=off", into buf. */
const char *fv_shade_variant_name(const fv_quality *q, bool translucent, char *buf, size_t size);

/** The pass's entry in the renderer's table. */
extern const fv_pass fv_shade_pass;

#endif
