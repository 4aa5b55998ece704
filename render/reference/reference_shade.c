/* @brief Shading of the reference renderer, in double. Model mode: render/include/fv_shade_common.glsl term by term
 * (fv_light_irradiance, fv_brdf_lambert, fv_shade_combine, fv_shade_surface's NaN guard and clamp) with exact
 * visibility from shadow rays where the GPU's fv_hook_visibility reads shadow maps. Path mode: the same punctual
 * lights by next-event estimation, emissive triangles as area lights with multiple importance sampling (power
 * heuristic, Veach 1997, eq. 9.13), cosine-weighted Lambert bounces, Russian roulette. */
#include <math.h>

#include "reference_internal.h"

/* fv_light_irradiance in double: the irradiance (per channel, W/m^2) light L delivers at pos with unit normal n;
 * also the unit direction toward the light and its distance (INFINITY for a directional light). */
static dvec3 light_irradiance(const ref_light *L, dvec3 pos, dvec3 n, dvec3 *out_l, double *out_dist)
{
    if (L->type == FV_LIGHT_DIRECTIONAL) {
        *out_l = dv_scale(L->direction, -1.0);
        *out_dist = INFINITY;
        return dv_scale(L->intensity, fmax(dv_dot(n, *out_l), 0.0));
    }
    dvec3 to = dv_sub(L->position, pos);
    double len2 = dv_dot(to, to);
    double d2 = fmax(len2, 1e-8);
    double d = sqrt(d2);
    dvec3 l = dv_scale(to, 1.0 / d);
    *out_l = l;
    *out_dist = sqrt(len2);
    double cos_surface = fmax(dv_dot(n, l), 0.0);
    double falloff = 1.0;
    if (L->type == FV_LIGHT_SPOT) {
        double cos_axis = -dv_dot(l, L->direction);
        double t = (cos_axis - L->cos_outer) / fmax(L->cos_inner - L->cos_outer, 1e-6);
        t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
        falloff = t * t * (3.0 - 2.0 * t);
    }
    if (L->range > 0.0) {
        double q = d / L->range;
        double w = 1.0 - q * q * q * q;
        w = w < 0.0 ? 0.0 : (w > 1.0 ? 1.0 : w);
        falloff *= w * w;
    }
    return dv_scale(L->intensity, falloff * cos_surface / d2);
}

dvec3 ref_light_irradiance(const ref_light *L, dvec3 pos, dvec3 n, dvec3 *out_l, double *out_dist)
{
    return light_irradiance(L, pos, n, out_l, out_dist);
}

/* Exact visibility of a point at distance dist along unit l from the hit (a shadow ray, counted). */
static bool visible_toward(const ref_world *w, const ref_hit *h, dvec3 l, double dist, double dist_eps,
                           ref_counts *counts)
{
    dvec3 o = ref_offset(h->pos, h->ng, l);
    double t_max = isinf(dist) ? INFINITY : dist - 2.0 * ref_offset_eps(h->pos) - dist_eps;
    if (!(t_max > 0)) return true; /* the light is within the offset of the surface: nothing can be between */
    counts->shadow++;
    return ref_visible(w, o, l, t_max);
}

/* Sum over the lights of visibility x irradiance at the hit (the loop of fv_shade_surface). When vis_light is a
 * light index, its visibility is traced even where it delivers nothing and returned in *out_vis. */
static dvec3 punctual_irradiance(const ref_world *w, const ref_hit *h, uint32_t vis_light, double *out_vis,
                                 ref_counts *counts)
{
    dvec3 sum = dv(0, 0, 0);
    if (out_vis) *out_vis = 0.0;
    for (uint32_t i = 0; i < w->light_count; i++) {
        dvec3 l;
        double dist;
        dvec3 e = light_irradiance(&w->lights[i], h->pos, h->n, &l, &dist);
        bool want = out_vis && i == vis_light;
        if (!(dv_maxc(e) > 0) && !want) continue;
        bool v = visible_toward(w, h, l, dist, 0.0, counts);
        if (want) *out_vis = v ? 1.0 : 0.0;
        if (v) sum = dv_add(sum, e);
    }
    return sum;
}

/* fv_shade_surface's guard: NaN -> 0, clamped to [0, 1e30]. */
static dvec3 finite_color(dvec3 c)
{
    if (isnan(c.x) || isnan(c.y) || isnan(c.z)) return dv(0, 0, 0);
    c.x = fmin(fmax(c.x, 0.0), 1e30);
    c.y = fmin(fmax(c.y, 0.0), 1e30);
    c.z = fmin(fmax(c.z, 0.0), 1e30);
    return c;
}

static double vulkan_depth(const double vp[16], dvec3 p)
{
    double z = vp[2] * p.x + vp[6] * p.y + vp[10] * p.z + vp[14];
    double wc = vp[3] * p.x + vp[7] * p.y + vp[11] * p.z + vp[15];
    double d = fabs(wc) > 1e-300 ? z / wc : 1.0;
    return isfinite(d) ? d : 1.0;
}

