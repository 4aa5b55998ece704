/* @brief The light quad-tree's pure parts (fv_gi_math): a cluster's irradiance at its extremes (zero flux, a
 * receiver at the VPL, normals facing away, a zero extent, huge and tiny distances) finite and bounded by the disk's
 * own exitance; the bottom-up build on fabricated leaves (sums, weighted means, extent, validity) including normals
 * that cancel and unlit children; the slab holding every VPL below; the cut's coverage; levels of every RSM size;
 * light views finite for any light; the walk records' pre-order. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "fv_gi_math.h"
#include "fv_test.h"

static fv_gi_node leaf(float x, float y, float z, float nx, float ny, float nz, float power, float depth)
{
    fv_gi_node n;
    memset(&n, 0, sizeof n);
    n.flux = (fv_gpu_vec4){power, power, power, power};
    n.pos = (fv_gpu_vec4){x, y, z, depth};
    n.normal = (fv_gpu_vec4){nx, ny, nz, 0.01f};
    n.info = (fv_gpu_vec4){1, 0.01f, 1, 0};
    return n;
}

static void irradiance_is_finite_and_bounded_at_the_extremes(void **state)
{
    (void)state;
    fv_gi_node c = leaf(0, 0, 0, 0, 1, 0, 1.0f, 0);
    double e[3], down[3] = {0, -1, 0};
    /* a receiver exactly at the VPL: 0, not NaN */
    double at[3] = {0, 0, 0};
    fv_gi_cluster_irradiance(&c, at, down, e);
    assert_true(e[0] == 0.0 && e[1] == 0.0 && e[2] == 0.0);
    /* approaching it on the axis: bounded by the disk's exitance Phi / (pi r^2), reached in the limit */
    double r = 0.01f, bound = 1.0 / (FV_PI * r * r), prev = 0;
    for (double d = 1.0; d > 1e-9; d *= 0.1) { /* below 1e-10 m the receiver is at the VPL: 0 */
        double x[3] = {0, d, 0};
        fv_gi_cluster_irradiance(&c, x, down, e);
        assert_true(isfinite(e[0]) && e[0] <= bound * (1 + 1e-12) && e[0] >= prev);
        prev = e[0];
    }
    assert_true(prev > 0.999 * bound);
    /* the far field falls as Phi / (pi d^2) */
    double far[3] = {0, 1e3, 0};
    fv_gi_cluster_irradiance(&c, far, down, e);
    assert_true(fabs(e[0] * FV_PI * 1e6 - 1.0) < 1e-6);
    /* facing away (either normal), zero flux, zero extent, a cluster whose normals cancelled (n = 0) */
    double up[3] = {0, 1, 0}, x1[3] = {0, 1, 0}, below[3] = {0, -1, 0};
    fv_gi_cluster_irradiance(&c, x1, up, e);
    assert_true(e[0] == 0.0);
    fv_gi_cluster_irradiance(&c, below, up, e);
    assert_true(e[0] == 0.0);
    fv_gi_node z = c;
    z.flux = (fv_gpu_vec4){0, 0, 0, 0};
    fv_gi_cluster_irradiance(&z, x1, down, e);
    assert_true(e[0] == 0.0);
    z = c;
    z.normal.w = 0.0f;
    double tiny[3] = {0, 1e-9, 0};
    fv_gi_cluster_irradiance(&z, tiny, down, e);
    assert_true(isfinite(e[0]));
    z = c;
    z.normal = (fv_gpu_vec4){0, 0, 0, 0.01f};
    fv_gi_cluster_irradiance(&z, x1, down, e);
    assert_true(e[0] == 0.0);
    /* huge flux and distance: still finite */
    z = c;
    z.flux = (fv_gpu_vec4){FLT_MAX, FLT_MAX, FLT_MAX, FLT_MAX};
    double huge[3] = {0, 1e30, 0};
    fv_gi_cluster_irradiance(&z, huge, down, e);
    assert_true(isfinite(e[0]));
}

