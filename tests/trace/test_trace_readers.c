/* @brief Trace readers on every real recording under ../shared/data/gaze: sample, invalid and blink counts that the
 * raw files really have (counted here from the raw text, independently of the readers), rates, axes; malformed rows
 * and missing columns; the fovea-format round trip; memory input. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "fv_clock.h"
#include "fv_test.h"
#include "fv_trace.h"

/* ------------------------------------------------------------------ raw helpers (independent of the readers) */

typedef void (*raw_row_fn)(void *user, char **f, int n);

/* Call fn for each data row of a separated text file (plain or .gz via gzgets); the header gives column indices. */
static int raw_rows(const char *path, char sep, int skip_header, raw_row_fn fn, void *user)
{
    gzFile gz = gzopen(path, "rb");
    assert_non_null(gz);
    static char buf[1 << 16];
    int rows = 0, first = 1;
    while (gzgets(gz, buf, sizeof buf)) {
        size_t len = strlen(buf);
        while (len && (buf[len - 1] == '\n' || buf[len - 1] == '\r')) buf[--len] = '\0';
        if (len == 0) continue;
        char *f[128];
        int n = 0;
        char *p = buf;
        f[n++] = p;
        while ((p = strchr(p, sep)) && n < 128) {
            *p++ = '\0';
            f[n++] = p;
        }
        if (first && skip_header) {
            first = 0;
            fn(user, f, -n); /* negative n: the header */
            continue;
        }
        first = 0;
        fn(user, f, n);
        rows++;
    }
    gzclose(gz);
    return rows;
}

static int col(char **f, int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(f[i], name) == 0) return i;
    fail_msg("raw header has no column '%s'", name);
    return -1;
}

/* ------------------------------------------------------------------ reader helpers */

typedef struct counts {
    uint64_t n, no_dir, eye_dir[2], comb_dir, blink, eye_pupil[2];
    double origin_x_sum[2];
    uint64_t origin_n[2];
    double comb_dir_z_sum;
    fv_trace_reader_stats rs;
    fv_trace_stats st;
    fv_trace_format format;
} counts;

static void check_eye(const fv_eye_sample *e)
{
    if (e->flags & FV_EYE_DIRECTION_VALID) {
        assert_true(fv_v3_isfinite(e->direction));
        assert_true(fabsf(fv_v3_len(e->direction) - 1.0f) < 1e-4f);
    } else {
        assert_true(isnan(e->direction.x));
    }
    if (e->flags & FV_EYE_ORIGIN_VALID) assert_true(fv_v3_isfinite(e->origin_mm));
    if (e->flags & FV_EYE_PUPIL_VALID) assert_true(e->pupil_mm > 0.0f && e->pupil_mm <= 20.0f);
    else assert_true(isnan(e->pupil_mm));
    if (e->flags & FV_EYE_OPENNESS_VALID) assert_true(e->openness >= 0.0f && e->openness <= 1.0f);
    if (e->flags & FV_EYE_BLINK)
        assert_int_equal(e->flags & (FV_EYE_DIRECTION_VALID | FV_EYE_PUPIL_VALID | FV_EYE_ORIGIN_VALID), 0);
}

static void read_counts(const char *path, const fv_trace_reader_desc *desc, counts *c)
{
    memset(c, 0, sizeof *c);
    fv_trace_reader *r = NULL;
    assert_int_equal(fv_trace_reader_create(path, desc, &r), FV_OK);
    assert_int_equal(fv_trace_stats_init(&c->st), FV_OK);
    fv_gaze_sample s;
    fv_result res;
    int64_t prev = INT64_MIN;
    while ((res = fv_trace_reader_next(r, &s)) == FV_OK) {
        assert_true(s.t_device_ns >= prev);
        prev = s.t_device_ns;
        c->n++;
        for (int e = 0; e < 2; e++) {
            check_eye(&s.eye[e]);
            if (s.eye[e].flags & FV_EYE_DIRECTION_VALID) c->eye_dir[e]++;
            if (s.eye[e].flags & FV_EYE_PUPIL_VALID) c->eye_pupil[e]++;
            if (s.eye[e].flags & FV_EYE_ORIGIN_VALID) {
                c->origin_x_sum[e] += s.eye[e].origin_mm.x;
                c->origin_n[e]++;
            }
        }
        check_eye(&s.combined);
        if (s.combined.flags & FV_EYE_DIRECTION_VALID) {
            c->comb_dir++;
            c->comb_dir_z_sum += s.combined.direction.z;
        }
        uint32_t all = s.eye[0].flags | s.eye[1].flags | s.combined.flags;
        if (!(all & FV_EYE_DIRECTION_VALID)) c->no_dir++;
        if (all & FV_EYE_BLINK) c->blink++;
        fv_trace_stats_push(&c->st, &s);
    }
    assert_int_equal(res, FV_END_OF_STREAM);
    c->rs = *fv_trace_reader_get_stats(r);
    c->format = fv_trace_reader_format(r);
    fv_trace_stats_finish(&c->st, c->rs.blink_events);
    fv_trace_reader_destroy(&r);
    assert_null(r);
}

/* Independently of the readers' rules (fv_gaze_validity.h, docs/gaze.md): a pair of eye directions in fovea's head
 * frame (x right, y up, -z forward) that no human makes — more than 10 deg divergent, 60 convergent or 10 apart
 * vertically. */
static int raw_pair_impossible(double lx, double ly, double lz, double rx, double ry, double rz)
{
    const double k = 180.0 / 3.14159265358979323846;
    double yl = atan2(lx, -lz) * k, yr = atan2(rx, -rz) * k;
    double pl = atan2(ly, hypot(lx, lz)) * k, pr = atan2(ry, hypot(rx, rz)) * k;
    return yl - yr < -10.0 || yl - yr > 60.0 || fabs(pl - pr) > 10.0;
}

static void near(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol)) fail_msg("%s: got %.6f, want %.6f +- %.6f", what, got, want, tol);
}

/* ------------------------------------------------------------------ SRanipal */

typedef struct sr_raw {
    int c_vl, c_vr, c_pl, c_dl, c_dr;
    int rows, dir_invalid[2], pupil_minus1_l, impossible;
} sr_raw;

static void sr_row(void *u, char **f, int n)
{
    sr_raw *r = u;
    if (n < 0) {
        r->c_vl = col(f, -n, "eye_valid_L");
        r->c_vr = col(f, -n, "eye_valid_R");
        r->c_pl = col(f, -n, "pupil_diameter_L(mm)");
        r->c_dl = col(f, -n, "gaze_direct_L.x");
        r->c_dr = col(f, -n, "gaze_direct_R.x");
        return;
    }
    r->rows++;
    int vl = atoi(f[r->c_vl]) & 2, vr = atoi(f[r->c_vr]) & 2;
    /* SRanipal's +x is to the wearer's left, +z forward: head frame (-x, y, -z) */
    double *d = (double[6]){0};
    for (int k = 0; k < 3; k++) d[k] = atof(f[r->c_dl + k]), d[3 + k] = atof(f[r->c_dr + k]);
    bool bad = vl && vr && raw_pair_impossible(-d[0], d[1], -d[2], -d[3], d[4], -d[5]);
    r->impossible += bad;
    if (!vl || bad) r->dir_invalid[0]++;
    if (!vr || bad) r->dir_invalid[1]++;
    if (atof(f[r->c_pl]) == -1.0) r->pupil_minus1_l++;
}

