/* @brief The frame budget of a run (`fovea run --budget auto`, the OpenXR runtime's frames): the controller
 * (runtime/budget) over the knob ladder (fv_app_ladder.h) from the run's own quality, fed one measured frame time at
 * a time. Each change is one line at the default log level (a warning: the frames were over budget, or there is
 * slack again) and one entry of a bounded log for the summary. One owner thread. */
#ifndef FV_APP_BUDGET_H
#define FV_APP_BUDGET_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_app_ladder.h"
#include "fv_budget.h"

#define FV_APP_BUDGET_LOG_MAX 256

typedef struct fv_app_budget_change {
    uint64_t frame;   /* the frame drawn next with the new level */
    uint32_t level;
    bool down;
    double gpu_ms;    /* the frame time that made the change */
} fv_app_budget_change;

typedef struct fv_app_budget {
    bool on;
    const char *who;               /* log module ("run", "xr") */
    double hz, scale;              /* the refresh rate budgeted for, and --budget-scale (1 = none) */
    fv_budget ctl;
    fv_quality base;               /* level 0: the run's own quality */
    const char *preset;
    fv_app_rung rungs[FV_APP_LADDER_MAX];
    size_t rung_count;
    fv_app_budget_change log[FV_APP_BUDGET_LOG_MAX];
    size_t log_n;
    uint64_t changes;
} fv_app_budget;

/** Start a budget for frames of `base` (preset name `preset`, from fv_quality_preset_name) at `hz` x `scale` (scale
 *  <= 0 means 1); the passes in off_passes (NULL-terminated ids, may be NULL) get no rungs. FV_ERR_INVALID_ARG (one
 *  line naming the period) when that period cannot be budgeted. */
FV_MUST_CHECK fv_result fv_app_budget_start(fv_app_budget *b, const char *who, const fv_quality *base,
                                            const char *preset, double hz, double scale,
                                            const char *const *off_passes);

/** Keep only the rungs of the knobs named (NULL-terminated): a program that uses only some knobs (the OpenXR
 *  runtime: foveation's MAR model) budgets with those. Restarts the controller at level 0. */
FV_MUST_CHECK fv_result fv_app_budget_keep_knobs(fv_app_budget *b, const char *const *names);

/** One finished frame's time (ms; non-finite counts as 0). On a change: logs it (one line), records it (frame_next:
 *  the frame that will be drawn with it) and sets *q to the base with the new level's rungs, keeping *q's view
 *  settings (exposure, view, overlay) and lens. Returns the step. No-op (KEEP) when the budget is off. */
fv_budget_step fv_app_budget_push(fv_app_budget *b, uint64_t frame_next, double frame_ms, fv_quality *q);

/** The frame time the budget allows, ms (0 when off). */
double fv_app_budget_target_ms(const fv_app_budget *b);

#endif
