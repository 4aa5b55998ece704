/* @brief The present pass: tonemap and encode linear colour to sRGB RGBA8 (a compute pass) into a headless target
 * (a 2-layer image that stays on the GPU), and read it back side by side (2W x H) or one eye. One owner thread. */
#ifndef FV_PRESENT_H
#define FV_PRESENT_H

#include <stdbool.h>

#include "fv_vk.h"
#include "present_interface.h"

typedef struct fv_present {
    fv_vk *vk;
    uint32_t width, height;
    const fv_vk_image *linear; /* not owned: the shading pass's colour image (GENERAL) */
    fv_vk_image output;        /* RGBA8 (sRGB-encoded values), 2 layers, always GENERAL */
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    VkDescriptorPool pool;
    VkDescriptorSet set;
    float exposure;
} fv_present;

/** tonemap: FV_TONEMAP_*. `linear` must stay alive and in GENERAL layout. */
FV_MUST_CHECK fv_result fv_present_init(fv_present *pr, fv_vk *vk, const fv_vk_image *linear, uint32_t tonemap);
void fv_present_fini(fv_present *pr);
/** Record the pass. Entry: linear colour in GENERAL with its writes visible to compute reads. Exit: the output in
 *  GENERAL, visible to transfers and compute reads. */
void fv_present_record(fv_present *pr, VkCommandBuffer cmd);
/** Read the output (submits and waits; call when the frame that wrote it has been submitted): sbs = both eyes
 *  side by side (2W x H x 4 bytes), else one eye (W x H x 4). */
FV_MUST_CHECK fv_result fv_present_read_rgba8(fv_present *pr, bool sbs, int eye, uint8_t *out, size_t out_size);

#endif
