#version 450
// @brief The light quad-tree (Ki & Oh 2007) built bottom-up from the reflective shadow maps, and its flat cut list.
// Stages (push constant ids.x): LEAF copies the RSM texels into level 0; REDUCE makes level k+1 from level k (flux
// summed; position, depth and normal averaged with the children's incident power as weights; extent = a sphere
// holding the children's; valid when every child is valid and each child's depth is within the depth threshold of
// the mean and its normal's dot product with the mean normal above the normal threshold); SCAN_LOCAL, SCAN_BLOCKS
// and SCATTER extract the cut at the limit level — the nodes that are valid (or at the limit level) under a parent
// that is not — as a flat list, by an exclusive prefix sum (deterministic order: light, then coarse to fine, then
// row-major).
#extension GL_GOOGLE_include_directive : require
#include "gi_interface.h"

layout(local_size_x = FV_GI_BUILD_GROUP, local_size_y = 1, local_size_z = 1) in;
layout(push_constant) uniform Push { fv_gi_build_push pc; };

layout(set = 0, binding = FV_GI_BUILD_BINDING_FLUX) uniform sampler2DArray rsm_flux;
layout(set = 0, binding = FV_GI_BUILD_BINDING_POS) uniform sampler2DArray rsm_pos;
layout(set = 0, binding = FV_GI_BUILD_BINDING_NORMAL) uniform sampler2DArray rsm_normal;
layout(std430, set = 0, binding = FV_GI_BUILD_BINDING_NODES) buffer Nodes { fv_gi_node nodes[]; };
layout(std430, set = 0, binding = FV_GI_BUILD_BINDING_HEADER) buffer Header { fv_gi_header header; fv_gi_cluster cut[]; };
layout(std430, set = 0, binding = FV_GI_BUILD_BINDING_SCAN) buffer Scan { uint scan[]; }; // prefixes, then blocks

shared uint s_scan[FV_GI_BUILD_GROUP];

uint level_offset(uint n, uint k)
{
    uint off = 0u;
    for (uint j = 0u; j < k; j++) off += (n >> j) * (n >> j);
    return off;
}

uint item_index()
{
    return gl_WorkGroupID.x * FV_GI_BUILD_GROUP + gl_LocalInvocationIndex +
           gl_WorkGroupID.y * gl_NumWorkGroups.x * FV_GI_BUILD_GROUP;
}

void leaf(uint i)
{
    uint N = pc.ids.z;
    uint per = N * N;
    if (i >= per * pc.tree.z) return;
    uint l = i / per, t = i % per;
    ivec3 c = ivec3(int(t % N), int(t / N), int(l));
    vec4 f = texelFetch(rsm_flux, c, 0);
    vec4 p = texelFetch(rsm_pos, c, 0);
    vec4 n = texelFetch(rsm_normal, c, 0);
    bool geometry = dot(n.xyz, n.xyz) > 0.25;
    fv_gi_node o;
    o.flux = geometry ? max(f, vec4(0.0)) : vec4(0.0);
    o.pos = geometry ? p : vec4(0.0);
    o.normal = geometry ? vec4(normalize(n.xyz), n.w) : vec4(0.0);
    o.info = vec4(1.0, geometry ? n.w : 0.0, geometry ? 1.0 : 0.0, 0.0);
    nodes[l * pc.tree.w + t] = o;
    if (o.flux.w > 0.0) atomicAdd(header.opts.z, 1u); // lit VPLs: what `exact` sums per pixel
}

