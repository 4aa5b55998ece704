/* @brief fovea's own trace format, version 1 (docs/trace-format.md): a text file (optionally gzip) whose first line
 * is "fovea-trace 1", then "# key: value" metadata lines, then a comma-separated column header and one row per
 * sample, already in fovea's head frame. Empty field = NaN/unknown. Columns are found by name; only t_device_ns is
 * required, so files from later versions with extra columns still read. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "trace_internal.h"

const char *const trace_fovea_cols[TRACE_FOVEA_NCOLS] = {
    "t_device_ns", "t_host_ns", "flags", "confidence", "seq",
    "l_flags", "l_origin_x_mm", "l_origin_y_mm", "l_origin_z_mm", "l_dir_x", "l_dir_y", "l_dir_z", "l_pupil_mm",
    "l_openness",
    "r_flags", "r_origin_x_mm", "r_origin_y_mm", "r_origin_z_mm", "r_dir_x", "r_dir_y", "r_dir_z", "r_pupil_mm",
    "r_openness",
    "c_flags", "c_origin_x_mm", "c_origin_y_mm", "c_origin_z_mm", "c_dir_x", "c_dir_y", "c_dir_z", "c_pupil_mm",
    "c_openness",
    "screen_x_mm", "screen_y_mm", "head_x_mm", "head_y_mm", "head_z_mm", "head_dir_x", "head_dir_y", "head_dir_z",
};

enum { F_T, F_HOST, F_FLAGS, F_CONF, F_SEQ, F_EYE0, F_SCREEN_X = F_EYE0 + 27, F_HEAD_X = F_SCREEN_X + 2 };

static fv_result begin(fv_trace_reader *r, char *line, size_t len)
{
    (void)len;
    const char *p = line;
    if (p[0] == '\xEF' && p[1] == '\xBB' && p[2] == '\xBF') p += 3;
    int64_t version = 0;
    if (strncmp(p, "fovea-trace ", 12) != 0 || !trace_parse_i64(p + 12, &version)) {
        FV_ERROR(TRACE_MOD, "%s:%llu: first line must be 'fovea-trace <version>'", r->name,
                 (unsigned long long)r->lines.line_no);
        return FV_ERR_PARSE;
    }
    if (version != 1) {
        FV_ERROR(TRACE_MOD, "%s:%llu: fovea-trace version %lld is not supported (this build reads version 1)",
                 r->name, (unsigned long long)r->lines.line_no, (long long)version);
        return FV_ERR_UNSUPPORTED;
    }
    for (;;) {
        char *l;
        size_t n;
        bool too_long;
        int rc = trace_lines_next(&r->lines, &l, &n, &too_long);
        if (rc < 0) {
            FV_ERROR(TRACE_MOD, "%s: %s", r->name, r->lines.err);
            return FV_ERR_IO;
        }
        if (rc == 0) {
            FV_ERROR(TRACE_MOD, "%s: no column header line after the metadata", r->name);
            return FV_ERR_PARSE;
        }
        if (r->lines.bytes > TRACE_MAX_SKIP) { /* endless metadata or blank lines */
            FV_ERROR(TRACE_MOD, "%s:%llu: no column header line in the first %u MiB", r->name,
                     (unsigned long long)r->lines.line_no, TRACE_MAX_SKIP >> 20);
            return FV_ERR_PARSE;
        }
        if (n == 0 || too_long) continue;
        if (l[0] == '#') {
            double v;
            if (strncmp(l, "# rate_hz:", 10) == 0 && trace_parse_f64(l + 10, &v) && isfinite(v) && v > 0 && v < 1e6)
                r->meta_rate_hz = v;
            continue;
        }
        int nf = trace_csv_split(l, ',', r->fields, TRACE_MAX_FIELDS);
        if (nf < 0) nf = 0;
        FV_TRY(trace_require_col(r, r->fields, nf, F_T, trace_fovea_cols[F_T]));
        for (int i = 1; i < TRACE_FOVEA_NCOLS; i++) trace_optional_col(r, r->fields, nf, i, trace_fovea_cols[i]);
        return FV_OK;
    }
}

/* Optional float column: empty/absent → NaN; junk → false. */
static bool opt_f(fv_trace_reader *r, int n, int slot, float *out)
{
    const char *f = trace_col(r, n, slot);
    double v;
    if (trace_field_empty(f)) {
        *out = NAN;
        return true;
    }
    if (!trace_parse_f64(f, &v)) {
        trace_why(r, "column '%s' is not a number", trace_fovea_cols[slot]);
        return false;
    }
    *out = trace_f32(v);
    return true;
}

static bool opt_u32(fv_trace_reader *r, int n, int slot, uint32_t *out)
{
    const char *f = trace_col(r, n, slot);
    int64_t v;
    if (trace_field_empty(f)) {
        *out = 0;
        return true;
    }
    if (!trace_parse_i64(f, &v) || v < 0 || v > (int64_t)UINT32_MAX) {
        trace_why(r, "column '%s' is not a flag set (0..4294967295)", trace_fovea_cols[slot]);
        return false;
    }
    *out = (uint32_t)v;
    return true;
}

static bool opt_v3(fv_trace_reader *r, int n, int slot, fv_vec3 *out)
{
    return opt_f(r, n, slot, &out->x) && opt_f(r, n, slot + 1, &out->y) && opt_f(r, n, slot + 2, &out->z);
}

