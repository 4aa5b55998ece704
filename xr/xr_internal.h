/* @brief fovea's OpenXR runtime, internal: the handle objects (instance, session, space, swapchain), the event queue,
 * the compositor, and the entry points each file implements. One mutex per instance serialises every call but
 * xrWaitFrame's sleep and xrWaitSwapchainImage's wait for the compositor; frames are composited off it (the
 * compositor's thread, or in a window the app's thread after xrEndFrame let go of it), so a wait thread paces on the
 * display clock while the previous frame composites. Lock order: instance lock, then the compositor's queue lock
 * (never the other way). XrTime is CLOCK_MONOTONIC in ns (fovea's host clock). */
#ifndef FV_XR_INTERNAL_H
#define FV_XR_INTERNAL_H

#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "fv_openxr.h"
#include "fv_app_run.h"
#include "fv_hmd.h"
#include "fv_log.h"
#include "fovea/fv_display.h"
#include "fovea/fv_frame_input.h"

#if FV_XR_HAVE_INPUT
#include "fv_xr_input.h"
#endif

#define FV_XR_LOG "xr"
#define FV_XR_SYSTEM_ID ((XrSystemId)1)
#define FV_XR_MAX_LAYERS 16        /* composition layers per frame (xrGetSystemProperties maxLayerCount); the spec's
                                    * minimum (XR_MIN_COMPOSITION_LAYERS_SUPPORTED) */
#define FV_XR_MAX_IMAGE_SIZE 4096u /* swapchain width / height (maxSwapchainImageWidth/Height, maxImageRect*) */
#define FV_XR_MAX_ARRAY_SIZE 16u   /* swapchain arraySize */
#define FV_XR_MAX_SAMPLES 1u       /* swapchain sampleCount (maxSwapchainSampleCount) */
#define FV_XR_MAX_CHAIN 64         /* links of a `next` chain the runtime walks (more, or a loop: VALIDATION_FAILURE) */
#define FV_XR_VENDOR_ID 0x10005u   /* XrSystemProperties::vendorId (non-zero): fovea has no vendor id of its own; the
                                    * Khronos-assigned id of Mesa (VK_VENDOR_ID_MESA), the stack it is built on */
#define FV_XR_MAX_SWAPCHAIN_IMAGES 3
#define FV_XR_EVENT_CAP 64
#define FV_XR_MAX_VIEWS 4          /* stereo, or quad views (XR_VARJO_quad_views) */

typedef struct fv_xr_compositor fv_xr_compositor;
typedef struct fv_xr_gaze fv_xr_gaze;
typedef struct fv_xr_budget fv_xr_budget;

enum { FV_XR_MAGIC_INSTANCE = 0x78696e73, FV_XR_MAGIC_SESSION = 0x78736573, FV_XR_MAGIC_SPACE = 0x78737063,
       FV_XR_MAGIC_SWAPCHAIN = 0x78737763 };

/** Which extensions the application enabled. */
typedef struct fv_xr_exts {
    bool vulkan, vulkan2, headless, eye_gaze, quad_views, foveated, local_floor, convert_timespec;
    bool opengl, opengl_es, egl; /* XR_KHR_opengl_enable, XR_KHR_opengl_es_enable, XR_MNDX_egl_enable */
} fv_xr_exts;

struct XrInstance_T {
    uint32_t magic;
    pthread_mutex_t lock;
    char app_name[XR_MAX_APPLICATION_NAME_SIZE];
    XrVersion api_version;
    fv_xr_exts ext;
    fv_hmd_profile hmd;
    float render_scale;        /* FOVEA_XR_SCALE: recommended image size = the HMD's per-eye panel x this */
    fv_app_run run;            /* the description of the session's runs, as `fovea run` has it (runtime/app): the HMD
                                  (FOVEA_XR_HMD, default generic, its field of view applied), the recommended per-eye
                                  image size (run.eye_w/eye_h: the panel x FOVEA_XR_SCALE), the gaze source
                                  (FOVEA_XR_GAZE), the quality (balanced) and the budget (FOVEA_XR_BUDGET, read when
                                  the session is created) */
    bool graphics_requirements_queried;
    struct { bool gl, gles; } gl_requirements_queried; /* xrGetOpenGL(ES)GraphicsRequirementsKHR called */
    fv_xr_compositor *comp;    /* the compositor's device (fovea's fv_vk), created on first graphics call */
    fv_xr_gaze *gaze;          /* FOVEA_XR_GAZE: fovea's gaze pipeline; NULL when no source is open */
    struct XrSession_T *session; /* the one session (a second one: XR_ERROR_LIMIT_REACHED) */
#if FV_XR_HAVE_INPUT
    fv_xr_input *input;
#endif
    /* the event queue (xrPollEvent) */
    XrEventDataBuffer events[FV_XR_EVENT_CAP];
    uint32_t event_head, event_count;
    uint64_t events_dropped;
};

