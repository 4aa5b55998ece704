/* @brief Shared command-line helpers for the fovea subcommands. */
#include "cli.h"

#include "fv_file.h"
#include "fv_log.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <float.h>
#include <limits.h>
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
    if (!errno && end != s && (*end == 'e' || *end == 'E')) {
        /* "1e9", "5E6": an integer times a power of ten, as the usage messages write large counts */
        char *e2 = NULL;
        long x = strtol(end + 1, &e2, 10);
        if (e2 == end + 1 || *e2 != '\0' || end[1] == '+' || end[1] == '-' || x < 0 || x > 18) return false;
        for (long k = 0; k < x; k++) {
            if (v > LLONG_MAX / 10 || v < LLONG_MIN / 10) return false;
            v *= 10;
        }
        end = e2;
    }
    if (errno || end == s || *end != '\0' || v < lo || v > hi) return false;
    *out = v;
    return true;
}

bool fv_cli_parse_f64(const char *s, double lo, double hi, double *out)
{
    if (!s || !*s) return false;
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    /* ERANGE on underflow (a denormal or a value that rounds to 0) is still a number: it is judged by the range
     * like any other, so "1e-310" is refused as out of range only when it is, and never as "not a number" */
    bool underflow = errno == ERANGE && fabs(v) <= DBL_MIN;
    if ((errno && !underflow) || end == s || *end != '\0' || !isfinite(v) || v < lo || v > hi) return false;
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

/* Length of the valid UTF-8 sequence at p (at most n bytes), or 0 when the byte there does not start one. */
static size_t utf8_sequence(const unsigned char *p, size_t n)
{
    unsigned char c = p[0];
    if (c < 0x80) return 1;
    size_t len;
    uint32_t cp, min;
    if (c >= 0xC2 && c <= 0xDF) len = 2, cp = c & 0x1Fu, min = 0x80;
    else if (c >= 0xE0 && c <= 0xEF) len = 3, cp = c & 0x0Fu, min = 0x800;
    else if (c >= 0xF0 && c <= 0xF4) len = 4, cp = c & 0x07u, min = 0x10000;
    else return 0;
    if (n < len) return 0;
    for (size_t i = 1; i < len; i++) {
        if ((p[i] & 0xC0u) != 0x80u) return 0;
        cp = cp << 6 | (p[i] & 0x3Fu);
    }
    if (cp < min || cp > 0x10FFFFu || (cp >= 0xD800u && cp <= 0xDFFFu)) return 0;
    return len;
}

/* s with every invalid byte replaced by `repl` (a NUL-terminated string); NULL when s is already valid (or no
 * memory: *out_oom). */
static char *utf8_repair(const char *s, const char *repl, bool *out_oom)
{
    const unsigned char *p = (const unsigned char *)s;
    size_t n = strlen(s), bad = 0;
    for (size_t i = 0; i < n;) {
        size_t k = utf8_sequence(p + i, n - i);
        if (!k) bad++, k = 1;
        i += k;
    }
    *out_oom = false;
    if (!bad) return NULL;
    size_t rl = strlen(repl);
    char *out = malloc(n + bad * rl + 1);
    if (!out) {
        *out_oom = true;
        return NULL;
    }
    size_t o = 0;
    for (size_t i = 0; i < n;) {
        size_t k = utf8_sequence(p + i, n - i);
        if (k) {
            memcpy(out + o, s + i, k);
            o += k;
            i += k;
        } else {
            memcpy(out + o, repl, rl);
            o += rl;
            i++;
        }
    }
    out[o] = '\0';
    return out;
}

cJSON *fv_cli_json_string(const char *s)
{
    if (!s) s = "";
    bool oom;
    char *fixed = utf8_repair(s, "\xEF\xBF\xBD", &oom); /* U+FFFD REPLACEMENT CHARACTER */
    if (oom) return NULL;
    cJSON *j = cJSON_CreateString(fixed ? fixed : s);
    free(fixed);
    return j;
}

cJSON *fv_cli_json_add_string(cJSON *obj, const char *key, const char *s)
{
    cJSON *j = fv_cli_json_string(s);
    if (j && !cJSON_AddItemToObject(obj, key, j)) {
        cJSON_Delete(j);
        return NULL;
    }
    return j;
}

char *fv_cli_json_text(const cJSON *root, bool pretty)
{
    char *text = root ? (pretty ? cJSON_Print(root) : cJSON_PrintUnformatted(root)) : NULL;
    if (!text) return NULL;
    /* Strings came through fv_cli_json_string; a key or anything else that did not is still made valid here (an
     * invalid byte can only sit inside a string, where the escape is valid JSON). */
    bool oom;
    char *fixed = utf8_repair(text, "\\ufffd", &oom);
    if (oom) {
        free(text);
        return NULL;
    }
    if (fixed) {
        free(text);
        text = fixed;
    }
    return text;
}

int fv_cli_json_print(const cJSON *root, bool pretty)
{
    char *text = fv_cli_json_text(root, pretty);
    if (!text) {
        fprintf(stderr, "fovea: out of memory printing the JSON output\n");
        return FV_EXIT_FAIL;
    }
    bool ok = puts(text) >= 0 && fflush(stdout) == 0;
    free(text);
    if (!ok) fprintf(stderr, "fovea: cannot write the JSON output: %s\n", strerror(errno));
    return ok ? FV_EXIT_OK : FV_EXIT_FAIL;
}

char *fv_cli_read_file(const char *cmd, const char *path, size_t max_bytes, size_t *out_len)
{
    char *buf, why[FV_FILE_ERR_MAX];
    size_t len = 0; /* out_len may be NULL */
    if (fv_file_read(path, NULL, max_bytes, &buf, &len, why, sizeof why) != FV_OK) {
        fprintf(stderr, "fovea %s: %s\n", cmd, why);
        return NULL;
    }
    if (out_len) *out_len = len;
    return buf;
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
