/* @brief GPU tests of the G-buffer motion vectors on lavapipe (or any Vulkan device) with the validation layer forced
 * on: zero for a static scene and head, the projected displacement of an animated (FV_ANIM_BOB) object, the
 * reprojection of static planes under head motion, and both together over consecutive frames, in both eyes, each
 * pixel against a CPU reference computed in double from the frame inputs' view/projection matrices. Convention
 * checked: RG16F per pixel and eye layer, uv units (x / W, y / H, y down), current position minus previous.
 * Without a Vulkan device the tests skip with a message, except under CI=true where that is a failure. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_renderer.h"
#include "fv_scene.h"
#include "fv_test.h"
#include "gpu_test.h"

/* Not square, so that a swapped x/y scale would show. */
#define W 128
#define H 96
#define TOL_PX 0.05      /* moving surfaces: |gpu - cpu| per component, pixels */
#define ZERO_TOL_PX 1e-3 /* static surfaces and empty pixels */

FV_GPU_TEST_GROUP_MOTION(W, H) /* the tests read the motion vectors back */

#define NEED_GPU() FV_NEED_GPU(g_r)

/* ---- double-precision matrices (column-major like fv_mat4: m[col][row]) -------------------------------------- */

typedef struct dmat4 {
    double m[4][4];
} dmat4;

static dmat4 dm_from(const fv_mat4 *a)
{
    dmat4 d;
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) d.m[c][r] = a->m[c][r];
    return d;
}

static dmat4 dm_mul(const dmat4 *a, const dmat4 *b)
{
    dmat4 o;
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double s = 0;
            for (int k = 0; k < 4; k++) s += a->m[k][r] * b->m[c][k];
            o.m[c][r] = s;
        }
    return o;
}

static void dm_apply(const dmat4 *a, const double in[4], double out[4])
{
    for (int r = 0; r < 4; r++)
        out[r] = a->m[0][r] * in[0] + a->m[1][r] * in[1] + a->m[2][r] * in[2] + a->m[3][r] * in[3];
}

/* Gauss-Jordan with partial pivoting. */
static bool dm_invert(const dmat4 *a, dmat4 *out)
{
    double t[4][8];
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            t[r][c] = a->m[c][r];
            t[r][c + 4] = r == c ? 1.0 : 0.0;
        }
    for (int c = 0; c < 4; c++) {
        int p = c;
        for (int r = c + 1; r < 4; r++)
            if (fabs(t[r][c]) > fabs(t[p][c])) p = r;
        if (fabs(t[p][c]) < 1e-300) return false;
        for (int k = 0; k < 8; k++) {
            double x = t[c][k];
            t[c][k] = t[p][k];
            t[p][k] = x;
        }
        double inv = 1.0 / t[c][c];
        for (int k = 0; k < 8; k++) t[c][k] *= inv;
        for (int r = 0; r < 4; r++) {
            if (r == c) continue;
            double f = t[r][c];
            for (int k = 0; k < 8; k++) t[r][k] -= f * t[c][k];
        }
    }
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) out->m[c][r] = t[r][c + 4];
    return true;
}

/* Pixel coordinates (x right, y down, pixel centres at +0.5) of a world point through a view-projection. */
static bool to_pixels(const dmat4 *vp, const double p[3], double *out_x, double *out_y)
{
    double in[4] = {p[0], p[1], p[2], 1.0}, c[4];
    dm_apply(vp, in, c);
    if (!(c[3] > 1e-9)) return false;
    *out_x = (c[0] / c[3] * 0.5 + 0.5) * W;
    *out_y = (c[1] / c[3] * 0.5 + 0.5) * H;
    return true;
}

/* ---- the scene: axis-aligned squares facing +z, each optionally bobbing ------------------------------------- */

typedef struct quad {
    double centre_m[3]; /* world, at time 0 phase 0 */
    double half_m;
    double amp_m[3]; /* FV_ANIM_BOB: centre + amp * sin(2 pi freq t + phase); zero = static */
    double freq_hz, phase_rad;
    float emissive[3]; /* unlit colour, to tell the squares apart in the image */
} quad;

static void quad_centre_at(const quad *q, double t_s, double out[3])
{
    double k = q->freq_hz != 0.0 ? sin(2.0 * FV_PI * q->freq_hz * t_s + q->phase_rad) : 0.0;
    for (int i = 0; i < 3; i++) out[i] = q->centre_m[i] + q->amp_m[i] * k;
}

