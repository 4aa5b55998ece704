/* @brief Vulkan core: instance, device selection, queue, command pool, validation messenger, checked calls, debug
 * names and labels, memory with a budget, buffers, 2D/array images, samplers, pipelines, descriptor sets, per-pass
 * GPU timestamps (per frame in flight), staging upload and image readback. One owner thread; not thread-safe,
 * except the validation-message counter, which the layer may bump from any thread. */
#ifndef FV_VK_H
#define FV_VK_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <vulkan/vulkan.h>

#include "fv_log.h"
#include "fv_result.h"

/** The most frames the renderer keeps in flight; every per-slot array in render/ is sized by it. */
#define FV_MAX_FRAMES_IN_FLIGHT 8
/** The most extra instance or device extensions a caller may ask fv_vk_create for. */
#define FV_VK_MAX_EXTENSIONS 16

/** Name of a VkResult ("VK_ERROR_DEVICE_LOST"); never NULL. */
const char *fv_vk_result_str(VkResult r);
/** Log a failed Vulkan call (call text, VkResult name, file:line) and map it to an fv_result. */
fv_result fv_vk_fail(VkResult r, const char *call, const char *file, int line);

/** Evaluate a Vulkan call; on failure log it and return FV_ERR_VULKAN (FV_ERR_DEVICE_LOST / FV_ERR_NO_MEMORY where
 *  that is the cause) from the enclosing function. */
