/* @brief Opening and reading users' files without blocking on FIFOs or reading past a limit (see fv_file.h). */
#include "fv_file.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void say(char *err, size_t err_size, const char *fmt, ...) FV_PRINTF(3, 4);
static void say(char *err, size_t err_size, const char *fmt, ...)
{
    if (!err || !err_size) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, err_size, fmt, ap);
    va_end(ap);
}

const char *fv_file_kind_str(mode_t mode)
{
    if (S_ISREG(mode)) return "a regular file";
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISLNK(mode)) return "a symbolic link";
    return "not a file";
}

/* Open without blocking, fstat what was opened, refuse what is not a regular file (or a FIFO when allowed) and a
 * regular file over max_bytes. The descriptor is still non-blocking. */
static fv_result open_checked(const char *path, const char *what, uint64_t max_bytes, bool allow_fifo, int *out_fd,
                              struct stat *st, char *err, size_t err_size)
{
    *out_fd = -1;
    if (!path || !*path) {
        say(err, err_size, "no file named");
        return FV_ERR_INVALID_ARG;
    }
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        int e = errno;
        say(err, err_size, "%s: cannot open%s%s: %s", path, what ? " " : "", what ? what : "", strerror(e));
        return e == ENOENT || e == ENOTDIR ? FV_ERR_NOT_FOUND : FV_ERR_IO;
    }
    if (fstat(fd, st) != 0) {
        int e = errno;
        close(fd);
        say(err, err_size, "%s: cannot open%s%s: %s", path, what ? " " : "", what ? what : "", strerror(e));
        return FV_ERR_IO;
    }
    if (!S_ISREG(st->st_mode) && !(allow_fifo && S_ISFIFO(st->st_mode))) {
        close(fd);
        say(err, err_size, "%s: not a regular file%s: it is %s", path, allow_fifo ? " or a FIFO" : "",
            fv_file_kind_str(st->st_mode));
        return FV_ERR_IO;
    }
    if (S_ISREG(st->st_mode) && st->st_size >= 0 && (uint64_t)st->st_size > max_bytes) {
        close(fd);
        say(err, err_size, "%s: %llu bytes, larger than the %llu-byte limit", path, (unsigned long long)st->st_size,
            (unsigned long long)max_bytes);
        return FV_ERR_RANGE;
    }
    *out_fd = fd;
    return FV_OK;
}

static fv_result make_blocking(const char *path, int fd, char *err, size_t err_size)
{
    int fl = fcntl(fd, F_GETFL);
    if (fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0) {
        say(err, err_size, "%s: cannot open: %s", path, strerror(errno));
        return FV_ERR_IO;
    }
    return FV_OK;
}

fv_result fv_file_open(const char *path, const char *what, uint64_t max_bytes, int *out_fd, uint64_t *out_size,
                       char *err, size_t err_size)
{
    struct stat st;
    *out_fd = -1;
    *out_size = 0;
    FV_TRY(open_checked(path, what, max_bytes, false, out_fd, &st, err, err_size));
    fv_result r = make_blocking(path, *out_fd, err, err_size);
    if (r != FV_OK) {
        close(*out_fd);
        *out_fd = -1;
        return r;
    }
    *out_size = st.st_size > 0 ? (uint64_t)st.st_size : 0;
    return FV_OK;
}

fv_result fv_file_open_stream(const char *path, const char *what, uint64_t max_bytes, int fifo_wait_ms, int *out_fd,
                              bool *out_fifo, char *err, size_t err_size)
{
    struct stat st;
    *out_fd = -1;
    *out_fifo = false;
    FV_TRY(open_checked(path, what, max_bytes, true, out_fd, &st, err, err_size));
    int fd = *out_fd;
    fv_result r = FV_OK;
    if (S_ISFIFO(st.st_mode)) {
        /* Until a writer has come, poll() reports nothing on the read end (no hang-up either): wait for its first
         * bytes or its close, not for ever. */
        struct pollfd p = {.fd = fd, .events = POLLIN};
        int n;
        do n = poll(&p, 1, fifo_wait_ms < 0 ? 0 : fifo_wait_ms);
        while (n < 0 && errno == EINTR);
        if (n < 0) {
            say(err, err_size, "%s: cannot wait for the FIFO's writer: %s", path, strerror(errno));
            r = FV_ERR_IO;
        } else if (n == 0) {
            say(err, err_size, "%s: a FIFO with no writer (nothing came in %d ms)", path, fifo_wait_ms);
            r = FV_ERR_IO;
        }
        *out_fifo = true;
    }
    if (r == FV_OK) r = make_blocking(path, fd, err, err_size);
    if (r != FV_OK) {
        close(fd);
        *out_fd = -1;
        *out_fifo = false;
    }
    return r;
}

/* read() until n bytes or the end; -1 on an error (errno set). */
static ssize_t read_full(int fd, char *buf, size_t n)
{
    size_t got = 0;
    while (got < n) {
        ssize_t k = read(fd, buf + got, n - got);
        if (k < 0 && errno == EINTR) continue;
        if (k < 0) return -1;
        if (k == 0) break;
        got += (size_t)k;
    }
    return (ssize_t)got;
}

fv_result fv_file_read(const char *path, const char *what, size_t max_bytes, char **out_data, size_t *out_size,
                       char *err, size_t err_size)
{
    *out_data = NULL;
    *out_size = 0;
    int fd;
    uint64_t size;
    FV_TRY(fv_file_open(path, what, max_bytes, &fd, &size, err, err_size));
    char *buf = malloc((size_t)size + 1);
    if (!buf) {
        close(fd);
        say(err, err_size, "%s: out of memory for its %llu bytes", path, (unsigned long long)size);
        return FV_ERR_NO_MEMORY;
    }
    ssize_t n = read_full(fd, buf, (size_t)size);
    char extra;
    ssize_t more = n >= 0 ? read_full(fd, &extra, 1) : 0; /* a byte past what fstat said: it grew */
    int e = errno;
    close(fd);
    if (n < 0 || more < 0) {
        free(buf);
        say(err, err_size, "%s: read error: %s", path, strerror(e));
        return FV_ERR_IO;
    }
    if (more > 0) {
        free(buf);
        say(err, err_size, "%s: grew while read (it had %llu bytes when opened)", path, (unsigned long long)size);
        return FV_ERR_IO;
    }
    buf[n] = '\0';
    *out_data = buf;
    *out_size = (size_t)n;
    return FV_OK;
}
