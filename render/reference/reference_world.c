/* @brief The reference renderer's world: the fv_scene flattened into world space at one time (double positions and
 * normals beside Embree's float copy), materials, textures and lights sanitised exactly as render/scene_gpu uploads
 * them, the emissive triangles with their area CDF; closest-hit and shadow queries through Embree with each hit
 * re-intersected in double; texture sampling as the GPU's sampler (bilinear, repeat, sRGB-decoded, no mipmaps). */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "reference_internal.h"

static double finite_or(double v, double fallback) { return isfinite(v) ? v : fallback; }
static double clamp01(double v) { return v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v); }

/* ---- sRGB decoding (IEC 61966-2-1), one table for the 256 codes ------------------------------------------------ */
static double g_srgb_lut[256];
static pthread_once_t g_srgb_once = PTHREAD_ONCE_INIT;

static void srgb_lut_init(void)
{
    for (int i = 0; i < 256; i++) {
        double c = i / 255.0;
        g_srgb_lut[i] = c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
    }
}

/* ---- building ------------------------------------------------------------------------------------------------ */

static void embree_error(void *user, enum RTCError code, const char *str)
{
    (void)user;
    FV_ERROR(REF_MOD, "embree error %d: %s", (int)code, str ? str : "(no message)");
}

static void sanitize_materials(ref_world *w, const fv_scene *s)
{
    for (uint32_t i = 0; i < w->material_count; i++) {
        fv_material m = i < s->material_count ? s->materials[i] : fv_material_default();
        ref_material *o = &w->materials[i];
        o->base_color = dv(clamp01(finite_or(m.base_color.x, 1)), clamp01(finite_or(m.base_color.y, 1)),
                           clamp01(finite_or(m.base_color.z, 1)));
        o->emissive = dv(fmax(finite_or(m.emissive.x, 0), 0), fmax(finite_or(m.emissive.y, 0), 0),
                         fmax(finite_or(m.emissive.z, 0), 0));
        o->texture = -1;
        /* The GPU binds the material's texture when the index is in range and the texture has pixels, else white. */
        if (i < s->material_count && m.base_color_texture >= 0 && (uint32_t)m.base_color_texture < w->texture_count &&
            w->textures[m.base_color_texture].rgba8)
            o->texture = m.base_color_texture;
    }
}

static void sanitize_textures(ref_world *w, const fv_scene *s)
{
    for (uint32_t i = 0; i < w->texture_count; i++) {
        const fv_texture *t = &s->textures[i];
        bool ok = t->rgba8 && t->width && t->height && t->width <= FV_SCENE_MAX_TEXTURE_DIM &&
                  t->height <= FV_SCENE_MAX_TEXTURE_DIM;
        w->textures[i] = (ref_texture){ok ? t->width : 0, ok ? t->height : 0, ok ? t->rgba8 : NULL};
    }
}

/* As render/scene_gpu's to_gpu_light, in double. */
static ref_light sanitize_light(const fv_light *l)
{
    ref_light o;
    memset(&o, 0, sizeof o);
    o.type = (unsigned)l->type <= FV_LIGHT_DIRECTIONAL ? (uint32_t)l->type : FV_LIGHT_POINT;
    o.position = fv_v3_isfinite(l->position_m) ? dv_from_f(l->position_m) : dv(0, 0, 0);
    dvec3 d = dv_from_f(l->direction);
    double len = sqrt(dv_dot(d, d));
    o.direction = isfinite(len) && len > 0 ? dv_scale(d, 1.0 / len) : dv(0, -1, 0);
    o.range = isfinite(l->range_m) && l->range_m > 0 ? l->range_m : 0.0;
    double intensity = isfinite(l->intensity) && l->intensity > 0 ? l->intensity : 0.0;
    fv_vec3 c = l->color;
    dvec3 col = dv(isfinite(c.x) && c.x > 0 ? c.x : 0, isfinite(c.y) && c.y > 0 ? c.y : 0,
                   isfinite(c.z) && c.z > 0 ? c.z : 0);
    o.intensity = dv_scale(col, intensity);
    float outer = isfinite(l->outer_cone_rad) ? fv_clampf(l->outer_cone_rad, 0.0f, (float)FV_PI / 2) : (float)FV_PI / 4;
    float inner = isfinite(l->inner_cone_rad) ? fv_clampf(l->inner_cone_rad, 0.0f, outer) : 0.0f;
    o.cos_inner = cos((double)inner);
    o.cos_outer = cos((double)outer);
    return o;
}

