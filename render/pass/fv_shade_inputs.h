/* @brief The shading inputs (set 1 of shading passes, render/include/fv_shade_inputs_interface.h): per frame in flight the
 * shadow block (fv_gpu_shadow) that the shadow pass fills before recording, and the shadow-map image (a 1x1 dummy
 * until a pass binds one); and the technique slots (GI, SSS): read-only storage buffers and sampled image arrays
 * that a producing pass binds once (a small dummy otherwise), and per slot a writable stats buffer that shading
 * counts the technique's work into (a per-slot dummy, never written, until the technique binds its own). Owned by
 * the renderer; producers fill it, consumers bind it. One owner thread. A producer that writes a bound buffer on the
 * GPU makes its writes visible to compute and fragment shader reads itself (a memory barrier at the end of its
 * record), and clears and reads back its stats buffer itself (before and after shading, with their barriers);
 * bound images get their barrier from fv_shade_inputs_use. */
#ifndef FV_SHADE_INPUTS_H
#define FV_SHADE_INPUTS_H

#include "fv_gpu.h"
#include "fv_images.h"
#include "fv_shade_inputs_interface.h"
#include "fv_vk.h"

typedef struct fv_shade_inputs {
    fv_vk *vk;
    uint32_t slots;
    VkDescriptorSetLayout layout;
    VkDescriptorPool pool;
    VkDescriptorSet sets[FV_MAX_FRAMES_IN_FLIGHT];
    fv_vk_buffer shadow[FV_MAX_FRAMES_IN_FLIGHT]; /* host-visible fv_gpu_shadow per slot */
    VkSampler nearest;
    fv_vk_image dummy;     /* 1x1, 1 layer, depth 1 (nothing occludes) */
    fv_image_id shadow_map; /* the image table's id of the bound shadow maps, or FV_IMAGE_MAX for the dummy */
    fv_vk_buffer dummy_buffer;  /* 256 zero bytes: an unbound technique buffer */
    fv_vk_buffer dummy_stats[FV_MAX_FRAMES_IN_FLIGHT]; /* 256 bytes per slot: an unbound stats buffer (never written) */
    fv_vk_image dummy_array;    /* 1x1, 1 layer, rgba32f zero: an unbound technique image */
    VkSampler linear;           /* clamp-to-edge linear, for technique images that ask for it */
    fv_image_id bound_image[FV_SHADE_INPUTS_BINDING_COUNT]; /* technique images of the table, FV_IMAGE_MAX if none */
} fv_shade_inputs;

FV_MUST_CHECK fv_result fv_shade_inputs_init(fv_shade_inputs *si, fv_vk *vk, uint32_t frames_in_flight);
void fv_shade_inputs_fini(fv_shade_inputs *si);
/** The slot's shadow block to fill (the GPU is done with the slot); fv_shade_inputs_begin_frame zeroes its counts. */
fv_gpu_shadow *fv_shade_inputs_shadow(fv_shade_inputs *si, uint32_t slot);
void fv_shade_inputs_begin_frame(fv_shade_inputs *si, uint32_t slot);
/** Make the slot's host writes visible (after every producer filled it). */
FV_MUST_CHECK fv_result fv_shade_inputs_end_frame(fv_shade_inputs *si, uint32_t slot);
/** Bind the shadow maps (an image of the table, sampled in DEPTH_STENCIL_READ_ONLY_OPTIMAL), or FV_IMAGE_MAX for
 *  the dummy. Rewrites every slot's set: the GPU must be idle. */
void fv_shade_inputs_bind_shadow_map(fv_shade_inputs *si, const fv_images *images, fv_image_id id);
VkDescriptorSet fv_shade_inputs_set(const fv_shade_inputs *si, uint32_t slot);
/** Bind a read-only storage buffer at a technique binding (FV_SHADE_INPUTS_BINDING_GI_BUFFER0 + k,
 *  _SSS_BUFFER0 + k, k < FV_SHADE_INPUTS_SLOT_BUFFERS) in every slot's set; buffer VK_NULL_HANDLE binds the dummy.
 *  The GPU must be idle (as for every descriptor rewrite here). FV_ERR_INVALID_ARG for a binding that is not a
 *  technique buffer. */
FV_MUST_CHECK fv_result fv_shade_inputs_bind_buffer(fv_shade_inputs *si, uint32_t binding, VkBuffer buffer,
                                                    VkDeviceSize offset, VkDeviceSize range);
/** Bind slot `slot`'s stats buffer of a technique (binding …_BUFFER0 + FV_SHADE_INPUTS_SLOT_STATS): shading passes
 *  that count the technique's work write it with atomics during that slot's frames; the technique clears it before
 *  they run and reads it back after. VK_NULL_HANDLE binds the slot's dummy. The GPU must be idle. FV_ERR_INVALID_ARG
 *  for another binding or a slot out of range. (fv_shade_inputs_bind_buffer with VK_NULL_HANDLE on a stats binding
 *  binds every slot's dummy; with a buffer it is FV_ERR_INVALID_ARG: stats are per slot.) */
FV_MUST_CHECK fv_result fv_shade_inputs_bind_stats(fv_shade_inputs *si, uint32_t binding, uint32_t slot,
                                                   VkBuffer buffer, VkDeviceSize offset, VkDeviceSize range);
/** Bind an image of the table (its view is a 2D array) at a technique image binding (…_IMAGE0 + k), sampled in
 *  SHADER_READ_ONLY_OPTIMAL with the nearest (linear = false) or linear clamp sampler; id FV_IMAGE_MAX binds the
 *  dummy. fv_shade_inputs_use then transitions it for the consumer. */
FV_MUST_CHECK fv_result fv_shade_inputs_bind_image(fv_shade_inputs *si, const fv_images *images, uint32_t binding,
                                                   fv_image_id id, bool linear);
/** Declare a consumer's read of the bound shadow maps and technique images at `stage` (a barrier when they were
 *  just written). */
void fv_shade_inputs_use(const fv_shade_inputs *si, fv_images *images, VkCommandBuffer cmd, VkPipelineStageFlags stage);

#endif
