/* @brief 1€ filter on 2-D gaze angles (Casiez et al. 2012). */
#include "fv_gaze_filter.h"

#include <math.h>

#include "fv_math.h"

static float pick(float v, float dflt) { return isfinite(v) && v > 0.0f ? v : dflt; }

void fv_gaze_one_euro_init(fv_gaze_one_euro *f, float min_cutoff_hz, float beta, float d_cutoff_hz)
{
    f->min_cutoff_hz = pick(min_cutoff_hz, 1.0f);
    f->beta = pick(beta, 0.3f);
    f->d_cutoff_hz = pick(d_cutoff_hz, 1.0f);
    f->started = false;
    f->t_ns = 0;
    f->x[0] = f->x[1] = 0.0;
    f->dx[0] = f->dx[1] = 0.0;
}

void fv_gaze_one_euro_reset(fv_gaze_one_euro *f, int64_t t_ns, const double in_deg[2])
{
    f->started = isfinite(in_deg[0]) && isfinite(in_deg[1]);
    f->t_ns = t_ns;
    f->x[0] = f->started ? in_deg[0] : 0.0;
    f->x[1] = f->started ? in_deg[1] : 0.0;
    f->dx[0] = f->dx[1] = 0.0;
}

/* Casiez et al. 2012, eq. for the smoothing factor: alpha = 1 / (1 + tau/Te), tau = 1/(2 pi fc). */
static double alpha(double cutoff_hz, double dt_s)
{
    double tau = 1.0 / (2.0 * FV_PI * cutoff_hz);
    return 1.0 / (1.0 + tau / dt_s);
}

void fv_gaze_one_euro_push(fv_gaze_one_euro *f, int64_t t_ns, const double in_deg[2], double out_deg[2])
{
    bool finite = isfinite(in_deg[0]) && isfinite(in_deg[1]);
    if (!f->started) {
        if (finite) fv_gaze_one_euro_reset(f, t_ns, in_deg);
    } else if (finite && t_ns > f->t_ns) {
        double dt = ((double)t_ns - (double)f->t_ns) * 1e-9;
        if (dt > 1.0) {
            /* a gap this long says nothing about speed: restart */
            fv_gaze_one_euro_reset(f, t_ns, in_deg);
        } else {
            double ad = alpha(f->d_cutoff_hz, dt);
            for (int k = 0; k < 2; k++) {
                double rate = (in_deg[k] - f->x[k]) / dt;
                f->dx[k] += ad * (rate - f->dx[k]);
            }
            double speed = sqrt(f->dx[0] * f->dx[0] + f->dx[1] * f->dx[1]);
            double cutoff = f->min_cutoff_hz + f->beta * speed;
            if (!isfinite(cutoff) || cutoff > 1.0e6) cutoff = 1.0e6;
            double a = alpha(cutoff, dt);
            for (int k = 0; k < 2; k++) f->x[k] += a * (in_deg[k] - f->x[k]);
            f->t_ns = t_ns;
        }
    }
    out_deg[0] = f->x[0];
    out_deg[1] = f->x[1];
}