static fv_mesh square_mesh(double half, uint32_t material) { return fv_gpu_test_square_mesh("square", half, material); }

static fv_scene *build_scene(const quad *qs, int n)
{
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_create("motion", &s), FV_OK);
    for (int i = 0; i < n; i++) {
        fv_material mat = fv_material_default();
        mat.base_color = fv_v3(0, 0, 0);
        mat.emissive = fv_v3(qs[i].emissive[0], qs[i].emissive[1], qs[i].emissive[2]);
        uint32_t mi, mesh;
        assert_int_equal(fv_scene_add_material(s, &mat, &mi), FV_OK);
        fv_mesh m = square_mesh(qs[i].half_m, mi);
        assert_int_equal(fv_scene_add_mesh(s, &m, &mesh), FV_OK);
        fv_node node = fv_node_default();
        node.mesh = (int32_t)mesh;
        node.translation_m = fv_v3((float)qs[i].centre_m[0], (float)qs[i].centre_m[1], (float)qs[i].centre_m[2]);
        node.rotation = fv_quat_axis_angle(fv_v3(1, 0, 0), (float)(FV_PI / 2)); /* local +y -> world +z */
        if (qs[i].freq_hz != 0.0) {
            node.anim.kind = FV_ANIM_BOB;
            node.anim.amplitude_m = fv_v3((float)qs[i].amp_m[0], (float)qs[i].amp_m[1], (float)qs[i].amp_m[2]);
            node.anim.freq_hz = (float)qs[i].freq_hz;
            node.anim.phase_rad = (float)qs[i].phase_rad;
        }
        assert_int_equal(fv_scene_add_node(s, &node, NULL), FV_OK);
    }
    s->head.position_m = fv_v3(0, 0, 0);
    s->head.orientation = fv_quat_identity();
    s->head.ipd_mm = 63.0f;
    s->head.from_file = true;
    return s;
}

/* The nearest square that the ray through pixel point (sx, sy) meets at time t_s: its index (-1: none) and the
 * world point. inv_vp is the inverse of the current frame's view-projection. */
static int trace(const quad *qs, int n, double t_s, const dmat4 *inv_vp, double sx, double sy, double out_p[3])
{
    double nx = 2.0 * sx / W - 1.0, ny = 2.0 * sy / H - 1.0;
    double a_in[4] = {nx, ny, 0.0, 1.0}, b_in[4] = {nx, ny, 1.0, 1.0}, a[4], b[4];
    dm_apply(inv_vp, a_in, a);
    dm_apply(inv_vp, b_in, b);
    double o[3], d[3];
    for (int k = 0; k < 3; k++) {
        o[k] = a[k] / a[3];
        d[k] = b[k] / b[3] - o[k];
    }
    int best = -1;
    double best_t = INFINITY;
    for (int i = 0; i < n; i++) {
        double c[3];
        quad_centre_at(&qs[i], t_s, c);
        if (fabs(d[2]) < 1e-12) continue;
        double tt = (c[2] - o[2]) / d[2];
        if (!(tt > 0.0 && tt < 1.0) || tt >= best_t) continue;
        double px = o[0] + tt * d[0] - c[0], py = o[1] + tt * d[1] - c[1];
        if (fabs(px) > qs[i].half_m || fabs(py) > qs[i].half_m) continue;
        best = i;
        best_t = tt;
        for (int k = 0; k < 3; k++) out_p[k] = o[k] + tt * d[k];
    }
    return best;
}

typedef struct check_result {
    int moving, still, empty; /* pixels checked on moving squares, on static squares, with nothing drawn */
    double max_err_px;        /* worst |gpu - cpu| component on moving squares */
    double max_still_px;      /* worst |mv| on static squares and empty pixels */
    double max_expect_px;     /* largest expected |mv| component */
    double mean_expect[2], mean_got[2]; /* over moving pixels, pixels */
} check_result;

/* Compare the last frame's motion of both eyes with the CPU reference: frame `cur` at t_cur, the previous frame
 * drawn from `prev` at t_prev. Pixels within a pixel of a square's edge are skipped (coverage is ambiguous there). */
