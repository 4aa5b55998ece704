/* @brief fv_ring: FIFO order, wrap-around, both overrun policies, argument checks, and a two-thread stress test that
 * checks order, integrity (no torn elements) and that every element is either delivered or counted as an overrun. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <string.h>

#include "fv_ring.h"
#include "fv_test.h"

typedef struct elem {
    uint64_t seq;
    uint64_t check; /* a function of seq: a torn copy would not match */
    uint8_t pad[112];
} elem;

static uint64_t check_of(uint64_t seq) { return seq * UINT64_C(0x9E3779B97F4A7C15) ^ UINT64_C(0xD1B54A32D192ED03); }

static elem make(uint64_t seq)
{
    elem e;
    e.seq = seq;
    e.check = check_of(seq);
    memset(e.pad, (int)(seq & 0xff), sizeof e.pad);
    return e;
}

static void ring_pops_in_fifo_order_across_wraparound(void **state)
{
    (void)state;
    fv_ring *r = NULL;
    assert_int_equal(fv_ring_create(sizeof(elem), 4, FV_RING_DROP_OLDEST, &r), FV_OK);
    assert_int_equal(fv_ring_capacity(r), 4);
    uint64_t next_in = 0, next_out = 0;
    for (int round = 0; round < 10; round++) {
        for (int k = 0; k < 3; k++) {
            elem e = make(next_in++);
            assert_int_equal(fv_ring_push(r, &e), FV_OK);
        }
        assert_int_equal(fv_ring_count(r), 3);
        elem out;
        while (fv_ring_pop(r, &out) == FV_OK) {
            assert_int_equal(out.seq, next_out);
            assert_int_equal(out.check, check_of(next_out));
            next_out++;
        }
    }
    assert_int_equal(next_out, 30);
    assert_int_equal(fv_ring_overruns(r), 0);
    assert_int_equal(fv_ring_pushed(r), 30);
    elem out;
    assert_int_equal(fv_ring_pop(r, &out), FV_NO_NEW_DATA);
    fv_ring_destroy(&r);
    assert_null(r);
}

static void full_ring_drops_oldest_and_keeps_newest(void **state)
{
    (void)state;
    fv_ring *r = NULL;
    assert_int_equal(fv_ring_create(sizeof(elem), 8, FV_RING_DROP_OLDEST, &r), FV_OK);
    for (uint64_t i = 0; i < 8; i++) {
        elem e = make(i);
        assert_int_equal(fv_ring_push(r, &e), FV_OK);
    }
    for (uint64_t i = 8; i < 20; i++) {
        elem e = make(i);
        assert_int_equal(fv_ring_push(r, &e), FV_NO_NEW_DATA); /* stored, but an old one was lost */
    }
    assert_int_equal(fv_ring_overruns(r), 12);
    assert_int_equal(fv_ring_count(r), 8);
    elem out;
    for (uint64_t want = 12; want < 20; want++) {
        assert_int_equal(fv_ring_pop(r, &out), FV_OK);
        assert_int_equal(out.seq, want);
    }
    assert_int_equal(fv_ring_pop(r, &out), FV_NO_NEW_DATA);
    fv_ring_destroy(&r);
}

static void full_ring_drops_newest_under_that_policy(void **state)
{
    (void)state;
    fv_ring *r = NULL;
    assert_int_equal(fv_ring_create(sizeof(elem), 3, FV_RING_DROP_NEWEST, &r), FV_OK);
    assert_int_equal(fv_ring_capacity(r), 4); /* rounded to a power of two */
    for (uint64_t i = 0; i < 6; i++) {
        elem e = make(i);
        assert_int_equal(fv_ring_push(r, &e), i < 4 ? FV_OK : FV_NO_NEW_DATA);
    }
    assert_int_equal(fv_ring_overruns(r), 2);
    elem out;
    for (uint64_t want = 0; want < 4; want++) {
        assert_int_equal(fv_ring_pop(r, &out), FV_OK);
        assert_int_equal(out.seq, want);
    }
    fv_ring_destroy(&r);
}

static void create_rejects_bad_arguments_with_a_reason(void **state)
{
    (void)state;
    fv_ring *r = (fv_ring *)&r;
    fv_test_log_capture_begin();
    assert_int_equal(fv_ring_create(0, 8, FV_RING_DROP_OLDEST, &r), FV_ERR_INVALID_ARG);
    assert_null(r);
    assert_int_equal(fv_ring_create(16, 0, FV_RING_DROP_OLDEST, &r), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_ring_create(16, ((size_t)1 << 20) + 1, FV_RING_DROP_OLDEST, &r), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_ring_create(16, 8, (fv_ring_policy)7, &r), FV_ERR_INVALID_ARG);
    fv_test_log_capture_end();
    fv_assert_log_contains("element size 0");
    fv_assert_log_contains("capacity 0");
    fv_assert_log_contains("overrun policy 7");
    fv_ring_destroy(&r); /* NULL: no-op */
}

