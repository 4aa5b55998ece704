/* @brief Pupil Labs exports. Pupil Core (Pupil Player "Raw Data Exporter" gaze_positions.csv) and Pupil Invisible /
 * Pupil Cloud (gaze.csv), each with an optional blinks.csv beside it whose intervals mark samples as blinks.
 *
 * Pupil Core: gaze_timestamp in s (Pupil time). 3D values are in the scene camera's frame (x right, y down,
 * z forward, mm); fovea's head frame (x right, y up, -z forward) is (x, -y, -z), a 180 degree turn about x. eye0 is
 * the right eye, eye1 the left. The combined ray points from the eyes' midpoint to gaze_point_3d; without 3D data
 * it comes from norm_pos (origin bottom-left) through the default camera model below. Samples below the minimum
 * confidence (0.6, Pupil Labs' recommendation) are kept as invalid samples. A confident row whose gaze_point_3d lies
 * behind the head (z < 0: the two lines of sight meet behind the eyes, a quirk of the binocular intersection that
 * Pupil Labs documents) is repaired as their tutorial does: the combined ray is the mean of the eyes' own gaze
 * normals (gaze_normal0/1) when they point forward, else the point flipped through the camera (-p); counted as
 * repaired (fv_gaze_validity.h). Nothing pointing backwards is passed on.
 *
 * Pupil Cloud: timestamp [ns] (Unix epoch). One combined gaze point: the direction comes from azimuth/elevation
 * (positive right and up) when present, else from the pixel position through the default camera model. Rows with a
 * `blink id` or inside a blinks.csv interval, and rows with worn = 0, are invalid. */
#include <math.h>
#include <stdio.h>

#include "trace_internal.h"

/* Default camera models (documented in docs/trace-format.md): pinhole, principal point at the image centre, no
 * distortion. Pupil Core world camera at 1280x720 with an 800 px focal length (about 77 x 48 degrees); Pupil
 * Invisible scene camera 1088x1080 with an 82 degree horizontal field of view (626 px). */
#define CORE_W_PX 1280.0
#define CORE_H_PX 720.0
#define CORE_F_PX 800.0
#define CLOUD_W_PX 1088.0
#define CLOUD_H_PX 1080.0
#define CLOUD_F_PX 626.0

/* ---------------- Pupil Core ---------------- */

enum {
    K_TS, K_CONF, K_NX, K_NY,
    K_P3_X, K_P3_Y, K_P3_Z,
    K_E0_X, K_E0_Y, K_E0_Z, K_N0_X, K_N0_Y, K_N0_Z,
    K_E1_X, K_E1_Y, K_E1_Z, K_N1_X, K_N1_Y, K_N1_Z,
    K_COUNT_
};

static const char *const g_core_cols[K_COUNT_] = {
    "gaze_timestamp", "confidence", "norm_pos_x", "norm_pos_y",
    "gaze_point_3d_x", "gaze_point_3d_y", "gaze_point_3d_z",
    "eye_center0_3d_x", "eye_center0_3d_y", "eye_center0_3d_z", "gaze_normal0_x", "gaze_normal0_y", "gaze_normal0_z",
    "eye_center1_3d_x", "eye_center1_3d_y", "eye_center1_3d_z", "gaze_normal1_x", "gaze_normal1_y", "gaze_normal1_z",
};

static fv_result core_begin(fv_trace_reader *r, char *line, size_t len)
{
    (void)len;
    int n = trace_csv_split(line, ',', r->fields, TRACE_MAX_FIELDS);
    if (n < 0) n = 0;
    for (int i = K_TS; i <= K_NY; i++) FV_TRY(trace_require_col(r, r->fields, n, i, g_core_cols[i]));
    for (int i = K_P3_X; i < K_COUNT_; i++) trace_optional_col(r, r->fields, n, i, g_core_cols[i]);
    return trace_blinks_open(r, "start_timestamp", "end_timestamp", 1e9);
}

/* Optional 3-vector: 1 = parsed, 0 = absent or empty (invalid value, not an error), -1 = junk (why set). */
static int opt_vec3(fv_trace_reader *r, int n, int slot, const char *const *names, double v[3])
{
    int empty = 0;
    for (int k = 0; k < 3; k++) {
        const char *f = trace_col(r, n, slot + k);
        if (trace_field_empty(f)) {
            empty++;
            continue;
        }
        if (!trace_parse_f64(f, &v[k])) {
            trace_why(r, "column '%s' is not a number", names[slot + k]);
            return -1;
        }
    }
    if (empty) return 0;
    return 1;
}

