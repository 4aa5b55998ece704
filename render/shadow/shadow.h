/* @brief The shadow pass: a depth map per shadowed light, drawn from the light with the scene's draws
 * (fv_scene_gpu_record_draws) into one 2D-array depth image of the table, bound as the shading inputs' shadow maps.
 * Directional lights: parallel-split shadow maps (Zhang et al. 2006) — the visible depth range split by the
 * practical scheme, one cropped orthographic map per split, shared by both eyes (fitted to the union of the two
 * frusta) or one set per eye (`shadow.stereo_shared`). Spot lights: one perspective map. Point lights: a cube map
 * (six 90-degree perspective faces). Knobs: fv_quality.shadow. Layout of the map on exit: DEPTH_STENCIL_READ_ONLY_OPTIMAL, visible
 * to compute and fragment reads (tracked in the image table). */
#ifndef FV_SHADOW_H
#define FV_SHADOW_H

#include "fv_pass.h"

/** The pass's entry in the renderer's table. */
extern const fv_pass fv_shadow_pass;

#endif
