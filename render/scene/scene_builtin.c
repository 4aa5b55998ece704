/* @brief Built-in procedural scenes: `cornell` (the measured Cornell box with a spot light under the ceiling, as in
 * Ki & Oh's light-tree scenes), `cornell-translucent` (the same plus a marble sphere, Jensen et al. 2001) and
 * `pillars` (a ground plane 400 m long with a grid of columns and boxes under a low sun: the large depth range that
 * parallel-split shadow maps are about, Zhang et al. 2006).
 *
 * Geometry: the Cornell box measurements (Cornell University Program of Computer Graphics, "Cornell Box Data",
 * millimetres; its camera looks along +z with +x to the viewer's left). We rotate it 180 degrees about +y and
 * centre it so that, in fovea's frame, the open side faces +z, the red wall is on the left (-x) and the green
 * wall on the right (+x), the floor is at y = 0 and the back wall at z = -0.2796 m. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_scene.h"
#include "scene_internal.h"

/* Measured reflectances commonly used for the Cornell box walls (linear RGB). */
#define CB_WHITE fv_v3(0.725f, 0.71f, 0.68f)
#define CB_RED fv_v3(0.63f, 0.065f, 0.05f)
#define CB_GREEN fv_v3(0.14f, 0.45f, 0.091f)

static const char *const g_builtin_names[] = {"cornell", "cornell-translucent", "pillars", NULL};

const char *const *fv_scene_builtin_names(void) { return g_builtin_names; }

/* ---- a tiny mesh builder ---------------------------------------------------------------------------------- */

typedef struct builder {
    fv_vec3 *p, *n;
    fv_vec2 *uv;
    uint32_t *idx;
    uint32_t nv, ni, cap_v, cap_i;
    bool oom;
} builder;

static bool reserve(builder *b, uint32_t add_v, uint32_t add_i)
{
    if (b->oom) return false;
    if (b->nv + add_v > b->cap_v) {
        uint32_t cap = b->cap_v ? b->cap_v : 64;
        while (cap < b->nv + add_v) cap *= 2;
        fv_vec3 *p = realloc(b->p, cap * sizeof *p);
        if (p) b->p = p;
        fv_vec3 *n = realloc(b->n, cap * sizeof *n);
        if (n) b->n = n;
        fv_vec2 *uv = realloc(b->uv, cap * sizeof *uv);
        if (uv) b->uv = uv;
        if (!p || !n || !uv) {
            b->oom = true;
            return false;
        }
        b->cap_v = cap;
    }
    if (b->ni + add_i > b->cap_i) {
        uint32_t cap = b->cap_i ? b->cap_i : 96;
        while (cap < b->ni + add_i) cap *= 2;
        uint32_t *idx = realloc(b->idx, cap * sizeof *idx);
        if (!idx) {
            b->oom = true;
            return false;
        }
        b->idx = idx;
        b->cap_i = cap;
    }
    return true;
}

static void builder_free(builder *b)
{
    free(b->p);
    free(b->n);
    free(b->uv);
    free(b->idx);
    memset(b, 0, sizeof *b);
}

/* Measured millimetres (Cornell frame) to fovea metres: rotate 180 degrees about y, centre x and z. */
static fv_vec3 cb(float x_mm, float y_mm, float z_mm)
{
    return fv_v3((278.0f - x_mm) * 0.001f, y_mm * 0.001f, (279.6f - z_mm) * 0.001f);
}

/* A planar quad with a flat normal that points to the same side as `facing` (winding made counter-clockwise as
 * seen from that side). UVs span [0,1]^2 over the corners. */
