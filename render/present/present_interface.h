/* @brief Present pass interface shared by C and GLSL: bindings, workgroup size, push constants, tonemap operators. */
#ifndef FV_PRESENT_INTERFACE_H
#define FV_PRESENT_INTERFACE_H

#define FV_PRESENT_BINDING_LINEAR 0 /* image2DArray rgba32f (read) */
#define FV_PRESENT_BINDING_OUTPUT 1 /* image2DArray rgba8 (written, sRGB-encoded values) */

#define FV_PRESENT_GROUP_X 8
#define FV_PRESENT_GROUP_Y 8

/* Specialization constant 0: tonemap operator. */
#define FV_TONEMAP_CLAMP 0    /* exposure, clamp to [0,1] */
#define FV_TONEMAP_REINHARD 1 /* exposure, c / (1 + c) */
#define FV_TONEMAP_REINHARD_EXT 2 /* exposure, Reinhard extended with white point FV_TONE_WHITE (fv_tone_curve.h):
                                   * the default */

#if defined(GL_core_profile) || defined(VULKAN) || defined(GL_SPIRV)
#define FV_PRESENT_UINT uint
#else
#include <stdint.h>
#define FV_PRESENT_UINT uint32_t
#endif

struct fv_present_push {
    float exposure;
    FV_PRESENT_UINT width, height;
    FV_PRESENT_UINT tone; /* 1: the tone curve (radiance: colour, direct, gi, sss views); 0: clamp (data views) */
};

#endif
