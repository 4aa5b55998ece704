/* @brief The simulated eye and the sim driver: determinism, blink statistics, the saccade main sequence, fixation
 * durations, pupil range and light response, vergence, tracker noise, sample timing, URI errors, clock pacing,
 * 24-bit timestamp unwrapping end to end, a counter that wraps faster than twice the sample interval refused at open,
 * and a 15-bit counter whose dropout gaps exceed half its wrap unwrapped exactly (checked against the host clock). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fv_sim_driver.h"
#include "fv_sim_eye.h"
#include "fv_test.h"

static fv_sim_eye *make_eye(uint64_t seed)
{
    fv_sim_eye_desc d;
    fv_sim_eye_desc_defaults(&d);
    d.seed = seed;
    fv_sim_eye *e = NULL;
    assert_int_equal(fv_sim_eye_create(&d, &e), FV_OK);
    return e;
}

static double angle_deg(fv_vec3 a, fv_vec3 b)
{
    double d = fv_v3_dot(a, b) / (fv_v3_len(a) * fv_v3_len(b));
    return acos(fmin(1.0, fmax(-1.0, d))) * 180.0 / FV_PI;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void sim_eye_is_deterministic_per_seed(void **state)
{
    (void)state;
    fv_sim_eye *a = make_eye(5), *b = make_eye(5), *c = make_eye(6);
    int differ = 0;
    for (int i = 0; i < 3000; i++) {
        fv_gaze_sample sa, sb, sc;
        fv_sim_truth ta, tb, tc;
        assert_int_equal(fv_sim_eye_next(a, &sa, &ta), FV_OK);
        /* querying the truth ahead must not change what follows */
        fv_sim_truth ahead;
        assert_true(fv_sim_eye_truth_at(a, ta.t_ns + 50000000, &ahead));
        assert_int_equal(fv_sim_eye_next(b, &sb, &tb), FV_OK);
        assert_int_equal(fv_sim_eye_next(c, &sc, &tc), FV_OK);
        assert_int_equal(sa.t_device_ns, sb.t_device_ns);
        assert_int_equal(sa.seq, sb.seq);
        assert_memory_equal(&sa.eye[0].direction, &sb.eye[0].direction, sizeof(fv_vec3));
        assert_true(ta.yaw_deg == tb.yaw_deg && ta.pitch_deg == tb.pitch_deg);
        if (ta.yaw_deg != tc.yaw_deg) differ++;
    }
    assert_true(differ > 2900);
    fv_sim_eye_destroy(&a);
    fv_sim_eye_destroy(&b);
    fv_sim_eye_destroy(&c);
    assert_null(a);
}

static void sim_eye_blinks_about_15_per_minute_of_100_to_400_ms(void **state)
{
    (void)state;
    fv_sim_eye *e = make_eye(11);
    const int64_t span = INT64_C(600) * 1000000000; /* 10 minutes */
    uint64_t blink_samples = 0, blink_samples_flagged = 0;
    fv_gaze_sample s;
    fv_sim_truth t;
    do {
        assert_int_equal(fv_sim_eye_next(e, &s, &t), FV_OK);
        if (t.blink) {
            blink_samples++;
            if ((s.eye[0].flags & FV_EYE_BLINK) && (s.eye[1].flags & FV_EYE_BLINK) &&
                !(s.eye[0].flags & FV_EYE_DIRECTION_VALID) && isnan(s.eye[0].direction.x) && isnan(s.eye[1].pupil_mm))
                blink_samples_flagged++;
        }
    } while (t.t_ns < span);
    int blinks = 0;
    for (size_t i = 0; i < fv_sim_eye_event_count(e); i++) {
        fv_sim_event ev;
        if (!fv_sim_eye_event_get(e, i, &ev) || ev.label != FV_SIM_BLINK || ev.t_start_ns >= span) continue;
        blinks++;
        double ms = (double)(ev.t_end_ns - ev.t_start_ns) * 1e-6;
        assert_true(ms >= 99.9 && ms <= 400.1);
    }
    double per_min = blinks / 10.0;
    print_message("blinks: %.1f per minute\n", per_min);
    assert_true(per_min > 11.0 && per_min < 19.0);
    assert_true(blink_samples > 1000);
    assert_int_equal(blink_samples, blink_samples_flagged); /* every blink sample is invalid and marked */
    fv_sim_eye_destroy(&e);
}

