/* @brief fovea's OpenXR misuse corpus: an app of our own through the real OpenXR loader (XR_RUNTIME_JSON = the
 * generated manifest, no API layer, so every call reaches the runtime) making dozens of calls a hostile or buggy app
 * makes, each checked to return the spec's XrResult without a crash, a hang or a sanitizer report (it runs in the
 * sanitizer build: label unit):
 *  - swapchain create infos against the limits the runtime reports (mips beyond floor(log2(max(w, h))) + 1, sizes
 *    above the max, sample counts, array sizes, face counts, zero sizes, unknown usage / create bits, formats not
 *    enumerated), xrEndFrame's layers (rects outside the image, array indices, view counts, more than maxLayerCount,
 *    the maximum itself composited), on a Vulkan session (lavapipe);
 *  - invalid, NULL and destroyed handles, wrong structure types, absurd counts and capacities;
 *  - out-of-order calls (xrBeginFrame without xrWaitFrame, xrEndFrame twice, frame calls before xrBeginSession and
 *    after xrDestroySession);
 *  - `next` chains: every structure type the runtime knows and an unknown one chained into every input struct it
 *    reads (ignored), looping and over-long chains (XR_ERROR_VALIDATION_FAILURE, never a hang);
 *  - the conformance points: maxLayerCount >= 16, a non-zero vendorId, XR_ERROR_FORM_FACTOR_UNSUPPORTED and
 *    XR_ERROR_REFERENCE_SPACE_UNSUPPORTED for unknown values, headless placeholder layers accepted, a headless
 *    session begun with a view configuration not enumerated refused (XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
 *  - an HMD profile too large for the swapchain limit: the recommended size clamped (aspect kept), said once;
 *  - layer names in enabledApiLayerNames (the core-validation layer) ignored by the runtime: frames run.
 * A watchdog (alarm) bounds the whole process: a hang fails the test instead of stalling the suite.
 * argv[1] = the runtime manifest; argv[2] (optional) = which tests (a cmocka filter pattern). */
#include <dlfcn.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fv_test.h"
#include "xr_app_vk.h"

#define WATCHDOG_S 60 /* the whole corpus runs in a few seconds */
#define EXPECT(want, call) assert_int_equal((int)(call), (int)(want))
#define CHECK_XR(call) EXPECT(XR_SUCCESS, call)
#define UNKNOWN_TYPE ((XrStructureType)0x7ffff00d) /* no structure has this type */

static const char *g_manifest;
static XrInstance g_open; /* the instance of the running test (destroyed by the teardown when the test failed) */

typedef struct app {
    XrInstance inst;
    XrSystemId sys;
    XrSession sess;
    XrSessionState state;
    XrSpace local;
    xr_app_vk vk; /* Vulkan sessions */
} app;

static XrResult create_instance(app *a, const char *const *exts, uint32_t n_exts, const char *const *layers,
                                uint32_t n_layers, const void *next)
{
    memset(a, 0, sizeof *a);
    setenv("XR_RUNTIME_JSON", g_manifest, 1);
    XrInstanceCreateInfo ci = {.type = XR_TYPE_INSTANCE_CREATE_INFO,
                               .next = next,
                               .enabledApiLayerCount = n_layers,
                               .enabledApiLayerNames = layers,
                               .enabledExtensionCount = n_exts,
                               .enabledExtensionNames = exts,
                               .applicationInfo = {.applicationName = "test_xr_misuse",
                                                   .apiVersion = XR_MAKE_VERSION(1, 0, 0)}};
    XrResult r = xrCreateInstance(&ci, &a->inst);
    if (r == XR_SUCCESS) g_open = a->inst;
    return r;
}

static int teardown(void **state)
{
    (void)state;
    if (g_open) xrDestroyInstance(g_open); /* the loader holds one instance at a time */
    g_open = XR_NULL_HANDLE;
    return 0;
}

static void open_headless(app *a, bool eye_gaze)
{
    const char *exts[] = {XR_MND_HEADLESS_EXTENSION_NAME, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME};
    CHECK_XR(create_instance(a, exts, eye_gaze ? 2 : 1, NULL, 0, NULL));
    XrSystemGetInfo sg = {.type = XR_TYPE_SYSTEM_GET_INFO, .formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY};
    CHECK_XR(xrGetSystem(a->inst, &sg, &a->sys));
}

static void poll_events(app *a)
{
    for (int i = 0; i < 256; i++) {
        XrEventDataBuffer ev = {.type = XR_TYPE_EVENT_DATA_BUFFER};
        XrResult r = xrPollEvent(a->inst, &ev);
        if (r == XR_EVENT_UNAVAILABLE) return;
        CHECK_XR(r);
        if (ev.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED)
            a->state = ((XrEventDataSessionStateChanged *)&ev)->state;
    }
}

static void create_session(app *a, const void *binding)
{
    XrSessionCreateInfo sc = {.type = XR_TYPE_SESSION_CREATE_INFO, .next = binding, .systemId = a->sys};
    CHECK_XR(xrCreateSession(a->inst, &sc, &a->sess));
    poll_events(a);
    assert_int_equal(a->state, XR_SESSION_STATE_READY);
    XrReferenceSpaceCreateInfo rs = {.type = XR_TYPE_REFERENCE_SPACE_CREATE_INFO,
                                     .referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL,
                                     .poseInReferenceSpace = {.orientation = {0, 0, 0, 1}}};
    CHECK_XR(xrCreateReferenceSpace(a->sess, &rs, &a->local));
}

static void begin_session(app *a)
{
    XrSessionBeginInfo bi = {.type = XR_TYPE_SESSION_BEGIN_INFO,
                             .primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO};
    CHECK_XR(xrBeginSession(a->sess, &bi));
    poll_events(a);
}

static void close_app(app *a)
{
    if (a->sess) {
        XrResult r = xrRequestExitSession(a->sess);
        assert_true(r == XR_SUCCESS || r == XR_ERROR_SESSION_NOT_RUNNING);
        poll_events(a);
        if (a->state == XR_SESSION_STATE_STOPPING) CHECK_XR(xrEndSession(a->sess));
        CHECK_XR(xrDestroySession(a->sess));
    }
    CHECK_XR(xrDestroyInstance(a->inst));
    g_open = XR_NULL_HANDLE;
    if (a->vk.device) vkDestroyDevice(a->vk.device, NULL);
    if (a->vk.instance) vkDestroyInstance(a->vk.instance, NULL);
}

/* One frame: wait, begin, end with `n` layers; the xrEndFrame result. */
static XrResult frame(app *a, const XrCompositionLayerBaseHeader *const *layers, uint32_t n)
{
    XrFrameState fs = {.type = XR_TYPE_FRAME_STATE};
    CHECK_XR(xrWaitFrame(a->sess, NULL, &fs));
    XrResult r = xrBeginFrame(a->sess, NULL);
    assert_true(r == XR_SUCCESS || r == XR_FRAME_DISCARDED); /* discarded: a refused xrEndFrame left it open */
    XrFrameEndInfo ei = {.type = XR_TYPE_FRAME_END_INFO, .displayTime = fs.predictedDisplayTime,
                         .environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE, .layerCount = n, .layers = layers};
    return xrEndFrame(a->sess, &ei);
}

