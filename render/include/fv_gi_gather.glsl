// @brief One-bounce indirect irradiance from the light quad-tree (render/gi; Ki & Oh 2007, papers/README.md §1),
// evaluated inside the shared shading function (fv_hook_indirect_irradiance), so full-resolution, listed-pixel and
// foveated shading all get it. Reads the GI technique slots of the shading-inputs set (fv_gi_interface.glsl). Modes:
// the flat cut list, the paper's per-pixel traversal, a lightcuts-style bound, RSM sampling (Dachsbacher &
// Stamminger 2005) and the exact sum over every VPL. Requires fv_gpu.h, fv_common.glsl and
// fv_shade_inputs_interface.h. Every result is finite and >= 0.
#ifndef FV_GI_GATHER_GLSL
#define FV_GI_GATHER_GLSL

#include "fv_gi_interface.glsl"

// The gather a pipeline has compiled in (fv_gpu.h FV_SPEC_ID_GI_MODE): every mode by default, none or one.
layout(constant_id = FV_SPEC_ID_GI_MODE) const int FV_SPEC_GI_MODE = FV_SPEC_GI_ANY;

layout(std430, set = FV_SHADE_INPUTS_SET, binding = FV_GI_BINDING_HEADER) readonly buffer FvGiHeader {
    fv_gi_header gi;
    fv_gi_cluster gi_cut[];
};
layout(std430, set = FV_SHADE_INPUTS_SET, binding = FV_GI_BINDING_NODES) readonly buffer FvGiNodes {
    fv_gi_node gi_nodes[];
};

// Counting (a shading pass that defines FV_GI_STATS before including the shading function): each invocation notes
// what its pixel's gather summed (fv_gi_stats_note, from the shading hook), and the pass calls fv_gi_stats_flush once
// at the end of main, in uniform control flow, which adds the notes to the slot's fv_gi_stats: per subgroup (the
// sum, the max and the pixels reduced first) or per pixel (FV_GI_STATS_ATOMIC). Without FV_GI_STATS both are empty
// and the stats buffer is not declared (the debug views and the other shaders that include the gather).
#ifdef FV_GI_STATS
layout(std430, set = FV_SHADE_INPUTS_SET, binding = FV_GI_BINDING_STATS) buffer FvGiStats {
    fv_gi_stats gi_stats;
};
uint fv_gi_noted_clusters = 0u; // this invocation's: clusters summed, pixels that ran the gather
uint fv_gi_noted_pixels = 0u;
#endif

void fv_gi_stats_note(uint used)
{
#ifdef FV_GI_STATS
    if (FV_SPEC_GI_MODE == FV_SPEC_GI_OFF || gi.counts.x == 0u) return; // GI off: no gather ran
    fv_gi_noted_clusters += used;
    fv_gi_noted_pixels++;
#endif
}

void fv_gi_stats_flush()
{
#ifdef FV_GI_STATS
    // With GI off the stats binding is the slot's dummy: never written. counts.x is the same for every invocation,
    // so this returns for the whole subgroup or for none of it (a pipeline without GI has no counting at all).
    if (FV_SPEC_GI_MODE == FV_SPEC_GI_OFF || gi.counts.x == 0u) return;
#if FV_GI_STATS == FV_GI_STATS_SUBGROUP
    uint pixels = subgroupAdd(fv_gi_noted_pixels);
    uint sum = subgroupAdd(fv_gi_noted_clusters); // < 2^32: at most 2^21 per pixel (every VPL of two 1024^2 RSMs)
    uint most = subgroupMax(fv_gi_noted_clusters);
    if (!subgroupElect()) return;
#else
    uint pixels = fv_gi_noted_pixels, sum = fv_gi_noted_clusters, most = sum;
#endif
    if (pixels == 0u) return;
    // 64-bit sum from 32-bit atomics: the addition that wraps the low word carries one into the high word.
    uint before = atomicAdd(gi_stats.counts.x, sum);
    if (before > 0xffffffffu - sum) atomicAdd(gi_stats.counts.y, 1u);
    atomicMax(gi_stats.counts.z, most);
    atomicAdd(gi_stats.counts.w, pixels);
#endif
}

