/* @brief The geometry of shadow maps (see fv_shadow_math.h). */
#include "fv_shadow_math.h"

#include <math.h>
#include <string.h>

uint32_t fv_shadow_split_distances(double n, double f, uint32_t m, double lambda, double *out)
{
    if (!(n > 0.0) || !isfinite(n)) n = 1e-4;
    if (!(f > n) || !isfinite(f)) f = n * 2.0;
    if (m < 1) m = 1;
    if (m > FV_SHADOW_SPLITS_MAX) m = FV_SHADOW_SPLITS_MAX;
    if (isnan(lambda)) lambda = 0.5;
    lambda = lambda < 0.0 ? 0.0 : (lambda > 1.0 ? 1.0 : lambda);
    double ratio = f / n, prev = n;
    out[0] = n;
    for (uint32_t i = 1; i < m; i++) {
        double s = (double)i / (double)m;
        double log_i = n * pow(ratio, s), uni_i = n + (f - n) * s;
        double c = lambda * log_i + (1.0 - lambda) * uni_i;
        if (!isfinite(c) || c < prev) c = prev; /* rounding never makes a split go backwards */
        if (c > f) c = f;
        out[i] = prev = c;
    }
    out[m] = f;
    return m;
}

uint32_t fv_shadow_splits_for_range(double n, double f, uint32_t want)
{
    if (want < 1) want = 1;
    if (want > FV_SHADOW_SPLITS_MAX) want = FV_SHADOW_SPLITS_MAX;
    if (!(n > 0.0) || !(f > n) || !isfinite(f / n)) return 1;
    double k = ceil(log2(f / n));
    uint32_t m = k < 1.0 ? 1u : (k > (double)want ? want : (uint32_t)k);
    return m;
}

bool fv_shadow_depth_range(const fv_mat4 *view, fv_vec3 bmin, fv_vec3 bmax, float near_m, float far_m, double *out_n,
                           double *out_f)
{
    double lo = INFINITY, hi = -INFINITY;
    for (int c = 0; c < 8; c++) {
        fv_vec3 p = fv_v3((c & 1) ? bmax.x : bmin.x, (c & 2) ? bmax.y : bmin.y, (c & 4) ? bmax.z : bmin.z);
        double d = -(double)fv_mat4_mul_point(view, p).z;
        if (!isfinite(d)) continue;
        lo = d < lo ? d : lo;
        hi = d > hi ? d : hi;
    }
    *out_n = near_m;
    *out_f = far_m;
    if (!(hi >= near_m) || !(lo <= far_m)) return false;
    *out_n = lo > near_m ? lo : near_m;
    *out_f = hi < far_m ? hi : far_m;
    if (!(*out_f > *out_n)) *out_f = *out_n * 1.001 + 1e-6;
    return true;
}

void fv_shadow_slice_corners(const fv_eye_view *eye, double d0, double d1, fv_vec3 out[8])
{
    fv_mat4 inv;
    (void)fv_mat4_invert(&eye->view, &inv);
    for (int c = 0; c < 8; c++) {
        double d = (c & 4) ? d1 : d0;
        double x = ((c & 1) ? eye->tan_right : eye->tan_left) * d;
        double y = ((c & 2) ? eye->tan_up : eye->tan_down) * d;
        out[c] = fv_mat4_mul_point(&inv, fv_v3((float)x, (float)y, (float)-d));
    }
}

fv_mat4 fv_shadow_ortho(double l, double r, double b, double t, double n, double f)
{
    if (!(r - l > 1e-9)) r = l + 1e-9;
    if (!(t - b > 1e-9)) t = b + 1e-9;
    if (!(f - n > 1e-9)) f = n + 1e-9;
    fv_mat4 m;
    memset(&m, 0, sizeof m);
    m.m[0][0] = (float)(2.0 / (r - l));
    m.m[3][0] = (float)(-(r + l) / (r - l));
    m.m[1][1] = (float)(-2.0 / (t - b)); /* Vulkan y points down */
    m.m[3][1] = (float)((t + b) / (t - b));
    m.m[2][2] = (float)(-1.0 / (f - n)); /* depth = (-z - n) / (f - n) */
    m.m[3][2] = (float)(-n / (f - n));
    m.m[3][3] = 1.0f;
    return m;
}

fv_mat4 fv_shadow_light_view(fv_vec3 dir)
{
    fv_vec3 d = fv_v3_normalize_or(dir, fv_v3(0, -1, 0));
    return fv_mat4_look_at(fv_v3(0, 0, 0), d, fabsf(d.y) < 0.99f ? fv_v3(0, 1, 0) : fv_v3(1, 0, 0));
}

