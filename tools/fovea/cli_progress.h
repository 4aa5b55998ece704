/* @brief One progress line on stderr for long work (`fovea run`, `bench`, `reference`): what is done (completed items,
 * and for frames how many were submitted ahead of them), the GPU time so far, the time elapsed and the time left
 * estimated from the completed items. A thread prints it, so a frame that the GPU takes a minute to finish still
 * shows the clock moving. At a terminal the line appears once the work has run FV_PROGRESS_AFTER_S and is cleared at
 * the end; FOVEA_PROGRESS=N shows it after N seconds also when stderr is not a terminal (one line a second, each
 * ending in a newline), FOVEA_PROGRESS=off never. */
#ifndef FV_CLI_PROGRESS_H
#define FV_CLI_PROGRESS_H

#include <stddef.h>
#include <stdint.h>

#define FV_PROGRESS_AFTER_S 2.0

typedef struct fv_progress fv_progress;

/** Start watching (`what`: "fovea run"; `unit`: "frame"; total: items, 0 = unknown). NULL when no line is wanted
 *  (not a terminal, FOVEA_PROGRESS=off) or on no memory: every other call accepts NULL. */
fv_progress *fv_progress_start(const char *what, const char *unit, int64_t total);
/** The work so far: items submitted (-1: not a notion here), completed, and the GPU time of the completed (ms; < 0:
 *  not measured). Any thread. */
void fv_progress_update(fv_progress *p, int64_t submitted, int64_t completed, double gpu_ms);
/** The total, when it is known only once the work runs (<= 0: unknown). Any thread. */
void fv_progress_set_total(fv_progress *p, int64_t total);
/** A short text after the counts ("point 3/12 shadow.resolution=1024"; NULL: none). Any thread; copied. */
void fv_progress_detail(fv_progress *p, const char *detail);
/** A new phase of the work (`detail` as fv_progress_detail): the time left is estimated from the items completed
 *  since it began, so a slow first phase (a baseline, a compile) does not inflate the estimate of the next; when the
 *  lines stay (not a terminal) and the line is due, the phase's line is printed at once. Any thread. */
void fv_progress_phase(fv_progress *p, const char *detail);
/** Stop the thread and clear the line (at a terminal). Sets *p to NULL; safe on NULL. */
void fv_progress_stop(fv_progress **p);

/** The line itself (no "\r" or newline): pure, for the thread and the tests. */
/** left_s: the time left estimated by the caller (< 0: not known yet). */
void fv_progress_format(char *out, size_t cap, const char *what, const char *unit, int64_t total, int64_t submitted,
                        int64_t completed, double gpu_ms, double elapsed_s, double left_s, const char *detail);

#endif