static void build_sums_weights_and_validates(void **state)
{
    (void)state;
    /* 2x2 leaves: a flat lit patch -> one valid parent */
    fv_gi_node t[5];
    memset(t, 0, sizeof t);
    t[0] = leaf(0, 0, 0, 0, 1, 0, 1, 0.5f);
    t[1] = leaf(1, 0, 0, 0, 1, 0, 3, 0.5f);
    t[2] = leaf(0, 0, 1, 0, 1, 0, 0, 0.5f); /* unlit but there */
    t[3] = leaf(1, 0, 1, 0, 1, 0, 0, 0.5f);
    fv_gi_build_cpu(t, 2, 0.1f, 0.9f, false);
    assert_true(fabsf(t[4].flux.w - 4.0f) < 1e-6f);
    assert_true(fabsf(t[4].pos.x - 0.75f) < 1e-6f && fabsf(t[4].pos.z) < 1e-6f); /* power-weighted */
    assert_true(t[4].info.x == 1.0f && t[4].info.z == 1.0f);
    assert_true(t[4].normal.w >= 0.75f); /* holds every child's disk */
    /* plain means (gi.average=plain): the same sums, the four positions alike */
    fv_gi_build_cpu(t, 2, 0.1f, 0.9f, true);
    assert_true(fabsf(t[4].flux.w - 4.0f) < 1e-6f);
    assert_true(fabsf(t[4].pos.x - 0.5f) < 1e-6f && fabsf(t[4].pos.z - 0.5f) < 1e-6f);
    fv_gi_build_cpu(t, 2, 0.1f, 0.9f, false);
    uint32_t cut[5];
    assert_int_equal(fv_gi_cut_cpu(t, 2, 1, 0, cut, 5), 1);
    assert_int_equal(cut[0], 4);
    /* normals that cancel: +x, -x, +z, -z -> mean 0, invalid, finite */
    t[0] = leaf(0, 0, 0, 1, 0, 0, 1, 0.5f);
    t[1] = leaf(0, 0, 0, -1, 0, 0, 1, 0.5f);
    t[2] = leaf(0, 0, 0, 0, 0, 1, 1, 0.5f);
    t[3] = leaf(0, 0, 0, 0, 0, -1, 1, 0.5f);
    fv_gi_build_cpu(t, 2, 1.0f, -1.0f, false);
    assert_true(t[4].info.x == 0.0f);
    assert_true(fabsf(t[4].normal.x) < 1e-6f && fabsf(t[4].normal.z) < 1e-6f);
    double e[3], x[3] = {1, 1, 1}, n[3] = {0, -1, 0};
    fv_gi_cluster_irradiance(&t[4], x, n, e);
    assert_true(isfinite(e[0]) && e[0] == 0.0);
    /* invalid root: the cut is the four leaves */
    assert_int_equal(fv_gi_cut_cpu(t, 2, 1, 0, cut, 5), 4);
    /* depth beyond the threshold: invalid */
    t[0] = leaf(0, 0, 0, 0, 1, 0, 1, 0.1f);
    t[1] = leaf(0, 0, 0, 0, 1, 0, 1, 0.9f);
    t[2] = leaf(0, 0, 0, 0, 1, 0, 1, 0.5f);
    t[3] = leaf(0, 0, 0, 0, 1, 0, 1, 0.5f);
    fv_gi_build_cpu(t, 2, 0.3f, 0.0f, false);
    assert_true(t[4].info.x == 0.0f);
    fv_gi_build_cpu(t, 2, 0.5f, 0.0f, false);
    assert_true(t[4].info.x == 1.0f);
    /* nothing there at all: an empty, valid node with no flux, cut empty */
    memset(t, 0, sizeof t);
    fv_gi_build_cpu(t, 2, 0.1f, 0.9f, false);
    assert_true(t[4].flux.w == 0.0f && t[4].info.z == 0.0f);
    assert_int_equal(fv_gi_cut_cpu(t, 2, 1, 0, cut, 5), 0);
    /* a 1x1 tree: the leaf is the root and the cut */
    fv_gi_node one = leaf(0, 0, 0, 0, 1, 0, 2, 0.5f);
    fv_gi_build_cpu(&one, 1, 0.1f, 0.9f, false);
    assert_int_equal(fv_gi_cut_cpu(&one, 1, 0, 0, cut, 1), 1);
}

