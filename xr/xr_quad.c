/* @brief Quad views (XR_VARJO_quad_views, extension 38) and gaze-driven insets (XR_VARJO_foveated_rendering,
 * extension 122). Views 0 and 1 are the wide left / right eye views over the HMD's whole field of view; views 2 and 3
 * are the insets, the same eyes' poses with a smaller field of view. The inset's angular radius comes from fovea's
 * linear MAR model (w = m e + w0, the quality's fovea.mar_slope / fovea.mar_w0_deg): with the wide views rendered at
 * FV_XR_QUAD_WIDE_DENSITY of the display's centre pixel density, the eye resolves a wide pixel only beyond the
 * eccentricity e_w where w(e_w) = the wide pixel's angle; the inset covers e_w plus the gaze pipeline's uncertainty
 * (>= the tracker's accuracy), plus the band over which the compositor blends it into the wide view. With foveated
 * rendering active the insets are centred on the gaze predicted to the views' display time; without it, or while
 * the gaze is not tracked, they sit at the centre of the field of view. */
#include <math.h>

#include "fovea/fv_frame_input.h"
#include "xr_internal.h"

#define DEG_PER_RAD 57.29577951308232
/* chosen: the wide views' linear pixel density, a fraction of the display's centre density, when foveated rendering
 * is active (the periphery at a quarter of the pixels); the insets are at the display's density */
#define FV_XR_QUAD_WIDE_DENSITY 0.5
/* chosen: the blend band, a fraction of the inset's angular radius, inside the inset's edge */
#define FV_XR_QUAD_BAND_FRAC 0.25
/* chosen: the gaze uncertainty the recommended inset size is sized for (the pipeline's floor, its default tracker
 * accuracy), and the largest one the inset grows by (a saccade's or a lost track's uncertainty) */
#define FV_XR_QUAD_NOMINAL_UNCERTAINTY_DEG 0.5
#define FV_XR_QUAD_MAX_UNCERTAINTY_DEG 10.0

/* The angle of the display's centre pixel (deg): 2 atan(dt / 2), dt the tangent step of one native panel pixel (the
 * HMD's density, not the app's render scale: the inset is a property of the display and the eye). */
static double centre_pixel_deg(const fv_hmd_profile *h)
{
    double tw = (double)h->fov[0].tan_left + (double)h->fov[0].tan_right;
    double th = (double)h->fov[0].tan_up + (double)h->fov[0].tan_down;
    double px_w = h->panel_width_px > 1 ? 0.5 * (double)h->panel_width_px : 1.0;
    double px_h = h->panel_height_px > 0 ? (double)h->panel_height_px : 1.0;
    double dt = fmin(tw / px_w, th / px_h);
    return 2.0 * atan(0.5 * dt) * DEG_PER_RAD;
}

double fv_xr_quad_inset_radius_deg(const struct XrInstance_T *inst, double uncertainty_deg)
{
    fv_quality q; /* foveation's knobs at the frame budget's level (xr_gaze.c) */
    fv_xr_budget_quality(inst->session ? inst->session->budget : NULL, &q);
    double m = q.fovea.mar_slope > 1e-4f ? (double)q.fovea.mar_slope : 1e-4;
    double w0 = (double)q.fovea.mar_w0_deg;
    double w_wide = centre_pixel_deg(&inst->hmd) / FV_XR_QUAD_WIDE_DENSITY;
    double e_w = w_wide > w0 ? (w_wide - w0) / m : 0.0; /* Guenter et al. 2012, linear MAR: w = m e + w0 */
    double u = isfinite(uncertainty_deg) ? fmin(fmax(uncertainty_deg, 0.0), FV_XR_QUAD_MAX_UNCERTAINTY_DEG)
                                         : FV_XR_QUAD_MAX_UNCERTAINTY_DEG;
    double r = (e_w + u) / (1.0 - FV_XR_QUAD_BAND_FRAC); /* full weight out to e_w + u, then the band */
    return fmin(fmax(r, 0.5), 60.0);
}

/* The wide view of eye e as angles (rad): left, right (of 0), up, down (of 0), as XrFovf. */
static XrFovf wide_fov(const fv_hmd_profile *h, uint32_t e)
{
    const fv_hmd_fov *f = &h->fov[e & 1u];
    return (XrFovf){-atanf(f->tan_left), atanf(f->tan_right), atanf(f->tan_up), -atanf(f->tan_down)};
}

