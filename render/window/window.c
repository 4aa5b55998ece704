/* @brief The window presenter: GLFW window, Vulkan surface and swapchain, the side-by-side copy, presents and the
 * swapchain clock's evidence (see fv_window.h). */
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "fv_window.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_clock.h"
#include "fv_log.h"
#include "fv_present_clock.h"

#define MOD "window"
#define MAX_IMAGES 8
#define KEY_QUEUE 32
#define ACQUIRE_TIMEOUT_NS 250000000ull /* per try; the window's events are handled between tries */
#define ACQUIRE_TRIES 40                /* 10 s without an image is an error */
#define WAITED_NS 300000                /* an acquire that blocked this long was released by a flip (a vsync) */

struct fv_window {
    fv_target target; /* first member: fv_target * <-> fv_window * */
    fv_window_desc desc;
    GLFWwindow *glfw;
    fv_vk *vk; /* the renderer's device, from the first frame until detach */
    VkSwapchainKHR swapchain;
    VkFormat format;
    VkExtent2D extent;
    uint32_t made_for_w, made_for_h; /* the framebuffer size the swapchain was made for (its extent may be clamped) */
    VkPresentModeKHR vk_mode;
    uint32_t image_count;
    VkImage images[MAX_IMAGES];
    bool need_recreate;
    bool frame_shown;     /* this frame acquired an image (begin) and presents it (end) */
    uint32_t image_index;
    VkOffset3D eye_rect[2][2]; /* per eye: the blit's destination corners */
    bool close_requested;
    int keys[KEY_QUEUE];
    uint32_t key_head, key_tail;
    fv_present_clock clock;
    bool display_timing; /* the device has VK_GOOGLE_display_timing enabled */
    bool clock_ready;
    PFN_vkGetPastPresentationTimingGOOGLE get_past_timing;
    uint32_t present_id;
    fv_window_stats stats;
};

static const char *const g_mode_names[] = {"fifo", "mailbox", "immediate"};

const char *fv_window_present_mode_str(fv_window_present_mode m)
{
    return (unsigned)m < 3 ? g_mode_names[m] : NULL;
}

bool fv_window_present_mode_parse(const char *s, fv_window_present_mode *out)
{
    for (int i = 0; s && i < 3; i++)
        if (strcmp(s, g_mode_names[i]) == 0) {
            *out = (fv_window_present_mode)i;
            return true;
        }
    return false;
}

static VkPresentModeKHR vk_mode_of(fv_window_present_mode m)
{
    return m == FV_WINDOW_MAILBOX ? VK_PRESENT_MODE_MAILBOX_KHR
           : m == FV_WINDOW_IMMEDIATE ? VK_PRESENT_MODE_IMMEDIATE_KHR
                                      : VK_PRESENT_MODE_FIFO_KHR;
}

static const char *vk_mode_str(VkPresentModeKHR m)
{
    switch (m) {
    case VK_PRESENT_MODE_FIFO_KHR: return "fifo";
    case VK_PRESENT_MODE_MAILBOX_KHR: return "mailbox";
    case VK_PRESENT_MODE_IMMEDIATE_KHR: return "immediate";
    case VK_PRESENT_MODE_FIFO_RELAXED_KHR: return "fifo_relaxed";
    default: return "other";
    }
}

/* ---- GLFW events ---------------------------------------------------------------------------------------------- */

static void on_glfw_error(int code, const char *text) { FV_ERROR(MOD, "GLFW error 0x%x: %s", code, text); }

static void on_key(GLFWwindow *gw, int key, int scancode, int action, int mods)
{
    (void)scancode;
    (void)mods;
    fv_window *w = glfwGetWindowUserPointer(gw);
    if (!w || action != GLFW_PRESS) return;
    if (key == GLFW_KEY_ESCAPE) {
        w->close_requested = true;
        return;
    }
    uint32_t next = (w->key_tail + 1) % KEY_QUEUE;
    if (next == w->key_head) return; /* full: the oldest presses win */
    w->keys[w->key_tail] = key;
    w->key_tail = next;
}

static void on_resize(GLFWwindow *gw, int width, int height)
{
    (void)width;
    (void)height;
    fv_window *w = glfwGetWindowUserPointer(gw);
    if (w) w->need_recreate = true;
}

void fv_window_request_close(fv_window *w)
{
    if (w) w->close_requested = true;
}

