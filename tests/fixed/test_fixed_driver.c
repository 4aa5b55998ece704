/* @brief The "fixed" driver: URIs (keys, defaults, ranges, malformed input), the gaze it reports (yaw + right,
 * pitch + up, unit directions, parallel without vergence, converging on the fixation point with it), sample pacing
 * on a simulated clock, and the registry opening it by scheme and treating it as virtual (never "auto"). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fv_fixed_driver.h"
#include "fv_registry.h"
#include "fv_test.h"

#define DEG (FV_PI / 180.0)

static double len3(fv_vec3 v) { return sqrt((double)v.x * v.x + (double)v.y * v.y + (double)v.z * v.z); }

static void parses_keys_and_defaults(void **state)
{
    (void)state;
    fv_fixed_desc d;
    assert_int_equal(fv_fixed_parse_uri("fixed:", &d), FV_OK);
    assert_true(d.yaw_deg == 0 && d.pitch_deg == 0 && d.vergence_m == 0 && d.rate_hz == 120 && d.ipd_mm == 63);
    assert_int_equal(fv_fixed_parse_uri("fixed:yaw_deg=10,pitch_deg=-5", &d), FV_OK);
    assert_true(d.yaw_deg == 10 && d.pitch_deg == -5);
    assert_int_equal(fv_fixed_parse_uri("fixed:pitch_deg=2.5&vergence_m=0.5?rate_hz=90,ipd_mm=60,pupil_mm=3", &d),
                     FV_OK);
    assert_true(d.pitch_deg == 2.5 && d.vergence_m == 0.5 && d.rate_hz == 90 && d.ipd_mm == 60 && d.pupil_mm == 3);
    /* the extremes of every range are accepted */
    assert_int_equal(fv_fixed_parse_uri("fixed:yaw_deg=-89,pitch_deg=89,vergence_m=0.05,rate_hz=2000", &d), FV_OK);
    assert_int_equal(fv_fixed_parse_uri("fixed:yaw_deg=89,pitch_deg=-89,vergence_m=1000,rate_hz=1", &d), FV_OK);
}

static void rejects_bad_uris(void **state)
{
    (void)state;
    fv_fixed_desc d;
    const char *parse[] = {NULL, "", "sim:seed=1", "fixed:yaw_deg", "fixed:yaw=3", "fixed:yaw_deg=",
                           "fixed:yaw_deg=abc", "fixed:yaw_deg=1x", "fixed:yaw_deg=1,yaw_deg=2", "fixed:yaw_deg=1e999"};
    for (size_t i = 0; i < sizeof parse / sizeof parse[0]; i++)
        if (fv_fixed_parse_uri(parse[i], &d) != FV_ERR_PARSE) fail_msg("'%s' was not refused as malformed", parse[i]);
    const char *range[] = {"fixed:yaw_deg=90", "fixed:yaw_deg=-90", "fixed:pitch_deg=89.5", "fixed:yaw_deg=nan",
                           "fixed:pitch_deg=inf", "fixed:vergence_m=0", "fixed:vergence_m=0.01",
                           "fixed:vergence_m=2000", "fixed:rate_hz=0", "fixed:rate_hz=1e6", "fixed:ipd_mm=10",
                           "fixed:pupil_mm=0", "fixed:pupil_mm=12"};
    for (size_t i = 0; i < sizeof range / sizeof range[0]; i++)
        if (fv_fixed_parse_uri(range[i], &d) != FV_ERR_RANGE) fail_msg("'%s' was not refused as out of range", range[i]);
    char longer[400];
    memset(longer, 'a', sizeof longer - 1);
    longer[sizeof longer - 1] = '\0';
    memcpy(longer, "fixed:", 6);
    assert_int_equal(fv_fixed_parse_uri(longer, &d), FV_ERR_PARSE);
}