// Irradiance (W/m^2 per channel) at x (unit normal n) from one cluster taken as a Lambertian disk of flux Phi:
//   E = Phi * max(0, n_c.(x - x_c)/d) * max(0, n.(x_c - x)/d) / (pi * (d^2 + r^2))
// (Ki & Oh 2007 eq. 1 / Dachsbacher & Stamminger 2005, with the Lambertian 1/pi that the papers fold into Phi).
// The papers' 1/d^4 (two cosines over d^2) has a singularity at the VPL; here the d^2 of the falloff becomes
// d^2 + r^2, r the cluster's extent: exactly the on-axis irradiance of a uniformly emitting disk of radius r, so a
// receiver at a cluster sees at most Phi / (pi r^2) (the disk's own exitance) — bounded by the physics, not by a
// tuning constant. n_c is the mean normal (shorter than unit where the children disagree: normals that cancel give
// no light instead of NaN). A receiver exactly at x_c (d = 0) gets 0; zero flux gives 0.
// The formula from a cluster's parts: flux phi, centre p, mean normal nm, extent r.
vec3 fv_gi_disk_irradiance(vec3 phi, vec3 p, vec3 nm, float r, vec3 x, vec3 n)
{
    vec3 v = x - p;
    float d2 = dot(v, v);
    if (!(d2 > 1e-20)) return vec3(0.0);
    float inv_d = inversesqrt(d2);
    float cos_c = max(dot(nm, v) * inv_d, 0.0);
    float cos_r = max(-dot(n, v) * inv_d, 0.0);
    return max(phi, vec3(0.0)) * (cos_c * cos_r / (FV_PI * (d2 + r * r)));
}

vec3 fv_gi_cluster_irradiance(fv_gi_node c, vec3 x, vec3 n)
{
    if (!(c.flux.w > 0.0)) return vec3(0.0);
    return fv_gi_disk_irradiance(c.flux.rgb, c.pos.xyz, c.normal.xyz, c.normal.w, x, n);
}

// Upper bound on what any VPL below cluster c can give x: every VPL i lies in the sphere (x_c, extent) and gives at
// most Phi_i cos / (pi (d_i^2 + r_i^2)) <= Phi_i cos_max / (pi (d_min^2 + r_min^2)). cos_max bounds the receiver's
// cosine over the sphere (1 inside it).
float fv_gi_cluster_bound(fv_gi_node c, vec3 x, vec3 n)
{
    vec3 v = c.pos.xyz - x;
    float d = length(v);
    float r = c.normal.w;
    float cos_max = 1.0;
    if (d > r && d > 1e-12) {
        float cos_t = dot(n, v) / d;
        float sin_a = r / d;
        float cos_a = sqrt(max(1.0 - sin_a * sin_a, 0.0));
        float sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
        // cos(theta - alpha) when the sphere does not straddle the normal's direction
        cos_max = cos_t >= cos_a ? 1.0 : clamp(cos_t * cos_a + sin_t * sin_a, 0.0, 1.0);
    }
    float dmin = max(d - r, 0.0);
    float rmin = max(c.info.y, 1e-4);
    float phi = max(max(c.flux.r, c.flux.g), max(c.flux.b, 0.0));
    return phi * cos_max / (FV_PI * (dmin * dmin + rmin * rmin));
}