bool fv_window_poll(fv_window *w)
{
    if (!w) return false;
    glfwPollEvents();
    if (glfwWindowShouldClose(w->glfw)) w->close_requested = true;
    return !w->close_requested;
}

int fv_window_next_key(fv_window *w)
{
    if (!w || w->key_head == w->key_tail) return 0;
    int k = w->keys[w->key_head];
    w->key_head = (w->key_head + 1) % KEY_QUEUE;
    return k;
}

/* Where each eye's image goes in a framebuffer of fw x fh: both eyes side by side at the eye aspect, as large as
 * fits, centred (the rest is black). */
static void layout_eyes(const fv_window *w, uint32_t fw, uint32_t fh, VkOffset3D out[2][2])
{
    double ew = w->desc.eye_width, eh = w->desc.eye_height;
    double s = fmin((double)fw / (2.0 * ew), (double)fh / eh);
    int32_t dw = (int32_t)floor(ew * s), dh = (int32_t)floor(eh * s);
    if (dw < 1) dw = 1;
    if (dh < 1) dh = 1;
    int32_t x0 = ((int32_t)fw - 2 * dw) / 2, y0 = ((int32_t)fh - dh) / 2;
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    for (int e = 0; e < 2; e++) {
        out[e][0] = (VkOffset3D){x0 + e * dw, y0, 0};
        out[e][1] = (VkOffset3D){x0 + (e + 1) * dw, y0 + dh, 1};
    }
}

bool fv_window_cursor(const fv_window *w, int *out_eye, float *out_u, float *out_v)
{
    if (!w || !glfwGetWindowAttrib(w->glfw, GLFW_HOVERED)) return false;
    double cx, cy;
    int ww, wh, fw, fh;
    glfwGetCursorPos(w->glfw, &cx, &cy);
    glfwGetWindowSize(w->glfw, &ww, &wh);
    glfwGetFramebufferSize(w->glfw, &fw, &fh);
    if (ww <= 0 || wh <= 0 || fw <= 0 || fh <= 0 || !isfinite(cx) || !isfinite(cy)) return false;
    double px = cx * fw / ww, py = cy * fh / wh; /* screen coordinates -> framebuffer pixels (HiDPI) */
    VkOffset3D r[2][2];
    layout_eyes(w, (uint32_t)fw, (uint32_t)fh, r);
    for (int e = 0; e < 2; e++) {
        if (px < r[e][0].x || px >= r[e][1].x || py < r[e][0].y || py >= r[e][1].y) continue;
        if (out_eye) *out_eye = e;
        if (out_u) *out_u = (float)((px - r[e][0].x) / (double)(r[e][1].x - r[e][0].x));
        if (out_v) *out_v = (float)((py - r[e][0].y) / (double)(r[e][1].y - r[e][0].y));
        return true;
    }
    return false;
}

void fv_window_set_title(fv_window *w, const char *title)
{
    if (w && title) glfwSetWindowTitle(w->glfw, title);
}

/* ---- swapchain ------------------------------------------------------------------------------------------------ */

static void destroy_swapchain(fv_window *w, VkSwapchainKHR sc)
{
    if (sc && w->vk) vkDestroySwapchainKHR(w->vk->device, sc, NULL);
}

/* A surface format that shows the display image's values as they are: 8-bit UNORM (the image holds sRGB-encoded
 * values already; an _SRGB swapchain would encode them twice) in the sRGB colour space. */
static fv_result pick_format(fv_window *w, VkSurfaceFormatKHR *out)
{
    fv_vk *vk = w->vk;
    uint32_t n = 0;
    FV_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(vk->phys, vk->surface, &n, NULL));
    VkSurfaceFormatKHR f[64];
    if (n > 64) n = 64;
    FV_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(vk->phys, vk->surface, &n, f));
    if (n == 0) {
        FV_ERROR(MOD, "the window's surface offers no formats");
        return FV_ERR_UNSUPPORTED;
    }
    const VkFormat want[] = {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_A8B8G8R8_UNORM_PACK32};
    for (size_t k = 0; k < sizeof want / sizeof want[0]; k++)
        for (uint32_t i = 0; i < n; i++)
            if (f[i].format == want[k] && f[i].colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR &&
                fv_vk_format_supports(vk, f[i].format, VK_FORMAT_FEATURE_BLIT_DST_BIT)) {
                *out = f[i];
                return FV_OK;
            }
    FV_ERROR(MOD, "the window's surface offers no 8-bit UNORM sRGB-space format that can be blitted to (%u formats, "
             "first %d)", n, (int)f[0].format);
    return FV_ERR_UNSUPPORTED;
}

