/* @brief Debug-view pass interface shared by C and GLSL: bindings of its own set (set 2, after the scene's and the
 * shading inputs), workgroup size. */
#ifndef FV_DEBUG_INTERFACE_H
#define FV_DEBUG_INTERFACE_H

#define FV_DEBUG_SET 2
#define FV_DEBUG_BINDING_DEPTH 0    /* sampler2DArray */
#define FV_DEBUG_BINDING_NORMAL 1   /* sampler2DArray (octahedral) */
#define FV_DEBUG_BINDING_ALBEDO 2   /* sampler2DArray */
#define FV_DEBUG_BINDING_MATERIAL 3 /* usampler2DArray */
#define FV_DEBUG_BINDING_COLOR 4    /* image2DArray rgba32f (written) */
#define FV_DEBUG_BINDING_COUNT 5

/* The foveation views (debug_fovea.comp): their own set after the scene's. */
#define FV_DEBUG_FOVEA_SET 1
#define FV_DEBUG_FOVEA_BINDING_PROB 0  /* image2DArray r32f "fovea prob" (read) */
#define FV_DEBUG_FOVEA_BINDING_MASK 1  /* uimage2DArray r32ui "fovea mask" (read) */
#define FV_DEBUG_FOVEA_BINDING_COLOR 2 /* image2DArray rgba32f (written) */
#define FV_DEBUG_FOVEA_BINDING_VORONOI 3 /* uimage2DArray r32ui "fovea voronoi": each pixel's nearest sample (read) */
#define FV_DEBUG_FOVEA_BINDING_COUNT 4
#define FV_DEBUG_GAZE_RING_PX 4.0      /* radius of the gaze ring of the samples view */

#define FV_DEBUG_GROUP_X 8
#define FV_DEBUG_GROUP_Y 8

/* The gaze view's spot: red = exp(-a^2 / (2 s^2)) for the angle a between a pixel's ray and the gaze ray, with
 * s = max(FV_DEBUG_GAZE_SIGMA_MIN_RAD, the gaze uncertainty). */
#define FV_DEBUG_GAZE_SIGMA_MIN_RAD 0.0174532925 /* 1 degree */

#endif
