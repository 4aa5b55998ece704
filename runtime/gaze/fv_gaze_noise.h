/* @brief Online estimate of a tracker's noise and rate, and the 1€ filter parameters that follow from them.
 * Noise: the sample-to-sample precision of eye-tracking practice (RMS of successive differences, Holmqvist,
 * Nyström & Mulvey, ETRA 2012), measured only during fixations: for white noise of SD σ per axis the successive
 * differences have variance 2σ², so σ = RMS-S2S / √2. Differences beyond 3 SD (microsaccades, a missed saccade onset)
 * are left out unless 8 come in a row (then they enter clipped at 3 SD: the noise rose); the running mean forgets
 * with a time constant of 2 s or 200 differences, whichever is longer.
 * Filter: for a fixation (a slow drift of speed v_d plus white noise σ, sampled every Δt) the exponential
 * smoother's mean squared error σ²α/(2−α) + (v_d Δt/α)² is least at α ≈ (2 v_d Δt/σ)^(2/3); that α is turned into
 * the 1€ minimum cutoff f_cmin = α / ((1−α) 2π Δt). β: the 1€ lag at speed |ẋ| tends to 1/(2πβ) degrees, so
 * β = 1/(2π k σ) keeps the lag of fast movements at k noise SDs. */
#ifndef FV_GAZE_NOISE_H
#define FV_GAZE_NOISE_H

#include <stdbool.h>
#include <stdint.h>

#define FV_GAZE_NOISE_MIN_DIFFS 16 /* successive differences needed before an estimate is reported */

typedef struct fv_gaze_noise {
    double ms_diff;   /* running mean of the squared successive difference, per axis, deg^2 */
    double dt_s;      /* running sample interval, s (0 before one) */
    uint32_t diffs;   /* differences used so far (saturates) */
    uint32_t outliers; /* consecutive differences beyond 3 SD left out */
    bool have_prev;
    int64_t t_prev_ns;
    double prev[2];
} fv_gaze_noise;

void fv_gaze_noise_init(fv_gaze_noise *n);
/** One valid sample (yaw, pitch deg) at t_ns. fixating: the sample belongs to a fixation (only those measure the
 *  noise; every sample measures the rate). A time that does not advance or a non-finite angle is ignored. */
void fv_gaze_noise_push(fv_gaze_noise *n, int64_t t_ns, const double pos_deg[2], bool fixating);
/** Break the chain of successive samples (a gap, a saccade): the next sample starts a new difference. */
void fv_gaze_noise_break(fv_gaze_noise *n);
/** Noise SD per axis in degrees; NaN before FV_GAZE_NOISE_MIN_DIFFS differences. */
double fv_gaze_noise_sigma_deg(const fv_gaze_noise *n);
/** Sample rate in Hz; 0 before two samples. */
double fv_gaze_noise_rate_hz(const fv_gaze_noise *n);
/** The 1€ parameters for noise sigma_deg (> 0) at rate_hz (> 0): see the file comment. Finite for any input
 *  (non-finite or non-positive arguments give the defaults 1 Hz and 0.3/deg); f_cmin in [0.05, 30] Hz, β in
 *  [0.005, 20]/deg. */
void fv_gaze_noise_filter_params(double sigma_deg, double rate_hz, float *out_min_cutoff_hz, float *out_beta);

#endif
