// @brief Subsurface light at a surface (render/sss): the dipole diffusion approximation (Jensen et al. 2001, with
// ../shared/papers/README.md section 4's corrected eq. 4) summed over the light-view samples of the surface's
// material, Lo = (1/pi) Ft(eta, wo) sum_i E_i A_i K_i(x_o), where K_i is the mean of Rd over the sample's
// footprint, the parallelogram its texel cuts from the surface (render/sss/fv_dipole.h's fv_dipole_tile_kernel, whose
// double version the CPU reference and the tests use; a cluster above the leaves: the disk of its area,
// fv_dipole_kernel). Within the receiver's near field (the material's flat radius, layer.view.w) each footprint is
// first carried along the light onto the receiver's tangent plane (fv_sss_near_footprint, render/sss/fv_sss_math.h).
// The leaves are the fine map's texels, s levels below the nominal texels of sss.map_size (fv_sss_sub_levels): a
// nominal texel resolved into one sample (it has a footprint: fv_sss_texel_resolve) is a leaf to both modes, the
// others (where the light grazes, at the silhouette) keep their fine samples.
// Exact mode sums every nominal texel, an unresolved one's fine samples within the receiver's near field and one
// disk of its area beyond (as the hierarchy); hierarchy mode walks each map's quad-tree from the start level,
// accepting a cluster of radius r at distance d when r <= distance_scale x eye distance x similarity x d, or at the
// limit level (Ki & Oh), but never one with leaves wholly in the near field, and dropping every node wholly beyond
// the material's cutoff radius (layer.view.z: outside it leaves the fraction sss.cutoff of a point's light).
// Requires fv_gpu.h, fv_common.glsl, the scene set and fv_gbuffer_decode.glsl; declares the SSS slot of the shading
// inputs (set 1).
// With no SSS pass the header is the slot's zero dummy: one load, then nothing.
#ifndef FV_SSS_GATHER_GLSL
#define FV_SSS_GATHER_GLSL
#extension GL_EXT_control_flow_attributes : require // [[unroll]] below

#include "fv_sss_interface.h"

layout(std430, set = FV_SHADE_INPUTS_SET, binding = FV_SSS_BINDING_HEADER) readonly buffer FvSssHeader {
    fv_gpu_sss sss_header;
};
layout(std430, set = FV_SHADE_INPUTS_SET, binding = FV_SSS_BINDING_NODES) readonly buffer FvSssNodes {
    fv_gpu_sss_node sss_nodes[];
};

const float FV_SSS_SIGMA_MAX = 1e10;  // per metre: keeps 1/zr^2 and its products inside float range

// One material's dipole, the three channels at once.
struct fv_sss_dipole {
    vec3 alpha;    // reduced albedo alpha' = sigma_s' / sigma_t'
    vec3 sigma_tr; // sqrt(3 sigma_a sigma_t')
    vec3 zr, zv;   // real source depth 1/sigma_t', virtual source height zr (1 + 4A/3); 0: no scattering
};

float fv_sss_fdr(float eta)
{
    eta = eta > 0.0 && eta <= 1e3 ? eta : 1.0;
    float f = eta >= 1.0 ? -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta
                         : -0.4399 + 0.7099 / eta - 0.3319 / (eta * eta) + 0.0636 / (eta * eta * eta);
    return clamp(f, 0.0, 0.999);
}

fv_sss_dipole fv_sss_dipole_of(fv_gpu_material m)
{
    vec3 sa = clamp(m.sigma_a.rgb, vec3(0.0), vec3(FV_SSS_SIGMA_MAX));
    vec3 sp = clamp(m.sigma_s.rgb, vec3(0.0), vec3(FV_SSS_SIGMA_MAX));
    vec3 st = sa + sp;
    float fdr = fv_sss_fdr(m.sigma_a.w);
    float a = (1.0 + fdr) / (1.0 - fdr);
    bvec3 some = greaterThan(st, vec3(0.0));
    fv_sss_dipole d;
    d.alpha = mix(vec3(0.0), sp / max(st, vec3(1e-30)), some);
    d.sigma_tr = sqrt(3.0 * sa * st);
    d.zr = mix(vec3(0.0), 1.0 / max(st, vec3(1e-30)), some);
    d.zv = d.zr * (1.0 + 4.0 * a / 3.0);
    return d;
}

