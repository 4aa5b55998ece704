/* @brief Line source for the trace readers: a file through zlib's gz streaming API (plain files are read
 * transparently) or a memory buffer (plain, or gzip inflated in chunks). Memory is bounded: one chunk plus one line
 * of at most TRACE_MAX_LINE bytes, whatever the input length; so is the work of one call (an over-long line is
 * handed back as soon as it passes the limit, and its rest is dropped at most TRACE_MAX_LINE bytes a call), so an
 * endless input without newlines cannot stall the caller. Only regular files and FIFOs are opened (fv_file: the
 * open never waits for a FIFO's writer; the first bytes are waited for TRACE_FIFO_WAIT_MS at most). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fv_file.h"
#include "fv_log.h"
#include "trace_internal.h"

/* How long a FIFO may stay silent after it is opened: its writer has that long to come and say something. */
#define TRACE_FIFO_WAIT_MS 10000

static void set_name(trace_lines *l, const char *name)
{
    snprintf(l->name, sizeof l->name, "%s", name ? name : "<memory>");
}

static fv_result alloc_chunk(trace_lines *l)
{
    l->chunk = malloc(TRACE_CHUNK + 1);
    if (!l->chunk) {
        FV_ERROR(TRACE_MOD, "%s: out of memory", l->name);
        return FV_ERR_NO_MEMORY;
    }
    return FV_OK;
}

fv_result trace_lines_open_file(trace_lines *l, const char *path, const char *name)
{
    memset(l, 0, sizeof *l);
    set_name(l, name ? name : path);
    /* open without waiting for a FIFO's writer, then look at what was opened (no race with a rename): a device such
     * as /dev/zero, a directory or a socket is refused before a byte is read; a FIFO (a live trace) gets
     * TRACE_FIFO_WAIT_MS for its writer's first bytes */
    int fd;
    bool fifo;
    char err[FV_FILE_ERR_MAX];
    fv_result opened = fv_file_open_stream(path, NULL, UINT64_MAX, TRACE_FIFO_WAIT_MS, &fd, &fifo, err, sizeof err);
    if (opened != FV_OK) {
        /* the message names the path; the trace's name (when given) is what the other messages use */
        size_t pl = strlen(path);
        if (strncmp(err, path, pl) == 0) FV_ERROR(TRACE_MOD, "%s%s", l->name, err + pl);
        else FV_ERROR(TRACE_MOD, "%s: %s", l->name, err);
        return opened;
    }
    errno = 0;
    l->gz = gzdopen(fd, "rb");
    if (!l->gz) {
        int e = errno;
        close(fd);
        FV_ERROR(TRACE_MOD, "%s: cannot open: %s", l->name, e ? strerror(e) : "out of memory");
        return FV_ERR_IO;
    }
    gzbuffer(l->gz, 128u * 1024u);
    fv_result r = alloc_chunk(l);
    if (r != FV_OK) trace_lines_close(l);
    return r;
}

fv_result trace_lines_open_mem(trace_lines *l, const void *data, size_t size, const char *name)
{
    memset(l, 0, sizeof *l);
    set_name(l, name);
    l->mem = data ? data : (const uint8_t *)"";
    l->mem_size = data ? size : 0;
    l->mem_gzip = l->mem_size >= 2 && l->mem[0] == 0x1f && l->mem[1] == 0x8b;
    if (l->mem_gzip) {
        /* 16 + MAX_WBITS: expect a gzip wrapper (RFC 1952) */
        if (inflateInit2(&l->zs, 16 + MAX_WBITS) != Z_OK) {
            FV_ERROR(TRACE_MOD, "%s: zlib inflateInit2 failed", l->name);
            return FV_ERR_NO_MEMORY;
        }
        l->zs_live = true;
    }
    fv_result r = alloc_chunk(l);
    if (r != FV_OK) trace_lines_close(l);
    return r;
}

