/* @brief A small open-addressing map from 64-bit handle values to pointers (linear probing, tombstones), so that
   every OpenXR call finds its XrActionSet / XrAction in constant time however many an app creates. */
#include <stdlib.h>

#include "xr_input_internal.h"

#define EMPTY 0u
#define TOMB UINT64_MAX

static uint32_t slot_of(uint64_t key, uint32_t mask)
{
    key ^= key >> 33; /* splitmix64's finaliser: handle values are sequential */
    key *= 0xff51afd7ed558ccdull;
    key ^= key >> 33;
    return (uint32_t)key & mask;
}

static bool grow(xri_map *m)
{
    uint32_t cap = m->cap ? m->cap * 2 : 64;
    if (m->count * 4 < m->cap) cap = m->cap; /* mostly tombstones: rebuild at the same size */
    uint64_t *key = calloc(cap, sizeof *key);
    void **val = calloc(cap, sizeof *val);
    if (!key || !val) {
        free(key);
        free(val);
        return false;
    }
    for (uint32_t i = 0; i < m->cap; i++) {
        if (m->key[i] == EMPTY || m->key[i] == TOMB) continue;
        uint32_t k = slot_of(m->key[i], cap - 1);
        while (key[k] != EMPTY) k = (k + 1) & (cap - 1);
        key[k] = m->key[i];
        val[k] = m->val[i];
    }
    free(m->key);
    free(m->val);
    m->key = key;
    m->val = val;
    m->cap = cap;
    m->used = m->count;
    return true;
}

bool xri_map_put(xri_map *m, uint64_t key, void *val)
{
    if ((m->used + 1) * 4 > m->cap * 3 && !grow(m)) return false;
    uint32_t mask = m->cap - 1;
    uint32_t k = slot_of(key, mask);
    while (m->key[k] != EMPTY && m->key[k] != TOMB && m->key[k] != key) k = (k + 1) & mask;
    if (m->key[k] == key) {
        m->val[k] = val;
        return true;
    }
    if (m->key[k] == EMPTY) m->used++;
    m->key[k] = key;
    m->val[k] = val;
    m->count++;
    return true;
}

static int find(const xri_map *m, uint64_t key)
{
    if (m->cap == 0 || key == EMPTY || key == TOMB) return -1;
    uint32_t mask = m->cap - 1;
    for (uint32_t k = slot_of(key, mask), n = 0; n < m->cap; k = (k + 1) & mask, n++) {
        if (m->key[k] == EMPTY) return -1;
        if (m->key[k] == key) return (int)k;
    }
    return -1;
}

void *xri_map_get(const xri_map *m, uint64_t key)
{
    int k = find(m, key);
    return k < 0 ? NULL : m->val[k];
}

void xri_map_del(xri_map *m, uint64_t key)
{
    int k = find(m, key);
    if (k < 0) return;
    m->key[k] = TOMB;
    m->val[k] = NULL;
    m->count--;
}

void xri_map_fini(xri_map *m)
{
    free(m->key);
    free(m->val);
    *m = (xri_map){0};
}
