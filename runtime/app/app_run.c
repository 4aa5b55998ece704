/* @brief The description of a run (see fv_app_run.h). */
#include "fv_app_run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_knobs.h"

void fv_app_run_defaults(fv_app_run *r)
{
    memset(r, 0, sizeof *r);
    fv_quality q = fv_quality_default();
    r->scene = "cornell";
    r->eye_w = 720;
    r->eye_h = 800;
    r->sbs = true;
    r->exposure = q.exposure;
    r->view = q.debug_view;
    r->head = FV_APP_HEAD_TRACE;
}

const char *fv_app_quality_choice_preset(const fv_app_quality_choice *c)
{
    return c->preset ? c->preset : "balanced";
}

bool fv_app_quality_choice_add(fv_app_quality_choice *c, const char *set)
{
    if (c->set_count >= FV_APP_RUN_MAX_SETS) return false;
    c->sets[c->set_count++] = set;
    return true;
}

fv_result fv_app_quality_choice_build(const fv_app_quality_choice *c, fv_quality *out, int *failed, char *err,
                                      size_t err_size)
{
    *failed = -1;
    fv_result res = fv_quality_preset(fv_app_quality_choice_preset(c), out, err, err_size);
    if (FV_FAILED(res)) return res;
    for (size_t i = 0; i < c->set_count && i < FV_APP_RUN_MAX_SETS; i++) {
        *failed = (int)i;
        if (FV_FAILED(res = fv_quality_set(out, c->sets[i], err, err_size))) return res;
    }
    *failed = -1;
    return FV_OK;
}

fv_result fv_app_run_quality(const fv_app_run *r, fv_quality *out, int *failed, char *err, size_t err_size)
{
    fv_result res = fv_app_quality_choice_build(&r->quality, out, failed, err, err_size);
    if (FV_FAILED(res)) return res;
    out->exposure = r->exposure;
    out->debug_view = r->view;
    return FV_OK;
}

bool fv_app_head_parse(const char *s, fv_app_head *out)
{
    static const char *const names[] = {"trace", "scene", "fixed"};
    for (int i = 0; i < 3; i++)
        if (strcmp(s, names[i]) == 0) {
            *out = (fv_app_head)i;
            return true;
        }
    return false;
}

const char *fv_app_head_name(fv_app_head h)
{
    return h == FV_APP_HEAD_SCENE ? "scene" : h == FV_APP_HEAD_FIXED ? "fixed" : "trace";
}

bool fv_app_run_eye_size_valid(uint32_t w, uint32_t h)
{
    return w >= 1 && h >= 1 && w <= FV_APP_RUN_MAX_EYE_SIZE && h <= FV_APP_RUN_MAX_EYE_SIZE;
}

bool fv_app_run_budget_scale_valid(double scale)
{
    return isfinite(scale) && scale >= FV_APP_RUN_BUDGET_SCALE_MIN && scale <= FV_APP_RUN_BUDGET_SCALE_MAX;
}

fv_result fv_app_run_budget_parse(fv_app_run *r, const char *s, char *err, size_t err_size)
{
    if (!s || !*s || !strcmp(s, "auto")) {
        r->budget = true;
        r->budget_scale = 0;
        return FV_OK;
    }
    if (!strcmp(s, "off")) {
        r->budget = false;
        r->budget_scale = 0;
        return FV_OK;
    }
    char *end;
    double scale = strtod(s, &end);
    if (end == s || *end || !fv_app_run_budget_scale_valid(scale)) {
        snprintf(err, err_size, "expected auto, off or a period scale in %g..%g", FV_APP_RUN_BUDGET_SCALE_MIN,
                 FV_APP_RUN_BUDGET_SCALE_MAX);
        return FV_ERR_INVALID_ARG;
    }
    r->budget = true;
    r->budget_scale = scale;
    return FV_OK;
}