static fv_result create_swapchain(fv_window *w, uint32_t fb_w, uint32_t fb_h)
{
    fv_vk *vk = w->vk;
    VkSurfaceCapabilitiesKHR caps;
    FV_VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(vk->phys, vk->surface, &caps));
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT)) {
        FV_ERROR(MOD, "the window's swapchain images cannot be transfer destinations");
        return FV_ERR_UNSUPPORTED;
    }
    uint32_t n = 0;
    FV_VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(vk->phys, vk->surface, &n, NULL));
    VkPresentModeKHR modes[16];
    if (n > 16) n = 16;
    FV_VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(vk->phys, vk->surface, &n, modes));
    VkPresentModeKHR want = vk_mode_of(w->desc.present_mode);
    bool have = false;
    char list[96] = "";
    for (uint32_t i = 0; i < n; i++) {
        have = have || modes[i] == want;
        size_t used = strlen(list);
        snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", vk_mode_str(modes[i]));
    }
    if (!have) {
        FV_ERROR(MOD, "--present-mode %s: this surface does not support it (it offers: %s)",
                 fv_window_present_mode_str(w->desc.present_mode), list);
        return FV_ERR_UNSUPPORTED;
    }
    VkSurfaceFormatKHR fmt = {0};
    FV_TRY(pick_format(w, &fmt));
    VkExtent2D ext = caps.currentExtent;
    if (ext.width == UINT32_MAX) { /* the surface takes the swapchain's size: the framebuffer's */
        ext.width = fb_w < caps.minImageExtent.width ? caps.minImageExtent.width
                    : fb_w > caps.maxImageExtent.width ? caps.maxImageExtent.width : fb_w;
        ext.height = fb_h < caps.minImageExtent.height ? caps.minImageExtent.height
                     : fb_h > caps.maxImageExtent.height ? caps.maxImageExtent.height : fb_h;
    }
    if (ext.width == 0 || ext.height == 0) return FV_NO_NEW_DATA; /* minimised: nothing to make yet */
    uint32_t count = caps.minImageCount + 1;
    if (caps.maxImageCount && count > caps.maxImageCount) count = caps.maxImageCount;
    if (count > MAX_IMAGES) count = MAX_IMAGES;
    /* A present queue of another family: the images are shared by both families (concurrent), so neither needs an
     * ownership transfer between the copy (graphics family) and the present (present family). */
    uint32_t families[2] = {vk->queue_family, vk->present_family};
    bool shared = vk->present_family != vk->queue_family;
    VkSwapchainCreateInfoKHR ci = {
        .sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR,
        .surface = vk->surface,
        .minImageCount = count,
        .imageFormat = fmt.format,
        .imageColorSpace = fmt.colorSpace,
        .imageExtent = ext,
        .imageArrayLayers = 1,
        .imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT,
        .imageSharingMode = shared ? VK_SHARING_MODE_CONCURRENT : VK_SHARING_MODE_EXCLUSIVE,
        .queueFamilyIndexCount = shared ? 2u : 0u,
        .pQueueFamilyIndices = shared ? families : NULL,
        .preTransform = (caps.supportedTransforms & VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR)
                            ? VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR
                            : caps.currentTransform,
        .compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                              ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                              : (VkCompositeAlphaFlagBitsKHR)(caps.supportedCompositeAlpha &
                                                               (~caps.supportedCompositeAlpha + 1)),
        .presentMode = want,
        .clipped = VK_TRUE,
        .oldSwapchain = w->swapchain,
    };
    VkSwapchainKHR sc = VK_NULL_HANDLE;
    FV_VK_CHECK(vkCreateSwapchainKHR(vk->device, &ci, NULL, &sc));
    destroy_swapchain(w, w->swapchain); /* retired by the new one; the device was idle */
    w->swapchain = sc;
    FV_VK_NAME(vk, VK_OBJECT_TYPE_SWAPCHAIN_KHR, sc, "window swapchain %ux%u", ext.width, ext.height);
    uint32_t ni = 0;
    FV_VK_CHECK(vkGetSwapchainImagesKHR(vk->device, sc, &ni, NULL));
    if (ni > MAX_IMAGES) {
        FV_ERROR(MOD, "the swapchain has %u images; at most %d are handled", ni, MAX_IMAGES);
        return FV_ERR_UNSUPPORTED;
    }
    FV_VK_CHECK(vkGetSwapchainImagesKHR(vk->device, sc, &ni, w->images));
    for (uint32_t i = 0; i < ni; i++) FV_VK_NAME(vk, VK_OBJECT_TYPE_IMAGE, w->images[i], "swapchain image %u", i);
    w->image_count = ni;
    w->format = fmt.format;
    w->extent = ext;
    w->made_for_w = fb_w;
    w->made_for_h = fb_h;
    w->vk_mode = want;
    layout_eyes(w, ext.width, ext.height, w->eye_rect);
    w->need_recreate = false;
    w->stats.swapchain_creations++;
    w->stats.width = ext.width;
    w->stats.height = ext.height;
    w->stats.present_mode = vk_mode_str(want);
    w->stats.separate_present_queue = shared;
    FV_INFO(MOD, "swapchain %ux%u, %u images, %s, format %d%s", ext.width, ext.height, ni, vk_mode_str(want),
            (int)fmt.format, shared ? ", shared with a separate present queue" : "");
    return FV_OK;
}

