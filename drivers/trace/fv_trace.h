/* @brief Recorded gaze: streaming readers for public eye-tracker exports (Pupil Core, Pupil Invisible/Cloud, HTC Vive
 * Pro Eye SRanipal, Tobii Pro Glasses 3, Pico Neo 3 Pro) and fovea's own trace format, a writer for fovea's format,
 * and summary statistics. Every reader maps the file's axes and units into fovea's head frame (+x right, +y up,
 * -z forward, mm) and keeps invalid samples as invalid samples. See docs/trace-format.md. */
#ifndef FV_TRACE_H
#define FV_TRACE_H

#include <stddef.h>
#include <stdint.h>

#include "fovea/fv_gaze_sample.h"
#include "fv_gaze_validity.h"
#include "fv_result.h"

typedef enum fv_trace_format {
    FV_TRACE_FORMAT_AUTO = 0,        /* detect by content */
    FV_TRACE_FORMAT_FOVEA = 1,       /* fovea's own text format ("fovea-trace 1") */
    FV_TRACE_FORMAT_PUPIL_CORE = 2,  /* Pupil Player raw export gaze_positions.csv (+ blinks.csv) */
    FV_TRACE_FORMAT_PUPIL_CLOUD = 3, /* Pupil Invisible / Pupil Cloud export gaze.csv (+ blinks.csv) */
    FV_TRACE_FORMAT_SRANIPAL = 4,    /* HTC Vive Pro Eye SRanipal log, ';'-separated */
    FV_TRACE_FORMAT_TOBII_G3 = 5,    /* Tobii Pro Glasses 3 gazedata(.gz), JSON lines */
    FV_TRACE_FORMAT_PICO = 6,        /* Pico Neo 3 Pro Eye Unity log, tab-separated */
    FV_TRACE_FORMAT_COUNT_
} fv_trace_format;

/** Short name ("fovea", "pupil-core", "pupil-cloud", "sranipal", "tobii-g3", "pico", "auto"); never NULL. */
const char *fv_trace_format_name(fv_trace_format f);
/** Parse a short name (also accepts "pupil-invisible", "tobii"); FV_ERR_NOT_FOUND for an unknown name. */
FV_MUST_CHECK fv_result fv_trace_format_parse(const char *name, fv_trace_format *out);

/** How to open a reader. Zero means default. */
typedef struct fv_trace_reader_desc {
    fv_trace_format format; /* AUTO: detect by content */
    /** Read from memory instead of a path (plain text or gzip). Borrowed; must outlive the reader. */
    const void *data;
    size_t size;
    /** Name used in messages (default: the path, or "<memory>"). */
    const char *name;
    /** Pupil formats: the blinks file. NULL = "blinks.csv" beside the gaze file when it exists; "" = none. */
    const char *blinks_path;
    /** Pupil formats: blinks.csv from memory instead (takes precedence over blinks_path). */
    const void *blinks_data;
    size_t blinks_size;
    /** Pupil Core: samples below this confidence are invalid. 0 = 0.6 (Pupil Labs' recommendation); <0 = keep all. */
    float min_confidence;
    /** Bad rows reported one by one before the reader goes quiet (a total is logged at destroy). 0 = 10. */
    uint32_t max_warnings;
} fv_trace_reader_desc;

/** Counters of one reader (all passes, rewinds included, unless noted). */
typedef struct fv_trace_reader_stats {
    uint64_t lines;        /* physical lines read (first pass) */
    uint64_t samples;      /* samples returned (first pass) */
    uint64_t rows_skipped; /* bad rows skipped with a warning (first pass) */
    uint64_t blink_events; /* distinct source blink events that covered at least one sample (first pass) */
    /* Physically impossible gaze (fv_gaze_validity.h), per kind, first pass: samples a format's documented rule
     * repaired, and samples whose impossible rays were marked invalid (outside blinks). */
    fv_gaze_validity_counts validity;
} fv_trace_reader_stats;

typedef struct fv_trace_reader fv_trace_reader;

/** Open a recording (path, or desc->data). Reads and checks the header: a missing required column is
 *  FV_ERR_PARSE naming the column and file; an unknown format is FV_ERR_PARSE listing what was seen. Memory use is
 *  bounded (one line and one chunk), whatever the file length. One owner; not thread-safe. */
FV_MUST_CHECK fv_result fv_trace_reader_create(const char *path, const fv_trace_reader_desc *desc,
                                               fv_trace_reader **out_reader);
