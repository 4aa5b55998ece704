/* @brief The shading pass: a compute shader reading the G-buffer, direct lighting (Lambert; point/spot/directional;
 * emissive; ambient) into linear RGBA32F per eye layer, for every pixel or for a list of packed pixels. The light
 * and BRDF code lives in render/include/fv_shade_common.glsl so later passes reuse the same shading function.
 * One owner thread. */
#ifndef FV_SHADE_H
#define FV_SHADE_H

#include "fv_gpu.h"
#include "fv_vk.h"
#include "gbuffer.h"
#include "shade_interface.h"

#define FV_SHADE_MAX_SLOTS 8

typedef struct fv_shade_push fv_shade_push;

typedef struct fv_shade {
    fv_vk *vk;
    uint32_t width, height, slots;
    fv_vk_image color; /* linear RGBA32F, 2 layers, always in VK_IMAGE_LAYOUT_GENERAL */
    VkSampler nearest;
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline_all, pipeline_list;
    VkDescriptorPool pool;
    VkDescriptorSet sets[FV_SHADE_MAX_SLOTS];
    fv_vk_buffer empty_list; /* a list with count 0, bound until a caller binds its own */
} fv_shade;

/** Pipelines, the colour image (left in GENERAL) and one set per frame in flight pointing at gb's images. */
FV_MUST_CHECK fv_result fv_shade_init(fv_shade *sh, fv_vk *vk, const fv_gbuffer *gb, uint32_t frames_in_flight);
void fv_shade_fini(fv_shade *sh);
/** Point the slot's set at the frame block, the lights and the materials (the GPU must not be using the slot). */
void fv_shade_bind_frame(fv_shade *sh, uint32_t slot, VkBuffer frame_buffer, VkDeviceSize frame_offset,
                         VkDeviceSize lights_offset, VkDeviceSize lights_range, VkBuffer materials);
/** Point the slot's set at a pixel list (header + packed pixels, see shade_interface.h); VK_NULL_HANDLE = empty. */
void fv_shade_bind_list(fv_shade *sh, uint32_t slot, VkBuffer list, VkDeviceSize offset, VkDeviceSize range);

typedef struct fv_shade_inputs {
    uint32_t slot;
    uint32_t mode;             /* FV_SHADE_MODE_ALL or FV_SHADE_MODE_LIST */
    VkBuffer indirect;         /* list mode: VkDispatchIndirectCommand (see FV_SHADE_LIST_GROUPS_X) */
    VkDeviceSize indirect_offset;
} fv_shade_inputs;

/** Record the pass. Entry: the G-buffer as fv_gbuffer_record leaves it; the colour image in GENERAL (earlier
 *  reads and writes of it by compute or transfer are waited for here). A host- or GPU-written list/indirect buffer
 *  must already be visible to compute reads/indirect commands. Exit: colour in GENERAL, its writes visible to
 *  compute reads and transfers. Pixels not shaded keep their values. */
void fv_shade_record(fv_shade *sh, VkCommandBuffer cmd, const fv_shade_inputs *in);
/** Pixels a full-image record shades (both eyes). */
uint64_t fv_shade_pixels_all(const fv_shade *sh);
/** Indirect dispatch arguments for a list of `count` pixels. */
VkDispatchIndirectCommand fv_shade_list_dispatch(uint32_t count);

#endif
