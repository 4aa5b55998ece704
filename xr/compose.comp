#version 450
#extension GL_GOOGLE_include_directive : require
// @brief fovea's OpenXR compositor: every layer of both eyes into the display image (sRGB-encoded RGBA8), in layer
// order, through each layer's homography (compose_interface.h); or, through the lens (LENS), an eye's layers
// straight into the pre-distorted display image: per display pixel and colour channel the ray the HMD's lens
// shows there (the evaluation of render/distort/distort.comp, fv_lens_panel_to_tan), the layer sampled along it.
#include "compose_interface.h"
#include "fv_common.glsl"

layout(local_size_x = FV_XR_COMPOSE_GROUP, local_size_y = FV_XR_COMPOSE_GROUP) in;
layout(set = 0, binding = FV_XR_COMPOSE_BINDING_SOURCES) uniform sampler2DArray sources[FV_XR_COMPOSE_MAX_SOURCES];
layout(set = 0, binding = FV_XR_COMPOSE_BINDING_DISPLAY, rgba8) uniform writeonly image2DArray display;
layout(set = 0, binding = FV_XR_COMPOSE_BINDING_LAYERS, std140) uniform Block { fv_xr_compose_block b; };
// A dispatch per eye, with that eye's own sources bound (a layer's info.x is its slot among them).
layout(push_constant) uniform Push { uint eye; } pc;

// The eye's source count, specialised (a pipeline per count, made on first use): sampler arrays are indexed by
// constants only (lavapipe has no shaderSampledImageArrayDynamicIndexing), and a source the frame does not bind is
// no branch at all. Every branch is run by every invocation on lavapipe (masked), so a switch over all 16 sources
// cost 16 samples per layer and pixel (10x the pass's time for the usual 1 or 2 sources).
layout(constant_id = FV_XR_COMPOSE_SPEC_NSRC) const uint NSRC = FV_XR_COMPOSE_MAX_SOURCES;
// Through the lens (up to FV_XR_COMPOSE_LENS_MAX_LAYERS per eye, the lens pre-distortion in this pass): one pass over
// the display instead of composing an image that the lens pass copies and resamples.
layout(constant_id = FV_XR_COMPOSE_SPEC_LENS) const bool LENS = false;

vec4 fetch(uint i, vec3 uvl)
{
    if (NSRC <= 1u || i == 0u) return textureLod(sources[0], uvl, 0.0);
    if (NSRC <= 2u || i == 1u) return textureLod(sources[1], uvl, 0.0);
    if (NSRC <= 3u || i == 2u) return textureLod(sources[2], uvl, 0.0);
    if (NSRC <= 4u || i == 3u) return textureLod(sources[3], uvl, 0.0);
    if (NSRC <= 5u || i == 4u) return textureLod(sources[4], uvl, 0.0);
    if (NSRC <= 6u || i == 5u) return textureLod(sources[5], uvl, 0.0);
    if (NSRC <= 7u || i == 6u) return textureLod(sources[6], uvl, 0.0);
    if (NSRC <= 8u || i == 7u) return textureLod(sources[7], uvl, 0.0);
    if (NSRC <= 9u || i == 8u) return textureLod(sources[8], uvl, 0.0);
    if (NSRC <= 10u || i == 9u) return textureLod(sources[9], uvl, 0.0);
    if (NSRC <= 11u || i == 10u) return textureLod(sources[10], uvl, 0.0);
    if (NSRC <= 12u || i == 11u) return textureLod(sources[11], uvl, 0.0);
    if (NSRC <= 13u || i == 12u) return textureLod(sources[12], uvl, 0.0);
    if (NSRC <= 14u || i == 13u) return textureLod(sources[13], uvl, 0.0);
    if (NSRC <= 15u || i == 14u) return textureLod(sources[14], uvl, 0.0);
    return textureLod(sources[15], uvl, 0.0);
}

// Layer l's colour along a display ray (tangent coordinates) from its source, premultiplied; false when the ray
// misses it.
bool sample_layer(fv_xr_compose_layer l, uint source, vec3 ray, out vec4 c, out vec2 uv)
{
    vec3 p = vec3(dot(l.h[0].xyz, ray), dot(l.h[1].xyz, ray), dot(l.h[2].xyz, ray));
    c = vec4(0.0);
    uv = vec2(0.0);
    if (!(p.z > 1e-6)) return false;
    uv = p.xy / p.z;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return false;
    c = fetch(source, vec3(l.uv_rect.xy + uv * l.uv_rect.zw, float(l.info.y)));
    const uint unpremultiplied = FV_XR_LAYER_ALPHA | FV_XR_LAYER_UNPREMULTIPLIED; // alpha only counts when blended
    if ((l.info.z & unpremultiplied) == unpremultiplied) c.rgb *= c.a;
    return true;
}

