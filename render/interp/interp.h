/* @brief Hierarchical screen-space interpolation (Ki & Oh, papers/README.md section 4): the "interp" pass, before
 * shading, builds a pyramid of the G-buffer's position, normal and albedo whose nodes know whether their members
 * agree (interp.threshold), and from interp.start_level down to the pixels decides for every pixel whether it is
 * shaded (a corner of a coherent node, or a pixel no coherent node holds) or filled by interpolation; the shaded
 * pixels become the renderer's frame sample list (a prefix sum over the tiles in an interleaved order), which the
 * shade pass shades by an indirect dispatch with the same shading function. "interp_fill", after shading, fills the
 * other pixels bilinearly from their node's four shaded corners (and draws `--view interp`).
 * Composition: when an earlier pass already made the frame's sample list (foveation), the pixels no coherent node
 * holds are shaded only when that list holds them and are left to the pass that made it (reconstruct, after
 * interp_fill) otherwise; corners are always shaded. Images: "interp level" (2-layer scratch, R32UI, GENERAL: each
 * pixel's code, interp_interface.h); the G-buffer is read as sampled images, FV_IMAGE_COLOR read and written by
 * interp_fill in GENERAL. */
#ifndef FV_INTERP_H
#define FV_INTERP_H

#include "fv_pass.h"

/** The entries of the renderer's table: "interp" before shading, "interp_fill" after it (before reconstruct). */
extern const fv_pass fv_interp_pass;
extern const fv_pass fv_interp_fill_pass;

/** Nodes per row of a level (1..FV_INTERP_MAX_LEVEL) for an image n px wide: max(1, ceil((n - 1) / 2^level)). */
uint32_t fv_interp_nodes_along(uint32_t n, uint32_t level);

#endif
