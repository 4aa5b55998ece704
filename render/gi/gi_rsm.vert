#version 450
// @brief Reflective shadow map, vertex stage: the scene from light `pc.ids.z` (view-projection in the push constants).
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "gi_interface.h"

FV_SCENE_SET_DECLARE
layout(push_constant) uniform Push { fv_gi_rsm_push pc; };

layout(location = FV_SCENE_ATTR_POSITION) in vec3 in_position;
layout(location = FV_SCENE_ATTR_NORMAL) in vec3 in_normal;
layout(location = FV_SCENE_ATTR_TEXCOORD) in vec2 in_texcoord;

layout(location = 0) out vec3 v_pos_world;
layout(location = 1) out vec3 v_normal_world;
layout(location = 2) out vec2 v_texcoord;

void main()
{
    vec4 p = draws[pc.ids.x].model * vec4(in_position, 1.0);
    v_pos_world = p.xyz;
    v_normal_world = mat3(draws[pc.ids.x].normal_matrix) * in_normal;
    v_texcoord = in_texcoord;
    gl_Position = pc.view_proj * p;
}
