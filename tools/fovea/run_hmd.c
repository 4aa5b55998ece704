/* @brief The HMD profile and the frame budget of `fovea run` (see run_hmd.h). */
#include "run_hmd.h"

#include <math.h>
#include <string.h>

#include "cli.h"
#include "fv_log.h"

#define MOD "run"

int run_hmd_option(run_hmd *h, int argc, char **argv, int *i, const char *usage)
{
    const char *v = NULL;
    int r = fv_cli_option(argc, argv, i, "--hmd", &v);
    if (r < 0) return fv_cli_usage_error("run", usage, "option --hmd needs a value");
    if (r) {
        h->run->hmd = v;
        return 1;
    }
    r = fv_cli_option(argc, argv, i, "--budget", &v);
    if (r < 0) return fv_cli_usage_error("run", usage, "option --budget needs a value");
    if (r) {
        if (strcmp(v, "auto") && strcmp(v, "off"))
            return fv_cli_usage_error("run", usage, "--budget: '%s' is not one of auto, off", v);
        h->run->budget = strcmp(v, "auto") == 0;
        h->budget_given = true;
        return 1;
    }
    r = fv_cli_option(argc, argv, i, "--budget-scale", &v);
    if (r < 0) return fv_cli_usage_error("run", usage, "option --budget-scale needs a value");
    if (r) {
        double x;
        if (!fv_cli_parse_f64(v, FV_APP_RUN_BUDGET_SCALE_MIN, FV_APP_RUN_BUDGET_SCALE_MAX, &x))
            return fv_cli_usage_error("run", usage, "--budget-scale: '%s' is not a number in %g..%g", v,
                                      FV_APP_RUN_BUDGET_SCALE_MIN, FV_APP_RUN_BUDGET_SCALE_MAX);
        h->run->budget_scale = x;
        h->budget_given = true;
        return 1;
    }
    return 0;
}

int run_hmd_load(run_hmd *h, fv_quality *q)
{
    q->distort.lens = (fv_lens){0};
    if (h->run->hmd && strcmp(h->run->hmd, "none") == 0) return 0;
    char err[512];
    fv_result res = fv_hmd_profile_load(h->run->hmd ? h->run->hmd : "generic", &h->profile, err, sizeof err);
    if (res != FV_OK) {
        fprintf(stderr, "fovea run: --hmd: %s\n", err);
        return FV_EXIT_FAIL;
    }
    h->have = true;
    q->distort.lens = h->profile.lens;
    return 0;
}

int run_hmd_lens(const char *cmd, const char *name, fv_lens *out)
{
    *out = (fv_lens){0};
    if (!strcmp(name, "none")) return 0;
    fv_hmd_profile p;
    char err[512];
    if (fv_hmd_profile_load(name, &p, err, sizeof err) != FV_OK) {
        fprintf(stderr, "fovea %s: --hmd: %s\n", cmd, err);
        return FV_EXIT_FAIL;
    }
    *out = p.lens;
    return 0;
}

void run_hmd_views(const run_hmd *h, fv_frame_input *in)
{
    if (!h->have || !h->run->hmd) return;
    float fov[8];
    for (int e = 0; e < 2; e++) {
        const fv_hmd_fov *f = &h->profile.fov[e];
        fov[4 * e + 0] = f->tan_left;
        fov[4 * e + 1] = f->tan_right;
        fov[4 * e + 2] = f->tan_up;
        fov[4 * e + 3] = f->tan_down;
    }
    fv_eye_views_build_fov(&in->head, in->eye[0].near_m, in->eye[0].far_m, fov, in->eye);
}

int run_hmd_budget_start(run_hmd *h, const fv_quality *base, const char *preset, double hz,
                         const fv_frame_plan *plan)
{
    if (!h->run->budget) return 0;
    const char *off[FV_MAX_PASSES + 1] = {NULL};
    for (uint32_t i = 0, n = 0; plan && i < plan->count; i++)
        if (!plan->entries[i].enabled) off[n++] = plan->entries[i].pass;
    if (FV_FAILED(fv_app_budget_start(&h->bud, "run", base, preset, hz, h->run->budget_scale, off))) {
        fprintf(stderr, "fovea run: --budget: a period of %g ms cannot be budgeted\n",
                1e3 / hz * (h->run->budget_scale > 0 ? h->run->budget_scale : 1.0));
        return FV_EXIT_FAIL;
    }
    return 0;
}

void run_hmd_budget_update(run_hmd *h, const fv_measure *m, uint64_t frame_id, fv_quality *q)
{
    if (!h->run->budget) return;
    size_t n = m->measured < m->cap ? m->measured : m->cap;
    for (; h->pushed < n; h->pushed++) (void)fv_app_budget_push(&h->bud, frame_id, m->frame_gpu_ms[h->pushed], q);
}

