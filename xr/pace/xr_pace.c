/* @brief The refresh divisor (see fv_xr_pace.h). */
#include "fv_xr_pace.h"

#include <math.h>

void fv_xr_pace_window_add(fv_xr_pace_window *w, double ms)
{
    if (!isfinite(ms) || ms < 0) return;
    w->ms[w->next] = ms;
    w->next = (w->next + 1) % FV_XR_PACE_WINDOW;
    if (w->count < FV_XR_PACE_WINDOW) w->count++;
}

bool fv_xr_pace_window_need(const fv_xr_pace_window *w, double *out_ms)
{
    if (w->count < FV_XR_PACE_MIN_FRAMES || w->count > FV_XR_PACE_WINDOW) return false;
    double v[FV_XR_PACE_WINDOW];
    for (uint32_t i = 0; i < w->count; i++) { /* insertion sort: 16 values */
        double x = w->ms[i];
        uint32_t j = i;
        for (; j > 0 && v[j - 1] > x; j--) v[j] = v[j - 1];
        v[j] = x;
    }
    *out_ms = v[(w->count * 3) / 4];
    return true;
}

/* The smallest k in 1..MAX with need_ms <= share * k * refresh_ms. */
static uint32_t holding(double need_ms, double share, double refresh_ms)
{
    double k = ceil(need_ms / (share * refresh_ms));
    return !(k >= 1.0) ? 1u : k >= (double)FV_XR_PACE_MAX ? FV_XR_PACE_MAX : (uint32_t)k;
}

uint32_t fv_xr_pace_divisor(uint32_t k, double need_ms, double refresh_ms)
{
    if (k < 1 || k > FV_XR_PACE_MAX) k = 1;
    if (!(refresh_ms > 0) || !isfinite(refresh_ms) || !isfinite(need_ms)) return 1;
    uint32_t up = holding(need_ms, 1.0, refresh_ms);
    if (up > k) return up;
    uint32_t down = holding(need_ms, FV_XR_PACE_HEADROOM, refresh_ms);
    return down < k ? down : k;
}
