/* @brief Foveated rendering (papers/README.md section 3): the "fovea" pass makes, from the predicted gaze of the
 * frame constants, a sampling probability per pixel (linear MAR) and a sample mask with at least one sample per
 * block; the "compact" pass turns the sampled pixels of both eyes into the renderer's frame sample list (with its
 * indirect dispatch), which the shade pass then shades instead of the whole frame; the "reconstruct" pass, after
 * shading, fills every unshaded pixel from the known ones: soft (per block up to 4 representatives, then per pixel
 * an edge-aware Gaussian of those of the blocks around, as wide as the local sample spacing), or nearest, Sibson or
 * idw over the samples' Voronoi diagram (1+JFA or the block search). Images (2-layer scratch, GENERAL): "fovea prob"
 * (R32F), "fovea mask" (R32UI), "fovea seeds a" / "fovea seeds b" (R32UI); FV_IMAGE_COLOR is read and written by
 * reconstruct in GENERAL. */
#ifndef FV_FOVEA_H
#define FV_FOVEA_H

#include "fv_pass.h"

/** The entries of the renderer's table: "fovea" (the sampling map) and "compact" (the list) before shading,
 *  "reconstruct" after it. */
extern const fv_pass fv_fovea_pass;
extern const fv_pass fv_compact_pass;
extern const fv_pass fv_reconstruct_pass;
/** "temporal", between shade and reconstruct (fovea.temporal > 0): the previous frame's known pixels reprojected
 *  through the motion vectors (the paper's depth test), blended into the shaded pixels and reused for unshaded
 *  ones, which reconstruction then takes as samples; the history is the renderer's (fv_images_history). */
extern const fv_pass fv_temporal_pass;

/** Append one named detail of up to three values when there is room; returns the new count. */
uint32_t fv_fovea_add_detail(fv_pass_detail *out, uint32_t n, uint32_t cap, const char *key, uint32_t count, double a,
                             double b, double c);

/** Whether the head jumped between two frames of one eye (view matrices and eye positions): moved more than
 *  FV_TEMPORAL_JUMP_M or turned more than FV_TEMPORAL_JUMP_DEG, or anything non-finite. The history resets. */
bool fv_fovea_head_jumped(const fv_mat4 *prev_view, const fv_vec3 *prev_eye, const fv_mat4 *view,
                          const fv_vec3 *eye);

/** The R2 value of pixel (x, y) of a block, as the GPU computes it (float). */
double fv_fovea_r2(uint32_t x, uint32_t y);
/** Each pixel's rank (0..B*B-1, row-major) in its block by R2 value, ties by index: the table the GPU reads. */
void fv_fovea_block_ranks(uint32_t block, uint32_t *out_ranks);

/** The JFA step sizes for a block side (1, then block, halving up to 1); returns how many (<= cap). */
uint32_t fv_fovea_jfa_steps(uint32_t block, uint32_t *out_steps, uint32_t cap);

#endif
