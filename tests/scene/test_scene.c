/* @brief Scene model: building in code, transforms and animation, queries, validation, framing, the built-in
 * Cornell scenes and the Jensen 2001 presets (checked against shared/data/materials/jensen2001.csv). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_scene.h"
#include "fv_test.h"

static fv_mesh make_triangle(const char *name, float size)
{
    fv_mesh m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%s", name);
    m.vertex_count = 3;
    m.index_count = 3;
    m.positions = malloc(3 * sizeof *m.positions);
    m.indices = malloc(3 * sizeof *m.indices);
    m.positions[0] = fv_v3(0, 0, 0);
    m.positions[1] = fv_v3(size, 0, 0);
    m.positions[2] = fv_v3(0, size, 0);
    for (uint32_t i = 0; i < 3; i++) m.indices[i] = i;
    return m;
}

static void assert_near(double a, double b, double tol)
{
    if (!(fabs(a - b) <= tol)) fail_msg("%.9g is not within %.3g of %.9g", a, tol, b);
}

static const fv_mesh *mesh_named(const fv_scene *s, const char *name)
{
    for (uint32_t i = 0; i < s->mesh_count; i++)
        if (!strcmp(s->meshes[i].name, name)) return &s->meshes[i];
    fail_msg("no mesh named %s", name);
    return NULL;
}

static void scene_built_in_code_has_counts_bounds_and_generated_normals(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("code", &s), FV_OK);
    assert_float_equal(s->head.ipd_mm, 63.0f, 1e-6f);
    fv_material mat = fv_material_default();
    uint32_t mi, mesh_i, root_i, child_i;
    assert_int_equal(fv_scene_add_material(s, &mat, &mi), FV_OK);
    /* Many adds: the arrays grow and keep earlier contents. */
    for (int i = 0; i < 40; i++) {
        fv_mesh m = make_triangle("tri", 1.0f + (float)i);
        m.material = mi;
        assert_int_equal(fv_scene_add_mesh(s, &m, &mesh_i), FV_OK);
        assert_int_equal(mesh_i, (uint32_t)i);
    }
    assert_float_equal(s->meshes[0].bounds_max.x, 1.0f, 1e-6f);
    assert_float_equal(s->meshes[39].bounds_max.y, 40.0f, 1e-6f);
    /* generated normals: the triangle faces +z */
    assert_non_null(s->meshes[0].normals);
    assert_float_equal(s->meshes[0].normals[1].z, 1.0f, 1e-6f);

    fv_node root = fv_node_default();
    root.translation_m = fv_v3(10, 0, 0);
    root.mesh = 0;
    assert_int_equal(fv_scene_add_node(s, &root, &root_i), FV_OK);
    fv_node child = fv_node_default();
    child.parent = (int32_t)root_i;
    child.translation_m = fv_v3(0, 5, 0);
    child.scale = fv_v3(2, 2, 2);
    child.mesh = 1;
    assert_int_equal(fv_scene_add_node(s, &child, &child_i), FV_OK);
    fv_node transform_only = fv_node_default();
    assert_int_equal(fv_scene_add_node(s, &transform_only, NULL), FV_OK);

    assert_int_equal(fv_scene_triangle_count(s), 2);
    fv_mat4 w = fv_scene_node_world(s, child_i, 0.0);
    fv_vec3 p = fv_mat4_mul_point(&w, fv_v3(1, 0, 0));
    assert_near(p.x, 12.0, 1e-5);
    assert_near(p.y, 5.0, 1e-5);
    fv_vec3 lo, hi;
    assert_true(fv_scene_world_bounds(s, 0.0, &lo, &hi));
    assert_near(lo.x, 10.0, 1e-5);
    assert_near(hi.x, 14.0, 1e-5); /* child: 10 + 2 * 2 */
    assert_near(hi.y, 9.0, 1e-5);  /* child: 5 + 2 * 2 */
    assert_false(fv_scene_is_animated(s));
    assert_false(fv_scene_has_translucency(s));
    assert_int_equal(fv_scene_validate(s), FV_OK);

    /* A node whose parent is not yet added is refused. */
    fv_node orphan = fv_node_default();
    orphan.parent = 99;
    fv_test_log_capture_begin();
    assert_int_equal(fv_scene_add_node(s, &orphan, NULL), FV_ERR_INVALID_ARG);
    fv_test_log_capture_end();
    fv_scene_destroy(&s);
    assert_null(s);
    fv_scene_destroy(&s); /* safe on NULL */
}

