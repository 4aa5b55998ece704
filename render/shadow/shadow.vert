#version 450
// @brief Shadow-map casters: the scene's positions through one map's light view-projection (a push constant).
#extension GL_GOOGLE_include_directive : require
#include "fv_gpu.h"
#include "fv_scene_set.h"

FV_SCENE_SET_DECLARE
layout(push_constant) uniform Push { uint draw_index; uint view; uint pad0; uint pad1; mat4 view_proj; } pc;
layout(location = FV_SCENE_ATTR_POSITION) in vec3 in_position;

void main()
{
    gl_Position = pc.view_proj * (draws[pc.draw_index].model * vec4(in_position, 1.0));
}
