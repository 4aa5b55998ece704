/* @brief Hex text → bytes, for descriptors and reports pasted from dmesg, usbhid-dump or documentation. */
#include <ctype.h>
#include <stddef.h>
#include <stdint.h>

#include "fv_hid_descriptor.h"
#include "fv_log.h"

static int hex_value(char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

fv_result fv_hid_hex_decode(const char *what, const char *text, size_t len, uint8_t *out, size_t cap,
                            size_t *out_len)
{
    return fv_hid_hex_decode_at(what, 1, 1, text, len, out, cap, out_len);
}

fv_result fv_hid_hex_decode_at(const char *what, size_t first_line, size_t first_col, const char *text, size_t len,
                               uint8_t *out, size_t cap, size_t *out_len)
{
    size_t n = 0, line = first_line ? first_line : 1, line_start = 0, col0 = first_col ? first_col - 1 : 0;
    size_t i = 0;
    *out_len = 0;
    while (i < len) {
        char c = text[i];
        if (c == '\n') {
            line++;
            line_start = ++i;
            col0 = 0;
            continue;
        }
        if (c == '#') {
            while (i < len && text[i] != '\n') i++;
            continue;
        }
        if (isspace((unsigned char)c) || c == ',') {
            i++;
            continue;
        }
        if (c == '0' && i + 1 < len && (text[i + 1] == 'x' || text[i + 1] == 'X')) i += 2;
        int hi = i < len ? hex_value(text[i]) : -1;
        int lo = i + 1 < len ? hex_value(text[i + 1]) : -1;
        bool ends = i + 2 >= len || isspace((unsigned char)text[i + 2]) || text[i + 2] == ',' || text[i + 2] == '#';
        if (hi < 0 || lo < 0 || !ends) {
            size_t col = col0 + i - line_start + 1;
            char tok[12]; /* the word found, printable */
            size_t k = 0;
            while (i + k < len && k + 1 < sizeof tok && !isspace((unsigned char)text[i + k]) && text[i + k] != ',' &&
                   text[i + k] != '#') {
                tok[k] = isprint((unsigned char)text[i + k]) ? text[i + k] : '?';
                k++;
            }
            tok[k] = '\0';
            FV_ERROR("hid", "%s:%zu:%zu: expected a two-digit hex byte, found '%s'", what, line, col,
                     k ? tok : "end of text");
            return FV_ERR_PARSE;
        }
        if (n >= cap) {
            FV_ERROR("hid", "%s:%zu: more than %zu bytes", what, line, cap);
            return FV_ERR_RANGE;
        }
        out[n++] = (uint8_t)(hi << 4 | lo);
        i += 2;
    }
    *out_len = n;
    return FV_OK;
}
