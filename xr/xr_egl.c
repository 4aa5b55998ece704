/* @brief OpenGL / OpenGL ES apps through EGL (XR_MNDX_egl_enable with XR_KHR_opengl_enable or
 * XR_KHR_opengl_es_enable): the graphics requirements, the session's EGL binding checked (display, config, context,
 * client API and version), swapchain formats as GL internal formats, the swapchain images as GL textures created in
 * the app's context, and their hand-over to fovea's Vulkan compositor, one of two ways:
 *  - shared memory, where the GL driver has GL_EXT_memory_object_fd and is the compositor's device and driver (the
 *    UUIDs match; lavapipe + llvmpipe do): each texture's storage is the compositor's image's memory, imported from
 *    its opaque fd. At xrReleaseSwapchainImage glFinish (llvmpipe has no GL_EXT_semaphore_fd) and fovea's queue
 *    acquires the image from VK_QUEUE_FAMILY_EXTERNAL (GENERAL -> the sampled layout); at the next acquire of that
 *    image it is released back to the external side in GENERAL.
 *  - a copy otherwise (or with FOVEA_XR_EGL_COPY=1): at xrReleaseSwapchainImage the image is read back
 *    (glReadPixels, which returns after the app's GL work on it has finished) into a host-visible staging buffer of
 *    fovea's device and copied into the compositor's image.
 * Either way GL's rows go bottom-up in the image; the compositor samples GL swapchains with v flipped, so a layer's
 * imageRect (bottom-left origin for GL) maps unchanged. Every GL and EGL call goes through the binding's
 * getProcAddress: the runtime links neither libEGL nor libGL. The GL context is made current on the calling thread
 * only when it is not already (and the previous one restored). */
#include <stdlib.h>
#include <string.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GL_GLES_PROTOTYPES 0
#include <GLES3/gl32.h>
#include <GLES2/gl2ext.h>
#include <unistd.h>

#include "fv_vk.h"
#include "xr_internal.h"

/* The GL versions fovea accepts: GLES 3.0 (glTexStorage, glReadPixels of RGBA8 and sRGB textures) up to 3.2; desktop
 * GL 4.2 (glTexStorage core) up to 4.6. */
#define FV_GLES_MIN XR_MAKE_VERSION(3, 0, 0)
#define FV_GLES_MAX XR_MAKE_VERSION(3, 2, 0)
#define FV_GL_MIN XR_MAKE_VERSION(4, 2, 0)
#define FV_GL_MAX XR_MAKE_VERSION(4, 6, 0)

typedef struct gl_fns {
    PFNGLGETERRORPROC GetError;
    PFNGLGETINTEGERVPROC GetIntegerv;
    PFNGLGETSTRINGIPROC GetStringi;
    PFNGLGENTEXTURESPROC GenTextures;
    PFNGLDELETETEXTURESPROC DeleteTextures;
    PFNGLBINDTEXTUREPROC BindTexture;
    PFNGLTEXSTORAGE2DPROC TexStorage2D;
    PFNGLTEXSTORAGE3DPROC TexStorage3D;
    PFNGLGENFRAMEBUFFERSPROC GenFramebuffers;
    PFNGLDELETEFRAMEBUFFERSPROC DeleteFramebuffers;
    PFNGLBINDFRAMEBUFFERPROC BindFramebuffer;
    PFNGLFRAMEBUFFERTEXTURE2DPROC FramebufferTexture2D;
    PFNGLFRAMEBUFFERTEXTURELAYERPROC FramebufferTextureLayer;
    PFNGLCHECKFRAMEBUFFERSTATUSPROC CheckFramebufferStatus;
    PFNGLREADBUFFERPROC ReadBuffer;
    PFNGLPIXELSTOREIPROC PixelStorei;
    PFNGLBINDBUFFERPROC BindBuffer;
    PFNGLREADPIXELSPROC ReadPixels;
    PFNGLFINISHPROC Finish;
    PFNGLTEXPARAMETERIPROC TexParameteri;
    /* GL_EXT_memory_object(_fd): NULL where the driver has none */
    PFNGLGETUNSIGNEDBYTEVEXTPROC GetUnsignedBytevEXT;
    PFNGLCREATEMEMORYOBJECTSEXTPROC CreateMemoryObjectsEXT;
    PFNGLDELETEMEMORYOBJECTSEXTPROC DeleteMemoryObjectsEXT;
    PFNGLMEMORYOBJECTPARAMETERIVEXTPROC MemoryObjectParameterivEXT;
    PFNGLIMPORTMEMORYFDEXTPROC ImportMemoryFdEXT;
    PFNGLTEXSTORAGEMEM2DEXTPROC TexStorageMem2DEXT;
    PFNGLTEXSTORAGEMEM3DEXTPROC TexStorageMem3DEXT;
} gl_fns;

struct fv_xr_egl {
    EGLDisplay dpy;
    EGLConfig cfg;
    EGLContext ctx;
    bool gles;              /* an OpenGL ES context (else desktop OpenGL) */
    XrVersion version;      /* the context's GL version */
    bool has_memory_object_fd; /* GL_EXT_memory_object_fd */
    bool share;             /* images shared by memory: the extension, the same device and driver (UUIDs), not
                             * FOVEA_XR_EGL_COPY=1 */
    PFNEGLGETCURRENTCONTEXTPROC GetCurrentContext;
    PFNEGLGETCURRENTDISPLAYPROC GetCurrentDisplay;
    PFNEGLGETCURRENTSURFACEPROC GetCurrentSurface;
    PFNEGLMAKECURRENTPROC MakeCurrent;
    PFNEGLQUERYCONTEXTPROC QueryContext;
    PFNEGLGETCONFIGATTRIBPROC GetConfigAttrib;
    PFNEGLGETERRORPROC GetError;
    gl_fns gl;
};

