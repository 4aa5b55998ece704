/* @brief Monotonic and simulated clocks. */
#include "fv_clock.h"

#include <errno.h>
#include <time.h>

int64_t fv_time_monotonic_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * FV_NS_PER_S + ts.tv_nsec;
}

static int64_t mono_now(const fv_clock *c)
{
    (void)c;
    return fv_time_monotonic_ns();
}

static void mono_sleep_until(const fv_clock *c, int64_t t_ns)
{
    (void)c;
    struct timespec ts = {.tv_sec = (time_t)(t_ns / FV_NS_PER_S), .tv_nsec = (long)(t_ns % FV_NS_PER_S)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {
    }
}

static const fv_clock g_monotonic = {mono_now, mono_sleep_until, 0};

const fv_clock *fv_clock_monotonic(void) { return &g_monotonic; }

static int64_t sim_now(const fv_clock *c) { return c->sim_now_ns; }

static void sim_sleep_until(const fv_clock *c, int64_t t_ns)
{
    fv_clock *m = (fv_clock *)c; /* the simulated clock is owned by its caller, who passes it mutable */
    if (t_ns > m->sim_now_ns) m->sim_now_ns = t_ns;
}

void fv_clock_sim_init(fv_clock *clock, int64_t start_ns)
{
    clock->now_ns = sim_now;
    clock->sleep_until_ns = sim_sleep_until;
    clock->sim_now_ns = start_ns;
}

void fv_clock_sim_advance(fv_clock *clock, int64_t dt_ns)
{
    if (dt_ns > 0) clock->sim_now_ns += dt_ns;
}
