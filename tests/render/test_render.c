/* @brief GPU tests of the renderer on lavapipe (or any Vulkan device) with the validation layer forced on (and
 * synchronization validation): the Cornell box walls, a spot-lit plane against a CPU double-precision reference, the
 * stereo parallax the IPD implies, list-of-pixels shading, timings, and zero validation messages throughout.
 * Without a Vulkan device the tests skip with a message, except under CI=true where that is a failure. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_gpu.h"
#include "fv_renderer.h"
#include "fv_scene.h"
#include "fv_test.h"
#include "gpu_test.h"

#define W 96
#define H 96

FV_GPU_TEST_GROUP(W, H)

#define NEED_GPU() FV_NEED_GPU(g_r)

/* Project a world point into an eye: pixel coordinates (x right, y down). */
static bool project(const fv_frame_input *in, int eye, fv_vec3 p, double *out_x, double *out_y)
{
    fv_mat4 vp = fv_mat4_mul(&in->eye[eye].proj, &in->eye[eye].view);
    fv_vec4 c = fv_mat4_mul_v4(&vp, (fv_vec4){p.x, p.y, p.z, 1.0f});
    if (!(c.w > 0)) return false;
    *out_x = (c.x / c.w * 0.5 + 0.5) * W;
    *out_y = (c.y / c.w * 0.5 + 0.5) * H;
    return true;
}

static int find_node(const fv_scene *s, const char *name)
{
    for (uint32_t i = 0; i < s->node_count; i++)
        if (strcmp(s->nodes[i].name, name) == 0) return (int)i;
    return -1;
}

/* ---- (1) Cornell box: left wall red, right wall green --------------------------------------------------------- */

static void check_wall(const fv_scene *s, const fv_frame_input *in, const uint8_t *rgba, const char *node, int channel)
{
    int n = find_node(s, node);
    assert_true(n >= 0);
    const fv_mesh *m = &s->meshes[s->nodes[n].mesh];
    fv_mat4 w = fv_scene_node_world(s, (uint32_t)n, 0.0);
    fv_vec3 centre = fv_mat4_mul_point(&w, fv_v3_scale(fv_v3_add(m->bounds_min, m->bounds_max), 0.5f));
    for (int eye = 0; eye < 2; eye++) {
        double x, y;
        assert_true(project(in, eye, centre, &x, &y));
        int px = (int)x, py = (int)y;
        assert_true(px >= 0 && px < W && py >= 0 && py < H);
        /* the wall is on its own side of the image */
        if (channel == 0) assert_true(px < W / 2);
        else assert_true(px >= W / 2);
        const uint8_t *p = rgba + ((size_t)py * 2 * W + (size_t)eye * W + (size_t)px) * 4;
        int other = channel == 0 ? 1 : 0;
        if (!(p[channel] > 40 && p[channel] > 1.3 * p[other] && p[channel] > 1.3 * p[2]))
            fail_msg("%s eye %d pixel (%d,%d) = (%u,%u,%u), expected %s", node, eye, px, py, p[0], p[1], p[2],
                     channel == 0 ? "red" : "green");
    }
}

static void cornell_left_wall_red_right_wall_green(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("cornell", &s), FV_OK);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    fv_frame_input in;
    assert_int_equal(fv_renderer_frame_input(g_r, NULL, 1, 0.0, &in), FV_OK);
    in.quality.fovea.enabled = false; /* full resolution: compared pixel by pixel (foveation is on by default) */
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    uint8_t *rgba = malloc((size_t)2 * W * H * 4);
    assert_non_null(rgba);
    assert_int_equal(fv_renderer_read_rgba8(g_r, true, 0, rgba, (size_t)2 * W * H * 4), FV_OK);
    check_wall(s, &in, rgba, "left_wall_red", 0);
    check_wall(s, &in, rgba, "right_wall_green", 1);
    /* the plan says why: no translucency in plain cornell */
    const fv_plan_entry *sss = fv_frame_plan_find(fv_renderer_plan(g_r), "sss");
    assert_non_null(sss);
    assert_false(sss->enabled);
    assert_non_null(strstr(sss->reason, "no translucent material"));
    free(rgba);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

/* ---- (2) a plane lit by one spot light vs a CPU double-precision reference ------------------------------------ */

static fv_mesh quad_mesh(double half, uint32_t material) { return fv_gpu_test_square_mesh("plane", half, material); }