/* ---- a Vulkan session (XR_KHR_vulkan_enable2; lavapipe here), no validation layer ---------------------------- */
static void open_vulkan(app *a)
{
    const char *exts[] = {XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME};
    setenv("FOVEA_XR_SCALE", "0.02", 1); /* a display of 29 x 29 px per eye: compositing on lavapipe stays cheap */
    CHECK_XR(create_instance(a, exts, 1, NULL, 0, NULL));
    unsetenv("FOVEA_XR_SCALE");
    XrSystemGetInfo sg = {.type = XR_TYPE_SYSTEM_GET_INFO, .formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY};
    CHECK_XR(xrGetSystem(a->inst, &sg, &a->sys));
    VkApplicationInfo ai = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO, .pApplicationName = "test_xr_misuse",
                            .apiVersion = VK_API_VERSION_1_1};
    VkInstanceCreateInfo ici = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO, .pApplicationInfo = &ai};
    xr_app_vk_create(a->inst, a->sys, &ici, &a->vk);
    XrGraphicsBindingVulkanKHR gb = xr_app_vk_binding(&a->vk);
    create_session(a, &gb);
}

static XrSwapchainCreateInfo colour_info(app *a, uint32_t w, uint32_t h)
{
    int64_t formats[64];
    uint32_t n = 0;
    CHECK_XR(xrEnumerateSwapchainFormats(a->sess, 64, &n, formats));
    assert_true(n > 0);
    return (XrSwapchainCreateInfo){.type = XR_TYPE_SWAPCHAIN_CREATE_INFO,
                                   .usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT |
                                                 XR_SWAPCHAIN_USAGE_SAMPLED_BIT,
                                   .format = formats[0], .sampleCount = 1, .width = w, .height = h, .faceCount = 1,
                                   .arraySize = 1, .mipCount = 1};
}

/* Acquire, wait, release one image (so layers may name the swapchain). */
static void cycle(XrSwapchain sc)
{
    uint32_t idx = 99;
    CHECK_XR(xrAcquireSwapchainImage(sc, NULL, &idx));
    assert_true(idx < 3);
    XrSwapchainImageWaitInfo wi = {.type = XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO, .timeout = XR_INFINITE_DURATION};
    CHECK_XR(xrWaitSwapchainImage(sc, &wi));
    CHECK_XR(xrReleaseSwapchainImage(sc, NULL));
}

/* (a) xrCreateSwapchain against the limits the runtime reports: 64x64 with 8 mips was accepted and corrupted the
 * heap; every other field of XrSwapchainCreateInfo likewise, each refused before anything is made. */
static void swapchain_create_infos_are_checked_against_the_reported_limits(void **state)
{
    (void)state;
    app a;
    open_vulkan(&a);
    XrSystemProperties sp = {.type = XR_TYPE_SYSTEM_PROPERTIES};
    CHECK_XR(xrGetSystemProperties(a.inst, a.sys, &sp));
    uint32_t maxw = sp.graphicsProperties.maxSwapchainImageWidth, maxh = sp.graphicsProperties.maxSwapchainImageHeight;
    XrViewConfigurationView views[2] = {{.type = XR_TYPE_VIEW_CONFIGURATION_VIEW},
                                        {.type = XR_TYPE_VIEW_CONFIGURATION_VIEW}};
    uint32_t nv = 0;
    CHECK_XR(
        xrEnumerateViewConfigurationViews(a.inst, a.sys, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 2, &nv, views));
    uint32_t max_samples = views[0].maxSwapchainSampleCount;
    XrSwapchain sc = XR_NULL_HANDLE;
    XrSwapchainCreateInfo ci = colour_info(&a, 64, 64);
    struct {
        const char *what;
        XrResult want;
        XrSwapchainCreateInfo ci;
    } bad[32];
    int nb = 0;
#define BAD(w, field, value)                                                                                           \
    do {                                                                                                               \
        bad[nb].what = #field " = " #value;                                                                            \
        bad[nb].want = (w);                                                                                            \
        bad[nb].ci = ci;                                                                                               \
        bad[nb].ci.field = (value);                                                                                    \
        nb++;                                                                                                          \
    } while (0)
    BAD(XR_ERROR_VALIDATION_FAILURE, mipCount, 8); /* 64x64 has 7 levels: the crash */
    BAD(XR_ERROR_VALIDATION_FAILURE, mipCount, 0);
    BAD(XR_ERROR_VALIDATION_FAILURE, mipCount, UINT32_MAX);
    BAD(XR_ERROR_VALIDATION_FAILURE, width, 0);
    BAD(XR_ERROR_VALIDATION_FAILURE, height, 0);
    BAD(XR_ERROR_VALIDATION_FAILURE, width, maxw + 1);
    BAD(XR_ERROR_VALIDATION_FAILURE, height, maxh + 1);
    BAD(XR_ERROR_VALIDATION_FAILURE, width, UINT32_MAX);
    BAD(XR_ERROR_VALIDATION_FAILURE, sampleCount, 0);
    BAD(XR_ERROR_FEATURE_UNSUPPORTED, sampleCount, max_samples * 2);
    BAD(XR_ERROR_FEATURE_UNSUPPORTED, sampleCount, UINT32_MAX);
    BAD(XR_ERROR_VALIDATION_FAILURE, arraySize, 0);
    BAD(XR_ERROR_VALIDATION_FAILURE, arraySize, UINT32_MAX);
    BAD(XR_ERROR_VALIDATION_FAILURE, faceCount, 0);
    BAD(XR_ERROR_VALIDATION_FAILURE, faceCount, 2);
    BAD(XR_ERROR_FEATURE_UNSUPPORTED, faceCount, 6); /* no cube layers */
    BAD(XR_ERROR_VALIDATION_FAILURE, usageFlags, (XrSwapchainUsageFlags)1 << 40);
    BAD(XR_ERROR_FEATURE_UNSUPPORTED, usageFlags, XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT); /* colour format */
    BAD(XR_ERROR_VALIDATION_FAILURE, createFlags, (XrSwapchainCreateFlags)1 << 20);
    BAD(XR_ERROR_FEATURE_UNSUPPORTED, createFlags, XR_SWAPCHAIN_CREATE_PROTECTED_CONTENT_BIT);
    BAD(XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED, format, 0x7fffffff);
    BAD(XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED, format, -1);
    BAD(XR_ERROR_VALIDATION_FAILURE, type, XR_TYPE_SESSION_CREATE_INFO);
#undef BAD
    for (int i = 0; i < nb; i++) {
        sc = XR_NULL_HANDLE;
        XrResult r = xrCreateSwapchain(a.sess, &bad[i].ci, &sc);
        print_message("xrCreateSwapchain(%s) = %d (want %d)\n", bad[i].what, (int)r, (int)bad[i].want);
        assert_int_equal(r, bad[i].want);
        assert_ptr_equal(sc, XR_NULL_HANDLE);
    }
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrCreateSwapchain(a.sess, NULL, &sc));
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrCreateSwapchain(a.sess, &ci, NULL));
    EXPECT(XR_ERROR_HANDLE_INVALID, xrCreateSwapchain(XR_NULL_HANDLE, &ci, &sc));
    /* the limits themselves are fine: every mip level of 64x64, the largest size, a 2-layer array */
    XrSwapchainCreateInfo good[3] = {ci, ci, ci};
    good[0].mipCount = 7;
    good[1].width = maxw;
    good[1].height = 16;
    good[2].arraySize = 2;
    for (int i = 0; i < 3; i++) {
        CHECK_XR(xrCreateSwapchain(a.sess, &good[i], &sc));
        cycle(sc);
        CHECK_XR(xrDestroySwapchain(sc));
        EXPECT(XR_ERROR_HANDLE_INVALID, xrDestroySwapchain(sc)); /* destroyed */
        uint32_t idx;
        EXPECT(XR_ERROR_HANDLE_INVALID, xrAcquireSwapchainImage(sc, NULL, &idx));
    }
    close_app(&a);
}

