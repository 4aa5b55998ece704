/* @brief The 1€ filter (Casiez, Roussel & Vogel, "1€ Filter: A Simple Speed-based Low-pass Filter for Noisy Input
 * in Interactive Systems", CHI 2012) on a 2-D gaze angle (yaw, pitch in degrees): an exponential low-pass whose
 * cutoff rises with the filtered speed, so fixations are smoothed and fast movements are followed with little lag.
 * Both axes share one cutoff, driven by the angular speed. */
#ifndef FV_GAZE_FILTER_H
#define FV_GAZE_FILTER_H

#include <stdbool.h>
#include <stdint.h>

/** Filter state; the caller embeds it. One owner; not thread-safe. */
typedef struct fv_gaze_one_euro {
    float min_cutoff_hz;   /* f_cmin: cutoff at zero speed */
    float beta;            /* cutoff gain per deg/s of speed (1/deg) */
    float d_cutoff_hz;     /* cutoff of the speed estimate */
    bool started;
    int64_t t_ns;          /* time of the last update */
    double x[2];           /* filtered angle, deg */
    double dx[2];          /* filtered rate, deg/s */
} fv_gaze_one_euro;

/** Defaults for zero/non-finite arguments: min_cutoff 1 Hz, beta 0.3/deg, d_cutoff 1 Hz. */
void fv_gaze_one_euro_init(fv_gaze_one_euro *f, float min_cutoff_hz, float beta, float d_cutoff_hz);
/** Restart at this value (the next push continues from it with zero rate). */
void fv_gaze_one_euro_reset(fv_gaze_one_euro *f, int64_t t_ns, const double in_deg[2]);
/** Filter one value at time t_ns; writes the filtered angle. A time that does not advance (dt <= 0) or a
 *  non-finite input leaves the state as it was. Output is always finite once started. */
void fv_gaze_one_euro_push(fv_gaze_one_euro *f, int64_t t_ns, const double in_deg[2], double out_deg[2]);

#endif
