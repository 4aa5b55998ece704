/* @brief Session life cycle (IDLE -> READY -> SYNCHRONIZED -> VISIBLE -> FOCUSED -> STOPPING -> EXITING, and
 * LOSS_PENDING when the display goes away) and the frame loop: xrWaitFrame paced by fovea's display clock (the
 * simulated display when headless) with a predictedDisplayTime that includes the app's frame time, the compositor's
 * time and the display's photon delay; xrBeginFrame / xrEndFrame call-order rules; layer validation; compositing. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fv_clock.h"
#include "fv_sim_display.h"
#include "fv_xr_pace.h"
#include "xr_internal.h"
#include "xr_present.h"

#define MS_PER_NS 1e-6

static const char *state_name(XrSessionState s)
{
    switch (s) {
    case XR_SESSION_STATE_IDLE: return "IDLE";
    case XR_SESSION_STATE_READY: return "READY";
    case XR_SESSION_STATE_SYNCHRONIZED: return "SYNCHRONIZED";
    case XR_SESSION_STATE_VISIBLE: return "VISIBLE";
    case XR_SESSION_STATE_FOCUSED: return "FOCUSED";
    case XR_SESSION_STATE_STOPPING: return "STOPPING";
    case XR_SESSION_STATE_LOSS_PENDING: return "LOSS_PENDING";
    case XR_SESSION_STATE_EXITING: return "EXITING";
    default: return "UNKNOWN";
    }
}

/* Every state change also goes to the statistics' history (FOVEA_XR_STATS). */
static char g_history[512];
static void set_state(struct XrSession_T *s, XrSessionState st)
{
    if (s->state == st) return;
    fv_xr_session_set_state(s, st);
    size_t n = strlen(g_history);
    snprintf(g_history + n, sizeof g_history - n, "%s%s", n ? " " : "", state_name(st));
}

/* ---- create / destroy ---------------------------------------------------------------------------------------- */
FV_XR_DECL(xrCreateSession)(XrInstance instance, const XrSessionCreateInfo *info, XrSession *out)
{
    struct XrInstance_T *inst = fv_xr_instance_check(instance);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_SESSION_CREATE_INFO || info->createFlags != 0)
        return XR_ERROR_VALIDATION_FAILURE;
    if (info->systemId != FV_XR_SYSTEM_ID) return XR_ERROR_SYSTEM_INVALID;
    /* a binding of an extension the app did not enable is ignored (like any structure the runtime does not know) */
    const XrGraphicsBindingVulkanKHR *vkb = NULL;
    const void *eglb = NULL;
    if (fv_xr_chain_find(info->next, inst->ext.vulkan || inst->ext.vulkan2 ? XR_TYPE_GRAPHICS_BINDING_VULKAN_KHR
                                                                            : XR_TYPE_UNKNOWN,
                         "xrCreateSession", (const void **)&vkb) != XR_SUCCESS ||
        fv_xr_chain_find(info->next, inst->ext.egl ? XR_TYPE_GRAPHICS_BINDING_EGL_MNDX : XR_TYPE_UNKNOWN,
                         "xrCreateSession", &eglb) != XR_SUCCESS)
        return XR_ERROR_VALIDATION_FAILURE;
    if (vkb && eglb) {
        FV_ERROR(FV_XR_LOG, "xrCreateSession: two graphics bindings (Vulkan and EGL)");
        return XR_ERROR_VALIDATION_FAILURE;
    }
    pthread_mutex_lock(&inst->lock);
    XrResult r = XR_SUCCESS;
    struct XrSession_T *s = NULL;
    struct fv_xr_egl *egl = NULL;
    if (inst->session) {
        r = XR_ERROR_LIMIT_REACHED; /* one session per instance */
        goto fail;
    }
    if (eglb) {
        if (!inst->comp) {
            r = XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING;
            goto fail;
        }
        r = fv_xr_egl_session_create(inst, eglb, &egl);
        if (r != XR_SUCCESS) goto fail;
    }
    if (!vkb && !egl && !inst->ext.headless) {
        FV_ERROR(FV_XR_LOG, "xrCreateSession: no graphics binding (and XR_MND_headless is not enabled)");
        r = XR_ERROR_GRAPHICS_DEVICE_INVALID;
        goto fail;
    }
    if (vkb) {
        if (!inst->graphics_requirements_queried || !inst->comp) {
            r = XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING;
            goto fail;
        }
        if (vkb->physicalDevice != VK_NULL_HANDLE && vkb->device != VK_NULL_HANDLE && vkb->instance != VK_NULL_HANDLE) {
            /* the app's physical device must be the compositor's (images are shared by memory) */
            if (!fv_xr_compositor_same_device(inst->comp, vkb->physicalDevice)) {
                FV_ERROR(FV_XR_LOG, "xrCreateSession: the app's Vulkan device is not the one "
                                    "xrGetVulkanGraphicsDeviceKHR named");
                r = XR_ERROR_GRAPHICS_DEVICE_INVALID;
                goto fail;
            }
        } else {
            r = XR_ERROR_GRAPHICS_DEVICE_INVALID;
            goto fail;
        }
    }
    s = calloc(1, sizeof *s);
    if (!s) {
        r = XR_ERROR_OUT_OF_MEMORY;
        goto fail;
    }
    s->magic = FV_XR_MAGIC_SESSION;
    s->inst = inst;
    s->headless = vkb == NULL && egl == NULL;
    s->egl = egl;
    egl = NULL;
    s->state = XR_SESSION_STATE_UNKNOWN;
    pthread_mutex_init(&s->frame_lock, NULL);
    pthread_cond_init(&s->frame_cond, NULL);
    const char *lose = getenv("FOVEA_XR_LOSE_DISPLAY_AFTER");
    if (lose && *lose) s->lose_after_frames = strtoull(lose, NULL, 10);
    const char *frames = getenv("FOVEA_XR_FRAMES");
    if (frames && *frames) s->exit_after_frames = strtoull(frames, NULL, 10);
    /* The display clock: the window's swapchain clock when presenting in a window (xr_present.h), else the simulated
     * display at the HMD's refresh rate on the host clock. */
    s->display = !s->headless ? fv_xr_present_display(fv_xr_compositor_present(inst->comp)) : NULL;
    fv_sim_display_desc dd = {.clock = fv_clock_monotonic(), .refresh_hz = inst->hmd.refresh_hz};
    if (!s->display && fv_sim_display_create(&dd, &s->display) != FV_OK) {
        r = XR_ERROR_RUNTIME_FAILURE;
        goto fail;
    }
    s->budget = fv_xr_budget_create(&inst->run, s->display->refresh_hz); /* runtime/app's frame budget (xr_gaze.c) */
    if (vkb) {
        s->vk.instance = vkb->instance;
        s->vk.phys = vkb->physicalDevice;
        s->vk.device = vkb->device;
        s->vk.queue_family = vkb->queueFamilyIndex;
        s->vk.queue_index = vkb->queueIndex;
        vkGetDeviceQueue(s->vk.device, s->vk.queue_family, s->vk.queue_index, &s->vk.queue);
        VkCommandPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                       .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                       .queueFamilyIndex = s->vk.queue_family};
        if (vkCreateCommandPool(s->vk.device, &pci, NULL, &s->vk.pool) != VK_SUCCESS) {
            r = XR_ERROR_RUNTIME_FAILURE;
            goto fail;
        }
    }
    if (!s->headless && fv_xr_compositor_session_begin(inst->comp, inst->run.eye_w, inst->run.eye_h) != FV_OK) {
        r = XR_ERROR_RUNTIME_FAILURE;
        goto fail;
    }
    r = fv_xr_input_session_init(s);
    if (r != XR_SUCCESS) goto fail_comp;
    fv_xr_handle_add(s);
    if (!fv_xr_handle_live(s, FV_XR_MAGIC_SESSION)) {
        fv_xr_input_session_fini(s);
        r = XR_ERROR_OUT_OF_MEMORY;
        goto fail_comp;
    }
    inst->session = s;
    g_history[0] = 0;
    set_state(s, XR_SESSION_STATE_IDLE);
    set_state(s, XR_SESSION_STATE_READY); /* nothing to wait for: the display is there */
    pthread_mutex_unlock(&inst->lock);
    *out = s;
    return XR_SUCCESS;
