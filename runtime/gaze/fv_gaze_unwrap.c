/* @brief N-bit timestamp unwrapping (see fv_gaze_unwrap.h). */
#include "fv_gaze_unwrap.h"

#include <string.h>

#include "fv_log.h"
#include "fv_stats.h"

fv_result fv_gaze_unwrap_init(fv_gaze_unwrap *u, unsigned bits, int64_t tick_ns)
{
    if (!u || bits < 1 || bits > 64 || tick_ns <= 0) return FV_ERR_INVALID_ARG;
    memset(u, 0, sizeof *u);
    u->bits = bits;
    u->mask = bits == 64 ? UINT64_MAX : ((UINT64_C(1) << bits) - 1u);
    u->tick_ns = tick_ns;
    return FV_OK;
}

void fv_gaze_unwrap_reset(fv_gaze_unwrap *u)
{
    u->started = false;
    u->last_raw = 0;
    u->last_ticks = 0;
    u->have_host = false;
    u->host_offset_ticks = 0;
    u->last_host_ns = 0;
}

int64_t fv_gaze_unwrap_wrap_ns(const fv_gaze_unwrap *u)
{
    return u->bits >= 63 ? INT64_MAX : fv_i64_mul_sat((int64_t)1 << u->bits, u->tick_ns);
}

/* The first value starts the timeline at raw ticks. */
static int64_t start(fv_gaze_unwrap *u, uint64_t raw)
{
    u->started = true;
    u->last_raw = raw;
    /* A 64-bit counter above INT64_MAX saturates; every narrower counter fits. */
    u->last_ticks = raw > (uint64_t)INT64_MAX ? INT64_MAX : (int64_t)raw;
    return u->last_ticks;
}

/* Modular difference to the reference, read as signed in [-2^(bits-1), 2^(bits-1)). */
static int64_t signed_delta(const fv_gaze_unwrap *u, uint64_t raw)
{
    uint64_t diff = (raw - u->last_raw) & u->mask;
    uint64_t half = UINT64_C(1) << (u->bits - 1);
    if (diff < half) return (int64_t)diff;
    uint64_t back = (u->mask - diff) + 1u; /* 2^bits - diff, in (0, 2^(bits-1)] */
    return back > (uint64_t)INT64_MAX ? INT64_MIN : -(int64_t)back;
}

/* Apply a difference in ticks; a forward (or equal) one makes raw the newest value. A late value (delta < 0) leaves
 * the reference alone. Returns the unwrapped ticks. */
static int64_t advance(fv_gaze_unwrap *u, uint64_t raw, int64_t delta)
{
    int64_t ticks = fv_i64_add_sat(u->last_ticks, delta);
    if (delta >= 0) {
        u->last_raw = raw;
        u->last_ticks = ticks;
    }
    return ticks;
}

int64_t fv_gaze_unwrap_push(fv_gaze_unwrap *u, uint64_t raw)
{
    raw &= u->mask;
    if (!u->started) return fv_i64_mul_sat(start(u, raw), u->tick_ns);
    return fv_i64_mul_sat(advance(u, raw, signed_delta(u, raw)), u->tick_ns);
}

#define OFFSET_SMOOTHING 32 /* values over which the receipt − device offset is averaged */

int64_t fv_gaze_unwrap_push_host(fv_gaze_unwrap *u, uint64_t raw, int64_t host_ns)
{
    if (u->bits >= 62 || (u->have_host && host_ns < u->last_host_ns))
        return fv_gaze_unwrap_push(u, raw); /* no wrap to resolve in a lifetime; a host time not to trust */
    raw &= u->mask;
    const int64_t host_ticks = host_ns / u->tick_ns;
    int64_t ticks;
    if (!u->started) {
        ticks = start(u, raw);
    } else {
        int64_t delta = signed_delta(u, raw);
        int64_t reading = fv_i64_add_sat(u->last_ticks, delta);
        /* The host's prediction of this value, against the counter's reading (ticks). */
        const int64_t wrap = (int64_t)1 << u->bits;
        int64_t gap = fv_i64_sub_sat(fv_i64_sub_sat(host_ticks, u->host_offset_ticks), reading);
        if (gap >= wrap / 2 || gap < -(wrap / 2)) {
            /* whole wraps the counter cannot show, rounded to the nearest */
            int64_t k = gap >= 0 ? (gap + wrap / 2) / wrap : -((-gap + wrap / 2 - 1) / wrap);
            int64_t corrected = fv_i64_add_sat(delta, fv_i64_mul_sat(k, wrap));
            u->host_corrections++;
            if (!u->warned) {
                FV_WARN("gaze", "%s: device timestamps disagree with the host clock: the %u-bit counter (wraps every "
                        "%.3f ms) reads %.3f ms after the previous value where the receipt times say %.3f ms; it wraps "
                        "faster than samples arrive or the device went quiet: wraps are resolved from the host clock "
                        "(reported once)",
                        u->label ? u->label : "device", u->bits, (double)fv_gaze_unwrap_wrap_ns(u) / 1e6,
                        (double)fv_i64_mul_sat(delta, u->tick_ns) / 1e6,
                        (double)fv_i64_mul_sat(corrected, u->tick_ns) / 1e6);
                u->warned = true;
            }
            delta = corrected;
        }
        ticks = advance(u, raw, delta);
        if (delta < 0) return fv_i64_mul_sat(ticks, u->tick_ns); /* a late value says little about the offset */
    }
    u->last_host_ns = host_ns;
    int64_t offset = fv_i64_sub_sat(host_ticks, ticks);
    if (!u->have_host) {
        u->host_offset_ticks = offset;
        u->have_host = true;
    } else {
        int64_t d = fv_i64_sub_sat(offset, u->host_offset_ticks);
        u->host_offset_ticks += (d >= 0 ? d + OFFSET_SMOOTHING / 2 : d - OFFSET_SMOOTHING / 2) / OFFSET_SMOOTHING;
    }
    return fv_i64_mul_sat(ticks, u->tick_ns);
}
