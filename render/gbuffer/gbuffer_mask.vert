#version 450
// @brief Hidden-area mask (fv_lens_hidden_mesh, runtime/hmd): triangles in NDC at depth 0 over the pixels the lens
// never shows, drawn first in the G-buffer pass so every scene fragment there fails the depth test. Each vertex
// carries its eye in z; in a multiview pass a view keeps only its own eye's triangles (the others collapse to a point
// outside the viewport).
#extension GL_EXT_multiview : require

layout(constant_id = 0) const uint USE_MULTIVIEW = 1u;
layout(location = 0) in vec3 in_ndc_eye;

void main()
{
    bool mine = USE_MULTIVIEW == 0u || uint(in_ndc_eye.z + 0.5) == gl_ViewIndex;
    gl_Position = mine ? vec4(in_ndc_eye.xy, 0.0, 1.0) : vec4(2.0, 2.0, 0.0, 1.0);
}
