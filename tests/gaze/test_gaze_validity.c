/* @brief The physical validity rules (fv_gaze_validity.h) on their own and in the pipeline: the vergence bounds at
 * their edges, backward rays, the one-line report, and a live device's impossible eye pair dropped by the pipeline
 * (it averaged the two eyes into a ray neither made before). */
#include <math.h>

#include "fv_gaze_pipeline.h"
#include "fv_gaze_validity.h"
#include "fv_test.h"

/* Head-frame direction of (yaw right, pitch up) in degrees. */
static fv_vec3 dir(double yaw, double pitch)
{
    double a[2] = {yaw, pitch};
    return fv_gaze_angles_to_dir(a);
}

static void validity_bounds_at_their_edges(void **state)
{
    (void)state;
    /* left yaw - right yaw: positive converging */
    assert_int_equal(fv_gaze_vergence_fault(dir(-4.9, 0), dir(4.9, 0)), -1);   /* 9.8 divergent */
    assert_int_equal(fv_gaze_vergence_fault(dir(-5.1, 0), dir(5.1, 0)), FV_GAZE_FAULT_DIVERGENT);
    assert_int_equal(fv_gaze_vergence_fault(dir(29.9, 0), dir(-29.9, 0)), -1); /* 59.8 convergent */
    assert_int_equal(fv_gaze_vergence_fault(dir(30.1, 0), dir(-30.1, 0)), FV_GAZE_FAULT_CONVERGENT);
    assert_int_equal(fv_gaze_vergence_fault(dir(0, 4.9), dir(0, -4.9)), -1);
    assert_int_equal(fv_gaze_vergence_fault(dir(0, 5.1), dir(0, -5.1)), FV_GAZE_FAULT_VERTICAL);
    /* a whole-field gaze shift with normal vergence is fine anywhere ahead */
    assert_int_equal(fv_gaze_vergence_fault(dir(42, -20), dir(40, -20)), -1);
    /* forward half-space only */
    assert_true(fv_gaze_direction_possible(fv_v3(0.999f, 0, -0.01f)));
    assert_false(fv_gaze_direction_possible(fv_v3(1, 0, 0)));
    assert_false(fv_gaze_direction_possible(fv_v3(0, 0, 1)));
    assert_false(fv_gaze_direction_possible(fv_v3(0, 0, 0)));
    assert_false(fv_gaze_direction_possible(fv_v3(NAN, 0, -1)));
}

static void validity_enforce_and_report(void **state)
{
    (void)state;
    fv_gaze_sample s;
    fv_gaze_sample_init_invalid(&s, 0, 0);
    s.eye[FV_EYE_LEFT].direction = dir(-8, 0);
    s.eye[FV_EYE_RIGHT].direction = dir(8, 0); /* 16 deg divergent */
    s.combined.direction = dir(0, 0);
    for (int e = 0; e < 2; e++) s.eye[e].flags = FV_EYE_DIRECTION_VALID;
    s.combined.flags = FV_EYE_DIRECTION_VALID;
    fv_vec3 d;
    assert_false(fv_gaze_sample_direction(&s, &d)); /* the truth of the evaluation: none */
    uint32_t f = fv_gaze_sample_enforce(&s);
    assert_int_equal(f, 1u << FV_GAZE_FAULT_DIVERGENT);
    assert_int_equal((s.eye[0].flags | s.eye[1].flags | s.combined.flags) & FV_EYE_DIRECTION_VALID, 0);
    assert_true(isnan(s.combined.direction.x));

    fv_gaze_validity_counts c = {0};
    char line[200];
    fv_gaze_validity_describe(&c, line, sizeof line);
    assert_string_equal(line, "none");
    fv_gaze_validity_count(&c, 1u << FV_GAZE_FAULT_POINT_BEHIND, f);
    fv_gaze_validity_count(&c, 0, 1u << FV_GAZE_FAULT_BACKWARD);
    fv_gaze_validity_describe(&c, line, sizeof line);
    assert_string_equal(line, "1 repaired (gaze point behind the head: 1), 2 dropped (direction pointing backwards: "
                              "1, eyes diverging: 1)");
    char tiny[12];
    fv_gaze_validity_describe(&c, tiny, sizeof tiny); /* truncated, terminated */
    assert_string_equal(tiny, "1 repaired ");
}

static void pipeline_drops_an_impossible_eye_pair(void **state)
{
    (void)state;
    fv_gaze_pipeline *p = NULL;
    assert_int_equal(fv_gaze_pipeline_create(NULL, &p), FV_OK);
    for (int i = 0; i < 10; i++) {
        fv_gaze_sample s;
        int64_t t = (int64_t)i * 8333333;
        fv_gaze_sample_init_invalid(&s, t, t);
        s.flags |= FV_GAZE_HOST_TIME_VALID;
        bool bad = i >= 5; /* eyes 20 deg apart vertically from the sixth sample on, no combined ray */
        s.eye[FV_EYE_LEFT].direction = dir(2, bad ? 10 : 0);
        s.eye[FV_EYE_RIGHT].direction = dir(-2, bad ? -10 : 0);
        for (int e = 0; e < 2; e++) s.eye[e].flags = FV_EYE_DIRECTION_VALID;
        assert_int_equal(fv_gaze_pipeline_push(p, &s), FV_OK);
    }
    fv_gaze_pipeline_stats st;
    fv_gaze_pipeline_get_stats(p, &st);
    assert_int_equal(st.invalid, 5);
    assert_int_equal(st.impossible, 5);
    fv_gaze_pipeline_destroy(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(validity_bounds_at_their_edges),
        cmocka_unit_test(validity_enforce_and_report),
        cmocka_unit_test(pipeline_drops_an_impossible_eye_pair),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
