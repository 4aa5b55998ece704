/* @brief Scene builders and views shared by the reference renderer's tests (tests/reference). Every helper fails the
 * running cmocka test on error. */
#ifndef FV_REFERENCE_TEST_H
#define FV_REFERENCE_TEST_H

#include <stdint.h>

#include "fovea/fv_frame_input.h"
#include "fv_scene.h"

/** A scene with one material (albedo, no emission) on a square of half-size `half` m in the plane y = 0 (normal
 *  +y), a node per mesh, the head 1.2 m above the origin looking straight down, no light. */
fv_scene *rt_plane_scene(fv_vec3 albedo, double half);
/** Append a material; returns its index. */
uint32_t rt_material(fv_scene *s, fv_vec3 base_color, fv_vec3 emissive);
/** A horizontal square (normal +y) of half-size `half` m centred at `centre`, as a mesh and a node. */
void rt_add_square(fv_scene *s, const char *name, fv_vec3 centre, double half, uint32_t material);
/** A closed axis-aligned cube of half-size `half` m (outward face normals), as a mesh and a node. */
void rt_add_box(fv_scene *s, fv_vec3 centre, double half, uint32_t material);
/** Triangles from `count` points (a multiple of 3), normals +y, as a mesh and a node; returns the mesh index. */
uint32_t rt_add_triangles(fv_scene *s, const char *name, const fv_vec3 *points, uint32_t count, uint32_t material);
/** A light of this type (cones 15/30 deg for a spot, no range); dir is ignored by point lights. */
fv_light rt_light(fv_light_type type, fv_vec3 position_m, fv_vec3 dir, fv_vec3 color, float intensity);
/** Both eyes' views from a head (near 0.1 m, far 10 m) at time 0. */
fv_frame_input rt_views(const fv_head *head, uint32_t w, uint32_t h);
/** The views `fovea run` draws for a scene's frame 0 (near/far from its bounds). */
fv_frame_input rt_views_auto(const fv_scene *s, uint32_t w, uint32_t h);
/** Zeroed w x h RGB images (caller frees). */
float *rt_image(uint32_t w, uint32_t h);
double *rt_image_f64(uint32_t w, uint32_t h);

#endif