static void sim_eye_saccades_follow_the_main_sequence(void **state)
{
    (void)state;
    fv_sim_eye *e = make_eye(3);
    fv_sim_eye_generate_until(e, INT64_C(120) * 1000000000);
    static double ratios[1024], dur_ratios[1024];
    int n = 0;
    for (size_t i = 0; i < fv_sim_eye_event_count(e) && n < 1024; i++) {
        fv_sim_event ev;
        if (!fv_sim_eye_event_get(e, i, &ev) || ev.label != FV_SIM_SACCADE) continue;
        assert_true(ev.amplitude_deg >= 1.9 && ev.amplitude_deg <= 30.1);
        /* measure the peak velocity from the truth itself (0.25 ms steps) */
        double peak = 0.0;
        fv_sim_truth a, b;
        for (int64_t t = ev.t_start_ns; t + 250000 <= ev.t_end_ns; t += 250000) {
            assert_true(fv_sim_eye_truth_at(e, t, &a));
            assert_true(fv_sim_eye_truth_at(e, t + 250000, &b));
            assert_int_equal(a.label, FV_SIM_SACCADE);
            peak = fmax(peak, angle_deg(a.dir_cyc, b.dir_cyc) / 0.00025);
        }
        double expect = 600.0 * (1.0 - exp(-ev.amplitude_deg / 9.0)); /* Vp = Vmax (1 - e^(-A/C)) */
        ratios[n++] = peak / expect;
        assert_true(peak / expect > 0.7 && peak / expect < 1.35);
        /* duration near Carpenter's 21 ms + 2.2 ms/deg (each within 60%, the median within 25%) */
        double dur_ms = (double)(ev.t_end_ns - ev.t_start_ns) * 1e-6, carpenter = 21.0 + 2.2 * ev.amplitude_deg;
        assert_true(fabs(dur_ms - carpenter) < 0.6 * carpenter);
        dur_ratios[n - 1] = dur_ms / carpenter;
    }
    assert_true(n > 250); /* ~2.5 saccades per second */
    qsort(ratios, (size_t)n, sizeof ratios[0], cmp_double);
    assert_true(fabs(ratios[n / 2] - 1.0) < 0.05); /* median on the main sequence */
    qsort(dur_ratios, (size_t)n, sizeof dur_ratios[0], cmp_double);
    print_message("saccades %d: median peak/main-sequence %.3f, median duration/Carpenter %.3f\n", n, ratios[n / 2],
                  dur_ratios[n / 2]);
    assert_true(fabs(dur_ratios[n / 2] - 1.0) < 0.25);
    fv_sim_eye_destroy(&e);
}