/* xrEndFrame's layers on a Vulkan session: each field checked against the swapchain and the session; the maximum
 * number of layers (maxLayerCount, at least the spec's 16) composited, one more refused. */
static void end_frame_layers_are_checked(void **state)
{
    (void)state;
    app a;
    const char *stats = fv_test_tmp("end_frame_stats.json");
    remove(stats);
    setenv("FOVEA_XR_STATS", stats, 1); /* written when the session is destroyed: how many frames were composited */
    open_vulkan(&a);
    XrSystemProperties sp = {.type = XR_TYPE_SYSTEM_PROPERTIES};
    CHECK_XR(xrGetSystemProperties(a.inst, a.sys, &sp));
    print_message("maxLayerCount %u\n", sp.graphicsProperties.maxLayerCount);
    assert_true(sp.graphicsProperties.maxLayerCount >= XR_MIN_COMPOSITION_LAYERS_SUPPORTED);
    uint32_t max_layers = sp.graphicsProperties.maxLayerCount;
    begin_session(&a);
    XrSwapchainCreateInfo ci = colour_info(&a, 32, 32);
    XrSwapchain sc;
    CHECK_XR(xrCreateSwapchain(a.sess, &ci, &sc));
    cycle(sc);
    CHECK_XR(frame(&a, NULL, 0)); /* the first frame: the session becomes visible */
    poll_events(&a);
    XrCompositionLayerQuad quads[64];
    const XrCompositionLayerBaseHeader *lp[64];
    for (int i = 0; i < 64; i++) {
        quads[i] = (XrCompositionLayerQuad){.type = XR_TYPE_COMPOSITION_LAYER_QUAD, .space = a.local,
                                            .eyeVisibility = XR_EYE_VISIBILITY_BOTH,
                                            .subImage = {sc, {{0, 0}, {32, 32}}, 0},
                                            .pose = {{0, 0, 0, 1}, {0, 0, -1.0f - 0.01f * (float)i}},
                                            .size = {0.5f, 0.5f}};
        lp[i] = (const XrCompositionLayerBaseHeader *)&quads[i];
    }
    assert_true(max_layers < 64);
    CHECK_XR(frame(&a, lp, max_layers));
    EXPECT(XR_ERROR_LAYER_LIMIT_EXCEEDED, frame(&a, lp, max_layers + 1));
    /* the frame is still open after a refused xrEndFrame: the next calls end it */
    XrFrameEndInfo ei = {.type = XR_TYPE_FRAME_END_INFO, .displayTime = 1,
                         .environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE, .layerCount = 1, .layers = lp};
    EXPECT(XR_ERROR_LAYER_LIMIT_EXCEEDED, (ei.layerCount = UINT32_MAX, xrEndFrame(a.sess, &ei)));
    ei.layerCount = 1;
    quads[0].subImage.imageRect = (XrRect2Di){{16, 0}, {32, 32}}; /* past the right edge */
    EXPECT(XR_ERROR_SWAPCHAIN_RECT_INVALID, xrEndFrame(a.sess, &ei));
    quads[0].subImage.imageRect = (XrRect2Di){{0, 0}, {0, 32}}; /* empty */
    EXPECT(XR_ERROR_SWAPCHAIN_RECT_INVALID, xrEndFrame(a.sess, &ei));
    quads[0].subImage.imageRect = (XrRect2Di){{-1, 0}, {8, 8}};
    EXPECT(XR_ERROR_SWAPCHAIN_RECT_INVALID, xrEndFrame(a.sess, &ei));
    quads[0].subImage.imageRect = (XrRect2Di){{INT32_MAX, INT32_MAX}, {INT32_MAX, INT32_MAX}};
    EXPECT(XR_ERROR_SWAPCHAIN_RECT_INVALID, xrEndFrame(a.sess, &ei));
    quads[0].subImage.imageRect = (XrRect2Di){{0, 0}, {32, 32}};
    quads[0].subImage.imageArrayIndex = 1; /* arraySize 1 */
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrEndFrame(a.sess, &ei));
    quads[0].subImage.imageArrayIndex = 0;
    quads[0].subImage.swapchain = XR_NULL_HANDLE;
    EXPECT(XR_ERROR_HANDLE_INVALID, xrEndFrame(a.sess, &ei));
    quads[0].subImage.swapchain = sc;
    quads[0].space = XR_NULL_HANDLE;
    EXPECT(XR_ERROR_HANDLE_INVALID, xrEndFrame(a.sess, &ei));
    quads[0].space = a.local;
    quads[0].pose.orientation.w = 0; /* not a unit quaternion */
    EXPECT(XR_ERROR_POSE_INVALID, xrEndFrame(a.sess, &ei));
    quads[0].pose.orientation.w = 1;
    quads[0].type = UNKNOWN_TYPE;
    EXPECT(XR_ERROR_LAYER_INVALID, xrEndFrame(a.sess, &ei));
    quads[0].type = XR_TYPE_COMPOSITION_LAYER_QUAD;
    const XrCompositionLayerBaseHeader *null_layer = NULL;
    ei.layers = &null_layer;
    EXPECT(XR_ERROR_LAYER_INVALID, xrEndFrame(a.sess, &ei));
    ei.layers = NULL;
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrEndFrame(a.sess, &ei));
    ei.layers = lp;
    /* a projection layer: its view count must be the session's (2) */
    XrCompositionLayerProjectionView pv[2];
    for (int e = 0; e < 2; e++)
        pv[e] = (XrCompositionLayerProjectionView){.type = XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW,
                                                   .pose = {{0, 0, 0, 1}, {0, 0, 0}},
                                                   .fov = {-0.7f, 0.7f, 0.7f, -0.7f},
                                                   .subImage = {sc, {{0, 0}, {32, 32}}, 0}};
    XrCompositionLayerProjection proj = {.type = XR_TYPE_COMPOSITION_LAYER_PROJECTION, .space = a.local,
                                         .viewCount = 1, .views = pv};
    const XrCompositionLayerBaseHeader *pl = (const XrCompositionLayerBaseHeader *)&proj;
    ei.layers = &pl;
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrEndFrame(a.sess, &ei));
    proj.viewCount = UINT32_MAX;
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrEndFrame(a.sess, &ei));
    proj.viewCount = 2;
    proj.views = NULL;
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrEndFrame(a.sess, &ei));
    proj.views = pv;
    pv[1].subImage.imageArrayIndex = 5;
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrEndFrame(a.sess, &ei));
    pv[1].subImage.imageArrayIndex = 0;
    pv[1].fov.angleLeft = NAN;
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrEndFrame(a.sess, &ei));
    pv[1].fov.angleLeft = -0.7f;
    ei.environmentBlendMode = (XrEnvironmentBlendMode)0x7fff;
    EXPECT(XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED, xrEndFrame(a.sess, &ei));
    ei.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    ei.displayTime = 0;
    EXPECT(XR_ERROR_TIME_INVALID, xrEndFrame(a.sess, &ei));
    ei.displayTime = 1;
    CHECK_XR(xrEndFrame(a.sess, &ei)); /* the projection layer as it should be */
    EXPECT(XR_ERROR_CALL_ORDER_INVALID, xrEndFrame(a.sess, &ei)); /* twice */
    /* the swapchain destroyed: its layers name a dead handle */
    CHECK_XR(xrDestroySwapchain(sc));
    EXPECT(XR_ERROR_HANDLE_INVALID, frame(&a, lp, 1));
    CHECK_XR(frame(&a, NULL, 0));
    close_app(&a);
    unsetenv("FOVEA_XR_STATS");
    /* the frames with layers were composited: the maximum (16 quads) and the projection layer */
    char *json = fv_test_read_file(stats, NULL);
    const char *k = strstr(json, "\"frames_composited\":");
    assert_non_null(k);
    print_message("frames composited: %d\n", atoi(k + strlen("\"frames_composited\":")));
    assert_int_equal(atoi(k + strlen("\"frames_composited\":")), 2);
    free(json);
}

