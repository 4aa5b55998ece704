/* @brief The contract between the renderer and a pass. A pass is a room (render/<pass>/) that exports one
 * fv_pass entry; the renderer's pass table (render/passes.c) lists the entries in frame order. From the scene, the
 * device and the quality settings, each entry's plan() decides once whether it runs and why; the renderer then
 * init()s the enabled entries, record()s them in order inside their own timestamp range each frame, and fini()s
 * them when the plan turns them off or the renderer goes. A pass receives its inputs and outputs from the
 * renderer's image table (fv_images.h) and the scene from fv_scene_gpu; it never includes another pass. */
#ifndef FV_PASS_H
#define FV_PASS_H

#include "fovea/fv_frame_input.h"
#include "fv_frame_samples.h"
#include "fv_images.h"
#include "fv_plan.h"
#include "fv_scene.h"
#include "fv_scene_gpu.h"
#include "fv_shade_inputs.h"
#include "fv_vk.h"

/** What a plan decision may look at. */
typedef struct fv_plan_context {
    const fv_scene *scene;             /* NULL: no scene loaded */
    const fv_vk_device_info *device;   /* NULL: planning without a device (fv_frame_plan_build) */
    bool multiview;                    /* the G-buffer draws both eyes in one multiview pass */
    const char *multiview_why;         /* when !multiview: why not (one line), else NULL */
    const fv_quality *quality;         /* never NULL */
    const char *target;                /* what the frame is shown on ("headless", "window"); NULL = headless */
    bool motion_target;                /* the G-buffer keeps its motion vectors for read-back (fv_renderer_desc) */
} fv_plan_context;

/** What init gets: everything a pass may keep pointers to until fini. */
typedef struct fv_pass_env {
    fv_vk *vk;
    fv_scene_gpu *scene;        /* its set_layout is set 0 (FV_SCENE_SET) of every pass's pipeline layout */
    fv_images *images;          /* request images here (fv_images_get / fv_images_scratch) */
    fv_shade_inputs *shade_inputs; /* set 1 of shading passes: producers bind their images here at init */
    uint32_t width, height;     /* per eye, px */
    uint32_t slots;             /* frames in flight */
    bool multiview;
    const fv_plan_entry *plan;  /* this pass's decision */
    fv_frame_samples *samples;  /* the renderer's frame sample list (a producer reserves it at init) */
    const fv_scene *scene_model; /* the loaded scene's structure as planning sees it (nodes, meshes without vertex
                                  * data, materials, lights; NULL: none), valid until fini */
} fv_pass_env;

/** A list of packed pixels to re-shade (fv_gpu.h: FV_GPU_LIST_*), its indirect dispatch arguments, and the count
 *  when the host knows it. Buffers already visible to compute reads and indirect commands. */
typedef struct fv_pixel_list {
    VkBuffer buffer;
    VkDeviceSize offset, range;
    VkBuffer indirect;
    VkDeviceSize indirect_offset;
    uint32_t host_count;
    bool count_on_gpu; /* the GPU wrote the count (host_count is 0): count the list in counters->gpu_lists; the
                        * renderer adds its size to pixels_shaded after the frame */
} fv_pixel_list;

/** What record gets, per frame. */
typedef struct fv_pass_frame {
    VkCommandBuffer cmd;
    uint32_t slot;
    const fv_frame_input *input;
    fv_images *images;
    fv_scene_gpu *scene;
    VkDescriptorSet scene_set;   /* the slot's shared set (set 0) */
    fv_shade_inputs *shade_inputs; /* the slot's set: fv_shade_inputs_set(shade_inputs, slot) */
    const fv_pixel_list *pixels; /* NULL: a whole frame; else the renderer re-shades these pixels only */
    fv_pass_counters *counters;  /* zeroed before record; the pass adds what it did */
    fv_frame_samples *samples;   /* record: a producer fills the slot's list and sets samples->active; the passes
                                  * after it then get it as `pixels` */
} fv_pass_frame;

/** A NULL-terminated list of image names for an entry's declarations: FV_PASS_NAMES("fovea mask", "fovea blocks"). */
#define FV_PASS_NAMES(...) ((const char *const[]){__VA_ARGS__, NULL})

/** Flags of a pass entry. */
#define FV_PASS_REPLAYS_ON_PIXELS 1u /* runs again, after shading, when the renderer re-shades a pixel list */

typedef struct fv_pass {
    const char *id; /* "gbuffer", "shade", ...: the plan's and the timings' name */
    uint32_t flags;
    /** Decide: out->enabled, out->reason (one line: what it does, or "off — why"), out->variant. out->pass is set. */
    void (*plan)(const fv_plan_context *ctx, fv_plan_entry *out);
    /** Pipelines, layouts, images, descriptor sets. NULL for a plan-only entry (a pass that does not exist yet). */
    fv_result (*init)(const fv_pass_env *env, void **out_state);
    /** Before recording (the GPU is done with the slot): write this slot's host-side data, e.g. the shadow block of
     *  the shading inputs. frame->cmd is not yet recording. NULL: nothing to prepare. */
    void (*prepare)(void *state, const fv_pass_frame *frame);
    /** Record the frame's work. Records only: never submits, waits or allocates device memory. */
    void (*record)(void *state, const fv_pass_frame *frame);
    /** After every pass recorded a whole frame (not a pixel-list replay): copy back what later passes wrote for this
     *  one (e.g. stats the shading passes counted), for the host to read after the slot's fence. Records only; no
     *  timestamp range of its own. NULL: nothing. */
    void (*record_end)(void *state, const fv_pass_frame *frame);
    /** Free everything (the GPU is idle). */
    void (*fini)(void *state);
    /** What it decided for the last prepared frame, as named numbers (NULL: nothing to say). Returns the count. */
    uint32_t (*details)(void *state, fv_pass_detail *out, uint32_t cap);
    /** Declared resources: the named images it makes (fv_images_scratch's desc name), those of other passes it
     *  needs whenever it runs, and those it uses only when their maker runs (fv_images_find), each a
     *  FV_PASS_NAMES list or NULL. The renderer checks the plan against them before any init (every need has an
     *  enabled maker earlier in the table; a maker after its reader or a name nobody makes is an error naming
     *  both passes: fv_frame_plan_check), and during init refuses an fv_images_find or fv_images_scratch of a name
     *  the pass did not declare. `fovea run --explain` prints them. */
    const char *const *makes;
    const char *const *needs;
    const char *const *uses_if_made;
} fv_pass;

#endif