static void sim_eye_fixation_durations_and_event_mix_are_realistic(void **state)
{
    (void)state;
    fv_sim_eye *e = make_eye(4);
    fv_sim_eye_generate_until(e, INT64_C(300) * 1000000000);
    static double fix[4096];
    int nf = 0, pursuits = 0, micro = 0;
    for (size_t i = 0; i < fv_sim_eye_event_count(e); i++) {
        fv_sim_event ev;
        if (!fv_sim_eye_event_get(e, i, &ev)) continue;
        if (ev.label == FV_SIM_FIXATION && nf < 4096) fix[nf++] = (double)(ev.t_end_ns - ev.t_start_ns) * 1e-6;
        if (ev.label == FV_SIM_PURSUIT) {
            pursuits++;
            assert_true(ev.amplitude_deg >= 2.0 && ev.amplitude_deg <= 25.1); /* speed deg/s */
        }
        if (ev.label == FV_SIM_MICROSACCADE) {
            micro++;
            assert_true(ev.amplitude_deg <= 0.81);
        }
    }
    qsort(fix, (size_t)nf, sizeof fix[0], cmp_double);
    print_message("fixations %d median %.0f ms, pursuits %d, microsaccades %d\n", nf, fix[nf / 2], pursuits, micro);
    assert_true(fix[nf / 2] > 180.0 && fix[nf / 2] < 320.0);
    assert_true(fix[0] >= 99.0 && fix[nf - 1] <= 1501.0);
    assert_true(pursuits > 20 && micro > 100);
    fv_sim_eye_destroy(&e);
}

static void sim_eye_pupil_stays_2_to_8_mm_and_follows_light(void **state)
{
    (void)state;
    fv_sim_eye *e = make_eye(8);
    double lo = 1e9, hi = -1e9, err = 0.0;
    int n = 0;
    fv_gaze_sample s;
    fv_sim_truth t;
    do {
        assert_int_equal(fv_sim_eye_next(e, &s, &t), FV_OK);
        assert_true(t.pupil_mm >= 2.0 && t.pupil_mm <= 8.0);
        lo = fmin(lo, t.pupil_mm);
        hi = fmax(hi, t.pupil_mm);
        if (s.eye[0].flags & FV_EYE_PUPIL_VALID) {
            err += fabs(s.eye[0].pupil_mm - t.pupil_mm);
            n++;
        }
    } while (t.t_ns < INT64_C(300) * 1000000000);
    print_message("pupil %.2f .. %.2f mm\n", lo, hi);
    assert_true(hi - lo > 3.0); /* light changes move it by millimetres */
    assert_true(err / n < 0.1); /* measured within the tracker's pupil noise */
    fv_sim_eye_destroy(&e);
}

static void sim_eye_vergence_noise_and_timing(void **state)
{
    (void)state;
    fv_sim_eye_desc d;
    fv_sim_eye_desc_defaults(&d);
    d.seed = 9;
    d.rate_hz = 250.0;
    d.dropout = 0.01;
    fv_sim_eye *e = NULL;
    assert_int_equal(fv_sim_eye_create(&d, &e), FV_OK);
    int n = 0, drops = 0;
    uint64_t prev_seq = 0;
    int64_t prev_t = -1;
    double err_sum = 0.0;
    int nerr = 0;
    for (int i = 0; i < 250 * 120; i++) {
        fv_gaze_sample s;
        fv_sim_truth t;
        assert_int_equal(fv_sim_eye_next(e, &s, &t), FV_OK);
        if (i > 0) drops += (int)(s.seq - prev_seq - 1);
        prev_seq = s.seq;
        assert_true(t.t_ns > prev_t);
        prev_t = t.t_ns;
        /* arrival = capture + latency (4 ms) + transport jitter */
        assert_true(s.t_host_ns - t.t_ns >= 4000000 - 1);
        assert_true(s.flags & FV_GAZE_HOST_TIME_VALID);
        /* vergence: the eyes converge on the fixated point */
        double verg = angle_deg(t.dir_eye[0], t.dir_eye[1]);
        /* the baseline seen from the target shrinks with eccentricity: ipd * sqrt(1 - x^2) */
        double base = d.ipd_mm * sqrt(1.0 - (double)t.dir_cyc.x * t.dir_cyc.x);
        double expect = 2.0 * atan(0.5 * base / (t.depth_m * 1000.0)) * 180.0 / FV_PI;
        assert_true(fabs(verg - expect) < 0.05 * expect + 0.05);
        if ((s.eye[0].flags & FV_EYE_DIRECTION_VALID) && t.label == FV_SIM_FIXATION) {
            double a = angle_deg(s.eye[0].direction, t.dir_eye[0]);
            err_sum += a;
            nerr++;
        }
        n++;
    }
    double seconds = (double)prev_t * 1e-9;
    double rate = (double)(prev_seq + 1) / seconds;
    assert_true(fabs(rate - 250.0) < 1.0);
    assert_true(drops > 150 && drops < 450); /* 1% of 30000 */
    /* accuracy 0.5 deg offset + precision 0.15 deg per axis: mean error near the offset */
    double mean = err_sum / nerr;
    print_message("mean error %.3f deg\n", mean);
    assert_true(mean > 0.4 && mean < 0.7);
    fv_sim_eye_destroy(&e);
}

