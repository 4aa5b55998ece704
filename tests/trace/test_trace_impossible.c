/* @brief Physically impossible gaze in recordings (issue 23, item 3): a Pupil Core export whose lines of sight meet
 * behind the head (gaze_point_3d_z < 0, confident rows) is repaired from the eyes' gaze normals (or the point
 * flipped) instead of being read as a ray reversed by ~180 deg; a direction pointing backwards (SRanipal eye, Pico
 * combined, Pupil Invisible azimuth) and a pair of eyes no human can make (Tobii: diverging, converging,
 * misaligned vertically) are marked invalid. Every case is counted per kind in the reader's stats, and the
 * evaluation of `fovea gaze eval` on such a recording neither scores nor predicts a reversed ray. The files are
 * made here, a few rows each. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fv_clock.h"
#include "fv_sim_eval.h"
#include "fv_test.h"
#include "fv_trace.h"
#include "fv_trace_driver.h"

#define MAX_ROWS 512

typedef struct read_result {
    fv_gaze_sample s[MAX_ROWS];
    int n;
    fv_trace_reader_stats rs;
} read_result;

static void read_mem(const char *text, read_result *out)
{
    memset(out, 0, sizeof *out);
    fv_trace_reader_desc d = {.data = text, .size = strlen(text), .blinks_path = ""};
    fv_trace_reader *r = NULL;
    assert_int_equal(fv_trace_reader_create(NULL, &d, &r), FV_OK);
    fv_result res;
    while (out->n < MAX_ROWS && (res = fv_trace_reader_next(r, &out->s[out->n])) == FV_OK) out->n++;
    out->rs = *fv_trace_reader_get_stats(r);
    fv_trace_reader_destroy(&r);
}

/* Nothing handed out points backwards, and a valid direction is a unit vector. */
static void no_reversed_ray(const read_result *rr)
{
    for (int i = 0; i < rr->n; i++) {
        const fv_eye_sample *e[3] = {&rr->s[i].eye[0], &rr->s[i].eye[1], &rr->s[i].combined};
        for (int k = 0; k < 3; k++)
            if (e[k]->flags & FV_EYE_DIRECTION_VALID) assert_true(e[k]->direction.z < 0.0f);
    }
}

static const char g_core_hdr[] =
    "gaze_timestamp,world_index,confidence,norm_pos_x,norm_pos_y,base_data,gaze_point_3d_x,gaze_point_3d_y,"
    "gaze_point_3d_z,eye_center0_3d_x,eye_center0_3d_y,eye_center0_3d_z,gaze_normal0_x,gaze_normal0_y,gaze_normal0_z,"
    "eye_center1_3d_x,eye_center1_3d_y,eye_center1_3d_z,gaze_normal1_x,gaze_normal1_y,gaze_normal1_z\n";

/* One Pupil Core row: the point (camera frame: x right, y down, z forward, mm); normals NULL = empty columns. */
static size_t core_row(char *buf, size_t cap, double t, double conf, const double p[3], const double n0[3],
                       const double n1[3])
{
    char e0[160] = ",,,,,", e1[160] = ",,,,,";
    if (n0) snprintf(e0, sizeof e0, "30,0,-20,%.6f,%.6f,%.6f", n0[0], n0[1], n0[2]);
    if (n1) snprintf(e1, sizeof e1, "-30,0,-20,%.6f,%.6f,%.6f", n1[0], n1[1], n1[2]);
    return (size_t)snprintf(buf, cap, "%.6f,1,%.3f,0.5,0.5,x,%.3f,%.3f,%.3f,%s,%s\n", t, conf, p[0], p[1], p[2], e0, e1);
}

