/* @brief The light quad-tree's pure parts (see fv_gi_math.h). */
#include "fv_gi_math.h"

#include <math.h>
#include <string.h>

uint32_t fv_gi_log2(uint32_t v)
{
    uint32_t k = 0;
    while (k < 31 && (1u << (k + 1)) <= v) k++;
    return k;
}

uint32_t fv_gi_nodes_for(uint32_t n)
{
    uint32_t total = 0;
    for (uint32_t s = n; s; s >>= 1) total += s * s;
    return total;
}

uint32_t fv_gi_level_offset(uint32_t n, uint32_t k)
{
    uint32_t off = 0;
    for (uint32_t j = 0; j < k && (n >> j); j++) off += (n >> j) * (n >> j);
    return off;
}

static uint32_t limit_side(fv_gi_limit l)
{
    return l == FV_GI_LIMIT_16 ? 16u : l == FV_GI_LIMIT_32 ? 32u : l == FV_GI_LIMIT_64 ? 64u : 0u;
}

void fv_gi_tree_levels(uint32_t n, const fv_quality_gi *q, uint32_t *out_start, uint32_t *out_limit)
{
    uint32_t ln = fv_gi_log2(n);
    uint32_t ss = q->start_level ? fv_gi_log2(q->start_level) : 0;
    uint32_t start = ss >= ln ? 0u : ln - ss;
    uint32_t side = limit_side(q->limit_level);
    uint32_t limit = side == 0 ? 0u : (fv_gi_log2(side) >= ln ? 0u : ln - fv_gi_log2(side));
    if (limit > start) start = limit;
    *out_start = start;
    *out_limit = limit;
}

void fv_gi_light_view(const fv_gpu_light *L, uint32_t kind, uint32_t n, fv_vec3 bmin, fv_vec3 bmax, fv_gi_view *out)
{
    memset(out, 0, sizeof *out);
    fv_vec3 c = fv_v3_scale(fv_v3_add(bmin, bmax), 0.5f);
    float r = 0.5f * fv_v3_len(fv_v3_sub(bmax, bmin));
    r = isfinite(r) && r > 1e-6f ? r * 1.01f : 1.0f;
    if (!fv_v3_isfinite(c)) c = fv_v3(0, 0, 0);
    fv_vec3 dir = fv_v3_normalize_or(fv_v3(L->direction_type.x, L->direction_type.y, L->direction_type.z),
                                     fv_v3(0, -1, 0));
    fv_vec3 up = fabsf(dir.y) < 0.99f ? fv_v3(0, 1, 0) : fv_v3(1, 0, 0);
    if (kind == FV_GI_KIND_SPOT) {
        fv_vec3 pos = fv_v3(L->position_range.x, L->position_range.y, L->position_range.z);
        if (!fv_v3_isfinite(pos)) pos = fv_v3(0, 0, 0);
        float outer = acosf(fv_clampf(isfinite(L->cone.y) ? L->cone.y : 0.0f, -1.0f, 1.0f));
        float half = fminf(outer * 1.02f, (float)fv_deg_to_rad(80.0));
        if (!(half > 1e-4f)) half = 1e-4f;
        float t = tanf(half);
        float far_m = fv_v3_len(fv_v3_sub(pos, c)) + r;
        if (!(far_m > 1e-3f) || !isfinite(far_m)) far_m = 1e-3f;
        float near_m = fmaxf(far_m * 1e-4f, 1e-5f);
        fv_mat4 view = fv_mat4_look_at(pos, fv_v3_add(pos, dir), up);
        fv_mat4 proj = fv_mat4_perspective_tan(-t, t, t, -t, near_m, far_m);
        out->view_proj = fv_mat4_mul(&proj, &view);
        out->params[0] = t;
    } else {
        /* x, y in [-r, r] of the sphere; depth 0 at distance r before its centre, 1 at r behind it */
        fv_vec3 eye = fv_v3_sub(c, fv_v3_scale(dir, 2.0f * r));
        fv_mat4 view = fv_mat4_look_at(eye, c, up);
        fv_mat4 proj;
        memset(&proj, 0, sizeof proj);
        proj.m[0][0] = 1.0f / r;
        proj.m[1][1] = -1.0f / r;
        proj.m[2][2] = -1.0f / (2.0f * r);
        proj.m[3][2] = -0.5f;
        proj.m[3][3] = 1.0f;
        out->view_proj = fv_mat4_mul(&proj, &view);
        fv_vec3 o = fv_v3_sub(c, fv_v3_scale(dir, r));
        out->params[0] = r;
        out->origin[0] = o.x;
        out->origin[1] = o.y;
        out->origin[2] = o.z;
    }
    out->params[1] = (float)n;
    out->params[2] = 2.0f * r;
}

