/* @brief The stereo G-buffer pass: the scene (fv_scene_gpu) drawn for both eyes, in one multiview pass (view mask
 * 0b11) or one render pass per eye where multiview is not trusted, into the image table's 2-layer G-buffer images:
 * depth (D32), octahedral normal, albedo (sRGB), material id + 1 (R16UI), motion vectors (RG16F, current uv -
 * previous uv) and, while foveation runs, the surface target foveation reads in one fetch (RGBA32F: motion, distance,
 * normal bits; gbuffer_interface.h). Layouts on exit: colour images SHADER_READ_ONLY_OPTIMAL, depth
 * DEPTH_STENCIL_READ_ONLY_OPTIMAL,
 * visible to compute, fragment and transfer reads (tracked in the image table). */
#ifndef FV_GBUFFER_H
#define FV_GBUFFER_H

#include "fv_pass.h"

/** The pass's entry in the renderer's table. */
extern const fv_pass fv_gbuffer_pass;

#endif