static void add_quad(builder *b, fv_vec3 a, fv_vec3 c1, fv_vec3 c2, fv_vec3 c3, fv_vec3 facing)
{
    if (!reserve(b, 4, 6)) return;
    fv_vec3 q[4] = {a, c1, c2, c3};
    fv_vec3 n = fv_v3_cross(fv_v3_sub(q[1], q[0]), fv_v3_sub(q[2], q[0]));
    if (fv_v3_dot(n, facing) < 0.0f) {
        fv_vec3 t = q[1];
        q[1] = q[3];
        q[3] = t;
        n = fv_v3_scale(n, -1.0f);
    }
    n = fv_v3_normalize_or(n, fv_v3_normalize_or(facing, fv_v3(0, 1, 0)));
    static const fv_vec2 uv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    uint32_t base = b->nv;
    for (int i = 0; i < 4; i++) {
        b->p[b->nv] = q[i];
        b->n[b->nv] = n;
        b->uv[b->nv] = uv[i];
        b->nv++;
    }
    static const uint32_t tri[6] = {0, 1, 2, 0, 2, 3};
    for (int i = 0; i < 6; i++) b->idx[b->ni++] = base + tri[i];
}

/* A block: the measured top quad extruded down to the floor (sides and top, normals outwards). */
static void add_block(builder *b, const float top_mm[4][2], float height_mm)
{
    fv_vec3 t[4], f[4], centre = fv_v3(0, 0, 0);
    for (int i = 0; i < 4; i++) {
        t[i] = cb(top_mm[i][0], height_mm, top_mm[i][1]);
        f[i] = cb(top_mm[i][0], 0.0f, top_mm[i][1]);
        centre = fv_v3_add(centre, fv_v3_scale(fv_v3_add(t[i], f[i]), 0.125f));
    }
    add_quad(b, t[0], t[1], t[2], t[3], fv_v3(0, 1, 0));
    for (int i = 0; i < 4; i++) {
        int j = (i + 1) % 4;
        fv_vec3 mid = fv_v3_scale(fv_v3_add(t[i], f[j]), 0.5f);
        add_quad(b, f[i], f[j], t[j], t[i], fv_v3_sub(mid, centre));
    }
}

/* UV sphere: `rings` latitude bands, `segments` longitude slices; normals radial, uv = (longitude, latitude). */
static void add_sphere(builder *b, fv_vec3 c, float r, uint32_t segments, uint32_t rings)
{
    if (!reserve(b, (segments + 1) * (rings + 1), segments * rings * 6)) return;
    uint32_t base = b->nv;
    for (uint32_t i = 0; i <= rings; i++) {
        double th = FV_PI * (double)i / rings;
        for (uint32_t j = 0; j <= segments; j++) {
            double ph = 2.0 * FV_PI * (double)j / segments;
            fv_vec3 n = fv_v3((float)(sin(th) * cos(ph)), (float)cos(th), (float)(-sin(th) * sin(ph)));
            b->p[b->nv] = fv_v3_add(c, fv_v3_scale(n, r));
            b->n[b->nv] = fv_v3_normalize_or(n, fv_v3(0, 1, 0));
            b->uv[b->nv] = (fv_vec2){(float)j / segments, (float)i / rings};
            b->nv++;
        }
    }
    for (uint32_t i = 0; i < rings; i++) {
        for (uint32_t j = 0; j < segments; j++) {
            uint32_t a = base + i * (segments + 1) + j, d = a + segments + 1;
            /* counter-clockwise seen from outside */
            uint32_t tri[6] = {a, d, a + 1, a + 1, d, d + 1};
            for (int k = 0; k < 6; k++) b->idx[b->ni++] = tri[k];
        }
    }
}

/* Hand the builder's arrays to a new mesh + node in the scene (ownership moves; the builder is reset). */
static fv_result emit(fv_scene *s, builder *b, const char *name, uint32_t material)
{
    if (b->oom) {
        builder_free(b);
        FV_ERROR("scene", "builtin:%s: out of memory building mesh '%s'", s->name, name);
        return FV_ERR_NO_MEMORY;
    }
    fv_mesh m;
    memset(&m, 0, sizeof m);
    fv_scene_copy_name(m.name, sizeof m.name, name);
    m.vertex_count = b->nv;
    m.index_count = b->ni;
    m.positions = b->p;
    m.normals = b->n;
    m.texcoords = b->uv;
    m.indices = b->idx;
    m.material = material;
    memset(b, 0, sizeof *b);
    uint32_t mi;
    FV_TRY(fv_scene_add_mesh(s, &m, &mi));
    fv_node n = fv_node_default();
    fv_scene_copy_name(n.name, sizeof n.name, name);
    n.mesh = (int32_t)mi;
    return fv_scene_add_node(s, &n, NULL);
}

