/* @brief Shadow maps on a device against exact visibility computed on the CPU in double: a plane under a spot light
 * and under a directional light (shared and per-eye cascades), with a box between them. Where the segment from a
 * plane point to the light crosses the box the GPU must shade it black (no ambient), elsewhere lit; pixels that
 * disagree are counted (only along the shadow's edge can a map of finite resolution disagree). A plane alone is
 * never shadowed by itself (no acne): shadows on and off give the same image. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_test.h"
#include "gpu_test.h"

#define W 128
#define H 128
#define BOX_LO_Y 0.45
#define BOX_HI_Y 0.55
#define BOX_HALF 0.15

FV_GPU_TEST_GROUP(W, H)
#define NEED_GPU() FV_NEED_GPU(g_r)

static uint64_t g_frame = 1;

/* Six outward quads of an axis-aligned box (arrays from malloc, as fv_scene_add_mesh takes them). */
static fv_mesh box_mesh(fv_vec3 lo, fv_vec3 hi, uint32_t material)
{
    fv_mesh m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "box");
    m.vertex_count = 24;
    m.index_count = 36;
    m.positions = malloc(24 * sizeof *m.positions);
    m.normals = malloc(24 * sizeof *m.normals);
    m.indices = malloc(36 * sizeof *m.indices);
    if (!m.positions || !m.normals || !m.indices) return m;
    for (int f = 0; f < 6; f++) {
        int axis = f / 2, side = f % 2;
        fv_vec3 n = fv_v3(0, 0, 0);
        float *nc = axis == 0 ? &n.x : (axis == 1 ? &n.y : &n.z);
        *nc = side ? 1.0f : -1.0f;
        for (int k = 0; k < 4; k++) {
            float c[3];
            int u = (axis + 1) % 3, v = (axis + 2) % 3;
            float lo3[3] = {lo.x, lo.y, lo.z}, hi3[3] = {hi.x, hi.y, hi.z};
            c[axis] = side ? hi3[axis] : lo3[axis];
            c[u] = (k == 1 || k == 2) ? hi3[u] : lo3[u];
            c[v] = (k >= 2) ? hi3[v] : lo3[v];
            m.positions[f * 4 + k] = fv_v3(c[0], c[1], c[2]);
            m.normals[f * 4 + k] = n;
        }
        uint32_t b = (uint32_t)f * 4, tri[6] = {b, b + 1, b + 2, b, b + 2, b + 3};
        memcpy(&m.indices[f * 6], tri, sizeof tri);
    }
    m.material = material;
    m.bounds_min = lo;
    m.bounds_max = hi;
    return m;
}

/* Does the segment p -> q cross the box (slab test, double)? */
static bool segment_hits_box(const double p[3], const double q[3], const double lo[3], const double hi[3])
{
    double t0 = 1e-9, t1 = 1.0;
    for (int k = 0; k < 3; k++) {
        double d = q[k] - p[k];
        if (fabs(d) < 1e-300) {
            if (p[k] < lo[k] || p[k] > hi[k]) return false;
            continue;
        }
        double a = (lo[k] - p[k]) / d, b = (hi[k] - p[k]) / d;
        if (a > b) {
            double t = a;
            a = b;
            b = t;
        }
        t0 = a > t0 ? a : t0;
        t1 = b < t1 ? b : t1;
        if (t0 > t1) return false;
    }
    return true;
}

typedef struct counts {
    int plane, shadowed, mismatched;
} counts;

/* Draw the scene seen from above and compare each eye's plane pixels with exact visibility. `to_light(p, out)` gives
 * the far end of the shadow segment for a plane point. */