/** Graphics binding of a session. */
typedef struct fv_xr_vk_binding {
    VkInstance instance;
    VkPhysicalDevice phys;
    VkDevice device;
    uint32_t queue_family, queue_index;
    VkQueue queue;
    VkCommandPool pool;
} fv_xr_vk_binding;

/** Frame-timing statistics of a session (FOVEA_XR_STATS writes them). */
typedef struct fv_xr_frame_stats {
    uint64_t waited, begun, ended, discarded, composited, missed;
    double app_ms_ema;         /* xrBeginFrame -> xrEndFrame (the app's frame work as the runtime sees it) */
    double composite_ms_ema;   /* the compositor's CPU wall time per frame (its thread), including the GPU wait */
    double composite_ms_sum, app_gpu_wait_ms_sum; /* over composited frames (means in the statistics); of
                                                    * composite_ms: waiting for the app's queue to finish releases */
    double oversleep_ms_ema;   /* how late xrWaitFrame's sleep wakes (the OS scheduler's share of the pipeline) */
    double overhead_ms_sum;    /* runtime time inside xrWaitFrame (not sleeping), xrBeginFrame, xrEndFrame */
    uint64_t overhead_frames;
    int64_t predicted_minus_photon_ns_max; /* |predicted display time - photon time of the vsync shown| */
    double predicted_error_ms_sum;         /* the same, summed over presented frames (mean = sum / presented) */
    uint64_t presented;
    int64_t gaze_sample_ns;    /* the newest gaze sample when the last xrWaitFrame returned (0: none) */
    double gaze_photon_ms_sum, gaze_photon_ms_max; /* its age at the photons of the vsync that showed the frame */
    uint64_t gaze_photon_frames;
    uint64_t replaced;         /* frames queued for the compositor and replaced by a newer one before it began */
    uint64_t through_lens;     /* of the composited: one pass through the lens (few layers per eye), no lens pass */
    uint32_t pace_k_max;       /* the largest refresh divisor apps were paced at (fv_xr_pace.h) */
    uint64_t paced;            /* frames waited at a divisor above 1 */
    double pace_need_ms;       /* the compositor's time per frame the divisor was last chosen by (ms; 0: none yet) */
} fv_xr_frame_stats;

/** A frame that finished at t_done_ns meant for vsync `target` (predicted photon time predicted_ns): which vsync
 *  shows it on display d, missed, the prediction's error and (gaze_sample_ns > 0) the gaze sample's age at its
 *  photons, added to *st. */
void fv_xr_stats_present(fv_xr_frame_stats *st, fv_display *d, int64_t t_done_ns, uint64_t target, int64_t predicted_ns,
                         int64_t gaze_sample_ns);

struct XrSession_T {
    uint32_t magic;
    struct XrInstance_T *inst;
    bool headless;                 /* XR_MND_headless without a graphics binding: no compositor, no frames shown */
    fv_xr_vk_binding vk;
    struct fv_xr_egl *egl;         /* an OpenGL (ES) app through EGL (xr_egl.c); NULL otherwise */
    XrSessionState state;
    bool running;                  /* between xrBeginSession and xrEndSession */
    bool exit_requested;
    bool loss_pending;
    XrViewConfigurationType view_config;
    uint32_t view_count;
    /* frame loop */
    pthread_mutex_t frame_lock;    /* guards the counters below for xrWaitFrame's wait */
    pthread_cond_t frame_cond;
    uint64_t frames_waited, frames_begun, frames_ended;
    bool frame_open;               /* between xrBeginFrame and xrEndFrame */
    int64_t begin_ns;              /* when the open frame began */
    int64_t wait_return_ns;        /* when the last xrWaitFrame returned: the app's frame starts there */
    fv_display *display;           /* the display clock: the simulated display (headless) */
    uint64_t target_vsync;         /* the vsync the last xrWaitFrame planned for */
    uint32_t pace_k;               /* apps are paced at every pace_k-th refresh (0 or 1: every one; fv_xr_pace.h) */
    uint32_t pace_k_warned;        /* the largest divisor the log has warned of */
    int64_t predicted_ns;          /* its predictedDisplayTime */
    fv_xr_frame_stats stats;
    fv_xr_budget *budget;          /* the frame budget (xr_gaze.c); NULL: FOVEA_XR_BUDGET=off */
    uint32_t visible_after;        /* frames ended before the session becomes VISIBLE/FOCUSED */
    uint64_t exit_after_frames;    /* FOVEA_XR_FRAMES: the runtime ends the session after this many frames (0 = never) */
    uint64_t lose_after_frames;    /* FOVEA_XR_LOSE_DISPLAY_AFTER: the simulated display goes away (0 = never) */
    struct fv_xr_space_list *spaces;
    struct XrSwapchain_T *swapchains;
#if FV_XR_HAVE_INPUT
    fv_xr_input_session *input;
#endif
    bool input_focused_once;
};

