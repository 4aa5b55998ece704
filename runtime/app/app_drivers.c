/* @brief The one driver list (see fv_app_drivers.h). */
#include "fv_app_drivers.h"

#include <dlfcn.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_registry.h"

#include "fv_fixed_driver.h"
#include "fv_hid_driver.h"
#include "fv_mouse_driver.h"
#include "fv_pupil_driver.h"
#include "fv_sim_driver.h"
#include "fv_trace_driver.h"
#include "fv_usb_driver.h"

#define MOD "devices"

/* Hardware first; plug-ins next; the recorded and simulated drivers last (the registry's order). */
static const fv_driver *const g_hardware[] = {&fv_hid_driver, &fv_usb_driver, &fv_pupil_driver};
static const fv_driver *const g_virtual[] = {&fv_trace_driver, &fv_fixed_driver, &fv_mouse_driver, &fv_sim_driver};
#define N_HW (sizeof g_hardware / sizeof g_hardware[0])
#define N_VIRT (sizeof g_virtual / sizeof g_virtual[0])

static const fv_driver *g_list[N_HW + FV_APP_MAX_PLUGINS + N_VIRT + 1];
static pthread_once_t g_once = PTHREAD_ONCE_INIT;

static bool scheme_taken(const char *scheme, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (strcmp(g_list[i]->scheme, scheme) == 0) return true;
    for (size_t i = 0; i < N_VIRT; i++)
        if (strcmp(g_virtual[i]->scheme, scheme) == 0) return true;
    return false;
}

/* One plug-in: its driver, or NULL after one error line. The library stays loaded for the process's life. */
static const fv_driver *load_plugin(const char *path, size_t n)
{
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        FV_ERROR(MOD, "FOVEA_DRIVERS: '%s': cannot load (%s); skipped", path, dlerror());
        return NULL;
    }
    fv_driver_plugin_fn fn;
    void *sym = dlsym(h, "fv_driver_plugin");
    memcpy(&fn, &sym, sizeof fn); /* ISO C has no object-to-function pointer conversion */
    const fv_driver *d = sym ? fn(FV_DRIVER_PLUGIN_VERSION) : NULL;
    const char *why = !sym ? "no symbol fv_driver_plugin"
                      : !d ? "its fv_driver_plugin refused interface version " "1"
                      : !d->scheme || !d->scheme[0] || !d->open || !d->probe ? "its driver lacks a scheme, open or probe"
                      : scheme_taken(d->scheme, n) ? "its scheme is already taken"
                                                   : NULL;
    if (why) {
        FV_ERROR(MOD, "FOVEA_DRIVERS: '%s': %s%s%s; skipped", path, why, d && d->scheme ? ": " : "",
                 d && d->scheme ? d->scheme : "");
        dlclose(h);
        return NULL;
    }
    FV_INFO(MOD, "FOVEA_DRIVERS: '%s': driver '%s' (%s)", path, d->scheme, d->summary ? d->summary : "");
    return d;
}

static void build(void)
{
    size_t n = 0;
    for (size_t i = 0; i < N_HW; i++) g_list[n++] = g_hardware[i];
    const char *env = getenv("FOVEA_DRIVERS");
    size_t plugins = 0;
    for (const char *p = env; p && *p;) {
        const char *end = strchr(p, ':');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        if (len >= 4096) {
            FV_ERROR(MOD, "FOVEA_DRIVERS: a path of %zu characters (at most 4095); skipped", len);
        } else if (len > 0) {
            char path[4096];
            memcpy(path, p, len);
            path[len] = '\0';
            if (plugins == FV_APP_MAX_PLUGINS) {
                FV_ERROR(MOD, "FOVEA_DRIVERS: '%s': more than %d plug-ins; skipped", path, FV_APP_MAX_PLUGINS);
            } else {
                const fv_driver *d = load_plugin(path, n);
                if (d) {
                    g_list[n++] = d;
                    plugins++;
                }
            }
        }
        p = end ? end + 1 : p + len;
    }
    for (size_t i = 0; i < N_VIRT; i++) g_list[n++] = g_virtual[i];
    g_list[n] = NULL;
}

const fv_driver *const *fv_app_drivers(void)
{
    pthread_once(&g_once, build);
    return g_list;
}

fv_result fv_app_declared_latency_ms(const char *uri, double *out_ms)
{
    *out_ms = 0.0;
    if (strncmp(uri, "sim:", 4) != 0) return FV_OK;
    fv_sim_eye_desc d;
    FV_TRY(fv_sim_driver_parse_uri(uri, &d, NULL));
    if (isfinite(d.latency_ms) && d.latency_ms >= 0) *out_ms = d.latency_ms;
    return FV_OK;
}

fv_result fv_app_device_open(const char *uri, const fv_device_open_desc *desc, fv_device **out)
{
    fv_registry reg; /* plain data over the one list: "auto", the scheme's driver, the known schemes when unknown */
    FV_TRY(fv_registry_init(&reg, fv_app_drivers()));
    return fv_registry_open(&reg, uri, desc, out);
}

fv_result fv_app_device_open_fn(void *user, const char *uri, const fv_device_open_desc *desc, fv_device **out)
{
    (void)user;
    return fv_app_device_open(uri, desc, out);
}
