#version 450
// @brief The quad-tree of light-view samples (Ki & Oh, section 4): level L (the leaves) from the maps' texels in
// Morton order, then each coarser level from its four children: areas and fluxes summed, centroid, normal and
// depth area-weighted, and a similarity in [0, 1] (leaves 1): the smallest of the children's, times how alike the
// children's normals are (the smallest cosine to the mean normal) and how flat they lie (1 - the largest depth
// offset from the mean over the cluster's size sqrt(area)); and its extent, the radius around the centroid that
// holds every child's extent (a leaf's: its footprint's half-diagonal), and the widest footprint half-diagonal among
// its leaves (the gather keeps the leaves whose near field may reach the receiver); a leaf also its texel's
// footprint (clusters have none: the gather takes the disk of their area). The leaves are the fine map's texels, s
// sub-levels below the nominal ones of sss.map_size (fv_sss_sub_levels); a node of level L - s (a nominal texel)
// whose fine samples allow it is resolved into one sample with a footprint (fv_sss_texel_resolve), which the gather
// takes as a leaf. One dispatch per level; empty children are left out.
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_common.glsl"
#include "fv_sss_interface.h"

layout(local_size_x = FV_SSS_BUILD_GROUP, local_size_y = 1, local_size_z = 1) in;
layout(set = FV_SSS_BUILD_SET, binding = FV_SSS_BUILD_BINDING_POS) uniform sampler2DArray map_pos;
layout(set = FV_SSS_BUILD_SET, binding = FV_SSS_BUILD_BINDING_FLUX) uniform sampler2DArray map_flux;
layout(set = FV_SSS_BUILD_SET, binding = FV_SSS_BUILD_BINDING_NORMAL) uniform sampler2DArray map_normal;
layout(set = FV_SSS_BUILD_SET, binding = FV_SSS_BUILD_BINDING_EDGE_A) uniform sampler2DArray map_edge_a;
layout(set = FV_SSS_BUILD_SET, binding = FV_SSS_BUILD_BINDING_EDGE_B) uniform sampler2DArray map_edge_b;
layout(std430, set = FV_SSS_BUILD_SET, binding = FV_SSS_BUILD_BINDING_NODES) buffer Nodes { fv_gpu_sss_node nodes[]; };
layout(push_constant) uniform Push { fv_sss_build_push pc; };

// The even bits of a Morton index.
uint compact_bits(uint v)
{
    v &= 0x55555555u;
    v = (v | (v >> 1)) & 0x33333333u;
    v = (v | (v >> 2)) & 0x0f0f0f0fu;
    v = (v | (v >> 4)) & 0x00ff00ffu;
    v = (v | (v >> 8)) & 0x0000ffffu;
    return v;
}