/* (Re)make the swapchain for the framebuffer's current size. FV_NO_NEW_DATA while minimised (zero size). */
static fv_result ensure_swapchain(fv_window *w)
{
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(w->glfw, &fw, &fh);
    if (fw <= 0 || fh <= 0) return FV_NO_NEW_DATA;
    if (w->swapchain && !w->need_recreate && (uint32_t)fw == w->made_for_w && (uint32_t)fh == w->made_for_h)
        return FV_OK;
    /* Frames in flight may still copy into or present the old images: wait for them first. */
    FV_VK_CHECK(vkDeviceWaitIdle(w->vk->device));
    return create_swapchain(w, (uint32_t)fw, (uint32_t)fh);
}

/* ---- display timing ------------------------------------------------------------------------------------------- */

static double monitor_hz(void)
{
    GLFWmonitor *mon = glfwGetPrimaryMonitor();
    const GLFWvidmode *vm = mon ? glfwGetVideoMode(mon) : NULL;
    return vm && vm->refreshRate > 0 ? (double)vm->refreshRate : 0.0;
}

/* With the first swapchain: where the clock's vsyncs will come from. The clock (and the frame loop reading it)
 * started at the window's creation; its timeline is kept, only its source and nominal rate are learnt here.
 * VK_GOOGLE_display_timing is used when the device was created with it (fv_vk enables only what a device has). */
static void init_clock(fv_window *w)
{
    w->clock_ready = true;
    if (w->display_timing) {
        fv_vk *vk = w->vk;
        PFN_vkGetRefreshCycleDurationGOOGLE get_cycle =
            (PFN_vkGetRefreshCycleDurationGOOGLE)vkGetDeviceProcAddr(vk->device, "vkGetRefreshCycleDurationGOOGLE");
        w->get_past_timing = (PFN_vkGetPastPresentationTimingGOOGLE)vkGetDeviceProcAddr(
            vk->device, "vkGetPastPresentationTimingGOOGLE");
        VkRefreshCycleDurationGOOGLE cycle = {0};
        if (get_cycle && w->get_past_timing && get_cycle(vk->device, w->swapchain, &cycle) == VK_SUCCESS &&
            cycle.refreshDuration > 0 && cycle.refreshDuration <= 1000000000ull) {
            w->clock.source = FV_PRESENT_CLOCK_DISPLAY_TIMING;
            w->clock.nominal_period_ns = (int64_t)cycle.refreshDuration;
        } else {
            w->display_timing = false;
        }
    }
    FV_INFO(MOD, "display clock: %s, %.2f Hz %s", fv_present_clock_source_str(w->clock.source),
            w->clock.base.refresh_hz,
            w->clock.nominal_period_ns ? "(from the display)" : "(assumed until the presents show their cadence)");
}

/* VK_GOOGLE_display_timing: the actual present times of earlier frames are vsyncs on CLOCK_MONOTONIC. */
static void take_past_timing(fv_window *w)
{
    if (!w->display_timing || !w->get_past_timing) return;
    VkPastPresentationTimingGOOGLE t[8];
    uint32_t n = 8;
    if (w->get_past_timing(w->vk->device, w->swapchain, &n, t) < 0) return;
    for (uint32_t i = 0; i < n; i++)
        if (t[i].actualPresentTime > 0) fv_present_clock_vsync(&w->clock, (int64_t)t[i].actualPresentTime);
}

