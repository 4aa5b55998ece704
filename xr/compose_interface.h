/* @brief The compose pass of fovea's OpenXR compositor, shared by C and GLSL: bindings, workgroup size, the layer
 * block (std140). Each layer maps a display pixel's view ray (tangent coordinates of the display eye) through a 3x3
 * homography onto its source image's [0,1]^2 (projection layers: rotation re-projection into the layer view's
 * frustum; quad layers: the ray's hit on the quad's plane), then blends in layer order. Through the lens (the
 * specialisation FV_XR_COMPOSE_SPEC_LENS): the display pixel is a point of the HMD's panel and each colour channel's
 * ray is the one the lens shows there (the block's lens, fv_lens.h), so the pass writes the pre-distorted display
 * image itself and each layer is sampled once per channel (no composed image in between). */
#ifndef FV_XR_COMPOSE_INTERFACE_H
#define FV_XR_COMPOSE_INTERFACE_H

#define FV_XR_COMPOSE_GROUP 8
#define FV_XR_COMPOSE_MAX_SOURCES 16 /* sampled images per frame: distinct swapchains (a stereo projection uses 1 or 2);
                                      * 16: Vulkan's minimum maxPerStageDescriptorSamplers */
#define FV_XR_COMPOSE_MAX_LAYERS 32  /* layers per eye: maxLayerCount (16), each with a quad-views inset */
#define FV_XR_COMPOSE_BINDING_SOURCES 0
#define FV_XR_COMPOSE_BINDING_DISPLAY 1
#define FV_XR_COMPOSE_BINDING_LAYERS 2
#define FV_XR_COMPOSE_SPEC_NSRC 0    /* specialisation constants: the eye's source count (through the lens: its
                                      * layer count, source i being layer i's image) */
#define FV_XR_COMPOSE_SPEC_LENS 1    /* 1: through the lens, 0: the composed display image */
#define FV_XR_COMPOSE_LENS_MAX_LAYERS 2 /* through the lens when no eye has more layers: each layer costs 3 samples
                                         * per pixel there (one per channel), against 1 and the lens pass's 3 (and
                                         * its copy) for the whole frame composed first: even at 2 full-view layers,
                                         * ahead for the usual projection layer and a quad (the CTS's frames) */

#define FV_XR_LAYER_ALPHA 1u         /* XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT */
#define FV_XR_LAYER_UNPREMULTIPLIED 2u /* XR_COMPOSITION_LAYER_UNPREMULTIPLIED_ALPHA_BIT */
#define FV_XR_LAYER_INSET 4u         /* a quad-views inset (XR_VARJO_quad_views): its weight falls smoothly to 0 over
                                      * the band at its edge (h[0].w, h[1].w: the band in u and v, xr_quad.c) */

#ifdef __cplusplus
#error C only
#endif
#ifdef GL_core_profile
#define FV_XR_STRUCT(name) struct name
#define FV_XR_VEC4 vec4
#define FV_XR_UVEC4 uvec4
#else
#include <stdint.h>
typedef struct fv_xr_vec4 { float x, y, z, w; } fv_xr_vec4;
typedef struct fv_xr_uvec4 { uint32_t x, y, z, w; } fv_xr_uvec4;
#define FV_XR_STRUCT(name) typedef struct name name; struct name
#define FV_XR_VEC4 fv_xr_vec4
#define FV_XR_UVEC4 fv_xr_uvec4
#endif

FV_XR_STRUCT(fv_xr_compose_layer) {
    FV_XR_VEC4 h[3];     /* rows of the homography: (u w, v w, w) = h * (tan_x, tan_y, 1) (xyz; w: see INSET) */
    FV_XR_VEC4 uv_rect;  /* source image rect in normalised coordinates: offset.xy, scale.zw */
    FV_XR_UVEC4 info;    /* x: source index (binding array element), y: array layer, z: FV_XR_LAYER_* flags */
};

FV_XR_STRUCT(fv_xr_compose_block) {
    FV_XR_UVEC4 counts;  /* x, y: layers of eye 0 / eye 1; z, w: display width, height per eye (px) */
    FV_XR_VEC4 tan[2];   /* per eye: tangents of the display's left (negative), right, up, down (negative) edges */
    /* the HMD's lens (fv_lens.h; read through the lens only): */
    FV_XR_VEC4 lens_centre;     /* xy: left eye's lens centre, zw: right eye's (metres in its viewport, y down) */
    FV_XR_VEC4 lens_k;          /* d(r) = k.x + k.y r + k.z r^2 + k.w r^3 */
    FV_XR_VEC4 lens_aberration; /* xyz: per-channel scale; w: visible radius (0 = the whole viewport) */
    FV_XR_VEC4 lens_geometry;   /* x, y: viewport metres; z: warp radius metres; w: tangent per metre */
    fv_xr_compose_layer layer[2 * FV_XR_COMPOSE_MAX_LAYERS]; /* eye e, layer i at e * MAX_LAYERS + i */
};

#ifndef GL_core_profile
_Static_assert(sizeof(fv_xr_compose_layer) == 80, "std140 layer");
_Static_assert(sizeof(fv_xr_compose_block) == 112 + 2 * FV_XR_COMPOSE_MAX_LAYERS * 80, "std140 block");
#endif
#endif