static void levels_and_views_for_every_size(void **state)
{
    (void)state;
    fv_quality_gi q = fv_quality_default().gi;
    for (uint32_t n = 1; n <= FV_GI_MAX_RSM; n *= 2) {
        for (int l = 0; l < 4; l++) {
            q.limit_level = (fv_gi_limit)l;
            for (uint32_t s = 1; s <= 64; s *= 2) {
                q.start_level = s;
                uint32_t start, limit;
                fv_gi_tree_levels(n, &q, &start, &limit);
                assert_true(start >= limit && start <= fv_gi_log2(n));
            }
        }
        assert_int_equal(fv_gi_level_offset(n, fv_gi_log2(n)) + 1, fv_gi_nodes_for(n));
    }
    /* any light: a finite view */
    const float bad[4] = {NAN, INFINITY, 0.0f, -1e30f};
    for (int i = 0; i < 4; i++)
        for (uint32_t kind = FV_GI_KIND_SPOT; kind <= FV_GI_KIND_DIRECTIONAL; kind++) {
            fv_gpu_light L;
            memset(&L, 0, sizeof L);
            L.position_range = (fv_gpu_vec4){bad[i], 1, 0, 0};
            L.direction_type = (fv_gpu_vec4){0, bad[i], 0, 1};
            L.cone = (fv_gpu_vec4){bad[i], bad[i], 0, 0};
            fv_gi_view v;
            fv_gi_light_view(&L, kind, 64, fv_v3(-1, -1, -1), fv_v3(bad[i], 1, 1), &v);
            for (int c = 0; c < 4; c++)
                for (int r = 0; r < 4; r++) assert_true(isfinite(v.view_proj.m[c][r]));
            for (int k = 0; k < 4; k++) assert_true(isfinite(v.params[k]) && isfinite(v.origin[k]));
        }
}

/* The slab (info.w) of every inner node holds every VPL below it: |nh.(x_i - pos)| <= slab (nh the unit mean
 * normal), and slab <= extent; on leaves spread over a floor, a wall and a tilted, bumpy patch with some unlit and
 * some without geometry. Flat parts give a thin slab (what lets the gather drop a coplanar subtree). */
static void slab_holds_every_vpl_below(void **state)
{
    (void)state;
    enum { N = 16 };
    fv_gi_node tree[4 * N * N]; /* more than fv_gi_nodes_for(16) = 341 */
    assert_true(fv_gi_nodes_for(N) <= 4 * N * N);
    memset(tree, 0, sizeof tree);
    uint32_t seed = 12345u;
    for (uint32_t y = 0; y < N; y++)
        for (uint32_t x = 0; x < N; x++) {
            seed = seed * 1664525u + 1013904223u;
            float u = (float)x / N, v = (float)y / N, jitter = (float)(seed >> 8) / 16777216.0f - 0.5f;
            fv_gi_node *l = &tree[y * N + x];
            if (x < 6) *l = leaf(u, 0.0f, v, 0, 1, 0, 1.0f + jitter, 0.3f + 0.1f * v);          /* floor */
            else if (x < 11) *l = leaf(0.4f, u, v, -1, 0, 0, 0.5f, 0.5f);                      /* wall */
            else *l = leaf(u, 0.2f * u + 0.01f * jitter, v, -0.196f, 0.98f, 0, 2.0f, 0.4f);   /* tilted, bumpy */
            if ((seed >> 4) % 7 == 0) l->flux = (fv_gpu_vec4){0, 0, 0, 0};                      /* unlit */
            if ((seed >> 4) % 11 == 0) memset(l, 0, sizeof *l);                                /* no geometry */
        }
    fv_gi_build_cpu(tree, N, 0.25f, 0.6f, false);
    uint32_t levels = fv_gi_log2(N) + 1, thin = 0;
    for (uint32_t k = 1; k < levels; k++) {
        uint32_t s = N >> k;
        for (uint32_t i = 0; i < s * s; i++) {
            const fv_gi_node *c = &tree[fv_gi_level_offset(N, k) + i];
            if (c->info.z < 0.5f) continue;
            float nl = sqrtf(c->normal.x * c->normal.x + c->normal.y * c->normal.y + c->normal.z * c->normal.z);
            assert_true(isfinite(c->info.w) && c->info.w >= 0.0f && c->info.w <= c->normal.w);
            if (nl > 1e-6f && c->info.w < 1e-3f * c->normal.w) thin++;
            uint32_t cx = i % s, cy = i / s;
            for (uint32_t y = cy << k; y < (cy + 1) << k; y++)
                for (uint32_t x = cx << k; x < (cx + 1) << k; x++) {
                    const fv_gi_node *l = &tree[y * N + x];
                    if (l->info.z < 0.5f) continue;
                    float d[3] = {l->pos.x - c->pos.x, l->pos.y - c->pos.y, l->pos.z - c->pos.z};
                    float off = nl > 1e-6f ? fabsf(d[0] * c->normal.x + d[1] * c->normal.y + d[2] * c->normal.z) / nl
                                           : sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                    if (!(off <= c->info.w * (1.0f + 1e-5f) + 1e-6f))
                        fail_msg("level %u node %u: VPL (%u, %u) %.7g from the plane, slab %.7g", k, i, x, y,
                                 (double)off, (double)c->info.w);
                }
        }
    }
    assert_true(thin > 0); /* the floor's and the wall's own clusters are flat */
}