// The receiver's horizon: true when every VPL below a node (centre pos, mean normal nm, extent r, slab h: see
// fv_gi_node) lies on or behind the plane through x normal to n, so each of them, and any cluster of them, gives
// max(0, n.(x_i - x)) = 0 here. A VPL is x_i = pos + a + b nh (nh = nm / |nm|, a across nh, |a| <= r, |b| <= h),
// so n.(x_i - x) <= n.(pos - x) + r sin(n, nh) + h |cos(n, nh)| (and <= n.(pos - x) + r always). The tolerance
// 1e-4 (|pos - x| + r) absorbs the float noise of coplanar points (a floor's VPLs seen from the floor): what it
// drops is a receiver cosine below 1e-4 (d + r) / d_i. Refinement skips such a node's whole subtree.
bool fv_gi_behind(vec3 pos, vec3 nm, float r, float h, vec3 x, vec3 n)
{
    float nl = length(nm);
    float cs = nl > 1e-6 ? dot(n, nm) / nl : 0.0;
    float sn = sqrt(max(1.0 - cs * cs, 0.0));
    vec3 v = pos - x;
    return dot(n, v) + min(r * sn + h * abs(cs), r) <= 1e-4 * (length(v) + r);
}

// First node of level k in a tree of side n (a power of two; level k has s = n >> k nodes per side):
// sum_{j<k} (n/2^j)^2 = 4 (n^2 - s^2) / 3, exact in integers (n^2 - s^2 = s^2 (4^k - 1)).
uint fv_gi_level_offset(uint n, uint k)
{
    uint s = n >> k;
    return (4u * (n * n - s * s)) / 3u;
}

#define FV_GI_STACK 48

// The cut with near-field refinement: the irradiance at x from the first `count` cut entries, each replaced by its
// subtree where near (extent^2 above tau2 d^2), added to e; returns how many records (cut nodes and the tree nodes
// below them) were visited. Each cut entry names its node's walk record (fv_gi_cluster), and one loop visits, per
// entry, that record and, while it splits, the records of its subtree: a node near (extent over tau d) and above the
// receiver (fv_gi_behind: else dropped with its subtree) is replaced by its children (the next record); any other
// is summed and its subtree skipped (+ its subtree size). Kept whole, a node is at least extent / tau away and is
// summed as a point (no d^2 + r^2 softening: that guard against 1/d^4 is the bound where a cluster may be
// arbitrarily near, and for a cluster kept whole it is only a bias, d^2 / (d^2 + r^2) >= 1 / (1 + tau^2)): a cut
// entry that is not split with the cut's own formula (flux / pi, as the flat loop), a node below it with the cluster
// formula at r = 0; a VPL reached by splitting keeps its disk. An unlit node (zero flux and extent) is never split
// and adds 0. One flat loop, not a loop per entry: each lane walks its own sequence, so a SIMD group costs the
// longest lane's total, not the sum over entries of the longest lane's walk.
uint fv_gi_cut_refined(uint count, float tau2, vec3 x, vec3 n, inout vec3 e)
{
    uint len = uint(gi_cut.length());
    uint j = 0u, i = 0u, end = 0u, top = 0u, used = 0u;
    for (;;) {
        if (i >= end) { // this entry's subtree is done: the next cut entry's record
            if (j >= count) break;
            top = min(uint(gi_cut[j].normal.w), len - 1u);
            j++;
            i = top;
            end = top + 1u;
        }
        fv_gi_cluster c = gi_cut[i];
        uint size = max(uint(c.normal.w), 1u);
        if (i == top) end = min(top + size, len);
        used++;
        float r = c.flux.w;
        vec3 v = x - c.pos.xyz;
        float d2 = dot(v, v);
        bool split = r * r > tau2 * d2;
        if (size > 1u && split) {
            if (!fv_gi_behind(c.pos.xyz, c.normal.xyz, r, c.pos.w, x, n)) {
                i++; // near and seen: descend to the first child
                continue;
            }
        } else if (i == top && !split) { // a cut entry kept whole: the flat cut's point formula
            float k = max(dot(c.normal.xyz, v), 0.0) * max(-dot(n, v), 0.0);
            if (d2 > 1e-20) e += (c.flux.rgb * (1.0 / 3.14159265358979)) * (k / (d2 * d2));
        } else {
            e += fv_gi_disk_irradiance(c.flux.rgb, c.pos.xyz, c.normal.xyz, size > 1u ? 0.0 : r, x, n);
        }
        i += size; // past this subtree
    }
    return used;
}