static void animation_rotates_about_the_node_origin_and_parents_follow(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("anim", &s), FV_OK);
    fv_node spin = fv_node_default();
    spin.translation_m = fv_v3(1, 0, 0);
    spin.anim.kind = FV_ANIM_ROTATE;
    spin.anim.axis = fv_v3(0, 1, 0);
    spin.anim.rate_rad_s = (float)(FV_PI / 2); /* a quarter turn per second */
    uint32_t a;
    assert_int_equal(fv_scene_add_node(s, &spin, &a), FV_OK);
    fv_node child = fv_node_default();
    child.parent = (int32_t)a;
    uint32_t b;
    assert_int_equal(fv_scene_add_node(s, &child, &b), FV_OK);
    assert_true(fv_scene_is_animated(s));
    /* After 1 s the local point (0,0,-1) has turned a quarter turn about +y: to (-1,0,0), plus the origin (1,0,0). */
    fv_mat4 w = fv_scene_node_world(s, b, 1.0);
    fv_vec3 p = fv_mat4_mul_point(&w, fv_v3(0, 0, -1));
    assert_near(p.x, 0.0, 1e-5);
    assert_near(p.z, 0.0, 1e-5);
    /* The node origin does not move. */
    fv_vec3 o = fv_mat4_mul_point(&w, fv_v3(0, 0, 0));
    assert_near(o.x, 1.0, 1e-6);
    /* Bob and pulse */
    s->nodes[a].anim.kind = FV_ANIM_BOB;
    s->nodes[a].anim.amplitude_m = fv_v3(0, 0.5f, 0);
    s->nodes[a].anim.freq_hz = 1.0f;
    w = fv_scene_node_world(s, a, 0.25);
    assert_near(fv_mat4_mul_point(&w, fv_v3(0, 0, 0)).y, 0.5, 1e-5);
    s->nodes[a].anim.kind = FV_ANIM_PULSE;
    s->nodes[a].anim.amplitude_m = fv_v3(0.5f, 0, 0);
    w = fv_scene_node_world(s, a, 0.25);
    assert_near(fv_mat4_mul_point(&w, fv_v3(1, 0, 0)).x, 1.0 + 1.5, 1e-5);
    /* Extremes: very long run times stay finite (angle reduced in double). */
    s->nodes[a].anim.kind = FV_ANIM_ROTATE;
    for (double t = 1e3; t <= 1e12; t *= 1e3) {
        w = fv_scene_node_world(s, b, t);
        fv_vec3 q = fv_mat4_mul_point(&w, fv_v3(0, 0, -1));
        assert_true(fv_v3_isfinite(q));
        assert_near(fv_v3_len(fv_v3_sub(q, fv_v3(1, 0, 0))), 1.0, 1e-4);
    }
    /* Out-of-range node index: identity, no read past the array. */
    w = fv_scene_node_world(s, 1000, 0.0);
    assert_float_equal(w.m[0][0], 1.0f, 0.0f);
    fv_scene_destroy(&s);
}