static void sim_eye_rejects_bad_descs(void **state)
{
    (void)state;
    fv_sim_eye_desc d;
    fv_sim_eye_desc_defaults(&d);
    d.rate_hz = 5000.0;
    fv_sim_eye *e = NULL;
    fv_test_log_capture_begin();
    assert_int_equal(fv_sim_eye_create(&d, &e), FV_ERR_RANGE);
    fv_sim_eye_desc_defaults(&d);
    d.precision_deg = NAN;
    assert_int_equal(fv_sim_eye_create(&d, &e), FV_ERR_RANGE);
    fv_test_log_capture_end();
    fv_assert_log_contains("rate_hz = 5000");
    fv_assert_log_contains("precision_deg");
    assert_null(e);
}

static void sim_driver_uri_errors_name_the_key(void **state)
{
    (void)state;
    fv_sim_eye_desc d;
    unsigned bits = 99;
    assert_int_equal(fv_sim_driver_parse_uri("sim:", &d, &bits), FV_OK);
    assert_int_equal(bits, 0);
    assert_int_equal(fv_sim_driver_parse_uri("sim:seed=42,rate_hz=250,microsaccades=off,ts_bits=32", &d, &bits),
                     FV_OK);
    assert_true(d.seed == 42 && d.rate_hz == 250.0 && !d.microsaccades && bits == 32);
    fv_test_log_capture_begin();
    assert_int_equal(fv_sim_driver_parse_uri("sim:sed=1", &d, NULL), FV_ERR_PARSE);
    assert_int_equal(fv_sim_driver_parse_uri("sim:rate_hz=fast", &d, NULL), FV_ERR_PARSE);
    assert_int_equal(fv_sim_driver_parse_uri("sim:seed=-3", &d, NULL), FV_ERR_PARSE);
    assert_int_equal(fv_sim_driver_parse_uri("sim:ts_bits=4", &d, NULL), FV_ERR_RANGE);
    assert_int_equal(fv_sim_driver_parse_uri("sim:microsaccades=maybe", &d, NULL), FV_ERR_PARSE);
    assert_int_equal(fv_sim_driver_parse_uri("sim:seed", &d, NULL), FV_ERR_PARSE);
    fv_device *dev = NULL;
    assert_int_equal(fv_sim_driver.open("sim:rate_hz=10", NULL, &dev), FV_ERR_RANGE);
    assert_null(dev);
    fv_test_log_capture_end();
    fv_assert_log_contains("unknown key 'sed'");
    fv_assert_log_contains("rate_hz='fast' is not a number");
    fv_assert_log_contains("ts_bits=4");
    fv_assert_log_contains("microsaccades='maybe'");
    fv_assert_log_contains("rate_hz = 10 is outside [30, 1200]");
    fv_device_info info[2];
    size_t count = 0;
    assert_int_equal(fv_sim_driver.probe(info, 2, &count), FV_OK);
    assert_int_equal(count, 1);
    assert_string_equal(info[0].driver, "sim");
}

