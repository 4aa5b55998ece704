/* @brief The renderer object's insides, shared by the files that do its jobs: renderer.c (create/destroy, the plan
 * and the pass loop, frames in flight), renderer_frame.c (the frame constants from the runtime's input),
 * renderer_scene.c (loading a scene and the copy of its structure that planning reads) and renderer_readback.c
 * (reading images back, re-shading pixel lists). Not a public header: only render/renderer*.c include it. */
#ifndef FV_RENDERER_INTERNAL_H
#define FV_RENDERER_INTERNAL_H

#include "fv_gpu.h"
#include "fv_images.h"
#include "fv_knobs.h"
#include "fv_passes.h"
#include "fv_renderer.h"
#include "fv_scene_gpu.h"
#include "fv_shade_inputs.h"
#include "fv_target.h"
#include "fv_vk.h"

#define MOD "render"

/* Per frame in flight: what the CPU writes or the GPU may still be using while the next frame is recorded. */
typedef struct frame_slot {
    VkCommandPool pool;
    VkCommandBuffer cmd;
    VkFence fence;
    VkSemaphore image_ready, frame_done; /* binary semaphores for the target's hand-overs */
    bool pending;                        /* submitted, fence not yet waited for */
    uint64_t seq;                        /* submission number (caller frame ids need not increase) */
    uint64_t frame_id;
    fv_pass_counters counters[FV_MAX_PASSES]; /* per timed pass, in timer order */
    bool sampled;                        /* a pass filled the frame sample list: its count is read back at retire */
    uint32_t counter_count;
} frame_slot;

struct fv_renderer {
    fv_renderer_desc desc;
    fv_vk *vk;
    fv_images images;
    fv_scene_gpu scene;
    fv_shade_inputs shade_inputs;
    fv_frame_samples samples; /* the frame sample list (fv_frame_samples.h) */
    fv_vk_timer timer;
    fv_target *target;
    frame_slot slots[FV_MAX_FRAMES_IN_FLIGHT];
    uint32_t slot_count, next_slot;
    /* the pass table, its plan and each enabled pass's state */
    const fv_pass *const *table;
    uint32_t pass_count;
    void *pass_state[FV_MAX_PASSES];
    uint32_t pass_variant[FV_MAX_PASSES]; /* the variant each live state was made for */
    fv_frame_plan plan;
    fv_quality plan_quality;
    bool multiview;
    char multiview_why[96];
    /* the loaded scene, as planning needs it (no vertex data, no textures) */
    bool scene_loaded;
    fv_scene plan_scene;
    fv_head head;
    fv_vec3 bounds_min, bounds_max;
    bool has_bounds;
    /* previous frame, for motion vectors */
    bool have_prev;
    double prev_time_s;
    fv_mat4 prev_view_proj[2];
    /* results */
    bool have_frame;
    uint32_t last_slot;
    fv_frame_input last_input;
    fv_render_stats stats;
    bool have_stats;
    fv_render_stats history[FV_RENDERER_STATS_HISTORY]; /* the last retired frames, by frame_id % N */
    bool history_valid[FV_RENDERER_STATS_HISTORY];
    uint64_t stats_seq, submitted;
};

/* ---- between the renderer's files ---------------------------------------------------------------------------- */

/** Decide the plan for `quality` and bring the passes in line with it (renderer.c). */
fv_result fv_renderer_plan_apply(fv_renderer *r, const fv_quality *quality);
/** Record the enabled passes of a frame or, with `replay`, of a pixel-list re-shade (renderer.c). */
void fv_renderer_record_passes(fv_renderer *r, VkCommandBuffer cmd, uint32_t slot, const fv_frame_input *in,
                               const fv_pixel_list *replay, bool timed, frame_slot *s);
/** Forget the loaded scene: GPU copy, planning copy, motion history (renderer_scene.c). */
void fv_renderer_release_scene(fv_renderer *r);
/** The GPU frame block for `in`, and each eye's view-projection (renderer_frame.c). */
void fv_renderer_frame_constants(fv_renderer *r, const fv_frame_input *in, fv_gpu_frame *fr, fv_mat4 vp[2]);
/** Every view and projection matrix of `in` finite (renderer_frame.c). */
bool fv_renderer_frame_input_ok(const fv_frame_input *in);
/** FV_OK after the first drawn frame, else an error naming `what` (renderer_readback.c). */
fv_result fv_renderer_need_frame(const fv_renderer *r, const char *what);

#endif
