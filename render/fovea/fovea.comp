#version 450
// @brief The sampling map (papers/README.md section 3; linear MAR): per pixel the eccentricity e from the predicted
// gaze ray, e' = max(0, e - u), w = m e' + w0, p = clamp(1 - (w - w_min) / w_far, xi, 1) (w_min, w_far: see
// fovea_interface.h), with fovea.dof w widened to the eye's defocus blur and with fovea.saliency p raised to the
// weighted saliency of the G-buffer (fovea_interface.h); per B x B block a sample mask from the ranks of a low-discrepancy (R2) pattern, turned by a
// cyclic shift each frame: a pixel is sampled when its rank r has r == 0 or r + 0.5 < p n (n pixels in the block),
// so every block holds at least one sample. One thread per pixel, no barriers; without saliency only the G-buffer's
// depth and material are read. p itself is stored only in the variant that a view or the overlay reads.
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fv_common.glsl"
#include "fovea_interface.h"

layout(local_size_x = FV_FOVEA_GROUP, local_size_y = FV_FOVEA_GROUP, local_size_z = 1) in;
// FV_FOVEA_SPEC_GBUFFER: whether the G-buffer is read at all (saliency, or DoF with a pupil). Off, no texel fetch is
// compiled in (on llvmpipe their presence alone costs ~10x the rest of the pass); the host picks the variant.
layout(constant_id = 0) const uint USE_GBUFFER = 1u;
// FV_FOVEA_SPEC_PROB: whether p is stored ("fovea prob": only a view and the overlay read it). A store per pixel is
// ~0.6x a present pass on llvmpipe (a store is paid per invocation, whatever the rest), so it is compiled in only
// where a reader runs.
layout(constant_id = 1) const uint WRITE_PROB = 1u;

FV_SCENE_SET_DECLARE
layout(set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_PROB, r32f) uniform writeonly image2DArray prob_img;
layout(set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_MASK, r32ui) uniform writeonly uimage2DArray mask_img;
layout(std430, set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_RANKS) readonly buffer Ranks { uint ranks[]; };
layout(set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_BLOCKS, r32ui) uniform coherent uimage2DArray blocks_img;
#define FV_GBUFFER_SET FV_FOVEA_SET
#define FV_GBUFFER_BINDING_DEPTH FV_FOVEA_BINDING_DEPTH
#define FV_GBUFFER_BINDING_NORMAL (FV_FOVEA_BINDING_DEPTH + 1)
#define FV_GBUFFER_BINDING_ALBEDO (FV_FOVEA_BINDING_DEPTH + 2)
#define FV_GBUFFER_BINDING_MATERIAL (FV_FOVEA_BINDING_DEPTH + 3)
#include "fv_gbuffer_decode.glsl"
layout(set = FV_FOVEA_SET, binding = FV_FOVEA_BINDING_MOTION, rgba32f) uniform readonly image2DArray g_motion;
layout(push_constant) uniform Push { fv_fovea_push pc; };

const float RAD_TO_DEG = 57.295779513082323;

// The albedo's stored 8-bit sRGB value decoded exactly (the host's table in double): a device's own decode may be
// an approximation (llvmpipe's is), and Delta E of nearby colours amplifies it. Re-encoding finds the stored byte.
vec3 exact_albedo(vec3 lin)
{
    uvec3 b = uvec3(clamp(round(fv_srgb_encode(clamp(lin, 0.0, 1.0)) * 255.0), 0.0, 255.0));
    return vec3(uintBitsToFloat(ranks[FV_FOVEA_SRGB_TABLE + b.x]), uintBitsToFloat(ranks[FV_FOVEA_SRGB_TABLE + b.y]),
                uintBitsToFloat(ranks[FV_FOVEA_SRGB_TABLE + b.z]));
}

// The G-buffer at pixel c of layer z (inside the image): drawn, world position, normal, albedo, motion.
struct gsurf {
    bool hit;
    vec3 pos, n, albedo;
    vec2 motion;
};
gsurf g_at(ivec3 c)
{
    gsurf g;
    g.hit = texelFetch(g_material, c, 0).r != 0u;
    g.pos = fv_gbuffer_position(uvec3(c), texelFetch(g_depth, c, 0).r);
    g.n = fv_oct_decode(texelFetch(g_normal, c, 0).rg);
    g.albedo = exact_albedo(texelFetch(g_albedo, c, 0).rgb);
    g.motion = imageLoad(g_motion, c).rg;
    return g;
}

