/* @brief Time as a parameter: an injected clock (monotonic for real use, simulated for tests and replay). */
#ifndef FV_CLOCK_H
#define FV_CLOCK_H

#include <stdint.h>

/** A clock: now_ns returns nanoseconds on a monotonic timeline. Thread-safe for the monotonic clock; a simulated
 *  clock is advanced by its one owner. */
typedef struct fv_clock {
    int64_t (*now_ns)(const struct fv_clock *clock);
    /** Block until the clock reaches t_ns (a simulated clock jumps there instead). */
    void (*sleep_until_ns)(const struct fv_clock *clock, int64_t t_ns);
    int64_t sim_now_ns; /* used by the simulated clock only */
} fv_clock;

/** The OS monotonic clock (CLOCK_MONOTONIC). A static object; never destroy. */
const fv_clock *fv_clock_monotonic(void);
/** A simulated clock starting at start_ns; sleep_until jumps forward, never back. */
void fv_clock_sim_init(fv_clock *clock, int64_t start_ns);
/** Advance a simulated clock by dt_ns (>= 0). */
void fv_clock_sim_advance(fv_clock *clock, int64_t dt_ns);

static inline int64_t fv_clock_now_ns(const fv_clock *c) { return c->now_ns(c); }

/** Read CLOCK_MONOTONIC directly, for measuring elapsed CPU time in tools and benchmarks only. */
int64_t fv_time_monotonic_ns(void);

#define FV_NS_PER_MS INT64_C(1000000)
#define FV_NS_PER_S INT64_C(1000000000)

#endif
