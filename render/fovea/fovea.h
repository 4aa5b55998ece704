/* @brief Foveated rendering (papers/README.md section 3): the "fovea" pass makes, from the predicted gaze of the
 * frame constants, a sampling probability per pixel (linear MAR) and a sample mask with at least one sample per
 * block, and compacts the sampled pixels of both eyes into the renderer's frame sample list (with its indirect
 * dispatch), which the shade pass then shades instead of the whole frame; the "reconstruct" pass, after shading,
 * gives every unshaded pixel its nearest sample's colour (1+JFA). Images (2-layer scratch, GENERAL): "fovea prob"
 * (R32F), "fovea mask" (R32UI), "fovea seeds a" / "fovea seeds b" (R32UI); FV_IMAGE_COLOR is read and written by
 * reconstruct in GENERAL. */
#ifndef FV_FOVEA_H
#define FV_FOVEA_H

#include "fv_pass.h"

/** The entries of the renderer's table: "fovea" before shading, "reconstruct" after it. */
extern const fv_pass fv_fovea_pass;
extern const fv_pass fv_reconstruct_pass;

/** The JFA step sizes for a block side (1, then block, halving up to 1); returns how many (<= cap). */
uint32_t fv_fovea_jfa_steps(uint32_t block, uint32_t *out_steps, uint32_t cap);

#endif
