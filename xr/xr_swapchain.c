/* @brief Swapchains: formats fovea's device can share with the app, creation rules, the acquire -> wait -> release
 * order (XR_ERROR_CALL_ORDER_INVALID when broken), static images, and the hand-overs of each image (xr_compositor.c). */
#include <stdlib.h>
#include <string.h>

#include "xr_internal.h"

XrSwapchain fv_xr_swapchain_check(XrSwapchain sc)
{
    return fv_xr_handle_live(sc, FV_XR_MAGIC_SWAPCHAIN) ? sc : XR_NULL_HANDLE;
}

FV_XR_DECL(xrEnumerateSwapchainFormats)(XrSession session, uint32_t cap, uint32_t *count, int64_t *formats)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!count || (cap && !formats)) return XR_ERROR_VALIDATION_FAILURE;
    if (s->headless) {
        *count = 0; /* XR_MND_headless: no swapchains */
        return XR_SUCCESS;
    }
    pthread_mutex_lock(&s->inst->lock);
    /* an EGL session's formats are GL internal formats */
    uint32_t (*list)(fv_xr_compositor *, int64_t *, uint32_t) = s->egl ? fv_xr_egl_formats : fv_xr_compositor_formats;
    uint32_t n = list(s->inst->comp, NULL, 0);
    *count = n;
    XrResult r = XR_SUCCESS;
    if (cap > 0 && cap < n) r = XR_ERROR_SIZE_INSUFFICIENT;
    else if (cap > 0) list(s->inst->comp, formats, cap);
    pthread_mutex_unlock(&s->inst->lock);
    return r;
}

/* The usage flags OpenXR 1.0 defines (and XR_MND_swapchain_usage_input_attachment_bit's). */
#define KNOWN_USAGE                                                                                                    \
    (XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |                       \
     XR_SWAPCHAIN_USAGE_UNORDERED_ACCESS_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_SRC_BIT |                                   \
     XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT | XR_SWAPCHAIN_USAGE_SAMPLED_BIT | XR_SWAPCHAIN_USAGE_MUTABLE_FORMAT_BIT |    \
     XR_SWAPCHAIN_USAGE_INPUT_ATTACHMENT_BIT_MND)

static XrResult refuse(XrResult r, const XrSwapchainCreateInfo *info, const char *why)
{
    FV_ERROR(FV_XR_LOG, "xrCreateSwapchain: %ux%u, %u mips, %u samples, array %u, faces %u, format %lld: %s",
             info->width, info->height, info->mipCount, info->sampleCount, info->arraySize, info->faceCount,
             (long long)info->format, why);
    return r;
}

/* XrSwapchainCreateInfo against the limits the runtime reports (xrGetSystemProperties,
 * xrEnumerateViewConfigurationViews, xrEnumerateSwapchainFormats), before anything is made. Instance lock held. */