fail_comp:
    if (!s->headless) fv_xr_compositor_session_end(inst->comp);
fail:
    if (s) {
        if (s->vk.pool) vkDestroyCommandPool(s->vk.device, s->vk.pool, NULL);
        fv_xr_egl_session_destroy(&s->egl);
        fv_xr_budget_destroy(&s->budget);
        fv_display_destroy(&s->display);
        pthread_cond_destroy(&s->frame_cond);
        pthread_mutex_destroy(&s->frame_lock);
        free(s);
    }
    fv_xr_egl_session_destroy(&egl);
    pthread_mutex_unlock(&inst->lock);
    return r;
}

static XrResult take_compositor(struct XrSession_T *s);

/* The compositor's time per frame, CPU (its thread, including the wait for the app's releases) and GPU. */
static void log_compositor(struct XrSession_T *s)
{
    const fv_xr_frame_stats *st = &s->stats;
    if (!st->composited) return;
    double gpu_ms[2] = {0, 0};
    fv_xr_compositor_gpu_ms(s->inst->comp, &gpu_ms[0], &gpu_ms[1]);
    double n = (double)st->composited;
    FV_INFO(FV_XR_LOG, "compositor: %llu frames composited, %llu replaced before it began them; per frame CPU %.3f ms "
                       "(of which waiting for the app's releases %.3f ms), GPU compose %.3f ms + distort %.3f ms",
            (unsigned long long)st->composited, (unsigned long long)st->replaced, st->composite_ms_sum / n,
            st->app_gpu_wait_ms_sum / n, gpu_ms[0], gpu_ms[1]);
}

