/* @brief Logging implementation: a default stderr sink, a replaceable sink, per-module levels. */
#include "fv_log.h"

#include "fv_clock.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_MODULES 32

typedef struct module_level {
    char name[24];
    fv_log_level level;
} module_level;

static pthread_once_t g_once = PTHREAD_ONCE_INIT;
static pthread_mutex_t g_mutex = PTHREAD_MUTEX_INITIALIZER;
static fv_log_sink_fn g_sink;
static void *g_sink_user;
static fv_log_level g_default = FV_LOG_LEVEL_WARN;
static module_level g_levels[MAX_MODULES];
static int g_level_count;

const char *fv_log_level_str(fv_log_level level)
{
    static const char *names[] = {"error", "warn", "info", "debug", "trace"};
    return (level >= 0 && level <= FV_LOG_LEVEL_TRACE) ? names[level] : "?";
}

static int parse_level(const char *s, size_t n, fv_log_level *out)
{
    for (int l = 0; l <= FV_LOG_LEVEL_TRACE; l++) {
        const char *name = fv_log_level_str((fv_log_level)l);
        if (strlen(name) == n && strncmp(s, name, n) == 0) {
            *out = (fv_log_level)l;
            return 1;
        }
    }
    return 0;
}

static void set_level_locked(const char *module, size_t n, fv_log_level level)
{
    if (n == 1 && module[0] == '*') {
        g_default = level;
        return;
    }
    if (n >= sizeof(g_levels[0].name)) return;
    for (int i = 0; i < g_level_count; i++) {
        if (strlen(g_levels[i].name) == n && strncmp(g_levels[i].name, module, n) == 0) {
            g_levels[i].level = level;
            return;
        }
    }
    if (g_level_count == MAX_MODULES) return;
    memcpy(g_levels[g_level_count].name, module, n);
    g_levels[g_level_count].name[n] = '\0';
    g_levels[g_level_count].level = level;
    g_level_count++;
}

/* FOVEA_LOG="hid=debug,gi=trace" or a bare level ("debug") for every module. Bad entries are ignored with a note. */
static void init_from_env(void)
{
    const char *env = getenv("FOVEA_LOG");
    if (!env) return;
    const char *p = env;
    while (*p) {
        const char *end = strchr(p, ',');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        const char *eq = memchr(p, '=', len);
        fv_log_level level;
        if (eq) {
            if (parse_level(eq + 1, len - (size_t)(eq + 1 - p), &level)) set_level_locked(p, (size_t)(eq - p), level);
            else fprintf(stderr, "fovea: FOVEA_LOG: ignoring '%.*s' (unknown level)\n", (int)len, p);
        } else if (parse_level(p, len, &level)) {
            g_default = level;
        } else {
            fprintf(stderr, "fovea: FOVEA_LOG: ignoring '%.*s' (expected module=level)\n", (int)len, p);
        }
        p += len;
        if (*p == ',') p++;
    }
}

static void ensure_init(void) { pthread_once(&g_once, init_from_env); }

void fv_log_set_sink(fv_log_sink_fn fn, void *user)
{
    pthread_mutex_lock(&g_mutex);
    g_sink = fn;
    g_sink_user = user;
    pthread_mutex_unlock(&g_mutex);
}

void fv_log_set_level(const char *module, fv_log_level level)
{
    ensure_init();
    pthread_mutex_lock(&g_mutex);
    set_level_locked(module, strlen(module), level);
    pthread_mutex_unlock(&g_mutex);
}

int fv_log_enabled(const char *module, fv_log_level level)
{
    ensure_init();
    fv_log_level limit = g_default;
    pthread_mutex_lock(&g_mutex);
    for (int i = 0; i < g_level_count; i++) {
        if (strcmp(g_levels[i].name, module) == 0) {
            limit = g_levels[i].level;
            break;
        }
    }
    pthread_mutex_unlock(&g_mutex);
    return level <= limit;
}