static check_result check_motion(const quad *qs, int n, const fv_frame_input *prev, double t_prev,
                                 const fv_frame_input *cur, double t_cur)
{
    check_result cr;
    memset(&cr, 0, sizeof cr);
    float *mv = malloc((size_t)W * H * 2 * sizeof *mv);
    float *rgba = malloc((size_t)W * H * 4 * sizeof *rgba);
    assert_true(mv && rgba);
    int bad = 0;
    for (int eye = 0; eye < 2; eye++) {
        assert_int_equal(fv_renderer_read_motion(g_r, eye, mv, (size_t)W * H * 2), FV_OK);
        assert_int_equal(fv_renderer_read_linear(g_r, eye, rgba, (size_t)W * H * 4), FV_OK);
        dmat4 pv = dm_from(&prev->eye[eye].proj), vv = dm_from(&prev->eye[eye].view);
        dmat4 pc = dm_from(&cur->eye[eye].proj), vc = dm_from(&cur->eye[eye].view);
        dmat4 vp_prev = dm_mul(&pv, &vv), vp_cur = dm_mul(&pc, &vc), inv_cur;
        assert_true(dm_invert(&vp_cur, &inv_cur));
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                double p[3], q[3];
                int hit = trace(qs, n, t_cur, &inv_cur, x + 0.5, y + 0.5, p);
                bool solid = true;
                for (int dy = -1; dy <= 1 && solid; dy++)
                    for (int dx = -1; dx <= 1 && solid; dx++)
                        if (trace(qs, n, t_cur, &inv_cur, x + 0.5 + dx, y + 0.5 + dy, q) != hit) solid = false;
                if (!solid) continue;
                const float *m = &mv[((size_t)y * W + x) * 2];
                const float *c = &rgba[((size_t)y * W + x) * 4];
                double got[2] = {m[0] * (double)W, m[1] * (double)H}; /* uv -> pixels */
                if (hit < 0) {
                    /* nothing drawn: the cleared motion and colour */
                    double a = fmax(fabs(got[0]), fabs(got[1]));
                    if (a > cr.max_still_px) cr.max_still_px = a;
                    if ((a > ZERO_TOL_PX || c[0] > 0.01f || c[1] > 0.01f || c[2] > 0.01f) && bad++ < 8)
                        print_error("eye %d pixel (%d,%d): empty, but motion (%.4g, %.4g) px colour (%.3g %.3g %.3g)\n",
                                    eye, x, y, got[0], got[1], c[0], c[1], c[2]);
                    cr.empty++;
                    continue;
                }
                /* the right square is there: its emissive colour */
                for (int k = 0; k < 3; k++)
                    if (fabs(c[k] - qs[hit].emissive[k]) > 0.02 && bad++ < 8)
                        print_error("eye %d pixel (%d,%d): colour %d is %.3g, square %d has %.3g\n", eye, x, y, k, c[k],
                                    hit, qs[hit].emissive[k]);
                /* the same surface point one frame earlier: the square's displacement undone */
                double c_cur[3], c_prev[3], pp[3];
                quad_centre_at(&qs[hit], t_cur, c_cur);
                quad_centre_at(&qs[hit], t_prev, c_prev);
                for (int k = 0; k < 3; k++) pp[k] = p[k] - c_cur[k] + c_prev[k];
                double xc, yc, xp, yp;
                assert_true(to_pixels(&vp_cur, p, &xc, &yc));
                assert_true(to_pixels(&vp_prev, pp, &xp, &yp));
                double want[2] = {xc - xp, yc - yp}; /* current minus previous */
                bool moving = fabs(want[0]) > ZERO_TOL_PX || fabs(want[1]) > ZERO_TOL_PX;
                double tol = moving ? TOL_PX : ZERO_TOL_PX;
                for (int k = 0; k < 2; k++) {
                    double e = fabs(got[k] - want[k]);
                    if (moving && e > cr.max_err_px) cr.max_err_px = e;
                    if (!moving && fabs(got[k]) > cr.max_still_px) cr.max_still_px = fabs(got[k]);
                    if (fabs(want[k]) > cr.max_expect_px) cr.max_expect_px = fabs(want[k]);
                }
                if ((!(fabs(got[0] - want[0]) <= tol) || !(fabs(got[1] - want[1]) <= tol)) && bad++ < 8)
                    print_error("eye %d pixel (%d,%d) square %d: gpu (%.4f, %.4f) px, cpu (%.4f, %.4f) px\n", eye, x, y,
                                hit, got[0], got[1], want[0], want[1]);
                if (moving) {
                    cr.moving++;
                    for (int k = 0; k < 2; k++) {
                        cr.mean_expect[k] += want[k];
                        cr.mean_got[k] += got[k];
                    }
                } else {
                    cr.still++;
                }
            }
    }
    if (cr.moving)
        for (int k = 0; k < 2; k++) {
            cr.mean_expect[k] /= cr.moving;
            cr.mean_got[k] /= cr.moving;
        }
    assert_int_equal(bad, 0);
    free(mv);
    free(rgba);
    return cr;
}

