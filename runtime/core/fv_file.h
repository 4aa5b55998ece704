/* @brief Opening and reading files named by users, the one way: open with O_RDONLY | O_NONBLOCK | O_CLOEXEC (a FIFO
 * without a writer cannot block the open), look at what was opened with fstat (no race with a rename), refuse what
 * is not a regular file naming what it is, refuse a size over the caller's limit before a byte is read, and read
 * at most that many bytes. Each failure is one line in the caller's buffer, "<path>: <reason>", for the caller to
 * log its own way. libc only; thread-safe. */
#ifndef FV_FILE_H
#define FV_FILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#include "fv_result.h"

/** A buffer this large holds any message of these functions for a path of up to 4096 bytes. */
#define FV_FILE_ERR_MAX 4352

/** What a file of this st_mode is, for messages: "a regular file", "a directory", "a FIFO", "a character device",
 *  "a block device", "a socket", "a symbolic link", else "not a file". */
const char *fv_file_kind_str(mode_t mode);

/** Open a regular file for reading. `what` names it in "cannot open <what>" (NULL: "cannot open"). On success
 *  *out_fd is a blocking descriptor (the caller closes it) and *out_size the size fstat gave, at most max_bytes.
 *  Errors, each with one line in err ("<path>: ..."): FV_ERR_NOT_FOUND (missing), FV_ERR_IO (cannot open; not a
 *  regular file: "not a regular file: it is a FIFO"), FV_ERR_RANGE ("N bytes, larger than the L-byte limit"). */
FV_MUST_CHECK fv_result fv_file_open(const char *path, const char *what, uint64_t max_bytes, int *out_fd,
                                     uint64_t *out_size, char *err, size_t err_size);

/** As fv_file_open, but a FIFO (a live stream) is accepted too: the open does not wait for its writer; this call
 *  then waits at most fifo_wait_ms for the writer's first bytes (or its close), and fails with FV_ERR_IO ("a FIFO
 *  with no writer for N ms") when none comes. Anything else is refused with "not a regular file or a FIFO: it is
 *  ...". *out_fifo tells which was opened; *out_fd is blocking. max_bytes applies to regular files only. */
FV_MUST_CHECK fv_result fv_file_open_stream(const char *path, const char *what, uint64_t max_bytes, int fifo_wait_ms,
                                            int *out_fd, bool *out_fifo, char *err, size_t err_size);

/** Read a whole regular file of at most max_bytes (fv_file_open's checks first, then a bounded read: a file that
 *  grows while read is refused). *out_data is malloc'ed with one NUL byte after *out_size bytes (free() it).
 *  Errors as fv_file_open, plus FV_ERR_IO (read error, grew while read) and FV_ERR_NO_MEMORY. */
FV_MUST_CHECK fv_result fv_file_read(const char *path, const char *what, size_t max_bytes, char **out_data,
                                     size_t *out_size, char *err, size_t err_size);

#endif
