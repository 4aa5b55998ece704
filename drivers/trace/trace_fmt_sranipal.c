/* @brief HTC Vive Pro Eye SRanipal logs: ';'-separated, one row per SRanipal eye frame. Clock: `time(100ns)`, .NET
 * DateTime ticks (100 ns since 0001-01-01), converted to Unix-epoch ns. Per-eye validity bitmask `eye_valid_L/R`
 * (bit0 origin, bit1 direction, bit2 pupil, bit3 openness). SRanipal axes are +x to the wearer's left, +y up,
 * +z forward; fovea's head frame is +x right, +y up, -z forward, so (x, y, z) -> (-x, y, -z), a 180 degree turn
 * about y (a proper rotation: handedness is kept). No combined ray in the log: it is built from the eyes.
 * Optional `helmet_pos_{x,y,z}` (m) and `helmet_rot_{x,y,z}` (Unity Euler angles, deg) are the head pose in Unity's
 * left-handed world; they map through trace_set_head_unity. A bad value there leaves only the head invalid. */
#include <stdio.h>

#include "trace_internal.h"

enum {
    C_TICKS,
    C_VALID_L, C_VALID_R,
    C_OPEN_L, C_OPEN_R,
    C_PUPIL_L, C_PUPIL_R,
    C_OL_X, C_OL_Y, C_OL_Z,
    C_OR_X, C_OR_Y, C_OR_Z,
    C_DL_X, C_DL_Y, C_DL_Z,
    C_DR_X, C_DR_Y, C_DR_Z,
    C_REQUIRED_,
    C_HP_X = C_REQUIRED_, C_HP_Y, C_HP_Z, /* optional head pose */
    C_HR_X, C_HR_Y, C_HR_Z,
    C_COUNT_,
};

static const char *const g_cols[] = {
    "time(100ns)",
    "eye_valid_L", "eye_valid_R",
    "openness_L", "openness_R",
    "pupil_diameter_L(mm)", "pupil_diameter_R(mm)",
    "gaze_origin_L.x(mm)", "gaze_origin_L.y(mm)", "gaze_origin_L.z(mm)",
    "gaze_origin_R.x(mm)", "gaze_origin_R.y(mm)", "gaze_origin_R.z(mm)",
    "gaze_direct_L.x", "gaze_direct_L.y", "gaze_direct_L.z",
    "gaze_direct_R.x", "gaze_direct_R.y", "gaze_direct_R.z",
    "helmet_pos_x", "helmet_pos_y", "helmet_pos_z",
    "helmet_rot_x", "helmet_rot_y", "helmet_rot_z",
};
_Static_assert(sizeof g_cols / sizeof g_cols[0] == C_COUNT_, "one name per column slot");

#define NET_TICKS_AT_UNIX_EPOCH INT64_C(621355968000000000) /* 1970-01-01T00:00:00Z in .NET ticks */

static fv_result begin(fv_trace_reader *r, char *line, size_t len)
{
    (void)len;
    int n = trace_csv_split(line, ';', r->fields, TRACE_MAX_FIELDS);
    for (int i = 0; i < C_REQUIRED_; i++) FV_TRY(trace_require_col(r, r->fields, n < 0 ? 0 : n, i, g_cols[i]));
    for (int i = C_REQUIRED_; i < C_COUNT_; i++) trace_optional_col(r, r->fields, n < 0 ? 0 : n, i, g_cols[i]);
    return FV_OK;
}

/* Parse three columns; false (with r->why naming the column) on junk. */
static bool vec3(fv_trace_reader *r, int n, int slot, double v[3])
{
    for (int k = 0; k < 3; k++) {
        if (!trace_parse_f64(trace_col(r, n, slot + k), &v[k])) {
            trace_why(r, "column '%s' is not a number", g_cols[slot + k]);
            return false;
        }
    }
    return true;
}

static fv_result row(fv_trace_reader *r, char *line, size_t len, fv_gaze_sample *s)
{
    (void)len;
    int n = trace_csv_split(line, ';', r->fields, TRACE_MAX_FIELDS);
    if (n < r->ncols_needed) {
        trace_why(r, "%d fields, the header needs at least %d", n < 0 ? 0 : n, r->ncols_needed);
        return FV_ERR_PARSE;
    }
    int64_t ticks;
    if (!trace_parse_i64(trace_col(r, n, C_TICKS), &ticks)) {
        trace_why(r, "column 'time(100ns)' is not an integer tick count");
        return FV_ERR_PARSE;
    }
    /* ns since the Unix epoch; reject tick counts whose ns value would not fit in int64 */
    if (ticks < NET_TICKS_AT_UNIX_EPOCH - INT64_MAX / 100 || ticks > NET_TICKS_AT_UNIX_EPOCH + INT64_MAX / 100) {
        trace_why(r, "column 'time(100ns)' = %lld is outside the representable time range", (long long)ticks);
        return FV_ERR_PARSE;
    }
    s->t_device_ns = (ticks - NET_TICKS_AT_UNIX_EPOCH) * 100;

    for (int e = 0; e < 2; e++) {
        int eye = e == 0 ? FV_EYE_LEFT : FV_EYE_RIGHT;
        int64_t mask;
        if (!trace_parse_i64(trace_col(r, n, C_VALID_L + e), &mask) || mask < 0 || mask > 255) {
            trace_why(r, "column '%s' is not a validity bitmask (0..255)", g_cols[C_VALID_L + e]);
            return FV_ERR_PARSE;
        }
        fv_eye_sample *es = &s->eye[eye];
        double v[3];
        if (mask & 1) {
            if (!vec3(r, n, e == 0 ? C_OL_X : C_OR_X, v)) return FV_ERR_PARSE;
            trace_eye_set_origin(es, -v[0], v[1], -v[2]);
        }
        if (mask & 2) {
            if (!vec3(r, n, e == 0 ? C_DL_X : C_DR_X, v)) return FV_ERR_PARSE;
            trace_eye_set_direction(es, -v[0], v[1], -v[2]); /* (0,0,0) stays invalid */
        }
        if (mask & 4) {
            if (!trace_parse_f64(trace_col(r, n, C_PUPIL_L + e), &v[0])) {
                trace_why(r, "column '%s' is not a number", g_cols[C_PUPIL_L + e]);
                return FV_ERR_PARSE;
            }
            trace_eye_set_pupil(es, v[0]); /* -1 stays invalid */
        }
        if (mask & 8) {
            if (!trace_parse_f64(trace_col(r, n, C_OPEN_L + e), &v[0])) {
                trace_why(r, "column '%s' is not a number", g_cols[C_OPEN_L + e]);
                return FV_ERR_PARSE;
            }
            trace_eye_set_openness(es, v[0]);
        }
    }
    trace_combine_eyes(s);
    const char *pos[3], *rot[3];
    for (int k = 0; k < 3; k++) {
        pos[k] = trace_col(r, n, C_HP_X + k);
        rot[k] = trace_col(r, n, C_HR_X + k);
    }
    trace_set_head_unity(s, pos, rot);
    return FV_OK;
}

const trace_format_ops trace_fmt_sranipal = {FV_TRACE_FORMAT_SRANIPAL, false, begin, row};
