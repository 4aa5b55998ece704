/* @brief Main sequence and saccade landing fit (see fv_gaze_saccade.h). */
#include "fv_gaze_saccade.h"

#include <math.h>

#define MAX_AMPLITUDE_DEG 90.0
/* the landing search stops at 50 deg: larger gaze shifts are made with the head, not the eye alone */
#define MAX_FIT_AMPLITUDE_DEG 50.0
#define MIN_AMPLITUDE_DEG 0.05
/* Early in a saccade the amplitude is poorly determined (the accelerating phase of a large, slower saccade looks
 * like that of a smaller one), so the fit is a MAP estimate: the squared residual over an assumed measurement
 * noise, plus a weak log-normal prior on the amplitude. Natural saccades are mostly small (Bahill, Adler & Stark
 * 1975: most are 15 deg or less); the prior's median is 7 deg with a log-SD of 0.8 (a factor of 2.2). */
#define FIT_NOISE_DEG 0.25
#define PRIOR_MEDIAN_DEG 7.0
#define PRIOR_LOG_SD 0.8
/* Individual saccades scatter around the main sequence (peak velocity SD ~10%): the duration is fitted too, as a
 * factor on the main-sequence duration with a log-normal prior of SD 0.1. */
#define SPEED_LOG_SD 0.1
static const double g_dur_factors[] = {0.8, 0.9, 1.0, 1.1, 1.25};

static double vmax(const fv_gaze_main_sequence *ms)
{
    return ms && isfinite(ms->vmax_deg_s) && ms->vmax_deg_s > 0.0f ? ms->vmax_deg_s : 600.0;
}
static double cdeg(const fv_gaze_main_sequence *ms)
{
    return ms && isfinite(ms->c_deg) && ms->c_deg > 0.0f ? ms->c_deg : 9.0;
}

static double clamp_amp(double a)
{
    if (!(a >= MIN_AMPLITUDE_DEG)) return MIN_AMPLITUDE_DEG; /* also NaN */
    return a > MAX_AMPLITUDE_DEG ? MAX_AMPLITUDE_DEG : a;
}

/* Baloh, Sills, Kumley & Honrubia 1975: Vp = Vmax (1 - exp(-A / C)). */
double fv_gaze_main_sequence_peak_deg_s(const fv_gaze_main_sequence *ms, double amplitude_deg)
{
    return vmax(ms) * (1.0 - exp(-clamp_amp(amplitude_deg) / cdeg(ms)));
}

/* Minimum-jerk peak velocity is 1.875 A / D (Flash & Hogan 1985), so D = 1.875 A / Vp. */
double fv_gaze_main_sequence_duration_s(const fv_gaze_main_sequence *ms, double amplitude_deg)
{
    double a = clamp_amp(amplitude_deg);
    return 1.875 * a / fv_gaze_main_sequence_peak_deg_s(ms, a);
}

double fv_gaze_minjerk(double u)
{
    if (!(u > 0.0)) return 0.0;
    if (u >= 1.0) return 1.0;
    double u3 = u * u * u;
    return u3 * (10.0 + u * (-15.0 + 6.0 * u));
}

double fv_gaze_minjerk_inverse(double fraction)
{
    if (!(fraction > 0.0)) return 0.0;
    if (fraction >= 1.0) return 1.0;
    /* safeguarded Newton on a monotonic polynomial: bracket [lo, hi], fall back to bisection outside it */
    double lo = 0.0, hi = 1.0, u = fraction;
    for (int i = 0; i < 30; i++) {
        double f = fv_gaze_minjerk(u) - fraction;
        if (fabs(f) < 1e-12) break;
        if (f < 0.0) lo = u;
        else hi = u;
        double df = 30.0 * u * u * (1.0 - u) * (1.0 - u); /* d/du (10u^3 - 15u^4 + 6u^5) */
        double next = df > 1e-12 ? u - f / df : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (fabs(next - u) < 1e-12) {
            u = next;
            break;
        }
        u = next;
    }
    return u;
}

/* Sum of squared residuals of a minimum-jerk saccade of amplitude amp and duration dur whose phase is pinned by
 * the newest displacement (u_now). */
static double sq_residual(const double *t_s, const double *d_deg, int n, double amp, double dur, double u_now)
{
    double t0 = -u_now * dur, e = 0.0;
    for (int i = 0; i < n; i++) {
        double r = d_deg[i] - amp * fv_gaze_minjerk((t_s[i] - t0) / dur);
        e += r * r;
    }
    return e;
}

typedef struct candidate {
    double e, amp, dur, u_now;
    int k;
} candidate;

/* MAP cost of one amplitude for every duration factor; keeps the best in *best. */
static void try_amplitude(const fv_gaze_main_sequence *ms, const double *t_s, const double *d_deg, int n, double amp,
                          int k_only, candidate *best)
{
    enum { NK = sizeof g_dur_factors / sizeof g_dur_factors[0] };
    double base = fv_gaze_main_sequence_duration_s(ms, amp);
    double u_now = fv_gaze_minjerk_inverse(d_deg[n - 1] / amp);
    double za = log(amp / PRIOR_MEDIAN_DEG) / PRIOR_LOG_SD;
    for (int k = 0; k < NK; k++) {
        if (k_only >= 0 && k != k_only) continue;
        double zk = log(g_dur_factors[k]) / SPEED_LOG_SD;
        double dur = base * g_dur_factors[k];
        double e = sq_residual(t_s, d_deg, n, amp, dur, u_now) / (FIT_NOISE_DEG * FIT_NOISE_DEG) +
                   0.5 * (za * za + zk * zk);
        if (e < best->e) *best = (candidate){e, amp, dur, u_now, k};
    }
}

bool fv_gaze_saccade_fit_landing(const fv_gaze_main_sequence *ms, const double *t_s, const double *d_deg, int n,
                                 fv_gaze_saccade_fit *out)
{
    if (n < 2) return false;
    for (int i = 0; i < n; i++)
        if (!isfinite(t_s[i]) || !isfinite(d_deg[i])) return false;
    double d_now = d_deg[n - 1];
    double lo = clamp_amp(d_now > 0.0 ? d_now : MIN_AMPLITUDE_DEG);
    double hi = fmax(MAX_FIT_AMPLITUDE_DEG, lo * 1.001);
    enum { STEPS = 28 };
    double ratio = pow(hi / lo, 1.0 / (STEPS - 1));
    candidate best = {INFINITY, lo, 0.0, 0.0, 2};
    double amp = lo;
    int best_i = 0;
    for (int i = 0; i < STEPS; i++, amp *= ratio) {
        double before = best.e;
        try_amplitude(ms, t_s, d_deg, n, amp, -1, &best);
        if (best.e < before) best_i = i;
    }
    /* refine the amplitude between the neighbours of the best grid point, at the best duration factor */
    double a_lo = best_i > 0 ? best.amp / ratio : best.amp, a_hi = best_i < STEPS - 1 ? best.amp * ratio : best.amp;
    int k_best = best.k;
    for (int i = 0; i <= 12; i++) try_amplitude(ms, t_s, d_deg, n, a_lo * pow(a_hi / a_lo, i / 12.0), k_best, &best);
    if (!isfinite(best.e) || !(best.dur > 0.0)) return false;
    out->amplitude_deg = best.amp;
    out->t_onset_s = -best.u_now * best.dur;
    out->duration_s = best.dur;
    out->rms_deg = sqrt(sq_residual(t_s, d_deg, n, best.amp, best.dur, best.u_now) / n);
    return true;
}