static void bad_meshes_are_refused_and_their_arrays_freed(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("bad", &s), FV_OK);
    fv_test_log_capture_begin();
    fv_mesh m = make_triangle("past_end", 1.0f);
    m.indices[2] = 3;
    assert_int_equal(fv_scene_add_mesh(s, &m, NULL), FV_ERR_PARSE);
    fv_assert_log_contains("mesh 'past_end': index 3");
    fv_assert_log_contains("past the vertex count 3");
    fv_mesh n = make_triangle("nan_vertex", 1.0f);
    n.positions[1].y = NAN;
    assert_int_equal(fv_scene_add_mesh(s, &n, NULL), FV_ERR_RANGE);
    fv_assert_log_contains("mesh 'nan_vertex': vertex 1 has a non-finite position");
    fv_mesh h = make_triangle("huge", 1.0f);
    h.vertex_count = FV_SCENE_MAX_VERTICES + 1;
    assert_int_equal(fv_scene_add_mesh(s, &h, NULL), FV_ERR_RANGE);
    fv_assert_log_contains("exceed the limits");
    fv_test_log_capture_end();
    assert_int_equal(s->mesh_count, 0);
    fv_scene_destroy(&s); /* LeakSanitizer proves the refused arrays were freed */
}

static void validate_reports_each_broken_rule(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("broken", &s), FV_OK);
    fv_material m = fv_material_default();
    assert_int_equal(fv_translucency_preset("marble", &m.translucency), FV_OK);
    m.translucency.sigma_a_per_mm[1] = -0.5f;
    m.translucency.eta = NAN;
    assert_int_equal(fv_scene_add_material(s, &m, NULL), FV_OK);
    fv_mesh t = make_triangle("tri", 1.0f);
    t.material = 7; /* no such material */
    assert_int_equal(fv_scene_add_mesh(s, &t, NULL), FV_OK);
    fv_light l;
    memset(&l, 0, sizeof l);
    l.type = FV_LIGHT_SPOT;
    l.direction = fv_v3(0, 0, 0);
    l.intensity = -1;
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    s->head.ipd_mm = INFINITY;
    fv_test_log_capture_begin();
    assert_int_equal(fv_scene_validate(s), FV_ERR_PARSE);
    fv_assert_log_contains("sigma_a_per_mm[1] = -0.5 is negative; a coefficient is 0 or in 1e-06..1e+06 mm^-1");
    fv_assert_log_contains("eta nan must be > 0");
    fv_assert_log_contains("mesh 0 'tri': material 7 does not exist");
    fv_assert_log_contains("direction is zero");
    fv_assert_log_contains("negative colour, intensity or range");
    fv_assert_log_contains("head: ipd_mm inf");
    fv_test_log_capture_end();
    fv_scene_destroy(&s);
}

