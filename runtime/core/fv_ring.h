/* @brief A bounded lock-free ring of fixed-size elements for one producer thread and one consumer thread (C11
 * atomics). Used between a device's reader thread (producer) and the frame loop (consumer) for fv_gaze_sample.
 *
 * When the ring is full the producer either drops the oldest element (FV_RING_DROP_OLDEST, the default: the consumer
 * wants the newest gaze) or the new one (FV_RING_DROP_NEWEST); either way the loss is counted as an overrun and the
 * producer never waits for the consumer. Each slot carries a sequence number (the bounded-queue scheme of D. Vyukov),
 * so a slot's bytes are only ever touched by the side that owns it: no torn reads, no data races. */
#ifndef FV_RING_H
#define FV_RING_H

#include <stddef.h>
#include <stdint.h>

#include "fv_result.h"

typedef enum fv_ring_policy {
    FV_RING_DROP_OLDEST = 0, /* full: discard the oldest unread element to make room (counted as an overrun) */
    FV_RING_DROP_NEWEST = 1, /* full: discard the element being pushed (counted as an overrun) */
} fv_ring_policy;

typedef struct fv_ring fv_ring;

/** Create a ring of at least `capacity` elements (rounded up to a power of two, 2 .. 1<<20) of `elem_size` bytes
 *  (1 .. 64 KiB). Not shared until the caller hands it to both threads. */
FV_MUST_CHECK fv_result fv_ring_create(size_t elem_size, size_t capacity, fv_ring_policy policy, fv_ring **out_ring);
/** Destroy and set *ring to NULL; safe on NULL. Neither thread may use the ring any more. */
void fv_ring_destroy(fv_ring **ring);

/** Producer only. Copy one element in. FV_OK when stored without loss; FV_NO_NEW_DATA when the ring was full and an
 *  element was dropped (the oldest under DROP_OLDEST — this one is then stored —, this one under DROP_NEWEST). Never
 *  blocks. */
FV_MUST_CHECK fv_result fv_ring_push(fv_ring *ring, const void *elem);
/** Consumer only. Copy the oldest element out: FV_OK, or FV_NO_NEW_DATA when empty. Never blocks. */
FV_MUST_CHECK fv_result fv_ring_pop(fv_ring *ring, void *out_elem);

/** The rounded capacity (elements). */
size_t fv_ring_capacity(const fv_ring *ring);
/** Elements currently stored (a snapshot; exact only when the other side is idle). */
size_t fv_ring_count(const fv_ring *ring);
/** Elements ever stored by push, and elements lost to overruns (either policy). Any thread. */
uint64_t fv_ring_pushed(const fv_ring *ring);
uint64_t fv_ring_overruns(const fv_ring *ring);

#endif
