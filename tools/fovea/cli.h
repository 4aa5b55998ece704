/* @brief Small helpers shared by the fovea subcommands: usage errors, number parsing, JSON output. */
#ifndef FV_CLI_H
#define FV_CLI_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

typedef struct cJSON cJSON;

/** Exit codes of the fovea command. */
enum {
    FV_EXIT_OK = 0,
    FV_EXIT_FAIL = 1,  /* the command ran and failed (bad file, device error) */
    FV_EXIT_USAGE = 2, /* bad command line */
};

/** Print "fovea CMD: <message>" and the usage to stderr; returns FV_EXIT_USAGE. */
int fv_cli_usage_error(const char *cmd, const char *usage, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/** Parse a whole string as an integer in [lo, hi] ("1000000000" or "1e9": digits, then optionally e and an exponent
 *  0..18); false on junk, overflow or out of range. */
bool fv_cli_parse_i64(const char *s, int64_t lo, int64_t hi, int64_t *out);
/** Parse a whole string as a finite double in [lo, hi]. */
bool fv_cli_parse_f64(const char *s, double lo, double hi, double *out);
/** Parse "WxH" with each in [1, max]. */
bool fv_cli_parse_size(const char *s, uint32_t max, uint32_t *out_w, uint32_t *out_h);
/** Parse "A,B" as two finite numbers, each in [lo, hi]. */
bool fv_cli_parse_f64_pair(const char *s, double lo, double hi, double out[2]);
/** Create a directory and any missing parents (as mkdir -p); true when it exists as a directory afterwards. On
 *  failure errno says why (ENOTDIR: a path component is a file). */
bool fv_cli_make_dirs(const char *dir);
/** The one way a string enters fovea's JSON output (every `--json`, bench.json): a cJSON string of s that is valid
 *  UTF-8 whatever s holds (each byte that does not begin a valid UTF-8 sequence becomes U+FFFD; overlong forms,
 *  surrogates and code points past U+10FFFF are invalid). s NULL gives "". cJSON escapes control characters. */
cJSON *fv_cli_json_string(const char *s);
/** Add fv_cli_json_string(s) to obj under key (a name from fovea's own tables). Returns the item or NULL. */
cJSON *fv_cli_json_add_string(cJSON *obj, const char *key, const char *s);
/** root as JSON text, pretty (tabs) or compact, checked to be valid UTF-8 (a byte that got in any other way is
 *  replaced by the escape \ufffd); free() it. NULL when out of memory. */
char *fv_cli_json_text(const cJSON *root, bool pretty);
/** Print root on stdout as one JSON text and a newline (it stays the caller's). FV_EXIT_OK, or FV_EXIT_FAIL when it
 *  cannot be printed. */
int fv_cli_json_print(const cJSON *root, bool pretty);
/** Read a whole file for command CMD (at most max_bytes; NUL-terminated, free() it). NULL after one message naming
 *  the file: missing, a directory, not a regular file, larger than max_bytes, or a read error. */
char *fv_cli_read_file(const char *cmd, const char *path, size_t max_bytes, size_t *out_len);
/** Add a number to a JSON object, or null when it is not finite (JSON has no inf or NaN: an infinite PSNR, a metric
 *  that does not apply). */
void fv_cli_json_number(cJSON *obj, const char *key, double v);
/** A number for a text table into buf: "-" for NaN (does not apply), "inf"/"-inf", else printf's `fmt`; returns buf. */
const char *fv_cli_format_number(char *buf, size_t size, const char *fmt, double v);
/** Inside an option loop (argc, argv, int i, int r and const char *v in scope): whether argv[i] is option NAME with
 *  a value (1, value in v), not this option (0), or this option without its value (-2, after printing the usage
 *  error for command CMD). */
#define FV_CLI_OPT(cmd, usage, name)                                                                                   \
    ((r = fv_cli_option(argc, argv, &i, name, &v)) < 0                                                                 \
         ? (fv_cli_usage_error(cmd, usage, "option %s needs a value", name), -2)                                       \
         : r)
/** Create an output directory (and its parents) for option OPT of command CMD; false after logging why. */
bool fv_cli_output_dir(const char *cmd, const char *opt, const char *dir);
/** True when argv[i] is "--help" or "-h". */
bool fv_cli_is_help(const char *arg);
/** Option with a value, as "--opt VALUE" or "--opt=VALUE". Returns 0 when argv[*i] is not this option, 1 when it
 *  is (value in *out_value; *i advanced past a separate value), -1 when it is but the value is missing. */
int fv_cli_option(int argc, char **argv, int *i, const char *name, const char **out_value);

#endif