static void sranipal_testna01_counts_rate_and_axes(void **state)
{
    (void)state;
    const char *path = fv_test_data("gaze/htc_vive_pro_eye_sranipal/TESTNA01_2D_Fist3.csv");
    sr_raw raw = {0};
    raw_rows(path, ';', 1, sr_row, &raw);
    assert_int_equal(raw.rows, 1518); /* PROVENANCE.md */
    counts c;
    read_counts(path, NULL, &c);
    assert_int_equal(c.format, FV_TRACE_FORMAT_SRANIPAL);
    assert_int_equal(c.n, raw.rows);
    assert_int_equal(c.n - c.eye_dir[FV_EYE_LEFT], raw.dir_invalid[0]);
    assert_int_equal(c.n - c.eye_dir[FV_EYE_RIGHT], raw.dir_invalid[1]);
    near(100.0 * (double)raw.dir_invalid[0] / raw.rows, 14.0, 0.05, "left invalid %"); /* PROVENANCE.md */
    /* -1 pupils are invalid pupils, never values */
    assert_true(c.n - c.eye_pupil[FV_EYE_LEFT] >= (uint64_t)raw.pupil_minus1_l);
    assert_int_equal(c.rs.rows_skipped, 0);
    assert_int_equal(c.no_dir, 210); /* both eyes invalid: 13.8 % */
    near(c.st.rate_hz, 120.0, 0.2, "rate");
    near((double)(c.st.t_last_ns - c.st.t_first_ns) / 1e9, 12.64, 0.01, "duration");
    /* SRanipal has +x to the wearer's left: in fovea's frame the left eye sits at negative x, gaze goes to -z */
    assert_true(c.origin_x_sum[FV_EYE_LEFT] / (double)c.origin_n[FV_EYE_LEFT] < -30.0);
    assert_true(c.origin_x_sum[FV_EYE_RIGHT] / (double)c.origin_n[FV_EYE_RIGHT] > 25.0);
    assert_true(c.comb_dir_z_sum / (double)c.comb_dir < -0.8);
    near(c.st.pupil_min_mm[0], 3.0, 0.05, "pupil min");
    near(c.st.pupil_max_mm[0], 4.55, 0.05, "pupil max"); /* PROVENANCE rounds to 4.6 */
    /* .NET ticks become Unix-epoch ns: 2023-10-30 */
    assert_true(c.st.t_first_ns > INT64_C(1698624000) * FV_NS_PER_S &&
                c.st.t_first_ns < INT64_C(1698796800) * FV_NS_PER_S);
    assert_int_equal(c.st.blinks, 0); /* SRanipal does not mark blinks; they are invalid samples */
    fv_trace_stats_fini(&c.st);
}

static void sranipal_testna10_is_monocular(void **state)
{
    (void)state;
    const char *path = fv_test_data("gaze/htc_vive_pro_eye_sranipal/TESTNA10_360VR_Fist3.csv");
    sr_raw raw = {0};
    raw_rows(path, ';', 1, sr_row, &raw);
    counts c;
    read_counts(path, NULL, &c);
    assert_int_equal(c.n, 1664);
    assert_int_equal(c.n, raw.rows);
    assert_int_equal(c.n - c.eye_dir[0], raw.dir_invalid[0]);
    assert_int_equal(c.n - c.eye_dir[1], raw.dir_invalid[1]);
    assert_int_equal(raw.impossible, 3); /* the eyes 11-14 deg apart vertically: dropped and counted */
    assert_int_equal(c.rs.validity.dropped[FV_GAZE_FAULT_VERTICAL], 3);
    assert_int_equal(fv_gaze_validity_total(&c.rs.validity, false), 3);
    /* PROVENANCE.md's shares of the file's own invalid flags (without the 3 impossible pairs) */
    near(100.0 * (double)(c.n - c.eye_dir[1] - raw.impossible) / c.n, 99.0, 0.1, "right invalid %");
    near(100.0 * (double)(c.n - c.eye_dir[0] - raw.impossible) / c.n, 37.5, 0.1, "left invalid %");
    /* the combined ray falls back to the one valid eye */
    assert_int_equal(c.comb_dir, c.n - c.no_dir);
    assert_true(c.comb_dir >= c.eye_dir[0]);
    near(c.st.rate_hz, 120.0, 0.2, "rate");
    near(c.st.pupil_min_mm[0], 5.2, 0.05, "pupil min");
    near(c.st.pupil_max_mm[0], 8.95, 0.06, "pupil max"); /* PROVENANCE rounds to 9.0 */
    fv_trace_stats_fini(&c.st);
}

/* ------------------------------------------------------------------ Tobii Glasses 3 */

typedef struct tobii_raw {
    int lines, empty_data, no_left, impossible[3];
} tobii_raw;

/* The eye's gazedirection in a Tobii line (+x to the wearer's left, +z forward), in the head frame (-x, y, -z). */
static bool tobii_raw_dir(const char *line, const char *eye, double d[3])
{
    const char *e = strstr(line, eye), *g = e ? strstr(e, "\"gazedirection\":[") : NULL;
    if (!g || sscanf(g + 17, "%lf,%lf,%lf", &d[0], &d[1], &d[2]) != 3) return false;
    d[0] = -d[0], d[2] = -d[2];
    return true;
}

static void tobii_line(void *u, char **f, int n)
{
    (void)n;
    tobii_raw *r = u;
    const char *line = f[0]; /* separator '\n' never splits: the whole line */
    r->lines++;
    if (strstr(line, "\"data\":{}")) r->empty_data++;
    double l[3], rr[3];
    bool bad = tobii_raw_dir(line, "\"eyeleft\":{", l) && tobii_raw_dir(line, "\"eyeright\":{", rr) &&
               raw_pair_impossible(l[0], l[1], l[2], rr[0], rr[1], rr[2]);
    r->impossible[0] += bad;
    if (!strstr(line, "\"eyeleft\":{\"") || bad) r->no_left++;
}

static void tobii_g3_counts_rate_and_axes(void **state)
{
    (void)state;
    const char *path = fv_test_data("gaze/tobii_pro_glasses3/gazedata.gz");
    tobii_raw raw = {0};
    raw_rows(path, '\n', 0, tobii_line, &raw);
    assert_int_equal(raw.lines, 6547); /* PROVENANCE.md */
    counts c;
    read_counts(path, NULL, &c);
    assert_int_equal(c.format, FV_TRACE_FORMAT_TOBII_G3);
    assert_int_equal(c.n, raw.lines);
    assert_int_equal(c.no_dir, raw.empty_data + raw.impossible[0]); /* data: {}, and eye pairs no human makes */
    assert_int_equal(raw.impossible[0], 272);
    assert_int_equal(fv_gaze_validity_total(&c.rs.validity, false), 272);
    near(100.0 * raw.empty_data / raw.lines, 6.3, 0.05, "empty data %");
    assert_int_equal(c.n - c.eye_dir[FV_EYE_LEFT], raw.no_left);
    near(c.st.rate_hz, 99.8, 0.05, "rate");
    near((double)c.st.median_dt_ns / 1e6, 10.01, 0.01, "median dt");
    near((double)(c.st.t_last_ns - c.st.t_first_ns) / 1e9, 65.58, 0.01, "duration");
    assert_true(c.origin_x_sum[FV_EYE_LEFT] / (double)c.origin_n[FV_EYE_LEFT] < -20.0);
    assert_true(c.origin_x_sum[FV_EYE_RIGHT] / (double)c.origin_n[FV_EYE_RIGHT] > 20.0);
    assert_true(c.comb_dir_z_sum / (double)c.comb_dir < -0.8);
    near(c.st.pupil_min_mm[0], 1.41, 0.005, "left pupil min");
    near(c.st.pupil_max_mm[0], 6.52, 0.005, "left pupil max");
    fv_trace_stats_fini(&c.st);
}

/* ------------------------------------------------------------------ Pupil Core */

typedef struct interval {
    double s, e;
} interval;

typedef struct core_raw {
    int c_ts, c_conf, c_s, c_e;
    interval iv[64];
    int niv;
    int rows, invalid, in_blink, runs, prev_in, impossible, c_n0, c_n1;
} core_raw;

