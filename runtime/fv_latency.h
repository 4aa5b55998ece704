/* @brief Latency records: one per frame id with every timepoint from the eye being sampled to the frame's photons,
 * and a summary (gaze-to-photon percentiles, late frames, repeated refreshes, the share of each stage).
 * All times are ns on the host clock, except t_sample_device_ns (the device's own timeline). Plain data. */
#ifndef FV_LATENCY_H
#define FV_LATENCY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fv_result.h"
#include "fv_stats.h"

typedef struct fv_latency_record {
    uint64_t frame_id;
    uint64_t target_vsync;        /* the refresh the frame was paced for */
    uint64_t shown_vsync;         /* the refresh that showed it */
    bool has_gaze;                /* a sample was latched and the device was live (not lost/ended/stalled); the
                                     percentiles use these frames. Sample fields are 0 when no sample ever came */
    bool fresh_gaze;              /* the latched sample arrived since the previous frame */
    bool late;                    /* shown after its target refresh: the frame missed its deadline */
    bool device_lost;             /* the gaze device was lost, ended or stalled when this frame latched */
    uint32_t repeated_vsyncs;     /* refreshes since the previous frame that showed the previous frame again */
    int gaze_event;               /* fv_gaze_event of the prediction */
    float uncertainty_deg;        /* the prediction's uncertainty radius */
    uint64_t sample_seq;          /* the latched sample's source sequence number */
    int64_t t_sample_device_ns;   /* latched sample: device timestamp (device timeline) */
    int64_t t_sample_capture_ns;  /* latched sample: when the eye was sampled = receipt − declared tracker latency */
    int64_t t_sample_received_ns; /* latched sample: host receipt (its t_host_ns) */
    int64_t t_wake_ns;            /* the loop woke for this frame */
    int64_t t_latch_ns;           /* newest gaze latched */
    int64_t t_cpu_begin_ns;       /* render callback called */
    int64_t t_submit_ns;          /* CPU work submitted */
    int64_t t_gpu_begin_ns, t_gpu_end_ns;
    int64_t t_present_ns;         /* handed to the display */
    int64_t t_vsync_ns;           /* scan-out of the shown refresh starts */
    int64_t t_photon_ns;          /* photons due (the display's photon time for that refresh) */
} fv_latency_record;

/** Gaze-to-photon of one record (photon − capture), saturated (records read from files may hold any times); only
 *  meaningful when has_gaze. */
static inline int64_t fv_latency_gaze_to_photon_ns(const fv_latency_record *r)
{
    return fv_i64_sub_sat(r->t_photon_ns, r->t_sample_capture_ns);
}

/** Consecutive stages; their durations add up to gaze-to-photon exactly. */
typedef enum fv_latency_stage {
    FV_LATENCY_TRACKER = 0,  /* capture → host receipt (the tracker's declared latency) */
    FV_LATENCY_SAMPLE_AGE,   /* receipt → latch (waiting for the frame to pick the sample up) */
    FV_LATENCY_LATCH,        /* latch → CPU begin (drain, predict, build the frame input) */
    FV_LATENCY_CPU,          /* CPU begin → submit */
    FV_LATENCY_GPU,          /* submit → GPU end */
    FV_LATENCY_PRESENT,      /* GPU end → vsync (present, wait for the refresh) */
    FV_LATENCY_DISPLAY,      /* vsync → photon (scan-out and persistence) */
    FV_LATENCY_STAGE_COUNT
} fv_latency_stage;

/** Short stable name ("tracker", "sample_age", ...), used as JSON keys. */
const char *fv_latency_stage_str(fv_latency_stage s);
/** Duration of one stage of a record, ns, saturated as gaze-to-photon is. */
int64_t fv_latency_stage_ns(const fv_latency_record *r, fv_latency_stage s);

typedef struct fv_latency_summary {
    size_t frames;
    size_t frames_with_gaze;      /* the percentiles are over these */
    size_t late_frames;           /* frames shown after their target refresh */
    size_t repeated_vsyncs;       /* refreshes that showed an old frame again (judder) */
    size_t missed;                /* late_frames + repeated_vsyncs: refreshes the loop did not make */
    size_t lost_frames;           /* frames latched while the device was lost/stalled */
    size_t stale_frames;          /* frames with gaze but no new sample since the previous frame */
    double g2p_min_ms, g2p_mean_ms, g2p_p50_ms, g2p_p95_ms, g2p_p99_ms, g2p_max_ms;
    double stage_mean_ms[FV_LATENCY_STAGE_COUNT];
    double stage_share[FV_LATENCY_STAGE_COUNT]; /* stage mean / gaze-to-photon mean, 0..1 */
    double frame_interval_mean_ms; /* mean time between consecutive shown refreshes */
} fv_latency_summary;

/** Summarize n records (n may be 0: all zero). Percentiles are nearest-rank (fv_percentile_i64). Finite for any input;
 *  FV_ERR_NO_MEMORY only if the sort buffer cannot be allocated. */
FV_MUST_CHECK fv_result fv_latency_summarize(const fv_latency_record *records, size_t n,
                                             fv_latency_summary *out_summary);

#endif