struct fv_xr_egl_swapchain {
    GLuint tex[FV_XR_MAX_SWAPCHAIN_IMAGES];
    GLuint mem[FV_XR_MAX_SWAPCHAIN_IMAGES]; /* shared: GL memory objects of the compositor's images' memory */
    bool shared;            /* the textures are the compositor's images (else the copy) */
    bool with_comp[FV_XR_MAX_SWAPCHAIN_IMAGES]; /* shared: fovea's queue holds it (released, not re-acquired) */
    GLenum target;          /* GL_TEXTURE_2D, or GL_TEXTURE_2D_ARRAY for arraySize > 1 */
    GLuint fbo;             /* the read framebuffer of the copy */
    fv_vk_buffer staging;   /* one image's texels, every layer (host-visible, on fovea's device) */
    size_t layer_bytes;
};

/* ---- formats ------------------------------------------------------------------------------------------------- */
typedef struct gl_format {
    int64_t gl;
    VkFormat vk;
} gl_format;

/* GL internal formats and the compositor's formats they are copied into, preferred first (sRGB, as the spec
 * recommends); depth formats stay on the GL side (the compositor does not read depth). */
static const gl_format g_formats[] = {
    {GL_SRGB8_ALPHA8, VK_FORMAT_R8G8B8A8_SRGB},   {GL_RGBA8, VK_FORMAT_R8G8B8A8_UNORM},
    {GL_DEPTH_COMPONENT32F, VK_FORMAT_D32_SFLOAT}, {GL_DEPTH_COMPONENT16, VK_FORMAT_D16_UNORM},
    {GL_DEPTH24_STENCIL8, VK_FORMAT_D24_UNORM_S8_UINT}, {GL_DEPTH32F_STENCIL8, VK_FORMAT_D32_SFLOAT_S8_UINT},
};
#define N_FORMATS (sizeof g_formats / sizeof g_formats[0])

VkFormat fv_xr_egl_format_vk(int64_t gl_format)
{
    for (size_t i = 0; i < N_FORMATS; i++)
        if (g_formats[i].gl == gl_format) return g_formats[i].vk;
    return VK_FORMAT_UNDEFINED;
}

uint32_t fv_xr_egl_formats(fv_xr_compositor *c, int64_t *out, uint32_t cap)
{
    int64_t vk[32];
    uint32_t nvk = fv_xr_compositor_formats(c, vk, 32), n = 0;
    if (nvk > 32) nvk = 32;
    for (size_t i = 0; i < N_FORMATS; i++) {
        bool ok = false;
        for (uint32_t j = 0; j < nvk; j++) ok |= vk[j] == (int64_t)g_formats[i].vk;
        if (!ok) continue;
        if (out && n < cap) out[n] = g_formats[i].gl;
        n++;
    }
    return n;
}

/* ---- graphics requirements ----------------------------------------------------------------------------------- */
/* The compositor's device must exist before a session (its formats); created here as the Vulkan path does. */
static XrResult requirements(XrInstance instance, XrSystemId system, bool gles, XrVersion *min, XrVersion *max)
{
    struct XrInstance_T *inst = fv_xr_instance_check(instance);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (system != FV_XR_SYSTEM_ID) return XR_ERROR_SYSTEM_INVALID;
    pthread_mutex_lock(&inst->lock);
    XrResult r = XR_SUCCESS;
    if (!inst->comp) {
        fv_result res = fv_xr_compositor_create(inst, &inst->comp);
        if (res != FV_OK) {
            FV_ERROR(FV_XR_LOG, "no Vulkan device for the compositor: %s", fv_result_str(res));
            r = XR_ERROR_RUNTIME_FAILURE;
        }
    }
    if (r == XR_SUCCESS) {
        *min = gles ? FV_GLES_MIN : FV_GL_MIN;
        *max = gles ? FV_GLES_MAX : FV_GL_MAX;
        if (gles) inst->gl_requirements_queried.gles = true;
        else inst->gl_requirements_queried.gl = true;
    }
    pthread_mutex_unlock(&inst->lock);
    return r;
}

FV_XR_DECL(xrGetOpenGLGraphicsRequirementsKHR)(XrInstance instance, XrSystemId system,
                                               XrGraphicsRequirementsOpenGLKHR *req)
{
    if (!req || req->type != XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR) return XR_ERROR_VALIDATION_FAILURE;
    return requirements(instance, system, false, &req->minApiVersionSupported, &req->maxApiVersionSupported);
}

FV_XR_DECL(xrGetOpenGLESGraphicsRequirementsKHR)(XrInstance instance, XrSystemId system,
                                                 XrGraphicsRequirementsOpenGLESKHR *req)
{
    if (!req || req->type != XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_ES_KHR) return XR_ERROR_VALIDATION_FAILURE;
    return requirements(instance, system, true, &req->minApiVersionSupported, &req->maxApiVersionSupported);
}

/* ---- the app's context ------------------------------------------------------------------------------------- */
typedef struct egl_saved {
    EGLDisplay dpy;
    EGLSurface draw, read;
    EGLContext ctx;
    bool switched;
} egl_saved;