dvec3 ref_shade_model(const ref_pixel_ctx *c, dvec3 o, dvec3 d, double t_max, ref_counts *counts)
{
    const ref_world *w = c->w;
    fv_reference_view view = c->desc->view;
    counts->primary++;
    ref_hit h;
    if (!ref_trace(w, o, d, t_max, &c->eye_pos, &h)) return view == FV_REFERENCE_VIEW_DEPTH ? dv(1, 1, 1) : dv(0, 0, 0);
    switch (view) {
    case FV_REFERENCE_VIEW_ALBEDO: return ref_albedo(w, &h);
    case FV_REFERENCE_VIEW_NORMAL: return dv_add(dv_scale(h.n, 0.5), dv(0.5, 0.5, 0.5));
    case FV_REFERENCE_VIEW_DEPTH: {
        double z = vulkan_depth(c->vp, h.pos);
        return dv(z, z, z);
    }
    case FV_REFERENCE_VIEW_SHADOW: {
        double v = 0.0;
        (void)punctual_irradiance(w, &h, c->desc->shadow_light, &v, counts);
        return dv(v, v, v);
    }
    case FV_REFERENCE_VIEW_DIRECT:
    case FV_REFERENCE_VIEW_COLOR:
    default: break;
    }
    dvec3 albedo = ref_albedo(w, &h);
    if (view == FV_REFERENCE_VIEW_GI) /* the GPU's gi view: Lambert albedo / pi times the indirect irradiance */
        return finite_color(c->gi ? dv_mul(dv_scale(albedo, 1.0 / FV_PI), ref_gi_irradiance(c->gi, h.pos, h.n))
                                  : dv(0, 0, 0));
    if (view == FV_REFERENCE_VIEW_SSS) /* the GPU's sss view: the subsurface term alone */
        return finite_color(ref_sss_active(c->sss, h.material)
                                ? ref_sss_radiance(c->sss, h.pos, h.n, dv_sub(c->eye_pos, h.pos), h.material)
                                : dv(0, 0, 0));
    if (view == FV_REFERENCE_VIEW_COLOR && ref_sss_active(c->sss, h.material)) {
        /* Translucent with SSS on: the dipole carries the direct light (fv_shade_surface); indirect light, emission
         * and ambient as on any surface. */
        dvec3 sss = ref_sss_radiance(c->sss, h.pos, h.n, dv_sub(c->eye_pos, h.pos), h.material);
        if (c->gi) sss = dv_add(sss, dv_mul(dv_scale(albedo, 1.0 / FV_PI), ref_gi_irradiance(c->gi, h.pos, h.n)));
        return finite_color(dv_add(sss, dv_add(w->materials[h.material].emissive, dv_mul(albedo, w->ambient))));
    }
    dvec3 irradiance = punctual_irradiance(w, &h, UINT32_MAX, NULL, counts);
    if (view == FV_REFERENCE_VIEW_COLOR && c->gi) irradiance = dv_add(irradiance, ref_gi_irradiance(c->gi, h.pos, h.n));
    /* fv_shade_combine: Lambert albedo / pi times irradiance, plus emission and albedo x ambient */
    dvec3 color = dv_mul(dv_scale(albedo, 1.0 / FV_PI), irradiance);
    if (view == FV_REFERENCE_VIEW_COLOR)
        color = dv_add(dv_add(color, w->materials[h.material].emissive), dv_mul(albedo, w->ambient));
    return finite_color(color);
}

/* ---- path mode ----------------------------------------------------------------------------------------------- */

static double power_heuristic(double a, double b)
{
    if (!isfinite(a)) return 1.0;
    if (!isfinite(b)) return 0.0;
    double a2 = a * a, b2 = b * b;
    return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0;
}

/* An orthonormal basis around unit n (Duff et al. 2017, listing 3). */
static void basis(dvec3 n, dvec3 *t, dvec3 *b)
{
    double s = n.z >= 0 ? 1.0 : -1.0;
    double a = -1.0 / (s + n.z);
    double bb = n.x * n.y * a;
    *t = dv(1.0 + s * n.x * n.x * a, s * bb, -s * n.x);
    *b = dv(bb, s + n.y * n.y * a, -n.y);
}

/* Next-event estimation of one point on the emissive triangles (uniform by area) at hit h with albedo/pi f.
 * continues: the path also samples the BSDF here, so the two strategies share the estimate by MIS. */
