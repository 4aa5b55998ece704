/* @brief Light-view map geometry of subsurface scattering (see fv_sss_math.h). */
#include "fv_sss_math.h"

#include <math.h>
#include <string.h>

static bool node_uses(const fv_scene *s, uint32_t node, uint32_t material)
{
    const fv_node *n = &s->nodes[node];
    return n->mesh >= 0 && (uint32_t)n->mesh < s->mesh_count && s->meshes[n->mesh].material == material &&
           s->meshes[n->mesh].index_count > 0;
}

uint32_t fv_sss_translucent_materials(const fv_scene *s, uint32_t *out, uint32_t cap)
{
    uint32_t n = 0;
    for (uint32_t m = 0; s && m < s->material_count; m++) {
        if (!s->materials || !s->materials[m].translucency.enabled) continue;
        bool used = false;
        for (uint32_t i = 0; i < s->node_count && !used; i++) used = node_uses(s, i, m);
        if (!used) continue;
        if (n < cap && out) out[n] = m;
        n++;
    }
    return n;
}

uint32_t fv_sss_pairs(const fv_scene *s, fv_sss_pair out[FV_SSS_MAX_LAYERS], uint32_t *out_wanted)
{
    uint32_t mats[FV_SSS_MAX_LAYERS];
    uint32_t nm = fv_sss_translucent_materials(s, mats, FV_SSS_MAX_LAYERS);
    uint32_t nl = s ? (s->light_count < FV_SSS_MAX_LIGHTS ? s->light_count : FV_SSS_MAX_LIGHTS) : 0;
    uint32_t n = 0;
    for (uint32_t l = 0; l < nl; l++)
        for (uint32_t m = 0; m < nm && m < FV_SSS_MAX_LAYERS; m++)
            if (n < FV_SSS_MAX_LAYERS) out[n++] = (fv_sss_pair){l, mats[m]};
    if (out_wanted) *out_wanted = nl * nm;
    return n;
}

bool fv_sss_material_bounds(const fv_scene *s, uint32_t material, double t_s, fv_vec3 *out_min, fv_vec3 *out_max)
{
    bool any = false;
    fv_vec3 lo = fv_v3(0, 0, 0), hi = fv_v3(0, 0, 0);
    for (uint32_t i = 0; s && i < s->node_count; i++) {
        if (!node_uses(s, i, material)) continue;
        any = fv_scene_node_bounds_grow(s, i, t_s, &lo, &hi, any);
    }
    if (any) {
        *out_min = lo;
        *out_max = hi;
    }
    return any;
}

/* Orthographic projection of view space (-z forward) to Vulkan clip: x, y in [-half, half], depth [near, far]. */
static fv_mat4 ortho(double half, double near_m, double far_m)
{
    fv_mat4 r;
    memset(&r, 0, sizeof r);
    r.m[0][0] = (float)(1.0 / half);
    r.m[1][1] = (float)(-1.0 / half); /* Vulkan y points down */
    r.m[2][2] = (float)(-1.0 / (far_m - near_m));
    r.m[3][2] = (float)(-near_m / (far_m - near_m));
    r.m[3][3] = 1.0f;
    return r;
}

static fv_vec3 up_for(fv_vec3 axis) { return fabsf(axis.y) > 0.9f ? fv_v3(0, 0, 1) : fv_v3(0, 1, 0); }