static void core_blink_row(void *u, char **f, int n)
{
    core_raw *r = u;
    if (n < 0) {
        r->c_s = col(f, -n, "start_timestamp");
        r->c_e = col(f, -n, "end_timestamp");
        return;
    }
    r->iv[r->niv++] = (interval){atof(f[r->c_s]), atof(f[r->c_e])};
}

static void core_gaze_row(void *u, char **f, int n)
{
    core_raw *r = u;
    if (n < 0) {
        r->c_ts = col(f, -n, "gaze_timestamp");
        r->c_conf = col(f, -n, "confidence");
        r->c_n0 = col(f, -n, "gaze_normal0_x");
        r->c_n1 = col(f, -n, "gaze_normal1_x");
        return;
    }
    r->rows++;
    double t = atof(f[r->c_ts]);
    int in = 0;
    for (int i = 0; i < r->niv; i++)
        if (t >= r->iv[i].s && t <= r->iv[i].e) in = 1;
    if (in) r->in_blink++;
    if (in && !r->prev_in) r->runs++;
    r->prev_in = in;
    /* eye0 = right, eye1 = left; camera frame (x right, y down, z forward) -> head (x, -y, -z) */
    double a[3], b[3];
    for (int k = 0; k < 3; k++) a[k] = atof(f[r->c_n1 + k]), b[k] = atof(f[r->c_n0 + k]);
    bool confident = atof(f[r->c_conf]) >= 0.6;
    bool bad = !in && confident && *f[r->c_n0] && *f[r->c_n1] &&
               raw_pair_impossible(a[0], -a[1], -a[2], b[0], -b[1], -b[2]);
    r->impossible += bad;
    if (in || !confident || bad) r->invalid++;
}

static void pupil_core_counts_blinks_and_axes(void **state)
{
    (void)state;
    core_raw raw = {0};
    raw_rows(fv_test_data("gaze/pupil_core/blinks.csv"), ',', 1, core_blink_row, &raw);
    assert_int_equal(raw.niv, 3); /* PROVENANCE.md */
    raw_rows(fv_test_data("gaze/pupil_core/gaze_positions.csv"), ',', 1, core_gaze_row, &raw);
    assert_int_equal(raw.rows, 2054);
    counts c;
    read_counts(fv_test_data("gaze/pupil_core/gaze_positions.csv"), NULL, &c);
    assert_int_equal(c.format, FV_TRACE_FORMAT_PUPIL_CORE);
    assert_int_equal(c.n, raw.rows);
    assert_int_equal(c.blink, raw.in_blink);
    assert_int_equal(c.no_dir, raw.invalid); /* blinks, confidence < 0.6 and eye pairs no human makes */
    assert_int_equal(raw.impossible, 2);
    assert_int_equal(fv_gaze_validity_total(&c.rs.validity, false), 2);
    assert_int_equal(c.rs.blink_events, 3);
    assert_int_equal(c.st.blinks, 3);
    assert_int_equal(raw.runs, 3);
    near(c.st.rate_hz, 296.0, 1.0, "rate");
    near((double)c.st.median_dt_ns / 1e6, 2.50, 0.01, "median dt");
    /* eye1 is the left eye: centre x ~ -39 mm in the camera frame, and x keeps its sign in fovea's frame */
    assert_true(c.origin_x_sum[FV_EYE_LEFT] / (double)c.origin_n[FV_EYE_LEFT] < -30.0);
    assert_true(c.origin_x_sum[FV_EYE_RIGHT] / (double)c.origin_n[FV_EYE_RIGHT] > 10.0);
    assert_true(c.comb_dir_z_sum / (double)c.comb_dir < -0.8);
    /* blink total: 0.38 - 0.45 s each */
    assert_true(c.st.blink_total_ns > 3 * 370 * FV_NS_PER_MS && c.st.blink_total_ns < 3 * 460 * FV_NS_PER_MS);

    /* keeping every confidence: only blinks stay invalid */
    fv_trace_reader_desc d = {.min_confidence = -1.0f};
    counts all;
    read_counts(fv_test_data("gaze/pupil_core/gaze_positions.csv"), &d, &all);
    /* ... and the eye pairs no human makes (each drops the whole sample), now among the unconfident rows too */
    const fv_gaze_validity_counts *v = &all.rs.validity;
    uint64_t pairs = v->dropped[FV_GAZE_FAULT_DIVERGENT] + v->dropped[FV_GAZE_FAULT_CONVERGENT] +
                     v->dropped[FV_GAZE_FAULT_VERTICAL];
    assert_int_equal(pairs, fv_gaze_validity_total(v, false));
    assert_int_equal(all.no_dir, raw.in_blink + pairs);
    /* without blinks.csv: no blink marks */
    fv_trace_reader_desc nb = {.blinks_path = ""};
    counts noblink;
    read_counts(fv_test_data("gaze/pupil_core/gaze_positions.csv"), &nb, &noblink);
    assert_int_equal(noblink.blink, 0);
    fv_trace_stats_fini(&c.st);
    fv_trace_stats_fini(&all.st);
    fv_trace_stats_fini(&noblink.st);
}

/* ------------------------------------------------------------------ Pupil Cloud (Invisible) */

typedef struct cloud_raw {
    int c_ts, c_b, c_s, c_e, c_az;
    int64_t iv_s[64], iv_e[64];
    int niv;
    int rows, blink_rows, az_pos;
} cloud_raw;

static void cloud_blink_row(void *u, char **f, int n)
{
    cloud_raw *r = u;
    if (n < 0) {
        r->c_s = col(f, -n, "start timestamp [ns]");
        r->c_e = col(f, -n, "end timestamp [ns]");
        return;
    }
    r->iv_s[r->niv] = atoll(f[r->c_s]);
    r->iv_e[r->niv++] = atoll(f[r->c_e]);
}

static void cloud_gaze_row(void *u, char **f, int n)
{
    cloud_raw *r = u;
    if (n < 0) {
        r->c_ts = col(f, -n, "timestamp [ns]");
        r->c_b = col(f, -n, "blink id");
        r->c_az = col(f, -n, "azimuth [deg]");
        return;
    }
    r->rows++;
    int64_t t = atoll(f[r->c_ts]);
    int in = f[r->c_b][0] != '\0';
    for (int i = 0; i < r->niv; i++)
        if (t >= r->iv_s[i] && t <= r->iv_e[i]) in = 1;
    if (in) r->blink_rows++;
    else if (atof(f[r->c_az]) > 0) r->az_pos++;
}

static void pupil_cloud_counts_blinks_and_axes(void **state)
{
    (void)state;
    cloud_raw raw = {0};
    raw_rows(fv_test_data("gaze/pupil_invisible/blinks.csv"), ',', 1, cloud_blink_row, &raw);
    assert_int_equal(raw.niv, 32);
    raw_rows(fv_test_data("gaze/pupil_invisible/gaze.csv"), ',', 1, cloud_gaze_row, &raw);
    assert_int_equal(raw.rows, 5338);
    counts c;
    fv_trace_reader *r = NULL;
    assert_int_equal(fv_trace_reader_create(fv_test_data("gaze/pupil_invisible/gaze.csv"), NULL, &r), FV_OK);
    fv_gaze_sample s;
    int right = 0;
    while (fv_trace_reader_next(r, &s) == FV_OK)
        if ((s.combined.flags & FV_EYE_DIRECTION_VALID) && s.combined.direction.x > 0) right++;
    fv_trace_reader_destroy(&r);
    assert_int_equal(right, raw.az_pos); /* positive azimuth = to the right = +x */
    read_counts(fv_test_data("gaze/pupil_invisible/gaze.csv"), NULL, &c);
    assert_int_equal(c.format, FV_TRACE_FORMAT_PUPIL_CLOUD);
    assert_int_equal(c.n, raw.rows);
    assert_int_equal(c.blink, raw.blink_rows);
    assert_int_equal(c.no_dir, raw.blink_rows);
    assert_int_equal(c.st.blinks, 32);
    assert_int_equal(c.eye_dir[0] + c.eye_dir[1], 0); /* no per-eye data in this format */
    near(c.st.rate_hz, 199.5, 0.5, "rate");
    near((double)c.st.median_dt_ns / 1e6, 4.02, 0.01, "median dt");
    near((double)(c.st.t_last_ns - c.st.t_first_ns) / 1e9, 26.75, 0.01, "duration");
    fv_trace_stats_fini(&c.st);
}

