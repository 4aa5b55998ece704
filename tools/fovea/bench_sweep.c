/* @brief `fovea bench`'s sweeps and their cross product (see bench_sweep.h). */
#include "bench_sweep.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* One value of a sweep, checked: a preset name, or NAME=VALUE through the knob table. */
static fv_result check_value(const fv_bench_sweep *s, const char *value, fv_quality *q, char *err, size_t err_size)
{
    *q = fv_quality_default();
    if (!s->knob) return fv_quality_preset(value, q, err, err_size);
    char assignment[1100];
    snprintf(assignment, sizeof assignment, "%s=%s", s->name, value);
    return fv_quality_set(q, assignment, err, err_size);
}

/* The index of an earlier value of s that parses to the same setting as `value` (its quality q): the knob's value
 * as stored, or the same preset; -1 when there is none. */
static int same_as(const fv_bench_sweep *s, const char *value, const fv_quality *q, const fv_knob_value *earlier)
{
    fv_knob_value a = s->knob ? fv_knob_get(s->knob, q) : (fv_knob_value){.i = 0};
    for (size_t i = 0; i < s->value_count; i++) {
        const fv_knob_value *b = &earlier[i];
        bool same = !s->knob                              ? strcmp(s->values[i], value) == 0
                    : s->knob->type == FV_KNOB_BOOL  ? a.b == b->b
                    : s->knob->type == FV_KNOB_FLOAT ? a.f == b->f
                                                     : a.i == b->i;
        if (same) return (int)i;
    }
    return -1;
}

fv_result fv_bench_plan_add(fv_bench_plan *p, const char *arg, char *err, size_t err_size)
{
    const char *eq = strchr(arg, '=');
    size_t name_len = eq ? (size_t)(eq - arg) : 0;
    if (!eq || name_len == 0) {
        snprintf(err, err_size, "'%s' is not NAME=V1,V2,... (e.g. shadow.splits=1,2,4; `fovea knobs` lists the names)",
                 arg);
        return FV_ERR_PARSE;
    }
    if (p->sweep_count >= FV_BENCH_MAX_SWEEPS) {
        snprintf(err, err_size, "more than %d sweeps", FV_BENCH_MAX_SWEEPS);
        return FV_ERR_RANGE;
    }
    fv_bench_sweep *s = &p->sweeps[p->sweep_count];
    memset(s, 0, sizeof *s);
    if (name_len >= sizeof s->name || strlen(eq + 1) >= sizeof s->text) {
        snprintf(err, err_size, "'%.80s...' is too long", arg);
        return FV_ERR_RANGE;
    }
    memcpy(s->name, arg, name_len);
    s->name[name_len] = '\0';
    if (strcmp(s->name, FV_BENCH_PRESET) != 0) {
        s->knob = fv_knob_find(s->name);
        if (!s->knob) { /* fv_quality_set names the knobs there are */
            fv_quality q = fv_quality_default();
            char assignment[128];
            snprintf(assignment, sizeof assignment, "%s=0", s->name);
            if (FV_FAILED(fv_quality_set(&q, assignment, err, err_size))) return FV_ERR_NOT_FOUND;
        }
    }
    for (size_t i = 0; i < p->sweep_count; i++)
        if (strcmp(p->sweeps[i].name, s->name) == 0) {
            snprintf(err, err_size, "%s is swept twice", s->name);
            return FV_ERR_RANGE;
        }
    strcpy(s->text, eq + 1);
    fv_knob_value parsed[FV_BENCH_MAX_VALUES]; /* each kept value as the knob stores it */
    for (char *v = s->text;;) {
        char *comma = strchr(v, ',');
        if (comma) *comma = '\0';
        if (s->value_count >= FV_BENCH_MAX_VALUES) {
            snprintf(err, err_size, "%s: more than %d values", s->name, FV_BENCH_MAX_VALUES);
            return FV_ERR_RANGE;
        }
        fv_quality q;
        fv_result res = check_value(s, v, &q, err, err_size);
        if (FV_FAILED(res)) return res;
        int dup = same_as(s, v, &q, parsed);
        if (dup >= 0) { /* benching the same setting twice only costs time: keep the first, say so once */
            size_t at = strlen(s->dropped), room = sizeof s->dropped - at;
            int n = snprintf(NULL, 0, "%s%s (as %s)", at ? ", " : "", v, s->values[dup]);
            if (n >= 0 && (size_t)n + 5 < room) /* keeps room for ", ...": a long list ends visibly, not cut */
                snprintf(s->dropped + at, room, "%s%s (as %s)", at ? ", " : "", v, s->values[dup]);
            else if (at < 3 || strcmp(s->dropped + at - 3, "...") != 0)
                snprintf(s->dropped + at, room, "%s...", at ? ", " : "");
            s->dropped_count++;
        } else {
            parsed[s->value_count] = s->knob ? fv_knob_get(s->knob, &q) : (fv_knob_value){.i = 0};
            s->values[s->value_count++] = v;
        }
        if (!comma) break;
        v = comma + 1;
    }
    p->sweep_count++;
    return FV_OK;
}

size_t fv_bench_plan_points(const fv_bench_plan *p)
{
    size_t n = 1;
    for (size_t i = 0; i < p->sweep_count; i++) {
        size_t c = p->sweeps[i].value_count;
        if (c && n > SIZE_MAX / c) return SIZE_MAX;
        n *= c;
    }
    return n;
}

void fv_bench_point_values(const fv_bench_plan *p, size_t index, size_t out_value_index[FV_BENCH_MAX_SWEEPS])
{
    memset(out_value_index, 0, FV_BENCH_MAX_SWEEPS * sizeof *out_value_index);
    for (size_t i = p->sweep_count; i-- > 0;) {
        size_t c = p->sweeps[i].value_count ? p->sweeps[i].value_count : 1;
        out_value_index[i] = index % c;
        index /= c;
    }
}

/* The preset's name in static storage (the knob table's), or NULL. */
static const char *preset_name(const char *name)
{
    for (int id = 0; id < FV_QUALITY_PRESET_COUNT; id++) {
        const char *n = fv_quality_preset_name((fv_quality_preset_id)id);
        if (strcmp(n, name) == 0) return n;
    }
    return NULL;
}

fv_result fv_bench_point_quality(const fv_bench_plan *p, size_t index, fv_quality *out, const char **out_preset,
                                 char *err, size_t err_size)
{
    size_t vi[FV_BENCH_MAX_SWEEPS];
    fv_bench_point_values(p, index, vi);
    const char *preset = fv_tool_quality_preset(&p->tq);
    for (size_t i = 0; i < p->sweep_count; i++)
        if (!p->sweeps[i].knob) preset = p->sweeps[i].values[vi[i]];
    FV_TRY(fv_quality_preset(preset, out, err, err_size));
    *out_preset = preset_name(preset);
    for (size_t i = 0; i < p->tq.set_count; i++) FV_TRY(fv_quality_set(out, p->tq.sets[i], err, err_size));
    for (size_t i = 0; i < p->sweep_count; i++) {
        const fv_bench_sweep *s = &p->sweeps[i];
        if (!s->knob) continue;
        char assignment[1100];
        snprintf(assignment, sizeof assignment, "%s=%s", s->name, s->values[vi[i]]);
        FV_TRY(fv_quality_set(out, assignment, err, err_size));
    }
    return FV_OK;
}
