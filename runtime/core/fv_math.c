/* @brief Small float math (see fv_math.h). */
#include "fv_math.h"

#include <string.h>

fv_vec3 fv_v3_normalize_or(fv_vec3 a, fv_vec3 fallback)
{
    float len = fv_v3_len(a);
    if (!(len > 1e-30f) || !isfinite(len)) return fallback;
    return fv_v3_scale(a, 1.0f / len);
}

fv_mat4 fv_mat4_identity(void)
{
    fv_mat4 r;
    memset(&r, 0, sizeof r);
    for (int i = 0; i < 4; i++) r.m[i][i] = 1.0f;
    return r;
}

fv_mat4 fv_mat4_mul(const fv_mat4 *a, const fv_mat4 *b)
{
    fv_mat4 r;
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) {
            float s = 0.0f;
            for (int k = 0; k < 4; k++) s += a->m[k][row] * b->m[c][k];
            r.m[c][row] = s;
        }
    return r;
}

fv_vec4 fv_mat4_mul_v4(const fv_mat4 *a, fv_vec4 v)
{
    float in[4] = {v.x, v.y, v.z, v.w}, out[4];
    for (int row = 0; row < 4; row++) {
        out[row] = 0.0f;
        for (int k = 0; k < 4; k++) out[row] += a->m[k][row] * in[k];
    }
    return (fv_vec4){out[0], out[1], out[2], out[3]};
}

fv_vec3 fv_mat4_mul_point(const fv_mat4 *a, fv_vec3 p)
{
    fv_vec4 r = fv_mat4_mul_v4(a, (fv_vec4){p.x, p.y, p.z, 1.0f});
    return (fv_vec3){r.x, r.y, r.z};
}

fv_vec3 fv_mat4_mul_dir(const fv_mat4 *a, fv_vec3 d)
{
    fv_vec4 r = fv_mat4_mul_v4(a, (fv_vec4){d.x, d.y, d.z, 0.0f});
    return (fv_vec3){r.x, r.y, r.z};
}

fv_mat4 fv_mat4_translate(fv_vec3 t)
{
    fv_mat4 r = fv_mat4_identity();
    r.m[3][0] = t.x;
    r.m[3][1] = t.y;
    r.m[3][2] = t.z;
    return r;
}

fv_mat4 fv_mat4_scale(fv_vec3 s)
{
    fv_mat4 r = fv_mat4_identity();
    r.m[0][0] = s.x;
    r.m[1][1] = s.y;
    r.m[2][2] = s.z;
    return r;
}

fv_mat4 fv_mat4_from_quat(fv_quat q)
{
    q = fv_quat_normalize(q);
    float x = q.x, y = q.y, z = q.z, w = q.w;
    fv_mat4 r = fv_mat4_identity();
    r.m[0][0] = 1 - 2 * (y * y + z * z);
    r.m[0][1] = 2 * (x * y + z * w);
    r.m[0][2] = 2 * (x * z - y * w);
    r.m[1][0] = 2 * (x * y - z * w);
    r.m[1][1] = 1 - 2 * (x * x + z * z);
    r.m[1][2] = 2 * (y * z + x * w);
    r.m[2][0] = 2 * (x * z + y * w);
    r.m[2][1] = 2 * (y * z - x * w);
    r.m[2][2] = 1 - 2 * (x * x + y * y);
    return r;
}

fv_mat4 fv_mat4_trs(fv_vec3 t, fv_quat rq, fv_vec3 s)
{
    fv_mat4 T = fv_mat4_translate(t), R = fv_mat4_from_quat(rq), S = fv_mat4_scale(s);
    fv_mat4 RS = fv_mat4_mul(&R, &S);
    return fv_mat4_mul(&T, &RS);
}

fv_mat4 fv_mat4_transpose(const fv_mat4 *a)
{
    fv_mat4 r;
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) r.m[c][row] = a->m[row][c];
    return r;
}