static counts compare(fv_scene *s, const fv_quality *q, bool with_box, void (*to_light)(const double p[3], double out[3]))
{
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    fv_frame_input in;
    assert_int_equal(fv_renderer_frame_input(g_r, NULL, g_frame++, 0.0, &in), FV_OK);
    in.quality = *q;
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    float *img = malloc((size_t)W * H * 4 * sizeof *img);
    assert_non_null(img);
    counts c = {0, 0, 0};
    double lo[3] = {-BOX_HALF, BOX_LO_Y, -BOX_HALF}, hi[3] = {BOX_HALF, BOX_HI_Y, BOX_HALF};
    for (int eye = 0; eye < 2; eye++) {
        assert_int_equal(fv_renderer_read_linear(g_r, eye, img, (size_t)W * H * 4), FV_OK);
        const fv_eye_view *v = &in.eye[eye];
        double right[3] = {v->view.m[0][0], v->view.m[1][0], v->view.m[2][0]};
        double up[3] = {v->view.m[0][1], v->view.m[1][1], v->view.m[2][1]};
        double back[3] = {v->view.m[0][2], v->view.m[1][2], v->view.m[2][2]};
        double o[3] = {v->pos_world.x, v->pos_world.y, v->pos_world.z};
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                double tx = v->tan_left + (x + 0.5) / W * ((double)v->tan_right - v->tan_left);
                double ty = v->tan_up - (y + 0.5) / H * ((double)v->tan_up - v->tan_down);
                double dir[3], far[3];
                for (int k = 0; k < 3; k++) dir[k] = tx * right[k] + ty * up[k] - back[k];
                for (int k = 0; k < 3; k++) far[k] = o[k] + 100.0 * dir[k];
                if (!(dir[1] < 0)) continue;
                double t = -o[1] / dir[1];
                double p[3] = {o[0] + t * dir[0], 0.0, o[2] + t * dir[2]};
                if (fabs(p[0]) > 1.9 || fabs(p[2]) > 1.9) continue;      /* the plane's edge */
                if (with_box && segment_hits_box(o, far, lo, hi)) continue; /* the box is seen, not the plane */
                double l[3];
                to_light(p, l);
                bool shadowed = with_box && segment_hits_box(p, l, lo, hi);
                const float *px = &img[((size_t)y * W + x) * 4];
                assert_true(isfinite(px[0]) && isfinite(px[1]) && isfinite(px[2]));
                double lum = px[0] + px[1] + px[2];
                if (lum < 1e-4 && !shadowed) continue; /* outside the light (its cone): says nothing about shadows */
                c.plane++;
                c.shadowed += shadowed;
                bool dark = lum < 1e-6;
                c.mismatched += dark != shadowed;
            }
    }
    free(img);
    return c;
}

/* A 4 m white plane with a box hovering above its centre; light added by the caller. */
static fv_scene *plane_scene(bool with_box)
{
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("shadow-plane", &s), FV_OK);
    fv_material mat = fv_material_default();
    mat.base_color = fv_v3(0.8f, 0.8f, 0.8f);
    uint32_t mi, mesh;
    assert_int_equal(fv_scene_add_material(s, &mat, &mi), FV_OK);
    fv_mesh plane = fv_gpu_test_square_mesh("plane", 2.0, mi);
    assert_int_equal(fv_scene_add_mesh(s, &plane, &mesh), FV_OK);
    fv_node node = fv_node_default();
    node.mesh = (int32_t)mesh;
    assert_int_equal(fv_scene_add_node(s, &node, NULL), FV_OK);
    if (with_box) {
        fv_mesh box = box_mesh(fv_v3(-BOX_HALF, BOX_LO_Y, -BOX_HALF), fv_v3(BOX_HALF, BOX_HI_Y, BOX_HALF), mi);
        assert_int_equal(fv_scene_add_mesh(s, &box, &mesh), FV_OK);
        node.mesh = (int32_t)mesh;
        assert_int_equal(fv_scene_add_node(s, &node, NULL), FV_OK);
    }
    /* The head 2.2 m up and 0.8 m back, looking at the plane's centre. */
    fv_scene_head_look_at(&s->head, fv_v3(0.0f, 2.2f, 0.8f), fv_v3(0.0f, 0.0f, 0.0f));
    s->head.ipd_mm = 63.0f;
    return s;
}

