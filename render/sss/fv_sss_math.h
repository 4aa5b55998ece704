/* @brief The geometry of subsurface scattering's light-view sample maps, without a GPU (shared by the pass and the
 * CPU reference): which (light, translucent material) pairs get a map, the world bounds of a material's draws, each
 * map's view-projection fitted to those bounds, and the surface area one texel covers. */
#ifndef FV_SSS_MATH_H
#define FV_SSS_MATH_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_dipole.h"
#include "fv_math.h"
#include "fv_scene.h"

/** The most maps (light x translucent material pairs); later pairs are left out (and the plan says so). */
#define FV_SSS_MAX_LAYERS 7
/** The lights considered (the first ones of the scene). */
#define FV_SSS_MAX_LIGHTS 4
/** The smallest cosine between a sample's normal and the light used for its area: a texel seen at grazing covers
 *  texel / cos of surface, capped at 1 / FV_SSS_MIN_COS times the texel. */
#define FV_SSS_MIN_COS 0.1
/** A map's widest half-angle from a point or spot light (a light inside the object's bounds sees only this cone). */
#define FV_SSS_MAX_HALF_ANGLE_DEG 80.0

typedef struct fv_sss_pair {
    uint32_t light, material;
} fv_sss_pair;

/** The translucent materials some drawn node uses, by index (at most cap); returns how many there are in all. */
uint32_t fv_sss_translucent_materials(const fv_scene *s, uint32_t *out, uint32_t cap);
/** The maps the scene gets: every light (< FV_SSS_MAX_LIGHTS) with every translucent material, light-major, at most
 *  FV_SSS_MAX_LAYERS; *out_wanted (may be NULL) gets how many pairs there would be without the cap. */
uint32_t fv_sss_pairs(const fv_scene *s, fv_sss_pair out[FV_SSS_MAX_LAYERS], uint32_t *out_wanted);
/** World bounds at t_s of the drawn nodes whose mesh uses `material`; false when there are none. */
bool fv_sss_material_bounds(const fv_scene *s, uint32_t material, double t_s, fv_vec3 *out_min, fv_vec3 *out_max);

/** A translucent material's dipole per RGB channel in the renderer's units (metres: the coefficients' mm^-1 times
 *  1000; non-finite or negative coefficients count as 0, eta outside (0, inf) as 1), as the GPU's fv_sss_dipole_of
 *  derives it in float. Returns eta as used. */
double fv_sss_material_dipoles(const fv_translucency *t, fv_dipole out[3]);

/** The cutoff radius of a material (m, knob sss.cutoff): the largest of its channels' fv_dipole_cutoff_radius(
 *  fraction); clusters wholly farther than it from a receiver are skipped. 0 = none (no scattering, or fraction
 *  outside (0, 1)). */
double fv_sss_cutoff_radius_m(const fv_translucency *t, double fraction);

/** One light-view map. */
typedef struct fv_sss_view {
    fv_mat4 view_proj;  /* world -> Vulkan clip of the map (y down, depth 0..1) */
    bool perspective;   /* point/spot: from the light; directional: orthographic along it */
    fv_vec3 origin;     /* perspective: the light's position */
    fv_vec3 axis;       /* unit: the map's forward direction (the way the light travels at its centre) */
    double texel_m;     /* orthographic: a texel's side in metres */
    double tan_half;    /* perspective: tangent of the half-angle */
    uint32_t size;      /* texels per side */
} fv_sss_view;

/** Fit a map of `size` texels to the bounding sphere of [obj_min, obj_max] as seen from a light of `type`
 *  (FV_LIGHT_*) at `pos` travelling along `dir`; the depth range reaches back to [scene_min, scene_max] so every
 *  occluder between the light and the object is drawn. False (out zeroed) for degenerate input. */
bool fv_sss_light_view(uint32_t type, fv_vec3 pos, fv_vec3 dir, fv_vec3 obj_min, fv_vec3 obj_max, fv_vec3 scene_min,
                       fv_vec3 scene_max, uint32_t size, fv_sss_view *out);
/** The surface area (m^2) one texel of the map covers at world point p whose unit normal makes cosine cos_i with
 *  the direction to the light: orthographic texel^2 / cos; perspective the texel's solid angle
 *  (2 tan_half / size)^2 cos^3(angle off the axis) times distance^2 / cos; cos clamped to FV_SSS_MIN_COS. */
