/* @brief The pass table and the frame plan built from it: which passes run for a scene, a device and the quality
 * settings, and why — including the passes that are planned but do not exist yet (plan-only entries, no init). */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "debug.h"
#include "distort.h"
#include "fovea.h"
#include "fv_passes.h"
#include "fv_renderer.h"
#include "gbuffer.h"
#include "overlay.h"
#include "gi.h"
#include "gi_gather.h"
#include "interp.h"
#include "present.h"
#include "shade.h"
#include "shadow.h"
#include "sss.h"

static const char *plural(uint64_t n) { return n == 1 ? "" : "s"; }

static void say(fv_plan_entry *e, bool enabled, const char *fmt, ...) FV_PRINTF(3, 4);

static void say(fv_plan_entry *e, bool enabled, const char *fmt, ...)
{
    e->enabled = enabled;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->reason, sizeof e->reason, fmt, ap);
    va_end(ap);
}

/* ---- plan-only entries: passes that are planned but not built yet ---------------------------------------------- */

static void motion_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    const fv_scene *s = ctx->scene;
    /* Drawn by the G-buffer where something reads them: foveation's surface target, or the motion target kept for
     * read-back (fv_renderer_desc.motion_target). */
    bool fovea = ctx->quality->fovea.enabled;
    if (!fovea && !ctx->motion_target) {
        say(out, false, "off — nothing reads motion vectors (fovea.enabled is false)");
        return;
    }
    const char *where = fovea && ctx->motion_target ? "G-buffer: foveation's surface and the motion target"
                        : fovea                     ? "G-buffer: foveation's surface target"
                                                    : "G-buffer: the motion target";
    uint32_t animated = 0;
    for (uint32_t i = 0; s && i < s->node_count; i++)
        if (s->nodes[i].anim.kind != FV_ANIM_NONE) animated++;
    if (s && !fv_scene_is_animated(s)) animated = 0;
    if (animated)
        say(out, true, "%u animated node%s: motion vectors from previous-frame transforms (%s)", animated,
            plural(animated), where);
    else
        say(out, true, "static scene: motion vectors from head motion only (%s)", where);
}


static const fv_pass motion_entry = {.id = "motion", .plan = motion_plan};

/* ---- the table ------------------------------------------------------------------------------------------------ */

/* Frame order. A new pass: its folder under render/, and one line here. */
static const fv_pass *const table[] = {
    &fv_gbuffer_pass, &motion_entry, &fv_shadow_pass, &fv_gi_pass, &fv_gi_gather_pass, &fv_sss_pass,
    &fv_fovea_pass,   &fv_compact_pass, &fv_interp_pass,  &fv_shade_pass,     &fv_interp_fill_pass, &fv_temporal_pass,
    &fv_reconstruct_pass, &fv_debug_pass, &fv_present_pass, &fv_overlay_pass, &fv_distort_pass,
};
_Static_assert(sizeof table / sizeof table[0] <= FV_MAX_PASSES, "FV_MAX_PASSES holds the table");

const fv_pass *const *fv_pass_table(uint32_t *out_count)
{
    *out_count = (uint32_t)(sizeof table / sizeof table[0]);
    return table;
}

/* ---- declared images -------------------------------------------------------------------------------------------- */

static bool listed(const char *const *names, const char *name)
{
    for (; names && *names; names++)
        if (strcmp(*names, name) == 0) return true;
    return false;
}

/* The table index of the pass that makes `name`, or -1. */
static int maker_of(const fv_pass *const *t, uint32_t n, const char *name)
{
    for (uint32_t i = 0; i < n; i++)
        if (listed(t[i]->makes, name)) return (int)i;
    return -1;
}

bool fv_frame_plan_reads_from(const fv_pass *const *t, uint32_t reader, uint32_t maker)
{
    for (const char *const *m = t[maker]->makes; m && *m; m++)
        if (listed(t[reader]->needs, *m) || listed(t[reader]->uses_if_made, *m)) return true;
    return false;
}

