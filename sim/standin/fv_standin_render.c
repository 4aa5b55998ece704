/* @brief Stand-in renderer of configurable cost (see fv_standin_render.h). */
#include "fv_standin_render.h"

#include <math.h>
#include <string.h>

#include "fv_log.h"

fv_result fv_standin_render_init(fv_standin_render *s, const fv_clock *clock, int64_t render_ns, double cpu_share,
                                 int64_t jitter_ns, uint64_t seed)
{
    if (!s) return FV_ERR_INVALID_ARG;
    memset(s, 0, sizeof *s);
    if (!clock) {
        FV_ERROR("frame", "stand-in renderer: a clock is required");
        return FV_ERR_INVALID_ARG;
    }
    if (render_ns < 0 || render_ns > 10 * FV_NS_PER_S || !(cpu_share >= 0.0 && cpu_share <= 1.0) || jitter_ns < 0 ||
        jitter_ns > render_ns) {
        FV_ERROR("frame", "stand-in renderer: render %lld ns (0..10 s), cpu share %g (0..1), jitter %lld ns "
                 "(0..render): out of range", (long long)render_ns, cpu_share, (long long)jitter_ns);
        return FV_ERR_RANGE;
    }
    s->clock = clock;
    s->cpu_ns = (int64_t)llround((double)render_ns * cpu_share);
    s->gpu_ns = render_ns - s->cpu_ns;
    s->jitter_ns = jitter_ns;
    s->seed = seed;
    s->rng = seed * UINT64_C(6364136223846793005) + UINT64_C(1442695040888963407);
    return FV_OK;
}

/* uniform in [-j/2, +j/2] */
static int64_t jitter(fv_standin_render *s)
{
    if (s->jitter_ns <= 0) return 0;
    s->rng = s->rng * UINT64_C(6364136223846793005) + UINT64_C(1442695040888963407);
    uint64_t u = s->rng >> 11; /* 53 bits */
    double x = (double)u / 9007199254740992.0 - 0.5;
    return (int64_t)llround(x * (double)s->jitter_ns);
}

fv_result fv_standin_render_frame(void *user, fv_frame_input *in, fv_frame_render_times *out)
{
    fv_standin_render *s = user;
    if (!s || !s->clock || !out) return FV_ERR_INVALID_ARG;
    (void)in;
    int64_t begin = fv_clock_now_ns(s->clock);
    int64_t cpu = s->cpu_ns + jitter(s);
    int64_t gpu = s->gpu_ns + jitter(s);
    if (cpu < 0) cpu = 0;
    if (gpu < 0) gpu = 0;
    /* the CPU part takes real (or simulated) time on this thread */
    s->clock->sleep_until_ns(s->clock, begin + cpu);
    int64_t submit = fv_clock_now_ns(s->clock);
    /* the GPU runs asynchronously, one frame after another */
    int64_t gpu_begin = submit > s->gpu_busy_until_ns ? submit : s->gpu_busy_until_ns;
    s->gpu_busy_until_ns = gpu_begin + gpu;
    out->t_submit_ns = submit;
    out->t_gpu_begin_ns = gpu_begin;
    out->t_gpu_end_ns = gpu_begin + gpu;
    s->frames++;
    return FV_OK;
}
