/* @brief G-buffer pass interface shared by C and GLSL: bindings, attachment locations, vertex layout. */
#ifndef FV_GBUFFER_INTERFACE_H
#define FV_GBUFFER_INTERFACE_H

/* set 0: per frame in flight */
#define FV_GBUFFER_BINDING_FRAME 0 /* uniform fv_gpu_frame */
#define FV_GBUFFER_BINDING_DRAWS 1 /* storage fv_gpu_draw[] */
#define FV_GBUFFER_BINDING_MATERIALS 2 /* storage fv_gpu_material[] (static, uploaded with the scene) */
/* set 1: per texture (the base colour texture of the draw's material, or a 1x1 white one) */
#define FV_GBUFFER_BINDING_BASE_COLOR 0

/* colour attachment locations */
#define FV_GBUFFER_OUT_NORMAL 0   /* octahedral world normal, facing the eye */
#define FV_GBUFFER_OUT_ALBEDO 1   /* linear albedo (stored sRGB-encoded by the format) */
#define FV_GBUFFER_OUT_MATERIAL 2 /* material index + 1; 0 = nothing drawn */
#define FV_GBUFFER_OUT_MOTION 3   /* current uv - previous uv (uv in [0,1], y down) */

/* vertex attributes (one interleaved stream: position, normal, texcoord) */
#define FV_GBUFFER_ATTR_POSITION 0
#define FV_GBUFFER_ATTR_NORMAL 1
#define FV_GBUFFER_ATTR_TEXCOORD 2

#endif