static const fv_vec3 spot_pos = {0.1f, 1.5f, -0.1f};
static void spot_end(const double p[3], double out[3])
{
    (void)p;
    out[0] = spot_pos.x, out[1] = spot_pos.y, out[2] = spot_pos.z;
}

static fv_vec3 sun_dir; /* the way the light travels */
static void sun_end(const double p[3], double out[3])
{
    for (int k = 0; k < 3; k++) out[k] = p[k] - 50.0 * (&sun_dir.x)[k];
}

static void add_spot(fv_scene *s)
{
    fv_light l;
    memset(&l, 0, sizeof l);
    l.type = FV_LIGHT_SPOT;
    l.position_m = spot_pos;
    l.direction = fv_v3(0, -1, 0);
    l.color = fv_v3(1, 1, 1);
    l.intensity = 2.0f;
    l.inner_cone_rad = (float)fv_deg_to_rad(40.0);
    l.outer_cone_rad = (float)fv_deg_to_rad(55.0);
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
}

static void add_sun(fv_scene *s)
{
    sun_dir = fv_v3_normalize_or(fv_v3(0.35f, -1.0f, 0.2f), fv_v3(0, -1, 0));
    fv_light l;
    memset(&l, 0, sizeof l);
    l.type = FV_LIGHT_DIRECTIONAL;
    l.direction = sun_dir;
    l.color = fv_v3(1, 1, 1);
    l.intensity = 2.0f;
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
}

static void add_point(fv_scene *s);

static void report(const char *what, counts c)
{
    double f = c.plane ? (double)c.mismatched / c.plane : 1.0;
    print_message("%s: %d plane pixels, %d shadowed, %d disagree with exact visibility (%.3f%%)\n", what, c.plane,
                  c.shadowed, c.mismatched, 100.0 * f);
    assert_true(c.plane > W * H / 4);
    assert_true(c.shadowed > 50);  /* the shadow is there to be found */
    assert_true(f < 0.02);         /* only its edge may disagree */
}