/* FOVEA_XR_STATS=path: the session's frame statistics as JSON (the hello_xr tests and BENCHMARKS read it). */
static void write_stats(struct XrSession_T *s)
{
    const char *path = getenv("FOVEA_XR_STATS");
    if (!path || !*path) return;
    FILE *f = fopen(path, "w");
    if (!f) {
        FV_ERROR(FV_XR_LOG, "FOVEA_XR_STATS=%s: cannot write: %s", path, strerror(errno));
        return;
    }
    const fv_xr_frame_stats *st = &s->stats;
    fv_xr_gaze_stats gs = {0};
    double gpu_ms[2] = {0, 0};
    if (s->inst->gaze) fv_xr_gaze_get_stats(s->inst->gaze, &gs);
    if (s->inst->comp) fv_xr_compositor_gpu_ms(s->inst->comp, &gpu_ms[0], &gpu_ms[1]);
    double nc = st->composited ? (double)st->composited : 1.0;
    fprintf(f, "{\n");
    fprintf(f, "  \"frames_waited\": %llu,\n", (unsigned long long)st->waited);
    fprintf(f, "  \"frames_begun\": %llu,\n", (unsigned long long)st->begun);
    fprintf(f, "  \"frames_ended\": %llu,\n", (unsigned long long)st->ended);
    fprintf(f, "  \"frames_discarded\": %llu,\n", (unsigned long long)st->discarded);
    fprintf(f, "  \"frames_composited\": %llu,\n", (unsigned long long)st->composited);
    fprintf(f, "  \"frames_missed\": %llu,\n", (unsigned long long)st->missed);
    fprintf(f, "  \"frames_replaced\": %llu,\n", (unsigned long long)st->replaced);
    fprintf(f, "  \"frames_through_lens\": %llu,\n", (unsigned long long)st->through_lens);
    fprintf(f, "  \"pace_divisor\": %u,\n", s->pace_k ? s->pace_k : 1u);
    fprintf(f, "  \"pace_divisor_max\": %u,\n", st->pace_k_max ? st->pace_k_max : 1u);
    fprintf(f, "  \"frames_paced\": %llu,\n", (unsigned long long)st->paced);
    fprintf(f, "  \"pace_need_ms\": %.4f,\n", st->pace_need_ms);
    fprintf(f, "  \"app_ms\": %.4f,\n", st->app_ms_ema);
    fprintf(f, "  \"composite_ms_mean\": %.4f,\n", st->composite_ms_sum / nc);
    fprintf(f, "  \"app_gpu_wait_ms_mean\": %.4f,\n", st->app_gpu_wait_ms_sum / nc);
    fprintf(f, "  \"compose_gpu_ms_mean\": %.4f,\n", gpu_ms[0]);
    fprintf(f, "  \"distort_gpu_ms_mean\": %.4f,\n", gpu_ms[1]);
    fprintf(f, "  \"runtime_overhead_ms\": %.4f,\n",
            st->overhead_frames ? st->overhead_ms_sum / (double)st->overhead_frames : 0.0);
    fprintf(f, "  \"predicted_vs_photon_max_ms\": %.4f,\n", (double)st->predicted_minus_photon_ns_max * MS_PER_NS);
    fprintf(f, "  \"predicted_vs_photon_mean_ms\": %.4f,\n",
            st->presented ? st->predicted_error_ms_sum / (double)st->presented : 0.0);
    fprintf(f, "  \"headless\": %s,\n", s->headless ? "true" : "false");
    fv_xr_present_write_stats(s->headless ? NULL : fv_xr_compositor_present(s->inst->comp), f);
    fprintf(f, "  \"gaze_to_photon_frames\": %llu,\n", (unsigned long long)st->gaze_photon_frames);
    fprintf(f, "  \"gaze_to_photon_ms_mean\": %.4f,\n",
            st->gaze_photon_frames ? st->gaze_photon_ms_sum / (double)st->gaze_photon_frames : 0.0);
    fprintf(f, "  \"gaze_to_photon_ms_max\": %.4f,\n", st->gaze_photon_ms_max);
    fprintf(f, "  \"validation_messages\": %u,\n",
            s->inst->comp ? fv_xr_compositor_validation_messages(s->inst->comp) : 0u);
    fprintf(f, "  \"gaze_locates\": %llu,\n", (unsigned long long)gs.count);
    fprintf(f, "  \"gaze_horizon_ms_mean\": %.4f,\n", gs.count ? gs.sum_ms / (double)gs.count : 0.0);
    fprintf(f, "  \"gaze_horizon_ms_max\": %.4f,\n", gs.max_ms);
    fv_xr_budget_write_stats(s->budget, f);
    fprintf(f, "  \"states\": \"%s\"\n}\n", g_history);
    fclose(f);
}

FV_XR_DECL(xrDestroySession)(XrSession session)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    struct XrInstance_T *inst = s->inst;
    pthread_mutex_lock(&inst->lock);
    fv_xr_handle_remove(s);
    fv_xr_spaces_destroy_all(s);
    fv_xr_swapchains_destroy_all(s);
    fv_xr_input_session_fini(s);
    if (!s->headless) {
        fv_xr_compositor_flush(inst->comp); /* every queued frame composited */
        (void)take_compositor(s);
        log_compositor(s);
        fv_xr_compositor_session_end(inst->comp);
        if (s->vk.pool) vkDestroyCommandPool(s->vk.device, s->vk.pool, NULL);
    }
    fv_xr_egl_session_destroy(&s->egl);
    write_stats(s);
    fv_xr_budget_destroy(&s->budget);
    fv_display_destroy(&s->display);
    /* events of this session still queued would name a dead handle: drop them */
    XrEventDataBuffer keep[FV_XR_EVENT_CAP];
    uint32_t n = 0;
    for (uint32_t i = 0; i < inst->event_count; i++) {
        XrEventDataBuffer *e = &inst->events[(inst->event_head + i) % FV_XR_EVENT_CAP];
        if (e->type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED &&
            ((XrEventDataSessionStateChanged *)e)->session == s)
            continue;
        if (e->type == XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED &&
            ((XrEventDataInteractionProfileChanged *)e)->session == s)
            continue;
        keep[n++] = *e;
    }
    memcpy(inst->events, keep, n * sizeof keep[0]);
    inst->event_head = 0;
    inst->event_count = n;
    inst->session = NULL;
    pthread_mutex_unlock(&inst->lock);
    s->magic = 0;
    pthread_cond_destroy(&s->frame_cond);
    pthread_mutex_destroy(&s->frame_lock);
    free(s);
    return XR_SUCCESS;
}