// Indirect irradiance at x (unit normal n), and how many clusters (or samples) it summed (with gi.refine: the
// flat clusters summed plus the tree nodes the refinement visited).
vec3 fv_gi_irradiance(vec3 x, vec3 n, out uint used)
{
    used = 0u;
    if (FV_SPEC_GI_MODE == FV_SPEC_GI_OFF || gi.counts.x == 0u) return vec3(0.0);
    // a pipeline specialised for one mode keeps only that mode's loop (the header says the same mode)
    uint mode = FV_SPEC_GI_MODE >= 0 ? uint(FV_SPEC_GI_MODE) : gi.counts.y;
    uint lights = min(gi.counts.z, uint(FV_GI_MAX_LIGHTS));
    uint N = max(gi.tree.x, 1u);
    uint levels = min(gi.tree.y, uint(FV_GI_MAX_LEVELS));
    uint start = min(gi.tree.z, levels - 1u), limit = min(gi.tree.w, start);
    vec3 e = vec3(0.0);
    if (mode == FV_GI_MODE_CUT) {
        // The same formula as fv_gi_cluster_irradiance with pi and r^2 folded in at the build and one division:
        // E = (Phi/pi) max(0, n_c.v) max(0, -n.v) / (d^2 (d^2 + r^2)).
        // gi.refine (tau > 0): a cluster whose extent r exceeds tau d at this pixel (the near field, where one
        // point light is furthest from its VPLs' sum) is replaced by its children, recursively, until each is
        // within tau or a VPL; the far field stays the flat cut, summed as points (r <= tau d: no softening).
        uint count = min(gi.counts.w, uint(gi_cut.length()));
        float tau2 = uintBitsToFloat(gi.opts.w);
        bool refine = tau2 > 0.0 && tau2 <= 1.0;
        if (!refine) { // the flat cut alone: the tight loop
            for (uint i = 0u; i < count; i++) {
                fv_gi_cluster c = gi_cut[i];
                vec3 v = x - c.pos.xyz;
                float d2 = dot(v, v);
                float k = max(dot(c.normal.xyz, v), 0.0) * max(-dot(n, v), 0.0);
                if (d2 > 1e-20) e += c.flux.rgb * (k / (d2 * (d2 + c.flux.w)));
            }
            used = count;
        } else {
            used = fv_gi_cut_refined(count, tau2, x, n, e);
        }
    } else if (mode == FV_GI_MODE_EXACT) {
        for (uint l = 0u; l < lights; l++) {
            uint base = gi.light[l].info.y;
            for (uint i = 0u; i < N * N; i++) {
                fv_gi_node c = gi_nodes[base + i];
                if (c.flux.w > 0.0) {
                    e += fv_gi_cluster_irradiance(c, x, n);
                    used++;
                }
            }
        }
    } else if (mode == FV_GI_MODE_RSM_SAMPLING) {
        // Dachsbacher & Stamminger 2005: samples around the receiver's projection into the RSM, denser near it:
        // radius R xi1, angle 2 pi xi2, one fixed pattern for every pixel. The density per texel is 1/(2 pi R r),
        // so each sample weighs 2 pi R^2 xi1 / S (unbiased over the disk of radius R; R = N sqrt 2 reaches every
        // texel from anywhere on the map).
        uint S = max(gi.opts.x, 1u);
        float R = gi.params.w;
        for (uint l = 0u; l < lights; l++) {
            // A receiver the light does not see in front of it (the ceiling beside a spot) still gets light from
            // the map: its disk is centred at the map's nearest point (the middle when behind the light), which
            // the radius N sqrt 2 still covers the map from.
            vec4 c = gi.light[l].view_proj * vec4(x, 1.0);
            vec2 centre = c.w > 1e-20 ? clamp((c.xy / c.w * 0.5 + 0.5) * float(N), vec2(0.0), vec2(float(N)))
                                      : vec2(0.5 * float(N));
            uint base = gi.light[l].info.y;
            for (uint i = 0u; i < S; i++) {
                float xi1 = (float(i) + 0.5) / float(S);
                float xi2 = fract(float(i) * 0.6180339887498949);
                float a = 2.0 * FV_PI * xi2;
                vec2 t = centre + (R * xi1) * vec2(cos(a), sin(a));
                if (any(lessThan(t, vec2(0.0))) || any(greaterThanEqual(t, vec2(float(N))))) continue;
                uvec2 q = min(uvec2(t), uvec2(N - 1u));
                e += fv_gi_cluster_irradiance(gi_nodes[base + q.y * N + q.x], x, n) *
                     (2.0 * FV_PI * R * R * xi1 / float(S));
                used++;
            }
        }
    } else {
        // Top-down from the start level (depth first: the same set of clusters as the paper's breadth-first order).
        // traverse: a valid cluster, or any node at the limit level, is one light (Ki & Oh 2007);
        // bound: a cluster is one light when its bound is at most gi.params.z times the start level's estimate
        // (a lightcuts-style error bound, Walter et al. 2005), refined down to the VPLs otherwise.
        bool bound = mode == FV_GI_MODE_BOUND;
        uint off[FV_GI_MAX_LEVELS];
        for (uint k = 0u; k < levels; k++) off[k] = fv_gi_level_offset(N, k);
        for (uint l = 0u; l < lights; l++) {
            uint base = gi.light[l].info.y;
            uint side = N >> start;
            float ref = 0.0;
            if (bound) {
                for (uint i = 0u; i < side * side; i++) {
                    vec3 c = fv_gi_cluster_irradiance(gi_nodes[base + off[start] + i], x, n);
                    ref += max(max(c.r, c.g), c.b);
                }
            }
            float tol = gi.params.z * ref;
            for (uint i = 0u; i < side * side; i++) {
                uint stack[FV_GI_STACK]; // packed: level << 24 | local index
                uint sp = 0u;
                stack[sp++] = (start << 24) | i;
                while (sp > 0u) {
                    uint item = stack[--sp];
                    uint k = item >> 24, idx = item & 0xffffffu;
                    fv_gi_node c = gi_nodes[base + off[k] + idx];
                    if (!(c.flux.w > 0.0)) continue;
                    bool leaf = bound ? k == 0u : (k <= limit || c.info.x > 0.5);
                    if (!leaf && bound) {
                        if (fv_gi_behind(c.pos.xyz, c.normal.xyz, c.normal.w, c.info.w, x, n)) continue;
                        leaf = fv_gi_cluster_bound(c, x, n) <= tol;
                    }
                    if (leaf || sp + 4u > uint(FV_GI_STACK)) {
                        e += fv_gi_cluster_irradiance(c, x, n);
                        used++;
                        continue;
                    }
                    uint s = N >> k, cx = (idx % s) * 2u, cy = (idx / s) * 2u, cs = s * 2u;
                    uint kc = (k - 1u) << 24;
                    stack[sp++] = kc | (cy * cs + cx);
                    stack[sp++] = kc | (cy * cs + cx + 1u);
                    stack[sp++] = kc | ((cy + 1u) * cs + cx);
                    stack[sp++] = kc | ((cy + 1u) * cs + cx + 1u);
                }
            }
        }
    }
    if (any(isnan(e)) || any(isinf(e))) e = vec3(0.0);
    return max(e, vec3(0.0));
}