typedef enum fv_xr_space_kind { FV_XR_SPACE_REFERENCE = 0, FV_XR_SPACE_ACTION = 1 } fv_xr_space_kind;

struct XrSpace_T {
    uint32_t magic;
    struct XrSession_T *session;
    fv_xr_space_kind kind;
    XrReferenceSpaceType ref_type;
    XrAction action;
    XrPath subaction_path;
    XrPosef offset; /* poseInReferenceSpace / poseInActionSpace */
    struct XrSpace_T *next;
};

typedef struct fv_xr_swapchain_image fv_xr_swapchain_image;

struct XrSwapchain_T {
    uint32_t magic;
    struct XrSession_T *session;
    XrSwapchainCreateInfo info;
    VkFormat format;
    bool depth;
    uint32_t image_count;
    fv_xr_swapchain_image *images;
    struct fv_xr_egl_swapchain *egl; /* an EGL session's GL textures and copy (xr_egl.c) */
    /* acquire / wait / release order (a FIFO of acquired indices) */
    uint32_t next_acquire;
    uint32_t acquired[FV_XR_MAX_SWAPCHAIN_IMAGES];
    uint32_t acquired_count;
    bool waited;                 /* the oldest acquired image was waited on */
    int32_t last_released;       /* -1 before the first release */
    bool static_used;            /* XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT: acquired once already */
    struct XrSwapchain_T *next;
};

/* ---- handles and errors ---------------------------------------------------------------------------------------- */
void fv_xr_handle_add(void *h);
void fv_xr_handle_remove(void *h);
bool fv_xr_handle_live(const void *h, uint32_t magic);
XrInstance fv_xr_instance_check(XrInstance instance);
XrSession fv_xr_session_check(XrSession session);
int64_t fv_xr_now_ns(void);
/** The one walker of `next` chains (input and output): the first struct of `type` in the chain from `next` (NULL:
 *  none; type XR_TYPE_UNKNOWN only checks the chain), the whole chain walked and bounded: a loop or more than
 *  FV_XR_MAX_CHAIN links is XR_ERROR_VALIDATION_FAILURE (logged, naming `what`). Structures of unknown types are
 *  skipped (the spec: a runtime ignores what it does not recognise). */
XrResult fv_xr_chain_find(const void *next, XrStructureType type, const char *what, const void **out);
/** fv_xr_chain_find(next, XR_TYPE_UNKNOWN, ...): the chain is walkable. */
XrResult fv_xr_chain_check(const void *next, const char *what);
/** Queue an event (the oldest is dropped and counted when the queue is full). Instance lock held. */
void fv_xr_event_push(struct XrInstance_T *inst, const void *event, size_t size);
/** Set a session's state and queue XrEventDataSessionStateChanged. Instance lock held. */
void fv_xr_session_set_state(struct XrSession_T *s, XrSessionState state);
bool fv_xr_pose_valid(const XrPosef *p);

/* ---- entry points, per file -------------------------------------------------------------------------------------- */
#define FV_XR_DECL(name) XRAPI_ATTR XrResult XRAPI_CALL fv_##name
/* xr_instance.c */
FV_XR_DECL(xrEnumerateInstanceExtensionProperties)(const char *layer, uint32_t cap, uint32_t *count,
                                                   XrExtensionProperties *props);
