/* @brief Gaze sources: samples flow in order through the ring (inline and threaded), a lost device is reported and
 * re-opened on an exponential backoff, a source faster than a ring per poll is read dry with the stale rest counted,
 * a flooding device is bounded, a hung device never blocks the consumer, and a bad first open fails with the
 * driver's error unless the source may start lost. */
#include <stdatomic.h>
#include <string.h>

#include "fake_tracker.h"
#include "fv_gaze_source.h"
#include "fv_test.h"

static fv_gaze_source *make_inline(fake_tracker *t, fv_clock *clk, int64_t retry_min, int64_t retry_max)
{
    fv_gaze_source_desc d = {.uri = "fake:1", .open = fake_tracker_open, .open_user = t,
                             .mode = FV_GAZE_SOURCE_INLINE, .clock = clk, .retry_min_ns = retry_min,
                             .retry_max_ns = retry_max};
    fv_gaze_source *s = NULL;
    assert_int_equal(fv_gaze_source_create(&d, &s), FV_OK);
    return s;
}

static void inline_source_delivers_every_due_sample_in_order(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, FV_NS_PER_S);
    fake_tracker t;
    fake_tracker_init(&t, &clk, 250.0, 4 * FV_NS_PER_MS);
    fv_gaze_source *s = make_inline(&t, &clk, 0, 0);
    fv_clock_sim_advance(&clk, 100 * FV_NS_PER_MS);
    fv_gaze_source_poll(s);
    fv_gaze_sample g;
    uint64_t n = 0;
    while (fv_gaze_source_pop(s, &g) == FV_OK) {
        assert_int_equal(g.seq, n);
        assert_int_equal(g.t_device_ns, FV_NS_PER_S + (int64_t)n * 4 * FV_NS_PER_MS);
        assert_int_equal(g.t_host_ns, g.t_device_ns + 4 * FV_NS_PER_MS);
        n++;
    }
    assert_int_equal(n, 25); /* captures at 0, 4, .. 96 ms are available by 100 ms with 4 ms latency */
    fv_gaze_source_status st;
    fv_gaze_source_get_status(s, &st);
    assert_int_equal(st.state, FV_GAZE_SOURCE_CONNECTED);
    assert_int_equal(st.samples, 25);
    assert_int_equal(st.overruns, 0);
    fv_gaze_source_destroy(&s);
    assert_null(s);
    assert_int_equal(t.closes, 1);
    fake_tracker_fini(&t);
}

static void lost_device_is_reopened_on_an_exponential_backoff(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fake_tracker t;
    fake_tracker_init(&t, &clk, 250.0, 0);
    t.lost_at_ns = 50 * FV_NS_PER_MS;
    t.back_at_ns = 300 * FV_NS_PER_MS;
    fv_gaze_source *s = make_inline(&t, &clk, 20 * FV_NS_PER_MS, 160 * FV_NS_PER_MS);
    fv_test_log_capture_begin();
    int64_t lost_seen = -1, back_seen = -1;
    uint64_t failures_at_back = 0;
    for (int64_t ms = 0; ms <= 500; ms += 5) {
        clk.sim_now_ns = ms * FV_NS_PER_MS;
        fv_gaze_source_poll(s);
        fv_gaze_sample g;
        while (fv_gaze_source_pop(s, &g) == FV_OK) {
        }
        fv_gaze_source_status st;
        fv_gaze_source_get_status(s, &st);
        if (st.state == FV_GAZE_SOURCE_LOST && lost_seen < 0) lost_seen = ms;
        if (lost_seen >= 0 && st.state == FV_GAZE_SOURCE_CONNECTED && back_seen < 0) {
            back_seen = ms;
            failures_at_back = st.open_failures;
        }
    }
    fv_test_log_capture_end();
    assert_int_equal(lost_seen, 50);
    /* retries at 70 (20 ms), 110 (+40), 190 (+80): refused; 350 (+160, capped): back */
    assert_int_equal(failures_at_back, 3);
    assert_int_equal(back_seen, 350);
    fv_gaze_source_status st;
    fv_gaze_source_get_status(s, &st);
    assert_int_equal(st.losses, 1);
    assert_int_equal(st.reopens, 1);
    assert_int_equal(t.opens, 2);
    assert_int_equal(t.closes, 1); /* the lost device was closed */
    fv_assert_log_contains("fake:1: device lost (FV_ERR_DEVICE_LOST)");
    fv_gaze_source_destroy(&s);
    fake_tracker_fini(&t);
}

