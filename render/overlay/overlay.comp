#version 450
// @brief The overlay: over the display image of each eye, the predicted gaze point (yellow dot), its uncertainty
// ring (cyan, at the predicted uncertainty's angular radius) and, with foveation on, the foveal boundary (magenta:
// where foveation's sampling probability falls below 1, i.e. the edge of the fully shaded region). Angles are
// measured between each pixel's ray and the gaze ray, so the marks are right for any field of view. Blends over the
// sRGB-encoded values (an overlay is not light).
#extension GL_GOOGLE_include_directive : require
#include "overlay_interface.h"

layout(local_size_x = FV_OVERLAY_GROUP_X, local_size_y = FV_OVERLAY_GROUP_Y, local_size_z = 1) in;

layout(set = 0, binding = FV_OVERLAY_BINDING_DISPLAY, rgba8) uniform image2DArray display_img;
layout(set = 0, binding = FV_OVERLAY_BINDING_PROB, r32f) uniform readonly image2DArray prob_img;
layout(push_constant) uniform Push { fv_overlay_push pc; };

vec3 pixel_ray(vec2 px, uint eye)
{
    vec4 t = pc.tan[eye];
    vec2 uv = (px + 0.5) / vec2(pc.width, pc.height);
    return normalize(vec3(mix(t.x, t.y, uv.x), mix(t.z, t.w, uv.y), -1.0));
}

bool full_rate(ivec3 p)
{
    p.xy = clamp(p.xy, ivec2(0), ivec2(pc.width, pc.height) - 1);
    return imageLoad(prob_img, p).r >= 0.999;
}

void main()
{
    uvec3 p = gl_GlobalInvocationID;
    if (p.x >= pc.width || p.y >= pc.height || p.z > 1u) return;
    uint eye = p.z;
    vec4 t = pc.tan[eye];
    // a pixel's angular size at the centre of the view (the marks are a few of these wide)
    float px_rad = max(min(abs(t.y - t.x) / float(pc.width), abs(t.z - t.w) / float(pc.height)), 1e-6);
    vec4 colour = vec4(0.0);
    vec4 g = pc.gaze[eye];
    if (g.w > 0.5) {
        vec3 r = pixel_ray(vec2(p.xy), eye);
        float e = atan(length(cross(r, g.xyz)), dot(r, g.xyz));
        float u = pc.info[eye].x;
        if (e <= 2.5 * px_rad) colour = vec4(1.0, 0.9, 0.1, 1.0);
        else if (e <= 3.5 * px_rad) colour = vec4(0.0, 0.0, 0.0, 1.0); // a dark rim keeps the dot visible on white
        else if (u > 4.0 * px_rad && abs(e - u) <= 0.75 * px_rad) colour = vec4(0.1, 0.9, 1.0, 0.9);
    }
    if (colour.a == 0.0 && (pc.flags & FV_OVERLAY_FLAG_FOVEA) != 0u) {
        ivec3 q = ivec3(p);
        bool inside = full_rate(q);
        bool edge = inside && (!full_rate(q + ivec3(1, 0, 0)) || !full_rate(q - ivec3(1, 0, 0)) ||
                               !full_rate(q + ivec3(0, 1, 0)) || !full_rate(q - ivec3(0, 1, 0)));
        if (edge) colour = vec4(1.0, 0.2, 0.9, 0.9);
    }
    if (colour.a == 0.0) return;
    vec4 under = imageLoad(display_img, ivec3(p));
    imageStore(display_img, ivec3(p), vec4(mix(under.rgb, colour.rgb, colour.a), 1.0));
}
