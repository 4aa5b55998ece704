/* @brief The JSON pre-scan (see fv_json_scan.h). */
#include "fv_json_scan.h"

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

void fv_json_scan_text(const char *json, size_t len, size_t depth_limit, fv_json_scan *out)
{
    *out = (fv_json_scan){1, 0, SIZE_MAX, SIZE_MAX, 0, SIZE_MAX};
    size_t depth = 0, string_at = 0;
    bool in_string = false;
    for (size_t i = 0; i < len; i++) {
        char ch = json[i];
        if (in_string) {
            if (ch == '\\') {
                if (i + 5 < len && json[i + 1] == 'u' && !memcmp(json + i + 2, "0000", 4)) {
                    if (out->nul_at == SIZE_MAX) out->nul_at = i;
                    out->nul_count++;
                }
                i++; /* the escaped character */
            } else if (ch == '"') {
                in_string = false;
            }
            continue;
        }
        if (ch == '"') {
            in_string = true;
            string_at = i;
        } else if (ch == '[' || ch == '{') {
            out->values++;
            if (++depth > out->depth) out->depth = depth;
            if (depth > depth_limit && out->too_deep_at == SIZE_MAX) out->too_deep_at = i;
        } else if (ch == ']' || ch == '}') {
            if (depth) depth--;
        } else if (ch == ',') {
            out->values++;
        }
    }
    if (in_string) out->open_string_at = string_at;
}

void fv_text_line_col(const char *text, size_t off, int *line, int *col)
{
    *line = 1;
    *col = 1;
    for (size_t i = 0; i < off; i++) {
        if (text[i] == '\n') {
            (*line)++;
            *col = 1;
        } else {
            (*col)++;
        }
    }
}