/* Upper-left 3x3 of the inverse transpose of the model matrix (the GPU's normal matrix), in double; the model
 * itself when it is singular, as render/scene_gpu's normal_matrix. n[col][row]. */
static void normal_matrix(const fv_mat4 *m, double n[3][3])
{
    double a[3][3];
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++) a[c][r] = m->m[c][r];
    /* cofactors: inverse = adj / det; inverse transpose = cof / det */
    double cof[3][3];
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++) {
            int c1 = (c + 1) % 3, c2 = (c + 2) % 3, r1 = (r + 1) % 3, r2 = (r + 2) % 3;
            cof[c][r] = a[c1][r1] * a[c2][r2] - a[c1][r2] * a[c2][r1];
        }
    double det = a[0][0] * cof[0][0] + a[0][1] * cof[0][1] + a[0][2] * cof[0][2];
    bool ok = isfinite(det) && det != 0.0;
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++) n[c][r] = ok ? cof[c][r] / det : a[c][r];
}

static void geom_release(ref_geom *g)
{
    free(g->pos);
    free(g->nrm);
    free(g->prim_tri);
    memset(g, 0, sizeof *g);
}

static fv_result add_geometry(ref_world *w, const fv_scene *s, uint32_t node, double t_s)
{
    const fv_mesh *mesh = &s->meshes[s->nodes[node].mesh];
    fv_mat4 m = fv_scene_node_world(s, node, t_s);
    double nm[3][3];
    normal_matrix(&m, nm);
    ref_geom *g = &w->geoms[w->geom_count];
    memset(g, 0, sizeof *g);
    g->node = node;
    g->mesh = mesh;
    g->material = mesh->material < w->material_count ? mesh->material : 0;
    uint32_t nv = mesh->vertex_count, ntri = mesh->index_count / 3;
    g->pos = malloc((nv ? nv : 1) * sizeof *g->pos);
    g->nrm = malloc((nv ? nv : 1) * sizeof *g->nrm);
    g->prim_tri = malloc((ntri ? ntri : 1) * sizeof *g->prim_tri);
    if (!g->pos || !g->nrm || !g->prim_tri) return FV_ERR_NO_MEMORY;
    for (uint32_t v = 0; v < nv; v++) {
        fv_vec3 p = mesh->positions ? mesh->positions[v] : fv_v3(0, 0, 0);
        fv_vec3 n = mesh->normals ? mesh->normals[v] : fv_v3(0, 1, 0);
        double pn[3] = {finite_or(n.x, 0), finite_or(n.y, 1), finite_or(n.z, 0)};
        double q[3], r[3];
        for (int k = 0; k < 3; k++) {
            q[k] = (double)m.m[0][k] * p.x + (double)m.m[1][k] * p.y + (double)m.m[2][k] * p.z + (double)m.m[3][k];
            r[k] = nm[0][k] * pn[0] + nm[1][k] * pn[1] + nm[2][k] * pn[2];
        }
        g->pos[v] = dv(q[0], q[1], q[2]);
        g->nrm[v] = dv(r[0], r[1], r[2]);
    }
    for (uint32_t t = 0; t < ntri; t++) {
        const uint32_t *ix = &mesh->indices[3 * t];
        bool ok = ix[0] < nv && ix[1] < nv && ix[2] < nv;
        if (ok) {
            dvec3 a = g->pos[ix[0]], b = g->pos[ix[1]], c = g->pos[ix[2]];
            for (int k = 0; k < 3 && ok; k++) {
                dvec3 p = k == 0 ? a : (k == 1 ? b : c);
                ok = dv_finite(p) && isfinite((float)p.x) && isfinite((float)p.y) && isfinite((float)p.z);
            }
            dvec3 cr = dv_cross(dv_sub(b, a), dv_sub(c, a));
            double area2 = dv_dot(cr, cr);
            ok = ok && isfinite(area2) && area2 > 0.0;
        }
        if (ok) g->prim_tri[g->prim_count++] = t;
        else w->skipped_triangles++;
    }
    if (g->prim_count == 0) { /* nothing Embree could hit: no geometry for this node */
        geom_release(g);
        return FV_OK;
    }
    RTCGeometry eg = rtcNewGeometry(w->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!eg) return FV_ERR_NO_MEMORY;
    float *vb = rtcSetNewGeometryBuffer(eg, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv);
    unsigned *ib = rtcSetNewGeometryBuffer(eg, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                           g->prim_count);
    if (!vb || !ib) {
        rtcReleaseGeometry(eg);
        return FV_ERR_NO_MEMORY;
    }
    for (uint32_t v = 0; v < nv; v++) {
        dvec3 p = g->pos[v];
        bool ok = dv_finite(p) && isfinite((float)p.x) && isfinite((float)p.y) && isfinite((float)p.z);
        vb[3 * v + 0] = ok ? (float)p.x : 0.0f;
        vb[3 * v + 1] = ok ? (float)p.y : 0.0f;
        vb[3 * v + 2] = ok ? (float)p.z : 0.0f;
    }
    for (uint32_t i = 0; i < g->prim_count; i++)
        for (int k = 0; k < 3; k++) ib[3 * i + k] = mesh->indices[3 * g->prim_tri[i] + k];
    rtcCommitGeometry(eg);
    rtcAttachGeometryByID(w->scene, eg, w->geom_count);
    rtcReleaseGeometry(eg);
    w->triangles += g->prim_count;
    w->geom_count++;
    return FV_OK;
}