/* Handles, structure types, call order and counts on a headless session (XR_MND_headless). */
static void handles_types_and_call_order_are_checked(void **state)
{
    (void)state;
    app a;
    open_headless(&a, true);
    XrSystemId sys;
    XrSystemGetInfo sg = {.type = XR_TYPE_SYSTEM_GET_INFO, .formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY};
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrGetSystem(a.inst, NULL, &sys));
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrGetSystem(a.inst, &sg, NULL));
    sg.type = XR_TYPE_SESSION_CREATE_INFO;
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrGetSystem(a.inst, &sg, &sys));
    sg.type = XR_TYPE_SYSTEM_GET_INFO;
    XrSystemProperties sp = {.type = XR_TYPE_SYSTEM_PROPERTIES};
    EXPECT(XR_ERROR_SYSTEM_INVALID, xrGetSystemProperties(a.inst, a.sys + 100, &sp));
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrGetSystemProperties(a.inst, a.sys, NULL));
    /* absurd capacities: the runtime writes only what there is */
    XrViewConfigurationType types[4];
    uint32_t n = 0;
    CHECK_XR(xrEnumerateViewConfigurations(a.inst, a.sys, 0, &n, NULL));
    assert_true(n >= 1 && n <= 4);
    CHECK_XR(xrEnumerateViewConfigurations(a.inst, a.sys, UINT32_MAX, &n, types));
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrEnumerateViewConfigurations(a.inst, a.sys, 4, &n, NULL));
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrEnumerateViewConfigurations(a.inst, a.sys, 4, NULL, types));
    XrViewConfigurationView views[2] = {{.type = XR_TYPE_VIEW_CONFIGURATION_VIEW},
                                        {.type = XR_TYPE_VIEW_CONFIGURATION_VIEW}};
    EXPECT(XR_ERROR_SIZE_INSUFFICIENT, xrEnumerateViewConfigurationViews(a.inst, a.sys,
                                                                        XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 1,
                                                                        &n, views));
    views[1].type = XR_TYPE_VIEW;
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrEnumerateViewConfigurationViews(a.inst, a.sys,
                                                                         XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO,
                                                                         UINT32_MAX, &n, views));
    char buf[XR_MAX_RESULT_STRING_SIZE];
    CHECK_XR(xrResultToString(a.inst, (XrResult)-0x7fffffff, buf));
    /* session calls before there is a session, on a NULL or foreign handle */
    XrFrameState fs = {.type = XR_TYPE_FRAME_STATE};
    EXPECT(XR_ERROR_HANDLE_INVALID, xrWaitFrame(XR_NULL_HANDLE, NULL, &fs));
    EXPECT(XR_ERROR_HANDLE_INVALID, xrBeginFrame((XrSession)(void *)a.inst, NULL)); /* an instance as a session */
    XrSessionCreateInfo sci = {.type = XR_TYPE_SESSION_CREATE_INFO, .systemId = a.sys};
    XrSession s2;
    sci.createFlags = 1;
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrCreateSession(a.inst, &sci, &s2));
    sci.createFlags = 0;
    sci.systemId = a.sys + 7;
    EXPECT(XR_ERROR_SYSTEM_INVALID, xrCreateSession(a.inst, &sci, &s2));
    create_session(&a, NULL);
    EXPECT(XR_ERROR_LIMIT_REACHED, (sci.systemId = a.sys, xrCreateSession(a.inst, &sci, &s2)));
    /* frame calls before xrBeginSession */
    EXPECT(XR_ERROR_SESSION_NOT_RUNNING, xrWaitFrame(a.sess, NULL, &fs));
    EXPECT(XR_ERROR_SESSION_NOT_RUNNING, xrBeginFrame(a.sess, NULL));
    XrFrameEndInfo ei = {.type = XR_TYPE_FRAME_END_INFO, .displayTime = 1,
                         .environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE};
    EXPECT(XR_ERROR_SESSION_NOT_RUNNING, xrEndFrame(a.sess, &ei));
    EXPECT(XR_ERROR_SESSION_NOT_RUNNING, xrEndSession(a.sess));
    EXPECT(XR_ERROR_SESSION_NOT_RUNNING, xrRequestExitSession(a.sess));
    XrSessionBeginInfo bi = {.type = XR_TYPE_SESSION_BEGIN_INFO,
                             .primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO};
    bi.type = XR_TYPE_FRAME_END_INFO;
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrBeginSession(a.sess, &bi));
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrBeginSession(a.sess, NULL));
    begin_session(&a);
    EXPECT(XR_ERROR_SESSION_RUNNING, (bi.type = XR_TYPE_SESSION_BEGIN_INFO, xrBeginSession(a.sess, &bi)));
    /* out of order: xrBeginFrame without xrWaitFrame, xrEndFrame without xrBeginFrame, xrEndFrame twice */
    EXPECT(XR_ERROR_CALL_ORDER_INVALID, xrBeginFrame(a.sess, NULL));
    EXPECT(XR_ERROR_CALL_ORDER_INVALID, xrEndFrame(a.sess, &ei));
    fs.type = XR_TYPE_FRAME_WAIT_INFO;
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrWaitFrame(a.sess, NULL, &fs));
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrWaitFrame(a.sess, NULL, NULL));
    fs.type = XR_TYPE_FRAME_STATE;
    CHECK_XR(xrWaitFrame(a.sess, NULL, &fs));
    XrFrameBeginInfo fbi = {.type = XR_TYPE_FRAME_STATE};
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrBeginFrame(a.sess, &fbi));
    CHECK_XR(xrBeginFrame(a.sess, NULL));
    ei.displayTime = fs.predictedDisplayTime;
    CHECK_XR(xrEndFrame(a.sess, &ei));
    EXPECT(XR_ERROR_CALL_ORDER_INVALID, xrEndFrame(a.sess, &ei));
    EXPECT(XR_ERROR_CALL_ORDER_INVALID, xrBeginFrame(a.sess, NULL));
    /* a headless session has no swapchains */
    int64_t fmt[8];
    CHECK_XR(xrEnumerateSwapchainFormats(a.sess, 8, &n, fmt));
    assert_int_equal(n, 0);
    XrSwapchainCreateInfo sci2 = {.type = XR_TYPE_SWAPCHAIN_CREATE_INFO, .width = 64, .height = 64, .mipCount = 8,
                                  .sampleCount = 1, .faceCount = 1, .arraySize = 1};
    XrSwapchain sc;
    EXPECT(XR_ERROR_FEATURE_UNSUPPORTED, xrCreateSwapchain(a.sess, &sci2, &sc));
    /* spaces */
    XrReferenceSpaceCreateInfo rs = {.type = XR_TYPE_REFERENCE_SPACE_CREATE_INFO,
                                     .referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW,
                                     .poseInReferenceSpace = {.orientation = {0, 0, 0, 1}}};
    XrSpace view;
    CHECK_XR(xrCreateReferenceSpace(a.sess, &rs, &view));
    XrSpaceLocation loc = {.type = XR_TYPE_SPACE_LOCATION};
    CHECK_XR(xrLocateSpace(view, a.local, fs.predictedDisplayTime, &loc));
    EXPECT(XR_ERROR_TIME_INVALID, xrLocateSpace(view, a.local, 0, &loc));
    EXPECT(XR_ERROR_HANDLE_INVALID, xrLocateSpace(view, XR_NULL_HANDLE, 1, &loc));
    CHECK_XR(xrDestroySpace(view));
    EXPECT(XR_ERROR_HANDLE_INVALID, xrLocateSpace(view, a.local, 1, &loc));
    EXPECT(XR_ERROR_HANDLE_INVALID, xrDestroySpace(view));
    rs.poseInReferenceSpace.orientation.w = 0;
    EXPECT(XR_ERROR_POSE_INVALID, xrCreateReferenceSpace(a.sess, &rs, &view));
    /* the session destroyed: its handle and its spaces are dead */
    XrSession dead = a.sess;
    XrSpace dead_space = a.local;
    CHECK_XR(xrRequestExitSession(a.sess));
    poll_events(&a);
    CHECK_XR(xrEndSession(a.sess));
    CHECK_XR(xrDestroySession(a.sess));
    a.sess = XR_NULL_HANDLE;
    EXPECT(XR_ERROR_HANDLE_INVALID, xrWaitFrame(dead, NULL, &fs));
    EXPECT(XR_ERROR_HANDLE_INVALID, xrBeginFrame(dead, NULL));
    EXPECT(XR_ERROR_HANDLE_INVALID, xrEndFrame(dead, &ei));
    EXPECT(XR_ERROR_HANDLE_INVALID, xrBeginSession(dead, &bi));
    EXPECT(XR_ERROR_HANDLE_INVALID, xrDestroySession(dead));
    EXPECT(XR_ERROR_HANDLE_INVALID, xrLocateSpace(dead_space, dead_space, 1, &loc));
    EXPECT(XR_ERROR_HANDLE_INVALID, xrEnumerateSwapchainFormats(dead, 0, &n, NULL));
    close_app(&a);
}

