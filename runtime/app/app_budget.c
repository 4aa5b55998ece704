/* @brief The frame budget of a run (see fv_app_budget.h). */
#include "fv_app_budget.h"

#include <math.h>
#include <string.h>

#include "fv_log.h"

fv_result fv_app_budget_start(fv_app_budget *b, const char *who, const fv_quality *base, const char *preset,
                              double hz, double scale, const char *const *off_passes)
{
    memset(b, 0, sizeof *b);
    b->who = who ? who : "budget";
    b->base = *base;
    b->preset = preset;
    b->hz = hz;
    b->scale = scale > 0 ? scale : 1.0;
    b->rung_count = fv_app_ladder_build_for(base, preset, off_passes, b->rungs, FV_APP_LADDER_MAX);
    double period_ns = hz > 0 ? 1e9 / hz * b->scale : 0.0;
    fv_budget_desc d = {.period_ns = isfinite(period_ns) && period_ns < 9e18 ? (int64_t)period_ns : 0,
                        .rungs = (uint32_t)b->rung_count};
    if (fv_budget_init(&b->ctl, &d) != FV_OK) {
        FV_ERROR(b->who, "budget: a period of %g ms (%g Hz x %g) cannot be budgeted", period_ns / 1e6, hz, b->scale);
        return FV_ERR_INVALID_ARG;
    }
    b->on = true;
    FV_INFO(b->who, "budget: %.3f ms per frame (%g Hz%s), %zu rung%s from %s towards fast",
            fv_budget_target_ns(&b->ctl) / 1e6, hz, b->scale != 1.0 ? ", scaled" : "", b->rung_count,
            b->rung_count == 1 ? "" : "s", preset);
    return FV_OK;
}

fv_result fv_app_budget_keep_knobs(fv_app_budget *b, const char *const *names)
{
    size_t n = 0;
    for (size_t i = 0; i < b->rung_count; i++) {
        bool keep = false;
        for (size_t k = 0; names && names[k] && !keep; k++) keep = !strcmp(b->rungs[i].knob->name, names[k]);
        if (keep) b->rungs[n++] = b->rungs[i];
    }
    b->rung_count = n;
    fv_budget_desc d = b->ctl.desc;
    d.rungs = (uint32_t)n;
    return fv_budget_init(&b->ctl, &d);
}

double fv_app_budget_target_ms(const fv_app_budget *b) { return b->on ? fv_budget_target_ns(&b->ctl) / 1e6 : 0.0; }

fv_budget_step fv_app_budget_push(fv_app_budget *b, uint64_t frame_next, double ms, fv_quality *q)
{
    if (!b->on) return FV_BUDGET_KEEP;
    fv_budget_step s = fv_budget_push(&b->ctl, isfinite(ms) ? (int64_t)(ms * 1e6) : 0);
    if (s == FV_BUDGET_KEEP) return s;
    b->changes++;
    bool down = s == FV_BUDGET_DOWN;
    if (b->log_n < FV_APP_BUDGET_LOG_MAX)
        b->log[b->log_n++] = (fv_app_budget_change){.frame = frame_next, .level = b->ctl.level, .down = down,
                                                    .gpu_ms = ms};
    const char *rung = b->rungs[down ? b->ctl.level - 1 : b->ctl.level].text;
    /* the default level: a user asked for a budget and sees each change it makes (one line each) */
    FV_WARN(b->who, "budget: frame %llu: %s to level %u/%zu (%s %s; frame %.2f ms, budget %.2f ms)",
            (unsigned long long)frame_next, down ? "down" : "up", b->ctl.level, b->rung_count,
            down ? "applied" : "took back", rung, ms, fv_budget_target_ns(&b->ctl) / 1e6);
    fv_quality next;
    fv_app_ladder_apply(&b->base, b->rungs, b->ctl.level, &next);
    /* the view settings and the lens are the run's, whatever the ladder did */
    next.exposure = q->exposure;
    next.debug_view = q->debug_view;
    next.overlay = q->overlay;
    next.distort.lens = q->distort.lens;
    *q = next;
    return s;
}
