/* @brief N-bit timestamp unwrapping (see fv_gaze_unwrap.h). */
#include "fv_gaze_unwrap.h"

#include <string.h>

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
}

int64_t fv_gaze_unwrap_push(fv_gaze_unwrap *u, uint64_t raw)
{
    raw &= u->mask;
    if (!u->started) {
        u->started = true;
        u->last_raw = raw;
        /* A 64-bit counter above INT64_MAX saturates; every narrower counter fits. */
        u->last_ticks = raw > (uint64_t)INT64_MAX ? INT64_MAX : (int64_t)raw;
        return fv_i64_mul_sat(u->last_ticks, u->tick_ns);
    }
    /* Modular difference, read as signed in [-2^(bits-1), 2^(bits-1)). */
    uint64_t diff = (raw - u->last_raw) & u->mask;
    uint64_t half = UINT64_C(1) << (u->bits - 1);
    int64_t delta;
    if (diff < half) {
        delta = (int64_t)diff;
    } else {
        uint64_t back = (u->mask - diff) + 1u; /* 2^bits - diff, in (0, 2^(bits-1)] */
        delta = back > (uint64_t)INT64_MAX ? INT64_MIN : -(int64_t)back;
    }
    int64_t ticks = fv_i64_add_sat(u->last_ticks, delta);
    if (delta >= 0) {
        /* Forward (or equal): this is the newest value. A late value (delta < 0) leaves the reference alone. */
        u->last_raw = raw;
        u->last_ticks = ticks;
    }
    return fv_i64_mul_sat(ticks, u->tick_ns);
}
