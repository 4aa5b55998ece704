#version 450
#extension GL_GOOGLE_include_directive : require
// @brief fovea's OpenXR compositor: every layer of both eyes into the display image (sRGB-encoded RGBA8), in layer
// order, through each layer's homography (compose_interface.h).
#include "compose_interface.h"

layout(local_size_x = FV_XR_COMPOSE_GROUP, local_size_y = FV_XR_COMPOSE_GROUP) in;
layout(set = 0, binding = FV_XR_COMPOSE_BINDING_SOURCES) uniform sampler2DArray sources[FV_XR_COMPOSE_MAX_SOURCES];
layout(set = 0, binding = FV_XR_COMPOSE_BINDING_DISPLAY, rgba8) uniform writeonly image2DArray display;
layout(set = 0, binding = FV_XR_COMPOSE_BINDING_LAYERS, std140) uniform Block { fv_xr_compose_block b; };

// The frame's source count, specialised (a pipeline per count, made on first use): sampler arrays are indexed by
// constants only (lavapipe has no shaderSampledImageArrayDynamicIndexing), and a source the frame does not bind is
// no branch at all. Every branch is run by every invocation on lavapipe (masked), so a switch over all 16 sources
// cost 16 samples per layer and pixel (10x the pass's time for the usual 1 or 2 sources).
layout(constant_id = 0) const uint NSRC = FV_XR_COMPOSE_MAX_SOURCES;

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

vec3 srgb_encode(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main()
{
    uint eye = gl_GlobalInvocationID.z;
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= b.counts.z || px.y >= b.counts.w || eye > 1u) return;
    vec4 t = b.tan[eye];
    vec2 f = (vec2(px) + 0.5) / vec2(b.counts.zw);
    vec3 ray = vec3(mix(t.x, t.y, f.x), mix(t.z, t.w, f.y), 1.0);
    vec3 color = vec3(0.0);
    uint n = eye == 0u ? b.counts.x : b.counts.y;
    for (uint i = 0u; i < n && i < uint(FV_XR_COMPOSE_MAX_LAYERS); i++) {
        fv_xr_compose_layer l = b.layer[eye * uint(FV_XR_COMPOSE_MAX_LAYERS) + i];
        vec3 p = vec3(dot(l.h[0].xyz, ray), dot(l.h[1].xyz, ray), dot(l.h[2].xyz, ray));
        if (!(p.z > 1e-6)) continue;
        vec2 uv = p.xy / p.z;
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) continue;
        vec4 c = fetch(l.info.x, vec3(l.uv_rect.xy + uv * l.uv_rect.zw, float(l.info.y)));
        vec3 under = color;
        if ((l.info.z & FV_XR_LAYER_ALPHA) != 0u) {
            vec3 src = (l.info.z & FV_XR_LAYER_UNPREMULTIPLIED) != 0u ? c.rgb * c.a : c.rgb;
            color = src + color * (1.0 - clamp(c.a, 0.0, 1.0));
        } else {
            color = c.rgb;
        }
        if ((l.info.z & FV_XR_LAYER_INSET) != 0u) {
            // an inset blends into what is under it (the wide view) over the band at its edge: a smoothstep per axis
            vec2 band = max(vec2(l.h[0].w, l.h[1].w), vec2(1e-6));
            vec2 s = smoothstep(vec2(0.0), band, min(uv, vec2(1.0) - uv));
            color = mix(under, color, s.x * s.y);
        }
    }
    imageStore(display, ivec3(px, eye), vec4(srgb_encode(color), 1.0));
}
