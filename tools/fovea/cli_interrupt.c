/* @brief Ctrl-C for every fovea command (see cli_interrupt.h). */
#include "cli_interrupt.h"

#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <string.h>
#include <unistd.h>

static sigset_t g_set;
static atomic_int g_count;     /* Ctrl-Cs taken so far */
static _Atomic(const char *) g_message; /* non-NULL: the command handles the first one */

/* Ended as if there were no handler: the default action, with the signal unblocked in this thread only. */
static void die_by_sigint(void)
{
    signal(SIGINT, SIG_DFL);
    raise(SIGINT); /* pending on this thread while it is blocked here */
    pthread_sigmask(SIG_UNBLOCK, &g_set, NULL);
    _exit(FV_EXIT_INTERRUPTED); /* not reached */
}

static void *waiter(void *arg)
{
    (void)arg;
    for (;;) {
        int sig = 0;
        if (sigwait(&g_set, &sig) != 0 || sig != SIGINT) continue;
        int before = atomic_fetch_add(&g_count, 1);
        const char *m = atomic_load(&g_message);
        if (!m) die_by_sigint();                    /* a command that does not handle Ctrl-C */
        if (before > 0) _exit(FV_EXIT_INTERRUPTED); /* the second Ctrl-C */
        (void)!write(STDERR_FILENO, m, strlen(m));
        (void)!write(STDERR_FILENO, "\n", 1);
    }
    return NULL;
}

static void on_sigint_unused(int sig) { (void)sig; }

void fv_cli_interrupt_install(const char *catch_message)
{
    atomic_store(&g_message, catch_message);
    sigemptyset(&g_set);
    sigaddset(&g_set, SIGINT);
    /* blocked first: from here a SIGINT stays pending until the waiter takes it */
    pthread_sigmask(SIG_BLOCK, &g_set, NULL);
    /* a disposition other than "ignore", so that the signal is kept for sigwait (a background job of a
     * non-interactive shell starts with SIGINT ignored); from here on one Ctrl-C is enough */
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_sigint_unused;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    pthread_t t;
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
    if (pthread_create(&t, &attr, waiter, NULL) != 0) {
        /* no waiter: Ctrl-C keeps its default action rather than being swallowed */
        signal(SIGINT, SIG_DFL);
        pthread_sigmask(SIG_UNBLOCK, &g_set, NULL);
    }
    pthread_attr_destroy(&attr);
}

bool fv_cli_interrupted(void) { return atomic_load(&g_count) > 0; }

void fv_cli_interrupt_child(void)
{
    sigset_t s;
    sigemptyset(&s);
    sigaddset(&s, SIGINT);
    sigprocmask(SIG_UNBLOCK, &s, NULL);
}
