/* @brief The light quad-tree's pure parts (no Vulkan), shared by the GI pass, the CPU reference and the tests: each
 * light's RSM view, the tree's levels, the bottom-up build and the cut on the CPU (the oracle of gi_build.comp), and
 * a cluster's irradiance in double (the formula of fv_gi_gather.glsl). Thread-safe, no allocation. */
#ifndef FV_GI_MATH_H
#define FV_GI_MATH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fovea/fv_frame_input.h"
#include "fv_gi_interface.glsl"

/** One light's RSM view: world -> the RSM's clip space (Vulkan), and the RSM shaders' parameters (see
 *  fv_gi_rsm_push in gi_interface.h: x tan of the half angle or half extent, y N, z scene size; origin of depth).
 *  Spot: perspective from the light over its outer cone (+2%, at most 80 degrees half-angle), far plane at the far
 *  side of the scene's bounding sphere. Directional: orthographic over the bounding sphere. Finite for any input. */
typedef struct fv_gi_view {
    fv_mat4 view_proj;
    float params[4];
    float origin[4];
} fv_gi_view;
void fv_gi_light_view(const fv_gpu_light *light, uint32_t kind, uint32_t n, fv_vec3 bounds_min, fv_vec3 bounds_max,
                      fv_gi_view *out);

/** floor(log2(v)), 0 for v <= 1. */
uint32_t fv_gi_log2(uint32_t v);
/** Nodes of one light's tree of side n (all levels). */
uint32_t fv_gi_nodes_for(uint32_t n);
/** First node of level k (n >> k nodes per side). */
uint32_t fv_gi_level_offset(uint32_t n, uint32_t k);
/** The start and limit levels for the knobs (start >= limit; level k has n >> k nodes per side). */
void fv_gi_tree_levels(uint32_t n, const fv_quality_gi *q, uint32_t *out_start, uint32_t *out_limit);

/** Build levels 1.. of one tree whose level 0 (n x n leaves) is filled, exactly as gi_build.comp's REDUCE stage;
 *  plain: the means weigh every child with geometry alike (gi.average=plain) instead of by incident power. */
void fv_gi_build_cpu(fv_gi_node *tree, uint32_t n, float depth_threshold, float normal_threshold, bool plain);
/** The cut of one tree between start and limit (as gi_build.comp's flags, same order); returns its size and writes
 *  at most cap node indices (relative to the tree). */
uint32_t fv_gi_cut_cpu(const fv_gi_node *tree, uint32_t n, uint32_t start, uint32_t limit, uint32_t *out, uint32_t cap);

/** The walk records' order (see fv_gi_cluster): the pre-order position within its light's tree of the node of level
 *  k at (x, y) (level k has n >> k nodes per side), and back from a position to the node's index in the tree
 *  (fv_gi_level_offset(n, k) + y * (n >> k) + x; n if pos is outside the tree). Subtree size of a level-k node:
 *  fv_gi_subtree(k) = (4^(k+1) - 1) / 3. */
uint32_t fv_gi_subtree(uint32_t k);
uint32_t fv_gi_walk_pos(uint32_t n, uint32_t k, uint32_t x, uint32_t y);
uint32_t fv_gi_walk_node(uint32_t n, uint32_t pos);
/** The walk record of node `node` of a tree (gi_build.comp's WALK stage). */
fv_gi_cluster fv_gi_walk_record(const fv_gi_node *tree, uint32_t n, uint32_t node);

/** The irradiance (W/m^2 per channel) at x with unit normal nrm from one cluster, in double:
 *  Phi max(0, n_c.v/d) max(0, -n.v/d) / (pi (d^2 + r^2)), v = x - x_c. 0 at d = 0 and for zero flux. */
void fv_gi_cluster_irradiance(const fv_gi_node *c, const double x[3], const double nrm[3], double out[3]);

#endif
