/* @brief The trace reader: opens a recording, detects its format by content, and hands rows to the per-format
 * parser; skips bad rows with a rate-limited warning (file:line and why); checks time (a row going back, an isolated
 * outlier far ahead: docs/trace-format.md, "Time checks") with a look-ahead of at most two rows; follows a blinks
 * file in step with the samples it hands out (both streamed). Every call does bounded work: TRACE_MAX_SKIP bytes
 * read without a result end the read with an error, so an endless input cannot stall the caller. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fv_log.h"
#include "fv_stats.h" /* saturating time arithmetic: a file can put its timestamps anywhere */
#include "trace_internal.h"

static const char *const g_names[FV_TRACE_FORMAT_COUNT_] = {
    "auto", "fovea", "pupil-core", "pupil-cloud", "sranipal", "tobii-g3", "pico",
};

const char *fv_trace_format_name(fv_trace_format f)
{
    return (f >= 0 && f < FV_TRACE_FORMAT_COUNT_) ? g_names[f] : "unknown";
}

fv_result fv_trace_format_parse(const char *name, fv_trace_format *out)
{
    if (!name) return FV_ERR_INVALID_ARG;
    for (int i = 0; i < FV_TRACE_FORMAT_COUNT_; i++)
        if (strcmp(name, g_names[i]) == 0) {
            *out = (fv_trace_format)i;
            return FV_OK;
        }
    static const struct {
        const char *alias;
        fv_trace_format f;
    } aliases[] = {{"pupil-invisible", FV_TRACE_FORMAT_PUPIL_CLOUD}, {"tobii", FV_TRACE_FORMAT_TOBII_G3},
                   {"vive", FV_TRACE_FORMAT_SRANIPAL},               {"pupil", FV_TRACE_FORMAT_PUPIL_CORE}};
    for (size_t i = 0; i < sizeof aliases / sizeof aliases[0]; i++)
        if (strcmp(name, aliases[i].alias) == 0) {
            *out = aliases[i].f;
            return FV_OK;
        }
    return FV_ERR_NOT_FOUND;
}

static const trace_format_ops *ops_of(fv_trace_format f)
{
    switch (f) {
    case FV_TRACE_FORMAT_FOVEA: return &trace_fmt_fovea;
    case FV_TRACE_FORMAT_PUPIL_CORE: return &trace_fmt_pupil_core;
    case FV_TRACE_FORMAT_PUPIL_CLOUD: return &trace_fmt_pupil_cloud;
    case FV_TRACE_FORMAT_SRANIPAL: return &trace_fmt_sranipal;
    case FV_TRACE_FORMAT_TOBII_G3: return &trace_fmt_tobii_g3;
    case FV_TRACE_FORMAT_PICO: return &trace_fmt_pico;
    default: return NULL;
    }
}

/* Printable excerpt of untrusted text for messages. */
static void excerpt(char *dst, size_t cap, const char *s, size_t len)
{
    size_t n = 0;
    for (size_t i = 0; i < len && n + 4 < cap; i++) {
        unsigned char c = (unsigned char)s[i];
        dst[n++] = (c >= 0x20 && c < 0x7f) ? (char)c : (c == '\t' ? ' ' : '?');
        if (n >= 60) {
            memcpy(dst + n, "...", 3);
            n += 3;
            break;
        }
    }
    dst[n] = '\0';
}

static bool has(const char *s, size_t len, const char *needle)
{
    size_t m = strlen(needle);
    if (m > len) return false;
    for (size_t i = 0; i + m <= len; i++)
        if (memcmp(s + i, needle, m) == 0) return true;
    return false;
}

/* What a header that is no gaze recording seems to be: the other files of the exports fovea reads. */
static const char *what_file(const char *line, size_t len)
{
    if (has(line, len, "dispersion") && has(line, len, "start_timestamp"))
        return " (this is a Pupil Player fixations export, fixations.csv: one row per fixation event, not gaze "
               "samples; read gaze_positions.csv beside it)";
    if (has(line, len, "fixation id"))
        return " (this is a Pupil Cloud fixations export: fixation events, not gaze samples; read gaze.csv beside it)";
    if (has(line, len, "saccade id"))
        return " (this is a Pupil Cloud saccades export: saccade events, not gaze samples; read gaze.csv beside it)";
    if (has(line, len, "pupil_timestamp") && has(line, len, "diameter"))
        return " (this is a Pupil Player pupil_positions.csv: pupil detections per eye camera, not gaze; read "
               "gaze_positions.csv beside it)";
    if (has(line, len, "gyro x"))
        return " (this is an IMU export: head motion, not gaze; read gaze.csv beside it)";
    if (has(line, len, "start_timestamp") || has(line, len, "blink id"))
        return " (this looks like a blinks file: open the gaze file beside it)";
    return "";
}