static dvec3 tri_vertex(const ref_geom *g, uint32_t tri, int k) { return g->pos[g->mesh->indices[3 * tri + k]]; }

static double tri_area(const ref_geom *g, uint32_t tri)
{
    dvec3 a = tri_vertex(g, tri, 0), b = tri_vertex(g, tri, 1), c = tri_vertex(g, tri, 2);
    dvec3 cr = dv_cross(dv_sub(b, a), dv_sub(c, a));
    return 0.5 * sqrt(dv_dot(cr, cr));
}

static fv_result build_emitters(ref_world *w)
{
    uint32_t n = 0;
    for (uint32_t g = 0; g < w->geom_count; g++)
        if (dv_maxc(w->materials[w->geoms[g].material].emissive) > 0) n += w->geoms[g].prim_count;
    if (n == 0) return FV_OK;
    w->emitters = malloc(n * sizeof *w->emitters);
    w->emitter_cdf = malloc(n * sizeof *w->emitter_cdf);
    if (!w->emitters || !w->emitter_cdf) return FV_ERR_NO_MEMORY;
    double sum = 0;
    for (uint32_t g = 0; g < w->geom_count; g++) {
        const ref_geom *geom = &w->geoms[g];
        if (!(dv_maxc(w->materials[geom->material].emissive) > 0)) continue;
        for (uint32_t i = 0; i < geom->prim_count; i++) {
            double a = tri_area(geom, geom->prim_tri[i]);
            if (!(a > 0) || !isfinite(a) || !isfinite(sum + a)) continue;
            sum += a;
            w->emitters[w->emitter_count] = (ref_emitter){g, geom->prim_tri[i], a};
            w->emitter_cdf[w->emitter_count++] = sum;
        }
    }
    w->emissive_area_m2 = sum;
    return FV_OK;
}

