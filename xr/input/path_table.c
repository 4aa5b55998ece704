/* @brief The per-instance path table: well-formed path rules (OpenXR 1.0, "Well-Formed Path Strings") and the
   bijection between path strings and XrPath atoms (atom = index + 1, never reused during the instance). */
#include <stdlib.h>
#include <string.h>

#include "xr_input_internal.h"

void xri_paths_init(xri_path_table *t, uint32_t max_paths)
{
    memset(t, 0, sizeof *t);
    t->max = max_paths;
}

void xri_paths_fini(xri_path_table *t)
{
    for (uint32_t i = 0; i < t->count; i++) free(t->str[i]);
    free(t->str);
    free(t->len);
    free(t->slot);
    memset(t, 0, sizeof *t);
}

static bool path_char_ok(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.' || c == '/';
}

bool xri_path_well_formed(const char *s, size_t n, const char **why)
{
    if (n == 0 || s[0] != '/') {
        *why = "a path must start with '/'";
        return false;
    }
    if (n + 1 > XR_MAX_PATH_LENGTH) {
        *why = "longer than XR_MAX_PATH_LENGTH (256 bytes with the terminator)";
        return false;
    }
    for (size_t i = 0; i < n; i++) {
        if (!path_char_ok(s[i])) {
            *why = "a character outside a-z 0-9 - _ . /";
            return false;
        }
    }
    if (s[n - 1] == '/') {
        *why = "a path must not end with '/'";
        return false;
    }
    /* Every component between two slashes (and after the last one) must be non-empty ("//") and not made of
       periods only ("/./", "/../", a final "/.."). */
    size_t start = 1;
    for (size_t i = 1; i <= n; i++) {
        if (i < n && s[i] != '/') continue;
        if (i == start) {
            *why = "two adjacent '/'";
            return false;
        }
        bool only_periods = true;
        for (size_t k = start; k < i; k++) only_periods = only_periods && s[k] == '.';
        if (only_periods) {
            *why = "a component made only of '.' characters";
            return false;
        }
        start = i + 1;
    }
    return true;
}

bool xri_name_component_ok(const char *s, const char **why)
{
    bool only_periods = true;
    for (const char *c = s; *c; c++) {
        if (*c == '/' || !path_char_ok(*c)) {
            *why = "a character not allowed in one level of a path (allowed: a-z 0-9 - _ .)";
            return false;
        }
        only_periods = only_periods && *c == '.';
    }
    if (only_periods) {
        *why = "a name made only of '.' characters is not a path level";
        return false;
    }
    return true;
}

static uint32_t hash_str(const char *s, size_t n)
{
    uint32_t h = 2166136261u; /* FNV-1a */
    for (size_t i = 0; i < n; i++) h = (h ^ (uint8_t)s[i]) * 16777619u;
    return h;
}

XrPath xri_paths_find(const xri_path_table *t, const char *s, size_t n)
{
    if (t->slot_cap == 0) return XR_NULL_PATH;
    uint32_t mask = t->slot_cap - 1;
    for (uint32_t i = hash_str(s, n) & mask;; i = (i + 1) & mask) {
        uint32_t p = t->slot[i];
        if (p == 0) return XR_NULL_PATH;
        if (t->len[p - 1] == n && memcmp(t->str[p - 1], s, n) == 0) return p;
    }
}

static bool rehash(xri_path_table *t, uint32_t new_cap)
{
    uint32_t *slot = calloc(new_cap, sizeof *slot);
    if (!slot) return false;
    uint32_t mask = new_cap - 1;
    for (uint32_t p = 1; p <= t->count; p++) {
        uint32_t i = hash_str(t->str[p - 1], t->len[p - 1]) & mask;
        while (slot[i]) i = (i + 1) & mask;
        slot[i] = p;
    }
    free(t->slot);
    t->slot = slot;
    t->slot_cap = new_cap;
    return true;
}

XrResult xri_paths_intern(xri_path_table *t, const char *s, size_t n, XrPath *out)
{
    XrPath found = xri_paths_find(t, s, n);
    if (found != XR_NULL_PATH) {
        *out = found;
        return XR_SUCCESS;
    }
    if (t->count >= t->max) return XR_ERROR_PATH_COUNT_EXCEEDED;
    if (t->count == t->cap) {
        uint32_t cap = t->cap ? t->cap * 2 : 64;
        char **str = realloc(t->str, cap * sizeof *str);
        if (!str) return XR_ERROR_OUT_OF_MEMORY;
        t->str = str;
        uint32_t *len = realloc(t->len, cap * sizeof *len);
        if (!len) return XR_ERROR_OUT_OF_MEMORY;
        t->len = len;
        t->cap = cap;
    }
    if ((uint64_t)(t->count + 1) * 2 > t->slot_cap) {
        if (!rehash(t, t->slot_cap ? t->slot_cap * 2 : 128)) return XR_ERROR_OUT_OF_MEMORY;
    }
    char *copy = malloc(n + 1);
    if (!copy) return XR_ERROR_OUT_OF_MEMORY;
    memcpy(copy, s, n);
    copy[n] = '\0';
    t->str[t->count] = copy;
    t->len[t->count] = (uint32_t)n;
    t->count++;
    XrPath p = t->count;
    uint32_t mask = t->slot_cap - 1;
    uint32_t i = hash_str(s, n) & mask;
    while (t->slot[i]) i = (i + 1) & mask;
    t->slot[i] = (uint32_t)p;
    *out = p;
    return XR_SUCCESS;
}

const char *xri_paths_str(const xri_path_table *t, XrPath p)
{
    if (p == XR_NULL_PATH || p > t->count) return NULL;
    return t->str[p - 1];
}