fv_result fv_trace_detect(const char *line, size_t len, fv_trace_format *out)
{
    const char *s = line;
    if (len >= 3 && (unsigned char)s[0] == 0xEF && (unsigned char)s[1] == 0xBB && (unsigned char)s[2] == 0xBF) {
        s += 3;
        len -= 3;
    }
    while (len > 0 && (*s == ' ' || *s == '\t')) {
        s++;
        len--;
    }
    if (len >= 11 && memcmp(s, "fovea-trace", 11) == 0) *out = FV_TRACE_FORMAT_FOVEA;
    else if (len > 0 && s[0] == '{' && (has(s, len, "\"timestamp\"") || has(s, len, "\"type\"")))
        *out = FV_TRACE_FORMAT_TOBII_G3;
    else if (has(s, len, "gaze_timestamp") && has(s, len, "norm_pos_x")) *out = FV_TRACE_FORMAT_PUPIL_CORE;
    else if (has(s, len, "timestamp [ns]") && has(s, len, "gaze x [px]")) *out = FV_TRACE_FORMAT_PUPIL_CLOUD;
    else if (has(s, len, ";") && (has(s, len, "time(100ns)") || has(s, len, "eye_valid_L")))
        *out = FV_TRACE_FORMAT_SRANIPAL;
    else if (has(s, len, "\t") && has(s, len, "Combine Eye Gaze Vector")) *out = FV_TRACE_FORMAT_PICO;
    else return FV_ERR_PARSE;
    return FV_OK;
}

void trace_why(fv_trace_reader *r, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->why, sizeof r->why, fmt, ap);
    va_end(ap);
}

fv_result trace_split_row(fv_trace_reader *r, char *line, char sep, int *out_n)
{
    int n = trace_csv_split(line, sep, r->fields, TRACE_MAX_FIELDS);
    *out_n = n;
    if (n < 0) {
        trace_why(r, "unterminated quoted field");
        return FV_ERR_PARSE;
    }
    if (n < r->ncols_needed) {
        trace_why(r, "%d fields, the header needs at least %d", n, r->ncols_needed);
        return FV_ERR_PARSE;
    }
    return FV_OK;
}

static void bad_row_in(fv_trace_reader *r, const char *name, uint64_t line_no, const char *why)
{
    if (r->pass != 0) return; /* reported on the first pass already */
    r->stats.rows_skipped++;
    if (r->stats.rows_skipped <= r->max_warnings)
        FV_WARN(TRACE_MOD, "%s:%llu: %s; row skipped%s", name, (unsigned long long)line_no, why,
                r->stats.rows_skipped == r->max_warnings ? " (further bad rows are counted, not reported)" : "");
}

void trace_reader_bad_row(fv_trace_reader *r, uint64_t line_no, const char *why)
{
    bad_row_in(r, r->name, line_no, why);
}

fv_result trace_require_col(fv_trace_reader *r, char *const *fields, int n, int slot, const char *name)
{
    int i = trace_csv_find(fields, n, name);
    if (i < 0) {
        FV_ERROR(TRACE_MOD, "%s:%llu: missing required column '%s' (%s format)", r->name,
                 (unsigned long long)r->lines.line_no, name, fv_trace_format_name(r->ops->format));
        return FV_ERR_PARSE;
    }
    r->col[slot] = i;
    if (i + 1 > r->ncols_needed) r->ncols_needed = i + 1;
    return FV_OK;
}

void trace_optional_col(fv_trace_reader *r, char *const *fields, int n, int slot, const char *name)
{
    r->col[slot] = trace_csv_find(fields, n, name);
}

const char *trace_col(const fv_trace_reader *r, int nfields, int slot)
{
    int i = r->col[slot];
    return (i >= 0 && i < nfields) ? r->fields[i] : NULL;
}

/* ---- blinks file ---- */