fv_result ref_world_init(ref_world *w, const fv_scene *s, double t_s)
{
    memset(w, 0, sizeof *w);
    pthread_once(&g_srgb_once, srgb_lut_init);
    fv_result res = FV_ERR_NO_MEMORY;
    /* Embree builds with its own threads (all CPUs), whatever desc.threads says: the BVH, and so which of two
     * triangles sharing an edge a ray reports, must not depend on the thread count. */
    w->device = rtcNewDevice("verbose=0");
    if (!w->device) {
        FV_ERROR(REF_MOD, "embree: cannot create a device (error %d)", (int)rtcGetDeviceError(NULL));
        return FV_ERR_UNSUPPORTED;
    }
    rtcSetDeviceErrorFunction(w->device, embree_error, NULL);
    w->scene = rtcNewScene(w->device);
    if (!w->scene) goto fail;
    rtcSetSceneFlags(w->scene, RTC_SCENE_FLAG_ROBUST);
    /* Medium quality (the default): Embree's high-quality (spatial split) build is not deterministic when
     * multithreaded (RenderKit/embree#20). */
    rtcSetSceneBuildQuality(w->scene, RTC_BUILD_QUALITY_MEDIUM);

    w->texture_count = s->texture_count;
    w->material_count = s->material_count ? s->material_count : 1;
    w->light_count = s->light_count;
    w->textures = calloc(w->texture_count ? w->texture_count : 1, sizeof *w->textures);
    w->materials = calloc(w->material_count, sizeof *w->materials);
    w->lights = calloc(w->light_count ? w->light_count : 1, sizeof *w->lights);
    w->geoms = calloc(s->node_count ? s->node_count : 1, sizeof *w->geoms);
    if (!w->textures || !w->materials || !w->lights || !w->geoms) goto fail;
    sanitize_textures(w, s);
    sanitize_materials(w, s);
    for (uint32_t i = 0; i < w->light_count; i++) w->lights[i] = sanitize_light(&s->lights[i]);
    w->ambient = fv_v3_isfinite(s->ambient) ? dv(fmax(s->ambient.x, 0), fmax(s->ambient.y, 0), fmax(s->ambient.z, 0))
                                            : dv(0, 0, 0);
    for (uint32_t i = 0; i < s->node_count; i++) {
        if (s->nodes[i].mesh < 0 || (uint32_t)s->nodes[i].mesh >= s->mesh_count) continue;
        res = add_geometry(w, s, i, t_s);
        if (res != FV_OK) goto fail;
    }
    res = build_emitters(w);
    if (res != FV_OK) goto fail;
    rtcCommitScene(w->scene);
    if (rtcGetDeviceError(w->device) != RTC_ERROR_NONE) {
        res = FV_ERR_NO_MEMORY;
        goto fail;
    }
    if (w->skipped_triangles)
        FV_INFO(REF_MOD, "%s: %u triangles left out (non-finite or out-of-range vertex, or zero area)", s->source,
                w->skipped_triangles);
    return FV_OK;
fail:
    if (res == FV_OK) res = FV_ERR_NO_MEMORY;
    FV_ERROR(REF_MOD, "%s: building the ray-tracing scene failed: %s", s->source, fv_result_str(res));
    /* geoms[geom_count] may hold a partly built entry: release it too */
    if (w->geoms && w->geom_count < (s->node_count ? s->node_count : 1)) geom_release(&w->geoms[w->geom_count]);
    ref_world_fini(w);
    return res;
}

void ref_world_fini(ref_world *w)
{
    if (!w) return;
    if (w->geoms)
        for (uint32_t i = 0; i < w->geom_count; i++) geom_release(&w->geoms[i]);
    free(w->geoms);
    free(w->materials);
    free(w->textures);
    free(w->lights);
    free(w->emitters);
    free(w->emitter_cdf);
    if (w->scene) rtcReleaseScene(w->scene);
    if (w->device) rtcReleaseDevice(w->device);
    memset(w, 0, sizeof *w);
}

/* ---- queries ------------------------------------------------------------------------------------------------- */

double ref_offset_eps(dvec3 pos) { return 2e-5 * (1.0 + dv_max_abs(pos)); }

dvec3 ref_offset(dvec3 pos, dvec3 ng, dvec3 dir)
{
    double s = dv_dot(ng, dir) >= 0 ? 1.0 : -1.0;
    return dv_add(pos, dv_scale(ng, s * ref_offset_eps(pos)));
}

