#version 450
// @brief Light-view sample map, vertices: the scene's positions and normals through the map's view-projection.
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fv_sss_interface.h"

FV_SCENE_SET_DECLARE
layout(push_constant) uniform Push { fv_sss_map_push pc; };
layout(location = FV_SCENE_ATTR_POSITION) in vec3 in_position;
layout(location = FV_SCENE_ATTR_NORMAL) in vec3 in_normal;
layout(location = 0) out vec3 v_pos_world;
layout(location = 1) out vec3 v_normal_world;

void main()
{
    uint draw = pc.ids.x;
    vec4 p = draws[draw].model * vec4(in_position, 1.0);
    v_pos_world = p.xyz;
    v_normal_world = mat3(draws[draw].normal_matrix) * in_normal;
    gl_Position = pc.view_proj * p;
}