/* ---- per-load budget ---- */

static _Thread_local fv_log_budget *t_budget;

void fv_log_budget_begin(fv_log_budget *b, const char *origin, unsigned per_kind)
{
    memset(b, 0, sizeof *b);
    b->origin = origin ? origin : "";
    b->per_kind = per_kind ? per_kind : 8;
    b->outer = t_budget;
    b->active = t_budget == NULL; /* nested: the outer budget counts */
    t_budget = b;
}

unsigned long long fv_log_budget_suppressed(const fv_log_budget *b)
{
    unsigned long long n = 0;
    for (unsigned i = 0; b->active && i <= FV_LOG_BUDGET_KINDS; i++)
        if (b->kinds[i].seen > b->per_kind) n += b->kinds[i].seen - b->per_kind;
    return n;
}

static fv_log_budget *active_budget(void)
{
    fv_log_budget *b = t_budget;
    while (b && !b->active) b = b->outer;
    return b;
}

/* The slot of this call site: its own while there is room, then one shared by every later kind. */
static unsigned budget_slot(fv_log_budget *b, const char *file, int line, fv_log_level level, const char *module)
{
    for (unsigned i = 0; i < b->kind_count; i++)
        if (b->kinds[i].line == line && (b->kinds[i].file == file || strcmp(b->kinds[i].file, file) == 0)) return i;
    unsigned i = b->kind_count < FV_LOG_BUDGET_KINDS ? b->kind_count++ : FV_LOG_BUDGET_KINDS;
    if (b->kinds[i].seen == 0) {
        b->kinds[i].file = file;
        b->kinds[i].line = line;
        b->kinds[i].level = level;
        b->kinds[i].module = module;
    }
    return i;
}

static void emit(fv_log_level level, const char *module, const char *file, int line, const char *msg);

/* Group digits by thousands: 112340 -> "112,340". */
static void group_digits(unsigned long long v, char *out, size_t cap)
{
    char tmp[32];
    int n = snprintf(tmp, sizeof tmp, "%llu", v);
    size_t o = 0;
    for (int i = 0; i < n && o + 2 < cap; i++) {
        if (i > 0 && (n - i) % 3 == 0) out[o++] = ',';
        out[o++] = tmp[i];
    }
    out[o] = '\0';
}

void fv_log_budget_end(fv_log_budget *b)
{
    if (t_budget == b) t_budget = b->outer;
    if (!b->active) return;
    for (unsigned i = 0; i <= FV_LOG_BUDGET_KINDS; i++) {
        if (b->kinds[i].seen <= b->per_kind) continue;
        char n[40], msg[400];
        group_digits(b->kinds[i].seen - b->per_kind, n, sizeof n);
        snprintf(msg, sizeof msg, "%s: ... and %s more like: %s", b->origin, n, b->kinds[i].first);
        emit(b->kinds[i].level, b->kinds[i].module, b->kinds[i].file, b->kinds[i].line, msg);
    }
}

void fv_log_write(fv_log_level level, const char *module, const char *file, int line, const char *fmt, ...)
{
    fv_log_budget *b = active_budget();
    int slot = b ? (int)budget_slot(b, file, line, level, module) : -1;
    if (slot >= 0 && ++b->kinds[slot].seen > b->per_kind) return; /* counted; summarised by fv_log_budget_end */
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (slot >= 0 && b->kinds[slot].seen == 1) {
        size_t n = strlen(msg), cap = sizeof b->kinds[slot].first;
        if (n >= cap) n = cap - 1;
        memcpy(b->kinds[slot].first, msg, n);
        b->kinds[slot].first[n] = '\0';
    }
    emit(level, module, file, line, msg);
}

/* ---- rate limit over time ---- */

#define RL_DEFAULT_BURST 10u
#define RL_DEFAULT_WINDOW_NS (5 * FV_NS_PER_S)

