/* @brief The scene on the GPU, in one place: one device-local vertex and index buffer for every mesh, the material
 * buffer (albedo, emission, translucency coefficients and eta), base colour textures, lights, the draw list with its
 * animation, and per frame in flight the frame constants, lights and draw records behind one shared descriptor set
 * (set 0 of every pass: fv_scene_set.h). Any pass can draw the scene from any view with fv_scene_gpu_record_draws.
 * One owner thread. */
#ifndef FV_SCENE_GPU_H
#define FV_SCENE_GPU_H

#include <stdbool.h>

#include "fv_gpu.h"
#include "fv_scene.h"
#include "fv_scene_set.h"
#include "fv_vk.h"

/** A mesh inside the shared vertex/index buffers. */
typedef struct fv_scene_gpu_mesh {
    uint32_t first_index, index_count;
    int32_t vertex_offset;
} fv_scene_gpu_mesh;

/** One drawn node: its mesh, material and texture; draw i uses fv_gpu_draw record i of the frame. */
typedef struct fv_scene_gpu_draw {
    uint32_t node, mesh, material;
    int32_t texture; /* -1: none (white) */
} fv_scene_gpu_draw;

typedef struct fv_scene_gpu {
    fv_vk *vk;
    uint32_t slots;
    VkDescriptorSetLayout set_layout;     /* set 0 (FV_SCENE_SET): frame, lights, materials, draws */
    VkDescriptorSetLayout texture_layout; /* set 1 when drawing (FV_SCENE_TEXTURE_SET): base colour */
    VkDescriptorPool pool;
    VkDescriptorSet sets[FV_MAX_FRAMES_IN_FLIGHT];
    VkSampler texture_sampler;
    fv_vk_image white;
    /* the loaded scene */
    bool loaded;
    fv_vk_buffer vertices, indices, materials;
    uint32_t material_count;
    fv_scene_gpu_mesh *meshes;
    uint32_t mesh_count;
    fv_vk_image *textures;
    uint32_t texture_count;
    VkDescriptorPool texture_pool;
    VkDescriptorSet *texture_sets; /* texture_count + 1: the last is the white texture */
    fv_scene anim;                 /* nodes and mesh headers (no data): fv_scene_node_world, world bounds */
    fv_scene_gpu_draw *draws;
    uint32_t draw_count;
    uint64_t triangle_count;       /* of the drawn meshes */
    fv_gpu_light *lights;
    uint32_t light_count;
    fv_vec3 ambient;
    /* per frame in flight: frame block | lights | draw records, at the device's offset alignment */
    fv_vk_buffer upload[FV_MAX_FRAMES_IN_FLIGHT];
    VkDeviceSize lights_offset, draws_offset, upload_size;
    uint64_t load_count; /* scenes loaded so far: a pass that keeps history across frames resets when it changes */
} fv_scene_gpu;

/** Layouts, sampler, white texture and the per-slot sets (bound to nothing until a scene is loaded). sg is zeroed
 *  first; fv_scene_gpu_fini is safe after a failure. */
FV_MUST_CHECK fv_result fv_scene_gpu_init(fv_scene_gpu *sg, fv_vk *vk, uint32_t frames_in_flight);
/** Free everything (the GPU must be idle). Safe twice. */
void fv_scene_gpu_fini(fv_scene_gpu *sg);
/** Upload a scene, replacing the previous one (the GPU must be idle; no pointer to `scene` is kept). On failure
 *  nothing stays loaded. */
FV_MUST_CHECK fv_result fv_scene_gpu_load(fv_scene_gpu *sg, const fv_scene *scene);
/** Drop the loaded scene (the GPU must be idle). */
void fv_scene_gpu_unload(fv_scene_gpu *sg);
/** Fill a slot's frame data (the GPU must be done with that slot): the frame constants as given, with the scene's
 *  ambient and light count set here; the lights; every draw's transform at t_s and at t_prev_s (for motion). */
FV_MUST_CHECK fv_result fv_scene_gpu_write_frame(fv_scene_gpu *sg, uint32_t slot, const fv_gpu_frame *frame,
                                                 double t_s, double t_prev_s);
/** World bounds of everything drawn at time t_s; false when nothing is drawn. */
bool fv_scene_gpu_world_bounds(const fv_scene_gpu *sg, double t_s, fv_vec3 *out_min, fv_vec3 *out_max);
/** The slot's shared set (set 0 of every pass). */
VkDescriptorSet fv_scene_gpu_set(const fv_scene_gpu *sg, uint32_t slot);

/** Vertex input of the scene's one interleaved stream, for graphics pipelines that draw it. */
void fv_scene_gpu_vertex_input(const VkVertexInputBindingDescription **out_binding,
                               const VkVertexInputAttributeDescription **out_attributes, uint32_t *out_attribute_count);

/** Record every draw of the scene inside a render pass, with `layout` (set 0 = fv_scene_gpu_set_layout, set 1 =
 *  texture_layout, push constants from offset 0 = { draw index, view }, for push_stages). view: the eye (0/1) for
 *  eye views, or a pass-defined index. Binds set 0, the vertex and index buffers, textures as they change. Returns
 *  the number of draws recorded. */
uint32_t fv_scene_gpu_record_draws(const fv_scene_gpu *sg, VkCommandBuffer cmd, VkPipelineLayout layout,
                           VkShaderStageFlags push_stages, uint32_t slot, uint32_t view);

#endif