FV_XR_DECL(xrEnumerateApiLayerProperties)(uint32_t cap, uint32_t *count, XrApiLayerProperties *props);
FV_XR_DECL(xrCreateInstance)(const XrInstanceCreateInfo *info, XrInstance *out);
FV_XR_DECL(xrDestroyInstance)(XrInstance instance);
FV_XR_DECL(xrGetInstanceProperties)(XrInstance instance, XrInstanceProperties *props);
FV_XR_DECL(xrPollEvent)(XrInstance instance, XrEventDataBuffer *event);
FV_XR_DECL(xrResultToString)(XrInstance instance, XrResult value, char buffer[XR_MAX_RESULT_STRING_SIZE]);
FV_XR_DECL(xrStructureTypeToString)(XrInstance instance, XrStructureType value,
                                    char buffer[XR_MAX_STRUCTURE_NAME_SIZE]);
FV_XR_DECL(xrGetSystem)(XrInstance instance, const XrSystemGetInfo *info, XrSystemId *out);
FV_XR_DECL(xrGetSystemProperties)(XrInstance instance, XrSystemId system, XrSystemProperties *props);
FV_XR_DECL(xrEnumerateEnvironmentBlendModes)(XrInstance instance, XrSystemId system, XrViewConfigurationType type,
                                             uint32_t cap, uint32_t *count, XrEnvironmentBlendMode *modes);
FV_XR_DECL(xrEnumerateViewConfigurations)(XrInstance instance, XrSystemId system, uint32_t cap, uint32_t *count,
                                          XrViewConfigurationType *types);
FV_XR_DECL(xrGetViewConfigurationProperties)(XrInstance instance, XrSystemId system, XrViewConfigurationType type,
                                             XrViewConfigurationProperties *props);
FV_XR_DECL(xrEnumerateViewConfigurationViews)(XrInstance instance, XrSystemId system, XrViewConfigurationType type,
                                              uint32_t cap, uint32_t *count, XrViewConfigurationView *views);
FV_XR_DECL(xrConvertTimespecTimeToTimeKHR)(XrInstance instance, const struct timespec *ts, XrTime *out);
FV_XR_DECL(xrConvertTimeToTimespecTimeKHR)(XrInstance instance, XrTime t, struct timespec *out);
/** Check a system id and view configuration type (XR_ERROR_SYSTEM_INVALID, XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED). */
XrResult fv_xr_check_view_config(struct XrInstance_T *inst, XrViewConfigurationType type, uint32_t *out_views);

/* xr_session.c */
FV_XR_DECL(xrCreateSession)(XrInstance instance, const XrSessionCreateInfo *info, XrSession *out);
FV_XR_DECL(xrDestroySession)(XrSession session);
FV_XR_DECL(xrBeginSession)(XrSession session, const XrSessionBeginInfo *info);
FV_XR_DECL(xrEndSession)(XrSession session);
FV_XR_DECL(xrRequestExitSession)(XrSession session);
FV_XR_DECL(xrWaitFrame)(XrSession session, const XrFrameWaitInfo *info, XrFrameState *state);
FV_XR_DECL(xrBeginFrame)(XrSession session, const XrFrameBeginInfo *info);
FV_XR_DECL(xrEndFrame)(XrSession session, const XrFrameEndInfo *info);

/* xr_space.c */
FV_XR_DECL(xrEnumerateReferenceSpaces)(XrSession session, uint32_t cap, uint32_t *count, XrReferenceSpaceType *types);
FV_XR_DECL(xrCreateReferenceSpace)(XrSession session, const XrReferenceSpaceCreateInfo *info, XrSpace *out);
FV_XR_DECL(xrGetReferenceSpaceBoundsRect)(XrSession session, XrReferenceSpaceType type, XrExtent2Df *bounds);
FV_XR_DECL(xrCreateActionSpace)(XrSession session, const XrActionSpaceCreateInfo *info, XrSpace *out);
FV_XR_DECL(xrLocateSpace)(XrSpace space, XrSpace base, XrTime time, XrSpaceLocation *location);
FV_XR_DECL(xrDestroySpace)(XrSpace space);
FV_XR_DECL(xrLocateViews)(XrSession session, const XrViewLocateInfo *info, XrViewState *state, uint32_t cap,
                          uint32_t *count, XrView *views);
