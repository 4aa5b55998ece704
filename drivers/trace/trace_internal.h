/* @brief Internals of drivers/trace: the line source (file through zlib, or memory, plain or gzip) and the reader
 * object the per-format parsers fill in. The pure helpers they use (CSV fields, numbers, validated sample setters)
 * are in trace_util.h, which knows nothing of the reader. Not a public header. */
#ifndef FV_TRACE_INTERNAL_H
#define FV_TRACE_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <zlib.h>

#include "fv_trace.h"
#include "trace_util.h"

#define TRACE_MOD "trace"
#define TRACE_CHUNK (64u * 1024u)       /* bytes read (or inflated) at a time */
#define TRACE_MAX_LINE (1024u * 1024u)  /* longer lines are skipped as bad rows */
#define TRACE_MAX_SKIP (16u * 1024u * 1024u) /* bytes read for nothing (no header, sample, blink) before giving up */
#define TRACE_MAX_FIELDS 256u           /* fields beyond this are ignored */
#define TRACE_MAX_COLS 64               /* columns one format looks up */
/* Isolated outliers in time (docs/trace-format.md, "Time checks"): a step "far" ahead is more than
 * TRACE_JUMP_FACTOR running median intervals (the median of the last TRACE_DT_WINDOW intervals; every step counts
 * while fewer than TRACE_DT_MIN_KNOWN are known) and more than TRACE_JUMP_MIN_NS. */
#define TRACE_DT_WINDOW 15
#define TRACE_DT_MIN_KNOWN 3
#define TRACE_JUMP_FACTOR 20
#define TRACE_JUMP_MIN_NS INT64_C(10000000) /* 10 ms */

/* ---- line source ---- */

typedef struct trace_lines {
    char name[512];
    gzFile gz;                 /* file input (zlib reads plain files transparently) */
    const uint8_t *mem;        /* memory input */
    size_t mem_size, mem_pos;
    bool mem_gzip;
    z_stream zs;
    bool zs_live;
    bool zs_ended;             /* the current gzip member ended cleanly */
    uint8_t *chunk;            /* TRACE_CHUNK + 1 */
    size_t chunk_len, chunk_pos;
    bool eof;
    char *line;                /* assembled line when it spans chunks */
    size_t line_len, line_cap;
    uint64_t line_no;          /* 1-based number of the line last returned */
    uint64_t bytes;            /* bytes consumed since the open or the last rewind (decompressed) */
    bool in_long_line;         /* the rest of an over-long line is still unread */
    char err[160];             /* why the source failed (read error, corrupt gzip) */
} trace_lines;

/** Open a file (plain or gzip) or a memory buffer (plain or gzip) as a line source. */
fv_result trace_lines_open_file(trace_lines *l, const char *path, const char *name);
fv_result trace_lines_open_mem(trace_lines *l, const void *data, size_t size, const char *name);
/** Next line without its "\n" / "\r\n", NUL-terminated, writable until the next call. 1 = a line; 0 = end;
 *  <0 = error (l->err says why). A line longer than TRACE_MAX_LINE comes back as soon as the limit is passed, empty,
 *  with *out_too_long set; its rest is dropped by the following calls, at most TRACE_MAX_LINE bytes each: a call
 *  that drops that much without reaching the newline hands the same line (same line_no) back again, too long. So
 *  one call reads at most about 2 x TRACE_MAX_LINE bytes, whatever the input. */
int trace_lines_next(trace_lines *l, char **out_line, size_t *out_len, bool *out_too_long);
fv_result trace_lines_rewind(trace_lines *l);
void trace_lines_close(trace_lines *l);

/* ---- reader ---- */

typedef struct blink_cursor {
    bool active;
    trace_lines lines;
    int col_start, col_end;
    double scale_to_ns;        /* 1e9 for seconds, 1 for ns */
    bool have;                 /* current interval valid */
    int64_t start_ns, end_ns;
    uint64_t index;            /* 1-based index of the current interval */
    bool done;
    uint64_t long_line_no;     /* over-long line already reported */
} blink_cursor;

/* A parsed row waiting for the reader's time checks (the look-ahead of fv_trace_reader_next). */
typedef struct trace_row {
    fv_gaze_sample s;
    uint64_t line_no;
    uint64_t blink_id;         /* the row parser's source blink event id (0 none) */
    uint32_t repaired, dropped; /* fv_gaze_fault bits: repaired by the row parser, dropped by the validity rules */
} trace_row;