bool fv_mat4_invert(const fv_mat4 *a, fv_mat4 *out_inv)
{
    /* Gauss-Jordan with partial pivoting, in double. */
    double m[4][8];
    for (int r = 0; r < 4; r++) {
        for (int c = 0; c < 4; c++) m[r][c] = a->m[c][r];
        for (int c = 0; c < 4; c++) m[r][4 + c] = (r == c) ? 1.0 : 0.0;
    }
    for (int col = 0; col < 4; col++) {
        int piv = col;
        for (int r = col + 1; r < 4; r++)
            if (fabs(m[r][col]) > fabs(m[piv][col])) piv = r;
        if (!(fabs(m[piv][col]) > 1e-300) || !isfinite(m[piv][col])) {
            *out_inv = fv_mat4_identity();
            return false;
        }
        if (piv != col)
            for (int c = 0; c < 8; c++) {
                double t = m[col][c];
                m[col][c] = m[piv][c];
                m[piv][c] = t;
            }
        double inv = 1.0 / m[col][col];
        for (int c = 0; c < 8; c++) m[col][c] *= inv;
        for (int r = 0; r < 4; r++) {
            if (r == col) continue;
            double f = m[r][col];
            if (f != 0.0)
                for (int c = 0; c < 8; c++) m[r][c] -= f * m[col][c];
        }
    }
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) out_inv->m[c][r] = (float)m[r][4 + c];
    return true;
}

fv_mat4 fv_mat4_look_at(fv_vec3 eye, fv_vec3 target, fv_vec3 up)
{
    fv_vec3 f = fv_v3_normalize_or(fv_v3_sub(target, eye), fv_v3(0, 0, -1));
    fv_vec3 s = fv_v3_cross(f, up);
    if (!(fv_v3_len(s) > 1e-6f)) s = fv_v3_cross(f, fabsf(f.y) < 0.9f ? fv_v3(0, 1, 0) : fv_v3(1, 0, 0));
    s = fv_v3_normalize_or(s, fv_v3(1, 0, 0));
    fv_vec3 u = fv_v3_cross(s, f);
    fv_mat4 r = fv_mat4_identity();
    r.m[0][0] = s.x; r.m[1][0] = s.y; r.m[2][0] = s.z;
    r.m[0][1] = u.x; r.m[1][1] = u.y; r.m[2][1] = u.z;
    r.m[0][2] = -f.x; r.m[1][2] = -f.y; r.m[2][2] = -f.z;
    r.m[3][0] = -fv_v3_dot(s, eye);
    r.m[3][1] = -fv_v3_dot(u, eye);
    r.m[3][2] = fv_v3_dot(f, eye);
    return r;
}

fv_mat4 fv_mat4_perspective_tan(float tl, float tr, float tu, float td, float n, float f)
{
    /* View space: -z forward, +y up. Vulkan clip: y down, z in [0,1]. x_ndc = (2 x/(-z) - (tr+tl)) / (tr-tl). */
    fv_mat4 r;
    memset(&r, 0, sizeof r);
    float w = tr - tl, h = tu - td;
    r.m[0][0] = 2.0f / w;
    r.m[2][0] = (tr + tl) / w;           /* multiplies z (negative), so sign folds in the -z */
    r.m[1][1] = -2.0f / h;               /* Vulkan y points down */
    r.m[2][1] = -(tu + td) / h;
    r.m[2][2] = f / (n - f);
    r.m[3][2] = (n * f) / (n - f);
    r.m[2][3] = -1.0f;
    return r;
}

fv_quat fv_quat_identity(void) { return (fv_quat){0, 0, 0, 1}; }

fv_quat fv_quat_axis_angle(fv_vec3 axis, float angle_rad)
{
    fv_vec3 a = fv_v3_normalize_or(axis, fv_v3(0, 1, 0));
    float s = sinf(angle_rad * 0.5f);
    return (fv_quat){a.x * s, a.y * s, a.z * s, cosf(angle_rad * 0.5f)};
}