static void check_eye(fv_eye_sample *e)
{
    e->flags &= FV_EYE_ORIGIN_VALID | FV_EYE_DIRECTION_VALID | FV_EYE_PUPIL_VALID | FV_EYE_OPENNESS_VALID |
                FV_EYE_BLINK;
    if ((e->flags & FV_EYE_ORIGIN_VALID) && !fv_v3_isfinite(e->origin_mm))
        trace_eye_set_origin(e, NAN, NAN, NAN);
    if (e->flags & FV_EYE_DIRECTION_VALID) {
        float len = fv_v3_isfinite(e->direction) ? fv_v3_len(e->direction) : NAN;
        if (!(fabsf(len - 1.0f) <= 1e-3f)) /* keep exact unit vectors bit for bit; renormalise the rest */
            trace_eye_set_direction(e, e->direction.x, e->direction.y, e->direction.z);
    }
    if ((e->flags & FV_EYE_PUPIL_VALID) && !(e->pupil_mm > 0.0f && e->pupil_mm <= 20.0f))
        trace_eye_set_pupil(e, NAN);
    if ((e->flags & FV_EYE_OPENNESS_VALID) && !(e->openness >= 0.0f && e->openness <= 1.0f))
        trace_eye_set_openness(e, NAN);
}

static fv_result row(fv_trace_reader *r, char *line, size_t len, fv_gaze_sample *s)
{
    (void)len;
    int n;
    FV_TRY(trace_split_row(r, line, ',', &n));
    if (!trace_parse_i64(trace_col(r, n, F_T), &s->t_device_ns)) {
        trace_why(r, "column 't_device_ns' is not an integer");
        return FV_ERR_PARSE;
    }
    const char *fh = trace_col(r, n, F_HOST);
    if (!trace_field_empty(fh)) {
        if (!trace_parse_i64(fh, &s->t_host_ns)) {
            trace_why(r, "column 't_host_ns' is not an integer");
            return FV_ERR_PARSE;
        }
    }
    const char *fs = trace_col(r, n, F_SEQ);
    int64_t seq = (int64_t)r->lines.line_no;
    if (!trace_field_empty(fs) && (!trace_parse_i64(fs, &seq) || seq < 0)) {
        trace_why(r, "column 'seq' is not a non-negative integer");
        return FV_ERR_PARSE;
    }
    s->seq = (uint64_t)seq;
    if (!opt_u32(r, n, F_FLAGS, &s->flags) || !opt_f(r, n, F_CONF, &s->confidence)) return FV_ERR_PARSE;
    fv_eye_sample *eyes[3] = {&s->eye[FV_EYE_LEFT], &s->eye[FV_EYE_RIGHT], &s->combined};
    for (int k = 0; k < 3; k++) {
        int b = F_EYE0 + 9 * k;
        fv_eye_sample *e = eyes[k];
        if (!opt_u32(r, n, b, &e->flags) || !opt_v3(r, n, b + 1, &e->origin_mm) ||
            !opt_v3(r, n, b + 4, &e->direction) || !opt_f(r, n, b + 7, &e->pupil_mm) ||
            !opt_f(r, n, b + 8, &e->openness))
            return FV_ERR_PARSE;
        check_eye(e);
    }
    if (!opt_f(r, n, F_SCREEN_X, &s->screen_point_mm.x) || !opt_f(r, n, F_SCREEN_X + 1, &s->screen_point_mm.y) ||
        !opt_v3(r, n, F_HEAD_X, &s->head_pos_mm) || !opt_v3(r, n, F_HEAD_X + 3, &s->head_dir))
        return FV_ERR_PARSE;
    s->flags &= FV_GAZE_HOST_TIME_VALID | FV_GAZE_HEAD_VALID | FV_GAZE_SCREEN_POINT_VALID;
    if (trace_field_empty(fh)) s->flags &= ~(uint32_t)FV_GAZE_HOST_TIME_VALID;
    if (!(isfinite(s->screen_point_mm.x) && isfinite(s->screen_point_mm.y)))
        s->flags &= ~(uint32_t)FV_GAZE_SCREEN_POINT_VALID;
    if (!fv_v3_isfinite(s->head_pos_mm) || !fv_v3_isfinite(s->head_dir)) s->flags &= ~(uint32_t)FV_GAZE_HEAD_VALID;
    if ((s->flags & FV_GAZE_HEAD_VALID) && !(fabsf(fv_v3_len(s->head_dir) - 1.0f) <= 1e-3f)) {
        /* as for eye directions: exact unit vectors stay bit for bit, others are renormalised or invalid */
        fv_eye_sample tmp = {.flags = 0};
        trace_eye_set_direction(&tmp, s->head_dir.x, s->head_dir.y, s->head_dir.z);
        if (tmp.flags & FV_EYE_DIRECTION_VALID) s->head_dir = tmp.direction;
        else s->flags &= ~(uint32_t)FV_GAZE_HEAD_VALID;
    }
    if (!(s->confidence >= 0.0f && s->confidence <= 1.0f)) s->confidence = NAN;
    return FV_OK;
}

const trace_format_ops trace_fmt_fovea = {FV_TRACE_FORMAT_FOVEA, false, begin, row};