fv_mat4 fv_shadow_crop_directional(const fv_mat4 *light_view, const fv_vec3 *pts, uint32_t count, fv_vec3 bmin,
                                   fv_vec3 bmax, uint32_t res, double *out_texel_m)
{
    double c[3] = {0, 0, 0};
    uint32_t used = 0;
    for (uint32_t i = 0; i < count; i++) {
        if (!fv_v3_isfinite(pts[i])) continue;
        c[0] += pts[i].x, c[1] += pts[i].y, c[2] += pts[i].z;
        used++;
    }
    if (used) c[0] /= used, c[1] /= used, c[2] /= used;
    double r = 0.0;
    for (uint32_t i = 0; i < count; i++) {
        if (!fv_v3_isfinite(pts[i])) continue;
        double dx = pts[i].x - c[0], dy = pts[i].y - c[1], dz = pts[i].z - c[2];
        double d = sqrt(dx * dx + dy * dy + dz * dz);
        r = d > r ? d : r;
    }
    if (!(r > 1e-6) || !isfinite(r)) r = 1e-6;
    /* A radius that does not flicker with rounding: up to a 1/64 step of its power of two. */
    double step = ldexp(1.0, (int)floor(log2(r)) - 6);
    r = ceil(r / step) * step;
    if (res < 1) res = 1;
    double texel = 2.0 * r / res;
    fv_vec3 cl = fv_mat4_mul_point(light_view, fv_v3((float)c[0], (float)c[1], (float)c[2]));
    double cx = floor(cl.x / texel) * texel, cy = floor(cl.y / texel) * texel;
    /* Depth: every caster between the light and the receivers, from the box (and the receivers' own sphere). */
    double zmin = cl.z - r, zmax = cl.z + r;
    for (int k = 0; k < 8; k++) {
        fv_vec3 p = fv_v3((k & 1) ? bmax.x : bmin.x, (k & 2) ? bmax.y : bmin.y, (k & 4) ? bmax.z : bmin.z);
        fv_vec3 q = fv_mat4_mul_point(light_view, p);
        if (!fv_v3_isfinite(q)) continue;
        zmin = q.z < zmin ? q.z : zmin;
        zmax = q.z > zmax ? q.z : zmax;
    }
    double margin = 1e-3 * (zmax - zmin) + 1e-4;
    fv_mat4 proj = fv_shadow_ortho(cx - r, cx + r, cy - r, cy + r, -zmax - margin, -zmin + margin);
    if (out_texel_m) *out_texel_m = texel;
    return fv_mat4_mul(&proj, light_view);
}

static double spot_half_angle(float outer_rad)
{
    double half = isfinite(outer_rad) ? fv_clampf(outer_rad, 1e-3f, 1.5f) * 1.02 : FV_PI / 4;
    return half > 1.55 ? 1.55 : half;
}

double fv_shadow_spot_texel_per_m(float outer_rad, uint32_t res)
{
    return 2.0 * tan(spot_half_angle(outer_rad)) / (res ? res : 1);
}

/* A square perspective map from pos along d with half-angle tangent t, far at the box's farthest corner. */
static fv_mat4 perspective_map(fv_vec3 pos, fv_vec3 d, fv_vec3 up, float t, fv_vec3 bmin, fv_vec3 bmax)
{
    fv_mat4 view = fv_mat4_look_at(pos, fv_v3_add(pos, d), up);
    double far_m = 1e-3;
    for (int k = 0; k < 8; k++) {
        fv_vec3 p = fv_v3((k & 1) ? bmax.x : bmin.x, (k & 2) ? bmax.y : bmin.y, (k & 4) ? bmax.z : bmin.z);
        double dist = fv_v3_len(fv_v3_sub(p, pos));
        if (isfinite(dist) && dist > far_m) far_m = dist;
    }
    far_m *= 1.01;
    fv_mat4 proj = fv_mat4_perspective_tan(-t, t, t, -t, (float)(far_m * 1e-3), (float)far_m);
    return fv_mat4_mul(&proj, &view);
}

fv_mat4 fv_shadow_spot(fv_vec3 pos, fv_vec3 dir, float outer_rad, fv_vec3 bmin, fv_vec3 bmax)
{
    fv_vec3 d = fv_v3_normalize_or(dir, fv_v3(0, -1, 0));
    if (!fv_v3_isfinite(pos)) pos = fv_v3(0, 0, 0);
    return perspective_map(pos, d, fabsf(d.y) < 0.99f ? fv_v3(0, 1, 0) : fv_v3(1, 0, 0),
                           (float)tan(spot_half_angle(outer_rad)), bmin, bmax);
}

#define CUBE_TAN 1.02f

fv_mat4 fv_shadow_cube_face(fv_vec3 pos, uint32_t face, fv_vec3 bmin, fv_vec3 bmax)
{
    static const fv_vec3 dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    static const fv_vec3 ups[6] = {{0, 1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
    if (face > 5) face = 5;
    if (!fv_v3_isfinite(pos)) pos = fv_v3(0, 0, 0);
    return perspective_map(pos, dirs[face], ups[face], CUBE_TAN, bmin, bmax);
}

double fv_shadow_cube_texel_per_m(uint32_t res) { return 2.0 * CUBE_TAN / (res ? res : 1); }
