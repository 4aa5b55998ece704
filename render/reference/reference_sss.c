/* @brief The reference's subsurface scattering in `model` mode: the exact dipole sum over every sample of each
 * light-view map (render/sss's model), in double — the oracle of the GPU's `exact` mode and of its hierarchy. The
 * maps are not rasterised but ray cast: one Embree ray from the light through each texel centre of the same fine
 * light view the GPU uses (fv_sss_light_view at fv_sss_sub_levels below sss.map_size), the point the GPU's rasteriser
 * samples; each nominal texel is resolved into one sample where its fine samples allow (fv_sss_texel_resolve), as
 * the GPU's quad-tree build does. Each sample carries what
 * sss_map.frag computes: the surface area the texel covers (fv_sss_texel_area), its footprint on the surface
 * (fv_sss_texel_footprint) and the flux entering the surface E A = Ft(eta, wi) E_light A. A receiver on the same
 * material sums flux x fv_dipole_tile_kernel over all of them, each footprint carried onto the receiver's tangent
 * plane as its near field takes it (fv_sss_near_footprint), a texel left at its fine samples walked on to them only
 * where the receiver's near field reaches it and beyond taken as one disk of its area (fv_sss_cluster_near,
 * fv_sss_near_cluster, fv_dipole_kernel), as the GPU's sums; no visibility inside the object (the model). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_dipole.h"
#include "fv_sss_math.h"
#include "reference_internal.h"

/* One fine sample: a ray through the centre of fine texel (i, j); what sss_map.frag stores there. False: none. */
static bool fine_sample(const ref_sss_map *m, const ref_world *w, const ref_light *L, const fv_sss_view *v,
                        const double inv[16], double eta, uint32_t i, uint32_t j, fv_sss_sample *s)
{
    memset(s, 0, sizeof *s);
    dvec3 p0, d;
    double len;
    if (!ref_ray_from_inverse(inv, v->size, v->size, i + 0.5, j + 0.5, &p0, &d, &len)) return false;
    ref_hit h;
    if (!ref_trace(w, p0, d, len, NULL, &h) || h.material != m->material) return false;
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
    if (!(area > 0.0) || !fv_sss_texel_footprint(v, pf, fv_v3((float)nrm.x, (float)nrm.y, (float)nrm.z), &fa, &fb))
        return false;
    dvec3 flux = dv_scale(e, fv_fresnel_transmittance(eta, cos_i) * area);
    const double pos[3] = {h.pos.x, h.pos.y, h.pos.z}, fl[3] = {flux.x, flux.y, flux.z}, nv[3] = {nrm.x, nrm.y, nrm.z},
                 ea[3] = {fa.x, fa.y, fa.z}, eb[3] = {fb.x, fb.y, fb.z};
    memcpy(s->pos, pos, sizeof s->pos);
    memcpy(s->flux, fl, sizeof s->flux);
    memcpy(s->n, nv, sizeof s->n);
    memcpy(s->a, ea, sizeof s->a);
    memcpy(s->b, eb, sizeof s->b);
    s->area = area;
    s->cos_i = cos_i;
    return true;
}

/* Appends n items of `size` bytes to *arr (count *len, capacity *cap), growing it. */
static bool append(void **arr, uint32_t *len, size_t *cap, const void *items, uint32_t n, size_t size)
{
    if (*len + (size_t)n > *cap) {
        size_t grown = *cap * 2 + n;
        void *more = realloc(*arr, grown * size);
        if (!more) return false;
        *arr = more;
        *cap = grown;
    }
    memcpy((char *)*arr + (size_t)*len * size, items, (size_t)n * size);
    *len += n;
    return true;
}

/* The samples of one map: its fine map `fine` (sub levels below the nominal texels: fv_sss_sub_levels) ray cast,
 * each nominal texel resolved into one sample where its fine samples allow (fv_sss_texel_resolve), else its cluster
 * and its fine samples (fv_sss_texel_cluster). */
