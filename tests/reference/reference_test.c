/* @brief Scene builders and views shared by the reference renderer's tests (see reference_test.h). */
#include "reference_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_renderer.h"
#include "fv_test.h"

static void add_node(fv_scene *s, const char *name, uint32_t mesh)
{
    fv_node n = fv_node_default();
    snprintf(n.name, sizeof n.name, "%s", name);
    n.mesh = (int32_t)mesh;
    assert_int_equal(fv_scene_add_node(s, &n, NULL), FV_OK);
}

/* A mesh of `nv` vertices and `ni` indices, arrays from malloc, as fv_scene_add_mesh takes them. */
static fv_mesh new_mesh(const char *name, uint32_t nv, uint32_t ni, uint32_t material)
{
    fv_mesh m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%s", name);
    m.vertex_count = nv;
    m.index_count = ni;
    m.positions = malloc(nv * sizeof *m.positions);
    m.normals = malloc(nv * sizeof *m.normals);
    m.indices = malloc(ni * sizeof *m.indices);
    assert_true(m.positions && m.normals && m.indices);
    m.material = material;
    return m;
}

uint32_t rt_material(fv_scene *s, fv_vec3 base_color, fv_vec3 emissive)
{
    fv_material m = fv_material_default();
    m.base_color = base_color;
    m.emissive = emissive;
    uint32_t i;
    assert_int_equal(fv_scene_add_material(s, &m, &i), FV_OK);
    return i;
}

void rt_add_square(fv_scene *s, const char *name, fv_vec3 c, double half, uint32_t material)
{
    fv_mesh m = new_mesh(name, 4, 6, material);
    float h = (float)half;
    fv_vec3 p[4] = {{c.x - h, c.y, c.z - h}, {c.x + h, c.y, c.z - h}, {c.x + h, c.y, c.z + h}, {c.x - h, c.y, c.z + h}};
    const uint32_t idx[6] = {0, 2, 1, 0, 3, 2};
    for (int i = 0; i < 4; i++) m.positions[i] = p[i], m.normals[i] = fv_v3(0, 1, 0);
    memcpy(m.indices, idx, sizeof idx);
    uint32_t mi;
    assert_int_equal(fv_scene_add_mesh(s, &m, &mi), FV_OK);
    add_node(s, name, mi);
}

void rt_add_box(fv_scene *s, fv_vec3 c, double half, uint32_t material)
{
    fv_mesh m = new_mesh("box", 24, 36, material);
    float h = (float)half;
    for (int f = 0; f < 6; f++) {
        int axis = f / 2;
        float sign = f % 2 ? 1.0f : -1.0f;
        int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (int k = 0; k < 4; k++) {
            float q[3] = {0, 0, 0};
            q[axis] = sign * h;
            q[u] = (k == 1 || k == 2) ? h : -h;
            q[v] = (k >= 2) ? h : -h;
            float n[3] = {0, 0, 0};
            n[axis] = sign;
            m.positions[4 * f + k] = fv_v3(c.x + q[0], c.y + q[1], c.z + q[2]);
            m.normals[4 * f + k] = fv_v3(n[0], n[1], n[2]);
        }
        const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
        for (int k = 0; k < 6; k++) m.indices[6 * f + k] = 4 * (uint32_t)f + idx[k];
    }
    uint32_t mi;
    assert_int_equal(fv_scene_add_mesh(s, &m, &mi), FV_OK);
    add_node(s, "box", mi);
}

uint32_t rt_add_triangles(fv_scene *s, const char *name, const fv_vec3 *points, uint32_t count, uint32_t material)
{
    fv_mesh m = new_mesh(name, count, count, material);
    for (uint32_t i = 0; i < count; i++) m.positions[i] = points[i], m.normals[i] = fv_v3(0, 1, 0), m.indices[i] = i;
    uint32_t mi;
    assert_int_equal(fv_scene_add_mesh(s, &m, &mi), FV_OK);
    add_node(s, name, mi);
    return mi;
}

fv_scene *rt_plane_scene(fv_vec3 albedo, double half)
{
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("reference test", &s), FV_OK);
    uint32_t mat = rt_material(s, albedo, fv_v3(0, 0, 0));
    rt_add_square(s, "plane", fv_v3(0, 0, 0), half, mat);
    s->head.position_m = fv_v3(0.0f, 1.2f, 0.0f);
    s->head.orientation = fv_quat_axis_angle(fv_v3(1, 0, 0), (float)(-FV_PI / 2)); /* -z onto -y */
    return s;
}

fv_light rt_light(fv_light_type type, fv_vec3 position_m, fv_vec3 dir, fv_vec3 color, float intensity)
{
    fv_light l;
    memset(&l, 0, sizeof l);
    l.type = type;
    l.position_m = position_m;
    l.direction = dir;
    l.color = color;
    l.intensity = intensity;
    l.inner_cone_rad = (float)fv_deg_to_rad(15.0);
    l.outer_cone_rad = (float)fv_deg_to_rad(30.0);
    return l;
}

fv_frame_input rt_views(const fv_head *head, uint32_t w, uint32_t h)
{
    fv_frame_input in;
    fv_frame_input_from_head(head, 0.1f, 10.0f, w, h, 0, 0.0, &in);
    in.quality.fovea.enabled = false; /* full resolution (foveation has its own tests) */
    return in;
}

fv_frame_input rt_views_auto(const fv_scene *s, uint32_t w, uint32_t h)
{
    fv_vec3 lo, hi;
    float n = 0, f = 0;
    if (fv_scene_world_bounds(s, 0.0, &lo, &hi)) fv_frame_near_far_from_bounds(&s->head, lo, hi, &n, &f);
    fv_frame_input in;
    fv_frame_input_from_head(&s->head, n, f, w, h, 0, 0.0, &in);
    in.quality.fovea.enabled = false; /* full resolution (foveation has its own tests) */
    return in;
}

float *rt_image(uint32_t w, uint32_t h)
{
    float *p = calloc((size_t)w * h * 3, sizeof *p);
    assert_non_null(p);
    return p;
}

double *rt_image_f64(uint32_t w, uint32_t h)
{
    double *p = calloc((size_t)w * h * 3, sizeof *p);
    assert_non_null(p);
    return p;
}
