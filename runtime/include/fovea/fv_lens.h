/* @brief An HMD's lens as plain data (the seam between runtime/hmd, which loads it from a profile, and the renderer's
 * distortion pass and hidden-area mask, which apply it): the radial polynomial and per-channel scale of the
 * "universal" (panotools) model that OpenHMD uses, around each eye's lens centre on its half of the panel.
 *
 * The model, for a point p of one eye's panel viewport (metres from its top-left corner, y down):
 *   q = p - centre_m[eye]                   (metres from the lens centre)
 *   r = |q| / warp_m                        (normalised radius)
 *   d(r) = k[0] + k[1] r + k[2] r^2 + k[3] r^3
 *   q_c = q d(r) aberration[c]               (channel c: where the undistorted image holds the colour this pixel shows)
 *   tangent of the ray (x right, y up) = (q_c.x, -q_c.y) * tan_per_m
 * so k = {1, 0, 0, 0} with aberration 1 is the identity. The undistorted tangent is then sampled from the eye's
 * rendered image through the frame's own frustum (fv_eye_view tan_*). Pure data; zero = no lens (valid false). */
#ifndef FV_LENS_H
#define FV_LENS_H

#include <stdbool.h>

/** The largest degree + 1 of the radial polynomial. */
#define FV_LENS_K 4

typedef struct fv_lens {
    bool valid;                  /* false: no HMD lens (nothing is distorted or masked) */
    float viewport_m[2];         /* one eye's panel viewport (half the panel): width, height in metres */
    float centre_m[2][2];        /* per eye (0 left, 1 right): the lens centre in its viewport, metres, y down */
    float warp_m;                /* the radius that r is normalised by, metres (> 0) */
    float tan_per_m;             /* 1 / eye-to-screen distance: tangent per undistorted metre (> 0) */
    float k[FV_LENS_K];          /* d(r) = k0 + k1 r + k2 r^2 + k3 r^3 */
    float aberration[3];         /* per-channel scale of the undistorted radius: red, green, blue */
    float visible_r;             /* normalised radius the lens shows; beyond it the panel is black and the rendered
                                  * pixels only seen there are masked. 0: the whole viewport rectangle */
} fv_lens;

/** Whether two lenses are the same (field by field; two invalid lenses are equal whatever they hold). */
static inline bool fv_lens_equal(const fv_lens *a, const fv_lens *b)
{
    if (a->valid != b->valid) return false;
    if (!a->valid) return true;
    bool same = a->warp_m == b->warp_m && a->tan_per_m == b->tan_per_m && a->visible_r == b->visible_r;
    for (int i = 0; i < 2; i++) {
        same = same && a->viewport_m[i] == b->viewport_m[i];
        for (int e = 0; e < 2; e++) same = same && a->centre_m[e][i] == b->centre_m[e][i];
    }
    for (int i = 0; i < FV_LENS_K; i++) same = same && a->k[i] == b->k[i];
    for (int c = 0; c < 3; c++) same = same && a->aberration[c] == b->aberration[c];
    return same;
}

#endif