/* Make the app's context current on this thread unless it is; false (logged) when EGL refuses (the context is
 * current on another thread: EGL_BAD_ACCESS). */
static bool egl_enter(struct fv_xr_egl *e, egl_saved *sv, const char *call)
{
    sv->switched = false;
    sv->ctx = e->GetCurrentContext();
    if (sv->ctx == e->ctx) return true;
    sv->dpy = e->GetCurrentDisplay();
    sv->draw = e->GetCurrentSurface(EGL_DRAW);
    sv->read = e->GetCurrentSurface(EGL_READ);
    if (!e->MakeCurrent(e->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, e->ctx)) {
        FV_ERROR(FV_XR_LOG, "%s: cannot make the session's EGL context current on this thread (EGL error 0x%x; is it "
                            "current on another thread?)", call, (unsigned)e->GetError());
        return false;
    }
    sv->switched = true;
    return true;
}

static void egl_leave(struct fv_xr_egl *e, const egl_saved *sv)
{
    if (!sv->switched) return;
    if (sv->ctx == EGL_NO_CONTEXT) e->MakeCurrent(e->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    else e->MakeCurrent(sv->dpy, sv->draw, sv->read, sv->ctx);
}

/* GL errors raised by the runtime's own calls (the app's pending errors were taken before: see gl_clear_errors). */
static bool gl_ok(struct fv_xr_egl *e, const char *what)
{
    GLenum err = e->gl.GetError(), first = err;
    while (err != GL_NO_ERROR) err = e->gl.GetError();
    if (first == GL_NO_ERROR) return true;
    FV_ERROR(FV_XR_LOG, "%s: GL error 0x%x", what, (unsigned)first);
    return false;
}

/* GL keeps one error flag per kind, so the runtime's checks would report the app's pending errors as its own: those
 * are taken first (the app can then no longer read them) and logged at debug level. */
static void gl_clear_errors(struct fv_xr_egl *e)
{
    GLenum err;
    int n = 0;
    while ((err = e->gl.GetError()) != GL_NO_ERROR && n++ < 16)
        FV_LOG(FV_LOG_LEVEL_DEBUG, FV_XR_LOG, "the app's pending GL error 0x%x (taken by the runtime)", (unsigned)err);
}

#define LOAD(dst, type, name)                                                                                          \
    do {                                                                                                               \
        dst = (type)b->getProcAddress(name);                                                                           \
        if (!dst) {                                                                                                    \
            FV_ERROR(FV_XR_LOG, "xrCreateSession: the EGL binding's getProcAddress has no %s", name);                  \
            goto invalid;                                                                                              \
        }                                                                                                              \
    } while (0)

XrResult fv_xr_egl_session_create(struct XrInstance_T *inst, const void *binding, struct fv_xr_egl **out)
{
    const XrGraphicsBindingEGLMNDX *b = binding;
    *out = NULL;
    if (!inst->ext.egl) {
        FV_ERROR(FV_XR_LOG, "xrCreateSession: XrGraphicsBindingEGLMNDX given but %s is not enabled",
                 XR_MNDX_EGL_ENABLE_EXTENSION_NAME);
        return XR_ERROR_VALIDATION_FAILURE;
    }
    if (!b->getProcAddress || b->display == EGL_NO_DISPLAY || b->context == EGL_NO_CONTEXT) {
        FV_ERROR(FV_XR_LOG, "xrCreateSession: XrGraphicsBindingEGLMNDX needs getProcAddress, display and context "
                            "(got %p, %p, %p)", (void *)(uintptr_t)b->getProcAddress, b->display, b->context);
        return XR_ERROR_VALIDATION_FAILURE;
    }
    struct fv_xr_egl *e = calloc(1, sizeof *e);
    if (!e) return XR_ERROR_OUT_OF_MEMORY;
    e->dpy = b->display;
    e->cfg = b->config;
    e->ctx = b->context;
    LOAD(e->GetCurrentContext, PFNEGLGETCURRENTCONTEXTPROC, "eglGetCurrentContext");
    LOAD(e->GetCurrentDisplay, PFNEGLGETCURRENTDISPLAYPROC, "eglGetCurrentDisplay");
    LOAD(e->GetCurrentSurface, PFNEGLGETCURRENTSURFACEPROC, "eglGetCurrentSurface");
    LOAD(e->MakeCurrent, PFNEGLMAKECURRENTPROC, "eglMakeCurrent");
    LOAD(e->QueryContext, PFNEGLQUERYCONTEXTPROC, "eglQueryContext");
    LOAD(e->GetConfigAttrib, PFNEGLGETCONFIGATTRIBPROC, "eglGetConfigAttrib");
    LOAD(e->GetError, PFNEGLGETERRORPROC, "eglGetError");
    /* the context on the display, its client API, and the config it was made with */
    EGLint api = 0, ctx_config = 0, cfg_id = 0;
    if (!e->QueryContext(e->dpy, e->ctx, EGL_CONTEXT_CLIENT_TYPE, &api)) {
        FV_ERROR(FV_XR_LOG, "xrCreateSession: the EGL binding's context is not a context of its display (EGL error "
                            "0x%x)", (unsigned)e->GetError());
        goto invalid;
    }
    if (api != EGL_OPENGL_ES_API && api != EGL_OPENGL_API) {
        FV_ERROR(FV_XR_LOG, "xrCreateSession: the EGL context's client API 0x%x is neither OpenGL nor OpenGL ES",
                 (unsigned)api);
        goto invalid;
    }
    e->gles = api == EGL_OPENGL_ES_API;
    if (e->cfg != (EGLConfig)0) { /* EGL_NO_CONFIG_KHR: a context made without a config (EGL_KHR_no_config_context) */
        if (!e->GetConfigAttrib(e->dpy, e->cfg, EGL_CONFIG_ID, &cfg_id)) {
            FV_ERROR(FV_XR_LOG, "xrCreateSession: the EGL binding's config is not a config of its display (EGL error "
                                "0x%x)", (unsigned)e->GetError());
            goto invalid;
        }
        if (e->QueryContext(e->dpy, e->ctx, EGL_CONFIG_ID, &ctx_config) && ctx_config != 0 && ctx_config != cfg_id) {
            FV_ERROR(FV_XR_LOG, "xrCreateSession: the EGL binding's config (id %d) is not the one its context was "
                                "created with (id %d)", cfg_id, ctx_config);
            goto invalid;
        }
    }
    if (e->gles ? !inst->ext.opengl_es : !inst->ext.opengl) {
        FV_ERROR(FV_XR_LOG, "xrCreateSession: an %s context needs %s enabled", e->gles ? "OpenGL ES" : "OpenGL",
                 e->gles ? XR_KHR_OPENGL_ES_ENABLE_EXTENSION_NAME : XR_KHR_OPENGL_ENABLE_EXTENSION_NAME);
        free(e);
        return XR_ERROR_GRAPHICS_DEVICE_INVALID;
    }
    if (e->gles ? !inst->gl_requirements_queried.gles : !inst->gl_requirements_queried.gl) {
        free(e);
        return XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING;
    }
    gl_fns *g = &e->gl;
    LOAD(g->GetError, PFNGLGETERRORPROC, "glGetError");
    LOAD(g->GetIntegerv, PFNGLGETINTEGERVPROC, "glGetIntegerv");
    LOAD(g->GetStringi, PFNGLGETSTRINGIPROC, "glGetStringi");
    LOAD(g->GenTextures, PFNGLGENTEXTURESPROC, "glGenTextures");
    LOAD(g->DeleteTextures, PFNGLDELETETEXTURESPROC, "glDeleteTextures");
    LOAD(g->BindTexture, PFNGLBINDTEXTUREPROC, "glBindTexture");
    LOAD(g->TexStorage2D, PFNGLTEXSTORAGE2DPROC, "glTexStorage2D");
    LOAD(g->TexStorage3D, PFNGLTEXSTORAGE3DPROC, "glTexStorage3D");
    LOAD(g->GenFramebuffers, PFNGLGENFRAMEBUFFERSPROC, "glGenFramebuffers");
    LOAD(g->DeleteFramebuffers, PFNGLDELETEFRAMEBUFFERSPROC, "glDeleteFramebuffers");
    LOAD(g->BindFramebuffer, PFNGLBINDFRAMEBUFFERPROC, "glBindFramebuffer");
    LOAD(g->FramebufferTexture2D, PFNGLFRAMEBUFFERTEXTURE2DPROC, "glFramebufferTexture2D");
    LOAD(g->FramebufferTextureLayer, PFNGLFRAMEBUFFERTEXTURELAYERPROC, "glFramebufferTextureLayer");
    LOAD(g->CheckFramebufferStatus, PFNGLCHECKFRAMEBUFFERSTATUSPROC, "glCheckFramebufferStatus");
    LOAD(g->ReadBuffer, PFNGLREADBUFFERPROC, "glReadBuffer");
    LOAD(g->PixelStorei, PFNGLPIXELSTOREIPROC, "glPixelStorei");
    LOAD(g->BindBuffer, PFNGLBINDBUFFERPROC, "glBindBuffer");
    LOAD(g->ReadPixels, PFNGLREADPIXELSPROC, "glReadPixels");
    LOAD(g->Finish, PFNGLFINISHPROC, "glFinish");
    LOAD(g->TexParameteri, PFNGLTEXPARAMETERIPROC, "glTexParameteri");
    g->GetUnsignedBytevEXT = (PFNGLGETUNSIGNEDBYTEVEXTPROC)b->getProcAddress("glGetUnsignedBytevEXT");
    g->CreateMemoryObjectsEXT = (PFNGLCREATEMEMORYOBJECTSEXTPROC)b->getProcAddress("glCreateMemoryObjectsEXT");
    g->DeleteMemoryObjectsEXT = (PFNGLDELETEMEMORYOBJECTSEXTPROC)b->getProcAddress("glDeleteMemoryObjectsEXT");
    g->MemoryObjectParameterivEXT =
        (PFNGLMEMORYOBJECTPARAMETERIVEXTPROC)b->getProcAddress("glMemoryObjectParameterivEXT");
    g->ImportMemoryFdEXT = (PFNGLIMPORTMEMORYFDEXTPROC)b->getProcAddress("glImportMemoryFdEXT");
    g->TexStorageMem2DEXT = (PFNGLTEXSTORAGEMEM2DEXTPROC)b->getProcAddress("glTexStorageMem2DEXT");
    g->TexStorageMem3DEXT = (PFNGLTEXSTORAGEMEM3DEXTPROC)b->getProcAddress("glTexStorageMem3DEXT");
    /* the context's version against the requirements the app was given */
    egl_saved sv;
    if (!egl_enter(e, &sv, "xrCreateSession")) goto invalid;
    GLint major = 0, minor = 0, next = 0;
    g->GetIntegerv(GL_MAJOR_VERSION, &major);
    g->GetIntegerv(GL_MINOR_VERSION, &minor);
    g->GetIntegerv(GL_NUM_EXTENSIONS, &next);
    for (GLint i = 0; i < next; i++) {
        const GLubyte *name = g->GetStringi(GL_EXTENSIONS, (GLuint)i);
        if (name && !strcmp((const char *)name, "GL_EXT_memory_object_fd")) e->has_memory_object_fd = true;
    }
    /* shared memory needs the same device and driver on both sides (GL_EXT_memory_object's UUIDs = Vulkan's) */
    bool same_device = false;
    if (e->has_memory_object_fd && g->GetUnsignedBytevEXT && g->CreateMemoryObjectsEXT && g->DeleteMemoryObjectsEXT &&
        g->MemoryObjectParameterivEXT && g->ImportMemoryFdEXT && g->TexStorageMem2DEXT && g->TexStorageMem3DEXT) {
        GLubyte dev[GL_UUID_SIZE_EXT] = {0}, drv[GL_UUID_SIZE_EXT] = {0};
        g->GetUnsignedBytevEXT(GL_DEVICE_UUID_EXT, dev);
        g->GetUnsignedBytevEXT(GL_DRIVER_UUID_EXT, drv);
        VkPhysicalDeviceIDProperties id = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES};
        VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &id};
        vkGetPhysicalDeviceProperties2(fv_xr_compositor_phys(inst->comp), &p2);
        same_device = !memcmp(dev, id.deviceUUID, VK_UUID_SIZE) && !memcmp(drv, id.driverUUID, VK_UUID_SIZE);
    }
    const char *copy = getenv("FOVEA_XR_EGL_COPY");
    if (copy && *copy && strcmp(copy, "0") != 0 && strcmp(copy, "1") != 0)
        FV_ERROR(FV_XR_LOG, "FOVEA_XR_EGL_COPY='%s': expected 0 or 1; sharing where possible", copy);
    e->share = same_device && !(copy && !strcmp(copy, "1"));
    gl_clear_errors(e);
    egl_leave(e, &sv);
    e->version = XR_MAKE_VERSION(major, minor, 0);
    XrVersion lo = e->gles ? FV_GLES_MIN : FV_GL_MIN, hi = e->gles ? FV_GLES_MAX : FV_GL_MAX;
    if (e->version < lo || XR_MAKE_VERSION(major, 0, 0) > XR_MAKE_VERSION(XR_VERSION_MAJOR(hi), 0, 0)) {
        FV_ERROR(FV_XR_LOG, "xrCreateSession: the EGL context is %s %d.%d; fovea needs %u.%u to %u.x",
                 e->gles ? "OpenGL ES" : "OpenGL", major, minor, (unsigned)XR_VERSION_MAJOR(lo),
                 (unsigned)XR_VERSION_MINOR(lo), (unsigned)XR_VERSION_MAJOR(hi));
        goto invalid;
    }
    FV_INFO(FV_XR_LOG, "EGL session: %s %d.%d; images reach the compositor %s", e->gles ? "OpenGL ES" : "OpenGL", major,
            minor,
            e->share ? "by shared memory (GL_EXT_memory_object_fd)"
            : same_device ? "by a copy (FOVEA_XR_EGL_COPY=1)"
                          : "by a copy (no GL_EXT_memory_object_fd on the compositor's device and driver)");
    *out = e;
    return XR_SUCCESS;