/* ---- the target ------------------------------------------------------------------------------------------------ */

static fv_result create_surface(VkInstance instance, void *user, VkSurfaceKHR *out)
{
    fv_window *w = user;
    VkResult r = glfwCreateWindowSurface(instance, w->glfw, NULL, out);
    if (r != VK_SUCCESS) return fv_vk_fail(r, "glfwCreateWindowSurface", __FILE__, __LINE__);
    return FV_OK;
}

static void window_configure_vk(fv_target *t, fv_vk_desc *d)
{
    fv_window *w = (fv_window *)t;
    uint32_t n = 0;
    const char **exts = glfwGetRequiredInstanceExtensions(&n);
    d->instance_extensions = exts;
    d->instance_extension_count = exts ? n : 0;
    d->create_surface = create_surface;
    d->surface_user = w;
    static const char *const optional[] = {VK_GOOGLE_DISPLAY_TIMING_EXTENSION_NAME};
    d->optional_device_extensions = optional;
    d->optional_device_extension_count = 1;
}

static fv_result window_begin(fv_target *t, const fv_target_frame *f, bool *out_wait, bool *out_signal)
{
    fv_window *w = (fv_window *)t;
    *out_wait = *out_signal = false;
    w->frame_shown = false;
    if (!w->vk) {
        w->vk = f->vk;
        if (!w->vk->surface) {
            FV_ERROR(MOD, "the renderer's device has no surface (the window target was not given to fv_vk_create)");
            return FV_ERR_STATE;
        }
        w->display_timing = fv_vk_optional_enabled(w->vk, VK_GOOGLE_DISPLAY_TIMING_EXTENSION_NAME);
    }
    for (int attempt = 0; attempt < 4; attempt++) {
        fv_result s = ensure_swapchain(w);
        while (s == FV_NO_NEW_DATA) { /* minimised: wait for a size (or a close) */
            if (w->close_requested || glfwWindowShouldClose(w->glfw)) {
                w->close_requested = true;
                w->stats.skipped++;
                return FV_OK;
            }
            glfwWaitEventsTimeout(0.05);
            s = ensure_swapchain(w);
        }
        FV_TRY(s);
        if (!w->clock_ready) init_clock(w);
        for (int tries = 0; tries < ACQUIRE_TRIES; tries++) {
            int64_t t0 = fv_time_monotonic_ns();
            VkResult r = vkAcquireNextImageKHR(w->vk->device, w->swapchain, ACQUIRE_TIMEOUT_NS, f->image_ready,
                                               VK_NULL_HANDLE, &w->image_index);
            int64_t t1 = fv_time_monotonic_ns();
            if (r == VK_TIMEOUT || r == VK_NOT_READY) {
                glfwPollEvents();
                if (glfwWindowShouldClose(w->glfw)) w->close_requested = true;
                if (w->close_requested) {
                    w->stats.skipped++;
                    return FV_OK;
                }
                continue;
            }
            if (r == VK_ERROR_OUT_OF_DATE_KHR) {
                w->stats.out_of_date++;
                w->need_recreate = true;
                break; /* the semaphore was not signalled: make a new swapchain and try again */
            }
            if (r < 0) return fv_vk_fail(r, "vkAcquireNextImageKHR", __FILE__, __LINE__);
            if (r == VK_SUBOPTIMAL_KHR) {
                w->stats.out_of_date++;
                w->need_recreate = true; /* shown this frame, made again before the next */
            }
            FV_DEBUG(MOD, "acquire %u after %.3f ms at %.3f ms", w->image_index, (double)(t1 - t0) / 1e6,
                     (double)(t1 % 1000000000) / 1e6);
            if (w->vk_mode == VK_PRESENT_MODE_FIFO_KHR && !w->display_timing && t1 - t0 >= WAITED_NS)
                fv_present_clock_vsync(&w->clock, t1);
            w->frame_shown = true;
            *out_wait = *out_signal = true;
            return FV_OK;
        }
        if (!w->need_recreate) {
            FV_ERROR(MOD, "the swapchain gave no image for %d s", (int)(ACQUIRE_TRIES * ACQUIRE_TIMEOUT_NS / 1000000000ull));
            return FV_ERR_DEVICE_LOST;
        }
    }
    FV_ERROR(MOD, "the swapchain stayed out of date after being made again 4 times");
    return FV_ERR_VULKAN;
}