static void frame_head_puts_the_whole_scene_in_the_hmd_field_of_view(void **state)
{
    (void)state;
    const float sizes[] = {1e-4f, 0.3f, 10.0f, 5e4f};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        fv_scene *s = NULL;
        assert_int_equal(fv_scene_create("frame", &s), FV_OK);
        fv_material mat = fv_material_default();
        assert_int_equal(fv_scene_add_material(s, &mat, NULL), FV_OK);
        fv_mesh m = make_triangle("t", sizes[k]);
        uint32_t mi;
        assert_int_equal(fv_scene_add_mesh(s, &m, &mi), FV_OK);
        fv_node n = fv_node_default();
        n.mesh = (int32_t)mi;
        n.translation_m = fv_v3(3, -2, 1);
        assert_int_equal(fv_scene_add_node(s, &n, NULL), FV_OK);
        fv_scene_frame_head(s);
        assert_false(s->head.from_file);
        assert_true(fv_v3_isfinite(s->head.position_m));
        fv_vec3 fwd = fv_quat_rotate(s->head.orientation, fv_v3(0, 0, -1));
        assert_true(fwd.z < -0.999f); /* looks along -z from the +z side */
        fv_vec3 lo, hi;
        assert_true(fv_scene_world_bounds(s, 0, &lo, &hi));
        for (int c = 0; c < 8; c++) {
            fv_vec3 p = fv_v3((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
            fv_vec3 d = fv_v3_normalize_or(fv_v3_sub(p, s->head.position_m), fv_v3(0, 0, 0));
            double ang = fv_rad_to_deg(acos(fv_clampf(fv_v3_dot(d, fwd), -1, 1)));
            if (!(ang < 42.0)) fail_msg("size %g: corner %d is %.1f deg off axis", (double)sizes[k], c, ang);
        }
        fv_scene_destroy(&s);
    }
    /* Empty scene: nothing to frame, still finite. */
    fv_scene *e = NULL;
    assert_int_equal(fv_scene_create("empty", &e), FV_OK);
    fv_scene_frame_head(e);
    assert_true(fv_v3_isfinite(e->head.position_m));
    assert_false(fv_scene_world_bounds(e, 0, NULL, NULL));
    fv_scene_destroy(&e);
}

static void builtin_cornell_has_red_left_wall_green_right_wall_and_a_spot_aiming_down(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("cornell", &s), FV_OK);
    assert_string_equal(s->source, "builtin:cornell");
    assert_int_equal(fv_scene_validate(s), FV_OK);
    const fv_mesh *red = mesh_named(s, "left_wall_red");
    const fv_mesh *green = mesh_named(s, "right_wall_green");
    const fv_material *rm = &s->materials[red->material];
    const fv_material *gm = &s->materials[green->material];
    assert_true(rm->base_color.x > 0.5f && rm->base_color.y < 0.1f && rm->base_color.z < 0.1f);
    assert_true(gm->base_color.y > 0.4f && gm->base_color.x < 0.2f && gm->base_color.z < 0.1f);
    /* The viewer looks along -z, so left is -x: the red wall at x = -0.278 m, the green one at +0.278 m. */
    assert_true(red->bounds_max.x < -0.27f && red->bounds_min.x > -0.29f);
    assert_true(green->bounds_min.x > 0.27f);
    assert_true(red->normals[0].x > 0.99f);   /* facing into the box */
    assert_true(green->normals[0].x < -0.99f);
    fv_vec3 lo, hi;
    assert_true(fv_scene_world_bounds(s, 0.0, &lo, &hi));
    assert_near(lo.y, 0.0, 1e-6);
    assert_near(hi.y, 0.5488, 1e-4);
    assert_near(hi.x - lo.x, 0.556, 2e-3);
    assert_near(hi.z - lo.z, 0.5592, 1e-4);
    /* Floor normal up, ceiling normal down, back wall normal towards the viewer. */
    const fv_mesh *white = mesh_named(s, "white_walls");
    assert_true(white->normals[0].y > 0.99f && white->normals[4].y < -0.99f && white->normals[8].z > 0.99f);
    /* two blocks, standing on the floor, the tall one twice the height */
    const fv_mesh *sb = mesh_named(s, "short_block");
    const fv_mesh *tb = mesh_named(s, "tall_block");
    assert_near(sb->bounds_max.y, 0.165, 1e-5);
    assert_near(tb->bounds_max.y, 0.330, 1e-5);
    assert_near(tb->bounds_min.y, 0.0, 1e-6);
    assert_true(tb->bounds_max.x < 0.05f); /* tall block at the back left, short at the front right */
    assert_true(sb->bounds_min.x > -0.02f && sb->bounds_max.z > tb->bounds_max.z);
    assert_int_equal(s->light_count, 1);
    assert_int_equal(s->lights[0].type, FV_LIGHT_SPOT);
    assert_true(s->lights[0].direction.y < -0.999f);
    assert_true(s->lights[0].position_m.y > 0.5f && s->lights[0].position_m.y < 0.5488f);
    assert_true(s->head.from_file);
    assert_float_equal(s->head.ipd_mm, 63.0f, 1e-6f);
    assert_true(s->head.position_m.z > hi.z); /* in front of the open side */
    fv_vec3 fwd = fv_quat_rotate(s->head.orientation, fv_v3(0, 0, -1));
    assert_true(fwd.z < -0.999f);
    assert_false(fv_scene_has_translucency(s));
    assert_false(fv_scene_is_animated(s));
    /* walls: 5 quads, blocks: 2 x 5 quads, lamp: 1 quad */
    assert_int_equal(fv_scene_triangle_count(s), 2 * (5 + 10 + 1));
    for (uint32_t i = 0; i < s->mesh_count; i++) assert_non_null(s->meshes[i].texcoords);
    fv_scene_destroy(&s);
}