void fv_xr_spaces_destroy_all(struct XrSession_T *s);
/** The pose of a space in the session's LOCAL space at time t (head, gaze or reference); flags as in
 *  XrSpaceLocation. */
XrSpaceLocationFlags fv_xr_space_pose(struct XrSpace_T *sp, XrTime t, XrPosef *out, bool *out_on_head);
/** Space a located in space b at time t; flags of the relation (the head's own tracking only where one end rides on
 *  the head and the other does not). */
XrSpaceLocationFlags fv_xr_space_relate(struct XrSpace_T *a, struct XrSpace_T *b, XrTime t, XrPosef *out_a_in_b);
/** The head (VIEW space) in LOCAL at time t. */
void fv_xr_head_pose(struct XrInstance_T *inst, XrTime t, XrPosef *out);

/* xr_swapchain.c */
FV_XR_DECL(xrEnumerateSwapchainFormats)(XrSession session, uint32_t cap, uint32_t *count, int64_t *formats);
FV_XR_DECL(xrCreateSwapchain)(XrSession session, const XrSwapchainCreateInfo *info, XrSwapchain *out);
FV_XR_DECL(xrDestroySwapchain)(XrSwapchain swapchain);
FV_XR_DECL(xrEnumerateSwapchainImages)(XrSwapchain swapchain, uint32_t cap, uint32_t *count,
                                       XrSwapchainImageBaseHeader *images);
FV_XR_DECL(xrAcquireSwapchainImage)(XrSwapchain swapchain, const XrSwapchainImageAcquireInfo *info, uint32_t *index);
FV_XR_DECL(xrWaitSwapchainImage)(XrSwapchain swapchain, const XrSwapchainImageWaitInfo *info);
FV_XR_DECL(xrReleaseSwapchainImage)(XrSwapchain swapchain, const XrSwapchainImageReleaseInfo *info);
XrSwapchain fv_xr_swapchain_check(XrSwapchain sc);
void fv_xr_swapchains_destroy_all(struct XrSession_T *s);

/* xr_vulkan.c */
FV_XR_DECL(xrGetVulkanInstanceExtensionsKHR)(XrInstance instance, XrSystemId system, uint32_t cap, uint32_t *count,
                                             char *buffer);
FV_XR_DECL(xrGetVulkanDeviceExtensionsKHR)(XrInstance instance, XrSystemId system, uint32_t cap, uint32_t *count,
                                           char *buffer);
FV_XR_DECL(xrGetVulkanGraphicsDeviceKHR)(XrInstance instance, XrSystemId system, VkInstance vk_instance,
                                         VkPhysicalDevice *out);
FV_XR_DECL(xrGetVulkanGraphicsRequirementsKHR)(XrInstance instance, XrSystemId system,
                                               XrGraphicsRequirementsVulkanKHR *req);
FV_XR_DECL(xrCreateVulkanInstanceKHR)(XrInstance instance, const XrVulkanInstanceCreateInfoKHR *info,
                                      VkInstance *out, VkResult *out_result);
FV_XR_DECL(xrCreateVulkanDeviceKHR)(XrInstance instance, const XrVulkanDeviceCreateInfoKHR *info, VkDevice *out,
                                    VkResult *out_result);
FV_XR_DECL(xrGetVulkanGraphicsDevice2KHR)(XrInstance instance, const XrVulkanGraphicsDeviceGetInfoKHR *info,
                                          VkPhysicalDevice *out);

/* xr_input_entry.c: the action system's entry points (xr/input behind fv_xr_input.h) */
PFN_xrVoidFunction fv_xr_input_proc(const char *name);
XrResult fv_xr_input_instance_init(struct XrInstance_T *inst);
void fv_xr_input_instance_fini(struct XrInstance_T *inst);
XrResult fv_xr_input_session_init(struct XrSession_T *s);
void fv_xr_input_session_fini(struct XrSession_T *s);
/** The session became FOCUSED (or the devices changed): update profiles, queue the profile-changed event. */
void fv_xr_input_focus(struct XrSession_T *s);
/** What the action space's action is bound to now (FV_XR_POSE_NONE = 0 when unbound or no input library). */
int fv_xr_input_space_source(struct XrSpace_T *sp);
XrResult fv_xr_input_check_space(struct XrSession_T *s, const XrActionSpaceCreateInfo *info);

