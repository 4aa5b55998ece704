/* @brief libFuzzer target for one trace reader (FUZZ_FORMAT, a fv_trace_format; AUTO fuzzes detection). The input
 * is the file's bytes (plain or gzip); for the Pupil formats a '\f' byte splits it into the gaze file and blinks.csv.
 * Checks: no crash or sanitizer report, every flagged value finite, directions unit, time never going back. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_trace.h"

#ifndef FUZZ_FORMAT
#define FUZZ_FORMAT FV_TRACE_FORMAT_AUTO
#endif

static void quiet(void *user, fv_log_level level, const char *module, const char *file, int line, const char *msg)
{
    (void)user, (void)level, (void)module, (void)file, (void)line;
    /* touch the message so that a bad format string or overread shows up under ASan */
    volatile size_t n = strlen(msg);
    (void)n;
}

static void check_eye(const fv_eye_sample *e)
{
    if ((e->flags & FV_EYE_DIRECTION_VALID) &&
        (!fv_v3_isfinite(e->direction) || fabsf(fv_v3_len(e->direction) - 1.0f) > 1e-3f))
        __builtin_trap();
    if ((e->flags & FV_EYE_ORIGIN_VALID) && !fv_v3_isfinite(e->origin_mm)) __builtin_trap();
    if ((e->flags & FV_EYE_PUPIL_VALID) && !(e->pupil_mm > 0.0f && e->pupil_mm <= 20.0f)) __builtin_trap();
    if ((e->flags & FV_EYE_OPENNESS_VALID) && !(e->openness >= 0.0f && e->openness <= 1.0f)) __builtin_trap();
}

/* A head pose marked valid is finite with a unit forward direction. */
static void check_head(const fv_gaze_sample *g)
{
    if (!(g->flags & FV_GAZE_HEAD_VALID)) return;
    if (!fv_v3_isfinite(g->head_pos_mm) || !fv_v3_isfinite(g->head_dir)) __builtin_trap();
    if (fabsf(fv_v3_len(g->head_dir) - 1.0f) > 1e-3f) __builtin_trap();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fv_log_set_sink(quiet, NULL);
    fv_trace_reader_desc d = {.format = FUZZ_FORMAT, .data = data, .size = size, .name = "fuzz"};
    const uint8_t *ff = size ? memchr(data, '\f', size) : NULL;
    if (ff && (FUZZ_FORMAT == FV_TRACE_FORMAT_PUPIL_CORE || FUZZ_FORMAT == FV_TRACE_FORMAT_PUPIL_CLOUD)) {
        d.size = (size_t)(ff - data);
        d.blinks_data = ff + 1;
        d.blinks_size = size - d.size - 1;
    }
    if (d.size == 0) d.data = ""; /* keep "memory input" even for an empty slice */
    fv_trace_reader *r = NULL;
    if (fv_trace_reader_create(NULL, &d, &r) != FV_OK) return 0;
    fv_trace_stats st;
    if (fv_trace_stats_init(&st) != FV_OK) abort();
    fv_gaze_sample s;
    for (int pass = 0; pass < 2; pass++) {
        int64_t prev = INT64_MIN;
        for (int i = 0; i < 200000 && fv_trace_reader_next(r, &s) == FV_OK; i++) {
            if (s.t_device_ns < prev) __builtin_trap();
            prev = s.t_device_ns;
            check_eye(&s.eye[0]);
            check_eye(&s.eye[1]);
            check_eye(&s.combined);
            check_head(&s);
            fv_trace_stats_push(&st, &s);
        }
        if (fv_trace_reader_rewind(r) != FV_OK) break;
    }
    fv_trace_stats_finish(&st, fv_trace_reader_get_stats(r)->blink_events);
    if (!isfinite(st.rate_hz) || st.median_dt_ns < 0) __builtin_trap();
    fv_trace_stats_fini(&st);
    fv_trace_reader_destroy(&r);
    return 0;
}
