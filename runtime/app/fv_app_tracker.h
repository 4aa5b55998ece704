/* @brief The gaze tracker of a run, as `fovea run --gaze`, `fovea latency` and the OpenXR runtime's eye gaze share
 * it: a gaze source on a URI opened through the one driver list (fv_app_drivers.h), the gaze pipeline (filter,
 * events, prediction), the one drain between them with loss and stall (fv_gaze_drain.h), prediction to any time,
 * the tracker's recorded head pose relative to its first (fv_head_follow.h), and USB hotplug re-probes for hid:/usb:
 * trackers. Opening fails fast (before any renderer is made) with one line naming the URI when the device cannot be
 * opened. One owner thread (the OpenXR runtime serialises with its lock). */
#ifndef FV_APP_TRACKER_H
#define FV_APP_TRACKER_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_clock.h"
#include "fv_gaze_drain.h"
#include "fv_gaze_pipeline.h"
#include "fv_gaze_source.h"
#include "fv_head_follow.h"

typedef struct fv_app_tracker_desc {
    const char *uri;              /* required */
    fv_gaze_source_mode mode;     /* 0 = a reader thread */
    const fv_clock *clock;        /* the host clock; NULL = monotonic (required non-NULL for inline mode) */
    bool no_predict;              /* the latest filtered sample instead of the prediction */
    int64_t stall_timeout_ns;     /* nothing new for this long: lost; 0 = 100 ms */
    size_t ring_capacity;         /* 0 = the source's default */
    const char *who;              /* the program, for the one failure line ("fovea run", "xr"); NULL = "gaze" */
} fv_app_tracker_desc;

/** What the tracker's head poses were like so far (to tell a user that --head trace has nothing to follow). */
typedef struct fv_app_head_report {
    uint64_t flagged;  /* samples that said they carry a head pose (FV_GAZE_HEAD_VALID) */
    uint64_t usable;   /* ... that had one (finite, a forward, in range); all zero poses are not */
    uint64_t moved;    /* ... that differ from the first usable pose */
} fv_app_head_report;

typedef struct fv_app_tracker fv_app_tracker;

/** Open the source and the pipeline. Fails (after one line "<who>: cannot open gaze source '<uri>': <reason>")
 *  when the device cannot be opened now or a sim: URI does not parse. */
FV_MUST_CHECK fv_result fv_app_tracker_open(const fv_app_tracker_desc *desc, fv_app_tracker **out);
void fv_app_tracker_close(fv_app_tracker **t);

/** Drain what the device sent into the pipeline (and re-open a lost hid:/usb: tracker that hotplug saw arrive).
 *  Returns whether the source counts as lost now. */
bool fv_app_tracker_drain(fv_app_tracker *t);
/** Only the hotplug part of a drain (for a frame loop that drains through fv_app_tracker_drain_state itself). */
void fv_app_tracker_hotplug(fv_app_tracker *t);
/** Drain, then the pipeline's prediction for t_target_ns (host clock). */
void fv_app_tracker_predict(fv_app_tracker *t, int64_t t_target_ns, fv_gaze_prediction *out);
/** The newest recorded head pose relative to the first usable one (no drain): rotation and translation (m) in the
 *  first pose's frame. false while there is none. */
bool fv_app_tracker_head(const fv_app_tracker *t, fv_quat *out_dq, fv_vec3 *out_dp_m);
void fv_app_tracker_head_report(const fv_app_tracker *t, fv_app_head_report *out);

/** The drain a frame loop latches from (fv_frame_loop_desc.drain). */
fv_gaze_drain *fv_app_tracker_drain_state(fv_app_tracker *t);
fv_gaze_source *fv_app_tracker_source(const fv_app_tracker *t);
fv_gaze_pipeline *fv_app_tracker_pipeline(const fv_app_tracker *t);
const char *fv_app_tracker_uri(const fv_app_tracker *t);
/** The capture-to-receipt latency the URI declares (fv_app_declared_latency_ms), ns. */
int64_t fv_app_tracker_latency_ns(const fv_app_tracker *t);
/** Re-opens that hotplug arrivals triggered. */
uint64_t fv_app_tracker_reprobes(const fv_app_tracker *t);

#endif
