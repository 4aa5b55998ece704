/* @brief The GI pass's own interface, shared by gi.c and its shaders (gi_rsm.vert/.frag, gi_build.comp): push
 * constants, bindings of the build's set, workgroup sizes, build stages. What shading reads is in
 * render/include/fv_gi_interface.glsl. */
#ifndef FV_GI_PASS_INTERFACE_H
#define FV_GI_PASS_INTERFACE_H

#include "fv_gi_interface.glsl"

/* RSM colour attachments */
#define FV_GI_RSM_OUT_FLUX 0   /* rgb reflected flux (W), a incident power (W, luminance) */
#define FV_GI_RSM_OUT_POS 1    /* xyz world (m), w depth from the light / scene size */
#define FV_GI_RSM_OUT_NORMAL 2 /* xyz unit normal facing the light (0: nothing drawn), w the texel's disk radius (m) */

/* The build's own set (set 0 of gi_build.comp) */
#define FV_GI_BUILD_BINDING_FLUX 0
#define FV_GI_BUILD_BINDING_POS 1
#define FV_GI_BUILD_BINDING_NORMAL 2
#define FV_GI_BUILD_BINDING_NODES 3
#define FV_GI_BUILD_BINDING_HEADER 4
#define FV_GI_BUILD_BINDING_SCAN 5
#define FV_GI_BUILD_BINDING_COUNT 6

#define FV_GI_BUILD_GROUP 256 /* threads per group, also the scan's block */

/* Build stages (fv_gi_build_push.ids.x) */
#define FV_GI_STAGE_LEAF 0        /* RSM texels -> level 0 */
#define FV_GI_STAGE_REDUCE 1      /* level ids.y -> ids.y + 1: sums, weighted means, validity */
#define FV_GI_STAGE_SCAN_LOCAL 2  /* cut flags of the candidates, exclusive scan per block, block totals */
#define FV_GI_STAGE_SCAN_BLOCKS 3 /* one group: scan the block totals; cut counts into the header */
#define FV_GI_STAGE_SCATTER 4     /* write each cut node (and its walk record's index) at its prefix */
#define FV_GI_STAGE_WALK 5        /* every node's walk record, in pre-order after the cut's room (fv_gi_cluster) */

struct fv_gi_build_push {
    FV_UVEC4 ids;   /* x stage, y level, z RSM side N, w levels */
    FV_UVEC4 tree;  /* x start level, y limit level, z lights, w nodes per light */
    FV_UVEC4 scan;  /* x candidates per light, y all candidates, z blocks, w items (threads) of this dispatch */
    FV_VEC4 params; /* x depth threshold, y normal threshold, z 1 = plain means (gi.average), w 0 */
};

/* RSM draw push constants: { draw, view } of fv_scene_gpu_record_draws, then these. */
struct fv_gi_rsm_push {
    FV_UVEC4 ids;    /* x draw, y view (= light), z light index, w kind (FV_GI_KIND_*) */
    FV_MAT4 view_proj;
    FV_VEC4 params;  /* x tan of the half angle (spot) or half extent in m (directional), y N, z scene size (m) */
    FV_VEC4 origin;  /* directional: xyz a point on the plane of depth 0; w 0 */
};

#ifndef FV_GLSL
_Static_assert(sizeof(struct fv_gi_build_push) == 64, "fv_gi_build_push layout");
_Static_assert(sizeof(struct fv_gi_rsm_push) == 112, "fv_gi_rsm_push layout");
#endif

#endif