/* (e) The conformance points: form factors and reference spaces the runtime does not know, view configurations,
 * maxLayerCount, vendorId; placeholder layers in a headless session. */
static void conformance_points(void **state)
{
    (void)state;
    app a;
    open_headless(&a, false);
    XrSystemId sys;
    XrSystemGetInfo sg = {.type = XR_TYPE_SYSTEM_GET_INFO, .formFactor = (XrFormFactor)0x7fffffff};
    EXPECT(XR_ERROR_FORM_FACTOR_UNSUPPORTED, xrGetSystem(a.inst, &sg, &sys));
    sg.formFactor = (XrFormFactor)99;
    EXPECT(XR_ERROR_FORM_FACTOR_UNSUPPORTED, xrGetSystem(a.inst, &sg, &sys));
    sg.formFactor = XR_FORM_FACTOR_HANDHELD_DISPLAY;
    EXPECT(XR_ERROR_FORM_FACTOR_UNSUPPORTED, xrGetSystem(a.inst, &sg, &sys));
    XrSystemProperties sp = {.type = XR_TYPE_SYSTEM_PROPERTIES};
    CHECK_XR(xrGetSystemProperties(a.inst, a.sys, &sp));
    assert_int_not_equal(sp.vendorId, 0);
    assert_true(sp.graphicsProperties.maxLayerCount >= XR_MIN_COMPOSITION_LAYERS_SUPPORTED);
    uint32_t n = 0;
    XrViewConfigurationProperties vp = {.type = XR_TYPE_VIEW_CONFIGURATION_PROPERTIES};
    EXPECT(XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED,
           xrGetViewConfigurationProperties(a.inst, a.sys, (XrViewConfigurationType)0x7fffffff, &vp));
    EXPECT(XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED,
           xrEnumerateViewConfigurationViews(a.inst, a.sys, XR_VIEW_CONFIGURATION_TYPE_MAX_ENUM, 0, &n, NULL));
    EXPECT(XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED,
           xrEnumerateEnvironmentBlendModes(a.inst, a.sys, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_MONO, 0, &n, NULL));
    create_session(&a, NULL);
    XrReferenceSpaceCreateInfo rs = {.type = XR_TYPE_REFERENCE_SPACE_CREATE_INFO,
                                     .referenceSpaceType = (XrReferenceSpaceType)0x7ffffff0,
                                     .poseInReferenceSpace = {.orientation = {0, 0, 0, 1}}};
    XrSpace sp2;
    EXPECT(XR_ERROR_REFERENCE_SPACE_UNSUPPORTED, xrCreateReferenceSpace(a.sess, &rs, &sp2));
    rs.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_MAX_ENUM;
    EXPECT(XR_ERROR_REFERENCE_SPACE_UNSUPPORTED, xrCreateReferenceSpace(a.sess, &rs, &sp2));
    rs.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_UNBOUNDED_MSFT;
    EXPECT(XR_ERROR_REFERENCE_SPACE_UNSUPPORTED, xrCreateReferenceSpace(a.sess, &rs, &sp2));
    XrExtent2Df bounds;
    EXPECT(XR_ERROR_REFERENCE_SPACE_UNSUPPORTED,
           xrGetReferenceSpaceBoundsRect(a.sess, (XrReferenceSpaceType)12345, &bounds));
    /* headless too: a view configuration the system does not enumerate is refused (the CTS's SessionState) */
    XrSessionBeginInfo mono = {.type = XR_TYPE_SESSION_BEGIN_INFO,
                               .primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_MONO};
    EXPECT(XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED, xrBeginSession(a.sess, &mono));
    mono.primaryViewConfigurationType = (XrViewConfigurationType)0x7ffffff1;
    EXPECT(XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED, xrBeginSession(a.sess, &mono));
    begin_session(&a);
    /* headless: a projection layer with no views and a quad with no swapchain are placeholders, ignored */
    XrCompositionLayerProjection proj = {.type = XR_TYPE_COMPOSITION_LAYER_PROJECTION, .space = a.local};
    XrCompositionLayerQuad quad = {.type = XR_TYPE_COMPOSITION_LAYER_QUAD, .space = a.local,
                                   .pose = {{0, 0, 0, 1}, {0, 0, -1}}, .size = {1, 1}};
    const XrCompositionLayerBaseHeader *layers[2] = {(const void *)&proj, (const void *)&quad};
    CHECK_XR(frame(&a, layers, 2));
    CHECK_XR(frame(&a, layers, 1));
    XrFrameState fs = {.type = XR_TYPE_FRAME_STATE};
    CHECK_XR(xrWaitFrame(a.sess, NULL, &fs));
    CHECK_XR(xrBeginFrame(a.sess, NULL));
    XrFrameEndInfo ei = {.type = XR_TYPE_FRAME_END_INFO, .displayTime = fs.predictedDisplayTime,
                         .environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE,
                         .layerCount = sp.graphicsProperties.maxLayerCount + 1, .layers = layers};
    EXPECT(XR_ERROR_LAYER_LIMIT_EXCEEDED, xrEndFrame(a.sess, &ei)); /* the limit holds headless too */
    ei.layerCount = 0;
    CHECK_XR(xrEndFrame(a.sess, &ei));
    close_app(&a);
}

