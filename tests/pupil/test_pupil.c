/* @brief The pupil driver: URI parsing, the pure decoder (3D binocular and monocular, 2D through the camera model,
 * every kind of malformed message, extremes), and the live driver against a fake Pupil Capture that replays the real
 * Pupil Core export (../shared/data/gaze/pupil_core) as the messages Capture sends: clock synchronisation, the same
 * samples as the recorded reader decodes from the same rows, malformed messages skipped with a warning while the
 * stream goes on, reconnection when Capture restarts on a new SUB port, and probing. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <msgpack.h>

#include "fake_capture.h"
#include "fake_export.h"
#include "fv_clock.h"
#include "fv_pupil_driver.h"
#include "fv_test.h"
#include "fv_trace.h"

/* Malformed messages, each with the phrase its warning must hold. */
typedef struct bad_kind {
    const char *phrase;
} bad_kind;

static const bad_kind g_bad[] = {
    {"payload is not msgpack (parse error: byte 0xc1 at offset 0"},
    {"truncated"},
    {"missing field 'timestamp'"},
    {"field 'timestamp' is a string, not a number"},
    {"field 'gaze_normals_3d.0[1]' is NaN"},
    {"field 'norm_pos' has 3 values, not 2"},
    {"payload is an array, not a map"},
    {"a topic frame with no payload frame"},
    {"field 'confidence' is infinite"},
    {"field 'eye_centers_3d' has a key that is not eye 0 or 1"},
    {"field 'base_data' is a string, not an array of pupil datums"},
};
#define N_BAD (sizeof g_bad / sizeof g_bad[0])

static void bad_message(size_t kind, const fake_msg *good, fake_msg *m)
{
    memset(m, 0, sizeof *m);
    snprintf(m->topic, sizeof m->topic, "gaze.3d.01.");
    m->due_pupil_ns = good->due_pupil_ns;
    pk k;
    pk_init(&k);
    double v3[3] = {0.1, NAN, -0.9}, v2[3] = {0.5, 0.5, 0.5};
    switch (kind) {
    case 0: msgpack_sbuffer_write(&k.sb, "\xc1\xc1\xc1 not msgpack", 15); break;
    case 1: msgpack_sbuffer_write(&k.sb, (const char *)good->payload, good->len / 2); break;
    case 2:
        msgpack_pack_map(&k.p, 1);
        pk_str(&k, "confidence");
        msgpack_pack_double(&k.p, 0.9);
        break;
    case 3:
        msgpack_pack_map(&k.p, 2);
        pk_str(&k, "timestamp");
        pk_str(&k, "329367.9");
        pk_str(&k, "confidence");
        msgpack_pack_double(&k.p, 0.9);
        break;
    case 4:
    case 9:
        msgpack_pack_map(&k.p, 3);
        pk_str(&k, "timestamp");
        msgpack_pack_double(&k.p, (double)good->due_pupil_ns * 1e-9);
        pk_str(&k, "confidence");
        msgpack_pack_double(&k.p, 0.9);
        pk_str(&k, kind == 4 ? "gaze_normals_3d" : "eye_centers_3d");
        msgpack_pack_map(&k.p, 1);
        msgpack_pack_int(&k.p, kind == 4 ? 0 : 2);
        pk_vec(&k, v3, 3);
        break;
    case 5:
    case 8:
    case 10:
        msgpack_pack_map(&k.p, 4);
        pk_str(&k, "timestamp");
        msgpack_pack_double(&k.p, (double)good->due_pupil_ns * 1e-9);
        pk_str(&k, "confidence");
        msgpack_pack_double(&k.p, kind == 8 ? INFINITY : 0.9);
        pk_str(&k, "norm_pos");
        pk_vec(&k, v2, kind == 5 ? 3 : 2);
        pk_str(&k, "base_data");
        if (kind == 10) pk_str(&k, "329367.890963-0");
        else msgpack_pack_array(&k.p, 0);
        break;
    case 6: pk_vec(&k, v2, 2); break;
    case 7: m->single_frame = true; break;
    }
    m->payload = pk_take(&k, &m->len);
}

/* ---------------- URI ---------------- */

static void uri_defaults_and_options(void **state)
{
    (void)state;
    fv_pupil_uri u;
    assert_int_equal(fv_pupil_uri_parse("pupil:", &u), FV_OK);
    assert_string_equal(u.host, "127.0.0.1");
    assert_int_equal(u.port, 50020);
    assert_true(u.camera.fx_px == 800.0 && u.camera.cx_px == 640.0 && u.camera.cy_px == 360.0);
    assert_true(u.min_confidence == 0.6);
    assert_int_equal(fv_pupil_uri_parse("pupil:10.0.0.2:50021?fx=600&width=640&height=480&min_confidence=-1", &u),
                     FV_OK);
    assert_string_equal(u.host, "10.0.0.2");
    assert_int_equal(u.port, 50021);
    assert_true(u.camera.fx_px == 600.0 && u.camera.fy_px == 600.0 && u.camera.cx_px == 320.0 &&
                u.camera.cy_px == 240.0 && u.min_confidence == -1.0);
    assert_int_equal(fv_pupil_uri_parse("pupil:[::1]:6000", &u), FV_OK);
    assert_string_equal(u.host, "::1");
    assert_int_equal(u.port, 6000);
    assert_int_equal(fv_pupil_uri_parse("pupil:capture.local", &u), FV_OK);
    assert_int_equal(u.port, 50020);
}

