/* @brief The renderer's frame images, owned in one table and handed to passes by id: the G-buffer targets, linear
 * colour, the history for temporal reuse, the display-encoded output, and per-pass scratch images. Each is a
 * 2-layer array (layer = eye) created on first request, and the table tracks its layout and last accesses so a pass
 * states only how it is about to use an image (fv_images_use) and gets exactly the barrier that needs. One owner
 * thread; recording order must be submission order (one queue). */
#ifndef FV_IMAGES_H
#define FV_IMAGES_H

#include <stdbool.h>

#include "fv_vk.h"

typedef enum fv_image_id {
    FV_IMAGE_DEPTH = 0,  /* D32, G-buffer depth (Vulkan 0..1) */
    FV_IMAGE_NORMAL,     /* octahedral world normal facing the eye: RG16_SNORM (RG32F where unsupported) */
    FV_IMAGE_ALBEDO,     /* RGBA8 sRGB, linear albedo on read */
    FV_IMAGE_MATERIAL,   /* R16UI material index + 1; 0 = nothing drawn */
    FV_IMAGE_MOTION,     /* RG16F current uv - previous uv */
    FV_IMAGE_SURFACE,    /* RGBA32F what foveation reads of a pixel in one fetch (FV_GBUFFER_OUT_SURFACE): motion,
                          * distance to the eye, normal bits; drawn only while foveation runs */
    FV_IMAGE_COLOR,      /* RGBA32F linear radiance (shading's output) */
    FV_IMAGE_HISTORY,    /* RGBA32F the previous frame's colour, its known pixels' distance and age in alpha
                          * (render/fovea: temporal reads it, reconstruction copies the frame's colour into it) */
    FV_IMAGE_DISPLAY,    /* RGBA8 UNORM holding sRGB-encoded values: the present pass's output, what targets show */
    FV_IMAGE_BUILTIN_COUNT,
    FV_IMAGE_MAX = FV_IMAGE_BUILTIN_COUNT + 16 /* + FV_IMAGE_SCRATCH_MAX scratch images of passes */
} fv_image_id;
/** How many scratch images the passes may hold at once (7 in use with every pass on); one more is an error
 *  (fv_images_scratch names the image and the limit). */
#define FV_IMAGE_SCRATCH_MAX (FV_IMAGE_MAX - FV_IMAGE_BUILTIN_COUNT)

typedef struct fv_image_slot {
    fv_vk_image img;
    bool created;
    char name[48];
    VkFormat format;
    VkImageUsageFlags usage;
    /* tracked state */
    VkImageLayout layout;
    VkPipelineStageFlags write_stage; /* stages of the last write (or layout change) */
    VkAccessFlags write_access;       /* its accesses, to be made available */
    VkPipelineStageFlags visible;     /* stages the last write was made visible to */
    VkPipelineStageFlags readers;     /* stages that read since the last write */
} fv_image_slot;

typedef struct fv_images {
    fv_vk *vk;
    uint32_t width, height; /* per eye */
    fv_image_slot slot[FV_IMAGE_MAX];
    uint32_t count;         /* builtins + scratch */
    /* While a pass starts (the renderer sets these around its init): its id and its declared image names (fv_pass
     * makes, needs, uses_if_made); fv_images_scratch and fv_images_find refuse any other name, with an error that
     * names the pass. starting NULL: nothing is checked (the renderer's own reads, tests). */
    const char *starting;
    const char *const *declared[3];
} fv_images;

/** Describe the builtin images (nothing allocated yet). t is zeroed first. */
FV_MUST_CHECK fv_result fv_images_init(fv_images *t, fv_vk *vk, uint32_t width, uint32_t height);
/** Destroy every image (the GPU must be idle). Safe twice. */
void fv_images_fini(fv_images *t);
/** The image of id, created on first request (in UNDEFINED layout). */
FV_MUST_CHECK fv_result fv_images_get(fv_images *t, fv_image_id id, const fv_vk_image **out);
/** Add (and create) a scratch image of a pass: 2 layers of width x height per eye unless desc says otherwise. While
 *  a pass starts, its name must be one the pass declares it makes (else FV_ERR_STATE). */
FV_MUST_CHECK fv_result fv_images_scratch(fv_images *t, const fv_vk_image_desc *desc, fv_image_id *out_id);
/** Destroy a scratch image and free its slot for the next fv_images_scratch (the GPU must be done with it). */
void fv_images_release(fv_images *t, fv_image_id id);
/** The id of the created image named `name` (a scratch image's desc name), or FV_ERR_NOT_FOUND. While a pass
 *  starts, the name must be one it declares (else FV_ERR_STATE, checked before the search). */
FV_MUST_CHECK fv_result fv_images_find(const fv_images *t, const char *name, fv_image_id *out_id);
/** The image as created (NULL before fv_images_get created it). */
const fv_vk_image *fv_images_image(const fv_images *t, fv_image_id id);

/** Record what `use` needs before it: a barrier from the image's tracked state when the use writes, changes the
 *  layout, or reads at a stage the last write was not yet made visible to; nothing otherwise. Updates the state. */
void fv_images_use(fv_images *t, VkCommandBuffer cmd, fv_image_id id, fv_vk_image_use use);
/** A render pass wrote the image itself (initial layout UNDEFINED, its external dependencies waiting for earlier
 *  work at `waits_for` stages and making its writes visible at `visible_to` stages): record a barrier for earlier
 *  users outside `waits_for` (before the render pass begins), then set the state to `done`. */
void fv_images_render_pass(fv_images *t, VkCommandBuffer cmd, fv_image_id id, VkPipelineStageFlags waits_for,
                           fv_vk_image_use done, VkPipelineStageFlags visible_to);
/** Reading the G-buffer in shaders at `stage`: depth, normal, albedo and material as sampled images, in the
 *  layouts the G-buffer pass leaves them (fv_images_use on each). */
void fv_images_use_gbuffer(fv_images *t, VkCommandBuffer cmd, VkPipelineStageFlags stage);
/** Write the G-buffer's depth, normal, albedo and material views into bindings first_binding .. first_binding + 3
 *  of `set` as combined image samplers with `sampler`, in those layouts (the images must exist: fv_images_get). */
void fv_images_bind_gbuffer(const fv_images *t, VkDescriptorSet set, uint32_t first_binding, VkSampler sampler);
/** Request the four G-buffer images a reader binds (creating them if needed). */
FV_MUST_CHECK fv_result fv_images_get_gbuffer(fv_images *t);

/** The tracked layout of an image. */
VkImageLayout fv_images_layout(const fv_images *t, fv_image_id id);


/** Read one layer back (submits and waits; the GPU must be done with every recorded use, e.g. after the frame's
 *  fence). Texels tightly packed with out_row_pitch bytes per row at out_offset. */
FV_MUST_CHECK fv_result fv_images_read(fv_images *t, fv_image_id id, uint32_t layer, void *out, size_t out_size,
                                       size_t out_offset, size_t out_row_pitch);

#endif
