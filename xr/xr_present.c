/* @brief The runtime's presenter choice and the window it presents in (see xr_present.h). */
#define _GNU_SOURCE
#include "xr_present.h"

#include <dlfcn.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_window.h"

#define MOD "xr"
#define MAX_OPTIONAL 8

struct fv_xr_present {
    fv_window *window; /* NULL: headless */
    const char *why;   /* why this presenter (the statistics say it) */
    bool closed;       /* the window was closed (the first poll that saw it) */
    atomic_bool lost;  /* the X server went away (Xlib's I/O error) */
    const char *optional[MAX_OPTIONAL]; /* the compositor's optional device extensions and the window's */
    char title[160];
};

/* The X server going away (libX11 >= 1.8; measured against a killed Xvfb): Xlib's fatal I/O error calls the
 * process's I/O error handler, whose default exits, then the display's exit handler, whose default exits too. Ours
 * mark the display lost and return for GLFW's display (the app lives; the session is lost), and hand any other
 * display to the handler that was there before (an app's own X connections keep their behaviour). One window per
 * process (GLFW's one initialisation): the watched display is process state. */
static void *g_x_display;
static fv_xr_present *g_x_present;
static int (*g_prev_io_handler)(void *dpy);

static void x_display_lost(void)
{
    if (!g_x_present || atomic_exchange(&g_x_present->lost, true)) return;
    FV_ERROR(MOD, "the window's X server went away: the display is lost");
    /* the presenter stops waiting on the dead server (e.g. for a size while its window reads as zero-sized) */
    fv_window_request_close(g_x_present->window);
}

static int on_x_io_error(void *dpy)
{
    if (dpy && dpy == g_x_display) {
        x_display_lost();
        return 0;
    }
    return g_prev_io_handler ? g_prev_io_handler(dpy) : 0;
}

static void on_x_io_exit(void *dpy, void *user)
{
    (void)dpy;
    (void)user;
    x_display_lost();
}

/* Where GLFW runs on X11 with a libX11 that lets an application live through the server going away, take those two
 * handlers. Looked up in the libraries already loaded (GLFW's build may be Wayland's, libX11 older than 1.8):
 * without them Xlib's defaults stay (the process ends with the server). */
static void watch_x_server(fv_xr_present *p)
{
    void *glfw = dlopen("libglfw.so.3", RTLD_LAZY | RTLD_NOLOAD), *x11 = dlopen("libX11.so.6", RTLD_LAZY | RTLD_NOLOAD);
    void *(*get_display)(void) = NULL;
    void (*set_exit)(void *, void (*)(void *, void *), void *) = NULL;
    int (*(*set_io)(int (*)(void *)))(void *) = NULL;
    /* POSIX's way to take a function from dlsym (ISO C has no object-to-function pointer conversion) */
    if (glfw) *(void **)&get_display = dlsym(glfw, "glfwGetX11Display");
    if (x11) *(void **)&set_exit = dlsym(x11, "XSetIOErrorExitHandler");
    if (x11) *(void **)&set_io = dlsym(x11, "XSetIOErrorHandler");
    void *dpy = get_display && getenv("DISPLAY") ? get_display() : NULL;
    if (dpy && set_exit && set_io && !g_x_display) {
        g_x_display = dpy;
        g_x_present = p;
        g_prev_io_handler = set_io(on_x_io_error);
        set_exit(dpy, on_x_io_exit, NULL);
    } else {
        FV_DEBUG(MOD, "the X server going away ends the process (not on X11, or libX11 older than 1.8)");
    }
    if (glfw) dlclose(glfw);
    if (x11) dlclose(x11);
}

/* The window goes: Xlib's handlers back as they were. */
static void unwatch_x_server(fv_xr_present *p)
{
    if (g_x_present != p) return;
    void *x11 = dlopen("libX11.so.6", RTLD_LAZY | RTLD_NOLOAD);
    int (*(*set_io)(int (*)(void *)))(void *) = NULL;
    if (x11) *(void **)&set_io = dlsym(x11, "XSetIOErrorHandler");
    if (set_io) set_io(g_prev_io_handler); /* NULL restores Xlib's default */
    if (x11) dlclose(x11);
    g_x_display = NULL;
    g_x_present = NULL;
    g_prev_io_handler = NULL;
}

static bool has_display(void)
{
    const char *x11 = getenv("DISPLAY"), *wl = getenv("WAYLAND_DISPLAY");
    return (x11 && *x11) || (wl && *wl);
}