/* The same formulas as render/include/fv_shade_common.glsl, in double. */
static double ref_spot(const fv_light *l, const double pos[3], const double n[3])
{
    double to[3] = {l->position_m.x - pos[0], l->position_m.y - pos[1], l->position_m.z - pos[2]};
    double d2 = to[0] * to[0] + to[1] * to[1] + to[2] * to[2];
    double d = sqrt(d2);
    double lv[3] = {to[0] / d, to[1] / d, to[2] / d};
    double cos_surface = fmax(n[0] * lv[0] + n[1] * lv[1] + n[2] * lv[2], 0.0);
    double dl = sqrt((double)l->direction.x * l->direction.x + (double)l->direction.y * l->direction.y +
                     (double)l->direction.z * l->direction.z);
    double cos_axis = -(lv[0] * l->direction.x + lv[1] * l->direction.y + lv[2] * l->direction.z) / dl;
    double ci = cos((double)l->inner_cone_rad), co = cos((double)l->outer_cone_rad);
    double t = fmin(fmax((cos_axis - co) / (ci - co), 0.0), 1.0);
    double falloff = t * t * (3.0 - 2.0 * t);
    return (double)l->intensity * falloff * cos_surface / d2;
}

static void spot_lit_plane_matches_cpu_reference(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("spot-plane", &s), FV_OK);
    fv_material mat = fv_material_default();
    mat.base_color = fv_v3(1, 1, 1);
    uint32_t mi;
    assert_int_equal(fv_scene_add_material(s, &mat, &mi), FV_OK);
    fv_mesh m = quad_mesh(6.0, mi) /* larger than the view: exercises clipping */;
    uint32_t mesh;
    assert_int_equal(fv_scene_add_mesh(s, &m, &mesh), FV_OK);
    fv_node node = fv_node_default();
    node.mesh = (int32_t)mesh;
    assert_int_equal(fv_scene_add_node(s, &node, NULL), FV_OK);
    fv_light l;
    memset(&l, 0, sizeof l);
    l.type = FV_LIGHT_SPOT;
    l.position_m = fv_v3(0.2f, 1.6f, -0.3f);
    l.direction = fv_v3_normalize_or(fv_v3(-0.2f, -1.0f, 0.1f), fv_v3(0, -1, 0));
    l.color = fv_v3(1.0f, 0.8f, 0.6f);
    l.intensity = 3.0f;
    l.inner_cone_rad = (float)fv_deg_to_rad(15.0);
    l.outer_cone_rad = (float)fv_deg_to_rad(30.0);
    assert_int_equal(fv_scene_add_light(s, &l, NULL), FV_OK);
    /* head 1.2 m above the plane, looking straight down (-z rotated onto -y) */
    s->head.position_m = fv_v3(0.0f, 1.2f, 0.0f);
    s->head.orientation = fv_quat_axis_angle(fv_v3(1, 0, 0), (float)(-FV_PI / 2));
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);

    fv_frame_input in;
    fv_frame_input_from_head(&s->head, 0.1f, 10.0f, W, H, 1, 0.0, &in);
    in.quality.fovea.enabled = false; /* full resolution: compared pixel by pixel (foveation is on by default) */
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    float *img = malloc((size_t)W * H * 4 * sizeof *img);
    assert_non_null(img);
    double colour[3] = {l.color.x, l.color.y, l.color.z};
    for (int eye = 0; eye < 2; eye++) {
        assert_int_equal(fv_renderer_read_linear(g_r, eye, img, (size_t)W * H * 4), FV_OK);
        const fv_eye_view *v = &in.eye[eye];
        /* eye basis in world from the view matrix rows */
        double right[3] = {v->view.m[0][0], v->view.m[1][0], v->view.m[2][0]};
        double up[3] = {v->view.m[0][1], v->view.m[1][1], v->view.m[2][1]};
        double back[3] = {v->view.m[0][2], v->view.m[1][2], v->view.m[2][2]};
        double o[3] = {v->pos_world.x, v->pos_world.y, v->pos_world.z};
        double peak = 0;
        double *ref = malloc((size_t)W * H * sizeof *ref);
        assert_non_null(ref);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                double tx = v->tan_left + (x + 0.5) / W * ((double)v->tan_right - v->tan_left);
                double ty = v->tan_up - (y + 0.5) / H * ((double)v->tan_up - v->tan_down); /* y down */
                double dir[3];
                for (int k = 0; k < 3; k++) dir[k] = tx * right[k] + ty * up[k] - back[k];
                double tt = -o[1] / dir[1]; /* plane y = 0 */
                double val = 0;
                if (dir[1] < 0 && tt > 0) {
                    double p[3] = {o[0] + tt * dir[0], o[1] + tt * dir[1], o[2] + tt * dir[2]};
                    double n[3] = {0, 1, 0};
                    val = ref_spot(&l, p, n) / FV_PI; /* Lambert, albedo 1 */
                }
                ref[y * W + x] = val;
                if (val > peak) peak = val;
            }
        assert_true(peak > 0.05);
        int lit = 0, bad = 0;
        double worst = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
                for (int c = 0; c < 3; c++) {
                    double want = ref[y * W + x] * colour[c];
                    double got = img[((size_t)y * W + x) * 4 + c];
                    assert_true(isfinite(got));
                    double peak_c = peak * colour[c];
                    if (want > 0.01 * peak_c) { /* lit: relative error */
                        double rel = fabs(got - want) / want;
                        if (rel > worst) worst = rel;
                        if (rel > 1e-3 && bad++ < 5)
                            print_error("eye %d pixel (%d,%d) ch %d: gpu %.6g cpu %.6g rel %.2e\n", eye, x, y, c, got,
                                        want, rel);
                        lit++;
                    } else if (fabs(got - want) > 1e-3 * peak_c) { /* the cone's fringe and the dark: absolute */
                        if (bad++ < 5)
                            print_error("eye %d pixel (%d,%d) ch %d: gpu %.6g cpu %.6g (fringe, peak %.4g)\n", eye, x,
                                        y, c, got, want, peak_c);
                    }
                }
        assert_int_equal(bad, 0);
        assert_true(lit > W * H / 20);
        print_message("eye %d: %d lit samples, worst relative error %.2e\n", eye, lit, worst);
        free(ref);
    }
    free(img);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