/* A hotplug arrival cuts the backoff short: the device is re-opened at the next poll, not at the next retry. */
static void reprobe_reopens_a_lost_device_without_waiting_out_the_backoff(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fake_tracker t;
    fake_tracker_init(&t, &clk, 250.0, 0);
    t.lost_at_ns = 50 * FV_NS_PER_MS;
    t.back_at_ns = 100 * FV_NS_PER_MS;
    fv_gaze_source *s = make_inline(&t, &clk, 400 * FV_NS_PER_MS, 800 * FV_NS_PER_MS);
    fv_test_log_capture_begin();
    fv_gaze_source_status st;
    clk.sim_now_ns = 50 * FV_NS_PER_MS;
    fv_gaze_source_poll(s);
    fv_gaze_source_get_status(s, &st);
    assert_int_equal(st.state, FV_GAZE_SOURCE_LOST); /* next retry would be at 450 ms */
    fv_gaze_source_reprobe(s); /* still unplugged: one refused re-open, then the backoff starts over */
    clk.sim_now_ns = 60 * FV_NS_PER_MS;
    fv_gaze_source_poll(s);
    fv_gaze_source_get_status(s, &st);
    assert_int_equal(st.state, FV_GAZE_SOURCE_LOST);
    assert_int_equal(st.open_failures, 1);
    clk.sim_now_ns = 120 * FV_NS_PER_MS; /* plugged back in at 100 ms; the hotplug callback fires */
    fv_gaze_source_poll(s);
    fv_gaze_source_get_status(s, &st);
    assert_int_equal(st.state, FV_GAZE_SOURCE_LOST); /* without a reprobe it waits for its retry */
    fv_gaze_source_reprobe(s);
    fv_gaze_source_poll(s);
    fv_gaze_source_get_status(s, &st);
    assert_int_equal(st.state, FV_GAZE_SOURCE_CONNECTED);
    assert_int_equal(st.reopens, 1);
    fv_gaze_source_reprobe(s); /* connected: no effect */
    fv_gaze_source_poll(s);
    assert_int_equal(t.opens, 2);
    fv_test_log_capture_end();
    fv_gaze_source_destroy(&s);
    fake_tracker_fini(&t);
}

static void end_of_stream_ends_the_source_without_retrying(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fake_tracker t;
    fake_tracker_init(&t, &clk, 100.0, 0);
    t.lost_at_ns = 30 * FV_NS_PER_MS;
    t.end_after_loss = true;
    fv_gaze_source *s = make_inline(&t, &clk, FV_NS_PER_MS, FV_NS_PER_MS);
    for (int ms = 0; ms < 200; ms += 10) {
        clk.sim_now_ns = ms * FV_NS_PER_MS;
        fv_gaze_source_poll(s);
    }
    fv_gaze_source_status st;
    fv_gaze_source_get_status(s, &st);
    assert_int_equal(st.state, FV_GAZE_SOURCE_ENDED);
    assert_int_equal(t.opens, 1);
    assert_int_equal(st.samples, 3); /* 0, 10, 20 ms */
    fv_gaze_source_destroy(&s);
    fake_tracker_fini(&t);
}

/* A source faster than a ring per poll: each poll reads everything due (nothing waits in the driver), the ring keeps
 * the newest, and what it dropped is counted: read = delivered + dropped. */
