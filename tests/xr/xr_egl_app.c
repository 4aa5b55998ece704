/* @brief An OpenGL ES (or, with --gl, desktop OpenGL) OpenXR app through EGL (XR_MNDX_egl_enable with
 * XR_KHR_opengl_es_enable / XR_KHR_opengl_enable) on Mesa's surfaceless platform (EGL_PLATFORM_SURFACELESS_MESA), run
 * through the OpenXR loader (XR_RUNTIME_JSON = fovea's manifest). Each frame it clears its GL swapchain textures
 * (GL_SRGB8_ALPHA8, one per eye): the left eye red, the right eye blue, the top quarter of each white, and in the
 * left quarter below it a green ramp that brightens upwards in 8 bands (GL's bottom-left origin: band 0 is the
 * bottom row) -- a composite that is upside down or mirrored shows it. Prints `gl,<version>`, `frame,N,...`,
 * `handover_ms_mean,X` (the time in xrAcquireSwapchainImage, xrWaitSwapchainImage and xrReleaseSwapchainImage per
 * eye: the runtime's hand-over of the image to its compositor and back) and
 * `frames,N` (--finish: the app's GL work finished before each release, so the hand-over time is the runtime's own).
 * --array: one swapchain of two layers, eye e in layer e (imageArrayIndex). --size WxH: swapchains of that size (the benchmark's; default the recommended size). --bad-bindings: only the session-creation checks (a missing context, a context that is not one, a
 * session before the requirements call), each printed as `bad_binding,<case>,<XrResult>`. Exit 77 when EGL cannot
 * give a surfaceless context here (the test skips); any failed call prints it and exits 1. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>

#define XR_USE_PLATFORM_EGL 1
#define XR_USE_GRAPHICS_API_OPENGL 1
#define XR_USE_GRAPHICS_API_OPENGL_ES 1
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include "xr_app.h"

#define CHECK_XR XR_APP_CHECK

#define MAX_IMAGES 8

typedef struct eye {
    XrSwapchain swapchain;
    uint32_t width, height, image_count;
    GLuint images[MAX_IMAGES];
} eye;

typedef struct app {
    bool desktop_gl;
    uint32_t width, height; /* --size: the swapchains' size (default: the recommended one) */
    bool array;             /* --array: one swapchain of two layers (layer e = eye e) */
    bool finish;            /* --finish: glFinish before each release (the hand-over time is then the runtime's own) */
    EGLDisplay dpy;
    EGLConfig cfg;
    EGLContext ctx;
    XrInstance inst;
    XrSystemId system;
    XrSession session;
    XrSpace local;
    eye eyes[2];
    GLuint fbo;
    double handover_ms_sum;
    int releases;
} app;

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* A surfaceless EGL context (GLES 3 or desktop GL 4.5 core), current on this thread; false when there is none. */
static bool create_egl(app *a)
{
    const char *exts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!exts || !strstr(exts, "EGL_MESA_platform_surfaceless")) {
        printf("skip: EGL has no EGL_MESA_platform_surfaceless\n");
        return false;
    }
    PFNEGLGETPLATFORMDISPLAYEXTPROC gpd = (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    a->dpy = gpd ? gpd(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL) : EGL_NO_DISPLAY;
    EGLint major = 0, minor = 0;
    if (a->dpy == EGL_NO_DISPLAY || !eglInitialize(a->dpy, &major, &minor)) {
        printf("skip: no surfaceless EGL display (0x%x)\n", (unsigned)eglGetError());
        return false;
    }
    EGLint want[] = {EGL_RENDERABLE_TYPE, a->desktop_gl ? EGL_OPENGL_BIT : EGL_OPENGL_ES3_BIT, EGL_SURFACE_TYPE,
                     EGL_PBUFFER_BIT, EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(a->dpy, want, &a->cfg, 1, &n) || n < 1) {
        printf("skip: no EGL config for %s\n", a->desktop_gl ? "OpenGL" : "OpenGL ES 3");
        return false;
    }
    if (!eglBindAPI(a->desktop_gl ? EGL_OPENGL_API : EGL_OPENGL_ES_API)) {
        printf("skip: eglBindAPI failed (0x%x)\n", (unsigned)eglGetError());
        return false;
    }
    EGLint attrs_gl[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLint attrs_es[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_NONE};
    a->ctx = eglCreateContext(a->dpy, a->cfg, EGL_NO_CONTEXT, a->desktop_gl ? attrs_gl : attrs_es);
    if (a->ctx == EGL_NO_CONTEXT || !eglMakeCurrent(a->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, a->ctx)) {
        printf("skip: no surfaceless %s context (0x%x)\n", a->desktop_gl ? "OpenGL 4.5" : "OpenGL ES 3",
               (unsigned)eglGetError());
        return false;
    }
    printf("gl,%s,%s\n", (const char *)glGetString(GL_VERSION), (const char *)glGetString(GL_RENDERER));
    return true;
}

static void create_instance(app *a)
{
    const char *gl_ext = a->desktop_gl ? XR_KHR_OPENGL_ENABLE_EXTENSION_NAME : XR_KHR_OPENGL_ES_ENABLE_EXTENSION_NAME;
    uint32_t n = 0;
    CHECK_XR(xrEnumerateInstanceExtensionProperties(NULL, 0, &n, NULL));
    XrExtensionProperties *props = calloc(n, sizeof *props);
    for (uint32_t i = 0; i < n; i++) props[i].type = XR_TYPE_EXTENSION_PROPERTIES;
    CHECK_XR(xrEnumerateInstanceExtensionProperties(NULL, n, &n, props));
    bool has_gl = false, has_egl = false;
    for (uint32_t i = 0; i < n; i++) {
        has_gl |= !strcmp(props[i].extensionName, gl_ext);
        has_egl |= !strcmp(props[i].extensionName, XR_MNDX_EGL_ENABLE_EXTENSION_NAME);
    }
    free(props);
    if (!has_gl || !has_egl) {
        fprintf(stderr, "xr_egl_app: the runtime lacks %s or %s\n", gl_ext, XR_MNDX_EGL_ENABLE_EXTENSION_NAME);
        exit(1);
    }
    const char *exts[] = {gl_ext, XR_MNDX_EGL_ENABLE_EXTENSION_NAME};
    XrInstanceCreateInfo ci = {.type = XR_TYPE_INSTANCE_CREATE_INFO, .enabledExtensionCount = 2,
                               .enabledExtensionNames = exts};
    snprintf(ci.applicationInfo.applicationName, sizeof ci.applicationInfo.applicationName, "xr_egl_app");
    ci.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    CHECK_XR(xrCreateInstance(&ci, &a->inst));
    XrSystemGetInfo si = {.type = XR_TYPE_SYSTEM_GET_INFO, .formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY};
    CHECK_XR(xrGetSystem(a->inst, &si, &a->system));
}

/* The graphics requirements (the spec: before xrCreateSession), checked against the context's version. */
static void requirements(app *a)
{
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    XrVersion have = XR_MAKE_VERSION(major, minor, 0);
    /* XrGraphicsRequirementsOpenGLKHR and ...OpenGLESKHR (and their functions) differ only in the type */
    PFN_xrGetOpenGLGraphicsRequirementsKHR get = NULL;
    CHECK_XR(xrGetInstanceProcAddr(a->inst,
                                   a->desktop_gl ? "xrGetOpenGLGraphicsRequirementsKHR"
                                                 : "xrGetOpenGLESGraphicsRequirementsKHR",
                                   (PFN_xrVoidFunction *)&get));
    XrGraphicsRequirementsOpenGLKHR req = {.type = a->desktop_gl ? XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR
                                                                 : XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_ES_KHR};
    CHECK_XR(get(a->inst, a->system, &req));
    XrVersion lo = req.minApiVersionSupported, hi = req.maxApiVersionSupported;
    printf("requirements,%u.%u,%u.%u\n", (unsigned)XR_VERSION_MAJOR(lo), (unsigned)XR_VERSION_MINOR(lo),
           (unsigned)XR_VERSION_MAJOR(hi), (unsigned)XR_VERSION_MINOR(hi));
    if (have < lo || XR_VERSION_MAJOR(have) > XR_VERSION_MAJOR(hi)) {
        fprintf(stderr, "xr_egl_app: GL %d.%d is outside the runtime's requirements\n", major, minor);
        exit(1);
    }
}

static XrResult try_session(app *a, EGLContext ctx)
{
    XrGraphicsBindingEGLMNDX b = {.type = XR_TYPE_GRAPHICS_BINDING_EGL_MNDX,
                                  .getProcAddress = eglGetProcAddress,
                                  .display = a->dpy,
                                  .config = a->cfg,
                                  .context = ctx};
    XrSessionCreateInfo ci = {.type = XR_TYPE_SESSION_CREATE_INFO, .next = &b, .systemId = a->system};
    XrSession s = XR_NULL_HANDLE;
    XrResult r = xrCreateSession(a->inst, &ci, &s);
    if (XR_SUCCEEDED(r) && ctx != a->ctx) xrDestroySession(s);
    if (XR_SUCCEEDED(r) && ctx == a->ctx) a->session = s;
    return r;
}

/* The session-creation checks (run without the core-validation layer: these calls are invalid on purpose). */
static int bad_bindings(app *a)
{
    printf("bad_binding,before_requirements,%d\n", (int)try_session(a, a->ctx));
    requirements(a);
    printf("bad_binding,no_context,%d\n", (int)try_session(a, EGL_NO_CONTEXT));
    /* a context of another display's kind: a pointer that is no context of this display */
    int not_a_context;
    printf("bad_binding,not_a_context,%d\n", (int)try_session(a, (EGLContext)&not_a_context));
    XrResult r = try_session(a, a->ctx);
    printf("bad_binding,valid,%d\n", (int)r);
    if (a->session) xrDestroySession(a->session);
    xrDestroyInstance(a->inst);
    return 0;
}

static void create_swapchains(app *a)
{
    uint32_t n = 0;
    CHECK_XR(xrEnumerateSwapchainFormats(a->session, 0, &n, NULL));
    int64_t formats[32];
    if (n > 32) n = 32;
    CHECK_XR(xrEnumerateSwapchainFormats(a->session, n, &n, formats));
    bool srgb = false;
    printf("formats");
    for (uint32_t i = 0; i < n; i++) {
        printf(",0x%llx", (unsigned long long)formats[i]);
        srgb |= formats[i] == GL_SRGB8_ALPHA8;
    }
    printf("\n");
    if (!srgb) {
        fprintf(stderr, "xr_egl_app: the runtime offers no GL_SRGB8_ALPHA8 swapchain\n");
        exit(1);
    }
    XrViewConfigurationView views[2] = {{.type = XR_TYPE_VIEW_CONFIGURATION_VIEW},
                                        {.type = XR_TYPE_VIEW_CONFIGURATION_VIEW}};
    CHECK_XR(xrEnumerateViewConfigurationViews(a->inst, a->system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 2, &n,
                                               views));
    for (int e = 0; e < (a->array ? 1 : 2); e++) {
        eye *t = &a->eyes[e];
        t->width = a->width ? a->width : views[e].recommendedImageRectWidth;
        t->height = a->height ? a->height : views[e].recommendedImageRectHeight;
        XrSwapchainCreateInfo ci = {.type = XR_TYPE_SWAPCHAIN_CREATE_INFO,
                                    .usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT |
                                                  XR_SWAPCHAIN_USAGE_SAMPLED_BIT,
                                    .format = GL_SRGB8_ALPHA8,
                                    .sampleCount = 1,
                                    .width = t->width,
                                    .height = t->height,
                                    .faceCount = 1,
                                    .arraySize = a->array ? 2 : 1,
                                    .mipCount = 1};
        CHECK_XR(xrCreateSwapchain(a->session, &ci, &t->swapchain));
        CHECK_XR(xrEnumerateSwapchainImages(t->swapchain, 0, &t->image_count, NULL));
        if (t->image_count > MAX_IMAGES) exit(1);
        /* XrSwapchainImageOpenGLKHR and ...OpenGLESKHR: the same layout, different types */
        XrSwapchainImageOpenGLKHR imgs[MAX_IMAGES];
        for (uint32_t i = 0; i < t->image_count; i++)
            imgs[i] = (XrSwapchainImageOpenGLKHR){
                .type = a->desktop_gl ? XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR : XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_ES_KHR};
        CHECK_XR(xrEnumerateSwapchainImages(t->swapchain, t->image_count, &t->image_count,
                                            (XrSwapchainImageBaseHeader *)imgs));
        for (uint32_t i = 0; i < t->image_count; i++) t->images[i] = imgs[i].image;
    }
    if (a->array) a->eyes[1] = a->eyes[0]; /* the same swapchain, layer 1 */
    printf("eye_size,%ux%u\n", a->eyes[0].width, a->eyes[0].height);
    glGenFramebuffers(1, &a->fbo);
}

static void clear_rect(GLint x, GLint y, GLsizei w, GLsizei h, float r, float g, float b)
{
    glScissor(x, y, w, h);
    glClearColor(r, g, b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
}

/* The pattern of the file comment, in GL's coordinates (y up). */
static void draw_eye(const eye *t, int e)
{
    GLsizei w = (GLsizei)t->width, h = (GLsizei)t->height;
    glViewport(0, 0, w, h);
    glEnable(GL_SCISSOR_TEST);
    clear_rect(0, 0, w, h, e == 0 ? 1.0f : 0.0f, 0.0f, e == 0 ? 0.0f : 1.0f);
    GLint top = h - h / 4;
    clear_rect(0, top, w, h - top, 1.0f, 1.0f, 1.0f);
    for (int k = 0; k < 8; k++) {
        GLint y0 = top * k / 8, y1 = top * (k + 1) / 8;
        clear_rect(0, y0, w / 4, y1 - y0, 0.0f, (float)(k + 1) / 8.0f, 0.0f);
    }
    glDisable(GL_SCISSOR_TEST);
}

static void frame(app *a, int n)
{
    XrFrameWaitInfo wi = {.type = XR_TYPE_FRAME_WAIT_INFO};
    XrFrameState fs = {.type = XR_TYPE_FRAME_STATE};
    CHECK_XR(xrWaitFrame(a->session, &wi, &fs));
    XrFrameBeginInfo fbi = {.type = XR_TYPE_FRAME_BEGIN_INFO};
    CHECK_XR(xrBeginFrame(a->session, &fbi));
    XrViewLocateInfo li = {.type = XR_TYPE_VIEW_LOCATE_INFO,
                           .viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO,
                           .displayTime = fs.predictedDisplayTime,
                           .space = a->local};
    XrViewState vs = {.type = XR_TYPE_VIEW_STATE};
    XrView views[2] = {{.type = XR_TYPE_VIEW}, {.type = XR_TYPE_VIEW}};
    uint32_t nv = 0;
    CHECK_XR(xrLocateViews(a->session, &li, &vs, 2, &nv, views));
    XrCompositionLayerProjectionView pv[2];
    bool draw_it = fs.shouldRender && (vs.viewStateFlags & XR_VIEW_STATE_ORIENTATION_VALID_BIT);
    uint32_t idx = 0;
    for (int e = 0; e < 2 && draw_it; e++) {
        eye *t = &a->eyes[e];
        bool first = !a->array || e == 0, last = !a->array || e == 1; /* an array swapchain: once per frame */
        if (first) {
            XrSwapchainImageAcquireInfo ai = {.type = XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO};
            double t_acq = now_ms();
            CHECK_XR(xrAcquireSwapchainImage(t->swapchain, &ai, &idx));
            XrSwapchainImageWaitInfo wti = {.type = XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO,
                                            .timeout = XR_INFINITE_DURATION};
            CHECK_XR(xrWaitSwapchainImage(t->swapchain, &wti));
            a->handover_ms_sum += now_ms() - t_acq;
        }
        glBindFramebuffer(GL_FRAMEBUFFER, a->fbo);
        if (a->array) glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, t->images[idx], 0, e);
        else glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->images[idx], 0);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            fprintf(stderr, "xr_egl_app: swapchain texture %u is not renderable\n", t->images[idx]);
            exit(1);
        }
        draw_eye(t, e);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        if (last) {
            if (a->finish) glFinish();
            XrSwapchainImageReleaseInfo ri = {.type = XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO};
            double t0 = now_ms();
            CHECK_XR(xrReleaseSwapchainImage(t->swapchain, &ri));
            a->handover_ms_sum += now_ms() - t0;
            a->releases++;
        }
        pv[e] = (XrCompositionLayerProjectionView){
            .type = XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW,
            .pose = views[e].pose,
            .fov = views[e].fov,
            .subImage = {.swapchain = t->swapchain,
                         .imageRect = {{0, 0}, {(int32_t)t->width, (int32_t)t->height}},
                         .imageArrayIndex = a->array ? (uint32_t)e : 0}};
    }
    if (glGetError() != GL_NO_ERROR) {
        fprintf(stderr, "xr_egl_app: GL error in frame %d\n", n);
        exit(1);
    }
    XrCompositionLayerProjection layer = {.type = XR_TYPE_COMPOSITION_LAYER_PROJECTION, .space = a->local,
                                          .viewCount = 2, .views = pv};
    const XrCompositionLayerBaseHeader *layers[1] = {(const XrCompositionLayerBaseHeader *)&layer};
    XrFrameEndInfo ei = {.type = XR_TYPE_FRAME_END_INFO,
                         .displayTime = fs.predictedDisplayTime,
                         .environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE,
                         .layerCount = draw_it ? 1 : 0,
                         .layers = layers};
    CHECK_XR(xrEndFrame(a->session, &ei));
    printf("frame,%d,drawn,%d\n", n, draw_it ? 1 : 0);
}

