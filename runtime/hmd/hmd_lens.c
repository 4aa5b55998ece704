/* @brief The lens model of fv_lens.h in double precision: forward and inverse mapping, validation against folding,
 * and the hidden-area mask (see fv_hmd.h). The polynomial is OpenHMD's "universal" distortion (the panotools form
 * a r^3 + b r^2 + c r + d, here k = {d, c, b, a}); its inverse is solved per ray, never tabulated. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "fv_hmd.h"
#include "hmd_internal.h"

#define PI 3.14159265358979323846
#define MAX_SEGMENTS 1024u
/* Samples of the slope of rho when checking for folding; a fold narrower than 1/FOLD_SAMPLES of the range between two
 * samples of positive slope would need a cubic with two roots that close, which then also dips at a sample. */
#define FOLD_SAMPLES 8192
#define MIN_SLOPE 1e-4

void fv_hmd_say(char *err, size_t n, const char *fmt, ...)
{
    if (!err || !n) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, n, fmt, ap);
    va_end(ap);
}
#define say fv_hmd_say

double fv_lens_d(const fv_lens *l, double r)
{
    return (double)l->k[0] + r * ((double)l->k[1] + r * ((double)l->k[2] + r * (double)l->k[3]));
}

double fv_lens_rho(const fv_lens *l, double r) { return r * fv_lens_d(l, r); }

/* d(r d(r))/dr = k0 + 2 k1 r + 3 k2 r^2 + 4 k3 r^3 */
static double rho_slope(const fv_lens *l, double r)
{
    return (double)l->k[0] + r * (2.0 * l->k[1] + r * (3.0 * l->k[2] + r * 4.0 * l->k[3]));
}

static double eye_r_max(const fv_lens *l, int eye)
{
    double w = l->viewport_m[0], h = l->viewport_m[1];
    double cx = l->centre_m[eye][0], cy = l->centre_m[eye][1];
    double dx = fmax(cx, w - cx), dy = fmax(cy, h - cy);
    return sqrt(dx * dx + dy * dy) / (double)l->warp_m;
}

double fv_lens_r_max(const fv_lens *l)
{
    double r = fmax(eye_r_max(l, 0), eye_r_max(l, 1));
    if (l->visible_r > 0.0f && (double)l->visible_r < r) r = l->visible_r;
    return r;
}

static bool pos_finite(float x) { return isfinite(x) && x > 0.0f; }

fv_result fv_lens_validate(const fv_lens *l, char *err, size_t err_size)
{
    if (!l || !l->valid) {
        say(err, err_size, "lens: no lens");
        return FV_ERR_INVALID_ARG;
    }
    if (!pos_finite(l->viewport_m[0]) || !pos_finite(l->viewport_m[1]) || l->viewport_m[0] > 10.0f ||
        l->viewport_m[1] > 10.0f) {
        say(err, err_size, "panel: an eye's viewport of %g x %g m is not a size in (0, 10] m", (double)l->viewport_m[0],
            (double)l->viewport_m[1]);
        return FV_ERR_RANGE;
    }
    for (int e = 0; e < 2; e++)
        for (int i = 0; i < 2; i++) {
            float c = l->centre_m[e][i];
            if (!(isfinite(c) && c > 0.0f && c < l->viewport_m[i])) {
                say(err, err_size, "lens: the %s eye's centre %s = %g m is not inside its viewport (0..%g m)",
                    e ? "right" : "left", i ? "y" : "x", (double)c, (double)l->viewport_m[i]);
                return FV_ERR_RANGE;
            }
        }
    if (!pos_finite(l->warp_m) || l->warp_m > 10.0f) {
        say(err, err_size, "lens.warp_scale_m: %g is not a radius in (0, 10] m", (double)l->warp_m);
        return FV_ERR_RANGE;
    }
    if (!pos_finite(l->tan_per_m) || l->tan_per_m > 1e4f) {
        say(err, err_size, "lens.eye_to_screen_m: 1/%g is not a distance in [1e-4, inf) m", (double)l->tan_per_m);
        return FV_ERR_RANGE;
    }
    for (int c = 0; c < 3; c++)
        if (!(isfinite(l->aberration[c]) && l->aberration[c] >= 0.5f && l->aberration[c] <= 2.0f)) {
            say(err, err_size, "lens.aberration[%d]: %g is not a scale in [0.5, 2]", c, (double)l->aberration[c]);
            return FV_ERR_RANGE;
        }
    for (int i = 0; i < FV_LENS_K; i++)
        if (!isfinite(l->k[i]) || fabsf(l->k[i]) > 1e3f) {
            say(err, err_size, "lens.k[%d]: %g is not a finite coefficient in [-1000, 1000]", i, (double)l->k[i]);
            return FV_ERR_RANGE;
        }
    if (!(isfinite(l->visible_r) && l->visible_r >= 0.0f && l->visible_r <= 100.0f)) {
        say(err, err_size, "lens.visible_radius: %g is not 0 (the whole viewport) or a radius in (0, 100]",
            (double)l->visible_r);
        return FV_ERR_RANGE;
    }
    if (!(l->k[0] > 0.0f)) {
        say(err, err_size, "lens.k[0]: %g: d(0) must be > 0 (the lens centre would show nothing or be mirrored)",
            (double)l->k[0]);
        return FV_ERR_RANGE;
    }
    double r_max = fv_lens_r_max(l);
    for (int i = 0; i <= FOLD_SAMPLES; i++) {
        double r = r_max * (double)i / FOLD_SAMPLES;
        double s = rho_slope(l, r);
        if (!(s > MIN_SLOPE) || !(fv_lens_d(l, r) > 0.0)) {
            say(err, err_size,
                "lens.k: the radial mapping r d(r) with k = [%g, %g, %g, %g] folds at r = %.4f (slope %.4g, d %.4g) "
                "inside the visible range r <= %.4f: the image would fold onto itself",
                (double)l->k[0], (double)l->k[1], (double)l->k[2], (double)l->k[3], r, s, fv_lens_d(l, r), r_max);
            return FV_ERR_RANGE;
        }
    }
    return FV_OK;
}

