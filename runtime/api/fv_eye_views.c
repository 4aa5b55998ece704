/* @brief The one builder of per-eye views from a head pose (see fv_frame_input.h): eyes at +-IPD/2 along the head's
 * x axis, the HMD default asymmetric field of view (outer side wider, mirrored per eye), near/far clamped to a usable
 * range. Finite for any input: NaN poses fall back to identity, IPD is clamped. */
#include <math.h>
#include <string.h>

#include "fovea/fv_frame_input.h"

#define DEFAULT_NEAR_M 0.05f
#define DEFAULT_FAR_M 100.0f
#define MIN_NEAR_M 1e-5f
#define MAX_FAR_M 1e9f

void fv_near_far_sanitize(float *near_m, float *far_m)
{
    float n = *near_m, f = *far_m;
    if (!(n > 0.0f) || !isfinite(n)) n = DEFAULT_NEAR_M;
    n = fv_clampf(n, MIN_NEAR_M, MAX_FAR_M / 2.0f);
    if (!(f > 0.0f) || !isfinite(f)) f = fmaxf(DEFAULT_FAR_M, n * 1000.0f);
    if (f > MAX_FAR_M) f = MAX_FAR_M;
    if (f < n * 1.001f) f = n * 1.001f; /* a non-empty depth range keeps the projection finite */
    *near_m = n;
    *far_m = f;
}

void fv_near_far_from_bounds(const fv_head_pose *head, fv_vec3 bounds_min, fv_vec3 bounds_max, float *out_near_m,
                             float *out_far_m)
{
    float n = 0.0f, f = 0.0f;
    if (head && fv_v3_isfinite(bounds_min) && fv_v3_isfinite(bounds_max) && fv_v3_isfinite(head->position_m)) {
        fv_vec3 c = fv_v3_scale(fv_v3_add(bounds_min, bounds_max), 0.5f);
        double r = 0.5 * fv_v3_len(fv_v3_sub(bounds_max, bounds_min));
        double d = fv_v3_len(fv_v3_sub(c, head->position_m));
        if (isfinite(r) && isfinite(d)) {
            double ipd_m = isfinite(head->ipd_mm) ? fabs((double)head->ipd_mm) * 1e-3 : 0.0;
            double fd = (d + r + ipd_m) * 1.05 + 1e-3;
            /* Outside the bounding sphere: near just in front of it; inside: a small fraction of its size. */
            double nd = d - r - ipd_m > 0.0 ? 0.9 * (d - r - ipd_m) : 0.005 * (r > 0 ? r : 1.0);
            if (nd > fd * 0.5) nd = fd * 0.5;
            n = (float)nd;
            f = (float)fd;
        }
    }
    fv_near_far_sanitize(&n, &f);
    if (out_near_m) *out_near_m = n;
    if (out_far_m) *out_far_m = f;
}

static float sane_ipd_mm(float ipd_mm)
{
    return fv_clampf(isfinite(ipd_mm) ? ipd_mm : FV_DEFAULT_IPD_MM, 0.0f, FV_MAX_IPD_MM);
}

void fv_eyes_in_head(float ipd_mm, fv_eye_in_head out[2])
{
    float half_m = sane_ipd_mm(ipd_mm) * 0.5e-3f;
    for (int e = 0; e < 2; e++)
        out[e] = (fv_eye_in_head){.offset_m = fv_v3(e == 0 ? -half_m : half_m, 0.0f, 0.0f),
                                  .orientation = fv_quat_identity()};
}

/* The eye's orientation in the head, unit; identity when it is not a finite non-zero quaternion. */
static fv_quat eye_orientation(const fv_eye_in_head *eye)
{
    fv_quat q = eye ? eye->orientation : fv_quat_identity();
    double n = sqrt((double)q.x * q.x + (double)q.y * q.y + (double)q.z * q.z + (double)q.w * q.w);
    if (!isfinite(n) || n < 1e-6) return fv_quat_identity();
    return (fv_quat){(float)(q.x / n), (float)(q.y / n), (float)(q.z / n), (float)(q.w / n)};
}

fv_eye_gaze fv_eye_gaze_from_head(const fv_eye_in_head *eye, fv_vec3 dir_head, float uncertainty_deg)
{
    fv_eye_gaze g = {.valid = false, .dir_eye = fv_v3(0.0f, 0.0f, -1.0f), .uncertainty_deg = 180.0f};
    double len = sqrt((double)dir_head.x * dir_head.x + (double)dir_head.y * dir_head.y +
                      (double)dir_head.z * dir_head.z);
    if (!fv_v3_isfinite(dir_head) || !isfinite(len) || len < 1e-12) return g;
    fv_quat q = eye_orientation(eye);
    fv_quat inv = {-q.x, -q.y, -q.z, q.w};
    fv_vec3 d = fv_quat_rotate(inv, fv_v3((float)(dir_head.x / len), (float)(dir_head.y / len),
                                          (float)(dir_head.z / len)));
    g.dir_eye = fv_v3_normalize_or(d, fv_v3(0.0f, 0.0f, -1.0f));
    g.valid = fv_v3_isfinite(d);
    g.uncertainty_deg = g.valid && isfinite(uncertainty_deg) ? fv_clampf(uncertainty_deg, 0.0f, 180.0f) : 180.0f;
    return g;
}

