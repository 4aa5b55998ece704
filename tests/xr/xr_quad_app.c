/* @brief A Vulkan2 OpenXR app of our own rendering quad views (XR_VARJO_quad_views) with gaze-driven insets
 * (XR_VARJO_foveated_rendering) on fovea's runtime, through the OpenXR loader (XR_RUNTIME_JSON) with the OpenXR
 * core-validation layer and the Vulkan validation layer on its own device. It enumerates the view configurations,
 * picks PRIMARY_QUAD_VARJO, asks for the foveated view sizes when the system supports foveated rendering, and each
 * frame locates the rendering gaze (XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO) and the views with foveated rendering
 * active while the gaze is tracked. Each view gets the same pattern of the world (brightness 0.6 + 0.4 cos cos of the
 * view ray's angles, period 10 deg) in blue for the wide views and red for the insets, written from the CPU into the
 * swapchain image (a buffer copy), so the composite shows where the runtime put each inset and how it blends.
 * Prints one CSV line per frame: `frame,N,composited,C,tracked,T,gaze_tx,X,gaze_ty,Y,inset_left,L,R,U,D,wide_left,
 * L,R,U,D,wide_right,L,R,U,D` (the gaze as tangents in VIEW, the left inset's and the wide views' fov in radians;
 * composited: the frame was ended while the session was VISIBLE or FOCUSED, so fovea composited it), and
 * `vk_validation_messages,N` at the end (exit 1 when N > 0).
 *   xr_quad_app [--frames N] [--stereo-only]
 * --stereo-only: enable neither Varjo extension and check that only PRIMARY_STEREO is offered (prints
 * `view_configs,STEREO` and exits). */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "xr_app.h"
#include "xr_app_vk.h"