/* gaze_point_3d (camera frame) behind the head: the lines of sight met behind the eyes. The repair Pupil Labs'
 * tutorial gives: the eyes' gaze normals (already in the head frame here), averaged over those that point forward;
 * without one, the point flipped through the camera. The reader's validity rules then check the result like any. */
static void core_point_behind(fv_gaze_sample *s, const double p[3])
{
    fv_eye_sample *cb = &s->combined;
    trace_combined_origin(s, true); /* the eyes' midpoint, one eye's centre, or none (the scene camera) */
    double sum[3] = {0, 0, 0};
    int used = 0;
    for (int e = 0; e < 2; e++) {
        const fv_eye_sample *es = &s->eye[e];
        if (!(es->flags & FV_EYE_DIRECTION_VALID) || !fv_gaze_direction_possible(es->direction)) continue;
        sum[0] += es->direction.x, sum[1] += es->direction.y, sum[2] += es->direction.z;
        used++;
    }
    if (used) trace_eye_set_direction(cb, sum[0], sum[1], sum[2]);
    else trace_eye_set_direction(cb, -p[0], p[1], p[2]); /* -p in the camera frame is (-x, y, z) in the head frame */
}

static fv_result core_row(fv_trace_reader *r, char *line, size_t len, fv_gaze_sample *s)
{
    (void)len;
    int n;
    FV_TRY(trace_split_row(r, line, ',', &n));
    double ts, conf, nx, ny;
    if (!trace_parse_f64(trace_col(r, n, K_TS), &ts) || !trace_seconds_to_ns(ts, &s->t_device_ns)) {
        trace_why(r, "column 'gaze_timestamp' is not a time in seconds");
        return FV_ERR_PARSE;
    }
    if (!trace_parse_f64(trace_col(r, n, K_CONF), &conf)) {
        trace_why(r, "column 'confidence' is not a number");
        return FV_ERR_PARSE;
    }
    s->confidence = (conf >= 0.0 && conf <= 1.0) ? (float)conf : NAN;

    /* eye0 = right, eye1 = left; camera (x right, y down, z forward) -> head (x, -y, -z) */
    for (int k = 0; k < 2; k++) {
        fv_eye_sample *e = &s->eye[k == 0 ? FV_EYE_RIGHT : FV_EYE_LEFT];
        double c[3], d[3];
        int rc = opt_vec3(r, n, k == 0 ? K_E0_X : K_E1_X, g_core_cols, c);
        if (rc < 0) return FV_ERR_PARSE;
        if (rc > 0) trace_eye_set_origin(e, c[0], -c[1], -c[2]);
        rc = opt_vec3(r, n, k == 0 ? K_N0_X : K_N1_X, g_core_cols, d);
        if (rc < 0) return FV_ERR_PARSE;
        if (rc > 0) trace_eye_set_direction(e, d[0], -d[1], -d[2]);
    }

    fv_eye_sample *cb = &s->combined;
    double p[3];
    int rc = opt_vec3(r, n, K_P3_X, g_core_cols, p);
    if (rc < 0) return FV_ERR_PARSE;
    const bool confident = r->min_confidence < 0.0f || conf >= (double)r->min_confidence;
    if (rc > 0 && p[2] < 0.0 && isfinite(p[0]) && isfinite(p[1]) && confident) {
        core_point_behind(s, p);
        r->row_repaired |= 1u << FV_GAZE_FAULT_POINT_BEHIND;
    } else if (rc > 0 && isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2])) {
        fv_vec3 ph = fv_v3(trace_f32(p[0]), trace_f32(-p[1]), trace_f32(-p[2]));
        trace_combined_origin(s, true);
        /* from the eye(s), or from the scene camera when no eye centre is known */
        fv_vec3 o = (cb->flags & FV_EYE_ORIGIN_VALID) ? cb->origin_mm : fv_v3(0, 0, 0);
        trace_eye_set_direction(cb, (double)ph.x - o.x, (double)ph.y - o.y, (double)ph.z - o.z);
    }
    if (!(cb->flags & FV_EYE_DIRECTION_VALID)) {
        const char *fx = trace_col(r, n, K_NX), *fy = trace_col(r, n, K_NY);
        if (!trace_field_empty(fx) || !trace_field_empty(fy)) {
            if (!trace_parse_f64(fx, &nx) || !trace_parse_f64(fy, &ny)) {
                trace_why(r, "column 'norm_pos_x' or 'norm_pos_y' is not a number");
                return FV_ERR_PARSE;
            }
            /* norm_pos: (0,0) bottom-left, (1,1) top-right of the scene image */
            trace_eye_set_direction(cb, (nx - 0.5) * CORE_W_PX / CORE_F_PX, (ny - 0.5) * CORE_H_PX / CORE_F_PX,
                                    -1.0);
        }
    }

    /* blinks.csv is applied by the reader once the row passes the time checks */
    if (r->min_confidence >= 0.0f && !(conf >= (double)r->min_confidence)) trace_sample_invalidate(s, false);
    return FV_OK;
}