/* ------------------------------------------------------------------ Pico */

typedef struct pico_raw {
    int c_vx, c_vy, c_vz, c_bl, c_br;
    int rows, zero_vec, blink_rows, runs, prev;
} pico_raw;

static void pico_row(void *u, char **f, int n)
{
    pico_raw *r = u;
    if (n < 0) {
        r->c_vx = col(f, -n, "Combine Eye Gaze Vector. x");
        r->c_vy = col(f, -n, "Combine Eye Gaze Vector. y");
        r->c_vz = col(f, -n, "Combine Eye Gaze Vector. z");
        r->c_bl = col(f, -n, "Eye Left Blinking");
        r->c_br = col(f, -n, "Eye Right Blinking");
        return;
    }
    r->rows++;
    if (atof(f[r->c_vx]) == 0 && atof(f[r->c_vy]) == 0 && atof(f[r->c_vz]) == 0) r->zero_vec++;
    int b = strcmp(f[r->c_bl], "True") == 0 || strcmp(f[r->c_br], "True") == 0;
    r->blink_rows += b;
    if (b && !r->prev) r->runs++;
    r->prev = b;
}

static void pico_counts_rate_and_axes(void **state)
{
    (void)state;
    const char *path = fv_test_data("gaze/pico_neo3_pro/boxing_VR.tsv");
    pico_raw raw = {0};
    raw_rows(path, '\t', 1, pico_row, &raw);
    assert_int_equal(raw.rows, 492);
    counts c;
    read_counts(path, NULL, &c);
    assert_int_equal(c.format, FV_TRACE_FORMAT_PICO);
    assert_int_equal(c.n, raw.rows);
    assert_int_equal(c.no_dir, raw.zero_vec); /* 1.2 % */
    assert_int_equal(c.blink, raw.blink_rows); /* 1.6 % */
    assert_int_equal(c.st.blinks, (uint64_t)raw.runs);
    near(c.st.rate_hz, 90.0, 0.1, "rate");
    assert_true(c.comb_dir_z_sum / (double)c.comb_dir < -0.8); /* Unity +z forward became -z */
    fv_trace_stats_fini(&c.st);
}

/* ------------------------------------------------------------------ malformed input */

static void bad_rows_are_skipped_with_line_and_reason(void **state)
{
    (void)state;
    const char *text = "time(100ns);eye_valid_L;eye_valid_R;openness_L;openness_R;pupil_diameter_L(mm);"
                       "pupil_diameter_R(mm);gaze_origin_L.x(mm);gaze_origin_L.y(mm);gaze_origin_L.z(mm);"
                       "gaze_origin_R.x(mm);gaze_origin_R.y(mm);gaze_origin_R.z(mm);gaze_direct_L.x;gaze_direct_L.y;"
                       "gaze_direct_L.z;gaze_direct_R.x;gaze_direct_R.y;gaze_direct_R.z\r\n"
                       "638342794000115346;31;31;0.9;0.9;3.5;3.7;39;2;-38;-30;1;-35;0.1;-0.1;0.98;0.1;-0.1;0.98\r\n"
                       "638342794000195116;31;31;0.9;0.9;abc;3.7;39;2;-38;-30;1;-35;0.1;-0.1;0.98;0.1;-0.1;0.98\r\n"
                       "638342794000284871;31;31;0.9\r\n"
                       "638342794000000000;31;31;0.9;0.9;3.5;3.7;39;2;-38;-30;1;-35;0.1;-0.1;0.98;0.1;-0.1;0.98\r\n"
                       "\r\n"
                       "638342794000384871;24;8;0.9;0.9;-1;-1;0;0;0;0;0;0;0;0;0;0;0;0\r\n";
    const char *path = fv_test_write_file("bad_rows.csv", text, strlen(text));
    fv_test_log_capture_begin();
    counts c;
    read_counts(path, NULL, &c);
    fv_test_log_capture_end();
    assert_int_equal(c.n, 2);
    assert_int_equal(c.rs.rows_skipped, 3);
    assert_int_equal(c.no_dir, 1); /* the invalid row stays, as an invalid sample */
    char want[1200];
    snprintf(want, sizeof want, "%s:3: column 'pupil_diameter_L(mm)' is not a number", path);
    fv_assert_log_contains(want);
    snprintf(want, sizeof want, "%s:4: 4 fields", path);
    fv_assert_log_contains(want);
    snprintf(want, sizeof want, "%s:5: timestamp", path);
    fv_assert_log_contains(want);
    fv_assert_log_contains("goes back in time");
    fv_trace_stats_fini(&c.st);
}

static void bad_row_warnings_are_rate_limited(void **state)
{
    (void)state;
    size_t cap = 64 * 1024, len = 0;
    char *text = malloc(cap);
    len += (size_t)snprintf(text + len, cap - len, "gaze_timestamp,confidence,norm_pos_x,norm_pos_y\n");
    for (int i = 0; i < 100; i++) len += (size_t)snprintf(text + len, cap - len, "%d.0,oops,0.5,0.5\n", i);
    len += (size_t)snprintf(text + len, cap - len, "200.0,0.9,0.5,0.5\n");
    fv_trace_reader_desc d = {.data = text, .size = len, .name = "mem.csv", .max_warnings = 5};
    fv_test_log_capture_begin();
    counts c;
    read_counts(NULL, &d, &c);
    fv_test_log_capture_end();
    assert_int_equal(c.n, 1);
    assert_int_equal(c.rs.rows_skipped, 100);
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_WARN), 6); /* 5 rows + the total at destroy */
    fv_assert_log_contains("mem.csv:2: column 'confidence' is not a number");
    fv_assert_log_contains("100 bad rows skipped in all");
    fv_trace_stats_fini(&c.st);
    free(text);
}

static void missing_column_names_column_and_file(void **state)
{
    (void)state;
    const char *text = "gaze_timestamp,norm_pos_x,norm_pos_y\n1.0,0.5,0.5\n";
    const char *path = fv_test_write_file("gaze_positions.csv", text, strlen(text));
    fv_trace_reader_desc d = {.blinks_path = ""};
    fv_trace_reader *r = NULL;
    fv_test_log_capture_begin();
    assert_int_equal(fv_trace_reader_create(path, &d, &r), FV_ERR_PARSE);
    fv_test_log_capture_end();
    assert_null(r);
    fv_assert_log_contains("missing required column 'confidence'");
    fv_assert_log_contains(path);

    /* a forced format that does not fit names what it misses */
    d.format = FV_TRACE_FORMAT_SRANIPAL;
    fv_test_log_capture_begin();
    assert_int_equal(fv_trace_reader_create(fv_test_data("gaze/pupil_core/gaze_positions.csv"), &d, &r),
                     FV_ERR_PARSE);
    fv_test_log_capture_end();
    fv_assert_log_contains("missing required column 'time(100ns)'");

    /* a broken blinks file is an error too */
    const char *blinks = "id,start_timestamp,duration\n1,2.0,0.3\n";
    d.format = FV_TRACE_FORMAT_AUTO;
    d.blinks_path = fv_test_write_file("bad_blinks.csv", blinks, strlen(blinks));
    fv_test_log_capture_begin();
    assert_int_equal(fv_trace_reader_create(fv_test_data("gaze/pupil_core/gaze_positions.csv"), &d, &r),
                     FV_ERR_PARSE);
    fv_test_log_capture_end();
    fv_assert_log_contains("missing required column 'end_timestamp'");
}

