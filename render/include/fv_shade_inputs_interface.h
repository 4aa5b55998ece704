/* @brief What shading passes read besides the scene and the G-buffer: set 1 of their pipelines, filled by the
 * passes that produce it (shadows now; indirect light and subsurface light later), owned by the renderer
 * (render/pass/fv_shade_inputs.h). Shared by C and GLSL. */
#ifndef FV_SHADE_INPUTS_INTERFACE_H
#define FV_SHADE_INPUTS_INTERFACE_H

#define FV_SHADE_INPUTS_SET 1 /* after the scene set; a shading pass's own set comes after it */
#define FV_SHADE_INPUTS_BINDING_SHADOW 0     /* storage fv_gpu_shadow (per frame in flight) */
#define FV_SHADE_INPUTS_BINDING_SHADOW_MAP 1 /* sampler2DArray: the shadow maps' depth (a 1x1 dummy when none) */
/* Slots for the passes that add to the shading function (fv_shade_inputs_bind_buffer / _bind_image): each gets
 * three storage buffers and three sampler2DArray images, a small dummy bound until it binds its own. Buffers 0 and 1
 * are read-only, the same in every frame in flight; buffer 2 (FV_SHADE_INPUTS_SLOT_STATS) is the technique's stats,
 * one per frame in flight (fv_shade_inputs_bind_stats), which shading passes that count the technique's work write
 * with atomics (a per-slot dummy, never written: the technique's code writes only while its header says it is on).
 * Light quad-tree GI (render/gi): buffers 2..4, images 5..7. Subsurface scattering (render/sss): buffers 8..10,
 * images 11..13. A technique names its bindings FV_SHADE_INPUTS_BINDING_GI_* / _SSS_* in its own header. */
#define FV_SHADE_INPUTS_BINDING_GI_BUFFER0 2
#define FV_SHADE_INPUTS_BINDING_GI_IMAGE0 5
#define FV_SHADE_INPUTS_BINDING_SSS_BUFFER0 8
#define FV_SHADE_INPUTS_BINDING_SSS_IMAGE0 11
#define FV_SHADE_INPUTS_SLOT_BUFFERS 3 /* storage buffers per technique */
#define FV_SHADE_INPUTS_SLOT_STATS 2   /* the technique's buffer that holds its per-frame stats (writable) */
#define FV_SHADE_INPUTS_SLOT_IMAGES 3  /* sampler2DArray images per technique */
#define FV_SHADE_INPUTS_BINDING_COUNT 14

#if defined(GL_core_profile) || defined(VULKAN) || defined(GL_SPIRV)
/* GLSL: declare set 2. Requires fv_gpu.h. */
#define FV_SHADE_INPUTS_DECLARE                                                                                        \
    layout(std430, set = FV_SHADE_INPUTS_SET, binding = FV_SHADE_INPUTS_BINDING_SHADOW) readonly buffer FvShadow {   \
        fv_gpu_shadow shadow;                                                                                          \
    };                                                                                                                 \
    layout(set = FV_SHADE_INPUTS_SET, binding = FV_SHADE_INPUTS_BINDING_SHADOW_MAP) uniform sampler2DArray shadow_map;
#endif

#endif
