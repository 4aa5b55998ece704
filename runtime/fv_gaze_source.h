/* @brief A gaze source: one open device, read continuously into a lock-free ring that the frame loop drains.
 *
 * Thread mode (real devices): a reader thread calls fv_device_read with a timeout and pushes every sample into an
 * SPSC ring (full: the oldest sample is dropped and counted). The frame loop only pops from the ring, so a device that
 * stalls, floods or disappears never blocks it. When a read fails (unplugged, hang-up, I/O error) the thread closes
 * the device, reports it lost and re-opens the URI with exponential backoff until it is back.
 *
 * Inline mode (simulated clock, replay): no thread; the frame loop calls fv_gaze_source_poll once per frame, which
 * reads with timeout 0 until the device has nothing more (everything due is read, so nothing waits in the driver
 * and latency stays bounded whatever the rate; what the ring cannot hold is dropped oldest first and counted) and
 * runs the same loss/re-open logic on the injected clock, so tests and `fovea latency` are deterministic. Only for
 * devices whose read does not block at timeout 0.
 *
 * Either way every sample read is delivered (popped), dropped as stale (an overrun: the ring was full, the newest
 * kept) or still queued: samples == delivered + overruns + queued. */
#ifndef FV_GAZE_SOURCE_H
#define FV_GAZE_SOURCE_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_device.h"
#include "fv_ring.h"

/** Opens a device by URI (fv_registry_open_fn, or a tool's own). */
typedef fv_result (*fv_gaze_source_open_fn)(void *user, const char *uri, const fv_device_open_desc *desc,
                                            fv_device **out_dev);

typedef enum fv_gaze_source_mode {
    FV_GAZE_SOURCE_THREAD = 0, /* a reader thread per device (default) */
    FV_GAZE_SOURCE_INLINE = 1, /* read from fv_gaze_source_poll on the caller's thread, paced by desc.clock */
} fv_gaze_source_mode;

typedef enum fv_gaze_source_state {
    FV_GAZE_SOURCE_CONNECTED = 0, /* the device is open and being read */
    FV_GAZE_SOURCE_LOST = 1,      /* the device went away or failed; re-opening with backoff */
    FV_GAZE_SOURCE_ENDED = 2,     /* a finite source (a trace) has played to its end */
    FV_GAZE_SOURCE_FAILED = 3,    /* re-opening cannot succeed (bad URI or arguments); given up */
} fv_gaze_source_state;

const char *fv_gaze_source_state_str(fv_gaze_source_state s);

/** Zero means default. */
typedef struct fv_gaze_source_desc {
    const char *uri;                 /* required; copied; opened (and re-opened) through `open` */
    fv_gaze_source_open_fn open;     /* required unless `device` is given and re-opening is not wanted */
    void *open_user;
    fv_device *device;               /* optional: an already open device for `uri`; ownership passes to the source
                                        (also when create fails) */
    fv_device_open_desc open_desc;   /* passed to open (the device's host clock) */
    fv_gaze_source_mode mode;
    const fv_clock *clock;           /* inline mode: required, paces re-open backoff. Thread mode: ignored, the
                                        thread paces itself on the monotonic clock */
    bool start_lost;                 /* if the first open fails, start LOST and keep retrying instead of failing */
    size_t ring_capacity;            /* samples; 0 = 512 */
    fv_ring_policy overrun_policy;   /* 0 = drop the oldest */
    size_t read_batch;               /* samples per read call; 0 = 32, at most 256 */
    size_t poll_max_samples;         /* inline mode: a poll stops after this many samples even if the device still
                                        has more (one that never runs dry; counted in poll_limited); 0 = 64 ring
                                        capacities */
    int read_timeout_ms;             /* thread mode: per read; 0 = 10 */
    int64_t retry_min_ns;            /* first re-open delay; 0 = 50 ms */
    int64_t retry_max_ns;            /* backoff cap; 0 = 2 s */
} fv_gaze_source_desc;

typedef struct fv_gaze_source fv_gaze_source;

/** Open the device (unless given) and, in thread mode, start the reader thread. Fails with the open's error (the
 *  driver logged why) unless start_lost is set. */
FV_MUST_CHECK fv_result fv_gaze_source_create(const fv_gaze_source_desc *desc, fv_gaze_source **out_source);
/** Stop the reader thread, close the device, free; sets *source to NULL; safe on NULL. Joins the thread: a driver
 *  whose read ignores its timeout delays this by as long as it blocks. */
void fv_gaze_source_destroy(fv_gaze_source **source);

/** Inline mode: read everything the device has now (up to poll_max_samples), handle loss and re-open on the injected
 *  clock. Thread mode: no-op. Consumer thread only. */
void fv_gaze_source_poll(fv_gaze_source *source);
/** Any thread: when the device is LOST, re-open it now instead of waiting out the backoff (and restart the backoff
 *  from its minimum). Called when USB hotplug reports a tracker arriving. No effect in other states. */
void fv_gaze_source_reprobe(fv_gaze_source *source);
/** Consumer thread only: the oldest unread sample (FV_OK) or FV_NO_NEW_DATA. Never blocks. */
FV_MUST_CHECK fv_result fv_gaze_source_pop(fv_gaze_source *source, fv_gaze_sample *out_sample);

typedef struct fv_gaze_source_status {
    fv_gaze_source_state state;
    uint64_t samples;        /* samples read from the device (all opens) */
    uint64_t delivered;      /* samples popped by the consumer */
    uint64_t overruns;       /* samples dropped as stale: the ring was full, the oldest went (newest kept) */
    uint64_t queued;         /* samples in the ring now (a snapshot) */
    uint64_t poll_limited;   /* inline polls that stopped at poll_max_samples with the device still delivering */
    uint64_t losses;         /* times the device was lost */
    uint64_t reopens;        /* successful re-opens after a loss */
    uint64_t open_failures;  /* failed re-open attempts */
    fv_result last_error;    /* the most recent read/open error (FV_OK if none) */
    size_t ring_capacity;
} fv_gaze_source_status;

/** Any thread: a snapshot of the state and counters. */
void fv_gaze_source_get_status(const fv_gaze_source *source, fv_gaze_source_status *out_status);
/** The URI this source reads. */
const char *fv_gaze_source_uri(const fv_gaze_source *source);

#endif