static void frame_cb(void *ctx, int n, bool visible)
{
    (void)visible; /* the runtime's shouldRender decides what is drawn */
    frame(ctx, n);
}

/* --size WxH (xr_app_args' `other`) */
static int size_arg(void *ctx, int argc, char **argv, int *i)
{
    app *a = ctx;
    if (strcmp(argv[*i], "--size") != 0 || *i + 1 >= argc) return 0;
    ++*i;
    if (sscanf(argv[*i], "%ux%u", &a->width, &a->height) != 2 || a->width < 1 || a->height < 1 || a->width > 4096 ||
        a->height > 4096) {
        fprintf(stderr, "xr_egl_app: --size %s: expected WxH, 1..4096 each\n", argv[*i]);
        return 2;
    }
    return 1;
}

int main(int argc, char **argv)
{
    int frames = 6;
    app a = {0};
    bool bad = false;
    const xr_app_flag flags[] = {{"--gl", &a.desktop_gl}, {"--bad-bindings", &bad}, {"--finish", &a.finish},
                                 {"--array", &a.array}};
    int bad_args = xr_app_args(argc, argv, "[--frames N] [--gl] [--size WxH] [--finish] [--array] [--bad-bindings]",
                               &frames, flags, 4, size_arg, &a);
    if (bad_args) return bad_args;
    setvbuf(stdout, NULL, _IOLBF, 0);
    if (!create_egl(&a)) return 77;
    create_instance(&a);
    if (bad) return bad_bindings(&a);
    requirements(&a);
    CHECK_XR(try_session(&a, a.ctx));
    XrReferenceSpaceCreateInfo rs = {.type = XR_TYPE_REFERENCE_SPACE_CREATE_INFO,
                                     .referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL,
                                     .poseInReferenceSpace = {{0, 0, 0, 1}, {0, 0, 0}}};
    CHECK_XR(xrCreateReferenceSpace(a.session, &rs, &a.local));
    create_swapchains(&a);
    int n = xr_app_run_session(a.inst, a.session, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, frames, frame_cb, &a);
    for (int e = 0; e < (a.array ? 1 : 2); e++) CHECK_XR(xrDestroySwapchain(a.eyes[e].swapchain));
    glDeleteFramebuffers(1, &a.fbo);
    CHECK_XR(xrDestroySpace(a.local));
    CHECK_XR(xrDestroySession(a.session));
    CHECK_XR(xrDestroyInstance(a.inst));
    eglMakeCurrent(a.dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(a.dpy, a.ctx);
    eglTerminate(a.dpy);
    printf("handover_ms_mean,%.4f\nframes,%d\n", a.releases ? a.handover_ms_sum / a.releases : 0.0, n);
    return 0;
}
