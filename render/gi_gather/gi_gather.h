/* @brief The reduced-rate GI gather (knob gi.rate = half | quarter): indirect light is smooth along a surface, so
 * instead of gathering it at every shaded pixel, one invocation per r x r block of each eye's G-buffer (r = 2, 4 or 8)
 * gathers it at the block's sample pixel (the same gather as the shading function, fv_gi_irradiance, from the light
 * quad-tree the GI pass built earlier in the frame) into one image bound in the first GI image slot of the shading
 * inputs (ceil(W / r) x ceil(H / r) per eye; the sample's position and normal are the G-buffer's at its pixel). The shading function
 * then upsamples per pixel with a joint-bilateral filter (fv_gi_upsample in render/include/fv_gi_gather.glsl:
 * bilinear over the 2 x 2 nearest samples, each weighted by how well it lies on the pixel's plane and shares its
 * normal) and gathers per pixel only where no sample matches (depth edges, creases, thin objects). The cost is the
 * gather at W H / r^2 pixels per eye, whatever shading then visits (every pixel, or a foveated list). Runs when GI
 * runs (gi.enabled, a spot or directional light) and gi.rate is not full; docs/gi.md. */
#ifndef FV_GI_GATHER_H
#define FV_GI_GATHER_H

#include "fv_pass.h"

/** The pass's entry in the renderer's table. */
extern const fv_pass fv_gi_gather_pass;

#endif