// ---- the reduced-rate gather's upsample (gi.rate; render/gi_gather writes the low-rate images) -------------------
//
// The rate a pipeline has compiled in (fv_gpu.h FV_SPEC_ID_GI_RATE): 0 the header's (run time), 1 the per-pixel
// gather alone (the upsample's code is not in the pipeline), 2, 4 or 8.
layout(constant_id = FV_SPEC_ID_GI_RATE) const int FV_SPEC_GI_RATE = 0;

// Joint-bilateral weights: a block sample counts for a pixel as far as it lies on the pixel's surface. Irradiance
// here is a function of position and normal alone (no visibility in the gather, no albedo), smooth along a surface;
// it jumps only where the position jumps (a depth discontinuity) or the normal turns (a crease). So the guides are
// geometric: the sample's distance off the pixel's tangent plane (and the pixel's off the sample's), relative to the
// distance between them (a scale-free angle: 0 on one plane whatever the view; ~1 across a depth step), and the
// angle between the normals. Material is not a guide: the albedo multiplies the irradiance afterwards.
#define FV_GI_UP_PLANE 0.08      // off-plane slope at which the plane weight reaches 0 (~4.6 degrees)
#define FV_GI_UP_NORMAL_POW 16.0 // normal weight dot(n, n_s)^16: 0.85 at 10 degrees, 0.19 at 25
#define FV_GI_UP_MIN_COVER 0.5 // the matching taps' share of the bilinear weight (each times its guide weight) below
                               // which the pixel gathers itself: interpolate, never extrapolate far across an edge