#define FV_VK_CHECK(call)                                                                                              \
    do {                                                                                                               \
        VkResult fv_vk_r_ = (call);                                                                                    \
        if (fv_vk_r_ < 0) return fv_vk_fail(fv_vk_r_, #call, __FILE__, __LINE__);                                     \
    } while (0)
/** Same, but stores the fv_result in `res` and jumps to `label` (for create functions with one cleanup path). */
#define FV_VK_CHECK_GOTO(call, res, label)                                                                             \
    do {                                                                                                               \
        VkResult fv_vk_r_ = (call);                                                                                    \
        if (fv_vk_r_ < 0) {                                                                                            \
            (res) = fv_vk_fail(fv_vk_r_, #call, __FILE__, __LINE__);                                                   \
            goto label;                                                                                                \
        }                                                                                                              \
    } while (0)

/* ---- device listing (for `fovea info`) ---------------------------------------------------------------------- */

typedef struct fv_vk_device_info {
    uint32_t index;
    char name[VK_MAX_PHYSICAL_DEVICE_NAME_SIZE];
    VkPhysicalDeviceType type;
    uint32_t api_version;
    uint32_t driver_version;
    char driver_name[VK_MAX_DRIVER_NAME_SIZE];
    char driver_info[VK_MAX_DRIVER_INFO_SIZE];
    bool usable;         /* meets fovea's requirements */
    char why_not[128];   /* when !usable: the first requirement it misses */
    bool multiview;
    uint32_t max_multiview_views;
    bool timestamps;     /* timestampComputeAndGraphics and valid bits on the chosen queue */
    float timestamp_period_ns;
    uint32_t subgroup_size;
    bool descriptor_indexing;
    bool storage_image_write_without_format;
    uint64_t device_local_bytes; /* largest device-local heap */
    uint32_t max_image_dimension_2d;
    uint32_t max_compute_workgroup_invocations;
    uint32_t shader_loop_limit; /* iterations a shader's loops may run in all before the device ends them (0: none;
                                 * llvmpipe: FV_VK_LLVMPIPE_LOOP_LIMIT) */
} fv_vk_device_info;

/** Name of a device type ("discrete GPU", "CPU"...). */
const char *fv_vk_device_type_str(VkPhysicalDeviceType t);

/** List every Vulkan device, and which one a selector picks (NULL = $FOVEA_DEVICE, else prefer a discrete GPU,
 *  then integrated, virtual, CPU). Creates a temporary instance. out_chosen is -1 when none qualifies; why names
 *  the reason for the choice (or the failure). */
FV_MUST_CHECK fv_result fv_vk_list_devices(const char *selector, fv_vk_device_info *out, uint32_t cap,
                                           uint32_t *out_count, int *out_chosen, char *why, size_t why_size);

/** Whether the device is Mesa llvmpipe (lavapipe), a CPU device with limits of its own (multiview below; a shader's
 *  loops end after FV_VK_LLVMPIPE_LOOP_LIMIT iterations in all, whatever the code says: shader_loop_limit). */
bool fv_vk_is_llvmpipe(const fv_vk_device_info *d);
#define FV_VK_LLVMPIPE_LOOP_LIMIT 65535u /* Mesa's LP_MAX_TGSI_LOOP_ITERATIONS */

/** Whether fovea should draw both eyes in one multiview pass on this device: false for Mesa llvmpipe (lavapipe),
 *  whose multiview (Mesa 22.3) loses or misplaces primitives of view 1 that need clipping; $FOVEA_MULTIVIEW=0/1
 *  overrides. why (may be NULL) gets a one-line reason. */
bool fv_vk_multiview_trusted(const fv_vk_device_info *d, char *why, size_t why_size);

/* ---- the core object -------------------------------------------------------------------------------------- */

typedef struct fv_vk_desc {
    const char *device;         /* index or name substring; NULL = $FOVEA_DEVICE, else the preferred device */
    int validation;             /* 1 on, 0 = from $FOVEA_VALIDATION, -1 off */
    uint64_t memory_budget_bytes; /* 0 = 80% of the largest device-local heap */
    const char *app_name;       /* NULL = "fovea" */
    /* Presenting to a surface (a window target): instance extensions it needs (e.g. from
     * glfwGetRequiredInstanceExtensions; VK_KHR_surface is implied), extra device extensions (VK_KHR_swapchain is
     * implied when create_surface is set), and a callback that creates the surface once the instance exists. A device
     * with no queue family able to present to that surface, or missing a device extension, is not usable. */
    const char *const *instance_extensions;
    uint32_t instance_extension_count;
    const char *const *device_extensions;
    uint32_t device_extension_count;
    fv_result (*create_surface)(VkInstance instance, void *user, VkSurfaceKHR *out_surface);
    void *surface_user;
    /* Device extensions enabled only when the chosen device has them (a device without them stays usable); the
     * strings must outlive the fv_vk (static names). fv_vk_optional_enabled says which were. */
    const char *const *optional_device_extensions;
    uint32_t optional_device_extension_count;
} fv_vk_desc;

typedef struct fv_vk {
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;
    VkPhysicalDevice phys;
    VkDevice device;
    VkQueue queue;
    uint32_t queue_family;
    VkSurfaceKHR surface;    /* from fv_vk_desc.create_surface, or VK_NULL_HANDLE (headless) */
    VkQueue present_queue;   /* a queue that can present to `surface` (== queue when one family does both) */
    uint32_t present_family; /* its family; images shared across two families need an ownership transfer */
    VkCommandPool pool;      /* for one-shot commands (uploads, readbacks); resettable buffers */
    VkFence oneshot_fence;
    VkPhysicalDeviceProperties props;
    VkPhysicalDeviceMemoryProperties mem_props;
    fv_vk_device_info info;
    char choice_reason[160];
    bool validation;
    bool debug_utils;
    atomic_uint validation_messages;
    uint64_t memory_budget_bytes;
    uint64_t memory_bytes;       /* currently allocated device memory (all heaps) */
    uint64_t memory_peak_bytes;
    uint32_t allocation_count;
    PFN_vkSetDebugUtilsObjectNameEXT set_object_name;
    PFN_vkCmdBeginDebugUtilsLabelEXT cmd_label_begin;
    PFN_vkCmdEndDebugUtilsLabelEXT cmd_label_end;
    const char *optional_enabled[FV_VK_MAX_EXTENSIONS]; /* the optional device extensions this device enabled */
    uint32_t optional_enabled_count;
    VkPipelineCache pipeline_cache; /* every pipeline is made through it; loaded from and saved to the file below */
    char pipeline_cache_path[1024]; /* "" = no file (FOVEA_PIPELINE_CACHE=off, or no cache directory) */
    size_t pipeline_cache_loaded_bytes;
    uint32_t pipelines_created;     /* this run: the file is written back only when it may have grown */
} fv_vk;

/** The pipeline cache: $FOVEA_PIPELINE_CACHE (a file; off or 0: none), else $XDG_CACHE_HOME/fovea/ or
 *  ~/.cache/fovea/pipelines-VENDOR-DEVICE-DRIVER.bin. A file whose header is not this device's and driver's, or that
 *  cannot be read, is ignored with one warning. Called by fv_vk_create; save by fv_vk_destroy. */
void fv_vk_pipeline_cache_open(fv_vk *vk);
void fv_vk_pipeline_cache_save(fv_vk *vk);

/** Create instance, messenger, device, queue and pool. Logs why when no device qualifies. */
FV_MUST_CHECK fv_result fv_vk_create(const fv_vk_desc *desc, fv_vk **out_vk);
/** Wait for the device, destroy everything, set *vk to NULL. Safe on NULL. Logs leaked allocations. */
void fv_vk_destroy(fv_vk **vk);
uint32_t fv_vk_validation_messages(const fv_vk *vk);
/** Whether an optional device extension (fv_vk_desc.optional_device_extensions) was enabled on this device. */
bool fv_vk_optional_enabled(const fv_vk *vk, const char *extension);

/** Give a Vulkan object a debug name (printf-style); no-op without debug utils. */
void fv_vk_name(fv_vk *vk, VkObjectType type, uint64_t handle, const char *fmt, ...) FV_PRINTF(4, 5);
#define FV_VK_NAME(vk, type, handle, ...) fv_vk_name((vk), (type), (uint64_t)(uintptr_t)(handle), __VA_ARGS__)
/** Debug label brackets around a pass in a command buffer. */
void fv_vk_label_begin(fv_vk *vk, VkCommandBuffer cmd, const char *name);
void fv_vk_label_end(fv_vk *vk, VkCommandBuffer cmd);

/* ---- memory ------------------------------------------------------------------------------------------------ */

typedef enum fv_vk_mem_kind {
    FV_VK_MEM_DEVICE = 0, /* device-local, not mapped */
    FV_VK_MEM_UPLOAD = 1, /* host-visible + coherent, persistently mapped (per-frame data, staging) */
    FV_VK_MEM_READBACK = 2, /* host-visible, cached if available, mapped */
} fv_vk_mem_kind;

typedef struct fv_vk_buffer {
    VkBuffer buffer;
    VkDeviceMemory memory;
    VkDeviceSize size;
    void *mapped;       /* non-NULL for UPLOAD/READBACK */
    bool coherent;
} fv_vk_buffer;

/** Allocate a buffer with its own memory after a budget check; named `name`. */
FV_MUST_CHECK fv_result fv_vk_buffer_create(fv_vk *vk, VkDeviceSize size, VkBufferUsageFlags usage,
                                            fv_vk_mem_kind kind, const char *name, fv_vk_buffer *out);
/** Destroy (safe on a zeroed or already destroyed buffer). The GPU must be done with it. */
void fv_vk_buffer_destroy(fv_vk *vk, fv_vk_buffer *b);
/** Make host writes visible / device writes readable on non-coherent memory. */
FV_MUST_CHECK fv_result fv_vk_buffer_flush(fv_vk *vk, fv_vk_buffer *b);
FV_MUST_CHECK fv_result fv_vk_buffer_invalidate(fv_vk *vk, fv_vk_buffer *b);

typedef struct fv_vk_image_desc {
    uint32_t width, height;
    uint32_t layers;          /* 1 = a 2D image (view type 2D), >1 = a 2D array (view type 2D_ARRAY) */
    bool array;               /* a 2D_ARRAY view even with one layer (for array samplers) */
    VkFormat format;
    VkImageUsageFlags usage;
    const char *name;
} fv_vk_image_desc;

typedef struct fv_vk_image {
    VkImage image;
    VkDeviceMemory memory;
    VkImageView view;         /* all layers */
    VkFormat format;
    VkImageAspectFlags aspect;
    uint32_t width, height, layers;
} fv_vk_image;

FV_MUST_CHECK fv_result fv_vk_image_create(fv_vk *vk, const fv_vk_image_desc *desc, fv_vk_image *out);
void fv_vk_image_destroy(fv_vk *vk, fv_vk_image *img);
/** Bytes per texel of the formats fovea uses (0 for others). */
uint32_t fv_vk_format_size(VkFormat f);
/** True when the format supports all of `features` with optimal tiling. */
bool fv_vk_format_supports(const fv_vk *vk, VkFormat f, VkFormatFeatureFlags features);

/** A sampler (nearest or linear, clamp or repeat). */
FV_MUST_CHECK fv_result fv_vk_sampler_create(fv_vk *vk, bool linear, bool repeat, const char *name, VkSampler *out);

/* ---- one-shot commands, upload and readback ---------------------------------------------------------------- */

/** Begin a one-shot command buffer on the core's pool. */
FV_MUST_CHECK fv_result fv_vk_oneshot_begin(fv_vk *vk, const char *label, VkCommandBuffer *out_cmd);
/** End, submit and wait for it, then free it. */
FV_MUST_CHECK fv_result fv_vk_oneshot_end(fv_vk *vk, VkCommandBuffer cmd);

/** Copy bytes into a device-local buffer through a staging buffer (submits and waits). The destination must not
 *  be in use by the GPU; after return, reads at vertex input/index/shader stages see the data. */
FV_MUST_CHECK fv_result fv_vk_upload_buffer(fv_vk *vk, fv_vk_buffer *dst, VkDeviceSize offset, const void *data,
                                            VkDeviceSize size);
/** Upload tightly packed texels into one layer of an image (all of it), leaving it in `final_layout`. */
FV_MUST_CHECK fv_result fv_vk_upload_image(fv_vk *vk, fv_vk_image *img, uint32_t layer, const void *data,
                                           size_t size, VkImageLayout final_layout);
/** Transition a whole image once (records, submits and waits), e.g. to GENERAL after creation. */
FV_MUST_CHECK fv_result fv_vk_image_set_layout(fv_vk *vk, fv_vk_image *img, VkImageLayout old_layout,
                                               VkImageLayout new_layout);
/** Read one layer of an image (in `layout`, written last at `src_stage`/`src_access`) into out as tightly packed
 *  texels (row pitch out_row_pitch bytes, at byte offset in out). Submits and waits; the image keeps its layout. */
FV_MUST_CHECK fv_result fv_vk_read_image(fv_vk *vk, fv_vk_image *img, uint32_t layer, VkImageLayout layout,
                                         VkPipelineStageFlags src_stage, VkAccessFlags src_access, void *out,
                                         size_t out_size, size_t out_offset, size_t out_row_pitch);

/* ---- synchronisation ----------------------------------------------------------------------------------------- */

/** How an image is (or is about to be) used: its layout, and the stages and accesses of that use. */
typedef struct fv_vk_image_use {
    VkImageLayout layout;
    VkPipelineStageFlags stage;
    VkAccessFlags access;
} fv_vk_image_use;

/** Record one image memory barrier over every layer and mip of img: the work of `from` (its accesses made
 *  available) happens before the work of `to` (made visible to its accesses), with the layout changed from
 *  from.layout to to.layout (UNDEFINED discards the contents). Same queue family on both sides. */
void fv_vk_barrier_image(VkCommandBuffer cmd, const fv_vk_image *img, fv_vk_image_use from, fv_vk_image_use to);
/** Record one global memory barrier: the work at src stages (its src_access made available) happens before the work
 *  at dst stages (made visible to dst_access); covers every buffer and image. Zero accesses: an execution
 *  dependency only (e.g. a write after a read). */
void fv_vk_barrier_memory(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags src_access,
                          VkPipelineStageFlags dst, VkAccessFlags dst_access);

/* ---- pipelines and descriptors ----------------------------------------------------------------------------- */

FV_MUST_CHECK fv_result fv_vk_shader_module(fv_vk *vk, const uint32_t *code, size_t size_bytes, const char *name,
                                            VkShaderModule *out);
/** A descriptor set layout from bindings. */
FV_MUST_CHECK fv_result fv_vk_set_layout(fv_vk *vk, const VkDescriptorSetLayoutBinding *bindings, uint32_t count,
                                         const char *name, VkDescriptorSetLayout *out);
FV_MUST_CHECK fv_result fv_vk_pipeline_layout(fv_vk *vk, const VkDescriptorSetLayout *sets, uint32_t set_count,
                                              uint32_t push_bytes, VkShaderStageFlags push_stages, const char *name,
                                              VkPipelineLayout *out);
/** A compute pipeline from embedded SPIR-V, with optional specialization constants (uint32 each, ids 0..n-1). */
FV_MUST_CHECK fv_result fv_vk_compute_pipeline(fv_vk *vk, const uint32_t *code, size_t size_bytes,
                                               VkPipelineLayout layout, const uint32_t *spec, uint32_t spec_count,
                                               const char *name, VkPipeline *out);

typedef struct fv_vk_graphics_desc {
    const uint32_t *vert;
    size_t vert_size;
    const uint32_t *frag;
    size_t frag_size;
    const VkVertexInputBindingDescription *bindings;
    uint32_t binding_count;
    const VkVertexInputAttributeDescription *attributes;
    uint32_t attribute_count;
    VkPipelineLayout layout;
    VkRenderPass render_pass;
    uint32_t color_attachments;
    bool depth_test;
    bool depth_bias;       /* depth bias enabled, set per draw with vkCmdSetDepthBias (a dynamic state) */
    VkCullModeFlags cull;
    const uint32_t *spec;  /* specialization constants (uint32 each, ids 0..n-1) for both stages, or NULL */
    uint32_t spec_count;
    const char *name;
} fv_vk_graphics_desc;

/** An attachment cleared at the start of its render pass and stored at its end, its old contents discarded
 *  (initial layout UNDEFINED), left in final_layout. */
VkAttachmentDescription fv_vk_attachment_cleared(VkFormat format, VkImageLayout final_layout);

/** A triangle-list graphics pipeline with dynamic viewport/scissor, no blending. */
FV_MUST_CHECK fv_result fv_vk_graphics_pipeline(fv_vk *vk, const fv_vk_graphics_desc *desc, VkPipeline *out);

/** A descriptor pool sized for `max_sets` sets with the given type counts. */
FV_MUST_CHECK fv_result fv_vk_descriptor_pool(fv_vk *vk, const VkDescriptorPoolSize *sizes, uint32_t size_count,
                                              uint32_t max_sets, const char *name, VkDescriptorPool *out);
FV_MUST_CHECK fv_result fv_vk_descriptor_set(fv_vk *vk, VkDescriptorPool pool, VkDescriptorSetLayout layout,
                                             const char *name, VkDescriptorSet *out);
/** Write one buffer / image binding of a set. */
void fv_vk_write_buffer(fv_vk *vk, VkDescriptorSet set, uint32_t binding, VkDescriptorType type, VkBuffer buffer,
                        VkDeviceSize offset, VkDeviceSize range);
void fv_vk_write_image(fv_vk *vk, VkDescriptorSet set, uint32_t binding, VkDescriptorType type, VkImageView view,
                       VkSampler sampler, VkImageLayout layout);

/** A compute pass's pipeline objects: its own descriptor set layout (after any shared sets), pipeline layout, one
 *  pipeline per variant (specialization constants), and `set_count` descriptor sets of its own layout. */
typedef struct fv_vk_compute_desc {
    const char *name;                         /* debug name prefix */
    const uint32_t *code;                     /* embedded SPIR-V */
    size_t code_size;
    const VkDescriptorSetLayout *shared_sets; /* sets 0..n-1 (e.g. the scene's set), not owned */
    uint32_t shared_set_count;
    const VkDescriptorSetLayoutBinding *bindings; /* the pass's own set (set number shared_set_count) */
    uint32_t binding_count;
    uint32_t set_count;                       /* descriptor sets of its own layout to allocate (0 = 1) */
    uint32_t push_bytes;                      /* push constant range (compute stage), 0 = none */
    const uint32_t *spec;                     /* variant_count x spec_count uint32 values (constant ids 0..) */
    uint32_t spec_count;
    uint32_t variant_count;                   /* pipelines to build (0 = 1) */
    bool lazy;                                /* build no pipeline at init: with variant_count, each variant is
                                               * made on its first fv_vk_compute_lazy (code, spec and name must
                                               * then outlive the compute: static data); without, the pass makes
                                               * its own (fv_vk_compute_pipeline with c->layout) and binds them
                                               * with fv_vk_compute_bind_pipeline */
} fv_vk_compute_desc;

#define FV_VK_COMPUTE_MAX_VARIANTS 4
#define FV_VK_COMPUTE_MAX_SETS FV_MAX_FRAMES_IN_FLIGHT

typedef struct fv_vk_compute {
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipelines[FV_VK_COMPUTE_MAX_VARIANTS];
    uint32_t variant_count;
    VkDescriptorPool pool;
    VkDescriptorSet sets[FV_VK_COMPUTE_MAX_SETS];
    uint32_t set_count;
    uint32_t own_set;    /* set number of the pass's own set (= shared_set_count) */
    uint32_t push_bytes;
    /* lazy variants (fv_vk_compute_desc.lazy with variant_count): what makes them, and those that failed */
    const uint32_t *code;
    size_t code_size;
    const uint32_t *spec;
    uint32_t spec_count, lazy_variants, lazy_failed;
    const char *name;
} fv_vk_compute;

/** Build everything of a compute pass (c is zeroed first; fv_vk_compute_fini is safe after a failure). */
FV_MUST_CHECK fv_result fv_vk_compute_init(fv_vk *vk, const fv_vk_compute_desc *desc, fv_vk_compute *c);
void fv_vk_compute_fini(fv_vk *vk, fv_vk_compute *c);
/** Bind variant's pipeline, the shared sets (may be NULL when there are none), own set `set_index`, and push
 *  `push` (push_bytes of it; NULL = none). */
void fv_vk_compute_bind(const fv_vk_compute *c, VkCommandBuffer cmd, uint32_t variant, const VkDescriptorSet *shared,
                        uint32_t shared_count, uint32_t set_index, const void *push);
/** A lazy compute's variant, made on its first use (in the command buffer's recording thread, before the bind);
 *  VK_NULL_HANDLE when it cannot be made (said once per variant) or `variant` is out of range. */
VkPipeline fv_vk_compute_lazy(fv_vk *vk, fv_vk_compute *c, uint32_t variant);
/** The same with a pipeline the pass made itself (a lazy variant, compatible with c->layout). */
void fv_vk_compute_bind_pipeline(const fv_vk_compute *c, VkCommandBuffer cmd, VkPipeline pipeline,
                                 const VkDescriptorSet *shared, uint32_t shared_count, uint32_t set_index,
                                 const void *push);

/* ---- per-pass GPU timestamps --------------------------------------------------------------------------------- */

/* Timed ranges per frame: the renderer times each recorded pass once, and asserts this holds FV_MAX_PASSES; one more
 * is refused by fv_vk_timer_begin (-1), which the renderer reports as an error. */
#define FV_VK_TIMER_MAX_PASSES 24
#define FV_VK_TIMER_NAME_MAX 24

/** One query range per frame in flight: 2 timestamps per pass. */
typedef struct fv_vk_timer {
    VkQueryPool pool;
    uint32_t slots;
    bool supported;
    double period_ns;
    uint64_t valid_mask;
    uint32_t pass_count[FV_MAX_FRAMES_IN_FLIGHT];                  /* per slot: passes recorded */
    char names[FV_MAX_FRAMES_IN_FLIGHT][FV_VK_TIMER_MAX_PASSES][FV_VK_TIMER_NAME_MAX];
} fv_vk_timer;

/** slots: frames in flight (<= FV_MAX_FRAMES_IN_FLIGHT). Timestamps unsupported: every call becomes a no-op and collect gives 0 passes. */
FV_MUST_CHECK fv_result fv_vk_timer_init(fv_vk_timer *t, fv_vk *vk, uint32_t slots);
void fv_vk_timer_fini(fv_vk_timer *t, fv_vk *vk);
/** Record a reset of the slot's range (start of the frame's command buffer, outside any render pass). */
void fv_vk_timer_reset(fv_vk_timer *t, VkCommandBuffer cmd, uint32_t slot);
/** Record the start/end timestamp of a pass (outside render passes: multiview would consume extra queries).
 *  begin returns the pass index, or -1 when the slot is full. */
int fv_vk_timer_begin(fv_vk_timer *t, VkCommandBuffer cmd, uint32_t slot, const char *name);
void fv_vk_timer_end(fv_vk_timer *t, VkCommandBuffer cmd, uint32_t slot, int pass);
/** After the slot's fence signalled: per-pass ms and the first-to-last span. Returns the number of passes. */
uint32_t fv_vk_timer_collect(fv_vk_timer *t, fv_vk *vk, uint32_t slot, double *out_ms,
                             char (*out_names)[FV_VK_TIMER_NAME_MAX], uint32_t cap, double *out_total_ms);

#endif