#define CHECK_XR(call)                                                                                                 \
    do {                                                                                                               \
        XrResult r_ = (call);                                                                                          \
        if (XR_FAILED(r_)) {                                                                                           \
            fprintf(stderr, "xr_quad_app: %s failed: %d\n", #call, (int)r_);                                           \
            exit(1);                                                                                                   \
        }                                                                                                              \
    } while (0)
#define CHECK_VK(call)                                                                                                 \
    do {                                                                                                               \
        VkResult r_ = (call);                                                                                          \
        if (r_ != VK_SUCCESS) {                                                                                        \
            fprintf(stderr, "xr_quad_app: %s failed: %d\n", #call, (int)r_);                                           \
            exit(1);                                                                                                   \
        }                                                                                                              \
    } while (0)

#define MAX_VIEWS 4
#define MAX_IMAGES 8

static int g_vk_messages;

static VKAPI_ATTR VkBool32 VKAPI_CALL on_vk_message(VkDebugUtilsMessageSeverityFlagBitsEXT sev,
                                                   VkDebugUtilsMessageTypeFlagsEXT type,
                                                   const VkDebugUtilsMessengerCallbackDataEXT *d, void *user)
{
    (void)type;
    (void)user;
    if (sev & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)) {
        g_vk_messages++;
        fprintf(stderr, "xr_quad_app: Vulkan validation: %s\n", d->pMessage);
    }
    return VK_FALSE;
}

typedef struct view_target {
    XrSwapchain swapchain;
    uint32_t width, height, image_count;
    VkImage images[MAX_IMAGES];
    VkBuffer staging;
    VkDeviceMemory staging_mem;
    uint8_t *pixels; /* mapped, width x height RGBA8 (sRGB-encoded) */
} view_target;

typedef struct app {
    XrInstance inst;
    XrSystemId system;
    XrSession session;
    XrSpace local, view, gaze;
    bool quad, foveated_supported;
    XrViewConfigurationType config;
    uint32_t view_count;
    VkInstance vk_inst;
    VkDebugUtilsMessengerEXT messenger;
    VkPhysicalDevice phys;
    VkDevice device;
    uint32_t family;
    VkQueue queue;
    VkCommandPool pool;
    VkCommandBuffer cmd;
    VkFence fence;
    view_target views[MAX_VIEWS];
} app;

static bool has_ext(const XrExtensionProperties *p, uint32_t n, const char *name)
{
    for (uint32_t i = 0; i < n; i++)
        if (!strcmp(p[i].extensionName, name)) return true;
    return false;
}

static const char *config_name(XrViewConfigurationType t)
{
    switch (t) {
    case XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO: return "STEREO";
    case XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO: return "QUAD_VARJO";
    case XR_VIEW_CONFIGURATION_TYPE_PRIMARY_MONO: return "MONO";
    default: return "OTHER";
    }
}

static void create_instance(app *a, bool stereo_only)
{
    uint32_t n = 0;
    CHECK_XR(xrEnumerateInstanceExtensionProperties(NULL, 0, &n, NULL));
    XrExtensionProperties *props = calloc(n, sizeof *props);
    for (uint32_t i = 0; i < n; i++) props[i].type = XR_TYPE_EXTENSION_PROPERTIES;
    CHECK_XR(xrEnumerateInstanceExtensionProperties(NULL, n, &n, props));
    const char *exts[4] = {XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME, XR_MND_HEADLESS_EXTENSION_NAME};
    uint32_t ne = 2;
    if (!stereo_only) {
        if (!has_ext(props, n, XR_VARJO_QUAD_VIEWS_EXTENSION_NAME) ||
            !has_ext(props, n, XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME)) {
            fprintf(stderr, "xr_quad_app: the runtime lacks XR_VARJO_quad_views or XR_VARJO_foveated_rendering\n");
            exit(1);
        }
        exts[ne++] = XR_VARJO_QUAD_VIEWS_EXTENSION_NAME;
        exts[ne++] = XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME;
    }
    free(props);
    XrInstanceCreateInfo ci = {.type = XR_TYPE_INSTANCE_CREATE_INFO,
                               .applicationInfo = {.applicationName = "fovea xr_quad_app",
                                                   .apiVersion = XR_CURRENT_API_VERSION},
                               .enabledExtensionCount = ne,
                               .enabledExtensionNames = exts};
    CHECK_XR(xrCreateInstance(&ci, &a->inst));
    XrSystemGetInfo gi = {.type = XR_TYPE_SYSTEM_GET_INFO, .formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY};
    CHECK_XR(xrGetSystem(a->inst, &gi, &a->system));
    XrSystemFoveatedRenderingPropertiesVARJO fr = {.type = XR_TYPE_SYSTEM_FOVEATED_RENDERING_PROPERTIES_VARJO};
    XrSystemProperties sp = {.type = XR_TYPE_SYSTEM_PROPERTIES, .next = stereo_only ? NULL : &fr};
    CHECK_XR(xrGetSystemProperties(a->inst, a->system, &sp));
    a->foveated_supported = !stereo_only && fr.supportsFoveatedRendering == XR_TRUE;
    /* the view configurations: quad views when offered */
    uint32_t nc = 0;
    XrViewConfigurationType types[8];
    CHECK_XR(xrEnumerateViewConfigurations(a->inst, a->system, 8, &nc, types));
    printf("view_configs");
    a->config = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    for (uint32_t i = 0; i < nc; i++) {
        printf(",%s", config_name(types[i]));
        if (types[i] == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO) a->config = types[i];
    }
    printf("\nsupports_foveated_rendering,%d\n", a->foveated_supported ? 1 : 0);
    a->quad = a->config == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO;
}

/* The app's Vulkan instance and device, made by the runtime (XR_KHR_vulkan_enable2), with the validation layer. */
static void create_vulkan(app *a)
{
    const char *layers[] = {"VK_LAYER_KHRONOS_validation"};
    const char *iexts[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    VkApplicationInfo ai = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO, .pApplicationName = "fovea xr_quad_app",
                            .apiVersion = VK_API_VERSION_1_1};
    VkDebugUtilsMessengerCreateInfoEXT mi = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity =
            VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = on_vk_message};
    VkInstanceCreateInfo ici = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
                                .pNext = &mi,
                                .pApplicationInfo = &ai,
                                .enabledLayerCount = 1,
                                .ppEnabledLayerNames = layers,
                                .enabledExtensionCount = 1,
                                .ppEnabledExtensionNames = iexts};
    xr_app_vk vk;
    xr_app_vk_create(a->inst, a->system, &ici, &vk);
    a->vk_inst = vk.instance;
    a->phys = vk.phys;
    a->device = vk.device;
    a->family = vk.family;
    PFN_vkCreateDebugUtilsMessengerEXT cm =
        (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(a->vk_inst, "vkCreateDebugUtilsMessengerEXT");
    if (cm) CHECK_VK(cm(a->vk_inst, &mi, NULL, &a->messenger));
    vkGetDeviceQueue(a->device, a->family, 0, &a->queue);
    VkCommandPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                   .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                   .queueFamilyIndex = a->family};
    CHECK_VK(vkCreateCommandPool(a->device, &pci, NULL, &a->pool));
    VkCommandBufferAllocateInfo cai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                       .commandPool = a->pool,
                                       .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                       .commandBufferCount = 1};
    CHECK_VK(vkAllocateCommandBuffers(a->device, &cai, &a->cmd));
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO, .flags = VK_FENCE_CREATE_SIGNALED_BIT};
    CHECK_VK(vkCreateFence(a->device, &fci, NULL, &a->fence));
}

