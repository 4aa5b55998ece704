/* @brief `fovea run --hmd PROFILE|FILE|none` and `--budget auto|off [--budget-scale X]`: the HMD profile (runtime/hmd)
 * whose lens the frames are pre-distorted and masked for, whose field of view the eye frusta take when it is named,
 * and whose refresh rate is the frame budget; and the frame-budget controller (runtime/budget) stepping the knob
 * ladder (run_ladder.h) from the measured GPU times. The pieces of `fovea run` that are the HMD's, kept out of
 * cmd_run.c. One owner thread. */
#ifndef FV_RUN_HMD_H
#define FV_RUN_HMD_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include <cjson/cJSON.h>

#include "fv_app_budget.h"
#include "fv_app_run.h"
#include "fv_hmd.h"
#include "run_measure.h"

/** The lines of `fovea run --help` for the options here. */
#define RUN_HMD_USAGE                                                                                                  \
    "  --hmd       the HMD whose lenses the frames are pre-distorted for (lens polynomial, chromatic aberration,\n"   \
    "              hidden-area mask): a built-in profile (generic, htc-vive, oculus-rift-dk2; default generic) or a\n" \
    "              profile file (hmd/NAME.json show the format); a named profile's field of view also sets the eye\n" \
    "              frusta; none: no HMD, undistorted (also --set distort.enabled=off)\n"                             \
    "  --budget    auto: keep each frame's GPU time within the refresh period (the --hz display's with --gaze,\n"    \
    "              else the HMD's) by stepping knobs down one preset at a time, least noticeable first, and back\n"  \
    "              up when there is slack; each change is one line on stderr and counted in the summary (default off;\n"\
    "              auto, at 100 ms per frame, on a software device's window and --gaze runs)\n"        \
    "  --budget-scale  multiply the budget's period by X (e.g. 10 on a software rasteriser; default 1)\n"

typedef struct run_hmd {
    fv_app_run *run;       /* the description of the run: --hmd (run->hmd: NULL = generic, the default, its fov not
                              applied; "none"), --budget (run->budget), --budget-scale (run->budget_scale: the period
                              x this, a stand-in for a slower GPU; 0 = 1) */
    bool have;             /* a profile is loaded */
    fv_hmd_profile profile;
    bool budget_given;     /* --budget or --budget-scale was given (a software device's interactive start keeps it) */
    fv_app_budget bud;     /* the application layer's budget (runtime/app) */
    size_t pushed;         /* measured frames given to the controller */
} run_hmd;

/** Take --hmd, --budget or --budget-scale at argv[*i]: 0 when it is none of them, 1 when taken, FV_EXIT_USAGE after
 *  the one-line error and the usage. */
int run_hmd_option(run_hmd *h, int argc, char **argv, int *i, const char *usage);

/** After the options: load the profile (unless none) and put its lens into *q. 0, or FV_EXIT_FAIL after one line on
 *  stderr naming the file, the field and the reason. */
int run_hmd_load(run_hmd *h, fv_quality *q);

/** The lens of a profile (name or file) for command `cmd` (`fovea bench --hmd`): 0, or FV_EXIT_FAIL after one line on
 *  stderr. "none" gives no lens. */
int run_hmd_lens(const char *cmd, const char *name, fv_lens *out);

/** Replace the eye views of `in` by the profile's field of view when the profile was named with --hmd (the default
 *  generic keeps fovea's default frusta, which share its field of view but fit the image's aspect). */
void run_hmd_views(const run_hmd *h, fv_frame_input *in);

/** Start the budget (when --budget auto) for a run of `base` (preset name `preset`) at `hz` (the display's refresh
 *  rate, or the profile's); the passes `plan` turned off get no rungs. 0, or FV_EXIT_FAIL after a line on stderr. */
int run_hmd_budget_start(run_hmd *h, const fv_quality *base, const char *preset, double hz,
                         const fv_frame_plan *plan);

/** Before drawing frame `frame_id`: give the controller every frame measured since the last call; on a change, set
 *  *q to the base with the new level's rungs and log it. */
void run_hmd_budget_update(run_hmd *h, const fv_measure *m, uint64_t frame_id, fv_quality *q);

/** Add "hmd" (profile, lens, mask fraction) and "budget" (mode, period, level, rungs, changes, log) to the summary. */
void run_hmd_add_json(const run_hmd *h, const fv_renderer *r, cJSON *j);
/** Print the same as text. */
void run_hmd_print(const run_hmd *h, const fv_renderer *r, FILE *f);

#endif
