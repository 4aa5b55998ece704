/* @brief Structs shared by C and GLSL (std140 uniform / std430 storage layouts): the per-frame block, per-draw data,
 * materials and lights. Only vec4/uvec4/mat4 members, so std140 and std430 agree with the C layout; the C side checks
 * sizes with _Static_assert. Include from C (after nothing) or from GLSL (GL_GOOGLE_include_directive). */
#ifndef FV_GPU_H
#define FV_GPU_H

#if defined(GL_core_profile) || defined(VULKAN) || defined(GL_SPIRV)
#define FV_GLSL 1
#define FV_VEC4 vec4
#define FV_UVEC4 uvec4
#define FV_MAT4 mat4
#else
#include <stdint.h>
typedef struct fv_gpu_vec4 { float x, y, z, w; } fv_gpu_vec4;
typedef struct fv_gpu_uvec4 { uint32_t x, y, z, w; } fv_gpu_uvec4;
typedef struct fv_gpu_mat4 { float m[16]; } fv_gpu_mat4; /* column-major, as fv_mat4 */
#define FV_VEC4 fv_gpu_vec4
#define FV_UVEC4 fv_gpu_uvec4
#define FV_MAT4 fv_gpu_mat4
#endif

/** Light types (fv_gpu_light.direction_type.w). Match fv_light_type. */
#define FV_GPU_LIGHT_POINT 0
#define FV_GPU_LIGHT_SPOT 1
#define FV_GPU_LIGHT_DIRECTIONAL 2

/** Per frame, both eyes (uniform block). Eye index = gl_ViewIndex / image layer. */
struct fv_gpu_frame {
    FV_MAT4 view_proj[2];      /* world -> clip (Vulkan: y down, depth 0..1) */
    FV_MAT4 prev_view_proj[2]; /* the previous frame's, for motion vectors */
    FV_MAT4 inv_view_proj[2];  /* clip -> world, for positions from depth */
    FV_VEC4 eye_pos[2];        /* xyz world metres */
    FV_VEC4 ambient;           /* rgb ambient radiance */
    FV_UVEC4 counts;           /* x lights, y width px, z height px, w frame index (low bits) */
    /* The runtime's view of the eyes at photon time (fv_frame_input), per eye: */
    FV_VEC4 gaze_dir[2];       /* xyz predicted unit gaze in the eye's view space (-z forward); w 1 = valid, 0 = no
                                * gaze (blink, lost, none: xyz is then straight ahead) */
    FV_VEC4 gaze_info[2];      /* x uncertainty (radians, [0, pi]), y pupil diameter mm (0 = unknown), z, w 0 */
    FV_VEC4 eye_tan[2];        /* the eye's frustum as tangents: x left, y right, z up, w down (a pixel's ray in
                                * view space is (mix(x, y, u), mix(z, w, v), -1), u, v in [0,1], v down) */
    FV_VEC4 time;              /* x scene time s (float); y, z, w 0 */
    FV_UVEC4 photon;           /* x low, y high 32 bits of the photon time (host clock ns, 0 = unknown); z debug
                                * view (FV_GPU_DEBUG_VIEW_*); w 0 */
    FV_VEC4 quality;           /* x exposure (linear scale before tonemapping); y, z, w 0 */
    FV_VEC4 pixel_angle;       /* x, y: eye 0's and eye 1's centre pixel as an angle, 2 atan(dt / 2) radians, dt the
                                * smaller of its tangent steps (the display's finest angle: foveation's w_px); z, w 0 */
};

/** The largest pupil diameter passed on as known (mm); larger values are not a pupil (gaze_info.y = 0). */
#define FV_GPU_PUPIL_MAX_MM 20.0f

/** Debug views (fv_gpu_frame.photon.z; fv_quality.debug_view). */
#define FV_GPU_DEBUG_VIEW_NONE 0
/* Specialization constant ids of the shared shading function (fv_shade_hooks.glsl, fv_gi_gather.glsl,
 * fv_sss_gather.glsl): a pipeline that knows a technique is off this frame compiles without its code (issue 25).
 * Id 0 stays the including shader's own (a debug view, a stage). Unset, each keeps its default: every technique in,
 * chosen at run time from the headers, as before. */
