/* @brief Writer of fovea's own trace format (version 1, docs/trace-format.md), through zlib's gz API: gzip when
 * asked (or the path ends in ".gz"), plain text otherwise ("wT" = transparent). Floats are written with 9
 * significant digits, which round-trips every float32 exactly; NaN is an empty field. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "fv_log.h"
#include "trace_internal.h"

struct fv_trace_writer {
    gzFile gz;
    char path[512];
    uint64_t rows;
    bool failed;
};

static fv_result put(fv_trace_writer *w, const char *s, size_t n)
{
    if (w->failed) return FV_ERR_IO;
    if (n == 0) return FV_OK;
    if (gzwrite(w->gz, s, (unsigned)n) != (int)n) {
        int errnum = 0;
        const char *msg = gzerror(w->gz, &errnum);
        FV_ERROR(TRACE_MOD, "%s: write failed: %s", w->path,
                 errnum == Z_ERRNO ? strerror(errno) : (msg ? msg : "unknown"));
        w->failed = true;
        return FV_ERR_IO;
    }
    return FV_OK;
}

fv_result fv_trace_writer_create(const char *path, const fv_trace_writer_desc *desc, fv_trace_writer **out_writer)
{
    static const fv_trace_writer_desc zero;
    if (!path || !out_writer) return FV_ERR_INVALID_ARG;
    *out_writer = NULL;
    if (!desc) desc = &zero;
    fv_result res = FV_OK;
    fv_trace_writer *w = calloc(1, sizeof *w);
    if (!w) return FV_ERR_NO_MEMORY;
    snprintf(w->path, sizeof w->path, "%s", path);
    size_t pl = strlen(path);
    bool gzip = desc->gzip || (pl > 3 && strcmp(path + pl - 3, ".gz") == 0);
    errno = 0;
    w->gz = gzopen(path, gzip ? "wb6" : "wbT");
    if (!w->gz) {
        FV_ERROR(TRACE_MOD, "%s: cannot create: %s", path, errno ? strerror(errno) : "out of memory");
        res = errno == ENOENT ? FV_ERR_NOT_FOUND : FV_ERR_IO;
        goto fail;
    }
    gzbuffer(w->gz, 128u * 1024u);
    char buf[1024];
    int n = snprintf(buf, sizeof buf, "fovea-trace 1\n# head frame: +x right, +y up, -z forward; mm, ns\n");
    res = put(w, buf, (size_t)n);
    if (res == FV_OK && desc->source) {
        /* one line: control characters in the source text become spaces */
        n = snprintf(buf, sizeof buf, "# source: %.900s\n", desc->source);
        for (int i = 10; i < n - 1; i++)
            if ((unsigned char)buf[i] < 0x20) buf[i] = ' ';
        res = put(w, buf, (size_t)n);
    }
    if (res == FV_OK && desc->rate_hz > 0 && isfinite(desc->rate_hz)) {
        n = snprintf(buf, sizeof buf, "# rate_hz: %.6g\n", desc->rate_hz);
        res = put(w, buf, (size_t)n);
    }
    for (int i = 0; res == FV_OK && i < TRACE_FOVEA_NCOLS; i++) {
        res = put(w, trace_fovea_cols[i], strlen(trace_fovea_cols[i]));
        if (res == FV_OK) res = put(w, i + 1 < TRACE_FOVEA_NCOLS ? "," : "\n", 1);
    }
    if (res != FV_OK) goto fail;
    *out_writer = w;
    return FV_OK;
fail:
    fv_trace_writer_destroy(&w);
    return res;
}

static char *put_f(char *p, float v)
{
    if (isfinite(v)) p += sprintf(p, "%.9g", (double)v);
    *p++ = ',';
    return p;
}

static char *put_v3(char *p, fv_vec3 v)
{
    p = put_f(p, v.x);
    p = put_f(p, v.y);
    return put_f(p, v.z);
}

fv_result fv_trace_writer_write(fv_trace_writer *w, const fv_gaze_sample *s)
{
    if (!w || !s) return FV_ERR_INVALID_ARG;
    /* 40 fields, the longest about 20 characters each */
    char buf[1200];
    char *p = buf;
    p += sprintf(p, "%lld,", (long long)s->t_device_ns);
    if (s->flags & FV_GAZE_HOST_TIME_VALID) p += sprintf(p, "%lld", (long long)s->t_host_ns);
    *p++ = ',';
    p += sprintf(p, "%u,", (unsigned)s->flags);
    p = put_f(p, s->confidence);
    p += sprintf(p, "%llu,", (unsigned long long)s->seq);
    const fv_eye_sample *eyes[3] = {&s->eye[FV_EYE_LEFT], &s->eye[FV_EYE_RIGHT], &s->combined};
    for (int k = 0; k < 3; k++) {
        p += sprintf(p, "%u,", (unsigned)eyes[k]->flags);
        p = put_v3(p, eyes[k]->origin_mm);
        p = put_v3(p, eyes[k]->direction);
        p = put_f(p, eyes[k]->pupil_mm);
        p = put_f(p, eyes[k]->openness);
    }
    p = put_f(p, s->screen_point_mm.x);
    p = put_f(p, s->screen_point_mm.y);
    p = put_v3(p, s->head_pos_mm);
    p = put_v3(p, s->head_dir);
    p[-1] = '\n';
    FV_TRY(put(w, buf, (size_t)(p - buf)));
    w->rows++;
    return FV_OK;
}

fv_result fv_trace_writer_finish(fv_trace_writer **pw)
{
    if (!pw || !*pw) return FV_ERR_INVALID_ARG;
    fv_trace_writer *w = *pw;
    fv_result res = w->failed ? FV_ERR_IO : FV_OK;
    int zr = gzclose(w->gz);
    w->gz = NULL;
    if (zr != Z_OK && res == FV_OK) {
        FV_ERROR(TRACE_MOD, "%s: closing failed (%s)", w->path, zr == Z_ERRNO ? strerror(errno) : "zlib error");
        res = FV_ERR_IO;
    }
    free(w);
    *pw = NULL;
    return res;
}

void fv_trace_writer_destroy(fv_trace_writer **pw)
{
    if (!pw || !*pw) return;
    if ((*pw)->gz) gzclose((*pw)->gz);
    free(*pw);
    *pw = NULL;
}