static fv_result add_named_material(fv_scene *s, const char *name, fv_vec3 color, fv_vec3 emissive, uint32_t *out)
{
    fv_material m = fv_material_default();
    fv_scene_copy_name(m.name, sizeof m.name, name);
    m.base_color = color;
    m.emissive = emissive;
    return fv_scene_add_material(s, &m, out);
}

static fv_result build_cornell(fv_scene *s)
{
    uint32_t white, red, green, lamp;
    FV_TRY(add_named_material(s, "white", CB_WHITE, fv_v3(0, 0, 0), &white));
    FV_TRY(add_named_material(s, "red", CB_RED, fv_v3(0, 0, 0), &red));
    FV_TRY(add_named_material(s, "green", CB_GREEN, fv_v3(0, 0, 0), &green));
    /* The lamp's visible face; its emission ratio follows the measured light spectrum (about 17:12:4). */
    FV_TRY(add_named_material(s, "lamp", fv_v3(0.78f, 0.78f, 0.78f), fv_v3(17.0f, 12.0f, 4.0f), &lamp));

    builder b;
    memset(&b, 0, sizeof b);
    /* floor, ceiling and back wall (white) */
    add_quad(&b, cb(552.8f, 0, 0), cb(0, 0, 0), cb(0, 0, 559.2f), cb(549.6f, 0, 559.2f), fv_v3(0, 1, 0));
    add_quad(&b, cb(556.0f, 548.8f, 0), cb(556.0f, 548.8f, 559.2f), cb(0, 548.8f, 559.2f), cb(0, 548.8f, 0),
             fv_v3(0, -1, 0));
    add_quad(&b, cb(549.6f, 0, 559.2f), cb(0, 0, 559.2f), cb(0, 548.8f, 559.2f), cb(556.0f, 548.8f, 559.2f),
             fv_v3(0, 0, 1));
    FV_TRY(emit(s, &b, "white_walls", white));
    /* red wall: measured x = 552.8..556, which becomes fovea's left (-x) */
    add_quad(&b, cb(552.8f, 0, 0), cb(549.6f, 0, 559.2f), cb(556.0f, 548.8f, 559.2f), cb(556.0f, 548.8f, 0),
             fv_v3(1, 0, 0));
    FV_TRY(emit(s, &b, "left_wall_red", red));
    /* green wall: measured x = 0, fovea's right (+x) */
    add_quad(&b, cb(0, 0, 559.2f), cb(0, 0, 0), cb(0, 548.8f, 0), cb(0, 548.8f, 559.2f), fv_v3(-1, 0, 0));
    FV_TRY(emit(s, &b, "right_wall_green", green));
    /* the two blocks, rotated as measured (top quads from the data, extruded to the floor) */
    static const float short_top[4][2] = {{130.0f, 65.0f}, {82.0f, 225.0f}, {240.0f, 272.0f}, {290.0f, 114.0f}};
    static const float tall_top[4][2] = {{423.0f, 247.0f}, {265.0f, 296.0f}, {314.0f, 456.0f}, {472.0f, 406.0f}};
    add_block(&b, short_top, 165.0f);
    FV_TRY(emit(s, &b, "short_block", white));
    add_block(&b, tall_top, 330.0f);
    FV_TRY(emit(s, &b, "tall_block", white));
    /* the lamp: the measured light quad, 1 mm under the ceiling, facing down */
    add_quad(&b, cb(343.0f, 547.8f, 227.0f), cb(343.0f, 547.8f, 332.0f), cb(213.0f, 547.8f, 332.0f),
             cb(213.0f, 547.8f, 227.0f), fv_v3(0, -1, 0));
    FV_TRY(emit(s, &b, "lamp", lamp));

    /* A spot light just under the ceiling at the lamp's centre, aiming straight down (Ki & Oh's Cornell scenes).
     * Radiant intensity: about 1 W/sr gives floor radiance near 0.8 for the white albedo. */
    fv_light l;
    memset(&l, 0, sizeof l);
    fv_scene_copy_name(l.name, sizeof l.name, "ceiling_spot");
    l.type = FV_LIGHT_SPOT;
    l.position_m = cb(278.0f, 540.0f, 279.5f);
    l.direction = fv_v3(0, -1, 0);
    l.color = fv_v3(1.0f, 0.85f, 0.65f);
    l.intensity = 1.0f;
    l.range_m = 0.0f;
    l.inner_cone_rad = (float)fv_deg_to_rad(45.0);
    l.outer_cone_rad = (float)fv_deg_to_rad(70.0);
    FV_TRY(fv_scene_add_light(s, &l, NULL));

    /* The measured camera stands at (278, 273, -800 mm) with a 39 degree field of view; an HMD sees about 95
     * degrees, so the head stands closer, 270 mm in front of the opening, where the box fills the view as it
     * fills the classic image. Looking at the box centre; IPD 63 mm. */
    fv_scene_head_look_at(&s->head, cb(278.0f, 273.0f, -270.0f), cb(278.0f, 273.0f, 279.6f));
    s->head.ipd_mm = FV_SCENE_DEFAULT_IPD_MM;
    s->head.from_file = true;
    return FV_OK;
}

