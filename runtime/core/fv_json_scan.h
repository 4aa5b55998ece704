/* @brief What a JSON text holds, found in one pass before a parser builds a tree for it: how many values, how deep
 * it nests (cJSON refuses more than CJSON_NESTING_LIMIT levels with no word of why), the first "\u0000" in a string
 * (cJSON cuts the string there, silently) and a string the text ends inside. Every JSON reader checks these first
 * and says which limit the text passes. Pure: no allocation, no parser, thread-safe. */
#ifndef FV_JSON_SCAN_H
#define FV_JSON_SCAN_H

#include <stddef.h>

typedef struct fv_json_scan {
    size_t values;         /* about how many values: one, plus one per '[', '{' and ',' outside strings */
    size_t depth;          /* the deepest nesting of arrays and objects */
    size_t too_deep_at;    /* offset of the bracket that passes depth_limit, or SIZE_MAX */
    size_t nul_at;         /* offset of the first \u0000 escape, or SIZE_MAX */
    size_t nul_count;
    size_t open_string_at; /* offset of the quote of a string the text ends inside, or SIZE_MAX */
} fv_json_scan;

/** Scan len bytes of json (no NUL needed); depth_limit is the parser's (cJSON: CJSON_NESTING_LIMIT). */
void fv_json_scan_text(const char *json, size_t len, size_t depth_limit, fv_json_scan *out);

/** Line and column (1-based) of byte offset off in text (off <= the text's length). */
void fv_text_line_col(const char *text, size_t off, int *line, int *col);

#endif