static fv_result blinks_header(fv_trace_reader *r, const char *start_col, const char *end_col)
{
    blink_cursor *c = &r->blinks;
    char *line;
    size_t len;
    bool too_long;
    int rc = trace_lines_next(&c->lines, &line, &len, &too_long);
    if (rc < 0) {
        FV_ERROR(TRACE_MOD, "%s: %s", c->lines.name, c->lines.err);
        return FV_ERR_IO;
    }
    if (rc == 0) { /* an empty blinks file: no blinks */
        c->done = true;
        return FV_OK;
    }
    char *fields[64];
    int n = trace_csv_split(line, ',', fields, 64);
    if (n < 0) n = 0;
    c->col_start = trace_csv_find(fields, n, start_col);
    c->col_end = trace_csv_find(fields, n, end_col);
    const char *missing = c->col_start < 0 ? start_col : (c->col_end < 0 ? end_col : NULL);
    if (missing) {
        FV_ERROR(TRACE_MOD, "%s:1: missing required column '%s' (blinks file of %s)", c->lines.name, missing,
                 r->name);
        return FV_ERR_PARSE;
    }
    return FV_OK;
}

fv_result trace_blinks_open(fv_trace_reader *r, const char *start_col, const char *end_col, double scale_to_ns)
{
    blink_cursor *c = &r->blinks;
    c->scale_to_ns = scale_to_ns;
    fv_result res;
    if (r->desc.blinks_data) {
        char nm[600];
        snprintf(nm, sizeof nm, "%s (blinks)", r->name);
        res = trace_lines_open_mem(&c->lines, r->desc.blinks_data, r->desc.blinks_size, nm);
    } else {
        char path[1024];
        if (r->desc.blinks_path) {
            if (!r->desc.blinks_path[0]) return FV_OK; /* explicitly none */
            snprintf(path, sizeof path, "%s", r->desc.blinks_path);
        } else {
            if (r->desc.data) return FV_OK; /* memory input without a blinks buffer */
            const char *slash = strrchr(r->name, '/');
            if (slash)
                snprintf(path, sizeof path, "%.*s/blinks.csv", (int)(slash - r->name), r->name);
            else
                snprintf(path, sizeof path, "blinks.csv");
            if (access(path, R_OK) != 0) {
                FV_INFO(TRACE_MOD, "%s: no %s beside it; blinks come from the gaze rows only", r->name, path);
                return FV_OK;
            }
        }
        res = trace_lines_open_file(&c->lines, path, NULL);
    }
    if (res != FV_OK) return res;
    c->active = true;
    return blinks_header(r, start_col, end_col);
}

/* 1-based index of the blink interval covering t (0 = none). Advances the cursor; blinks must be sorted by start.
 * At most TRACE_MAX_SKIP bytes are read in one call: more than that without reaching t ends the blinks, with a
 * warning (a blinks file has one short row per blink). */
static uint64_t blinks_at(fv_trace_reader *r, int64_t t_ns)
{
    blink_cursor *c = &r->blinks;
    if (!c->active) return 0;
    const uint64_t start = c->lines.bytes;
    for (;;) {
        if (c->have && t_ns <= c->end_ns) return t_ns >= c->start_ns ? c->index : 0;
        if (c->done) return 0;
        if (c->lines.bytes - start > TRACE_MAX_SKIP) {
            if (r->pass == 0)
                FV_WARN(TRACE_MOD, "%s:%llu: %u MiB read without a blink interval reaching %lld ns; no further blinks",
                        c->lines.name, (unsigned long long)c->lines.line_no, TRACE_MAX_SKIP >> 20, (long long)t_ns);
            c->done = true;
            c->have = false;
            return 0;
        }
        char *line;
        size_t len;
        bool too_long;
        int rc = trace_lines_next(&c->lines, &line, &len, &too_long);
        if (rc <= 0) {
            if (rc < 0 && r->pass == 0) FV_WARN(TRACE_MOD, "%s: %s; no further blinks", c->lines.name, c->lines.err);
            c->done = true;
            c->have = false;
            return 0;
        }
        if (too_long && c->lines.line_no == c->long_line_no) continue; /* the rest of a line already reported */
        if (too_long) c->long_line_no = c->lines.line_no;
        if (len == 0 && !too_long) continue;
        char *f[64];
        int n = too_long ? -1 : trace_csv_split(line, ',', f, 64);
        int64_t t[2] = {0, 0};
        int need = (c->col_start > c->col_end ? c->col_start : c->col_end) + 1;
        const char *why = NULL;
        if (n < need) why = too_long ? "line too long" : "too few fields";
        for (int k = 0; k < 2 && !why; k++) {
            const char *fld = f[k == 0 ? c->col_start : c->col_end];
            double v;
            /* integer ns are taken exactly (a double holds Unix-epoch ns only to ~256 ns) */
            if (c->scale_to_ns == 1.0 && trace_parse_i64(fld, &t[k])) continue;
            if (!trace_parse_f64(fld, &v)) why = k == 0 ? "start time is not a number" : "end time is not a number";
            else if (!((v *= c->scale_to_ns) > -9.2e18 && v < 9.2e18)) why = "time out of range";
            else t[k] = llround(v);
        }
        if (!why && t[1] < t[0]) why = "blink ends before it starts";
        if (why) {
            bad_row_in(r, c->lines.name, c->lines.line_no, why);
            continue;
        }
        c->start_ns = t[0];
        c->end_ns = t[1];
        c->have = true;
        c->index++;
    }
}

