/* @brief --quality / --set parsing, the knob list of --help, and knob values as text and JSON, from the knob table. */
#include "tool_knobs.h"

#include <string.h>

#include "cli.h"

int fv_tool_quality_option(fv_tool_quality *tq, int argc, char **argv, int *i, const char *cmd, const char *usage)
{
    const char *v = NULL;
    int r = fv_cli_option(argc, argv, i, "--quality", &v);
    if (r == 0) r = 2 * fv_cli_option(argc, argv, i, "--set", &v);
    if (r == 0) return 0;
    const char *name = (r == 1 || r == -1) ? "--quality" : "--set";
    if (r < 0)
        return fv_cli_usage_error(cmd, usage, "option %s needs a value (%s)", name,
                                  r == -1 ? fv_quality_preset_names() : "NAME=VALUE; `fovea knobs` lists the names");
    if (r == 1) {
        tq->preset = v;
        return 1;
    }
    if (!fv_app_quality_choice_add(tq, v))
        return fv_cli_usage_error(cmd, usage, "--set: more than %d of them", FV_TOOL_MAX_SETS);
    return 1;
}

const char *fv_tool_quality_preset(const fv_tool_quality *tq) { return fv_app_quality_choice_preset(tq); }

int fv_tool_quality_build(const fv_tool_quality *tq, const char *cmd, const char *usage, fv_quality *out)
{
    char err[512];
    int failed;
    if (FV_FAILED(fv_app_quality_choice_build(tq, out, &failed, err, sizeof err)))
        return fv_cli_usage_error(cmd, usage, "%s: %s", failed < 0 ? "--quality" : "--set", err);
    return 0;
}

void fv_tool_knobs_help(FILE *f)
{
    size_t n = 0;
    const fv_knob *k = fv_knobs(&n);
    fv_quality q = fv_quality_default();
    fprintf(f, "knobs for --set (balanced default in brackets; `fovea knobs` describes them and their presets):\n");
    for (size_t i = 0; i < n; i++) {
        char range[96], value[48];
        fv_knob_format_range(&k[i], range, sizeof range);
        if (k[i].unit[0]) {
            size_t len = strlen(range);
            snprintf(range + len, sizeof range - len, " %s", k[i].unit);
        }
        fprintf(f, "  %-22s %-30s [%s]\n", k[i].name, range, fv_knob_format(&k[i], &q, value, sizeof value));
    }
}

cJSON *fv_tool_knob_json(const fv_knob *k, const fv_quality *q)
{
    fv_knob_value v = fv_knob_get(k, q);
    char buf[48];
    switch (k->type) {
    case FV_KNOB_BOOL: return cJSON_CreateBool(v.b);
    case FV_KNOB_INT: return cJSON_CreateNumber((double)v.i);
    case FV_KNOB_FLOAT: return cJSON_CreateNumber((double)v.f);
    case FV_KNOB_ENUM: return fv_cli_json_string(fv_knob_format(k, q, buf, sizeof buf));
    }
    return cJSON_CreateNull();
}

void fv_tool_quality_add_json(cJSON *obj, const char *preset, const fv_quality *q)
{
    size_t n = 0;
    const fv_knob *k = fv_knobs(&n);
    fv_cli_json_add_string(obj, "preset", preset);
    for (size_t i = 0; i < n; i++) cJSON_AddItemToObject(obj, k[i].name, fv_tool_knob_json(&k[i], q));
}

void fv_tool_quality_print(FILE *f, const char *preset, const fv_quality *q)
{
    size_t n = 0;
    const fv_knob *k = fv_knobs(&n);
    fv_quality base;
    if (FV_FAILED(fv_quality_preset(preset, &base, NULL, 0))) base = fv_quality_default();
    fprintf(f, "  quality: %s", preset);
    const char *sep = "; ";
    for (size_t i = 0; i < n; i++) {
        char a[48], b[48];
        fv_knob_format(&k[i], q, a, sizeof a);
        if (strcmp(a, fv_knob_format(&k[i], &base, b, sizeof b)) == 0) continue;
        fprintf(f, "%s%s=%s", sep, k[i].name, a);
        sep = " ";
    }
    fputc('\n', f);
}
