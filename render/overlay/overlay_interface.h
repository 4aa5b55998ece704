/* @brief Overlay pass interface shared by C and GLSL: bindings, workgroup size, push constants. */
#ifndef FV_OVERLAY_INTERFACE_H
#define FV_OVERLAY_INTERFACE_H

#define FV_OVERLAY_BINDING_DISPLAY 0 /* image2DArray rgba8: the display image (sRGB-encoded values), read and written */
#define FV_OVERLAY_BINDING_PROB 1    /* image2DArray r32f: foveation's sampling probability (a 1x1 dummy without it) */

#define FV_OVERLAY_GROUP_X 8
#define FV_OVERLAY_GROUP_Y 8

#define FV_OVERLAY_FLAG_FOVEA 1u /* draw the foveal boundary from the probability image */

#if defined(GL_core_profile) || defined(VULKAN) || defined(GL_SPIRV)
#define FV_OVERLAY_UINT uint
#define FV_OVERLAY_VEC4 vec4
#else
#include <stdint.h>
#define FV_OVERLAY_UINT uint32_t
typedef struct fv_overlay_vec4 {
    float x, y, z, w;
} fv_overlay_vec4;
#define FV_OVERLAY_VEC4 fv_overlay_vec4
#endif

/* Per eye: the predicted gaze (unit direction in eye space, w = 1 when valid), the frustum tangents (left, right,
 * up, down, signed) and x = the uncertainty radius in radians (0..pi). */
struct fv_overlay_push {
    FV_OVERLAY_VEC4 gaze[2];
    FV_OVERLAY_VEC4 tan[2];
    FV_OVERLAY_VEC4 info[2];
    FV_OVERLAY_UINT width, height, flags, pad;
};

#endif