static void sim_driver_paces_by_clock_and_unwraps_24bit_counters(void **state)
{
    (void)state;
    fv_clock clock;
    fv_clock_sim_init(&clock, INT64_C(5) * 1000000000);
    fv_device_open_desc od = {.clock = &clock};
    fv_device *dev = NULL;
    assert_int_equal(fv_sim_driver.open("sim:seed=2,ts_bits=24", &od, &dev), FV_OK);
    assert_non_null(fv_sim_device_eye(dev));
    assert_true(dev->nominal_rate_hz == 120.0);
    fv_gaze_sample buf[16];
    size_t n = 0;
    /* nothing is due at open (the first sample arrives after the device latency) */
    assert_int_equal(fv_device_read(dev, buf, 16, &n, 0), FV_TIMEOUT);
    assert_int_equal(n, 0);
    int64_t prev_dev = INT64_MIN;
    uint64_t total = 0;
    while (fv_clock_now_ns(&clock) < INT64_C(65) * 1000000000) { /* 60 s: the 24-bit µs counter wraps 3 times */
        fv_result r = fv_device_read(dev, buf, 16, &n, 20);
        assert_true(r == FV_OK || r == FV_TIMEOUT);
        for (size_t i = 0; i < n; i++) {
            assert_true(buf[i].t_device_ns > prev_dev);
            if (prev_dev != INT64_MIN) assert_true(buf[i].t_device_ns - prev_dev < 100000000);
            prev_dev = buf[i].t_device_ns;
            assert_true(buf[i].t_host_ns <= fv_clock_now_ns(&clock));
            fv_sim_truth t;
            assert_true(fv_sim_device_truth(dev, buf[i].seq, &t));
            total++;
        }
    }
    assert_true(total > 7000 && total < 7300);
    fv_device_close(&dev);
    assert_null(dev);
}

/* A µs counter that wraps before two samples have passed cannot be unwrapped: refused at open with one line naming
 * ts_bits, the rate and the wrap period. */
static void sim_driver_refuses_a_counter_that_wraps_faster_than_twice_the_sample_interval(void **state)
{
    (void)state;
    fv_clock clock;
    fv_clock_sim_init(&clock, FV_NS_PER_S);
    fv_device_open_desc od = {.clock = &clock};
    fv_device *dev = NULL;
    fv_test_log_capture_begin();
    assert_int_equal(fv_sim_driver.open("sim:ts_bits=8", &od, &dev), FV_ERR_RANGE);
    assert_null(dev);
    fv_test_log_capture_end();
    fv_assert_log_contains("'sim:ts_bits=8': ts_bits=8 (a microsecond counter) wraps every 0.256 ms, faster than "
                           "twice the sample interval at rate_hz=120 (2 x 8.333 ms)");
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_TRACE), 1); /* one message, of one line */
    const char *nl = strchr(fv_test_log_text(), '\n');
    assert_true(!nl || nl[1] == '\0');
    /* 2^14 us = 16.4 ms < 2 x 8.33 ms: refused; 2^15 us = 32.8 ms: accepted. At 1200 Hz 11 bits (2.05 ms) suffice. */
    fv_test_log_capture_begin();
    assert_int_equal(fv_sim_driver.open("sim:ts_bits=14", &od, &dev), FV_ERR_RANGE);
    assert_int_equal(fv_sim_driver.open("sim:ts_bits=10,rate_hz=1200", &od, &dev), FV_ERR_RANGE);
    fv_test_log_capture_end();
    fv_assert_log_contains("use ts_bits=15 or more, or 0");
    fv_assert_log_contains("use ts_bits=11 or more, or 0");
    assert_int_equal(fv_sim_driver.open("sim:ts_bits=15", &od, &dev), FV_OK);
    fv_device_close(&dev);
    assert_int_equal(fv_sim_driver.open("sim:ts_bits=11,rate_hz=1200", &od, &dev), FV_OK);
    fv_device_close(&dev);
}

