/* @brief `fovea knobs`: the knob table (name, type, range, unit, the value under each preset, doc, what exact uses
 * where the exact version is not possible on the GPU), as text or JSON. */
#include <stdio.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "tool_knobs.h"

static const char *const USAGE =
    "usage: fovea knobs [--json]\n"
    "\n"
    "List every speed/accuracy knob: its name (for `fovea run --set NAME=VALUE`), type, range, unit, its value\n"
    "under each preset (`fovea run --quality PRESET`; balanced is the default), and what it does.\n"
    "exact turns every shortcut off and keeps the same model; where that is not possible on the GPU, the knob says\n"
    "what exact uses instead.\n"
    "  --json   one JSON object on stdout\n";

/* The four presets, in fv_quality_preset_id order. */
static void presets(fv_quality out[FV_QUALITY_PRESET_COUNT])
{
    for (int p = 0; p < FV_QUALITY_PRESET_COUNT; p++)
        if (FV_FAILED(fv_quality_preset(fv_quality_preset_name((fv_quality_preset_id)p), &out[p], NULL, 0)))
            out[p] = fv_quality_default(); /* not reached: the names come from the table */
}

static void print_text(const fv_knob *k, size_t n, const fv_quality q[FV_QUALITY_PRESET_COUNT])
{
    printf("%-22s %-5s %-26s %-6s", "knob", "type", "range", "unit");
    for (int p = 0; p < FV_QUALITY_PRESET_COUNT; p++)
        printf(p + 1 < FV_QUALITY_PRESET_COUNT ? " %-8s" : " %s\n", fv_quality_preset_name((fv_quality_preset_id)p));
    for (size_t i = 0; i < n; i++) {
        char range[96];
        printf("%-22s %-5s %-26s %-6s", k[i].name, fv_knob_type_name(k[i].type),
               fv_knob_format_range(&k[i], range, sizeof range), k[i].unit[0] ? k[i].unit : "-");
        for (int p = 0; p < FV_QUALITY_PRESET_COUNT; p++) {
            char v[48];
            printf(p + 1 < FV_QUALITY_PRESET_COUNT ? " %-8s" : " %s\n", fv_knob_format(&k[i], &q[p], v, sizeof v));
        }
        printf("    %s\n", k[i].doc);
        if (k[i].exact_note) printf("    exact: %s\n", k[i].exact_note);
    }
}

static void print_json(const fv_knob *k, size_t n, const fv_quality q[FV_QUALITY_PRESET_COUNT])
{
    cJSON *root = cJSON_CreateObject();
    cJSON *names = cJSON_AddArrayToObject(root, "presets");
    for (int p = 0; p < FV_QUALITY_PRESET_COUNT; p++)
        cJSON_AddItemToArray(names, fv_cli_json_string(fv_quality_preset_name((fv_quality_preset_id)p)));
    fv_cli_json_add_string(root, "default_preset", fv_quality_preset_name(FV_QUALITY_BALANCED));
    cJSON *arr = cJSON_AddArrayToObject(root, "knobs");
    for (size_t i = 0; i < n; i++) {
        cJSON *o = cJSON_CreateObject();
        char range[96];
        fv_cli_json_add_string(o, "name", k[i].name);
        fv_cli_json_add_string(o, "type", fv_knob_type_name(k[i].type));
        fv_cli_json_add_string(o, "range", fv_knob_format_range(&k[i], range, sizeof range));
        if (k[i].type == FV_KNOB_INT || k[i].type == FV_KNOB_FLOAT) {
            cJSON_AddNumberToObject(o, "min", k[i].min);
            cJSON_AddNumberToObject(o, "max", k[i].max);
            cJSON_AddBoolToObject(o, "power_of_two", k[i].pow2);
        }
        if (k[i].type == FV_KNOB_ENUM) {
            cJSON *c = cJSON_AddArrayToObject(o, "choices");
            for (uint32_t j = 0; j < k[i].choice_count; j++) cJSON_AddItemToArray(c, fv_cli_json_string(k[i].choices[j]));
        }
        fv_cli_json_add_string(o, "unit", k[i].unit);
        cJSON *pv = cJSON_AddObjectToObject(o, "presets");
        for (int p = 0; p < FV_QUALITY_PRESET_COUNT; p++)
            cJSON_AddItemToObject(pv, fv_quality_preset_name((fv_quality_preset_id)p), fv_tool_knob_json(&k[i], &q[p]));
        fv_cli_json_add_string(o, "doc", k[i].doc);
        if (k[i].exact_note) fv_cli_json_add_string(o, "exact_note", k[i].exact_note);
        else cJSON_AddNullToObject(o, "exact_note");
        cJSON_AddItemToArray(arr, o);
    }
    (void)fv_cli_json_print(root, false);
    cJSON_Delete(root);
}

int fv_cmd_knobs(int argc, char **argv)
{
    bool json = false;
    for (int i = 1; i < argc; i++) {
        if (fv_cli_is_help(argv[i])) {
            fputs(USAGE, stdout);
            return FV_EXIT_OK;
        }
        if (strcmp(argv[i], "--json") == 0) json = true;
        else return fv_cli_usage_error("knobs", USAGE, "unknown option '%s'", argv[i]);
    }
    size_t n = 0;
    const fv_knob *k = fv_knobs(&n);
    fv_quality q[FV_QUALITY_PRESET_COUNT];
    presets(q);
    if (json) print_json(k, n, q);
    else print_text(k, n, q);
    return FV_EXIT_OK;
}