// The CIELAB f(t); the cube root refined by a Newton step (pow alone is exp2(log2(t) / 3), about 1e-4 off on some
// devices, which Delta E's differences of large values amplify).
float lab_f(float t)
{
    if (!(t > 0.008856451679)) return t / 0.12841854934 + 0.137931034483;
    float y = pow(t, 1.0 / 3.0);
    return y - (y * y * y - t) / (3.0 * y * y);
}

// CIELAB (D65 white) of a linear sRGB colour.
vec3 lab(vec3 c)
{
    vec3 xyz = vec3(dot(vec3(0.4124564, 0.3575761, 0.1804375), c), dot(vec3(0.2126729, 0.7151522, 0.0721750), c),
                    dot(vec3(0.0193339, 0.1191920, 0.9503041), c));
    vec3 f = vec3(lab_f(xyz.x / 0.95047), lab_f(xyz.y), lab_f(xyz.z / 1.08883));
    return vec3(116.0 * f.y - 16.0, 500.0 * (f.x - f.y), 200.0 * (f.y - f.z));
}

// The saliency S of pixel p (see fovea_interface.h), in [0, 1].
float saliency(ivec3 p, ivec2 size, gsurf g)
{
    vec3 lp = lab(g.albedo);
    float sa = 0.0, sn = 0.0;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            ivec2 q = p.xy + ivec2(dx, dy);
            if ((dx == 0 && dy == 0) || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
            ivec3 c = ivec3(q, p.z);
            bool qhit = texelFetch(g_material, c, 0).r != 0u;
            if (qhit != g.hit) {
                sn = 1.0;
                continue;
            }
            if (!g.hit) continue;
            sa = max(sa, distance(lp, lab(exact_albedo(texelFetch(g_albedo, c, 0).rgb))));
            sn = max(sn, 1.0 - dot(g.n, fv_oct_decode(texelFetch(g_normal, c, 0).rg)));
        }
    float sv = 0.0;
    if (g.hit) {
        // the object's own motion: the G-buffer's less the head's alone (the point held still, projected by this
        // and the previous frame's matrices: the error of the position from depth cancels)
        vec4 c = frame.view_proj[p.z] * vec4(g.pos, 1.0), c0 = frame.prev_view_proj[p.z] * vec4(g.pos, 1.0);
        vec2 cam = c.w > 1e-30 && c0.w > 1e-30 ? (c.xy / c.w - c0.xy / c0.w) * 0.5 : g.motion;
        sv = length((g.motion - cam) * vec2(size)) / float(FV_FOVEA_SAL_MOTION_PX);
    }
    float s = max(max(sa / float(FV_FOVEA_SAL_DELTA_E), sn / float(FV_FOVEA_SAL_NORMAL)), sv);
    return isnan(s) ? 1.0 : clamp(s, 0.0, 1.0);
}

