/* @brief `fovea trace`: inspect (info), convert and record gaze recordings. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "cli_interrupt.h"
#include "fv_clock.h"
#include "fv_file.h"
#include "fv_log.h"
#include "fv_trace.h"
#include "fv_app_drivers.h"

static const char *const g_usage =
    "usage: fovea trace info FILE [--format NAME] [--blinks PATH|none] [--min-confidence C] [--json] [--bench]\n"
    "       fovea trace convert IN OUT [--format NAME] [--blinks PATH|none] [--min-confidence C] [--gzip]\n"
    "       fovea trace record URI OUT --seconds S [--sim-clock] [--gzip]\n"
    "\n"
    "  info     format, duration, sample count, median interval and rate, per-eye validity, pupil range,\n"
    "           blinks and gaps; --bench also measures how many rows per second the reader parses\n"
    "  convert  rewrite any supported recording in fovea's own trace format (docs/trace-format.md)\n"
    "  record   open a gaze device by URI (trace:FILE, sim:..., hid:...) and write S seconds of it in fovea's\n"
    "           format; --sim-clock steps a simulated clock instead of waiting in real time\n"
    "\n"
    "  formats: fovea, pupil-core, pupil-cloud, sranipal, tobii-g3, pico (detected by content when not given)\n"
    "  --blinks: Pupil exports read blinks.csv beside the gaze file unless given here; 'none' reads none\n"
    "  --min-confidence: Pupil Core samples below it are invalid (default 0.6; -1 keeps all)\n";

#define CMD "trace"

typedef struct reader_opts {
    fv_trace_reader_desc desc;
    const char *blinks;
} reader_opts;

/* Common reader options; returns 1 when argv[*i] was one, 0 when not, -1 on a usage error (already printed). */
static int reader_option(int argc, char **argv, int *i, reader_opts *o, int *rc)
{
    const char *v = NULL;
    int m;
    if ((m = fv_cli_option(argc, argv, i, "--format", &v)) != 0) {
        if (m < 0) {
            *rc = fv_cli_usage_error(CMD, g_usage, "--format needs a value");
            return -1;
        }
        if (fv_trace_format_parse(v, &o->desc.format) != FV_OK) {
            *rc = fv_cli_usage_error(CMD, g_usage, "unknown format '%s'", v);
            return -1;
        }
        return 1;
    }
    if ((m = fv_cli_option(argc, argv, i, "--blinks", &v)) != 0) {
        if (m < 0) {
            *rc = fv_cli_usage_error(CMD, g_usage, "--blinks needs a value");
            return -1;
        }
        o->desc.blinks_path = strcmp(v, "none") == 0 ? "" : v;
        return 1;
    }
    if ((m = fv_cli_option(argc, argv, i, "--min-confidence", &v)) != 0) {
        double c;
        if (m < 0 || !fv_cli_parse_f64(v, -1.0, 1.0, &c)) {
            *rc = fv_cli_usage_error(CMD, g_usage, "--min-confidence needs a number in [-1, 1]");
            return -1;
        }
        o->desc.min_confidence = c == 0.0 ? -1e-9f : (float)c;
        return 1;
    }
    return 0;
}

static double pct(uint64_t a, uint64_t b) { return b ? 100.0 * (double)a / (double)b : 0.0; }

static cJSON *num_or_null(double v) { return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull(); }

/* One pass over a file: stats (when s is not NULL). Returns the reader's result. */
static fv_result scan(const char *path, const fv_trace_reader_desc *desc, fv_trace_stats *s,
                      fv_trace_reader_stats *out_rs, fv_trace_format *out_format)
{
    fv_trace_reader *r = NULL;
    FV_TRY(fv_trace_reader_create(path, desc, &r));
    fv_gaze_sample g;
    fv_result res;
    while ((res = fv_trace_reader_next(r, &g)) == FV_OK)
        if (s) fv_trace_stats_push(s, &g);
    if (out_rs) *out_rs = *fv_trace_reader_get_stats(r);
    if (out_format) *out_format = fv_trace_reader_format(r);
    fv_trace_reader_destroy(&r);
    return res == FV_END_OF_STREAM ? FV_OK : res;
}

static void print_pupil(const char *label, const fv_trace_stats *s, int e)
{
    if (isfinite(s->pupil_min_mm[e]))
        printf("%s %.2f-%.2f mm", label, (double)s->pupil_min_mm[e], (double)s->pupil_max_mm[e]);
    else
        printf("%s none", label);
}