static void fast_device_is_read_dry_each_poll_and_the_stale_rest_is_counted(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, FV_NS_PER_S);
    fake_tracker t;
    fake_tracker_init(&t, &clk, 1200.0, 4 * FV_NS_PER_MS);
    fv_gaze_source *s = make_inline(&t, &clk, 0, 0);
    uint64_t popped = 0;
    for (int frame = 1; frame <= 30; frame++) {
        clk.sim_now_ns = FV_NS_PER_S + frame * FV_NS_PER_S; /* a 1 Hz consumer: 1200 samples per poll */
        fv_gaze_source_poll(s);
        /* nothing due is left in the driver */
        assert_true(fake_tracker_capture_ns(&t, t.next_index) + t.latency_ns > clk.sim_now_ns);
        fv_gaze_sample g, last = {0};
        uint64_t n = 0;
        while (fv_gaze_source_pop(s, &g) == FV_OK) {
            if (n) assert_int_equal(g.seq, last.seq + 1);
            last = g;
            n++;
        }
        popped += n;
        assert_int_equal(n, 512);                 /* the ring's worth, the newest ones */
        assert_int_equal(last.seq, t.next_index - 1); /* the newest due sample reached the consumer */
        assert_true(clk.sim_now_ns - last.t_host_ns < (int64_t)(FV_NS_PER_S / 1200) + 1);
        fv_gaze_source_status st;
        fv_gaze_source_get_status(s, &st);
        assert_int_equal(st.samples, t.next_index);
        assert_int_equal(st.samples, popped + st.overruns); /* every sample read was delivered or counted */
        assert_int_equal(st.delivered, popped);
        assert_int_equal(st.queued, 0);
        assert_int_equal(st.poll_limited, 0);
    }
    fv_gaze_source_destroy(&s);
    fake_tracker_fini(&t);
}

static void flooding_device_is_bounded_per_poll_and_keeps_the_newest(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fake_tracker t;
    fake_tracker_init(&t, &clk, 250.0, 0);
    t.flood = true;
    fv_gaze_source_desc d = {.uri = "fake:flood", .open = fake_tracker_open, .open_user = &t,
                             .mode = FV_GAZE_SOURCE_INLINE, .clock = &clk, .ring_capacity = 64, .read_batch = 48,
                             .poll_max_samples = 200};
    fv_gaze_source *s = NULL;
    assert_int_equal(fv_gaze_source_create(&d, &s), FV_OK);
    fv_test_log_capture_begin();
    fv_gaze_source_poll(s); /* returns although the device never runs dry */
    fv_gaze_source_status st;
    fv_gaze_source_get_status(s, &st);
    assert_int_equal(st.samples, 240); /* five batches reach the 200-sample limit */
    assert_int_equal(st.overruns, 176);
    assert_int_equal(st.poll_limited, 1);
    fv_gaze_sample g, last;
    size_t n = 0;
    while (fv_gaze_source_pop(s, &g) == FV_OK) {
        last = g;
        n++;
    }
    assert_int_equal(n, 64);
    assert_int_equal(last.seq, 239); /* the newest survived */
    fv_gaze_source_poll(s);
    fv_test_log_capture_end();
    fv_gaze_source_get_status(s, &st);
    assert_int_equal(st.poll_limited, 2);
    assert_int_equal(st.samples, st.delivered + st.overruns + st.queued);
    const char *log = fv_test_log_text();
    const char *needle = "fake:flood: still delivering after 240 samples in one poll";
    const char *hit = strstr(log, needle);
    assert_non_null(hit);
    assert_null(strstr(hit + strlen(needle), "still delivering")); /* reported once */
    fv_gaze_source_destroy(&s);
    fake_tracker_fini(&t);
}