void fv_log_ratelimit_init(fv_log_ratelimit *rl, unsigned burst, int64_t window_ns, const struct fv_clock *clock)
{
    memset(rl, 0, sizeof *rl);
    pthread_mutex_init(&rl->lock, NULL);
    rl->burst = burst;
    rl->window_ns = window_ns;
    rl->clock = clock;
}

static int64_t rl_now(const fv_log_ratelimit *rl)
{
    return fv_clock_now_ns(rl->clock ? rl->clock : fv_clock_monotonic());
}

static int64_t rl_window(const fv_log_ratelimit *rl)
{
    return rl->window_ns > 0 ? rl->window_ns : RL_DEFAULT_WINDOW_NS;
}

/* Close the open window: its summary when something was counted. Called with the lock held (the summary must come
 * out before the message that opens the next window). */
static void rl_close_locked(fv_log_ratelimit *rl, int64_t now)
{
    if (rl->open && rl->suppressed) {
        int64_t span = now > rl->window_start_ns ? now - rl->window_start_ns : 0;
        fv_log_write(rl->level, rl->module, rl->file, rl->line, "... %llu more like this in the last %.1f s; the "
                     "first: %s", rl->suppressed, (double)span * 1e-9, rl->first);
    }
    rl->open = 0;
    rl->shown = 0;
    rl->suppressed = 0;
}

static int rl_window_over(const fv_log_ratelimit *rl, int64_t now)
{
    return rl->open && now - rl->window_start_ns >= rl_window(rl);
}

void fv_log_ratelimit_write(fv_log_ratelimit *rl, fv_log_level level, const char *module, const char *file, int line,
                            const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    pthread_mutex_lock(&rl->lock);
    int64_t now = rl_now(rl);
    if (rl_window_over(rl, now)) rl_close_locked(rl, now);
    if (!rl->open) {
        rl->open = 1;
        rl->window_start_ns = now;
    }
    if (rl->shown < (rl->burst ? rl->burst : RL_DEFAULT_BURST)) {
        rl->shown++;
        va_start(ap, fmt);
        vsnprintf(msg, sizeof msg, fmt, ap);
        va_end(ap);
        fv_log_write(level, module, file, line, "%s", msg);
    } else {
        if (rl->suppressed++ == 0) { /* the first counted one: kept for the summary */
            va_start(ap, fmt);
            vsnprintf(rl->first, sizeof rl->first, fmt, ap);
            va_end(ap);
            rl->level = level;
            rl->module = module;
            rl->file = file;
            rl->line = line;
        }
        rl->total_suppressed++;
    }
    pthread_mutex_unlock(&rl->lock);
}

void fv_log_ratelimit_tick(fv_log_ratelimit *rl)
{
    pthread_mutex_lock(&rl->lock);
    int64_t now = rl_now(rl);
    if (rl_window_over(rl, now)) rl_close_locked(rl, now);
    pthread_mutex_unlock(&rl->lock);
}

void fv_log_ratelimit_flush(fv_log_ratelimit *rl)
{
    pthread_mutex_lock(&rl->lock);
    rl_close_locked(rl, rl_now(rl));
    pthread_mutex_unlock(&rl->lock);
}

unsigned long long fv_log_ratelimit_suppressed(fv_log_ratelimit *rl)
{
    pthread_mutex_lock(&rl->lock);
    unsigned long long n = rl->total_suppressed;
    pthread_mutex_unlock(&rl->lock);
    return n;
}

static void emit(fv_log_level level, const char *module, const char *file, int line, const char *msg)
{
    const char *base = strrchr(file, '/');
    base = base ? base + 1 : file;
    pthread_mutex_lock(&g_mutex);
    fv_log_sink_fn sink = g_sink;
    void *user = g_sink_user;
    pthread_mutex_unlock(&g_mutex);
    if (sink) {
        sink(user, level, module, base, line, msg);
        return;
    }
    fprintf(stderr, "fovea: %s: %s: %s (%s:%d)\n", fv_log_level_str(level), module, msg, base, line);
}