void fv_lens_panel_to_tan(const fv_lens *l, int eye, int c, double u, double v, double *out_tx, double *out_ty)
{
    eye = eye ? 1 : 0;
    c = c < 0 ? 0 : c > 2 ? 2 : c;
    double qx = u * l->viewport_m[0] - l->centre_m[eye][0];
    double qy = v * l->viewport_m[1] - l->centre_m[eye][1];
    double r = sqrt(qx * qx + qy * qy) / (double)l->warp_m;
    double s = fv_lens_d(l, r) * (double)l->aberration[c] * (double)l->tan_per_m;
    *out_tx = qx * s;
    *out_ty = -qy * s;
}

/* The r in [0, r_hi] with rho(r) = target (rho increasing there): Newton steps kept inside a bisection bracket. */
static double rho_inverse(const fv_lens *l, double target, double r_hi)
{
    double lo = 0.0, hi = r_hi, r = fmin(target / (double)l->k[0], r_hi);
    for (int it = 0; it < 100; it++) {
        double f = fv_lens_rho(l, r) - target;
        if (fabs(f) < 1e-12) break;
        if (f > 0) hi = r;
        else lo = r;
        double s = rho_slope(l, r);
        double next = s > 0 ? r - f / s : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        r = next;
        if (hi - lo < 1e-13) break;
    }
    return r;
}

bool fv_lens_tan_to_panel(const fv_lens *l, int eye, int c, double tx, double ty, double *out_u, double *out_v)
{
    eye = eye ? 1 : 0;
    c = c < 0 ? 0 : c > 2 ? 2 : c;
    if (!isfinite(tx) || !isfinite(ty)) return false;
    /* undistorted metres from the lens centre, y down */
    double qx = tx / (double)l->tan_per_m, qy = -ty / (double)l->tan_per_m;
    double len = sqrt(qx * qx + qy * qy);
    double target = len / ((double)l->warp_m * (double)l->aberration[c]);
    double r_hi = fv_lens_r_max(l);
    if (target > fv_lens_rho(l, r_hi) * (1.0 + 1e-12)) return false;
    double r = len > 0 ? rho_inverse(l, target, r_hi) : 0.0;
    double scale = len > 0 ? r * (double)l->warp_m / len : 0.0;
    *out_u = (qx * scale + l->centre_m[eye][0]) / (double)l->viewport_m[0];
    *out_v = (qy * scale + l->centre_m[eye][1]) / (double)l->viewport_m[1];
    return true;
}

static int widest_channel(const fv_lens *l)
{
    int c = 0;
    for (int i = 1; i < 3; i++)
        if (l->aberration[i] > l->aberration[c]) c = i;
    return c;
}