static void uri_errors_name_the_option(void **state)
{
    (void)state;
    struct {
        const char *uri, *phrase;
    } bad[] = {
        {"pupil:host:0", "port '0' must be a number in 1..65535"},
        {"pupil:host:70000", "port '70000' must be a number in 1..65535"},
        {"pupil:host:x1", "port 'x1' must be"},
        {"pupil:host:", "port must be a number"},
        {"pupil:host?speed=2", "unknown option 'speed'"},
        {"pupil:host?fx=-1", "fx '-1' must be a number in [1, 100000]"},
        {"pupil:host?fx=nan", "fx 'nan' must be"},
        {"pupil:host?fy", "malformed option 'fy'"},
        {"pupil:host?width=100&cx=300", "principal point (300, 360) px lies outside"},
        {"pupil:ho st", "not allowed in a host name"},
        {"pupil:[::1", "'[' without ']'"},
        {"pupil:host?timeout_ms=0", "timeout_ms '0' must be an integer"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        fv_pupil_uri u;
        fv_test_log_capture_begin();
        assert_int_equal(fv_pupil_uri_parse(bad[i].uri, &u), FV_ERR_INVALID_ARG);
        fv_assert_log_contains(bad[i].phrase);
        fv_test_log_capture_end();
    }
}

/* ---------------- decoder ---------------- */

static fv_result decode(const char *topic, const fake_msg *m, fv_gaze_sample *s, char *why)
{
    fv_pupil_camera cam = fv_pupil_camera_default();
    return fv_pupil_decode_gaze(topic, strlen(topic), m->payload, m->len, &cam, 0.6, s, why, 160);
}

static void decode_2d_through_the_camera_model(void **state)
{
    (void)state;
    fv_pupil_camera cam = {1000, 800, 500, 500, 500, 400};
    double norm[][2] = {{0.5, 0.5}, {0.75, 0.25}, {0, 0}, {1, 1}, {1e6, -1e6}};
    for (size_t i = 0; i < 5; i++) {
        pk k;
        pk_init(&k);
        msgpack_pack_map(&k.p, 3);
        pk_str(&k, "timestamp");
        msgpack_pack_double(&k.p, 12.5);
        pk_str(&k, "confidence");
        msgpack_pack_double(&k.p, 1.0);
        pk_str(&k, "norm_pos");
        pk_vec(&k, norm[i], 2);
        size_t len;
        unsigned char *b = pk_take(&k, &len);
        fv_gaze_sample s;
        char why[160];
        assert_int_equal(fv_pupil_decode_gaze("gaze.2d.0.", 10, b, len, &cam, 0.6, &s, why, sizeof why), FV_OK);
        free(b);
        assert_true(s.t_device_ns == INT64_C(12500000000));
        if (i == 4) { /* a million image widths off: a ray 90 degrees to the side no eye can make: dropped */
            assert_false(s.combined.flags & FV_EYE_DIRECTION_VALID);
            continue;
        }
        assert_true(s.combined.flags & FV_EYE_DIRECTION_VALID);
        double x = (norm[i][0] * 1000 - 500) / 500, y = (400 - (1 - norm[i][1]) * 800) / 500, z = -1;
        double l = sqrt(x * x + y * y + z * z);
        assert_true(fabs(s.combined.direction.x - x / l) < 1e-6);
        assert_true(fabs(s.combined.direction.y - y / l) < 1e-6);
        assert_true(fabs(s.combined.direction.z - z / l) < 1e-6);
        assert_true(fv_v3_isfinite(s.combined.direction));
        assert_false(s.eye[0].flags & FV_EYE_PUPIL_VALID); /* no base_data */
    }
}

static void decode_rejects_each_malformed_kind(void **state)
{
    (void)state;
    size_t n;
    row *rows = fake_export_rows(&n);
    fake_msg good;
    fake_row_message(&rows[0], 0, &good);
    fv_gaze_sample s;
    char why[160];
    assert_int_equal(decode(good.topic, &good, &s, why), FV_OK);
    for (size_t kind = 0; kind < N_BAD; kind++) {
        if (kind == 7) continue; /* a transport fault: checked on the live stream */
        fake_msg m;
        bad_message(kind, &good, &m);
        assert_int_equal(decode(m.topic, &m, &s, why), FV_ERR_PARSE);
        if (!strstr(why, g_bad[kind].phrase)) fail_msg("kind %zu: expected '%s' in '%s'", kind, g_bad[kind].phrase, why);
        assert_false(s.combined.flags & FV_EYE_DIRECTION_VALID);
        free(m.payload);
    }
    /* wrong topic, empty payload, oversized payload, timestamps out of range */
    assert_int_equal(decode("pupil.0.3d", &good, &s, why), FV_ERR_PARSE);
    fv_assert_contains(why, "not a gaze topic");
    fv_pupil_camera cam = fv_pupil_camera_default();
    assert_int_equal(fv_pupil_decode_gaze("gaze.", 5, good.payload, 0, &cam, 0.6, &s, why, sizeof why), FV_ERR_PARSE);
    fv_assert_contains(why, "empty payload");
    assert_int_equal(fv_pupil_decode_gaze("gaze.", 5, good.payload, FV_PUPIL_MAX_PAYLOAD + 1, &cam, 0.6, &s, why,
                                          sizeof why), FV_ERR_PARSE);
    fv_assert_contains(why, "exceeds");
    double ts_bad[] = {-1.0, 1e10, 1e300};
    for (int i = 0; i < 3; i++) {
        pk k;
        pk_init(&k);
        msgpack_pack_map(&k.p, 2);
        pk_str(&k, "timestamp");
        msgpack_pack_double(&k.p, ts_bad[i]);
        pk_str(&k, "confidence");
        msgpack_pack_double(&k.p, 1);
        fake_msg m = {0};
        m.payload = pk_take(&k, &m.len);
        assert_int_equal(decode("gaze.2d.0.", &m, &s, why), FV_ERR_PARSE);
        fv_assert_contains(why, "outside [0, 9e9] s");
        free(m.payload);
    }
    free(good.payload);
    free(rows);
}

/* A hostile server's payloads: every count and size is bounded by the bytes the message has left, and the depth, before
 * msgpack-c allocates (the 5-byte map32 asked it for 192 GiB: under ASan the original aborted here). Each is refused
 * with the reason: what claims how much, where, and what is left. */
static void decode_bounds_what_it_allocates_by_the_message(void **state)
{
    (void)state;
    for (size_t i = 0; i < FAKE_HOSTILE_COUNT; i++) {
        unsigned char buf[256];
        const char *name, *phrase;
        fake_msg m = {0};
        m.payload = buf;
        m.len = fake_hostile_payload(i, buf, sizeof buf, &name, &phrase);
        fv_gaze_sample s;
        char why[160];
        assert_int_equal(decode("gaze.3d.01.", &m, &s, why), FV_ERR_PARSE);
        if (!strstr(why, phrase)) fail_msg("%s: expected '%s' in '%s'", name, phrase, why);
        assert_false(s.combined.flags & FV_EYE_DIRECTION_VALID);
    }
    /* within the bounds: an array of 60,000 empty maps fills 60,005 bytes exactly; decoded, then refused as not a
     * map (msgpack-c allocates one object per element: bounded by the payload) */
    size_t len = 5 + 60000;
    unsigned char *big = malloc(len);
    big[0] = 0xdd, big[1] = 0, big[2] = 0, big[3] = 0xea, big[4] = 0x60;
    memset(big + 5, 0x80, 60000);
    fake_msg m = {.payload = big, .len = len};
    fv_gaze_sample s;
    char why[160];
    assert_int_equal(decode("gaze.3d.01.", &m, &s, why), FV_ERR_PARSE);
    fv_assert_contains(why, "payload is an array, not a map");
    big[4] = 0x61; /* one element more than the bytes hold */
    assert_int_equal(decode("gaze.3d.01.", &m, &s, why), FV_ERR_PARSE);
    fv_assert_contains(why, "an array of 60001 elements at offset 0, 60000 bytes left");
    free(big);
    /* a real datum with one byte more: trailing bytes */
    size_t n;
    row *rows = fake_export_rows(&n);
    fake_msg good;
    fake_row_message(&rows[0], 0, &good);
    unsigned char *more = malloc(good.len + 1);
    memcpy(more, good.payload, good.len);
    more[good.len] = 0xc0;
    fake_msg t = {.payload = more, .len = good.len + 1};
    assert_int_equal(decode(good.topic, &t, &s, why), FV_ERR_PARSE);
    fv_assert_contains(why, "payload has 1 bytes after its msgpack value");
    free(more);
    free(good.payload);
    free(rows);
}

/* Extremes that are valid messages: a zero gaze normal, huge eye centres, pupil 0 and 25 mm, confidence 0 and 1.
 * Nothing non-finite comes out; what cannot be a measurement stays invalid. */
static void decode_extremes_stay_finite(void **state)
{
    (void)state;
    double zero[3] = {0, 0, 0}, far[3] = {1e30, 0, 0}, p[3] = {0, 0, 500}, np[2] = {0.5, 0.5};
    double conf[] = {0.0, 1.0};
    double dia[] = {0.0, 25.0};
    for (int c = 0; c < 2; c++) {
        pk k;
        pk_init(&k);
        msgpack_pack_map(&k.p, 7);
        pk_str(&k, "timestamp");
        msgpack_pack_double(&k.p, 0.0);
        pk_str(&k, "confidence");
        msgpack_pack_double(&k.p, conf[c]);
        pk_str(&k, "norm_pos");
        pk_vec(&k, np, 2);
        pk_str(&k, "gaze_point_3d");
        pk_vec(&k, p, 3);
        pk_str(&k, "eye_centers_3d");
        msgpack_pack_map(&k.p, 2);
        msgpack_pack_int(&k.p, 0);
        pk_vec(&k, far, 3);
        pk_str(&k, "1");
        pk_vec(&k, zero, 3);
        pk_str(&k, "gaze_normals_3d");
        msgpack_pack_map(&k.p, 2);
        msgpack_pack_int(&k.p, 0);
        pk_vec(&k, zero, 3);
        msgpack_pack_int(&k.p, 1);
        pk_vec(&k, p, 3);
        pk_str(&k, "base_data");
        msgpack_pack_array(&k.p, 2);
        for (int e = 0; e < 2; e++) {
            msgpack_pack_map(&k.p, 2);
            pk_str(&k, "id");
            msgpack_pack_int(&k.p, e);
            pk_str(&k, "diameter_3d");
            msgpack_pack_double(&k.p, dia[e]);
        }
        fake_msg m = {0};
        m.payload = pk_take(&k, &m.len);
        fv_gaze_sample s;
        char why[160];
        assert_int_equal(decode("gaze.3d.01.", &m, &s, why), FV_OK);
        free(m.payload);
        const fv_eye_sample *r = &s.eye[FV_EYE_RIGHT], *l = &s.eye[FV_EYE_LEFT];
        assert_false(r->flags & (FV_EYE_ORIGIN_VALID | FV_EYE_DIRECTION_VALID | FV_EYE_PUPIL_VALID));
        assert_false(l->flags & FV_EYE_PUPIL_VALID); /* 25 mm is not a pupil */
        if (c == 0) {
            assert_false(s.combined.flags & FV_EYE_DIRECTION_VALID); /* below the confidence floor */
        } else {
            assert_true(l->flags & FV_EYE_ORIGIN_VALID);
            assert_true(l->flags & FV_EYE_DIRECTION_VALID);
            assert_true(fabs(l->direction.z + 1.0f) < 1e-6); /* camera +z forward is head -z */
            assert_true(s.combined.flags & FV_EYE_DIRECTION_VALID);
            assert_true(fv_v3_isfinite(s.combined.direction) && fv_v3_isfinite(s.combined.origin_mm));
        }
    }
}

/* ---------------- live: the export through a fake Capture ---------------- */

typedef struct expect {
    int64_t t_ns;
    fv_gaze_sample s;
} expect;

static int cmp_expect(const void *a, const void *b)
{
    int64_t x = ((const expect *)a)->t_ns, y = ((const expect *)b)->t_ns;
    return x < y ? -1 : x > y;
}

static bool near3(fv_vec3 a, fv_vec3 b, float tol)
{
    return fabsf(a.x - b.x) <= tol && fabsf(a.y - b.y) <= tol && fabsf(a.z - b.z) <= tol;
}

#define MASK (FV_EYE_ORIGIN_VALID | FV_EYE_DIRECTION_VALID)

/* The driver on the fake's Pupil Remote (query: "" or "?timeout_ms=200"), the log captured from here on. */
static fv_device *open_on(const fake_capture *f, const char *query, const fv_device_open_desc *desc)
{
    char uri[160];
    snprintf(uri, sizeof uri, "pupil:127.0.0.1:%d%s", f->remote_port, query);
    fv_test_log_capture_begin();
    fv_device *dev = NULL;
    assert_int_equal(fv_pupil_driver.open(uri, desc, &dev), FV_OK);
    return dev;
}

static void live_replay_matches_recorded_reader(void **state)
{
    (void)state;
    size_t n;
    row *rows = fake_export_rows(&n);
    assert_true(n > 2000);
    /* The recorded reader's decoding of the same rows (no blinks file: Capture does not send blinks) */
    fv_trace_reader_desc rd = {.format = FV_TRACE_FORMAT_PUPIL_CORE, .blinks_path = ""};
    fv_trace_reader *reader;
    assert_int_equal(fv_trace_reader_create(fv_test_data("gaze/pupil_core/gaze_positions.csv"), &rd, &reader), FV_OK);
    expect *ex = calloc(n + 1, sizeof *ex);
    size_t nex = 0;
    while (nex < n && fv_trace_reader_next(reader, &ex[nex].s) == FV_OK) {
        ex[nex].t_ns = ex[nex].s.t_device_ns;
        nex++;
    }
    fv_trace_reader_destroy(&reader);
    qsort(ex, nex, sizeof *ex, cmp_expect);

    /* Script: every row at its own Pupil time, and one of each malformed kind every 150 rows */
    size_t nmsg = 0;
    fake_msg *script = calloc(n + N_BAD, sizeof *script);
    for (size_t i = 0; i < n; i++) {
        fake_row_message(&rows[i], i, &script[nmsg++]);
        if (i % 150 == 75 && i / 150 < N_BAD) {
            bad_message(i / 150, &script[nmsg - 1], &script[nmsg]);
            nmsg++;
        }
    }

    fake_capture f;
    /* Pupil clock 100 ms before the first row: the replay runs in real time */
    assert_int_equal(fake_capture_start(&f, 0, script[0].due_pupil_ns - 100 * FV_NS_PER_MS), 0);
    int64_t host0 = fv_time_monotonic_ns(), pupil0 = fake_capture_pupil_now_ns(&f);
    fv_device *dev = open_on(&f, "", NULL);
    assert_int_equal(fake_capture_play(&f, script, nmsg), 0);

    size_t got = 0, matched = 0, pupils = 0, sync_checked = 0;
    int64_t last_t = INT64_MIN, worst_sync_ns = 0;
    fv_gaze_sample buf[64];
    int64_t deadline = fv_time_monotonic_ns() + 30 * FV_NS_PER_S;
    while (got < n && fv_time_monotonic_ns() < deadline) {
        size_t c = 0;
        fv_result r = fv_device_read(dev, buf, 64, &c, 50);
        assert_true(r == FV_OK || r == FV_TIMEOUT);
        for (size_t i = 0; i < c; i++) {
            const fv_gaze_sample *s = &buf[i];
            assert_true(s->t_device_ns > last_t); /* in order, nothing twice */
            last_t = s->t_device_ns;
            assert_true(s->flags & FV_GAZE_HOST_TIME_VALID);
            /* Clock sync: the fake took this sample at host0 + (t - pupil0) */
            int64_t truth = host0 + (s->t_device_ns - pupil0), err = s->t_host_ns - truth;
            if (err < 0) err = -err;
            if (err > worst_sync_ns) worst_sync_ns = err;
            sync_checked++;
            expect key = {.t_ns = s->t_device_ns}, *e = bsearch(&key, ex, nex, sizeof *ex, cmp_expect);
            if (e) {
                for (int k = 0; k < 2; k++) {
                    assert_int_equal(s->eye[k].flags & MASK, e->s.eye[k].flags & MASK);
                    if (s->eye[k].flags & FV_EYE_DIRECTION_VALID)
                        assert_true(near3(s->eye[k].direction, e->s.eye[k].direction, 1e-6f));
                    if (s->eye[k].flags & FV_EYE_ORIGIN_VALID)
                        assert_true(near3(s->eye[k].origin_mm, e->s.eye[k].origin_mm, 1e-3f));
                }
                assert_int_equal(s->combined.flags & MASK, e->s.combined.flags & MASK);
                if (s->combined.flags & FV_EYE_DIRECTION_VALID)
                    assert_true(near3(s->combined.direction, e->s.combined.direction, 1e-5f));
                assert_true(s->confidence == e->s.confidence);
                matched++;
            }
            /* base_data's diameter_3d, per eye, for samples above the confidence floor */
            size_t row_i = 0;
            while (row_i < n && llround(rows[row_i].ts * 1e9) != s->t_device_ns) row_i++;
            assert_true(row_i < n);
            const row *rw = &rows[row_i];
            for (int b = 0; b < rw->base_n && rw->conf >= 0.6; b++) {
                const fv_eye_sample *es = &s->eye[rw->base_id[b] == 0 ? FV_EYE_RIGHT : FV_EYE_LEFT];
                assert_true(es->flags & FV_EYE_PUPIL_VALID);
                assert_true(fabsf(es->pupil_mm - (float)fake_diameter_mm(row_i, rw->base_id[b])) < 1e-5f);
                pupils++;
            }
        }
        got += c;
    }
    fv_device_close(&dev);
    fake_capture_stop(&f);
    printf("pupil live: %zu of %zu rows received, %zu matched the recorded reader, %zu pupils, worst clock error "
           "%.1f us\n", got, n, matched, pupils, (double)worst_sync_ns * 1e-3);
    assert_int_equal(got, n);               /* every good message, and no malformed one */
    assert_true(matched >= n - n / 100);    /* the recorded reader drops only rows its time checks refuse */
    assert_true(pupils > n);                /* binocular rows carry two */
    assert_true(sync_checked == got);
    assert_true(worst_sync_ns < 20 * FV_NS_PER_MS); /* loopback: the sync error is well below a frame */
    /* each malformed message: one warning that names what is wrong, "skipped" */
    for (size_t k = 0; k < N_BAD; k++) fv_assert_log_contains(g_bad[k].phrase);
    const char *log = fv_test_log_text();
    size_t skipped = 0;
    for (const char *p = log; (p = strstr(p, "; skipped")); p++) skipped++;
    assert_int_equal(skipped, N_BAD);
    fv_test_log_capture_end();
    for (size_t i = 0; i < nmsg; i++) free(script[i].payload);
    free(script);
    free(ex);
    free(rows);
}

/* Capture quits and comes back on a new SUB port: the driver warns, then reconnects and the stream goes on. */
static void live_reconnects_when_capture_restarts(void **state)
{
    (void)state;
    size_t n;
    row *rows = fake_export_rows(&n);
    enum { PART = 40 };
    fake_msg a[PART], b[PART];
    for (size_t i = 0; i < PART; i++) {
        fake_row_message(&rows[i], i, &a[i]);
        fake_row_message(&rows[200 + i], 200 + i, &b[i]);
    }
    fake_capture f;
    assert_int_equal(fake_capture_start(&f, 0, a[0].due_pupil_ns - 50 * FV_NS_PER_MS), 0);
    int remote = f.remote_port, sub_a = f.sub_port;
    char uri[128];
    snprintf(uri, sizeof uri, "pupil:127.0.0.1:%d", remote);
    fv_test_log_capture_begin();
    fv_device *dev = NULL;
    assert_int_equal(fv_pupil_driver.open(uri, NULL, &dev), FV_OK);
    assert_int_equal(fake_capture_play(&f, a, PART), 0);
    fv_gaze_sample buf[64];
    size_t got_a = 0, got_b = 0;
    for (int i = 0; i < 200 && got_a < PART; i++) {
        size_t c = 0;
        (void)fv_device_read(dev, buf, 64, &c, 20);
        got_a += c;
    }
    assert_int_equal(got_a, PART);
    fake_capture_stop(&f); /* Capture quits */
    for (int i = 0; i < 40; i++) { /* 2 s of silence: the driver notices */
        size_t c = 0;
        assert_int_equal(fv_device_read(dev, buf, 64, &c, 50), FV_TIMEOUT);
    }
    fv_assert_log_contains("stopped answering");
    /* Capture restarts: same Pupil Remote port, a new SUB port (bound while the old one may still be held) */
    fake_capture g;
    assert_int_equal(fake_capture_start(&g, remote, b[0].due_pupil_ns - 50 * FV_NS_PER_MS), 0);
    assert_int_equal(g.remote_port, remote);
    assert_int_equal(fake_capture_play(&g, b, PART), 0);
    int64_t first_b = 0;
    for (int i = 0; i < 300 && got_b < PART; i++) {
        size_t c = 0;
        (void)fv_device_read(dev, buf, 64, &c, 20);
        if (c && !first_b) first_b = buf[0].t_device_ns;
        got_b += c;
    }
    printf("pupil reconnect: SUB port %d -> %d, %zu + %zu samples\n", sub_a, g.sub_port, got_a, got_b);
    assert_int_equal(got_b, PART);
    assert_true(first_b == b[0].due_pupil_ns);
    fv_assert_log_contains("reconnected");
    fv_test_log_capture_end();
    fv_device_close(&dev);
    fake_capture_stop(&g);
    for (size_t i = 0; i < PART; i++) {
        free(a[i].payload);
        free(b[i].payload);
    }
    free(rows);
}

/* A hostile Capture sends 10,000 malformed messages. Over the simulated seconds the reads take, the warnings are at
 * most 20 lines per 30 s window and one summary per window, and the summaries count exactly the rest (the original
 * printed 20 lines, then one per 1000 without end, and no count of what it did not show). */
static void live_flood_of_malformed_messages_is_rate_limited(void **state)
{
    (void)state;
    enum { FLOOD = 10000 };
    size_t n;
    row *rows = fake_export_rows(&n);
    fake_msg good, *script = calloc(FLOOD + 1, sizeof *script);
    fake_row_message(&rows[0], 0, &good);
    for (size_t i = 0; i < FLOOD; i++) {
        bad_message(i % N_BAD, &good, &script[i]);
        script[i].due_pupil_ns = 0; /* all at once */
    }
    fake_row_message(&rows[1], 1, &script[FLOOD]); /* then one good message: the flood has been read */
    int64_t last_t = script[FLOOD].due_pupil_ns;
    script[FLOOD].due_pupil_ns = 0;
    static fake_capture f; /* static: a failed assertion leaves its threads running */
    assert_int_equal(fake_capture_start(&f, 0, 1000 * FV_NS_PER_S), 0);
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fv_device_open_desc desc = {.clock = &clk};
    fv_device *dev = open_on(&f, "", &desc);
    assert_int_equal(fake_capture_play(&f, script, FLOOD + 1), 0);
    bool done = false;
    int reads = 0;
    int64_t deadline = fv_time_monotonic_ns() + 60 * FV_NS_PER_S;
    while (!done && fv_time_monotonic_ns() < deadline) {
        fv_gaze_sample buf[64];
        size_t c = 0;
        (void)fv_device_read(dev, buf, 64, &c, 20);
        for (size_t i = 0; i < c; i++) done |= buf[i].t_device_ns == last_t;
        fv_clock_sim_advance(&clk, 100 * FV_NS_PER_MS); /* each read: 0.1 s of simulated time */
        reads++;
    }
    int64_t span = fv_clock_now_ns(&clk);
    fv_device_close(&dev);
    fake_capture_stop(&f);
    fv_test_log_capture_end();
    assert_true(done);
    unsigned long long summarised = 0;
    int summaries = fv_test_log_lines("more like this in the last", &summarised);
    int shown = fv_test_log_lines("; skipped", NULL) - summaries; /* a summary quotes its first message */
    int windows = (int)(span / (30 * FV_NS_PER_S)) + 1;
    printf("pupil flood: %d malformed messages in %d reads over %.1f simulated s: %d lines shown, %d summaries of "
           "%llu\n", FLOOD, reads, (double)span * 1e-9, shown, summaries, summarised);
    assert_true(reads >= FLOOD / (64 + 257)); /* a read skips a bounded number: the flood cannot hold it */
    assert_true((unsigned long long)shown + summarised == FLOOD);
    assert_true(shown >= 20 && shown <= 20 * windows);
    assert_true(summaries >= 1 && summaries <= windows);
    fv_assert_log_contains("payload is not msgpack (parse error: byte 0xc1 at offset 0");
    /* the good message at the end may be far from the simulated clock: a clock jump, said once */
    int others = fv_test_log_lines("the Pupil clock jumped", NULL);
    assert_true(others <= 1);
    if (fv_test_log_count(FV_LOG_LEVEL_WARN) != shown + summaries + others) {
        fputs(fv_test_log_text(), stderr);
        fail_msg("lines other than the malformed messages' and their summary: see above");
    }
    for (size_t i = 0; i <= FLOOD; i++) free(script[i].payload);
    free(script);
    free(good.payload);
    free(rows);
}

/* Gaze whose Pupil time is an hour from what Pupil Remote's `t` says (a clock that jumped, or a hostile Capture):
 * each such sample carries its receipt time and is warned about through a rate limit (3 lines, then a summary with
 * the exact count); the driver resynchronises at most once a second (the original resynchronised at every read:
 * six `t` round trips each time); the samples after the jump map to the right host time again. */
static void live_clock_jumps_are_rate_limited_and_resync_is_throttled(void **state)
{
    (void)state;
    size_t n;
    row *rows = fake_export_rows(&n);
    enum { BEFORE = 30, JUMPED = 300, AFTER = 30, TOTAL = BEFORE + JUMPED + AFTER };
    fake_msg script[TOTAL];
    int64_t jump_ns = 3600 * FV_NS_PER_S;
    for (size_t i = 0; i < TOTAL; i++) {
        row r = rows[i];
        bool jumped = i >= BEFORE && i < BEFORE + JUMPED;
        if (jumped) r.ts += 3600.0;
        fake_row_message(&r, i, &script[i]);
        script[i].due_pupil_ns = (int64_t)llround(rows[i].ts * 1e9);
    }
    static fake_capture f; /* static: a failed assertion leaves its threads running */
    assert_int_equal(fake_capture_start(&f, 0, script[0].due_pupil_ns - 50 * FV_NS_PER_MS), 0);
    int64_t host0 = fv_time_monotonic_ns(), pupil0 = fake_capture_pupil_now_ns(&f);
    fv_device *dev = open_on(&f, "", NULL);
    int t_open = atomic_load(&f.t_requests);
    int64_t start = fv_time_monotonic_ns();
    assert_int_equal(fake_capture_play(&f, script, TOTAL), 0);
    size_t got = 0, jumped = 0, after_ok = 0;
    int64_t deadline = start + 20 * FV_NS_PER_S;
    while (got < TOTAL && fv_time_monotonic_ns() < deadline) {
        fv_gaze_sample buf[64];
        size_t c = 0;
        (void)fv_device_read(dev, buf, 64, &c, 50);
        for (size_t i = 0; i < c; i++, got++) {
            const fv_gaze_sample *s = &buf[i];
            if (s->t_device_ns > pupil0 + jump_ns / 2) {
                jumped++;
            } else if (got >= BEFORE + JUMPED) {
                int64_t err = s->t_host_ns - (host0 + (s->t_device_ns - pupil0));
                after_ok += err > -20 * FV_NS_PER_MS && err < 20 * FV_NS_PER_MS;
            }
        }
    }
    double secs = (double)(fv_time_monotonic_ns() - start) * 1e-9;
    int t_during = atomic_load(&f.t_requests) - t_open;
    fv_device_close(&dev);
    fake_capture_stop(&f);
    fv_test_log_capture_end();
    unsigned long long summarised = 0;
    int summaries = fv_test_log_lines("more like this in the last", &summarised);
    int shown = fv_test_log_lines("the Pupil clock jumped", NULL) - summaries;
    printf("pupil clock jump: %zu of %d samples, %zu jumped: %d lines + %d summaries of %llu; %d 't' requests in "
           "%.2f s\n", got, TOTAL, jumped, shown, summaries, summarised, t_during, secs);
    assert_int_equal(got, TOTAL);
    assert_int_equal(jumped, JUMPED);
    assert_true(shown >= 1 && shown <= 3);
    assert_true((unsigned long long)shown + summarised == JUMPED);
    fv_assert_log_contains("gaze at Pupil time 33296"); /* an hour after the export's 329367 s */
    fv_assert_log_contains("s from its receipt: the Pupil clock jumped; resynchronising");
    assert_true(t_during <= 6 * (int)(secs + 2.0)); /* six exchanges per resynchronisation, at most one a second */
    assert_int_equal(after_ok, AFTER);
    for (size_t i = 0; i < TOTAL; i++) free(script[i].payload);
    free(rows);
}

/* A frame larger than any gaze payload (16 MiB) is refused by the socket at its header, before it is allocated
 * (ZMQ_MAXMSGSIZE; the original took it whole and then said "exceeds"). libzmq drops that connection for good: after
 * a second without gaze the driver subscribes again and the stream goes on. */
static void live_oversized_frame_is_refused_before_it_is_allocated(void **state)
{
    (void)state;
    size_t n;
    row *rows = fake_export_rows(&n);
    enum { PART = 20, TOTAL = 2 * PART + 1 };
    fake_msg script[TOTAL];
    for (size_t i = 0; i < TOTAL; i++) {
        row r = rows[i];
        if (i > PART) r.ts += 2.0; /* the second part 2 s later: the driver subscribes again after 1 s of silence */
        fake_row_message(&r, i, &script[i]);
    }
    free(script[PART].payload);
    script[PART].len = (size_t)16 << 20;
    script[PART].payload = calloc(script[PART].len, 1);
    static fake_capture f; /* static: a failed assertion leaves its threads running */
    assert_int_equal(fake_capture_start(&f, 0, script[0].due_pupil_ns - 50 * FV_NS_PER_MS), 0);
    fv_device *dev = open_on(&f, "", NULL);
    assert_int_equal(fake_capture_play(&f, script, TOTAL), 0);
    size_t got = 0;
    int64_t deadline = fv_time_monotonic_ns() + 10 * FV_NS_PER_S;
    while (got < 2 * PART && fv_time_monotonic_ns() < deadline) {
        fv_gaze_sample buf[64];
        size_t c = 0;
        (void)fv_device_read(dev, buf, 64, &c, 50);
        got += c;
    }
    fv_device_close(&dev);
    fake_capture_stop(&f);
    fv_test_log_capture_end();
    printf("pupil oversized frame: %zu of %d good messages around it\n", got, 2 * PART);
    assert_null(strstr(fv_test_log_text(), "exceeds"));
    assert_int_equal(got, 2 * PART);
    for (size_t i = 0; i < TOTAL; i++) free(script[i].payload);
    free(rows);
}

/* Pupil Remote answers `t` with garbage, or not in time: the warning says which, quoting what came back (escaped,
 * shortened), instead of calling both "no answer". */
static void open_tells_a_garbage_answer_to_t_from_no_answer(void **state)
{
    (void)state;
    static fake_capture f; /* static: a failed assertion leaves its threads running */
    assert_int_equal(fake_capture_start(&f, 0, 1000 * FV_NS_PER_S), 0);
    static const char garbage[] = "\x01garbage\nanswer\0with a NUL, and longer than thirty-two bytes";
    f.t_reply = garbage;
    f.t_reply_len = sizeof garbage - 1;
    char want[256];
    fv_device *dev = open_on(&f, "?timeout_ms=200", NULL);
    snprintf(want, sizeof want, "no clock synchronisation with Pupil time (Pupil Remote answered 't' with "
             "'\\x01garbage\\x0aanswer\\x00with a NUL, and ...' (%zu bytes), not a time in seconds)",
             sizeof garbage - 1);
    fv_assert_log_contains(want);
    assert_null(strstr(fv_test_log_text(), "no answer"));
    fv_assert_contains(dev->info.detail, "clock not synchronised");
    fv_device_close(&dev);
    fv_test_log_capture_end();

    f.t_reply = NULL;
    f.t_delay_ms = 400; /* answers after the driver's 200 ms */
    dev = open_on(&f, "?timeout_ms=200", NULL);
    fv_assert_log_contains("no clock synchronisation with Pupil time ('t' got no answer within 200 ms)");
    assert_null(strstr(fv_test_log_text(), "answered 't'"));
    fv_device_close(&dev);
    fv_test_log_capture_end();

    struct timespec ts = {0, 400 * 1000000L}; /* the fake's late answer is out */
    nanosleep(&ts, NULL);
    f.t_delay_ms = 0;
    dev = open_on(&f, "?timeout_ms=200", NULL);
    assert_null(strstr(fv_test_log_text(), "clock synchronisation"));
    fv_assert_contains(dev->info.detail, "clock synchronised");
    fv_device_close(&dev);
    fv_test_log_capture_end();
    fake_capture_stop(&f);
}

static void open_and_probe_without_capture(void **state)
{
    (void)state;
    /* a free port nobody listens on */
    fake_capture f;
    assert_int_equal(fake_capture_start(&f, 0, 0), 0);
    int port = f.remote_port;
    char env[64];
    snprintf(env, sizeof env, "127.0.0.1:%d", port);
    setenv("FOVEA_PUPIL_REMOTE", env, 1);
    fv_device_info info[4];
    size_t count = 0;
    assert_int_equal(fv_pupil_driver.probe(info, 4, &count), FV_OK);
    assert_int_equal(count, 1); /* Capture answers: listed */
    char want[64];
    snprintf(want, sizeof want, "pupil:127.0.0.1:%d", port);
    assert_string_equal(info[0].uri, want);
    fv_assert_contains(info[0].name, "Pupil Capture 3.5.fake");
    fv_assert_contains(info[0].detail, "SUB port");
    assert_string_equal(info[0].driver, "pupil");
    fake_capture_stop(&f);

    int64_t t0 = fv_time_monotonic_ns();
    assert_int_equal(fv_pupil_driver.probe(info, 4, &count), FV_OK);
    assert_int_equal(count, 0); /* nobody answers: nothing listed, quickly */
    assert_true(fv_time_monotonic_ns() - t0 < FV_NS_PER_S);
    unsetenv("FOVEA_PUPIL_REMOTE");

    char uri[96];
    snprintf(uri, sizeof uri, "pupil:127.0.0.1:%d?timeout_ms=200", port);
    fv_device *dev = NULL;
    fv_test_log_capture_begin();
    t0 = fv_time_monotonic_ns();
    assert_int_equal(fv_pupil_driver.open(uri, NULL, &dev), FV_ERR_NOT_FOUND);
    assert_true(fv_time_monotonic_ns() - t0 < FV_NS_PER_S);
    assert_null(dev);
    fv_assert_log_contains("did not answer within 200 ms (is Pupil Capture running");
    fv_test_log_capture_end();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(uri_defaults_and_options),
        cmocka_unit_test(uri_errors_name_the_option),
        cmocka_unit_test(decode_2d_through_the_camera_model),
        cmocka_unit_test(decode_rejects_each_malformed_kind),
        cmocka_unit_test(decode_extremes_stay_finite),
        cmocka_unit_test(decode_bounds_what_it_allocates_by_the_message),
        cmocka_unit_test(open_and_probe_without_capture),
        cmocka_unit_test(live_reconnects_when_capture_restarts),
        cmocka_unit_test(live_replay_matches_recorded_reader),
        cmocka_unit_test(live_flood_of_malformed_messages_is_rate_limited),
        cmocka_unit_test(live_clock_jumps_are_rate_limited_and_resync_is_throttled),
        cmocka_unit_test(open_tells_a_garbage_answer_to_t_from_no_answer),
        cmocka_unit_test(live_oversized_frame_is_refused_before_it_is_allocated),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