static void pupil_core_point_behind_the_head_is_repaired_not_reversed(void **state)
{
    (void)state;
    static char text[8192];
    size_t n = (size_t)snprintf(text, sizeof text, "%s", g_core_hdr);
    /* eye0 = right eye at x = +30 turned 3.4 deg nasally (left), eye1 = left eye turned right, both slightly down */
    const double n0[3] = {-0.06, 0.1, 0.993}, n1[3] = {0.06, 0.1, 0.993};
    const double ahead[3] = {0, 50, 500}, behind[3] = {40, 20, -400};
    n += core_row(text + n, sizeof text - n, 100.000, 0.95, ahead, n0, n1);  /* fine */
    n += core_row(text + n, sizeof text - n, 100.004, 0.95, behind, n0, n1); /* behind: the normals repair it */
    n += core_row(text + n, sizeof text - n, 100.008, 0.95, behind, NULL, NULL); /* behind, no normals: flipped */
    n += core_row(text + n, sizeof text - n, 100.012, 0.30, behind, n0, n1); /* not confident: invalid anyway */
    n += core_row(text + n, sizeof text - n, 100.016, 0.95, ahead, n0, n1);
    read_result *rr = test_malloc(sizeof *rr);
    read_mem(text, rr);
    assert_int_equal(rr->n, 5);
    no_reversed_ray(rr);
    /* repaired from the normals: their mean in the head frame (x, -y, -z) = (0, -0.1, -0.993), normalised */
    const fv_eye_sample *c = &rr->s[1].combined;
    assert_true(c->flags & FV_EYE_DIRECTION_VALID);
    assert_float_equal(c->direction.x, 0.0, 1e-5);
    assert_float_equal(c->direction.y, -0.1 / sqrt(0.01 + 0.993 * 0.993), 1e-4);
    /* flipped: -p = (-40, -20, 400) in the camera frame, (-40, 20, -400) in the head frame */
    c = &rr->s[2].combined;
    assert_true(c->flags & FV_EYE_DIRECTION_VALID);
    double len = sqrt(40.0 * 40 + 20 * 20 + 400 * 400);
    assert_float_equal(c->direction.x, -40.0 / len, 1e-5);
    assert_float_equal(c->direction.y, 20.0 / len, 1e-5);
    assert_float_equal(c->direction.z, -400.0 / len, 1e-5);
    assert_false(rr->s[3].combined.flags & FV_EYE_DIRECTION_VALID);
    /* counted once per repaired sample, the unconfident row not among them; nothing dropped */
    assert_int_equal(rr->rs.validity.repaired[FV_GAZE_FAULT_POINT_BEHIND], 2);
    assert_int_equal(fv_gaze_validity_total(&rr->rs.validity, true), 2);
    assert_int_equal(fv_gaze_validity_total(&rr->rs.validity, false), 0);
    char why[256];
    fv_gaze_validity_describe(&rr->rs.validity, why, sizeof why);
    assert_string_equal(why, "2 repaired (gaze point behind the head: 2), 0 dropped");
    test_free(rr);
}

static void sranipal_backward_eye_is_dropped(void **state)
{
    (void)state;
    /* SRanipal: +x to the wearer's left, +z forward; an eye direction with z < 0 points backwards */
    static const char text[] =
        "time(100ns);eye_valid_L;eye_valid_R;openness_L;openness_R;pupil_diameter_L(mm);pupil_diameter_R(mm);"
        "gaze_origin_L.x(mm);gaze_origin_L.y(mm);gaze_origin_L.z(mm);gaze_origin_R.x(mm);gaze_origin_R.y(mm);"
        "gaze_origin_R.z(mm);gaze_direct_L.x;gaze_direct_L.y;gaze_direct_L.z;gaze_direct_R.x;gaze_direct_R.y;"
        "gaze_direct_R.z\n"
        "637000000000000000;31;31;1;1;3;3;32;0;0;-32;0;0;0.02;0;0.9998;-0.02;0;0.9998\n"
        "637000000000083333;31;31;1;1;3;3;32;0;0;-32;0;0;0.02;0;-0.9998;-0.02;0;0.9998\n";
    read_result *rr = test_malloc(sizeof *rr);
    read_mem(text, rr);
    assert_int_equal(rr->n, 2);
    no_reversed_ray(rr);
    assert_false(rr->s[1].eye[FV_EYE_LEFT].flags & FV_EYE_DIRECTION_VALID);
    assert_true(rr->s[1].eye[FV_EYE_RIGHT].flags & FV_EYE_DIRECTION_VALID);
    /* the combined ray is the right eye's alone, not a mean with the reversed one */
    assert_true(rr->s[1].combined.flags & FV_EYE_DIRECTION_VALID);
    assert_float_equal(rr->s[1].combined.direction.x, rr->s[1].eye[FV_EYE_RIGHT].direction.x, 1e-6);
    assert_int_equal(rr->rs.validity.dropped[FV_GAZE_FAULT_BACKWARD], 1);
    assert_int_equal(fv_gaze_validity_total(&rr->rs.validity, false), 1);
    test_free(rr);
}

