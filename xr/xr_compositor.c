/* @brief fovea's OpenXR compositor: fovea's Vulkan core (fv_vk) owns the device, and the swapchain images live on it,
 * shared with the app's device (xr_swapchain_images.c). A frame: xrEndFrame maps every layer onto the display eyes and
 * queues the frame (fv_xr_compositor_submit); the compositor thread (in a window, the app's thread after the instance
 * lock is released) runs the compose pass onto the display image (fovea's FV_IMAGE_DISPLAY, sRGB-encoded), fovea's
 * lens-distortion pass pre-distorts it for the HMD's lens, and a target shows it (headless; PNG files with
 * FOVEA_XR_OUT). */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <stdint.h>

#include "compose_comp.spv.h"
#include "compose_interface.h"
#include "fv_images.h"
#include "fv_math.h"
#include "fv_pass.h"
#include "fv_post_chain.h"
#include "fv_target.h"
#include "fv_vk.h"
#include "xr_internal.h"
#include "xr_compositor_internal.h"
#include "xr_present.h"

static void *comp_thread(void *arg);

/* ---- device ------------------------------------------------------------------------------------------------ */
static const char *const g_optional_exts[] = {VK_KHR_EXTERNAL_MEMORY_FD_EXTENSION_NAME};

fv_result fv_xr_compositor_create(struct XrInstance_T *inst, fv_xr_compositor **out)
{
    fv_xr_compositor *c = calloc(1, sizeof *c);
    if (!c) return FV_ERR_NO_MEMORY;
    fv_vk_desc d = {.app_name = "fovea OpenXR compositor",
                    .optional_device_extensions = g_optional_exts,
                    .optional_device_extension_count = 1};
    fv_result res = fv_xr_present_create(inst->app_name, inst->run.eye_w, inst->run.eye_h, &c->present);
    if (res == FV_OK) {
        fv_xr_present_configure_vk(c->present, &d);
        res = fv_vk_create(&d, &c->vk);
    }
    if (res != FV_OK) {
        fv_xr_present_destroy(&c->present);
        free(c);
        return res;
    }
    if (!fv_vk_optional_enabled(c->vk, VK_KHR_EXTERNAL_MEMORY_FD_EXTENSION_NAME)) {
        FV_ERROR(FV_XR_LOG, "the Vulkan device '%s' lacks VK_KHR_external_memory_fd: swapchain images cannot be shared "
                            "with the application", c->vk->info.name);
        fv_vk_destroy(&c->vk);
        fv_xr_present_destroy(&c->present);
        free(c);
        return FV_ERR_UNSUPPORTED;
    }
    c->get_memory_fd = (PFN_vkGetMemoryFdKHR)vkGetDeviceProcAddr(c->vk->device, "vkGetMemoryFdKHR");
    VkPhysicalDeviceIDProperties id = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES};
    VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &id};
    vkGetPhysicalDeviceProperties2(c->vk->phys, &p2);
    memcpy(c->uuid, id.deviceUUID, VK_UUID_SIZE);
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_cond_init(&c->cv, &ca);
    pthread_condattr_destroy(&ca);
    pthread_mutex_init(&c->mu, NULL);
    pthread_mutex_init(&c->gpu_mu, NULL);
    int failed;
    char err[256];
    if (FV_FAILED(fv_app_run_quality(&inst->run, &c->input.quality, &failed, err, sizeof err))) {
        FV_ERROR(FV_XR_LOG, "the session's quality: %s; using balanced", err);
        c->input.quality = fv_quality_default();
    }
    c->input.quality.distort.lens = inst->hmd.lens;
    const char *dist = getenv("FOVEA_XR_DISTORT");
    c->input.quality.distort.enabled = !(dist && !strcmp(dist, "0"));
    /* the display eye frusta: the HMD profile's */
    float fov[8];
    for (int e = 0; e < 2; e++) {
        fov[4 * e + 0] = inst->hmd.fov[e].tan_left;
        fov[4 * e + 1] = inst->hmd.fov[e].tan_right;
        fov[4 * e + 2] = inst->hmd.fov[e].tan_up;
        fov[4 * e + 3] = inst->hmd.fov[e].tan_down;
    }
    fv_eye_views_build_fov(NULL, 0.05f, 100.0f, fov, c->input.eye);
    *out = c;
    return FV_OK;
}

void fv_xr_compositor_destroy(fv_xr_compositor **pc)
{
    if (!pc || !*pc) return;
    fv_xr_compositor *c = *pc;
    fv_xr_compositor_session_end(c);
    fv_xr_present_detach(c->present, c->vk); /* the window's swapchain goes before the device, the window after */
    fv_vk_destroy(&c->vk);
    fv_xr_present_destroy(&c->present);
    pthread_cond_destroy(&c->cv);
    pthread_mutex_destroy(&c->mu);
    pthread_mutex_destroy(&c->gpu_mu);
    free(c);
    *pc = NULL;
}

VkPhysicalDevice fv_xr_compositor_phys(const fv_xr_compositor *c) { return c->vk->phys; }
fv_xr_present *fv_xr_compositor_present(fv_xr_compositor *c) { return c ? c->present : NULL; }
void fv_xr_compositor_device_uuid(const fv_xr_compositor *c, uint8_t out_uuid[VK_UUID_SIZE])
{
    memcpy(out_uuid, c->uuid, VK_UUID_SIZE);
}
bool fv_xr_compositor_same_device(const fv_xr_compositor *c, VkPhysicalDevice phys)
{
    VkPhysicalDeviceIDProperties id = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES};
    VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &id};
    vkGetPhysicalDeviceProperties2(phys, &p2);
    return memcmp(c->uuid, id.deviceUUID, VK_UUID_SIZE) == 0;
}