/* The walk records' pre-order: positions and nodes are inverse, every subtree is contiguous (a node's children follow
 * it, each child's subtree right after its elder sibling's), and the record of an unlit node has zero flux and extent
 * (the walk never splits it and it adds 0). */
static void walk_order_is_a_preorder(void **state)
{
    (void)state;
    for (uint32_t n = 1; n <= 64; n *= 2) {
        uint32_t top = fv_gi_log2(n), total = fv_gi_nodes_for(n);
        assert_int_equal(fv_gi_subtree(top), total);
        assert_int_equal(fv_gi_walk_node(n, total), total); /* outside */
        for (uint32_t k = 0; k <= top; k++) {
            uint32_t s = n >> k;
            for (uint32_t y = 0; y < s; y++)
                for (uint32_t x = 0; x < s; x++) {
                    uint32_t p = fv_gi_walk_pos(n, k, x, y);
                    assert_true(p < total);
                    assert_int_equal(fv_gi_walk_node(n, p), fv_gi_level_offset(n, k) + y * s + x);
                    if (k == 0) continue;
                    uint32_t next = p + 1;
                    for (uint32_t d = 0; d < 4; d++) {
                        assert_int_equal(fv_gi_walk_pos(n, k - 1, 2 * x + (d & 1), 2 * y + (d >> 1)), next);
                        next += fv_gi_subtree(k - 1);
                    }
                    assert_int_equal(next, p + fv_gi_subtree(k));
                }
        }
    }
    fv_gi_node t[5];
    t[0] = leaf(0, 0, 0, 0, 1, 0, 1, 0);
    t[1] = leaf(1, 0, 0, 0, 1, 0, 0, 0); /* unlit */
    t[2] = leaf(0, 0, 1, 0, 1, 0, 2, 0);
    t[3] = leaf(1, 0, 1, 0, 1, 0, 3, 0);
    fv_gi_build_cpu(t, 2, 1.0f, 0.5f, false);
    fv_gi_cluster r = fv_gi_walk_record(t, 2, 4);
    assert_true(r.normal.w == 5.0f && r.flux.w == t[4].normal.w && r.pos.w == t[4].info.w && r.flux.x == 6.0f);
    r = fv_gi_walk_record(t, 2, 1);
    assert_true(r.normal.w == 1.0f && r.flux.x == 0.0f && r.flux.w == 0.0f);
    r = fv_gi_walk_record(t, 2, 3);
    assert_true(r.normal.w == 1.0f && r.flux.x == 3.0f && r.flux.w == 0.01f && r.pos.x == 1.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(irradiance_is_finite_and_bounded_at_the_extremes),
        cmocka_unit_test(build_sums_weights_and_validates),
        cmocka_unit_test(levels_and_views_for_every_size),
        cmocka_unit_test(slab_holds_every_vpl_below),
        cmocka_unit_test(walk_order_is_a_preorder),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
