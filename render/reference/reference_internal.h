/* @brief Inside the reference renderer: the flattened world (world-space geometry in double beside Embree's float
 * copy, sanitised materials, textures and lights as the GPU receives them, the emissive triangles), hits
 * re-computed in double, the per-pixel random stream, and the shading entry points of both modes. */
#ifndef FV_REFERENCE_INTERNAL_H
#define FV_REFERENCE_INTERNAL_H

#include <embree3/rtcore.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "fv_reference.h"

#define REF_MOD "reference"

/* ---- small double vectors ---------------------------------------------------------------------------------- */
typedef struct dvec3 { double x, y, z; } dvec3;

static inline dvec3 dv(double x, double y, double z) { return (dvec3){x, y, z}; }
static inline dvec3 dv_add(dvec3 a, dvec3 b) { return dv(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline dvec3 dv_sub(dvec3 a, dvec3 b) { return dv(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline dvec3 dv_scale(dvec3 a, double s) { return dv(a.x * s, a.y * s, a.z * s); }
static inline dvec3 dv_mul(dvec3 a, dvec3 b) { return dv(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline double dv_dot(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline dvec3 dv_cross(dvec3 a, dvec3 b)
{
    return dv(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline dvec3 dv_from_f(fv_vec3 v) { return dv(v.x, v.y, v.z); }
static inline bool dv_finite(dvec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
static inline double dv_maxc(dvec3 a) { return fmax(a.x, fmax(a.y, a.z)); }
static inline double dv_max_abs(dvec3 a) { return fmax(fabs(a.x), fmax(fabs(a.y), fabs(a.z))); }

/* ---- the world ----------------------------------------------------------------------------------------------- */
typedef struct ref_texture {
    uint32_t width, height;
    const uint8_t *rgba8; /* the scene's pixels (borrowed); NULL = white, as the GPU's fallback */
} ref_texture;

typedef struct ref_material {
    dvec3 base_color; /* clamped to [0,1], non-finite = 1 (as uploaded) */
    dvec3 emissive;   /* >= 0, non-finite = 0 */
    int32_t texture;  /* index into ref_world.textures, or -1 (white) */
} ref_material;

typedef struct ref_light {
    uint32_t type;   /* FV_LIGHT_* (an unknown type is a point light, as on the GPU) */
    dvec3 position;  /* non-finite = origin */
    dvec3 direction; /* unit, the way the light travels */
    dvec3 intensity; /* colour x intensity: W/sr (point, spot) or W/m^2 (directional) */
    double range;    /* 0 = infinite */
    double cos_inner, cos_outer;
} ref_light;

/** One drawn node: its mesh in world space at the render time. */
typedef struct ref_geom {
    uint32_t node, material;
    const fv_mesh *mesh;
    dvec3 *pos; /* world positions (the node's float matrix applied in double) */
    dvec3 *nrm; /* world normals through the normal matrix (inverse transpose), not normalised, as the GPU */
    uint32_t *prim_tri;  /* Embree primitive -> triangle of the mesh */
    uint32_t prim_count;
} ref_geom;

typedef struct ref_emitter {
    uint32_t geom, tri;
    double area_m2;
} ref_emitter;

typedef struct ref_world {
    RTCDevice device;
    RTCScene scene;
    ref_geom *geoms; /* by Embree geometry id */
    uint32_t geom_count;
    ref_material *materials;
    uint32_t material_count; /* >= 1: a scene without materials gets fv_material_default(), as on the GPU */
    ref_texture *textures;
    uint32_t texture_count;
    ref_light *lights;
    uint32_t light_count;
    dvec3 ambient;
    ref_emitter *emitters;
    double *emitter_cdf; /* emitter_count running sums of area, the last = emissive_area_m2 */
    uint32_t emitter_count;
    double emissive_area_m2;
    uint32_t triangles, skipped_triangles;
} ref_world;

/** Build the world of `scene` at time t_s (Embree BVH committed). On failure everything is released. */
FV_MUST_CHECK fv_result ref_world_init(ref_world *w, const fv_scene *scene, double t_s);
void ref_world_fini(ref_world *w);

/* ---- rays and hits ------------------------------------------------------------------------------------------- */
typedef struct ref_hit {
    uint32_t geom, tri;
    double t;
    dvec3 pos;      /* on the triangle's plane, in double */
    dvec3 ng;       /* unit geometric normal, facing the side the ray came from */
    dvec3 n;        /* unit shading normal (interpolated; faced as the caller asked) */
    double uv[2];   /* interpolated texcoords */
    uint32_t material;
} ref_hit;

/** Per-thread counters. */
typedef struct ref_counts {
    uint64_t primary, shadow, bounce, nonfinite;
} ref_counts;

/** Closest hit along o + t d, t in (0, t_max]; d unit. The hit is re-intersected in double against the triangle
 *  Embree found. face_to: the point the shading normal is turned toward (the eye, as the G-buffer does), NULL =
 *  toward -d. */
bool ref_trace(const ref_world *w, dvec3 o, dvec3 d, double t_max, const dvec3 *face_to, ref_hit *out);
/** True when nothing blocks o + t d for t in (0, t_max). */
bool ref_visible(const ref_world *w, dvec3 o, dvec3 d, double t_max);
/** A ray origin just off the surface at `pos` on the side of `dir` (geometric normal ng), robust against
 *  self-intersection of Embree's float test: the offset scales with the coordinates' magnitude. */
dvec3 ref_offset(dvec3 pos, dvec3 ng, dvec3 dir);
/** The offset distance ref_offset uses at `pos`. */
double ref_offset_eps(dvec3 pos);
/** Linear albedo at a hit: base colour x the base colour texture (bilinear, repeat, sRGB-decoded texels),
 *  clamped to [0,1], as the G-buffer stores it. */
dvec3 ref_albedo(const ref_world *w, const ref_hit *h);
/** Uniform point on the emissive triangles (by area) from two uniform numbers; its unit geometric normal and
 *  emitter index. False when there are none. */
bool ref_sample_emitter(const ref_world *w, double u0, double u1, double u2, dvec3 *out_pos, dvec3 *out_ng,
                        uint32_t *out_emitter);

/* ---- random numbers ------------------------------------------------------------------------------------------ */
typedef struct ref_rng { uint64_t state; } ref_rng;
/** The stream of one pixel sample. */
ref_rng ref_rng_seed(uint64_t seed, uint32_t eye, uint32_t x, uint32_t y, uint32_t sample);
/** Uniform in [0, 1). */
double ref_rng_next(ref_rng *r);

/* ---- shading ------------------------------------------------------------------------------------------------- */
/** One sample of one pixel: the primary ray (o, d, t_max) from the eye at eye_pos (its view-projection vp, column
 *  major, for the depth view). Writes linear RGB. */
/* ---- one-bounce GI (reference_gi.c) -------------------------------------------------------------------------- */
/** One VPL: a texel of a light's reflective shadow map, as render/gi stores it, in double. */
typedef struct ref_vpl {
    dvec3 flux, pos, n; /* reflected flux (W), world position, unit normal facing the light */
    double r;           /* the texel's disk radius (m), bounding the 1/d^4 near the VPL */
} ref_vpl;
typedef struct ref_gi {
    bool enabled;
    ref_vpl *vpl;
    uint32_t count;
} ref_gi;
/** The VPLs of in->quality.gi (nothing when gi.enabled is off): ray-cast RSMs of the GPU's light views. */
FV_MUST_CHECK fv_result ref_gi_init(ref_gi *g, const ref_world *w, const fv_scene *scene, const fv_frame_input *in);
void ref_gi_fini(ref_gi *g);
/** The exact VPL sum at x (unit normal n), no visibility (the model). */
dvec3 ref_gi_irradiance(const ref_gi *g, dvec3 x, dvec3 n);

/** Invert a column-major 4x4 in double (false when singular), and the ray through image point (px, py) of a
 *  width x height view with inverse view-projection inv (near to far plane, unit direction), as the primary rays. */
bool ref_invert4(const double m[16], double out[16]);
bool ref_ray_from_inverse(const double inv[16], uint32_t width, uint32_t height, double px, double py, dvec3 *o,
                          dvec3 *d, double *t_max);

/* ---- subsurface scattering (reference_sss.c) ----------------------------------------------------------------- */
#include "fv_dipole.h"
#include "fv_sss_math.h"
/** A nominal texel left at its fine samples: its cluster (fv_sss_texel_cluster) and its fine samples
 *  fine[first .. first + count). */
typedef struct ref_sss_texel {
    fv_sss_cluster cluster;
    uint32_t first, count;
} ref_sss_texel;
typedef struct ref_sss_map {
    uint32_t material;
    double eta;
    fv_dipole dipole[3]; /* per channel, per metre */
    double flat_m;       /* the material's flat radius (fv_sss_flat_radius_m) */
    ref_light light;     /* the map's light: the direction it travels at a receiver */
    fv_sss_sample *samples; /* the resolved nominal texels (fv_sss_math.h) */
    uint32_t count;
    fv_sss_sample *fine;    /* the fine samples of the others, texel by texel */
    uint32_t fine_count;
    ref_sss_texel *texels;  /* the others: each its cluster and its fine samples */
    uint32_t texel_count;
} ref_sss_map;
typedef struct ref_sss {
    bool enabled;
    ref_sss_map map[FV_SSS_MAX_LAYERS];
    uint32_t count;
} ref_sss;
/** The samples of in->quality.sss (nothing when sss.enabled is off): ray-cast maps of the GPU's light views. */
FV_MUST_CHECK fv_result ref_sss_init(ref_sss *s, const ref_world *w, const fv_scene *scene, const fv_frame_input *in);
void ref_sss_fini(ref_sss *s);
/** Whether `material` has a map (its diffuse light is then the dipole's, as on the GPU). */
bool ref_sss_active(const ref_sss *s, uint32_t material);
/** Lo toward the eye at x (unit normal n, to_eye toward the eye): (1/pi) Ft(eta, wo) sum of flux x kernel, each
 *  footprint as the receiver's near field takes it (fv_sss_near_footprint). */
dvec3 ref_sss_radiance(const ref_sss *s, dvec3 x, dvec3 n, dvec3 to_eye, uint32_t material);
/** fv_light_irradiance in double (reference_shade.c): irradiance of L at pos with unit normal n; the unit direction
 *  toward the light and its distance (INFINITY for a directional light). */
dvec3 ref_light_irradiance(const ref_light *L, dvec3 pos, dvec3 n, dvec3 *out_l, double *out_dist);

typedef struct ref_pixel_ctx {
    const ref_world *w;
    const fv_reference_desc *desc; /* defaults applied */
    const ref_gi *gi;              /* model mode's one-bounce GI (NULL or empty: none) */
    const ref_sss *sss;            /* model mode's subsurface light (NULL or disabled: none) */
    dvec3 eye_pos;
    double vp[16];
} ref_pixel_ctx;

dvec3 ref_shade_model(const ref_pixel_ctx *c, dvec3 o, dvec3 d, double t_max, ref_counts *counts);
dvec3 ref_shade_path(const ref_pixel_ctx *c, dvec3 o, dvec3 d, double t_max, ref_rng *rng, ref_counts *counts);

#endif
