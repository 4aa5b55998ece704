/* @brief OpenGL apps through EGL (XR_MNDX_egl_enable) on fovea's runtime: our app xr_egl_app (Mesa's surfaceless
 * EGL; OpenGL ES 3 and desktop OpenGL 4.5) runs headless through the OpenXR loader with the core-validation layer and
 * the Vulkan validation layer on fovea's compositor device (FOVEA_VALIDATION=1; the core-validation layer only where
 * it accepts the EGL binding: see run_app_validated), lens distortion off
 * (FOVEA_XR_DISTORT=0: the composite is the display image in tangent space, and the app's views have the display's
 * fov, so its images land one to one). Both hand-overs: shared memory (where the runtime finds it: on lavapipe +
 * llvmpipe it must) and the copy (FOVEA_XR_EGL_COPY=1), with a swapchain per eye and with one array swapchain.
 * Read back from the composite, per eye: the eye's own colour (left red, right
 * blue), the white band at the top (not the bottom: GL's bottom-left origin handled), the green ramp on the left (not
 * the right: not mirrored) darkening downwards. Zero messages from either layer. The session-creation checks: before
 * the requirements call XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING, no context XR_ERROR_VALIDATION_FAILURE, a
 * pointer that is no context XR_ERROR_GRAPHICS_DEVICE_INVALID. Skips (with the app's reason) only when EGL gives no
 * surfaceless context. argv[1] = xr_egl_app, argv[2] = manifest. */
#include <fcntl.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stb/stb_image.h>

#include "fv_test.h"
#include "xr_test_child.h"

static const char *g_app, *g_manifest;

#define SCALE "0.1" /* the generic HMD's 1440 x 1453 per eye -> 144 x 145 */
#define FRAMES 5

typedef struct run {
    char dir[1024];
    char *log;
    int rc;
    bool layer; /* under the OpenXR core-validation layer */
} run;

static const char *g_copy = "0"; /* FOVEA_XR_EGL_COPY of the next run */

static void run_app(run *r, const char *name, const char *arg, bool layer)
{
    snprintf(r->dir, sizeof r->dir, "%s", fv_test_tmp(name));
    mkdir(r->dir, 0755);
    char log_path[1200], stats[1200];
    snprintf(log_path, sizeof log_path, "%s/app.log", r->dir);
    snprintf(stats, sizeof stats, "%s/stats.json", r->dir);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        xr_test_child_env(log_path, g_manifest, layer, SCALE, stats);
        setenv("FOVEA_LOG", "info", 1);
        setenv("FOVEA_XR_EGL_COPY", g_copy, 1);
        setenv("FOVEA_XR_DISTORT", "0", 1);
        setenv("FOVEA_XR_OUT", r->dir, 1);
        setenv("FOVEA_XR_OUT_ALL", "1", 1);
        unsetenv("FOVEA_XR_GAZE");
        unsetenv("FOVEA_XR_FRAMES");
        unsetenv("DISPLAY");
        char nf[16];
        snprintf(nf, sizeof nf, "%d", FRAMES);
        if (arg) execl(g_app, g_app, "--frames", nf, arg, (char *)NULL);
        else execl(g_app, g_app, "--frames", nf, (char *)NULL);
        _exit(127);
    }
    r->rc = fv_test_wait(pid, fv_test_cmd_limit_s(), g_app); /* fails the case, naming the app, past the limit */
    r->log = fv_test_read_file(log_path, NULL);
    r->layer = layer;
}

/* Under the core-validation layer; Debian's 1.0.20 layer does not know XrGraphicsBindingEGLMNDX in xrCreateSession's
 * chain (KhronosGroup/OpenXR-SDK-Source#570, open) and refuses the session itself without calling the runtime: only
 * that exact refusal sends the run again without the layer (the Vulkan validation layer stays on). */
static void run_app_validated(run *r, const char *name, const char *arg)
{
    run_app(r, name, arg, true);
    if (r->rc == 1 && strstr(r->log, "VUID-XrSessionCreateInfo-next-next") &&
        strstr(r->log, "try_session(&a, a.ctx) failed: -1")) {
        print_message("  the core-validation layer refuses XrGraphicsBindingEGLMNDX (OpenXR-SDK-Source#570): "
                      "running without it\n");
        free(r->log);
        char again[256];
        snprintf(again, sizeof again, "%s_nolayer", name);
        run_app(r, again, arg, false);
    }
}