// Layer l's colour c (premultiplied, sample_layer) at uv over what is under it.
vec3 blend(fv_xr_compose_layer l, vec4 c, vec2 uv, vec3 under)
{
    vec3 color = (l.info.z & FV_XR_LAYER_ALPHA) != 0u ? c.rgb + under * (1.0 - clamp(c.a, 0.0, 1.0)) : c.rgb;
    if ((l.info.z & FV_XR_LAYER_INSET) != 0u) {
        // an inset blends into what is under it (the wide view) over the band at its edge: a smoothstep per axis
        vec2 band = max(vec2(l.h[0].w, l.h[1].w), vec2(1e-6));
        vec2 s = smoothstep(vec2(0.0), band, min(uv, vec2(1.0) - uv));
        color = mix(under, color, s.x * s.y);
    }
    return color;
}

// Every layer of an eye along a display ray, in layer order.
vec3 compose(uint eye, vec3 ray)
{
    vec3 color = vec3(0.0);
    uint n = eye == 0u ? b.counts.x : b.counts.y;
    for (uint i = 0u; i < n && i < uint(FV_XR_COMPOSE_MAX_LAYERS); i++) {
        fv_xr_compose_layer l = b.layer[eye * uint(FV_XR_COMPOSE_MAX_LAYERS) + i];
        vec4 c;
        vec2 uv;
        if (sample_layer(l, l.info.x, ray, c, uv)) color = blend(l, c, uv, color);
    }
    return color;
}

// An eye's layers through the lens: each channel along its own ray (chromatic aberration), black where the ray
// leaves the display frustum (the extent of the image the lens pass would have sampled) or past the visible radius.
vec3 through_lens(uint eye, uvec2 px)
{
    vec3 color = vec3(0.0);
    uint n = eye == 0u ? b.counts.x : b.counts.y;
    vec2 q = (vec2(px) + 0.5) / vec2(b.counts.zw) * b.lens_geometry.xy -
             (eye == 0u ? b.lens_centre.xy : b.lens_centre.zw); // metres from the lens centre, y down
    float r = length(q) / b.lens_geometry.z;
    if (n == 0u || (b.lens_aberration.w > 0.0 && r > b.lens_aberration.w)) return color;
    vec4 k = b.lens_k, t = b.tan[eye];
    float d = (k.x + r * (k.y + r * (k.z + r * k.w))) * b.lens_geometry.w;
    vec3 ray[3];
    bool inside[3];
    for (int ch = 0; ch < 3; ch++) {
        vec2 tt = q * (d * b.lens_aberration[ch]); // tangent x right, y down
        ray[ch] = vec3(tt.x, -tt.y, 1.0);
        inside[ch] = ray[ch].x >= t.x && ray[ch].x <= t.y && ray[ch].y <= t.z && ray[ch].y >= t.w;
    }
    // NSRC is the eye's layer count here and source i is layer i's image: the loop's count is a constant, each
    // layer's fetch one sample (lavapipe runs every branch of fetch's chain when the index is not a constant)
    for (uint i = 0u; i < NSRC; i++) {
        if (i >= n) break;
        fv_xr_compose_layer l = b.layer[eye * uint(FV_XR_COMPOSE_MAX_LAYERS) + i];
        for (int ch = 0; ch < 3; ch++) {
            vec4 c;
            vec2 uv;
            if (inside[ch] && sample_layer(l, i, ray[ch], c, uv)) color[ch] = blend(l, c, uv, vec3(color[ch]))[ch];
        }
    }
    return color;
}

void main()
{
    uint eye = pc.eye;
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= b.counts.z || px.y >= b.counts.w || eye > 1u) return;
    vec3 color;
    if (LENS) {
        color = through_lens(eye, px);
    } else {
        vec4 t = b.tan[eye];
        vec2 f = (vec2(px) + 0.5) / vec2(b.counts.zw);
        color = compose(eye, vec3(mix(t.x, t.y, f.x), mix(t.z, t.w, f.y), 1.0));
    }
    imageStore(display, ivec3(px, eye), vec4(fv_srgb_encode(color), 1.0));
}
