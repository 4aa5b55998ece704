/* @brief Shared test helpers (see fv_test.h). */
#include "fv_test.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

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

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec / 1e9;
}

double fv_test_cmd_limit_s(void)
{
    const char *e = getenv("FV_TEST_CMD_LIMIT_S");
    double v = e && *e ? atof(e) : 0.0;
    return v > 0 ? v : FV_TEST_CMD_LIMIT_S;
}

pid_t fv_test_spawn(const char *const argv[], const char *stdout_path, const char *stderr_path)
{
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) fail_msg("fork failed: %s", strerror(errno));
    if (pid == 0) {
        setpgid(0, 0); /* its own process group: a time limit can end it and everything it started */
        sigset_t none;
        sigemptyset(&none);
        sigprocmask(SIG_SETMASK, &none, NULL);
        signal(SIGINT, SIG_DFL);
        int in = open("/dev/null", O_RDONLY);
        if (in >= 0) dup2(in, STDIN_FILENO);
        const char *paths[2] = {stdout_path, stderr_path};
        for (int k = 0; k < 2; k++) {
            if (!paths[k]) continue;
            int fd = open(paths[k], O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (fd >= 0) dup2(fd, k + 1);
        }
        execvp(argv[0], (char *const *)argv);
        _exit(127);
    }
    setpgid(pid, pid); /* also here: whichever runs first */
    return pid;
}

/* Kill the process group: TERM, then KILL after 2 s. */
static void kill_group(pid_t pid)
{
    kill(-pid, SIGTERM);
    double t0 = now_s();
    while (now_s() - t0 < 2.0) {
        if (waitpid(pid, NULL, WNOHANG) == pid) {
            kill(-pid, SIGKILL); /* whatever it left behind in its group */
            return;
        }
        usleep(10000);
    }
    kill(-pid, SIGKILL);
    waitpid(pid, NULL, 0);
}

int fv_test_wait(pid_t pid, double limit_s, const char *what)
{
    double t0 = now_s();
    int st = 0;
    for (;;) {
        pid_t r = waitpid(pid, &st, WNOHANG);
        if (r == pid) break;
        if (r < 0 && errno != EINTR) fail_msg("waitpid for '%s': %s", what, strerror(errno));
        if (now_s() - t0 > limit_s) {
            kill_group(pid);
            fail_msg("TIMED OUT after %.0f s (its process group was killed): %s", limit_s, what);
        }
        usleep(now_s() - t0 < 1.0 ? 2000 : 20000);
    }
    kill(-pid, SIGKILL); /* nothing it started outlives it */
    const char *log = getenv("FV_TEST_CMD_LOG"); /* the durations of test commands, to find the slow ones */
    if (log && *log) {
        FILE *f = fopen(log, "a");
        if (f) {
            fprintf(f, "%.2f\t%s\n", now_s() - t0, what);
            fclose(f);
        }
    }
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

void fv_test_run_cmd_limit(fv_test_cmd *res, double limit_s, const char *env, const char *program, const char *args)
{
    char out_path[1024], err_path[1024], cmd[8192];
    snprintf(out_path, sizeof out_path, "%s", fv_test_tmp("cmd_stdout.txt"));
    snprintf(err_path, sizeof err_path, "%s", fv_test_tmp("cmd_stderr.txt"));
    int n = snprintf(cmd, sizeof cmd, "%s %s %s", env ? env : "", program, args ? args : "");
    if (n < 0 || (size_t)n >= sizeof cmd) fail_msg("command line too long: %s %s", program, args);
    const char *argv[] = {"/bin/sh", "-c", cmd, NULL};
    pid_t pid = fv_test_spawn(argv, out_path, err_path);
    res->exit_code = fv_test_wait(pid, limit_s, cmd);
    slurp(out_path, res->out, sizeof res->out);
    slurp(err_path, res->err, sizeof res->err);
}

void fv_test_run_cmd(fv_test_cmd *res, const char *env, const char *program, const char *args)
{
    fv_test_run_cmd_limit(res, fv_test_cmd_limit_s(), env, program, args);
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