fv_result fv_xr_present_create(const char *app_name, uint32_t eye_w, uint32_t eye_h, fv_xr_present **out)
{
    *out = NULL;
    const char *mode = getenv("FOVEA_XR_PRESENT");
    if (!mode || !*mode) mode = "auto";
    bool want_window = strcmp(mode, "window") == 0, want_auto = strcmp(mode, "auto") == 0;
    if (!want_window && !want_auto && strcmp(mode, "headless") != 0) {
        FV_ERROR(MOD, "FOVEA_XR_PRESENT=%s: expected window, headless or auto", mode);
        return FV_ERR_INVALID_ARG;
    }
    fv_window_present_mode pm = FV_WINDOW_FIFO;
    const char *pms = getenv("FOVEA_XR_PRESENT_MODE");
    if (pms && *pms && !fv_window_present_mode_parse(pms, &pm)) {
        FV_ERROR(MOD, "FOVEA_XR_PRESENT_MODE=%s: expected fifo, mailbox or immediate", pms);
        return FV_ERR_INVALID_ARG;
    }
    fv_xr_present *p = calloc(1, sizeof *p);
    if (!p) return FV_ERR_NO_MEMORY;
    const char *files = getenv("FOVEA_XR_OUT");
    if (want_auto && files && *files) {
        p->why = "headless (FOVEA_XR_OUT writes the frames to files)";
    } else if (want_auto && !has_display()) {
        p->why = "headless (no DISPLAY or WAYLAND_DISPLAY)";
    } else if (want_window || want_auto) {
        if (want_window && files && *files)
            FV_WARN(MOD, "FOVEA_XR_PRESENT=window: FOVEA_XR_OUT=%s is not written (the frames go to the window)",
                    files);
        snprintf(p->title, sizeof p->title, "fovea OpenXR: %s", app_name && *app_name ? app_name : "app");
        fv_window_desc wd = {.eye_width = eye_w, .eye_height = eye_h, .title = p->title, .present_mode = pm};
        fv_result res = fv_window_create(&wd, &p->window);
        if (res != FV_OK && want_window) {
            FV_ERROR(MOD, "FOVEA_XR_PRESENT=window: no window (see above); FOVEA_XR_PRESENT=headless runs without");
            free(p);
            return res;
        }
        p->why = res == FV_OK ? "window" : "headless (the window could not be opened: see above)";
        if (res == FV_OK) watch_x_server(p);
    } else {
        p->why = "headless (FOVEA_XR_PRESENT=headless)";
    }
    FV_INFO(MOD, "presenting: %s%s%s", p->why, p->window ? ", present mode " : "",
            p->window ? fv_window_present_mode_str(pm) : "");
    *out = p;
    return FV_OK;
}

void fv_xr_present_destroy(fv_xr_present **pp)
{
    if (!pp || !*pp) return;
    fv_window_destroy(&(*pp)->window);
    unwatch_x_server(*pp);
    free(*pp);
    *pp = NULL;
}

void fv_xr_present_configure_vk(fv_xr_present *p, fv_vk_desc *d)
{
    if (!p || !p->window) return;
    fv_target *t = fv_window_target(p->window);
    fv_vk_desc w = {0};
    t->ops->configure_vk(t, &w);
    /* the window's optional device extensions join the compositor's (deduplicated; the strings are static) */
    uint32_t n = 0;
    for (uint32_t i = 0; i < d->optional_device_extension_count && n < MAX_OPTIONAL; i++)
        p->optional[n++] = d->optional_device_extensions[i];
    for (uint32_t i = 0; i < w.optional_device_extension_count && n < MAX_OPTIONAL; i++) {
        bool dup = false;
        for (uint32_t k = 0; k < n; k++) dup = dup || strcmp(p->optional[k], w.optional_device_extensions[i]) == 0;
        if (!dup) p->optional[n++] = w.optional_device_extensions[i];
    }
    d->optional_device_extensions = p->optional;
    d->optional_device_extension_count = n;
    d->instance_extensions = w.instance_extensions;
    d->instance_extension_count = w.instance_extension_count;
    d->device_extensions = w.device_extensions;
    d->device_extension_count = w.device_extension_count;
    d->create_surface = w.create_surface;
    d->surface_user = w.surface_user;
}

void fv_xr_present_detach(fv_xr_present *p, fv_vk *vk)
{
    if (!p || !p->window || !vk) return;
    fv_target *t = fv_window_target(p->window);
    if (t->ops->detach) t->ops->detach(t, vk);
}

bool fv_xr_present_windowed(const fv_xr_present *p) { return p && p->window; }

fv_target *fv_xr_present_target(fv_xr_present *p) { return p && p->window ? fv_window_target(p->window) : NULL; }

fv_display *fv_xr_present_display(fv_xr_present *p) { return p && p->window ? fv_window_display(p->window) : NULL; }

bool fv_xr_present_lost(const fv_xr_present *p) { return p && atomic_load(&((fv_xr_present *)p)->lost); }

bool fv_xr_present_poll(fv_xr_present *p)
{
    if (!p || !p->window || atomic_load(&p->lost)) return true; /* a dead display has no events (the loss decides) */
    bool open = p->closed ? false : fv_window_poll(p->window);
    if (atomic_load(&p->lost)) return true; /* the server went away during the poll: not a close */
    if (!p->closed && !open) {
        p->closed = true;
        FV_INFO(MOD, "the window was closed: the session stops");
    }
    return !p->closed;
}

void fv_xr_present_write_stats(const fv_xr_present *p, FILE *f)
{
    fprintf(f, "  \"presenter\": \"%s\",\n", p ? p->why : "none (no graphics session)");
    if (!p || !p->window) return;
    fv_window_stats ws;
    fv_window_get_stats(p->window, &ws);
    fprintf(f, "  \"window_presents\": %llu,\n", (unsigned long long)ws.presents);
    fprintf(f, "  \"window_skipped\": %llu,\n", (unsigned long long)ws.skipped);
    fprintf(f, "  \"window_size\": [%u, %u],\n", ws.width, ws.height);
    fprintf(f, "  \"window_present_mode\": \"%s\",\n", ws.present_mode ? ws.present_mode : "");
    fprintf(f, "  \"window_clock\": \"%s\",\n", fv_window_clock_name(p->window));
    fprintf(f, "  \"window_refresh_hz\": %.3f,\n", fv_window_display(p->window)->refresh_hz);
    fprintf(f, "  \"window_refresh_measured\": %s,\n", ws.refresh_measured ? "true" : "false");
    fprintf(f, "  \"window_closed\": %s,\n", p->closed ? "true" : "false");
}
