/* @brief HMD profiles and the lens model (runtime/hmd): a profile is a small JSON file (hmd/NAME.json in the repository,
 * embedded in the binary, or any file) giving the panel, its refresh rate, the lenses (centres, the radial polynomial,
 * the per-channel chromatic scale, the visible radius), each eye's field of view and the source of every value. The
 * lens model (fv_lens.h) is evaluated here in double precision, forward (panel -> tangent) and inverse (tangent ->
 * panel), validated (a polynomial that folds the image over the visible range is refused), and turned into the
 * hidden-area mask (the rendered pixels no panel pixel shows, as triangles). Pure C: no Vulkan, no clock; the loader
 * reads one file. Thread-safe (no shared state). */
#ifndef FV_HMD_H
#define FV_HMD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fovea/fv_lens.h"
#include "fv_result.h"

#define FV_HMD_NAME_MAX 64
#define FV_HMD_TEXT_MAX 256

/** One eye's field of view as the tangents of its four half-angles (all > 0 for a frustum around the view axis). */
typedef struct fv_hmd_fov {
    float tan_left, tan_right, tan_up, tan_down;
} fv_hmd_fov;

/** A loaded HMD profile. */
typedef struct fv_hmd_profile {
    char name[FV_HMD_NAME_MAX];         /* "generic", "htc-vive", ... */
    char description[FV_HMD_TEXT_MAX];
    char origin[FV_HMD_TEXT_MAX];       /* "builtin:NAME" or the file path it was read from */
    uint32_t panel_width_px, panel_height_px; /* the whole panel, both eyes side by side */
    float panel_width_m, panel_height_m;
    float refresh_hz;
    fv_lens lens;                       /* valid */
    fv_hmd_fov fov[2];                  /* per eye (0 left, 1 right); consistent with the lens geometry (checked) */
} fv_hmd_profile;

/** The names of the built-in profiles, NULL-terminated (static storage). */
const char *const *fv_hmd_builtin_names(void);

/** Load a profile: a built-in name (fv_hmd_builtin_names) or a path to a JSON file (a byte-identical copy of a
 *  built-in profile's file loads as that profile, origin "builtin:NAME ..." included). On error *out is untouched and
 *  err receives one line naming the file, the field and the reason (FV_ERR_NOT_FOUND: no such profile or file;
 *  FV_ERR_IO: unreadable; FV_ERR_PARSE: not JSON or a field missing or of the wrong type; FV_ERR_RANGE: a value out
 *  of range, inconsistent, or a lens that folds the image). */
FV_MUST_CHECK fv_result fv_hmd_profile_load(const char *name_or_path, fv_hmd_profile *out, char *err, size_t err_size);

/** Parse a profile from JSON text (`origin` names it in messages). Same errors as fv_hmd_profile_load. */
FV_MUST_CHECK fv_result fv_hmd_profile_parse(const char *json, size_t len, const char *origin, fv_hmd_profile *out,
                                             char *err, size_t err_size);

/* ---- the lens model (fv_lens.h), double precision --------------------------------------------------------------- */

/** d(r) = k0 + k1 r + k2 r^2 + k3 r^3. */
double fv_lens_d(const fv_lens *l, double r);
/** The radial mapping rho(r) = r d(r) (normalised radius on the panel -> normalised undistorted radius). */
double fv_lens_rho(const fv_lens *l, double r);
/** The largest normalised panel radius either eye shows: the farthest viewport corner from its lens centre, or
 *  visible_r when that is smaller. The range over which the lens must not fold. */
double fv_lens_r_max(const fv_lens *l);

/** Check a lens: finite positive sizes, centres inside their viewports, aberration in [0.5, 2], k0 > 0 and rho
 *  strictly increasing over [0, fv_lens_r_max] (else the image folds onto itself). FV_OK, or FV_ERR_RANGE with one
 *  line in err naming the field ("lens.k", ...) and the reason. */
FV_MUST_CHECK fv_result fv_lens_validate(const fv_lens *l, char *err, size_t err_size);

/** Forward: the point (u, v) of eye's panel viewport (uv in [0,1], y down) shows, in channel c (0 R, 1 G, 2 B), the
 *  undistorted ray of tangent (tx right, ty up). Finite for finite input. */
void fv_lens_panel_to_tan(const fv_lens *l, int eye, int c, double u, double v, double *out_tx, double *out_ty);
/** Inverse: the panel point whose channel c shows the ray of tangent (tx, ty). False when no panel radius in
 *  [0, fv_lens_r_max] maps there (the ray is beyond what the lens shows); out_u/out_v then unset. Accurate to 1e-9
 *  in normalised radius (Newton steps inside a bisection bracket). */
bool fv_lens_tan_to_panel(const fv_lens *l, int eye, int c, double tx, double ty, double *out_u, double *out_v);
/** Whether any channel of any visible panel point of eye (inside its viewport and within visible_r) shows the ray
 *  of tangent (tx, ty): false means a rendered pixel there is never seen. */
bool fv_lens_tan_visible(const fv_lens *l, int eye, double tx, double ty);

/** The hidden-area mask of one eye as triangles in Vulkan NDC of a frustum with these tangents (x right, y down;
 *  3 floats per vertex: x, y and `tag`, which the caller may use to tell eyes apart; 3 vertices per triangle),
 *  conservative: every point it covers is at least margin_tan (a tangent distance, e.g. 1.5 texels so that no
 *  bilinear tap of a visible sample reads a masked texel) from any point fv_lens_tan_visible shows, and it covers
 *  all other hidden points but a thin band (< 1e-4 of the radius plus the chord sag between 16 checks per sector).
 *  `segments` angular sectors (clamped to 16..1024). Writes at most cap_vertices vertices; returns the count it
 *  needs (call with cap 0 to size). */
uint32_t fv_lens_hidden_mesh(const fv_lens *l, int eye, const fv_hmd_fov *frustum, uint32_t segments,
                             double margin_tan, float tag, float *out_xyz, uint32_t cap_vertices);

/** Over the pixel centres of a width x height eye image of that frustum: the fraction never seen (exact, from
 *  fv_lens_tan_visible; the expensive one, NULL skips it) and the fraction the mask of fv_lens_hidden_mesh with the
 *  same segments and margin covers. Either out may be NULL. */
void fv_lens_hidden_fraction(const fv_lens *l, int eye, const fv_hmd_fov *frustum, uint32_t width, uint32_t height,
                             uint32_t segments, double margin_tan, double *out_hidden, double *out_masked);

/** The margin the renderer's mask keeps from the visible region: 1.5 texels of a width x height eye image of this
 *  frustum (its larger texel side), so bilinear sampling of the visible region never reads a masked texel. */
double fv_lens_mask_margin(const fv_hmd_fov *frustum, uint32_t width, uint32_t height);

/** The mask's segment count used by the renderer. */
#define FV_LENS_MASK_SEGMENTS 256u

#endif
