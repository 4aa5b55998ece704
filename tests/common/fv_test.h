/* @brief Shared test helpers: a recording log sink, shared-data paths, temp files. Used with cmocka. */
#ifndef FV_TEST_H
#define FV_TEST_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <string.h>
#include <sys/types.h>

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
/** The time limit of a test's child command, in seconds: $FV_TEST_CMD_LIMIT_S, else FV_TEST_CMD_LIMIT_S. A hung
 *  child fails its test case in this time, naming the command, instead of costing the whole test's ctest timeout. */
#define FV_TEST_CMD_LIMIT_S 60.0
double fv_test_cmd_limit_s(void);
/** Run `ENV PROGRAM ARGS` through the shell (env and args may be NULL), stdout and stderr captured separately
 *  through temp files, under fv_test_cmd_limit_s(): past it the command's process group is killed and the test
 *  case fails naming the command. */
void fv_test_run_cmd(fv_test_cmd *res, const char *env, const char *program, const char *args);
/** fv_test_run_cmd with its own limit in seconds (a command known to take longer). */
void fv_test_run_cmd_limit(fv_test_cmd *res, double limit_s, const char *env, const char *program, const char *args);
/** Start argv (argv[0] looked up on PATH) in its own process group, stdin from /dev/null, stdout / stderr into the
 *  files named (NULL: inherited), with no signal blocked or ignored; returns its pid. Pair with fv_test_wait. */
pid_t fv_test_spawn(const char *const argv[], const char *stdout_path, const char *stderr_path);
/** Wait for a child of fv_test_spawn at most limit_s seconds: its exit code (128 + signal when killed). Past the
 *  limit its process group is killed and the test case fails, naming `what` (the command). Whatever else is left
 *  in its group is killed when it ends. With $FV_TEST_CMD_LOG set, appends "seconds<TAB>what" to that file. */
int fv_test_wait(pid_t pid, double limit_s, const char *what);
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