/* Refill the chunk. 0 = some bytes or end (chunk_len 0 and eof set); -1 = error in l->err. */
static int fill(trace_lines *l)
{
    l->chunk_pos = 0;
    l->chunk_len = 0;
    if (l->eof) return 0;
    if (l->gz) {
        int n = gzread(l->gz, l->chunk, TRACE_CHUNK);
        if (n < 0) {
            int errnum = 0;
            const char *msg = gzerror(l->gz, &errnum);
            snprintf(l->err, sizeof l->err, "read error: %s", msg ? msg : "unknown");
            l->eof = true;
            return -1;
        }
        if ((unsigned)n < TRACE_CHUNK) {
            int errnum = 0;
            const char *msg = gzerror(l->gz, &errnum);
            if (errnum == Z_BUF_ERROR) {
                FV_WARN(TRACE_MOD, "%s: compressed data ends early (%s); reading what is there", l->name,
                        msg ? msg : "truncated");
                l->eof = true;
            } else if (errnum != Z_OK) {
                snprintf(l->err, sizeof l->err, "read error: %s", msg ? msg : "unknown");
                l->eof = true;
                return -1;
            }
            if (n == 0) l->eof = true;
        }
        l->chunk_len = (size_t)n;
        return 0;
    }
    if (!l->mem_gzip) {
        size_t left = l->mem_size - l->mem_pos;
        size_t n = left < TRACE_CHUNK ? left : TRACE_CHUNK;
        memcpy(l->chunk, l->mem + l->mem_pos, n);
        l->mem_pos += n;
        l->chunk_len = n;
        if (n == 0) l->eof = true;
        return 0;
    }
    /* gzip in memory: inflate until the chunk has bytes or the input is exhausted. */
    while (l->chunk_len == 0) {
        size_t left = l->mem_size - l->mem_pos;
        if (left == 0) {
            if (!l->zs_ended) FV_WARN(TRACE_MOD, "%s: compressed data ends early; reading what is there", l->name);
            l->eof = true;
            return 0;
        }
        uInt in_n = left > (size_t)0x40000000u ? 0x40000000u : (uInt)left;
        l->zs.next_in = (Bytef *)(uintptr_t)(l->mem + l->mem_pos);
        l->zs.avail_in = in_n;
        l->zs.next_out = l->chunk;
        l->zs.avail_out = TRACE_CHUNK;
        int zr = inflate(&l->zs, Z_NO_FLUSH);
        size_t used = in_n - l->zs.avail_in;
        l->mem_pos += used;
        l->chunk_len = TRACE_CHUNK - l->zs.avail_out;
        if (zr == Z_STREAM_END) {
            l->zs_ended = true;
            /* Another gzip member may follow (concatenated .gz); anything else after the end is ignored. */
            size_t rest = l->mem_size - l->mem_pos;
            if (rest >= 2 && l->mem[l->mem_pos] == 0x1f && l->mem[l->mem_pos + 1] == 0x8b) {
                inflateReset(&l->zs);
                l->zs_ended = false;
            } else {
                l->mem_pos = l->mem_size;
            }
            continue;
        }
        if (zr == Z_BUF_ERROR || (zr == Z_OK && used == 0 && l->chunk_len == 0)) {
            FV_WARN(TRACE_MOD, "%s: compressed data ends early; reading what is there", l->name);
            l->mem_pos = l->mem_size;
            l->eof = true;
            return 0;
        }
        if (zr != Z_OK) {
            snprintf(l->err, sizeof l->err, "corrupt gzip data after %zu compressed bytes: %s", l->mem_pos,
                     l->zs.msg ? l->zs.msg : "inflate error");
            l->eof = true;
            return -1;
        }
    }
    return 0;
}

static fv_result keep(trace_lines *l, const uint8_t *p, size_t n)
{
    if (l->line_len + n + 1 > l->line_cap) {
        size_t cap = l->line_cap ? l->line_cap : 4096;
        while (cap < l->line_len + n + 1) cap *= 2;
        char *nl = realloc(l->line, cap);
        if (!nl) {
            snprintf(l->err, sizeof l->err, "out of memory");
            return FV_ERR_NO_MEMORY;
        }
        l->line = nl;
        l->line_cap = cap;
    }
    memcpy(l->line + l->line_len, p, n);
    l->line_len += n;
    return FV_OK;
}

/* Make chunk bytes available: 1 = some, 0 = end of input, -1 = error. */
static int avail(trace_lines *l)
{
    if (l->chunk_pos < l->chunk_len) return 1;
    if (l->eof) return 0;
    if (fill(l) < 0) return -1;
    return l->chunk_len > 0 ? 1 : 0;
}