void reduce(uint i)
{
    uint N = pc.ids.z, k = pc.ids.y;
    uint s = N >> (k + 1u), sc = N >> k;
    uint per = s * s;
    if (i >= per * pc.tree.z) return;
    uint l = i / per, t = i % per;
    uint x = t % s, y = t / s;
    uint base = l * pc.tree.w;
    uint child_off = base + level_offset(N, k);
    fv_gi_node ch[4];
    ch[0] = nodes[child_off + (2u * y) * sc + 2u * x];
    ch[1] = nodes[child_off + (2u * y) * sc + 2u * x + 1u];
    ch[2] = nodes[child_off + (2u * y + 1u) * sc + 2u * x];
    ch[3] = nodes[child_off + (2u * y + 1u) * sc + 2u * x + 1u];
    float wsum = 0.0, geo = 0.0;
    for (int j = 0; j < 4; j++) {
        wsum += ch[j].flux.w;
        geo += ch[j].info.z;
    }
    fv_gi_node o;
    o.flux = vec4(0.0);
    o.pos = vec4(0.0);
    o.normal = vec4(0.0);
    o.info = vec4(1.0, 0.0, 0.0, 0.0);
    if (geo > 0.0) {
        // Weights (gi.average): flux = the children's incident power (unlit children, all zero, count equally
        // among those with geometry); plain = every child with geometry alike.
        bool plain = pc.params.z > 0.5;
        vec3 nsum = vec3(0.0);
        for (int j = 0; j < 4; j++) {
            float w = wsum > 0.0 && !plain ? ch[j].flux.w / wsum : ch[j].info.z / geo;
            o.flux += ch[j].flux;
            o.pos += w * ch[j].pos;
            nsum += w * ch[j].normal.xyz;
        }
        float extent = 0.0, rmin = 3.0e38, slab = 0.0;
        bool valid = true;
        float nlen = length(nsum);
        vec3 nmean = nlen > 1e-6 ? nsum / nlen : vec3(0.0);
        for (int j = 0; j < 4; j++) {
            if (ch[j].info.z < 0.5) continue;
            vec3 dp = ch[j].pos.xyz - o.pos.xyz;
            extent = max(extent, length(dp) + ch[j].normal.w);
            rmin = min(rmin, ch[j].info.y);
            float cl = length(ch[j].normal.xyz);
            vec3 cn = cl > 1e-6 ? ch[j].normal.xyz / cl : vec3(0.0);
            float cs = dot(cn, nmean);
            valid = valid && ch[j].info.x > 0.5 && abs(ch[j].pos.w - o.pos.w) < pc.params.x &&
                    nlen > 1e-6 && cs > pc.params.y;
            // slab: every VPL of child j lies within r_j sin + h_j |cos| of its centre along nmean (r_j its
            // extent, h_j its own slab along its normal, the angle between the two normals); r_j without a normal
            float sn = sqrt(max(1.0 - cs * cs, 0.0));
            float across = cl > 1e-6 && nlen > 1e-6 ? min(ch[j].normal.w * sn + ch[j].info.w * abs(cs), ch[j].normal.w)
                                                    : ch[j].normal.w;
            slab = max(slab, abs(dot(nmean, dp)) + across);
        }
        o.normal = vec4(nsum, extent);
        o.info = vec4(valid ? 1.0 : 0.0, rmin, 1.0, nlen > 1e-6 ? min(slab, extent) : extent);
    }
    nodes[base + level_offset(N, k + 1u) + t] = o;
}

// Subtree size of a level-k node, (4^(k+1) - 1) / 3, and the pre-order position of the level-k node (x, y) in its
// light's tree (render/gi/gi_math.c fv_gi_subtree, fv_gi_walk_pos).
uint subtree(uint k)
{
    return ((1u << (2u * k + 2u)) - 1u) / 3u;
}

uint walk_pos(uint k, uint x, uint y)
{
    uint pos = 0u;
    for (uint j = pc.ids.w - 1u; j > k; j--) {
        uint sh = j - 1u - k;
        pos += 1u + (((x >> sh) & 1u) + 2u * ((y >> sh) & 1u)) * subtree(j - 1u);
    }
    return pos;
}

// Node `node` (an index into nodes[]): its light, level and (x, y).
void node_place(uint node, out uint l, out uint k, out uint x, out uint y)
{
    uint N = pc.ids.z;
    l = node / pc.tree.w;
    uint t = node - l * pc.tree.w;
    k = 0u;
    while (k + 1u < pc.ids.w && t >= level_offset(N, k + 1u)) k++;
    t -= level_offset(N, k);
    x = t % (N >> k);
    y = t / (N >> k);
}

// The index in cut[] of node `node`'s walk record.
uint walk_index(uint node)
{
    uint l, k, x, y;
    node_place(node, l, k, x, y);
    return pc.tree.w * pc.tree.z + l * pc.tree.w + walk_pos(k, x, y);
}

void walk(uint i)
{
    if (i >= pc.tree.w * pc.tree.z) return;
    uint l, k, x, y;
    node_place(i, l, k, x, y);
    fv_gi_node c = nodes[i];
    bool lit = c.flux.w > 0.0;
    fv_gi_cluster o;
    o.flux = lit ? vec4(max(c.flux.rgb, vec3(0.0)), c.normal.w) : vec4(0.0);
    o.pos = vec4(c.pos.xyz, c.info.w);
    o.normal = vec4(c.normal.xyz, float(subtree(k)));
    cut[pc.tree.w * pc.tree.z + l * pc.tree.w + walk_pos(k, x, y)] = o;
}