/* xr_compositor.c: fovea's fv_vk device, images shared with the app, compositing into the presenter */
fv_result fv_xr_compositor_create(struct XrInstance_T *inst, fv_xr_compositor **out);
void fv_xr_compositor_destroy(fv_xr_compositor **c);
VkPhysicalDevice fv_xr_compositor_phys(const fv_xr_compositor *c);
void fv_xr_compositor_device_uuid(const fv_xr_compositor *c, uint8_t out_uuid[VK_UUID_SIZE]);
uint32_t fv_xr_compositor_api_version(const fv_xr_compositor *c);
/** Where the frames are shown (xr_present.h: a window or headless); NULL without a compositor. */
struct fv_xr_present *fv_xr_compositor_present(fv_xr_compositor *c);
/** Whether an app's physical device (of any instance on the same loader) is the compositor's (device UUID). */
bool fv_xr_compositor_same_device(const fv_xr_compositor *c, VkPhysicalDevice phys);
/** Formats the compositor can sample (colour) or hold (depth) and share with the app, preferred first. */
bool fv_xr_format_is_depth(int64_t vk_format);
uint32_t fv_xr_compositor_formats(fv_xr_compositor *c, int64_t *out, uint32_t cap);
/** Start presenting for a session (the output target and the images, sized per eye). */
fv_result fv_xr_compositor_session_begin(fv_xr_compositor *c, uint32_t width, uint32_t height);
void fv_xr_compositor_session_end(fv_xr_compositor *c);
/** Swapchain images: created on fovea's device with exportable memory and imported into the app's device. */
XrResult fv_xr_swapchain_images_create(fv_xr_compositor *c, struct XrSwapchain_T *sc);
void fv_xr_swapchain_images_destroy(fv_xr_compositor *c, struct XrSwapchain_T *sc);
VkImage fv_xr_swapchain_app_image(struct XrSwapchain_T *sc, uint32_t index);
/** The compositor's image of a swapchain image, and the compositor's device (the EGL copy writes them). */
VkImage fv_xr_swapchain_comp_image(struct XrSwapchain_T *sc, uint32_t index);
struct fv_vk *fv_xr_compositor_vk(fv_xr_compositor *c);
/** An opaque fd of the compositor's image's (dedicated) memory and its size; -1 for none. The caller owns the fd. */
int fv_xr_swapchain_export_fd(fv_xr_compositor *c, struct XrSwapchain_T *sc, uint32_t index, uint64_t *out_size);
/** App-side hand-overs on the app's queue: acquire (the image comes back to the app in its layout) and release
 *  (to the compositor, signalling the image's fence). */
XrResult fv_xr_swapchain_image_acquire(fv_xr_compositor *c, struct XrSwapchain_T *sc, uint32_t index);
XrResult fv_xr_swapchain_image_release(fv_xr_compositor *c, struct XrSwapchain_T *sc, uint32_t index);
XrResult fv_xr_swapchain_image_wait(fv_xr_compositor *c, struct XrSwapchain_T *sc, uint32_t index, XrDuration timeout);
/** Hand one frame's layers (already validated) to the compositor: the layers are mapped for the head at
 *  info->displayTime now (instance lock held: spaces, poses), the released images they read are held for the
 *  compositor (xrWaitSwapchainImage waits for them, fv_xr_compositor_image_idle) and the frame is queued. Without a
 *  window a compositor thread composites it while the app goes on; a frame still queued when the next one comes is
 *  replaced (counted). In a window (GLFW's thread rule) the caller composites it on its own thread with
 *  fv_xr_compositor_run_pending once it has let go of the instance lock. The frame's presentation statistics are
 *  measured against the session's display clock, planned vsync and prediction as they are now. */
void fv_xr_compositor_submit(fv_xr_compositor *c, struct XrSession_T *s, const XrFrameEndInfo *info);
/** Whether frames are composited on the caller's thread (a window): then call fv_xr_compositor_run_pending. */
bool fv_xr_compositor_inline(const fv_xr_compositor *c);
/** Composite the queued frame on this thread (a window); the instance lock must NOT be held. */
void fv_xr_compositor_run_pending(fv_xr_compositor *c);
/** Wait until every queued frame is composited (before images go, the session ends, statistics are read). */
void fv_xr_compositor_drain(fv_xr_compositor *c);
/** xrWaitFrame's back-pressure: wait (up to 5 s) until the compositor has begun the frame queued last, so an app
 *  faster than the compositor is paced by it instead of having its frames replaced. No lock held by the caller. */
