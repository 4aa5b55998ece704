/* @brief Pico Neo 3 Pro Eye Unity log: tab-separated, `Timeline` in s. One combined gaze vector,
 * `Combine Eye Gaze Vector.*`, in Unity's left-handed head frame (+x right, +y up, +z forward): fovea's head frame is
 * (x, y, -z). Per eye only openness (0 or 1), a blink flag and a pose status (0 = invalid) are given. A row whose
 * eyes both blink or both have an invalid pose, or whose vector is (0,0,0), has an invalid combined ray.
 * Optional `Head Position.*` (m) and `Head Rotation.*` (Unity Euler angles, deg) are the head pose in Unity's
 * left-handed world; they map through trace_set_head_unity. A bad value there leaves only the head invalid. */
#include <strings.h>

#include "trace_internal.h"

enum {
    Q_T, Q_VX, Q_VY, Q_VZ, Q_STAT_L, Q_STAT_R, Q_BLINK_L, Q_BLINK_R,
    Q_OPEN_L, Q_OPEN_R, Q_HP_X, Q_HP_Y, Q_HP_Z, Q_HR_X, Q_HR_Y, Q_HR_Z, /* optional */
    Q_COUNT_
};

static const char *const g_cols[Q_COUNT_] = {
    "Timeline",
    "Combine Eye Gaze Vector. x", "Combine Eye Gaze Vector. y", "Combine Eye Gaze Vector. z",
    "Left Eye Pose Status", "Right Eye Pose Status",
    "Eye Left Blinking", "Eye Right Blinking",
    "Left Eye Gaze Openness", "Right Eye Gaze Openness",
    "Head Position. x", "Head Position. y", "Head Position. z",
    "Head Rotation. x", "Head Rotation. y", "Head Rotation. z",
};

static fv_result begin(fv_trace_reader *r, char *line, size_t len)
{
    (void)len;
    int n = trace_csv_split(line, '\t', r->fields, TRACE_MAX_FIELDS);
    if (n < 0) n = 0;
    for (int i = Q_T; i <= Q_BLINK_R; i++) FV_TRY(trace_require_col(r, r->fields, n, i, g_cols[i]));
    for (int i = Q_OPEN_L; i < Q_COUNT_; i++) trace_optional_col(r, r->fields, n, i, g_cols[i]);
    return FV_OK;
}

static bool parse_bool(const char *s, bool *out)
{
    if (!s) return false;
    while (*s == ' ') s++;
    if (strncasecmp(s, "true", 4) == 0 && trace_field_empty(s + 4)) *out = true;
    else if (strncasecmp(s, "false", 5) == 0 && trace_field_empty(s + 5)) *out = false;
    else if ((s[0] == '0' || s[0] == '1') && trace_field_empty(s + 1)) *out = s[0] == '1';
    else return false;
    return true;
}

static fv_result row(fv_trace_reader *r, char *line, size_t len, fv_gaze_sample *s)
{
    (void)len;
    int n;
    FV_TRY(trace_split_row(r, line, '\t', &n));
    double t, v[3];
    if (!trace_parse_f64(trace_col(r, n, Q_T), &t) || !trace_seconds_to_ns(t, &s->t_device_ns)) {
        trace_why(r, "column 'Timeline' is not a time in seconds");
        return FV_ERR_PARSE;
    }
    for (int k = 0; k < 3; k++)
        if (!trace_parse_f64(trace_col(r, n, Q_VX + k), &v[k])) {
            trace_why(r, "column '%s' is not a number", g_cols[Q_VX + k]);
            return FV_ERR_PARSE;
        }
    bool blink[2], pose_ok[2];
    for (int e = 0; e < 2; e++) {
        int64_t st;
        if (!trace_parse_i64(trace_col(r, n, Q_STAT_L + e), &st)) {
            trace_why(r, "column '%s' is not an integer", g_cols[Q_STAT_L + e]);
            return FV_ERR_PARSE;
        }
        pose_ok[e] = st != 0;
        if (!parse_bool(trace_col(r, n, Q_BLINK_L + e), &blink[e])) {
            trace_why(r, "column '%s' is not True or False", g_cols[Q_BLINK_L + e]);
            return FV_ERR_PARSE;
        }
        fv_eye_sample *es = &s->eye[e == 0 ? FV_EYE_LEFT : FV_EYE_RIGHT];
        if (blink[e]) {
            es->flags |= FV_EYE_BLINK;
            continue;
        }
        const char *fo = trace_col(r, n, Q_OPEN_L + e);
        double o;
        if (!trace_field_empty(fo)) {
            if (!trace_parse_f64(fo, &o)) {
                trace_why(r, "column '%s' is not a number", g_cols[Q_OPEN_L + e]);
                return FV_ERR_PARSE;
            }
            trace_eye_set_openness(es, o);
        }
    }
    if ((pose_ok[0] || pose_ok[1]) && !(blink[0] && blink[1]))
        trace_eye_set_direction(&s->combined, v[0], v[1], -v[2]); /* (0,0,0) stays invalid */
    if (blink[0] && blink[1]) s->combined.flags |= FV_EYE_BLINK;
    const char *pos[3], *rot[3];
    for (int k = 0; k < 3; k++) {
        pos[k] = trace_col(r, n, Q_HP_X + k);
        rot[k] = trace_col(r, n, Q_HR_X + k);
    }
    trace_set_head_unity(s, pos, rot);
    return FV_OK;
}

const trace_format_ops trace_fmt_pico = {FV_TRACE_FORMAT_PICO, false, begin, row};
