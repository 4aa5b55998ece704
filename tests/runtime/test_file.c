/* @brief fv_file (runtime/core): the one way users' files are opened and read. A regular file is read whole and
 * NUL-terminated; a directory, a FIFO (even one with no writer: the open never waits) and a character device are
 * refused before a byte is read, naming what they are; a file over the limit is refused from its size, naming both;
 * a missing file is FV_ERR_NOT_FOUND. The stream variant takes a FIFO, waits a bounded time for its writer, and
 * reads what the writer sends. An alarm turns a hang into a failure. */
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "fv_file.h"
#include "fv_test.h"

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static const char *fifo_path(const char *name)
{
    const char *p = fv_test_tmp(name);
    unlink(p);
    assert_int_equal(mkfifo(p, 0600), 0);
    return p;
}

static void a_regular_file_is_read_whole_and_nul_terminated(void **state)
{
    (void)state;
    const char *p = fv_test_write_file("ten.txt", "0123456789", 10);
    char *data, err[FV_FILE_ERR_MAX];
    size_t n;
    assert_int_equal(fv_file_read(p, NULL, 10, &data, &n, err, sizeof err), FV_OK);
    assert_int_equal(n, 10);
    assert_memory_equal(data, "0123456789", 11); /* with its NUL */
    free(data);
    p = fv_test_write_file("empty.txt", "", 0);
    assert_int_equal(fv_file_read(p, NULL, 10, &data, &n, err, sizeof err), FV_OK);
    assert_int_equal(n, 0);
    assert_int_equal(data[0], '\0');
    free(data);
}

static void a_file_over_the_limit_is_refused_from_its_size(void **state)
{
    (void)state;
    const char *p = fv_test_write_file("eleven.txt", "0123456789a", 11);
    char *data = (char *)1, err[FV_FILE_ERR_MAX];
    size_t n = 7;
    assert_int_equal(fv_file_read(p, NULL, 10, &data, &n, err, sizeof err), FV_ERR_RANGE);
    assert_null(data);
    assert_int_equal(n, 0);
    fv_assert_contains(err, "eleven.txt: 11 bytes, larger than the 10-byte limit");
    int fd;
    uint64_t size;
    assert_int_equal(fv_file_open(p, NULL, 10, &fd, &size, err, sizeof err), FV_ERR_RANGE);
    assert_int_equal(fd, -1);
}

static void what_is_not_a_regular_file_is_refused_by_name_without_waiting(void **state)
{
    (void)state;
    char *data, err[FV_FILE_ERR_MAX];
    size_t n;
    const char *dir = fv_test_tmp("adir");
    mkdir(dir, 0700);
    assert_int_equal(fv_file_read(dir, NULL, 1000, &data, &n, err, sizeof err), FV_ERR_IO);
    fv_assert_contains(err, "adir: not a regular file: it is a directory");
    const char *fifo = fifo_path("nowriter.fifo");
    double t0 = now_s();
    assert_int_equal(fv_file_read(fifo, NULL, 1000, &data, &n, err, sizeof err), FV_ERR_IO);
    assert_true(now_s() - t0 < 5.0); /* the open does not wait for a writer */
    fv_assert_contains(err, "nowriter.fifo: not a regular file: it is a FIFO");
    assert_int_equal(fv_file_read("/dev/zero", NULL, (size_t)1 << 30, &data, &n, err, sizeof err), FV_ERR_IO);
    assert_string_equal(err, "/dev/zero: not a regular file: it is a character device");
    assert_int_equal(fv_file_read("/nonexistent/x.txt", "the thing", 10, &data, &n, err, sizeof err),
                     FV_ERR_NOT_FOUND);
    fv_assert_contains(err, "/nonexistent/x.txt: cannot open the thing: ");
    assert_string_equal(fv_file_kind_str(S_IFSOCK), "a socket");
    assert_string_equal(fv_file_kind_str(S_IFBLK), "a block device");
}

static void *write_later(void *arg)
{
    const char *path = arg;
    usleep(100 * 1000);
    FILE *f = fopen(path, "w"); /* waits for the reader, which has opened already */
    if (f) {
        fputs("hello\n", f);
        fclose(f);
    }
    return NULL;
}

static void a_stream_takes_a_fifo_and_waits_a_bounded_time_for_its_writer(void **state)
{
    (void)state;
    char err[FV_FILE_ERR_MAX];
    int fd;
    bool fifo;
    /* no writer: refused after the wait, not blocked for ever */
    const char *lonely = fifo_path("lonely.fifo");
    double t0 = now_s();
    assert_int_equal(fv_file_open_stream(lonely, NULL, 100, 200, &fd, &fifo, err, sizeof err), FV_ERR_IO);
    double dt = now_s() - t0;
    assert_true(dt >= 0.15 && dt < 5.0);
    fv_assert_contains(err, "lonely.fifo: a FIFO with no writer (nothing came in 200 ms)");
    assert_int_equal(fd, -1);
    /* a writer that comes: its bytes are read, through a blocking descriptor */
    const char *live = fifo_path("live.fifo");
    pthread_t th;
    assert_int_equal(pthread_create(&th, NULL, write_later, (void *)live), 0);
    assert_int_equal(fv_file_open_stream(live, NULL, 100, 10000, &fd, &fifo, err, sizeof err), FV_OK);
    assert_true(fifo);
    char buf[16] = {0};
    size_t got = 0;
    ssize_t k;
    while (got < 6 && (k = read(fd, buf + got, sizeof buf - 1 - got)) > 0) got += (size_t)k;
    close(fd);
    pthread_join(th, NULL);
    assert_string_equal(buf, "hello\n");
    /* a device is still refused, naming what is accepted */
    assert_int_equal(fv_file_open_stream("/dev/zero", NULL, 100, 100, &fd, &fifo, err, sizeof err), FV_ERR_IO);
    assert_string_equal(err, "/dev/zero: not a regular file or a FIFO: it is a character device");
    /* a regular file: its size limit holds */
    const char *p = fv_test_write_file("stream.txt", "abc", 3);
    assert_int_equal(fv_file_open_stream(p, NULL, 2, 100, &fd, &fifo, err, sizeof err), FV_ERR_RANGE);
    assert_int_equal(fv_file_open_stream(p, NULL, 3, 100, &fd, &fifo, err, sizeof err), FV_OK);
    assert_false(fifo);
    close(fd);
}

int main(void)
{
    alarm(60); /* a hang is a failure, not a stuck suite */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_regular_file_is_read_whole_and_nul_terminated),
        cmocka_unit_test(a_file_over_the_limit_is_refused_from_its_size),
        cmocka_unit_test(what_is_not_a_regular_file_is_refused_by_name_without_waiting),
        cmocka_unit_test(a_stream_takes_a_fifo_and_waits_a_bounded_time_for_its_writer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
