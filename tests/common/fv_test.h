/* @brief Shared test helpers: a recording log sink, shared-data paths, temp files. Used with cmocka. */
#ifndef FV_TEST_H
#define FV_TEST_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <string.h>

#include "fv_log.h"

/** Path of a file under ../shared/data (from $FV_SHARED_DATA_DIR, else the configure-time path). Static buffer
 *  rotated over 8 slots. */
const char *fv_test_data(const char *relative);
/** A fresh path under the test's temp dir ($FV_TEST_TMP), creating the dir. Static buffer rotated over 8 slots. */
const char *fv_test_tmp(const char *name);
/** Write bytes to a temp file and return its path. */
const char *fv_test_write_file(const char *name, const void *data, size_t size);

/** Read a whole file, NUL-terminated (caller frees); *out_len (may be NULL) gets its size. Fails the test when the
 *  file cannot be read. */
char *fv_test_read_file(const char *path, size_t *out_len);

/** Result of running a command: exit code (128 + signal when killed) and captured stdout / stderr (truncated). */
typedef struct fv_test_cmd {
    int exit_code;
    char out[65536];
    char err[65536];
} fv_test_cmd;
/** Run `ENV PROGRAM ARGS` through the shell (env and args may be NULL), stdout and stderr captured separately
 *  through temp files. */
void fv_test_run_cmd(fv_test_cmd *res, const char *env, const char *program, const char *args);
/** A standard normal deviate from the 64-bit LCG state *rng (Knuth's MMIX constants) by Box-Muller: reproducible
 *  noise for tests. */
double fv_test_normal(uint64_t *rng);
/** The first line of s (without its newline), in a static buffer of 1024 bytes (longer lines are cut). */
const char *fv_test_first_line(const char *s);
/** Fail unless `hay` contains `needle`, printing both. */
#define fv_assert_contains(hay, needle)                                                                                \
    do {                                                                                                               \
        if (!strstr((hay), (needle))) fail_msg("expected \"%s\" in:\n%s", (needle), (hay));                         \
    } while (0)

/** Capture log messages (errors and warnings) into a buffer instead of stderr. */
void fv_test_log_capture_begin(void);
void fv_test_log_capture_end(void);
/** Everything captured since begin, one message per line as "level module: message". */
const char *fv_test_log_text(void);
/** Number of captured messages at or above `level` (error=0 is highest). */
int fv_test_log_count(fv_log_level at_most);
/** Captured lines that contain `needle`; with sum (may be NULL), the sum of the counts that follow "... " in them
 *  (the summaries of fv_log_ratelimit: "... N more like this in the last T s; the first: ..."). */
int fv_test_log_lines(const char *needle, unsigned long long *sum);
/** Assert that the captured text contains `needle`. */
#define fv_assert_log_contains(needle)                                                                                 \
    do {                                                                                                               \
        if (!strstr(fv_test_log_text(), (needle)))                                                                     \
            fail_msg("log does not contain \"%s\"; log was:\n%s", (needle), fv_test_log_text());                      \
    } while (0)

#endif