static void print_result(const char *what, const check_result *cr)
{
    print_message("%s: %d moving px (mean gpu (%.3f, %.3f) cpu (%.3f, %.3f) px, largest %.2f px), worst error %.2e px; "
                  "%d static + %d empty px, worst |mv| %.2e px\n",
                  what, cr->moving, cr->mean_got[0], cr->mean_got[1], cr->mean_expect[0], cr->mean_expect[1],
                  cr->max_expect_px, cr->max_err_px, cr->still, cr->empty, cr->max_still_px);
}

static fv_frame_input frame_at(const fv_head *head, uint64_t id, double t_s)
{
    fv_frame_input in;
    assert_int_equal(fv_renderer_frame_input(g_r, head, id, t_s, &in), FV_OK);
    /* Full resolution: the colours tell the objects apart per pixel (foveation, on by default, would fill the
     * periphery from the nearest samples). */
    in.quality.fovea.enabled = false;
    return in;
}

/* ---- (1) static scene, static head ---------------------------------------------------------------------------- */

static void static_scene_and_head_give_zero_motion_in_both_eyes(void **state)
{
    (void)state;
    NEED_GPU();
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load("cornell", &s), FV_OK);
    assert_false(fv_scene_is_animated(s));
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    float *mv = malloc((size_t)W * H * 2 * sizeof *mv);
    float *rgba = malloc((size_t)W * H * 4 * sizeof *rgba);
    assert_true(mv && rgba);
    /* time advances, nothing moves */
    for (uint64_t f = 0; f < 3; f++) {
        fv_frame_input in = frame_at(NULL, f, (double)f / 60.0);
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        for (int eye = 0; eye < 2; eye++) {
            assert_int_equal(fv_renderer_read_motion(g_r, eye, mv, (size_t)W * H * 2), FV_OK);
            assert_int_equal(fv_renderer_read_linear(g_r, eye, rgba, (size_t)W * H * 4), FV_OK);
            int covered = 0;
            double worst = 0;
            for (size_t p = 0; p < (size_t)W * H; p++) {
                double a = fmax(fabs(mv[p * 2] * (double)W), fabs(mv[p * 2 + 1] * (double)H));
                if (!(a <= ZERO_TOL_PX)) fail_msg("frame %d eye %d pixel %zu: motion %.4g px", (int)f, eye, p, a);
                if (a > worst) worst = a;
                if (rgba[p * 4] + rgba[p * 4 + 1] + rgba[p * 4 + 2] > 0.0f) covered++;
            }
            /* lit pixels (the box's dark corners do not count): something was drawn */
            if (!(covered > W * H / 4)) fail_msg("eye %d: only %d of %d px lit", eye, covered, W * H);
            if (f == 2) print_message("cornell eye %d: %d lit px, worst |mv| %.2e px\n", eye, covered, worst);
        }
    }
    fv_scene_destroy(&s);

    /* An animated scene drawn twice at the same time (and head) does not move either. */
    const quad qs[2] = {
        {.centre_m = {0, 0, -1.0}, .half_m = 0.15, .amp_m = {0.2, 0.05, 0}, .freq_hz = 0.5, .emissive = {1, 0, 0}},
        {.centre_m = {0, 0, -2.5}, .half_m = 4.0, .emissive = {0, 1, 0}},
    };
    s = build_scene(qs, 2);
    assert_true(fv_scene_is_animated(s));
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    fv_frame_input a = frame_at(NULL, 10, 0.3), b = frame_at(NULL, 11, 0.3);
    assert_int_equal(fv_renderer_draw(g_r, &a), FV_OK);
    assert_int_equal(fv_renderer_draw(g_r, &b), FV_OK);
    check_result cr = check_motion(qs, 2, &a, 0.3, &b, 0.3);
    print_result("animated scene, same time twice", &cr);
    assert_int_equal(cr.moving, 0);
    assert_true(cr.still > W * H);
    free(mv);
    free(rgba);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

/* ---- (2) an object bobbing sideways, static head ------------------------------------------------------------ */

