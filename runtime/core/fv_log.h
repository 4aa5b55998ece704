/* @brief Logging: one replaceable sink, per-module levels from FOVEA_LOG ("hid=debug,gi=trace,*=warn"). */
#ifndef FV_LOG_H
#define FV_LOG_H

#include <pthread.h>
#include <stdint.h>

#include "fv_result.h"

struct fv_clock;

typedef enum fv_log_level {
    FV_LOG_LEVEL_ERROR = 0,
    FV_LOG_LEVEL_WARN = 1,
    FV_LOG_LEVEL_INFO = 2,
    FV_LOG_LEVEL_DEBUG = 3,
    FV_LOG_LEVEL_TRACE = 4,
} fv_log_level;

/** A sink receives a formatted message (no trailing newline). Called from any thread; must be thread-safe. */
typedef void (*fv_log_sink_fn)(void *user, fv_log_level level, const char *module, const char *file, int line,
                               const char *msg);

/** Replace the sink (NULL restores the default: stderr). Returns nothing; not thread-safe against logging. */
void fv_log_set_sink(fv_log_sink_fn fn, void *user);
/** Set the level of one module ("*" for the default). Overrides FOVEA_LOG. */
void fv_log_set_level(const char *module, fv_log_level level);
/** True when a message of this level for this module would be emitted. */
int fv_log_enabled(const char *module, fv_log_level level);
void fv_log_write(fv_log_level level, const char *module, const char *file, int line, const char *fmt, ...)
    FV_PRINTF(5, 6);
const char *fv_log_level_str(fv_log_level level);

/** A per-load message budget (a loader's defence against a flood of one error): between begin and end, on the
 *  calling thread, each kind of message (one call site: file and line) is shown `per_kind` times; the rest are
 *  counted and end() logs one line per kind, "ORIGIN: ... and N more like: <first message>". Budgets nest: an inner
 *  begin (a model file inside a scene file) shares the outer budget. The caller owns the struct; one thread. */
#define FV_LOG_BUDGET_KINDS 32
typedef struct fv_log_budget {
    const char *origin; /* named in the summary lines (the file being loaded) */
    unsigned per_kind;  /* messages of one kind shown; 0 = 8 */
    unsigned kind_count;
    struct fv_log_budget *outer; /* the budget this one nests in (internal) */
    int active;                  /* 1 when this budget counts (the outermost one) */
    struct {
        const char *file;
        int line;
        fv_log_level level;
        const char *module;
        unsigned long long seen;
        char first[160]; /* the first message of this kind, for the summary */
    } kinds[FV_LOG_BUDGET_KINDS + 1]; /* the last slot holds every kind past FV_LOG_BUDGET_KINDS */
} fv_log_budget;
void fv_log_budget_begin(fv_log_budget *b, const char *origin, unsigned per_kind);
void fv_log_budget_end(fv_log_budget *b);
/** Messages counted but not shown so far (0 for a nested budget). */
unsigned long long fv_log_budget_suppressed(const fv_log_budget *b);

/** A rate limit over time for one repeated message (one call site, or one kind of event of one device): at most
 *  `burst` lines in a window of `window_ns`; past that the messages are counted, not formatted into the log, and
 *  when the window ends one summary line says "... N more like this in the last T s; the first: <message>". The
 *  summary comes with the next message after the window (which then opens a new window), or from
 *  fv_log_ratelimit_tick (call it where the code passes often, e.g. each read) once the window is over, or from
 *  fv_log_ratelimit_flush (at close: whatever is counted, now). Thread-safe: a driver's reader thread and another
 *  thread may share one. The clock is injectable for tests (NULL: the monotonic clock). A static one at a call site:
 *  `static fv_log_ratelimit rl = FV_LOG_RATELIMIT_INIT(10, 5);` (10 lines per 5 s). */
typedef struct fv_log_ratelimit {
    pthread_mutex_t lock;
    unsigned burst;               /* lines shown per window; 0 = 10 */
    int64_t window_ns;            /* 0 = 5 s */
    const struct fv_clock *clock; /* NULL = fv_clock_monotonic() */
    int open;                     /* a window is open (since window_start_ns) */
    int64_t window_start_ns;
    unsigned shown;                      /* lines shown in this window */
    unsigned long long suppressed;       /* counted in this window, not shown yet summarised */
    unsigned long long total_suppressed; /* over the limit's life */
    fv_log_level level;                  /* of the first counted message, for the summary */
    const char *module, *file;
    int line;
    char first[160]; /* the first counted message of this window */
} fv_log_ratelimit;
#define FV_LOG_RATELIMIT_INIT(burst_, seconds_)                                                                        \
    {.lock = PTHREAD_MUTEX_INITIALIZER, .burst = (burst_), .window_ns = (int64_t)(seconds_) * INT64_C(1000000000)}
void fv_log_ratelimit_init(fv_log_ratelimit *rl, unsigned burst, int64_t window_ns, const struct fv_clock *clock);
void fv_log_ratelimit_write(fv_log_ratelimit *rl, fv_log_level level, const char *module, const char *file, int line,
                            const char *fmt, ...) FV_PRINTF(6, 7);
/** The summary of a window that has ended (nothing when none has, or nothing was counted). */
void fv_log_ratelimit_tick(fv_log_ratelimit *rl);
/** The summary of what is counted so far, now, window over or not; the next message opens a new window. */
void fv_log_ratelimit_flush(fv_log_ratelimit *rl);
/** Messages counted and not shown over the limit's life (summarised or still pending). */
unsigned long long fv_log_ratelimit_suppressed(fv_log_ratelimit *rl);

#define FV_LOG(level, module, ...)                                                                                     \
    do {                                                                                                               \
        if (fv_log_enabled((module), (level))) fv_log_write((level), (module), __FILE__, __LINE__, __VA_ARGS__);       \
    } while (0)
#define FV_ERROR(module, ...) FV_LOG(FV_LOG_LEVEL_ERROR, module, __VA_ARGS__)
#define FV_WARN(module, ...) FV_LOG(FV_LOG_LEVEL_WARN, module, __VA_ARGS__)
#define FV_INFO(module, ...) FV_LOG(FV_LOG_LEVEL_INFO, module, __VA_ARGS__)
#define FV_DEBUG(module, ...) FV_LOG(FV_LOG_LEVEL_DEBUG, module, __VA_ARGS__)
#define FV_TRACE(module, ...) FV_LOG(FV_LOG_LEVEL_TRACE, module, __VA_ARGS__)
/* Through a rate limit (fv_log_ratelimit *rl); a message below the module's level is neither shown nor counted. */
#define FV_LOG_RL(rl, level, module, ...)                                                                              \
    do {                                                                                                               \
        if (fv_log_enabled((module), (level)))                                                                         \
            fv_log_ratelimit_write((rl), (level), (module), __FILE__, __LINE__, __VA_ARGS__);                          \
    } while (0)
#define FV_ERROR_RL(rl, module, ...) FV_LOG_RL(rl, FV_LOG_LEVEL_ERROR, module, __VA_ARGS__)
#define FV_WARN_RL(rl, module, ...) FV_LOG_RL(rl, FV_LOG_LEVEL_WARN, module, __VA_ARGS__)

#endif