static void assert_clean(const run *r)
{
    if (r->layer) fv_assert_contains(r->log, "Core Validation output type");
    if (strstr(r->log, "VUID-") || strstr(r->log, "Validation Error") || strstr(r->log, "[Error") ||
        strstr(r->log, "[Warning") || strstr(r->log, "XR_ERROR") || strstr(r->log, "fovea: error") ||
        strstr(r->log, "Vulkan validation:") || strstr(r->log, "GL error"))
        fail_msg("validation or error output:\n%s", r->log);
    char stats_path[1200];
    snprintf(stats_path, sizeof stats_path, "%s/stats.json", r->dir);
    char *stats = fv_test_read_file(stats_path, NULL);
    fv_assert_contains(stats, "\"validation_messages\": 0,");
    free(stats);
}

static const unsigned char *px_at(const unsigned char *px, int w, int x, int y)
{
    return px + 4 * ((size_t)y * (size_t)w + (size_t)x);
}

/* A composite pixel is near (r, g, b) (8-bit sRGB-encoded; resampling at edges is avoided by the probe points). */
static bool near(const unsigned char *p, int r, int g, int b)
{
    return abs(p[0] - r) <= 12 && abs(p[1] - g) <= 12 && abs(p[2] - b) <= 12;
}

static void check_composite(const run *r)
{
    char png[1200];
    snprintf(png, sizeof png, "%s/frame_%05d.png", r->dir, FRAMES - 2); /* frames 0..FRAMES-2 were composited */
    int w = 0, h = 0, c = 0;
    unsigned char *px = stbi_load(png, &w, &h, &c, 4);
    if (!px) fail_msg("no composite %s\n%s", png, r->log);
    int ew = w / 2;
    for (int e = 0; e < 2; e++) {
        int x0 = e * ew;
        const unsigned char *body = px_at(px, w, x0 + ew * 6 / 10, h * 6 / 10);
        const unsigned char *top = px_at(px, w, x0 + ew * 6 / 10, h / 10);
        const unsigned char *bottom = px_at(px, w, x0 + ew * 6 / 10, h * 95 / 100);
        const unsigned char *right = px_at(px, w, x0 + ew * 90 / 100, h * 6 / 10);
        print_message("  eye %d: body %d,%d,%d top %d,%d,%d bottom %d,%d,%d\n", e, body[0], body[1], body[2], top[0],
                      top[1], top[2], bottom[0], bottom[1], bottom[2]);
        int er = e == 0 ? 255 : 0, eb = e == 0 ? 0 : 255;
        if (!near(body, er, 0, eb) || !near(bottom, er, 0, eb) || !near(right, er, 0, eb))
            fail_msg("eye %d: the eye's colour is not where it belongs", e);
        if (!near(top, 255, 255, 255)) fail_msg("eye %d: the white band is not at the top (upside down?)", e);
        /* the green ramp: left quarter, below the white band; green falls going down, red and blue are 0 */
        int prev = 256, steps = 0;
        for (int y = h * 30 / 100; y < h * 97 / 100; y += h / 40) {
            const unsigned char *p = px_at(px, w, x0 + ew / 10, y);
            if (p[0] > 12 || p[2] > 12) fail_msg("eye %d: no green ramp at the left (mirrored?) at y %d", e, y);
            if (p[1] > prev + 2) fail_msg("eye %d: the green ramp brightens downwards (upside down?) at y %d", e, y);
            if (p[1] < prev - 2) steps++;
            prev = p[1];
        }
        assert_true(steps >= 5);
        assert_true(prev < 140); /* the bottom band: green 1/8 (sRGB-encoded ~99) */
    }
    stbi_image_free(px);
}

static void skip_if_no_egl(const run *r)
{
    if (r->rc == 77) {
        print_message("SKIP: %s", r->log);
        skip();
    }
}

/* Which hand-over ran: on lavapipe + llvmpipe (same device and driver UUIDs, GL_EXT_memory_object_fd) shared memory
 * unless the copy is forced; elsewhere whatever the runtime says it chose. */