/* "impossible_gaze": {"repaired": N, "dropped": M, "kinds": {"<kind>": {"repaired": n, "dropped": m}, ...}} */
static void validity_json(cJSON *j, const fv_gaze_validity_counts *c)
{
    cJSON *o = cJSON_AddObjectToObject(j, "impossible_gaze");
    cJSON_AddNumberToObject(o, "repaired", (double)fv_gaze_validity_total(c, true));
    cJSON_AddNumberToObject(o, "dropped", (double)fv_gaze_validity_total(c, false));
    cJSON *k = cJSON_AddObjectToObject(o, "kinds");
    static const char *const names[FV_GAZE_FAULTS] = {"point_behind_head", "backward", "divergent", "convergent",
                                                      "vertical"};
    for (int i = 0; i < FV_GAZE_FAULTS; i++) {
        cJSON *e = cJSON_AddObjectToObject(k, names[i]);
        cJSON_AddNumberToObject(e, "repaired", (double)c->repaired[i]);
        cJSON_AddNumberToObject(e, "dropped", (double)c->dropped[i]);
    }
}

static int cmd_info(int argc, char **argv)
{
    reader_opts o = {0};
    const char *file = NULL;
    bool json = false, bench = false;
    int rc = FV_EXIT_OK;
    for (int i = 2; i < argc; i++) {
        int m = reader_option(argc, argv, &i, &o, &rc);
        if (m < 0) return rc;
        if (m > 0) continue;
        if (strcmp(argv[i], "--json") == 0) json = true;
        else if (strcmp(argv[i], "--bench") == 0) bench = true;
        else if (argv[i][0] == '-' && argv[i][1]) return fv_cli_usage_error(CMD, g_usage, "unknown option '%s'", argv[i]);
        else if (!file) file = argv[i];
        else return fv_cli_usage_error(CMD, g_usage, "info takes one FILE (got '%s' too)", argv[i]);
    }
    if (!file) return fv_cli_usage_error(CMD, g_usage, "info needs a FILE");

    fv_trace_stats s;
    if (fv_trace_stats_init(&s) != FV_OK) return FV_EXIT_FAIL;
    fv_trace_reader_stats rs = {0};
    fv_trace_format fmt = FV_TRACE_FORMAT_AUTO;
    fv_result res = scan(file, &o.desc, &s, &rs, &fmt);
    if (res != FV_OK) {
        fprintf(stderr, "fovea trace: cannot read '%s' (%s)\n", file, fv_result_str(res));
        fv_trace_stats_fini(&s);
        return FV_EXIT_FAIL;
    }
    fv_trace_stats_finish(&s, rs.blink_events);

    double rows_per_s = 0, mb_per_s = 0;
    uint64_t bench_passes = 0;
    if (bench) {
        /* re-parse (no statistics) for at least 1 s and 3 passes; warnings were shown on the first pass */
        fv_log_set_level("trace", FV_LOG_LEVEL_ERROR);
        uint64_t rows = 0;
        int64_t t0 = fv_time_monotonic_ns(), t1 = t0;
        while (bench_passes < 3 || t1 - t0 < FV_NS_PER_S) {
            fv_trace_reader_stats b = {0};
            if (scan(file, &o.desc, NULL, &b, NULL) != FV_OK) break;
            rows += b.lines;
            bench_passes++;
            t1 = fv_time_monotonic_ns();
        }
        fv_log_set_level("trace", FV_LOG_LEVEL_WARN);
        double secs = (double)(t1 - t0) / 1e9;
        if (secs > 0) rows_per_s = (double)rows / secs;
        int fd; /* the size through fv_file: a FIFO is not opened again (that open would wait for a new writer) */
        uint64_t size;
        char why[FV_FILE_ERR_MAX];
        if (secs > 0 && fv_file_open(file, NULL, UINT64_MAX, &fd, &size, why, sizeof why) == FV_OK) {
            close(fd);
            mb_per_s = (double)size * (double)bench_passes / secs / 1e6;
        }
    }

    double dur_s = ((double)s.t_last_ns - (double)s.t_first_ns) / 1e9; /* no int64 overflow on hostile files */
    if (json) {
        cJSON *j = cJSON_CreateObject();
        fv_cli_json_add_string(j, "file", file);
        fv_cli_json_add_string(j, "format", fv_trace_format_name(fmt));
        cJSON_AddNumberToObject(j, "samples", (double)s.samples);
        cJSON_AddNumberToObject(j, "invalid", (double)s.invalid);
        cJSON_AddNumberToObject(j, "duration_s", dur_s);
        cJSON_AddNumberToObject(j, "median_interval_ms", (double)s.median_dt_ns / 1e6);
        cJSON_AddNumberToObject(j, "max_interval_ms", (double)s.max_dt_ns / 1e6);
        cJSON_AddNumberToObject(j, "rate_hz", s.rate_hz);
        cJSON *v = cJSON_AddObjectToObject(j, "validity_pct");
        cJSON_AddItemToObject(v, "left", s.eye_present[0] ? cJSON_CreateNumber(pct(s.eye_valid[0], s.samples))
                                                          : cJSON_CreateNull());
        cJSON_AddItemToObject(v, "right", s.eye_present[1] ? cJSON_CreateNumber(pct(s.eye_valid[1], s.samples))
                                                           : cJSON_CreateNull());
        cJSON_AddNumberToObject(v, "combined", pct(s.combined_valid, s.samples));
        cJSON_AddNumberToObject(v, "any", pct(s.samples - s.invalid, s.samples));
        cJSON *p = cJSON_AddObjectToObject(j, "pupil_mm");
        for (int e = 0; e < 2; e++) {
            cJSON *a = cJSON_CreateArray();
            cJSON_AddItemToArray(a, num_or_null(s.pupil_min_mm[e]));
            cJSON_AddItemToArray(a, num_or_null(s.pupil_max_mm[e]));
            cJSON_AddItemToObject(p, e == 0 ? "left" : "right", a);
        }
        cJSON *b = cJSON_AddObjectToObject(j, "blinks");
        cJSON_AddNumberToObject(b, "count", (double)s.blinks);
        cJSON_AddNumberToObject(b, "total_s", (double)s.blink_total_ns / 1e9);
        cJSON_AddNumberToObject(b, "samples", (double)s.blink_samples);
        cJSON *g = cJSON_AddObjectToObject(j, "gaps");
        cJSON_AddNumberToObject(g, "count", (double)s.gaps);
        cJSON_AddNumberToObject(g, "total_s", (double)s.gap_total_ns / 1e9);
        cJSON_AddNumberToObject(g, "invalid_runs", (double)s.invalid_runs);
        cJSON_AddNumberToObject(j, "lines", (double)rs.lines);
        cJSON_AddNumberToObject(j, "rows_skipped", (double)rs.rows_skipped);
        validity_json(j, &rs.validity);
        if (bench) {
            cJSON *bj = cJSON_AddObjectToObject(j, "bench");
            cJSON_AddNumberToObject(bj, "passes", (double)bench_passes);
            cJSON_AddNumberToObject(bj, "rows_per_s", rows_per_s);
            cJSON_AddNumberToObject(bj, "mb_per_s", mb_per_s);
        }
        if (fv_cli_json_print(j, true) != FV_EXIT_OK) rc = FV_EXIT_FAIL;
        cJSON_Delete(j);
    } else {
        printf("file       %s\n", file);
        printf("format     %s\n", fv_trace_format_name(fmt));
        printf("samples    %llu (%llu invalid, %.1f %%)\n", (unsigned long long)s.samples,
               (unsigned long long)s.invalid, pct(s.invalid, s.samples));
        printf("duration   %.3f s\n", dur_s);
        printf("interval   median %.3f ms, max %.3f ms; rate %.1f Hz\n", (double)s.median_dt_ns / 1e6,
               (double)s.max_dt_ns / 1e6, s.rate_hz);
        printf("validity   ");
        for (int e = 0; e < 2; e++) {
            if (s.eye_present[e]) printf("%s %.1f %%, ", e ? "right" : "left", pct(s.eye_valid[e], s.samples));
            else printf("%s -, ", e ? "right" : "left");
        }
        printf("combined %.1f %%\n", pct(s.combined_valid, s.samples));
        printf("pupil      ");
        print_pupil("left", &s, 0);
        print_pupil(", right", &s, 1);
        printf("\n");
        printf("blinks     %llu, %.3f s in all (%llu samples)\n", (unsigned long long)s.blinks,
               (double)s.blink_total_ns / 1e9, (unsigned long long)s.blink_samples);
        printf("gaps       %llu longer than 3x the median, %.3f s in all; %llu runs of invalid samples\n",
               (unsigned long long)s.gaps, (double)s.gap_total_ns / 1e9, (unsigned long long)s.invalid_runs);
        printf("bad rows   %llu skipped of %llu lines\n", (unsigned long long)rs.rows_skipped,
               (unsigned long long)rs.lines);
        char why[320];
        fv_gaze_validity_describe(&rs.validity, why, sizeof why);
        printf("impossible %s\n", why);
        if (bench)
            printf("bench      %.0f rows/s (%.1f MB/s of file), %llu passes\n", rows_per_s, mb_per_s,
                   (unsigned long long)bench_passes);
    }
    fv_trace_stats_fini(&s);
    return rc;
}