static void window_record(fv_target *t, const fv_target_frame *f)
{
    fv_window *w = (fv_window *)t;
    if (!w->frame_shown) return;
    VkCommandBuffer cmd = f->cmd;
    VkImage dst = w->images[w->image_index];
    const fv_vk_image sc = {.image = dst, .aspect = VK_IMAGE_ASPECT_COLOR_BIT, .layers = 1};
    const fv_vk_image_use write = {VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                   VK_ACCESS_TRANSFER_WRITE_BIT};
    fv_vk_label_begin(w->vk, cmd, "window: copy both eyes into the swapchain image");
    /* The acquire's semaphore is waited at the transfer stage: the layout change starts after it (old contents
     * discarded). */
    fv_vk_barrier_image(cmd, &sc, (fv_vk_image_use){VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_TRANSFER_BIT, 0},
                        write);
    VkClearColorValue black = {.float32 = {0.0f, 0.0f, 0.0f, 1.0f}};
    VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &black, 1, &range);
    /* The clear and the blits write the same image: order them (write after write). */
    fv_vk_barrier_image(cmd, &sc, write, write);
    fv_images_use(f->images, cmd, FV_IMAGE_DISPLAY,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                    VK_ACCESS_TRANSFER_READ_BIT});
    const fv_vk_image *src = fv_images_image(f->images, FV_IMAGE_DISPLAY);
    for (uint32_t e = 0; e < 2 && src; e++) {
        VkImageBlit blit = {
            .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, e, 1},
            .srcOffsets = {{0, 0, 0}, {(int32_t)f->width, (int32_t)f->height, 1}},
            .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
            .dstOffsets = {w->eye_rect[e][0], w->eye_rect[e][1]},
        };
        vkCmdBlitImage(cmd, src->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                       1, &blit, VK_FILTER_LINEAR);
    }
    /* Hand the image to the presentation engine; the present waits for the submit's semaphore, which covers these
     * writes (no access on the present side). */
    fv_vk_barrier_image(cmd, &sc, write,
                        (fv_vk_image_use){VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0});
    fv_vk_label_end(w->vk, cmd);
}

static fv_result window_end(fv_target *t, const fv_target_frame *f)
{
    fv_window *w = (fv_window *)t;
    if (!w->frame_shown) return FV_OK;
    w->frame_shown = false;
    VkPresentTimeGOOGLE when = {.presentID = ++w->present_id, .desiredPresentTime = 0};
    VkPresentTimesInfoGOOGLE times = {.sType = VK_STRUCTURE_TYPE_PRESENT_TIMES_INFO_GOOGLE, .swapchainCount = 1,
                                      .pTimes = &when};
    VkPresentInfoKHR pi = {
        .sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR,
        .pNext = w->display_timing ? &times : NULL,
        .waitSemaphoreCount = 1,
        .pWaitSemaphores = &f->frame_done,
        .swapchainCount = 1,
        .pSwapchains = &w->swapchain,
        .pImageIndices = &w->image_index,
    };
    VkResult r = vkQueuePresentKHR(w->vk->present_queue, &pi);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
        w->stats.out_of_date++;
        w->need_recreate = true;
    } else if (r < 0) {
        return fv_vk_fail(r, "vkQueuePresentKHR", __FILE__, __LINE__);
    }
    w->stats.presents++;
    take_past_timing(w);
    return FV_OK;
}

static void window_detach(fv_target *t, fv_vk *vk)
{
    fv_window *w = (fv_window *)t;
    if (!w->vk || w->vk != vk) return;
    vkDeviceWaitIdle(vk->device);
    destroy_swapchain(w, w->swapchain);
    w->swapchain = VK_NULL_HANDLE;
    w->image_count = 0;
    w->vk = NULL;
}

static void window_destroy_target(fv_target *t) { (void)t; /* the window owns its target: fv_window_destroy */ }

static const fv_target_ops g_window_ops = {
    .name = "window",
    .begin = window_begin,
    .record = window_record,
    .end = window_end,
    .destroy = window_destroy_target,
    .configure_vk = window_configure_vk,
    .detach = window_detach,
};

/* ---- create / destroy ------------------------------------------------------------------------------------------ */