static void embree_ray(struct RTCRay *r, dvec3 o, dvec3 d, double t_max)
{
    memset(r, 0, sizeof *r);
    r->org_x = (float)o.x, r->org_y = (float)o.y, r->org_z = (float)o.z;
    r->dir_x = (float)d.x, r->dir_y = (float)d.y, r->dir_z = (float)d.z;
    r->tnear = 0.0f;
    r->tfar = t_max < (double)INFINITY && t_max < 3e38 ? (float)t_max : INFINITY;
    r->mask = 0xffffffffu;
}

/* Whether Embree takes the ray: it asserts (and aborts) on an origin past its FLT_LARGE (1.8e18) or a non-finite
 * value. fv_reference_render refuses scenes and eyes beyond FV_SCENE_MAX_COORD_M first; this is the last guard. */
#define REF_MAX_RAY_ORIGIN 1.0e18
static bool ray_ok(dvec3 o, dvec3 d)
{
    return dv_finite(o) && dv_finite(d) && fabs(o.x) <= REF_MAX_RAY_ORIGIN && fabs(o.y) <= REF_MAX_RAY_ORIGIN &&
           fabs(o.z) <= REF_MAX_RAY_ORIGIN;
}

bool ref_trace(const ref_world *w, dvec3 o, dvec3 d, double t_max, const dvec3 *face_to, ref_hit *out)
{
    if (!ray_ok(o, d) || !(t_max > 0)) return false;
    struct RTCRayHit rh;
    embree_ray(&rh.ray, o, d, t_max);
    memset(&rh.hit, 0, sizeof rh.hit);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcIntersect1(w->scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.geomID >= w->geom_count) return false;
    const ref_geom *g = &w->geoms[rh.hit.geomID];
    if (rh.hit.primID >= g->prim_count) return false;
    uint32_t tri = g->prim_tri[rh.hit.primID];
    const uint32_t *ix = &g->mesh->indices[3 * tri];
    dvec3 v0 = g->pos[ix[0]], v1 = g->pos[ix[1]], v2 = g->pos[ix[2]];
    /* Re-intersect in double (Moeller & Trumbore 1997) the triangle Embree found in float; a grazing ray keeps
     * Embree's float answer. */
    dvec3 e1 = dv_sub(v1, v0), e2 = dv_sub(v2, v0);
    dvec3 pv = dv_cross(d, e2);
    double det = dv_dot(e1, pv);
    double t = rh.ray.tfar, b1 = rh.hit.u, b2 = rh.hit.v;
    double scale = sqrt(dv_dot(e1, e1) * dv_dot(e2, e2));
    if (fabs(det) > 1e-9 * scale) {
        double inv = 1.0 / det;
        dvec3 tv = dv_sub(o, v0);
        dvec3 qv = dv_cross(tv, e1);
        double tt = dv_dot(e2, qv) * inv, u = dv_dot(tv, pv) * inv, v = dv_dot(d, qv) * inv;
        if (isfinite(tt) && isfinite(u) && isfinite(v) && tt > 0) {
            t = tt;
            b1 = u;
            b2 = v;
        }
    }
    double b0 = 1.0 - b1 - b2;
    out->geom = rh.hit.geomID;
    out->tri = tri;
    out->t = t;
    out->pos = dv_add(o, dv_scale(d, t));
    out->material = g->material;
    dvec3 ng = dv_cross(e1, e2);
    double ln = sqrt(dv_dot(ng, ng));
    ng = ln > 0 && isfinite(ln) ? dv_scale(ng, 1.0 / ln) : dv_scale(d, -1.0);
    out->ng = dv_dot(ng, d) > 0 ? dv_scale(ng, -1.0) : ng;
    /* The G-buffer's normal: interpolated, normalised (zero length: +y), turned toward the eye. */
    dvec3 n = dv_add(dv_add(dv_scale(g->nrm[ix[0]], b0), dv_scale(g->nrm[ix[1]], b1)), dv_scale(g->nrm[ix[2]], b2));
    double len2 = dv_dot(n, n);
    n = len2 > 1e-30 && isfinite(len2) ? dv_scale(n, 1.0 / sqrt(len2)) : dv(0, 1, 0);
    dvec3 to = face_to ? dv_sub(*face_to, out->pos) : dv_scale(d, -1.0);
    out->n = dv_dot(n, to) < 0 ? dv_scale(n, -1.0) : n;
    const fv_vec2 *tc = g->mesh->texcoords;
    for (int k = 0; k < 2; k++) {
        double c[3];
        for (int j = 0; j < 3; j++) c[j] = tc ? finite_or(k == 0 ? tc[ix[j]].x : tc[ix[j]].y, 0) : 0.0;
        out->uv[k] = b0 * c[0] + b1 * c[1] + b2 * c[2];
    }
    return true;
}