// The distance from the eye to the surface at the gaze, or 0 when there is none (no valid gaze, off the image,
// nothing drawn there).
float focus_distance(uint z, ivec2 size, bool valid, vec3 d)
{
    if (!valid || !(d.z < 0.0)) return 0.0;
    vec4 t = frame.eye_tan[z];
    vec2 uv = vec2((d.x / -d.z - t.x) / (t.y - t.x), (d.y / -d.z - t.z) / (t.w - t.z));
    if (any(isnan(uv)) || any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return 0.0;
    ivec3 c = ivec3(min(ivec2(uv * vec2(size)), size - 1), int(z));
    if (texelFetch(g_material, c, 0).r == 0u) return 0.0;
    vec3 pos = fv_gbuffer_position(uvec3(c), texelFetch(g_depth, c, 0).r);
    float df = length(pos - frame.eye_pos[z].xyz);
    return isnan(df) || isinf(df) ? 0.0 : max(df, float(FV_FOVEA_DOF_MIN_M));
}

float sampling_prob(uvec3 p)
{
    vec4 t = frame.eye_tan[p.z];
    vec2 size = vec2(frame.counts.y, frame.counts.z);
    vec2 uv = (vec2(p.xy) + 0.5) / size;
    vec3 r = normalize(vec3(mix(t.x, t.y, uv.x), mix(t.z, t.w, uv.y), -1.0));
    vec4 g = frame.gaze_dir[p.z];
    float glen = length(g.xyz);
    bool valid = g.w > 0.5 && glen > 0.0 && !isnan(glen) && !isinf(glen);
    vec3 d = valid ? g.xyz / glen : vec3(0.0, 0.0, -1.0);
    float u = !valid ? float(FV_FOVEA_LOST_WIDEN_RAD)
                     : ((pc.flags & FV_FOVEA_FLAG_UNCERTAINTY) != 0u ? frame.gaze_info[p.z].x : 0.0);
    if (isnan(u)) u = 3.14159265;
    float e = atan(length(cross(r, d)), dot(r, d)); // exact near 0, unlike acos(dot)
    float ep = max(0.0, e - u);
    float w_px = frame.pixel_angle[p.z] * RAD_TO_DEG;
    float w_min = max(pc.mar_w0_deg, w_px);
    float w_far = (float(FV_FOVEA_FAR_PX) - 1.0) * w_px;
    float w = pc.mar_slope * ep * RAD_TO_DEG + pc.mar_w0_deg;
    if (USE_GBUFFER == 0u || (pc.flags & (FV_FOVEA_FLAG_SALIENCY | FV_FOVEA_FLAG_DOF)) == 0u)
        return clamp(1.0 - (w - w_min) / w_far, pc.min_prob, 1.0);
    ivec2 isize = ivec2(size);
    bool sal = (pc.flags & FV_FOVEA_FLAG_SALIENCY) != 0u;
    gsurf gs;
    if (sal) {
        gs = g_at(ivec3(p));
    } else { // DoF alone: drawn and position only
        gs.hit = texelFetch(g_material, ivec3(p), 0).r != 0u;
        gs.pos = fv_gbuffer_position(p, texelFetch(g_depth, ivec3(p), 0).r);
    }
    float blur = 0.0; // degrees
    float pupil = frame.gaze_info[p.z].y;
    if ((pc.flags & FV_FOVEA_FLAG_DOF) != 0u && pupil > 0.0) {
        float df = focus_distance(p.z, isize, valid, d);
        if (df > 0.0) {
            float dist = gs.hit ? max(length(gs.pos - frame.eye_pos[p.z].xyz), float(FV_FOVEA_DOF_MIN_M)) : 0.0;
            float inv = gs.hit && !isnan(dist) && !isinf(dist) ? 1.0 / dist : 0.0;
            blur = min(pupil * 1e-3 * abs(inv - 1.0 / df) * RAD_TO_DEG, 180.0);
        }
    }
    float pm = 1.0 - (max(w, blur) - w_min) / w_far;
    if (sal) {
        float seen = clamp(1.0 - (blur - w_min) / w_far, 0.0, 1.0);
        pm = max(pm, pc.saliency * saliency(ivec3(p), isize, gs) * seen);
    }
    return clamp(pm, pc.min_prob, 1.0);
}

// The R2 value of a pixel of its block.
float pattern(uvec2 l) { return fract(0.5 + float(l.x) * 0.75487766625 + float(l.y) * 0.56984029101); }

// The frame's cyclic shift of the ranks of an n-pixel block (golden-ratio sequence over the frames).
uint frame_shift(uint n) { return uint(fract(float(frame.counts.w & 1023u) * 0.61803398875) * float(n)) % n; }

bool sampled(uvec3 p, float prob)
{
    uint B = pc.block;
    uvec2 size = uvec2(frame.counts.y, frame.counts.z);
    uvec2 b0 = (p.xy / B) * B;
    uvec2 bs = min(uvec2(B), size - b0);
    uint n = bs.x * bs.y;
    uvec2 l = p.xy - b0;
    uint rank;
    if (n == B * B) {
        rank = ranks[l.y * B + l.x]; // a whole block: the table the host made for B
    } else {
        // a block cut by the image edge: rank among its own pixels (R2 value, ties by index)
        uint me = l.y * bs.x + l.x;
        float mine = pattern(l);
        rank = 0u;
        for (uint k = 0u; k < n; k++) {
            float o = pattern(uvec2(k % bs.x, k / bs.x));
            rank += (o < mine || (o == mine && k < me)) ? 1u : 0u;
        }
    }
    rank = (rank + frame_shift(n)) % n;
    return rank == 0u || float(rank) + 0.5 < prob * float(n);
}

void main()
{
    uvec3 p = gl_GlobalInvocationID;
    if (p.x >= frame.counts.y || p.y >= frame.counts.z || p.z > 1u) return;
    float prob = sampling_prob(p);
    bool s = sampled(p, prob);
    if (WRITE_PROB != 0u) imageStore(prob_img, ivec3(p), vec4(prob));
    imageStore(mask_img, ivec3(p), uvec4(s ? FV_SAMPLE_MASK_SHADED : FV_SAMPLE_MASK_UNKNOWN));
    if (s) {
        uint B = pc.block, k = (p.y % B) * B + p.x % B;
        imageAtomicOr(blocks_img, ivec3(int((p.x / B) * pc.block_words + k / 32u), int(p.y / B), int(p.z)),
                      1u << (k % 32u));
    }
}
