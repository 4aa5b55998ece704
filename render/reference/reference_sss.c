/* @brief The reference's subsurface scattering in `model` mode: the exact dipole sum over every sample of each
 * light-view map (render/sss's model), in double — the oracle of the GPU's `exact` mode and of its hierarchy. The
 * maps are not rasterised but ray cast: one Embree ray from the light through each texel centre of the same light
 * view the GPU uses (fv_sss_light_view), the point the GPU's rasteriser samples. Each sample carries what
 * sss_map.frag computes: the surface area the texel covers (fv_sss_texel_area), its footprint on the surface
 * (fv_sss_texel_footprint) and the flux entering the surface E A = Ft(eta, wi) E_light A. A receiver on the same
 * material sums flux x fv_dipole_tile_kernel over all of them, each footprint carried onto the receiver's tangent
 * plane as its near field takes it (fv_sss_near_footprint); no visibility inside the object (the model). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_dipole.h"
#include "fv_sss_math.h"
#include "reference_internal.h"

/* The samples of one map: a ray through each texel centre; what sss_map.frag stores there. */
static fv_result map_samples(ref_sss_map *m, const ref_world *w, const ref_light *L, const fv_sss_view *v, double eta)
{
    uint32_t n = v->size;
    m->samples = calloc((size_t)n * n, sizeof *m->samples);
    if (!m->samples) return FV_ERR_NO_MEMORY;
    double vp[16], inv[16];
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) vp[c * 4 + r] = v->view_proj.m[c][r];
    if (!ref_invert4(vp, inv)) return FV_OK;
    for (uint32_t j = 0; j < n; j++)
        for (uint32_t i = 0; i < n; i++) {
            dvec3 p0, d;
            double len;
            if (!ref_ray_from_inverse(inv, n, n, i + 0.5, j + 0.5, &p0, &d, &len)) continue; /* the texel's centre */
            ref_hit h;
            if (!ref_trace(w, p0, d, len, NULL, &h) || h.material != m->material) continue;
            dvec3 l;
            double dist;
            dvec3 nrm = h.n;
            dvec3 to_light = L->type == FV_LIGHT_DIRECTIONAL ? dv_scale(L->direction, -1.0) : dv_sub(L->position, h.pos);
            if (dv_dot(nrm, to_light) < 0) nrm = dv_scale(nrm, -1.0); /* the side the light sees, as the GPU */
            dvec3 e = ref_light_irradiance(L, h.pos, nrm, &l, &dist);
            double cos_i = dv_dot(nrm, l);
            fv_vec3 pf = fv_v3((float)h.pos.x, (float)h.pos.y, (float)h.pos.z);
            double area = fv_sss_texel_area(v, pf, cos_i);
            fv_vec3 fa, fb;
            if (!(area > 0.0) ||
                !fv_sss_texel_footprint(v, pf, fv_v3((float)nrm.x, (float)nrm.y, (float)nrm.z), &fa, &fb))
                continue;
            double ft = fv_fresnel_transmittance(eta, cos_i);
            ref_sss_sample *s = &m->samples[m->count++];
            s->pos = h.pos;
            s->flux = dv_scale(e, ft * area);
            s->area = area;
            const double ea[3] = {fa.x, fa.y, fa.z}, eb[3] = {fb.x, fb.y, fb.z};
            memcpy(s->a, ea, sizeof s->a);
            memcpy(s->b, eb, sizeof s->b);
            const double nv[3] = {nrm.x, nrm.y, nrm.z};
            memcpy(s->n, nv, sizeof s->n);
        }
    return FV_OK;
}

fv_result ref_sss_init(ref_sss *s, const ref_world *w, const fv_scene *scene, const fv_frame_input *in)
{
    memset(s, 0, sizeof *s);
    const fv_quality_sss *q = &in->quality.sss;
    if (!q->enabled) return FV_OK;
    fv_sss_pair pairs[FV_SSS_MAX_LAYERS];
    uint32_t n = fv_sss_pairs(scene, pairs, NULL);
    fv_vec3 smin, smax;
    if (!n || !fv_scene_world_bounds(scene, in->time_s, &smin, &smax)) return FV_OK;
    uint32_t size = q->map_size_px >= 16 && q->map_size_px <= 512 ? q->map_size_px : 128;
    for (uint32_t p = 0; p < n; p++) {
        ref_sss_map *m = &s->map[s->count++];
        m->material = pairs[p].material;
        fv_vec3 omin, omax;
        if (pairs[p].light >= w->light_count || !fv_sss_material_bounds(scene, m->material, in->time_s, &omin, &omax))
            continue;
        const ref_light *L = &w->lights[pairs[p].light];
        m->light = *L;
        m->flat_m = fv_sss_flat_radius_m(&scene->materials[m->material].translucency);
        fv_vec3 pos = fv_v3((float)L->position.x, (float)L->position.y, (float)L->position.z);
        fv_vec3 dir = fv_v3((float)L->direction.x, (float)L->direction.y, (float)L->direction.z);
        fv_sss_view v;
        if (!fv_sss_light_view(L->type, pos, dir, omin, omax, smin, smax, size, &v)) continue;
        double eta = fv_sss_material_dipoles(&scene->materials[m->material].translucency, m->dipole);
        m->eta = eta;
        FV_TRY(map_samples(m, w, L, &v, eta));
    }
    s->enabled = true;
    return FV_OK;
}

void ref_sss_fini(ref_sss *s)
{
    for (uint32_t i = 0; i < FV_SSS_MAX_LAYERS; i++) free(s->map[i].samples);
    memset(s, 0, sizeof *s);
}

bool ref_sss_active(const ref_sss *s, uint32_t material)
{
    for (uint32_t i = 0; s && s->enabled && i < s->count; i++)
        if (s->map[i].material == material) return true;
    return false;
}

dvec3 ref_sss_radiance(const ref_sss *s, dvec3 x, dvec3 n, dvec3 to_eye, uint32_t material)
{
    dvec3 sum = dv(0, 0, 0);
    double eta = 1.0;
    for (uint32_t i = 0; s && s->enabled && i < s->count; i++) {
        const ref_sss_map *m = &s->map[i];
        if (m->material != material) continue;
        eta = m->eta;
        const double xr[3] = {x.x, x.y, x.z}, nr[3] = {n.x, n.y, n.z};
        dvec3 wl = m->light.type == FV_LIGHT_DIRECTIONAL ? m->light.direction : dv_sub(x, m->light.position);
        const double wr[3] = {wl.x, wl.y, wl.z};
        fv_sss_receiver rc;
        fv_sss_receiver_make(xr, nr, wr, m->flat_m, &rc);
        for (uint32_t k = 0; k < m->count; k++) {
            const ref_sss_sample *p = &m->samples[k];
            const double c0[3] = {p->pos.x, p->pos.y, p->pos.z};
            double c[3], a[3], b[3];
            fv_sss_near_footprint(&rc, c0, p->a, p->b, p->n, c, a, b);
            sum.x += p->flux.x * fv_dipole_tile_kernel(&m->dipole[0], c, a, b, xr);
            sum.y += p->flux.y * fv_dipole_tile_kernel(&m->dipole[1], c, a, b, xr);
            sum.z += p->flux.z * fv_dipole_tile_kernel(&m->dipole[2], c, a, b, xr);
        }
    }
    double len = sqrt(dv_dot(to_eye, to_eye));
    double cos_o = len > 0 ? dv_dot(n, to_eye) / len : 1.0;
    return dv_scale(sum, fv_fresnel_transmittance(eta, cos_o) / FV_PI);
}
