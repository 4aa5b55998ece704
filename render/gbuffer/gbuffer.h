/* @brief The stereo G-buffer pass: both eyes drawn once with multiview (view mask 0b11) into 2-layer array images:
 * depth (D32), octahedral normal (RG16_SNORM, else RG32F), albedo (RGBA8 sRGB), material id + 1 (R16UI) and motion
 * vectors (RG16F, current uv - previous uv). Owns the scene's GPU copy: one device-local vertex and index buffer for
 * every mesh, the material buffer, and the base colour textures. One owner thread. */
#ifndef FV_GBUFFER_H
#define FV_GBUFFER_H

#include "fv_gpu.h"
#include "fv_scene.h"
#include "fv_vk.h"

#define FV_GBUFFER_MAX_SLOTS 8

typedef struct fv_gbuffer_desc {
    uint32_t width, height;    /* per eye, px */
    uint32_t frames_in_flight; /* 1..FV_GBUFFER_MAX_SLOTS */
    bool multiview;            /* true: both eyes in one multiview pass; false: one render pass per eye (a
                                * workaround for drivers whose multiview is broken, see fv_vk_multiview_trusted) */
} fv_gbuffer_desc;

/** A mesh inside the shared vertex/index buffers. */
typedef struct fv_gbuffer_mesh {
    uint32_t first_index, index_count;
    int32_t vertex_offset;
} fv_gbuffer_mesh;

/** One draw: draw_index selects the fv_gpu_draw record in the frame's draw buffer. */
typedef struct fv_gbuffer_draw {
    uint32_t mesh;
    int32_t texture; /* -1: none (white) */
} fv_gbuffer_draw;

typedef struct fv_gbuffer {
    fv_vk *vk;
    uint32_t width, height, slots;
    fv_vk_image depth, normal, albedo, material, motion;
    bool multiview;
    VkRenderPass render_pass;
    VkFramebuffer framebuffer;          /* multiview: all layers */
    VkFramebuffer eye_framebuffer[2];   /* per-eye passes: one layer each */
    VkImageView eye_views[2][5];        /* per-eye passes: single-layer views of the 5 images */
    VkDescriptorSetLayout frame_layout, texture_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    VkSampler texture_sampler;
    VkDescriptorPool frame_pool;
    VkDescriptorSet frame_sets[FV_GBUFFER_MAX_SLOTS];
    /* scene */
    fv_vk_buffer vertices, indices, materials;
    uint32_t material_count;
    fv_gbuffer_mesh *meshes;
    uint32_t mesh_count;
    fv_vk_image white;
    fv_vk_image *textures;
    uint32_t texture_count;
    VkDescriptorPool texture_pool;
    VkDescriptorSet *texture_sets; /* texture_count + 1: the last is the white texture */
} fv_gbuffer;

/** Images, render pass, pipeline and layouts. gb is zeroed first; fv_gbuffer_fini is safe after a failure. */
FV_MUST_CHECK fv_result fv_gbuffer_init(fv_gbuffer *gb, fv_vk *vk, const fv_gbuffer_desc *desc);
/** Free everything (the GPU must be idle). Safe twice. */
void fv_gbuffer_fini(fv_gbuffer *gb);
/** Upload every mesh, material and texture of a scene (replacing the previous one). The GPU must be idle. */
FV_MUST_CHECK fv_result fv_gbuffer_load_scene(fv_gbuffer *gb, const fv_scene *scene);
/** Point the slot's set at the frame block and draw records (the GPU must not be using that slot). */
void fv_gbuffer_bind_frame(fv_gbuffer *gb, uint32_t slot, VkBuffer buffer, VkDeviceSize frame_offset,
                           VkDeviceSize draws_offset, VkDeviceSize draws_range);

typedef struct fv_gbuffer_inputs {
    uint32_t slot;                /* frame in flight whose set to use */
    const fv_gbuffer_draw *draws; /* draw i uses fv_gpu_draw record i */
    uint32_t draw_count;
} fv_gbuffer_inputs;

/** Record the pass. Layouts: every image UNDEFINED on entry (it is cleared; the render pass waits for earlier
 *  compute reads); on exit colour images are SHADER_READ_ONLY_OPTIMAL and depth DEPTH_STENCIL_READ_ONLY_OPTIMAL,
 *  visible to compute and fragment shader reads. */
void fv_gbuffer_record(fv_gbuffer *gb, VkCommandBuffer cmd, const fv_gbuffer_inputs *in);

/** Layout of each image after the pass. */
#define FV_GBUFFER_COLOR_LAYOUT VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL
#define FV_GBUFFER_DEPTH_LAYOUT VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL

#endif