bool fv_sss_light_view(uint32_t type, fv_vec3 pos, fv_vec3 dir, fv_vec3 obj_min, fv_vec3 obj_max, fv_vec3 scene_min,
                       fv_vec3 scene_max, uint32_t size, fv_sss_view *out)
{
    memset(out, 0, sizeof *out);
    if (!size || !fv_v3_isfinite(obj_min) || !fv_v3_isfinite(obj_max)) return false;
    fv_vec3 c = fv_v3_scale(fv_v3_add(obj_min, obj_max), 0.5f);
    double radius = 0.5 * fv_v3_len(fv_v3_sub(obj_max, obj_min)) * 1.02 + 1e-6;
    out->size = size;
    if (type == FV_LIGHT_DIRECTIONAL) {
        fv_vec3 axis = fv_v3_normalize_or(dir, fv_v3(0, -1, 0));
        /* Back to the farthest scene corner against the light, so every occluder lies inside the depth range. */
        double back = radius;
        for (int k = 0; k < 8; k++) {
            fv_vec3 p = fv_v3((k & 1) ? scene_max.x : scene_min.x, (k & 2) ? scene_max.y : scene_min.y,
                              (k & 4) ? scene_max.z : scene_min.z);
            double along = -fv_v3_dot(fv_v3_sub(p, c), axis);
            if (isfinite(along) && along > back) back = along;
        }
        back += 0.01 * radius;
        fv_vec3 eye = fv_v3_sub(c, fv_v3_scale(axis, (float)back));
        fv_mat4 view = fv_mat4_look_at(eye, c, up_for(axis));
        fv_mat4 proj = ortho(radius, 0.0, back + radius);
        out->view_proj = fv_mat4_mul(&proj, &view);
        out->axis = axis;
        out->origin = eye;
        out->texel_m = 2.0 * radius / size;
        return true;
    }
    if (!fv_v3_isfinite(pos)) return false;
    fv_vec3 to = fv_v3_sub(c, pos);
    double dist = fv_v3_len(to);
    fv_vec3 axis = dist > 1e-9 ? fv_v3_scale(to, (float)(1.0 / dist)) : fv_v3_normalize_or(dir, fv_v3(0, -1, 0));
    double max_half = FV_SSS_MAX_HALF_ANGLE_DEG * 3.14159265358979323846 / 180.0;
    double half = dist > radius ? asin(radius / dist) : max_half;
    if (half > max_half) half = max_half;
    double t = tan(half);
    double far_m = dist + radius;
    double near_m = fmax(1e-3 * far_m, 1e-4);
    fv_mat4 view = fv_mat4_look_at(pos, fv_v3_add(pos, axis), up_for(axis));
    fv_mat4 proj = fv_mat4_perspective_tan((float)-t, (float)t, (float)t, (float)-t, (float)near_m, (float)far_m);
    out->view_proj = fv_mat4_mul(&proj, &view);
    out->perspective = true;
    out->origin = pos;
    out->axis = axis;
    out->tan_half = t;
    return true;
}

double fv_sss_texel_area(const fv_sss_view *v, fv_vec3 p, double cos_i)
{
    if (!v || !v->size) return 0.0;
    double c = isfinite(cos_i) ? fmax(fmin(cos_i, 1.0), FV_SSS_MIN_COS) : 1.0;
    if (!v->perspective) return v->texel_m * v->texel_m / c;
    fv_vec3 d = fv_v3_sub(p, v->origin);
    double dist2 = fv_v3_dot(d, d);
    if (!(dist2 > 0.0) || !isfinite(dist2)) return 0.0;
    double cos_axis = fv_v3_dot(d, v->axis) / sqrt(dist2);
    if (!(cos_axis > 0.0)) return 0.0;
    double side = 2.0 * v->tan_half / v->size;
    return side * side * cos_axis * cos_axis * cos_axis * dist2 / c;
}

typedef struct dv3 {
    double x, y, z;
} dv3;