double fv_sss_texel_area(const fv_sss_view *v, fv_vec3 p, double cos_i);
/** The footprint of the texel whose sample lies at world point p with unit normal n (either side; the side facing
 *  the light is taken): the parallelogram p +- a/2 +- b/2 that the texel's square (its sides along the map's x and y
 *  axes, the first two rows of view_proj) cuts from the surface's tangent plane, carried along the light's ray
 *  (orthographic: the map's axis; perspective: from the light through p). Where the light grazes (cos_i <
 *  FV_SSS_MIN_COS) the plane is tilted toward the light to that cosine, so |a x b| = fv_sss_texel_area always.
 *  Neighbouring texels' footprints on a plane tile it exactly (fv_dipole_tile_kernel). False (a, b zero) for a
 *  degenerate view, normal or point. The GPU's copy is render/sss/sss_map.frag. */
bool fv_sss_texel_footprint(const fv_sss_view *v, fv_vec3 p, fv_vec3 n, fv_vec3 *out_a, fv_vec3 *out_b);

/* ---- where the light grazes: the map drawn finer (issue 28 item 5) ------------------------------------------
 * Near the light's silhouette one texel column covers many texels of surface along the light (at 128 px on a
 * sphere of 80 mm, the last texel of a row spans up to 19 mm of arc), and which texels the silhouette's staircase
 * keeps, where their rays meet the surface and how far their footprints reach changes from row to row: the dipole's
 * sub-millimetre light just past the terminator showed each step (dim streaks along the texel columns). So the map is
 * drawn 2^s times finer per side (the fine map: s sub-levels below the nominal texels of sss.map_size), and each
 * nominal texel whose fine samples are all present and lit at a cosine of at least FV_SSS_RESOLVE_COS is resolved
 * into one sample (their flux and area summed, centroid and normal area-weighted, the footprint 2^s times the
 * mean of theirs: on a plane exactly the nominal texel's); every other nominal texel (grazing, at the silhouette,
 * at a shadow's or the object's edge) keeps its fine samples. */
/** The sub-levels s below the nominal texels... */
#define FV_SSS_SUB_LEVELS 2
/** ... as far as a fine map of this side (leaf level 9: the GPU's Morton indices and its node buffer). */
#define FV_SSS_FINE_MAX 1024
/** A nominal texel is resolved into one sample when every fine sample's cosine to the light is at least this. */
#define FV_SSS_RESOLVE_COS 0.3

/** The sub-levels s of a map of `size` (nominal) texels per side: FV_SSS_SUB_LEVELS, fewer where the fine map
 *  (size 2^s) would pass FV_SSS_FINE_MAX; 0 for a size that is not a power of two in [1, FV_SSS_FINE_MAX]. */
uint32_t fv_sss_sub_levels(uint32_t size);

/** One light-view sample (of the fine map, or a resolved nominal texel), in double. */
typedef struct fv_sss_sample {
    double pos[3];  /* world position (m) */
    double flux[3]; /* flux entering the surface E A (W) */
    double area;    /* surface area (m^2); 0 = no sample */
    double n[3];    /* normal facing the light (unit for a fine sample; a resolved one: the area-weighted mean) */
    double a[3], b[3]; /* the footprint pos +- a/2 +- b/2 (fv_sss_texel_footprint) */
    double cos_i;   /* cosine between the normal and the direction to the light (a fine sample) */
} fv_sss_sample;

/** Whether the count = 4^s fine samples `sub` of one nominal texel (any order) resolve into one (all present, every
 *  cos_i >= FV_SSS_RESOLVE_COS), and if so that sample in *out: flux and area summed, position and normal
 *  area-weighted, the footprint's edges the sum of theirs over 2^s. The GPU's copy is render/sss/sss_build.comp. */
bool fv_sss_texel_resolve(const fv_sss_sample *sub, uint32_t count, uint32_t sub_levels, fv_sss_sample *out);

/** A nominal texel left at its fine samples (fv_sss_texel_resolve false) as the GPU's quad-tree build makes its node
 *  (render/sss/sss_build.comp): area and flux summed, position and normal area-weighted (the normal not normalised),
 *  its reach (the radius around its centroid that holds every fine footprint's half-diagonal, built level by level
 *  as the GPU's) and the widest half-diagonal among its fine footprints. Both sums (the GPU's exact mode and the
 *  reference) and the hierarchy walk its fine samples only where the receiver's near field reaches it
 *  (fv_sss_cluster_near) and beyond take it as one disk of its area (fv_sss_near_cluster, fv_dipole_kernel). */
typedef struct fv_sss_cluster {
    double pos[3], flux[3], n[3];
    double area;   /* m^2; 0: no fine sample */
    double reach;  /* m */
    double widest; /* m */
} fv_sss_cluster;

/** The cluster of the count = 4^s fine samples `sub` of one nominal texel, in row-major order (k = 2^s per side:
 *  sample q at (q % k, q / k)); empty ones (area 0) left out. False (and *out zero) when none is present. */
