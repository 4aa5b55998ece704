/* @brief Shared test helpers (see fv_test.h). */
#include "fv_test.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include "fovea_config.h"

static char g_paths[8][1024];
static int g_path_slot;

static char *next_slot(void)
{
    char *p = g_paths[g_path_slot];
    g_path_slot = (g_path_slot + 1) % 8;
    return p;
}

const char *fv_test_data(const char *relative)
{
    const char *root = getenv("FV_SHARED_DATA_DIR");
    if (!root || !*root) root = FV_SHARED_DATA_DIR;
    char *p = next_slot();
    snprintf(p, 1024, "%s/%s", root, relative);
    return p;
}

static void mkdirs(const char *dir)
{
    char tmp[1024];
    snprintf(tmp, sizeof tmp, "%s", dir);
    for (char *s = tmp + 1; *s; s++) {
        if (*s == '/') {
            *s = '\0';
            mkdir(tmp, 0755);
            *s = '/';
        }
    }
    mkdir(tmp, 0755);
}

const char *fv_test_tmp(const char *name)
{
    const char *root = getenv("FV_TEST_TMP");
    if (!root || !*root) root = "/tmp/fovea-test";
    mkdirs(root);
    char *p = next_slot();
    snprintf(p, 1024, "%s/%s", root, name);
    return p;
}

const char *fv_test_write_file(const char *name, const void *data, size_t size)
{
    const char *path = fv_test_tmp(name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    if (size) assert_int_equal(fwrite(data, 1, size, f), size);
    fclose(f);
    return path;
}

char *fv_test_read_file(const char *path, size_t *out_len)
{
    FILE *f = fopen(path, "rb");
    if (!f) fail_msg("cannot open %s: %s", path, strerror(errno));
    if (fseek(f, 0, SEEK_END) != 0) fail_msg("cannot seek %s", path);
    long n = ftell(f);
    if (n < 0 || fseek(f, 0, SEEK_SET) != 0) fail_msg("cannot size %s", path);
    char *buf = malloc((size_t)n + 1);
    assert_non_null(buf);
    if (fread(buf, 1, (size_t)n, f) != (size_t)n) fail_msg("short read of %s", path);
    buf[n] = '\0';
    fclose(f);
    if (out_len) *out_len = (size_t)n;
    return buf;
}

static void slurp(const char *path, char *buf, size_t cap)
{
    FILE *f = fopen(path, "rb");
    size_t n = 0;
    if (f) {
        n = fread(buf, 1, cap - 1, f);
        fclose(f);
    }
    buf[n] = '\0';
}

const char *fv_test_first_line(const char *s)
{
    static char line[1024];
    size_t n = strcspn(s, "\n");
    if (n >= sizeof line) n = sizeof line - 1;
    memcpy(line, s, n);
    line[n] = '\0';
    return line;
}

void fv_test_run_cmd(fv_test_cmd *res, const char *env, const char *program, const char *args)
{
    char out_path[1024], err_path[1024], cmd[8192];
    snprintf(out_path, sizeof out_path, "%s", fv_test_tmp("cmd_stdout.txt"));
    snprintf(err_path, sizeof err_path, "%s", fv_test_tmp("cmd_stderr.txt"));
    int n = snprintf(cmd, sizeof cmd, "%s %s %s >%s 2>%s", env ? env : "", program, args ? args : "", out_path,
                     err_path);
    if (n < 0 || (size_t)n >= sizeof cmd) fail_msg("command line too long: %s %s", program, args);
    int st = system(cmd);
    res->exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    slurp(out_path, res->out, sizeof res->out);
    slurp(err_path, res->err, sizeof res->err);
}

static pthread_mutex_t g_mutex = PTHREAD_MUTEX_INITIALIZER;
static char *g_log;
static size_t g_log_len, g_log_cap;
static int g_counts[FV_LOG_LEVEL_TRACE + 1];

static void sink(void *user, fv_log_level level, const char *module, const char *file, int line, const char *msg)
{
    (void)user;
    (void)file;
    (void)line;
    char buf[1400];
    int n = snprintf(buf, sizeof buf, "%s %s: %s\n", fv_log_level_str(level), module, msg);
    if (n < 0) return;
    if ((size_t)n >= sizeof buf) n = (int)sizeof buf - 1;
    pthread_mutex_lock(&g_mutex);
    if (g_log_len + (size_t)n + 1 > g_log_cap) {
        size_t cap = (g_log_cap ? g_log_cap * 2 : 4096) + (size_t)n;
        char *p = realloc(g_log, cap);
        if (p) {
            g_log = p;
            g_log_cap = cap;
        }
    }
    if (g_log_len + (size_t)n + 1 <= g_log_cap) {
        memcpy(g_log + g_log_len, buf, (size_t)n);
        g_log_len += (size_t)n;
        g_log[g_log_len] = '\0';
    }
    if (level >= 0 && level <= FV_LOG_LEVEL_TRACE) g_counts[level]++;
    pthread_mutex_unlock(&g_mutex);
}

void fv_test_log_capture_begin(void)
{
    pthread_mutex_lock(&g_mutex);
    g_log_len = 0;
    if (g_log) g_log[0] = '\0';
    memset(g_counts, 0, sizeof g_counts);
    pthread_mutex_unlock(&g_mutex);
    fv_log_set_sink(sink, NULL);
}

void fv_test_log_capture_end(void) { fv_log_set_sink(NULL, NULL); }

const char *fv_test_log_text(void) { return g_log ? g_log : ""; }

int fv_test_log_count(fv_log_level at_most)
{
    int n = 0;
    for (int l = 0; l <= (int)at_most && l <= FV_LOG_LEVEL_TRACE; l++) n += g_counts[l];
    return n;
}

int fv_test_log_lines(const char *needle, unsigned long long *sum)
{
    int n = 0;
    if (sum) *sum = 0;
    for (const char *p = fv_test_log_text(); *p;) {
        const char *end = strchr(p, '\n');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        char line[1500];
        snprintf(line, sizeof line, "%.*s", (int)len, p);
        if (strstr(line, needle)) {
            n++;
            const char *dots = strstr(line, "... ");
            if (sum && dots) *sum += strtoull(dots + 4, NULL, 10);
        }
        p += len + (end ? 1 : 0);
    }
    return n;
}

double fv_test_normal(uint64_t *rng)
{
    double u[2];
    for (int i = 0; i < 2; i++) {
        *rng = *rng * 6364136223846793005ULL + 1442695040888963407ULL;
        u[i] = ((double)(*rng >> 11) + 0.5) * (1.0 / 9007199254740992.0);
    }
    return sqrt(-2.0 * log(u[0])) * cos(2.0 * 3.14159265358979323846 * u[1]);
}
