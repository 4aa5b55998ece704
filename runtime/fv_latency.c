/* @brief Latency records: stage durations and summaries (see fv_latency.h). */
#include "fv_latency.h"

#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_stats.h"

const char *fv_latency_stage_str(fv_latency_stage s)
{
    switch (s) {
    case FV_LATENCY_TRACKER: return "tracker";
    case FV_LATENCY_SAMPLE_AGE: return "sample_age";
    case FV_LATENCY_LATCH: return "latch";
    case FV_LATENCY_CPU: return "cpu";
    case FV_LATENCY_GPU: return "gpu";
    case FV_LATENCY_PRESENT: return "present";
    case FV_LATENCY_DISPLAY: return "display";
    case FV_LATENCY_STAGE_COUNT: break;
    }
    return "unknown";
}

int64_t fv_latency_stage_ns(const fv_latency_record *r, fv_latency_stage s)
{
    switch (s) {
    case FV_LATENCY_TRACKER: return fv_i64_sub_sat(r->t_sample_received_ns, r->t_sample_capture_ns);
    case FV_LATENCY_SAMPLE_AGE: return fv_i64_sub_sat(r->t_latch_ns, r->t_sample_received_ns);
    case FV_LATENCY_LATCH: return fv_i64_sub_sat(r->t_cpu_begin_ns, r->t_latch_ns);
    case FV_LATENCY_CPU: return fv_i64_sub_sat(r->t_submit_ns, r->t_cpu_begin_ns);
    case FV_LATENCY_GPU: return fv_i64_sub_sat(r->t_gpu_end_ns, r->t_submit_ns);
    case FV_LATENCY_PRESENT: return fv_i64_sub_sat(r->t_vsync_ns, r->t_gpu_end_ns);
    case FV_LATENCY_DISPLAY: return fv_i64_sub_sat(r->t_photon_ns, r->t_vsync_ns);
    case FV_LATENCY_STAGE_COUNT: break;
    }
    return 0;
}

static double ms(double ns) { return ns / 1e6; }

fv_result fv_latency_summarize(const fv_latency_record *records, size_t n, fv_latency_summary *out)
{
    if (!out || (n && !records)) return FV_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    out->frames = n;
    if (n == 0) return FV_OK;
    int64_t *g2p = malloc(n * sizeof *g2p);
    if (!g2p) {
        FV_ERROR("latency", "out of memory summarizing %zu frames", n);
        return FV_ERR_NO_MEMORY;
    }
    size_t m = 0;
    double sum = 0.0, stage_sum[FV_LATENCY_STAGE_COUNT] = {0};
    for (size_t i = 0; i < n; i++) {
        const fv_latency_record *r = &records[i];
        if (r->late) out->late_frames++;
        out->repeated_vsyncs += r->repeated_vsyncs;
        if (r->device_lost) out->lost_frames++;
        if (!r->has_gaze) continue;
        if (!r->fresh_gaze) out->stale_frames++;
        int64_t v = fv_latency_gaze_to_photon_ns(r);
        g2p[m++] = v;
        sum += (double)v;
        for (int s = 0; s < FV_LATENCY_STAGE_COUNT; s++)
            stage_sum[s] += (double)fv_latency_stage_ns(r, (fv_latency_stage)s);
    }
    out->missed = out->late_frames + out->repeated_vsyncs;
    out->frames_with_gaze = m;
    if (n >= 2) {
        double span = (double)fv_i64_sub_sat(records[n - 1].t_vsync_ns, records[0].t_vsync_ns);
        out->frame_interval_mean_ms = ms(span / (double)(n - 1));
    }
    if (m) {
        out->g2p_mean_ms = ms(sum / (double)m);
        out->g2p_p50_ms = ms((double)fv_percentile_i64(g2p, m, 50.0));
        out->g2p_p95_ms = ms((double)fv_percentile_i64(g2p, m, 95.0));
        out->g2p_p99_ms = ms((double)fv_percentile_i64(g2p, m, 99.0));
        out->g2p_min_ms = ms((double)g2p[0]); /* sorted by the percentile calls */
        out->g2p_max_ms = ms((double)g2p[m - 1]);
        for (int s = 0; s < FV_LATENCY_STAGE_COUNT; s++) {
            out->stage_mean_ms[s] = ms(stage_sum[s] / (double)m);
            out->stage_share[s] = sum != 0.0 ? stage_sum[s] / sum : 0.0;
        }
    }
    free(g2p);
    return FV_OK;
}
