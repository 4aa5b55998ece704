/* @brief The frame-budget controller (runtime/budget): from each frame's GPU time and the display's refresh period it
 * picks a level on an ordered ladder of quality reductions (level 0 = the run's own quality, level n = all n rungs
 * applied). It steps down one rung when the recent frames use more than their share of the period, and back up with
 * hysteresis: only after a run of frames with slack, only when the cost measured at the better level predicts that
 * it fits, and with a hold that doubles each time a step up had to be taken back (so an oscillating cost cannot make
 * the quality oscillate). Pure and deterministic: no clock, no allocation, no knowledge of what a rung changes (the
 * ladder is built from the knob table above it, in runtime/app (fv_app_budget.h), and passed in as a count). One owner. */
#ifndef FV_BUDGET_H
#define FV_BUDGET_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_result.h"

#define FV_BUDGET_MAX_RUNGS 64
#define FV_BUDGET_MAX_WINDOW 64

/** Zero means the default (fv_budget_init applies them). */
typedef struct fv_budget_desc {
    int64_t period_ns;   /* the display's refresh period (required, > 0) */
    uint32_t rungs;      /* ladder length: levels 0..rungs (required, <= FV_BUDGET_MAX_RUNGS) */
    float target;        /* share of the period the GPU may use, (0, 1]; default 0.9 */
    float up_margin;     /* step up only when the better level is predicted under up_margin x target; default 0.85 */
    uint32_t window;     /* frames a decision looks at (mean), 2..FV_BUDGET_MAX_WINDOW; default 8 */
    uint32_t up_hold;    /* frames of slack before a step up, >= window; default 30 (doubles after each reversal) */
    uint32_t max_hold;   /* the longest hold after reversals; default 960 */
} fv_budget_desc;

/** What one frame did to the controller. */
typedef enum fv_budget_step {
    FV_BUDGET_KEEP = 0,
    FV_BUDGET_DOWN = 1, /* one more rung applied: cheaper, lower quality */
    FV_BUDGET_UP = 2,   /* one rung taken back: better quality */
} fv_budget_step;

typedef struct fv_budget {
    fv_budget_desc desc;
    uint32_t level;                      /* rungs applied now, 0..desc.rungs */
    int64_t window_ns[FV_BUDGET_MAX_WINDOW];
    uint32_t filled, head;               /* frames in the window since the last change */
    uint32_t slack_frames;               /* consecutive frames under the step-up threshold */
    uint32_t hold;                       /* the current step-up hold (desc.up_hold, doubled by reversals) */
    double ratio[FV_BUDGET_MAX_RUNGS + 1]; /* ratio[l]: level l-1's cost / level l's, measured around the last step
                                            * down to l (>= 1; 0 = never measured) */
    double down_from_ns;                 /* the window mean that made the last step down (0 after a step up) */
    bool fresh;                          /* the first full window since a change is still to come */
    bool last_was_up;                    /* the last change was a step up (a step down right after is a reversal) */
    uint64_t frames, misses;             /* frames pushed; frames whose GPU time exceeded the period */
    uint64_t downs, ups, reversals;      /* changes made; step-ups taken back by the next change */
} fv_budget;

/** Check desc, apply defaults, start at level 0. FV_ERR_INVALID_ARG (period <= 0, too many rungs, a window or a
 *  target out of range, a hold shorter than the window). */
FV_MUST_CHECK fv_result fv_budget_init(fv_budget *b, const fv_budget_desc *desc);

/** One finished frame's GPU time (ns; negative or absurd values count as 0 and as the period x 1000 at most).
 *  Returns whether the level changed; b->level is the level for the next frame. */
fv_budget_step fv_budget_push(fv_budget *b, int64_t gpu_ns);

/** The GPU time a frame may take (period x target), ns. */
int64_t fv_budget_target_ns(const fv_budget *b);

#endif
