/* @brief The frame-budget controller (see fv_budget.h). */
#include <math.h>
#include <string.h>

#include "fv_budget.h"

fv_result fv_budget_init(fv_budget *b, const fv_budget_desc *desc)
{
    if (!b || !desc) return FV_ERR_INVALID_ARG;
    fv_budget_desc d = *desc;
    if (d.target == 0.0f) d.target = 0.9f;
    if (d.up_margin == 0.0f) d.up_margin = 0.85f;
    if (d.window == 0) d.window = 8;
    if (d.up_hold == 0) d.up_hold = 30;
    if (d.max_hold == 0) d.max_hold = 960;
    if (d.period_ns <= 0 || d.rungs > FV_BUDGET_MAX_RUNGS || !(d.target > 0.0f && d.target <= 1.0f) ||
        !(d.up_margin > 0.0f && d.up_margin < 1.0f) || d.window < 2 || d.window > FV_BUDGET_MAX_WINDOW ||
        d.up_hold < d.window || d.max_hold < d.up_hold)
        return FV_ERR_INVALID_ARG;
    memset(b, 0, sizeof *b);
    b->desc = d;
    b->hold = d.up_hold;
    return FV_OK;
}

int64_t fv_budget_target_ns(const fv_budget *b) { return (int64_t)((double)b->desc.period_ns * b->desc.target); }

static double window_mean(const fv_budget *b)
{
    double s = 0.0;
    for (uint32_t i = 0; i < b->filled; i++) s += (double)b->window_ns[i];
    return b->filled ? s / b->filled : 0.0;
}

static void changed(fv_budget *b, bool up, double mean)
{
    b->filled = b->head = 0;
    b->slack_frames = 0;
    b->fresh = true;
    b->down_from_ns = up ? 0.0 : mean;
    if (up) b->ups++;
    else b->downs++;
    if (!up && b->last_was_up) {
        /* The step up did not hold: wait twice as long for slack before the next one. */
        b->reversals++;
        b->hold = b->hold * 2 > b->desc.max_hold ? b->desc.max_hold : b->hold * 2;
    }
    b->last_was_up = up;
}

fv_budget_step fv_budget_push(fv_budget *b, int64_t gpu_ns)
{
    const fv_budget_desc *d = &b->desc;
    int64_t cap = d->period_ns > INT64_MAX / 1000 ? INT64_MAX : d->period_ns * 1000;
    if (gpu_ns < 0) gpu_ns = 0;
    if (gpu_ns > cap) gpu_ns = cap;
    b->frames++;
    if (gpu_ns > d->period_ns) b->misses++;
    b->window_ns[b->head] = gpu_ns;
    b->head = (b->head + 1) % d->window;
    if (b->filled < d->window) b->filled++;

    double target = (double)fv_budget_target_ns(b);
    double up_under = target * d->up_margin;
    /* Slack is counted per frame, from the frame's own time, so one slow frame restarts the run. */
    b->slack_frames = (double)gpu_ns < up_under ? b->slack_frames + 1 : 0;
    /* A decision needs a full window measured at this level. */
    if (b->filled < d->window) return FV_BUDGET_KEEP;
    double mean = window_mean(b);
    if (b->fresh) {
        /* The first window at a level reached by a step down: what that rung saved, measured back to back (a
         * better level never costs less, so at least 1). */
        if (b->down_from_ns > 0.0 && mean > 0.0) b->ratio[b->level] = fmax(1.0, b->down_from_ns / mean);
        b->fresh = false;
    }

    if (mean > target && b->level < d->rungs) {
        b->level++;
        changed(b, false, mean);
        return FV_BUDGET_DOWN;
    }
    if (b->level > 0 && b->slack_frames >= b->hold) {
        /* Predict the better level's cost from what the rung saved when it was taken (a scene that got cheaper
         * overall keeps that ratio); never measured: assume it fits and let the next window tell. */
        double r = b->ratio[b->level];
        double predicted = r > 0.0 ? mean * r : 0.0;
        if (predicted < up_under) {
            b->level--;
            changed(b, true, mean);
            return FV_BUDGET_UP;
        }
    }
    return FV_BUDGET_KEEP;
}