/* Append "<label> a, b (maker), ..." to the entry's io line. */
static void io_add(fv_plan_entry *e, size_t *at, const char *label, const char *const *names, const fv_pass *const *t,
                   uint32_t n)
{
    for (uint32_t k = 0; names && names[k] && *at < sizeof e->io; k++) {
        int m = maker_of(t, n, names[k]);
        int w = snprintf(e->io + *at, sizeof e->io - *at, "%s%s%s%s%s%s", *at ? (k ? ", " : "; ") : "",
                         k ? "" : label, names[k], m >= 0 && label[0] != 'm' ? " (" : "",
                         m >= 0 && label[0] != 'm' ? t[m]->id : "", m >= 0 && label[0] != 'm' ? ")" : "");
        *at = w < 0 ? sizeof e->io : *at + (size_t)w;
    }
}

void fv_frame_plan_build_table(const fv_pass *const *t, uint32_t n, const fv_plan_context *ctx, fv_frame_plan *out)
{
    memset(out, 0, sizeof *out);
    fv_quality q = fv_quality_default();
    fv_plan_context c = *ctx;
    if (!c.quality) c.quality = &q;
    for (uint32_t i = 0; i < n && i < FV_MAX_PASSES; i++) {
        fv_plan_entry *e = &out->entries[out->count++];
        snprintf(e->pass, sizeof e->pass, "%s", t[i]->id);
        t[i]->plan(&c, e);
        size_t at = 0;
        io_add(e, &at, "makes ", t[i]->makes, t, n);
        io_add(e, &at, "needs ", t[i]->needs, t, n);
        io_add(e, &at, "uses if made ", t[i]->uses_if_made, t, n);
    }
}

void fv_frame_plan_build_ctx(const fv_plan_context *ctx, fv_frame_plan *out)
{
    uint32_t n = 0;
    const fv_pass *const *t = fv_pass_table(&n);
    fv_frame_plan_build_table(t, n, ctx, out);
}

fv_result fv_frame_plan_check(const fv_pass *const *t, uint32_t n, const fv_frame_plan *plan, char *err,
                              size_t err_size)
{
    if (err && err_size) err[0] = '\0';
    for (uint32_t i = 0; i < n && i < plan->count; i++) {
        for (const char *const *m = t[i]->makes; m && *m; m++) {
            int first = maker_of(t, n, *m);
            if (first != (int)i) {
                if (err) snprintf(err, err_size, "image '%s' is made by two passes, %s and %s", *m, t[first]->id, t[i]->id);
                return FV_ERR_STATE;
            }
        }
        if (!plan->entries[i].enabled) continue;
        for (int optional = 0; optional < 2; optional++) {
            for (const char *const *r = optional ? t[i]->uses_if_made : t[i]->needs; r && *r; r++) {
                int m = maker_of(t, n, *r);
                const char *why = NULL;
                if (m < 0) why = "no pass of the table makes it";
                else if (m > (int)i) why = "its maker records after it";
                else if (m < (int)i && !optional && !plan->entries[m].enabled) why = "its maker is off";
                if (!why) continue;
                if (err)
                    snprintf(err, err_size, "pass %s %s image '%s'%s%s, but %s%s%s", t[i]->id,
                             optional ? "uses" : "needs", *r, m >= 0 ? " of pass " : "", m >= 0 ? t[m]->id : "", why,
                             m >= 0 && !plan->entries[m].enabled ? ": " : "",
                             m >= 0 && !plan->entries[m].enabled ? plan->entries[m].reason : "");
                return FV_ERR_STATE;
            }
        }
    }
    return FV_OK;
}

void fv_frame_plan_build(const fv_scene *scene, fv_frame_plan *out)
{
    fv_quality q = fv_quality_default();
    fv_plan_context ctx = {.scene = scene, .multiview = true, .quality = &q};
    fv_frame_plan_build_ctx(&ctx, out);
}

const fv_plan_entry *fv_frame_plan_find(const fv_frame_plan *p, const char *pass)
{
    if (!p || !pass) return NULL;
    for (uint32_t i = 0; i < p->count; i++)
        if (strcmp(p->entries[i].pass, pass) == 0) return &p->entries[i];
    return NULL;
}
