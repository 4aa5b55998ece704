/* @brief Shared command-line helpers for the fovea subcommands. */
#include "cli.h"

#include "fv_log.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int fv_cli_usage_error(const char *cmd, const char *usage, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "fovea %s: ", cmd);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\n%s", usage);
    va_end(ap);
    return FV_EXIT_USAGE;
}

bool fv_cli_parse_i64(const char *s, int64_t lo, int64_t hi, int64_t *out)
{
    if (!s || !*s) return false;
    char *end = NULL;
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (errno || *end != '\0' || v < lo || v > hi) return false;
    *out = v;
    return true;
}

bool fv_cli_parse_f64(const char *s, double lo, double hi, double *out)
{
    if (!s || !*s) return false;
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || *end != '\0' || !isfinite(v) || v < lo || v > hi) return false;
    *out = v;
    return true;
}

bool fv_cli_parse_size(const char *s, uint32_t max, uint32_t *out_w, uint32_t *out_h)
{
    if (!s) return false;
    const char *x = strchr(s, 'x');
    if (!x || x == s) return false;
    char wbuf[16];
    size_t n = (size_t)(x - s);
    if (n >= sizeof wbuf) return false;
    memcpy(wbuf, s, n);
    wbuf[n] = '\0';
    int64_t w, h;
    if (!fv_cli_parse_i64(wbuf, 1, max, &w) || !fv_cli_parse_i64(x + 1, 1, max, &h)) return false;
    *out_w = (uint32_t)w;
    *out_h = (uint32_t)h;
    return true;
}

bool fv_cli_parse_f64_pair(const char *s, double lo, double hi, double out[2])
{
    const char *comma = s ? strchr(s, ',') : NULL;
    char first[64];
    if (!comma || (size_t)(comma - s) >= sizeof first) return false;
    memcpy(first, s, (size_t)(comma - s));
    first[comma - s] = '\0';
    return fv_cli_parse_f64(first, lo, hi, &out[0]) && fv_cli_parse_f64(comma + 1, lo, hi, &out[1]);
}

static bool is_dir(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0) return false;
    if (S_ISDIR(st.st_mode)) return true;
    errno = ENOTDIR;
    return false;
}

bool fv_cli_make_dirs(const char *dir)
{
    char path[4096];
    size_t n = dir ? strlen(dir) : 0;
    if (n == 0 || n >= sizeof path) {
        errno = n ? ENAMETOOLONG : ENOENT;
        return false;
    }
    memcpy(path, dir, n + 1);
    /* Each parent in turn, then the whole path; EEXIST is fine as long as it is a directory. */
    for (size_t i = 1; i <= n; i++) {
        if (path[i] != '/' && path[i] != '\0') continue;
        char c = path[i];
        path[i] = '\0';
        if (mkdir(path, 0755) != 0 && errno != EEXIST) return false;
        if (!is_dir(path)) return false;
        path[i] = c;
    }
    return true;
}

void fv_cli_json_number(cJSON *obj, const char *key, double v)
{
    if (isfinite(v)) cJSON_AddNumberToObject(obj, key, v);
    else cJSON_AddNullToObject(obj, key);
}

const char *fv_cli_format_number(char *buf, size_t size, const char *fmt, double v)
{
    if (isnan(v)) snprintf(buf, size, "-");
    else if (isinf(v)) snprintf(buf, size, v > 0 ? "inf" : "-inf");
    else snprintf(buf, size, fmt, v);
    return buf;
}

bool fv_cli_output_dir(const char *cmd, const char *opt, const char *dir)
{
    if (fv_cli_make_dirs(dir)) return true;
    FV_ERROR(cmd, "%s %s: cannot create directory (%s)", opt, dir, strerror(errno ? errno : ENOTDIR));
    return false;
}

bool fv_cli_is_help(const char *arg) { return strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0; }

int fv_cli_option(int argc, char **argv, int *i, const char *name, const char **out_value)
{
    size_t n = strlen(name);
    const char *a = argv[*i];
    if (strncmp(a, name, n) != 0) return 0;
    if (a[n] == '=') {
        *out_value = a + n + 1;
        return 1;
    }
    if (a[n] != '\0') return 0;
    if (*i + 1 >= argc) return -1;
    (*i)++;
    *out_value = argv[*i];
    return 1;
}