static void unknown_content_and_missing_file_are_clear_errors(void **state)
{
    (void)state;
    fv_trace_reader *r = NULL;
    const char *text = "hello,world\n1,2\n";
    fv_trace_reader_desc d = {.data = text, .size = strlen(text), .name = "x.csv"};
    fv_test_log_capture_begin();
    assert_int_equal(fv_trace_reader_create(NULL, &d, &r), FV_ERR_PARSE);
    assert_int_equal(fv_trace_reader_create(fv_test_data("gaze/pupil_core/blinks.csv"), NULL, &r), FV_ERR_PARSE);
    assert_int_equal(fv_trace_reader_create("/nonexistent/trace.csv", NULL, &r), FV_ERR_NOT_FOUND);
    d.size = 0;
    assert_int_equal(fv_trace_reader_create(NULL, &d, &r), FV_ERR_PARSE);
    fv_test_log_capture_end();
    fv_assert_log_contains("x.csv:1: cannot tell the format from the first line 'hello,world'");
    fv_assert_log_contains("looks like a blinks file");
    fv_assert_log_contains("/nonexistent/trace.csv: cannot open");
    fv_assert_log_contains("empty file");
}

static void format_names_round_trip(void **state)
{
    (void)state;
    for (int f = 1; f < FV_TRACE_FORMAT_COUNT_; f++) {
        fv_trace_format g;
        assert_int_equal(fv_trace_format_parse(fv_trace_format_name((fv_trace_format)f), &g), FV_OK);
        assert_int_equal(g, f);
    }
    fv_trace_format g;
    assert_int_equal(fv_trace_format_parse("pupil-invisible", &g), FV_OK);
    assert_int_equal(g, FV_TRACE_FORMAT_PUPIL_CLOUD);
    assert_int_equal(fv_trace_format_parse("nope", &g), FV_ERR_NOT_FOUND);
}

static void over_long_line_is_skipped_and_reading_goes_on(void **state)
{
    (void)state;
    size_t big = 2u * 1024u * 1024u;
    char *text = malloc(big + 256);
    size_t len = (size_t)sprintf(text, "gaze_timestamp,confidence,norm_pos_x,norm_pos_y\n1.0,0.9,0.5,0.5\n");
    memset(text + len, '7', big);
    len += big;
    len += (size_t)sprintf(text + len, "\n2.0,0.9,0.5,0.5\n");
    fv_trace_reader_desc d = {.data = text, .size = len, .name = "long.csv"};
    fv_test_log_capture_begin();
    counts c;
    read_counts(NULL, &d, &c);
    fv_test_log_capture_end();
    assert_int_equal(c.n, 2);
    assert_int_equal(c.rs.rows_skipped, 1);
    fv_assert_log_contains("long.csv:3: line longer than");
    fv_trace_stats_fini(&c.st);
    free(text);
}

/* ------------------------------------------------------------------ round trip and memory input */