static void blinks_rewind(fv_trace_reader *r)
{
    blink_cursor *c = &r->blinks;
    if (!c->active) return;
    c->have = false;
    c->done = false;
    c->index = 0;
    c->long_line_no = 0;
    char *line;
    size_t len;
    if (trace_lines_rewind(&c->lines) != FV_OK || trace_lines_next(&c->lines, &line, &len, NULL) <= 0) c->done = true;
}

void trace_count_blink_event(fv_trace_reader *r, uint64_t id) { r->row_blink_id = id; }

/* ---- reader ---- */

fv_result fv_trace_reader_create(const char *path, const fv_trace_reader_desc *desc, fv_trace_reader **out_reader)
{
    static const fv_trace_reader_desc zero;
    if (!out_reader || (!path && !(desc && desc->data))) return FV_ERR_INVALID_ARG;
    *out_reader = NULL;
    if (!desc) desc = &zero;
    fv_result res = FV_OK;
    fv_trace_reader *r = calloc(1, sizeof *r);
    if (!r) return FV_ERR_NO_MEMORY;
    r->desc = *desc;
    r->max_warnings = desc->max_warnings ? desc->max_warnings : 10;
    r->min_confidence = desc->min_confidence == 0.0f ? 0.6f : desc->min_confidence;
    for (int i = 0; i < TRACE_MAX_COLS; i++) r->col[i] = -1;
    snprintf(r->name, sizeof r->name, "%s", desc->name ? desc->name : (path && !desc->data ? path : "<memory>"));

    res = desc->data ? trace_lines_open_mem(&r->lines, desc->data, desc->size, r->name)
                     : trace_lines_open_file(&r->lines, path, r->name);
    if (res != FV_OK) goto fail;

    char *line = NULL;
    size_t len = 0;
    bool too_long = false;
    int rc;
    for (;;) { /* blank lines before the header, but not endless ones */
        rc = trace_lines_next(&r->lines, &line, &len, &too_long);
        if (rc <= 0 || len > 0 || too_long) break;
        if (r->lines.bytes > TRACE_MAX_SKIP) {
            FV_ERROR(TRACE_MOD, "%s: %llu empty lines and no header line in the first %u MiB", r->name,
                     (unsigned long long)r->lines.line_no, TRACE_MAX_SKIP >> 20);
            res = FV_ERR_PARSE;
            goto fail;
        }
    }
    if (rc < 0) {
        FV_ERROR(TRACE_MOD, "%s: %s", r->name, r->lines.err);
        res = FV_ERR_IO;
        goto fail;
    }
    if (rc == 0) {
        FV_ERROR(TRACE_MOD, "%s: empty file: no header line", r->name);
        res = FV_ERR_PARSE;
        goto fail;
    }
    if (too_long) {
        FV_ERROR(TRACE_MOD, "%s:%llu: header line longer than %u bytes", r->name,
                 (unsigned long long)r->lines.line_no, TRACE_MAX_LINE);
        res = FV_ERR_PARSE;
        goto fail;
    }
    fv_trace_format f = desc->format;
    if (f == FV_TRACE_FORMAT_AUTO) {
        if (fv_trace_detect(line, len, &f) != FV_OK) {
            char ex[80];
            excerpt(ex, sizeof ex, line, len);
            const char *hint = what_file(line, len);
            FV_ERROR(TRACE_MOD,
                     "%s:%llu: cannot tell the format from the first line '%s'%s; known formats: fovea, pupil-core, "
                     "pupil-cloud, sranipal, tobii-g3, pico (force one with ?format= or --format)",
                     r->name, (unsigned long long)r->lines.line_no, ex, hint);
            res = FV_ERR_PARSE;
            goto fail;
        }
    }
    r->ops = ops_of(f);
    if (!r->ops) {
        FV_ERROR(TRACE_MOD, "%s: format %d is not a trace format", r->name, (int)f);
        res = FV_ERR_INVALID_ARG;
        goto fail;
    }
    res = r->ops->begin(r, line, len);
    if (res != FV_OK) goto fail;
    r->data_start_line = r->lines.line_no;
    if (r->ops->first_line_is_data) {
        r->data_start_line = 0;
        res = trace_lines_rewind(&r->lines);
        if (res != FV_OK) goto fail;
    }
    *out_reader = r;
    return FV_OK;
fail:
    fv_trace_reader_destroy(&r);
    return res;
}

