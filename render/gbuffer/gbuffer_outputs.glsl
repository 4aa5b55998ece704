// @brief The G-buffer's fragment outputs (gbuffer_interface.h), declared once for the scene's and the hidden-area
// mask's fragment shaders; the surface target's only with FV_GBUFFER_SURFACE defined.
layout(location = FV_GBUFFER_OUT_NORMAL) out vec2 out_normal;
layout(location = FV_GBUFFER_OUT_ALBEDO) out vec4 out_albedo;
layout(location = FV_GBUFFER_OUT_MATERIAL) out uint out_material;
layout(location = FV_GBUFFER_OUT_MOTION) out vec2 out_motion;
#ifdef FV_GBUFFER_SURFACE
layout(location = FV_GBUFFER_OUT_SURFACE) out vec4 out_surface;
#endif