#define FV_SPEC_ID_GI_MODE 1 /* int: -2 any (run time), -1 GI off, else the one gi.mode compiled in */
#define FV_SPEC_ID_SSS 2     /* bool: the subsurface term compiled in */
#define FV_SPEC_ID_SHADOWS 3 /* bool: shadow-map lookups compiled in */
#define FV_SPEC_ID_GI_RATE 4 /* int: 0 the GI header's rate (run time), 1 per-pixel gather only, 2, 4, 8 upsampled */
#define FV_SPEC_GI_ANY (-2)
#define FV_SPEC_GI_OFF (-1)

#define FV_GPU_DEBUG_VIEW_NORMAL 1  /* world normal * 0.5 + 0.5 */
#define FV_GPU_DEBUG_VIEW_GAZE 2    /* r: closeness to the predicted gaze ray, g: pupil mm / 10, b: gaze valid */
#define FV_GPU_DEBUG_VIEW_DIRECT 3  /* direct light only (visibility x irradiance x BRDF): no emission, no ambient */
#define FV_GPU_DEBUG_VIEW_SHADOW 4  /* visibility of light 0, 0..1, grey */
#define FV_GPU_DEBUG_VIEW_CASCADE 5 /* which of light 0's maps holds the pixel, as a colour (black: none) */
#define FV_GPU_DEBUG_VIEW_ALBEDO 6  /* linear albedo */
#define FV_GPU_DEBUG_VIEW_DEPTH 7   /* Vulkan depth 0..1 of the eye's projection, grey (1 where nothing is drawn) */
#define FV_GPU_DEBUG_VIEW_SAMPLES 8 /* foveation's sample mask: r = g = 1 where shaded; b = 1 on a ring at the gaze */
#define FV_GPU_DEBUG_VIEW_PROB 9    /* foveation's sampling probability, grey */
#define FV_GPU_DEBUG_VIEW_VORONOI 10  /* foveation: each pixel coloured by the sample it was filled from */
#define FV_GPU_DEBUG_VIEW_GI 11       /* indirect light only */
#define FV_GPU_DEBUG_VIEW_CLUSTERS 12 /* the GI cut over the reflective shadow map, by level */
#define FV_GPU_DEBUG_VIEW_SSS 13      /* the subsurface term alone */
#define FV_GPU_DEBUG_VIEW_INTERP 14   /* hierarchical interpolation: the level each pixel was shaded or filled at */

/** One drawn node (storage buffer, indexed by a push constant). */
struct fv_gpu_draw {
    FV_MAT4 model;         /* object -> world at this frame's time */
    FV_MAT4 prev_model;    /* at the previous frame's time (object motion) */
    FV_MAT4 normal_matrix; /* inverse transpose of model (upper 3x3 used) */
    FV_UVEC4 info;         /* x material index, y texture index or 0xffffffff */
};

/** One material (storage buffer, indexed by material id - 1). */
struct fv_gpu_material {
    FV_VEC4 base_color; /* linear rgb albedo factor */
    FV_VEC4 emissive;   /* rgb emitted radiance */
    FV_UVEC4 info;      /* x texture index or 0xffffffff, y flags (bit 0: translucent) */
    FV_VEC4 sigma_a;    /* translucent: rgb absorption coefficient per metre of the scene (converted from mm^-1),
                         * w relative index of refraction eta (1 when opaque) */
    FV_VEC4 sigma_s;    /* translucent: rgb reduced scattering coefficient per metre; w 0 */
};

/** One light (storage buffer). */
struct fv_gpu_light {
    FV_VEC4 position_range; /* xyz world metres, w range in metres (0 = infinite) */
    FV_VEC4 direction_type; /* xyz unit direction the light travels, w type (FV_GPU_LIGHT_*) */
    FV_VEC4 intensity;      /* rgb: colour * intensity (W/sr for point/spot, W/m^2 for directional) */
    FV_VEC4 cone;           /* spot: x cos(inner), y cos(outer) */
};