/* ---- (b) next chains ---------------------------------------------------------------------------------------- */
typedef struct any_struct {
    XrStructureType type;
    const void *next;
    uint8_t payload[512]; /* room for any structure's fields: an output structure the runtime fills stays inside */
} any_struct;

/* Every structure type the runtime looks for in a chain (input and output), those of extensions this app did not
 * enable among them, and one no one knows; linked in order. Returns the head. */
static const void *known_chain(any_struct *c, int *n)
{
    static const XrStructureType types[] = {
        XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT, XR_TYPE_SYSTEM_FOVEATED_RENDERING_PROPERTIES_VARJO,
        XR_TYPE_FOVEATED_VIEW_CONFIGURATION_VIEW_VARJO,    XR_TYPE_VIEW_LOCATE_FOVEATED_RENDERING_VARJO,
        XR_TYPE_SPACE_VELOCITY,                            XR_TYPE_GRAPHICS_BINDING_VULKAN_KHR,
        XR_TYPE_GRAPHICS_BINDING_EGL_MNDX,                 XR_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        UNKNOWN_TYPE};
    *n = (int)(sizeof types / sizeof types[0]);
    for (int i = 0; i < *n; i++) {
        memset(&c[i], 0, sizeof c[i]);
        c[i].type = types[i];
        c[i].next = i + 1 < *n ? &c[i + 1] : NULL;
    }
    return &c[0];
}

/* A chain of `len` unknown structures, its last linking back to `loop_to` (NULL: ends). */
static const void *unknown_chain(any_struct *c, int len, const any_struct *loop_to)
{
    for (int i = 0; i < len; i++) {
        memset(&c[i], 0, sizeof c[i]);
        c[i].type = UNKNOWN_TYPE;
        c[i].next = i + 1 < len ? (const void *)&c[i + 1] : (const void *)loop_to;
    }
    return &c[0];
}

/* Every input (and output) struct the runtime reads a chain of, called with `chain`; `want` for each. */
static void call_with_chain(app *a, const void *chain, XrResult want, bool session_calls)
{
    XrSystemId sys;
    XrSystemGetInfo sg = {.type = XR_TYPE_SYSTEM_GET_INFO, .next = chain,
                          .formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY};
    EXPECT(want, xrGetSystem(a->inst, &sg, &sys));
    XrSystemProperties sp = {.type = XR_TYPE_SYSTEM_PROPERTIES, .next = (void *)chain};
    EXPECT(want, xrGetSystemProperties(a->inst, a->sys, &sp));
    XrViewConfigurationView views[2] = {{.type = XR_TYPE_VIEW_CONFIGURATION_VIEW, .next = (void *)chain},
                                        {.type = XR_TYPE_VIEW_CONFIGURATION_VIEW}};
    uint32_t n = 0;
    EXPECT(want, xrEnumerateViewConfigurationViews(a->inst, a->sys, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 2, &n,
                                                   views));
    if (!session_calls) return;
    XrReferenceSpaceCreateInfo rs = {.type = XR_TYPE_REFERENCE_SPACE_CREATE_INFO, .next = chain,
                                     .referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW,
                                     .poseInReferenceSpace = {.orientation = {0, 0, 0, 1}}};
    XrSpace view = XR_NULL_HANDLE;
    EXPECT(want, xrCreateReferenceSpace(a->sess, &rs, &view));
    if (view) CHECK_XR(xrDestroySpace(view));
    XrSpaceLocation loc = {.type = XR_TYPE_SPACE_LOCATION, .next = (void *)chain};
    XrFrameWaitInfo wi = {.type = XR_TYPE_FRAME_WAIT_INFO, .next = chain};
    XrFrameState fs = {.type = XR_TYPE_FRAME_STATE};
    EXPECT(want, xrWaitFrame(a->sess, &wi, &fs));
    if (want != XR_SUCCESS) CHECK_XR(xrWaitFrame(a->sess, NULL, &fs));
    EXPECT(want, xrLocateSpace(a->local, a->local, fs.predictedDisplayTime, &loc));
    XrViewLocateInfo li = {.type = XR_TYPE_VIEW_LOCATE_INFO, .next = chain,
                           .viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO,
                           .displayTime = fs.predictedDisplayTime, .space = a->local};
    XrViewState vs = {.type = XR_TYPE_VIEW_STATE};
    XrView xv[2] = {{.type = XR_TYPE_VIEW}, {.type = XR_TYPE_VIEW}};
    EXPECT(want, xrLocateViews(a->sess, &li, &vs, 2, &n, xv));
    XrFrameBeginInfo bi = {.type = XR_TYPE_FRAME_BEGIN_INFO, .next = chain};
    EXPECT(want, xrBeginFrame(a->sess, &bi));
    if (want != XR_SUCCESS) CHECK_XR(xrBeginFrame(a->sess, NULL));
    XrCompositionLayerQuad quad = {.type = XR_TYPE_COMPOSITION_LAYER_QUAD, .next = chain, .space = a->local,
                                   .pose = {{0, 0, 0, 1}, {0, 0, -1}}, .size = {1, 1}};
    const XrCompositionLayerBaseHeader *layers[1] = {(const void *)&quad};
    XrFrameEndInfo ei = {.type = XR_TYPE_FRAME_END_INFO, .next = chain, .displayTime = fs.predictedDisplayTime,
                         .environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE};
    EXPECT(want, xrEndFrame(a->sess, &ei));
    if (want == XR_SUCCESS) { /* the frame ended: the next one for the layer's chain */
        CHECK_XR(xrWaitFrame(a->sess, NULL, &fs));
        CHECK_XR(xrBeginFrame(a->sess, NULL));
        ei.displayTime = fs.predictedDisplayTime;
    }
    ei.next = NULL;
    ei.layerCount = 1;
    ei.layers = layers;
    EXPECT(want, xrEndFrame(a->sess, &ei)); /* the chain on a layer */
    if (want != XR_SUCCESS) {
        ei.layerCount = 0;
        CHECK_XR(xrEndFrame(a->sess, &ei));
    }
}

