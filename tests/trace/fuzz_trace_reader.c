/* @brief libFuzzer target for one trace reader (FUZZ_FORMAT, a fv_trace_format; AUTO fuzzes detection). The input
 * is the file's bytes (plain or gzip); for the Pupil formats a '\f' byte splits it into the gaze file and blinks.csv.
 * Checks: no crash or sanitizer report, every flagged value finite, directions unit, time never going back. Then the
 * same bytes are replayed by the trace driver on a simulated clock, stepped (polls, timed reads, jumps to the end
 * of time), at a speed and loop setting drawn from the input's length: the replay never overflows (UBSan), never
 * stalls (every read returns; libFuzzer's timeout), keeps time going forward, and hands out every sample the reader
 * gave. */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_trace.h"
#include "fv_trace_driver.h"

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

/* The trace driver's replay timing over the same bytes. samples: what the reader gave on its first pass. */
static void replay(const fv_trace_reader_desc *d, uint64_t samples, size_t size)
{
    static const double speeds[] = {1.0, 0.001, 2.5, 1000.0};
    static const int64_t starts[] = {0, INT64_MIN + 1, INT64_MAX - 1000, -5};
    fv_trace_reader *r = NULL;
    if (fv_trace_reader_create(NULL, d, &r) != FV_OK) __builtin_trap(); /* it opened the first time */
    fv_clock clock;
    fv_clock_sim_init(&clock, starts[(size >> 3) % 4]);
    fv_trace_replay_desc rd = {.speed = speeds[(size >> 1) % 4], .loop = (int)(size & 1), .clock = &clock};
    fv_device *dev = NULL;
    if (fv_trace_replay_open(r, &rd, &dev) != FV_OK) return; /* the reader is gone with the failure */
    if (!isfinite(dev->nominal_rate_hz) || dev->nominal_rate_hz < 0) __builtin_trap();
    fv_gaze_sample buf[16];
    int64_t prev_dev = INT64_MIN, prev_host = INT64_MIN, prev_now = fv_clock_now_ns(&clock);
    uint64_t got = 0;
    bool ended = false, failed = false;
    /* looping: a little past the second pass is enough (every pass re-reads the file) */
    for (int step = 0; step < 120 && !ended && !failed && !(rd.loop && got > 2 * samples + 16); step++) {
        if (step == 60) clock.sleep_until_ns(&clock, INT64_MAX); /* the rest is due: it must all come out */
        size_t n = 0;
        int timeout_ms = (step % 3 == 0) ? 0 : (step % 3 == 1 ? 7 : 100000);
        fv_result res = fv_device_read(dev, buf, 1 + (size_t)step % 16, &n, timeout_ms);
        int64_t now = fv_clock_now_ns(&clock);
        if (now < prev_now) __builtin_trap();
        prev_now = now;
        if (res == FV_END_OF_STREAM) ended = true;
        else if (res != FV_OK && res != FV_TIMEOUT) failed = true; /* a read error (corrupt gzip): reported, fine */
        if ((res == FV_OK) != (n > 0)) __builtin_trap();
        for (size_t k = 0; k < n; k++) {
            if (buf[k].t_device_ns < prev_dev || buf[k].t_host_ns < prev_host || buf[k].t_host_ns > now)
                __builtin_trap();
            prev_dev = buf[k].t_device_ns;
            prev_host = buf[k].t_host_ns;
        }
        got += n;
    }
    /* not looping, with the clock at the end of time: every sample came out, then the end */
    if (!rd.loop && !failed && ended && got != samples) __builtin_trap();
    if (!rd.loop && !failed && !ended && samples <= 50) __builtin_trap(); /* 60 reads of >= 1 each: enough */
    fv_device_close(&dev);
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
    uint64_t samples = fv_trace_reader_get_stats(r)->samples;
    fv_trace_reader_destroy(&r);
    replay(&d, samples, size);
    return 0;
}