typedef struct stress {
    fv_ring *ring;
    uint64_t n;
    atomic_int done;
} stress;

static void *producer(void *arg)
{
    stress *s = arg;
    for (uint64_t i = 0; i < s->n; i++) {
        elem e = make(i);
        fv_result res = fv_ring_push(s->ring, &e);
        (void)res; /* overruns are counted by the ring */
    }
    atomic_store(&s->done, 1);
    return NULL;
}

static void run_stress(fv_ring_policy policy, size_t capacity, uint64_t n)
{
    stress s = {.n = n};
    atomic_init(&s.done, 0);
    assert_int_equal(fv_ring_create(sizeof(elem), capacity, policy, &s.ring), FV_OK);
    pthread_t th;
    assert_int_equal(pthread_create(&th, NULL, producer, &s), 0);
    uint64_t popped = 0, last = 0;
    int have_last = 0;
    for (;;) {
        elem out;
        if (fv_ring_pop(s.ring, &out) == FV_OK) {
            assert_true(out.seq < n);
            assert_int_equal(out.check, check_of(out.seq));
            assert_int_equal(out.pad[0], (uint8_t)(out.seq & 0xff));
            assert_int_equal(out.pad[sizeof out.pad - 1], (uint8_t)(out.seq & 0xff));
            if (have_last) assert_true(out.seq > last); /* strictly increasing: order kept, no duplicates */
            last = out.seq;
            have_last = 1;
            popped++;
            /* consume in bursts so the ring really fills and both overrun paths run */
            if ((popped & 1023) == 0)
                for (volatile int k = 0; k < 20000; k++) {
                }
        } else if (atomic_load(&s.done)) {
            if (fv_ring_pop(s.ring, &out) == FV_OK) { /* a last element may have landed after our empty check */
                assert_int_equal(out.check, check_of(out.seq));
                assert_true(!have_last || out.seq > last);
                last = out.seq;
                popped++;
                continue;
            }
            break;
        }
    }
    pthread_join(th, NULL);
    /* every element was either delivered or counted lost */
    assert_int_equal(popped + fv_ring_overruns(s.ring), n);
    assert_true(popped > 0);
    print_message("policy %d capacity %zu: %llu delivered, %llu overruns\n", (int)policy, capacity,
                  (unsigned long long)popped, (unsigned long long)fv_ring_overruns(s.ring));
    fv_ring_destroy(&s.ring);
}

static void two_threads_deliver_in_order_without_loss_or_tearing(void **state)
{
    (void)state;
    run_stress(FV_RING_DROP_OLDEST, 64, 400000);
    run_stress(FV_RING_DROP_NEWEST, 64, 400000);
    run_stress(FV_RING_DROP_OLDEST, 2, 200000); /* tiny ring: the drop path races the consumer constantly */
}

static void drop_oldest_delivers_the_last_element_pushed(void **state)
{
    (void)state;
    /* Under DROP_OLDEST the newest element always survives: after the producer finishes, the last element the
     * consumer sees is the last one pushed (unless the consumer was mid-copy of that very slot, which a single
     * thread cannot produce). */
    fv_ring *r = NULL;
    assert_int_equal(fv_ring_create(sizeof(elem), 16, FV_RING_DROP_OLDEST, &r), FV_OK);
    for (uint64_t i = 0; i < 1000; i++) {
        elem e = make(i);
        fv_result res = fv_ring_push(r, &e);
        assert_int_equal(res, i < 16 ? FV_OK : FV_NO_NEW_DATA);
    }
    elem out, last = {0};
    while (fv_ring_pop(r, &out) == FV_OK) last = out;
    assert_int_equal(last.seq, 999);
    fv_ring_destroy(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ring_pops_in_fifo_order_across_wraparound),
        cmocka_unit_test(full_ring_drops_oldest_and_keeps_newest),
        cmocka_unit_test(full_ring_drops_newest_under_that_policy),
        cmocka_unit_test(create_rejects_bad_arguments_with_a_reason),
        cmocka_unit_test(two_threads_deliver_in_order_without_loss_or_tearing),
        cmocka_unit_test(drop_oldest_delivers_the_last_element_pushed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
