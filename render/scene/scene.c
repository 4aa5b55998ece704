/* @brief The in-memory scene: creation, growing arrays, node transforms with animation, queries, validation and
 * automatic head framing. */
#include "fv_scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "scene_internal.h"

/* The public struct is the first member, so an fv_scene* is an fv_scene_impl*. Capacities stay private. */
typedef struct fv_scene_impl {
    fv_scene pub;
    uint32_t cap_meshes, cap_nodes, cap_materials, cap_textures, cap_lights, cap_cameras;
} fv_scene_impl;

/* HMD field of view used to frame a scene: the narrowest half-angle of the default per-eye frustum
 * (fv_frame_input.h: outer 50, inner 42, up 45, down 48 degrees). */
#define FRAME_HALF_ANGLE_DEG 42.0
#define FRAME_MARGIN 1.08

void fv_scene_copy_name(char *dst, size_t cap, const char *src)
{
    if (!cap) return;
    if (!src) src = "";
    size_t n = strlen(src);
    bool cut = n >= cap;
    if (cut) {
        /* never silently: a cut name ends in "..." (when the buffer has room for it) */
        n = cap > 4 ? cap - 4 : cap - 1;
        /* cut before a UTF-8 character the buffer cannot hold whole (continuation bytes are 10xxxxxx) */
        while (n > 0 && ((unsigned char)src[n] & 0xC0u) == 0x80u) n--;
    }
    memcpy(dst, src, n);
    if (cut && cap > 4) {
        memcpy(dst + n, "...", 3);
        n += 3;
    }
    dst[n] = '\0';
}

fv_result fv_scene_create(const char *name, fv_scene **out_scene)
{
    if (!out_scene) return FV_ERR_INVALID_ARG;
    *out_scene = NULL;
    fv_scene_impl *impl = calloc(1, sizeof *impl);
    if (!impl) {
        FV_ERROR("scene", "out of memory creating scene '%s'", name ? name : "");
        return FV_ERR_NO_MEMORY;
    }
    fv_scene *s = &impl->pub;
    fv_scene_copy_name(s->name, sizeof s->name, name ? name : "scene");
    s->unit_scale_m = 1.0f;
    s->head.position_m = fv_v3(0, 0, 0);
    s->head.orientation = fv_quat_identity();
    s->head.ipd_mm = FV_SCENE_DEFAULT_IPD_MM;
    s->head.from_file = false;
    *out_scene = s;
    return FV_OK;
}

static void free_mesh_arrays(fv_mesh *m)
{
    free(m->positions);
    free(m->normals);
    free(m->texcoords);
    free(m->indices);
    m->positions = NULL;
    m->normals = NULL;
    m->texcoords = NULL;
    m->indices = NULL;
}

void fv_scene_destroy(fv_scene **scene)
{
    if (!scene || !*scene) return;
    fv_scene *s = *scene;
    for (uint32_t i = 0; i < s->mesh_count; i++) free_mesh_arrays(&s->meshes[i]);
    for (uint32_t i = 0; i < s->texture_count; i++) free(s->textures[i].rgba8);
    free(s->meshes);
    free(s->nodes);
    free(s->materials);
    free(s->textures);
    free(s->lights);
    free(s->cameras);
    free((fv_scene_impl *)s);
    *scene = NULL;
}

/* Make room for one more element in a growing array; doubles the capacity. */
static fv_result grow(const fv_scene *s, void **arr, uint32_t *cap, uint32_t count, size_t elem, const char *what)
{
    if (count >= FV_SCENE_MAX_ITEMS) {
        FV_ERROR("scene", "%s: too many %s (limit %u)", s->source[0] ? s->source : s->name, what,
                 FV_SCENE_MAX_ITEMS);
        return FV_ERR_RANGE;
    }
    if (count < *cap) return FV_OK;
    uint32_t ncap = *cap ? *cap * 2 : 8;
    if (ncap > FV_SCENE_MAX_ITEMS) ncap = FV_SCENE_MAX_ITEMS;
    void *p = realloc(*arr, (size_t)ncap * elem);
    if (!p) {
        FV_ERROR("scene", "%s: out of memory adding %s", s->source[0] ? s->source : s->name, what);
        return FV_ERR_NO_MEMORY;
    }
    *arr = p;
    *cap = ncap;
    return FV_OK;
}

fv_material fv_material_default(void)
{
    fv_material m;
    memset(&m, 0, sizeof m);
    fv_scene_copy_name(m.name, sizeof m.name, "default");
    m.base_color = fv_v3(0.8f, 0.8f, 0.8f);
    m.base_color_texture = -1;
    m.emissive = fv_v3(0, 0, 0);
    m.translucency.enabled = false;
    m.translucency.eta = 1.0f;
    return m;
}

fv_node fv_node_default(void)
{
    fv_node n;
    memset(&n, 0, sizeof n);
    n.mesh = -1;
    n.parent = -1;
    n.translation_m = fv_v3(0, 0, 0);
    n.rotation = fv_quat_identity();
    n.scale = fv_v3(1, 1, 1);
    n.anim.kind = FV_ANIM_NONE;
    n.anim.axis = fv_v3(0, 1, 0);
    return n;
}

