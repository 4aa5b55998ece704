/* @brief The geometry of shadow maps, pure functions (no GPU): the parallel-split scheme's split distances (Zhang et
 * al. 2006), the visible depth range of a box from an eye, the corners of a frustum slice, the crop of an
 * orthographic light view around a set of points (stable under head motion: a fixed-size sphere snapped to whole
 * texels), and Vulkan orthographic projections. Finite for any input. */
#ifndef FV_SHADOW_MATH_H
#define FV_SHADOW_MATH_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_frame_input.h"
#include "fv_math.h"

/** Split distances C_0..C_m along view depth (Zhang et al. 2006, practical scheme):
 *  C_i = lambda * n * (f/n)^(i/m) + (1 - lambda) * (n + (f - n) * i/m). out holds m + 1 values; out[0] = n and
 *  out[m] = f exactly, non-decreasing, finite. Input is sanitised: n <= 0 or non-finite -> 1e-4 (and f > n forced),
 *  lambda clamped to [0, 1] (NaN -> 0.5), m clamped to [1, FV_SHADOW_SPLITS_MAX]. Returns the m used. */
#define FV_SHADOW_SPLITS_MAX 8
uint32_t fv_shadow_split_distances(double n, double f, uint32_t m, double lambda, double *out);

/** How many of `want` splits a depth range deserves: perspective aliasing grows with log(f/n), so a shallow range
 *  gets fewer, min(want, max(1, ceil(log2(f/n)))). */
uint32_t fv_shadow_splits_for_range(double n, double f, uint32_t want);

/** The view depths (along the eye's -z) at which the box [bmin, bmax] is seen through `view`, clamped to
 *  [near_m, far_m]; false (and near/far as given) when the box is entirely outside that range. */
bool fv_shadow_depth_range(const fv_mat4 *view, fv_vec3 bmin, fv_vec3 bmax, float near_m, float far_m, double *out_n,
                           double *out_f);

/** The 8 world-space corners of the eye's frustum between view depths d0 and d1. */
void fv_shadow_slice_corners(const fv_eye_view *eye, double d0, double d1, fv_vec3 out[8]);

/** Vulkan orthographic projection of a light view (looking down -z): x in [l, r] -> [-1, 1], y in [b, t] -> [1, -1]
 *  (Vulkan y down), view depth -z in [n, f] -> [0, 1]. Degenerate extents are widened to stay invertible. */
fv_mat4 fv_shadow_ortho(double l, double r, double b, double t, double n, double f);

/** A rotation-only view looking along `dir` (the way the light travels). */
fv_mat4 fv_shadow_light_view(fv_vec3 dir);

/** View-projection of an orthographic light map that holds every point of `pts` (the receivers) with casters
 *  toward the light out to the box [bmin, bmax]: a bounding sphere of the points, its radius rounded up to a
 *  1/64 step of its power of two and its centre snapped to whole texels of a res x res map, so the map stays put
 *  as the head moves. out_texel_m (may be NULL): world size of one texel. */
fv_mat4 fv_shadow_crop_directional(const fv_mat4 *light_view, const fv_vec3 *pts, uint32_t count, fv_vec3 bmin,
                                   fv_vec3 bmax, uint32_t res, double *out_texel_m);

/** View-projection of a spot light's perspective map: from pos along dir, half-angle outer_rad (+2%), far at the
 *  box's farthest corner, near = far / 1000. */
fv_mat4 fv_shadow_spot(fv_vec3 pos, fv_vec3 dir, float outer_rad, fv_vec3 bmin, fv_vec3 bmax);
/** View-projection of one face of a point light's cube map (face 0..5 = +x -x +y -y +z -z): 90 degrees (+2% so
 *  filtering at face edges stays inside), far at the box's farthest corner, near = far / 1000. */
fv_mat4 fv_shadow_cube_face(fv_vec3 pos, uint32_t face, fv_vec3 bmin, fv_vec3 bmax);
/** A cube face's texel size per metre of distance from the light, for a res x res face. */
double fv_shadow_cube_texel_per_m(uint32_t res);
/** A spot map's texel size per metre of distance from the light, for a res x res map. */
double fv_shadow_spot_texel_per_m(float outer_rad, uint32_t res);

#endif
