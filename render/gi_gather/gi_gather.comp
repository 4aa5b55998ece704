#version 450
// @brief The reduced-rate GI gather (gi.rate): one invocation per r x r block of each eye's G-buffer gathers the
// one-bounce indirect irradiance (fv_gi_irradiance, the per-pixel gather of the shading function) at the block's
// sample pixel (r i + r/2, clamped to the image) and writes it for the shading function's joint-bilateral upsample
// (fv_gi_upsample, which reads the sample's position and normal from the G-buffer). A block whose sample pixel shows nothing is written
// with w = 0 (matches no pixel). The gather's work is counted into the GI stats per invocation (atomics).
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fv_shade_inputs_interface.h"
#include "fv_common.glsl"
#include "gi_gather_interface.h"

layout(local_size_x = FV_GI_GATHER_GROUP_X, local_size_y = FV_GI_GATHER_GROUP_Y, local_size_z = 1) in;

FV_SCENE_SET_DECLARE
FV_SHADE_INPUTS_DECLARE
#define FV_GBUFFER_SET FV_GI_GATHER_SET
#define FV_GBUFFER_BINDING_DEPTH FV_GI_GATHER_BINDING_DEPTH
#define FV_GBUFFER_BINDING_NORMAL FV_GI_GATHER_BINDING_NORMAL
#define FV_GBUFFER_BINDING_ALBEDO FV_GI_GATHER_BINDING_ALBEDO
#define FV_GBUFFER_BINDING_MATERIAL FV_GI_GATHER_BINDING_MATERIAL
#include "fv_gbuffer_decode.glsl"
layout(set = FV_GI_GATHER_SET, binding = FV_GI_GATHER_BINDING_OUT_E, rgba32f) uniform writeonly image2DArray out_e;
layout(push_constant) uniform Push { fv_gi_gather_push pc; };

// The gather alone: this pass writes the images the upsample reads, so it must not declare them.
#define FV_GI_STATS FV_GI_STATS_ATOMIC
#define FV_GI_NO_UPSAMPLE
#include "fv_gi_gather.glsl"

void main()
{
    uvec3 q = gl_GlobalInvocationID;
    uint r = max(pc.dims.x, 1u);
    if (q.x < pc.dims.y && q.y < pc.dims.z && q.z <= 1u && frame.counts.y > 0u && frame.counts.z > 0u) {
        uvec3 p = uvec3(min(q.xy * r + r / 2u, uvec2(frame.counts.y, frame.counts.z) - 1u), q.z);
        fv_surface s = fv_gbuffer_surface(p);
        vec4 e = vec4(0.0);
        if (s.hit) {
            uint used;
            e = vec4(fv_gi_irradiance(s.pos_world, s.normal, used), 1.0);
            fv_gi_stats_note(used);
        }
        imageStore(out_e, ivec3(q), e);
    }
    fv_gi_stats_flush();
}
