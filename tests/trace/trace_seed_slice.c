/* @brief Build-time helper for the trace fuzzers: writes a small slice of a real recording (the header line, then
 * N lines after SKIP) as a seed, optionally gzip-compressed, optionally followed by '\f' and a slice of a second
 * file (the Pupil fuzzers read "gaze \f blinks"). Reads plain or gzip input through zlib. Nothing is copied into the
 * repository: the seeds live in the build tree. GZIP = 2 converts the slice to fovea's own format instead.
 * usage: trace_seed_slice OUT GZIP IN HEADER SKIP N [IN2 HEADER2 SKIP2 N2] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "fv_trace.h"

static int slice(const char *in, int header, long skip, long n, char **buf, size_t *len, size_t *cap)
{
    gzFile g = gzopen(in, "rb");
    if (!g) {
        fprintf(stderr, "trace_seed_slice: cannot open %s\n", in);
        return 1;
    }
    static char line[1 << 16];
    long i = 0;
    while (gzgets(g, line, sizeof line)) {
        int take = (header && i == 0) || (i - header >= skip && i - header < skip + n);
        i++;
        if (!take) continue;
        size_t l = strlen(line);
        if (*len + l + 1 > *cap) {
            *cap = (*len + l + 1) * 2;
            *buf = realloc(*buf, *cap);
            if (!*buf) return 1;
        }
        memcpy(*buf + *len, line, l);
        *len += l;
    }
    gzclose(g);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 7 && argc != 11) {
        fprintf(stderr, "usage: trace_seed_slice OUT GZIP IN HEADER SKIP N [IN2 HEADER2 SKIP2 N2]\n");
        return 2;
    }
    char *buf = NULL;
    size_t len = 0, cap = 0;
    if (slice(argv[3], atoi(argv[4]), atol(argv[5]), atol(argv[6]), &buf, &len, &cap)) return 1;
    if (argc == 11) {
        if (len + 1 > cap) buf = realloc(buf, cap = len + 1);
        if (!buf) return 1;
        buf[len++] = '\f';
        if (slice(argv[7], atoi(argv[8]), atol(argv[9]), atol(argv[10]), &buf, &len, &cap)) return 1;
    }
    if (atoi(argv[2]) == 2) { /* fovea's format, through the reader and the writer */
        fv_trace_reader_desc d = {.data = buf, .size = len, .blinks_path = ""};
        fv_trace_reader *r = NULL;
        fv_trace_writer *w = NULL;
        fv_gaze_sample s;
        if (fv_trace_reader_create(NULL, &d, &r) != FV_OK || fv_trace_writer_create(argv[1], NULL, &w) != FV_OK)
            return 1;
        while (fv_trace_reader_next(r, &s) == FV_OK)
            if (fv_trace_writer_write(w, &s) != FV_OK) return 1;
        fv_trace_reader_destroy(&r);
        free(buf);
        return fv_trace_writer_finish(&w) == FV_OK ? 0 : 1;
    }
    gzFile out = gzopen(argv[1], atoi(argv[2]) ? "wb9" : "wbT");
    if (!out || (len && gzwrite(out, buf, (unsigned)len) != (int)len) || gzclose(out) != Z_OK) {
        fprintf(stderr, "trace_seed_slice: cannot write %s\n", argv[1]);
        return 1;
    }
    free(buf);
    return 0;
}
