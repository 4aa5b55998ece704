/* @brief Summary statistics of a gaze trace (fovea trace info), computed in one streaming pass with bounded memory:
 * the sample interval goes into a 10 us histogram up to 1 s (beyond that: counted and summed exactly). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_stats.h" /* saturating time arithmetic: a hostile file can put its timestamps anywhere */
#include "fv_trace.h"

#define HIST_BIN_NS INT64_C(10000)
#define HIST_BINS 100000 /* 10 us x 100k = 1 s */

fv_result fv_trace_stats_init(fv_trace_stats *s)
{
    memset(s, 0, sizeof *s);
    for (int e = 0; e < 2; e++) s->pupil_min_mm[e] = s->pupil_max_mm[e] = NAN;
    s->hist_ = calloc(HIST_BINS, sizeof *s->hist_);
    return s->hist_ ? FV_OK : FV_ERR_NO_MEMORY;
}

static bool any_direction(const fv_gaze_sample *g)
{
    return ((g->eye[0].flags | g->eye[1].flags | g->combined.flags) & FV_EYE_DIRECTION_VALID) != 0;
}

void fv_trace_stats_push(fv_trace_stats *s, const fv_gaze_sample *g)
{
    int64_t t = g->t_device_ns;
    if (s->samples == 0) {
        s->t_first_ns = t;
    } else {
        int64_t dt = fv_i64_sub_sat(t, s->prev_t_ns_);
        if (dt < 0) dt = 0;
        if (dt > s->max_dt_ns) s->max_dt_ns = dt;
        int64_t bin = dt / HIST_BIN_NS;
        if (bin < HIST_BINS) {
            if (s->hist_) s->hist_[bin]++;
        } else {
            s->over_count_++;
            s->over_sum_ = fv_i64_add_sat(s->over_sum_, dt);
        }
    }
    s->samples++;
    s->t_last_ns = t;

    bool valid = any_direction(g);
    if (!valid) {
        s->invalid++;
        if (!s->in_invalid_) s->invalid_runs++;
    }
    s->in_invalid_ = !valid;
    for (int e = 0; e < 2; e++) {
        const fv_eye_sample *es = &g->eye[e];
        if (es->flags & FV_EYE_DIRECTION_VALID) {
            s->eye_valid[e]++;
            s->eye_present[e] = 1;
        }
        if ((es->flags & FV_EYE_PUPIL_VALID) && isfinite(es->pupil_mm)) {
            if (!(s->pupil_min_mm[e] <= es->pupil_mm)) s->pupil_min_mm[e] = es->pupil_mm;
            if (!(s->pupil_max_mm[e] >= es->pupil_mm)) s->pupil_max_mm[e] = es->pupil_mm;
        }
    }
    if (g->combined.flags & FV_EYE_DIRECTION_VALID) s->combined_valid++;

    bool blink = ((g->eye[0].flags | g->eye[1].flags | g->combined.flags) & FV_EYE_BLINK) != 0;
    if (blink) {
        s->blink_samples++;
        if (!s->in_blink_) {
            s->blinks++;
            s->blink_start_ns_ = t;
        }
    } else if (s->in_blink_) {
        s->blink_total_ns = fv_i64_add_sat(s->blink_total_ns, fv_i64_sub_sat(t, s->blink_start_ns_)); /* until the next sample */
    }
    s->in_blink_ = blink;
    s->prev_t_ns_ = t;
}

void fv_trace_stats_finish(fv_trace_stats *s, uint64_t blink_events)
{
    if (s->in_blink_) {
        s->blink_total_ns = fv_i64_add_sat(s->blink_total_ns, fv_i64_sub_sat(s->t_last_ns, s->blink_start_ns_));
        s->in_blink_ = 0;
    }
    if (blink_events > 0) s->blinks = blink_events;
    uint64_t n = s->samples > 1 ? s->samples - 1 : 0;
    s->median_dt_ns = 0;
    s->rate_hz = 0;
    s->gaps = 0;
    s->gap_total_ns = 0;
    if (n == 0 || !s->hist_) return;
    /* median of the n intervals: the mean of the two middle ones when n is even (bin centres) */
    uint64_t lo_rank = (n + 1) / 2, hi_rank = n / 2 + 1, acc = 0;
    int64_t lo_bin = -1, hi_bin = -1;
    for (int64_t b = 0; b < HIST_BINS && hi_bin < 0; b++) {
        acc += s->hist_[b];
        if (lo_bin < 0 && acc >= lo_rank) lo_bin = b;
        if (acc >= hi_rank) hi_bin = b;
    }
    int64_t over_mean = s->over_count_ ? s->over_sum_ / (int64_t)s->over_count_ : 0;
    int64_t lo_ns = lo_bin >= 0 ? lo_bin * HIST_BIN_NS + HIST_BIN_NS / 2 : over_mean;
    int64_t hi_ns = hi_bin >= 0 ? hi_bin * HIST_BIN_NS + HIST_BIN_NS / 2 : over_mean;
    s->median_dt_ns = lo_ns + (hi_ns - lo_ns) / 2;
    if (s->median_dt_ns > s->max_dt_ns) s->median_dt_ns = s->max_dt_ns; /* a bin centre past the longest interval */
    /* the rate is the mean over the whole trace: trackers that stamp in whole ms alternate 8 and 9 ms at 120 Hz */
    if (s->t_last_ns > s->t_first_ns) s->rate_hz = (double)n * 1e9 / (double)fv_i64_sub_sat(s->t_last_ns, s->t_first_ns);
    int64_t gap_ns = fv_i64_mul_sat(3, s->median_dt_ns);
    for (int64_t b = gap_ns / HIST_BIN_NS + 1; b < HIST_BINS; b++) {
        if (!s->hist_[b]) continue;
        s->gaps += s->hist_[b];
        s->gap_total_ns = fv_i64_add_sat(s->gap_total_ns, fv_i64_mul_sat((int64_t)s->hist_[b], b * HIST_BIN_NS + HIST_BIN_NS / 2));
    }
    s->gaps += s->over_count_;
    s->gap_total_ns = fv_i64_add_sat(s->gap_total_ns, s->over_sum_);
}

void fv_trace_stats_fini(fv_trace_stats *s)
{
    free(s->hist_);
    s->hist_ = NULL;
}
