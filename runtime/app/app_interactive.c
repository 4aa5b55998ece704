/* @brief Where an interactive run starts on a software device (see fv_app_interactive.h). */
#include "fv_app_interactive.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void fv_app_interactive_start(const fv_app_interactive_in *in, fv_app_interactive *out)
{
    memset(out, 0, sizeof *out);
    out->eye_w = in->eye_w;
    out->eye_h = in->eye_h;
    if (!in->software || !in->interactive || in->size_given || in->budget_given || !in->eye_w || !in->eye_h ||
        !(in->hz > 0))
        return;
    double cores = in->cpu_cores ? (double)in->cpu_cores : 1.0;
    double pixels = FV_APP_SOFT_PIXELS_PER_CORE * cores / 2.0; /* per eye */
    double have = (double)in->eye_w * (double)in->eye_h;
    double k = have > pixels ? sqrt(pixels / have) : 1.0;
    uint32_t w = (uint32_t)(in->eye_w * k) & ~1u, h = (uint32_t)(in->eye_h * k) & ~1u;
    if (w < FV_APP_SOFT_MIN_SIDE) w = in->eye_w < FV_APP_SOFT_MIN_SIDE ? in->eye_w : FV_APP_SOFT_MIN_SIDE;
    if (h < FV_APP_SOFT_MIN_SIDE) h = in->eye_h < FV_APP_SOFT_MIN_SIDE ? in->eye_h : FV_APP_SOFT_MIN_SIDE;
    out->applied = true;
    out->eye_w = w;
    out->eye_h = h;
    out->budget = true;
    out->budget_scale = FV_APP_SOFT_FRAME_MS * 1e-3 * in->hz; /* the period: FV_APP_SOFT_FRAME_MS */
    snprintf(out->line, sizeof out->line,
             "a software Vulkan device (%u CPU cores): starting at %ux%u per eye with --budget auto for a %.0f ms "
             "frame, so that it stays interactive (override: --eye-size WxH, --budget off or --budget-scale X)",
             in->cpu_cores, w, h, FV_APP_SOFT_FRAME_MS);
}
