/* @brief The subsurface-scattering pass (render/sss): for every (light, translucent material) pair a light-view
 * sample map — the scene drawn from the light, the material's nearest surfaces becoming samples of position, the
 * surface area each texel covers, the flux entering through Schlick's transmittance, depth and normal, everything
 * else occluding — then the quad-tree of those samples (sss_build.comp), bound with a per-frame header in the shading
 * inputs' SSS slot, where the shared shading function sums the dipole over a per-pixel cut (or every sample in
 * exact mode: render/include/fv_sss_gather.glsl). Planned only when a drawn material is translucent, a light exists
 * and sss.enabled; otherwise nothing is created. Its own images (maps, RGBA32F x 3 and a depth image) leave the
 * render pass in SHADER_READ_ONLY_OPTIMAL; the node and header buffers are made visible to compute and fragment
 * reads at the end of record. Knobs: fv_quality.sss. */
#ifndef FV_SSS_H
#define FV_SSS_H

#include "fv_pass.h"

/** The pass's entry in the renderer's table. */
extern const fv_pass fv_sss_pass;

#endif
