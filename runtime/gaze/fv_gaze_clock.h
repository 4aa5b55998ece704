/* @brief Device-to-host clock mapping: estimates offset and skew between a tracker's clock and the host clock from
 * (device time, host receipt time) pairs. Receipt = capture + transport delay, and the delay is only ever positive,
 * so the estimator fits the lower envelope of host−device: per-bucket minima over a sliding window, then the line
 * under all of them that lies closest to them (the lower convex hull edge spanning their mean; Moon, Skelly &
 * Towsley, "Estimation and removal of clock skew from network delay measurements", INFOCOM 1999). The mapped time
 * is the device time on the host clock plus the smallest transport delay (which no passive method can see). */
#ifndef FV_GAZE_CLOCK_H
#define FV_GAZE_CLOCK_H

#include <stdbool.h>
#include <stdint.h>

#define FV_GAZE_CLOCK_MAX_BUCKETS 64

/** Clock mapper state; the caller embeds it. One owner; not thread-safe. */
typedef struct fv_gaze_clock_map {
    int64_t bucket_ns;     /* device-time span of one bucket (default 250 ms) */
    int nbuckets;          /* buckets in the window (default 64: 16 s) */
    bool started;
    int64_t x0_dev_ns;     /* device time of the first observation (x origin) */
    int64_t y0_ns;         /* host−device of the first observation (y origin) */
    int64_t last_dev_ns;
    /* completed bucket minima, oldest first in ring order: x in s since x0, y in ns relative to y0 */
    double px[FV_GAZE_CLOCK_MAX_BUCKETS], py[FV_GAZE_CLOCK_MAX_BUCKETS];
    int head, count;
    bool cur_valid;
    int64_t cur_start_dev_ns;
    double cur_x, cur_y;
    /* current fit: host − device − y0 = a_ns + b_ns_per_s * x_s */
    double a_ns, b_ns_per_s;
    int resets;            /* how many discontinuities restarted the estimate */
} fv_gaze_clock_map;

/** Defaults: 250 ms buckets, 16 s window. bucket_ns/nbuckets of 0 take the defaults; nbuckets <= 64. */
void fv_gaze_clock_map_init(fv_gaze_clock_map *m, int64_t bucket_ns, int nbuckets);
void fv_gaze_clock_map_reset(fv_gaze_clock_map *m);
/** Add one (device time, host receipt time) pair. Returns true when a discontinuity (device clock jumped back, or
 *  forward far below the envelope) restarted the estimate with this pair. */
bool fv_gaze_clock_map_observe(fv_gaze_clock_map *m, int64_t t_device_ns, int64_t t_host_ns);
/** Map a device time to the host clock; false (and *out untouched) before the first observation. */
bool fv_gaze_clock_map_to_host(const fv_gaze_clock_map *m, int64_t t_device_ns, int64_t *out_host_ns);
/** Current skew estimate in parts per million (host runs this much faster than the device). 0 before two buckets. */
double fv_gaze_clock_map_skew_ppm(const fv_gaze_clock_map *m);

#endif