static void pico_and_pupil_invisible_backward_rays_are_dropped(void **state)
{
    (void)state;
    static const char pico[] =
        "Timeline\tCombine Eye Gaze Vector. x\tCombine Eye Gaze Vector. y\tCombine Eye Gaze Vector. z\t"
        "Left Eye Pose Status\tRight Eye Pose Status\tEye Left Blinking\tEye Right Blinking\n"
        "1.000\t0.1\t0\t0.99\t1\t1\tFalse\tFalse\n"
        "1.011\t0.1\t0\t-0.99\t1\t1\tFalse\tFalse\n"
        "1.022\t0.1\t0\t0.99\t1\t1\tFalse\tFalse\n";
    read_result *rr = test_malloc(sizeof *rr);
    read_mem(pico, rr);
    assert_int_equal(rr->n, 3);
    no_reversed_ray(rr);
    assert_false(rr->s[1].combined.flags & FV_EYE_DIRECTION_VALID);
    assert_int_equal(rr->rs.validity.dropped[FV_GAZE_FAULT_BACKWARD], 1);

    static const char cloud[] =
        "section id,recording id,timestamp [ns],gaze x [px],gaze y [px],worn,fixation id,blink id,azimuth [deg],"
        "elevation [deg]\n"
        "s,r,1629390345036471431,484,525,1,,,-6.1,1.4\n"
        "s,r,1629390345041471431,484,525,1,,,170.0,1.4\n"
        "s,r,1629390345046471431,484,525,1,,,-6.1,1.4\n";
    read_mem(cloud, rr);
    assert_int_equal(rr->n, 3);
    no_reversed_ray(rr);
    assert_false(rr->s[1].combined.flags & FV_EYE_DIRECTION_VALID);
    assert_int_equal(rr->rs.validity.dropped[FV_GAZE_FAULT_BACKWARD], 1);
    test_free(rr);
}

/* A Tobii G3 line; eye directions in Tobii's frame (+x to the wearer's left, +z forward). */
static size_t tobii_line(char *buf, size_t cap, double t, double lx, double ly, double rx, double ry)
{
    return (size_t)snprintf(buf, cap,
                            "{\"type\":\"gaze\",\"timestamp\":%.3f,\"data\":{\"gaze2d\":[0.5,0.5],"
                            "\"gaze3d\":[0,0,600],\"eyeleft\":{\"gazeorigin\":[31,0,-20],\"gazedirection\":"
                            "[%.6f,%.6f,%.6f],\"pupildiameter\":3},\"eyeright\":{\"gazeorigin\":[-31,0,-20],"
                            "\"gazedirection\":[%.6f,%.6f,%.6f],\"pupildiameter\":3}}}\n",
                            t, lx, ly, sqrt(1 - lx * lx - ly * ly), rx, ry, sqrt(1 - rx * rx - ry * ry));
}

