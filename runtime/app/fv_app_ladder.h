/* @brief The frame-budget ladder (`fovea run --budget auto`, the OpenXR runtime), derived from the knob table: rungs that
 * each move one knob one preset cheaper, from the run's preset towards `fast`, so the ladder's bounds are the
 * presets' own values. Within each preset step the knobs the eye notices least come first (a fixed perceptual order
 * of the knobs known here, then any other knob in table order, then whole-effect `*.enabled` switches); knobs of an
 * effect that is off (or that an earlier rung turned off), a switch turning an effect on, and the lens (distort.*:
 * not a quality trade) are never rungs. Pure: no allocation. */
#ifndef FV_APP_LADDER_H
#define FV_APP_LADDER_H

#include <stddef.h>

#include "fv_knobs.h"

#define FV_APP_LADDER_MAX 64

typedef struct fv_app_rung {
    const fv_knob *knob;
    fv_knob_value value;  /* the knob's value once this rung is applied */
    char text[64];        /* "shadow.resolution=2048", as fv_quality_set parses it */
    int step;             /* the preset step it belongs to: 0 = the first preset cheaper than the run's */
} fv_app_rung;

/** The ladder for a run of `base` (its preset `preset`, a name from fv_quality_preset_name, then its --set knobs).
 *  Returns the rung count (<= cap). */
size_t fv_app_ladder_build(const fv_quality *base, const char *preset, fv_app_rung *out, size_t cap);
/** The same without the knobs of passes the frame plan turned off (`off_passes`: pass ids, NULL-terminated, e.g.
 *  "sss" when the scene has no translucent material): a rung there would save nothing. */
size_t fv_app_ladder_build_for(const fv_quality *base, const char *preset, const char *const *off_passes, fv_app_rung *out,
                            size_t cap);

/** *out = base with rungs 0..level-1 applied, in order. */
void fv_app_ladder_apply(const fv_quality *base, const fv_app_rung *rungs, size_t level, fv_quality *out);

#endif
