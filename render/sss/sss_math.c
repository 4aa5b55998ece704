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
