/* @brief Online tracker noise and rate, and the 1€ parameters derived from them (see fv_gaze_noise.h). */
#include "fv_gaze_noise.h"

#include <math.h>
#include <string.h>

#include "fv_math.h"

#define MEMORY_S 2.0          /* the running means forget with this time constant */
#define MEMORY_MIN_DIFFS 200.0 /* ... or over this many differences, whichever is longer */
#define CLIP_SD2 9.0          /* squared differences are clipped at 3 SD (9 x the mean square) */
#define MAX_DT_FACTOR 3.0     /* a difference over a longer interval than 3 x the rate's is not successive */
#define MAX_OUTLIER_RUN 8      /* this many outliers in a row: the noise rose */
#define FIRST_MAX_DT_S 0.05   /* ... and before the rate is known, over 50 ms */
#define DRIFT_DEG_S 1.0       /* v_d: the slow movement a fixation filter must still follow */
#define LAG_NOISE_SDS 2.0     /* k: the lag of fast movements, in noise SDs */

void fv_gaze_noise_init(fv_gaze_noise *n) { memset(n, 0, sizeof *n); }

void fv_gaze_noise_break(fv_gaze_noise *n) { n->have_prev = false; }

void fv_gaze_noise_push(fv_gaze_noise *n, int64_t t_ns, const double pos[2], bool fixating)
{
    if (!isfinite(pos[0]) || !isfinite(pos[1])) return;
    if (n->have_prev && t_ns <= n->t_prev_ns) return;
    if (n->have_prev) {
        double dt = ((double)t_ns - (double)n->t_prev_ns) * 1e-9;
        double limit = n->dt_s > 0.0 ? MAX_DT_FACTOR * n->dt_s : FIRST_MAX_DT_S;
        if (dt <= 0.25) { /* the rate: every interval of a stream that is not a hole */
            if (n->dt_s <= 0.0) n->dt_s = dt;
            else if (dt <= limit) n->dt_s += fmin(1.0, dt / MEMORY_S * 4.0) * (dt - n->dt_s);
        }
        if (fixating && dt <= limit) {
            double dx = pos[0] - n->prev[0], dy = pos[1] - n->prev[1];
            double q = 0.5 * (dx * dx + dy * dy);
            if (n->diffs >= FV_GAZE_NOISE_MIN_DIFFS && q > CLIP_SD2 * n->ms_diff) {
                /* an outlier (a microsaccade, a missed onset) is left out; a run of them means the noise rose:
                 * then they enter, clipped */
                if (++n->outliers < MAX_OUTLIER_RUN) goto keep;
                q = CLIP_SD2 * n->ms_diff;
            }
            n->outliers = 0;
            double w = fmax(1.0 / ((double)n->diffs + 1.0), fmin(1.0 / MEMORY_MIN_DIFFS, dt / MEMORY_S));
            if (isfinite(q)) {
                n->ms_diff += w * (q - n->ms_diff);
                if (n->diffs < UINT32_MAX) n->diffs++;
            }
        }
    }
keep:
    n->have_prev = true;
    n->t_prev_ns = t_ns;
    n->prev[0] = pos[0];
    n->prev[1] = pos[1];
}

double fv_gaze_noise_sigma_deg(const fv_gaze_noise *n)
{
    if (n->diffs < FV_GAZE_NOISE_MIN_DIFFS) return NAN;
    return sqrt(fmax(0.0, n->ms_diff) / 2.0);
}

double fv_gaze_noise_rate_hz(const fv_gaze_noise *n) { return n->dt_s > 0.0 ? 1.0 / n->dt_s : 0.0; }

void fv_gaze_noise_filter_params(double sigma_deg, double rate_hz, float *out_min_cutoff_hz, float *out_beta)
{
    if (!(sigma_deg > 0.0) || !isfinite(sigma_deg) || !(rate_hz > 0.0) || !isfinite(rate_hz)) {
        *out_min_cutoff_hz = 1.0f;
        *out_beta = 0.3f;
        return;
    }
    double sigma = fmax(sigma_deg, 1e-3), dt = 1.0 / fmin(fmax(rate_hz, 1.0), 1e5);
    double alpha = pow(2.0 * DRIFT_DEG_S * dt / sigma, 2.0 / 3.0);
    alpha = fmin(0.9, fmax(1e-3, alpha));
    double fc = alpha / ((1.0 - alpha) * 2.0 * FV_PI * dt);
    double beta = 1.0 / (2.0 * FV_PI * LAG_NOISE_SDS * sigma);
    *out_min_cutoff_hz = (float)fmin(30.0, fmax(0.05, fc));
    *out_beta = (float)fmin(20.0, fmax(0.005, beta));
}
