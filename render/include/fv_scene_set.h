/* @brief The scene's shared descriptor set (set 0 of every pass's pipelines), shared by C and GLSL: its bindings,
 * and the declarations a shader includes to use them. Owned by render/scene_gpu; filled once per frame in flight. */
#ifndef FV_SCENE_SET_H
#define FV_SCENE_SET_H

#define FV_SCENE_SET 0                /* set number in every pass's pipeline layout */
#define FV_SCENE_BINDING_FRAME 0      /* uniform fv_gpu_frame (per frame in flight) */
#define FV_SCENE_BINDING_LIGHTS 1     /* storage fv_gpu_light[] (per frame in flight) */
#define FV_SCENE_BINDING_MATERIALS 2  /* storage fv_gpu_material[] (uploaded with the scene) */
#define FV_SCENE_BINDING_DRAWS 3      /* storage fv_gpu_draw[] (per frame in flight) */
#define FV_SCENE_BINDING_COUNT 4

/* Drawing the scene (fv_scene_gpu_record_draws): set 1 is the draw's base colour texture, and the push constants start with
 * { uint draw_index; uint view; } (view: the eye for eye views, a pass-defined index for other views). */
#define FV_SCENE_TEXTURE_SET 1
#define FV_SCENE_BINDING_BASE_COLOR 0
#define FV_SCENE_DRAW_PUSH_BYTES 8

/* Vertex attributes of the scene's one interleaved vertex stream (position, normal, texcoord; 32 bytes). */
#define FV_SCENE_ATTR_POSITION 0
#define FV_SCENE_ATTR_NORMAL 1
#define FV_SCENE_ATTR_TEXCOORD 2

#if defined(GL_core_profile) || defined(VULKAN) || defined(GL_SPIRV)
/* GLSL: declare the shared set. Requires fv_gpu.h. */
#define FV_SCENE_SET_DECLARE                                                                                           \
    layout(std140, set = FV_SCENE_SET, binding = FV_SCENE_BINDING_FRAME) uniform FvFrame { fv_gpu_frame frame; };      \
    layout(std430, set = FV_SCENE_SET, binding = FV_SCENE_BINDING_LIGHTS) readonly buffer FvLights {                 \
        fv_gpu_light lights[];                                                                                         \
    };                                                                                                                 \
    layout(std430, set = FV_SCENE_SET, binding = FV_SCENE_BINDING_MATERIALS) readonly buffer FvMaterials {           \
        fv_gpu_material materials[];                                                                                   \
    };                                                                                                                 \
    layout(std430, set = FV_SCENE_SET, binding = FV_SCENE_BINDING_DRAWS) readonly buffer FvDraws {                   \
        fv_gpu_draw draws[];                                                                                           \
    };
#endif

#endif