// Rd(r) per channel (eq. 4 corrected): alpha'/(4 pi) [zr (s + 1/dr) e^(-s dr)/dr^2 + zv (s + 1/dv) e^(-s dv)/dv^2].
vec3 fv_sss_rd(fv_sss_dipole d, float r)
{
    vec3 dr = sqrt(r * r + d.zr * d.zr), dv = sqrt(r * r + d.zv * d.zv);
    vec3 tr = d.zr * (d.sigma_tr + 1.0 / max(dr, vec3(1e-30))) * exp(-d.sigma_tr * dr) / max(dr * dr, vec3(1e-30));
    vec3 tv = d.zv * (d.sigma_tr + 1.0 / max(dv, vec3(1e-30))) * exp(-d.sigma_tr * dv) / max(dv * dv, vec3(1e-30));
    return mix(vec3(0.0), d.alpha * (1.0 / (4.0 * FV_PI)) * (tr + tv), greaterThan(d.zr, vec3(0.0)));
}

// e^(-s x1)/x1 - e^(-s x2)/x2 with x2 = x1 + delta, without cancellation.
vec3 fv_sss_source_diff(vec3 s, vec3 x1, vec3 delta)
{
    vec3 x = max(x1, vec3(1e-30));
    vec3 sd = s * delta;
    vec3 ed = exp(-sd);
    // -expm1(-s delta): 1 - e^(-s delta), by its series where that cancels
    vec3 one_minus = mix(1.0 - ed, sd - 0.5 * sd * sd + sd * sd * sd * (1.0 / 6.0), lessThan(sd, vec3(1e-3)));
    return exp(-s * x) / x * (one_minus + ed * delta / (x + delta));
}

// The integral of Rd over radii [r1, r2] (times 2 pi r), the disk integral's antiderivative differenced.
vec3 fv_sss_disk_ring(fv_sss_dipole d, float r1, float r2)
{
    float ring = (r2 - r1) * (r2 + r1);
    if (!(ring > 0.0)) return vec3(0.0);
    vec3 dr1 = sqrt(r1 * r1 + d.zr * d.zr), dr2 = sqrt(r2 * r2 + d.zr * d.zr);
    vec3 dv1 = sqrt(r1 * r1 + d.zv * d.zv), dv2 = sqrt(r2 * r2 + d.zv * d.zv);
    vec3 v = 0.5 * d.alpha * (d.zr * fv_sss_source_diff(d.sigma_tr, dr1, ring / max(dr1 + dr2, vec3(1e-30))) +
                              d.zv * fv_sss_source_diff(d.sigma_tr, dv1, ring / max(dv1 + dv2, vec3(1e-30))));
    return mix(vec3(0.0), max(v, vec3(0.0)), greaterThan(d.zr, vec3(0.0)));
}

// The mean of Rd over the disk of radius s centred `dist` from the receiver (polar coordinates around it).
vec3 fv_sss_disk_mean(fv_sss_dipole d, float dist, float s)
{
    const float gx[4] = float[4](-0.8611363116, -0.3399810436, 0.3399810436, 0.8611363116);
    const float gw[4] = float[4](0.3478548451, 0.6521451549, 0.6521451549, 0.3478548451);
    bool inside = dist < s;
    float half_range = inside ? 0.5 * FV_PI : 0.5 * asin(min(s / max(dist, 1e-30), 1.0));
    vec3 sum = vec3(0.0);
    for (int k = 0; k < 4; k++) {
        float phi = half_range * (gx[k] + 1.0);
        float sn = sin(phi), c = cos(phi);
        float q = sqrt(max(s * s - dist * dist * sn * sn, 0.0));
        float r1 = inside ? 0.0 : max(dist * c - q, 0.0);
        float r2 = inside ? max(q - dist * c, 0.0) : dist * c + q;
        sum += gw[k] * fv_sss_disk_ring(d, r1, r2);
    }
    return sum * (half_range / (FV_PI * FV_PI * s * s));
}