/* ---- begin / end / exit -------------------------------------------------------------------------------------- */
FV_XR_DECL(xrBeginSession)(XrSession session, const XrSessionBeginInfo *info)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_SESSION_BEGIN_INFO ||
        fv_xr_chain_check(info->next, "xrBeginSession") != XR_SUCCESS)
        return XR_ERROR_VALIDATION_FAILURE;
    pthread_mutex_lock(&s->inst->lock);
    XrResult r = XR_SUCCESS;
    uint32_t views = 0;
    if (s->loss_pending) r = XR_ERROR_SESSION_LOST;
    else if (s->running) r = XR_ERROR_SESSION_RUNNING;
    else if (s->state != XR_SESSION_STATE_READY) r = XR_ERROR_SESSION_NOT_READY;
    /* headless too (it has no views to show, but the type is the system's or unsupported: the CTS's SessionState) */
    else r = fv_xr_check_view_config(s->inst, info->primaryViewConfigurationType, &views);
    if (r == XR_SUCCESS) {
        s->running = true;
        s->exit_requested = false;
        s->view_config = info->primaryViewConfigurationType;
        s->view_count = views;
        pthread_mutex_lock(&s->frame_lock);
        s->frames_waited = s->frames_begun = s->frames_ended = 0;
        s->frame_open = false;
        pthread_mutex_unlock(&s->frame_lock);
        /* A headless session has no frame loop to synchronise: it goes straight to FOCUSED (XR_MND_headless). */
        if (s->headless) {
            set_state(s, XR_SESSION_STATE_SYNCHRONIZED);
            set_state(s, XR_SESSION_STATE_VISIBLE);
            set_state(s, XR_SESSION_STATE_FOCUSED);
            fv_xr_input_focus(s);
        }
    }
    pthread_mutex_unlock(&s->inst->lock);
    return r;
}

/* From a running state down to STOPPING, through every state in between. Instance lock held. */
static void go_stopping(struct XrSession_T *s)
{
    if (s->state == XR_SESSION_STATE_FOCUSED) set_state(s, XR_SESSION_STATE_VISIBLE);
    if (s->state == XR_SESSION_STATE_VISIBLE) set_state(s, XR_SESSION_STATE_SYNCHRONIZED);
    if (s->state == XR_SESSION_STATE_READY) set_state(s, XR_SESSION_STATE_SYNCHRONIZED);
    if (s->state == XR_SESSION_STATE_SYNCHRONIZED) set_state(s, XR_SESSION_STATE_STOPPING);
}

FV_XR_DECL(xrRequestExitSession)(XrSession session)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    pthread_mutex_lock(&s->inst->lock);
    XrResult r = XR_SUCCESS;
    if (s->loss_pending) r = XR_ERROR_SESSION_LOST;
    else if (!s->running) r = XR_ERROR_SESSION_NOT_RUNNING;
    else {
        s->exit_requested = true;
        go_stopping(s);
    }
    pthread_mutex_unlock(&s->inst->lock);
    return r;
}

FV_XR_DECL(xrEndSession)(XrSession session)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    pthread_mutex_lock(&s->inst->lock);
    XrResult r = XR_SUCCESS;
    if (s->loss_pending) r = XR_ERROR_SESSION_LOST;
    else if (!s->running) r = XR_ERROR_SESSION_NOT_RUNNING;
    else if (s->state != XR_SESSION_STATE_STOPPING) r = XR_ERROR_SESSION_NOT_STOPPING;
    else {
        s->running = false;
        /* the spec: while the session is not running, every action reads inactive */
        if (s->input) fv_xr_input_deactivate(s->input);
        pthread_mutex_lock(&s->frame_lock);
        s->frame_open = false;
        pthread_cond_broadcast(&s->frame_cond);
        pthread_mutex_unlock(&s->frame_lock);
        set_state(s, XR_SESSION_STATE_IDLE);
        /* the runtime stops only when asked to: then the app should exit; else the display is still there */
        set_state(s, s->exit_requested ? XR_SESSION_STATE_EXITING : XR_SESSION_STATE_READY);
    }
    pthread_mutex_unlock(&s->inst->lock);
    return r;
}

/* The display went away (FOVEA_XR_LOSE_DISPLAY_AFTER frames on the simulated display, or the compositor's device
 * was lost): LOSS_PENDING; from now on the session's calls return XR_ERROR_SESSION_LOST. Instance lock held. */