bool fv_lens_tan_visible(const fv_lens *l, int eye, double tx, double ty)
{
    /* All channels map a ray along the same direction; the widest reaches it from the smallest panel radius. */
    double u, v;
    if (!fv_lens_tan_to_panel(l, eye, widest_channel(l), tx, ty, &u, &v)) return false;
    if (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0) return false;
    if (l->visible_r > 0.0f) {
        eye = eye ? 1 : 0;
        double qx = u * l->viewport_m[0] - l->centre_m[eye][0], qy = v * l->viewport_m[1] - l->centre_m[eye][1];
        if (sqrt(qx * qx + qy * qy) / (double)l->warp_m > (double)l->visible_r * (1.0 + 1e-12)) return false;
    }
    return true;
}

/* The tangent radius of the visible region's boundary along tangent direction theta: the panel boundary (viewport
 * edge or visible radius) along the same direction, mapped by the widest channel. */
static double boundary_tan(const fv_lens *l, int eye, double theta)
{
    double dx = cos(theta), dy = -sin(theta); /* panel direction, y down */
    double w = l->viewport_m[0], h = l->viewport_m[1];
    double cx = l->centre_m[eye][0], cy = l->centre_m[eye][1];
    double t = INFINITY;
    if (dx > 1e-15) t = fmin(t, (w - cx) / dx);
    if (dx < -1e-15) t = fmin(t, -cx / dx);
    if (dy > 1e-15) t = fmin(t, (h - cy) / dy);
    if (dy < -1e-15) t = fmin(t, -cy / dy);
    double r = t / (double)l->warp_m;
    if (l->visible_r > 0.0f && (double)l->visible_r < r) r = l->visible_r;
    return fv_lens_rho(l, r) * (double)l->warp_m * (double)l->aberration[widest_channel(l)] * (double)l->tan_per_m;
}

static uint32_t clamp_segments(uint32_t n) { return n < 16 ? 16 : n > MAX_SEGMENTS ? MAX_SEGMENTS : n; }

/* The tangent radius at angle phi of the chord from (theta0, a) to (theta1, b), in polar form. */
static double chord_radius(double theta0, double a, double theta1, double b, double phi)
{
    return a * b * sin(theta1 - theta0) / (a * sin(phi - theta0) + b * sin(theta1 - phi));
}

/* Radii of the mask polygon's inner vertices at theta_i = 2 pi i / n: the visible region's boundary there, pushed out
 * until each sector's chord lies outside the boundary at 16 angles across the sector (the largest ratio of boundary
 * to chord), plus 1e-4. Moving a vertex outward along its ray only moves the chords through it outward, so a vertex
 * takes the larger push of its two sectors. The region is star-shaped about the lens axis (a radial map of the
 * convex viewport-and-circle), so the polygon's outside is never seen. */
static void inner_radii(const fv_lens *l, int eye, uint32_t n, double margin, double *out)
{
    double b[MAX_SEGMENTS], push[MAX_SEGMENTS];
    const int sub = 16;
    for (uint32_t i = 0; i < n; i++) b[i] = boundary_tan(l, eye, 2.0 * PI * i / n);
    for (uint32_t i = 0; i < n; i++) {
        double t0 = 2.0 * PI * i / n, t1 = 2.0 * PI * (i + 1) / n, m = 1.0;
        for (int s = 1; s < sub; s++) {
            double phi = t0 + (t1 - t0) * s / sub;
            m = fmax(m, boundary_tan(l, eye, phi) / chord_radius(t0, b[i], t1, b[(i + 1) % n], phi));
        }
        push[i] = m * (1.0 + 1e-4);
    }
    /* The margin: moving a vertex out by m along its ray moves a chord through it by m cos(angle between the ray and
     * the chord's normal), so each sector asks m / cos of the larger of its two angles (cos capped at 0.1) of both
     * its vertices, and a vertex takes the larger ask of its two sectors. */
    double m = isfinite(margin) && margin > 0 ? margin : 0.0, ask[MAX_SEGMENTS];
    for (uint32_t i = 0; i < n; i++) {
        uint32_t j = (i + 1) % n;
        double t0 = 2.0 * PI * i / n, t1 = 2.0 * PI * (i + 1) / n;
        double ri = b[i] * push[i], rj = b[j] * push[i];
        double ax = ri * cos(t0), ay = ri * sin(t0), bx = rj * cos(t1), by = rj * sin(t1);
        double nx = by - ay, ny = ax - bx, len = sqrt(nx * nx + ny * ny);
        double c0 = len > 0 ? fabs(nx * cos(t0) + ny * sin(t0)) / len : 1.0;
        double c1 = len > 0 ? fabs(nx * cos(t1) + ny * sin(t1)) / len : 1.0;
        ask[i] = m / fmax(fmin(c0, c1), 0.1);
    }
    for (uint32_t i = 0; i < n; i++)
        out[i] = b[i] * fmax(push[i], push[(i + n - 1) % n]) + fmax(ask[i], ask[(i + n - 1) % n]);
}