void fv_xr_compositor_wait_queue_free(fv_xr_compositor *c);
/** Wait (up to timeout_ns; < 0: the compositor's own 5 s) until no queued or running frame reads this image:
 *  false on timeout. Never holds the instance lock's callers' other locks. */
bool fv_xr_compositor_image_idle(fv_xr_compositor *c, struct XrSwapchain_T *sc, uint32_t index, int64_t timeout_ns);
/** Take what the compositor did since the last call: composited frames, their CPU time and presentation
 *  (composited, replaced, composite_ms_sum, app_gpu_wait_ms_sum and the presentation fields of fv_xr_frame_stats,
 *  added to *acc), the compositor's CPU time per frame (EMA, ms), the time a frame needs of it for pacing
 *  (fv_xr_pace_window_need over its own time, without the wait for the app's releases and a window's acquire and
 *  present; -1 while unknown) and the
 *  first failure (FV_OK: none). */
fv_result fv_xr_compositor_take(fv_xr_compositor *c, fv_xr_frame_stats *acc, double *out_cpu_ms_ema,
                                double *out_need_ms);
/** A frame with nothing to composite: it cost the compositor nothing (a 0 in the pacing window). */
void fv_xr_compositor_pace_idle(fv_xr_compositor *c);
/** The compositor's Vulkan device's command pool and queue are shared by the compositor thread and the EGL
 *  hand-overs: hold this around any other use of them. */
void fv_xr_compositor_gpu_lock(fv_xr_compositor *c);
void fv_xr_compositor_gpu_unlock(fv_xr_compositor *c);
/** Write the last composited frame (FOVEA_XR_OUT) and the statistics. */
void fv_xr_compositor_flush(fv_xr_compositor *c);
uint32_t fv_xr_compositor_validation_messages(const fv_xr_compositor *c);
/** Mean GPU time per composited frame of the compose pass and of the distortion pass (0 without timestamps). */
void fv_xr_compositor_gpu_ms(const fv_xr_compositor *c, double *out_compose_ms, double *out_distort_ms);

/* xr_egl.c: OpenGL / OpenGL ES apps through EGL (XR_MNDX_egl_enable), images copied to the compositor */
FV_XR_DECL(xrGetOpenGLGraphicsRequirementsKHR)(XrInstance instance, XrSystemId system,
                                               XrGraphicsRequirementsOpenGLKHR *req);
FV_XR_DECL(xrGetOpenGLESGraphicsRequirementsKHR)(XrInstance instance, XrSystemId system,
                                                 XrGraphicsRequirementsOpenGLESKHR *req);
/** Check an XrGraphicsBindingEGLMNDX (display, config, context, client API and version, the extensions and the
 *  requirements call); instance lock held. */
XrResult fv_xr_egl_session_create(struct XrInstance_T *inst, const void *binding, struct fv_xr_egl **out);
void fv_xr_egl_session_destroy(struct fv_xr_egl **e);
/** GL internal formats an EGL session's swapchains may have (the compositor's formats they map to), preferred first. */
uint32_t fv_xr_egl_formats(fv_xr_compositor *c, int64_t *out, uint32_t cap);
/** The compositor's format a GL internal format is copied into (VK_FORMAT_UNDEFINED: not one of fovea's). */
VkFormat fv_xr_egl_format_vk(int64_t gl_format);
XrResult fv_xr_egl_swapchain_create(struct XrSession_T *s, struct XrSwapchain_T *sc);
void fv_xr_egl_swapchain_destroy(struct XrSession_T *s, struct XrSwapchain_T *sc);
/** XrSwapchainImageOpenGLKHR / XrSwapchainImageOpenGLESKHR: the GL texture names. */
XrResult fv_xr_egl_enumerate_images(struct XrSwapchain_T *sc, XrSwapchainImageBaseHeader *images);
/** Hand the released image to the compositor: its texels copied into the compositor's image, or (shared memory)
 *  the app's GL work finished and the image acquired by fovea's queue; done when it returns. */
XrResult fv_xr_egl_release(struct XrSwapchain_T *sc, uint32_t index);
/** The image back to the app (shared memory: released by fovea's queue to the external GL side). */
XrResult fv_xr_egl_acquire(struct XrSwapchain_T *sc, uint32_t index);