static const char *src_of(const fv_scene *s) { return s->source[0] ? s->source : s->name; }

fv_result fv_scene_add_material(fv_scene *s, const fv_material *m, uint32_t *out_index)
{
    if (!s || !m) return FV_ERR_INVALID_ARG;
    fv_scene_impl *impl = (fv_scene_impl *)s;
    FV_TRY(grow(s, (void **)&s->materials, &impl->cap_materials, s->material_count, sizeof *m, "materials"));
    s->materials[s->material_count] = *m;
    if (out_index) *out_index = s->material_count;
    s->material_count++;
    return FV_OK;
}

/* Area-weighted vertex normals; degenerate or unreferenced vertices get +y, never NaN. */
static fv_result generate_normals(fv_mesh *m)
{
    fv_vec3 *n = calloc(m->vertex_count ? m->vertex_count : 1, sizeof *n);
    if (!n) return FV_ERR_NO_MEMORY;
    for (uint32_t t = 0; t + 2 < m->index_count; t += 3) {
        uint32_t a = m->indices[t], b = m->indices[t + 1], c = m->indices[t + 2];
        fv_vec3 e1 = fv_v3_sub(m->positions[b], m->positions[a]);
        fv_vec3 e2 = fv_v3_sub(m->positions[c], m->positions[a]);
        fv_vec3 fn = fv_v3_cross(e1, e2); /* length = 2 * area: area weighting for free */
        if (!fv_v3_isfinite(fn)) continue;
        n[a] = fv_v3_add(n[a], fn);
        n[b] = fv_v3_add(n[b], fn);
        n[c] = fv_v3_add(n[c], fn);
    }
    for (uint32_t v = 0; v < m->vertex_count; v++) n[v] = fv_v3_normalize_or(n[v], fv_v3(0, 1, 0));
    m->normals = n;
    return FV_OK;
}

fv_result fv_scene_add_mesh(fv_scene *s, fv_mesh *mesh, uint32_t *out_index)
{
    if (!s || !mesh) {
        if (mesh) free_mesh_arrays(mesh);
        return FV_ERR_INVALID_ARG;
    }
    fv_result r = FV_OK;
    const char *src = src_of(s);
    if (mesh->vertex_count > FV_SCENE_MAX_VERTICES || mesh->index_count > FV_SCENE_MAX_INDICES) {
        FV_ERROR("scene", "%s: mesh '%s': %u vertices / %u indices exceed the limits (%u / %u)", src, mesh->name,
                 mesh->vertex_count, mesh->index_count, FV_SCENE_MAX_VERTICES, FV_SCENE_MAX_INDICES);
        r = FV_ERR_RANGE;
        goto fail;
    }
    if (mesh->index_count % 3 != 0) {
        FV_ERROR("scene", "%s: mesh '%s': index count %u is not a multiple of 3", src, mesh->name,
                 mesh->index_count);
        r = FV_ERR_PARSE;
        goto fail;
    }
    if ((mesh->vertex_count && !mesh->positions) || (mesh->index_count && !mesh->indices)) {
        FV_ERROR("scene", "%s: mesh '%s': missing positions or indices", src, mesh->name);
        r = FV_ERR_INVALID_ARG;
        goto fail;
    }
    for (uint32_t i = 0; i < mesh->index_count; i++) {
        if (mesh->indices[i] >= mesh->vertex_count) {
            FV_ERROR("scene", "%s: mesh '%s': index %u (position %u) is past the vertex count %u", src, mesh->name,
                     mesh->indices[i], i, mesh->vertex_count);
            r = FV_ERR_PARSE;
            goto fail;
        }
    }
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        if (!fv_v3_isfinite(mesh->positions[v])) {
            FV_ERROR("scene", "%s: mesh '%s': vertex %u has a non-finite position", src, mesh->name, v);
            r = FV_ERR_RANGE;
            goto fail;
        }
    }
    if (!mesh->normals && mesh->vertex_count) {
        r = generate_normals(mesh);
        if (r < 0) {
            FV_ERROR("scene", "%s: mesh '%s': out of memory generating normals", src, mesh->name);
            goto fail;
        }
    } else {
        for (uint32_t v = 0; v < mesh->vertex_count; v++)
            mesh->normals[v] = fv_v3_normalize_or(mesh->normals[v], fv_v3(0, 1, 0));
    }
    if (mesh->texcoords) {
        for (uint32_t v = 0; v < mesh->vertex_count; v++) {
            if (!isfinite(mesh->texcoords[v].x) || !isfinite(mesh->texcoords[v].y)) mesh->texcoords[v] = (fv_vec2){0, 0};
        }
    }
    fv_vec3 lo = fv_v3(0, 0, 0), hi = fv_v3(0, 0, 0);
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        lo = v ? fv_v3_min(lo, mesh->positions[v]) : mesh->positions[v];
        hi = v ? fv_v3_max(hi, mesh->positions[v]) : mesh->positions[v];
    }
    mesh->bounds_min = lo;
    mesh->bounds_max = hi;
    fv_scene_impl *impl = (fv_scene_impl *)s;
    r = grow(s, (void **)&s->meshes, &impl->cap_meshes, s->mesh_count, sizeof *mesh, "meshes");
    if (r < 0) goto fail;
    s->meshes[s->mesh_count] = *mesh;
    if (out_index) *out_index = s->mesh_count;
    s->mesh_count++;
    return FV_OK;
