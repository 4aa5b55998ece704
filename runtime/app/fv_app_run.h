/* @brief The description of a run, one for `fovea run`, `fovea bench`, `fovea reference` and the OpenXR runtime's
 * sessions: the scene, the per-eye size and layout, the quality (a preset and NAME=VALUE knobs after it, applied in
 * order), the view settings, the HMD, the gaze source and the head the cameras follow, and the frame budget. The
 * commands fill it from their options (tools/fovea/tool_image.c), the OpenXR runtime from its FOVEA_XR_* variables
 * (xr/xr_instance.c); the defaults, the limits and the validation are here, once. Pure: no I/O, no allocation. */
#ifndef FV_APP_RUN_H
#define FV_APP_RUN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fv_quality.h"
#include "fv_result.h"

/** The most NAME=VALUE knobs one run may set (--set). */
#define FV_APP_RUN_MAX_SETS 64
/** The largest per-eye width or height. */
#define FV_APP_RUN_MAX_EYE_SIZE 8192u
/** The frame budget's period scale (--budget-scale, FOVEA_XR_BUDGET=SCALE): 0.01..1000. */
#define FV_APP_RUN_BUDGET_SCALE_MIN 0.01
#define FV_APP_RUN_BUDGET_SCALE_MAX 1000.0

/** The quality of a run as chosen: a preset (NULL: balanced), then each NAME=VALUE in order (pointers the caller
 *  keeps alive, e.g. into argv). */
typedef struct fv_app_quality_choice {
    const char *preset;
    const char *sets[FV_APP_RUN_MAX_SETS];
    size_t set_count;
} fv_app_quality_choice;

/** Which head the cameras follow in a gaze-driven run: trace (the scene's head moved by the tracker's recorded head
 *  pose), scene (the tracker's pose ignored), fixed (the scene's head at time 0). */
typedef enum fv_app_head { FV_APP_HEAD_TRACE = 0, FV_APP_HEAD_SCENE, FV_APP_HEAD_FIXED } fv_app_head;

typedef struct fv_app_run {
    const char *scene;             /* a built-in scene's name or a file (default cornell) */
    uint32_t eye_w, eye_h;         /* per eye (default 720x800; 1..FV_APP_RUN_MAX_EYE_SIZE) */
    bool sbs;                      /* both eyes side by side (default) or one image per eye */
    fv_app_quality_choice quality; /* preset + knobs */
    float exposure;                /* view settings: linear exposure and the debug view (fv_quality_default's) */
    fv_debug_view view;
    const char *hmd;               /* the HMD profile (a built-in name or a file); NULL: generic, its field of view not
                                      applied to the eye frusta; "none": no HMD, no lens */
    const char *gaze_uri;          /* the gaze source (any driver URI); NULL: none */
    fv_app_head head;              /* with a gaze source (default trace) */
    bool budget;                   /* the frame budget on (auto) */
    double budget_scale;           /* its period x this; 0 = 1 */
} fv_app_run;

/** The defaults above. */
void fv_app_run_defaults(fv_app_run *r);

/** The preset's name (NULL: "balanced"). */
const char *fv_app_quality_choice_preset(const fv_app_quality_choice *c);
/** Append one NAME=VALUE: false when FV_APP_RUN_MAX_SETS are already there. */
bool fv_app_quality_choice_add(fv_app_quality_choice *c, const char *set);
/** *out = the preset, then each knob in order. FV_OK, or an error with *failed = -1 (the preset) or the index of the
 *  refused knob, and the reason in err (the knob table's one line: the name, the value, what is allowed). */
fv_result fv_app_quality_choice_build(const fv_app_quality_choice *c, fv_quality *out, int *failed, char *err,
                                      size_t err_size);

/** The run's quality: the choice, then the view settings (exposure, view). The lens is the HMD's (its profile is
 *  loaded by the caller). As fv_app_quality_choice_build. */
fv_result fv_app_run_quality(const fv_app_run *r, fv_quality *out, int *failed, char *err, size_t err_size);

/** "trace", "scene", "fixed"; false for anything else. */
bool fv_app_head_parse(const char *s, fv_app_head *out);
const char *fv_app_head_name(fv_app_head h);

/** A per-eye size within 1..FV_APP_RUN_MAX_EYE_SIZE. */
bool fv_app_run_eye_size_valid(uint32_t w, uint32_t h);
/** A budget period scale within FV_APP_RUN_BUDGET_SCALE_MIN..MAX (finite). */
bool fv_app_run_budget_scale_valid(double scale);
/** The budget as one word (FOVEA_XR_BUDGET): "auto" or "" (on, scale 1), "off", or a period scale (on, that scale).
 *  FV_OK with r->budget and r->budget_scale set, or FV_ERR_INVALID_ARG (r unchanged) naming what is expected. */
fv_result fv_app_run_budget_parse(fv_app_run *r, const char *s, char *err, size_t err_size);

#endif