static void next_chains_are_bounded_and_unknown_structures_ignored(void **state)
{
    (void)state;
    static any_struct c[128];
    int n = 0;
    app a;
    /* instance creation: an over-long chain refused, a known-and-unknown one ignored (loops: the loader walks this
     * chain itself before the runtime sees it, so only the runtime's calls below get loops) */
    EXPECT(XR_ERROR_VALIDATION_FAILURE,
           create_instance(&a, (const char *const[]){XR_MND_HEADLESS_EXTENSION_NAME}, 1, NULL, 0,
                           unknown_chain(c, 100, NULL)));
    CHECK_XR(create_instance(&a, (const char *const[]){XR_MND_HEADLESS_EXTENSION_NAME}, 1, NULL, 0,
                             unknown_chain(c, 3, NULL)));
    CHECK_XR(xrDestroyInstance(a.inst));
    g_open = XR_NULL_HANDLE;
    /* XR_EXT_eye_gaze_interaction and XR_VARJO_foveated_rendering not enabled: their structures are ignored */
    open_headless(&a, false);
    const void *known = known_chain(c, &n);
    call_with_chain(&a, known, XR_SUCCESS, false);
    XrSystemEyeGazeInteractionPropertiesEXT gp = {.type = XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT,
                                                  .supportsEyeGazeInteraction = (XrBool32)77};
    XrSystemProperties sp = {.type = XR_TYPE_SYSTEM_PROPERTIES, .next = &gp};
    CHECK_XR(xrGetSystemProperties(a.inst, a.sys, &sp));
    assert_int_equal(gp.supportsEyeGazeInteraction, 77); /* not the runtime's to write */
    /* a session whose create info chains a Vulkan and an EGL binding of extensions not enabled: headless */
    XrSessionCreateInfo sci = {.type = XR_TYPE_SESSION_CREATE_INFO, .next = unknown_chain(c, 64, NULL),
                               .systemId = a.sys};
    CHECK_XR(xrCreateSession(a.inst, &sci, &a.sess));
    CHECK_XR(xrDestroySession(a.sess));
    sci.next = unknown_chain(c, 65, NULL);
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrCreateSession(a.inst, &sci, &a.sess));
    sci.next = unknown_chain(c, 2, &c[0]);
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrCreateSession(a.inst, &sci, &a.sess));
    a.sess = XR_NULL_HANDLE;
    create_session(&a, known_chain(c, &n));
    XrSessionBeginInfo bi = {.type = XR_TYPE_SESSION_BEGIN_INFO, .next = unknown_chain(c, 1, &c[0]),
                             .primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO};
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrBeginSession(a.sess, &bi));
    bi.next = known_chain(c, &n);
    CHECK_XR(xrBeginSession(a.sess, &bi));
    poll_events(&a);
    /* every call: the known-and-unknown chain ignored; a loop of one, a loop of many, an over-long chain refused */
    call_with_chain(&a, known_chain(c, &n), XR_SUCCESS, true);
    call_with_chain(&a, unknown_chain(c, 64, NULL), XR_SUCCESS, true);
    call_with_chain(&a, unknown_chain(c, 1, &c[0]), XR_ERROR_VALIDATION_FAILURE, true);
    call_with_chain(&a, unknown_chain(c, 7, &c[3]), XR_ERROR_VALIDATION_FAILURE, true);
    call_with_chain(&a, unknown_chain(c, 65, NULL), XR_ERROR_VALIDATION_FAILURE, true);
    /* a known structure inside a loop: found or not, the loop is refused */
    known_chain(c, &n);
    c[n - 1].next = &c[0];
    call_with_chain(&a, &c[0], XR_ERROR_VALIDATION_FAILURE, true);
    close_app(&a);
    /* with the extensions enabled, their output structures are filled */
    open_headless(&a, true);
    gp.supportsEyeGazeInteraction = (XrBool32)77;
    sp.next = &gp;
    CHECK_XR(xrGetSystemProperties(a.inst, a.sys, &sp));
    assert_true(gp.supportsEyeGazeInteraction == XR_FALSE || gp.supportsEyeGazeInteraction == XR_TRUE);
    /* the action system's input structs with the known-and-unknown chain: ignored */
    create_session(&a, known_chain(c, &n));
    XrActionSetCreateInfo si = {.type = XR_TYPE_ACTION_SET_CREATE_INFO, .next = known_chain(c, &n),
                                .actionSetName = "misuse", .localizedActionSetName = "Misuse"};
    XrActionSet set;
    CHECK_XR(xrCreateActionSet(a.inst, &si, &set));
    XrActionCreateInfo ai = {.type = XR_TYPE_ACTION_CREATE_INFO, .next = known_chain(c, &n), .actionName = "gaze",
                             .actionType = XR_ACTION_TYPE_POSE_INPUT, .localizedActionName = "Gaze"};
    XrAction gaze;
    CHECK_XR(xrCreateAction(set, &ai, &gaze));
    XrPath profile, binding;
    CHECK_XR(xrStringToPath(a.inst, "/interaction_profiles/ext/eye_gaze_interaction", &profile));
    CHECK_XR(xrStringToPath(a.inst, "/user/eyes_ext/input/gaze_ext/pose", &binding));
    XrActionSuggestedBinding sb = {gaze, binding};
    XrInteractionProfileSuggestedBinding ps = {.type = XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING,
                                               .next = known_chain(c, &n), .interactionProfile = profile,
                                               .countSuggestedBindings = 1, .suggestedBindings = &sb};
    CHECK_XR(xrSuggestInteractionProfileBindings(a.inst, &ps));
    XrSessionActionSetsAttachInfo at = {.type = XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO, .next = known_chain(c, &n),
                                        .countActionSets = 1, .actionSets = &set};
    CHECK_XR(xrAttachSessionActionSets(a.sess, &at));
    XrActionSpaceCreateInfo asi = {.type = XR_TYPE_ACTION_SPACE_CREATE_INFO, .next = known_chain(c, &n),
                                   .action = gaze, .poseInActionSpace = {.orientation = {0, 0, 0, 1}}};
    XrSpace gaze_space;
    CHECK_XR(xrCreateActionSpace(a.sess, &asi, &gaze_space));
    asi.next = unknown_chain(c, 3, &c[1]);
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrCreateActionSpace(a.sess, &asi, &gaze_space));
    begin_session(&a);
    XrActiveActionSet active = {set, XR_NULL_PATH};
    XrActionsSyncInfo sync = {.type = XR_TYPE_ACTIONS_SYNC_INFO, .next = known_chain(c, &n),
                              .countActiveActionSets = 1, .activeActionSets = &active};
    CHECK_XR(xrSyncActions(a.sess, &sync));
    XrActionStateGetInfo gi = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .next = known_chain(c, &n), .action = gaze};
    XrActionStatePose pose = {.type = XR_TYPE_ACTION_STATE_POSE, .next = (void *)known_chain(c, &n)};
    CHECK_XR(xrGetActionStatePose(a.sess, &gi, &pose));
    close_app(&a);
}