static XrResult check_create_info(struct XrSession_T *s, const XrSwapchainCreateInfo *info)
{
    if (info->createFlags & ~(XrSwapchainCreateFlags)(XR_SWAPCHAIN_CREATE_PROTECTED_CONTENT_BIT |
                                                       XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT))
        return refuse(XR_ERROR_VALIDATION_FAILURE, info, "unknown createFlags bits");
    if (info->createFlags & XR_SWAPCHAIN_CREATE_PROTECTED_CONTENT_BIT)
        return refuse(XR_ERROR_FEATURE_UNSUPPORTED, info, "protected content is not supported");
    if (info->usageFlags & ~(XrSwapchainUsageFlags)KNOWN_USAGE)
        return refuse(XR_ERROR_VALIDATION_FAILURE, info, "unknown usageFlags bits");
    if (info->width == 0 || info->height == 0 || info->width > FV_XR_MAX_IMAGE_SIZE ||
        info->height > FV_XR_MAX_IMAGE_SIZE)
        return refuse(XR_ERROR_VALIDATION_FAILURE, info, "width and height must be 1..maxSwapchainImageWidth/Height");
    uint32_t max_mips = 1; /* floor(log2(max(w, h))) + 1 */
    for (uint32_t d = info->width > info->height ? info->width : info->height; d > 1; d >>= 1) max_mips++;
    if (info->mipCount == 0 || info->mipCount > max_mips)
        return refuse(XR_ERROR_VALIDATION_FAILURE, info, "mipCount must be 1..floor(log2(max(width, height)))+1");
    if (info->sampleCount == 0) return refuse(XR_ERROR_VALIDATION_FAILURE, info, "sampleCount must not be 0");
    if (info->sampleCount > FV_XR_MAX_SAMPLES)
        return refuse(XR_ERROR_FEATURE_UNSUPPORTED, info, "sampleCount above maxSwapchainSampleCount");
    if (info->faceCount != 1 && info->faceCount != 6)
        return refuse(XR_ERROR_VALIDATION_FAILURE, info, "faceCount must be 1 or 6");
    if (info->faceCount == 6)
        return refuse(XR_ERROR_FEATURE_UNSUPPORTED, info, "cube maps (faceCount 6) are not supported");
    if (info->arraySize == 0 || info->arraySize > FV_XR_MAX_ARRAY_SIZE)
        return refuse(XR_ERROR_VALIDATION_FAILURE, info, "arraySize must be 1..FV_XR_MAX_ARRAY_SIZE (16)");
    int64_t formats[32];
    uint32_t n = (s->egl ? fv_xr_egl_formats : fv_xr_compositor_formats)(s->inst->comp, formats, 32);
    bool ok = false;
    for (uint32_t i = 0; i < n && i < 32; i++) ok |= formats[i] == info->format;
    if (!ok) return refuse(XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED, info, "not a format of xrEnumerateSwapchainFormats");
    bool depth = fv_xr_format_is_depth(s->egl ? fv_xr_egl_format_vk(info->format) : (VkFormat)info->format);
    if (depth &&
        (info->usageFlags & (XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_UNORDERED_ACCESS_BIT)))
        return refuse(XR_ERROR_FEATURE_UNSUPPORTED, info, "a depth format cannot be a colour or storage image");
    if (!depth && (info->usageFlags & XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT))
        return refuse(XR_ERROR_FEATURE_UNSUPPORTED, info, "a colour format cannot be a depth-stencil attachment");
    return XR_SUCCESS;
}

FV_XR_DECL(xrCreateSwapchain)(XrSession session, const XrSwapchainCreateInfo *info, XrSwapchain *out)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_SWAPCHAIN_CREATE_INFO ||
        fv_xr_chain_check(info->next, "xrCreateSwapchain") != XR_SUCCESS)
        return XR_ERROR_VALIDATION_FAILURE;
    if (s->headless) return XR_ERROR_FEATURE_UNSUPPORTED; /* XR_MND_headless sessions have no swapchains */
    pthread_mutex_lock(&s->inst->lock);
    struct XrSwapchain_T *sc = NULL;
    XrResult r = check_create_info(s, info);
    if (r != XR_SUCCESS) goto done;
    sc = calloc(1, sizeof *sc);
    if (!sc) {
        r = XR_ERROR_OUT_OF_MEMORY;
        goto done;
    }
    sc->magic = FV_XR_MAGIC_SWAPCHAIN;
    sc->session = s;
    sc->info = *info;
    sc->info.next = NULL;
    sc->format = s->egl ? fv_xr_egl_format_vk(info->format) : (VkFormat)info->format;
    sc->depth = fv_xr_format_is_depth(sc->format);
    sc->image_count = (info->createFlags & XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT) ? 1 : FV_XR_MAX_SWAPCHAIN_IMAGES;
    sc->last_released = -1;
    r = fv_xr_swapchain_images_create(s->inst->comp, sc);
    if (r != XR_SUCCESS) goto done;
    if (s->egl && (r = fv_xr_egl_swapchain_create(s, sc)) != XR_SUCCESS) {
        fv_xr_swapchain_images_destroy(s->inst->comp, sc);
        goto done;
    }
    fv_xr_handle_add(sc);
    if (!fv_xr_handle_live(sc, FV_XR_MAGIC_SWAPCHAIN)) {
        fv_xr_egl_swapchain_destroy(s, sc);
        fv_xr_swapchain_images_destroy(s->inst->comp, sc);
        r = XR_ERROR_OUT_OF_MEMORY;
        goto done;
    }
    sc->next = s->swapchains;
    s->swapchains = sc;
    *out = sc;
    sc = NULL;