static void lose_display(struct XrSession_T *s, const char *why)
{
    if (s->loss_pending) return;
    FV_WARN(FV_XR_LOG, "the display went away (%s): session LOSS_PENDING", why);
    s->loss_pending = true;
    if (s->input) fv_xr_input_deactivate(s->input);
    set_state(s, XR_SESSION_STATE_LOSS_PENDING);
    pthread_mutex_lock(&s->frame_lock);
    pthread_cond_broadcast(&s->frame_cond);
    pthread_mutex_unlock(&s->frame_lock);
}

/* ---- the frame loop -------------------------------------------------------------------------------------------- */
static void sleep_until_ns(int64_t t_ns)
{
    struct timespec ts = {(time_t)(t_ns / 1000000000), (long)(t_ns % 1000000000)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {
    }
}

/* The host time of the newest gaze sample now (0 when no source or no sample). Instance lock held. */
static void note_gaze_sample(struct XrSession_T *s)
{
    s->stats.gaze_sample_ns = s->inst->gaze ? fv_xr_gaze_newest_sample_ns(s->inst->gaze) : 0;
}

static double ema(double old, double v, uint64_t n) { return n <= 1 ? v : old + 0.1 * (v - old); }

void fv_xr_stats_present(fv_xr_frame_stats *st, fv_display *d, int64_t t_done_ns, uint64_t target, int64_t predicted_ns,
                         int64_t gaze_sample_ns)
{
    fv_vsync shown_at;
    if (fv_display_present(d, t_done_ns, target, &shown_at) != FV_OK) return;
    if (shown_at.index > target) st->missed++;
    int64_t photon = fv_display_photon_ns(d, &shown_at);
    int64_t err = photon - predicted_ns;
    if (err < 0) err = -err;
    if (err > st->predicted_minus_photon_ns_max) st->predicted_minus_photon_ns_max = err;
    st->predicted_error_ms_sum += (double)err * MS_PER_NS;
    st->presented++;
    if (gaze_sample_ns > 0) { /* the gaze sample's age at the photons */
        double g_ms = (double)(photon - gaze_sample_ns) * MS_PER_NS;
        st->gaze_photon_ms_sum += g_ms;
        if (g_ms > st->gaze_photon_ms_max) st->gaze_photon_ms_max = g_ms;
        st->gaze_photon_frames++;
    }
}

/* The refresh divisor for a compositor that needs need_ms per frame (fv_xr_pace.h): said in the log when it rises
 * above any before (warning) and when it is back at 1. Instance lock held. */
static void repace(struct XrSession_T *s, double need_ms)
{
    uint32_t k = s->pace_k ? s->pace_k : 1;
    double refresh_ms = (double)s->display->period_ns * MS_PER_NS;
    uint32_t nk = fv_xr_pace_divisor(k, need_ms, refresh_ms);
    s->stats.pace_need_ms = need_ms;
    if (nk == k) return;
    if (nk > s->pace_k_warned) {
        FV_WARN(FV_XR_LOG, "compositor needs %.1f ms, refresh period %.1f ms: apps paced at 1/%u of the refresh",
                need_ms, refresh_ms, nk);
        s->pace_k_warned = nk;
    } else if (nk == 1) {
        FV_INFO(FV_XR_LOG, "compositor needs %.1f ms, refresh period %.1f ms: apps paced at every refresh again",
                need_ms, refresh_ms);
    }
    s->pace_k = nk;
    if (nk > s->stats.pace_k_max) s->stats.pace_k_max = nk;
}

/* Fold what the compositor did since the last call into the session's statistics; a failure of a frame it
 * composited: the display is lost (the device, or a window that cannot be presented to), else RUNTIME_FAILURE.
 * Instance lock held. */
static XrResult take_compositor(struct XrSession_T *s)
{
    if (s->headless || !s->inst->comp) return XR_SUCCESS;
    fv_xr_frame_stats *st = &s->stats;
    uint64_t before = st->composited;
    double cpu_ms = 0.0, need_ms = -1.0;
    fv_result fr = fv_xr_compositor_take(s->inst->comp, st, &cpu_ms, &need_ms);
    if (st->composited > before) st->composite_ms_ema = cpu_ms; /* xrWaitFrame plans with it */
    if (need_ms >= 0) repace(s, need_ms);
    if (fr == FV_OK) return XR_SUCCESS;
    bool windowed = fv_xr_present_windowed(fv_xr_compositor_present(s->inst->comp));
    if (fr == FV_ERR_DEVICE_LOST || windowed) {
        lose_display(s, windowed ? "the window could not be presented to" : "the compositor's GPU device was lost");
        return XR_SUCCESS;
    }
    return XR_ERROR_RUNTIME_FAILURE;
}

FV_XR_DECL(xrWaitFrame)(XrSession session, const XrFrameWaitInfo *info, XrFrameState *state)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if ((info && info->type != XR_TYPE_FRAME_WAIT_INFO) || !state || state->type != XR_TYPE_FRAME_STATE ||
        (info && fv_xr_chain_check(info->next, "xrWaitFrame") != XR_SUCCESS) ||
        fv_xr_chain_check(state->next, "xrWaitFrame: XrFrameState") != XR_SUCCESS)
        return XR_ERROR_VALIDATION_FAILURE;
    int64_t t_enter = fv_xr_now_ns();
    pthread_mutex_lock(&s->inst->lock);
    XrResult r = XR_SUCCESS;
    if (s->loss_pending) r = XR_ERROR_SESSION_LOST;
    else if (!s->running) r = XR_ERROR_SESSION_NOT_RUNNING;
    double app_ms = s->stats.app_ms_ema, comp_ms = s->stats.composite_ms_ema, late_ms = s->stats.oversleep_ms_ema;
    uint32_t k = s->pace_k ? s->pace_k : 1; /* vsyncs k refreshes apart (the compositor's pace, fv_xr_pace.h) */
    pthread_mutex_unlock(&s->inst->lock);
    if (r != XR_SUCCESS) return r;
    /* A second xrWaitFrame blocks until the previous frame was begun (another thread calls xrBeginFrame). */
    pthread_mutex_lock(&s->frame_lock);
    while (s->frames_waited > s->frames_begun && s->running && !s->loss_pending)
        pthread_cond_wait(&s->frame_cond, &s->frame_lock);
    bool stopped = !s->running || s->loss_pending;
    pthread_mutex_unlock(&s->frame_lock);
    if (stopped) return s->loss_pending ? XR_ERROR_SESSION_LOST : XR_ERROR_SESSION_NOT_RUNNING;
    /* the compositor has begun the last frame handed to it (it composites one while the app renders the next) */
    if (!s->headless) fv_xr_compositor_wait_queue_free(s->inst->comp);
    t_enter = fv_xr_now_ns(); /* the runtime's own time from here (blocking is not overhead) */

    /* Plan the vsync: the app needs app_ms for its frame, the compositor comp_ms, and the display's latch margin;
     * the first vsync after all that, and at least k refreshes after the one the previous frame aimed at (the
     * compositor shows a frame every k-th refresh: the period reported), is the frame's. */
    fv_display *d = s->display;
    int64_t period_ns = (int64_t)k * d->period_ns;
    int64_t need_ns = (int64_t)((app_ms + comp_ms + 2.0 * late_ms) * 1e6) + d->present_margin_ns;
    if (need_ns > 4 * period_ns) need_ns = 4 * period_ns; /* a stalled frame never pushes the plan away */
    int64_t now = fv_xr_now_ns();
    fv_vsync v;
    if (fv_display_vsync_at_or_after(d, now + need_ns, &v) != FV_OK) return XR_ERROR_RUNTIME_FAILURE;
    uint64_t first = s->target_vsync + k; /* a vsync's time is found half a refresh before it (a clock's
                                           * jitter, and an integer period_ns short of the exact one k times) */
    if (s->frames_waited > 0 && v.index < first &&
        fv_display_vsync_at_or_after(d, v.t_ns + (int64_t)(first - v.index) * d->period_ns - d->period_ns / 2, &v) !=
            FV_OK)
        return XR_ERROR_RUNTIME_FAILURE;
    int64_t wake = v.t_ns - need_ns;
    int64_t t_work = fv_xr_now_ns() - t_enter;
    bool slept = wake > fv_xr_now_ns();
    if (slept) sleep_until_ns(wake);
    int64_t t_resume = fv_xr_now_ns();

    pthread_mutex_lock(&s->inst->lock);
    s->target_vsync = v.index;
    s->predicted_ns = fv_display_photon_ns(d, &v);
    state->predictedDisplayTime = s->predicted_ns;
    state->predictedDisplayPeriod = period_ns;
    state->shouldRender = s->state == XR_SESSION_STATE_VISIBLE || s->state == XR_SESSION_STATE_FOCUSED;
    s->stats.waited++;
    s->stats.paced += k > 1;
    if (slept) s->stats.oversleep_ms_ema = ema(s->stats.oversleep_ms_ema, (double)(t_resume - wake) * MS_PER_NS, s->stats.waited);
    s->stats.overhead_ms_sum += (double)t_work * MS_PER_NS;
    s->wait_return_ns = fv_xr_now_ns();
    /* the newest gaze sample an app locating its gaze now would be predicted from (gaze-to-photon statistics) */
    note_gaze_sample(s);
    pthread_mutex_unlock(&s->inst->lock);
    pthread_mutex_lock(&s->frame_lock);
    s->frames_waited++;
    pthread_mutex_unlock(&s->frame_lock);
    return XR_SUCCESS;
}

