/* @brief The GI pass: one-bounce diffuse indirect light from a light quad-tree (Ki & Oh 2007). Per spot or
 * directional light (the first FV_GI_MAX_LIGHTS of them) a reflective shadow map is drawn from the light with the
 * scene's draws (fv_scene_gpu_record_draws with the pass's own RSM shaders: the shadow pass's maps hold depth only,
 * and its cascades are fitted to the eyes, not to everything the light sees); its texels (VPLs) become the leaves
 * of a quad-tree pyramid built bottom-up in compute (gi_build.comp), with the paper's validity test per node, and
 * the cut at the limit level is extracted as a flat list by a prefix sum. Shading gathers from it in the shared
 * shading function (render/include/fv_gi_gather.glsl via fv_hook_indirect_irradiance), reading the GI technique
 * slots of the shading inputs (header + cut, nodes). The RSM, the tree and the cut are rebuilt only when a light,
 * what it sees or a gi.* knob changes. Point lights cast no indirect light (no cube RSM; the plan says so).
 * Knobs: fv_quality.gi. The tree's buffers are written on the GPU and made visible to compute and fragment reads
 * at the end of a rebuild; the RSM images are the pass's own (colour: SHADER_READ_ONLY_OPTIMAL between builds).
 * Every frame the pass clears the slot's stats (fv_gi_stats, the third GI slot of the shading inputs) before shading,
 * the shading pass counts into them what each pixel's gather summed (clusters, tree nodes or samples), and
 * record_end copies them back: details() reports the newest frame's clusters per pixel (mean, max, pixels). */
#ifndef FV_GI_H
#define FV_GI_H

#include "fv_gi_interface.glsl"
#include "fv_pass.h"

/** The pass's entry in the renderer's table. */
extern const fv_pass fv_gi_pass;

/** For tests: copy the tree back (the GPU must be idle; `state` from fv_renderer_pass_state(r, "gi")): the header,
 *  up to node_cap nodes (every light's tree, light after light) and up to cut_cap cut entries. Any output may be
 *  NULL. out_nodes_per_light gets the size of one light's tree. */
FV_MUST_CHECK fv_result fv_gi_read_tree(void *state, fv_gi_header *out_header, fv_gi_node *out_nodes, size_t node_cap,
                                        uint32_t *out_cut, size_t cut_cap, uint32_t *out_nodes_per_light);

/** For tests: copy back up to cap walk records (fv_gi_cluster: every light's tree in pre-order, light after light). */
FV_MUST_CHECK fv_result fv_gi_read_walk(void *state, fv_gi_cluster *out, size_t cap);

#endif