/* ---- (d) an HMD profile bigger than the swapchain limit ------------------------------------------------------- */
static void recommended_sizes_stay_within_the_reported_maximum(void **state)
{
    (void)state;
    /* generic.json with a 16384 x 16384 panel (the largest `--hmd` accepts): 8192 x 16384 per eye */
    char *json = fv_test_read_file(FV_XR_TEST_HMD_DIR "/generic.json", NULL);
    char *w = strstr(json, "\"width_px\"");
    char *h = strstr(json, "\"height_px\"");
    assert_non_null(w);
    assert_non_null(h);
    char out[16384];
    size_t o = 0;
    for (char *p = json; *p && o + 64 < sizeof out;) {
        if (p == w || p == h) {
            o += (size_t)snprintf(out + o, sizeof out - o, "%s: 16384", p == w ? "\"width_px\"" : "\"height_px\"");
            p = strpbrk(p + 1, ",}");
            assert_non_null(p);
        } else {
            out[o++] = *p++;
        }
    }
    out[o] = 0;
    free(json);
    const char *path = fv_test_write_file("hmd_16k.json", out, o);
    /* the runtime's log (stderr) into a file: the clamp is said once */
    const char *log = fv_test_tmp("xr_16k.log");
    fflush(stderr);
    int saved = dup(2), fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    assert_true(saved >= 0 && fd >= 0);
    dup2(fd, 2);
    close(fd);
    setenv("FOVEA_XR_HMD", path, 1);
    /* the answers gathered with stderr in the file, checked after it is back */
    XrViewConfigurationView v[2][3][2];
    XrSystemProperties sp[2];
    uint32_t n[2][3];
    for (int scale = 0; scale < 2; scale++) {
        setenv("FOVEA_XR_SCALE", scale ? "2.0" : "1.0", 1);
        app a;
        open_headless(&a, false);
        sp[scale] = (XrSystemProperties){.type = XR_TYPE_SYSTEM_PROPERTIES};
        CHECK_XR(xrGetSystemProperties(a.inst, a.sys, &sp[scale]));
        for (int k = 0; k < 3; k++) {
            v[scale][k][0] = v[scale][k][1] = (XrViewConfigurationView){.type = XR_TYPE_VIEW_CONFIGURATION_VIEW};
            CHECK_XR(xrEnumerateViewConfigurationViews(a.inst, a.sys, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 2,
                                                       &n[scale][k], v[scale][k]));
        }
        close_app(&a);
    }
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    unsetenv("FOVEA_XR_HMD");
    unsetenv("FOVEA_XR_SCALE");
    for (int scale = 0; scale < 2; scale++) {
        const XrSystemGraphicsProperties *g = &sp[scale].graphicsProperties;
        for (int k = 0; k < 3; k++) {
            assert_int_equal(n[scale][k], 2);
            for (uint32_t i = 0; i < 2; i++) {
                const XrViewConfigurationView *x = &v[scale][k][i];
                print_message("scale %d: recommended %ux%u, max %ux%u (system %ux%u)\n", scale + 1,
                              x->recommendedImageRectWidth, x->recommendedImageRectHeight, x->maxImageRectWidth,
                              x->maxImageRectHeight, g->maxSwapchainImageWidth, g->maxSwapchainImageHeight);
                assert_true(x->recommendedImageRectWidth <= x->maxImageRectWidth);
                assert_true(x->recommendedImageRectHeight <= x->maxImageRectHeight);
                assert_true(x->recommendedImageRectWidth <= g->maxSwapchainImageWidth);
                assert_true(x->recommendedImageRectHeight <= g->maxSwapchainImageHeight);
                /* the panel's per-eye aspect (1:2) kept, the larger side at the maximum */
                assert_int_equal(x->recommendedImageRectHeight, g->maxSwapchainImageHeight);
                assert_int_equal(x->recommendedImageRectWidth * 2, x->recommendedImageRectHeight);
            }
        }
    }
    char *text = fv_test_read_file(log, NULL);
    int said = 0;
    for (const char *p = text; (p = strstr(p, "exceeds the largest swapchain image")); p++) said++;
    print_message("the clamp said %d times (once per instance)\n", said);
    assert_int_equal(said, 2);
    free(text);
}

/* ---- (c) layer names in enabledApiLayerNames ----------------------------------------------------------------- */
static void named_api_layers_are_left_to_the_loader(void **state)
{
    (void)state;
    unsetenv("XR_ENABLE_API_LAYERS");
    setenv("XR_CORE_VALIDATION_EXPORT_TYPE", "text", 1);
    const char *vlog = fv_test_tmp("core_validation.txt");
    remove(vlog);
    setenv("XR_CORE_VALIDATION_FILE_NAME", vlog, 1);
    const char *layers[] = {"XR_APILAYER_LUNARG_core_validation"};
    const char *exts[] = {XR_MND_HEADLESS_EXTENSION_NAME};
    app a;
    CHECK_XR(create_instance(&a, exts, 1, layers, 1, NULL));
    XrSystemGetInfo sg = {.type = XR_TYPE_SYSTEM_GET_INFO, .formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY};
    CHECK_XR(xrGetSystem(a.inst, &sg, &a.sys));
    create_session(&a, NULL);
    begin_session(&a);
    for (int i = 0; i < 5; i++) CHECK_XR(frame(&a, NULL, 0));
    poll_events(&a);
    assert_int_equal(a.state, XR_SESSION_STATE_FOCUSED);
    /* the layer is there: a call only it refuses (a NULL info; the runtime says the same) goes into its report */
    XrSystemId sys;
    EXPECT(XR_ERROR_VALIDATION_FAILURE, xrGetSystem(a.inst, NULL, &sys));
    close_app(&a);
    char *report = fv_test_read_file(vlog, NULL);
    print_message("core validation's report:\n%s\n", report);
    assert_non_null(strstr(report, "xrGetSystem"));
    /* and nothing about the valid session and frames */
    assert_null(strstr(report, "xrCreateSession"));
    assert_null(strstr(report, "Frame"));
    free(report);
    unsetenv("XR_CORE_VALIDATION_FILE_NAME");
    unsetenv("XR_CORE_VALIDATION_EXPORT_TYPE");
}

static void on_watchdog(int sig)
{
    (void)sig;
    static const char msg[] = "test_xr_misuse: watchdog: a call did not return (hang)\n";
    (void)!write(2, msg, sizeof msg - 1);
    _exit(124);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s RUNTIME_MANIFEST [TEST_NAME_PATTERN]\n", argv[0]);
        return 2;
    }
    g_manifest = argv[1];
    /* Mesa's lavapipe stays loaded after the last VkInstance goes, so that LeakSanitizer can name it in its report
     * (lavapipe keeps a few allocations per load: suppressed in lsan_openxr_loader.supp); absent elsewhere: no-op */
    dlopen("libvulkan_lvp.so", RTLD_NOW | RTLD_NODELETE);
    signal(SIGALRM, on_watchdog);
    alarm(WATCHDOG_S);
    unsetenv("XR_ENABLE_API_LAYERS"); /* every call reaches the runtime */
    unsetenv("FOVEA_XR_GAZE");
    unsetenv("FOVEA_XR_HMD");
    unsetenv("FOVEA_XR_SCALE");
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_teardown(swapchain_create_infos_are_checked_against_the_reported_limits, teardown),
        cmocka_unit_test_teardown(end_frame_layers_are_checked, teardown),
        cmocka_unit_test_teardown(handles_types_and_call_order_are_checked, teardown),
        cmocka_unit_test_teardown(conformance_points, teardown),
        cmocka_unit_test_teardown(next_chains_are_bounded_and_unknown_structures_ignored, teardown),
        cmocka_unit_test_teardown(recommended_sizes_stay_within_the_reported_maximum, teardown),
        cmocka_unit_test_teardown(named_api_layers_are_left_to_the_loader, teardown),
    };
    if (argc > 2) cmocka_set_test_filter(argv[2]);
    return cmocka_run_group_tests(tests, NULL, NULL);
}