/* xr_gaze.c: fovea's gaze pipeline from FOVEA_XR_GAZE */
fv_result fv_xr_gaze_create(const char *uri, fv_xr_gaze **out);
void fv_xr_gaze_destroy(fv_xr_gaze **g);
/** Feed the pipeline with what the source has now (any thread; locks itself). */
void fv_xr_gaze_update(fv_xr_gaze *g);
/** The head pose the gaze source's tracker recorded (samples with a head), relative to its first: orientation
 *  (x, y, z, w) and position (m) in LOCAL; false while none came (the head then stays where it started). */
bool fv_xr_gaze_head(fv_xr_gaze *g, float out_q[4], float out_p_m[3]);
/** The predicted combined gaze at t (ns, host clock), in the head frame: origin (m) and unit direction; false when
 *  not tracked (blink, lost, no samples yet). */
bool fv_xr_gaze_predict(fv_xr_gaze *g, int64_t t_ns, float out_origin_m[3], float out_dir[3]);
bool fv_xr_gaze_present(fv_xr_gaze *g);
/** The host time of the newest sample the pipeline has (after taking what the source has now); 0 when none. */
int64_t fv_xr_gaze_newest_sample_ns(fv_xr_gaze *g);
/** Whether the gaze is tracked at t (not counted in the statistics: the runtime's own question). */
bool fv_xr_gaze_tracked(fv_xr_gaze *g, int64_t t_ns);
/** The prediction horizons the app asked for while tracked: requested time minus the newest sample's host time (the
 *  gaze-to-photon latency when the app asks for its frame's predicted display time). */
typedef struct fv_xr_gaze_stats {
    uint64_t count;
    double sum_ms, max_ms;
} fv_xr_gaze_stats;
void fv_xr_gaze_get_stats(fv_xr_gaze *g, fv_xr_gaze_stats *out);
/* xr_gaze.c: the session's frame budget (runtime/app's fv_app_budget over foveation's knobs, from the run's quality;
 * FOVEA_XR_BUDGET=off, auto (default) or a period scale, read into run->budget and run->budget_scale here). NULL when
 * off; every call accepts NULL. Instance lock held. */
fv_xr_budget *fv_xr_budget_create(fv_app_run *run, double refresh_hz);
void fv_xr_budget_destroy(fv_xr_budget **b);
/** One ended frame's time (ms: the app's frame and the composite). */
void fv_xr_budget_frame(fv_xr_budget *b, double frame_ms);
/** The quality at the budget's level (fv_quality_default() without a budget). */
void fv_xr_budget_quality(const fv_xr_budget *b, fv_quality *out);
void fv_xr_budget_write_stats(const fv_xr_budget *b, FILE *f);
/** fv_xr_gaze_predict, and the pipeline's uncertainty radius of that prediction (deg, finite). */
bool fv_xr_gaze_predict_uncertainty(fv_xr_gaze *g, int64_t t_ns, float out_origin_m[3], float out_dir[3],
                                    float *out_uncertainty_deg);

/* xr_quad.c: quad views (XR_VARJO_quad_views) and gaze-driven insets (XR_VARJO_foveated_rendering) */
/** The inset's angular radius (deg) from fovea's MAR model for a gaze uncertainty (deg). */
double fv_xr_quad_inset_radius_deg(const struct XrInstance_T *inst, double uncertainty_deg);
/** Recommended image size of quad view `view` (0, 1 wide; 2, 3 insets); foveated: XrFoveatedViewConfigurationViewVARJO
 *  asked for the foveated sizes. */
void fv_xr_quad_view_size(const struct XrInstance_T *inst, uint32_t view, bool foveated, uint32_t *out_w,
                          uint32_t *out_h);
/** xrLocateViews of the quad configuration: views 0 and 1 located by the caller; sets the insets (2, 3), on the
 *  gaze predicted to info->displayTime when XrViewLocateFoveatedRenderingVARJO asks for it. Instance lock held.
 *  Returns whether the insets follow a tracked gaze. */
bool fv_xr_quad_locate(struct XrSession_T *s, const XrViewLocateInfo *info, XrView *views);
/** The compositor's blend band at an inset's edge, in the inset's normalised image coordinates (u, v). */
void fv_xr_quad_blend_band(const XrFovf *fov, float *out_band_u, float *out_band_v);

#endif
