/* @brief Distortion pass interface shared by C and GLSL: bindings, workgroup size and the push constants (the lens
 * of fv_lens.h and each eye's frustum tangents, so the pass samples exactly the frustum that was rendered). */
#ifndef FV_DISTORT_INTERFACE_H
#define FV_DISTORT_INTERFACE_H

#define FV_DISTORT_BINDING_SOURCE 0 /* sampler2DArray: the undistorted eye images (sRGB format: filtered in linear) */
#define FV_DISTORT_BINDING_OUTPUT 1 /* image2DArray rgba8: the display image (sRGB-encoded values) */

#define FV_DISTORT_GROUP_X 8
#define FV_DISTORT_GROUP_Y 8

#if defined(GL_core_profile) || defined(VULKAN) || defined(GL_SPIRV)
#define FV_DISTORT_UINT uint
#define FV_DISTORT_VEC4 vec4
#else
#include <stdint.h>
#define FV_DISTORT_UINT uint32_t
#define FV_DISTORT_VEC4 struct { float x, y, z, w; }
#endif

/* 112 bytes (the guaranteed push-constant range is 128). */
struct fv_distort_push {
    FV_DISTORT_VEC4 centre_m;    /* xy: left eye's lens centre, zw: right eye's (metres in its viewport, y down) */
    FV_DISTORT_VEC4 k;           /* d(r) = k.x + k.y r + k.z r^2 + k.w r^3 */
    FV_DISTORT_VEC4 aberration;  /* xyz: per-channel scale; w: visible radius (0 = the whole viewport) */
    FV_DISTORT_VEC4 geometry;    /* x, y: viewport metres; z: warp radius metres; w: tangent per metre */
    FV_DISTORT_VEC4 frustum[2];  /* per eye: tan left, right, up, down of the rendered frustum */
    FV_DISTORT_UINT width, height; /* per eye, px */
    FV_DISTORT_UINT pad0, pad1;
};

#endif