done:
    free(sc);
    pthread_mutex_unlock(&s->inst->lock);
    return r;
}

static void unlink_swapchain(struct XrSession_T *s, struct XrSwapchain_T *sc)
{
    struct XrSwapchain_T **pp = &s->swapchains;
    while (*pp && *pp != sc) pp = &(*pp)->next;
    if (*pp) *pp = sc->next;
}

static void swapchain_free(struct XrSwapchain_T *sc)
{
    fv_xr_handle_remove(sc);
    fv_xr_egl_swapchain_destroy(sc->session, sc);
    fv_xr_swapchain_images_destroy(sc->session->inst->comp, sc);
    sc->magic = 0;
    free(sc);
}

FV_XR_DECL(xrDestroySwapchain)(XrSwapchain swapchain)
{
    struct XrSwapchain_T *sc = fv_xr_swapchain_check(swapchain);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    struct XrSession_T *s = sc->session;
    pthread_mutex_lock(&s->inst->lock);
    unlink_swapchain(s, sc);
    swapchain_free(sc);
    pthread_mutex_unlock(&s->inst->lock);
    return XR_SUCCESS;
}

void fv_xr_swapchains_destroy_all(struct XrSession_T *s)
{
    while (s->swapchains) {
        struct XrSwapchain_T *sc = s->swapchains;
        s->swapchains = sc->next;
        swapchain_free(sc);
    }
}

FV_XR_DECL(xrEnumerateSwapchainImages)(XrSwapchain swapchain, uint32_t cap, uint32_t *count,
                                       XrSwapchainImageBaseHeader *images)
{
    struct XrSwapchain_T *sc = fv_xr_swapchain_check(swapchain);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    if (!count || (cap && !images)) return XR_ERROR_VALIDATION_FAILURE;
    *count = sc->image_count;
    if (cap == 0) return XR_SUCCESS;
    if (cap < sc->image_count) return XR_ERROR_SIZE_INSUFFICIENT;
    if (sc->egl) return fv_xr_egl_enumerate_images(sc, images);
    XrSwapchainImageVulkanKHR *vi = (XrSwapchainImageVulkanKHR *)images;
    for (uint32_t i = 0; i < sc->image_count; i++) {
        if (vi[i].type != XR_TYPE_SWAPCHAIN_IMAGE_VULKAN_KHR) return XR_ERROR_VALIDATION_FAILURE;
        vi[i].image = fv_xr_swapchain_app_image(sc, i);
    }
    return XR_SUCCESS;
}

FV_XR_DECL(xrAcquireSwapchainImage)(XrSwapchain swapchain, const XrSwapchainImageAcquireInfo *info, uint32_t *index)
{
    struct XrSwapchain_T *sc = fv_xr_swapchain_check(swapchain);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    if ((info && (info->type != XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO ||
                  fv_xr_chain_check(info->next, "xrAcquireSwapchainImage") != XR_SUCCESS)) ||
        !index)
        return XR_ERROR_VALIDATION_FAILURE;
    struct XrSession_T *s = sc->session;
    pthread_mutex_lock(&s->inst->lock);
    XrResult r = XR_SUCCESS;
    if (s->loss_pending) r = XR_ERROR_SESSION_LOST;
    else if (sc->acquired_count == sc->image_count) r = XR_ERROR_CALL_ORDER_INVALID; /* every image is acquired */
    else if ((sc->info.createFlags & XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT) && sc->static_used)
        r = XR_ERROR_CALL_ORDER_INVALID; /* a static image is acquired once */
    if (r == XR_SUCCESS) { /* the index only: the image comes back to the app in xrWaitSwapchainImage */
        uint32_t i = sc->next_acquire;
        sc->acquired[sc->acquired_count++] = i;
        sc->next_acquire = (i + 1) % sc->image_count;
        sc->static_used = true;
        *index = i;
    }
    pthread_mutex_unlock(&s->inst->lock);
    return r;
}