// How much sample (position ps, normal ns) stands for the surface at x (unit normal n): 1 on the same plane with the
// same normal, falling to 0 off it.
float fv_gi_guide_weight(vec3 x, vec3 n, vec3 ps, vec3 ns)
{
    vec3 d = ps - x;
    float dist = length(d);
    float off = max(abs(dot(n, d)), abs(dot(ns, d)));
    float wp = dist > 1e-7 ? clamp(1.0 - off / (FV_GI_UP_PLANE * dist), 0.0, 1.0) : 1.0;
    float wn = pow(max(dot(n, ns), 0.0), FV_GI_UP_NORMAL_POW);
    return wp * wp * wn;
}

#ifndef FV_GI_NO_UPSAMPLE
layout(set = FV_SHADE_INPUTS_SET, binding = FV_GI_BINDING_LOW_IRRADIANCE) uniform sampler2DArray gi_low_e;

// The irradiance at pixel s from the 2 x 2 block samples around it (bilinear in the block grid, each tap weighted by
// fv_gi_guide_weight); false when the matching taps hold less than FV_GI_UP_MIN_COVER of the weight, or the images
// bound are not this frame's grid (the dummy, whose w = 0, matches nothing).
bool fv_gi_upsample(fv_surface s, uint r, out vec3 e)
{
    e = vec3(0.0);
    uint w = frame.counts.y, h = frame.counts.z;
    ivec2 lo = ivec2((w + r - 1u) / r, (h + r - 1u) / r);
    ivec3 size = textureSize(gi_low_e, 0);
    if (size.x != lo.x || size.y != lo.y || int(s.pixel.z) >= size.z) return false;
    // Sample i sits at pixel r i + r/2: pixel p lies at (p - r/2) / r in sample units.
    vec2 u = (vec2(s.pixel.xy) - float(r / 2u)) / float(r);
    vec2 f0 = floor(u);
    vec2 t = u - f0;
    ivec2 i0 = ivec2(f0);
    vec3 sum = vec3(0.0);
    float wsum = 0.0;
    for (int k = 0; k < 4; k++) {
        ivec2 o = ivec2(k & 1, k >> 1);
        ivec3 q = ivec3(clamp(i0 + o, ivec2(0), lo - 1), int(s.pixel.z));
        vec4 es = texelFetch(gi_low_e, q, 0);
        if (!(es.w > 0.5)) continue;
        // the sample's surface, from the G-buffer at its pixel (fv_gbuffer_decode.glsl)
        uvec3 sp = uvec3(min(uvec2(q.xy) * r + r / 2u, uvec2(w, h) - 1u), s.pixel.z);
        vec3 ps = fv_gbuffer_position(sp, texelFetch(g_depth, ivec3(sp), 0).r);
        float g = fv_gi_guide_weight(s.pos_world, s.normal, ps, fv_oct_decode(texelFetch(g_normal, ivec3(sp), 0).rg));
        float b = (o.x == 1 ? t.x : 1.0 - t.x) * (o.y == 1 ? t.y : 1.0 - t.y);
        sum += (b * g) * max(es.rgb, vec3(0.0));
        wsum += b * g;
    }
    if (!(wsum >= FV_GI_UP_MIN_COVER)) return false;
    e = sum / wsum;
    return !(any(isnan(e)) || any(isinf(e)));
}