/** Next sample, in the head frame, t_device_ns from the file's clock (t_host_ns is only set, with
 *  FV_GAZE_HOST_TIME_VALID, by fovea traces that recorded it). Bad rows are skipped with a rate-limited warning naming file:line and the reason.
 *  FV_OK, FV_END_OF_STREAM at the end, or an error (unreadable/corrupt compressed data). */
FV_MUST_CHECK fv_result fv_trace_reader_next(fv_trace_reader *r, fv_gaze_sample *out);
/** Start over from the first sample (for looping). Warnings are not repeated on later passes. */
FV_MUST_CHECK fv_result fv_trace_reader_rewind(fv_trace_reader *r);
fv_trace_format fv_trace_reader_format(const fv_trace_reader *r);
const fv_trace_reader_stats *fv_trace_reader_get_stats(const fv_trace_reader *r);
/** Name used in messages (the path). */
const char *fv_trace_reader_name(const fv_trace_reader *r);
/** Free; logs the number of skipped rows when there were more than were reported. Safe on NULL. */
void fv_trace_reader_destroy(fv_trace_reader **r);

/** Detect the format from the first bytes of a file (decompressed when gzip). FV_ERR_PARSE when unknown. */
FV_MUST_CHECK fv_result fv_trace_detect(const char *first_line, size_t len, fv_trace_format *out);

/* ---- writer: fovea's own format ---- */

typedef struct fv_trace_writer_desc {
    const char *source;   /* free text written as "# source: ..." (e.g. the URI or input file); NULL = none */
    double rate_hz;       /* nominal rate written as "# rate_hz: ..." (0 = unknown) */
    int gzip;             /* 1: gzip-compress; 0: plain text, or gzip when the path ends in ".gz" */
} fv_trace_writer_desc;

typedef struct fv_trace_writer fv_trace_writer;

/** Create (truncate) a fovea trace at path and write its header. */
FV_MUST_CHECK fv_result fv_trace_writer_create(const char *path, const fv_trace_writer_desc *desc,
                                               fv_trace_writer **out_writer);
/** Append one sample (exactly: floats round-trip bit for bit, NaN as an empty field). */
FV_MUST_CHECK fv_result fv_trace_writer_write(fv_trace_writer *w, const fv_gaze_sample *s);
/** Flush and close; reports a write error (disk full) that earlier writes could not see. Frees w; sets *w NULL. */
FV_MUST_CHECK fv_result fv_trace_writer_finish(fv_trace_writer **w);
/** Abandon without checking (error paths). Safe on NULL. */
void fv_trace_writer_destroy(fv_trace_writer **w);

/* ---- statistics (fovea trace info) ---- */

typedef struct fv_trace_stats {
    uint64_t samples;
    uint64_t invalid;           /* samples with no valid gaze direction at all (no eye, no combined) */
    uint64_t eye_valid[2];      /* samples whose FV_EYE_LEFT / FV_EYE_RIGHT direction is valid */
    uint64_t combined_valid;
    uint64_t eye_present[2];    /* 1 when the source has this eye at all (some sample had a valid value) */
    int64_t t_first_ns, t_last_ns;
    int64_t median_dt_ns;       /* median sample interval (10 us resolution); 0 with fewer than 2 samples */
    double rate_hz;             /* mean rate: (samples - 1) / duration; 0 when unknown */
    int64_t max_dt_ns;
    float pupil_min_mm[2], pupil_max_mm[2]; /* NaN when the eye has no valid pupil */
    uint64_t blinks;            /* blink events (source events when the reader knows them, else sample runs) */
    uint64_t blink_samples;     /* samples flagged FV_EYE_BLINK (any eye) */
    int64_t blink_total_ns;     /* time inside blink runs */
    uint64_t gaps;              /* intervals longer than 3x the median */
    int64_t gap_total_ns;
    uint64_t invalid_runs;      /* runs of consecutive invalid samples */
    /* private */
    uint32_t *hist_;            /* dt histogram, 10 us bins */
    uint64_t over_count_;
    int64_t over_sum_;
    int in_blink_, in_invalid_;
    int64_t blink_start_ns_, prev_t_ns_;
} fv_trace_stats;

/** Zero the counters and allocate the interval histogram (bounded: 100k bins). */
FV_MUST_CHECK fv_result fv_trace_stats_init(fv_trace_stats *s);
void fv_trace_stats_push(fv_trace_stats *s, const fv_gaze_sample *g);
/** Compute median, rate and gaps. blink_events > 0 overrides the run count (a reader's source events). */
void fv_trace_stats_finish(fv_trace_stats *s, uint64_t blink_events);
/** Free the histogram; safe twice and after a failed init. */
void fv_trace_stats_fini(fv_trace_stats *s);

#endif