static void builtin_cornell_translucent_adds_a_marble_sphere(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("builtin:cornell-translucent", &s), FV_OK);
    assert_true(fv_scene_has_translucency(s));
    const fv_mesh *sp = mesh_named(s, "marble_sphere");
    const fv_material *m = &s->materials[sp->material];
    assert_true(m->translucency.enabled);
    assert_string_equal(m->translucency.preset, "Marble");
    assert_float_equal(m->translucency.sigma_s_prime_per_mm[0], 2.19f, 1e-6f);
    assert_float_equal(m->translucency.eta, 1.5f, 1e-6f);
    assert_near(sp->bounds_min.y, 0.0, 1e-5); /* resting on the floor */
    /* radial normals of unit length */
    for (uint32_t v = 0; v < sp->vertex_count; v++) assert_near(fv_v3_len(sp->normals[v]), 1.0, 1e-5);
    /* the sphere must not intersect either block */
    const fv_mesh *tb = mesh_named(s, "tall_block");
    const fv_mesh *sb = mesh_named(s, "short_block");
    assert_true(sp->bounds_max.z < tb->bounds_min.z || sp->bounds_min.z > tb->bounds_max.z ||
                sp->bounds_max.x < tb->bounds_min.x);
    assert_true(sp->bounds_max.x < sb->bounds_min.x);
    fv_scene_destroy(&s);
    fv_test_log_capture_begin();
    assert_int_equal(fv_scene_builtin("cornel", &s), FV_ERR_NOT_FOUND);
    fv_assert_log_contains("builtin:cornel: no built-in scene");
    fv_test_log_capture_end();
    const char *const *names = fv_scene_builtin_names();
    assert_string_equal(names[0], "cornell");
    assert_string_equal(names[1], "cornell-translucent");
    assert_string_equal(names[2], "pillars");
    assert_null(names[3]);
}

/* Read the CSV and compare it with the C table row by row. */
static void presets_equal_the_jensen2001_csv_row_by_row(void **state)
{
    (void)state;
    FILE *f = fopen(fv_test_data("materials/jensen2001.csv"), "r");
    assert_non_null(f);
    char line[512];
    assert_non_null(fgets(line, sizeof line, f)); /* header */
    assert_non_null(strstr(line, "sigma_s_prime_r_per_mm"));
    const char *const *names = fv_translucency_preset_names();
    int rows = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '\n' || line[0] == '\0') continue;
        char name[64], checked[8];
        double sp[3], sa[3], eta;
        int n = sscanf(line, "%63[^,],%lf,%lf,%lf,%lf,%lf,%lf,%lf,%7s", name, &sp[0], &sp[1], &sp[2], &sa[0], &sa[1],
                       &sa[2], &eta, checked);
        assert_int_equal(n, 9);
        assert_non_null(names[rows]);
        assert_string_equal(names[rows], name); /* same order */
        fv_translucency t;
        assert_int_equal(fv_translucency_preset(name, &t), FV_OK);
        assert_true(t.enabled);
        for (int c = 0; c < 3; c++) {
            assert_float_equal(t.sigma_s_prime_per_mm[c], (float)sp[c], 0.0f);
            assert_float_equal(t.sigma_a_per_mm[c], (float)sa[c], 0.0f);
        }
        assert_float_equal(t.eta, (float)eta, 0.0f);
        rows++;
    }
    fclose(f);
    assert_int_equal(rows, 12);
    assert_null(names[12]);
    fv_translucency t;
    assert_int_equal(fv_translucency_preset("MARBLE", &t), FV_OK);
    assert_string_equal(t.preset, "Marble");
    assert_int_equal(fv_translucency_preset("skin1", &t), FV_OK);
    assert_float_equal(t.sigma_a_per_mm[2], 0.48f, 0.0f);
    assert_int_equal(fv_translucency_preset("Spectralon", &t), FV_OK);
    assert_float_equal(t.sigma_a_per_mm[0], 0.0f, 0.0f); /* sigma_a = 0 edge case is valid */
    assert_int_equal(fv_translucency_preset("marble ", &t), FV_ERR_NOT_FOUND);
    assert_int_equal(fv_translucency_preset("jade", &t), FV_ERR_NOT_FOUND);
}

