#version 450
// @brief The shading pass (shade.glsl), counting the GI gather's work per subgroup (arithmetic subgroup operations
// in compute shaders; shade_atomic.comp where the device has none).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#define FV_GI_STATS FV_GI_STATS_SUBGROUP
#include "shade.glsl"
