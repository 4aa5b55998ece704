/* @brief Subsurface scattering's GPU interface, shared by C and GLSL (render/sss and render/include/fv_sss_gather.glsl):
 * the two storage buffers the pass binds in the shading inputs' SSS slot (the header with one entry per light-view
 * map, and every map's quad-tree of samples), the map pass's push constants and the build shader's bindings. */
#ifndef FV_SSS_INTERFACE_H
#define FV_SSS_INTERFACE_H

#include "fv_gpu.h"
#include "fv_shade_inputs_interface.h"

/** Shading inputs set (set 1 of shading passes): the header and the nodes. */
#define FV_SSS_BINDING_HEADER (FV_SHADE_INPUTS_BINDING_SSS_BUFFER0 + 0)
#define FV_SSS_BINDING_NODES (FV_SHADE_INPUTS_BINDING_SSS_BUFFER0 + 1)
#define FV_SSS_GPU_MAX_LAYERS 7 /* = FV_SSS_MAX_LAYERS; the header fits the slot's 256-byte dummy */
#define FV_SSS_GPU_MODE_HIERARCHY 0u
#define FV_SSS_GPU_MODE_EXACT 1u
#define FV_SSS_GPU_MIN_COS 0.1 /* = FV_SSS_MIN_COS */
#define FV_SSS_GPU_RESOLVE_COS 0.3 /* = FV_SSS_RESOLVE_COS */
#define FV_SSS_STACK 32        /* traversal stack entries per pixel: 3 per level below the start, plus one */
/* The receiver's near field (render/sss/fv_sss_math.h's fv_sss_near_footprint): */
#define FV_SSS_GPU_FLAT_FOOTPRINTS 2.0 /* = FV_SSS_FLAT_FOOTPRINTS */
#define FV_SSS_GPU_FLAT_COS_LO 0.05    /* = FV_SSS_FLAT_COS_LO */
#define FV_SSS_GPU_FLAT_COS_HI 0.2     /* = FV_SSS_FLAT_COS_HI */
#define FV_SSS_GPU_FLAT_NORMAL_LO 0.7  /* = FV_SSS_FLAT_NORMAL_LO */
#define FV_SSS_GPU_FLAT_NORMAL_HI 0.9  /* = FV_SSS_FLAT_NORMAL_HI */

/** One light-view map. */
struct fv_gpu_sss_layer {
    FV_UVEC4 info; /* x material index, y light index, z first node (of its level 0), w leaf level L (2^L texels of
                    * the fine map) | s << 8, its sub-levels (fv_sss_sub_levels): the nodes of level L - s (the
                    * nominal texels) that have a footprint are resolved (leaves to the gather) */
    FV_VEC4 view;  /* x 1 = perspective, y texel side m (orthographic) or tan(half-angle), z the material's cutoff
                    * radius (m, fv_sss_cutoff_radius_m; 0 = none), w its flat radius (m, fv_sss_flat_radius_m: the
                    * receiver's near field) */
};

/** The header (binding FV_SSS_BINDING_HEADER); all zero = no subsurface light (the slot's dummy). */
struct fv_gpu_sss {
    FV_UVEC4 counts; /* x maps, y mode (FV_SSS_GPU_MODE_*), z start level, w limit level */
    FV_VEC4 params;  /* x distance scale (1/m), y, z, w 0 */
#ifdef FV_GLSL
    fv_gpu_sss_layer layer[FV_SSS_GPU_MAX_LAYERS];
#else
    struct fv_gpu_sss_layer layer[FV_SSS_GPU_MAX_LAYERS];
#endif
};

/** One quad-tree node (binding FV_SSS_BINDING_NODES): level k of map m holds 4^k nodes in Morton order from
 *  layer[m].info.z + (4^k - 1) / 3; the children of node i of level k are nodes 4i..4i+3 of level k + 1. */
struct fv_gpu_sss_node {
    FV_VEC4 pos_area;    /* xyz area-weighted centroid (world m), w surface area (m^2; 0 = empty) */
    FV_VEC4 flux_sim;    /* rgb flux entering the surface, E * area (W), w similarity (leaves 1, 0..1) */
    FV_VEC4 normal_depth; /* xyz area-weighted mean normal, w mean depth along the light (m) */
    FV_VEC4 extent;       /* x bounding radius around the centroid (m): how far the footprints of its samples reach
                           * (a leaf or a resolved nominal texel: its footprint's half-diagonal); yzw the footprint's
                           * edge a (m) */
    FV_VEC4 edge_b;       /* xyz the footprint's edge b (m), w the largest footprint half-diagonal of its leaves (m).
                           * The footprint is the parallelogram centroid +- a/2 +- b/2 on the surface
                           * (fv_sss_texel_footprint; |a x b| = area) of a leaf's texel or of a resolved nominal
                           * texel (fv_sss_texel_resolve); a cluster has none (a = b = 0: the disk of its area stands
                           * in) */
};