static void head_look_at_handles_straight_down_and_degenerate_targets(void **state)
{
    (void)state;
    fv_head h;
    memset(&h, 0, sizeof h);
    fv_scene_head_look_at(&h, fv_v3(0, 2, 0), fv_v3(0, 0, 0));
    fv_vec3 f = fv_quat_rotate(h.orientation, fv_v3(0, 0, -1));
    assert_near(f.y, -1.0, 1e-5);
    fv_scene_head_look_at(&h, fv_v3(1, 1, 1), fv_v3(1, 1, 1));
    f = fv_quat_rotate(h.orientation, fv_v3(0, 0, -1));
    assert_true(fv_v3_isfinite(f));
    assert_near(fv_v3_len(f), 1.0, 1e-5);
    fv_scene_head_look_at(&h, fv_v3(0, 0, 0), fv_v3(3, 0, 0)); /* look along +x */
    f = fv_quat_rotate(h.orientation, fv_v3(0, 0, -1));
    assert_near(f.x, 1.0, 1e-5);
    fv_vec3 up = fv_quat_rotate(h.orientation, fv_v3(0, 1, 0));
    assert_near(up.y, 1.0, 1e-5);
}

/* 65,536 lights (the documented limit) cost ~500 s a frame at the default size with no word: past
 * FV_SCENE_LIGHTS_WARN lights the renderer that takes the scene says so in one line, with the estimate at its size
 * and at the default, and what to change. Checked at a tiny size: the warning is about lights per pixel. */
static void many_lights_are_announced_with_the_per_frame_estimate(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("lamps", &s), FV_OK);
    fv_light l;
    memset(&l, 0, sizeof l);
    l.type = FV_LIGHT_POINT;
    l.color = fv_v3(1, 1, 1);
    l.intensity = 1;
    for (uint32_t i = 0; i < FV_SCENE_LIGHTS_WARN; i++) assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    assert_int_equal(fv_scene_light_evaluations(s, 16, 16), 256u * 2u * 16u * 16u);
    fv_test_log_capture_begin();
    assert_false(fv_scene_warn_cost(s, 16, 16, "the shade pass")); /* at the threshold: quiet */
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_WARN), 0);
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    assert_true(fv_scene_warn_cost(s, 16, 16, "the shade pass"));
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_WARN), 1);
    fv_assert_log_contains("lamps: 257 lights, and the shade pass sums every light at every pixel: about 1.3e+05 "
                           "light evaluations a frame at 16x16 per eye (3e+08 at the default 720x800");
    fv_assert_log_contains("keep to 256 lights or fewer");
    fv_test_log_capture_end();
    assert_int_equal(fv_scene_light_evaluations(s, UINT32_MAX, UINT32_MAX), UINT64_MAX); /* saturates */
    fv_scene_destroy(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(scene_built_in_code_has_counts_bounds_and_generated_normals),
        cmocka_unit_test(animation_rotates_about_the_node_origin_and_parents_follow),
        cmocka_unit_test(bad_meshes_are_refused_and_their_arrays_freed),
        cmocka_unit_test(validate_reports_each_broken_rule),
        cmocka_unit_test(frame_head_puts_the_whole_scene_in_the_hmd_field_of_view),
        cmocka_unit_test(builtin_cornell_has_red_left_wall_green_right_wall_and_a_spot_aiming_down),
        cmocka_unit_test(builtin_cornell_translucent_adds_a_marble_sphere),
        cmocka_unit_test(presets_equal_the_jensen2001_csv_row_by_row),
        cmocka_unit_test(head_look_at_handles_straight_down_and_degenerate_targets),
        cmocka_unit_test(many_lights_are_announced_with_the_per_frame_estimate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
