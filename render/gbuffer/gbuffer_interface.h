/* @brief G-buffer pass interface shared by C and GLSL: colour attachment locations. The shaders use the scene's
 * shared set (fv_scene_set.h: set 0, and set 1 = the draw's texture) and its vertex layout. */
#ifndef FV_GBUFFER_INTERFACE_H
#define FV_GBUFFER_INTERFACE_H

/* colour attachment locations */
#define FV_GBUFFER_OUT_NORMAL 0   /* octahedral world normal, facing the eye */
#define FV_GBUFFER_OUT_ALBEDO 1   /* linear albedo (stored sRGB-encoded by the format) */
#define FV_GBUFFER_OUT_MATERIAL 2 /* material index + 1; 0 = nothing drawn */
#define FV_GBUFFER_OUT_MOTION 3   /* current uv - previous uv (uv in [0,1], y down): only with FV_GBUFFER_VARIANT_MOTION */
#define FV_GBUFFER_OUT_SURFACE 4  /* only while foveation runs (the pass's variant FV_GBUFFER_VARIANT_SURFACE): rg the
                                   * motion, b the distance from the eye to the surface (m; 0 = nothing drawn), a the
                                   * octahedral normal as packSnorm2x16 bits (the normal target's value): what
                                   * foveation's per-pixel passes read of a pixel in one fetch
                                   * (render/include/fv_gbuffer_decode.glsl fv_gbuffer_fovea) */
/* The pass's plan variant: bits */
#define FV_GBUFFER_VARIANT_MASK 1u    /* the hidden-area mask is drawn */
#define FV_GBUFFER_VARIANT_SURFACE 2u /* the foveation surface target is drawn */
#define FV_GBUFFER_VARIANT_MOTION 4u  /* the motion target is drawn (no pass reads it: the surface target holds the
                                       * motion foveation needs; fv_renderer_desc.motion_target keeps it for
                                       * fv_renderer_read_motion); without, its location is an unused attachment */

#endif