typedef struct trace_format_ops {
    fv_trace_format format;
    bool first_line_is_data;   /* no header line: the line given to begin is re-read as data */
    /** Called with the first line (already split for the format's separator by the format itself). Set up columns;
     *  FV_ERR_PARSE naming a missing column. */
    fv_result (*begin)(fv_trace_reader *r, char *first_line, size_t len);
    /** Parse one data line. FV_OK = *out filled; FV_NO_NEW_DATA = not a sample (skip silently); FV_ERR_PARSE = bad
     *  row, with the reason in r->why. */
    fv_result (*row)(fv_trace_reader *r, char *line, size_t len, fv_gaze_sample *out);
} trace_format_ops;

struct fv_trace_reader {
    trace_lines lines;
    const trace_format_ops *ops;
    fv_trace_reader_stats stats;
    fv_trace_reader_desc desc;
    char name[512];
    char why[256];             /* reason of the last bad row */
    uint32_t max_warnings;
    uint32_t pass;             /* 0 on the first pass through the file */
    uint64_t data_start_line;  /* lines consumed by the header (re-skipped on rewind) */
    int64_t last_t_ns;         /* time of the last sample handed out (this pass) */
    bool have_last_t;
    trace_row ahead[3];        /* parsed rows not yet handed out: the time checks look at up to three */
    int n_ahead;
    bool ahead_done;           /* no more rows: ahead_res says why (FV_END_OF_STREAM or an error) */
    fv_result ahead_res;
    int64_t dt_ns[TRACE_DT_WINDOW]; /* the last intervals between samples handed out (a ring) */
    uint32_t dt_n;
    uint64_t long_line_no;     /* over-long line already reported (its rest comes back too long, same number) */
    char *fields[TRACE_MAX_FIELDS];
    int col[TRACE_MAX_COLS];   /* column indices (format-specific meaning), -1 when absent */
    int ncols_needed;          /* fields a row needs (1 + highest required index) */
    /* format state */
    blink_cursor blinks;
    uint64_t last_blink_event; /* id of the blink event of the previous sample (0 none) */
    bool in_blink_run;
    float min_confidence;
    uint64_t row_blink_id;     /* set by a row parser that knows the source's blink event id */
    uint32_t row_repaired;     /* set by a row parser that repaired an impossible value its format documents
                                  (1u << fv_gaze_fault) */
    double meta_rate_hz;       /* fovea format: "# rate_hz:" from the header (0 unknown) */
    char other_kind[48];       /* a row parser's name for the first non-sample row it skipped ("syncport"), for the
                                  error of a file without samples */
    uint64_t other_rows;       /* rows skipped as not samples (FV_NO_NEW_DATA), first pass */
};

/** Split a data row into r->fields and check it has the fields the header needs; on failure records why (for the
 *  file:line warning) and returns FV_ERR_PARSE. */
fv_result trace_split_row(fv_trace_reader *r, char *line, char sep, int *out_n);
/** Report a bad row (rate-limited) and count it. */
void trace_reader_bad_row(fv_trace_reader *r, uint64_t line_no, const char *why);
/** Set r->why. */
void trace_why(fv_trace_reader *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/** Look up a required column: sets r->col[slot] or logs "missing required column" and returns FV_ERR_PARSE. */
fv_result trace_require_col(fv_trace_reader *r, char *const *fields, int n, int slot, const char *name);
void trace_optional_col(fv_trace_reader *r, char *const *fields, int n, int slot, const char *name);
/** Field of a column slot in the current row, or NULL when the column is absent or the row is short. */
const char *trace_col(const fv_trace_reader *r, int nfields, int slot);

/** Pupil formats: open blinks.csv (beside the gaze file, or from desc); columns in seconds or ns. */
fv_result trace_blinks_open(fv_trace_reader *r, const char *start_col, const char *end_col, double scale_to_ns);
/* The reader applies the blinks file to each sample it hands out, after the time checks (so a skipped row, an
 * outlier far in the future above all, never moves the cursor): a sample inside an interval becomes invalid with
 * FV_EYE_BLINK, and its blink event is the interval's index. Row parsers do not look at blinks.csv. */
/** Count a blink event id for the reader stats (first pass): a new id != previous and != 0 counts once. */
void trace_count_blink_event(fv_trace_reader *r, uint64_t id);

#define TRACE_FOVEA_NCOLS 40
/** Column names of fovea's format, in the order the writer writes them. */
extern const char *const trace_fovea_cols[TRACE_FOVEA_NCOLS];

extern const trace_format_ops trace_fmt_fovea;
extern const trace_format_ops trace_fmt_pupil_core;
extern const trace_format_ops trace_fmt_pupil_cloud;
extern const trace_format_ops trace_fmt_sranipal;
extern const trace_format_ops trace_fmt_tobii_g3;
extern const trace_format_ops trace_fmt_pico;

#endif
