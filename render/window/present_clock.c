/* @brief The swapchain's display clock (see fv_present_clock.h). */
#include "fv_present_clock.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"

#define MOD "display"
#define MIN_PERIOD_NS 1000000.0    /* 1000 Hz */
#define MAX_PERIOD_NS 1000000000.0 /* 1 Hz */
#define MAX_MULTIPLE 8.0           /* an interval longer than 8 periods says nothing about the period */
#define FOLD_TOLERANCE 0.2         /* an interval within 20% of a whole number of periods counts */
#define MIN_INTERVALS_UNSEEDED 8
#define MAX_MEASURED_PERIOD_NS 50000000.0 /* 20 Hz: the slowest refresh a measurement may claim */   /* overruling the nominal rate takes this many intervals */

const char *fv_present_clock_source_str(fv_present_clock_source s)
{
    return s == FV_PRESENT_CLOCK_DISPLAY_TIMING ? "VK_GOOGLE_display_timing"
                                                : "host timestamps (acquire/present cadence)";
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

static double clamp_period(double p)
{
    if (!isfinite(p)) return 1e9 / 60.0;
    return p < MIN_PERIOD_NS ? MIN_PERIOD_NS : p > MAX_PERIOD_NS ? MAX_PERIOD_NS : p;
}

/* The period from intervals that are whole multiples of it: a seed (nominal, else the smallest interval that is not
 * an outlier), then the mean of interval / round(interval / seed) over the intervals within FOLD_TOLERANCE of a
 * whole multiple. 0 when nothing fits. */
static double period_from(const int64_t *in, uint32_t n, double seed, uint32_t *out_used)
{
    *out_used = 0;
    if (n == 0) return 0.0;
    int64_t s[FV_PRESENT_CLOCK_WINDOW];
    memcpy(s, in, n * sizeof *s);
    qsort(s, n, sizeof *s, cmp_i64);
    if (!(seed > 0.0)) seed = (double)s[n / 4]; /* lower quartile: robust to a few short outliers */
    if (!(seed >= MIN_PERIOD_NS / 2)) return 0.0;
    double sum = 0.0;
    uint32_t used = 0;
    for (uint32_t i = 0; i < n; i++) {
        double k = round((double)s[i] / seed);
        if (k < 1.0 || k > MAX_MULTIPLE) continue;
        double per = (double)s[i] / k;
        if (fabs(per / seed - 1.0) > FOLD_TOLERANCE / k) continue;
        sum += per;
        used++;
    }
    *out_used = used;
    return used ? sum / (double)used : 0.0;
}

static void set_period(fv_present_clock *c, double p)
{
    c->period_exact_ns = clamp_period(p);
    c->base.period_ns = (int64_t)llround(c->period_exact_ns);
    c->base.refresh_hz = 1e9 / c->period_exact_ns;
}

/* The nominal period seeds the estimate; when fewer than half the intervals fit it (the display is not what it
 * claimed), the intervals alone decide. */
static void update_period(fv_present_clock *c)
{
    uint32_t used = 0;
    double p = period_from(c->intervals, c->interval_count, (double)c->nominal_period_ns, &used);
    if (c->nominal_period_ns > 0 && 2 * used < c->interval_count) {
        p = 0.0;
        if (c->interval_count >= MIN_INTERVALS_UNSEEDED) p = period_from(c->intervals, c->interval_count, 0.0, &used);
    }
    /* A "display" slower than 20 Hz is a renderer that blocked the acquire (a software presenter copying the image,
     * a loaded machine), not a refresh: the evidence is not taken. */
    if (p > 0.0 && used > 0 && p <= MAX_MEASURED_PERIOD_NS) {
        set_period(c, p);
        c->period_measured = true;
    }
}

void fv_present_clock_vsync(fv_present_clock *c, int64_t t_ns)
{
    if (t_ns <= c->anchor_ns) return; /* not newer than what the grid already knows */
    int64_t dt = t_ns - c->anchor_ns;
    /* Intervals between events (the first one's anchor is the creation time, not a vsync); a gap of more than
     * MAX_MULTIPLE periods (a pause, a suspended machine) moves the grid but says nothing about the period. */
    if (c->vsync_events > 0 && (double)dt <= MAX_MULTIPLE * c->period_exact_ns * (1.0 + FOLD_TOLERANCE)) {
        c->intervals[c->interval_next] = dt;
        c->interval_next = (c->interval_next + 1) % FV_PRESENT_CLOCK_WINDOW;
        if (c->interval_count < FV_PRESENT_CLOCK_WINDOW) c->interval_count++;
        update_period(c);
    }
    /* Whole periods since the anchor (at least one: the event is later than the anchor). */
    double k = round((double)dt / c->period_exact_ns);
    if (k < 1.0) k = 1.0;
    if (k > 1e12) k = 1e12;
    c->anchor_index += (uint64_t)k;
    c->anchor_ns = t_ns;
    c->vsync_events++;
}

static fv_result pc_vsync_at_or_after(fv_display *d, int64_t t_ns_min, fv_vsync *out)
{
    fv_present_clock *c = (fv_present_clock *)d;
    if (!out) return FV_ERR_INVALID_ARG;
    double ahead = (double)t_ns_min - (double)c->anchor_ns;
    double k = ceil(ahead / c->period_exact_ns);
    if (!isfinite(k) || ahead > 2.3e18) { /* ~73 years: refuse rather than let vsync times overflow */
        FV_ERROR(MOD, "time %lld ns is beyond the swapchain clock's timeline", (long long)t_ns_min);
        return FV_ERR_RANGE;
    }
    if (k < -(double)c->anchor_index) k = -(double)c->anchor_index; /* never before vsync 0 */
    int64_t t = c->anchor_ns + (int64_t)llround(k * c->period_exact_ns);
    if (t < t_ns_min && k >= 0) { /* rounding: one more period */
        k += 1.0;
        t = c->anchor_ns + (int64_t)llround(k * c->period_exact_ns);
    }
    out->index = (uint64_t)((int64_t)c->anchor_index + (int64_t)k);
    out->t_ns = t;
    return FV_OK;
}

/* A desktop panel scans out top to bottom over about a period: its middle row lights half a period after the
 * vsync (persistence unknown: counted as 0). */
static int64_t pc_photon_ns(fv_display *d, const fv_vsync *v)
{
    fv_present_clock *c = (fv_present_clock *)d;
    return v->t_ns + (int64_t)llround(c->period_exact_ns / 2.0);
}

static fv_result pc_present(fv_display *d, int64_t t_present_ns, uint64_t target_index, fv_vsync *out_shown)
{
    fv_present_clock *c = (fv_present_clock *)d;
    if (!out_shown) return FV_ERR_INVALID_ARG;
    c->presents++;
    if (t_present_ns > INT64_MAX - c->base.present_margin_ns) return FV_ERR_RANGE;
    /* The swapchain has no target time: a frame is shown at the first vsync after it reached the swapchain (its
     * latch), earlier than the loop's target when it was early, later when it missed it. */
    (void)target_index;
    fv_vsync first;
    FV_TRY(pc_vsync_at_or_after(d, t_present_ns + c->base.present_margin_ns, &first));
    *out_shown = first;
    return FV_OK;
}

static void pc_destroy(fv_display *d) { (void)d; /* embedded in its presenter, which frees it */ }

static const fv_display_ops g_present_clock_ops = {
    .vsync_at_or_after = pc_vsync_at_or_after,
    .photon_ns = pc_photon_ns,
    .present = pc_present,
    .destroy = pc_destroy,
};

void fv_present_clock_init(fv_present_clock *c, fv_present_clock_source source, double nominal_hz, int64_t t0_ns)
{
    memset(c, 0, sizeof *c);
    c->base.ops = &g_present_clock_ops;
    c->base.present_margin_ns = 500000; /* 0.5 ms: the compositor's latch */
    c->source = source;
    bool known = isfinite(nominal_hz) && nominal_hz >= 1.0 && nominal_hz <= 1000.0;
    c->nominal_period_ns = known ? (int64_t)llround(1e9 / nominal_hz) : 0;
    set_period(c, known ? 1e9 / nominal_hz : 1e9 / 60.0);
    c->anchor_ns = t0_ns;
}
