/* @brief The per-frame CSV record of `fovea run --frame-log` (see run_frame_log.h): writer and reader. */
#include "run_frame_log.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fv_file.h"
#include "fv_gaze_pipeline.h"
#include "fv_log.h"

#define MOD "frame-log"
#define MAX_ROWS 10000000u
#define LINE_MAX_BYTES 4096 /* a line of at most 4094 bytes, its newline (\r\n) and the NUL */
/* The largest frame log read: MAX_ROWS rows of about 400 bytes; refused from its size before a byte is read. */
#define FRAME_LOG_MAX_BYTES ((uint64_t)4 << 30)

enum {
    C_FRAME, C_HAS_GAZE, C_FRESH, C_LATE, C_LOST, C_EVENT, C_SEQ,
    C_T_DEV, C_T_CAPTURE, C_T_RECEIVED, C_T_WAKE, C_T_LATCH, C_T_CPU, C_T_SUBMIT, C_T_GPU_BEGIN, C_T_GPU_END,
    C_T_PRESENT, C_T_VSYNC, C_T_PHOTON, C_TARGET_VSYNC, C_SHOWN_VSYNC, C_REPEATED, C_G2P,
    C_L_VALID, C_L_YAW, C_L_PITCH, C_R_VALID, C_R_YAW, C_R_PITCH, C_UNC, C_PUPIL, C_GPU, C_CPU,
    C_HEAD_SOURCE, C_HEAD_SEQ, C_HEAD_X, C_HEAD_Y, C_HEAD_Z, C_FWD_X, C_FWD_Y, C_FWD_Z,
    C_COUNT
};

static const char *const g_cols[C_COUNT] = {
    "frame_id", "has_gaze", "fresh_gaze", "late", "device_lost", "gaze_event", "sample_seq",
    "t_sample_device_ns", "t_sample_capture_ns", "t_sample_received_ns", "t_wake_ns", "t_latch_ns", "t_cpu_begin_ns",
    "t_submit_ns", "t_gpu_begin_ns", "t_gpu_end_ns", "t_present_ns", "t_vsync_ns", "t_photon_ns", "target_vsync",
    "shown_vsync", "repeated_vsyncs", "gaze_to_photon_ms",
    "left_gaze_valid", "left_gaze_yaw_deg", "left_gaze_pitch_deg", "right_gaze_valid", "right_gaze_yaw_deg",
    "right_gaze_pitch_deg", "uncertainty_deg", "pupil_mm", "gpu_ms", "cpu_ms",
    "head_source", "head_sample_seq", "head_x_m", "head_y_m", "head_z_m", "head_fwd_x", "head_fwd_y", "head_fwd_z",
};

/* ---- writing ---- */

static void put_f(FILE *f, double v, const char *fmt)
{
    fputc(',', f);
    if (isfinite(v)) fprintf(f, fmt, v);
}

static void put_i(FILE *f, int64_t v) { fprintf(f, ",%" PRId64, v); }

/* Gaze in eye view space (-z forward) as yaw (right +) and pitch (up +), degrees. */
static void put_gaze(FILE *f, const fv_eye_gaze *g)
{
    fprintf(f, ",%d", g->valid ? 1 : 0);
    double x = g->dir_eye.x, y = g->dir_eye.y, z = g->dir_eye.z;
    bool ok = g->valid && isfinite(x) && isfinite(y) && isfinite(z) && (x * x + y * y + z * z) > 0.0;
    put_f(f, ok ? atan2(x, -z) * (180.0 / 3.14159265358979323846) : NAN, "%.4f");
    put_f(f, ok ? atan2(y, sqrt(x * x + z * z)) * (180.0 / 3.14159265358979323846) : NAN, "%.4f");
}