invalid:
    free(e);
    return XR_ERROR_GRAPHICS_DEVICE_INVALID;
}
#undef LOAD

void fv_xr_egl_session_destroy(struct fv_xr_egl **pe)
{
    if (!pe) return;
    free(*pe);
    *pe = NULL;
}

/* ---- swapchains ------------------------------------------------------------------------------------------------ */
static void swapchain_gl_free(struct fv_xr_egl *e, struct fv_xr_egl_swapchain *g, uint32_t count)
{
    if (g->tex[0]) e->gl.DeleteTextures((GLsizei)count, g->tex);
    for (uint32_t i = 0; i < count; i++)
        if (g->mem[i]) e->gl.DeleteMemoryObjectsEXT(1, &g->mem[i]);
    if (g->fbo) e->gl.DeleteFramebuffers(1, &g->fbo);
    memset(g->tex, 0, sizeof g->tex);
    memset(g->mem, 0, sizeof g->mem);
    g->fbo = 0;
}

/* Texture i on the compositor's image's memory (GL_EXT_memory_object_fd): the exported fd imported as a dedicated
 * memory object (GL owns the fd once the import succeeded), the texture's storage on it with optimal tiling, the
 * same levels, layers and format as the Vulkan image. Context current, texture bound. */
static bool import_texture(struct fv_xr_egl *e, struct XrSwapchain_T *sc, struct fv_xr_egl_swapchain *g, uint32_t i)
{
    const XrSwapchainCreateInfo *ci = &sc->info;
    uint64_t size = 0;
    int fd = fv_xr_swapchain_export_fd(sc->session->inst->comp, sc, i, &size);
    if (fd < 0) return false;
    e->gl.CreateMemoryObjectsEXT(1, &g->mem[i]);
    GLint dedicated = GL_TRUE;
    e->gl.MemoryObjectParameterivEXT(g->mem[i], GL_DEDICATED_MEMORY_OBJECT_EXT, &dedicated);
    e->gl.ImportMemoryFdEXT(g->mem[i], size, GL_HANDLE_TYPE_OPAQUE_FD_EXT, fd);
    if (!gl_ok(e, "xrCreateSwapchain: importing the compositor's image memory")) {
        close(fd); /* a failed import leaves the fd with us */
        return false;
    }
    e->gl.TexParameteri(g->target, GL_TEXTURE_TILING_EXT, GL_OPTIMAL_TILING_EXT);
    if (g->target == GL_TEXTURE_2D)
        e->gl.TexStorageMem2DEXT(g->target, (GLsizei)ci->mipCount, (GLenum)ci->format, (GLsizei)ci->width,
                                 (GLsizei)ci->height, g->mem[i], 0);
    else
        e->gl.TexStorageMem3DEXT(g->target, (GLsizei)ci->mipCount, (GLenum)ci->format, (GLsizei)ci->width,
                                 (GLsizei)ci->height, (GLsizei)ci->arraySize, g->mem[i], 0);
    return gl_ok(e, "xrCreateSwapchain: the texture on the compositor's image memory");
}

