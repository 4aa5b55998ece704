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