fail:
    free_mesh_arrays(mesh);
    return r;
}

fv_result fv_scene_add_node(fv_scene *s, const fv_node *n, uint32_t *out_index)
{
    if (!s || !n) return FV_ERR_INVALID_ARG;
    if (n->parent >= 0 && (uint32_t)n->parent >= s->node_count) {
        FV_ERROR("scene", "%s: node '%s': parent %d must be added before the child (node %u)", src_of(s), n->name,
                 n->parent, s->node_count);
        return FV_ERR_INVALID_ARG;
    }
    fv_scene_impl *impl = (fv_scene_impl *)s;
    FV_TRY(grow(s, (void **)&s->nodes, &impl->cap_nodes, s->node_count, sizeof *n, "nodes"));
    s->nodes[s->node_count] = *n;
    if (out_index) *out_index = s->node_count;
    s->node_count++;
    return FV_OK;
}

fv_result fv_scene_add_light(fv_scene *s, const fv_light *l, uint32_t *out_index)
{
    if (!s || !l) return FV_ERR_INVALID_ARG;
    fv_scene_impl *impl = (fv_scene_impl *)s;
    FV_TRY(grow(s, (void **)&s->lights, &impl->cap_lights, s->light_count, sizeof *l, "lights"));
    s->lights[s->light_count] = *l;
    if (out_index) *out_index = s->light_count;
    s->light_count++;
    return FV_OK;
}

fv_result fv_scene_add_camera(fv_scene *s, const fv_camera *c, uint32_t *out_index)
{
    if (!s || !c) return FV_ERR_INVALID_ARG;
    fv_scene_impl *impl = (fv_scene_impl *)s;
    FV_TRY(grow(s, (void **)&s->cameras, &impl->cap_cameras, s->camera_count, sizeof *c, "cameras"));
    s->cameras[s->camera_count] = *c;
    if (out_index) *out_index = s->camera_count;
    s->camera_count++;
    return FV_OK;
}

fv_result fv_scene_add_texture(fv_scene *s, fv_texture *tex, uint32_t *out_index)
{
    if (!s || !tex) {
        if (tex) {
            free(tex->rgba8);
            tex->rgba8 = NULL;
        }
        return FV_ERR_INVALID_ARG;
    }
    fv_result r = FV_OK;
    if (!tex->rgba8 || tex->width == 0 || tex->height == 0 || tex->width > FV_SCENE_MAX_TEXTURE_DIM ||
        tex->height > FV_SCENE_MAX_TEXTURE_DIM) {
        FV_ERROR("scene", "%s: texture '%s': bad size %ux%u (limit %u) or no pixels", src_of(s), tex->source,
                 tex->width, tex->height, FV_SCENE_MAX_TEXTURE_DIM);
        r = FV_ERR_RANGE;
        goto fail;
    }
    fv_scene_impl *impl = (fv_scene_impl *)s;
    r = grow(s, (void **)&s->textures, &impl->cap_textures, s->texture_count, sizeof *tex, "textures");
    if (r < 0) goto fail;
    s->textures[s->texture_count] = *tex;
    if (out_index) *out_index = s->texture_count;
    s->texture_count++;
    return FV_OK;
fail:
    free(tex->rgba8);
    tex->rgba8 = NULL;
    return r;
}

/* ---- transforms ------------------------------------------------------------------------------------------- */

static fv_mat4 node_local(const fv_node *n, double t_s)
{
    fv_vec3 t = n->translation_m;
    fv_quat r = n->rotation;
    fv_vec3 sc = n->scale;
    const fv_animation *a = &n->anim;
    double ph = 2.0 * FV_PI * (double)a->freq_hz * t_s + (double)a->phase_rad;
    switch (a->kind) {
    case FV_ANIM_ROTATE: {
        /* Rotate about an axis through the node origin, in the parent frame: T * Ranim * R * S. Reduce the angle
         * modulo a turn in double so long run times stay accurate. */
        double ang = fmod((double)a->rate_rad_s * t_s, 2.0 * FV_PI);
        if (!isfinite(ang)) ang = 0.0;
        fv_quat q = fv_quat_axis_angle(fv_v3_normalize_or(a->axis, fv_v3(0, 1, 0)), (float)ang);
        r = fv_quat_normalize(fv_quat_mul(q, r));
        break;
    }
    case FV_ANIM_BOB: {
        float k = (float)sin(fmod(ph, 2.0 * FV_PI));
        if (isfinite(k)) t = fv_v3_add(t, fv_v3_scale(a->amplitude_m, k));
        break;
    }
    case FV_ANIM_PULSE: {
        float k = 1.0f + a->amplitude_m.x * (float)sin(fmod(ph, 2.0 * FV_PI));
        if (isfinite(k)) sc = fv_v3_scale(sc, k);
        break;
    }
    case FV_ANIM_NONE:
    default:
        break;
    }
    return fv_mat4_trs(t, r, sc);
}