static float v3len(const float *v) { return sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/* gi_build.comp's REDUCE for one node, in float as on the GPU. */
static fv_gi_node reduce(const fv_gi_node ch[4], float depth_threshold, float normal_threshold, bool plain)
{
    fv_gi_node o;
    memset(&o, 0, sizeof o);
    o.info.x = 1.0f;
    float wsum = 0.0f, geo = 0.0f;
    for (int j = 0; j < 4; j++) {
        wsum += ch[j].flux.w;
        geo += ch[j].info.z;
    }
    if (!(geo > 0.0f)) return o;
    float nsum[3] = {0, 0, 0};
    for (int j = 0; j < 4; j++) {
        float w = wsum > 0.0f && !plain ? ch[j].flux.w / wsum : ch[j].info.z / geo;
        o.flux.x += ch[j].flux.x;
        o.flux.y += ch[j].flux.y;
        o.flux.z += ch[j].flux.z;
        o.flux.w += ch[j].flux.w;
        o.pos.x += w * ch[j].pos.x;
        o.pos.y += w * ch[j].pos.y;
        o.pos.z += w * ch[j].pos.z;
        o.pos.w += w * ch[j].pos.w;
        nsum[0] += w * ch[j].normal.x;
        nsum[1] += w * ch[j].normal.y;
        nsum[2] += w * ch[j].normal.z;
    }
    float extent = 0.0f, rmin = 3.0e38f, slab = 0.0f;
    bool valid = true;
    float nlen = v3len(nsum);
    float nmean[3] = {0, 0, 0};
    if (nlen > 1e-6f)
        for (int k = 0; k < 3; k++) nmean[k] = nsum[k] / nlen;
    for (int j = 0; j < 4; j++) {
        if (ch[j].info.z < 0.5f) continue;
        float d[3] = {ch[j].pos.x - o.pos.x, ch[j].pos.y - o.pos.y, ch[j].pos.z - o.pos.z};
        extent = fmaxf(extent, v3len(d) + ch[j].normal.w);
        rmin = fminf(rmin, ch[j].info.y);
        float cn[3] = {ch[j].normal.x, ch[j].normal.y, ch[j].normal.z};
        float cl = v3len(cn);
        float dot = 0.0f;
        if (cl > 1e-6f) dot = (cn[0] * nmean[0] + cn[1] * nmean[1] + cn[2] * nmean[2]) / cl;
        valid = valid && ch[j].info.x > 0.5f && fabsf(ch[j].pos.w - o.pos.w) < depth_threshold && nlen > 1e-6f &&
                dot > normal_threshold;
        float sn = sqrtf(fmaxf(1.0f - dot * dot, 0.0f));
        float across = cl > 1e-6f && nlen > 1e-6f ? fminf(ch[j].normal.w * sn + ch[j].info.w * fabsf(dot), ch[j].normal.w)
                                                  : ch[j].normal.w;
        slab = fmaxf(slab, fabsf(nmean[0] * d[0] + nmean[1] * d[1] + nmean[2] * d[2]) + across);
    }
    o.normal = (fv_gpu_vec4){nsum[0], nsum[1], nsum[2], extent};
    o.info = (fv_gpu_vec4){valid ? 1.0f : 0.0f, rmin, 1.0f, nlen > 1e-6f ? fminf(slab, extent) : extent};
    return o;
}

void fv_gi_build_cpu(fv_gi_node *tree, uint32_t n, float depth_threshold, float normal_threshold, bool plain)
{
    uint32_t levels = fv_gi_log2(n) + 1;
    for (uint32_t k = 0; k + 1 < levels; k++) {
        uint32_t sc = n >> k, s = n >> (k + 1);
        const fv_gi_node *child = tree + fv_gi_level_offset(n, k);
        fv_gi_node *parent = tree + fv_gi_level_offset(n, k + 1);
        for (uint32_t y = 0; y < s; y++)
            for (uint32_t x = 0; x < s; x++) {
                fv_gi_node ch[4] = {child[(2 * y) * sc + 2 * x], child[(2 * y) * sc + 2 * x + 1],
                                    child[(2 * y + 1) * sc + 2 * x], child[(2 * y + 1) * sc + 2 * x + 1]};
                parent[y * s + x] = reduce(ch, depth_threshold, normal_threshold, plain);
            }
    }
}

uint32_t fv_gi_cut_cpu(const fv_gi_node *tree, uint32_t n, uint32_t start, uint32_t limit, uint32_t *out, uint32_t cap)
{
    uint32_t count = 0;
    for (uint32_t k = start + 1; k-- > limit;) {
        uint32_t s = n >> k, off = fv_gi_level_offset(n, k);
        for (uint32_t i = 0; i < s * s; i++) {
            const fv_gi_node *c = &tree[off + i];
            if (!(c->flux.w > 0.0f)) continue;
            if (k != limit && c->info.x < 0.5f) continue;
            if (k != start) {
                uint32_t ps = s >> 1;
                const fv_gi_node *p = &tree[fv_gi_level_offset(n, k + 1) + ((i / s) >> 1) * ps + ((i % s) >> 1)];
                if (p->info.x > 0.5f) continue;
            }
            if (count < cap) out[count] = off + i;
            count++;
        }
    }
    return count;
}

void fv_gi_cluster_irradiance(const fv_gi_node *c, const double x[3], const double nrm[3], double out[3])
{
    out[0] = out[1] = out[2] = 0.0;
    double v[3] = {x[0] - c->pos.x, x[1] - c->pos.y, x[2] - c->pos.z};
    double d2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    if (!(d2 > 1e-20) || !(c->flux.w > 0.0f) || !isfinite(d2)) return;
    double inv_d = 1.0 / sqrt(d2);
    double cos_c = fmax((c->normal.x * v[0] + c->normal.y * v[1] + c->normal.z * v[2]) * inv_d, 0.0);
    double cos_r = fmax(-(nrm[0] * v[0] + nrm[1] * v[1] + nrm[2] * v[2]) * inv_d, 0.0);
    double r = c->normal.w;
    double k = cos_c * cos_r / (FV_PI * (d2 + r * r));
    out[0] = fmax(c->flux.x, 0.0) * k;
    out[1] = fmax(c->flux.y, 0.0) * k;
    out[2] = fmax(c->flux.z, 0.0) * k;
}

uint32_t fv_gi_subtree(uint32_t k)
{
    return k >= 15 ? 0xffffffffu : ((1u << (2 * k + 2)) - 1u) / 3u;
}

uint32_t fv_gi_walk_pos(uint32_t n, uint32_t k, uint32_t x, uint32_t y)
{
    uint32_t top = fv_gi_log2(n), pos = 0;
    for (uint32_t j = top; j > k; j--) {
        uint32_t sh = j - 1 - k;
        uint32_t digit = ((x >> sh) & 1u) + 2u * ((y >> sh) & 1u);
        pos += 1u + digit * fv_gi_subtree(j - 1);
    }
    return pos;
}

uint32_t fv_gi_walk_node(uint32_t n, uint32_t pos)
{
    uint32_t k = fv_gi_log2(n), x = 0, y = 0;
    if (pos >= fv_gi_subtree(k)) return fv_gi_nodes_for(n);
    while (pos > 0) { /* pos is inside the subtree of the level-k node (x, y), past the node itself */
        pos--;
        uint32_t s = fv_gi_subtree(k - 1), digit = pos / s;
        pos -= digit * s;
        k--;
        x = 2 * x + (digit & 1u);
        y = 2 * y + (digit >> 1);
    }
    return fv_gi_level_offset(n, k) + y * (n >> k) + x;
}

fv_gi_cluster fv_gi_walk_record(const fv_gi_node *tree, uint32_t n, uint32_t node)
{
    uint32_t k = 0;
    while ((n >> (k + 1)) && node >= fv_gi_level_offset(n, k + 1)) k++;
    const fv_gi_node *c = &tree[node];
    bool lit = c->flux.w > 0.0f;
    fv_gi_cluster o;
    o.flux = lit ? (fv_gpu_vec4){fmaxf(c->flux.x, 0.0f), fmaxf(c->flux.y, 0.0f), fmaxf(c->flux.z, 0.0f), c->normal.w}
                 : (fv_gpu_vec4){0, 0, 0, 0};
    o.pos = (fv_gpu_vec4){c->pos.x, c->pos.y, c->pos.z, c->info.w};
    o.normal = (fv_gpu_vec4){c->normal.x, c->normal.y, c->normal.z, (float)fv_gi_subtree(k)};
    return o;
}