static int cmd_convert(int argc, char **argv)
{
    reader_opts o = {0};
    const char *in = NULL, *out = NULL;
    int gzip = 0, rc = FV_EXIT_OK;
    for (int i = 2; i < argc; i++) {
        int m = reader_option(argc, argv, &i, &o, &rc);
        if (m < 0) return rc;
        if (m > 0) continue;
        if (strcmp(argv[i], "--gzip") == 0) gzip = 1;
        else if (argv[i][0] == '-' && argv[i][1]) return fv_cli_usage_error(CMD, g_usage, "unknown option '%s'", argv[i]);
        else if (!in) in = argv[i];
        else if (!out) out = argv[i];
        else return fv_cli_usage_error(CMD, g_usage, "convert takes IN and OUT (got '%s' too)", argv[i]);
    }
    if (!in || !out) return fv_cli_usage_error(CMD, g_usage, "convert needs IN and OUT");

    fv_trace_reader *r = NULL;
    fv_trace_writer *w = NULL;
    fv_result res = fv_trace_reader_create(in, &o.desc, &r);
    if (res != FV_OK) goto fail;
    char src[1100];
    snprintf(src, sizeof src, "%s (%s)", in, fv_trace_format_name(fv_trace_reader_format(r)));
    fv_trace_writer_desc wd = {.source = src, .gzip = gzip};
    res = fv_trace_writer_create(out, &wd, &w);
    if (res != FV_OK) goto fail;
    fv_gaze_sample g;
    uint64_t n = 0;
    while ((res = fv_trace_reader_next(r, &g)) == FV_OK) {
        res = fv_trace_writer_write(w, &g);
        if (res != FV_OK) goto fail;
        n++;
    }
    if (res != FV_END_OF_STREAM) goto fail;
    res = fv_trace_writer_finish(&w);
    if (res != FV_OK) goto fail;
    printf("wrote %llu samples from %s to %s (fovea-trace 1); %llu bad rows skipped\n", (unsigned long long)n, src,
           out, (unsigned long long)fv_trace_reader_get_stats(r)->rows_skipped);
    fv_trace_reader_destroy(&r);
    return FV_EXIT_OK;
fail:
    fprintf(stderr, "fovea trace: convert '%s' -> '%s' failed (%s)\n", in, out, fv_result_str(res));
    fv_trace_writer_destroy(&w);
    fv_trace_reader_destroy(&r);
    return FV_EXIT_FAIL;
}