static void spot_shadow_matches_exact_visibility(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = plane_scene(true);
    add_spot(s);
    fv_quality q = fv_quality_default();
    q.fovea.enabled = false; /* full resolution (foveation has its own tests) */
    q.shadow.filter = FV_SHADOW_FILTER_NONE; /* binary visibility, as the exact one */
    report("spot, 2048px, no filter", compare(s, &q, true, spot_end));
    const fv_plan_entry *e = fv_frame_plan_find(fv_renderer_plan(g_r), "shadow");
    assert_non_null(e);
    assert_true(e->enabled);
    assert_non_null(strstr(e->reason, "spot"));
    /* Shadows off: the same pixels are all lit. */
    q.shadow.enabled = false;
    counts off = compare(s, &q, true, spot_end);
    assert_int_equal(off.mismatched, off.shadowed);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

static void directional_cascades_match_exact_visibility_shared_and_per_eye(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = plane_scene(true);
    add_sun(s);
    fv_quality q = fv_quality_default();
    q.fovea.enabled = false; /* full resolution (foveation has its own tests) */
    q.shadow.filter = FV_SHADOW_FILTER_NONE;
    report("sun, 4 shared splits", compare(s, &q, true, sun_end));
    q.shadow.stereo_shared = false;
    report("sun, 4 splits per eye", compare(s, &q, true, sun_end));
    q.shadow.splits = 1;
    q.shadow.resolution_px = 1024;
    report("sun, 1 split of 1024px", compare(s, &q, true, sun_end));
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

static void a_plane_alone_never_shadows_itself(void **state)
{
    (void)state;
    NEED_GPU();
    void (*adders[3])(fv_scene *) = {add_spot, add_sun, add_point};
    void (*ends[3])(const double *, double *) = {spot_end, sun_end, spot_end};
    const fv_shadow_filter filters[3] = {FV_SHADOW_FILTER_NONE, FV_SHADOW_FILTER_PCF3, FV_SHADOW_FILTER_PCF5};
    for (int k = 0; k < 3; k++) {
        fv_scene *s = plane_scene(false);
        adders[k](s);
        for (int f = 0; f < 3; f++) {
            fv_quality q = fv_quality_default();
            q.fovea.enabled = false; /* full resolution (foveation has its own tests) */
            q.shadow.filter = filters[f];
            counts c = compare(s, &q, false, ends[k]);
            static const char *const kinds[3] = {"spot", "directional", "point"};
            if (c.mismatched) fail_msg("%s light, filter %d: %d of %d lit plane pixels shadowed (acne)", kinds[k], f,
                                       c.mismatched, c.plane);
            assert_true(c.plane > W * H / 4);
        }
        fv_scene_destroy(&s);
    }
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

static void add_point(fv_scene *s)
{
    fv_light l;
    memset(&l, 0, sizeof l);
    l.type = FV_LIGHT_POINT;
    l.position_m = spot_pos;
    l.color = fv_v3(1, 1, 1);
    l.intensity = 2.0f;
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
}

/* A point light's cube map: the plane sees the light through several faces (the box's shadow falls in the -y face,
 * the plane's far parts in the side faces). */
static void point_light_cube_map_matches_exact_visibility(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = plane_scene(true);
    add_point(s);
    fv_quality q = fv_quality_default();
    q.fovea.enabled = false; /* full resolution (foveation has its own tests) */
    q.shadow.filter = FV_SHADOW_FILTER_NONE;
    report("point, cube map of 2048px, no filter", compare(s, &q, true, spot_end));
    const fv_plan_entry *e = fv_frame_plan_find(fv_renderer_plan(g_r), "shadow");
    assert_non_null(e);
    assert_true(e->enabled);
    assert_non_null(strstr(e->reason, "1 point: a cube map (6 faces)"));
    fv_render_stats st;
    assert_int_equal(fv_renderer_stats(g_r, &st), FV_OK);
    for (uint32_t i = 0; i < st.pass_count; i++)
        if (strcmp(st.pass_name[i], "shadow") == 0) assert_int_equal(st.pass_counters[i].draws, 6 * 2); /* 6 faces */
    /* The plane alone under the point light: no acne in any face. */
    fv_scene_destroy(&s);
    s = plane_scene(false);
    add_point(s);
    counts c = compare(s, &q, false, spot_end);
    assert_int_equal(c.mismatched, 0);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

static void shadow_plan_says_why_it_is_off(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = NULL;
    /* No lights at all: off, and why. */
    assert_int_equal(fv_scene_create("dark", &s), FV_OK);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    const fv_plan_entry *e = fv_frame_plan_find(fv_renderer_plan(g_r), "shadow");
    assert_false(e->enabled);
    assert_non_null(strstr(e->reason, "off — no lights"));
    fv_scene_destroy(&s);
    /* The knob off: off, and why. */
    s = plane_scene(false);
    add_spot(s);
    fv_quality q = fv_quality_default();
    q.fovea.enabled = false; /* full resolution (foveation has its own tests) */
    q.shadow.enabled = false;
    assert_int_equal(fv_renderer_set_quality(g_r, &q), FV_OK);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    e = fv_frame_plan_find(fv_renderer_plan(g_r), "shadow");
    assert_false(e->enabled);
    assert_non_null(strstr(e->reason, "shadow.enabled is false"));
    q = fv_quality_default();
    q.fovea.enabled = false; /* full resolution (foveation has its own tests) */
    assert_int_equal(fv_renderer_set_quality(g_r, &q), FV_OK);
    assert_true(fv_frame_plan_find(fv_renderer_plan(g_r), "shadow")->enabled);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(spot_shadow_matches_exact_visibility),
        cmocka_unit_test(directional_cascades_match_exact_visibility_shared_and_per_eye),
        cmocka_unit_test(a_plane_alone_never_shadows_itself),
        cmocka_unit_test(point_light_cube_map_matches_exact_visibility),
        cmocka_unit_test(shadow_plan_says_why_it_is_off),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
