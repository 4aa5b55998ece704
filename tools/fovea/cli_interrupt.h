/* @brief Ctrl-C for every fovea command, never lost: SIGINT is blocked in every thread from the first line of main()
 * and taken by one waiter thread with sigwait, so it cannot land in a driver's or the Vulkan driver's thread (where
 * an interrupted wait might not resume) or in a window between two calls. A command that can end its work cleanly
 * (run, bench, reference, trace record) names a message for it in main's command table: the first Ctrl-C then only sets a flag that
 * its loops poll (it finishes the frame or point in flight and prints its summary, exit 130); a second one ends the
 * process at once (_exit(130)). Every other command is ended by Ctrl-C as if fovea had no handler (killed by
 * SIGINT). */
#ifndef FV_CLI_INTERRUPT_H
#define FV_CLI_INTERRUPT_H

#include <stdbool.h>

/** Block SIGINT in the calling thread (every thread made later inherits it) and start the waiter. Call first in
 *  main(), before anything else makes a thread. `catch_message` (a constant string, e.g. "fovea run: Ctrl-C:
 *  finishing the frame in flight...") non-NULL: the first Ctrl-C is the command's to handle: the message goes to
 *  stderr and fv_cli_interrupted() turns true; NULL: Ctrl-C ends the process as if there were no handler. */
void fv_cli_interrupt_install(const char *catch_message);
/** Whether Ctrl-C came (in a command that catches it; otherwise the process has already ended). */
bool fv_cli_interrupted(void);
/** For a forked child before exec: SIGINT unblocked again (exec keeps the mask, not the handler). Async-signal-safe. */
void fv_cli_interrupt_child(void);
/** Exit code of an interrupted command: 128 + SIGINT, as a shell reports it. */
#define FV_EXIT_INTERRUPTED 130

#endif