static fv_result build_cornell_translucent(fv_scene *s)
{
    FV_TRY(build_cornell(s));
    fv_material m = fv_material_default();
    fv_scene_copy_name(m.name, sizeof m.name, "marble");
    m.base_color = fv_v3(0.83f, 0.79f, 0.75f);
    FV_TRY(fv_translucency_preset("marble", &m.translucency));
    uint32_t mi;
    FV_TRY(fv_scene_add_material(s, &m, &mi));
    builder b;
    memset(&b, 0, sizeof b);
    /* A marble ball resting on the floor in the free front-left quarter, clear of both blocks. */
    const float r = 0.08f;
    add_sphere(&b, fv_v3(-0.14f, r, 0.16f), r, 48, 24);
    return emit(s, &b, "marble_sphere", mi);
}

/* An axis-aligned box from min to max corner (six quads, normals outwards). */
static void add_box(builder *b, fv_vec3 lo, fv_vec3 hi)
{
    fv_vec3 c[8];
    for (int i = 0; i < 8; i++) c[i] = fv_v3((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    add_quad(b, c[0], c[1], c[3], c[2], fv_v3(0, 0, -1)); /* z = lo */
    add_quad(b, c[4], c[5], c[7], c[6], fv_v3(0, 0, 1));  /* z = hi */
    add_quad(b, c[0], c[2], c[6], c[4], fv_v3(-1, 0, 0)); /* x = lo */
    add_quad(b, c[1], c[3], c[7], c[5], fv_v3(1, 0, 0));  /* x = hi */
    add_quad(b, c[0], c[1], c[5], c[4], fv_v3(0, -1, 0)); /* y = lo */
    add_quad(b, c[2], c[3], c[7], c[6], fv_v3(0, 1, 0));  /* y = hi */
}

#define PILLARS_LENGTH_M 400.0f /* ground along -z from the viewer */
#define PILLARS_WIDTH_M 60.0f
#define PILLARS_ROWS 20         /* columns every 20 m in depth */
#define PILLARS_COLUMNS 3       /* at x = -6, 0, +6 m */

static fv_result build_pillars(fv_scene *s)
{
    uint32_t ground, stone, crate;
    FV_TRY(add_named_material(s, "ground", fv_v3(0.55f, 0.52f, 0.45f), fv_v3(0, 0, 0), &ground));
    FV_TRY(add_named_material(s, "stone", fv_v3(0.75f, 0.74f, 0.72f), fv_v3(0, 0, 0), &stone));
    FV_TRY(add_named_material(s, "crate", fv_v3(0.60f, 0.38f, 0.20f), fv_v3(0, 0, 0), &crate));
    builder b;
    memset(&b, 0, sizeof b);
    float w = PILLARS_WIDTH_M * 0.5f;
    add_quad(&b, fv_v3(-w, 0, 10.0f), fv_v3(w, 0, 10.0f), fv_v3(w, 0, -PILLARS_LENGTH_M), fv_v3(-w, 0, -PILLARS_LENGTH_M),
             fv_v3(0, 1, 0));
    FV_TRY(emit(s, &b, "ground", ground));
    /* Columns 0.8 m square, 6 m tall, from 5 m in front of the viewer to the far end. */
    for (int r = 0; r < PILLARS_ROWS; r++)
        for (int c = 0; c < PILLARS_COLUMNS; c++) {
            float x = -6.0f + 6.0f * (float)c, z = -5.0f - 20.0f * (float)r;
            add_box(&b, fv_v3(x - 0.4f, 0.0f, z - 0.4f), fv_v3(x + 0.4f, 6.0f, z + 0.4f));
        }
    FV_TRY(emit(s, &b, "columns", stone));
    /* A few boxes near and far, so that contact shadows at every depth can be seen. */
    static const float boxes[][4] = {{-2.5f, -3.0f, 0.6f, 0.6f}, {2.0f, -8.0f, 1.0f, 1.5f}, {-3.5f, -30.0f, 1.5f, 1.0f},
                                     {3.0f, -75.0f, 2.0f, 2.0f}, {-2.0f, -150.0f, 3.0f, 3.0f}};
    for (size_t i = 0; i < sizeof boxes / sizeof boxes[0]; i++) {
        float x = boxes[i][0], z = boxes[i][1], hw = boxes[i][2] * 0.5f, h = boxes[i][3];
        add_box(&b, fv_v3(x - hw, 0.0f, z - hw), fv_v3(x + hw, h, z + hw));
    }
    FV_TRY(emit(s, &b, "boxes", crate));
    /* A sun 15 degrees above the horizon, from the front left: long shadows over the whole depth range. */
    fv_light l;
    memset(&l, 0, sizeof l);
    fv_scene_copy_name(l.name, sizeof l.name, "sun");
    l.type = FV_LIGHT_DIRECTIONAL;
    double elev = fv_deg_to_rad(15.0), az = fv_deg_to_rad(35.0);
    l.direction = fv_v3((float)(cos(elev) * sin(az)), (float)-sin(elev), (float)(-cos(elev) * cos(az)));
    l.color = fv_v3(1.0f, 0.95f, 0.85f);
    l.intensity = 3.0f; /* W/m^2: a white surface facing the sun reflects about 0.7 */
    FV_TRY(fv_scene_add_light(s, &l, NULL));
    s->ambient = fv_v3(0.03f, 0.035f, 0.045f);
    /* Standing eye height, looking down the avenue of columns, slightly down. */
    fv_scene_head_look_at(&s->head, fv_v3(0.0f, 1.7f, 2.0f), fv_v3(0.0f, 1.0f, -30.0f));
    s->head.ipd_mm = FV_SCENE_DEFAULT_IPD_MM;
    s->head.from_file = true;
    return FV_OK;
}

fv_result fv_scene_builtin(const char *name, fv_scene **out_scene)
{
    if (!name || !out_scene) return FV_ERR_INVALID_ARG;
    *out_scene = NULL;
    fv_result (*build)(fv_scene *) = NULL;
    const char *canon = NULL;
    if (!strcmp(name, "cornell")) {
        build = build_cornell;
        canon = "cornell";
    } else if (!strcmp(name, "cornell-translucent")) {
        build = build_cornell_translucent;
        canon = "cornell-translucent";
    } else if (!strcmp(name, "pillars")) {
        build = build_pillars;
        canon = "pillars";
    } else {
        FV_ERROR("scene", "builtin:%s: no built-in scene of that name (known: cornell, cornell-translucent, pillars)",
                 name);
        return FV_ERR_NOT_FOUND;
    }
    fv_scene *s = NULL;
    fv_result r = fv_scene_create(canon, &s);
    if (r < 0) return r;
    snprintf(s->source, sizeof s->source, "builtin:%s", canon);
    r = build(s);
    if (r < 0) goto fail;
    r = fv_scene_validate(s);
    if (r < 0) goto fail;
    *out_scene = s;
    return FV_OK;
fail:
    fv_scene_destroy(&s);
    return r;
}