static void bobbing_object_moves_by_its_projected_displacement(void **state)
{
    (void)state;
    NEED_GPU();
    /* A red square 1 m ahead bobbing right and up (and a little towards the eyes) in front of a static green wall
     * 2.5 m away that leaves a border of empty pixels. */
    const quad qs[2] = {
        {.centre_m = {0, 0, -1.0}, .half_m = 0.15, .amp_m = {0.2, 0.06, 0.05}, .freq_hz = 0.5, .emissive = {1, 0, 0}},
        {.centre_m = {0, 0, -2.5}, .half_m = 2.2, .emissive = {0, 1, 0}},
    };
    fv_scene *s = build_scene(qs, 2);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    /* The first frame after a load has no previous frame: zero motion. */
    const double t[3] = {0.0, 1.0 / 6.0, 0.25};
    fv_frame_input in[3];
    in[0] = frame_at(NULL, 0, t[0]);
    assert_int_equal(fv_renderer_draw(g_r, &in[0]), FV_OK);
    check_result cr = check_motion(qs, 2, &in[0], t[0], &in[0], t[0]);
    assert_int_equal(cr.moving, 0);
    /* Frame N-1 -> N, then N -> N+1 (previous means the last frame drawn, not the first). */
    for (int f = 1; f < 3; f++) {
        in[f] = frame_at(NULL, (uint64_t)f, t[f]);
        assert_int_equal(fv_renderer_draw(g_r, &in[f]), FV_OK);
        cr = check_motion(qs, 2, &in[f - 1], t[f - 1], &in[f], t[f]);
        char what[64];
        snprintf(what, sizeof what, "bob t %.3f -> %.3f s", t[f - 1], t[f]);
        print_result(what, &cr);
        assert_true(cr.moving > 200);      /* the square covers many pixels of both eyes */
        assert_true(cr.still > W * H / 2); /* the wall, in both eyes */
        assert_true(cr.empty > W * H / 8); /* and the cleared border */
        assert_true(cr.max_expect_px > 1.0); /* a real displacement */
        /* sign: the square moved right (+x) and up (-y in the image), and the vectors say so */
        assert_true(cr.mean_got[0] > 1.0);
        assert_true(cr.mean_got[1] < -0.2);
    }
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

/* ---- (3) the head moves over a static scene ----------------------------------------------------------------- */

static fv_head head_pose(double x, double y, double z, double yaw_deg, double pitch_deg)
{
    fv_head h = {.position_m = fv_v3((float)x, (float)y, (float)z), .ipd_mm = 63.0f, .from_file = true};
    fv_quat yaw = fv_quat_axis_angle(fv_v3(0, 1, 0), (float)fv_deg_to_rad(yaw_deg));
    fv_quat pitch = fv_quat_axis_angle(fv_v3(1, 0, 0), (float)fv_deg_to_rad(pitch_deg));
    h.orientation = fv_quat_normalize(fv_quat_mul(yaw, pitch));
    return h;
}

static void head_motion_reprojects_static_planes_at_their_depths(void **state)
{
    (void)state;
    NEED_GPU();
    /* A wall 2 m away and a smaller square 0.8 m away: different depths, different parallax. */
    const quad qs[2] = {
        {.centre_m = {0.1, -0.05, -0.8}, .half_m = 0.15, .emissive = {1, 0, 0}},
        {.centre_m = {0, 0, -2.0}, .half_m = 4.0, .emissive = {0, 1, 0}},
    };
    fv_scene *s = build_scene(qs, 2);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    /* translation only, then translation and rotation */
    const fv_head a = head_pose(0, 0, 0, 0, 0);
    const fv_head b = head_pose(0.03, -0.02, 0.04, 0, 0);
    const fv_head c = head_pose(0.05, 0.0, 0.02, 2.0, -1.5);
    fv_frame_input fa = frame_at(&a, 0, 0.0), fb = frame_at(&b, 1, 1.0 / 90), fc = frame_at(&c, 2, 2.0 / 90);
    assert_int_equal(fv_renderer_draw(g_r, &fa), FV_OK);
    assert_int_equal(fv_renderer_draw(g_r, &fb), FV_OK);
    check_result cr = check_motion(qs, 2, &fa, 0.0, &fb, 1.0 / 90);
    print_result("head translates", &cr);
    assert_true(cr.moving > W * H); /* everything moves, in both eyes */
    assert_true(cr.max_expect_px > 1.0);
    /* the head moved left-to-right: the world slides left (-x) in the image */
    assert_true(cr.mean_got[0] < -0.5);
    assert_int_equal(fv_renderer_draw(g_r, &fc), FV_OK);
    cr = check_motion(qs, 2, &fb, 1.0 / 90, &fc, 2.0 / 90);
    print_result("head translates and turns", &cr);
    assert_true(cr.moving > W * H);
    assert_true(cr.max_expect_px > 2.0);
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

/* ---- (4) both at once over consecutive frames ---------------------------------------------------------------- */

static void head_and_object_motion_combine_over_consecutive_frames(void **state)
{
    (void)state;
    NEED_GPU();
    const quad qs[3] = {
        {.centre_m = {-0.1, 0, -0.9}, .half_m = 0.12, .amp_m = {0.15, -0.1, 0.08}, .freq_hz = 0.7, .phase_rad = 0.4,
         .emissive = {1, 0, 0}},
        {.centre_m = {0.25, 0.15, -1.4}, .half_m = 0.2, .amp_m = {0, 0.2, 0}, .freq_hz = 0.3, .emissive = {0, 0, 1}},
        {.centre_m = {0, 0, -3.0}, .half_m = 6.0, .emissive = {0, 1, 0}},
    };
    fv_scene *s = build_scene(qs, 3);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    fv_frame_input prev;
    double t_prev = 0;
    for (int f = 0; f < 4; f++) {
        double t = 0.1 + f / 30.0;
        fv_head h = head_pose(0.01 * f, 0.004 * f * f, -0.01 * f, -1.0 * f, 0.5 * f);
        fv_frame_input in = frame_at(&h, (uint64_t)f, t);
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        if (f > 0) {
            check_result cr = check_motion(qs, 3, &prev, t_prev, &in, t);
            char what[64];
            snprintf(what, sizeof what, "head and objects, frame %d", f);
            print_result(what, &cr);
            assert_true(cr.moving > W * H);
            assert_true(cr.max_expect_px > 1.0);
        }
        prev = in;
        t_prev = t;
    }
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

static void read_motion_refuses_bad_calls(void **state)
{
    (void)state;
    NEED_GPU();
    float small[4];
    fv_test_log_capture_begin();
    assert_int_equal(fv_renderer_read_motion(g_r, 0, small, 4), FV_ERR_INVALID_ARG);
    fv_test_log_capture_end();
    fv_assert_log_contains("read_motion needs");
    assert_int_equal(fv_renderer_read_motion(g_r, 2, small, 4), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_renderer_read_motion(g_r, 0, NULL, 0), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

/* No pass reads the motion vectors (foveation's surface target holds its own): a renderer made without
 * fv_renderer_desc.motion_target draws no motion target (the G-buffer's plan says which), and read_motion says so
 * instead of returning an image nobody drew; with it (g_r), the plan says they are kept. */
static void motion_vectors_are_drawn_only_when_asked_for(void **state)
{
    (void)state;
    NEED_GPU();
    fv_renderer *r = NULL;
    assert_int_equal(fv_gpu_test_setup(16, 16, &r), 0);
    assert_non_null(r);
    const quad qs[1] = {{.centre_m = {0, 0, -1.0}, .half_m = 0.15, .emissive = {1, 0, 0}}};
    fv_scene *s = build_scene(qs, 1);
    assert_int_equal(fv_renderer_load_scene(r, s), FV_OK);
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);
    fv_frame_input in = frame_at(NULL, 1, 0.0);
    assert_int_equal(fv_renderer_draw(r, &in), FV_OK);
    const fv_plan_entry *without = fv_frame_plan_find(fv_renderer_plan(r), "gbuffer");
    const fv_plan_entry *with = fv_frame_plan_find(fv_renderer_plan(g_r), "gbuffer");
    assert_non_null(without);
    assert_non_null(with);
    assert_null(strstr(without->reason, "motion vectors kept"));
    assert_non_null(strstr(with->reason, "motion vectors kept"));
    float mv[16 * 16 * 2];
    fv_test_log_capture_begin();
    assert_int_equal(fv_renderer_read_motion(r, 0, mv, 16 * 16 * 2), FV_ERR_STATE);
    fv_test_log_capture_end();
    fv_assert_log_contains("draws no motion vectors");
    assert_int_equal(fv_gpu_test_teardown(&r), 0);
    fv_scene_destroy(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(static_scene_and_head_give_zero_motion_in_both_eyes),
        cmocka_unit_test(motion_vectors_are_drawn_only_when_asked_for),
        cmocka_unit_test(bobbing_object_moves_by_its_projected_displacement),
        cmocka_unit_test(head_motion_reprojects_static_planes_at_their_depths),
        cmocka_unit_test(head_and_object_motion_combine_over_consecutive_frames),
        cmocka_unit_test(read_motion_refuses_bad_calls),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