fv_mat4 fv_scene_node_world(const fv_scene *s, uint32_t node, double t_s)
{
    if (!s || node >= s->node_count) return fv_mat4_identity();
    /* Walk up the parents (they have smaller indices, so the chain is finite); guard anyway. */
    fv_mat4 world = node_local(&s->nodes[node], t_s);
    int32_t p = s->nodes[node].parent;
    uint32_t guard = 0;
    while (p >= 0 && (uint32_t)p < s->node_count && guard++ < s->node_count) {
        fv_mat4 pl = node_local(&s->nodes[p], t_s);
        world = fv_mat4_mul(&pl, &world);
        p = s->nodes[p].parent;
    }
    return world;
}

bool fv_scene_is_animated(const fv_scene *s)
{
    if (!s) return false;
    for (uint32_t i = 0; i < s->node_count; i++) {
        const fv_animation *a = &s->nodes[i].anim;
        if (a->kind == FV_ANIM_ROTATE && a->rate_rad_s != 0.0f) return true;
        if ((a->kind == FV_ANIM_BOB || a->kind == FV_ANIM_PULSE) && a->freq_hz != 0.0f &&
            (a->amplitude_m.x != 0.0f || a->amplitude_m.y != 0.0f || a->amplitude_m.z != 0.0f))
            return true;
    }
    return false;
}

static bool node_draws(const fv_scene *s, const fv_node *n)
{
    return n->mesh >= 0 && (uint32_t)n->mesh < s->mesh_count;
}

bool fv_scene_has_translucency(const fv_scene *s)
{
    if (!s) return false;
    for (uint32_t i = 0; i < s->node_count; i++) {
        const fv_node *n = &s->nodes[i];
        if (!node_draws(s, n)) continue;
        uint32_t m = s->meshes[n->mesh].material;
        if (m < s->material_count && s->materials[m].translucency.enabled) return true;
    }
    return false;
}

bool fv_scene_node_bounds_grow(const fv_scene *s, uint32_t node, double t_s, fv_vec3 *lo, fv_vec3 *hi, bool any)
{
    if (!s || node >= s->node_count) return any;
    const fv_mesh *m = &s->meshes[s->nodes[node].mesh];
    fv_mat4 w = fv_scene_node_world(s, node, t_s);
    for (int c = 0; c < 8; c++) {
        fv_vec3 p = fv_v3((c & 1) ? m->bounds_max.x : m->bounds_min.x, (c & 2) ? m->bounds_max.y : m->bounds_min.y,
                          (c & 4) ? m->bounds_max.z : m->bounds_min.z);
        fv_vec3 q = fv_mat4_mul_point(&w, p);
        if (!fv_v3_isfinite(q)) continue;
        *lo = any ? fv_v3_min(*lo, q) : q;
        *hi = any ? fv_v3_max(*hi, q) : q;
        any = true;
    }
    return any;
}

bool fv_scene_world_bounds(const fv_scene *s, double t_s, fv_vec3 *out_min, fv_vec3 *out_max)
{
    if (!s) return false;
    bool any = false;
    fv_vec3 lo = fv_v3(0, 0, 0), hi = fv_v3(0, 0, 0);
    for (uint32_t i = 0; i < s->node_count; i++) {
        const fv_node *n = &s->nodes[i];
        if (!node_draws(s, n)) continue;
        if (!s->meshes[n->mesh].vertex_count) continue;
        any = fv_scene_node_bounds_grow(s, i, t_s, &lo, &hi, any);
    }
    if (any) {
        if (out_min) *out_min = lo;
        if (out_max) *out_max = hi;
    }
    return any;
}

uint64_t fv_scene_triangle_count(const fv_scene *s)
{
    if (!s) return 0;
    uint64_t n = 0;
    for (uint32_t i = 0; i < s->node_count; i++)
        if (node_draws(s, &s->nodes[i])) n += s->meshes[s->nodes[i].mesh].index_count / 3;
    return n;
}

/* ---- validation ------------------------------------------------------------------------------------------- */

/* The component of v farthest from 0 that is beyond FV_SCENE_MAX_COORD_M or not finite; false when none is. */
static bool v3_beyond(fv_vec3 v, double bound, double *out)
{
    const float c[3] = {v.x, v.y, v.z};
    for (int k = 0; k < 3; k++)
        if (!(fabs((double)c[k]) <= bound)) {
            *out = c[k];
            return true;
        }
    return false;
}

