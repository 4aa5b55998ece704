/* @brief Shading pass interface shared by C and GLSL: bindings of its own set (set 2; set 0 is the scene's, set 1
 * the shading inputs),
 * workgroup size, push constants, modes. */
#ifndef FV_SHADE_INTERFACE_H
#define FV_SHADE_INTERFACE_H

#define FV_SHADE_SET 2
#define FV_SHADE_BINDING_DEPTH 0    /* sampler2DArray (D32) */
#define FV_SHADE_BINDING_NORMAL 1   /* sampler2DArray (octahedral) */
#define FV_SHADE_BINDING_ALBEDO 2   /* sampler2DArray (sRGB -> linear on read) */
#define FV_SHADE_BINDING_MATERIAL 3 /* usampler2DArray (id + 1) */
#define FV_SHADE_BINDING_COLOR 4    /* image2DArray rgba32f, linear radiance (written) */
#define FV_SHADE_BINDING_PIXELS 5   /* storage pixel list (fv_gpu.h FV_GPU_LIST_*; list mode) */
#define FV_SHADE_BINDING_COUNT 6

#define FV_SHADE_GROUP_X 8
#define FV_SHADE_GROUP_Y 8
#define FV_SHADE_GROUP_SIZE (FV_SHADE_GROUP_X * FV_SHADE_GROUP_Y)

/* What to shade (push constant `mode`: one pipeline for both, as the shading function is most of its compile). */
#define FV_SHADE_MODE_ALL 0  /* every pixel of both eyes (tiles interleaved over the dispatch) */
#define FV_SHADE_MODE_LIST 1 /* only the packed pixels of the list buffer (FV_GPU_PIXEL_PACK) */

/* Full-image mode: tiles are visited in an interleaved order so that any contiguous range of workgroups (one CPU
 * thread's share on lavapipe, which splits a dispatch into contiguous parts) covers the whole image evenly:
 * workgroup g shades tile (g % stripes) * tiles_per_stripe + g / stripes. */
#define FV_SHADE_STRIPES 32u

#if defined(GL_core_profile) || defined(VULKAN) || defined(GL_SPIRV)
#define FV_SHADE_UINT uint
#else
#include <stdint.h>
#define FV_SHADE_UINT uint32_t
#endif

struct fv_shade_push {
    FV_SHADE_UINT tiles_x, tiles_y; /* per eye */
    FV_SHADE_UINT tile_count;       /* tiles_x * tiles_y * 2 */
    FV_SHADE_UINT tiles_per_stripe; /* ceil(tile_count / FV_SHADE_STRIPES) */
    FV_SHADE_UINT groups_x;         /* dispatch width (workgroups are linearised as x + y * groups_x) */
    FV_SHADE_UINT mode;             /* FV_SHADE_MODE_ALL or FV_SHADE_MODE_LIST */
    FV_SHADE_UINT pad[2];
};

#endif
