/* @brief The knob table as the fovea commands use it: --quality PRESET and --set NAME=VALUE into an fv_quality, the
 * knob list of --help, and knob values in the text and JSON summaries. */
#ifndef FV_TOOL_KNOBS_H
#define FV_TOOL_KNOBS_H

#include <stddef.h>
#include <stdio.h>

#include <cjson/cJSON.h>

#include "fv_app_run.h"
#include "fv_knobs.h"

/** The most --set options one command line may hold (a run's, fv_app_run.h). */
#define FV_TOOL_MAX_SETS FV_APP_RUN_MAX_SETS

/** --quality and --set as given (pointers into argv), applied by fv_tool_quality_build: the quality choice of the
 *  description of a run (fv_app_run.h). Zero-initialise. */
typedef fv_app_quality_choice fv_tool_quality;

/** Take --quality PRESET or --set NAME=VALUE (also as --opt=VALUE) at argv[*i]. Returns 0 when argv[*i] is neither,
 *  1 when taken (*i advanced past a separate value), FV_EXIT_USAGE after printing "fovea CMD: ..." and the usage
 *  (value missing, too many --set). */
int fv_tool_quality_option(fv_tool_quality *tq, int argc, char **argv, int *i, const char *cmd, const char *usage);

/** The preset's name (tq->preset or "balanced"). */
const char *fv_tool_quality_preset(const fv_tool_quality *tq);

/** *out = the preset, then each --set in order. Returns 0, or FV_EXIT_USAGE after printing one line "fovea CMD: ..."
 *  naming the preset or the knob, the value and what is allowed, and the usage. */
int fv_tool_quality_build(const fv_tool_quality *tq, const char *cmd, const char *usage, fv_quality *out);

/** The lines of --help that list the knobs: each knob's name, range and unit, and its balanced default. */
void fv_tool_knobs_help(FILE *f);

/** The knob's value in q as JSON: a bool, a number, or the enum value's name. */
cJSON *fv_tool_knob_json(const fv_knob *k, const fv_quality *q);

/** Add "preset" and every knob's value of q (under its dotted name) to obj. */
void fv_tool_quality_add_json(cJSON *obj, const char *preset, const fv_quality *q);

/** Print "  quality: PRESET" and the knobs whose value in q differs from the preset's ("; shadow.splits=3"). */
void fv_tool_quality_print(FILE *f, const char *preset, const fv_quality *q);

#endif