static int float_same(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

static void assert_eye_equal(const fv_eye_sample *a, const fv_eye_sample *b)
{
    assert_int_equal(a->flags, b->flags);
    assert_true(float_same(a->origin_mm.x, b->origin_mm.x) && float_same(a->origin_mm.y, b->origin_mm.y) &&
                float_same(a->origin_mm.z, b->origin_mm.z));
    assert_true(float_same(a->direction.x, b->direction.x) && float_same(a->direction.y, b->direction.y) &&
                float_same(a->direction.z, b->direction.z));
    assert_true(float_same(a->pupil_mm, b->pupil_mm));
    assert_true(float_same(a->openness, b->openness));
}

static void assert_sample_equal(const fv_gaze_sample *a, const fv_gaze_sample *b)
{
    assert_int_equal(a->t_device_ns, b->t_device_ns);
    assert_int_equal(a->flags, b->flags);
    if (a->flags & FV_GAZE_HOST_TIME_VALID) assert_int_equal(a->t_host_ns, b->t_host_ns);
    assert_int_equal(a->seq, b->seq);
    assert_true(float_same(a->confidence, b->confidence));
    for (int e = 0; e < 2; e++) assert_eye_equal(&a->eye[e], &b->eye[e]);
    assert_eye_equal(&a->combined, &b->combined);
    if (a->flags & FV_GAZE_HEAD_VALID) {
        assert_true(float_same(a->head_pos_mm.x, b->head_pos_mm.x) && float_same(a->head_pos_mm.y, b->head_pos_mm.y) &&
                    float_same(a->head_pos_mm.z, b->head_pos_mm.z));
        assert_true(float_same(a->head_dir.x, b->head_dir.x) && float_same(a->head_dir.y, b->head_dir.y) &&
                    float_same(a->head_dir.z, b->head_dir.z));
    }
}

/* Convert the first max samples of in to fovea's format and read them back. */
static void convert_round_trip(const char *in, const char *out_name, int gzip, uint64_t max)
{
    fv_trace_reader *r = NULL, *back = NULL;
    fv_trace_writer *w = NULL;
    const char *out = fv_test_tmp(out_name);
    assert_int_equal(fv_trace_reader_create(in, NULL, &r), FV_OK);
    fv_trace_writer_desc wd = {.source = "test\nwith newline", .rate_hz = 120.0, .gzip = gzip};
    assert_int_equal(fv_trace_writer_create(out, &wd, &w), FV_OK);
    fv_gaze_sample s, t;
    uint64_t n = 0;
    while (n < max && fv_trace_reader_next(r, &s) == FV_OK) {
        assert_int_equal(fv_trace_writer_write(w, &s), FV_OK);
        n++;
    }
    assert_int_equal(fv_trace_writer_finish(&w), FV_OK);
    assert_null(w);
    assert_int_equal(fv_trace_reader_rewind(r), FV_OK);
    assert_int_equal(fv_trace_reader_create(out, NULL, &back), FV_OK);
    assert_int_equal(fv_trace_reader_format(back), FV_TRACE_FORMAT_FOVEA);
    uint64_t m = 0;
    while (m < n && fv_trace_reader_next(r, &s) == FV_OK) {
        assert_int_equal(fv_trace_reader_next(back, &t), FV_OK);
        assert_sample_equal(&s, &t);
        m++;
    }
    assert_int_equal(fv_trace_reader_next(back, &t), FV_END_OF_STREAM);
    assert_int_equal(m, n);
    assert_true(n > 400);
    fv_trace_reader_destroy(&r);
    fv_trace_reader_destroy(&back);
}

static void every_format_round_trips_through_fovea_format(void **state)
{
    (void)state;
    /* whole files, except the first 1500 samples of the long Tobii file (JSON is slow under ASan) */
    convert_round_trip(fv_test_data("gaze/htc_vive_pro_eye_sranipal/TESTNA01_2D_Fist3.csv"), "rt_sr.fvt", 0, UINT64_MAX);
    convert_round_trip(fv_test_data("gaze/tobii_pro_glasses3/gazedata.gz"), "rt_tobii.fvt", 0, 1500);
    convert_round_trip(fv_test_data("gaze/pupil_core/gaze_positions.csv"), "rt_core.fvt.gz", 0, UINT64_MAX);
    convert_round_trip(fv_test_data("gaze/pupil_invisible/gaze.csv"), "rt_cloud.fvt", 1, UINT64_MAX);
    convert_round_trip(fv_test_data("gaze/pico_neo3_pro/boxing_VR.tsv"), "rt_pico.fvt", 0, UINT64_MAX);
}

static void *slurp(const char *path, size_t *out_size) { return fv_test_read_file(path, out_size); }

static void memory_input_reads_the_same_as_the_file(void **state)
{
    (void)state;
    const char *files[] = {"gaze/tobii_pro_glasses3/gazedata.gz", "gaze/pupil_core/gaze_positions.csv"};
    for (int i = 0; i < 2; i++) {
        const char *path = fv_test_data(files[i]);
        size_t size, bsize = 0;
        void *data = slurp(path, &size);
        void *blinks = i == 1 ? slurp(fv_test_data("gaze/pupil_core/blinks.csv"), &bsize) : NULL;
        fv_trace_reader_desc d = {.data = data, .size = size, .blinks_data = blinks, .blinks_size = bsize};
        fv_trace_reader *a = NULL, *b = NULL;
        assert_int_equal(fv_trace_reader_create(path, NULL, &a), FV_OK);
        assert_int_equal(fv_trace_reader_create(NULL, &d, &b), FV_OK);
        fv_gaze_sample s, t;
        uint64_t n = 0;
        while (n < 2100 && fv_trace_reader_next(a, &s) == FV_OK) {
            assert_int_equal(fv_trace_reader_next(b, &t), FV_OK);
            assert_sample_equal(&s, &t);
            n++;
        }
        if (n < 2100) assert_int_equal(fv_trace_reader_next(b, &t), FV_END_OF_STREAM);
        assert_true(n >= 2054);
        fv_trace_reader_destroy(&a);
        fv_trace_reader_destroy(&b);
        free(data);
        free(blinks);
    }
}

static void truncated_gzip_gives_what_is_there(void **state)
{
    (void)state;
    size_t size;
    unsigned char *data = slurp(fv_test_data("gaze/tobii_pro_glasses3/gazedata.gz"), &size);
    fv_trace_reader_desc d = {.data = data, .size = size / 2, .name = "half.gz"};
    fv_test_log_capture_begin();
    counts c;
    read_counts(NULL, &d, &c);
    fv_test_log_capture_end();
    assert_true(c.n > 2000 && c.n < 6547);
    fv_assert_log_contains("compressed data ends early");
    /* corrupt bytes in the middle of the deflate stream: an error, never a crash */
    for (size_t i = size / 3; i < size / 3 + 64; i++) data[i] ^= 0x5a;
    d.size = size;
    fv_trace_reader *r = NULL;
    fv_test_log_capture_begin();
    fv_result res = fv_trace_reader_create(NULL, &d, &r);
    if (res == FV_OK) {
        fv_gaze_sample s;
        while ((res = fv_trace_reader_next(r, &s)) == FV_OK) {
        }
        fv_trace_reader_destroy(&r);
    }
    fv_test_log_capture_end();
    assert_int_equal(res, FV_ERR_IO);
    fv_assert_log_contains("corrupt gzip data");
    fv_trace_stats_fini(&c.st);
    free(data);
}

static void extreme_values_stay_finite_or_invalid(void **state)
{
    (void)state;
    const char *text =
        "fovea-trace 1\n# rate_hz: 100\n"
        "t_device_ns,flags,l_flags,l_origin_x_mm,l_origin_y_mm,l_origin_z_mm,l_dir_x,l_dir_y,l_dir_z,l_pupil_mm,"
        "l_openness,c_flags,c_dir_x,c_dir_y,c_dir_z\n"
        "0,0,15,1e300,0,0,1e-30,0,0,-3,2,2,0,0,0\n"
        "1,0,15,1,2,3,3,0,-4,4.5,0.5,2,1e38,1e38,-1e38\n"
        "9223372036854775807,7,255,nan,inf,-inf,nan,0,0,1e39,-0,2,-0,-0,-1\n";
    fv_trace_reader_desc d = {.data = text, .size = strlen(text), .name = "x.fvt"};
    fv_trace_reader *r = NULL;
    assert_int_equal(fv_trace_reader_create(NULL, &d, &r), FV_OK);
    fv_gaze_sample s;
    assert_int_equal(fv_trace_reader_next(r, &s), FV_OK);
    check_eye(&s.eye[0]);
    assert_int_equal(s.eye[0].flags, 0); /* origin beyond float, 1e-30 direction, pupil -3, openness 2 */
    assert_int_equal(s.combined.flags, 0);
    assert_int_equal(fv_trace_reader_next(r, &s), FV_OK);
    check_eye(&s.eye[0]);
    check_eye(&s.combined);
    assert_int_equal(s.eye[0].flags, 15);
    assert_true(fabsf(s.eye[0].direction.x - 0.6f) < 1e-6f); /* (3,0,-4) renormalised */
    assert_true(fabsf(s.combined.direction.x - 0.57735f) < 1e-4f); /* 1e38 components: no overflow to inf */
    assert_int_equal(fv_trace_reader_next(r, &s), FV_OK);
    check_eye(&s.eye[0]);
    assert_int_equal(s.eye[0].flags, FV_EYE_BLINK | FV_EYE_OPENNESS_VALID);
    assert_int_equal(s.flags, 0); /* host time, head, screen: flagged but absent */
    assert_int_equal(fv_trace_reader_next(r, &s), FV_END_OF_STREAM);
    fv_trace_reader_destroy(&r);

    /* fovea format: a head pose flagged valid keeps a unit direction; a zero or infinite one makes it invalid */
    const char *head =
        "fovea-trace 1\n"
        "t_device_ns,flags,head_x_mm,head_y_mm,head_z_mm,head_dir_x,head_dir_y,head_dir_z\n"
        "0,2,1,2,3,0,3,4\n"
        "1,2,1,2,3,0,0,0\n"
        "2,2,1,2,3,1e39,0,0\n";
    fv_trace_reader_desc hd = {.data = head, .size = strlen(head), .name = "head.fvt"};
    assert_int_equal(fv_trace_reader_create(NULL, &hd, &r), FV_OK);
    assert_int_equal(fv_trace_reader_next(r, &s), FV_OK);
    assert_true(s.flags & FV_GAZE_HEAD_VALID);
    assert_true(fabsf(s.head_dir.y - 0.6f) < 1e-6f && fabsf(s.head_dir.z - 0.8f) < 1e-6f);
    assert_int_equal(fv_trace_reader_next(r, &s), FV_OK);
    assert_false(s.flags & FV_GAZE_HEAD_VALID);
    assert_int_equal(fv_trace_reader_next(r, &s), FV_OK);
    assert_false(s.flags & FV_GAZE_HEAD_VALID);
    fv_trace_reader_destroy(&r);

    /* intervals of ~4.5e18 ns (a fuzzer found these): gaps and durations saturate instead of overflowing */
    fv_trace_stats big;
    assert_int_equal(fv_trace_stats_init(&big), FV_OK);
    const int64_t ts[] = {INT64_MIN / 2 - 12345, 0, INT64_MAX / 2 + 12345, INT64_MAX};
    for (size_t i = 0; i < sizeof ts / sizeof ts[0]; i++) {
        fv_gaze_sample g;
        fv_gaze_sample_init_invalid(&g, ts[i], 0);
        g.eye[0].flags = FV_EYE_BLINK; /* one long blink across all of it */
        fv_trace_stats_push(&big, &g);
    }
    fv_trace_stats_finish(&big, 0);
    assert_true(big.median_dt_ns > 0);
    assert_true(big.gap_total_ns > 0 && big.blink_total_ns > 0); /* saturated, not wrapped negative */
    assert_true(isfinite(big.rate_hz) && big.rate_hz >= 0);
    fv_trace_stats_fini(&big);

    /* two samples 1 ns apart at a Unix-epoch time: as doubles they are equal, yet the rate must stay finite */
    fv_trace_stats near1;
    assert_int_equal(fv_trace_stats_init(&near1), FV_OK);
    for (int64_t k = 0; k < 2; k++) {
        fv_gaze_sample g;
        fv_gaze_sample_init_invalid(&g, INT64_C(1698682607842919999) + k, 0);
        fv_trace_stats_push(&near1, &g);
    }
    fv_trace_stats_finish(&near1, 0);
    assert_true(isfinite(near1.rate_hz) && near1.rate_hz > 0);
    fv_trace_stats_fini(&near1);

    /* statistics of nothing are zeros, not NaN or a division by zero */
    fv_trace_stats st;
    assert_int_equal(fv_trace_stats_init(&st), FV_OK);
    fv_trace_stats_finish(&st, 0);
    assert_int_equal(st.median_dt_ns, 0);
    assert_true(st.rate_hz == 0.0);
    fv_trace_stats_fini(&st);
    fv_trace_stats_fini(&st);
}

/* ------------------------------------------------------------------ head pose (SRanipal and Pico, Unity world) */

/* Independent reference: Unity's rotation from Euler angles (deg) is R = Ry·Rx·Rz, built here as full 3×3 matrices
 * (roll included) and applied to Unity's forward (0,0,1); then (x, y, z) -> (x, y, -z). */
static void unity_forward_ref(double ax, double ay, double az, double out[3])
{
    const double d = 3.14159265358979323846 / 180.0;
    double cx = cos(ax * d), sx = sin(ax * d), cy = cos(ay * d), sy = sin(ay * d), cz = cos(az * d), sz = sin(az * d);
    double rx[3][3] = {{1, 0, 0}, {0, cx, -sx}, {0, sx, cx}};
    double ry[3][3] = {{cy, 0, sy}, {0, 1, 0}, {-sy, 0, cy}};
    double rz[3][3] = {{cz, -sz, 0}, {sz, cz, 0}, {0, 0, 1}};
    double t[3][3] = {{0}}, m[3][3] = {{0}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++) t[i][j] += rx[i][k] * rz[k][j];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++) m[i][j] += ry[i][k] * t[k][j];
    out[0] = m[0][2];
    out[1] = m[1][2];
    out[2] = -m[2][2];
}