fv_result run_frame_log_write(const char *path, const run_frame_row *rows, size_t n)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        FV_ERROR(MOD, "%s: cannot create the frame log: %s", path, strerror(errno));
        return FV_ERR_IO;
    }
    for (int c = 0; c < C_COUNT; c++) fprintf(f, "%s%s", c ? "," : "", g_cols[c]);
    fputc('\n', f);
    for (size_t i = 0; i < n; i++) {
        const run_frame_row *r = &rows[i];
        const fv_latency_record *l = r->lat;
        fprintf(f, "%" PRIu64, r->frame_id);
        if (l) {
            fprintf(f, ",%d,%d,%d,%d,%s,%" PRIu64, l->has_gaze, l->fresh_gaze, l->late, l->device_lost,
                    fv_gaze_event_str((fv_gaze_event)l->gaze_event), l->sample_seq);
            const int64_t t[] = {l->t_sample_device_ns, l->t_sample_capture_ns, l->t_sample_received_ns, l->t_wake_ns,
                                 l->t_latch_ns, l->t_cpu_begin_ns, l->t_submit_ns, l->t_gpu_begin_ns,
                                 l->t_gpu_end_ns, l->t_present_ns, l->t_vsync_ns, l->t_photon_ns};
            for (size_t k = 0; k < sizeof t / sizeof t[0]; k++) {
                /* sample times are 0 when no sample ever came: unknown, not the epoch */
                if (k < 3 && !l->sample_seq && !l->t_sample_received_ns) fputc(',', f);
                else put_i(f, t[k]);
            }
            fprintf(f, ",%" PRIu64 ",%" PRIu64 ",%u", l->target_vsync, l->shown_vsync, l->repeated_vsyncs);
            put_f(f, l->has_gaze ? (double)fv_latency_gaze_to_photon_ns(l) / 1e6 : NAN, "%.6f");
            put_gaze(f, &r->gaze[0]);
            put_gaze(f, &r->gaze[1]);
            put_f(f, l->uncertainty_deg, "%.4f");
        } else {
            for (int c = C_HAS_GAZE; c < C_UNC + 1; c++) fputc(',', f);
        }
        put_f(f, r->pupil_mm, "%.4f");
        put_f(f, r->gpu_ms, "%.6f");
        put_f(f, r->cpu_ms, "%.6f");
        fprintf(f, ",%s,", r->head_source ? r->head_source : "scene");
        if (r->head_recorded) fprintf(f, "%" PRIu64, r->head_seq);
        fv_vec3 fwd = fv_quat_rotate(r->head.orientation, fv_v3(0, 0, -1));
        put_f(f, r->head.position_m.x, "%.9g");
        put_f(f, r->head.position_m.y, "%.9g");
        put_f(f, r->head.position_m.z, "%.9g");
        put_f(f, fwd.x, "%.9g");
        put_f(f, fwd.y, "%.9g");
        put_f(f, fwd.z, "%.9g");
        fputc('\n', f);
    }
    bool bad = ferror(f) != 0;
    if (fclose(f) != 0) bad = true;
    if (bad) {
        FV_ERROR(MOD, "%s: writing the frame log failed (disk full?)", path);
        return FV_ERR_IO;
    }
    return FV_OK;
}

/* ---- reading ---- */

static int split(char *line, char **f, int cap)
{
    int n = 0;
    for (char *p = line;; n++) {
        if (n >= cap) return -1;
        f[n] = p;
        char *c = strchr(p, ',');
        if (!c) {
            p[strcspn(p, "\r\n")] = '\0';
            return n + 1;
        }
        *c = '\0';
        p = c + 1;
    }
}

/* A line fgets left unfinished (the buffer full, no newline, the file goes on) is read on to its end without being
 * kept: its length, without the newline (the file's size bounds the work). 0 for a line that fits. */
static uint64_t over_long(const char *line, size_t cap, FILE *fp)
{
    size_t len = strlen(line);
    if (len < cap - 1 || line[len - 1] == '\n') return 0;
    int c = fgetc(fp);
    if (c == EOF) return 0; /* the last line, exactly as long as the buffer allows, without a newline */
    uint64_t n = len;
    int prev = (unsigned char)line[len - 1];
    for (; c != EOF && c != '\n'; c = fgetc(fp)) n++, prev = c;
    if (c == '\n' && prev == '\r') n--; /* the CR of a CRLF is not counted */
    return n > cap - 2 ? n : 0;
}

typedef struct rd {
    const char *path;
    uint64_t line;
} rd;

static bool get_i64(const rd *r, char **f, const int *col, int c, bool required, int64_t *out)
{
    const char *s = col[c] >= 0 ? f[col[c]] : "";
    if (!*s) {
        if (required) FV_ERROR(MOD, "%s:%llu: column '%s' is empty", r->path, (unsigned long long)r->line, g_cols[c]);
        *out = 0;
        return !required;
    }
    char *end;
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (end == s || *end || errno) {
        FV_ERROR(MOD, "%s:%llu: column '%s': '%.32s' is not an integer", r->path, (unsigned long long)r->line,
                 g_cols[c], s);
        return false;
    }
    *out = v;
    return true;
}