fv_quat fv_quat_mul(fv_quat a, fv_quat b)
{
    return (fv_quat){a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                     a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}

fv_quat fv_quat_normalize(fv_quat q)
{
    float len = sqrtf(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    if (!(len > 1e-30f) || !isfinite(len)) return fv_quat_identity();
    return (fv_quat){q.x / len, q.y / len, q.z / len, q.w / len};
}

fv_vec3 fv_quat_rotate(fv_quat q, fv_vec3 v)
{
    fv_vec3 u = {q.x, q.y, q.z};
    fv_vec3 t = fv_v3_scale(fv_v3_cross(u, v), 2.0f);
    return fv_v3_add(fv_v3_add(v, fv_v3_scale(t, q.w)), fv_v3_cross(u, t));
}

fv_quat fv_quat_slerp(fv_quat a, fv_quat b, float t)
{
    float d = a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
    if (d < 0) {
        b = (fv_quat){-b.x, -b.y, -b.z, -b.w};
        d = -d;
    }
    if (d > 0.9995f) {
        fv_quat r = {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.z + t * (b.z - a.z), a.w + t * (b.w - a.w)};
        return fv_quat_normalize(r);
    }
    float th = acosf(fv_clampf(d, -1.0f, 1.0f));
    float s = sinf(th);
    float wa = sinf((1 - t) * th) / s, wb = sinf(t * th) / s;
    return (fv_quat){wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z, wa * a.w + wb * b.w};
}

fv_quat fv_quat_from_basis(fv_vec3 right, fv_vec3 up, fv_vec3 back)
{
    /* Rotation matrix with columns right, up, back (local +x, +y, +z in world) to a quaternion (Shoemake). */
    float m00 = right.x, m10 = right.y, m20 = right.z;
    float m01 = up.x, m11 = up.y, m21 = up.z;
    float m02 = back.x, m12 = back.y, m22 = back.z;
    float tr = m00 + m11 + m22;
    fv_quat q;
    if (tr > 0.0f) {
        float k = sqrtf(tr + 1.0f) * 2.0f;
        q = (fv_quat){(m21 - m12) / k, (m02 - m20) / k, (m10 - m01) / k, 0.25f * k};
    } else if (m00 > m11 && m00 > m22) {
        float k = sqrtf(fmaxf(1.0f + m00 - m11 - m22, 1e-12f)) * 2.0f;
        q = (fv_quat){0.25f * k, (m01 + m10) / k, (m02 + m20) / k, (m21 - m12) / k};
    } else if (m11 > m22) {
        float k = sqrtf(fmaxf(1.0f + m11 - m00 - m22, 1e-12f)) * 2.0f;
        q = (fv_quat){(m01 + m10) / k, 0.25f * k, (m12 + m21) / k, (m02 - m20) / k};
    } else {
        float k = sqrtf(fmaxf(1.0f + m22 - m00 - m11, 1e-12f)) * 2.0f;
        q = (fv_quat){(m02 + m20) / k, (m12 + m21) / k, 0.25f * k, (m10 - m01) / k};
    }
    q = fv_quat_normalize(q);
    if (!(isfinite(q.x) && isfinite(q.y) && isfinite(q.z) && isfinite(q.w))) q = fv_quat_identity();
    return q;
}

fv_quat fv_quat_look_along(fv_vec3 forward)
{
    fv_vec3 f = fv_v3_normalize_or(forward, fv_v3(0, 0, -1));
    fv_vec3 r = fv_v3_cross(f, fv_v3(0, 1, 0));
    if (!(fv_v3_len(r) > 1e-6f)) r = fv_v3_cross(f, fv_v3(0, 0, -1)); /* looking straight up or down */
    r = fv_v3_normalize_or(r, fv_v3(1, 0, 0));
    fv_vec3 u = fv_v3_normalize_or(fv_v3_cross(r, f), fv_v3(0, 1, 0));
    return fv_quat_from_basis(r, u, fv_v3_scale(f, -1.0f));
}