typedef struct head_raw {
    int c[6];           /* pos x y z, rot x y z */
    const char *names[6];
    int rows;
    double v[2048][6];
} head_raw;

static void head_row(void *u, char **f, int n)
{
    head_raw *r = u;
    if (n < 0) {
        for (int k = 0; k < 6; k++) r->c[k] = col(f, -n, r->names[k]);
        return;
    }
    assert_true(r->rows < 2048);
    for (int k = 0; k < 6; k++) r->v[r->rows][k] = atof(f[r->c[k]]);
    r->rows++;
}

typedef struct box {
    double lo[3], hi[3];
} box;

/* Read path, compare every head pose with the raw columns (independent reference) and check it lies in b. Returns
 * the number of samples with a valid head; *min_dir_y gets the lowest head_dir.y. */
static uint64_t check_head_file(const char *path, char sep, const char *const names[6], const box *b,
                                double *min_dir_y, double *max_dir_y)
{
    static head_raw raw;
    memset(&raw, 0, sizeof raw);
    memcpy(raw.names, names, sizeof raw.names);
    raw_rows(path, sep, 1, head_row, &raw);
    fv_trace_reader *r = NULL;
    assert_int_equal(fv_trace_reader_create(path, NULL, &r), FV_OK);
    fv_gaze_sample s;
    uint64_t n = 0, valid = 0;
    *min_dir_y = INFINITY;
    *max_dir_y = -INFINITY;
    while (fv_trace_reader_next(r, &s) == FV_OK) {
        assert_true(n < (uint64_t)raw.rows);
        const double *v = raw.v[n++];
        if (!(s.flags & FV_GAZE_HEAD_VALID)) {
            assert_true(isnan(s.head_pos_mm.x) && isnan(s.head_dir.x));
            continue;
        }
        valid++;
        assert_true(fv_v3_isfinite(s.head_pos_mm) && fv_v3_isfinite(s.head_dir));
        assert_true(fabsf(fv_v3_len(s.head_dir) - 1.0f) < 1e-6f);
        near(s.head_pos_mm.x, v[0] * 1000.0, 1e-3, "head x");
        near(s.head_pos_mm.y, v[1] * 1000.0, 1e-3, "head y");
        near(s.head_pos_mm.z, -v[2] * 1000.0, 1e-3, "head z");
        double ref[3];
        unity_forward_ref(v[3], v[4], v[5], ref);
        near(s.head_dir.x, ref[0], 1e-6, "head_dir x");
        near(s.head_dir.y, ref[1], 1e-6, "head_dir y");
        near(s.head_dir.z, ref[2], 1e-6, "head_dir z");
        const float p[3] = {s.head_pos_mm.x, s.head_pos_mm.y, s.head_pos_mm.z};
        for (int k = 0; k < 3; k++)
            if (!(p[k] >= b->lo[k] && p[k] <= b->hi[k]))
                fail_msg("%s row %llu: head[%d] = %.1f mm outside [%.0f, %.0f]", path, (unsigned long long)n, k,
                         (double)p[k], b->lo[k], b->hi[k]);
        if (s.head_dir.y < *min_dir_y) *min_dir_y = s.head_dir.y;
        if (s.head_dir.y > *max_dir_y) *max_dir_y = s.head_dir.y;
    }
    assert_int_equal(n, raw.rows);
    fv_trace_reader_destroy(&r);
    return valid;
}

static void real_files_map_the_unity_head_pose(void **state)
{
    (void)state;
    static const char *const sr_names[6] = {"helmet_pos_x", "helmet_pos_y", "helmet_pos_z",
                                            "helmet_rot_x", "helmet_rot_y", "helmet_rot_z"};
    static const char *const pico_names[6] = {"Head Position. x", "Head Position. y", "Head Position. z",
                                              "Head Rotation. x", "Head Rotation. y", "Head Rotation. z"};
    double lo, hi;
    /* TESTNA01, seated: Unity x 0.93..1.03 m, y 1.167..1.190 m (head height seated), z 0.49..0.57 m; boxes are the
     * observed ranges plus ~10 cm, with z negated (Unity +z forward -> fovea -z). */
    const box sr = {{800, 1050, -700}, {1150, 1300, -380}};
    uint64_t v = check_head_file(fv_test_data("gaze/htc_vive_pro_eye_sranipal/TESTNA01_2D_Fist3.csv"), ';', sr_names,
                                 &sr, &lo, &hi);
    assert_int_equal(v, 1518); /* every row has a numeric, non-zero pose */
    /* TESTNA10 (360° video): the helmet columns are present but 0 on every row, i.e. not logged: head stays invalid */
    const box any = {{-1e6, -1e6, -1e6}, {1e6, 1e6, 1e6}};
    v = check_head_file(fv_test_data("gaze/htc_vive_pro_eye_sranipal/TESTNA10_360VR_Fist3.csv"), ';', sr_names, &any,
                        &lo, &hi);
    assert_int_equal(v, 0);
    /* Pico, standing boxer: Unity x -0.02..0.21 m, y 1.19..1.61 m, z -0.41..-0.27 m -> fovea z +265..+406 mm.
     * Pitch (Rotation.x) is 6.3..20.2° on every row: the head looks down, so head_dir.y is -0.11..-0.35. */
    const box pico = {{-150, 1050, 150}, {350, 1750, 550}};
    v = check_head_file(fv_test_data("gaze/pico_neo3_pro/boxing_VR.tsv"), '\t', pico_names, &pico, &lo, &hi);
    assert_int_equal(v, 492);
    assert_true(hi < -0.10 && lo > -0.36);
}

static void read_mem(const char *text, const char *name, fv_gaze_sample *out, int n_expected)
{
    fv_trace_reader_desc d = {.data = text, .size = strlen(text), .name = name};
    fv_trace_reader *r = NULL;
    assert_int_equal(fv_trace_reader_create(NULL, &d, &r), FV_OK);
    for (int i = 0; i < n_expected; i++) assert_int_equal(fv_trace_reader_next(r, &out[i]), FV_OK);
    assert_int_equal(fv_trace_reader_next(r, &out[n_expected]), FV_END_OF_STREAM);
    assert_int_equal(fv_trace_reader_get_stats(r)->rows_skipped, 0);
    fv_trace_reader_destroy(&r);
}