fv_result fv_scene_check_extent(const fv_scene *s)
{
    if (!s) return FV_ERR_INVALID_ARG;
    const char *src = src_of(s);
    const double B = FV_SCENE_MAX_COORD_M;
    int bad = 0;
    double v;
#define BEYOND(what, ...)                                                                                              \
    do {                                                                                                               \
        if (bad < 16)                                                                                                  \
            FV_ERROR("scene", "%s: " what ": %g is beyond the +-%g m bound of a position or size", src, __VA_ARGS__, v, \
                     B);                                                                                               \
        bad++;                                                                                                         \
    } while (0)
    for (uint32_t i = 0; i < s->node_count; i++) {
        const fv_node *n = &s->nodes[i];
        if (v3_beyond(n->translation_m, B, &v)) BEYOND("node %u '%s': translation (m)", i, n->name);
        if (v3_beyond(n->scale, B, &v)) BEYOND("node %u '%s': scale", i, n->name);
        if (v3_beyond(n->anim.amplitude_m, B, &v)) BEYOND("node %u '%s': animation amplitude", i, n->name);
        if (!node_draws(s, n) || !s->meshes[n->mesh].vertex_count) continue;
        const fv_mesh *m = &s->meshes[n->mesh];
        fv_mat4 w = fv_scene_node_world(s, i, 0.0);
        for (int c = 0; c < 8; c++) {
            fv_vec3 p = fv_v3((c & 1) ? m->bounds_max.x : m->bounds_min.x, (c & 2) ? m->bounds_max.y : m->bounds_min.y,
                              (c & 4) ? m->bounds_max.z : m->bounds_min.z);
            if (v3_beyond(fv_mat4_mul_point(&w, p), B, &v)) {
                BEYOND("node %u '%s': mesh '%s' in world space (m)", i, n->name, m->name);
                break;
            }
        }
    }
    for (uint32_t i = 0; i < s->light_count; i++)
        if (s->lights[i].type != FV_LIGHT_DIRECTIONAL && v3_beyond(s->lights[i].position_m, B, &v))
            BEYOND("light %u '%s': position (m)", i, s->lights[i].name);
    for (uint32_t i = 0; i < s->camera_count; i++)
        if (v3_beyond(s->cameras[i].position_m, B, &v)) BEYOND("camera %u '%s': position (m)", i, s->cameras[i].name);
    if (v3_beyond(s->head.position_m, B, &v)) BEYOND("head: position (m)%s", "");
#undef BEYOND
    if (bad > 16) FV_ERROR("scene", "%s: ... and %d more positions beyond the bound", src, bad - 16);
    return bad ? FV_ERR_RANGE : FV_OK;
}

static bool finite_quat(fv_quat q) { return isfinite(q.x) && isfinite(q.y) && isfinite(q.z) && isfinite(q.w); }