static void directions_follow_yaw_pitch_and_vergence(void **state)
{
    (void)state;
    fv_fixed_desc d;
    fv_gaze_sample s;
    assert_int_equal(fv_fixed_parse_uri("fixed:yaw_deg=10,pitch_deg=-5", &d), FV_OK);
    fv_fixed_sample(&d, &s);
    for (int e = 0; e < 2; e++) {
        fv_vec3 v = s.eye[e].direction;
        assert_true(fabs(len3(v) - 1.0) < 1e-6);
        assert_true(v.x > 0 && v.y < 0 && v.z < 0); /* right, down, forward */
        assert_true(fabs(atan2(v.x, -v.z) - 10 * DEG) < 1e-6);
        assert_true(fabs(asin(v.y) + 5 * DEG) < 1e-6);
        assert_true(s.eye[e].flags & FV_EYE_DIRECTION_VALID);
    }
    /* parallel without vergence; the eyes at -+ipd/2 */
    assert_true(s.eye[0].direction.x == s.eye[1].direction.x && s.eye[0].origin_mm.x == -31.5f &&
                s.eye[1].origin_mm.x == 31.5f);
    assert_true(s.confidence == 1.0f && s.eye[0].pupil_mm == 4.0f);
    /* straight ahead at 0.5 m: the eyes turn in, each towards the point (0, 0, -500 mm) */
    assert_int_equal(fv_fixed_parse_uri("fixed:vergence_m=0.5", &d), FV_OK);
    fv_fixed_sample(&d, &s);
    assert_true(s.eye[0].direction.x > 0 && s.eye[1].direction.x < 0);
    for (int e = 0; e < 2; e++) {
        fv_vec3 o = s.eye[e].origin_mm, v = s.eye[e].direction;
        double t = -500.0 / v.z; /* where the ray reaches z = -500 */
        assert_true(fabs(o.x + t * v.x) < 1e-3 && fabs(o.y + t * v.y) < 1e-3);
        assert_true(fabs(len3(v) - 1.0) < 1e-6);
    }
    /* the extremes stay finite */
    assert_int_equal(fv_fixed_parse_uri("fixed:yaw_deg=-89,pitch_deg=89,vergence_m=0.05", &d), FV_OK);
    fv_fixed_sample(&d, &s);
    for (int e = 0; e < 2; e++) assert_true(fv_v3_isfinite(s.eye[e].direction) && fabs(len3(s.eye[e].direction) - 1) < 1e-6);
}

static void paces_samples_on_the_clock(void **state)
{
    (void)state;
    fv_clock clock;
    fv_clock_sim_init(&clock, 5 * FV_NS_PER_S);
    fv_device_open_desc od = {.clock = &clock};
    fv_device *dev = NULL;
    assert_int_equal(fv_fixed_driver.open("fixed:yaw_deg=3,rate_hz=100", &od, &dev), FV_OK);
    fv_gaze_sample out[64];
    size_t n = 0;
    assert_int_equal(fv_device_read(dev, out, 64, &n, 0), FV_OK); /* sample 0 is due at the open */
    assert_int_equal(n, 1);
    assert_int_equal(fv_device_read(dev, out, 64, &n, 0), FV_TIMEOUT);
    fv_clock_sim_advance(&clock, 50 * FV_NS_PER_MS); /* 5 more at 10 ms */
    assert_int_equal(fv_device_read(dev, out, 64, &n, 0), FV_OK);
    assert_int_equal(n, 5);
    for (size_t i = 0; i < n; i++) {
        assert_int_equal(out[i].t_host_ns, 5 * FV_NS_PER_S + (int64_t)(i + 1) * 10 * FV_NS_PER_MS);
        assert_int_equal(out[i].seq, i + 1);
        assert_true(out[i].flags & FV_GAZE_HOST_TIME_VALID);
    }
    /* waiting sleeps to the next sample (the simulated clock jumps there) */
    assert_int_equal(fv_device_read(dev, out, 64, &n, 100), FV_OK);
    assert_int_equal(n, 1);
    /* a reader far behind gets the newest `cap` samples, not a backlog */
    fv_clock_sim_advance(&clock, 10 * FV_NS_PER_S);
    assert_int_equal(fv_device_read(dev, out, 4, &n, 0), FV_OK);
    assert_int_equal(n, 4);
    assert_true(fv_clock_now_ns(&clock) - out[3].t_host_ns < 10 * FV_NS_PER_MS);
    assert_int_equal(fv_device_read(dev, out, 4, &n, 0), FV_TIMEOUT);
    fv_device_close(&dev);
    assert_null(dev);
}

static void registry_opens_it_and_keeps_it_virtual(void **state)
{
    (void)state;
    const fv_driver *drivers[] = {&fv_fixed_driver, NULL};
    fv_registry reg;
    assert_int_equal(fv_registry_init(&reg, drivers), FV_OK);
    assert_true(fv_registry_is_virtual(&fv_fixed_driver));
    fv_device *dev = NULL;
    assert_int_equal(fv_registry_open(&reg, "fixed:yaw_deg=-10", NULL, &dev), FV_OK);
    assert_string_equal(dev->info.driver, "fixed");
    fv_device_close(&dev);
    assert_int_equal(fv_registry_open(&reg, "auto", NULL, &dev), FV_ERR_NOT_FOUND); /* not a tracker */
    assert_int_not_equal(fv_registry_open(&reg, "fixed:yaw_deg=100", NULL, &dev), FV_OK);
    assert_null(dev);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(parses_keys_and_defaults),
        cmocka_unit_test(rejects_bad_uris),
        cmocka_unit_test(directions_follow_yaw_pitch_and_vergence),
        cmocka_unit_test(paces_samples_on_the_clock),
        cmocka_unit_test(registry_opens_it_and_keeps_it_virtual),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