/* An inset of angular radius r (rad) centred at angles (cx, cy) (rad), kept inside the wide view. */
static XrFovf inset_fov(XrFovf wide, double cx, double cy, double r)
{
    double w = fmin(2.0 * r, (double)(wide.angleRight - wide.angleLeft));
    double hgt = fmin(2.0 * r, (double)(wide.angleUp - wide.angleDown));
    double l = fmin(fmax(cx - 0.5 * w, (double)wide.angleLeft), (double)wide.angleRight - w);
    double d = fmin(fmax(cy - 0.5 * hgt, (double)wide.angleDown), (double)wide.angleUp - hgt);
    return (XrFovf){(float)l, (float)(l + w), (float)(d + hgt), (float)d};
}

void fv_xr_quad_view_size(const struct XrInstance_T *inst, uint32_t view, bool foveated, uint32_t *out_w,
                          uint32_t *out_h)
{
    if (view < 2) {
        double s = foveated ? FV_XR_QUAD_WIDE_DENSITY : 1.0;
        *out_w = (uint32_t)fmax(16.0, round(inst->run.eye_w * s));
        *out_h = (uint32_t)fmax(16.0, round(inst->run.eye_h * s));
        return;
    }
    /* the inset at the display's density: its tangent extent times the recommended pixels per tangent unit */
    XrFovf wide = wide_fov(&inst->hmd, view);
    double r = fv_xr_quad_inset_radius_deg(inst, FV_XR_QUAD_NOMINAL_UNCERTAINTY_DEG) / DEG_PER_RAD;
    XrFovf in = inset_fov(wide, 0.0, 0.0, r);
    double px_per_tan_x = inst->run.eye_w / (tan((double)wide.angleRight) - tan((double)wide.angleLeft));
    double px_per_tan_y = inst->run.eye_h / (tan((double)wide.angleUp) - tan((double)wide.angleDown));
    *out_w = (uint32_t)fmax(16.0, round((tan((double)in.angleRight) - tan((double)in.angleLeft)) * px_per_tan_x));
    *out_h = (uint32_t)fmax(16.0, round((tan((double)in.angleUp) - tan((double)in.angleDown)) * px_per_tan_y));
}

bool fv_xr_quad_locate(struct XrSession_T *s, const XrViewLocateInfo *info, XrView *views)
{
    struct XrInstance_T *inst = s->inst;
    const XrViewLocateFoveatedRenderingVARJO *fr = NULL; /* xrLocateViews checked the chain */
    if (inst->ext.foveated)
        fv_xr_chain_find(info->next, XR_TYPE_VIEW_LOCATE_FOVEATED_RENDERING_VARJO, "xrLocateViews", (const void **)&fr);
    bool foveated = fr && fr->foveatedRenderingActive;
    double cx = 0.0, cy = 0.0, u = FV_XR_QUAD_NOMINAL_UNCERTAINTY_DEG;
    bool tracked = false;
    if (foveated && inst->gaze) {
        float o[3], d[3], unc = 0.0f;
        tracked = fv_xr_gaze_predict_uncertainty(inst->gaze, info->displayTime, o, d, &unc);
        /* the gaze ray in the head frame (-z forward), as the angles of its tangents: the eye views share the head's
         * orientation, so these are the inset's centre in either eye's frustum */
        if (tracked && d[2] < -1e-3f) {
            cx = atan((double)d[0] / -(double)d[2]);
            cy = atan((double)d[1] / -(double)d[2]);
            u = (double)unc;
        } else {
            tracked = false;
        }
    }
    double r = fv_xr_quad_inset_radius_deg(inst, u) / DEG_PER_RAD;
    for (uint32_t e = 0; e < 2; e++) {
        views[2 + e].pose = views[e].pose;
        views[2 + e].fov = inset_fov(wide_fov(&inst->hmd, e), cx, cy, r);
    }
    return tracked;
}

void fv_xr_quad_blend_band(const XrFovf *fov, float *out_band_u, float *out_band_v)
{
    /* the band in the inset's own normalised coordinates: a fraction of its angular radius over its angular width */
    double w = (double)fov->angleRight - (double)fov->angleLeft, h = (double)fov->angleUp - (double)fov->angleDown;
    double band = FV_XR_QUAD_BAND_FRAC * 0.5 * fmin(w, h);
    *out_band_u = w > 1e-6 ? (float)fmin(band / w, 0.5) : 0.5f;
    *out_band_v = h > 1e-6 ? (float)fmin(band / h, 0.5) : 0.5f;
}