FV_XR_DECL(xrBeginFrame)(XrSession session, const XrFrameBeginInfo *info)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (info && (info->type != XR_TYPE_FRAME_BEGIN_INFO || fv_xr_chain_check(info->next, "xrBeginFrame") != XR_SUCCESS))
        return XR_ERROR_VALIDATION_FAILURE;
    int64_t t0 = fv_xr_now_ns();
    pthread_mutex_lock(&s->inst->lock);
    XrResult r = XR_SUCCESS;
    if (s->loss_pending) r = XR_ERROR_SESSION_LOST;
    else if (!s->running) r = XR_ERROR_SESSION_NOT_RUNNING;
    if (r == XR_SUCCESS) {
        pthread_mutex_lock(&s->frame_lock);
        if (s->frames_waited == s->frames_begun) {
            r = XR_ERROR_CALL_ORDER_INVALID; /* no xrWaitFrame for this frame */
        } else {
            if (s->frame_open) {
                r = XR_FRAME_DISCARDED; /* the previous frame was begun but never ended: it is dropped */
                s->stats.discarded++;
            }
            s->frame_open = true;
            s->frames_begun++;
            s->begin_ns = fv_xr_now_ns();
            s->stats.begun++;
            pthread_cond_broadcast(&s->frame_cond);
        }
        pthread_mutex_unlock(&s->frame_lock);
    }
    s->stats.overhead_ms_sum += (double)(fv_xr_now_ns() - t0) * MS_PER_NS;
    pthread_mutex_unlock(&s->inst->lock);
    return r;
}