fv_vec3 fv_eye_dir_to_head(const fv_eye_in_head *eye, fv_vec3 dir_eye)
{
    return fv_quat_rotate(eye_orientation(eye), dir_eye);
}

fv_vec3 fv_eye_point_to_head(const fv_eye_in_head *eye, fv_vec3 p_eye)
{
    fv_vec3 o = eye && fv_v3_isfinite(eye->offset_m) ? eye->offset_m : fv_v3(0.0f, 0.0f, 0.0f);
    return fv_v3_add(o, fv_quat_rotate(eye_orientation(eye), p_eye));
}

/* Both eyes' views from the head and each eye's frustum extents (tangents of its left, right, up and down half-angles,
 * all magnitudes); near/far already sanitized. */
static void build_views(const fv_head_pose *head, float near_m, float far_m, double ext[2][4], fv_eye_view out[2])
{
    fv_vec3 pos = head && fv_v3_isfinite(head->position_m) ? head->position_m : fv_v3(0, 0, 0);
    fv_quat q = head ? fv_quat_normalize(head->orientation) : fv_quat_identity();
    if (!(isfinite(q.x) && isfinite(q.y) && isfinite(q.z) && isfinite(q.w))) q = fv_quat_identity();
    fv_eye_in_head eyes[2]; /* where the eyes sit in the head: the same poses the gaze meets them by */
    fv_eyes_in_head(head ? head->ipd_mm : FV_DEFAULT_IPD_MM, eyes);

    fv_mat4 rot = fv_mat4_from_quat(q);
    fv_mat4 rot_t = fv_mat4_transpose(&rot);
    for (int e = 0; e < 2; e++) {
        fv_eye_view *v = &out[e];
        memset(v, 0, sizeof *v);
        fv_vec3 offset = fv_quat_rotate(q, eyes[e].offset_m); /* left eye at -x of the head */
        v->pos_world = fv_v3_add(pos, offset);
        /* view = R^T * T(-eye) */
        v->view = rot_t;
        fv_vec3 t = fv_mat4_mul_dir(&rot_t, v->pos_world);
        v->view.m[3][0] = -t.x;
        v->view.m[3][1] = -t.y;
        v->view.m[3][2] = -t.z;
        v->tan_left = (float)-ext[e][0];
        v->tan_right = (float)ext[e][1];
        v->tan_up = (float)ext[e][2];
        v->tan_down = (float)-ext[e][3];
        v->near_m = near_m;
        v->far_m = far_m;
        v->proj = fv_mat4_perspective_tan(v->tan_left, v->tan_right, v->tan_up, v->tan_down, near_m, far_m);
    }
}

void fv_eye_views_build(const fv_head_pose *head, float near_m, float far_m, uint32_t eye_width, uint32_t eye_height,
                        fv_eye_view out[2])
{
    fv_near_far_sanitize(&near_m, &far_m);

    /* Field of view: the vertical extent of the HMD default; the horizontal extent follows the image aspect so that
     * pixels stay square, split between the outer and inner side in the HMD's proportion (outer wider). Without an
     * image size, the HMD's own horizontal extent. */
    double t_up = tan(fv_deg_to_rad(FV_HMD_FOV_UP_DEG)), t_down = tan(fv_deg_to_rad(FV_HMD_FOV_DOWN_DEG));
    double t_outer = tan(fv_deg_to_rad(FV_HMD_FOV_OUTER_DEG)), t_inner = tan(fv_deg_to_rad(FV_HMD_FOV_INNER_DEG));
    double outer = t_outer, inner = t_inner;
    if (eye_width && eye_height) {
        double span_x = (t_up + t_down) * (double)eye_width / (double)eye_height;
        outer = span_x * t_outer / (t_outer + t_inner);
        inner = span_x - outer;
    }
    double ext[2][4] = {{outer, inner, t_up, t_down}, {inner, outer, t_up, t_down}};
    build_views(head, near_m, far_m, ext, out);
}

void fv_eye_views_build_fov(const fv_head_pose *head, float near_m, float far_m, const float fov[8],
                            fv_eye_view out[2])
{
    fv_near_far_sanitize(&near_m, &far_m);
    /* the default's extents stand in for any that is not a finite tangent in [1e-3, 100] (0.06..89.4 degrees) */
    const double def[4] = {tan(fv_deg_to_rad(FV_HMD_FOV_OUTER_DEG)), tan(fv_deg_to_rad(FV_HMD_FOV_INNER_DEG)),
                           tan(fv_deg_to_rad(FV_HMD_FOV_UP_DEG)), tan(fv_deg_to_rad(FV_HMD_FOV_DOWN_DEG))};
    double ext[2][4];
    for (int e = 0; e < 2; e++)
        for (int i = 0; i < 4; i++) {
            double t = fov ? (double)fov[4 * e + i] : NAN;
            int d = i < 2 && e == 1 ? 1 - i : i; /* the default mirrored: the right eye's outer side is its right */
            ext[e][i] = isfinite(t) && t >= 1e-3 && t <= 100.0 ? t : def[d];
        }
    build_views(head, near_m, far_m, ext, out);
}
