/* @brief Bounded lock-free SPSC ring with per-slot sequence numbers (see fv_ring.h).
 *
 * Slot i holds sequence seq[i]. A slot at position pos is free for the producer when seq == pos, holds an unread
 * element when seq == pos + 1, and is free again for the next lap (pos + capacity) once a reader has copied it out.
 * Readers claim a position by CAS on `tail`; there are at most two of them: the consumer, and the producer itself when
 * it discards the oldest element under FV_RING_DROP_OLDEST. Because a slot's bytes are written only between a
 * successful claim and the release store of its sequence, neither side ever reads bytes the other is writing. */
#include "fv_ring.h"

#include <stdalign.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"

#define CACHE_LINE 64
#define RING_MAX_CAPACITY ((size_t)1 << 20)
#define RING_MAX_ELEM ((size_t)64 * 1024)

struct fv_ring {
    /* Producer-owned write position; read by fv_ring_count from anywhere. */
    alignas(CACHE_LINE) _Atomic size_t head;
    /* Read position, claimed by CAS (consumer, or the producer discarding the oldest). Own line: no false sharing
     * with head. */
    alignas(CACHE_LINE) _Atomic size_t tail;
    alignas(CACHE_LINE) _Atomic uint64_t pushed;
    _Atomic uint64_t overruns;
    size_t mask;
    size_t elem_size;
    fv_ring_policy policy;
    _Atomic size_t *seq;
    unsigned char *data;
};

static size_t round_up_pow2(size_t n)
{
    size_t c = 2;
    while (c < n) c <<= 1;
    return c;
}

fv_result fv_ring_create(size_t elem_size, size_t capacity, fv_ring_policy policy, fv_ring **out_ring)
{
    if (!out_ring) return FV_ERR_INVALID_ARG;
    *out_ring = NULL;
    if (elem_size == 0 || elem_size > RING_MAX_ELEM) {
        FV_ERROR("ring", "element size %zu outside 1..%zu bytes", elem_size, RING_MAX_ELEM);
        return FV_ERR_INVALID_ARG;
    }
    if (capacity == 0 || capacity > RING_MAX_CAPACITY) {
        FV_ERROR("ring", "capacity %zu outside 1..%zu elements", capacity, RING_MAX_CAPACITY);
        return FV_ERR_INVALID_ARG;
    }
    if (policy != FV_RING_DROP_OLDEST && policy != FV_RING_DROP_NEWEST) {
        FV_ERROR("ring", "unknown overrun policy %d", (int)policy);
        return FV_ERR_INVALID_ARG;
    }
    size_t cap = round_up_pow2(capacity);
    size_t bytes = (sizeof(fv_ring) + CACHE_LINE - 1) / CACHE_LINE * CACHE_LINE;
    fv_ring *r = aligned_alloc(CACHE_LINE, bytes);
    if (!r) goto fail;
    memset(r, 0, sizeof *r);
    r->seq = malloc(cap * sizeof *r->seq);
    r->data = malloc(cap * elem_size);
    if (!r->seq || !r->data) goto fail;
    for (size_t i = 0; i < cap; i++) atomic_init(&r->seq[i], i);
    atomic_init(&r->head, 0);
    atomic_init(&r->tail, 0);
    atomic_init(&r->pushed, 0);
    atomic_init(&r->overruns, 0);
    r->mask = cap - 1;
    r->elem_size = elem_size;
    r->policy = policy;
    *out_ring = r;
    return FV_OK;
fail:
    FV_ERROR("ring", "out of memory for %zu elements of %zu bytes", cap, elem_size);
    fv_ring_destroy(&r);
    return FV_ERR_NO_MEMORY;
}

void fv_ring_destroy(fv_ring **ring)
{
    if (!ring || !*ring) return;
    free((void *)(*ring)->seq);
    free((*ring)->data);
    free(*ring);
    *ring = NULL;
}