static dvec3 area_light_sample(const ref_world *w, const ref_hit *h, dvec3 f, bool continues, ref_rng *rng,
                               ref_counts *counts)
{
    double u0 = ref_rng_next(rng), u1 = ref_rng_next(rng), u2 = ref_rng_next(rng);
    dvec3 y, ny;
    uint32_t e;
    if (!ref_sample_emitter(w, u0, u1, u2, &y, &ny, &e)) return dv(0, 0, 0);
    dvec3 to = dv_sub(y, h->pos);
    double dist2 = dv_dot(to, to);
    if (!(dist2 > 0) || !isfinite(dist2)) return dv(0, 0, 0);
    double dist = sqrt(dist2);
    dvec3 wi = dv_scale(to, 1.0 / dist);
    double cos_x = dv_dot(h->n, wi), cos_y = fabs(dv_dot(ny, wi));
    if (!(cos_x > 0) || !(cos_y > 0)) return dv(0, 0, 0);
    if (!visible_toward(w, h, wi, dist, ref_offset_eps(y), counts)) return dv(0, 0, 0);
    double pdf_light = dist2 / (cos_y * w->emissive_area_m2); /* solid angle */
    double weight = continues ? power_heuristic(pdf_light, cos_x / FV_PI) : 1.0;
    dvec3 le = w->materials[w->geoms[w->emitters[e].geom].material].emissive;
    return dv_scale(dv_mul(f, le), cos_x / pdf_light * weight);
}

dvec3 ref_shade_path(const ref_pixel_ctx *c, dvec3 o, dvec3 d, double t_max, ref_rng *rng, ref_counts *counts)
{
    fv_reference_view view = c->desc->view;
    if (view != FV_REFERENCE_VIEW_COLOR && view != FV_REFERENCE_VIEW_DIRECT) return ref_shade_model(c, o, d, t_max, counts);
    const ref_world *w = c->w;
    bool direct_only = view == FV_REFERENCE_VIEW_DIRECT;
    uint32_t max_bounces = direct_only ? 0 : c->desc->bounces;
    dvec3 radiance = dv(0, 0, 0), beta = dv(1, 1, 1);
    double pdf_bsdf = 0.0; /* solid-angle pdf of the bounce that led here */
    for (uint32_t depth = 0;; depth++) {
        ref_hit h;
        if (depth == 0) counts->primary++;
        else counts->bounce++;
        /* The first hit faces its normal to the eye, exactly as model mode (and the G-buffer) does. */
        if (!ref_trace(w, o, d, t_max, depth == 0 ? &c->eye_pos : NULL, &h)) {
            if (depth > 0) radiance = dv_add(radiance, dv_mul(beta, w->ambient));
            break;
        }
        dvec3 le = w->materials[h.material].emissive;
        if (!direct_only && dv_maxc(le) > 0) {
            double weight = 1.0;
            if (depth > 0) {
                double cos_y = fabs(dv_dot(h.ng, d));
                double pdf_light = cos_y > 0 && w->emissive_area_m2 > 0
                                       ? h.t * h.t / (cos_y * w->emissive_area_m2)
                                       : INFINITY;
                weight = power_heuristic(pdf_bsdf, pdf_light);
            }
            radiance = dv_add(radiance, dv_scale(dv_mul(beta, le), weight));
        }
        dvec3 albedo = ref_albedo(w, &h);
        dvec3 f = dv_scale(albedo, 1.0 / FV_PI);
        bool continues = depth < max_bounces;
        radiance = dv_add(radiance, dv_mul(beta, dv_mul(f, punctual_irradiance(w, &h, UINT32_MAX, NULL, counts))));
        if (w->emitter_count)
            radiance = dv_add(radiance, dv_mul(beta, area_light_sample(w, &h, f, continues, rng, counts)));
        if (!continues) break;
        /* Cosine-weighted bounce around the shading normal: f cos / pdf = albedo. */
        double u1 = ref_rng_next(rng), u2 = ref_rng_next(rng);
        double r = sqrt(u1), phi = 2.0 * FV_PI * u2;
        double lz = sqrt(fmax(0.0, 1.0 - u1));
        dvec3 t, b;
        basis(h.n, &t, &b);
        dvec3 wi = dv_add(dv_add(dv_scale(t, r * cos(phi)), dv_scale(b, r * sin(phi))), dv_scale(h.n, lz));
        if (!(dv_dot(wi, h.ng) > 0) || !(lz > 0)) break; /* below the geometric surface: absorbed */
        beta = dv_mul(beta, albedo);
        pdf_bsdf = lz / FV_PI;
        if (depth + 1 >= FV_REFERENCE_RR_BOUNCES) {
            double p = fmin(dv_maxc(beta), 0.95);
            if (!(p > 0) || ref_rng_next(rng) >= p) break;
            beta = dv_scale(beta, 1.0 / p);
        }
        o = ref_offset(h.pos, h.ng, wi);
        d = wi;
        t_max = INFINITY;
    }
    if (!dv_finite(radiance) || isnan(radiance.x) || isnan(radiance.y) || isnan(radiance.z)) {
        counts->nonfinite++;
        return dv(0, 0, 0);
    }
    return finite_color(radiance);
}