static void failed_first_open_fails_create_unless_allowed_to_start_lost(void **state)
{
    (void)state;
    fv_clock clk;
    fv_clock_sim_init(&clk, 0);
    fake_tracker t;
    fake_tracker_init(&t, &clk, 250.0, 0);
    t.lost_fired = true; /* refuse opens until back_at */
    t.back_at_ns = 100 * FV_NS_PER_MS;
    fv_gaze_source_desc d = {.uri = "fake:late", .open = fake_tracker_open, .open_user = &t,
                             .mode = FV_GAZE_SOURCE_INLINE, .clock = &clk, .retry_min_ns = 30 * FV_NS_PER_MS};
    fv_gaze_source *s = (fv_gaze_source *)&s;
    assert_int_equal(fv_gaze_source_create(&d, &s), FV_ERR_NOT_FOUND);
    assert_null(s);
    d.start_lost = true;
    fv_test_log_capture_begin();
    assert_int_equal(fv_gaze_source_create(&d, &s), FV_OK);
    fv_test_log_capture_end();
    fv_assert_log_contains("fake:late: not available yet (FV_ERR_NOT_FOUND)");
    fv_gaze_source_status st;
    for (int ms = 0; ms <= 300; ms += 10) {
        clk.sim_now_ns = ms * FV_NS_PER_MS;
        fv_gaze_source_poll(s);
    }
    fv_gaze_source_get_status(s, &st);
    assert_int_equal(st.state, FV_GAZE_SOURCE_CONNECTED);
    assert_int_equal(st.reopens, 1);
    fv_gaze_source_destroy(&s);
    /* no URI, no open: clear errors */
    fv_test_log_capture_begin();
    fv_gaze_source_desc bad = {0};
    assert_int_equal(fv_gaze_source_create(&bad, &s), FV_ERR_INVALID_ARG);
    bad.uri = "x:1";
    assert_int_equal(fv_gaze_source_create(&bad, &s), FV_ERR_INVALID_ARG);
    bad.open = fake_tracker_open;
    bad.mode = FV_GAZE_SOURCE_INLINE;
    assert_int_equal(fv_gaze_source_create(&bad, &s), FV_ERR_INVALID_ARG);
    fv_test_log_capture_end();
    fv_assert_log_contains("a URI is required");
    fv_assert_log_contains("x:1: neither an open function nor an open device");
    fv_assert_log_contains("inline mode needs a clock");
    fake_tracker_fini(&t);
}

/* ---- threaded ---- */

static bool wait_for(bool (*cond)(void *), void *arg)
{
    int64_t deadline = fv_time_monotonic_ns() + 10 * FV_NS_PER_S;
    while (fv_time_monotonic_ns() < deadline) {
        if (cond(arg)) return true;
        fv_clock_monotonic()->sleep_until_ns(fv_clock_monotonic(), fv_time_monotonic_ns() + FV_NS_PER_MS);
    }
    return false;
}

typedef struct drain_ctx {
    fv_gaze_source *s;
    uint64_t popped, last_seq;
    uint64_t want;
    bool in_order;
} drain_ctx;

static bool drained_enough(void *arg)
{
    drain_ctx *c = arg;
    fv_gaze_sample g;
    while (fv_gaze_source_pop(c->s, &g) == FV_OK) {
        if (c->popped && g.seq <= c->last_seq) c->in_order = false;
        c->last_seq = g.seq;
        c->popped++;
    }
    return c->popped >= c->want;
}

static void reader_thread_delivers_samples_in_order(void **state)
{
    (void)state;
    fake_tracker t;
    fake_tracker_init(&t, fv_clock_monotonic(), 1000.0, 0);
    fv_gaze_source_desc d = {.uri = "fake:thread", .open = fake_tracker_open, .open_user = &t,
                             .read_timeout_ms = 2};
    fv_gaze_source *s = NULL;
    assert_int_equal(fv_gaze_source_create(&d, &s), FV_OK);
    drain_ctx c = {.s = s, .want = 50, .in_order = true};
    assert_true(wait_for(drained_enough, &c));
    assert_true(c.in_order);
    fv_gaze_source_destroy(&s);
    assert_int_equal(t.closes, 1);
    fake_tracker_fini(&t);
}

typedef struct reopen_ctx {
    fv_gaze_source *s;
    drain_ctx drain;
} reopen_ctx;

static bool reopened_and_flowing(void *arg)
{
    reopen_ctx *c = arg;
    fv_gaze_source_status st;
    fv_gaze_source_get_status(c->s, &st);
    if (st.reopens < 1) {
        drained_enough(&c->drain);
        c->drain.want = c->drain.popped + 20; /* after the re-open, 20 more */
        return false;
    }
    return drained_enough(&c->drain);
}

