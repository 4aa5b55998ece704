/* @brief The progress line of long work (see cli_progress.h). */
#include "cli_progress.h"

#include <errno.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "fv_clock.h"

struct fv_progress {
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t cond;
    bool stop, tty, shown;
    double after_s;
    char what[48], unit[24], detail[160];
    int64_t total, submitted, completed;
    double gpu_ms;
    int64_t t_start_ns;
    int64_t t_phase_ns, phase_completed; /* where the current phase began: the time left is estimated from there */
    size_t width; /* the longest line printed (to clear it) */
};

void fv_progress_format(char *out, size_t cap, const char *what, const char *unit, int64_t total, int64_t submitted,
                        int64_t completed, double gpu_ms, double elapsed_s, double left_s, const char *detail)
{
    size_t n = 0;
#define ADD(...) (n += (size_t)snprintf(out + (n < cap ? n : cap), n < cap ? cap - n : 0, __VA_ARGS__))
    if (cap) out[0] = '\0';
    ADD("%s: ", what);
    if (total > 0) ADD("%lld/%lld %s%s done", (long long)completed, (long long)total, unit, total == 1 ? "" : "s");
    else ADD("%lld %s%s done", (long long)completed, unit, completed == 1 ? "" : "s");
    if (submitted > completed) ADD(" (%lld submitted)", (long long)submitted);
    if (gpu_ms >= 0) ADD(", GPU %.0f ms so far", gpu_ms);
    ADD(", %.1f s", elapsed_s);
    if (total > 0 && completed >= total) ADD(", finishing");
    else if (total > 0 && left_s >= 0) ADD(", about %.0f s left", left_s);
    else if (total > 0) ADD(", time left known after the first %s", unit);
    if (detail && detail[0]) ADD("; %s", detail);
#undef ADD
}

static void print_line(fv_progress *p)
{
    char line[400];
    int64_t now = fv_time_monotonic_ns();
    double s = (double)(now - p->t_start_ns) / 1e9, left = -1.0;
    int64_t done_in_phase = p->completed - p->phase_completed;
    if (p->total > 0 && done_in_phase > 0)
        left = (double)(now - p->t_phase_ns) / 1e9 / (double)done_in_phase * (double)(p->total - p->completed);
    fv_progress_format(line, sizeof line, p->what, p->unit, p->total, p->submitted, p->completed, p->gpu_ms, s, left,
                       p->detail);
    size_t len = strlen(line);
    if (p->tty) {
        fprintf(stderr, "\r%s%*s", line, (int)(p->width > len ? p->width - len : 0), "");
        if (len > p->width) p->width = len;
    } else {
        fprintf(stderr, "%s\n", line);
    }
    fflush(stderr);
    p->shown = true;
}

static void *run(void *arg)
{
    fv_progress *p = arg;
    pthread_mutex_lock(&p->lock);
    int64_t next_ns = p->t_start_ns + (int64_t)(p->after_s * 1e9);
    while (!p->stop) {
        struct timespec ts;
        clock_gettime(CLOCK_MONOTONIC, &ts);
        int64_t now = (int64_t)ts.tv_sec * FV_NS_PER_S + ts.tv_nsec;
        if (now >= next_ns) {
            print_line(p);
            next_ns = now + (p->tty ? 250 : 1000) * FV_NS_PER_MS;
        }
        int64_t until = next_ns;
        struct timespec w = {(time_t)(until / FV_NS_PER_S), (long)(until % FV_NS_PER_S)};
        int rc = pthread_cond_timedwait(&p->cond, &p->lock, &w);
        (void)rc; /* ETIMEDOUT or a wake-up: the loop looks again */
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

fv_progress *fv_progress_start(const char *what, const char *unit, int64_t total)
{
    const char *env = getenv("FOVEA_PROGRESS");
    bool tty = isatty(STDERR_FILENO) != 0;
    double after = FV_PROGRESS_AFTER_S;
    if (env && *env) {
        if (!strcmp(env, "off")) return NULL;
        char *end;
        double v = strtod(env, &end);
        if (end != env && *end == '\0' && v >= 0 && v < 1e6) after = v;
        else fprintf(stderr, "%s: FOVEA_PROGRESS='%s' is not off or a number of seconds; using %g s\n", what, env,
                     FV_PROGRESS_AFTER_S);
    } else if (!tty) {
        return NULL;
    }
    fv_progress *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    p->tty = tty;
    p->after_s = after;
    p->gpu_ms = -1;
    p->submitted = -1;
    p->total = total;
    snprintf(p->what, sizeof p->what, "%s", what);
    snprintf(p->unit, sizeof p->unit, "%s", unit);
    p->t_start_ns = p->t_phase_ns = fv_time_monotonic_ns();
    pthread_mutex_init(&p->lock, NULL);
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_cond_init(&p->cond, &ca);
    pthread_condattr_destroy(&ca);
    if (pthread_create(&p->thread, NULL, run, p) != 0) {
        pthread_cond_destroy(&p->cond);
        pthread_mutex_destroy(&p->lock);
        free(p);
        return NULL;
    }
    return p;
}

void fv_progress_update(fv_progress *p, int64_t submitted, int64_t completed, double gpu_ms)
{
    if (!p) return;
    pthread_mutex_lock(&p->lock);
    p->submitted = submitted;
    p->completed = completed;
    p->gpu_ms = gpu_ms;
    pthread_mutex_unlock(&p->lock);
}

void fv_progress_set_total(fv_progress *p, int64_t total)
{
    if (!p) return;
    pthread_mutex_lock(&p->lock);
    p->total = total;
    pthread_mutex_unlock(&p->lock);
}

void fv_progress_detail(fv_progress *p, const char *detail)
{
    if (!p) return;
    pthread_mutex_lock(&p->lock);
    snprintf(p->detail, sizeof p->detail, "%s", detail ? detail : "");
    pthread_mutex_unlock(&p->lock);
}

void fv_progress_phase(fv_progress *p, const char *detail)
{
    if (!p) return;
    pthread_mutex_lock(&p->lock);
    snprintf(p->detail, sizeof p->detail, "%s", detail ? detail : "");
    p->t_phase_ns = fv_time_monotonic_ns();
    p->phase_completed = p->completed;
    if (!p->tty && (double)(p->t_phase_ns - p->t_start_ns) / 1e9 >= p->after_s) print_line(p);
    pthread_mutex_unlock(&p->lock);
}

void fv_progress_stop(fv_progress **pp)
{
    if (!pp || !*pp) return;
    fv_progress *p = *pp;
    pthread_mutex_lock(&p->lock);
    p->stop = true;
    pthread_cond_signal(&p->cond);
    pthread_mutex_unlock(&p->lock);
    pthread_join(p->thread, NULL);
    if (p->shown && p->tty) {
        fprintf(stderr, "\r%*s\r", (int)p->width, "");
        fflush(stderr);
    } else if (!p->tty && (double)(fv_time_monotonic_ns() - p->t_start_ns) / 1e9 >= p->after_s) {
        print_line(p); /* where the lines stay (not a terminal): the last state too */
    }
    pthread_cond_destroy(&p->cond);
    pthread_mutex_destroy(&p->lock);
    free(p);
    *pp = NULL;
}