static dv3 d3(double x, double y, double z) { return (dv3){x, y, z}; }
static dv3 d3_add(dv3 a, dv3 b) { return d3(a.x + b.x, a.y + b.y, a.z + b.z); }
static dv3 d3_scale(dv3 a, double k) { return d3(a.x * k, a.y * k, a.z * k); }
static double d3_dot(dv3 a, dv3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static dv3 d3_of(fv_vec3 v) { return d3(v.x, v.y, v.z); }

/* v without its component along the unit u, made unit; false when nothing is left. */
static bool d3_unit_across(dv3 v, dv3 u, dv3 *out)
{
    dv3 r = d3_add(v, d3_scale(u, -d3_dot(v, u)));
    double l = sqrt(d3_dot(r, r));
    if (!(l > 1e-30) || !isfinite(l)) return false;
    *out = d3_scale(r, 1.0 / l);
    return true;
}

bool fv_sss_texel_footprint(const fv_sss_view *v, fv_vec3 p, fv_vec3 n, fv_vec3 *out_a, fv_vec3 *out_b)
{
    *out_a = *out_b = fv_v3(0, 0, 0);
    if (!v || !v->size) return false;
    dv3 axis = d3_of(v->axis), pp = d3_of(p), nn = d3_of(n);
    double nl = sqrt(d3_dot(nn, nn));
    if (!(nl > 1e-30) || !isfinite(nl)) return false;
    nn = d3_scale(nn, 1.0 / nl);
    /* The map's x and y axes: the first two rows of its view-projection, across the axis. */
    dv3 right, up;
    const fv_mat4 *m = &v->view_proj;
    if (!d3_unit_across(d3(m->m[0][0], m->m[1][0], m->m[2][0]), axis, &right) ||
        !d3_unit_across(d3(m->m[0][1], m->m[1][1], m->m[2][1]), axis, &up) || !d3_unit_across(up, right, &up))
        return false;
    /* The texel's sides across the ray, and the ray's direction w (from the light). */
    double side;
    dv3 w;
    if (v->perspective) {
        dv3 d = d3_add(pp, d3_scale(d3_of(v->origin), -1.0));
        double len = sqrt(d3_dot(d, d)), along = d3_dot(d, axis);
        if (!(len > 0.0) || !(along > 0.0) || !isfinite(len)) return false;
        side = 2.0 * v->tan_half / v->size * along;
        w = d3_scale(d, 1.0 / len);
    } else {
        side = v->texel_m;
        w = axis;
    }
    /* The side facing the light, its cosine clamped (the plane tilted toward the light where it grazes). */
    dv3 l = d3_scale(w, -1.0);
    double cos_i = d3_dot(nn, l);
    if (cos_i < 0.0) {
        nn = d3_scale(nn, -1.0);
        cos_i = -cos_i;
    }
    double c = cos_i;
    if (c < FV_SSS_MIN_COS) {
        c = FV_SSS_MIN_COS;
        dv3 t;
        if (!d3_unit_across(nn, l, &t)) return false;
        nn = d3_add(d3_scale(l, c), d3_scale(t, sqrt(1.0 - c * c)));
    }
    /* Each side carried along the ray onto the plane: e + w (n.e) / c. */
    dv3 ex = d3_scale(right, side), ey = d3_scale(up, side);
    dv3 a = d3_add(ex, d3_scale(w, d3_dot(nn, ex) / c)), b = d3_add(ey, d3_scale(w, d3_dot(nn, ey) / c));
    if (!isfinite(d3_dot(a, a)) || !isfinite(d3_dot(b, b)) || !(side > 0.0)) return false;
    *out_a = fv_v3((float)a.x, (float)a.y, (float)a.z);
    *out_b = fv_v3((float)b.x, (float)b.y, (float)b.z);
    return true;
}

static double per_m(float per_mm) { return isfinite(per_mm) && per_mm > 0.0f ? (double)per_mm * 1000.0 : 0.0; }

double fv_sss_material_dipoles(const fv_translucency *t, fv_dipole out[3])
{
    double eta = isfinite(t->eta) && t->eta > 0.0f ? (double)t->eta : 1.0;
    for (int c = 0; c < 3; c++)
        out[c] = fv_dipole_make(per_m(t->sigma_a_per_mm[c]), per_m(t->sigma_s_prime_per_mm[c]), eta);
    return eta;
}

double fv_sss_cutoff_radius_m(const fv_translucency *t, double fraction)
{
    fv_dipole d[3];
    fv_sss_material_dipoles(t, d);
    double r = 0.0;
    for (int c = 0; c < 3; c++) r = fmax(r, fv_dipole_cutoff_radius(&d[c], fraction));
    return r;
}

double fv_sss_flat_radius_m(const fv_translucency *t)
{
    fv_dipole d[3];
    fv_sss_material_dipoles(t, d);
    double r = 0.0;
    for (int c = 0; c < 3; c++) r = fmax(r, fv_dipole_cutoff_radius(&d[c], FV_SSS_FLAT_FRACTION));
    return r;
}

/* 0 below lo, 1 above hi, Hermite between (GLSL's smoothstep); NaN: 0. */
static double smooth01(double lo, double hi, double v)
{
    double t = (v - lo) / (hi - lo);
    t = t > 0.0 ? (t < 1.0 ? t : 1.0) : 0.0;
    return t * t * (3.0 - 2.0 * t);
}

void fv_sss_receiver_make(const double x[3], const double n[3], const double w[3], double flat_m,
                          fv_sss_receiver *out)
{
    memset(out, 0, sizeof *out);
    dv3 nn = d3(n[0], n[1], n[2]), ww = d3(w[0], w[1], w[2]);
    memcpy(out->x, x, sizeof out->x);
    out->flat_m = isfinite(flat_m) && flat_m > 0.0 ? flat_m : 0.0;
    double nl = sqrt(d3_dot(nn, nn)), wl = sqrt(d3_dot(ww, ww));
    if (!(nl > 1e-30) || !(wl > 1e-30) || !isfinite(nl) || !isfinite(wl)) return;
    nn = d3_scale(nn, 1.0 / nl);
    ww = d3_scale(ww, 1.0 / wl);
    dv3 l = d3_scale(ww, -1.0);
    double cos_x = d3_dot(nn, l);
    /* Facing away from the light (the dark side of a closed object, whose normal faces the eye): no near field. */
    if (!(cos_x > 0.0)) return;
    dv3 nc = nn;
    if (cos_x < FV_SSS_MIN_COS) { /* tilted toward the light, as the map tilts a grazing sample's footprint */
        dv3 t;
        if (!d3_unit_across(nn, l, &t)) return;
        nc = d3_add(d3_scale(l, FV_SSS_MIN_COS), d3_scale(t, sqrt(1.0 - FV_SSS_MIN_COS * FV_SSS_MIN_COS)));
    }
    const double nv[3] = {nn.x, nn.y, nn.z}, ncv[3] = {nc.x, nc.y, nc.z}, wv[3] = {ww.x, ww.y, ww.z};
    memcpy(out->n, nv, sizeof out->n);
    memcpy(out->nc, ncv, sizeof out->nc);
    memcpy(out->w, wv, sizeof out->w);
    out->wn = d3_dot(ww, nc);
    out->facing = smooth01(FV_SSS_FLAT_COS_LO, FV_SSS_FLAT_COS_HI, cos_x);
}

/* The carry of fv_sss_near_footprint for a footprint (or a cluster: a = b = 0) of half-diagonal half_diag. */
static double near_carry(const fv_sss_receiver *r, const double c[3], const double a[3], const double b[3],
                         const double n_s[3], double half_diag, double out_c[3], double out_a[3], double out_b[3])
{
    memcpy(out_c, c, 3 * sizeof *c);
    memcpy(out_a, a, 3 * sizeof *a);
    memcpy(out_b, b, 3 * sizeof *b);
    if (!(r->facing > 0.0) || !(r->wn < 0.0)) return 0.0;
    dv3 off = d3(c[0] - r->x[0], c[1] - r->x[1], c[2] - r->x[2]), av = d3(a[0], a[1], a[2]), bv = d3(b[0], b[1], b[2]);
    double dist = sqrt(d3_dot(off, off));
    if (!isfinite(dist) || !isfinite(half_diag)) return 0.0; /* a broken footprint stays as it came */
    double d1 = fmax(r->flat_m, FV_SSS_FLAT_FOOTPRINTS * half_diag);
    if (!(dist < 2.0 * d1)) return 0.0;
    dv3 ns = d3(n_s[0], n_s[1], n_s[2]), n = d3(r->n[0], r->n[1], r->n[2]);
    double ls = sqrt(d3_dot(ns, ns));
    double alike = ls > 1e-30 ? d3_dot(ns, n) / ls : 0.0;
    double beta = (1.0 - smooth01(d1, 2.0 * d1, dist)) * r->facing *
                  smooth01(FV_SSS_FLAT_NORMAL_LO, FV_SSS_FLAT_NORMAL_HI, alike);
    if (!(beta > 0.0) || !isfinite(beta)) return 0.0;
    dv3 nc = d3(r->nc[0], r->nc[1], r->nc[2]);
    double tc = -d3_dot(off, nc) / r->wn, ta = -d3_dot(av, nc) / r->wn, tb = -d3_dot(bv, nc) / r->wn;
    for (int k = 0; k < 3; k++) {
        out_c[k] = c[k] + beta * tc * r->w[k];
        out_a[k] = a[k] + beta * ta * r->w[k];
        out_b[k] = b[k] + beta * tb * r->w[k];
    }
    return beta;
}

static double half_diagonal(const double a[3], const double b[3])
{
    dv3 av = d3(a[0], a[1], a[2]), bv = d3(b[0], b[1], b[2]), diff = d3_add(av, d3_scale(bv, -1.0));
    return 0.5 * sqrt(fmax(d3_dot(d3_add(av, bv), d3_add(av, bv)), d3_dot(diff, diff)));
}

double fv_sss_near_footprint(const fv_sss_receiver *r, const double c[3], const double a[3], const double b[3],
                             const double n_s[3], double out_c[3], double out_a[3], double out_b[3])
{
    return near_carry(r, c, a, b, n_s, half_diagonal(a, b), out_c, out_a, out_b);
}

double fv_sss_near_cluster(const fv_sss_receiver *r, const fv_sss_cluster *c, double out_c[3])
{
    const double zero[3] = {0.0, 0.0, 0.0};
    double za[3], zb[3];
    return near_carry(r, c->pos, zero, zero, c->n, c->widest, out_c, za, zb);
}

bool fv_sss_cluster_near(const fv_sss_receiver *r, const fv_sss_cluster *c)
{
    dv3 off = d3(c->pos[0] - r->x[0], c->pos[1] - r->x[1], c->pos[2] - r->x[2]);
    return sqrt(d3_dot(off, off)) - c->reach < fmax(r->flat_m, FV_SSS_FLAT_FOOTPRINTS * c->widest);
}

bool fv_sss_texel_cluster(const fv_sss_sample *sub, uint32_t count, uint32_t sub_levels, fv_sss_cluster *out)
{
    memset(out, 0, sizeof *out);
    if (!sub || sub_levels > FV_SSS_SUB_LEVELS || count != 1u << (2 * sub_levels)) return false;
    /* level by level from the fine samples, 2 x 2 children per node, as sss_build.comp (its Morton children are
     * these 2 x 2 blocks) */
    fv_sss_cluster node[1u << (2 * FV_SSS_SUB_LEVELS)];
    uint32_t k = 1u << sub_levels;
    for (uint32_t q = 0; q < count; q++) {
        fv_sss_cluster *o = &node[q];
        memset(o, 0, sizeof *o);
        if (!(sub[q].area > 0.0)) continue;
        o->area = sub[q].area;
        memcpy(o->pos, sub[q].pos, sizeof o->pos);
        memcpy(o->flux, sub[q].flux, sizeof o->flux);
        memcpy(o->n, sub[q].n, sizeof o->n);
        o->reach = o->widest = half_diagonal(sub[q].a, sub[q].b);
    }
    for (; k > 1; k /= 2) {
        uint32_t h = k / 2;
        for (uint32_t j = 0; j < h; j++)
            for (uint32_t i = 0; i < h; i++) {
                const fv_sss_cluster *ch[4] = {&node[2 * j * k + 2 * i], &node[2 * j * k + 2 * i + 1],
                                               &node[(2 * j + 1) * k + 2 * i], &node[(2 * j + 1) * k + 2 * i + 1]};
                fv_sss_cluster o;
                memset(&o, 0, sizeof o);
                for (int c = 0; c < 4; c++) {
                    double a = ch[c]->area;
                    if (!(a > 0.0)) continue;
                    o.area += a;
                    for (int e = 0; e < 3; e++) {
                        o.pos[e] += a * ch[c]->pos[e];
                        o.flux[e] += ch[c]->flux[e];
                        o.n[e] += a * ch[c]->n[e];
                    }
                }
                if (o.area > 0.0) {
                    for (int e = 0; e < 3; e++) {
                        o.pos[e] /= o.area;
                        o.n[e] /= o.area;
                    }
                    for (int c = 0; c < 4; c++) {
                        if (!(ch[c]->area > 0.0)) continue;
                        dv3 off = d3(ch[c]->pos[0] - o.pos[0], ch[c]->pos[1] - o.pos[1], ch[c]->pos[2] - o.pos[2]);
                        o.reach = fmax(o.reach, sqrt(d3_dot(off, off)) + ch[c]->reach);
                        o.widest = fmax(o.widest, ch[c]->widest);
                    }
                }
                node[j * h + i] = o; /* row-major at the coarser level: written behind what is still read */
            }
    }
    *out = node[0];
    return out->area > 0.0 && isfinite(out->area);
}

uint32_t fv_sss_sub_levels(uint32_t size)
{
    if (!size || size > FV_SSS_FINE_MAX || (size & (size - 1u))) return 0;
    uint32_t s = 0;
    while (s < FV_SSS_SUB_LEVELS && (size << (s + 1)) <= FV_SSS_FINE_MAX) s++;
    return s;
}

bool fv_sss_texel_resolve(const fv_sss_sample *sub, uint32_t count, uint32_t sub_levels, fv_sss_sample *out)
{
    memset(out, 0, sizeof *out);
    if (!sub || !count || sub_levels > 15 || count != 1u << (2 * sub_levels)) return false;
    for (uint32_t i = 0; i < count; i++)
        if (!(sub[i].area > 0.0) || !(sub[i].cos_i >= FV_SSS_RESOLVE_COS)) return false;
    double k = 1.0 / (double)(1u << sub_levels);
    for (uint32_t i = 0; i < count; i++) {
        const fv_sss_sample *q = &sub[i];
        out->area += q->area;
        for (int c = 0; c < 3; c++) {
            out->pos[c] += q->area * q->pos[c];
            out->flux[c] += q->flux[c];
            out->n[c] += q->area * q->n[c];
            out->a[c] += k * q->a[c];
            out->b[c] += k * q->b[c];
        }
    }
    for (int c = 0; c < 3; c++) {
        out->pos[c] /= out->area;
        out->n[c] /= out->area;
    }
    out->cos_i = 1.0; /* resolved: not used again */
    return isfinite(out->area) && isfinite(out->pos[0] + out->pos[1] + out->pos[2]);
}
