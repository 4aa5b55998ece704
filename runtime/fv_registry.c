/* @brief Device registry: driver ordering, probing all drivers, opening by URI scheme (see fv_registry.h). */
#include "fv_registry.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"

bool fv_registry_is_virtual(const fv_driver *driver)
{
    return driver && (strcmp(driver->scheme, "sim") == 0 || strcmp(driver->scheme, "trace") == 0 ||
                      strcmp(driver->scheme, "fixed") == 0 || strcmp(driver->scheme, "mouse") == 0);
}

/* Order rank: hardware 0, trace and fixed 1, sim 2 (sim, trace and fixed register last; sim the very last). */
static int rank_of(const fv_driver *d)
{
    if (strcmp(d->scheme, "sim") == 0) return 2;
    if (strcmp(d->scheme, "trace") == 0 || strcmp(d->scheme, "fixed") == 0 || strcmp(d->scheme, "mouse") == 0)
        return 1;
    return 0;
}

fv_result fv_registry_init(fv_registry *reg, const fv_driver *const *drivers)
{
    if (!reg) return FV_ERR_INVALID_ARG;
    memset(reg, 0, sizeof *reg);
    if (!drivers) return FV_OK;
    size_t n = 0;
    for (; drivers[n]; n++) {
        const fv_driver *d = drivers[n];
        if (n >= FV_REGISTRY_MAX_DRIVERS) {
            FV_ERROR("devices", "more than %d drivers", FV_REGISTRY_MAX_DRIVERS);
            return FV_ERR_RANGE;
        }
        if (!d->scheme || !d->scheme[0] || !d->probe || !d->open) {
            FV_ERROR("devices", "driver #%zu ('%s') lacks a scheme, probe or open", n, d->scheme ? d->scheme : "?");
            return FV_ERR_INVALID_ARG;
        }
        for (size_t k = 0; k < n; k++) {
            if (strcmp(drivers[k]->scheme, d->scheme) == 0) {
                FV_ERROR("devices", "two drivers answer the scheme '%s'", d->scheme);
                return FV_ERR_INVALID_ARG;
            }
        }
    }
    /* stable: hardware in the given order, then trace, then sim */
    for (int rank = 0; rank <= 2; rank++)
        for (size_t i = 0; i < n; i++)
            if (rank_of(drivers[i]) == rank) reg->drivers[reg->count++] = drivers[i];
    return FV_OK;
}

const fv_driver *fv_registry_find(const fv_registry *reg, const char *scheme, size_t len)
{
    for (size_t i = 0; i < reg->count; i++) {
        const char *s = reg->drivers[i]->scheme;
        if (strlen(s) == len && strncmp(s, scheme, len) == 0) return reg->drivers[i];
    }
    return NULL;
}

static void terminate_strings(fv_device_info *info)
{
    info->uri[sizeof info->uri - 1] = '\0';
    info->name[sizeof info->name - 1] = '\0';
    info->driver[sizeof info->driver - 1] = '\0';
    info->detail[sizeof info->detail - 1] = '\0';
}

static fv_result probe_one(const fv_driver *d, fv_registry_driver_listing *out)
{
    out->driver = d;
    size_t cap = 16;
    for (int attempt = 0; attempt < 2; attempt++) {
        fv_device_info *buf = calloc(cap, sizeof *buf);
        if (!buf) {
            FV_ERROR("devices", "out of memory probing '%s'", d->scheme);
            return FV_ERR_NO_MEMORY;
        }
        size_t count = 0;
        fv_result r = d->probe(buf, cap, &count);
        if (FV_FAILED(r)) {
            free(buf);
            out->result = r;
            return FV_OK; /* listed with its result; the other drivers still run */
        }
        if (count > cap && attempt == 0 && count <= FV_REGISTRY_MAX_DEVICES) {
            free(buf);
            cap = count; /* the driver told us how many: ask again with room for all */
            continue;
        }
        out->truncated = count > cap;
        out->count = count > cap ? cap : count;
        out->devices = buf;
        out->result = r;
        for (size_t i = 0; i < out->count; i++) {
            terminate_strings(&buf[i]);
            if (!buf[i].driver[0]) { /* a driver that forgot to say who found it */
                strncpy(buf[i].driver, d->scheme, sizeof buf[i].driver - 1);
            }
        }
        if (out->truncated)
            FV_WARN("devices", "'%s' reports %zu devices; listing the first %zu", d->scheme, count, out->count);
        return FV_OK;
    }
    return FV_OK;
}

