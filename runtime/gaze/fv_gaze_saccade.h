/* @brief Saccade kinematics: the main sequence (peak velocity and duration vs amplitude) and a landing-point fit
 * for a saccade under way. The main sequence is the saturating exponential of Baloh et al. (1975),
 * Vp = Vmax (1 − e^(−A/C)); the velocity profile is minimum-jerk (Flash & Hogan 1985), whose peak is 1.875 A/D,
 * so the duration is D = 1.875 A / Vp — with the defaults this stays within ~30% of Carpenter's (1988)
 * D ≈ 21 ms + 2.2 ms/deg · A for 1–40 deg. */
#ifndef FV_GAZE_SACCADE_H
#define FV_GAZE_SACCADE_H

#include <stdbool.h>

typedef struct fv_gaze_main_sequence {
    float vmax_deg_s; /* asymptotic peak velocity; 0 = 600 deg/s */
    float c_deg;      /* amplitude constant; 0 = 9 deg */
} fv_gaze_main_sequence;

/** Peak angular velocity (deg/s) of a saccade of amplitude_deg (>= 0). Finite for any input. */
double fv_gaze_main_sequence_peak_deg_s(const fv_gaze_main_sequence *ms, double amplitude_deg);
/** Duration (s) of a saccade of amplitude_deg on the main sequence with a minimum-jerk profile; > 0. */
double fv_gaze_main_sequence_duration_s(const fv_gaze_main_sequence *ms, double amplitude_deg);
/** Minimum-jerk position fraction at normalised time u (clamped to [0,1]): 10u^3 − 15u^4 + 6u^5. */
double fv_gaze_minjerk(double u);
/** Inverse of fv_gaze_minjerk on [0,1] (fraction clamped). */
double fv_gaze_minjerk_inverse(double fraction);

typedef struct fv_gaze_saccade_fit {
    double amplitude_deg; /* fitted total amplitude */
    double t_onset_s;     /* onset time relative to the newest sample (<= 0) */
    double duration_s;    /* main-sequence duration for the amplitude */
    double rms_deg;       /* RMS residual of the fit */
} fv_gaze_saccade_fit;

/** Fit a main-sequence minimum-jerk saccade to n displacement samples d_deg (along the saccade direction, from
 *  the start point) at times t_s (relative to the newest sample, ascending, the last one 0). The phase is pinned
 *  by the newest displacement; the amplitude (MAP: residual with 0.25 deg noise, log-normal priors on the amplitude, median 7 deg, and on a duration factor)
 *  is searched on a log grid and refined. false when n < 2 or nothing
 *  fits (non-finite input). */
bool fv_gaze_saccade_fit_landing(const fv_gaze_main_sequence *ms, const double *t_s, const double *d_deg, int n,
                                 fv_gaze_saccade_fit *out);

#endif