fv_result fv_window_create(const fv_window_desc *desc_in, fv_window **out)
{
    if (!out) return FV_ERR_INVALID_ARG;
    *out = NULL;
    fv_window_desc desc = desc_in ? *desc_in : (fv_window_desc){0};
    if (!desc.eye_width || !desc.eye_height) {
        desc.eye_width = 720;
        desc.eye_height = 800;
    }
    if ((desc.width == 0) != (desc.height == 0) || desc.width > 16384 || desc.height > 16384) {
        FV_ERROR(MOD, "window size %ux%u: each must be in 1..16384 (or both 0 for the default)", desc.width,
                 desc.height);
        return FV_ERR_RANGE;
    }
    if (!fv_window_present_mode_str(desc.present_mode)) {
        FV_ERROR(MOD, "unknown present mode %d", (int)desc.present_mode);
        return FV_ERR_INVALID_ARG;
    }
    const char *x11 = getenv("DISPLAY"), *wl = getenv("WAYLAND_DISPLAY");
    if ((!x11 || !*x11) && (!wl || !*wl)) {
        FV_ERROR(MOD, "no display: neither DISPLAY nor WAYLAND_DISPLAY is set (use --present headless, or run under "
                 "a desktop or Xvfb)");
        return FV_ERR_UNSUPPORTED;
    }
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        FV_ERROR(MOD, "GLFW could not start (no usable display at DISPLAY=%s WAYLAND_DISPLAY=%s)", x11 ? x11 : "",
                 wl ? wl : "");
        return FV_ERR_UNSUPPORTED;
    }
    if (!glfwVulkanSupported()) {
        FV_ERROR(MOD, "GLFW finds no Vulkan loader with surface support");
        glfwTerminate();
        return FV_ERR_UNSUPPORTED;
    }
    fv_window *w = calloc(1, sizeof *w);
    if (!w) {
        glfwTerminate();
        return FV_ERR_NO_MEMORY;
    }
    w->target.ops = &g_window_ops;
    w->desc = desc;
    if (!desc.width || desc.fit_to_screen) {
        double ww = desc.width ? desc.width : 2.0 * desc.eye_width, wh = desc.height ? desc.height : desc.eye_height;
        GLFWmonitor *mon = glfwGetPrimaryMonitor();
        const GLFWvidmode *vm = mon ? glfwGetVideoMode(mon) : NULL;
        if (vm && vm->width > 0 && vm->height > 0) {
            double s = fmin(1.0, fmin(0.9 * vm->width / ww, 0.9 * vm->height / wh));
            ww *= s;
            wh *= s;
        }
        w->desc.width = (uint32_t)fmax(1.0, floor(ww));
        w->desc.height = (uint32_t)fmax(1.0, floor(wh));
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    w->glfw = glfwCreateWindow((int)w->desc.width, (int)w->desc.height, desc.title ? desc.title : "fovea", NULL, NULL);
    if (!w->glfw) {
        FV_ERROR(MOD, "the window (%ux%u) could not be created", w->desc.width, w->desc.height);
        free(w);
        glfwTerminate();
        return FV_ERR_UNSUPPORTED;
    }
    glfwSetWindowUserPointer(w->glfw, w);
    glfwSetKeyCallback(w->glfw, on_key);
    glfwSetFramebufferSizeCallback(w->glfw, on_resize);
    fv_present_clock_init(&w->clock, FV_PRESENT_CLOCK_CADENCE, monitor_hz(), fv_time_monotonic_ns());
    *out = w;
    return FV_OK;
}

void fv_window_destroy(fv_window **pw)
{
    if (!pw || !*pw) return;
    fv_window *w = *pw;
    if (w->vk) window_detach(&w->target, w->vk);
    if (w->glfw) glfwDestroyWindow(w->glfw);
    glfwTerminate();
    free(w);
    *pw = NULL;
}

fv_target *fv_window_target(fv_window *w) { return w ? &w->target : NULL; }

fv_display *fv_window_display(fv_window *w) { return w ? &w->clock.base : NULL; }

const char *fv_window_clock_name(const fv_window *w)
{
    return fv_present_clock_source_str(w ? w->clock.source : FV_PRESENT_CLOCK_CADENCE);
}

void fv_window_get_stats(const fv_window *w, fv_window_stats *out)
{
    if (!out) return;
    memset(out, 0, sizeof *out);
    if (!w) return;
    *out = w->stats;
    out->refresh_measured = w->clock.period_measured;
    out->vsync_events = w->clock.vsync_events;
    if (!out->present_mode) out->present_mode = fv_window_present_mode_str(w->desc.present_mode);
}