static uint32_t host_memory_type(app *a, uint32_t bits)
{
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(a->phys, &mp);
    VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    for (uint32_t i = 0; i < mp.memoryTypeCount; i++)
        if ((bits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & want) == want) return i;
    fprintf(stderr, "xr_quad_app: no host-visible coherent memory\n");
    exit(1);
}

static void create_session(app *a)
{
    XrGraphicsBindingVulkan2KHR gb = {.type = XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR,
                                      .instance = a->vk_inst,
                                      .physicalDevice = a->phys,
                                      .device = a->device,
                                      .queueFamilyIndex = a->family,
                                      .queueIndex = 0};
    XrSessionCreateInfo sci = {.type = XR_TYPE_SESSION_CREATE_INFO, .next = &gb, .systemId = a->system};
    CHECK_XR(xrCreateSession(a->inst, &sci, &a->session));
    XrReferenceSpaceCreateInfo rs = {.type = XR_TYPE_REFERENCE_SPACE_CREATE_INFO,
                                     .referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL,
                                     .poseInReferenceSpace = {{0, 0, 0, 1}, {0, 0, 0}}};
    CHECK_XR(xrCreateReferenceSpace(a->session, &rs, &a->local));
    rs.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW;
    CHECK_XR(xrCreateReferenceSpace(a->session, &rs, &a->view));
    if (a->quad) {
        rs.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO; /* the rendering gaze */
        CHECK_XR(xrCreateReferenceSpace(a->session, &rs, &a->gaze));
    }
    /* the views' recommended sizes: the foveated ones when the system can follow the gaze */
    XrViewConfigurationView cv[MAX_VIEWS];
    XrFoveatedViewConfigurationViewVARJO fv[MAX_VIEWS];
    for (uint32_t i = 0; i < MAX_VIEWS; i++) {
        fv[i] = (XrFoveatedViewConfigurationViewVARJO){.type = XR_TYPE_FOVEATED_VIEW_CONFIGURATION_VIEW_VARJO,
                                                       .foveatedRenderingActive = XR_TRUE};
        cv[i] = (XrViewConfigurationView){.type = XR_TYPE_VIEW_CONFIGURATION_VIEW,
                                          .next = a->foveated_supported ? &fv[i] : NULL};
    }
    CHECK_XR(xrEnumerateViewConfigurationViews(a->inst, a->system, a->config, MAX_VIEWS, &a->view_count, cv));
    /* an sRGB colour format the runtime offers */
    int64_t formats[32];
    uint32_t nfmt = 0;
    CHECK_XR(xrEnumerateSwapchainFormats(a->session, 32, &nfmt, formats));
    int64_t format = 0;
    for (uint32_t i = 0; i < nfmt && !format; i++)
        if (formats[i] == VK_FORMAT_R8G8B8A8_SRGB) format = formats[i];
    if (!format) {
        fprintf(stderr, "xr_quad_app: the runtime offers no VK_FORMAT_R8G8B8A8_SRGB swapchain\n");
        exit(1);
    }
    for (uint32_t v = 0; v < a->view_count; v++) {
        view_target *t = &a->views[v];
        t->width = cv[v].recommendedImageRectWidth;
        t->height = cv[v].recommendedImageRectHeight;
        printf("view,%u,%ux%u\n", v, t->width, t->height);
        XrSwapchainCreateInfo sc = {.type = XR_TYPE_SWAPCHAIN_CREATE_INFO,
                                    .usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT |
                                                  XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT,
                                    .format = format,
                                    .sampleCount = 1,
                                    .width = t->width,
                                    .height = t->height,
                                    .faceCount = 1,
                                    .arraySize = 1,
                                    .mipCount = 1};
        CHECK_XR(xrCreateSwapchain(a->session, &sc, &t->swapchain));
        XrSwapchainImageVulkan2KHR imgs[MAX_IMAGES];
        for (uint32_t i = 0; i < MAX_IMAGES; i++) imgs[i] = (XrSwapchainImageVulkan2KHR){
                                                      .type = XR_TYPE_SWAPCHAIN_IMAGE_VULKAN2_KHR};
        CHECK_XR(xrEnumerateSwapchainImages(t->swapchain, MAX_IMAGES, &t->image_count,
                                            (XrSwapchainImageBaseHeader *)imgs));
        for (uint32_t i = 0; i < t->image_count; i++) t->images[i] = imgs[i].image;
        VkBufferCreateInfo bi = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                                 .size = (VkDeviceSize)t->width * t->height * 4,
                                 .usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT};
        CHECK_VK(vkCreateBuffer(a->device, &bi, NULL, &t->staging));
        VkMemoryRequirements mr;
        vkGetBufferMemoryRequirements(a->device, t->staging, &mr);
        VkMemoryAllocateInfo mai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                    .allocationSize = mr.size,
                                    .memoryTypeIndex = host_memory_type(a, mr.memoryTypeBits)};
        CHECK_VK(vkAllocateMemory(a->device, &mai, NULL, &t->staging_mem));
        CHECK_VK(vkBindBufferMemory(a->device, t->staging, t->staging_mem, 0));
        CHECK_VK(vkMapMemory(a->device, t->staging_mem, 0, VK_WHOLE_SIZE, 0, (void **)&t->pixels));
    }
}