static bool get_f64(const rd *r, char **f, const int *col, int c, double *out)
{
    const char *s = col[c] >= 0 ? f[col[c]] : "";
    *out = NAN;
    if (!*s) return true;
    char *end;
    double v = strtod(s, &end);
    if (end == s || *end || !isfinite(v)) {
        FV_ERROR(MOD, "%s:%llu: column '%s': '%.32s' is not a finite number", r->path, (unsigned long long)r->line,
                 g_cols[c], s);
        return false;
    }
    *out = v;
    return true;
}

void run_frame_log_fini(run_frame_log *log)
{
    free(log->records);
    free(log->gpu_ms);
    free(log->uncertainty_deg);
    memset(log, 0, sizeof *log);
}

fv_result run_frame_log_read(const char *path, run_frame_log *out)
{
    memset(out, 0, sizeof *out);
    int fd;
    uint64_t size;
    char err[FV_FILE_ERR_MAX];
    fv_result opened = fv_file_open(path, "the frame log", FRAME_LOG_MAX_BYTES, &fd, &size, err, sizeof err);
    if (opened != FV_OK) {
        FV_ERROR(MOD, "%s", err);
        return opened;
    }
    FILE *fp = fdopen(fd, "r");
    if (!fp) {
        FV_ERROR(MOD, "%s: cannot open the frame log: %s", path, strerror(errno));
        close(fd);
        return FV_ERR_IO;
    }
    static char line[LINE_MAX_BYTES];
    char *f[C_COUNT + 16];
    int col[C_COUNT];
    rd r = {path, 1};
    fv_result res = FV_ERR_PARSE;
    size_t cap = 0;
    if (!fgets(line, sizeof line, fp)) {
        FV_ERROR(MOD, "%s: empty file: not a frame log (write one with fovea run --frame-log FILE.csv)", path);
        goto fail;
    }
    uint64_t long_line = over_long(line, sizeof line, fp);
    if (long_line) {
        FV_ERROR(MOD, "%s:1: the header line is %llu bytes, longer than the limit of %d: not a frame log of fovea "
                 "run --frame-log", path, (unsigned long long)long_line, LINE_MAX_BYTES - 2);
        goto fail;
    }
    int nh = split(line, f, C_COUNT + 16);
    for (int c = 0; c < C_COUNT; c++) {
        col[c] = -1;
        for (int i = 0; i < nh; i++)
            if (strcmp(f[i], g_cols[c]) == 0) col[c] = i;
    }
    static const int required[] = {C_FRAME, C_HAS_GAZE, C_T_CAPTURE, C_T_PHOTON, C_T_VSYNC};
    for (size_t k = 0; k < sizeof required / sizeof required[0]; k++)
        if (col[required[k]] < 0) {
            FV_ERROR(MOD, "%s:1: no column '%s': not a frame log of fovea run --frame-log", path,
                     g_cols[required[k]]);
            goto fail;
        }
    while (fgets(line, sizeof line, fp)) {
        r.line++;
        if ((long_line = over_long(line, sizeof line, fp)) != 0) {
            FV_ERROR(MOD, "%s:%llu: the line is %llu bytes, longer than the limit of %d", path,
                     (unsigned long long)r.line, (unsigned long long)long_line, LINE_MAX_BYTES - 2);
            goto fail;
        }
        if (line[0] == '\n' || line[0] == '\0') continue;
        int n = split(line, f, C_COUNT + 16);
        if (n != nh) {
            FV_ERROR(MOD, "%s:%llu: %d fields, the header has %d", path, (unsigned long long)r.line, n < 0 ? 0 : n,
                     nh);
            goto fail;
        }
        if (out->n >= MAX_ROWS) {
            FV_ERROR(MOD, "%s: more than %u rows", path, MAX_ROWS);
            goto fail;
        }
        if (out->n == cap) {
            size_t nc = cap ? cap * 2 : 1024;
            fv_latency_record *nr = realloc(out->records, nc * sizeof *nr);
            if (nr) out->records = nr;
            double *ng = realloc(out->gpu_ms, nc * sizeof *ng);
            if (ng) out->gpu_ms = ng;
            double *nu = realloc(out->uncertainty_deg, nc * sizeof *nu);
            if (nu) out->uncertainty_deg = nu;
            if (!nr || !ng || !nu) {
                res = FV_ERR_NO_MEMORY;
                goto fail;
            }
            cap = nc;
        }
        fv_latency_record *l = &out->records[out->n];
        memset(l, 0, sizeof *l);
        int64_t v;
        bool gaze_cols = f[col[C_HAS_GAZE]][0] != '\0';
        if (!get_i64(&r, f, col, C_FRAME, true, &v)) goto fail;
        l->frame_id = (uint64_t)v;
        if (gaze_cols) {
            out->rows_with_gaze_columns++;
            int64_t b[4];
            const int bc[4] = {C_HAS_GAZE, C_FRESH, C_LATE, C_LOST};
            for (int k = 0; k < 4; k++) {
                if (!get_i64(&r, f, col, bc[k], false, &b[k])) goto fail;
                if (b[k] != 0 && b[k] != 1) {
                    FV_ERROR(MOD, "%s:%llu: column '%s' is %lld, not 0 or 1", path, (unsigned long long)r.line,
                             g_cols[bc[k]], (long long)b[k]);
                    goto fail;
                }
            }
            l->has_gaze = b[0], l->fresh_gaze = b[1], l->late = b[2], l->device_lost = b[3];
            int64_t *dst[] = {&l->t_sample_device_ns, &l->t_sample_capture_ns, &l->t_sample_received_ns,
                              &l->t_wake_ns, &l->t_latch_ns, &l->t_cpu_begin_ns, &l->t_submit_ns,
                              &l->t_gpu_begin_ns, &l->t_gpu_end_ns, &l->t_present_ns, &l->t_vsync_ns,
                              &l->t_photon_ns};
            for (int k = 0; k < 12; k++)
                if (!get_i64(&r, f, col, C_T_DEV + k, false, dst[k])) goto fail;
            if (!get_i64(&r, f, col, C_SEQ, false, &v)) goto fail;
            l->sample_seq = (uint64_t)v;
            if (!get_i64(&r, f, col, C_TARGET_VSYNC, false, &v)) goto fail;
            l->target_vsync = (uint64_t)v;
            if (!get_i64(&r, f, col, C_SHOWN_VSYNC, false, &v)) goto fail;
            l->shown_vsync = (uint64_t)v;
            if (!get_i64(&r, f, col, C_REPEATED, false, &v)) goto fail;
            if (v < 0 || v > UINT32_MAX) {
                FV_ERROR(MOD, "%s:%llu:%d: column '%s' is %lld, outside 0..%u", path, (unsigned long long)r.line,
                         col[C_REPEATED] + 1, g_cols[C_REPEATED], (long long)v, UINT32_MAX);
                goto fail;
            }
            l->repeated_vsyncs = (uint32_t)v;
            int64_t g2p = fv_latency_gaze_to_photon_ns(l); /* saturated */
            if (l->has_gaze && (g2p < 0 || g2p == INT64_MAX)) {
                FV_ERROR(MOD, "%s:%llu: %s (t_photon_ns %lld, t_sample_capture_ns %lld)", path,
                         (unsigned long long)r.line,
                         g2p < 0 ? "photons before the sample was captured: a negative gaze-to-photon latency"
                                 : "a gaze-to-photon latency past the 64-bit ns range",
                         (long long)l->t_photon_ns, (long long)l->t_sample_capture_ns);
                goto fail;
            }
        }
        double unc;
        if (!get_f64(&r, f, col, C_GPU, &out->gpu_ms[out->n]) || !get_f64(&r, f, col, C_UNC, &unc)) goto fail;
        out->uncertainty_deg[out->n] = unc;
        l->uncertainty_deg = isfinite(unc) ? (float)unc : 0.0f;
        out->n++;
    }
    if (ferror(fp)) {
        FV_ERROR(MOD, "%s: read error", path);
        res = FV_ERR_IO;
        goto fail;
    }
    if (out->n == 0) {
        FV_ERROR(MOD, "%s: a header and no frames", path);
        goto fail;
    }
    fclose(fp);
    return FV_OK;
fail:
    fclose(fp);
    run_frame_log_fini(out);
    return res;
}
