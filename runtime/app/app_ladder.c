/* @brief The frame-budget ladder from the knob table (see fv_app_ladder.h). */
#include "fv_app_ladder.h"

#include <stdio.h>
#include <string.h>

/* Least noticeable first. Shadow-map resolution and its filter change shadow edges by a texel or two; the split
 * scheme and bias move where aliasing falls; shared splits change only the far eye's texel density; fewer splits
 * alias distant shadows more. Foveation's knobs widen what the periphery is filled from (only when it is on). */
static const char *const g_order[] = {
    "shadow.resolution", "shadow.filter",  "shadow.lambda",    "shadow.bias",     "shadow.stereo_shared",
    "shadow.splits",     "fovea.min_prob", "fovea.mar_slope",  "fovea.mar_w0_deg", "fovea.block",
    "fovea.uncertainty",
};
#define ORDER_COUNT (sizeof g_order / sizeof g_order[0])

static bool same(const fv_knob *k, fv_knob_value a, fv_knob_value b)
{
    return k->type == FV_KNOB_BOOL ? a.b == b.b : k->type == FV_KNOB_FLOAT ? a.f == b.f : a.i == b.i;
}

/* The knob's effect is off in base: its "<group>.enabled" knob exists and is false (the switch itself excepted). */
static bool effect_off(const fv_knob *k, const fv_quality *base)
{
    const char *dot = strchr(k->name, '.');
    if (!dot || strcmp(dot, ".enabled") == 0) return false;
    char name[64];
    snprintf(name, sizeof name, "%.*s.enabled", (int)(dot - k->name), k->name);
    const fv_knob *en = fv_knob_find(name);
    return en && en->type == FV_KNOB_BOOL && !fv_knob_get(en, base).b;
}

static int rank(const fv_knob *k)
{
    for (size_t i = 0; i < ORDER_COUNT; i++)
        if (strcmp(g_order[i], k->name) == 0) return (int)i;
    const char *dot = strchr(k->name, '.');
    return dot && strcmp(dot, ".enabled") == 0 ? 2000 : 1000; /* unknown knobs after, whole effects last */
}

static bool pass_off(const fv_knob *k, const char *const *off)
{
    const char *dot = strchr(k->name, '.');
    for (size_t i = 0; off && dot && off[i]; i++)
        if (strlen(off[i]) == (size_t)(dot - k->name) && !strncmp(off[i], k->name, (size_t)(dot - k->name))) return true;
    return false;
}

size_t fv_app_ladder_build(const fv_quality *base, const char *preset, fv_app_rung *out, size_t cap)
{
    return fv_app_ladder_build_for(base, preset, NULL, out, cap);
}

size_t fv_app_ladder_build_for(const fv_quality *base, const char *preset, const char *const *off_passes, fv_app_rung *out,
                            size_t cap)
{
    /* the presets cheaper than the run's, in order towards fast */
    fv_quality_preset_id start = FV_QUALITY_BALANCED;
    for (int p = 0; p < FV_QUALITY_PRESET_COUNT; p++)
        if (preset && strcmp(preset, fv_quality_preset_name((fv_quality_preset_id)p)) == 0)
            start = (fv_quality_preset_id)p;
    static const fv_quality_preset_id cheaper[] = {FV_QUALITY_EXACT, FV_QUALITY_HIGH, FV_QUALITY_BALANCED,
                                                   FV_QUALITY_FAST}; /* costliest first */
    int first = 0;
    while (first < 4 && cheaper[first] != start) first++;
    size_t count_knobs = 0;
    const fv_knob *knobs = fv_knobs(&count_knobs);
    fv_quality cur = *base; /* the ladder so far */
    size_t n = 0;
    for (int s = first + 1; s < 4; s++) {
        fv_quality step;
        char err[8];
        if (fv_quality_preset(fv_quality_preset_name(cheaper[s]), &step, err, sizeof err) != FV_OK) continue;
        /* this step's rungs in rank order (a stable selection: knob counts are small) */
        bool used[256] = {false};
        for (;;) {
            int best = -1, best_rank = 0;
            for (size_t i = 0; i < count_knobs && i < 256; i++) {
                const fv_knob *k = &knobs[i];
                if (used[i] || strncmp(k->name, "distort.", 8) == 0 || effect_off(k, &cur) ||
                    pass_off(k, off_passes))
                    continue;
                if (same(k, fv_knob_get(k, &cur), fv_knob_get(k, &step))) continue;
                /* turning an effect on is never cheaper */
                const char *dot = strchr(k->name, '.');
                if (k->type == FV_KNOB_BOOL && dot && !strcmp(dot, ".enabled") && fv_knob_get(k, &step).b) continue;
                int r = rank(k);
                if (best < 0 || r < best_rank) {
                    best = (int)i;
                    best_rank = r;
                }
            }
            if (best < 0 || n >= cap) break;
            used[best] = true;
            const fv_knob *k = &knobs[best];
            fv_app_rung *g = &out[n++];
            memset(g, 0, sizeof *g);
            g->knob = k;
            g->value = fv_knob_get(k, &step);
            g->step = s - first - 1;
            char v[48];
            fv_knob_format(k, &step, v, sizeof v);
            snprintf(g->text, sizeof g->text, "%s=%s", k->name, v);
            char e2[8];
            if (fv_quality_set(&cur, g->text, e2, sizeof e2) != FV_OK) n--; /* cannot happen: a preset's value */
        }
    }
    return n;
}

void fv_app_ladder_apply(const fv_quality *base, const fv_app_rung *rungs, size_t level, fv_quality *out)
{
    *out = *base;
    for (size_t i = 0; i < level; i++) {
        char err[8];
        if (fv_quality_set(out, rungs[i].text, err, sizeof err) != FV_OK) break;
    }
}
