/* @brief Hostile input and overload for drivers/trace (issue 13): timestamps at both ends of int64 replayed without
 * overflow, endless input (devices, FIFOs without newlines, floods of bad or empty lines) refused or given up on in
 * bounded time, and an isolated outlier in time skipped in every format while the recording plays on. */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "fv_clock.h"
#include "fv_test.h"
#include "fv_trace.h"
#include "fv_trace_driver.h"
#include "trace_test.h"

#define MS FV_NS_PER_MS
#define CLOUD_HEADER                                                                                                   \
    "section id,recording id,timestamp [ns],gaze x [px],gaze y [px],worn,fixation id,blink id,azimuth [deg],"         \
    "elevation [deg]\n"

/* ------------------------------------------------------------------ helpers */

typedef struct text {
    char *p;
    size_t len, cap;
} text;

static void put(text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(text *t, const char *fmt, ...)
{
    va_list ap;
    for (;;) {
        va_start(ap, fmt);
        int n = vsnprintf(t->p ? t->p + t->len : NULL, t->p ? t->cap - t->len : 0, fmt, ap);
        va_end(ap);
        assert_true(n >= 0);
        if (t->p && t->len + (size_t)n < t->cap) {
            t->len += (size_t)n;
            return;
        }
        t->cap = (t->cap + (size_t)n + 1) * 2;
        t->p = realloc(t->p, t->cap);
        assert_non_null(t->p);
    }
}

static void put_bytes(text *t, int c, size_t n)
{
    if (t->len + n + 1 > t->cap) {
        t->cap = t->len + n + 1;
        t->p = realloc(t->p, t->cap);
        assert_non_null(t->p);
    }
    memset(t->p + t->len, c, n);
    t->len += n;
    t->p[t->len] = '\0';
}

static void cloud_row(text *t, int64_t ts) { put(t, "s,r,%lld,484.3,525.1,1,,,-6.12,1.44\n", (long long)ts); }

typedef struct read_all {
    uint64_t n, rows_skipped;
    fv_trace_stats st;
    int64_t first_ns, last_ns;
    fv_result end;
} read_all;

/* Every sample of a reader (first pass), checking that time never goes back; stats as `fovea trace info` does. */
static void read_everything(const char *path, const fv_trace_reader_desc *desc, read_all *out)
{
    memset(out, 0, sizeof *out);
    fv_trace_reader *r = NULL;
    assert_int_equal(fv_trace_reader_create(path, desc, &r), FV_OK);
    assert_int_equal(fv_trace_stats_init(&out->st), FV_OK);
    fv_gaze_sample s;
    int64_t prev = INT64_MIN;
    while ((out->end = fv_trace_reader_next(r, &s)) == FV_OK) {
        assert_true(s.t_device_ns >= prev);
        prev = s.t_device_ns;
        if (out->n == 0) out->first_ns = s.t_device_ns;
        out->last_ns = s.t_device_ns;
        out->n++;
        fv_trace_stats_push(&out->st, &s);
    }
    fv_trace_stats_finish(&out->st, fv_trace_reader_get_stats(r)->blink_events);
    out->rows_skipped = fv_trace_reader_get_stats(r)->rows_skipped;
    fv_trace_reader_destroy(&r);
}

/* read_everything on text in memory (no blinks), with the log captured for the asserts that follow. */
static void read_logged(const text *t, const char *name, read_all *out)
{
    fv_trace_reader_desc d = {.data = t->p, .size = t->len, .name = name, .blinks_path = ""};
    fv_test_log_capture_begin();
    read_everything(NULL, &d, out);
    fv_test_log_capture_end();
}

/* ------------------------------------------------------------------ 1. signed overflow in replay */

static void timestamps_at_both_ends_of_int64_replay_without_overflow(void **state)
{
    (void)state;
    text t = {0};
    put(&t, CLOUD_HEADER);
    cloud_row(&t, INT64_MIN + 1);
    cloud_row(&t, INT64_MAX - 1);
    const char *path = fv_test_write_file("int64_ends.csv", t.p, t.len);

    /* the reader gives both rows, and the statistics stay finite */
    fv_trace_reader_desc rd = {.blinks_path = ""};
    read_all a;
    read_everything(path, &rd, &a);
    assert_int_equal(a.n, 2);
    assert_int_equal(a.end, FV_END_OF_STREAM);
    assert_true(isfinite(a.st.rate_hz) && a.st.rate_hz >= 0.0);
    assert_true(a.st.median_dt_ns >= 0 && a.st.max_dt_ns == INT64_MAX);
    fv_trace_stats_fini(&a.st);

    /* replay on a simulated clock: the first sample now, the second due at the end of time (saturated) */
    fv_clock clock;
    const int64_t t0 = 7 * FV_NS_PER_S;
    fv_clock_sim_init(&clock, t0);
    fv_device *dev = trace_test_open_uri("trace:%s?blinks=none", path, &clock);
    assert_true(isfinite(dev->nominal_rate_hz) && dev->nominal_rate_hz > 0.0);
    fv_gaze_sample buf[8];
    size_t n = 0;
    assert_int_equal(fv_device_read(dev, buf, 8, &n, 0), FV_OK);
    assert_int_equal(n, 1);
    assert_int_equal(buf[0].t_host_ns, t0);
    assert_int_equal(buf[0].t_device_ns, INT64_MIN + 1);
    assert_int_equal(fv_device_read(dev, buf, 8, &n, 1000), FV_TIMEOUT);
    assert_int_equal(clock.sim_now_ns, t0 + 1000 * MS);
    clock.sleep_until_ns(&clock, INT64_MAX);
    assert_int_equal(fv_device_read(dev, buf, 8, &n, 1000), FV_OK); /* now + timeout saturates too */
    assert_int_equal(n, 1);
    assert_int_equal(buf[0].t_host_ns, INT64_MAX);
    assert_int_equal(buf[0].t_device_ns, INT64_MAX - 1);
    assert_int_equal(fv_device_read(dev, buf, 8, &n, 1000), FV_END_OF_STREAM);
    fv_device_close(&dev);

    /* slow, fast and looped replays of the same file: bounded reads, time never goes back */
    static const char *const uris[] = {"trace:%s?blinks=none&speed=0.001", "trace:%s?blinks=none&speed=1000",
                                       "trace:%s?blinks=none&loop=1", "trace:%s?blinks=none&loop=1&speed=0.5"};
    for (size_t u = 0; u < sizeof uris / sizeof uris[0]; u++) {
        fv_clock_sim_init(&clock, INT64_MIN + 5);
        dev = trace_test_open_uri(uris[u], path, &clock);
        int64_t prev_dev = INT64_MIN, prev_host = INT64_MIN;
        uint64_t got = 0;
        for (int i = 0; i < 40; i++) {
            if (i == 3) clock.sleep_until_ns(&clock, INT64_MAX);
            fv_result r = fv_device_read(dev, buf, 4, &n, i % 2 ? 1000 : 0);
            if (r == FV_END_OF_STREAM) break;
            assert_true(r == FV_OK || r == FV_TIMEOUT);
            for (size_t k = 0; k < n; k++) {
                assert_true(buf[k].t_device_ns >= prev_dev && buf[k].t_host_ns >= prev_host);
                assert_true(buf[k].t_host_ns <= clock.sim_now_ns);
                prev_dev = buf[k].t_device_ns;
                prev_host = buf[k].t_host_ns;
            }
            got += n;
        }
        assert_true(got >= 2); /* both samples of the file come out, looped or not */
        fv_device_close(&dev);
    }
    free(t.p);
}

/* ------------------------------------------------------------------ 2. endless input */

static void devices_and_directories_are_refused_like_the_scene_loader(void **state)
{
    (void)state;
    fv_trace_reader *r = NULL;
    fv_test_log_capture_begin();
    assert_int_equal(fv_trace_reader_create("/dev/zero", NULL, &r), FV_ERR_IO);
    assert_null(r);
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", fv_test_tmp("a_directory"));
    assert_true(mkdir(dir, 0700) == 0 || errno == EEXIST);
    assert_int_equal(fv_trace_reader_create(dir, NULL, &r), FV_ERR_IO);
    fv_device *dev = NULL;
    fv_device_open_desc d = {0};
    assert_int_not_equal(fv_trace_driver.open("trace:/dev/zero", &d, &dev), FV_OK);
    assert_null(dev);
    fv_test_log_capture_end();
    fv_assert_log_contains("/dev/zero: not a regular file or a FIFO");
    char want[1100];
    snprintf(want, sizeof want, "%s: not a regular file or a FIFO", dir);
    fv_assert_log_contains(want);
}

/* A FIFO fed by a thread: `head` once, then `body` (len bytes) again and again until the reader goes away. */
typedef struct feeder {
    char path[1024];
    const char *head, *body;
    size_t body_len;
    pthread_t thread;
} feeder;

static void *feed(void *arg)
{
    feeder *f = arg;
    int fd = open(f->path, O_WRONLY);
    if (fd < 0) return NULL;
    size_t hl = strlen(f->head);
    if (hl && write(fd, f->head, hl) != (ssize_t)hl) goto out;
    for (;;) /* ends with EPIPE once the reader closes */
        if (write(fd, f->body, f->body_len) < 0) break;
out:
    close(fd);
    return NULL;
}

static void feeder_start(feeder *f, const char *name, const char *head, const char *body, size_t body_len)
{
    snprintf(f->path, sizeof f->path, "%s", fv_test_tmp(name));
    unlink(f->path);
    assert_int_equal(mkfifo(f->path, 0600), 0);
    f->head = head;
    f->body = body;
    f->body_len = body_len;
    assert_int_equal(pthread_create(&f->thread, NULL, feed, f), 0);
}

static void feeder_join(feeder *f)
{
    pthread_join(f->thread, NULL); /* the reader has closed the FIFO: the writer's next write fails (EPIPE) */
    unlink(f->path);
}

static void endless_fifos_end_with_a_clear_error_in_bounded_time(void **state)
{
    (void)state;
    signal(SIGPIPE, SIG_IGN);
    static char zeros[65536];
    static const char ys[] = "y\ny\ny\ny\ny\ny\ny\ny\n";
    static const char back[] = "s,r,1,484.3,525.1,1,,,-6.12,1.44\n";
    struct {
        const char *name, *head, *body;
        size_t body_len;
        fv_result at_create;
        const char *msg;
    } cases[] = {
        /* /dev/zero through a pipe: no newline ever */
        {"zeros.fifo", "", zeros, sizeof zeros, FV_ERR_PARSE, "header line longer than 1048576 bytes"},
        {"hdr_zeros.fifo", CLOUD_HEADER, zeros, sizeof zeros, FV_OK, "MiB read without a sample; giving up"},
        /* `yes` into a FIFO: endless lines that are no rows */
        {"yes.fifo", CLOUD_HEADER, ys, sizeof ys - 1, FV_OK, "MiB read without a sample; giving up"},
        /* endless rows that all go back in time */
        {"back.fifo",
         CLOUD_HEADER "s,r,100000000,484.3,525.1,1,,,-6.12,1.44\n"
                      "s,r,105000000,484.3,525.1,1,,,-6.12,1.44\n",
         back, sizeof back - 1, FV_OK, "MiB read without a sample; giving up"},
        /* endless empty lines before any header */
        {"empty.fifo", "", "\n\n\n\n\n\n\n\n", 8, FV_ERR_PARSE, "empty lines and no header line"},
        /* endless metadata in fovea's format */
        {"meta.fifo", "fovea-trace 1\n", "# k: v\n", 7, FV_ERR_PARSE, "no column header line in the first"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        feeder f;
        feeder_start(&f, cases[i].name, cases[i].head, cases[i].body, cases[i].body_len);
        fv_trace_reader_desc d = {.blinks_path = ""};
        fv_trace_reader *r = NULL;
        fv_test_log_capture_begin();
        fv_result res = fv_trace_reader_create(f.path, &d, &r);
        if (res != cases[i].at_create) fail_msg("%s: create gave %s", cases[i].name, fv_result_str(res));
        if (res == FV_OK) {
            fv_gaze_sample s;
            uint64_t n = 0;
            while ((res = fv_trace_reader_next(r, &s)) == FV_OK) n++;
            assert_int_equal(res, FV_ERR_PARSE);
            assert_true(n <= 2);
            fv_trace_reader_destroy(&r);
        }
        fv_test_log_capture_end();
        fv_assert_log_contains(cases[i].msg);
        feeder_join(&f);
    }
}

static void over_long_lines_are_reported_once_and_floods_are_bounded(void **state)
{
    (void)state;
    /* a 5 MiB line between good rows: one bad row, the rows around it read */
    text t = {0};
    put(&t, CLOUD_HEADER);
    cloud_row(&t, 1000 * MS);
    put_bytes(&t, '7', 5u * 1024u * 1024u);
    put(&t, "\n");
    cloud_row(&t, 1005 * MS);
    read_all a;
    read_logged(&t, "long5.csv", &a);
    assert_int_equal(a.n, 2);
    assert_int_equal(a.rows_skipped, 1);
    assert_int_equal(a.end, FV_END_OF_STREAM);
    fv_assert_log_contains("long5.csv:3: line longer than 1048576 bytes");
    fv_trace_stats_fini(&a.st);

    /* 17 MiB of blinks that all end before the first sample: the blinks end with a warning, the samples read */
    t.len = 0;
    put(&t, "start timestamp [ns],end timestamp [ns]\n");
    while (t.len < 17u * 1024u * 1024u) put(&t, "1,2\n1,2\n1,2\n1,2\n1,2\n1,2\n1,2\n1,2\n");
    text g = {0};
    put(&g, CLOUD_HEADER);
    for (int i = 0; i < 5; i++) cloud_row(&g, 1000 * MS + i * 5 * MS);
    fv_trace_reader_desc db = {.data = g.p, .size = g.len, .name = "g.csv", .blinks_data = t.p, .blinks_size = t.len};
    fv_test_log_capture_begin();
    read_everything(NULL, &db, &a);
    fv_test_log_capture_end();
    assert_int_equal(a.n, 5);
    assert_int_equal(a.end, FV_END_OF_STREAM);
    fv_assert_log_contains("without a blink interval reaching");
    fv_trace_stats_fini(&a.st);
    free(t.p);
    free(g.p);
}

/* ------------------------------------------------------------------ 3. an isolated outlier in time */

#define N_GOOD 39     /* 20 rows, the outlier, 19 rows */
#define OUTLIER_AT 20 /* index among the rows: line 22 of a file with a one-line header */

/* Row i of a 200 Hz recording; the outlier 3.3e9 s ahead. Times in the format's unit, as text. */
typedef enum unit { U_NS, U_S, U_TICKS } unit;

static void time_text(char *dst, size_t cap, unit u, double base, int i, bool outlier)
{
    double off_s = outlier ? 3.3e9 : i * 0.005;
    switch (u) {
    case U_NS: snprintf(dst, cap, "%lld", (long long)base + (long long)llround(off_s * 1e9)); break;
    case U_S: snprintf(dst, cap, "%.9f", base + off_s); break;
    case U_TICKS: snprintf(dst, cap, "%lld", (long long)base + (long long)llround(off_s * 1e7)); break;
    }
}

/* A recording in one format, built from the first data row of a real file (its time field replaced). */
typedef struct fmt_case {
    const char *name, *file;
    char sep;          /* 0: JSON lines (the time follows "timestamp":) */
    const char *col;   /* time column */
    unit u;
    double base;       /* time of row 0 */
} fmt_case;

static char *first_lines(const char *path, char *header, size_t cap, char *row)
{
    gzFile gz = gzopen(path, "rb");
    assert_non_null(gz);
    assert_non_null(gzgets(gz, header, (int)cap));
    assert_non_null(gzgets(gz, row, (int)cap));
    gzclose(gz);
    return row;
}

static const char *make_outlier_file(const fmt_case *c, const int64_t *first_row_override)
{
    static char header[65536], row[65536];
    first_lines(fv_test_data(c->file), header, sizeof header, row);
    text t = {0};
    int tcol = -1;
    if (c->sep) {
        put(&t, "%s", header);
        char *h = header;
        for (int k = 0; h; k++) {
            char *next = strchr(h, c->sep);
            size_t n = next ? (size_t)(next - h) : strcspn(h, "\r\n");
            if (n == strlen(c->col) && memcmp(h, c->col, n) == 0) tcol = k;
            h = next ? next + 1 : NULL;
        }
        assert_true(tcol >= 0);
    } else {
        snprintf(row, sizeof row, "%s", header); /* JSON lines: no header, the first line is a row */
    }
    for (int i = 0; i <= N_GOOD; i++) {
        bool outlier = i == OUTLIER_AT;
        int idx = i > OUTLIER_AT ? i - 1 : i;
        char ts[64];
        time_text(ts, sizeof ts, c->u, c->base, idx, outlier);
        if (first_row_override && i == 0) snprintf(ts, sizeof ts, "%lld", (long long)*first_row_override);
        if (c->sep) {
            char *p = row;
            for (int k = 0; k < tcol; k++) p = strchr(p, c->sep) + 1;
            char *end = p + strcspn(p, c->sep == '\t' ? "\t\r\n" : (c->sep == ';' ? ";\r\n" : ",\r\n"));
            put(&t, "%.*s%s%s", (int)(p - row), row, ts, end);
        } else {
            char *p = strstr(row, "\"timestamp\":");
            assert_non_null(p);
            p += 12;
            char *end = p + strcspn(p, ",}");
            put(&t, "%.*s%s%s", (int)(p - row), row, ts, end);
        }
    }
    char name[96];
    snprintf(name, sizeof name, "outlier_%s.txt", c->name);
    const char *path = fv_test_write_file(name, t.p, t.len);
    free(t.p);
    return path;
}

static const fmt_case g_fmts[] = {
    {"pupil_cloud", "gaze/pupil_invisible/gaze.csv", ',', "timestamp [ns]", U_NS, 1629390345036471431.0},
    {"pupil_core", "gaze/pupil_core/gaze_positions.csv", ',', "gaze_timestamp", U_S, 329367.897894},
    {"sranipal", "gaze/htc_vive_pro_eye_sranipal/TESTNA01_2D_Fist3.csv", ';', "time(100ns)", U_TICKS,
     638342794000115346.0},
    {"pico", "gaze/pico_neo3_pro/boxing_VR.tsv", '\t', "Timeline", U_S, 12.5},
    {"tobii_g3", "gaze/tobii_pro_glasses3/gazedata.gz", 0, NULL, U_S, 0.006684},
};

static void isolated_outlier_is_skipped_in_every_format_and_the_recording_plays_on(void **state)
{
    (void)state;
    for (size_t f = 0; f < sizeof g_fmts / sizeof g_fmts[0]; f++) {
        const fmt_case *c = &g_fmts[f];
        const char *path = make_outlier_file(c, NULL);
        fv_trace_reader_desc d = {.blinks_path = ""};
        fv_test_log_capture_begin();
        read_all a;
        read_everything(path, &d, &a);
        fv_test_log_capture_end();
        if (a.n != N_GOOD) fail_msg("%s: %llu samples, want %d", c->name, (unsigned long long)a.n, N_GOOD);
        assert_int_equal(a.rows_skipped, 1);
        char want[1200];
        snprintf(want, sizeof want, "%s:%d: timestamp", path, OUTLIER_AT + (c->sep ? 2 : 1));
        fv_assert_log_contains(want);
        fv_assert_log_contains("an isolated outlier in time; row skipped");
        /* rate, median and duration as if the outlier had never been there (SRanipal ticks round to 100 ns) */
        if (fabs(a.st.rate_hz - 200.0) > 0.01) fail_msg("%s: rate %g Hz", c->name, a.st.rate_hz);
        assert_true(llabs(a.st.median_dt_ns - 5 * MS) <= 10000);
        assert_true(llabs(a.st.max_dt_ns - 5 * MS) <= 1000);
        assert_true(llabs((a.last_ns - a.first_ns) - 190 * MS) <= 1000);
        fv_trace_stats_fini(&a.st);
    }
}

static void replay_plays_on_past_an_outlier(void **state)
{
    (void)state;
    const char *path = make_outlier_file(&g_fmts[0], NULL);
    fv_clock clock;
    fv_clock_sim_init(&clock, 0);
    fv_test_log_capture_begin();
    fv_device *dev = trace_test_open_uri("trace:%s?blinks=none", path, &clock);
    assert_true(fabs(dev->nominal_rate_hz - 200.0) < 1e-6);
    fv_gaze_sample s;
    size_t n;
    int got = 0;
    fv_result r;
    while ((r = fv_device_read(dev, &s, 1, &n, 100)) == FV_OK) {
        assert_int_equal(s.t_host_ns, got * 5 * MS); /* paced at 200 Hz throughout */
        got++;
    }
    fv_test_log_capture_end();
    assert_int_equal(r, FV_END_OF_STREAM);
    assert_int_equal(got, N_GOOD);
    fv_device_close(&dev);
}

static void a_far_future_first_row_is_an_outlier_too(void **state)
{
    (void)state;
    const int64_t far = INT64_C(4929390345036471431);
    /* the first row far ahead (and the usual one at line 22): both skipped */
    const char *path = make_outlier_file(&g_fmts[0], &far);
    fv_trace_reader_desc d = {.blinks_path = ""};
    fv_test_log_capture_begin();
    read_all a;
    read_everything(path, &d, &a);
    fv_test_log_capture_end();
    assert_int_equal(a.n, N_GOOD - 1);
    assert_int_equal(a.rows_skipped, 2);
    fv_assert_log_contains(":2: timestamp 4929390345036471431 ns is");
    fv_assert_log_contains("ahead of the next two rows (lines 3 and 4), which agree");
    assert_true(fabs(a.st.rate_hz - 200.0) < 0.01);
    fv_trace_stats_fini(&a.st);
}

static void a_jump_that_the_next_rows_follow_is_a_real_gap(void **state)
{
    (void)state;
    text t = {0};
    put(&t, CLOUD_HEADER);
    const int64_t t0 = INT64_C(1629390345036471431);
    for (int i = 0; i < 20; i++) cloud_row(&t, t0 + i * 5 * MS);
    for (int i = 0; i < 20; i++) cloud_row(&t, t0 + 10 * FV_NS_PER_S + i * 5 * MS); /* tracking lost 10 s */
    /* and a jump followed by a row before the previous sample: that row is the bad one, the jump is kept */
    cloud_row(&t, t0 + 100 * FV_NS_PER_S);
    cloud_row(&t, t0);
    cloud_row(&t, t0 + 100 * FV_NS_PER_S + 5 * MS);
    read_all a;
    read_logged(&t, "gap.csv", &a);
    assert_int_equal(a.n, 42);
    assert_int_equal(a.rows_skipped, 1);
    fv_assert_log_contains("gap.csv:43: timestamp 1629390345036471431 ns goes back in time");
    assert_int_equal(a.last_ns, t0 + 100 * FV_NS_PER_S + 5 * MS);
    assert_int_equal(a.st.gaps, 2);
    fv_trace_stats_fini(&a.st);
    free(t.p);
}

static void blinks_after_an_outlier_still_apply(void **state)
{
    (void)state;
    const int64_t t0 = INT64_C(1629390345036471431);
    text g = {0}, b = {0};
    put(&g, CLOUD_HEADER);
    for (int i = 0; i < 20; i++) cloud_row(&g, t0 + i * 5 * MS);
    cloud_row(&g, t0 + INT64_C(3300000000) * FV_NS_PER_S);
    for (int i = 20; i < 39; i++) cloud_row(&g, t0 + i * 5 * MS);
    put(&b, "start timestamp [ns],end timestamp [ns]\n");
    put(&b, "%lld,%lld\n", (long long)(t0 + 30 * 5 * MS), (long long)(t0 + 32 * 5 * MS)); /* 3 samples */
    fv_trace_reader_desc d = {
        .data = g.p, .size = g.len, .name = "gb.csv", .blinks_data = b.p, .blinks_size = b.len};
    fv_test_log_capture_begin();
    read_all a;
    read_everything(NULL, &d, &a);
    fv_test_log_capture_end();
    assert_int_equal(a.n, 39);
    assert_int_equal(a.st.blink_samples, 3);
    assert_int_equal(a.st.blinks, 1);
    fv_trace_stats_fini(&a.st);
    free(g.p);
    free(b.p);
}

/* `test_trace_hostile PATTERN` runs only the tests whose name matches (cmocka's filter: * and ? wildcards). */
int main(int argc, char **argv)
{
    if (argc > 1) cmocka_set_test_filter(argv[1]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(timestamps_at_both_ends_of_int64_replay_without_overflow),
        cmocka_unit_test(devices_and_directories_are_refused_like_the_scene_loader),
        cmocka_unit_test(endless_fifos_end_with_a_clear_error_in_bounded_time),
        cmocka_unit_test(over_long_lines_are_reported_once_and_floods_are_bounded),
        cmocka_unit_test(isolated_outlier_is_skipped_in_every_format_and_the_recording_plays_on),
        cmocka_unit_test(replay_plays_on_past_an_outlier),
        cmocka_unit_test(a_far_future_first_row_is_an_outlier_too),
        cmocka_unit_test(a_jump_that_the_next_rows_follow_is_a_real_gap),
        cmocka_unit_test(blinks_after_an_outlier_still_apply),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
