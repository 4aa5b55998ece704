/* @brief G-buffer pass interface shared by C and GLSL: colour attachment locations. The shaders use the scene's
 * shared set (fv_scene_set.h: set 0, and set 1 = the draw's texture) and its vertex layout. */
#ifndef FV_GBUFFER_INTERFACE_H
#define FV_GBUFFER_INTERFACE_H

/* colour attachment locations */
#define FV_GBUFFER_OUT_NORMAL 0   /* octahedral world normal, facing the eye */
#define FV_GBUFFER_OUT_ALBEDO 1   /* linear albedo (stored sRGB-encoded by the format) */
#define FV_GBUFFER_OUT_MATERIAL 2 /* material index + 1; 0 = nothing drawn */
#define FV_GBUFFER_OUT_MOTION 3   /* current uv - previous uv (uv in [0,1], y down) */

#endif