/* The GL textures: on the compositor's images' memory (g->shared), or their own storage. Context current. */
static bool create_textures(struct fv_xr_egl *e, struct XrSwapchain_T *sc, struct fv_xr_egl_swapchain *g)
{
    const XrSwapchainCreateInfo *ci = &sc->info;
    GLint prev = 0;
    e->gl.GetIntegerv(g->target == GL_TEXTURE_2D ? GL_TEXTURE_BINDING_2D : GL_TEXTURE_BINDING_2D_ARRAY, &prev);
    e->gl.GenTextures((GLsizei)sc->image_count, g->tex);
    bool ok = true;
    for (uint32_t i = 0; i < sc->image_count && ok; i++) {
        e->gl.BindTexture(g->target, g->tex[i]);
        if (g->shared) ok = import_texture(e, sc, g, i);
        else if (g->target == GL_TEXTURE_2D)
            e->gl.TexStorage2D(g->target, (GLsizei)ci->mipCount, (GLenum)ci->format, (GLsizei)ci->width,
                               (GLsizei)ci->height);
        else
            e->gl.TexStorage3D(g->target, (GLsizei)ci->mipCount, (GLenum)ci->format, (GLsizei)ci->width,
                               (GLsizei)ci->height, (GLsizei)ci->arraySize);
    }
    e->gl.BindTexture(g->target, (GLuint)prev);
    if (ok && !sc->depth && !g->shared) e->gl.GenFramebuffers(1, &g->fbo);
    return gl_ok(e, "xrCreateSwapchain: creating the GL textures") && ok;
}