bool fv_sss_texel_cluster(const fv_sss_sample *sub, uint32_t count, uint32_t sub_levels, fv_sss_cluster *out);

/* ---- the receiver's near field (issue 28 item 5) -------------------------------------------------------------
 * Near a receiver the surface is taken as its tangent plane: each sample's footprint is carried along the light
 * onto that plane (the texel columns cut it into footprints that tile it exactly, and the flux of each column is
 * spread at the density the receiver's own normal gives), blended by a weight beta into the footprint as cast (its
 * own position and plane) with distance. On a mesh whose samples lie on flat facets while the shading follows the
 * interpolated normal, the footprints as cast leave gaps and overlaps where the facets bend (bands of several
 * percent with the facets and the texel rows, at any map size); carried onto the receiver's plane they tile it, and
 * the sum converges with the map's size. */
/** The flat radius holds all but this fraction of a point source's diffuse reflectance (fv_dipole_cutoff_radius):
 *  marble 4 mm. */
#define FV_SSS_FLAT_FRACTION 0.25
/** ... and at least this many half-diagonals of the sample's footprint (its neighbours on a coarse map). */
#define FV_SSS_FLAT_FOOTPRINTS 2.0
/** beta: 1 within the flat distance d1 = max(flat radius, FV_SSS_FLAT_FOOTPRINTS half-diagonals), 0 beyond 2 d1;
 *  times a smoothstep of the receiver's cosine to the light over [FV_SSS_FLAT_COS_LO, FV_SSS_FLAT_COS_HI] (at the
 *  terminator the plane would hold the light's direction) and one of the cosine between the sample's and the
 *  receiver's normals over [FV_SSS_FLAT_NORMAL_LO, FV_SSS_FLAT_NORMAL_HI] (another sheet, an edge: as cast). */
#define FV_SSS_FLAT_COS_LO 0.05
#define FV_SSS_FLAT_COS_HI 0.2
#define FV_SSS_FLAT_NORMAL_LO 0.7
#define FV_SSS_FLAT_NORMAL_HI 0.9

/** A material's flat radius (m): the largest of its channels' fv_dipole_cutoff_radius(FV_SSS_FLAT_FRACTION);
 *  0 without scattering. */
double fv_sss_flat_radius_m(const fv_translucency *t);

/** A receiver as its near field needs it. */
typedef struct fv_sss_receiver {
    double x[3];   /* position (m) */
    double n[3];   /* unit shading normal */
    double nc[3];  /* the plane's normal: n tilted toward the light to a cosine of at least FV_SSS_MIN_COS */
    double w[3];   /* unit direction the light travels at x */
    double wn;     /* w . nc (at most -FV_SSS_MIN_COS) */
    double facing; /* the receiver's cosine weight, 0..1 */
    double flat_m; /* the material's flat radius */
} fv_sss_receiver;

/** The receiver at x with unit normal n (as shaded: facing the eye) lit along w (the unit direction the light
 *  travels at x: a directional light's direction, or from a spot or point light to x), for a material of flat
 *  radius flat_m. Facing away from the light (the dark side), a degenerate normal or direction: facing 0 (every
 *  footprint as cast). */
void fv_sss_receiver_make(const double x[3], const double n[3], const double w[3], double flat_m,
                          fv_sss_receiver *out);

/** The footprint of a sample (centre c, edges a, b: fv_sss_texel_footprint; n_s its unit normal facing the light)
 *  as the receiver's sum takes it: carried along w by the fraction beta of the way onto the receiver's plane,
 *  c' = c + beta t_c w with t_c = ((x - c) . nc) / wn, and each edge e' = e - beta ((e . nc) / wn) w. Returns beta
 *  (0: out = the footprint as cast; also for a footprint that is not finite). The GPU's copy is
 *  render/include/fv_sss_gather.glsl's fv_sss_near_footprint. */
double fv_sss_near_footprint(const fv_sss_receiver *r, const double c[3], const double a[3], const double b[3],
                             const double n_s[3], double out_c[3], double out_a[3], double out_b[3]);

/** Whether the receiver's near field reaches the cluster, the hierarchy's test (render/include/fv_sss_gather.glsl):
 *  |c - x| - reach < max(flat radius, FV_SSS_FLAT_FOOTPRINTS x widest). */
bool fv_sss_cluster_near(const fv_sss_receiver *r, const fv_sss_cluster *c);

/** The cluster's centroid carried as fv_sss_near_footprint carries a footprint whose half-diagonal is the cluster's
 *  widest (the GPU's fv_sss_near_footprint with the node's edge_b.w), for the disk of its area. Returns beta. */
double fv_sss_near_cluster(const fv_sss_receiver *r, const fv_sss_cluster *c, double out_c[3]);

#endif
