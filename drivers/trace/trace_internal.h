/* @brief Internals of drivers/trace: the line source (file through zlib, or memory, plain or gzip), CSV field
 * splitting, number parsing, and the reader object the per-format parsers fill in. Not a public header. */
#ifndef FV_TRACE_INTERNAL_H
#define FV_TRACE_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <zlib.h>

#include "fv_trace.h"

#define TRACE_MOD "trace"
#define TRACE_CHUNK (64u * 1024u)       /* bytes read (or inflated) at a time */
#define TRACE_MAX_LINE (1024u * 1024u)  /* longer lines are skipped as bad rows */
#define TRACE_MAX_FIELDS 256u           /* fields beyond this are ignored */
#define TRACE_MAX_COLS 64               /* columns one format looks up */

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
    char err[160];             /* why the source failed (read error, corrupt gzip) */
} trace_lines;

/** Open a file (plain or gzip) or a memory buffer (plain or gzip) as a line source. */
fv_result trace_lines_open_file(trace_lines *l, const char *path, const char *name);
fv_result trace_lines_open_mem(trace_lines *l, const void *data, size_t size, const char *name);
/** Next line without its "\n" / "\r\n", NUL-terminated, writable until the next call. 1 = a line; 0 = end;
 *  <0 = error (l->err says why). *out_too_long set when the line was cut at TRACE_MAX_LINE (the rest is dropped). */
int trace_lines_next(trace_lines *l, char **out_line, size_t *out_len, bool *out_too_long);
fv_result trace_lines_rewind(trace_lines *l);
void trace_lines_close(trace_lines *l);

/* ---- CSV ---- */

/** Split a line in place on sep; double-quoted fields ("a,b", "" for a quote) are unquoted. Returns the field count
 *  (at most cap; the rest are dropped). Returns -1 for an unterminated quote. */
int trace_csv_split(char *line, char sep, char **fields, int cap);
/** Split a data row into r->fields and check it has the fields the header needs; on failure records why (for the
 *  file:line warning) and returns FV_ERR_PARSE. */
fv_result trace_split_row(fv_trace_reader *r, char *line, char sep, int *out_n);
/** Index of column name (exact match after trimming spaces and a UTF-8 BOM) or -1. */
int trace_csv_find(char *const *fields, int n, const char *name);
/** Whole-field parses; false on empty, junk, overflow. Spaces around the number are allowed. */
bool trace_parse_f64(const char *s, double *out);
bool trace_parse_i64(const char *s, int64_t *out);
bool trace_field_empty(const char *s);
/** Seconds (finite, |s| < 9.2e9) to ns. */
bool trace_seconds_to_ns(double s, int64_t *out_ns);

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
} blink_cursor;

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
    int64_t last_t_ns;
    bool have_last_t;
    char *fields[TRACE_MAX_FIELDS];
    int col[TRACE_MAX_COLS];   /* column indices (format-specific meaning), -1 when absent */
    int ncols_needed;          /* fields a row needs (1 + highest required index) */
    /* format state */
    blink_cursor blinks;
    uint64_t last_blink_event; /* id of the blink event of the previous sample (0 none) */
    bool in_blink_run;
    float min_confidence;
    uint64_t row_blink_id;     /* set by a row parser that knows the source's blink event id */
    double meta_rate_hz;       /* fovea format: "# rate_hz:" from the header (0 unknown) */
};

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
/** 1-based blink event index covering t (0 = none). Advances the cursor; blinks must be sorted by start. */
uint64_t trace_blinks_at(fv_trace_reader *r, int64_t t_ns);
void trace_blinks_rewind(fv_trace_reader *r);
/** Count a blink event id for the reader stats (first pass): a new id != previous and != 0 counts once. */
void trace_count_blink_event(fv_trace_reader *r, uint64_t id);

/* ---- sample helpers (trace_sample.c) ---- */

/** Validated setters: a value outside its plausible range leaves the field invalid (NaN, flag clear). */
void trace_eye_set_origin(fv_eye_sample *e, double x, double y, double z);
/** Normalises; a zero, tiny or non-finite vector leaves the direction invalid. */
void trace_eye_set_direction(fv_eye_sample *e, double x, double y, double z);
void trace_eye_set_pupil(fv_eye_sample *e, double mm);
void trace_eye_set_openness(fv_eye_sample *e, double v);
/** Clear every value of an eye (NaN) and its validity flags; FV_EYE_BLINK is kept. */
void trace_eye_invalidate(fv_eye_sample *e);
/** Combined ray from the eyes when the source gives none: both valid → mean origin and normalised sum of directions;
 *  one → that eye's direction, origin unknown. */
void trace_combine_eyes(fv_gaze_sample *s);
/** Head pose from a Unity log (Pico, SRanipal): pos_m is the position in metres and euler_deg the Euler angles in
 *  degrees (x, y, z; Unity applies Z, then X, then Y: R = Ry·Rx·Rz), both in Unity's left-handed world (+x right,
 *  +y up, +z forward). Sets head_pos_mm = (x, y, −z)·1000, head_dir = R·(0,0,1) mapped the same way (x, y, −z), and
 *  FV_GAZE_HEAD_VALID. A value that is NULL (column absent or row short), not a number, non-finite, a position beyond
 *  1 km or an angle beyond ±720°, or an all-zero pose (position and angles all exactly 0: the head was not logged),
 *  leaves the head invalid (NaN, flag clear); the sample itself is kept. */
void trace_set_head_unity(fv_gaze_sample *s, const char *const pos_m[3], const char *const euler_deg[3]);
/** A float from a double; non-finite or beyond FLT_MAX → NaN. */
float trace_f32(double v);

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