/** Shadows (set 2 of shading passes, fv_shade_inputs_interface.h): per shadowed light its maps in one 2D-array depth image. */
#define FV_SHADOW_MAX_LIGHTS 4
#define FV_SHADOW_MAX_SPLITS 8
#define FV_SHADOW_MAX_MAPS 64 /* lights x (2 eyes) x splits, or 6 faces of a point light */
#define FV_SHADOW_KIND_NONE 0
#define FV_SHADOW_KIND_CASCADES 1    /* directional light: parallel-split shadow maps (orthographic per split) */
#define FV_SHADOW_KIND_PERSPECTIVE 2 /* spot light: one perspective map */
#define FV_SHADOW_KIND_CUBE 3        /* point light: six perspective faces, +x -x +y -y +z -z (the major axis of
                                      * surface - light picks the face) */

struct fv_gpu_shadow_light {
    FV_UVEC4 info;        /* x kind (FV_SHADOW_KIND_*), y first map, z splits (1 for spot), w maps per eye (0: both
                           * eyes share the maps; else eye e uses first + e * w) */
    FV_VEC4 split_far[2]; /* view depth (m) where each split ends, splits 0..7; a deeper pixel uses the last */
    FV_VEC4 params;       /* x filter radius in texels (0: one tap, 1: 3x3, 2: 5x5), y 1 / resolution, z (spot,
                           * cube) a texel's world size per metre of distance from the light, w 0 */
    FV_VEC4 split_texel[2]; /* cascades: a texel's world size (m) in each split, for the receiver's normal offset */
};

struct fv_gpu_shadow {
    FV_UVEC4 counts; /* x lights with an entry (scene lights 0..x-1; others unshadowed), y maps, z resolution, w 0 */
#ifdef FV_GLSL
    fv_gpu_shadow_light light[FV_SHADOW_MAX_LIGHTS];
#else
    struct fv_gpu_shadow_light light[FV_SHADOW_MAX_LIGHTS];
#endif
    FV_MAT4 map_view_proj[FV_SHADOW_MAX_MAPS]; /* world -> the map's clip space (Vulkan: y down, depth 0..1) */
};

#ifndef FV_GLSL
typedef struct fv_gpu_shadow_light fv_gpu_shadow_light;
typedef struct fv_gpu_shadow fv_gpu_shadow;
_Static_assert(sizeof(fv_gpu_shadow_light) == 96, "fv_gpu_shadow_light layout");
_Static_assert(sizeof(fv_gpu_shadow) == 16 + 96 * FV_SHADOW_MAX_LIGHTS + 64 * FV_SHADOW_MAX_MAPS, "fv_gpu_shadow layout");
typedef struct fv_gpu_frame fv_gpu_frame;
typedef struct fv_gpu_draw fv_gpu_draw;
typedef struct fv_gpu_material fv_gpu_material;
typedef struct fv_gpu_light fv_gpu_light;
_Static_assert(sizeof(fv_gpu_frame) == 6 * 64 + 4 * 16 + 10 * 16, "fv_gpu_frame layout");
_Static_assert(sizeof(fv_gpu_draw) == 3 * 64 + 16, "fv_gpu_draw layout");
_Static_assert(sizeof(fv_gpu_material) == 80, "fv_gpu_material layout");
_Static_assert(sizeof(fv_gpu_light) == 64, "fv_gpu_light layout");
#endif

/** Sparse shading: a pixel of one eye packed in 32 bits (x: 15 bits, y: 15 bits, eye layer: 2 bits). */
#define FV_GPU_PIXEL_PACK(x, y, layer) (((x) & 0x7fffu) | (((y) & 0x7fffu) << 15) | (((layer) & 3u) << 30))
#define FV_GPU_PIXEL_MAX_DIM 32768u

/** A pixel list (storage buffer): a 16-byte header { uint count; uint pad[3]; } then `count` packed pixels. Lists
 *  are consumed by indirect dispatches of FV_GPU_LIST_GROUP_SIZE pixels per workgroup: x = min(groups,
 *  FV_GPU_LIST_GROUPS_X), y = ceil(groups / FV_GPU_LIST_GROUPS_X), z = 1 with groups = ceil(count / group size);
 *  workgroup (x, y) takes entries from (x + y * FV_GPU_LIST_GROUPS_X) * FV_GPU_LIST_GROUP_SIZE. */
#define FV_GPU_LIST_HEADER_BYTES 16u
#define FV_GPU_LIST_GROUP_SIZE 64u
#define FV_GPU_LIST_GROUPS_X 65535u

#endif
