/* @brief Logging: one replaceable sink, per-module levels from FOVEA_LOG ("hid=debug,gi=trace,*=warn"). */
#ifndef FV_LOG_H
#define FV_LOG_H

#include "fv_result.h"

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

#define FV_LOG(level, module, ...)                                                                                     \
    do {                                                                                                               \
        if (fv_log_enabled((module), (level))) fv_log_write((level), (module), __FILE__, __LINE__, __VA_ARGS__);       \
    } while (0)
#define FV_ERROR(module, ...) FV_LOG(FV_LOG_LEVEL_ERROR, module, __VA_ARGS__)
#define FV_WARN(module, ...) FV_LOG(FV_LOG_LEVEL_WARN, module, __VA_ARGS__)
#define FV_INFO(module, ...) FV_LOG(FV_LOG_LEVEL_INFO, module, __VA_ARGS__)
#define FV_DEBUG(module, ...) FV_LOG(FV_LOG_LEVEL_DEBUG, module, __VA_ARGS__)
#define FV_TRACE(module, ...) FV_LOG(FV_LOG_LEVEL_TRACE, module, __VA_ARGS__)

#endif