/* One image barrier over every level and layer of a compositor image, on fovea's queue, waited for. */
static XrResult comp_barrier(struct XrSwapchain_T *sc, uint32_t index, VkImageLayout from, VkImageLayout to,
                             uint32_t src_family, uint32_t dst_family, VkAccessFlags dst_access,
                             VkPipelineStageFlags src_stage, VkPipelineStageFlags dst_stage)
{
    fv_xr_compositor *c = sc->session->inst->comp;
    fv_vk *vk = fv_xr_compositor_vk(c);
    VkCommandBuffer cmd;
    fv_xr_compositor_gpu_lock(c); /* the device's pool and queue, shared with the compositor thread */
    if (fv_vk_oneshot_begin(vk, "xr egl hand-over", &cmd) != FV_OK) {
        fv_xr_compositor_gpu_unlock(c);
        return XR_ERROR_RUNTIME_FAILURE;
    }
    VkImageMemoryBarrier b = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                              .dstAccessMask = dst_access,
                              .oldLayout = from,
                              .newLayout = to,
                              .srcQueueFamilyIndex = src_family == UINT32_MAX ? vk->queue_family : src_family,
                              .dstQueueFamilyIndex = dst_family == UINT32_MAX ? vk->queue_family : dst_family,
                              .image = fv_xr_swapchain_comp_image(sc, index),
                              .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0,
                                                   VK_REMAINING_ARRAY_LAYERS}};
    vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, NULL, 0, NULL, 1, &b);
    fv_result res = fv_vk_oneshot_end(vk, cmd);
    fv_xr_compositor_gpu_unlock(c);
    if (res == FV_ERR_DEVICE_LOST) return XR_ERROR_SESSION_LOST;
    return res == FV_OK ? XR_SUCCESS : XR_ERROR_RUNTIME_FAILURE;
}
#define FAMILY_COMP UINT32_MAX /* comp_barrier: the compositor's queue family */