/* Why a tracker could not be opened, in words (the result's name follows). */
static const char *open_failure(fv_result r)
{
    switch (r) {
    case FV_ERR_NOT_FOUND: return "nothing answered there: FV_ERR_NOT_FOUND";
    case FV_ERR_INVALID_ARG: return "the URI is not understood: FV_ERR_INVALID_ARG";
    case FV_ERR_PARSE: return "the URI is not understood: FV_ERR_PARSE";
    case FV_ERR_UNSUPPORTED: return "this build has no driver for it: FV_ERR_UNSUPPORTED";
    case FV_ERR_IO: return "the system refused the connection or file: FV_ERR_IO";
    case FV_ERR_PROTOCOL: return "it answered, but not in its protocol: FV_ERR_PROTOCOL";
    default: return fv_result_str(r);
    }
}

static int cmd_record(int argc, char **argv)
{
    const char *uri = NULL, *out = NULL, *v = NULL;
    double seconds = -1;
    bool sim = false;
    int gzip = 0;
    for (int i = 2; i < argc; i++) {
        int m = fv_cli_option(argc, argv, &i, "--seconds", &v);
        if (m != 0) {
            if (m < 0 || !fv_cli_parse_f64(v, 0.001, 86400.0, &seconds))
                return fv_cli_usage_error(CMD, g_usage, "--seconds needs a number in [0.001, 86400]");
            continue;
        }
        if (strcmp(argv[i], "--sim-clock") == 0) sim = true;
        else if (strcmp(argv[i], "--gzip") == 0) gzip = 1;
        else if (argv[i][0] == '-' && argv[i][1]) return fv_cli_usage_error(CMD, g_usage, "unknown option '%s'", argv[i]);
        else if (!uri) uri = argv[i];
        else if (!out) out = argv[i];
        else return fv_cli_usage_error(CMD, g_usage, "record takes URI and OUT (got '%s' too)", argv[i]);
    }
    if (!uri || !out) return fv_cli_usage_error(CMD, g_usage, "record needs URI and OUT");
    if (seconds < 0) return fv_cli_usage_error(CMD, g_usage, "record needs --seconds S");

    fv_clock simclock;
    fv_clock_sim_init(&simclock, 0);
    const fv_clock *clock = sim ? &simclock : fv_clock_monotonic();
    fv_device_open_desc od = {.clock = clock};
    fv_device *dev = NULL;
    fv_trace_writer *w = NULL;
    fv_result res = fv_app_device_open(uri, &od, &dev);
    if (res != FV_OK) {
        /* The driver's log line above says what it tried; this one says what it means and what to do. */
        fprintf(stderr, "fovea trace: record: no eye tracker at '%s' (%s); nothing was recorded to '%s'. Check that the "
                "tracker (or its software: Pupil Capture with Pupil Remote for pupil:) is running and reachable, "
                "`fovea devices` lists what each driver sees, and sim: records a simulated eye\n",
                uri, open_failure(res), out);
        return FV_EXIT_FAIL;
    }
    fv_trace_writer_desc wd = {.source = uri, .rate_hz = dev->nominal_rate_hz, .gzip = gzip};
    res = fv_trace_writer_create(out, &wd, &w);
    if (res != FV_OK) {
        fprintf(stderr, "fovea trace: record: cannot create '%s' (%s); nothing was recorded\n", out,
                fv_result_str(res));
        fv_device_close(&dev);
        return FV_EXIT_FAIL;
    }
    /* Ctrl-C (caught from main's first line: cli_interrupt.h) ends the recording early and keeps what was recorded
     * (a whole file, exit 130) */
    int64_t t0 = fv_clock_now_ns(clock), end = t0 + (int64_t)llround(seconds * 1e9);
    fv_gaze_sample buf[256];
    uint64_t n = 0;
    bool finished = false;
    while (!finished && fv_clock_now_ns(clock) < end && !fv_cli_interrupted()) {
        size_t cnt = 0;
        int64_t left_ms = (end - fv_clock_now_ns(clock)) / FV_NS_PER_MS;
        res = fv_device_read(dev, buf, sizeof buf / sizeof buf[0], &cnt, (int)(left_ms < 100 ? left_ms + 1 : 100));
        if (res == FV_END_OF_STREAM) {
            finished = true;
            res = FV_OK;
        } else if (res == FV_TIMEOUT) {
            res = FV_OK;
        } else if (res != FV_OK) {
            goto fail;
        }
        for (size_t k = 0; k < cnt; k++) {
            if (buf[k].t_host_ns >= end && (buf[k].flags & FV_GAZE_HOST_TIME_VALID)) {
                finished = true;
                break;
            }
            res = fv_trace_writer_write(w, &buf[k]);
            if (res != FV_OK) goto fail;
            n++;
        }
    }
    res = fv_trace_writer_finish(&w);
    if (res != FV_OK) goto fail;
    bool interrupted = fv_cli_interrupted();
    printf("recorded %llu samples from %s to %s in %.3f s%s%s\n", (unsigned long long)n, uri, out,
           (double)(fv_clock_now_ns(clock) - t0) / 1e9, sim ? " (simulated clock)" : "",
           interrupted ? " (interrupted by Ctrl-C)" : "");
    fv_device_close(&dev);
    return interrupted ? FV_EXIT_INTERRUPTED : FV_EXIT_OK;
fail:
    fprintf(stderr, "fovea trace: record '%s' -> '%s' failed (%s)\n", uri, out, fv_result_str(res));
    fv_trace_writer_destroy(&w);
    fv_device_close(&dev);
    return FV_EXIT_FAIL;
}

int fv_cmd_trace(int argc, char **argv)
{
    if (argc < 2) return fv_cli_usage_error(CMD, g_usage, "needs a subcommand (info, convert, record)");
    const char *sub = argv[1];
    if (fv_cli_is_help(sub) || strcmp(sub, "help") == 0) {
        fputs(g_usage, stdout);
        return FV_EXIT_OK;
    }
    for (int i = 2; i < argc; i++)
        if (fv_cli_is_help(argv[i])) {
            fputs(g_usage, stdout);
            return FV_EXIT_OK;
        }
    if (strcmp(sub, "info") == 0) return cmd_info(argc, argv);
    if (strcmp(sub, "convert") == 0) return cmd_convert(argc, argv);
    if (strcmp(sub, "record") == 0) return cmd_record(argc, argv);
    return fv_cli_usage_error(CMD, g_usage, "unknown subcommand '%s' (info, convert, record)", sub);
}
