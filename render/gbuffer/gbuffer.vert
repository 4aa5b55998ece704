#version 450
// @brief G-buffer vertex shader: both eyes in one draw (multiview); per-eye view/projection via gl_ViewIndex.
#extension GL_EXT_multiview : require
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "gbuffer_interface.h"

FV_SCENE_SET_DECLARE
layout(push_constant) uniform Push { uint draw_index; uint eye; } pc;
// 1: both eyes in one multiview pass (eye = gl_ViewIndex); 0: one pass per eye (eye from the push constant).
layout(constant_id = 0) const uint USE_MULTIVIEW = 1u;

layout(location = FV_SCENE_ATTR_POSITION) in vec3 in_position;
layout(location = FV_SCENE_ATTR_NORMAL) in vec3 in_normal;
layout(location = FV_SCENE_ATTR_TEXCOORD) in vec2 in_texcoord;

layout(location = 0) out vec3 v_pos_world;
layout(location = 1) out vec3 v_normal_world;
layout(location = 2) out vec2 v_texcoord;
layout(location = 3) out vec4 v_clip;
layout(location = 4) out vec4 v_prev_clip;

void main()
{
    uint eye = USE_MULTIVIEW != 0u ? gl_ViewIndex : pc.eye;
    vec4 p = draws[pc.draw_index].model * vec4(in_position, 1.0);
    vec4 prev = draws[pc.draw_index].prev_model * vec4(in_position, 1.0);
    v_pos_world = p.xyz;
    v_normal_world = mat3(draws[pc.draw_index].normal_matrix) * in_normal;
    v_texcoord = in_texcoord;
    v_clip = frame.view_proj[eye] * p;
    v_prev_clip = frame.prev_view_proj[eye] * prev;
    gl_Position = v_clip;
}