XrResult fv_xr_egl_swapchain_create(struct XrSession_T *s, struct XrSwapchain_T *sc)
{
    struct fv_xr_egl *e = s->egl;
    struct fv_xr_egl_swapchain *g = calloc(1, sizeof *g);
    if (!g) return XR_ERROR_OUT_OF_MEMORY;
    const XrSwapchainCreateInfo *ci = &sc->info;
    /* the create info was checked against the runtime's limits (mips, size, layers) by xrCreateSwapchain */
    egl_saved sv;
    if (!egl_enter(e, &sv, "xrCreateSwapchain")) {
        free(g);
        return XR_ERROR_RUNTIME_FAILURE;
    }
    gl_clear_errors(e);
    g->target = ci->arraySize > 1 ? GL_TEXTURE_2D_ARRAY : GL_TEXTURE_2D;
    g->shared = e->share && !sc->depth;
    bool ok = create_textures(e, sc, g);
    if (!ok && g->shared) { /* the driver refused the import: the copy, for this swapchain */
        FV_WARN(FV_XR_LOG, "xrCreateSwapchain: the GL driver cannot use the compositor's image memory; copying");
        swapchain_gl_free(e, g, sc->image_count);
        g->shared = false;
        ok = create_textures(e, sc, g);
    }
    egl_leave(e, &sv);
    XrResult r = ok ? XR_SUCCESS : XR_ERROR_RUNTIME_FAILURE;
    if (r == XR_SUCCESS && !sc->depth && !g->shared) {
        g->layer_bytes = (size_t)ci->width * ci->height * 4u;
        fv_vk *vk = fv_xr_compositor_vk(s->inst->comp);
        if (fv_vk_buffer_create(vk, g->layer_bytes * ci->arraySize, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                FV_VK_MEM_UPLOAD, "xr egl staging", &g->staging) != FV_OK)
            r = XR_ERROR_OUT_OF_MEMORY;
    }
    /* shared: every image starts with the GL side (VK_QUEUE_FAMILY_EXTERNAL) in the GENERAL layout, the layout GL
     * uses for memory it did not get from a semaphore's layout hand-over (EXT_external_objects) */
    for (uint32_t i = 0; r == XR_SUCCESS && g->shared && i < sc->image_count; i++)
        r = comp_barrier(sc, i, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, FAMILY_COMP,
                         VK_QUEUE_FAMILY_EXTERNAL, 0, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                         VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
    if (r != XR_SUCCESS) {
        if (egl_enter(e, &sv, "xrCreateSwapchain")) {
            swapchain_gl_free(e, g, sc->image_count);
            egl_leave(e, &sv);
        }
        fv_vk_buffer_destroy(fv_xr_compositor_vk(s->inst->comp), &g->staging);
        free(g);
        return r;
    }
    sc->egl = g;
    return XR_SUCCESS;
}

void fv_xr_egl_swapchain_destroy(struct XrSession_T *s, struct XrSwapchain_T *sc)
{
    struct fv_xr_egl_swapchain *g = sc->egl;
    if (!g) return;
    egl_saved sv;
    /* the textures go with the app's context when it cannot be made current here (then it is being torn down) */
    if (egl_enter(s->egl, &sv, "xrDestroySwapchain")) {
        swapchain_gl_free(s->egl, g, sc->image_count);
        egl_leave(s->egl, &sv);
    }
    fv_vk_buffer_destroy(fv_xr_compositor_vk(s->inst->comp), &g->staging);
    free(g);
    sc->egl = NULL;
}

XrResult fv_xr_egl_enumerate_images(struct XrSwapchain_T *sc, XrSwapchainImageBaseHeader *images)
{
    struct fv_xr_egl *e = sc->session->egl;
    XrStructureType want = e->gles ? XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_ES_KHR : XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR;
    for (uint32_t i = 0; i < sc->image_count; i++) {
        /* XrSwapchainImageOpenGLKHR and XrSwapchainImageOpenGLESKHR have the same layout (type, next, image) */
        XrSwapchainImageOpenGLKHR *im = &((XrSwapchainImageOpenGLKHR *)images)[i];
        if (im->type != want) {
            FV_ERROR(FV_XR_LOG, "xrEnumerateSwapchainImages: image %u has type %d; an %s session's images are %s", i,
                     (int)im->type, e->gles ? "OpenGL ES" : "OpenGL",
                     e->gles ? "XrSwapchainImageOpenGLESKHR" : "XrSwapchainImageOpenGLKHR");
            return XR_ERROR_VALIDATION_FAILURE;
        }
        im->image = sc->egl->tex[i];
    }
    return XR_SUCCESS;
}

/* The hand-over to the compositor. Shared memory: see the file comment. The copy: every layer of mip 0 read back in
 * the app's context into the staging buffer (rows bottom-up, as GL stores them), then copied into the compositor's image on fovea's queue and left in the layout the compose pass
 * samples. glReadPixels into client memory returns when the app's GL commands writing the texture have finished,
 * and the Vulkan copy is waited for, so the compositor reads a finished image. */
XrResult fv_xr_egl_release(struct XrSwapchain_T *sc, uint32_t index)
{
    if (sc->depth) return XR_SUCCESS; /* stays with the app */
    struct XrSession_T *s = sc->session;
    struct fv_xr_egl *e = s->egl;
    struct fv_xr_egl_swapchain *g = sc->egl;
    const XrSwapchainCreateInfo *ci = &sc->info;
    egl_saved sv;
    if (!egl_enter(e, &sv, "xrReleaseSwapchainImage")) return XR_ERROR_RUNTIME_FAILURE;
    if (g->shared) {
        /* the app's GL work on the texture finished (no GL_EXT_semaphore_fd needed), then fovea's queue takes the
         * image from the external side into the layout the compose pass samples */
        e->gl.Finish();
        egl_leave(e, &sv);
        XrResult r = comp_barrier(sc, index, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                  VK_QUEUE_FAMILY_EXTERNAL, FAMILY_COMP, VK_ACCESS_SHADER_READ_BIT,
                                  VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
        if (r == XR_SUCCESS) g->with_comp[index] = true;
        return r;
    }
    gl_clear_errors(e);
    GLint prev_fbo = 0, prev_pack_buffer = 0, prev_align = 4, prev_row = 0, prev_skip_rows = 0, prev_skip_px = 0;
    e->gl.GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &prev_fbo);
    e->gl.GetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &prev_pack_buffer);
    e->gl.GetIntegerv(GL_PACK_ALIGNMENT, &prev_align);
    e->gl.GetIntegerv(GL_PACK_ROW_LENGTH, &prev_row);
    e->gl.GetIntegerv(GL_PACK_SKIP_ROWS, &prev_skip_rows);
    e->gl.GetIntegerv(GL_PACK_SKIP_PIXELS, &prev_skip_px);
    e->gl.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    e->gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    e->gl.PixelStorei(GL_PACK_ROW_LENGTH, 0);
    e->gl.PixelStorei(GL_PACK_SKIP_ROWS, 0);
    e->gl.PixelStorei(GL_PACK_SKIP_PIXELS, 0);
    e->gl.BindFramebuffer(GL_READ_FRAMEBUFFER, g->fbo);
    bool ok = true;
    for (uint32_t layer = 0; layer < ci->arraySize && ok; layer++) {
        if (g->target == GL_TEXTURE_2D)
            e->gl.FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g->tex[index], 0);
        else
            e->gl.FramebufferTextureLayer(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, g->tex[index], 0, (GLint)layer);
        e->gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
        GLenum st = e->gl.CheckFramebufferStatus(GL_READ_FRAMEBUFFER);
        if (st != GL_FRAMEBUFFER_COMPLETE) {
            FV_ERROR(FV_XR_LOG, "xrReleaseSwapchainImage: the swapchain texture cannot be read (framebuffer status "
                                "0x%x)", (unsigned)st);
            ok = false;
            break;
        }
        e->gl.ReadPixels(0, 0, (GLsizei)ci->width, (GLsizei)ci->height, GL_RGBA, GL_UNSIGNED_BYTE,
                         (uint8_t *)g->staging.mapped + layer * g->layer_bytes);
    }
    e->gl.BindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)prev_fbo);
    e->gl.BindBuffer(GL_PIXEL_PACK_BUFFER, (GLuint)prev_pack_buffer);
    e->gl.PixelStorei(GL_PACK_ALIGNMENT, prev_align);
    e->gl.PixelStorei(GL_PACK_ROW_LENGTH, prev_row);
    e->gl.PixelStorei(GL_PACK_SKIP_ROWS, prev_skip_rows);
    e->gl.PixelStorei(GL_PACK_SKIP_PIXELS, prev_skip_px);
    ok = gl_ok(e, "xrReleaseSwapchainImage: reading the swapchain texture") && ok;
    egl_leave(e, &sv);
    if (!ok) return XR_ERROR_RUNTIME_FAILURE;

    fv_vk *vk = fv_xr_compositor_vk(s->inst->comp);
    if (fv_vk_buffer_flush(vk, &g->staging) != FV_OK) return XR_ERROR_RUNTIME_FAILURE;
    VkCommandBuffer cmd;
    fv_xr_compositor_gpu_lock(s->inst->comp); /* the device's pool and queue, shared with the compositor thread */
    if (fv_vk_oneshot_begin(vk, "xr egl copy", &cmd) != FV_OK) {
        fv_xr_compositor_gpu_unlock(s->inst->comp);
        return XR_ERROR_RUNTIME_FAILURE;
    }
    /* mip 0 is overwritten whole: its old contents are discarded (the compositor's last read of it was fenced) */
    fv_vk_image img = {.image = fv_xr_swapchain_comp_image(sc, index), .aspect = VK_IMAGE_ASPECT_COLOR_BIT,
                       .layers = ci->arraySize};
    fv_vk_barrier_image(cmd, &img,
                        (fv_vk_image_use){VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0},
                        (fv_vk_image_use){VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                          VK_ACCESS_TRANSFER_WRITE_BIT});
    VkBufferImageCopy region = {.bufferOffset = 0,
                                .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, ci->arraySize},
                                .imageExtent = {ci->width, ci->height, 1}};
    vkCmdCopyBufferToImage(cmd, g->staging.buffer, img.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    fv_vk_barrier_image(cmd, &img,
                        (fv_vk_image_use){VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                          VK_ACCESS_TRANSFER_WRITE_BIT},
                        (fv_vk_image_use){VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT});
    fv_result res = fv_vk_oneshot_end(vk, cmd);
    fv_xr_compositor_gpu_unlock(s->inst->comp);
    if (res == FV_ERR_DEVICE_LOST) return XR_ERROR_SESSION_LOST;
    return res == FV_OK ? XR_SUCCESS : XR_ERROR_RUNTIME_FAILURE;
}

XrResult fv_xr_egl_acquire(struct XrSwapchain_T *sc, uint32_t index)
{
    struct fv_xr_egl_swapchain *g = sc->egl;
    if (!g->shared || !g->with_comp[index]) return XR_SUCCESS; /* the copy's textures never leave the app */
    /* back to the GL side in GENERAL; the compositor's reads of it were fenced (xrWaitSwapchainImage waited for
     * the frames that read it) */
    XrResult r = comp_barrier(sc, index, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL, FAMILY_COMP,
                              VK_QUEUE_FAMILY_EXTERNAL, 0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                              VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
    if (r == XR_SUCCESS) g->with_comp[index] = false;
    return r;
}