// One source's Rd term at r and its radial derivatives (fv_dipole.h's source_derivs), per channel: g, d^2/dr^2 g and
// (1/r) d/dr g.
void fv_sss_source_derivs(vec3 z, vec3 s, float r, out vec3 g, out vec3 frr, out vec3 fr_r)
{
    vec3 D = sqrt(r * r + z * z);
    vec3 e = z * exp(-s * D), i1 = 1.0 / max(D, vec3(1e-30)), i2 = i1 * i1, i3 = i2 * i1, i4 = i2 * i2, i5 = i4 * i1;
    vec3 g1 = -e * (s * s * i2 + 3.0 * s * i3 + 3.0 * i4);
    vec3 g2 = e * (s * s * s * i2 + 5.0 * s * s * i3 + 12.0 * s * i4 + 12.0 * i5);
    g = e * (s + i1) * i2;
    frr = g2 * (r * r) * i2 + g1 * (z * z) * i3;
    fr_r = g1 * i1;
}

// The mean of Rd over a region of second moment M at distance r, to second order (fv_dipole.h's rd_smoothed):
// Rd + (1/2)(f_rr m_uu + (f_r / r)(tr M - m_uu)), m_uu = u^T M u along the direction u to the region.
vec3 fv_sss_smoothed(fv_sss_dipole d, float r, float m_uu, float m_trace)
{
    vec3 gr, rr, fr, gv, rv, fv;
    fv_sss_source_derivs(d.zr, d.sigma_tr, r, gr, rr, fr);
    fv_sss_source_derivs(d.zv, d.sigma_tr, r, gv, rv, fv);
    vec3 v = d.alpha * (1.0 / (4.0 * FV_PI)) *
             (gr + gv + 0.5 * ((rr + rv) * m_uu + (fr + fv) * (m_trace - m_uu)));
    return mix(vec3(0.0), max(v, vec3(0.0)), greaterThan(d.zr, vec3(0.0)));
}

// The isotropic kernel (fv_dipole_kernel): mean Rd over the disk of the node's area centred `dist` from the
// receiver; beyond FV_DIPOLE_KERNEL_NEAR = 4 radii (where sigma_tr s <= 0.25) its second-order mean. For a cluster
// without a footprint (some of its children empty).
vec3 fv_sss_kernel(fv_sss_dipole d, float dist, float area)
{
    float s = sqrt(max(area, 0.0) * (1.0 / FV_PI));
    if (!(s > 0.0)) return fv_sss_rd(d, dist);
    bvec3 smooth_ok = lessThanEqual(d.sigma_tr * s, vec3(0.25)); // FV_DIPOLE_KERNEL_SMOOTH
    bool far_ = dist > 4.0 * s;                                  // FV_DIPOLE_KERNEL_NEAR
    vec3 smoothed = far_ ? fv_sss_smoothed(d, dist, 0.25 * s * s, 0.5 * s * s) : vec3(0.0);
    if (far_ && all(smooth_ok)) return smoothed;
    vec3 quad = fv_sss_disk_mean(d, dist, s);
    return far_ ? mix(quad, smoothed, smooth_ok) : quad;
}

// fv_sss_disk_ring signed: negative when r2 < r1.
vec3 fv_sss_ring_signed(fv_sss_dipole d, float r1, float r2)
{
    return (r2 >= r1 ? 1.0 : -1.0) * fv_sss_disk_ring(d, min(r1, r2), max(r1, r2));
}