static uint8_t srgb8(double c)
{
    c = c < 0 ? 0 : c > 1 ? 1 : c;
    double s = c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
    return (uint8_t)lround(s * 255.0);
}

/* The view's image: the world pattern through its fov; blue for the wide views, red for the insets. */
static void draw(view_target *t, const XrFovf *fov, bool inset)
{
    double tl = tan((double)fov->angleLeft), tr = tan((double)fov->angleRight);
    double tu = tan((double)fov->angleUp), td = tan((double)fov->angleDown);
    const double base[2][3] = {{0.05, 0.10, 0.90}, {0.90, 0.10, 0.05}};
    const double *c = base[inset ? 1 : 0];
    for (uint32_t y = 0; y < t->height; y++) {
        double ty = tu + ((double)y + 0.5) / t->height * (td - tu);
        double ay = atan(ty) * 180.0 / M_PI;
        for (uint32_t x = 0; x < t->width; x++) {
            double tx = tl + ((double)x + 0.5) / t->width * (tr - tl);
            double ax = atan(tx) * 180.0 / M_PI;
            double b = 0.6 + 0.4 * cos(2.0 * M_PI * ax / 10.0) * cos(2.0 * M_PI * ay / 10.0);
            uint8_t *p = t->pixels + 4 * ((size_t)y * t->width + x);
            p[0] = srgb8(c[0] * b);
            p[1] = srgb8(c[1] * b);
            p[2] = srgb8(c[2] * b);
            p[3] = 255;
        }
    }
}

