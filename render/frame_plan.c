/* @brief The frame plan: which passes run for a scene and why, including the passes that do not exist yet. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "fv_renderer.h"

static void add(fv_frame_plan *p, const char *pass, bool enabled, const char *fmt, ...) FV_PRINTF(4, 5);

static void add(fv_frame_plan *p, const char *pass, bool enabled, const char *fmt, ...)
{
    if (p->count >= FV_MAX_PASSES) return;
    fv_plan_entry *e = &p->entries[p->count++];
    snprintf(e->pass, sizeof e->pass, "%s", pass);
    e->enabled = enabled;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->reason, sizeof e->reason, fmt, ap);
    va_end(ap);
}

static const char *plural(uint64_t n) { return n == 1 ? "" : "s"; }

void fv_frame_plan_build(const fv_scene *s, fv_frame_plan *out)
{
    memset(out, 0, sizeof *out);
    uint32_t draws = 0, animated = 0, translucent = 0, emissive = 0;
    uint32_t by_type[3] = {0, 0, 0};
    uint64_t triangles = 0;
    if (s) {
        for (uint32_t i = 0; i < s->node_count; i++) {
            const fv_node *n = &s->nodes[i];
            if (n->anim.kind != FV_ANIM_NONE) animated++;
            if (n->mesh < 0 || (uint32_t)n->mesh >= s->mesh_count) continue;
            draws++;
            triangles += s->meshes[n->mesh].index_count / 3;
        }
        /* Materials that some drawn mesh uses. */
        for (uint32_t m = 0; m < s->material_count; m++) {
            bool used = false;
            for (uint32_t i = 0; i < s->node_count && !used; i++) {
                const fv_node *n = &s->nodes[i];
                used = n->mesh >= 0 && (uint32_t)n->mesh < s->mesh_count && s->meshes[n->mesh].material == m;
            }
            if (!used) continue;
            const fv_material *mat = &s->materials[m];
            if (mat->translucency.enabled) translucent++;
            if (mat->emissive.x > 0 || mat->emissive.y > 0 || mat->emissive.z > 0) emissive++;
        }
        for (uint32_t l = 0; l < s->light_count; l++)
            if ((unsigned)s->lights[l].type < 3) by_type[s->lights[l].type]++;
        if (!fv_scene_is_animated(s)) animated = 0;
    }
    uint32_t lights = by_type[0] + by_type[1] + by_type[2];
    bool ambient = s && (s->ambient.x > 0 || s->ambient.y > 0 || s->ambient.z > 0);

    add(out, "gbuffer", true, "always: stereo G-buffer, both eyes in one multiview pass (%llu triangle%s in %u draw%s)",
        (unsigned long long)triangles, plural(triangles), draws, plural(draws));
    if (animated)
        add(out, "motion", true, "%u animated node%s: motion vectors from previous-frame transforms (G-buffer)", animated,
            plural(animated));
    else
        add(out, "motion", true, "static scene: motion vectors from head motion only (G-buffer)");
    if (lights)
        add(out, "shadow", false, "needed (%u light%s cast shadows) — not implemented yet: unshadowed", lights,
            plural(lights));
    else
        add(out, "shadow", false, "off — no lights");
    if (lights)
        add(out, "gi", false, "needed (one-bounce indirect light from %u light%s) — not implemented yet", lights,
            plural(lights));
    else
        add(out, "gi", false, "off — no lights");
    if (translucent)
        add(out, "sss", false, "needed (%u translucent material%s) — not implemented yet: shaded as opaque", translucent,
            plural(translucent));
    else
        add(out, "sss", false, "off — no translucent material");
    add(out, "fovea", false, "not implemented yet - every pixel shaded at full resolution");
    char what[120];
    int n = snprintf(what, sizeof what, "direct lighting from %u light%s (%u point, %u spot, %u directional)", lights,
                     plural(lights), by_type[FV_LIGHT_POINT], by_type[FV_LIGHT_SPOT], by_type[FV_LIGHT_DIRECTIONAL]);
    if (emissive && n > 0 && (size_t)n < sizeof what)
        n += snprintf(what + n, sizeof what - (size_t)n, " + %u emissive material%s", emissive, plural(emissive));
    if (ambient && n > 0 && (size_t)n < sizeof what) snprintf(what + n, sizeof what - (size_t)n, " + ambient");
    add(out, "shade", true, "%s%s", what, (!lights && !emissive && !ambient) ? " — nothing emits light: black" : "");
    add(out, "present", true, "tonemap (clamp) + sRGB encode into a headless target");
}

const fv_plan_entry *fv_frame_plan_find(const fv_frame_plan *p, const char *pass)
{
    if (!p || !pass) return NULL;
    for (uint32_t i = 0; i < p->count; i++)
        if (strcmp(p->entries[i].pass, pass) == 0) return &p->entries[i];
    return NULL;
}