/** The map pass's push constants (vertex and fragment stages): the scene's {draw, view} then ours. */
struct fv_sss_map_push {
    FV_UVEC4 ids;      /* x draw index (fv_scene_gpu_record_draws), y view, z material of the map, w light */
    FV_MAT4 view_proj; /* world -> the map's clip */
    FV_VEC4 view;      /* as fv_gpu_sss_layer.view */
    FV_VEC4 origin;    /* xyz the light's position (perspective) or eye of the orthographic map, w 0 */
    FV_VEC4 axis;      /* xyz unit forward of the map, w map size (texels) */
};

/** The build shader (sss_build.comp): set 0 scene, set 1 its own. */
#define FV_SSS_BUILD_SET 1
#define FV_SSS_BUILD_BINDING_POS 0    /* sampler2DArray: xyz position, w area */
#define FV_SSS_BUILD_BINDING_FLUX 1   /* sampler2DArray: rgb flux, w depth along the light */
#define FV_SSS_BUILD_BINDING_NORMAL 2 /* sampler2DArray: xyz normal, w its cosine to the light */
#define FV_SSS_BUILD_BINDING_NODES 3  /* the nodes (written) */
#define FV_SSS_BUILD_BINDING_EDGE_A 4 /* sampler2DArray: xyz footprint edge a */
#define FV_SSS_BUILD_BINDING_EDGE_B 5 /* sampler2DArray: xyz footprint edge b */
#define FV_SSS_BUILD_BINDING_COUNT 6
#define FV_SSS_BUILD_GROUP 64

struct fv_sss_build_push {
    FV_UVEC4 level; /* x level being written (leaves: L), y leaf level L, z maps, w sub-levels s (level L - s: the
                     * nominal texels, resolved where they can be) */
};

/** Map attachments (fragment outputs). */
#define FV_SSS_OUT_POS 0
#define FV_SSS_OUT_FLUX 1
#define FV_SSS_OUT_NORMAL 2 /* xyz normal facing the light, w its cosine to the light */
#define FV_SSS_OUT_EDGE_A 3 /* xyz the texel's footprint's edge a along the map's x (fv_sss_texel_footprint), w 0 */
#define FV_SSS_OUT_EDGE_B 4 /* xyz its edge b along the map's y, w 0 */
#define FV_SSS_MAP_TARGETS 5

#ifdef FV_GLSL
/* GLSL (after fv_common.glsl): */
// Schlick's Fresnel transmittance 1 - F (F0 = ((eta - 1) / (eta + 1))^2).
float fv_sss_fresnel_t(float eta, float cos_theta)
{
    eta = eta > 0.0 ? eta : 1.0;
    float f0 = (eta - 1.0) / (eta + 1.0);
    f0 *= f0;
    float m = 1.0 - clamp(cos_theta, 0.0, 1.0);
    float m2 = m * m;
    return clamp(1.0 - (f0 + (1.0 - f0) * m2 * m2 * m), 0.0, 1.0);
}

// v without its component along the unit u, made unit (zero when nothing is left).
vec3 fv_sss_unit_across(vec3 v, vec3 u)
{
    vec3 r = v - u * dot(v, u);
    float l = length(r);
    return l > 1e-30 ? r / l : vec3(0.0);
}
#endif

#ifndef FV_GLSL
typedef struct fv_gpu_sss_layer fv_gpu_sss_layer;
typedef struct fv_gpu_sss fv_gpu_sss;
typedef struct fv_gpu_sss_node fv_gpu_sss_node;
_Static_assert(sizeof(fv_gpu_sss_layer) == 32, "fv_gpu_sss_layer layout");
_Static_assert(sizeof(fv_gpu_sss) <= 256, "the SSS header fits the shading inputs' dummy buffer");
_Static_assert(sizeof(fv_gpu_sss_node) == 80, "fv_gpu_sss_node layout");
_Static_assert(sizeof(struct fv_sss_map_push) == 128, "fv_sss_map_push layout");
_Static_assert(sizeof(struct fv_sss_build_push) == 16, "fv_sss_build_push layout");
#endif

#endif