fv_result fv_scene_validate(const fv_scene *s)
{
    if (!s) return FV_ERR_INVALID_ARG;
    const char *src = src_of(s);
    int bad = 0;
#define BROKEN(...)                                                                                                    \
    do {                                                                                                               \
        if (bad < 32) FV_ERROR("scene", __VA_ARGS__);                                                                  \
        bad++;                                                                                                         \
    } while (0)
    if (!(isfinite(s->unit_scale_m) && s->unit_scale_m > 0.0f)) BROKEN("%s: unit_scale_m %g must be > 0", src, (double)s->unit_scale_m);
    if (s->mesh_count > FV_SCENE_MAX_ITEMS || s->node_count > FV_SCENE_MAX_ITEMS ||
        s->material_count > FV_SCENE_MAX_ITEMS || s->light_count > FV_SCENE_MAX_ITEMS ||
        s->texture_count > FV_SCENE_MAX_ITEMS || s->camera_count > FV_SCENE_MAX_ITEMS)
        BROKEN("%s: more than %u items of one kind", src, FV_SCENE_MAX_ITEMS);
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        const fv_mesh *m = &s->meshes[i];
        if (m->vertex_count > FV_SCENE_MAX_VERTICES) BROKEN("%s: mesh %u '%s': %u vertices exceed the limit %u", src, i, m->name, m->vertex_count, FV_SCENE_MAX_VERTICES);
        if (m->index_count > FV_SCENE_MAX_INDICES) BROKEN("%s: mesh %u '%s': %u indices exceed the limit %u", src, i, m->name, m->index_count, FV_SCENE_MAX_INDICES);
        if (m->index_count % 3) BROKEN("%s: mesh %u '%s': index count %u is not a multiple of 3", src, i, m->name, m->index_count);
        if ((m->vertex_count && (!m->positions || !m->normals)) || (m->index_count && !m->indices)) {
            BROKEN("%s: mesh %u '%s': missing vertex or index arrays", src, i, m->name);
            continue;
        }
        for (uint32_t k = 0; k < m->index_count; k++) {
            if (m->indices[k] >= m->vertex_count) {
                BROKEN("%s: mesh %u '%s': index %u at position %u is past the vertex count %u", src, i, m->name, m->indices[k], k, m->vertex_count);
                break;
            }
        }
        for (uint32_t v = 0; v < m->vertex_count; v++) {
            if (!fv_v3_isfinite(m->positions[v]) || !fv_v3_isfinite(m->normals[v])) {
                BROKEN("%s: mesh %u '%s': vertex %u has a non-finite position or normal", src, i, m->name, v);
                break;
            }
        }
        if (m->material >= s->material_count) BROKEN("%s: mesh %u '%s': material %u does not exist (%u materials)", src, i, m->name, m->material, s->material_count);
    }
    for (uint32_t i = 0; i < s->node_count; i++) {
        const fv_node *n = &s->nodes[i];
        if (n->mesh >= 0 && (uint32_t)n->mesh >= s->mesh_count) BROKEN("%s: node %u '%s': mesh %d does not exist", src, i, n->name, n->mesh);
        if (n->parent >= 0 && (uint32_t)n->parent >= i) BROKEN("%s: node %u '%s': parent %d must come before the node", src, i, n->name, n->parent);
        if (!fv_v3_isfinite(n->translation_m) || !fv_v3_isfinite(n->scale) || !finite_quat(n->rotation))
            BROKEN("%s: node %u '%s': non-finite transform", src, i, n->name);
        if (!fv_v3_isfinite(n->anim.axis) || !fv_v3_isfinite(n->anim.amplitude_m) || !isfinite(n->anim.rate_rad_s) ||
            !isfinite(n->anim.freq_hz) || !isfinite(n->anim.phase_rad))
            BROKEN("%s: node %u '%s': non-finite animation", src, i, n->name);
    }
    for (uint32_t i = 0; i < s->material_count; i++) {
        const fv_material *m = &s->materials[i];
        if (!fv_v3_isfinite(m->base_color) || m->base_color.x < 0 || m->base_color.y < 0 || m->base_color.z < 0)
            BROKEN("%s: material %u '%s': base colour must be finite and >= 0", src, i, m->name);
        if (!fv_v3_isfinite(m->emissive) || m->emissive.x < 0 || m->emissive.y < 0 || m->emissive.z < 0)
            BROKEN("%s: material %u '%s': emissive must be finite and >= 0", src, i, m->name);
        if (m->base_color_texture >= 0 && (uint32_t)m->base_color_texture >= s->texture_count)
            BROKEN("%s: material %u '%s': texture %d does not exist", src, i, m->name, m->base_color_texture);
        const fv_translucency *t = &m->translucency;
        if (t->enabled) {
            bool any_s = false;
            for (int c = 0; c < 3; c++) {
                const char *why = fv_translucency_coefficient_problem(t->sigma_a_per_mm[c]);
                if (why) BROKEN("%s: material %u '%s': sigma_a_per_mm[%d] = %g %s", src, i, m->name, c, (double)t->sigma_a_per_mm[c], why);
                why = fv_translucency_coefficient_problem(t->sigma_s_prime_per_mm[c]);
                if (why) BROKEN("%s: material %u '%s': sigma_s_prime_per_mm[%d] = %g %s", src, i, m->name, c, (double)t->sigma_s_prime_per_mm[c], why);
                if (t->sigma_s_prime_per_mm[c] > 0) any_s = true;
            }
            if (!any_s) BROKEN("%s: material %u '%s': sigma_s_prime_per_mm is all zero", src, i, m->name);
            if (!isfinite(t->eta) || t->eta <= 0) BROKEN("%s: material %u '%s': eta %g must be > 0", src, i, m->name, (double)t->eta);
        }
    }
    for (uint32_t i = 0; i < s->texture_count; i++) {
        const fv_texture *t = &s->textures[i];
        if (!t->rgba8 || !t->width || !t->height || t->width > FV_SCENE_MAX_TEXTURE_DIM || t->height > FV_SCENE_MAX_TEXTURE_DIM)
            BROKEN("%s: texture %u '%s': bad size %ux%u or no pixels", src, i, t->source, t->width, t->height);
    }
    for (uint32_t i = 0; i < s->light_count; i++) {
        const fv_light *l = &s->lights[i];
        if (l->type != FV_LIGHT_POINT && l->type != FV_LIGHT_SPOT && l->type != FV_LIGHT_DIRECTIONAL)
            BROKEN("%s: light %u '%s': unknown type %d", src, i, l->name, (int)l->type);
        if (!fv_v3_isfinite(l->position_m) || !fv_v3_isfinite(l->direction) || !fv_v3_isfinite(l->color) ||
            !isfinite(l->intensity) || !isfinite(l->range_m) || !isfinite(l->inner_cone_rad) || !isfinite(l->outer_cone_rad))
            BROKEN("%s: light %u '%s': non-finite value", src, i, l->name);
        if (l->intensity < 0 || l->color.x < 0 || l->color.y < 0 || l->color.z < 0 || l->range_m < 0)
            BROKEN("%s: light %u '%s': negative colour, intensity or range", src, i, l->name);
        if (l->type != FV_LIGHT_POINT && !(fv_v3_len(l->direction) > 1e-6f))
            BROKEN("%s: light %u '%s': direction is zero", src, i, l->name);
        if (l->type == FV_LIGHT_SPOT && !(l->inner_cone_rad >= 0 && l->inner_cone_rad <= l->outer_cone_rad && l->outer_cone_rad <= (float)(FV_PI / 2) + 1e-5f))
            BROKEN("%s: light %u '%s': cone angles need 0 <= inner <= outer <= 90 deg (got %g, %g deg)", src, i, l->name,
                   fv_rad_to_deg(l->inner_cone_rad), fv_rad_to_deg(l->outer_cone_rad));
    }
    for (uint32_t i = 0; i < s->camera_count; i++) {
        const fv_camera *c = &s->cameras[i];
        if (!fv_v3_isfinite(c->position_m) || !finite_quat(c->orientation) || !isfinite(c->yfov_rad) ||
            !isfinite(c->near_m) || !isfinite(c->far_m) || c->yfov_rad < 0 || c->yfov_rad >= (float)FV_PI)
            BROKEN("%s: camera %u '%s': non-finite or out-of-range value", src, i, c->name);
    }
    if (!fv_v3_isfinite(s->head.position_m) || !finite_quat(s->head.orientation))
        BROKEN("%s: head: non-finite pose", src);
    if (!(isfinite(s->head.ipd_mm) && s->head.ipd_mm > 0.0f && s->head.ipd_mm <= FV_SCENE_MAX_IPD_MM))
        BROKEN("%s: head: ipd_mm %g must be in (0, %g]", src, (double)s->head.ipd_mm, (double)FV_SCENE_MAX_IPD_MM);
    if (!fv_v3_isfinite(s->ambient)) BROKEN("%s: ambient must be finite", src);