const trace_format_ops trace_fmt_pupil_core = {FV_TRACE_FORMAT_PUPIL_CORE, false, core_begin, core_row};

/* ---------------- Pupil Cloud (Invisible) ---------------- */

enum { P_TS, P_GX, P_GY, P_AZ, P_EL, P_BLINK, P_WORN, P_COUNT_ };

static const char *const g_cloud_cols[P_COUNT_] = {
    "timestamp [ns]", "gaze x [px]", "gaze y [px]", "azimuth [deg]", "elevation [deg]", "blink id", "worn",
};

static fv_result cloud_begin(fv_trace_reader *r, char *line, size_t len)
{
    (void)len;
    int n = trace_csv_split(line, ',', r->fields, TRACE_MAX_FIELDS);
    if (n < 0) n = 0;
    for (int i = P_TS; i <= P_GY; i++) FV_TRY(trace_require_col(r, r->fields, n, i, g_cloud_cols[i]));
    for (int i = P_AZ; i < P_COUNT_; i++) trace_optional_col(r, r->fields, n, i, g_cloud_cols[i]);
    return trace_blinks_open(r, "start timestamp [ns]", "end timestamp [ns]", 1.0);
}

static fv_result cloud_row(fv_trace_reader *r, char *line, size_t len, fv_gaze_sample *s)
{
    (void)len;
    int n;
    FV_TRY(trace_split_row(r, line, ',', &n));
    if (!trace_parse_i64(trace_col(r, n, P_TS), &s->t_device_ns)) {
        trace_why(r, "column 'timestamp [ns]' is not an integer");
        return FV_ERR_PARSE;
    }
    fv_eye_sample *cb = &s->combined;
    const char *faz = trace_col(r, n, P_AZ), *fel = trace_col(r, n, P_EL);
    double az, el, gx, gy;
    if (!trace_field_empty(faz) && !trace_field_empty(fel)) {
        if (!trace_parse_f64(faz, &az) || !trace_parse_f64(fel, &el)) {
            trace_why(r, "column 'azimuth [deg]' or 'elevation [deg]' is not a number");
            return FV_ERR_PARSE;
        }
        if (isfinite(az) && isfinite(el) && fabs(az) <= 360.0 && fabs(el) <= 90.0) {
            double a = az * (3.14159265358979323846 / 180.0), b = el * (3.14159265358979323846 / 180.0);
            trace_eye_set_direction(cb, cos(b) * sin(a), sin(b), -cos(b) * cos(a));
        }
    } else {
        const char *fx = trace_col(r, n, P_GX), *fy = trace_col(r, n, P_GY);
        if (!trace_field_empty(fx) || !trace_field_empty(fy)) {
            if (!trace_parse_f64(fx, &gx) || !trace_parse_f64(fy, &gy)) {
                trace_why(r, "column 'gaze x [px]' or 'gaze y [px]' is not a number");
                return FV_ERR_PARSE;
            }
            /* pixels, origin top-left, y down */
            trace_eye_set_direction(cb, (gx - 0.5 * CLOUD_W_PX) / CLOUD_F_PX, (0.5 * CLOUD_H_PX - gy) / CLOUD_F_PX,
                                    -1.0);
        }
    }
    const char *fw = trace_col(r, n, P_WORN);
    int64_t worn = 1;
    if (!trace_field_empty(fw) && !trace_parse_i64(fw, &worn)) {
        trace_why(r, "column 'worn' is not 0 or 1");
        return FV_ERR_PARSE;
    }
    const char *fb = trace_col(r, n, P_BLINK);
    uint64_t blink = 0;
    if (!trace_field_empty(fb)) {
        int64_t id;
        if (!trace_parse_i64(fb, &id) || id < 1 || id > INT64_C(1) << 40) {
            trace_why(r, "column 'blink id' is not a positive integer");
            return FV_ERR_PARSE;
        }
        blink = (uint64_t)id;
    }
    /* Events are counted by blinks.csv interval when that file is there (it covers every blink id and a few edge
     * samples more; the reader applies it once the row passes the time checks), else by the blink id column. */
    if (blink) {
        trace_sample_invalidate(s, true);
        if (!r->blinks.active) trace_count_blink_event(r, blink);
    } else if (worn == 0) {
        trace_sample_invalidate(s, false);
    }
    return FV_OK;
}

const trace_format_ops trace_fmt_pupil_cloud = {FV_TRACE_FORMAT_PUPIL_CLOUD, false, cloud_begin, cloud_row};
