/* @brief The frame sample list: a renderer-owned pixel list (fv_gpu.h FV_GPU_LIST_*) per frame in flight that a pass
 * fills on the GPU (the foveation pass: the sampled pixels of both eyes) and marks active while recording; the
 * renderer then hands it as frame->pixels to the passes after it, and reads its count back after the slot's fence.
 * Buffers are made on the first fv_frame_samples_reserve. One owner thread. */
#ifndef FV_FRAME_SAMPLES_H
#define FV_FRAME_SAMPLES_H

#include <stdbool.h>

#include "fv_gpu.h"
#include "fv_vk.h"

typedef struct fv_frame_samples {
    fv_vk *vk;
    uint32_t slots;
    uint32_t capacity;                               /* pixels a list holds: both eyes, every pixel */
    fv_vk_buffer list[FV_MAX_FRAMES_IN_FLIGHT];      /* header {count} + packed pixels; host-readable for the count */
    fv_vk_buffer indirect[FV_MAX_FRAMES_IN_FLIGHT];  /* VkDispatchIndirectCommand (storage + indirect) */
    bool active;                                     /* this frame's list was filled by a pass (reset per frame) */
} fv_frame_samples;

/** Describe (nothing allocated). */
void fv_frame_samples_init(fv_frame_samples *s, fv_vk *vk, uint32_t slots, uint32_t capacity);
/** Create the buffers if not yet there (at pass init: the GPU is idle). */
FV_MUST_CHECK fv_result fv_frame_samples_reserve(fv_frame_samples *s);
/** Destroy the buffers (the GPU is idle). Safe twice. */
void fv_frame_samples_fini(fv_frame_samples *s);
/** The slot's list count as the GPU wrote it (after the slot's fence; 0 before any). */
uint32_t fv_frame_samples_count(fv_frame_samples *s, uint32_t slot);

#endif