static fv_result map_samples(ref_sss_map *m, const ref_world *w, const ref_light *L, const fv_sss_view *fine,
                             uint32_t sub, double eta)
{
    uint32_t k = 1u << sub, size = fine->size >> sub;
    size_t cap = 0, fine_cap = 0, texel_cap = 0;
    fv_sss_sample *part = calloc((size_t)k * k, sizeof *part);
    fv_result res = part ? FV_OK : FV_ERR_NO_MEMORY;
    double vp[16], inv[16];
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) vp[c * 4 + r] = fine->view_proj.m[c][r];
    bool ok = ref_invert4(vp, inv);
    for (uint32_t t = 0; ok && res == FV_OK && t < size * size; t++) {
        uint32_t ti = t % size, tj = t / size;
        for (uint32_t q = 0; q < k * k; q++)
            fine_sample(m, w, L, fine, inv, eta, ti * k + q % k, tj * k + q / k, &part[q]);
        fv_sss_sample one;
        bool grown = true;
        if (sub == 0) { /* no fine map: every texel a leaf, as on the GPU */
            if (part[0].area > 0.0) grown = append((void **)&m->samples, &m->count, &cap, &part[0], 1, sizeof *part);
        } else if (fv_sss_texel_resolve(part, k * k, sub, &one)) {
            grown = append((void **)&m->samples, &m->count, &cap, &one, 1, sizeof one);
        } else {
            ref_sss_texel texel = {.first = m->fine_count};
            if (!fv_sss_texel_cluster(part, k * k, sub, &texel.cluster)) continue; /* no fine sample */
            for (uint32_t q = 0; q < k * k && grown; q++)
                if (part[q].area > 0.0)
                    grown = append((void **)&m->fine, &m->fine_count, &fine_cap, &part[q], 1, sizeof *part);
            texel.count = m->fine_count - texel.first;
            grown = grown && append((void **)&m->texels, &m->texel_count, &texel_cap, &texel, 1, sizeof texel);
        }
        if (!grown) res = FV_ERR_NO_MEMORY;
    }
    free(part);
    return res;
}

/* flux x the footprint kernel of one sample, per channel, its footprint as the receiver's near field takes it. */
static dvec3 sample_term(const ref_sss_map *m, const fv_sss_receiver *rc, const fv_sss_sample *p)
{
    double c[3], a[3], b[3];
    fv_sss_near_footprint(rc, p->pos, p->a, p->b, p->n, c, a, b);
    return dv(p->flux[0] * fv_dipole_tile_kernel(&m->dipole[0], c, a, b, rc->x),
              p->flux[1] * fv_dipole_tile_kernel(&m->dipole[1], c, a, b, rc->x),
              p->flux[2] * fv_dipole_tile_kernel(&m->dipole[2], c, a, b, rc->x));
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
        uint32_t sub = fv_sss_sub_levels(size);
        fv_sss_view v; /* the fine map's, as the GPU draws it */
        if (!fv_sss_light_view(L->type, pos, dir, omin, omax, smin, smax, size << sub, &v)) continue;
        double eta = fv_sss_material_dipoles(&scene->materials[m->material].translucency, m->dipole);
        m->eta = eta;
        FV_TRY(map_samples(m, w, L, &v, sub, eta));
    }
    s->enabled = true;
    return FV_OK;
}

void ref_sss_fini(ref_sss *s)
{
    for (uint32_t i = 0; i < FV_SSS_MAX_LAYERS; i++) {
        free(s->map[i].samples);
        free(s->map[i].fine);
        free(s->map[i].texels);
    }
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
        for (uint32_t k = 0; k < m->count; k++) sum = dv_add(sum, sample_term(m, &rc, &m->samples[k]));
        /* a texel left at its fine samples: they within the receiver's near field, beyond it one disk of its area
         * (the GPU's exact mode and its hierarchy alike) */
        for (uint32_t t = 0; t < m->texel_count; t++) {
            const ref_sss_texel *tx = &m->texels[t];
            if (fv_sss_cluster_near(&rc, &tx->cluster)) {
                for (uint32_t k = 0; k < tx->count; k++)
                    sum = dv_add(sum, sample_term(m, &rc, &m->fine[tx->first + k]));
                continue;
            }
            double c[3];
            fv_sss_near_cluster(&rc, &tx->cluster, c);
            dvec3 off = dv_sub(dv(c[0], c[1], c[2]), x);
            double dist = sqrt(dv_dot(off, off));
            sum = dv_add(sum, dv(tx->cluster.flux[0] * fv_dipole_kernel(&m->dipole[0], dist, tx->cluster.area),
                                 tx->cluster.flux[1] * fv_dipole_kernel(&m->dipole[1], dist, tx->cluster.area),
                                 tx->cluster.flux[2] * fv_dipole_kernel(&m->dipole[2], dist, tx->cluster.area)));
        }
    }
    double len = sqrt(dv_dot(to_eye, to_eye));
    double cos_o = len > 0 ? dv_dot(n, to_eye) / len : 1.0;
    return dv_scale(sum, fv_fresnel_transmittance(eta, cos_o) / FV_PI);
}