// Indirect irradiance at a decoded surface at the frame's gather rate: upsampled from the block samples where they
// match it, else gathered here (fv_gi_irradiance: `gathered` true, `used` what it summed).
vec3 fv_gi_indirect(fv_surface s, out uint used, out bool gathered)
{
    used = 0u;
    gathered = true;
    if (FV_SPEC_GI_MODE == FV_SPEC_GI_OFF || FV_SPEC_GI_RATE == 1) return fv_gi_irradiance(s.pos_world, s.normal, used);
    uint r = FV_SPEC_GI_RATE > 1 ? uint(FV_SPEC_GI_RATE) : gi.rate.x;
    vec3 e;
    if (gi.counts.x != 0u && r > 1u && r <= FV_GI_MAX_RATE && fv_gi_upsample(s, r, e)) {
        gathered = false;
        return e;
    }
    return fv_gi_irradiance(s.pos_world, s.normal, used);
}

vec3 fv_gi_indirect(fv_surface s)
{
    uint used;
    bool gathered;
    return fv_gi_indirect(s, used, gathered);
}
#endif

// The clusters view: light 0's RSM at uv in [0,1]^2, each texel coloured by the level of the cut node that holds it
// (levels from the limit, red, to coarser: yellow, green, cyan, blue, magenta), with
// a checkerboard of the cut nodes so neighbouring clusters stay apart. Black: no geometry or no light.
vec3 fv_gi_clusters_colour(vec2 uv)
{
    if (gi.counts.x == 0u || gi.counts.z == 0u) return vec3(0.0);
    uint N = max(gi.tree.x, 1u);
    uint levels = min(gi.tree.y, uint(FV_GI_MAX_LEVELS));
    uint start = min(gi.tree.z, levels - 1u), limit = min(gi.tree.w, start);
    uvec2 t = min(uvec2(clamp(uv, vec2(0.0), vec2(1.0)) * float(N)), uvec2(N - 1u));
    uint base = gi.light[0].info.y;
    for (int k = int(start); k >= int(limit); k--) {
        uint s = N >> uint(k);
        uvec2 q = t >> uint(k);
        fv_gi_node c = gi_nodes[base + fv_gi_level_offset(N, uint(k)) + q.y * s + q.x];
        if (c.info.x > 0.5 || k == int(limit)) {
            if (!(c.flux.w > 0.0)) return vec3(0.0);
            const vec3 pal[6] = vec3[6](vec3(1, 0.15, 0.1), vec3(1, 0.9, 0.1), vec3(0.2, 1, 0.2), vec3(0.1, 0.9, 1),
                                        vec3(0.25, 0.35, 1), vec3(1, 0.2, 1));
            vec3 col = pal[uint(k - int(limit)) % 6u];
            float checker = ((q.x + q.y) & 1u) == 0u ? 1.0 : 0.6;
            return col * checker;
        }
    }
    return vec3(0.0);
}

#endif
