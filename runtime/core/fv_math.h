/* @brief Small float math: vec2/3/4, column-major mat4 (matches GLSL), quaternions, Vulkan projections.
 * Frames: right-handed, +x right, +y up, -z forward (view looks down -z). Clip space is Vulkan's: x right, y down,
 * depth 0 (near) .. 1 (far). */
#ifndef FV_MATH_H
#define FV_MATH_H

#include <math.h>
#include <stdbool.h>

#define FV_PI 3.14159265358979323846

typedef struct fv_vec2 { float x, y; } fv_vec2;
typedef struct fv_vec3 { float x, y, z; } fv_vec3;
typedef struct fv_vec4 { float x, y, z, w; } fv_vec4;
/** Column-major: m[col][row], as GLSL mat4. */
typedef struct fv_mat4 { float m[4][4]; } fv_mat4;
/** Unit quaternion (x, y, z, w), w the scalar part. */
typedef struct fv_quat { float x, y, z, w; } fv_quat;

static inline fv_vec3 fv_v3(float x, float y, float z) { return (fv_vec3){x, y, z}; }
static inline fv_vec3 fv_v3_add(fv_vec3 a, fv_vec3 b) { return (fv_vec3){a.x + b.x, a.y + b.y, a.z + b.z}; }
static inline fv_vec3 fv_v3_sub(fv_vec3 a, fv_vec3 b) { return (fv_vec3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static inline fv_vec3 fv_v3_scale(fv_vec3 a, float s) { return (fv_vec3){a.x * s, a.y * s, a.z * s}; }
static inline fv_vec3 fv_v3_mul(fv_vec3 a, fv_vec3 b) { return (fv_vec3){a.x * b.x, a.y * b.y, a.z * b.z}; }
static inline float fv_v3_dot(fv_vec3 a, fv_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline fv_vec3 fv_v3_cross(fv_vec3 a, fv_vec3 b)
{
    return (fv_vec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static inline float fv_v3_len(fv_vec3 a) { return sqrtf(fv_v3_dot(a, a)); }
static inline fv_vec3 fv_v3_min(fv_vec3 a, fv_vec3 b) { return (fv_vec3){fminf(a.x, b.x), fminf(a.y, b.y), fminf(a.z, b.z)}; }
static inline fv_vec3 fv_v3_max(fv_vec3 a, fv_vec3 b) { return (fv_vec3){fmaxf(a.x, b.x), fmaxf(a.y, b.y), fmaxf(a.z, b.z)}; }
/** Normalise; a zero or non-finite vector returns `fallback` instead of NaN. */
fv_vec3 fv_v3_normalize_or(fv_vec3 a, fv_vec3 fallback);
static inline bool fv_v3_isfinite(fv_vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

fv_mat4 fv_mat4_identity(void);
fv_mat4 fv_mat4_mul(const fv_mat4 *a, const fv_mat4 *b);      /* a * b */
fv_vec4 fv_mat4_mul_v4(const fv_mat4 *a, fv_vec4 v);
fv_vec3 fv_mat4_mul_point(const fv_mat4 *a, fv_vec3 p);        /* w = 1, no divide */
fv_vec3 fv_mat4_mul_dir(const fv_mat4 *a, fv_vec3 d);          /* w = 0 */
fv_mat4 fv_mat4_translate(fv_vec3 t);
fv_mat4 fv_mat4_scale(fv_vec3 s);
fv_mat4 fv_mat4_from_quat(fv_quat q);
/** T * R * S, the glTF node order. */
fv_mat4 fv_mat4_trs(fv_vec3 t, fv_quat r, fv_vec3 s);
fv_mat4 fv_mat4_transpose(const fv_mat4 *a);
/** General inverse; returns false (and identity) when singular or non-finite. */
bool fv_mat4_invert(const fv_mat4 *a, fv_mat4 *out_inv);
/** View matrix of an eye at `eye` looking at `target` with `up`. Degenerate input falls back to a valid basis. */
fv_mat4 fv_mat4_look_at(fv_vec3 eye, fv_vec3 target, fv_vec3 up);
/** Asymmetric perspective for Vulkan clip space (y down, depth 0..1), from the tangents of the four half-angles
 *  (left and down are negative for a centred frustum, as OpenXR's fov angles). near > 0, far > near. */
fv_mat4 fv_mat4_perspective_tan(float tan_left, float tan_right, float tan_up, float tan_down, float near_m,
                                float far_m);

fv_quat fv_quat_identity(void);
fv_quat fv_quat_axis_angle(fv_vec3 axis, float angle_rad);
fv_quat fv_quat_mul(fv_quat a, fv_quat b);
fv_quat fv_quat_normalize(fv_quat q);
fv_vec3 fv_quat_rotate(fv_quat q, fv_vec3 v);
/** Spherical interpolation along the shorter arc; t in [0,1]. */
fv_quat fv_quat_slerp(fv_quat a, fv_quat b, float t);
/** The rotation whose local +x, +y, +z are right, up, back (an orthonormal basis); identity when not finite. */
fv_quat fv_quat_from_basis(fv_vec3 right, fv_vec3 up, fv_vec3 back);
/** The orientation that looks down `forward` (its local -z) with +y up and no roll; straight up or down: a defined
 *  right axis; a zero or non-finite forward: -z. */
fv_quat fv_quat_look_along(fv_vec3 forward);

static inline float fv_clampf(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }
static inline double fv_deg_to_rad(double d) { return d * (FV_PI / 180.0); }
static inline double fv_rad_to_deg(double r) { return r * (180.0 / FV_PI); }

#endif