static void check_path(const run *r, bool forced_copy)
{
    const char *path = strstr(r->log, "images reach the compositor by ");
    if (!path) fail_msg("the runtime did not say how images reach the compositor:\n%s", r->log);
    print_message("  %.*s\n", (int)strcspn(path, "\n"), path);
    if (forced_copy) fv_assert_contains(r->log, "by a copy (FOVEA_XR_EGL_COPY=1)");
    else if (strstr(r->log, "llvmpipe")) fv_assert_contains(r->log, "by shared memory (GL_EXT_memory_object_fd)");
}

static void gles_app_composites_each_eye_upright(void **state)
{
    (void)state;
    run r;
    g_copy = "0";
    run_app_validated(&r, "egl_gles", NULL);
    skip_if_no_egl(&r);
    if (r.rc != 0) fail_msg("xr_egl_app exited %d:\n%s", r.rc, r.log);
    check_path(&r, false);
    fv_assert_contains(r.log, "gl,OpenGL ES 3");
    fv_assert_contains(r.log, "requirements,3.0,3.2");
    fv_assert_contains(r.log, "formats,0x8c43,0x8058"); /* GL_SRGB8_ALPHA8, GL_RGBA8 first */
    fv_assert_contains(r.log, "frames,5");
    assert_clean(&r);
    check_composite(&r);
    free(r.log);
}

static void gles_app_by_copy_composites_each_eye_upright(void **state)
{
    (void)state;
    run r;
    g_copy = "1";
    run_app_validated(&r, "egl_gles_copy", NULL);
    g_copy = "0";
    skip_if_no_egl(&r);
    if (r.rc != 0) fail_msg("xr_egl_app (copy) exited %d:\n%s", r.rc, r.log);
    check_path(&r, true);
    assert_clean(&r);
    check_composite(&r);
    free(r.log);
}

/* One swapchain of two layers (eye e in layer e): the runtime's array textures, shared and copied. */
static void gles_array_swapchain_composites_each_layer(void **state)
{
    (void)state;
    const char *copies[2] = {"0", "1"};
    for (int k = 0; k < 2; k++) {
        run r;
        g_copy = copies[k];
        run_app_validated(&r, k ? "egl_array_copy" : "egl_array", "--array");
        g_copy = "0";
        skip_if_no_egl(&r);
        if (r.rc != 0) fail_msg("xr_egl_app --array exited %d:\n%s", r.rc, r.log);
        check_path(&r, k == 1);
        assert_clean(&r);
        check_composite(&r);
        free(r.log);
    }
}

static void desktop_gl_app_composites_each_eye_upright(void **state)
{
    (void)state;
    run r;
    g_copy = "0";
    run_app_validated(&r, "egl_gl", "--gl");
    skip_if_no_egl(&r);
    if (r.rc != 0) fail_msg("xr_egl_app --gl exited %d:\n%s", r.rc, r.log);
    check_path(&r, false);
    fv_assert_contains(r.log, "gl,4.");
    fv_assert_contains(r.log, "requirements,4.2,4.6");
    assert_clean(&r);
    check_composite(&r);
    free(r.log);
}

static void bad_bindings_are_refused_clearly(void **state)
{
    (void)state;
    run r;
    run_app(&r, "egl_bad", "--bad-bindings", false);
    skip_if_no_egl(&r);
    if (r.rc != 0) fail_msg("xr_egl_app --bad-bindings exited %d:\n%s", r.rc, r.log);
    char line[128];
    snprintf(line, sizeof line, "bad_binding,before_requirements,%d", (int)-50); /* REQUIREMENTS_CALL_MISSING */
    fv_assert_contains(r.log, line);
    fv_assert_contains(r.log, "bad_binding,no_context,-1");     /* XR_ERROR_VALIDATION_FAILURE */
    fv_assert_contains(r.log, "bad_binding,not_a_context,-38"); /* XR_ERROR_GRAPHICS_DEVICE_INVALID */
    fv_assert_contains(r.log, "bad_binding,valid,0");
    fv_assert_contains(r.log, "not a context of its display"); /* the runtime says why */
    free(r.log);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: %s XR_EGL_APP MANIFEST\n", argv[0]);
        return 2;
    }
    g_app = argv[1];
    g_manifest = argv[2];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gles_app_composites_each_eye_upright),
        cmocka_unit_test(gles_app_by_copy_composites_each_eye_upright),
        cmocka_unit_test(gles_array_swapchain_composites_each_layer),
        cmocka_unit_test(desktop_gl_app_composites_each_eye_upright),
        cmocka_unit_test(bad_bindings_are_refused_clearly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