// The footprint kernel (fv_dipole_tile_kernel): the mean of Rd over the parallelogram c +- a/2 +- b/2 seen from the
// receiver x. Near (within FV_DIPOLE_KERNEL_NEAR half-diagonals): each edge's triangle from the receiver's foot on the
// footprint's plane, integrated exactly in the radius
// along 4 Gauss-Legendre directions (neighbours share an edge's directions, so the footprints of a map tile the
// surface without ripple); far: the second-order mean with M = (a a^T + b b^T) / 12, or the disk of its area where
// the footprint is wide against the diffusion length. No footprint (a x b = 0): the isotropic kernel of the area.
vec3 fv_sss_tile_kernel(fv_sss_dipole d, vec3 c, vec3 a, vec3 b, float area, vec3 x)
{
    vec3 off = c - x;
    float dist = length(off);
    vec3 nrm = cross(a, b);
    float fa = length(nrm), la = length(a);
    if (!(fa > 0.0) || !(la > 0.0)) return fv_sss_kernel(d, dist, area);
    float radius = 0.5 * sqrt(max(dot(a + b, a + b), dot(a - b, a - b)));
    bvec3 smooth_ok = lessThanEqual(d.sigma_tr * radius, vec3(0.25));
    if (dist > 4.0 * radius) { // far: the second-order mean, or (a footprint wide against the diffusion length) the
                               // disk of its area
        float ua = dot(off, a) / dist, ub = dot(off, b) / dist;
        vec3 smoothed = fv_sss_smoothed(d, dist, (ua * ua + ub * ub) * (1.0 / 12.0), (dot(a, a) + dot(b, b)) * (1.0 / 12.0));
        if (all(smooth_ok)) return smoothed;
        return mix(fv_sss_disk_mean(d, dist, sqrt(area * (1.0 / FV_PI))), smoothed, smooth_ok);
    }
    const float gx[4] = float[4](-0.8611363116, -0.3399810436, 0.3399810436, 0.8611363116);
    const float gw[4] = float[4](0.3478548451, 0.6521451549, 0.6521451549, 0.3478548451);
    vec3 n = nrm / fa, e1 = a / la, e2 = cross(n, e1);
    float h = dot(off, n);
    vec2 o = vec2(dot(off, e1), dot(off, e2)); // the centre, relative to the receiver's foot
    vec2 ha = vec2(0.5 * la, 0.0), hb = 0.5 * vec2(dot(b, e1), dot(b, e2));
    vec2 q[4] = vec2[4](o - ha - hb, o + ha - hb, o + ha + hb, o - ha + hb);
    float r0 = sqrt(dot(o, o) + h * h);
    vec3 tot = vec3(0.0);
    float wind = 0.0;
    // Loops kept rolled: this body inlined 16 x 16 times (an unrolled sample loop of exact mode's, once) took
    // llvmpipe over a minute to compile (they run only for the few footprints near the receiver).
    [[dont_unroll]] for (int k = 0; k < 4; k++) {
        vec2 P = q[k], Q = q[(k + 1) & 3], E = Q - P;
        float cr = P.x * E.y - P.y * E.x;
        bool ends = dot(P, P) > 0.0 && dot(Q, Q) > 0.0;
        float dl = ends ? atan(P.x * Q.y - P.y * Q.x, dot(P, Q)) : 0.0;
        float ph0 = ends ? atan(P.y, P.x) : 0.0;
        vec3 sum = vec3(0.0);
        [[dont_unroll]] for (int j = 0; j < 4; j++) {
            float ph = ph0 + 0.5 * dl * (gx[j] + 1.0);
            float den = cos(ph) * E.y - sin(ph) * E.x;
            float rho = den != 0.0 ? max(cr / den, 0.0) : 0.0;
            sum += gw[j] * fv_sss_ring_signed(d, r0, sqrt(rho * rho + h * h));
        }
        tot += 0.5 * dl * sum;
        wind += dl;
    }
    vec3 quad = max((tot + wind * fv_sss_disk_ring(d, abs(h), r0)) * (1.0 / (2.0 * FV_PI * fa)), vec3(0.0));
    return mix(vec3(0.0), quad, greaterThan(d.zr, vec3(0.0)));
}

