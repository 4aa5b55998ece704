/* @brief The G-buffer pass's hidden-area mask (internal to render/gbuffer): the triangles of fv_lens_hidden_mesh
 * (runtime/hmd) for each eye's frustum, in a host-visible vertex buffer per frame in flight, drawn at depth 0 before
 * the scene so that no scene fragment there is shaded and every later pass sees "nothing drawn" (material 0). */
#ifndef FV_GBUFFER_MASK_H
#define FV_GBUFFER_MASK_H

#include "fv_hmd.h"
#include "fv_pass.h"

typedef struct gbuffer_mask {
    fv_vk *vk;
    uint32_t width, height, slots;
    bool multiview;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    fv_vk_buffer vertices[FV_MAX_FRAMES_IN_FLIGHT];
    uint32_t count[FV_MAX_FRAMES_IN_FLIGHT][2]; /* vertices per eye in the slot's buffer */
    bool built[FV_MAX_FRAMES_IN_FLIGHT];
    fv_lens lens[FV_MAX_FRAMES_IN_FLIGHT];      /* what the slot's mesh was built for */
    fv_hmd_fov fov[FV_MAX_FRAMES_IN_FLIGHT][2];
    double fraction[2];                         /* of each eye's pixels the last built mesh covers */
} gbuffer_mask;

/** Whether a frame of this quality is masked: distortion and the mask on, and a lens. */
bool gbuffer_mask_wanted(const fv_quality *q);
/** The mask pipeline in the G-buffer's render pass (with that many colour attachments), and the per-slot vertex
 *  buffers. fini is safe after a failure. */
FV_MUST_CHECK fv_result gbuffer_mask_init(gbuffer_mask *m, fv_vk *vk, VkRenderPass render_pass, bool multiview,
                                          uint32_t slots, uint32_t width, uint32_t height, uint32_t color_attachments);
/** Host side, before recording: (re)build the slot's mesh when the frame's lens or frustum changed. */
void gbuffer_mask_prepare(gbuffer_mask *m, uint32_t slot, const fv_frame_input *in);
/** Inside the G-buffer render pass, before the scene: draw the slot's mask for `eye` (-1: both, multiview).
 *  Returns the triangles drawn. */
uint32_t gbuffer_mask_record(gbuffer_mask *m, VkCommandBuffer cmd, uint32_t slot, int eye);
void gbuffer_mask_fini(gbuffer_mask *m);

#endif