/* Claim the oldest unread position. Returns 1 and the position, or 0 when empty. */
static int claim_oldest(fv_ring *r, size_t *out_pos)
{
    size_t pos = atomic_load_explicit(&r->tail, memory_order_relaxed);
    for (;;) {
        /* acquire: pairs with the producer's release store, so the element bytes are visible once seq says so */
        size_t seq = atomic_load_explicit(&r->seq[pos & r->mask], memory_order_acquire);
        intptr_t dif = (intptr_t)(seq - (pos + 1));
        if (dif == 0) {
            if (atomic_compare_exchange_weak_explicit(&r->tail, &pos, pos + 1, memory_order_relaxed,
                                                      memory_order_relaxed)) {
                *out_pos = pos;
                return 1;
            }
            /* lost the race: pos now holds the current tail */
        } else if (dif < 0) {
            return 0; /* the slot at tail has not been written: empty */
        } else {
            pos = atomic_load_explicit(&r->tail, memory_order_relaxed); /* another reader moved on */
        }
    }
}

/* Hand a claimed slot back to the producer for its next lap. release: our copy-out happens before the producer may
 * overwrite the bytes. */
static void release_slot(fv_ring *r, size_t pos)
{
    atomic_store_explicit(&r->seq[pos & r->mask], pos + r->mask + 1, memory_order_release);
}

/* 1 when the producer's slot at pos is free for writing. */
static int slot_free(fv_ring *r, size_t pos)
{
    return atomic_load_explicit(&r->seq[pos & r->mask], memory_order_acquire) == pos;
}

fv_result fv_ring_push(fv_ring *r, const void *elem)
{
    size_t pos = atomic_load_explicit(&r->head, memory_order_relaxed); /* only this thread writes head */
    fv_result res = FV_OK;
    if (!slot_free(r, pos)) {
        if (r->policy == FV_RING_DROP_NEWEST) {
            atomic_fetch_add_explicit(&r->overruns, 1, memory_order_relaxed);
            return FV_NO_NEW_DATA;
        }
        size_t old;
        if (claim_oldest(r, &old)) { /* discard the oldest without copying it (the consumer may have emptied the
                                        ring since our check, in which case nothing is lost) */
            release_slot(r, old);
            atomic_fetch_add_explicit(&r->overruns, 1, memory_order_relaxed);
            res = FV_NO_NEW_DATA;
        }
        if (!slot_free(r, pos)) {
            /* The consumer is still copying out exactly this slot (it claimed it before our discard, which then
             * took the next-oldest one). Do not wait for it: drop the new element too. */
            atomic_fetch_add_explicit(&r->overruns, 1, memory_order_relaxed);
            return FV_NO_NEW_DATA;
        }
    }
    memcpy(r->data + (pos & r->mask) * r->elem_size, elem, r->elem_size);
    /* release: the bytes above are visible to whoever acquires this sequence */
    atomic_store_explicit(&r->seq[pos & r->mask], pos + 1, memory_order_release);
    atomic_store_explicit(&r->head, pos + 1, memory_order_relaxed);
    atomic_fetch_add_explicit(&r->pushed, 1, memory_order_relaxed);
    return res;
}

fv_result fv_ring_pop(fv_ring *r, void *out_elem)
{
    size_t pos;
    if (!claim_oldest(r, &pos)) return FV_NO_NEW_DATA;
    memcpy(out_elem, r->data + (pos & r->mask) * r->elem_size, r->elem_size);
    release_slot(r, pos);
    return FV_OK;
}

size_t fv_ring_capacity(const fv_ring *r) { return r->mask + 1; }

size_t fv_ring_count(const fv_ring *r)
{
    fv_ring *m = (fv_ring *)r; /* atomic loads need a non-const object in C11 */
    size_t tail = atomic_load_explicit(&m->tail, memory_order_relaxed);
    size_t head = atomic_load_explicit(&m->head, memory_order_relaxed);
    size_t n = head - tail;
    if (n > r->mask + 1) n = (intptr_t)n < 0 ? 0 : r->mask + 1; /* torn snapshot across the two loads */
    return n;
}

uint64_t fv_ring_pushed(const fv_ring *r)
{
    return atomic_load_explicit(&((fv_ring *)r)->pushed, memory_order_relaxed);
}

uint64_t fv_ring_overruns(const fv_ring *r)
{
    return atomic_load_explicit(&((fv_ring *)r)->overruns, memory_order_relaxed);
}