/* The swapchain image a layer's sub-image names, checked (LAYER_INVALID, SWAPCHAIN_RECT_INVALID, ...). */
static XrResult check_sub_image(struct XrSession_T *s, const XrSwapchainSubImage *si)
{
    struct XrSwapchain_T *sc = fv_xr_swapchain_check(si->swapchain);
    if (!sc || sc->session != s) return XR_ERROR_HANDLE_INVALID;
    if (sc->last_released < 0) return XR_ERROR_LAYER_INVALID; /* no image released yet */
    const XrRect2Di *rc = &si->imageRect;
    if (rc->offset.x < 0 || rc->offset.y < 0 || rc->extent.width <= 0 || rc->extent.height <= 0 ||
        (int64_t)rc->offset.x + rc->extent.width > (int64_t)sc->info.width ||
        (int64_t)rc->offset.y + rc->extent.height > (int64_t)sc->info.height)
        return XR_ERROR_SWAPCHAIN_RECT_INVALID;
    if (si->imageArrayIndex >= sc->info.arraySize) return XR_ERROR_VALIDATION_FAILURE;
    if (sc->depth) return XR_ERROR_LAYER_INVALID; /* a depth swapchain is not a colour layer */
    return XR_SUCCESS;
}

static bool fov_valid(const XrFovf *f)
{
    const float a[4] = {f->angleLeft, f->angleRight, f->angleUp, f->angleDown};
    for (int i = 0; i < 4; i++)
        if (!isfinite(a[i]) || fabsf(a[i]) >= 1.5707963f) return false;
    return f->angleLeft < f->angleRight && f->angleDown < f->angleUp;
}

static XrResult check_layers(struct XrSession_T *s, const XrFrameEndInfo *info)
{
    if (info->displayTime <= 0) return XR_ERROR_TIME_INVALID;
    /* fovea's display is opaque: any other mode, known or not (as the conformance suite asks) */
    if (info->environmentBlendMode != XR_ENVIRONMENT_BLEND_MODE_OPAQUE)
        return XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED;
    if (info->layerCount > FV_XR_MAX_LAYERS) return XR_ERROR_LAYER_LIMIT_EXCEEDED;
    if (info->layerCount && !info->layers) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < info->layerCount; i++) {
        const XrCompositionLayerBaseHeader *l = info->layers[i];
        if (!l) return XR_ERROR_LAYER_INVALID;
        if (fv_xr_chain_check(l->next, "xrEndFrame: layer") != XR_SUCCESS) return XR_ERROR_VALIDATION_FAILURE;
        /* XR_MND_headless: nothing is shown, so the layers are ignored, placeholders included (a projection with no
         * views, a quad with no swapchain: an app's frame loop written for a display) */
        if (s->headless) continue;
        if (!fv_xr_handle_live(l->space, FV_XR_MAGIC_SPACE) || ((struct XrSpace_T *)l->space)->session != s)
            return XR_ERROR_HANDLE_INVALID;
        if (l->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
            const XrCompositionLayerProjection *p = (const void *)l;
            if (p->viewCount != s->view_count || !p->views) return XR_ERROR_VALIDATION_FAILURE;
            for (uint32_t v = 0; v < p->viewCount; v++) {
                if (p->views[v].type != XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW ||
                    fv_xr_chain_check(p->views[v].next, "xrEndFrame: projection view") != XR_SUCCESS)
                    return XR_ERROR_VALIDATION_FAILURE;
                if (!fv_xr_pose_valid(&p->views[v].pose)) return XR_ERROR_POSE_INVALID;
                if (!fov_valid(&p->views[v].fov)) return XR_ERROR_VALIDATION_FAILURE;
                XrResult r = check_sub_image(s, &p->views[v].subImage);
                if (r != XR_SUCCESS) return r;
            }
        } else if (l->type == XR_TYPE_COMPOSITION_LAYER_QUAD) {
            const XrCompositionLayerQuad *q = (const void *)l;
            if (q->eyeVisibility > XR_EYE_VISIBILITY_RIGHT) return XR_ERROR_VALIDATION_FAILURE;
            if (!fv_xr_pose_valid(&q->pose)) return XR_ERROR_POSE_INVALID;
            if (!isfinite(q->size.width) || !isfinite(q->size.height) || q->size.width < 0 || q->size.height < 0)
                return XR_ERROR_VALIDATION_FAILURE;
            XrResult r = check_sub_image(s, &q->subImage);
            if (r != XR_SUCCESS) return r;
        } else {
            return XR_ERROR_LAYER_INVALID;
        }
    }
    return XR_SUCCESS;
}