static void reader_thread_reopens_a_device_that_disappears(void **state)
{
    (void)state;
    fake_tracker t;
    const fv_clock *mono = fv_clock_monotonic();
    fake_tracker_init(&t, mono, 1000.0, 0);
    t.lost_at_ns = fv_clock_now_ns(mono) + 20 * FV_NS_PER_MS;
    t.back_at_ns = t.lost_at_ns + 40 * FV_NS_PER_MS;
    fv_gaze_source_desc d = {.uri = "fake:unplug", .open = fake_tracker_open, .open_user = &t,
                             .read_timeout_ms = 2, .retry_min_ns = 5 * FV_NS_PER_MS,
                             .retry_max_ns = 10 * FV_NS_PER_MS};
    fv_gaze_source *s = NULL;
    fv_test_log_capture_begin();
    assert_int_equal(fv_gaze_source_create(&d, &s), FV_OK);
    reopen_ctx c = {.s = s, .drain = {.s = s, .want = UINT64_MAX, .in_order = true}};
    assert_true(wait_for(reopened_and_flowing, &c));
    fv_gaze_source_status st;
    fv_gaze_source_get_status(s, &st);
    fv_gaze_source_destroy(&s); /* joins the thread before we read the tracker's counters */
    fv_test_log_capture_end();
    assert_int_equal(st.losses, 1);
    assert_int_equal(st.reopens, 1);
    assert_true(st.open_failures >= 1); /* refused at least once while "unplugged" */
    assert_true(c.drain.in_order);
    assert_int_equal(t.opens, 2);
    assert_int_equal(t.closes, 2);
    fv_assert_log_contains("fake:unplug: device lost");
    fake_tracker_fini(&t);
}

static bool is_in_read(void *arg) { return fake_tracker_in_read(arg); }

static void hung_device_never_blocks_the_consumer(void **state)
{
    (void)state;
    fake_tracker t;
    fake_tracker_init(&t, NULL, 250.0, 0);
    t.hang = true;
    fv_gaze_source_desc d = {.uri = "fake:hang", .open = fake_tracker_open, .open_user = &t, .read_timeout_ms = 1};
    fv_gaze_source *s = NULL;
    assert_int_equal(fv_gaze_source_create(&d, &s), FV_OK);
    assert_true(wait_for(is_in_read, &t)); /* the reader is now stuck inside the driver */
    int64_t t0 = fv_time_monotonic_ns();
    fv_gaze_sample g;
    for (int i = 0; i < 100000; i++) assert_int_equal(fv_gaze_source_pop(s, &g), FV_NO_NEW_DATA);
    fv_gaze_source_status st;
    fv_gaze_source_get_status(s, &st);
    assert_int_equal(st.state, FV_GAZE_SOURCE_CONNECTED);
    assert_true(fv_time_monotonic_ns() - t0 < 5 * FV_NS_PER_S); /* the pops returned at once, not after the read */
    fake_tracker_set_hang(&t, false); /* let destroy join */
    fv_gaze_source_destroy(&s);
    fake_tracker_fini(&t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(inline_source_delivers_every_due_sample_in_order),
        cmocka_unit_test(lost_device_is_reopened_on_an_exponential_backoff),
        cmocka_unit_test(reprobe_reopens_a_lost_device_without_waiting_out_the_backoff),
        cmocka_unit_test(end_of_stream_ends_the_source_without_retrying),
        cmocka_unit_test(fast_device_is_read_dry_each_poll_and_the_stale_rest_is_counted),
        cmocka_unit_test(flooding_device_is_bounded_per_poll_and_keeps_the_newest),
        cmocka_unit_test(failed_first_open_fails_create_unless_allowed_to_start_lost),
        cmocka_unit_test(reader_thread_delivers_samples_in_order),
        cmocka_unit_test(reader_thread_reopens_a_device_that_disappears),
        cmocka_unit_test(hung_device_never_blocks_the_consumer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