// A receiver's near field (render/sss/fv_sss_math.h's fv_sss_receiver): near it the surface is its tangent plane,
// onto which each footprint is carried along the light.
struct fv_sss_receiver {
    vec3 x, n;     // position, unit shading normal
    vec3 nc;       // the plane's normal: n tilted toward the light to a cosine of at least FV_SSS_GPU_MIN_COS
    vec3 w;        // unit direction the light travels at x
    float wn;      // w . nc (< 0)
    float facing;  // the receiver's cosine weight, 0..1 (0: every footprint as cast)
    float flat_m;  // the material's flat radius (m)
};

// fv_sss_receiver_make: x with unit normal n (facing the eye), lit by light `light`.
fv_sss_receiver fv_sss_receiver_of(vec3 x, vec3 n, uint light, float flat_m)
{
    fv_sss_receiver r;
    r.x = x;
    r.n = n;
    r.nc = n;
    r.w = vec3(0.0);
    r.wn = 0.0;
    r.facing = 0.0;
    r.flat_m = flat_m > 0.0 ? flat_m : 0.0;
    if (light >= uint(lights.length())) return r;
    fv_gpu_light L = lights[light];
    bool directional = uint(L.direction_type.w + 0.5) == FV_GPU_LIGHT_DIRECTIONAL;
    vec3 w = directional ? L.direction_type.xyz : x - L.position_range.xyz;
    float wl = length(w), nl = length(n);
    if (!(wl > 1e-30) || !(nl > 1e-30)) return r;
    w /= wl;
    n /= nl;
    float cos_x = -dot(n, w);
    if (!(cos_x > 0.0)) return r; // the dark side: no near field
    vec3 nc = n;
    if (cos_x < FV_SSS_GPU_MIN_COS) {
        vec3 t = fv_sss_unit_across(n, -w);
        if (dot(t, t) == 0.0) return r;
        nc = -w * FV_SSS_GPU_MIN_COS + t * sqrt(1.0 - FV_SSS_GPU_MIN_COS * FV_SSS_GPU_MIN_COS);
    }
    r.n = n;
    r.nc = nc;
    r.w = w;
    r.wn = dot(w, nc);
    r.facing = smoothstep(FV_SSS_GPU_FLAT_COS_LO, FV_SSS_GPU_FLAT_COS_HI, cos_x);
    return r;
}

// fv_sss_near_footprint: the footprint (c, a, b; normal n_s, half-diagonal hd) carried along the light by the
// fraction beta of the way onto the receiver's plane; beta 1 within d1 = max(flat radius, 2 half-diagonals), 0
// beyond 2 d1, times the receiver's facing and the normals' likeness.
void fv_sss_near_footprint(fv_sss_receiver r, inout vec3 c, inout vec3 a, inout vec3 b, vec3 n_s, float hd)
{
    if (!(r.facing > 0.0) || !(r.wn < 0.0)) return;
    vec3 off = c - r.x;
    float dist = length(off);
    float d1 = max(r.flat_m, float(FV_SSS_GPU_FLAT_FOOTPRINTS) * hd);
    if (!(dist < 2.0 * d1)) return;
    float ls = length(n_s);
    float alike = ls > 1e-30 ? dot(n_s, r.n) / ls : 0.0;
    float beta = (1.0 - smoothstep(d1, 2.0 * d1, dist)) * r.facing *
                 smoothstep(FV_SSS_GPU_FLAT_NORMAL_LO, FV_SSS_GPU_FLAT_NORMAL_HI, alike);
    if (!(beta > 0.0)) return;
    float k = beta / r.wn;
    c -= (k * dot(off, r.nc)) * r.w;
    a -= (k * dot(a, r.nc)) * r.w;
    b -= (k * dot(b, r.nc)) * r.w;
}

// One leaf's footprint kernel at the receiver, its footprint as the receiver's near field takes it.
vec3 fv_sss_node_kernel(fv_sss_dipole d, fv_gpu_sss_node n, fv_sss_receiver r)
{
    vec3 c = n.pos_area.xyz, a = n.extent.yzw, b = n.edge_b.xyz;
    fv_sss_near_footprint(r, c, a, b, n.normal_depth.xyz, n.extent.x);
    return fv_sss_tile_kernel(d, c, a, b, n.pos_area.w, r.x);
}