FV_XR_DECL(xrWaitSwapchainImage)(XrSwapchain swapchain, const XrSwapchainImageWaitInfo *info)
{
    struct XrSwapchain_T *sc = fv_xr_swapchain_check(swapchain);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO ||
        fv_xr_chain_check(info->next, "xrWaitSwapchainImage") != XR_SUCCESS)
        return XR_ERROR_VALIDATION_FAILURE;
    struct XrSession_T *s = sc->session;
    pthread_mutex_lock(&s->inst->lock);
    XrResult r = XR_SUCCESS;
    if (s->loss_pending) r = XR_ERROR_SESSION_LOST;
    else if (sc->acquired_count == 0 || sc->waited) r = XR_ERROR_CALL_ORDER_INVALID; /* nothing acquired to wait on */
    uint32_t i = sc->acquired_count ? sc->acquired[0] : 0;
    pthread_mutex_unlock(&s->inst->lock);
    if (r != XR_SUCCESS) return r;
    /* the spec: wait until the compositor has finished reading the image (a frame queued or being composited
     * reads its last released image); without the instance lock, so the frame loop's other calls go on */
    int64_t t0 = fv_xr_now_ns();
    if (!fv_xr_compositor_image_idle(s->inst->comp, sc, i, info->timeout)) return XR_TIMEOUT_EXPIRED;
    XrDuration left = info->timeout - (fv_xr_now_ns() - t0);
    pthread_mutex_lock(&s->inst->lock);
    if (s->loss_pending) r = XR_ERROR_SESSION_LOST;
    else if (sc->acquired_count == 0 || sc->waited || sc->acquired[0] != i) r = XR_ERROR_CALL_ORDER_INVALID;
    /* the image back to the app on its queue (an EGL session: its own hand-over, xr_egl.c), then waited for */
    else if (sc->egl) r = fv_xr_egl_acquire(sc, i);
    else if ((r = fv_xr_swapchain_image_acquire(s->inst->comp, sc, i)) == XR_SUCCESS)
        r = fv_xr_swapchain_image_wait(s->inst->comp, sc, i, left > 0 ? left : 0);
    if (r == XR_SUCCESS) sc->waited = true;
    pthread_mutex_unlock(&s->inst->lock);
    return r;
}

FV_XR_DECL(xrReleaseSwapchainImage)(XrSwapchain swapchain, const XrSwapchainImageReleaseInfo *info)
{
    struct XrSwapchain_T *sc = fv_xr_swapchain_check(swapchain);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    if (info && (info->type != XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO ||
                 fv_xr_chain_check(info->next, "xrReleaseSwapchainImage") != XR_SUCCESS))
        return XR_ERROR_VALIDATION_FAILURE;
    struct XrSession_T *s = sc->session;
    pthread_mutex_lock(&s->inst->lock);
    XrResult r = XR_SUCCESS;
    if (s->loss_pending) r = XR_ERROR_SESSION_LOST;
    else if (sc->acquired_count == 0 || !sc->waited) r = XR_ERROR_CALL_ORDER_INVALID; /* not waited on */
    else {
        uint32_t i = sc->acquired[0];
        r = sc->egl ? fv_xr_egl_release(sc, i) : fv_xr_swapchain_image_release(s->inst->comp, sc, i);
        if (r == XR_SUCCESS) {
            memmove(sc->acquired, sc->acquired + 1, (sc->acquired_count - 1) * sizeof sc->acquired[0]);
            sc->acquired_count--;
            sc->waited = false;
            sc->last_released = (int32_t)i;
        }
    }
    pthread_mutex_unlock(&s->inst->lock);
    return r;
}