uint32_t fv_xr_compositor_api_version(const fv_xr_compositor *c) { return c->vk->props.apiVersion; }
uint32_t fv_xr_compositor_validation_messages(const fv_xr_compositor *c) { return fv_vk_validation_messages(c->vk); }

/* ---- the session's output ---------------------------------------------------------------------------------- */
static const VkDescriptorSetLayoutBinding g_bindings[] = {
    {FV_XR_COMPOSE_BINDING_SOURCES, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, FV_XR_COMPOSE_MAX_SOURCES,
     VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    {FV_XR_COMPOSE_BINDING_DISPLAY, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    {FV_XR_COMPOSE_BINDING_LAYERS, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
};

fv_result fv_xr_compositor_session_begin(fv_xr_compositor *c, uint32_t width, uint32_t height)
{
    if (c->active) return FV_ERR_STATE;
    c->width = width;
    c->height = height;
    fv_result res = fv_images_init(&c->images, c->vk, width, height);
    if (res != FV_OK) return res;
    c->images_ready = true;
    const fv_vk_image *display = NULL;
    res = fv_images_get(&c->images, FV_IMAGE_DISPLAY, &display);
    fv_vk_compute_desc cd = {.name = "xr compose",
                             .code = fv_spv_compose_comp,
                             .code_size = sizeof fv_spv_compose_comp,
                             .bindings = g_bindings,
                             .binding_count = 3,
                             .set_count = 2,
                             .push_bytes = sizeof(uint32_t),
                             .lazy = true};
    if (res == FV_OK) res = fv_vk_compute_init(c->vk, &cd, &c->cs);
    if (res == FV_OK) res = fv_vk_sampler_create(c->vk, true, false, "xr compose sampler (linear, clamp)", &c->sampler);
    if (res == FV_OK)
        res = fv_vk_buffer_create(c->vk, sizeof(fv_xr_compose_block), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                  FV_VK_MEM_UPLOAD, "xr compose layers", &c->block);
    if (res == FV_OK) {
        for (uint32_t e = 0; e < 2; e++) { /* a set per eye (its sources; the same display and layers) */
            fv_vk_write_image(c->vk, c->cs.sets[e], FV_XR_COMPOSE_BINDING_DISPLAY, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                              display->view, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
            fv_vk_write_buffer(c->vk, c->cs.sets[e], FV_XR_COMPOSE_BINDING_LAYERS, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                               c->block.buffer, 0, sizeof(fv_xr_compose_block));
        }
        VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                          .commandPool = c->vk->pool,
                                          .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                          .commandBufferCount = 1};
        FV_VK_CHECK_GOTO(vkAllocateCommandBuffers(c->vk->device, &ai, &c->cmd), res, done);
        VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        FV_VK_CHECK_GOTO(vkCreateFence(c->vk->device, &fci, NULL, &c->fence), res, done);
        VkSemaphoreCreateInfo sci = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        FV_VK_CHECK_GOTO(vkCreateSemaphore(c->vk->device, &sci, NULL, &c->sem_ready), res, done);
        FV_VK_CHECK_GOTO(vkCreateSemaphore(c->vk->device, &sci, NULL, &c->sem_done), res, done);
    }
    if (res == FV_OK) {
        res = fv_vk_timer_init(&c->timer, c->vk, 1);
        c->timer_ready = res == FV_OK;
    }
    /* the renderer's post chain (lens pre-distortion, on when the HMD has a lens), planned by the renderer's rules */
    if (res == FV_OK && (res = fv_post_chain_create(c->vk, &c->images, width, height, &c->input.quality,
                                                    &c->post)) == FV_OK)
        for (uint32_t k = 0; k < fv_post_chain_planned(c->post); k++)
            FV_INFO(FV_XR_LOG, "%s: %s", fv_post_chain_pass_id(c->post, k), fv_post_chain_reason(c->post, k));
    /* the chain's one pass is the lens (distort): a frame of few layers per eye is composed through the lens instead
     * (compose.comp's LENS: one pass, each layer sampled once per channel), others are composed and then distorted */
    c->lens_in_compose = res == FV_OK && c->input.quality.distort.lens.valid && fv_post_chain_count(c->post) == 1 &&
                         fv_post_chain_planned(c->post) == 1 && !strcmp(fv_post_chain_pass_id(c->post, 0), "distort");
    if (c->lens_in_compose)
        FV_INFO(FV_XR_LOG, "frames of up to %d layers per eye: composed through the lens in one pass (no distort pass)",
                FV_XR_COMPOSE_LENS_MAX_LAYERS);
    /* the target: the window when presenting in one (xr_present.h), PNG files of the last frame with
     * FOVEA_XR_OUT=dir, else headless */
    const char *out = getenv("FOVEA_XR_OUT");
    if (res == FV_OK && fv_xr_present_windowed(c->present)) {
        c->target = fv_xr_present_target(c->present);
    } else if (res == FV_OK && out && *out) {
        snprintf(c->out_dir, sizeof c->out_dir, "%s", out);
        /* FOVEA_XR_OUT_ALL=1: every composited frame (frame_NNNNN.png, N = composited frames before it) */
        const char *all = getenv("FOVEA_XR_OUT_ALL");
        if (all && *all && strcmp(all, "0") != 0 && strcmp(all, "1") != 0)
            FV_ERROR(FV_XR_LOG, "FOVEA_XR_OUT_ALL='%s': expected 0 or 1; writing the last frame only", all);
        fv_target_files_desc fd = {.dir = c->out_dir, .side_by_side = true,
                                   .save = all && !strcmp(all, "1") ? FV_TARGET_SAVE_EVERY : FV_TARGET_SAVE_LAST};
        res = fv_target_files_create(&fd, &c->target);
    } else if (res == FV_OK) {
        c->target = fv_target_headless();
    }
done:
    if (res != FV_OK) {
        c->active = true;
        fv_xr_compositor_session_end(c);
        return res;
    }
    c->active = true;
    c->frame_id = 0;
    c->pace = (fv_xr_pace_window){0};
    /* frames are composited on the compositor's own thread; a window's on the app's thread (GLFW's rule) */
    c->stop = c->has_pending = c->busy = false;
    c->threaded = !fv_xr_present_windowed(c->present);
    if (c->threaded && pthread_create(&c->thread, NULL, comp_thread, c) != 0) {
        FV_ERROR(FV_XR_LOG, "the compositor thread could not be started");
        c->threaded = false;
        fv_xr_compositor_session_end(c);
        return FV_ERR_NO_MEMORY;
    }
    return FV_OK;
}

void fv_xr_compositor_session_end(fv_xr_compositor *c)
{
    if (!c || !c->active) return;
    if (c->threaded) { /* the thread composites what is queued, then ends */
        pthread_mutex_lock(&c->mu);
        c->stop = true;
        pthread_cond_broadcast(&c->cv);
        pthread_mutex_unlock(&c->mu);
        pthread_join(c->thread, NULL);
        c->threaded = false;
    }
    fv_xr_compositor_drain(c);
    vkDeviceWaitIdle(c->vk->device);
    fv_target_destroy(&c->target);
    fv_post_chain_destroy(&c->post);
    if (c->sem_ready) vkDestroySemaphore(c->vk->device, c->sem_ready, NULL);
    if (c->sem_done) vkDestroySemaphore(c->vk->device, c->sem_done, NULL);
    if (c->fence) vkDestroyFence(c->vk->device, c->fence, NULL);
    if (c->cmd) vkFreeCommandBuffers(c->vk->device, c->vk->pool, 1, &c->cmd);
    c->sem_ready = c->sem_done = VK_NULL_HANDLE;
    c->fence = VK_NULL_HANDLE;
    c->cmd = VK_NULL_HANDLE;
    fv_vk_buffer_destroy(c->vk, &c->block);
    if (c->timer_ready) fv_vk_timer_fini(&c->timer, c->vk);
    c->timer_ready = false;
    if (c->sampler) vkDestroySampler(c->vk->device, c->sampler, NULL);
    c->sampler = VK_NULL_HANDLE;
    for (uint32_t l = 0; l < 2; l++)
        for (uint32_t i = 0; i < FV_XR_COMPOSE_MAX_SOURCES; i++) {
            if (c->compose[l][i]) vkDestroyPipeline(c->vk->device, c->compose[l][i], NULL);
            c->compose[l][i] = VK_NULL_HANDLE;
        }
    fv_vk_compute_fini(c->vk, &c->cs);
    if (c->images_ready) fv_images_fini(&c->images);
    c->images_ready = false;
    c->active = false;
}

void fv_xr_compositor_flush(fv_xr_compositor *c)
{
    if (!c || !c->active) return;
    fv_xr_compositor_drain(c);
    if (!c->target || c->frame_id == 0 || !fv_target_files_dir(c->target)) return;
    if (fv_target_files_flush(c->target) != FV_OK) FV_ERROR(FV_XR_LOG, "FOVEA_XR_OUT: the last frame was not written");
}

/* ---- one frame ----------------------------------------------------------------------------------------------- */
typedef struct mat3 {
    float m[3][3];
} mat3;

static mat3 mat3_mul(mat3 a, mat3 b)
{
    mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
    return r;
}

/* rotation matrix of a unit quaternion (rows) */
static mat3 mat3_rot(fv_quat q)
{
    float x = q.x, y = q.y, z = q.z, w = q.w;
    return (mat3){{{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                   {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                   {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}}};
}

static mat3 mat3_transpose(mat3 a)
{
    mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) r.m[i][j] = a.m[j][i];
    return r;
}

static fv_quat qx(XrQuaternionf q) { return (fv_quat){q.x, q.y, q.z, q.w}; }

/* a display-eye ray in tangent coordinates (x_t, y_t, 1) as a view-space direction (x_t, y_t, -1) */
static const mat3 RAY_TO_DIR = {{{1, 0, 0}, {0, 1, 0}, {0, 0, -1}}};

/* Projection view: rotate the display eye's ray into the layer view's frame, project into its frustum. */
static mat3 projection_homography(const XrPosef *eye_local, const XrPosef *view_local, const XrFovf *fov)
{
    float tl = tanf(fov->angleLeft), tr = tanf(fov->angleRight), tu = tanf(fov->angleUp), td = tanf(fov->angleDown);
    mat3 k = {{{1.0f / (tr - tl), 0, tl / (tr - tl)}, {0, -1.0f / (tu - td), -tu / (tu - td)}, {0, 0, -1}}};
    mat3 r = mat3_mul(mat3_transpose(mat3_rot(qx(view_local->orientation))), mat3_rot(qx(eye_local->orientation)));
    return mat3_mul(mat3_mul(k, r), RAY_TO_DIR);
}

/* Quad: the display eye's ray hits the quad's plane (z = 0 in the quad's frame, facing +z), in [0,1]^2 of its size. */
static bool quad_homography(const XrPosef *eye_local, const XrPosef *quad_local, XrExtent2Df size, mat3 *out)
{
    if (!(size.width > 0) || !(size.height > 0)) return false;
    fv_quat qi = {-quad_local->orientation.x, -quad_local->orientation.y, -quad_local->orientation.z,
                  quad_local->orientation.w};
    fv_vec3 d = {eye_local->position.x - quad_local->position.x, eye_local->position.y - quad_local->position.y,
                 eye_local->position.z - quad_local->position.z};
    fv_vec3 o = fv_quat_rotate(qi, d); /* the eye in the quad's frame */
    if (fabsf(o.z) < 1e-6f) return false; /* the eye is in the quad's plane: it is seen edge-on */
    mat3 m = mat3_mul(mat3_mul(mat3_transpose(mat3_rot(qx(quad_local->orientation))),
                               mat3_rot(qx(eye_local->orientation))),
                      RAY_TO_DIR);
    float sgn = o.z > 0 ? -1.0f : 1.0f; /* w = t's sign: the hit is in front of the eye */
    for (int j = 0; j < 3; j++) {
        float rx = o.x * m.m[2][j] - o.z * m.m[0][j];
        float ry = o.y * m.m[2][j] - o.z * m.m[1][j];
        float rz = m.m[2][j];
        out->m[0][j] = sgn * (rx / size.width + 0.5f * rz);
        out->m[1][j] = sgn * (0.5f * rz - ry / size.height);
        out->m[2][j] = sgn * rz;
    }
    return true;
}

static XrPosef pose_mul(XrPosef a, XrPosef b)
{
    fv_quat qa = qx(a.orientation);
    fv_quat q = fv_quat_normalize(fv_quat_mul(qa, qx(b.orientation)));
    fv_vec3 p = fv_v3_add((fv_vec3){a.position.x, a.position.y, a.position.z},
                          fv_quat_rotate(qa, (fv_vec3){b.position.x, b.position.y, b.position.z}));
    return (XrPosef){{q.x, q.y, q.z, q.w}, {p.x, p.y, p.z}};
}

/* The source slot of a swapchain's released image in eye e's binding array (added on first use), and in the frame's
 * list of the images it reads (held, acquired and released once each); -1 when either is full. */
static int source_slot(comp_job *j, int e, struct XrSwapchain_T *sc)
{
    uint32_t g = 0;
    while (g < j->nsrc && j->src[g].sc != sc) g++;
    for (uint32_t i = 0; i < j->eye_nsrc[e]; i++)
        if (j->eye_src[e][i] == g) return (int)i;
    if (j->eye_nsrc[e] == FV_XR_COMPOSE_MAX_SOURCES) return -1;
    if (g == j->nsrc) {
        if (j->nsrc == FV_XR_COMPOSE_MAX_SOURCES) return -1;
        j->src[j->nsrc++] = (source_ref){sc, (uint32_t)sc->last_released};
    }
    j->eye_src[e][j->eye_nsrc[e]] = (uint8_t)g;
    return (int)j->eye_nsrc[e]++;
}

static void set_layer(fv_xr_compose_layer *l, const mat3 *h, const XrSwapchainSubImage *si, uint32_t slot,
                      XrCompositionLayerFlags flags)
{
    const struct XrSwapchain_T *sc = si->swapchain;
    for (int r = 0; r < 3; r++) l->h[r] = (fv_xr_vec4){h->m[r][0], h->m[r][1], h->m[r][2], 0};
    float w = (float)sc->info.width, hh = (float)sc->info.height;
    l->uv_rect = (fv_xr_vec4){(float)si->imageRect.offset.x / w, (float)si->imageRect.offset.y / hh,
                              (float)si->imageRect.extent.width / w, (float)si->imageRect.extent.height / hh};
    if (sc->egl) { /* GL's rows are bottom-up (copied as they are): v runs from the rect's top row downwards */
        l->uv_rect.y += l->uv_rect.w;
        l->uv_rect.w = -l->uv_rect.w;
    }
    uint32_t f = 0;
    if (flags & XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT) f |= FV_XR_LAYER_ALPHA;
    if (flags & XR_COMPOSITION_LAYER_UNPREMULTIPLIED_ALPHA_BIT) f |= FV_XR_LAYER_UNPREMULTIPLIED;
    l->info = (fv_xr_uvec4){slot, si->imageArrayIndex, f, 0};
}

/* Map the layers onto the display eyes for the head at the frame's display time (instance lock held: the spaces). */
static void job_build(fv_xr_compositor *c, struct XrSession_T *s, const XrFrameEndInfo *info, comp_job *j)
{
    fv_xr_compose_block *blk = &j->blk;
    memset(blk, 0, sizeof *blk);
    blk->counts.z = c->width;
    blk->counts.w = c->height;
    j->nsrc = j->eye_nsrc[0] = j->eye_nsrc[1] = 0;
    j->app_device = s->vk.device;
    j->display_time = info->displayTime;
    j->display = s->display;
    j->target_vsync = s->target_vsync;
    j->predicted_ns = s->predicted_ns;
    j->gaze_sample_ns = s->stats.gaze_sample_ns;
    /* the display eyes in LOCAL at the frame's display time */
    XrPosef head;
    fv_xr_head_pose(s->inst, info->displayTime, &head);
    XrPosef eye_local[2];
    for (int e = 0; e < 2; e++) {
        const fv_eye_view *v = &c->input.eye[e];
        blk->tan[e] = (fv_xr_vec4){v->tan_left, v->tan_right, v->tan_up, v->tan_down};
        XrPosef off = {{0, 0, 0, 1}, {(e == 0 ? -0.5f : 0.5f) * 0.063f, 0, 0}};
        eye_local[e] = pose_mul(head, off);
    }
    uint32_t nl[2] = {0, 0};
    for (uint32_t i = 0; i < info->layerCount; i++) {
        const XrCompositionLayerBaseHeader *lh = info->layers[i];
        XrPosef space_local;
        XrSpaceLocationFlags sf = fv_xr_space_pose(lh->space, info->displayTime, &space_local, NULL);
        if (!(sf & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT)) continue; /* its space is not located: not shown */
        for (int e = 0; e < 2; e++) {
            if (nl[e] == FV_XR_COMPOSE_MAX_LAYERS) continue;
            const XrSwapchainSubImage *si;
            mat3 h;
            if (lh->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
                const XrCompositionLayerProjectionView *pv = &((const XrCompositionLayerProjection *)lh)->views[e];
                XrPosef view_local = pose_mul(space_local, pv->pose);
                h = projection_homography(&eye_local[e], &view_local, &pv->fov);
                si = &pv->subImage;
            } else {
                const XrCompositionLayerQuad *q = (const void *)lh;
                if ((q->eyeVisibility == XR_EYE_VISIBILITY_LEFT && e != 0) ||
                    (q->eyeVisibility == XR_EYE_VISIBILITY_RIGHT && e != 1))
                    continue;
                XrPosef quad_local = pose_mul(space_local, q->pose);
                if (!quad_homography(&eye_local[e], &quad_local, q->size, &h)) continue;
                si = &q->subImage;
            }
            int slot = source_slot(j, e, si->swapchain);
            if (slot < 0) continue; /* more distinct swapchains than the pass binds: the layer is dropped */
            set_layer(&blk->layer[e * FV_XR_COMPOSE_MAX_LAYERS + nl[e]], &h, si, (uint32_t)slot, lh->layerFlags);
            nl[e]++;
            /* quad views (XR_VARJO_quad_views): the eye's inset (view e + 2) over its wide view, blended at its edge */
            const XrCompositionLayerProjection *pl = (const void *)lh;
            if (lh->type != XR_TYPE_COMPOSITION_LAYER_PROJECTION || pl->viewCount != 4 ||
                nl[e] == FV_XR_COMPOSE_MAX_LAYERS)
                continue;
            const XrCompositionLayerProjectionView *iv = &pl->views[e + 2];
            XrPosef inset_local = pose_mul(space_local, iv->pose);
            h = projection_homography(&eye_local[e], &inset_local, &iv->fov);
            if ((slot = source_slot(j, e, iv->subImage.swapchain)) < 0) continue;
            fv_xr_compose_layer *il = &blk->layer[e * FV_XR_COMPOSE_MAX_LAYERS + nl[e]++];
            set_layer(il, &h, &iv->subImage, (uint32_t)slot, lh->layerFlags);
            fv_xr_quad_blend_band(&iv->fov, &il->h[0].w, &il->h[1].w);
            il->info.z |= FV_XR_LAYER_INSET;
        }
    }
    blk->counts.x = nl[0];
    blk->counts.y = nl[1];
    /* through the lens: few layers per eye (compose_interface.h) */
    j->through_lens = c->lens_in_compose && nl[0] <= FV_XR_COMPOSE_LENS_MAX_LAYERS &&
                      nl[1] <= FV_XR_COMPOSE_LENS_MAX_LAYERS;
    for (uint32_t e = 0; j->through_lens && e < 2; e++)
        for (uint32_t i = 0; i < nl[e]; i++)
            j->lens_src[e][i] = j->eye_src[e][blk->layer[e * FV_XR_COMPOSE_MAX_LAYERS + i].info.x];
    const fv_lens *lens = &c->input.quality.distort.lens;
    blk->lens_centre = (fv_xr_vec4){lens->centre_m[0][0], lens->centre_m[0][1], lens->centre_m[1][0],
                                    lens->centre_m[1][1]};
    blk->lens_k = (fv_xr_vec4){lens->k[0], lens->k[1], lens->k[2], lens->k[3]};
    blk->lens_aberration = (fv_xr_vec4){lens->aberration[0], lens->aberration[1], lens->aberration[2],
                                        lens->visible_r};
    blk->lens_geometry = (fv_xr_vec4){lens->viewport_m[0], lens->viewport_m[1], lens->warp_m, lens->tan_per_m};
}

/* The images a job reads are held (+1) or let go (-1). c->mu held. */
static void job_hold(comp_job *j, int d)
{
    for (uint32_t i = 0; i < j->nsrc; i++) j->src[i].sc->images[j->src[i].index].comp_refs += (uint32_t)d;
}

void fv_xr_compositor_submit(fv_xr_compositor *c, struct XrSession_T *s, const XrFrameEndInfo *info)
{
    comp_job j;
    job_build(c, s, info, &j);
    pthread_mutex_lock(&c->mu);
    if (c->has_pending) { /* the compositor has not begun the previous frame: this one replaces it */
        job_hold(&c->pending, -1);
        c->acc.replaced++;
        pthread_cond_broadcast(&c->cv);
    }
    c->pending = j;
    job_hold(&c->pending, +1);
    c->has_pending = true;
    pthread_cond_broadcast(&c->cv);
    pthread_mutex_unlock(&c->mu);
}

/* Composite a job: wait for the app's releases, record the compose and distortion passes and the target's
 * hand-over, submit, wait. The compositor's own thread (or a window's app thread), c->gpu_mu held. */
static fv_result job_run(fv_xr_compositor *c, comp_job *j, double *out_app_wait_ms, double *out_target_ms)
{
    *out_app_wait_ms = *out_target_ms = 0.0;
    if (!c->active) return FV_ERR_STATE;
    fv_vk *vk = c->vk;
    source_ref *src = j->src;
    uint32_t nsrc = j->nsrc;
    /* the app's releases must have run before fovea's device reads the images */
    int64_t t_wait = fv_xr_now_ns();
    for (uint32_t i = 0; i < nsrc; i++) {
        fv_xr_swapchain_image *im = &src[i].sc->images[src[i].index];
        if (!im->app_fence) continue; /* an EGL session's copy finished in xrReleaseSwapchainImage */
        VkResult vr = vkWaitForFences(j->app_device, 1, &im->app_fence, VK_TRUE, FV_XR_FENCE_TIMEOUT_NS);
        if (vr != VK_SUCCESS) {
            FV_ERROR(FV_XR_LOG, "the app's queue did not finish a swapchain release: %s", fv_vk_result_str(vr));
            return vr == VK_ERROR_DEVICE_LOST ? FV_ERR_DEVICE_LOST : FV_ERR_VULKAN;
        }
    }
    *out_app_wait_ms = (double)(fv_xr_now_ns() - t_wait) * 1e-6;
    if (nsrc == 0) return FV_OK; /* nothing to show (no located layer) */
    /* per eye: the compose pass for as many sources as that eye reads (through the lens or not), made on first use,
     * and its own descriptor set: eye e's sources (unused slots repeat the first: every element must be valid) */
    VkPipeline pipe[2];
    VkDescriptorImageInfo ii[2][FV_XR_COMPOSE_MAX_SOURCES];
    VkWriteDescriptorSet w[2];
    for (uint32_t e = 0; e < 2; e++) {
        /* through the lens: a source per layer (layer i's image bound as source i); else the eye's distinct ones */
        const uint8_t *table = j->through_lens ? j->lens_src[e] : j->eye_src[e];
        uint32_t count = j->through_lens ? (e ? j->blk.counts.y : j->blk.counts.x) : j->eye_nsrc[e];
        uint32_t n = count ? count : 1;
        VkPipeline *p = &c->compose[j->through_lens][n - 1];
        if (!*p) {
            uint32_t spec[2] = {[FV_XR_COMPOSE_SPEC_NSRC] = n, [FV_XR_COMPOSE_SPEC_LENS] = j->through_lens};
            char name[64];
            snprintf(name, sizeof name, "xr compose (%u sources%s)", n, j->through_lens ? ", through the lens" : "");
            fv_result pr = fv_vk_compute_pipeline(vk, fv_spv_compose_comp, sizeof fv_spv_compose_comp, c->cs.layout,
                                                  spec, 2, name, p);
            if (pr != FV_OK) return pr;
        }
        pipe[e] = *p;
        for (uint32_t i = 0; i < FV_XR_COMPOSE_MAX_SOURCES; i++) {
            const source_ref *r = &src[i < count ? table[i] : count ? table[0] : 0];
            ii[e][i] = (VkDescriptorImageInfo){c->sampler, r->sc->images[r->index].comp_view,
                                               VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        }
        w[e] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                                      .dstSet = c->cs.sets[e],
                                      .dstBinding = FV_XR_COMPOSE_BINDING_SOURCES,
                                      .descriptorCount = FV_XR_COMPOSE_MAX_SOURCES,
                                      .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                      .pImageInfo = ii[e]};
    }
    memcpy(c->block.mapped, &j->blk, sizeof j->blk); /* the previous frame's GPU work finished (its fence) */
    fv_result res = fv_vk_buffer_flush(vk, &c->block);
    if (res != FV_OK) return res;
    vkUpdateDescriptorSets(vk->device, 2, w, 0, NULL);

    VkCommandBuffer cmd = c->cmd;
    FV_VK_CHECK(vkResetCommandBuffer(cmd, 0));
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    FV_VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
    fv_vk_label_begin(vk, cmd, "xr composite");
    fv_vk_timer_reset(&c->timer, cmd, 0);
    int tp_compose = fv_vk_timer_begin(&c->timer, cmd, 0, "compose");
    /* acquire every source from the external owner (the app's release), in the layout the pass samples */
    VkImageMemoryBarrier acq[2 * FV_XR_COMPOSE_MAX_SOURCES], rel[FV_XR_COMPOSE_MAX_SOURCES]; /* two per source */
    uint32_t nacq = 0;
    for (uint32_t i = 0; i < nsrc; i++) {
        struct XrSwapchain_T *sc = src[i].sc;
        fv_xr_swapchain_image *im = &sc->images[src[i].index];
        if (im->owner == OWNER_EXTERNAL) {
            acq[nacq++] = fv_xr_image_barrier(sc, im->comp_image, im->ext_old, im->ext_new, VK_QUEUE_FAMILY_EXTERNAL,
                                  vk->queue_family, 0, VK_ACCESS_SHADER_READ_BIT);
            if (im->ext_new != VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
                acq[nacq++] = fv_xr_image_barrier(sc, im->comp_image, im->ext_new, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                      VK_QUEUE_FAMILY_IGNORED, VK_QUEUE_FAMILY_IGNORED, 0, VK_ACCESS_SHADER_READ_BIT);
        }
    }
    if (nacq)
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, NULL,
                             0, NULL, nacq, acq);
    fv_images_use(&c->images, cmd, FV_IMAGE_DISPLAY,
                  (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                    VK_ACCESS_SHADER_WRITE_BIT});
    for (uint32_t e = 0; e < 2; e++) { /* an eye per dispatch: its own sources (a sampler array is indexed by
                                        * constants; on lavapipe each source an eye could read is sampled per pixel) */
        fv_vk_compute_bind_pipeline(&c->cs, cmd, pipe[e], NULL, 0, e, &e);
        vkCmdDispatch(cmd, (c->width + FV_XR_COMPOSE_GROUP - 1) / FV_XR_COMPOSE_GROUP,
                      (c->height + FV_XR_COMPOSE_GROUP - 1) / FV_XR_COMPOSE_GROUP, 1);
    }
    fv_vk_timer_end(&c->timer, cmd, 0, tp_compose);
    /* give every source back to the external owner, in the layout the app renders in */
    uint32_t nrel = 0;
    for (uint32_t i = 0; i < nsrc; i++) {
        struct XrSwapchain_T *sc = src[i].sc;
        fv_xr_swapchain_image *im = &sc->images[src[i].index];
        if (im->owner != OWNER_EXTERNAL) continue;
        rel[nrel++] = fv_xr_image_barrier(sc, im->comp_image, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                              VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, vk->queue_family, VK_QUEUE_FAMILY_EXTERNAL,
                              0, 0);
    }
    if (nrel)
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0,
                             NULL, 0, NULL, nrel, rel);
    /* the renderer's post chain (lens pre-distortion), then the target's hand-over */
    c->input.frame_id = c->frame_id;
    c->input.t_photon_ns = j->display_time;
    if (!j->through_lens) fv_post_chain_record(c->post, cmd, &c->input, &c->timer, 0);
    fv_target_frame tf = {.vk = vk, .images = &c->images, .width = c->width, .height = c->height, .slot = 0,
                          .frame_id = c->frame_id, .cmd = cmd, .image_ready = c->sem_ready,
                          .frame_done = c->sem_done};
    bool wait_ready = false, signal_done = false;
    int64_t t_target = fv_xr_now_ns(); /* a window's acquire and present wait for its display, not for us */
    if (c->target->ops->begin && (res = c->target->ops->begin(c->target, &tf, &wait_ready, &signal_done)) != FV_OK)
        return res;
    *out_target_ms = (double)(fv_xr_now_ns() - t_target) * 1e-6;
    if (c->target->ops->record) c->target->ops->record(c->target, &tf);
    fv_vk_label_end(vk, cmd);
    FV_VK_CHECK(vkEndCommandBuffer(cmd));
    VkPipelineStageFlags ws = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                       .waitSemaphoreCount = wait_ready ? 1 : 0,
                       .pWaitSemaphores = &c->sem_ready,
                       .pWaitDstStageMask = &ws,
                       .commandBufferCount = 1,
                       .pCommandBuffers = &cmd,
                       .signalSemaphoreCount = signal_done ? 1 : 0,
                       .pSignalSemaphores = &c->sem_done};
    FV_VK_CHECK(vkQueueSubmit(vk->queue, 1, &si, c->fence));
    FV_VK_CHECK(vkWaitForFences(vk->device, 1, &c->fence, VK_TRUE, FV_XR_FENCE_TIMEOUT_NS));
    FV_VK_CHECK(vkResetFences(vk->device, 1, &c->fence));
    double ms[2] = {0, 0}, total = 0;
    char names[2][FV_VK_TIMER_NAME_MAX];
    if (fv_vk_timer_collect(&c->timer, vk, 0, ms, names, 2, &total) > 0) {
        c->gpu_ms_sum[0] += ms[0];
        c->gpu_ms_sum[1] += fv_post_chain_count(c->post) && !j->through_lens ? ms[1] : 0.0;
        c->gpu_frames++;
    }
    for (uint32_t i = 0; i < nsrc; i++) {
        fv_xr_swapchain_image *im = &src[i].sc->images[src[i].index];
        if (im->owner != OWNER_EXTERNAL) continue;
        im->ext_old = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL; /* the compositor's release is now the one in flight */
        im->ext_new = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    }
    t_target = fv_xr_now_ns();
    if (c->target->ops->end && (res = c->target->ops->end(c->target, &tf)) != FV_OK) return res;
    *out_target_ms += (double)(fv_xr_now_ns() - t_target) * 1e-6;
    c->frame_id++;
    return FV_OK;
}

/* Run the job taken from the queue (c->busy set by the caller, c->mu not held) and account for it. */
static void job_complete(fv_xr_compositor *c, comp_job *j)
{
    int64_t t0 = fv_xr_now_ns();
    double wait_ms = 0.0;
    pthread_mutex_lock(&c->gpu_mu);
    double target_ms = 0.0;
    fv_result res = job_run(c, j, &wait_ms, &target_ms);
    pthread_mutex_unlock(&c->gpu_mu);
    int64_t t_done = fv_xr_now_ns();
    double ms = (double)(t_done - t0) * 1e-6;
    pthread_mutex_lock(&c->mu);
    job_hold(j, -1);
    if (res == FV_OK) {
        c->acc.composited++;
        c->acc.through_lens += j->through_lens;
        c->acc.composite_ms_sum += ms;
        c->acc.app_gpu_wait_ms_sum += wait_ms;
        c->cpu_ms_ema = c->cpu_frames++ == 0 ? ms : c->cpu_ms_ema + 0.1 * (ms - c->cpu_ms_ema);
        fv_xr_pace_window_add(&c->pace, ms - wait_ms - target_ms); /* its own work: pacing (fv_xr_pace.h) */
        fv_xr_stats_present(&c->acc, j->display, t_done, j->target_vsync, j->predicted_ns, j->gaze_sample_ns);
    } else if (c->error == FV_OK) {
        c->error = res;
    }
    c->busy = false;
    pthread_cond_broadcast(&c->cv);
    pthread_mutex_unlock(&c->mu);
}

/* Take the queued job to run. c->mu held; false when none. */
static bool job_take(fv_xr_compositor *c)
{
    if (!c->has_pending || c->busy) return false;
    c->running = c->pending;
    c->has_pending = false;
    c->busy = true;
    return true;
}

/* The compositor thread (no window): composites queued frames until told to stop, the last queued one included. */
static void *comp_thread(void *arg)
{
    fv_xr_compositor *c = arg;
    pthread_mutex_lock(&c->mu);
    for (;;) {
        while (!c->has_pending && !c->stop) pthread_cond_wait(&c->cv, &c->mu);
        if (!job_take(c)) break; /* stopped with nothing queued */
        pthread_mutex_unlock(&c->mu);
        job_complete(c, &c->running);
        pthread_mutex_lock(&c->mu);
    }
    pthread_mutex_unlock(&c->mu);
    return NULL;
}

bool fv_xr_compositor_inline(const fv_xr_compositor *c) { return !c->threaded; }

void fv_xr_compositor_run_pending(fv_xr_compositor *c)
{
    if (!c || c->threaded) return;
    pthread_mutex_lock(&c->mu);
    while (c->busy) pthread_cond_wait(&c->cv, &c->mu); /* another thread's frame first (frames keep their order) */
    bool take = job_take(c);
    pthread_mutex_unlock(&c->mu);
    if (take) job_complete(c, &c->running);
}

void fv_xr_compositor_drain(fv_xr_compositor *c)
{
    if (!c) return;
    pthread_mutex_lock(&c->mu);
    for (;;) {
        if (!c->threaded && job_take(c)) { /* a window's frame its thread has not run yet: run it here */
            pthread_mutex_unlock(&c->mu);
            job_complete(c, &c->running);
            pthread_mutex_lock(&c->mu);
            continue;
        }
        if (!c->has_pending && !c->busy) break;
        pthread_cond_wait(&c->cv, &c->mu);
    }
    pthread_mutex_unlock(&c->mu);
}

void fv_xr_compositor_wait_queue_free(fv_xr_compositor *c)
{
    if (!c) return;
    int64_t end = fv_xr_now_ns() + (int64_t)FV_XR_FENCE_TIMEOUT_NS;
    struct timespec ts = {(time_t)(end / 1000000000), (long)(end % 1000000000)};
    pthread_mutex_lock(&c->mu);
    while (c->has_pending && c->active && pthread_cond_timedwait(&c->cv, &c->mu, &ts) != ETIMEDOUT) {
    }
    pthread_mutex_unlock(&c->mu);
}

bool fv_xr_compositor_image_idle(fv_xr_compositor *c, struct XrSwapchain_T *sc, uint32_t index, int64_t timeout_ns)
{
    if (!c || !sc->images) return true;
    if (timeout_ns < 0 || timeout_ns > (int64_t)FV_XR_FENCE_TIMEOUT_NS) timeout_ns = (int64_t)FV_XR_FENCE_TIMEOUT_NS;
    int64_t end = fv_xr_now_ns() + timeout_ns;
    struct timespec ts = {(time_t)(end / 1000000000), (long)(end % 1000000000)};
    pthread_mutex_lock(&c->mu);
    bool idle = true;
    while (sc->images[index].comp_refs > 0) {
        if (!c->threaded && job_take(c)) { /* a window's queued frame reads it: composite it now */
            pthread_mutex_unlock(&c->mu);
            job_complete(c, &c->running);
            pthread_mutex_lock(&c->mu);
            continue;
        }
        if (pthread_cond_timedwait(&c->cv, &c->mu, &ts) == ETIMEDOUT) {
            idle = sc->images[index].comp_refs == 0;
            break;
        }
    }
    pthread_mutex_unlock(&c->mu);
    return idle;
}

fv_result fv_xr_compositor_take(fv_xr_compositor *c, fv_xr_frame_stats *acc, double *out_cpu_ms_ema,
                                double *out_need_ms)
{
    pthread_mutex_lock(&c->mu);
    fv_xr_frame_stats *a = &c->acc;
    acc->composited += a->composited;
    acc->replaced += a->replaced;
    acc->through_lens += a->through_lens;
    acc->composite_ms_sum += a->composite_ms_sum;
    acc->app_gpu_wait_ms_sum += a->app_gpu_wait_ms_sum;
    acc->presented += a->presented;
    acc->missed += a->missed;
    acc->predicted_error_ms_sum += a->predicted_error_ms_sum;
    if (a->predicted_minus_photon_ns_max > acc->predicted_minus_photon_ns_max)
        acc->predicted_minus_photon_ns_max = a->predicted_minus_photon_ns_max;
    acc->gaze_photon_frames += a->gaze_photon_frames;
    acc->gaze_photon_ms_sum += a->gaze_photon_ms_sum;
    if (a->gaze_photon_ms_max > acc->gaze_photon_ms_max) acc->gaze_photon_ms_max = a->gaze_photon_ms_max;
    memset(a, 0, sizeof *a);
    *out_cpu_ms_ema = c->cpu_ms_ema;
    if (!fv_xr_pace_window_need(&c->pace, out_need_ms)) *out_need_ms = -1.0;
    fv_result e = c->error;
    c->error = FV_OK;
    pthread_mutex_unlock(&c->mu);
    return e;
}

void fv_xr_compositor_pace_idle(fv_xr_compositor *c)
{
    pthread_mutex_lock(&c->mu);
    fv_xr_pace_window_add(&c->pace, 0.0);
    pthread_mutex_unlock(&c->mu);
}

void fv_xr_compositor_gpu_lock(fv_xr_compositor *c) { pthread_mutex_lock(&c->gpu_mu); }
void fv_xr_compositor_gpu_unlock(fv_xr_compositor *c) { pthread_mutex_unlock(&c->gpu_mu); }

void fv_xr_compositor_gpu_ms(const fv_xr_compositor *c, double *out_compose_ms, double *out_distort_ms)
{
    double n = c && c->gpu_frames ? (double)c->gpu_frames : 0.0;
    *out_compose_ms = n > 0 ? c->gpu_ms_sum[0] / n : 0.0;
    *out_distort_ms = n > 0 ? c->gpu_ms_sum[1] / n : 0.0;
}
