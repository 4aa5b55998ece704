/* @brief The one drain of a gaze source into a gaze pipeline (see fv_gaze_drain.h). */
#include "fv_gaze_drain.h"

#include <string.h>

#include "fv_log.h"

void fv_gaze_drain_init(fv_gaze_drain *d, fv_gaze_source *source, fv_gaze_pipeline *pipeline,
                        int64_t stall_timeout_ns, int64_t t_now_ns)
{
    memset(d, 0, sizeof *d);
    d->source = source;
    d->pipeline = pipeline;
    d->stall_timeout_ns = stall_timeout_ns > 0 ? stall_timeout_ns : 100 * FV_NS_PER_MS;
    d->last_new_sample_ns = t_now_ns;
}

static void take(fv_gaze_drain *d, int64_t t_now)
{
    fv_gaze_source *src = d->source;
    fv_gaze_source_poll(src); /* inline sources read here; threaded ones already filled the ring */
    fv_gaze_source_status st;
    fv_gaze_source_get_status(src, &st);
    fv_gaze_sample s;
    for (size_t i = 0; i < st.ring_capacity && fv_gaze_source_pop(src, &s) == FV_OK; i++) {
        fv_result r = fv_gaze_pipeline_push(d->pipeline, &s);
        if (r != FV_OK) {
            if (FV_FAILED(r) && !d->warned_push) {
                FV_WARN("frame", "%s: the gaze pipeline refused sample %llu (%s); further refusals are not logged",
                        fv_gaze_source_uri(src), (unsigned long long)s.seq, fv_result_str(r));
                d->warned_push = true;
            }
            continue; /* duplicates and out-of-order samples are not "newest" */
        }
        int64_t received = (s.flags & FV_GAZE_HOST_TIME_VALID) ? s.t_host_ns : t_now;
        if (received > t_now) {
            if (!d->warned_future_receipt) {
                FV_WARN("frame", "%s: sample received at %lld ns, after the drain's now %lld ns (another clock?); "
                        "using the drain time", fv_gaze_source_uri(src), (long long)received, (long long)t_now);
                d->warned_future_receipt = true;
            }
            received = t_now;
        }
        d->newest = s;
        if (s.flags & FV_GAZE_HEAD_VALID) {
            d->newest_head = s;
            d->have_head = true;
        }
        d->newest_received_ns = received;
        d->have_sample = true;
        d->serial++;
        d->last_new_sample_ns = t_now;
        if (d->on_sample) d->on_sample(d->user, &s);
    }
}

bool fv_gaze_drain_step(fv_gaze_drain *d, int64_t t_now)
{
    take(d, t_now);
    fv_gaze_source_status st;
    fv_gaze_source_get_status(d->source, &st);
    bool lost = st.state != FV_GAZE_SOURCE_CONNECTED || t_now - d->last_new_sample_ns > d->stall_timeout_ns;
    if (lost != d->lost) {
        if (lost)
            FV_WARN("frame", "%s: no gaze (%s%s); widening the uncertainty", fv_gaze_source_uri(d->source),
                    fv_gaze_source_state_str(st.state), st.state == FV_GAZE_SOURCE_CONNECTED ? ", stalled" : "");
        else
            FV_WARN("frame", "%s: gaze back", fv_gaze_source_uri(d->source)); /* pairs with the warning above */
        fv_gaze_pipeline_set_device_lost(d->pipeline, lost, t_now);
        d->lost = lost;
    }
    return lost;
}
