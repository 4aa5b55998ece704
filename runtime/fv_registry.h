/* @brief The device registry: the drivers a program has (an array of `const fv_driver *`), probed all together and
 * opened by URI scheme. Hardware drivers keep their given order; the replay ("trace") and simulated ("sim") drivers
 * always come last, so that "auto" and listings prefer a real tracker. Plain data; not thread-safe. */
#ifndef FV_REGISTRY_H
#define FV_REGISTRY_H

#include <stdbool.h>
#include <stddef.h>

#include "fovea/fv_device.h"

#define FV_REGISTRY_MAX_DRIVERS 16
/** Devices kept per driver in a listing; a driver reporting more is listed as truncated. */
#define FV_REGISTRY_MAX_DEVICES 256

typedef struct fv_registry {
    const fv_driver *drivers[FV_REGISTRY_MAX_DRIVERS];
    size_t count;
} fv_registry;

/** Fill from a NULL-terminated array. Rejects (and logs) a driver without scheme/probe/open, a duplicate scheme, or
 *  more than FV_REGISTRY_MAX_DRIVERS. Nothing to free. */
FV_MUST_CHECK fv_result fv_registry_init(fv_registry *reg, const fv_driver *const *drivers);

/** The driver answering `scheme` (compared over `len` characters), or NULL. */
const fv_driver *fv_registry_find(const fv_registry *reg, const char *scheme, size_t len);
/** True for the drivers that are not hardware ("sim", "trace"). */
bool fv_registry_is_virtual(const fv_driver *driver);

/** What one driver saw. */
typedef struct fv_registry_driver_listing {
    const fv_driver *driver;
    fv_result result;          /* the probe's result (FV_OK, or why it could not look) */
    fv_device_info *devices;   /* heap, `count` entries (strings always NUL-terminated) */
    size_t count;
    bool truncated;            /* the driver reported more than FV_REGISTRY_MAX_DEVICES */
} fv_registry_driver_listing;

typedef struct fv_registry_listing {
    fv_registry_driver_listing drivers[FV_REGISTRY_MAX_DRIVERS];
    size_t driver_count;
    size_t hardware_devices;   /* devices seen by drivers other than sim and trace */
} fv_registry_listing;

/** Probe every driver in order. A driver whose probe fails is listed with its result (the rest still run); only an
 *  allocation failure fails the call. Free with fv_registry_listing_fini (also after a failure). */
FV_MUST_CHECK fv_result fv_registry_probe(const fv_registry *reg, fv_registry_listing *out_listing);
void fv_registry_listing_fini(fv_registry_listing *listing);

/** Open by URI with the driver of its scheme. "auto" opens the first device a hardware driver lists
 *  (FV_ERR_NOT_FOUND, "no eye trackers attached", when there is none). An unknown scheme is FV_ERR_NOT_FOUND with the
 *  known schemes in the log. A driver that reports success without a usable device is FV_ERR_PROTOCOL. */
FV_MUST_CHECK fv_result fv_registry_open(const fv_registry *reg, const char *uri, const fv_device_open_desc *desc,
                                         fv_device **out_dev);

/** fv_registry_open with the registry as `user`: fits fv_gaze_source_open_fn. */
FV_MUST_CHECK fv_result fv_registry_open_fn(void *reg, const char *uri, const fv_device_open_desc *desc,
                                            fv_device **out_dev);

#endif