#undef BROKEN
    if (bad > 32) FV_ERROR("scene", "%s: ... and %d more problems", src, bad - 32);
    if (!bad && fv_scene_check_extent(s) < 0) return FV_ERR_RANGE; /* finite, but too far out */
    return bad ? FV_ERR_PARSE : FV_OK;
}

/* ---- cost ------------------------------------------------------------------------------------------------- */

uint64_t fv_scene_light_evaluations(const fv_scene *s, uint32_t eye_w, uint32_t eye_h)
{
    if (!s) return 0;
    uint64_t px = 2u * (uint64_t)eye_w * eye_h, n = s->light_count;
    return n && px > UINT64_MAX / n ? UINT64_MAX : n * px;
}

bool fv_scene_warn_cost(const fv_scene *s, uint32_t eye_w, uint32_t eye_h, const char *who)
{
    if (!s || s->light_count <= FV_SCENE_LIGHTS_WARN) return false;
    FV_WARN("scene", "%s: %u lights, and %s sums every light at every pixel: about %.2g light evaluations a frame at "
            "%ux%u per eye (%.2g at the default 720x800; lavapipe manages about 1.5e8 a second); keep to %u lights or "
            "fewer (merge them, or drop the faint and far ones) or render smaller", src_of(s), s->light_count,
            who ? who : "the renderer", (double)fv_scene_light_evaluations(s, eye_w, eye_h), eye_w, eye_h,
            (double)fv_scene_light_evaluations(s, 720, 800), FV_SCENE_LIGHTS_WARN);
    return true;
}

/* ---- head ------------------------------------------------------------------------------------------------- */
static bool node_draws(const fv_scene *s, const fv_node *n);

void fv_scene_head_look_at(fv_head *head, fv_vec3 position_m, fv_vec3 target_m)
{
    if (!head) return;
    head->position_m = position_m;
    head->orientation = fv_quat_look_along(fv_v3_normalize_or(fv_v3_sub(target_m, position_m), fv_v3(0, 0, -1)));
}