// Whether the surface's light is carried by the dipole (a translucent material with a map this frame).
layout(constant_id = FV_SPEC_ID_SSS) const bool FV_SPEC_SSS = true;

bool fv_sss_active(fv_surface s)
{
    if (!FV_SPEC_SSS) return false; // specialised without SSS: the dipole's code is not compiled in
    uint maps = min(sss_header.counts.x, uint(FV_SSS_GPU_MAX_LAYERS));
    if (maps == 0u || !s.hit || (materials[s.material].info.y & 1u) == 0u) return false;
    for (uint l = 0u; l < maps; l++)
        if (sss_header.layer[l].info.x == s.material) return true;
    return false;
}


// Lo(xo) toward the eye, W/(m^2 sr) per channel; out_clusters: the nodes it summed.
vec3 fv_sss_radiance(fv_surface s, out uint out_clusters)
{
    out_clusters = 0u;
    if (!fv_sss_active(s)) return vec3(0.0);
    fv_gpu_material m = materials[s.material];
    fv_sss_dipole d = fv_sss_dipole_of(m);
    vec3 x = s.pos_world;
    float eye_dist = length(frame.eye_pos[min(s.pixel.z, 1u)].xyz - x);
    float theta = max(sss_header.params.x, 0.0) * eye_dist;
    uint maps = min(sss_header.counts.x, uint(FV_SSS_GPU_MAX_LAYERS));
    uint total = uint(sss_nodes.length());
    vec3 sum = vec3(0.0);
    uint count = 0u;
    for (uint l = 0u; l < maps; l++) {
        fv_gpu_sss_layer layer = sss_header.layer[l];
        if (layer.info.x != s.material) continue;
        uint leaf = min(layer.info.w & 0xffu, 10u);
        uint sub = min(layer.info.w >> 8, leaf), nominal = leaf - sub; // the fine map's sub-levels (fv_sss_sub_levels)
        uint base = layer.info.z;
        fv_sss_receiver rc = fv_sss_receiver_of(x, s.normal, layer.info.y, layer.view.w);
        if (sss_header.counts.y == FV_SSS_GPU_MODE_EXACT) {
            // Every nominal texel: resolved, its one sample; else (fv_sss_texel_resolve) its 4^s fine samples where
            // the receiver's near field reaches it and one disk of its area beyond, as the hierarchy takes it (the
            // fine samples everywhere passed llvmpipe's loop limit on the marble bunny at 128 px: 3% of its light).
            // One loop whose every iteration is one texel or one fine sample, with one call of each kernel:
            // llvmpipe ends a shader's loops after 65535 iterations in all (LP_MAX_TGSI_LOOP_ITERATIONS, shared by
            // every loop), and a loop over the fine samples nested in the branch that takes them ran (and counted)
            // for every grazing texel whether any invocation was near it or not: the marble bunny's sum at 128 px
            // was cut short again; render/sss/sss.c's exact_iterations counts them.
            uint first = base + ((1u << (2u * nominal)) - 1u) / 3u, n = 1u << (2u * nominal);
            uint first_leaf = base + ((1u << (2u * leaf)) - 1u) / 3u, per = 1u << (2u * sub);
            uint t = 0u, from = 0u, left = 0u; // the next texel; the fine samples still to walk from `from`
            while (t < n || left > 0u) {
                uint at = left > 0u ? from++ : first + t++;
                bool fine = left > 0u;
                if (fine) left--;
                if (at >= total) continue;
                fv_gpu_sss_node node = sss_nodes[at];
                float area = node.pos_area.w;
                if (!(area > 0.0)) continue;
                if (!fine && sub > 0u && !(dot(node.extent.yzw, node.extent.yzw) > 0.0)) { // left at its fine samples
                    float near_field = max(rc.flat_m, float(FV_SSS_GPU_FLAT_FOOTPRINTS) * node.edge_b.w);
                    if (length(node.pos_area.xyz - x) - node.extent.x < near_field) {
                        from = first_leaf + (t - 1u) * per;
                        left = per;
                        continue;
                    }
                    // the hierarchy's accept of a cluster: the disk of its area
                    vec3 cc = node.pos_area.xyz, za = vec3(0.0), zb = vec3(0.0);
                    fv_sss_near_footprint(rc, cc, za, zb, node.normal_depth.xyz, node.edge_b.w);
                    sum += node.flux_sim.rgb * fv_sss_kernel(d, length(cc - x), area);
                    count++;
                    continue;
                }
                sum += node.flux_sim.rgb * fv_sss_node_kernel(d, node, rc);
                count++;
            }
            continue;
        }
        float cutoff = layer.view.z; // clusters wholly beyond it are dropped (fv_sss_cutoff_radius_m)
        uint limit = min(sss_header.counts.w, nominal);
        uint start = min(sss_header.counts.z, limit);
        // the levels are the nominal map's: a texel left at its fine samples (where the light grazes) is walked on
        // to them within the near field only; beyond it one disk of its area is as good and 16x cheaper (walking
        // every receiver's band to the fine leaves cost balanced's shade pass 2x)
        uint starts = 1u << (2u * start);
        uint stack[FV_SSS_STACK];
        for (uint r = 0u; r < starts; r++) {
            uint top = 0u;
            stack[top++] = (start << 24) | r; // level in the high byte, Morton index below (< 4^10 = 2^20)
            while (top > 0u) {
                uint e = stack[--top];
                uint k = e >> 24, i = e & 0xffffffu;
                uint at = base + ((1u << (2u * k)) - 1u) / 3u + i;
                if (at >= total) continue;
                fv_gpu_sss_node node = sss_nodes[at];
                float area = node.pos_area.w;
                if (!(area > 0.0)) continue;
                float dist = length(node.pos_area.xyz - x);
                if (cutoff > 0.0 && dist - node.extent.x > cutoff) continue;
                float radius = sqrt(area * (1.0 / FV_PI));
                // a cluster some of whose leaves the receiver's near field carries wholly onto its plane is
                // refined; one accepted where it fades out has its centroid carried by the same fraction
                float near_field = max(rc.flat_m, float(FV_SSS_GPU_FLAT_FOOTPRINTS) * node.edge_b.w);
                // the near field is refined to the leaves whatever the limit level: a cluster's one disk there
                // shows as a disk on the surface (the fast preset's 64 px map cut at level 5 did), on the side
                // facing the light and on the side facing away alike (the marble bunny's shaded face and the
                // hollows of its ears under the fast preset: blotches of one disk each)
                bool near = dist - node.extent.x < near_field;
                // a leaf, or a nominal texel resolved into one sample (its footprint): as a leaf
                bool leaf_like = k >= leaf || (k >= nominal && dot(node.extent.yzw, node.extent.yzw) > 0.0);
                bool accept = leaf_like || (!near && (k >= limit || (node.flux_sim.w > 0.0 &&
                                                                     radius <= theta * node.flux_sim.w * dist)));
                if (accept || top + 4u > uint(FV_SSS_STACK)) {
                    // a leaf or a resolved nominal texel: its footprint; a cluster: the disk of its area (the
                    // quadrature over a footprint costs 4x a disk's, and a cluster is accepted only away from the
                    // receiver)
                    vec3 cc = node.pos_area.xyz, za = vec3(0.0), zb = vec3(0.0);
                    if (!leaf_like) fv_sss_near_footprint(rc, cc, za, zb, node.normal_depth.xyz, node.edge_b.w);
                    sum += node.flux_sim.rgb *
                           (leaf_like ? fv_sss_node_kernel(d, node, rc) : fv_sss_kernel(d, length(cc - x), area));
                    count++;
                    continue;
                }
                for (uint c = 0u; c < 4u; c++) stack[top++] = ((k + 1u) << 24) | (i * 4u + 3u - c);
            }
        }
    }
    out_clusters = count;
    float ft_o = fv_sss_fresnel_t(m.sigma_a.w, dot(s.normal, s.view_dir));
    vec3 lo = sum * (ft_o / FV_PI);
    return mix(lo, vec3(0.0), isnan(lo));
}

#endif