// Candidate i of the cut (all lights): its light, level and index in the level; coarse levels first.
bool candidate(uint i, out uint l, out uint k, out uint idx)
{
    uint C = pc.scan.x;
    l = i / C;
    uint j = i % C;
    uint N = pc.ids.z;
    for (k = pc.tree.x; k >= pc.tree.y; k--) {
        uint side = N >> k;
        if (j < side * side) {
            idx = j;
            return true;
        }
        j -= side * side;
        if (k == 0u) break;
    }
    idx = 0u;
    return false;
}

bool in_cut(uint i, out uint node)
{
    uint l, k, idx;
    node = 0u;
    if (i >= pc.scan.y || !candidate(i, l, k, idx)) return false;
    uint N = pc.ids.z;
    uint base = l * pc.tree.w;
    node = base + level_offset(N, k) + idx;
    fv_gi_node c = nodes[node];
    if (!(c.flux.w > 0.0)) return false;
    if (k != pc.tree.y && c.info.x < 0.5) return false;
    if (k == pc.tree.x) return true;
    uint s = N >> k, ps = s >> 1u;
    uint parent = base + level_offset(N, k + 1u) + ((idx / s) >> 1u) * ps + ((idx % s) >> 1u);
    return nodes[parent].info.x < 0.5;
}

void main()
{
    uint stage = pc.ids.x;
    uint i = item_index();
    if (stage == FV_GI_STAGE_LEAF) {
        leaf(i);
    } else if (stage == FV_GI_STAGE_REDUCE) {
        reduce(i);
    } else if (stage == FV_GI_STAGE_SCAN_LOCAL) {
        uint node;
        uint flag = in_cut(i, node) ? 1u : 0u;
        uint lid = gl_LocalInvocationIndex;
        s_scan[lid] = flag;
        barrier();
        // Hillis-Steele inclusive scan over the block.
        for (uint off = 1u; off < FV_GI_BUILD_GROUP; off <<= 1u) {
            uint v = lid >= off ? s_scan[lid - off] : 0u;
            barrier();
            s_scan[lid] += v;
            barrier();
        }
        if (i < pc.scan.y) scan[i] = s_scan[lid] - flag;
        uint block = i / FV_GI_BUILD_GROUP;
        if (lid == FV_GI_BUILD_GROUP - 1u && block < pc.scan.z) scan[pc.scan.y + block] = s_scan[lid];
    } else if (stage == FV_GI_STAGE_SCAN_BLOCKS) {
        // One group: exclusive scan of the block totals in chunks, carrying the sum.
        uint lid = gl_LocalInvocationIndex;
        uint carry = 0u;
        for (uint c0 = 0u; c0 < pc.scan.z; c0 += FV_GI_BUILD_GROUP) {
            uint b = c0 + lid;
            uint v = b < pc.scan.z ? scan[pc.scan.y + b] : 0u;
            s_scan[lid] = v;
            barrier();
            for (uint off = 1u; off < FV_GI_BUILD_GROUP; off <<= 1u) {
                uint u = lid >= off ? s_scan[lid - off] : 0u;
                barrier();
                s_scan[lid] += u;
                barrier();
            }
            if (b < pc.scan.z) scan[pc.scan.y + b] = carry + s_scan[lid] - v;
            carry += s_scan[FV_GI_BUILD_GROUP - 1u];
            barrier();
        }
        memoryBarrierBuffer();
        barrier();
        if (lid == 0u) {
            uint C = pc.scan.x;
            uint lights = min(pc.tree.z, uint(FV_GI_MAX_LIGHTS));
            for (uint l = 0u; l < lights; l++) {
                uint a = l * C, e = (l + 1u) * C;
                uint first = a < pc.scan.y ? scan[pc.scan.y + a / FV_GI_BUILD_GROUP] + scan[a] : carry;
                uint last = e < pc.scan.y ? scan[pc.scan.y + e / FV_GI_BUILD_GROUP] + scan[e] : carry;
                header.light[l].info.z = first;
                header.light[l].info.w = last - first;
            }
            header.counts.w = carry;
        }
    } else if (stage == FV_GI_STAGE_WALK) {
        walk(i);
    } else if (stage == FV_GI_STAGE_SCATTER) {
        uint node;
        if (in_cut(i, node)) {
            fv_gi_node c = nodes[node];
            fv_gi_cluster o;
            o.flux = vec4(max(c.flux.rgb, vec3(0.0)) * (1.0 / 3.14159265358979), c.normal.w * c.normal.w);
            o.pos = vec4(c.pos.xyz, c.info.w);
            o.normal = vec4(c.normal.xyz, float(walk_index(node)));
            cut[scan[pc.scan.y + i / FV_GI_BUILD_GROUP] + scan[i]] = o;
        }
    }
}