/* The next row that parses, as it is in the file (no time checks). At most TRACE_MAX_SKIP bytes are read since
 * `start` (the byte count when the caller's fv_trace_reader_next began): more without a sample is an error. */
static fv_result parse_next(fv_trace_reader *r, uint64_t start, trace_row *out)
{
    for (;;) {
        if (r->lines.bytes - start > TRACE_MAX_SKIP) {
            FV_ERROR(TRACE_MOD, "%s:%llu: %u MiB read without a sample; giving up (this does not look like a %s "
                                "recording)", r->name, (unsigned long long)r->lines.line_no, TRACE_MAX_SKIP >> 20,
                     fv_trace_format_name(r->ops->format));
            return FV_ERR_PARSE;
        }
        char *line;
        size_t len;
        bool too_long;
        int rc = trace_lines_next(&r->lines, &line, &len, &too_long);
        if (rc == 0) return FV_END_OF_STREAM;
        if (rc < 0) {
            FV_ERROR(TRACE_MOD, "%s: after line %llu: %s", r->name, (unsigned long long)r->lines.line_no,
                     r->lines.err);
            return FV_ERR_IO;
        }
        if (r->pass == 0) r->stats.lines = r->lines.line_no;
        uint64_t ln = r->lines.line_no;
        if (too_long) {
            if (ln == r->long_line_no) continue; /* the rest of a line already reported */
            r->long_line_no = ln;
            trace_why(r, "line longer than %u bytes", TRACE_MAX_LINE);
            trace_reader_bad_row(r, ln, r->why);
            continue;
        }
        size_t k = 0;
        while (k < len && (line[k] == ' ' || line[k] == '\t')) k++;
        if (k == len) continue; /* blank line */
        if (memchr(line, '\0', len)) {
            trace_reader_bad_row(r, ln, "line contains a NUL byte");
            continue;
        }
        fv_gaze_sample_init_invalid(&out->s, 0, 0);
        r->why[0] = '\0';
        r->row_blink_id = 0;
        r->row_repaired = 0;
        fv_result res = r->ops->row(r, line, len, &out->s);
        if (res == FV_NO_NEW_DATA) continue;
        if (res != FV_OK) {
            trace_reader_bad_row(r, ln, r->why[0] ? r->why : "malformed row");
            continue;
        }
        out->line_no = ln;
        out->blink_id = r->row_blink_id;
        /* every format's sample obeys the same rules: an impossible ray is marked invalid, never handed out */
        out->repaired = r->row_repaired;
        out->dropped = fv_gaze_sample_enforce(&out->s);
        return FV_OK;
    }
}

/* Have at least n rows ahead, unless the file ends (or fails) first: then r->ahead_res says why. */
static void look_ahead(fv_trace_reader *r, int n, uint64_t start)
{
    while (r->n_ahead < n && !r->ahead_done) {
        fv_result res = parse_next(r, start, &r->ahead[r->n_ahead]);
        if (res == FV_OK) {
            r->n_ahead++;
        } else {
            r->ahead_done = true;
            r->ahead_res = res;
        }
    }
}

