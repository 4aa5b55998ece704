#version 450
// @brief Debug views of foveation (FV_GPU_DEBUG_VIEW_SAMPLES / _PROB) over the linear colour: the sample mask
// (r = g = 1 where the pixel was shaded; b = 1 on a ring of FV_DEBUG_GAZE_RING_PX around where the predicted gaze
// pierces the image) or the sampling probability p (grey), from the fovea pass's "fovea mask" / "fovea prob".
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "debug_interface.h"

layout(local_size_x = FV_DEBUG_GROUP_X, local_size_y = FV_DEBUG_GROUP_Y, local_size_z = 1) in;
layout(constant_id = 0) const uint VIEW = FV_GPU_DEBUG_VIEW_SAMPLES;

FV_SCENE_SET_DECLARE
layout(set = FV_DEBUG_FOVEA_SET, binding = FV_DEBUG_FOVEA_BINDING_PROB, r32f) uniform readonly image2DArray prob_img;
layout(set = FV_DEBUG_FOVEA_SET, binding = FV_DEBUG_FOVEA_BINDING_MASK, r32ui) uniform readonly uimage2DArray mask_img;
layout(set = FV_DEBUG_FOVEA_SET, binding = FV_DEBUG_FOVEA_BINDING_COLOR, rgba32f) uniform writeonly image2DArray out_color;

void main()
{
    uvec3 p = gl_GlobalInvocationID;
    if (p.x >= frame.counts.y || p.y >= frame.counts.z || p.z > 1u) return;
    vec3 c;
    if (VIEW == FV_GPU_DEBUG_VIEW_PROB) {
        c = vec3(imageLoad(prob_img, ivec3(p)).x);
    } else {
        float m = imageLoad(mask_img, ivec3(p)).x != 0u ? 1.0 : 0.0;
        vec4 g = frame.gaze_dir[p.z];
        vec3 d = g.w > 0.5 ? g.xyz : vec3(0.0, 0.0, -1.0);
        float ring = 0.0;
        if (d.z < 0.0) {
            vec4 t = frame.eye_tan[p.z];
            vec2 uv = vec2((d.x / -d.z - t.x) / (t.y - t.x), (d.y / -d.z - t.z) / (t.w - t.z));
            vec2 at = uv * vec2(frame.counts.y, frame.counts.z) - 0.5;
            float r = length(vec2(p.xy) - at);
            ring = abs(r - float(FV_DEBUG_GAZE_RING_PX)) <= 0.75 ? 1.0 : 0.0;
        }
        c = vec3(m, m, ring);
    }
    imageStore(out_color, ivec3(p), vec4(c, 1.0));
}
