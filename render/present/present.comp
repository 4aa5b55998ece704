#version 450
// @brief Tonemap and encode: linear RGBA32F -> sRGB-encoded RGBA8, per eye layer (the display image).
#extension GL_GOOGLE_include_directive : require
#include "fv_common.glsl"
#include "present_interface.h"
#include "fv_tone_curve.h"

layout(local_size_x = FV_PRESENT_GROUP_X, local_size_y = FV_PRESENT_GROUP_Y, local_size_z = 1) in;
layout(constant_id = 0) const uint TONEMAP = FV_TONEMAP_REINHARD_EXT;

layout(set = 0, binding = FV_PRESENT_BINDING_LINEAR, rgba32f) uniform readonly image2DArray in_linear;
layout(set = 0, binding = FV_PRESENT_BINDING_OUTPUT, rgba8) uniform writeonly image2DArray out_srgb;
layout(push_constant) uniform Push { fv_present_push pc; };

void main()
{
    uvec3 p = gl_GlobalInvocationID;
    if (p.x >= pc.width || p.y >= pc.height || p.z > 1u) return;
    vec3 c = imageLoad(in_linear, ivec3(p)).rgb * pc.exposure;
    // NaN and negative -> 0, +Inf -> white (per channel: a NaN in one channel no longer blacks out the others)
    c = vec3(fv_tone_sanitize(c.r), fv_tone_sanitize(c.g), fv_tone_sanitize(c.b));
    if (TONEMAP == FV_TONEMAP_REINHARD) c = c / (1.0 + c);
    if (TONEMAP == FV_TONEMAP_REINHARD_EXT && pc.tone != 0u)
        c = vec3(fv_tone_reinhard_ext(c.r), fv_tone_reinhard_ext(c.g), fv_tone_reinhard_ext(c.b));
    imageStore(out_srgb, ivec3(p), vec4(fv_srgb_encode(c), 1.0));
}
