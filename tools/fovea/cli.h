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
/** Parse a whole string as an integer in [lo, hi]; false on junk, overflow or out of range. */
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