static void drop_ahead(fv_trace_reader *r, int i)
{
    for (int k = i; k + 1 < r->n_ahead; k++) r->ahead[k] = r->ahead[k + 1];
    r->n_ahead--;
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* The median of the last intervals, or -1 while fewer than TRACE_DT_MIN_KNOWN are known. */
static int64_t running_median(const fv_trace_reader *r)
{
    uint32_t n = r->dt_n < TRACE_DT_WINDOW ? r->dt_n : TRACE_DT_WINDOW;
    if (n < TRACE_DT_MIN_KNOWN) return -1;
    int64_t v[TRACE_DT_WINDOW];
    memcpy(v, r->dt_ns, n * sizeof v[0]);
    qsort(v, n, sizeof v[0], cmp_i64);
    return v[n / 2];
}

/* A step far beyond the interval (median < 0: unknown, every step past the minimum counts). */
static bool far_ahead(int64_t dt_ns, int64_t median_ns)
{
    return dt_ns > TRACE_JUMP_MIN_NS && (median_ns < 0 || dt_ns > fv_i64_mul_sat(TRACE_JUMP_FACTOR, median_ns));
}

static void skip_ahead(fv_trace_reader *r, int i) /* report ahead[i] with r->why and drop it */
{
    trace_reader_bad_row(r, r->ahead[i].line_no, r->why);
    drop_ahead(r, i);
}

/* Hand out ahead[0]: blinks.csv, the interval window, the counters. */
static void emit(fv_trace_reader *r, fv_gaze_sample *out)
{
    trace_row *c = &r->ahead[0];
    if (r->blinks.active) {
        uint64_t iv = blinks_at(r, c->s.t_device_ns);
        if (iv) {
            trace_sample_invalidate(&c->s, true);
            c->repaired = c->dropped = 0; /* a blink: no gaze to repair or drop */
        }
        c->blink_id = iv;
    }
    if (r->have_last_t) r->dt_ns[r->dt_n++ % TRACE_DT_WINDOW] = fv_i64_sub_sat(c->s.t_device_ns, r->last_t_ns);
    r->last_t_ns = c->s.t_device_ns;
    r->have_last_t = true;
    if (r->ops->format != FV_TRACE_FORMAT_FOVEA) c->s.seq = c->line_no;
    if (r->pass == 0) {
        r->stats.samples++;
        fv_gaze_validity_count(&r->stats.validity, c->repaired, c->dropped);
        bool blink = ((c->s.eye[0].flags | c->s.eye[1].flags | c->s.combined.flags) & FV_EYE_BLINK) != 0;
        if (blink) {
            if (c->blink_id) {
                if (c->blink_id != r->last_blink_event) r->stats.blink_events++;
                r->last_blink_event = c->blink_id;
            } else if (!r->in_blink_run) {
                r->stats.blink_events++;
            }
        }
        r->in_blink_run = blink;
    }
    *out = c->s;
    drop_ahead(r, 0);
}

/* The whole file went by without one gaze sample: an error that says what the file seems to be. */
static fv_result no_samples(fv_trace_reader *r)
{
    const char *fmt = fv_trace_format_name(r->ops->format);
    if (r->ops->format == FV_TRACE_FORMAT_TOBII_G3 && r->other_kind[0])
        FV_ERROR(TRACE_MOD, "%s: no gaze samples in %llu lines: this is a Tobii Pro Glasses 3 event file (rows of type "
                 "'%s', no type 'gaze'), not gaze data; read gazedata.gz from the same recording", r->name,
                 (unsigned long long)r->stats.lines, r->other_kind);
    else if (r->stats.rows_skipped)
        FV_ERROR(TRACE_MOD, "%s: no gaze samples: all %llu data rows were bad (see the warnings above); is this a "
                 "%s recording?", r->name, (unsigned long long)r->stats.rows_skipped, fmt);
    else
        FV_ERROR(TRACE_MOD, "%s: no gaze samples: a %s header and no data rows%s%s", r->name, fmt,
                 r->other_kind[0] ? "; rows of another kind: " : "", r->other_kind);
    return FV_ERR_PARSE;
}

fv_result fv_trace_reader_next(fv_trace_reader *r, fv_gaze_sample *out)
{
    const uint64_t start = r->lines.bytes;
    for (;;) {
        look_ahead(r, 1, start);
        if (r->n_ahead == 0) {
            if (r->ahead_res == FV_END_OF_STREAM && r->pass == 0 && r->stats.samples == 0) return no_samples(r);
            return r->ahead_res;
        }
        const int64_t t = r->ahead[0].s.t_device_ns;
        if (!r->have_last_t) {
            /* The first row has no sample before it: it is an outlier when the next two rows both lie before it,
             * in order, and it is far ahead of them (measured by their interval). */
            look_ahead(r, 2, start);
            if (r->n_ahead >= 2 && r->ahead[1].s.t_device_ns < t) look_ahead(r, 3, start);
            if (r->n_ahead >= 3) {
                int64_t t1 = r->ahead[1].s.t_device_ns, t2 = r->ahead[2].s.t_device_ns;
                if (t1 < t && t1 <= t2 && t2 < t && far_ahead(fv_i64_sub_sat(t, t2), fv_i64_sub_sat(t2, t1))) {
                    trace_why(r, "timestamp %lld ns is %.6g s ahead of the next two rows (lines %llu and %llu), "
                                 "which agree: an isolated outlier in time", (long long)t,
                              (double)fv_i64_sub_sat(t, t2) / 1e9, (unsigned long long)r->ahead[1].line_no,
                              (unsigned long long)r->ahead[2].line_no);
                    skip_ahead(r, 0);
                    continue;
                }
            }
            emit(r, out);
            return FV_OK;
        }
        if (t < r->last_t_ns) {
            trace_why(r, "timestamp %lld ns goes back in time (previous row %lld ns)", (long long)t,
                      (long long)r->last_t_ns);
            skip_ahead(r, 0);
            continue;
        }
        const int64_t dt = fv_i64_sub_sat(t, r->last_t_ns), median = running_median(r);
        if (far_ahead(dt, median)) {
            /* A jump: the next row decides. Followed (at or after it): a real gap, kept. Back between the previous
             * sample and it: an isolated outlier, skipped. Before the previous sample: that next row is the bad
             * one (it goes back in time on either count). */
            look_ahead(r, 2, start);
            if (r->n_ahead >= 2) {
                const int64_t t1 = r->ahead[1].s.t_device_ns;
                if (t1 < r->last_t_ns) {
                    trace_why(r, "timestamp %lld ns goes back in time (previous row %lld ns)", (long long)t1,
                              (long long)r->last_t_ns);
                    skip_ahead(r, 1);
                    continue;
                }
                if (t1 < t) {
                    char med[48];
                    if (median >= 0) snprintf(med, sizeof med, "%.6g ms", (double)median / 1e6);
                    else snprintf(med, sizeof med, "not known yet");
                    trace_why(r, "timestamp %lld ns is %.6g s after the previous row (median interval %s) and the "
                                 "next row (line %llu) does not follow it: an isolated outlier in time", (long long)t,
                              (double)dt / 1e9, med, (unsigned long long)r->ahead[1].line_no);
                    skip_ahead(r, 0);
                    continue;
                }
            }
        }
        emit(r, out);
        return FV_OK;
    }
}

fv_result fv_trace_reader_rewind(fv_trace_reader *r)
{
    FV_TRY(trace_lines_rewind(&r->lines));
    while (r->lines.line_no < r->data_start_line) { /* the header again (it read in bounded time the first time) */
        char *line;
        size_t len;
        if (trace_lines_next(&r->lines, &line, &len, NULL) <= 0) {
            FV_ERROR(TRACE_MOD, "%s: file changed while rewinding", r->name);
            return FV_ERR_IO;
        }
    }
    blinks_rewind(r);
    r->pass++;
    r->have_last_t = false;
    r->n_ahead = 0;
    r->ahead_done = false;
    r->ahead_res = FV_OK;
    r->dt_n = 0;
    r->long_line_no = 0;
    return FV_OK;
}

fv_trace_format fv_trace_reader_format(const fv_trace_reader *r) { return r->ops->format; }
const fv_trace_reader_stats *fv_trace_reader_get_stats(const fv_trace_reader *r) { return &r->stats; }
const char *fv_trace_reader_name(const fv_trace_reader *r) { return r->name; }

void fv_trace_reader_destroy(fv_trace_reader **pr)
{
    if (!pr || !*pr) return;
    fv_trace_reader *r = *pr;
    if (r->stats.rows_skipped > r->max_warnings)
        FV_WARN(TRACE_MOD, "%s: %llu bad rows skipped in all (%u reported)", r->name,
                (unsigned long long)r->stats.rows_skipped, r->max_warnings);
    trace_lines_close(&r->lines);
    if (r->blinks.active) trace_lines_close(&r->blinks.lines);
    free(r);
    *pr = NULL;
}