static void tan_to_ndc(const fv_hmd_fov *f, double tx, double ty, float tag, float *out)
{
    out[0] = (float)(2.0 * (tx + f->tan_left) / ((double)f->tan_left + f->tan_right) - 1.0);
    out[1] = (float)(2.0 * (f->tan_up - ty) / ((double)f->tan_up + f->tan_down) - 1.0);
    out[2] = tag;
}

double fv_lens_mask_margin(const fv_hmd_fov *f, uint32_t width, uint32_t height)
{
    if (!width || !height) return 0.0;
    double tx = ((double)f->tan_left + f->tan_right) / width, ty = ((double)f->tan_up + f->tan_down) / height;
    return 1.5 * fmax(tx, ty);
}

static double corner_radius(const fv_hmd_fov *f)
{
    double x = fmax(f->tan_left, f->tan_right), y = fmax(f->tan_up, f->tan_down);
    return sqrt(x * x + y * y);
}

uint32_t fv_lens_hidden_mesh(const fv_lens *l, int eye, const fv_hmd_fov *frustum, uint32_t segments,
                             double margin_tan, float tag, float *out_xyz, uint32_t cap_vertices)
{
    eye = eye ? 1 : 0;
    uint32_t n = clamp_segments(segments);
    double r[MAX_SEGMENTS];
    inner_radii(l, eye, n, margin_tan, r);
    double corner = corner_radius(frustum);
    double outer = 2.0 * corner / cos(PI / n);
    uint32_t count = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t j = (i + 1) % n;
        if (fmin(r[i], r[j]) * cos(PI / n) >= corner) continue; /* the whole sector of the frustum is visible */
        double a0 = 2.0 * PI * i / n, a1 = 2.0 * PI * (i + 1) / n;
        double p[4][2] = {{r[i] * cos(a0), r[i] * sin(a0)},
                          {r[j] * cos(a1), r[j] * sin(a1)},
                          {outer * cos(a1), outer * sin(a1)},
                          {outer * cos(a0), outer * sin(a0)}};
        static const int tri[6] = {0, 1, 2, 0, 2, 3};
        for (int t = 0; t < 6; t++, count++)
            if (out_xyz && count < cap_vertices) tan_to_ndc(frustum, p[tri[t]][0], p[tri[t]][1], tag, out_xyz + 3 * count);
    }
    return count;
}

void fv_lens_hidden_fraction(const fv_lens *l, int eye, const fv_hmd_fov *frustum, uint32_t width, uint32_t height,
                             uint32_t segments, double margin_tan, double *out_hidden, double *out_masked)
{
    eye = eye ? 1 : 0;
    uint32_t n = clamp_segments(segments);
    double r[MAX_SEGMENTS];
    inner_radii(l, eye, n, margin_tan, r);
    uint64_t hidden = 0, masked = 0, total = (uint64_t)width * height;
    for (uint32_t y = 0; y < height; y++)
        for (uint32_t x = 0; x < width; x++) {
            double tx = -frustum->tan_left + ((double)x + 0.5) / width * ((double)frustum->tan_left + frustum->tan_right);
            double ty = frustum->tan_up - ((double)y + 0.5) / height * ((double)frustum->tan_up + frustum->tan_down);
            if (out_hidden && !fv_lens_tan_visible(l, eye, tx, ty)) hidden++;
            /* inside the mask: beyond the chord between the sector's two inner vertices */
            double phi = atan2(ty, tx);
            if (phi < 0) phi += 2.0 * PI;
            uint32_t i = (uint32_t)(phi / (2.0 * PI) * n) % n, j = (i + 1) % n;
            double a0 = 2.0 * PI * i / n, a1 = 2.0 * PI * (i + 1) / n;
            double ax = r[i] * cos(a0), ay = r[i] * sin(a0), bx = r[j] * cos(a1), by = r[j] * sin(a1);
            /* the point is outside the polygon when it lies on the far side of the chord a->b from the origin */
            double cross_p = (bx - ax) * (ty - ay) - (by - ay) * (tx - ax);
            double cross_o = (bx - ax) * (0 - ay) - (by - ay) * (0 - ax);
            if (cross_p * cross_o < 0) masked++;
        }
    if (out_hidden) *out_hidden = total ? (double)hidden / (double)total : 0.0;
    if (out_masked) *out_masked = total ? (double)masked / (double)total : 0.0;
}
