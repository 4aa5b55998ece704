#version 450
// @brief Hierarchical screen-space interpolation, after shading, without a sample mask in the frame (foveation off):
// the fill or `--view interp` (interp_fill.glsl).
#extension GL_GOOGLE_include_directive : require
#include "interp_fill.glsl"

void main() { interp_fill_pixel(gl_GlobalInvocationID); }