static void v3_is(fv_vec3 got, double x, double y, double z, double tol, const char *what)
{
    near(got.x, x, tol, what);
    near(got.y, y, tol, what);
    near(got.z, z, tol, what);
}

static void unity_euler_angles_give_the_expected_head_vectors(void **state)
{
    (void)state;
    const double c30 = 0.86602540378443865;
    fv_gaze_sample s[8];
    /* SRanipal: yaw 90° (Unity forward -> +x -> fovea +x), then pitch +30° with roll 45° (looks down; roll does not
     * move the forward), then junk: a word, a NaN, a short row, a row of zeros. Eyes are read on every row. */
#define SR_HDR "time(100ns);eye_valid_L;eye_valid_R;openness_L;openness_R;pupil_diameter_L(mm);pupil_diameter_R(mm);" \
               "gaze_origin_L.x(mm);gaze_origin_L.y(mm);gaze_origin_L.z(mm);gaze_origin_R.x(mm);gaze_origin_R.y(mm);" \
               "gaze_origin_R.z(mm);gaze_direct_L.x;gaze_direct_L.y;gaze_direct_L.z;gaze_direct_R.x;gaze_direct_R.y;" \
               "gaze_direct_R.z;helmet_pos_x;helmet_pos_y;helmet_pos_z;helmet_rot_x;helmet_rot_y;helmet_rot_z\n"
#define SR_EYES "31;31;0.9;0.9;3.5;3.7;39;2;-38;-30;1;-35;0.1;-0.1;0.98;0.1;-0.1;0.98"
    const char *sr = SR_HDR "638342794000000000;" SR_EYES ";1;1.5;2;0;90;0\n"
                            "638342794000100000;" SR_EYES ";-0.25;1.2;-0.5;30;0;45\n"
                            "638342794000200000;" SR_EYES ";1;1.5;2;0;abc;0\n"
                            "638342794000300000;" SR_EYES ";nan;1.5;2;0;0;0\n"
                            "638342794000400000;" SR_EYES ";1;1.5\n"
                            "638342794000500000;" SR_EYES ";0;0;0;0;0;0\n";
    read_mem(sr, "head.csv", s, 6);
    assert_true(s[0].flags & FV_GAZE_HEAD_VALID);
    assert_true(s[0].head_pos_mm.x == 1000.0f && s[0].head_pos_mm.y == 1500.0f && s[0].head_pos_mm.z == -2000.0f);
    assert_true(s[0].head_dir.x == 1.0f && s[0].head_dir.y == 0.0f && s[0].head_dir.z == 0.0f); /* exact */
    assert_true(s[1].flags & FV_GAZE_HEAD_VALID);
    v3_is(s[1].head_pos_mm, -250.0, 1200.0, 500.0, 1e-4, "pos row 2");
    v3_is(s[1].head_dir, 0.0, -0.5, -c30, 1e-7, "dir row 2"); /* pitch +30: down and forward (-z) */
    for (int i = 2; i < 6; i++) {
        assert_false(s[i].flags & FV_GAZE_HEAD_VALID); /* the sample is kept, only the head is invalid */
        assert_true(isnan(s[i].head_pos_mm.x) && isnan(s[i].head_dir.z));
        assert_true(s[i].combined.flags & FV_EYE_DIRECTION_VALID);
    }

    /* Pico: yaw -90° (-> fovea -x), yaw 180° with pitch -30° (looks up and backwards: fovea +z), yaw 450° = 90°,
     * then an empty field and an infinity. */
#define PICO_HDR "Timeline\tHead Position. x\tHead Position. y\tHead Position. z\t" \
                 "Head Rotation. x\tHead Rotation. y\tHead Rotation. z\t" \
                 "Combine Eye Gaze Vector. x\tCombine Eye Gaze Vector. y\tCombine Eye Gaze Vector. z\t" \
                 "Left Eye Pose Status\tRight Eye Pose Status\tEye Left Blinking\tEye Right Blinking\n"
#define PICO_EYES "0\t0\t1\t52\t52\tFalse\tFalse"
    const char *pico = PICO_HDR "0.011\t0.0067\t1.6033\t-0.366\t0\t-90\t0\t" PICO_EYES "\n"
                                "0.022\t0\t1.6\t0.3\t-30\t180\t10\t" PICO_EYES "\n"
                                "0.033\t0\t1.6\t0.3\t0\t450\t0\t" PICO_EYES "\n"
                                "0.044\t0\t\t0.3\t0\t0\t0\t" PICO_EYES "\n"
                                "0.055\t0\t1.6\t0.3\tinf\t0\t0\t" PICO_EYES "\n";
    read_mem(pico, "head.tsv", s, 5);
    assert_true(s[0].flags & FV_GAZE_HEAD_VALID);
    v3_is(s[0].head_pos_mm, 6.7, 1603.3, 366.0, 1e-4, "pico pos row 1");
    assert_true(s[0].head_dir.x == -1.0f && s[0].head_dir.y == 0.0f && s[0].head_dir.z == 0.0f);
    v3_is(s[1].head_dir, 0.0, 0.5, c30, 1e-7, "pico dir row 2");
    assert_true(s[2].head_dir.x == 1.0f && s[2].head_dir.y == 0.0f && s[2].head_dir.z == 0.0f);
    for (int i = 3; i < 5; i++) {
        assert_false(s[i].flags & FV_GAZE_HEAD_VALID);
        assert_true(s[i].combined.flags & FV_EYE_DIRECTION_VALID);
    }

    /* no head columns at all: the file reads, the head is invalid */
    const char *bare = "Timeline\tCombine Eye Gaze Vector. x\tCombine Eye Gaze Vector. y\tCombine Eye Gaze Vector. z\t"
                       "Left Eye Pose Status\tRight Eye Pose Status\tEye Left Blinking\tEye Right Blinking\n"
                       "0.011\t" PICO_EYES "\n";
    read_mem(bare, "bare.tsv", s, 1);
    assert_false(s[0].flags & FV_GAZE_HEAD_VALID);
    assert_true(s[0].combined.flags & FV_EYE_DIRECTION_VALID);
#undef SR_HDR
#undef SR_EYES
#undef PICO_HDR
#undef PICO_EYES
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sranipal_testna01_counts_rate_and_axes),
        cmocka_unit_test(sranipal_testna10_is_monocular),
        cmocka_unit_test(tobii_g3_counts_rate_and_axes),
        cmocka_unit_test(pupil_core_counts_blinks_and_axes),
        cmocka_unit_test(pupil_cloud_counts_blinks_and_axes),
        cmocka_unit_test(pico_counts_rate_and_axes),
        cmocka_unit_test(bad_rows_are_skipped_with_line_and_reason),
        cmocka_unit_test(bad_row_warnings_are_rate_limited),
        cmocka_unit_test(missing_column_names_column_and_file),
        cmocka_unit_test(unknown_content_and_missing_file_are_clear_errors),
        cmocka_unit_test(format_names_round_trip),
        cmocka_unit_test(over_long_line_is_skipped_and_reading_goes_on),
        cmocka_unit_test(every_format_round_trips_through_fovea_format),
        cmocka_unit_test(memory_input_reads_the_same_as_the_file),
        cmocka_unit_test(truncated_gzip_gives_what_is_there),
        cmocka_unit_test(extreme_values_stay_finite_or_invalid),
        cmocka_unit_test(real_files_map_the_unity_head_pose),
        cmocka_unit_test(unity_euler_angles_give_the_expected_head_vectors),
    };
    if (getenv("FV_TEST_FILTER")) cmocka_set_test_filter(getenv("FV_TEST_FILTER")); /* run one test by name */
    return cmocka_run_group_tests(tests, NULL, NULL);
}