/* ---- (3) parallax: the eyes see a near object shifted by IPD * f / d ----------------------------------------- */

static bool centroid(const float *img, double *out_x, double *out_y)
{
    double sx = 0, sy = 0, n = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double v = img[((size_t)y * W + x) * 4];
            if (v > 0.5) {
                sx += x + 0.5;
                sy += y + 0.5;
                n += 1;
            }
        }
    if (n < 4) return false;
    *out_x = sx / n;
    *out_y = sy / n;
    return true;
}

static void eyes_differ_by_ipd_parallax(void **state)
{
    (void)state;
    NEED_GPU();
    const double depths[2] = {0.4, 1.0};
    for (int k = 0; k < 2; k++) {
        double d = depths[k];
        fv_scene *s = NULL;
        assert_int_equal(fv_scene_create("parallax", &s), FV_OK);
        fv_material mat = fv_material_default();
        mat.base_color = fv_v3(0, 0, 0);
        mat.emissive = fv_v3(1, 1, 1); /* unlit: only the geometry matters */
        uint32_t mi;
        assert_int_equal(fv_scene_add_material(s, &mat, &mi), FV_OK);
        fv_mesh m = quad_mesh(0.04 * d, mi); /* a small square facing the eyes (rotated below) */
        uint32_t mesh;
        assert_int_equal(fv_scene_add_mesh(s, &m, &mesh), FV_OK);
        fv_node node = fv_node_default();
        node.mesh = (int32_t)mesh;
        node.translation_m = fv_v3(0, 0, (float)-d);
        node.rotation = fv_quat_axis_angle(fv_v3(1, 0, 0), (float)(FV_PI / 2)); /* plane y=0 -> facing +z */
        assert_int_equal(fv_scene_add_node(s, &node, NULL), FV_OK);
        s->head.position_m = fv_v3(0, 0, 0);
        s->head.orientation = fv_quat_identity();
        s->head.ipd_mm = 63.0f;
        assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
        fv_frame_input in;
        fv_frame_input_from_head(&s->head, 0.05f, 10.0f, W, H, 1, 0.0, &in);
        in.quality.fovea.enabled = false; /* full resolution: compared pixel by pixel (foveation is on by default) */
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        float *img = malloc((size_t)W * H * 4 * sizeof *img);
        assert_non_null(img);
        double cx[2], cy[2];
        for (int eye = 0; eye < 2; eye++) {
            assert_int_equal(fv_renderer_read_linear(g_r, eye, img, (size_t)W * H * 4), FV_OK);
            assert_true(centroid(img, &cx[eye], &cy[eye]));
        }
        /* Where the straight-ahead direction lands differs per eye (asymmetric, mirrored frusta); remove that,
         * then the remaining shift is the parallax: IPD * f / d, the left eye seeing the object further right. */
        double f_px = W / ((double)in.eye[0].tan_right - in.eye[0].tan_left);
        double centre_l = -in.eye[0].tan_left * f_px, centre_r = -in.eye[1].tan_left * f_px;
        double shift = (cx[0] - centre_l) - (cx[1] - centre_r);
        double expect = 0.063 * f_px / d;
        double px[2], py[2];
        assert_true(project(&in, 0, fv_v3(0, 0, (float)-d), &px[0], &py[0]));
        assert_true(project(&in, 1, fv_v3(0, 0, (float)-d), &px[1], &py[1]));
        print_message("depth %.2f m: parallax %.2f px, expected %.2f px (centroids %.2f %.2f, projected %.2f %.2f)\n",
                      d, shift, expect, cx[0], cx[1], px[0], px[1]);
        assert_true(fabs(shift - expect) < 1.0);
        assert_true(fabs(cy[0] - cy[1]) < 0.5);
        free(img);
        fv_scene_destroy(&s);
    }
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

/* ---- (5) list-of-pixels shading ------------------------------------------------------------------------------ */

static void shading_a_pixel_list_matches_full_shading_and_leaves_others(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("cornell", &s), FV_OK);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    fv_frame_input in;
    assert_int_equal(fv_renderer_frame_input(g_r, NULL, 7, 0.0, &in), FV_OK);
    in.quality.fovea.enabled = false; /* full resolution: compared pixel by pixel (foveation is on by default) */
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    size_t n = (size_t)W * H * 4;
    float *full[2], *part[2];
    for (int e = 0; e < 2; e++) {
        full[e] = malloc(n * sizeof(float));
        part[e] = malloc(n * sizeof(float));
        assert_true(full[e] && part[e]);
        assert_int_equal(fv_renderer_read_linear(g_r, e, full[e], n), FV_OK);
    }
    /* every 7th pixel of both eyes, in a scrambled order */
    uint32_t cap = 2 * W * H / 7 + 2, count = 0;
    uint32_t *list = malloc(cap * sizeof *list);
    assert_non_null(list);
    for (uint32_t i = 0; i < 2u * W * H; i += 7) {
        uint32_t j = (i * 7919u) % (2u * W * H);
        uint32_t layer = j / (W * H), p = j % (W * H);
        list[count++] = FV_GPU_PIXEL_PACK(p % W, p / W, layer);
    }
    const float sentinel[4] = {-2.0f, 3.0f, -4.0f, 0.5f};
    assert_int_equal(fv_renderer_shade_pixels(g_r, list, count, sentinel), FV_OK);
    uint8_t *listed = calloc(2u * W * H, 1);
    assert_non_null(listed);
    for (uint32_t i = 0; i < count; i++) {
        uint32_t x = list[i] & 0x7fffu, y = (list[i] >> 15) & 0x7fffu, layer = list[i] >> 30;
        listed[layer * W * H + y * W + x] = 1;
    }
    int shaded = 0;
    for (int e = 0; e < 2; e++) {
        assert_int_equal(fv_renderer_read_linear(g_r, e, part[e], n), FV_OK);
        for (size_t p = 0; p < (size_t)W * H; p++)
            for (int c = 0; c < 4; c++) {
                float a = full[e][p * 4 + c], b = part[e][p * 4 + c];
                if (listed[e * W * H + p]) {
                    if (fabsf(a - b) > 1e-6f + 1e-3f * fabsf(a))
                        fail_msg("eye %d pixel %zu ch %d: list %g, full %g", e, p, c, b, a);
                } else if (b != sentinel[c]) {
                    fail_msg("eye %d pixel %zu ch %d: not listed but changed to %g", e, p, c, b);
                }
            }
        for (size_t p = 0; p < (size_t)W * H; p++) shaded += listed[e * W * H + p];
    }
    assert_int_equal(shaded, (int)count);
    fv_render_stats st;
    assert_int_equal(fv_renderer_stats(g_r, &st), FV_OK);
    assert_int_equal(st.pixels_shaded, count);
    /* out-of-range pixels are refused with a message, nothing shaded */
    uint32_t bad = FV_GPU_PIXEL_PACK(W, 0, 0);
    fv_test_log_capture_begin();
    assert_int_equal(fv_renderer_shade_pixels(g_r, &bad, 1, NULL), FV_ERR_RANGE);
    fv_test_log_capture_end();
    fv_assert_log_contains("outside");
    for (int e = 0; e < 2; e++) {
        free(full[e]);
        free(part[e]);
    }
    free(list);
    free(listed);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

/* ---- stats, frames in flight, animation ---------------------------------------------------------------------- */

static void stats_report_per_pass_gpu_time_and_memory(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("cornell", &s), FV_OK);
    /* make one block rotate so that motion vectors and per-frame transforms are exercised */
    s->nodes[s->node_count - 1].anim.kind = FV_ANIM_ROTATE;
    s->nodes[s->node_count - 1].anim.axis = fv_v3(0, 1, 0);
    s->nodes[s->node_count - 1].anim.rate_rad_s = 1.0f;
    /* motion vectors are drawn where something reads them: foveation (on by default) */
    fv_quality q = fv_quality_default();
    assert_int_equal(fv_renderer_set_quality(g_r, &q), FV_OK);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    const fv_plan_entry *motion = fv_frame_plan_find(fv_renderer_plan(g_r), "motion");
    assert_non_null(motion);
    assert_non_null(strstr(motion->reason, "animated"));
    for (uint64_t f = 0; f < 5; f++) {
        fv_frame_input in;
        assert_int_equal(fv_renderer_frame_input(g_r, NULL, f, (double)f / 60.0, &in), FV_OK);
        in.quality.shadow.enabled = false; /* the three passes of direct lighting; shadows: test_render_shadow */
        /* ... and no foveation (on by default): the full-resolution pass list; test_render_fovea checks the other */
        in.quality.fovea.enabled = false;
        in.quality.gi.enabled = false; /* ... and no GI pass (on by default; tests/gi) */
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
    }
    assert_int_equal(fv_renderer_finish(g_r), FV_OK);
    fv_render_stats st;
    assert_int_equal(fv_renderer_stats(g_r, &st), FV_OK);
    assert_int_equal(st.frame_id, 4);
    assert_int_equal(st.pass_count, 3);
    assert_string_equal(st.pass_name[0], "gbuffer");
    assert_string_equal(st.pass_name[1], "shade");
    assert_string_equal(st.pass_name[2], "present");
    for (uint32_t i = 0; i < st.pass_count; i++) assert_true(st.pass_gpu_ms[i] > 0.0 && st.pass_gpu_ms[i] < 10000.0);
    assert_true(st.frame_gpu_ms >= st.pass_gpu_ms[1]);
    assert_int_equal(st.pixels_shaded, 2u * W * H);
    assert_true(st.device_memory_bytes > (uint64_t)W * H * 2 * 8);
    assert_true(st.peak_device_memory_bytes >= st.device_memory_bytes);
    print_message("gbuffer %.3f ms, shade %.3f ms, present %.3f ms, memory %llu (peak %llu) bytes\n",
                  st.pass_gpu_ms[0], st.pass_gpu_ms[1], st.pass_gpu_ms[2], (unsigned long long)st.device_memory_bytes,
                  (unsigned long long)st.peak_device_memory_bytes);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

static void bad_calls_are_refused_with_a_message(void **state)
{
    (void)state;
    NEED_GPU();
    fv_frame_input in;
    fv_head h = {.position_m = {0, 0, 0}, .orientation = {0, 0, 0, 1}, .ipd_mm = 63};
    fv_frame_input_from_head(&h, 0.1f, 10.0f, W, H, 1, 0.0, &in);
    in.quality.fovea.enabled = false; /* full resolution (foveation has its own tests) */
    in.eye[1].proj.m[0][0] = NAN;
    fv_test_log_capture_begin();
    assert_int_equal(fv_renderer_draw(g_r, &in), FV_ERR_RANGE);
    fv_test_log_capture_end();
    fv_assert_log_contains("non-finite");
    uint8_t small[16];
    assert_int_equal(fv_renderer_read_rgba8(g_r, true, 0, small, sizeof small) < 0, 1);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cornell_left_wall_red_right_wall_green),
        cmocka_unit_test(spot_lit_plane_matches_cpu_reference),
        cmocka_unit_test(eyes_differ_by_ipd_parallax),
        cmocka_unit_test(shading_a_pixel_list_matches_full_shading_and_leaves_others),
        cmocka_unit_test(stats_report_per_pass_gpu_time_and_memory),
        cmocka_unit_test(bad_calls_are_refused_with_a_message),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
