/* @brief Helpers shared by the HID tests: load a hex file from the shared data, find a labelled synthetic report. */
#ifndef HID_TEST_UTIL_H
#define HID_TEST_UTIL_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_hid_descriptor.h"
#include "fv_test.h"

/** Read a whole text file (NUL-terminated, caller frees). Fails the test when missing. */
static inline char *hid_test_read_text(const char *path, size_t *out_len) { return fv_test_read_file(path, out_len); }

/** Load "hid/<name>" (hex text) into bytes. */
static inline size_t hid_test_load_hex(const char *name, uint8_t *out, size_t cap)
{
    char rel[256];
    snprintf(rel, sizeof rel, "hid/%s", name);
    size_t len;
    char *text = hid_test_read_text(fv_test_data(rel), &len);
    size_t n = 0;
    assert_int_equal(fv_hid_hex_decode(rel, text, len, out, cap, &n), FV_OK);
    free(text);
    return n;
}

/** The bytes of one labelled line of SYNTHETIC-eye-tracker-reports.txt ("label (N bytes): hex..."). */
static inline size_t hid_test_synthetic(const char *label, uint8_t *out, size_t cap)
{
    char *text = hid_test_read_text(fv_test_data("hid/SYNTHETIC-eye-tracker-reports.txt"), NULL);
    size_t n = 0;
    size_t lab = strlen(label);
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        if (strncmp(line, label, lab) != 0 || (line[lab] != ' ' && line[lab] != ':')) continue;
        char *colon = strchr(line, ':');
        assert_non_null(colon);
        assert_int_equal(fv_hid_hex_decode(label, colon + 1, strlen(colon + 1), out, cap, &n), FV_OK);
        free(text);
        return n;
    }
    free(text);
    fail_msg("no synthetic report labelled %s", label);
    return 0;
}

#endif