FV_XR_DECL(xrEndFrame)(XrSession session, const XrFrameEndInfo *info)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_FRAME_END_INFO || fv_xr_chain_check(info->next, "xrEndFrame") != XR_SUCCESS)
        return XR_ERROR_VALIDATION_FAILURE;
    int64_t t0 = fv_xr_now_ns();
    pthread_mutex_lock(&s->inst->lock);
    XrResult r = XR_SUCCESS;
    if (s->loss_pending) r = XR_ERROR_SESSION_LOST;
    else if (!s->running) r = XR_ERROR_SESSION_NOT_RUNNING;
    else if (!s->frame_open) r = XR_ERROR_CALL_ORDER_INVALID; /* no xrBeginFrame */
    else r = check_layers(s, info);
    /* what the compositor did with the frames before this one (a failure of theirs is this call's: the frame stays
     * open, as for any other error) */
    if (r == XR_SUCCESS && !s->headless) r = take_compositor(s);
    if (r != XR_SUCCESS) {
        pthread_mutex_unlock(&s->inst->lock);
        return r;
    }
    pthread_mutex_lock(&s->frame_lock);
    s->frame_open = false;
    s->frames_ended++;
    pthread_mutex_unlock(&s->frame_lock);
    fv_xr_frame_stats *st = &s->stats;
    st->ended++;
    /* the app's frame: from xrWaitFrame's return (it may locate and simulate before xrBeginFrame) to xrEndFrame */
    int64_t app_start = s->wait_return_ns && s->wait_return_ns < s->begin_ns ? s->wait_return_ns : s->begin_ns;
    st->app_ms_ema = ema(st->app_ms_ema, (double)(t0 - app_start) * MS_PER_NS, st->ended);
    /* a headless session (XR_MND_headless) may run a frame loop for its timing; it has nothing to show */
    bool shown = (s->state == XR_SESSION_STATE_VISIBLE || s->state == XR_SESSION_STATE_FOCUSED) && !s->headless;
    if (shown && fv_xr_present_lost(fv_xr_compositor_present(s->inst->comp))) {
        lose_display(s, "the window's X server went away");
        shown = false;
    }
    /* the layers go to the compositor (its thread, or this thread once the instance lock is let go in a window):
     * the app's next frame does not wait for this one's compositing */
    bool composite = shown && info->layerCount > 0 && !s->loss_pending;
    if (composite) fv_xr_compositor_submit(s->inst->comp, s, info);
    int64_t t_done = fv_xr_now_ns();
    /* the budget's frame: the app's frame and the compositor's (its own thread's time per frame; both must fit) */
    fv_xr_budget_frame(s->budget, (double)(t0 - app_start) * MS_PER_NS + st->composite_ms_ema);
    /* nothing to composite: shown (as nothing) at once, on the display clock */
    if (!composite) {
        fv_xr_stats_present(st, s->display, t_done, s->target_vsync, s->predicted_ns, 0);
        if (!s->headless && s->inst->comp) fv_xr_compositor_pace_idle(s->inst->comp); /* it cost the compositor 0 */
        FV_LOG(FV_LOG_LEVEL_DEBUG, FV_XR_LOG, "frame %llu: app %.2f ms, nothing composited",
               (unsigned long long)st->ended, (double)(t0 - s->begin_ns) * MS_PER_NS);
    }
    st->overhead_ms_sum += (double)(t_done - t0) * MS_PER_NS;
    st->overhead_frames++;
    /* the life cycle: the first frame synchronises the session; it is then visible and focused */
    if (s->state == XR_SESSION_STATE_READY && !s->exit_requested) {
        set_state(s, XR_SESSION_STATE_SYNCHRONIZED);
        set_state(s, XR_SESSION_STATE_VISIBLE);
        set_state(s, XR_SESSION_STATE_FOCUSED);
        fv_xr_input_focus(s);
    }
    /* the window's events (its share of the runtime's time); closed: the runtime stops the session (the app then
     * ends it and the session exits) */
    int64_t t_poll = fv_xr_now_ns();
    bool open = s->headless || fv_xr_present_poll(fv_xr_compositor_present(s->inst->comp));
    st->overhead_ms_sum += (double)(fv_xr_now_ns() - t_poll) * MS_PER_NS;
    if (!open && !s->exit_requested && !s->loss_pending) {
        s->exit_requested = true;
        go_stopping(s);
    }
    /* a fixed number of frames (FOVEA_XR_FRAMES, like `fovea run --frames`): the runtime stops the session as a
     * window's close button would; the app then ends it and the session exits */
    if (s->exit_after_frames && st->ended >= s->exit_after_frames && !s->exit_requested) {
        s->exit_requested = true;
        go_stopping(s);
    }
    if (s->lose_after_frames && st->ended >= s->lose_after_frames)
        lose_display(s, "FOVEA_XR_LOSE_DISPLAY_AFTER frames on the simulated display");
    fv_xr_compositor *comp = composite ? s->inst->comp : NULL;
    pthread_mutex_unlock(&s->inst->lock);
    /* a window: this frame is composited here, without the instance lock (the wait thread goes on meanwhile) */
    if (comp && fv_xr_compositor_inline(comp)) fv_xr_compositor_run_pending(comp);
    return XR_SUCCESS;
}