/* Read `seconds` of a sim device on its own simulated clock. */
static size_t read_all(const char *uri, int64_t seconds, fv_gaze_sample *out, size_t cap)
{
    fv_clock clock;
    fv_clock_sim_init(&clock, FV_NS_PER_S);
    fv_device_open_desc od = {.clock = &clock};
    fv_device *dev = NULL;
    assert_int_equal(fv_sim_driver.open(uri, &od, &dev), FV_OK);
    size_t total = 0;
    while (fv_clock_now_ns(&clock) < (1 + seconds) * FV_NS_PER_S) {
        size_t n = 0;
        fv_result r = fv_device_read(dev, out + total, cap - total < 16 ? cap - total : 16, &n, 20);
        assert_true(r == FV_OK || r == FV_TIMEOUT);
        total += n;
        assert_true(total < cap);
    }
    fv_device_close(&dev);
    return total;
}

/* At 120 Hz a 15-bit µs counter wraps every 32.8 ms: one dropped sample makes a 16.7 ms gap, over half the wrap, which
 * the counter alone reads as a step back. Checked against the host clock the timeline is exactly the 64-bit one:
 * no sample rejected, none invented, the disagreement reported once. */
static void sim_driver_unwraps_a_15bit_counter_through_dropout_gaps_exactly(void **state)
{
    (void)state;
    enum { CAP = 8192 };
    fv_gaze_sample *wide = calloc(CAP, sizeof *wide), *narrow = calloc(CAP, sizeof *narrow);
    assert_non_null(wide);
    assert_non_null(narrow);
    size_t n_wide = read_all("sim:seed=2", 40, wide, CAP);
    fv_test_log_capture_begin();
    size_t n_narrow = read_all("sim:seed=2,ts_bits=15", 40, narrow, CAP);
    fv_test_log_capture_end();
    assert_int_equal(n_wide, n_narrow);
    size_t long_gaps = 0;
    const int64_t t0_us = wide[0].t_device_ns / 1000;
    for (size_t i = 0; i < n_wide; i++) {
        assert_int_equal(narrow[i].seq, wide[i].seq);
        /* the device sends floor(t / 1 us) modulo 2^15; unwrapped, it must advance like the 64-bit clock */
        assert_int_equal(narrow[i].t_device_ns - narrow[0].t_device_ns, (wide[i].t_device_ns / 1000 - t0_us) * 1000);
        if (i && wide[i].t_device_ns - wide[i - 1].t_device_ns > (INT64_C(1) << 14) * 1000) long_gaps++;
    }
    print_message("15-bit counter: %zu samples, %zu gaps over half its wrap\n", n_narrow, long_gaps);
    assert_true(long_gaps >= 2); /* the case is exercised */
    const char *log = fv_test_log_text();
    const char *needle = "sim:seed=2,ts_bits=15: device timestamps disagree with the host clock";
    const char *hit = strstr(log, needle);
    assert_non_null(hit);
    assert_null(strstr(hit + strlen(needle), "disagree with the host clock")); /* reported once */
    free(wide);
    free(narrow);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sim_eye_is_deterministic_per_seed),
        cmocka_unit_test(sim_eye_blinks_about_15_per_minute_of_100_to_400_ms),
        cmocka_unit_test(sim_eye_saccades_follow_the_main_sequence),
        cmocka_unit_test(sim_eye_fixation_durations_and_event_mix_are_realistic),
        cmocka_unit_test(sim_eye_pupil_stays_2_to_8_mm_and_follows_light),
        cmocka_unit_test(sim_eye_vergence_noise_and_timing),
        cmocka_unit_test(sim_eye_rejects_bad_descs),
        cmocka_unit_test(sim_driver_uri_errors_name_the_key),
        cmocka_unit_test(sim_driver_paces_by_clock_and_unwraps_24bit_counters),
        cmocka_unit_test(sim_driver_refuses_a_counter_that_wraps_faster_than_twice_the_sample_interval),
        cmocka_unit_test(sim_driver_unwraps_a_15bit_counter_through_dropout_gaps_exactly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