bool ref_visible(const ref_world *w, dvec3 o, dvec3 d, double t_max)
{
    if (!(t_max > 0)) return true;
    if (!ray_ok(o, d)) return false;
    struct RTCRay r;
    embree_ray(&r, o, d, t_max);
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcOccluded1(w->scene, &ctx, &r);
    return r.tfar >= 0.0f; /* Embree sets tfar to -inf when something is hit */
}

/* Vulkan's LINEAR filter with REPEAT addressing on an sRGB format: texels decoded to linear, then blended at
 * (u * w - 0.5, v * h - 0.5). Exact weights (the GPU quantises them to its sub-texel precision). */
static dvec3 sample_texture(const ref_texture *t, double u, double v)
{
    if (!t->rgba8) return dv(1, 1, 1);
    u = isfinite(u) ? u - floor(u) : 0.0;
    v = isfinite(v) ? v - floor(v) : 0.0;
    double x = u * t->width - 0.5, y = v * t->height - 0.5;
    double fx = floor(x), fy = floor(y);
    double ax = x - fx, ay = y - fy;
    int64_t x0 = (int64_t)fx, y0 = (int64_t)fy;
    double acc[3] = {0, 0, 0};
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
            int64_t xi = ((x0 + i) % (int64_t)t->width + t->width) % t->width;
            int64_t yi = ((y0 + j) % (int64_t)t->height + t->height) % t->height;
            double wgt = (i ? ax : 1.0 - ax) * (j ? ay : 1.0 - ay);
            const uint8_t *p = &t->rgba8[((size_t)yi * t->width + (size_t)xi) * 4];
            for (int c = 0; c < 3; c++) acc[c] += wgt * g_srgb_lut[p[c]];
        }
    return dv(acc[0], acc[1], acc[2]);
}

dvec3 ref_albedo(const ref_world *w, const ref_hit *h)
{
    const ref_material *m = &w->materials[h->material];
    dvec3 t = m->texture >= 0 ? sample_texture(&w->textures[m->texture], h->uv[0], h->uv[1]) : dv(1, 1, 1);
    dvec3 a = dv_mul(m->base_color, t);
    return dv(clamp01(a.x), clamp01(a.y), clamp01(a.z));
}

bool ref_sample_emitter(const ref_world *w, double u0, double u1, double u2, dvec3 *out_pos, dvec3 *out_ng,
                        uint32_t *out_emitter)
{
    if (!w->emitter_count) return false;
    double target = u0 * w->emissive_area_m2;
    uint32_t lo = 0, hi = w->emitter_count - 1;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (w->emitter_cdf[mid] <= target) lo = mid + 1;
        else hi = mid;
    }
    const ref_emitter *e = &w->emitters[lo];
    const ref_geom *g = &w->geoms[e->geom];
    dvec3 a = tri_vertex(g, e->tri, 0), b = tri_vertex(g, e->tri, 1), c = tri_vertex(g, e->tri, 2);
    double su = sqrt(u1);
    /* Uniform on the triangle (Osada et al. 2002, eq. 1): b0 = 1 - sqrt(u1), b1 = u2 sqrt(u1). */
    double b0 = 1.0 - su, b1 = u2 * su, b2 = 1.0 - b0 - b1;
    *out_pos = dv_add(dv_add(dv_scale(a, b0), dv_scale(b, b1)), dv_scale(c, b2));
    dvec3 ng = dv_cross(dv_sub(b, a), dv_sub(c, a));
    *out_ng = dv_scale(ng, 1.0 / sqrt(dv_dot(ng, ng)));
    *out_emitter = lo;
    return true;
}
