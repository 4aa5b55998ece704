/* @brief What the compositor's files share (xr/xr_compositor.c: the device, the session's output, the frame queue
 * and its thread; xr/xr_swapchain_images.c: swapchain images on fovea's device, shared with the app's, and their
 * hand-overs): the compositor object, a swapchain image's state, a queued frame. Only those two files include it. */
#ifndef FV_XR_COMPOSITOR_INTERNAL_H
#define FV_XR_COMPOSITOR_INTERNAL_H

#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>

#include "compose_interface.h"
#include "fv_images.h"
#include "fv_pass.h"
#include "fv_post_chain.h"
#include "fv_target.h"
#include "fv_vk.h"
#include "fv_xr_pace.h"
#include "xr_internal.h"
#include "xr_present.h"

#define FV_XR_FENCE_TIMEOUT_NS 5000000000ull /* an app queue that does not finish a release in 5 s is hung */

/* Where an image is: the app holds it, or a release to VK_QUEUE_FAMILY_EXTERNAL is in flight (by either side). */
typedef enum image_owner { OWNER_UNINIT = 0, OWNER_APP, OWNER_EXTERNAL, OWNER_COMP } image_owner;

struct fv_xr_swapchain_image {
    VkImage comp_image;          /* fovea's device */
    VkDeviceMemory comp_mem;
    VkImageView comp_view;       /* 2D array view of every layer, sampled by the compose pass */
    VkImage app_image;           /* the app's device: same memory */
    VkDeviceMemory app_mem;
    VkCommandBuffer app_cmd;     /* hand-over commands on the app's queue */
    VkFence app_fence;           /* signalled when the last hand-over on the app's queue finished */
    image_owner owner;
    VkImageLayout ext_old, ext_new; /* the layouts of the release in flight (OWNER_EXTERNAL) */
    VkImageLayout layout;        /* the current layout on the owning side */
    uint32_t comp_refs;          /* queued or running frames that read it (c->mu): the app may not take it back */
};

typedef struct source_ref {
    struct XrSwapchain_T *sc;
    uint32_t index;
} source_ref;

/* One frame for the compositor: the layers mapped onto the display eyes (xrEndFrame, instance lock held), the
 * released images they read, and what its presentation is measured against. */
typedef struct comp_job {
    fv_xr_compose_block blk;
    bool through_lens;           /* compose.comp's LENS variant (few layers per eye, the lens on) */
    source_ref src[FV_XR_COMPOSE_MAX_SOURCES]; /* every image the frame reads */
    uint32_t nsrc;
    uint8_t eye_src[2][FV_XR_COMPOSE_MAX_SOURCES]; /* eye e's binding array: indices into src (a layer's info.x is
                                                    * its eye's slot) */
    uint32_t eye_nsrc[2];
    uint8_t lens_src[2][FV_XR_COMPOSE_LENS_MAX_LAYERS]; /* through the lens: eye e's layer i reads src[lens_src[e][i]]
                                                         * (bound as source i: a constant index per layer) */
    VkDevice app_device;         /* the app's fences of the releases */
    XrTime display_time;
    fv_display *display;
    uint64_t target_vsync;
    int64_t predicted_ns, gaze_sample_ns;
} comp_job;

struct fv_xr_compositor {
    fv_vk *vk;
    PFN_vkGetMemoryFdKHR get_memory_fd;
    uint8_t uuid[VK_UUID_SIZE];
    /* the output of a session */
    bool active;
    uint32_t width, height;
    fv_images images;
    bool images_ready;
    fv_post_chain *post;         /* the renderer's post chain: lens pre-distortion of the display image */
    fv_target *target;
    fv_xr_present *present;      /* a window when there is a display (xr_present.h), else headless */
    char out_dir[1024];
    fv_vk_compute cs;            /* the compose pass's layout and sets (one per eye: its sources); its pipelines are
                                  * made per source count */
    VkPipeline compose[2][FV_XR_COMPOSE_MAX_SOURCES]; /* [lens][n - 1]: specialised for n sources and through the lens
                                                       * or not (compose.comp's NSRC, LENS) */
    bool lens_in_compose;        /* the post chain's one pass is the lens: frames of few layers per eye go through the
                                  * lens in the compose pass, the chain is not recorded for them */
    VkSampler sampler;
    fv_vk_buffer block;          /* fv_xr_compose_block, host-visible */
    VkCommandBuffer cmd;
    VkFence fence;
    VkSemaphore sem_ready, sem_done; /* the target hand-over semaphores (unused by headless and files targets) */
    fv_frame_input input;        /* eye frusta and the lens for the distortion pass */
    uint64_t frame_id;
    fv_vk_timer timer;           /* GPU time of the compose and distortion passes */
    bool timer_ready;
    double gpu_ms_sum[2];        /* compose, distort: summed over frames */
    uint64_t gpu_frames;
    /* the frame queue: xrEndFrame queues (submit), the compositor thread (or, in a window, the app's thread) runs */
    pthread_mutex_t mu;          /* the queue, images' comp_refs, the results; never held with the instance lock
                                  * taken after it (the instance lock may be held when taking it) */
    pthread_cond_t cv;           /* CLOCK_MONOTONIC */
    pthread_mutex_t gpu_mu;      /* the device's command pool and queue (the thread's frame, EGL's hand-overs) */
    pthread_t thread;
    bool threaded, stop;
    bool has_pending, busy;      /* a frame queued; a frame being composited */
    comp_job pending, running;
    fv_xr_frame_stats acc;       /* results since the last fv_xr_compositor_take */
    fv_result error;             /* the first failure since then */
    double cpu_ms_ema;
    uint64_t cpu_frames;
    fv_xr_pace_window pace;      /* the compositor's own time of its last frames (fv_xr_pace.h) */
};

/** An image barrier on a swapchain image (its aspect from the swapchain's format), for the hand-overs between the
 * app's queue family, VK_QUEUE_FAMILY_EXTERNAL and the compositor's. */
VkImageMemoryBarrier fv_xr_image_barrier(const struct XrSwapchain_T *sc, VkImage image, VkImageLayout from,
                                         VkImageLayout to, uint32_t src_family, uint32_t dst_family, VkAccessFlags src,
                                         VkAccessFlags dst);

#endif