static double mask_fraction(const fv_renderer *r, int eye)
{
    fv_pass_detail d[16];
    uint32_t n = r ? fv_renderer_pass_details(r, "gbuffer", d, 16) : 0;
    for (uint32_t i = 0; i < n; i++)
        if (strcmp(d[i].key, "mask.fraction") == 0 && d[i].count == 2) return d[i].value[eye];
    return NAN;
}

void run_hmd_add_json(const run_hmd *h, const fv_renderer *r, cJSON *j)
{
    cJSON *jh = cJSON_AddObjectToObject(j, "hmd");
    if (h->have) {
        fv_cli_json_add_string(jh, "name", h->profile.name);
        fv_cli_json_add_string(jh, "origin", h->profile.origin);
        fv_cli_json_number(jh, "refresh_hz", h->profile.refresh_hz);
        cJSON_AddBoolToObject(jh, "fov_applied", h->run->hmd != NULL);
        double m0 = mask_fraction(r, 0), m1 = mask_fraction(r, 1);
        if (isfinite(m0) && isfinite(m1)) {
            cJSON *a = cJSON_AddArrayToObject(jh, "masked_fraction");
            cJSON_AddItemToArray(a, cJSON_CreateNumber(m0));
            cJSON_AddItemToArray(a, cJSON_CreateNumber(m1));
        } else {
            cJSON_AddNullToObject(jh, "masked_fraction");
        }
    } else {
        cJSON_AddNullToObject(jh, "name");
    }
    cJSON *jb = cJSON_AddObjectToObject(j, "budget");
    fv_cli_json_add_string(jb, "mode", h->run->budget ? "auto" : "off");
    if (!h->run->budget) return;
    const fv_app_budget *b = &h->bud;
    fv_cli_json_number(jb, "hz", b->hz);
    fv_cli_json_number(jb, "scale", b->scale);
    fv_cli_json_number(jb, "budget_ms", fv_app_budget_target_ms(b));
    fv_cli_json_number(jb, "level", b->ctl.level);
    fv_cli_json_number(jb, "changes", (double)b->changes);
    fv_cli_json_number(jb, "downs", (double)b->ctl.downs);
    fv_cli_json_number(jb, "ups", (double)b->ctl.ups);
    fv_cli_json_number(jb, "reversals", (double)b->ctl.reversals);
    fv_cli_json_number(jb, "frames", (double)b->ctl.frames);
    fv_cli_json_number(jb, "misses", (double)b->ctl.misses);
    cJSON *rungs = cJSON_AddArrayToObject(jb, "rungs");
    for (size_t i = 0; i < b->rung_count; i++) cJSON_AddItemToArray(rungs, fv_cli_json_string(b->rungs[i].text));
    cJSON *applied = cJSON_AddArrayToObject(jb, "applied");
    for (size_t i = 0; i < b->ctl.level; i++) cJSON_AddItemToArray(applied, fv_cli_json_string(b->rungs[i].text));
    cJSON *log = cJSON_AddArrayToObject(jb, "log");
    for (size_t i = 0; i < b->log_n; i++) {
        cJSON *e = cJSON_CreateObject();
        fv_cli_json_number(e, "frame", (double)b->log[i].frame);
        fv_cli_json_add_string(e, "step", b->log[i].down ? "down" : "up");
        fv_cli_json_number(e, "level", b->log[i].level);
        fv_cli_json_number(e, "gpu_ms", b->log[i].gpu_ms);
        cJSON_AddItemToArray(log, e);
    }
}

void run_hmd_print(const run_hmd *h, const fv_renderer *r, FILE *f)
{
    if (h->have) {
        double m0 = mask_fraction(r, 0), m1 = mask_fraction(r, 1);
        fprintf(f, "  hmd: %s (%s), %g Hz%s", h->profile.name, h->profile.origin, (double)h->profile.refresh_hz,
                h->run->hmd ? ", its field of view" : "");
        if (isfinite(m0)) fprintf(f, "; hidden-area mask %.1f%% / %.1f%% of the pixels", 100 * m0, 100 * m1);
        fputc('\n', f);
    } else {
        fprintf(f, "  hmd: none (undistorted)\n");
    }
    if (!h->run->budget) return;
    const fv_app_budget *b = &h->bud;
    fprintf(f, "  budget: %.2f ms per frame (%g Hz x %g), level %u of %zu after %llu change%s (%llu down, %llu up), "
            "%llu of %llu frames over the period\n", fv_app_budget_target_ms(b), b->hz, b->scale, b->ctl.level,
            b->rung_count, (unsigned long long)b->changes, b->changes == 1 ? "" : "s", (unsigned long long)b->ctl.downs,
            (unsigned long long)b->ctl.ups, (unsigned long long)b->ctl.misses, (unsigned long long)b->ctl.frames);
    for (size_t i = 0; i < b->ctl.level; i++) fprintf(f, "    rung %zu: %s\n", i + 1, b->rungs[i].text);
}
