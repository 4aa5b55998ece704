/* @brief The reduced-rate GI gather's own interface, shared by gi_gather.c and gi_gather.comp: its set (set 2; set 0
 * is the scene's, set 1 the shading inputs, whose GI slots hold the tree it gathers from), workgroup size, push
 * constants. What it writes is read through the shading inputs (fv_gi_interface.glsl FV_GI_BINDING_LOW_*). */
#ifndef FV_GI_GATHER_INTERFACE_H
#define FV_GI_GATHER_INTERFACE_H

#include "fv_gpu.h"

#define FV_GI_GATHER_SET 2
#define FV_GI_GATHER_BINDING_DEPTH 0      /* sampler2DArray: the G-buffer (depth, normal, albedo, material) */
#define FV_GI_GATHER_BINDING_NORMAL 1
#define FV_GI_GATHER_BINDING_ALBEDO 2
#define FV_GI_GATHER_BINDING_MATERIAL 3
#define FV_GI_GATHER_BINDING_OUT_E 4      /* image2DArray rgba32f: irradiance, w 1 = a sample (written) */
#define FV_GI_GATHER_BINDING_COUNT 5

#define FV_GI_GATHER_GROUP_X 8
#define FV_GI_GATHER_GROUP_Y 8

struct fv_gi_gather_push {
    FV_UVEC4 dims; /* x the rate r, y, z the block grid's size per eye, w 0 */
};

#ifndef FV_GLSL
_Static_assert(sizeof(struct fv_gi_gather_push) == 16, "fv_gi_gather_push layout");
#endif

#endif
