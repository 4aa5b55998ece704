/* @brief The device interface: drivers answer a URI scheme ("hid", "usb", "trace", "sim"), list what they see,
 * and open devices that yield fv_gaze_sample. A driver is reachable only through this interface. */
#ifndef FV_DEVICE_H
#define FV_DEVICE_H

#include <stddef.h>
#include <stdint.h>

#include "fv_clock.h"
#include "fv_gaze_sample.h"
#include "fv_result.h"

/** What a driver sees: one attached (or openable) device. */
typedef struct fv_device_info {
    char uri[256];      /* a URI that opens this device ("hid:/dev/hidraw3", "sim:seed=1") */
    char name[128];     /* human-readable product name */
    char driver[16];    /* scheme of the driver that found it */
    char detail[256];   /* free text: VID:PID, serial, usage page, why it matched */
} fv_device_info;

/** Options common to every open. Zero means default. */
typedef struct fv_device_open_desc {
    const fv_clock *clock; /* host clock for t_host_ns and replay pacing; NULL = monotonic */
} fv_device_open_desc;

typedef struct fv_device fv_device;

/** Operations of an open device. read is called from one reader thread only. */
typedef struct fv_device_ops {
    /** Read up to cap samples, waiting at most timeout_ms (0 = poll). FV_OK with *out_count >= 1, FV_TIMEOUT with 0,
     *  FV_END_OF_STREAM for a finished finite source, FV_ERR_DEVICE_LOST when unplugged, other errors as they are. */
    fv_result (*read)(fv_device *dev, fv_gaze_sample *out, size_t cap, size_t *out_count, int timeout_ms);
    /** Close and free everything, the device object included. */
    void (*close)(fv_device *dev);
} fv_device_ops;

/** Base of every open device; drivers embed it as their first member. */
struct fv_device {
    const fv_device_ops *ops;
    fv_device_info info;
    double nominal_rate_hz; /* the rate the device declares (0 unknown) */
};

typedef struct fv_driver {
    const char *scheme; /* "hid", "usb", "trace", "sim" */
    const char *summary;
    /** List what this driver sees; *out_count may exceed cap (only cap are written). */
    fv_result (*probe)(fv_device_info *out, size_t cap, size_t *out_count);
    /** Open by full URI ("trace:rec.csv?speed=2"). */
    fv_result (*open)(const char *uri, const fv_device_open_desc *desc, fv_device **out_dev);
} fv_driver;

static inline fv_result fv_device_read(fv_device *dev, fv_gaze_sample *out, size_t cap, size_t *out_count,
                                       int timeout_ms)
{
    return dev->ops->read(dev, out, cap, out_count, timeout_ms);
}

/** Close and set *dev to NULL; safe on NULL. */
static inline void fv_device_close(fv_device **dev)
{
    if (dev && *dev) {
        (*dev)->ops->close(*dev);
        *dev = NULL;
    }
}

#endif
