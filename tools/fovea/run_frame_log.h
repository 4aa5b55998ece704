/* @brief The per-frame record of `fovea run --frame-log FILE.csv`, and reading it back for `fovea latency
 * --frame-log`. One CSV row per frame; the header names every column with its unit as a suffix (_ns: host
 * monotonic clock, except t_sample_device_ns on the tracker's own clock; _ms, _deg, _mm, _m); an empty field is
 * unknown or does not apply (no --gaze, no sample yet). */
#ifndef FV_RUN_FRAME_LOG_H
#define FV_RUN_FRAME_LOG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fovea/fv_frame_input.h"
#include "fv_latency.h"
#include "fv_scene.h"

/** What one frame did, beyond its latency record. */
typedef struct run_frame_row {
    uint64_t frame_id;
    const fv_latency_record *lat; /* NULL without --gaze */
    fv_eye_gaze gaze[2];          /* predicted gaze per eye as the frame drew it (eye view space) */
    float pupil_mm;               /* NaN when unknown */
    double gpu_ms, cpu_ms;        /* NaN when unknown */
    fv_head head;                 /* the head the frame was drawn from */
    const char *head_source;      /* "trace", "scene", "fixed" */
    bool head_recorded;           /* a recorded head pose moved it */
    uint64_t head_seq;            /* that pose's sample sequence number */
} run_frame_row;

/** Write the header and n rows to path (created or truncated). Logs and returns FV_ERR_IO naming the file when it
 *  cannot be written completely. */
FV_MUST_CHECK fv_result run_frame_log_write(const char *path, const run_frame_row *rows, size_t n);

/** A frame log read back: the latency records (one per row that has a frame id) and each row's GPU time. */
typedef struct run_frame_log {
    fv_latency_record *records;
    double *gpu_ms, *uncertainty_deg; /* NaN where the row has none */
    size_t n;
    size_t rows_with_gaze_columns;    /* rows that came from a --gaze run */
} run_frame_log;

/** Read a frame log written by run_frame_log_write. Bad input is FV_ERR_PARSE with file:line, the column and why
 *  (logged); a file with no rows is an error too. */
FV_MUST_CHECK fv_result run_frame_log_read(const char *path, run_frame_log *out);
void run_frame_log_fini(run_frame_log *log);

#endif