static void tobii_impossible_eye_pairs_are_dropped(void **state)
{
    (void)state;
    static char text[8192];
    size_t n = 0;
    const double s20 = sin(20.0 * 3.14159265358979 / 180.0), s40 = sin(40.0 * 3.14159265358979 / 180.0);
    /* Tobii x is to the wearer's left: the left eye turned right (nasal) has x < 0. Converging 6 deg: fine. */
    n += tobii_line(text + n, sizeof text - n, 1.00, -0.05, 0, 0.05, 0);
    n += tobii_line(text + n, sizeof text - n, 1.01, s20, 0, -s20, 0);  /* each eye 20 deg outward: 40 divergent */
    n += tobii_line(text + n, sizeof text - n, 1.02, -s40, 0, s40, 0);  /* each 40 deg inward: 80 convergent */
    n += tobii_line(text + n, sizeof text - n, 1.03, 0, s20, 0, -s20);  /* one up, one down: 40 vertical */
    n += tobii_line(text + n, sizeof text - n, 1.04, -0.05, 0, 0.05, 0);
    read_result *rr = test_malloc(sizeof *rr);
    read_mem(text, rr);
    assert_int_equal(rr->n, 5);
    no_reversed_ray(rr);
    for (int i = 0; i < 5; i++) {
        bool ok = i == 0 || i == 4;
        uint32_t any = rr->s[i].eye[0].flags | rr->s[i].eye[1].flags | rr->s[i].combined.flags;
        assert_int_equal((any & FV_EYE_DIRECTION_VALID) != 0, ok);
    }
    assert_int_equal(rr->rs.validity.dropped[FV_GAZE_FAULT_DIVERGENT], 1);
    assert_int_equal(rr->rs.validity.dropped[FV_GAZE_FAULT_CONVERGENT], 1);
    assert_int_equal(rr->rs.validity.dropped[FV_GAZE_FAULT_VERTICAL], 1);
    assert_int_equal(fv_gaze_validity_total(&rr->rs.validity, false), 3);
    test_free(rr);
}

/* `fovea gaze eval`'s engine on a Pupil Core recording whose every third confident row lies behind the head: with
 * the rows read as reversed rays the p95 at 20 ms was ~180 deg; repaired, the eye fixates and the error is small. */
static void gaze_eval_on_points_behind_the_head_scores_no_reversed_ray(void **state)
{
    (void)state;
    static char text[1 << 16];
    size_t n = (size_t)snprintf(text, sizeof text, "%s", g_core_hdr);
    const double n0[3] = {-0.06, 0.0, 0.998}, n1[3] = {0.06, 0.0, 0.998};
    for (int i = 0; i < 400; i++) {
        double t = 200.0 + i * 0.005, yaw = 0.02 * (i % 7); /* a fixation with a little noise, 200 Hz */
        double p[3] = {500.0 * sin(yaw * 3.14159265358979 / 180.0), 0.0, 500.0};
        if (i % 3 == 1) p[2] = -300.0, p[0] = -p[0];
        n += core_row(text + n, sizeof text - n, t, 0.95, p, n0, n1);
    }
    const char *path = fv_test_write_file("core_behind_gaze_positions.csv", text, n);
    char uri[1200];
    snprintf(uri, sizeof uri, "trace:%s?blinks=none", path);
    fv_clock clock;
    fv_clock_sim_init(&clock, 1000000000);
    fv_device_open_desc od = {.clock = &clock};
    fv_device *dev = NULL;
    assert_int_equal(fv_trace_driver.open(uri, &od, &dev), FV_OK);
    fv_sim_eval_desc d = {0};
    fv_sim_eval_result *res = test_malloc(sizeof *res);
    assert_int_equal(fv_sim_eval_run(dev, &clock, &d, res), FV_OK);
    const fv_trace_reader_stats *rs = fv_trace_device_reader_stats(dev);
    assert_non_null(rs);
    const uint64_t repaired = rs->validity.repaired[FV_GAZE_FAULT_POINT_BEHIND];
    fv_device_close(&dev);
    for (int t = FV_SIM_EVAL_TRUTH_RAW; t <= FV_SIM_EVAL_TRUTH_SMOOTHED; t++)
        for (int m = 0; m < FV_SIM_EVAL_METHODS; m++) {
            const fv_sim_eval_error *e = &res->err[t][m][2];
            assert_int_equal(res->horizon_ms[2], 20);
            assert_true(e->n > 300);
            assert_true(e->p95_deg < 5.0);
        }
    assert_int_equal(repaired, 133);
    test_free(res);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(pupil_core_point_behind_the_head_is_repaired_not_reversed),
        cmocka_unit_test(sranipal_backward_eye_is_dropped),
        cmocka_unit_test(pico_and_pupil_invisible_backward_rays_are_dropped),
        cmocka_unit_test(tobii_impossible_eye_pairs_are_dropped),
        cmocka_unit_test(gaze_eval_on_points_behind_the_head_scores_no_reversed_ray),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
