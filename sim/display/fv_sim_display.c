/* @brief Simulated display clock (see fv_sim_display.h). Vsync k happens at t0 + round(k * period) + jitter(k), with
 * jitter(k) a seeded hash of k in [-J, +J]; J < period/4 keeps the vsyncs strictly increasing. */
#include "fv_sim_display.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "fv_log.h"

typedef struct sim_display {
    fv_display base; /* first member: fv_display * <-> sim_display * */
    int64_t t0_ns;
    double period_exact_ns;
    int64_t jitter_ns;
    uint64_t seed;
    int64_t photon_offset_ns;
} sim_display;

/* splitmix64: a well-mixed 64-bit hash of the vsync index */
static uint64_t mix64(uint64_t x)
{
    x += UINT64_C(0x9E3779B97F4A7C15);
    x = (x ^ (x >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    x = (x ^ (x >> 27)) * UINT64_C(0x94D049BB133111EB);
    return x ^ (x >> 31);
}

static int64_t vsync_time(const sim_display *s, uint64_t k)
{
    int64_t nominal = s->t0_ns + (int64_t)llround((double)k * s->period_exact_ns);
    if (s->jitter_ns == 0) return nominal;
    uint64_t h = mix64(s->seed ^ mix64(k));
    int64_t j = (int64_t)(h % (uint64_t)(2 * s->jitter_ns + 1)) - s->jitter_ns;
    return nominal + j;
}

static fv_result sim_vsync_at_or_after(fv_display *d, int64_t t_ns_min, fv_vsync *out)
{
    sim_display *s = (sim_display *)d;
    if (!out) return FV_ERR_INVALID_ARG;
    uint64_t k = 0;
    if (t_ns_min > s->t0_ns) {
        uint64_t since = (uint64_t)t_ns_min - (uint64_t)s->t0_ns; /* well defined even across the int64 range */
        if (since > ((uint64_t)1 << 61)) { /* ~73 years: refuse rather than let vsync times overflow */
            FV_ERROR("display", "time %lld ns is beyond the simulated display's timeline", (long long)t_ns_min);
            return FV_ERR_RANGE;
        }
        k = (uint64_t)ceil((double)since / s->period_exact_ns);
    }
    /* the estimate ignores jitter (< period/4), so the answer is at most one step away */
    while (k > 0 && vsync_time(s, k - 1) >= t_ns_min) k--;
    while (vsync_time(s, k) < t_ns_min) k++;
    out->index = k;
    out->t_ns = vsync_time(s, k);
    return FV_OK;
}

static int64_t sim_photon_ns(fv_display *d, const fv_vsync *v)
{
    sim_display *s = (sim_display *)d;
    return v->t_ns + s->photon_offset_ns;
}

static fv_result sim_present(fv_display *d, int64_t t_present_ns, uint64_t target_index, fv_vsync *out_shown)
{
    sim_display *s = (sim_display *)d;
    if (!out_shown) return FV_ERR_INVALID_ARG;
    fv_vsync first;
    if (t_present_ns > INT64_MAX - s->base.present_margin_ns) {
        FV_ERROR("display", "present time %lld ns is beyond the simulated display's timeline",
                 (long long)t_present_ns);
        return FV_ERR_RANGE;
    }
    /* the first vsync whose latch deadline (vsync - margin) the frame made */
    FV_TRY(sim_vsync_at_or_after(d, t_present_ns + s->base.present_margin_ns, &first));
    if (first.index < target_index) { /* early frames wait for their target (FIFO, no tearing) */
        first.index = target_index;
        first.t_ns = vsync_time(s, target_index);
    }
    *out_shown = first;
    return FV_OK;
}

static void sim_destroy(fv_display *d) { free(d); }

static const fv_display_ops g_sim_display_ops = {
    .vsync_at_or_after = sim_vsync_at_or_after,
    .photon_ns = sim_photon_ns,
    .present = sim_present,
    .destroy = sim_destroy,
};

fv_result fv_sim_display_create(const fv_sim_display_desc *desc, fv_display **out_display)
{
    if (!out_display) return FV_ERR_INVALID_ARG;
    *out_display = NULL;
    if (!desc || !desc->clock) {
        FV_ERROR("display", "simulated display: a clock is required");
        return FV_ERR_INVALID_ARG;
    }
    bool ok = true;
    double hz = desc->refresh_hz == 0.0 ? 90.0 : desc->refresh_hz;
    if (!(hz >= 1.0 && hz <= 1000.0)) { /* also false for NaN */
        FV_ERROR("display", "simulated display: refresh_hz %g outside 1..1000", desc->refresh_hz);
        return FV_ERR_RANGE;
    }
    double period = 1e9 / hz;
    int64_t period_ns = (int64_t)llround(period);
    int64_t scanout = desc->scanout_ns == 0 ? (int64_t)llround(0.95 * period) : desc->scanout_ns;
    int64_t persistence = desc->persistence_ns;
    if (persistence == 0) persistence = 2 * FV_NS_PER_MS < period_ns ? 2 * FV_NS_PER_MS : period_ns;
    int64_t margin = desc->present_margin_ns == 0 ? FV_NS_PER_MS / 2 : desc->present_margin_ns;
    int64_t t0_offset = desc->t0_offset_ns == 0 ? period_ns : desc->t0_offset_ns;
    if (desc->vsync_jitter_ns < 0 || desc->vsync_jitter_ns > period_ns / 4) {
        FV_ERROR("display", "simulated display: vsync_jitter_ns %lld outside 0..%lld (a quarter period)",
                 (long long)desc->vsync_jitter_ns, (long long)(period_ns / 4));
        ok = false;
    }
    if (scanout < 0 || scanout > period_ns) {
        FV_ERROR("display", "simulated display: scanout_ns %lld outside 0..%lld (one period)", (long long)scanout,
                 (long long)period_ns);
        ok = false;
    }
    if (persistence < 0 || persistence > period_ns) {
        FV_ERROR("display", "simulated display: persistence_ns %lld outside 0..%lld (one period)",
                 (long long)persistence, (long long)period_ns);
        ok = false;
    }
    if (margin < 0 || margin > period_ns / 2) {
        FV_ERROR("display", "simulated display: present_margin_ns %lld outside 0..%lld (half a period)",
                 (long long)margin, (long long)(period_ns / 2));
        ok = false;
    }
    if (desc->scan != FV_SIM_DISPLAY_ROLLING && desc->scan != FV_SIM_DISPLAY_GLOBAL) {
        FV_ERROR("display", "simulated display: unknown scan mode %d", (int)desc->scan);
        ok = false;
    }
    if (t0_offset < 0 || t0_offset > 1000 * FV_NS_PER_S) {
        FV_ERROR("display", "simulated display: t0_offset_ns %lld outside 0..1000 s", (long long)t0_offset);
        ok = false;
    }
    if (!ok) return FV_ERR_RANGE;

    sim_display *s = calloc(1, sizeof *s);
    if (!s) {
        FV_ERROR("display", "simulated display: out of memory");
        return FV_ERR_NO_MEMORY;
    }
    s->base.ops = &g_sim_display_ops;
    s->base.refresh_hz = hz;
    s->base.period_ns = period_ns;
    s->base.present_margin_ns = margin;
    s->t0_ns = fv_clock_now_ns(desc->clock) + t0_offset;
    s->period_exact_ns = period;
    s->jitter_ns = desc->vsync_jitter_ns;
    s->seed = desc->seed;
    /* rolling: the middle row starts emitting half a scan-out after vsync; global: the flash follows the whole
     * scan-out. Either way the light's mean time is half the persistence later. */
    s->photon_offset_ns = (desc->scan == FV_SIM_DISPLAY_GLOBAL ? scanout : scanout / 2) + persistence / 2;
    *out_display = &s->base;
    return FV_OK;
}

int64_t fv_sim_display_photon_offset_ns(const fv_display *display)
{
    return ((const sim_display *)display)->photon_offset_ns;
}