/* Render one frame's views (the images acquired), then release them. */
static void render(app *a, const XrView *views, XrCompositionLayerProjectionView *pv)
{
    CHECK_VK(vkWaitForFences(a->device, 1, &a->fence, VK_TRUE, UINT64_MAX)); /* the staging buffers are free */
    CHECK_VK(vkResetFences(a->device, 1, &a->fence));
    uint32_t index[MAX_VIEWS];
    for (uint32_t v = 0; v < a->view_count; v++) {
        view_target *t = &a->views[v];
        XrSwapchainImageAcquireInfo ai = {.type = XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO};
        CHECK_XR(xrAcquireSwapchainImage(t->swapchain, &ai, &index[v]));
        XrSwapchainImageWaitInfo wi = {.type = XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO, .timeout = XR_INFINITE_DURATION};
        CHECK_XR(xrWaitSwapchainImage(t->swapchain, &wi));
        draw(t, &views[v].fov, v >= 2);
        pv[v] = (XrCompositionLayerProjectionView){.type = XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW,
                                                   .pose = views[v].pose,
                                                   .fov = views[v].fov,
                                                   .subImage = {t->swapchain,
                                                                {{0, 0}, {(int32_t)t->width, (int32_t)t->height}},
                                                                0}};
    }
    CHECK_VK(vkResetCommandBuffer(a->cmd, 0));
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    CHECK_VK(vkBeginCommandBuffer(a->cmd, &bi));
    for (uint32_t v = 0; v < a->view_count; v++) {
        view_target *t = &a->views[v];
        VkImage img = t->images[index[v]];
        VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        /* the whole image is overwritten: its old contents are not needed */
        VkImageMemoryBarrier to_dst = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                                       .srcAccessMask = 0,
                                       .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                                       .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
                                       .newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                       .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                       .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                       .image = img,
                                       .subresourceRange = range};
        vkCmdPipelineBarrier(a->cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0,
                             NULL, 1, &to_dst);
        VkBufferImageCopy copy = {.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                                  .imageExtent = {t->width, t->height, 1}};
        vkCmdCopyBufferToImage(a->cmd, t->staging, img, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
        /* back to the layout the runtime hands the image over in (XR_KHR_vulkan_enable2) */
        VkImageMemoryBarrier to_att = to_dst;
        to_att.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        to_att.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_READ_BIT;
        to_att.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
        to_att.newLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        vkCmdPipelineBarrier(a->cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0,
                             0, NULL, 0, NULL, 1, &to_att);
    }
    CHECK_VK(vkEndCommandBuffer(a->cmd));
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &a->cmd};
    CHECK_VK(vkQueueSubmit(a->queue, 1, &si, a->fence));
    for (uint32_t v = 0; v < a->view_count; v++) {
        XrSwapchainImageReleaseInfo ri = {.type = XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO};
        CHECK_XR(xrReleaseSwapchainImage(a->views[v].swapchain, &ri));
    }
}

/* One frame: wait, locate the gaze and the views (foveated while the gaze is tracked), draw, end. */
static void frame(app *a, int n, bool visible)
{
    XrFrameWaitInfo wi = {.type = XR_TYPE_FRAME_WAIT_INFO};
    XrFrameState fs = {.type = XR_TYPE_FRAME_STATE};
    CHECK_XR(xrWaitFrame(a->session, &wi, &fs));
    XrFrameBeginInfo fbi = {.type = XR_TYPE_FRAME_BEGIN_INFO};
    CHECK_XR(xrBeginFrame(a->session, &fbi));
    bool tracked = false;
    double gx = NAN, gy = NAN;
    if (a->quad) {
        XrSpaceLocation loc = {.type = XR_TYPE_SPACE_LOCATION};
        CHECK_XR(xrLocateSpace(a->gaze, a->view, fs.predictedDisplayTime, &loc));
        tracked = a->foveated_supported && (loc.locationFlags & XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT);
        if (loc.locationFlags & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT) {
            XrQuaternionf q = loc.pose.orientation; /* the gaze: the pose's -z */
            double dx = -(2.0 * (q.x * q.z + q.y * q.w)), dy = -(2.0 * (q.y * q.z - q.x * q.w));
            double dz = -(1.0 - 2.0 * (q.x * q.x + q.y * q.y));
            if (dz < -1e-3) {
                gx = dx / -dz;
                gy = dy / -dz;
            }
        }
    }
    XrViewLocateFoveatedRenderingVARJO fr = {.type = XR_TYPE_VIEW_LOCATE_FOVEATED_RENDERING_VARJO,
                                             .foveatedRenderingActive = tracked ? XR_TRUE : XR_FALSE};
    XrViewLocateInfo li = {.type = XR_TYPE_VIEW_LOCATE_INFO,
                           .next = a->foveated_supported ? &fr : NULL,
                           .viewConfigurationType = a->config,
                           .displayTime = fs.predictedDisplayTime,
                           .space = a->local};
    XrViewState vs = {.type = XR_TYPE_VIEW_STATE};
    XrView views[MAX_VIEWS];
    for (uint32_t i = 0; i < MAX_VIEWS; i++) views[i] = (XrView){.type = XR_TYPE_VIEW};
    uint32_t nv = 0;
    CHECK_XR(xrLocateViews(a->session, &li, &vs, MAX_VIEWS, &nv, views));
    XrCompositionLayerProjectionView pv[MAX_VIEWS];
    XrCompositionLayerProjection layer = {.type = XR_TYPE_COMPOSITION_LAYER_PROJECTION,
                                          .space = a->local,
                                          .viewCount = a->view_count,
                                          .views = pv};
    const XrCompositionLayerBaseHeader *layers[1] = {(const XrCompositionLayerBaseHeader *)&layer};
    bool draw_it = fs.shouldRender && (vs.viewStateFlags & XR_VIEW_STATE_ORIENTATION_VALID_BIT);
    if (draw_it) render(a, views, pv);
    XrFrameEndInfo ei = {.type = XR_TYPE_FRAME_END_INFO,
                         .displayTime = fs.predictedDisplayTime,
                         .environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE,
                         .layerCount = draw_it ? 1 : 0,
                         .layers = layers};
    CHECK_XR(xrEndFrame(a->session, &ei));
    const XrFovf *f = &views[a->view_count == 4 ? 2 : 0].fov, *w = &views[0].fov, *wr = &views[1].fov;
    printf("frame,%d,composited,%d,tracked,%d,gaze_tx,%.6f,gaze_ty,%.6f,inset_left,%.6f,%.6f,%.6f,%.6f,"
           "wide_left,%.6f,%.6f,%.6f,%.6f,wide_right,%.6f,%.6f,%.6f,%.6f\n",
           n, draw_it && visible ? 1 : 0, tracked ? 1 : 0, gx, gy, (double)f->angleLeft, (double)f->angleRight,
           (double)f->angleUp, (double)f->angleDown, (double)w->angleLeft, (double)w->angleRight, (double)w->angleUp,
           (double)w->angleDown, (double)wr->angleLeft, (double)wr->angleRight, (double)wr->angleUp,
           (double)wr->angleDown);
}

