/* @brief Device-to-host clock mapping by the lower envelope of host−device (see fv_gaze_clock.h). */
#include "fv_gaze_clock.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_BUCKET_NS (250 * INT64_C(1000000))
#define DEFAULT_BUCKETS 64
#define MAX_SKEW_NS_PER_S 1.0e6       /* 1000 ppm: beyond any crystal; clamp a degenerate fit */
#define JUMP_BACK_NS INT64_C(1000000000)  /* device time going back more than 1 s: the device clock restarted */
#define BELOW_ENVELOPE_NS 100.0e6     /* a point 100 ms under the envelope: the device clock jumped forward */

void fv_gaze_clock_map_init(fv_gaze_clock_map *m, int64_t bucket_ns, int nbuckets)
{
    memset(m, 0, sizeof *m);
    m->bucket_ns = bucket_ns > 0 ? bucket_ns : DEFAULT_BUCKET_NS;
    m->nbuckets = nbuckets > 0 && nbuckets <= FV_GAZE_CLOCK_MAX_BUCKETS ? nbuckets : DEFAULT_BUCKETS;
}

void fv_gaze_clock_map_reset(fv_gaze_clock_map *m)
{
    int64_t bucket_ns = m->bucket_ns;
    int nbuckets = m->nbuckets, resets = m->resets;
    fv_gaze_clock_map_init(m, bucket_ns, nbuckets);
    m->resets = resets;
}

static double cross(double ox, double oy, double ax, double ay, double bx, double by)
{
    return (ax - ox) * (by - oy) - (ay - oy) * (bx - ox);
}

/* Refit the line: lower hull of the minima (already sorted by x), then the hull edge spanning the mean x. */
static void refit(fv_gaze_clock_map *m)
{
    double xs[FV_GAZE_CLOCK_MAX_BUCKETS + 1], ys[FV_GAZE_CLOCK_MAX_BUCKETS + 1];
    int n = 0;
    for (int i = 0; i < m->count; i++) {
        int k = (m->head + i) % FV_GAZE_CLOCK_MAX_BUCKETS;
        xs[n] = m->px[k];
        ys[n] = m->py[k];
        n++;
    }
    if (m->cur_valid) {
        xs[n] = m->cur_x;
        ys[n] = m->cur_y;
        n++;
    }
    if (n == 0) return;
    double ymin = ys[0], xmean = 0.0;
    for (int i = 0; i < n; i++) {
        if (ys[i] < ymin) ymin = ys[i];
        xmean += xs[i];
    }
    xmean /= n;
    if (n < 3 || xs[n - 1] - xs[0] < 1.0) {
        /* Too short a span to see skew: offset only, from the lowest point. */
        m->a_ns = ymin;
        m->b_ns_per_s = 0.0;
        return;
    }
    int hull[FV_GAZE_CLOCK_MAX_BUCKETS + 1], h = 0;
    for (int i = 0; i < n; i++) {
        while (h >= 2 && cross(xs[hull[h - 2]], ys[hull[h - 2]], xs[hull[h - 1]], ys[hull[h - 1]], xs[i], ys[i]) <= 0.0)
            h--;
        hull[h++] = i;
    }
    double a = ymin, b = 0.0;
    for (int e = 0; e + 1 < h; e++) {
        double x1 = xs[hull[e]], y1 = ys[hull[e]], x2 = xs[hull[e + 1]], y2 = ys[hull[e + 1]];
        if (xmean >= x1 && xmean <= x2 && x2 > x1) {
            b = (y2 - y1) / (x2 - x1);
            a = y1 - b * x1;
            break;
        }
    }
    if (!(fabs(b) <= MAX_SKEW_NS_PER_S)) { /* also catches NaN */
        b = 0.0;
        a = ymin;
    }
    m->a_ns = a;
    m->b_ns_per_s = b;
}

static double fit_at(const fv_gaze_clock_map *m, double x) { return m->a_ns + m->b_ns_per_s * x; }

static void start(fv_gaze_clock_map *m, int64_t t_device_ns, int64_t t_host_ns)
{
    m->started = true;
    m->x0_dev_ns = t_device_ns;
    /* host − device, saturating: absurd inputs stay finite */
    double d = (double)t_host_ns - (double)t_device_ns;
    m->y0_ns = d > 9.0e18 ? INT64_C(9000000000000000000) : d < -9.0e18 ? -INT64_C(9000000000000000000)
                                                                       : (int64_t)d;
    m->last_dev_ns = t_device_ns;
    m->cur_valid = true;
    m->cur_start_dev_ns = t_device_ns;
    m->cur_x = 0.0;
    m->cur_y = d - (double)m->y0_ns;
    refit(m);
}

bool fv_gaze_clock_map_observe(fv_gaze_clock_map *m, int64_t t_device_ns, int64_t t_host_ns)
{
    if (!m->started) {
        start(m, t_device_ns, t_host_ns);
        return false;
    }
    double x = ((double)t_device_ns - (double)m->x0_dev_ns) * 1e-9;
    double y = (double)t_host_ns - (double)t_device_ns - (double)m->y0_ns;
    bool jumped_back = t_device_ns < m->last_dev_ns && (double)m->last_dev_ns - (double)t_device_ns > (double)JUMP_BACK_NS;
    bool below = y < fit_at(m, x) - BELOW_ENVELOPE_NS;
    if (jumped_back || below || !isfinite(x) || !isfinite(y)) {
        fv_gaze_clock_map_reset(m);
        m->resets++;
        start(m, t_device_ns, t_host_ns);
        return true;
    }
    if (t_device_ns > m->last_dev_ns) m->last_dev_ns = t_device_ns;
    bool changed = false;
    if ((double)t_device_ns - (double)m->cur_start_dev_ns >= (double)m->bucket_ns) {
        /* close the current bucket and open a new one */
        if (m->count == m->nbuckets) {
            m->head = (m->head + 1) % FV_GAZE_CLOCK_MAX_BUCKETS;
            m->count--;
        }
        int k = (m->head + m->count) % FV_GAZE_CLOCK_MAX_BUCKETS;
        m->px[k] = m->cur_x;
        m->py[k] = m->cur_y;
        m->count++;
        m->cur_start_dev_ns = t_device_ns;
        m->cur_x = x;
        m->cur_y = y;
        changed = true;
    } else if (y < m->cur_y) {
        m->cur_x = x;
        m->cur_y = y;
        changed = true;
    }
    if (changed) refit(m);
    return false;
}

bool fv_gaze_clock_map_to_host(const fv_gaze_clock_map *m, int64_t t_device_ns, int64_t *out_host_ns)
{
    if (!m->started) return false;
    double x = ((double)t_device_ns - (double)m->x0_dev_ns) * 1e-9;
    double host = (double)t_device_ns + (double)m->y0_ns + fit_at(m, x);
    if (!isfinite(host)) return false;
    if (host > 9.2e18) host = 9.2e18;
    if (host < -9.2e18) host = -9.2e18;
    /* Keep integer precision where it matters: add the offset to the integer device time. */
    double off = (double)m->y0_ns + fit_at(m, x);
    if (fabs(off) < 4.0e18 && llabs(t_device_ns) < INT64_C(4000000000000000000)) {
        *out_host_ns = t_device_ns + (int64_t)llround(off);
    } else {
        *out_host_ns = (int64_t)host;
    }
    return true;
}

double fv_gaze_clock_map_skew_ppm(const fv_gaze_clock_map *m) { return m->b_ns_per_s * 1e-3; }