fv_result fv_registry_probe(const fv_registry *reg, fv_registry_listing *out)
{
    if (!reg || !out) return FV_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    for (size_t i = 0; i < reg->count; i++) {
        fv_registry_driver_listing *l = &out->drivers[out->driver_count++];
        FV_TRY(probe_one(reg->drivers[i], l));
        if (!fv_registry_is_virtual(reg->drivers[i])) out->hardware_devices += l->count;
    }
    return FV_OK;
}

void fv_registry_listing_fini(fv_registry_listing *listing)
{
    if (!listing) return;
    for (size_t i = 0; i < listing->driver_count; i++) {
        free(listing->drivers[i].devices);
        listing->drivers[i].devices = NULL;
        listing->drivers[i].count = 0;
    }
    listing->driver_count = 0;
    listing->hardware_devices = 0;
}

static void known_schemes(const fv_registry *reg, char *buf, size_t size)
{
    buf[0] = '\0';
    for (size_t i = 0; i < reg->count; i++) {
        size_t used = strlen(buf);
        snprintf(buf + used, size - used, "%s%s", i ? ", " : "", reg->drivers[i]->scheme);
    }
    if (!buf[0]) snprintf(buf, size, "none");
}

static fv_result open_with(const fv_driver *d, const char *uri, const fv_device_open_desc *desc, fv_device **out)
{
    fv_device *dev = NULL;
    fv_result r = d->open(uri, desc, &dev);
    if (FV_FAILED(r)) return r; /* the driver logged why; on failure it owns (and freed) whatever it made */
    if (!dev || !dev->ops || !dev->ops->read || !dev->ops->close) {
        FV_ERROR("devices", "'%s': driver '%s' reported success without a usable device", uri, d->scheme);
        if (dev && dev->ops && dev->ops->close) dev->ops->close(dev);
        return FV_ERR_PROTOCOL;
    }
    *out = dev;
    return FV_OK;
}

static fv_result open_auto(const fv_registry *reg, const fv_device_open_desc *desc, fv_device **out)
{
    fv_registry_listing listing;
    fv_result r = fv_registry_probe(reg, &listing);
    if (FV_FAILED(r)) goto done;
    r = FV_ERR_NOT_FOUND;
    for (size_t i = 0; i < listing.driver_count && r == FV_ERR_NOT_FOUND; i++) {
        const fv_registry_driver_listing *l = &listing.drivers[i];
        if (fv_registry_is_virtual(l->driver)) continue;
        for (size_t k = 0; k < l->count; k++) {
            r = open_with(l->driver, l->devices[k].uri, desc, out);
            if (r == FV_OK) {
                FV_INFO("devices", "auto: opened %s (%s)", l->devices[k].uri, l->devices[k].name);
                break;
            }
            FV_WARN("devices", "auto: %s would not open (%s); trying the next", l->devices[k].uri, fv_result_str(r));
            r = FV_ERR_NOT_FOUND;
        }
    }
    if (r == FV_ERR_NOT_FOUND) FV_ERROR("devices", "auto: no eye trackers attached");
done:
    fv_registry_listing_fini(&listing);
    return r;
}

fv_result fv_registry_open(const fv_registry *reg, const char *uri, const fv_device_open_desc *desc,
                           fv_device **out_dev)
{
    if (!reg || !uri || !out_dev) return FV_ERR_INVALID_ARG;
    *out_dev = NULL;
    if (strcmp(uri, "auto") == 0) return open_auto(reg, desc, out_dev);
    const char *colon = strchr(uri, ':');
    size_t n = colon ? (size_t)(colon - uri) : strlen(uri);
    const fv_driver *d = fv_registry_find(reg, uri, n);
    if (!d) {
        char known[160];
        known_schemes(reg, known, sizeof known);
        FV_ERROR("devices", "'%s': unknown URI scheme '%.*s' (known: %s)", uri, (int)(n > 32 ? 32 : n), uri, known);
        return FV_ERR_NOT_FOUND;
    }
    return open_with(d, uri, desc, out_dev);
}

fv_result fv_registry_open_fn(void *reg, const char *uri, const fv_device_open_desc *desc, fv_device **out_dev)
{
    return fv_registry_open((const fv_registry *)reg, uri, desc, out_dev);
}
