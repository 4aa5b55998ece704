/* @brief The renderer's post chain: the passes of the pass table that work on a finished display image
 * (FV_IMAGE_DISPLAY in an image table) — lens pre-distortion — for a compositor that makes that image itself (the
 * OpenXR runtime's compose pass). The chain plans each pass by the renderer's rules (its own plan function, the same
 * context), creates the enabled ones, records them in table order with a GPU timer slot each, and destroys them:
 * no caller drives a pass by hand. One owner thread. */
#ifndef FV_POST_CHAIN_H
#define FV_POST_CHAIN_H

#include <stdbool.h>
#include <stdint.h>

#include <vulkan/vulkan.h>

#include "fovea/fv_frame_input.h"
#include "fv_images.h"
#include "fv_result.h"
#include "fv_vk.h"

typedef struct fv_post_chain fv_post_chain;

/** Plan and create the chain for a w x h (per eye) display image in `images` (which must outlive the chain) under
 *  quality q (its lens and distort.* knobs). FV_OK with *out set (a chain whose passes are all off records nothing),
 *  or the first pass's init error (nothing is left created). */
fv_result fv_post_chain_create(fv_vk *vk, fv_images *images, uint32_t w, uint32_t h, const fv_quality *q,
                               fv_post_chain **out);
/** How many passes the chain records (0: all planned off). */
uint32_t fv_post_chain_count(const fv_post_chain *pc);
/** The chain's passes as planned (on or off), in table order: how many, and pass k's id and one-line reason. */
uint32_t fv_post_chain_planned(const fv_post_chain *pc);
const char *fv_post_chain_pass_id(const fv_post_chain *pc, uint32_t k);
const char *fv_post_chain_reason(const fv_post_chain *pc, uint32_t k);
/** Record the enabled passes on cmd for frame `in` (its quality, lens and eye frusta), each timed in `timer`'s slot
 *  `slot` under its pass id when timer is not NULL. */
void fv_post_chain_record(fv_post_chain *pc, VkCommandBuffer cmd, const fv_frame_input *in, fv_vk_timer *timer,
                          uint32_t slot);
void fv_post_chain_destroy(fv_post_chain **pc);

#endif