/* Hand out an over-long line: empty text, too long, the rest of it still unread. */
static int too_long_line(trace_lines *l, char **out_line, size_t *out_len, bool *out_too_long)
{
    l->line_len = 0;
    if (keep(l, (const uint8_t *)"", 0) != FV_OK) return -1;
    l->line[0] = '\0';
    *out_line = l->line;
    *out_len = 0;
    if (out_too_long) *out_too_long = true;
    return 1;
}

int trace_lines_next(trace_lines *l, char **out_line, size_t *out_len, bool *out_too_long)
{
    bool any = false;
    char *line = NULL;
    size_t len = 0;
    l->line_len = 0;
    if (l->in_long_line) {
        /* the rest of an over-long line: dropped up to its newline, at most TRACE_MAX_LINE bytes a call */
        size_t dropped = 0;
        while (l->in_long_line) {
            int a = avail(l);
            if (a < 0) return -1;
            if (a == 0) {
                l->in_long_line = false;
                return 0;
            }
            uint8_t *start = l->chunk + l->chunk_pos;
            size_t n = l->chunk_len - l->chunk_pos;
            if (n > TRACE_MAX_LINE - dropped) n = TRACE_MAX_LINE - dropped;
            uint8_t *nl = memchr(start, '\n', n);
            size_t seg = nl ? (size_t)(nl - start) + 1 : n;
            l->chunk_pos += seg;
            l->bytes += seg;
            dropped += seg;
            if (nl) l->in_long_line = false;
            else if (dropped >= TRACE_MAX_LINE) return too_long_line(l, out_line, out_len, out_too_long);
        }
    }
    for (;;) {
        int a = avail(l);
        if (a < 0) return -1;
        if (a == 0) break;
        uint8_t *start = l->chunk + l->chunk_pos;
        size_t n = l->chunk_len - l->chunk_pos;
        uint8_t *nl = memchr(start, '\n', n);
        size_t seg = nl ? (size_t)(nl - start) : n;
        any = true;
        if (l->line_len + seg > TRACE_MAX_LINE) {
            /* rejected as soon as the limit is passed: the rest is dropped by the next calls, never buffered */
            size_t take = TRACE_MAX_LINE - l->line_len;
            l->chunk_pos += take;
            l->bytes += take;
            l->in_long_line = true;
            l->line_no++;
            return too_long_line(l, out_line, out_len, out_too_long);
        }
        if (nl && l->line_len == 0) { /* whole line inside the chunk: hand it out in place */
            *nl = '\0';
            l->chunk_pos += seg + 1;
            l->bytes += seg + 1;
            line = (char *)start;
            len = seg;
            goto done;
        }
        if (keep(l, start, seg) != FV_OK) return -1;
        l->chunk_pos += seg + (nl ? 1 : 0);
        l->bytes += seg + (nl ? 1 : 0);
        if (nl) break;
    }
    if (!any) return 0;
    if (keep(l, (const uint8_t *)"", 0) != FV_OK) return -1; /* room for the terminator */
    l->line[l->line_len] = '\0';
    line = l->line;
    len = l->line_len;
done:
    l->line_no++;
    if (len > 0 && line[len - 1] == '\r') line[--len] = '\0';
    *out_line = line;
    *out_len = len;
    if (out_too_long) *out_too_long = false;
    return 1;
}

fv_result trace_lines_rewind(trace_lines *l)
{
    l->chunk_len = l->chunk_pos = 0;
    l->eof = false;
    l->line_no = 0;
    l->bytes = 0;
    l->in_long_line = false;
    l->line_len = 0;
    l->err[0] = '\0';
    if (l->gz) {
        if (gzrewind(l->gz) != 0) {
            FV_ERROR(TRACE_MOD, "%s: cannot rewind", l->name);
            return FV_ERR_IO;
        }
        gzclearerr(l->gz);
        return FV_OK;
    }
    l->mem_pos = 0;
    if (l->zs_live) inflateReset(&l->zs);
    l->zs_ended = false;
    return FV_OK;
}

void trace_lines_close(trace_lines *l)
{
    if (l->gz) gzclose(l->gz);
    if (l->zs_live) inflateEnd(&l->zs);
    free(l->chunk);
    free(l->line);
    memset(l, 0, sizeof *l);
}
