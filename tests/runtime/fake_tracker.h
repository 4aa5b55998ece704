/* @brief A scriptable fake eye tracker for runtime and latency tests: samples at a fixed rate on an injected clock
 * (device timeline = host timeline, so the true capture time of each sample is known), a tracker latency, and
 * scripted misbehaviour: a stall (samples withheld), a disappearance (read fails, re-open refused until a time), a
 * flood (every read returns a full buffer), and a hang (read blocks, ignoring its timeout, until released). */
#ifndef FAKE_TRACKER_H
#define FAKE_TRACKER_H

#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_device.h"

typedef struct fake_tracker {
    /* configuration (set before the first open) */
    const fv_clock *clock;    /* NULL: the device never reads a clock (hang/flood tests with threads) */
    double rate_hz;           /* 0 = 250 */
    int64_t latency_ns;       /* capture -> available to the host */
    int64_t first_capture_ns; /* capture time of sample 0 */
    int64_t stall_from_ns, stall_to_ns; /* samples captured in [from, to) are never sent */
    int64_t lost_at_ns;       /* the first read at or after this time fails with FV_ERR_DEVICE_LOST (0 never) */
    int64_t back_at_ns;       /* after the loss, opens before this time fail with FV_ERR_NOT_FOUND */
    bool flood;               /* every read returns a full buffer of new samples */
    bool end_after_loss;      /* instead of DEVICE_LOST, report END_OF_STREAM at lost_at_ns */
    /* hang control: while `hang` is set, read blocks on the condition variable */
    pthread_mutex_t lock;
    pthread_cond_t cond;
    bool hang;
    bool in_read;
    /* counters */
    int opens, open_failures, closes;
    uint64_t reads;
    uint64_t next_index;
    bool lost_fired;
} fake_tracker;

void fake_tracker_init(fake_tracker *t, const fv_clock *clock, double rate_hz, int64_t latency_ns);
void fake_tracker_fini(fake_tracker *t);
/** Set or clear the hang (wakes a blocked read when cleared). */
void fake_tracker_set_hang(fake_tracker *t, bool hang);
/** True once a read is blocked in the hang. */
bool fake_tracker_in_read(fake_tracker *t);
/** fv_gaze_source_open_fn: user is the fake_tracker. */
fv_result fake_tracker_open(void *user, const char *uri, const fv_device_open_desc *desc, fv_device **out_dev);
/** Capture time of sample i. */
int64_t fake_tracker_capture_ns(const fake_tracker *t, uint64_t i);

#endif