static void frame_cb(void *ctx, int n, bool visible) { frame(ctx, n, visible); }

static void destroy(app *a)
{
    if (a->device) vkDeviceWaitIdle(a->device);
    for (uint32_t v = 0; v < a->view_count; v++) {
        view_target *t = &a->views[v];
        if (t->swapchain) CHECK_XR(xrDestroySwapchain(t->swapchain));
        if (t->staging) vkDestroyBuffer(a->device, t->staging, NULL);
        if (t->staging_mem) vkFreeMemory(a->device, t->staging_mem, NULL);
    }
    if (a->gaze) CHECK_XR(xrDestroySpace(a->gaze));
    if (a->view) CHECK_XR(xrDestroySpace(a->view));
    if (a->local) CHECK_XR(xrDestroySpace(a->local));
    if (a->session) CHECK_XR(xrDestroySession(a->session));
    if (a->fence) vkDestroyFence(a->device, a->fence, NULL);
    if (a->pool) vkDestroyCommandPool(a->device, a->pool, NULL);
    if (a->device) vkDestroyDevice(a->device, NULL);
    if (a->messenger) {
        PFN_vkDestroyDebugUtilsMessengerEXT dm =
            (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(a->vk_inst, "vkDestroyDebugUtilsMessengerEXT");
        if (dm) dm(a->vk_inst, a->messenger, NULL);
    }
    if (a->vk_inst) vkDestroyInstance(a->vk_inst, NULL);
    CHECK_XR(xrDestroyInstance(a->inst));
}

int main(int argc, char **argv)
{
    int frames = 30;
    bool stereo_only = false;
    const xr_app_flag flags[] = {{"--stereo-only", &stereo_only}};
    int bad_args = xr_app_args(argc, argv, "[--frames N] [--stereo-only]", &frames, flags, 1, NULL, NULL);
    if (bad_args) return bad_args;
    setvbuf(stdout, NULL, _IOLBF, 0);
    app a = {0};
    create_instance(&a, stereo_only);
    if (stereo_only) {
        /* an app that did not enable XR_VARJO_quad_views sees stereo only, and the quad configuration is refused */
        uint32_t n = 0;
        XrResult r = xrEnumerateViewConfigurationViews(a.inst, a.system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO,
                                                       0, &n, NULL);
        printf("quad_views_without_extension,%s\n", XR_FAILED(r) ? "refused" : "offered");
        CHECK_XR(xrDestroyInstance(a.inst));
        return XR_FAILED(r) && !a.quad ? 0 : 1;
    }
    create_vulkan(&a);
    create_session(&a);
    /* the session's life cycle; the app ends after `frames` frames */
    int n = xr_app_run_session(a.inst, a.session, a.config, frames, frame_cb, &a);
    destroy(&a);
    printf("frames,%d\nvk_validation_messages,%d\n", n, g_vk_messages);
    return g_vk_messages ? 1 : 0;
}
