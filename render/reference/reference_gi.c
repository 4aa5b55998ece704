/* @brief The reference's one-bounce GI in `model` mode: the exact sum over every VPL of each light's reflective
 * shadow map (render/gi's model, Ki & Oh 2007), in double — the oracle of the GPU's `exact` gather and of its
 * cluster approximations. The RSM is not rasterised but ray cast: one Embree ray from the light through each texel
 * centre of the same light view the GPU uses (fv_gi_light_view), which is the point the GPU's rasteriser samples.
 * Each VPL carries what gi_rsm.frag computes (reflected flux from the texel's solid angle or beam area, the normal
 * facing the light, the texel's disk radius); the receiver sums fv_gi_cluster_irradiance over all of them, with no
 * visibility between VPL and receiver (the model's own bias, which `path` mode with --bounces 1 shows). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_gi_math.h"
#include "reference_internal.h"

static fv_gpu_light gpu_light(const ref_light *L)
{
    fv_gpu_light g;
    memset(&g, 0, sizeof g);
    g.position_range = (fv_gpu_vec4){(float)L->position.x, (float)L->position.y, (float)L->position.z, (float)L->range};
    g.direction_type = (fv_gpu_vec4){(float)L->direction.x, (float)L->direction.y, (float)L->direction.z, (float)L->type};
    g.cone = (fv_gpu_vec4){(float)L->cos_inner, (float)L->cos_outer, 0, 0};
    return g;
}

/* One light's VPLs: a ray through each texel centre, and what gi_rsm.frag stores there. */
static void light_vpls(ref_gi *g, const ref_world *w, const ref_light *L, uint32_t n, fv_vec3 bmin, fv_vec3 bmax)
{
    uint32_t kind = L->type == FV_LIGHT_SPOT ? FV_GI_KIND_SPOT : FV_GI_KIND_DIRECTIONAL;
    fv_gpu_light gl = gpu_light(L);
    fv_gi_view v;
    fv_gi_light_view(&gl, kind, n, bmin, bmax, &v);
    double vp[16], inv[16];
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) vp[c * 4 + r] = v.view_proj.m[c][r];
    if (!ref_invert4(vp, inv)) return;
    double T = v.params[0], scale = v.params[2];
    (void)scale;
    for (uint32_t j = 0; j < n; j++)
        for (uint32_t i = 0; i < n; i++) {
            double x = ((double)i + 0.5) / n * 2.0 - 1.0, y = ((double)j + 0.5) / n * 2.0 - 1.0;
            dvec3 p0, d;
            double len;
            if (!ref_ray_from_inverse(inv, n, n, i + 0.5, j + 0.5, &p0, &d, &len)) continue; /* the texel's centre */
            ref_hit h;
            if (!ref_trace(w, p0, d, len, NULL, &h)) continue;
            double share, dist2 = 1.0, window = 1.0;
            dvec3 dir;
            if (kind == FV_GI_KIND_SPOT) {
                dvec3 wv = dv_sub(h.pos, L->position);
                dist2 = fmax(dv_dot(wv, wv), 1e-12);
                double dl = sqrt(dist2);
                dir = dv_scale(wv, 1.0 / dl);
                double tx = x * T, ty = y * T, q = 1.0 + tx * tx + ty * ty;
                share = (2.0 * T / n) * (2.0 * T / n) / (q * sqrt(q));
                double cos_axis = dv_dot(dir, L->direction);
                double s = (cos_axis - L->cos_outer) / fmax(L->cos_inner - L->cos_outer, 1e-6);
                s = s < 0 ? 0 : (s > 1 ? 1 : s);
                window = s * s * (3.0 - 2.0 * s);
                if (L->range > 0) {
                    double r4 = pow(dl / L->range, 4.0);
                    double rw = fmin(fmax(1.0 - r4, 0.0), 1.0);
                    window *= rw * rw;
                }
            } else {
                dir = L->direction;
                double texel = 2.0 * T / n;
                share = texel * texel;
            }
            dvec3 nrm = h.n;
            if (dv_dot(nrm, dir) > 0) nrm = dv_scale(nrm, -1.0);
            double cos_i = fmax(-dv_dot(nrm, dir), 0.02);
            dvec3 incident = dv_scale(dv(fmax(L->intensity.x, 0), fmax(L->intensity.y, 0), fmax(L->intensity.z, 0)),
                                      window * share);
            double power = 0.2126 * incident.x + 0.7152 * incident.y + 0.0722 * incident.z;
            if (!(power > 0)) continue;
            ref_vpl *o = &g->vpl[g->count++];
            o->flux = dv_mul(ref_albedo(w, &h), incident);
            o->pos = h.pos;
            o->n = nrm;
            o->r = fmax(sqrt(share * dist2 / cos_i / FV_PI), 1e-5);
        }
}

fv_result ref_gi_init(ref_gi *g, const ref_world *w, const fv_scene *scene, const fv_frame_input *in)
{
    memset(g, 0, sizeof g[0]);
    const fv_quality_gi *q = &in->quality.gi;
    if (!q->enabled || !scene) return FV_OK;
    uint32_t n = q->rsm_size >= 1 && q->rsm_size <= FV_GI_MAX_RSM ? q->rsm_size : 1;
    fv_vec3 bmin, bmax;
    if (!fv_scene_world_bounds(scene, isfinite(in->time_s) ? in->time_s : 0.0, &bmin, &bmax)) return FV_OK;
    uint32_t lights = 0;
    for (uint32_t l = 0; l < w->light_count; l++)
        if (w->lights[l].type == FV_LIGHT_SPOT || w->lights[l].type == FV_LIGHT_DIRECTIONAL) lights++;
    if (lights > FV_GI_MAX_LIGHTS) lights = FV_GI_MAX_LIGHTS;
    if (!lights) return FV_OK;
    g->vpl = calloc((size_t)n * n * lights, sizeof *g->vpl);
    if (!g->vpl) return FV_ERR_NO_MEMORY;
    for (uint32_t l = 0, used = 0; l < w->light_count && used < lights; l++) {
        const ref_light *L = &w->lights[l];
        if (L->type != FV_LIGHT_SPOT && L->type != FV_LIGHT_DIRECTIONAL) continue;
        light_vpls(g, w, L, n, bmin, bmax);
        used++;
    }
    g->enabled = true;
    return FV_OK;
}

void ref_gi_fini(ref_gi *g)
{
    if (!g) return;
    free(g->vpl);
    memset(g, 0, sizeof g[0]);
}

dvec3 ref_gi_irradiance(const ref_gi *g, dvec3 x, dvec3 n)
{
    dvec3 e = dv(0, 0, 0);
    for (uint32_t i = 0; g && i < g->count; i++) {
        const ref_vpl *c = &g->vpl[i];
        dvec3 v = dv_sub(x, c->pos);
        double d2 = dv_dot(v, v);
        if (!(d2 > 1e-20)) continue;
        double inv_d = 1.0 / sqrt(d2);
        double cos_c = fmax(dv_dot(c->n, v) * inv_d, 0.0);
        double cos_r = fmax(-dv_dot(n, v) * inv_d, 0.0);
        e = dv_add(e, dv_scale(c->flux, cos_c * cos_r / (FV_PI * (d2 + c->r * c->r))));
    }
    return dv_finite(e) ? e : dv(0, 0, 0);
}