void main()
{
    uint level = pc.level.x, leaf = pc.level.y, maps = pc.level.z;
    uint per_map = 1u << (2u * level);
    uint g = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * FV_SSS_BUILD_GROUP;
    if (g >= per_map * maps) return;
    uint map = g / per_map, i = g % per_map;
    uint total = ((1u << (2u * (leaf + 1u))) - 1u) / 3u; // nodes per map
    uint at = map * total + ((1u << (2u * level)) - 1u) / 3u + i;
    if (at >= uint(nodes.length())) return;
    fv_gpu_sss_node o;
    if (level == leaf) {
        ivec3 t = ivec3(int(compact_bits(i)), int(compact_bits(i >> 1)), int(map));
        vec4 p = texelFetch(map_pos, t, 0), f = texelFetch(map_flux, t, 0), n = texelFetch(map_normal, t, 0);
        vec3 ea = texelFetch(map_edge_a, t, 0).xyz, eb = texelFetch(map_edge_b, t, 0).xyz;
        bool ok = p.w > 0.0 && !any(isnan(p)) && !any(isnan(f)) && !any(isnan(ea)) && !any(isnan(eb));
        o.pos_area = ok ? p : vec4(0.0);
        o.flux_sim = ok ? vec4(f.rgb, 1.0) : vec4(0.0);
        o.normal_depth = ok ? vec4(n.xyz, f.w) : vec4(0.0);
        float half_diagonal = 0.5 * sqrt(max(dot(ea + eb, ea + eb), dot(ea - eb, ea - eb)));
        o.extent = ok ? vec4(half_diagonal, ea) : vec4(0.0);
        o.edge_b = ok ? vec4(eb, half_diagonal) : vec4(0.0);
        nodes[at] = o;
        return;
    }
    uint child = map * total + ((1u << (2u * (level + 1u))) - 1u) / 3u + i * 4u;
    float area = 0.0, sim = 1.0;
    vec3 pos = vec3(0.0), flux = vec3(0.0), nrm = vec3(0.0);
    float depth = 0.0;
    for (uint c = 0u; c < 4u; c++) {
        fv_gpu_sss_node k = nodes[child + c];
        float a = k.pos_area.w;
        if (!(a > 0.0)) continue;
        area += a;
        pos += a * k.pos_area.xyz;
        flux += k.flux_sim.rgb;
        nrm += a * k.normal_depth.xyz;
        depth += a * k.normal_depth.w;
        sim = min(sim, k.flux_sim.w);
    }
    if (!(area > 0.0)) {
        nodes[at] = fv_gpu_sss_node(vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0));
        return;
    }
    pos /= area;
    nrm /= area;
    depth /= area;
    vec3 mean_n = length(nrm) > 1e-20 ? normalize(nrm) : vec3(0.0);
    float size = sqrt(area);
    float alike = 1.0, flat_ = 1.0, reach = 0.0, widest = 0.0;
    for (uint c = 0u; c < 4u; c++) {
        fv_gpu_sss_node k = nodes[child + c];
        if (!(k.pos_area.w > 0.0)) continue;
        vec3 kn = k.normal_depth.xyz;
        float kl = length(kn);
        alike = min(alike, kl > 1e-20 ? max(dot(kn / kl, mean_n), 0.0) : 0.0);
        flat_ = min(flat_, clamp(1.0 - abs(k.normal_depth.w - depth) / max(size, 1e-30), 0.0, 1.0));
        reach = max(reach, length(k.pos_area.xyz - pos) + k.extent.x);
        widest = max(widest, k.edge_b.w);
    }
    o.pos_area = vec4(pos, area);
    o.flux_sim = vec4(flux, sim * alike * flat_);
    o.normal_depth = vec4(nrm, depth);
    o.extent = vec4(reach, 0.0, 0.0, 0.0);
    o.edge_b = vec4(0.0, 0.0, 0.0, widest);
    // A nominal texel (level L - s): resolved into one sample when its 4^s fine samples are all present and lit at
    // a cosine of at least FV_SSS_GPU_RESOLVE_COS (fv_sss_texel_resolve): the footprint the sum of theirs over 2^s,
    // the rest as summed above (the area-weighted centroid and normal).
    uint sub = pc.level.w;
    if (sub > 0u && level + sub == leaf) {
        uint n = 1u << (2u * sub);
        bool resolved = true;
        vec3 ea = vec3(0.0), eb = vec3(0.0);
        for (uint q = 0u; q < n && resolved; q++) {
            uint m = i * n + q;
            ivec3 t = ivec3(int(compact_bits(m)), int(compact_bits(m >> 1)), int(map));
            resolved = texelFetch(map_pos, t, 0).w > 0.0 && texelFetch(map_normal, t, 0).w >= float(FV_SSS_GPU_RESOLVE_COS);
            ea += texelFetch(map_edge_a, t, 0).xyz;
            eb += texelFetch(map_edge_b, t, 0).xyz;
        }
        ea /= float(1u << sub);
        eb /= float(1u << sub);
        if (resolved && !any(isnan(ea)) && !any(isnan(eb)) && !any(isinf(ea)) && !any(isinf(eb))) {
            float half_diagonal = 0.5 * sqrt(max(dot(ea + eb, ea + eb), dot(ea - eb, ea - eb)));
            o.flux_sim.w = 1.0;
            o.extent = vec4(half_diagonal, ea);
            o.edge_b = vec4(eb, half_diagonal);
        }
    }
    nodes[at] = o;
}