void fv_scene_frame_head(fv_scene *s)
{
    if (!s) return;
    fv_vec3 lo, hi;
    float ipd = s->head.ipd_mm;
    if (!fv_scene_world_bounds(s, 0.0, &lo, &hi)) {
        s->head.position_m = fv_v3(0, 0, 0);
        s->head.orientation = fv_quat_identity();
        s->head.from_file = false;
        return;
    }
    /* Bounding sphere of the box, seen from the +z side: at distance d = r / sin(half-angle) the sphere touches
     * the narrowest side of the HMD frustum; a small margin keeps the edges visible. */
    fv_vec3 c = fv_v3_scale(fv_v3_add(lo, hi), 0.5f);
    double r = 0.5 * fv_v3_len(fv_v3_sub(hi, lo));
    if (!(r > 1e-6)) r = 1e-6;
    double d = FRAME_MARGIN * r / sin(fv_deg_to_rad(FRAME_HALF_ANGLE_DEG));
    /* Look from +z unless clearly more surface faces -z (a box open towards -z, like the measured Cornell data in
     * its own frame): sum the area seen front-on from each side. */
    double towards_pz = 0, towards_nz = 0;
    for (uint32_t i = 0; i < s->node_count; i++) {
        const fv_node *n = &s->nodes[i];
        if (!node_draws(s, n)) continue;
        const fv_mesh *m = &s->meshes[n->mesh];
        fv_mat4 w = fv_scene_node_world(s, i, 0.0);
        for (uint32_t t = 0; t + 2 < m->index_count; t += 3) {
            fv_vec3 a = fv_mat4_mul_point(&w, m->positions[m->indices[t]]);
            fv_vec3 b = fv_mat4_mul_point(&w, m->positions[m->indices[t + 1]]);
            fv_vec3 e = fv_mat4_mul_point(&w, m->positions[m->indices[t + 2]]);
            double z = 0.5 * (double)fv_v3_cross(fv_v3_sub(b, a), fv_v3_sub(e, a)).z; /* signed area along z */
            if (!isfinite(z)) continue;
            if (z > 0) towards_pz += z;
            else towards_nz -= z;
        }
    }
    double side = towards_nz > 1.5 * towards_pz ? -1.0 : 1.0;
    fv_vec3 eye = fv_v3(c.x, c.y, (float)(c.z + side * d));
    if (!fv_v3_isfinite(eye)) eye = fv_v3(c.x, c.y, c.z + 1.0f);
    fv_scene_head_look_at(&s->head, eye, c);
    s->head.ipd_mm = (isfinite(ipd) && ipd > 0) ? ipd : FV_SCENE_DEFAULT_IPD_MM;
    s->head.from_file = false;
}

/* ---- merging (scene files compose several models) -------------------------------------------------------- */

fv_result fv_scene_merge(fv_scene *dst, fv_scene *src, const fv_scene_merge_desc *desc)
{
    if (!dst || !src || !desc) return FV_ERR_INVALID_ARG;
    uint32_t tex_base = dst->texture_count, mat_base = dst->material_count, mesh_base = dst->mesh_count;
    for (uint32_t i = 0; i < src->texture_count; i++) {
        fv_texture t = src->textures[i];
        src->textures[i].rgba8 = NULL; /* ownership moves even on failure */
        FV_TRY(fv_scene_add_texture(dst, &t, NULL));
    }
    for (uint32_t i = 0; i < src->material_count; i++) {
        fv_material m = src->materials[i];
        if (m.base_color_texture >= 0) m.base_color_texture += (int32_t)tex_base;
        if (desc->override) {
            if (desc->override_mask & FV_MERGE_BASE_COLOR) {
                m.base_color = desc->override->base_color;
                m.base_color_texture = -1;
            }
            if (desc->override_mask & FV_MERGE_TRANSLUCENCY) m.translucency = desc->override->translucency;
            if (desc->override_mask & FV_MERGE_EMISSIVE) m.emissive = desc->override->emissive;
        }
        FV_TRY(fv_scene_add_material(dst, &m, NULL));
    }
    for (uint32_t i = 0; i < src->mesh_count; i++) {
        fv_mesh m = src->meshes[i];
        memset(&src->meshes[i], 0, sizeof src->meshes[i]);
        src->meshes[i].vertex_count = 0;
        m.material += mat_base;
        /* Arrays are already checked and normals present: append directly without re-checking. */
        fv_scene_impl *impl = (fv_scene_impl *)dst;
        fv_result r = grow(dst, (void **)&dst->meshes, &impl->cap_meshes, dst->mesh_count, sizeof m, "meshes");
        if (r < 0) {
            free_mesh_arrays(&m);
            return r;
        }
        dst->meshes[dst->mesh_count++] = m;
    }
    int32_t root_index = -1;
    if (desc->root) {
        uint32_t ri;
        fv_node root = *desc->root;
        root.mesh = -1;
        root.parent = -1;
        FV_TRY(fv_scene_add_node(dst, &root, &ri));
        root_index = (int32_t)ri;
    }
    uint32_t node_base = dst->node_count;
    for (uint32_t i = 0; i < src->node_count; i++) {
        fv_node n = src->nodes[i];
        if (n.mesh >= 0) n.mesh += (int32_t)mesh_base;
        n.parent = n.parent >= 0 ? n.parent + (int32_t)node_base : root_index;
        FV_TRY(fv_scene_add_node(dst, &n, NULL));
    }
    if (desc->take_lights) {
        fv_mat4 w = desc->root ? fv_mat4_trs(desc->root->translation_m, desc->root->rotation, desc->root->scale)
                               : fv_mat4_identity();
        for (uint32_t i = 0; i < src->light_count; i++) {
            fv_light l = src->lights[i];
            l.position_m = fv_mat4_mul_point(&w, l.position_m);
            l.direction = fv_v3_normalize_or(fv_mat4_mul_dir(&w, l.direction), l.direction);
            FV_TRY(fv_scene_add_light(dst, &l, NULL));
        }
    }
    return FV_OK;
}
