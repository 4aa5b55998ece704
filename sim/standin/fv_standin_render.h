/* @brief A stand-in renderer for the frame loop: costs a configurable CPU time and GPU time (optionally with seeded
 * jitter) by advancing the clock instead of drawing. On a simulated clock the cost is exact and instant; on the
 * monotonic clock it sleeps. Fits fv_frame_render_fn. One owner; not thread-safe. */
#ifndef FV_STANDIN_RENDER_H
#define FV_STANDIN_RENDER_H

#include <stdint.h>

#include "fv_frame_loop.h"

typedef struct fv_standin_render {
    const fv_clock *clock;  /* the loop's clock */
    int64_t cpu_ns;         /* CPU cost per frame (the callback returns this much later) */
    int64_t gpu_ns;         /* GPU cost per frame, after submit; GPU frames do not overlap */
    int64_t jitter_ns;      /* each cost varies by up to ±jitter/2 (deterministic from seed); 0 none */
    uint64_t seed;
    /* state */
    int64_t gpu_busy_until_ns;
    uint64_t frames;
    uint64_t rng;
} fv_standin_render;

/** Set up a stand-in of total cost render_ns split cpu_share (0..1) to the CPU and the rest to the GPU. */
FV_MUST_CHECK fv_result fv_standin_render_init(fv_standin_render *s, const fv_clock *clock, int64_t render_ns,
                                               double cpu_share, int64_t jitter_ns, uint64_t seed);
/** The render callback: user is a fv_standin_render *. */
fv_result fv_standin_render_frame(void *user, fv_frame_input *in, fv_frame_render_times *out_times);

#endif
