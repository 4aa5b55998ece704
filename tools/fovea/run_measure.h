/* @brief What a rendering command measures, shared by `fovea run` and `fovea bench`: per frame the CPU time of the
 * recording thread and the wall time, per completed frame the GPU time of every pass and of the whole frame and
 * each pass's counters; summarised as median and p95 in text or JSON. One owner thread. */
#ifndef FV_RUN_MEASURE_H
#define FV_RUN_MEASURE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "fv_renderer.h"

typedef struct cJSON cJSON;

typedef struct fv_pass_series {
    char name[FV_PASS_ID_MAX];
    double *ms; /* one per measured frame */
    size_t n;
    fv_pass_counters last; /* the counters of the last measured frame */
} fv_pass_series;

typedef struct fv_measure {
    size_t cap;           /* frames the series hold */
    double *cpu_ms, *wall_ms, *frame_gpu_ms;
    size_t drawn;         /* frames whose CPU time was recorded */
    size_t walled;        /* frames whose wall time was recorded */
    size_t measured;      /* frames whose GPU timings were taken */
    uint64_t last_timed;  /* frame id of the newest frame taken (UINT64_MAX: none) */
    fv_pass_series passes[FV_MAX_PASSES];
    uint32_t pass_count;
    fv_render_stats last_stats;
    double run_wall_ms;   /* fv_measure_run_wall: from the first frame's start to the last frame done (0: not set) */
    size_t run_frames;
} fv_measure;

/** Room for `frames` frames. FV_ERR_NO_MEMORY when it does not fit. */
FV_MUST_CHECK fv_result fv_measure_init(fv_measure *m, size_t frames);
void fv_measure_fini(fv_measure *m);
/** CPU time of the calling thread, ns (recording and submitting; driver worker threads are not counted). */
int64_t fv_measure_thread_cpu_ns(void);
/** One frame's CPU / wall time (ignored past the capacity). */
void fv_measure_cpu(fv_measure *m, double ms);
void fv_measure_wall(fv_measure *m, double ms);
/** The whole run: its elapsed time until the last frame was done, and its frames (the completed frames' wall time per
 *  frame, beside the loop's per-frame time, which does not wait for the GPU when frames overlap). */
void fv_measure_run_wall(fv_measure *m, double ms, size_t frames);
/** The GPU time of the frames taken so far, ms. */
double fv_measure_gpu_ms_sum(const fv_measure *m);
/** Take the GPU timings of every frame that completed since the last call, each once (frames complete in order;
 *  at most FV_RENDERER_STATS_HISTORY are kept by the renderer). false when out of memory. */
bool fv_measure_take(fv_measure *m, const fv_renderer *r);
/** Leave out every frame that completed so far (warm-up frames): later fv_measure_take calls start after them. */
void fv_measure_skip(fv_measure *m, const fv_renderer *r);
/** Add the summary (passes with median/p95 GPU ms and last-frame counters, frame GPU, CPU and wall percentiles,
 *  pixels shaded, peak device memory) to a JSON object. */
void fv_measure_add_json(const fv_measure *m, cJSON *obj);
/** Print the same as a table. */
void fv_measure_print(const fv_measure *m, FILE *f);
/** Foveation, when its passes ran: per eye the sampled fraction of the newest retired frame (cache hits: null
 *  until temporal reuse exists), and the median GPU time of each stage (map = pass "fovea", compaction =
 *  "compact", shading = "shade", temporal, reconstruction = "reconstruct", with its jfa/fill split of the newest
 *  retired frame) as the object "fovea" of j, or a table. Nothing when foveation is off. */
void fv_measure_add_fovea_json(const fv_measure *m, const fv_renderer *r, cJSON *j);
void fv_measure_print_fovea(const fv_measure *m, const fv_renderer *r, FILE *f);
/** One-bounce GI, when its pass ran: clusters per pixel as the shading pass measured them on the GPU in the newest
 *  frame read back (mean, max, and the pixels that ran the gather; null before any frame was read back),
 *  the cut's size, the GPU time of the last rebuild's stages (rsm, pyramid, cut) and the median of the gather's
 *  pass (it runs inside "shade", with the direct light) as the object "gi" of j, or a line. Nothing when GI is off. */
void fv_measure_add_gi_json(const fv_measure *m, const fv_renderer *r, cJSON *j);
void fv_measure_print_gi(const fv_measure *m, const fv_renderer *r, FILE *f);

#endif
