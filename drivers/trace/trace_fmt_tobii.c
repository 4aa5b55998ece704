/* @brief Tobii Pro Glasses 3 gazedata(.gz): JSON Lines, one object per line,
 * {"type":"gaze","timestamp":<s since recording start>,"data":{gaze2d, gaze3d, eyeleft, eyeright}}. The file is
 * streamed through zlib and each line is parsed on its own with cJSON. Tobii's head-unit frame is +x to the
 * wearer's left, +y up, +z forward (mm); fovea's head frame is (x, y, z) -> (-x, y, -z). `data: {}` (tracking
 * lost, blink) and an empty eye object are kept as invalid samples / eyes. Lines of another type are skipped. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "trace_internal.h"

/* Default scene camera model for gaze2d when gaze3d is missing: pinhole, 95 x 63 degrees (Glasses 3 scene camera). */
#define TOBII_HFOV_DEG 95.0
#define TOBII_VFOV_DEG 63.0

static fv_result begin(fv_trace_reader *r, char *line, size_t len)
{
    (void)r;
    (void)line;
    (void)len;
    return FV_OK; /* no header: the first line is data */
}

/* A JSON array of exactly three finite numbers. */
static bool arr3(const cJSON *a, double v[3])
{
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != 3) return false;
    for (int i = 0; i < 3; i++) {
        const cJSON *x = cJSON_GetArrayItem(a, i);
        if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble)) return false;
        v[i] = x->valuedouble;
    }
    return true;
}

static void eye_from_json(fv_eye_sample *e, const cJSON *o)
{
    double v[3];
    if (!cJSON_IsObject(o)) return;
    if (arr3(cJSON_GetObjectItemCaseSensitive(o, "gazeorigin"), v)) trace_eye_set_origin(e, -v[0], v[1], -v[2]);
    if (arr3(cJSON_GetObjectItemCaseSensitive(o, "gazedirection"), v))
        trace_eye_set_direction(e, -v[0], v[1], -v[2]);
    const cJSON *p = cJSON_GetObjectItemCaseSensitive(o, "pupildiameter");
    if (cJSON_IsNumber(p)) trace_eye_set_pupil(e, p->valuedouble);
}

static fv_result row(fv_trace_reader *r, char *line, size_t len, fv_gaze_sample *s)
{
    cJSON *j = cJSON_ParseWithLength(line, len);
    fv_result res = FV_OK;
    if (!j || !cJSON_IsObject(j)) {
        trace_why(r, "not a JSON object");
        res = FV_ERR_PARSE;
        goto done;
    }
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(j, "type");
    if (type && (!cJSON_IsString(type) || strcmp(type->valuestring, "gaze") != 0)) {
        res = FV_NO_NEW_DATA; /* syncport, event, imu, ... */
        if (!r->other_kind[0])
            snprintf(r->other_kind, sizeof r->other_kind, "%s", cJSON_IsString(type) ? type->valuestring : "?");
        goto done;
    }
    const cJSON *ts = cJSON_GetObjectItemCaseSensitive(j, "timestamp");
    if (!cJSON_IsNumber(ts) || !trace_seconds_to_ns(ts->valuedouble, &s->t_device_ns)) {
        trace_why(r, "field 'timestamp' is missing or not a time in seconds");
        res = FV_ERR_PARSE;
        goto done;
    }
    const cJSON *data = cJSON_GetObjectItemCaseSensitive(j, "data");
    if (!cJSON_IsObject(data)) {
        trace_why(r, "field 'data' is missing or not an object");
        res = FV_ERR_PARSE;
        goto done;
    }
    eye_from_json(&s->eye[FV_EYE_LEFT], cJSON_GetObjectItemCaseSensitive(data, "eyeleft"));
    eye_from_json(&s->eye[FV_EYE_RIGHT], cJSON_GetObjectItemCaseSensitive(data, "eyeright"));

    fv_eye_sample *cb = &s->combined;
    trace_combined_origin(s, false);
    double g[3];
    if (arr3(cJSON_GetObjectItemCaseSensitive(data, "gaze3d"), g)) {
        fv_vec3 o = (cb->flags & FV_EYE_ORIGIN_VALID) ? cb->origin_mm : fv_v3(0, 0, 0); /* else: scene camera */
        trace_eye_set_direction(cb, -g[0] - o.x, g[1] - o.y, -g[2] - o.z);
    } else {
        const cJSON *g2 = cJSON_GetObjectItemCaseSensitive(data, "gaze2d");
        if (cJSON_IsArray(g2) && cJSON_GetArraySize(g2) == 2) {
            const cJSON *x = cJSON_GetArrayItem(g2, 0), *y = cJSON_GetArrayItem(g2, 1);
            if (cJSON_IsNumber(x) && cJSON_IsNumber(y)) {
                /* normalised image coordinates, origin top-left; the image's right is the wearer's right */
                double tx = tan(TOBII_HFOV_DEG * 0.5 * 3.14159265358979323846 / 180.0);
                double ty = tan(TOBII_VFOV_DEG * 0.5 * 3.14159265358979323846 / 180.0);
                trace_eye_set_direction(cb, (x->valuedouble - 0.5) * 2.0 * tx, (0.5 - y->valuedouble) * 2.0 * ty,
                                        -1.0);
            }
        }
    }
done:
    cJSON_Delete(j);
    return res;
}

const trace_format_ops trace_fmt_tobii_g3 = {FV_TRACE_FORMAT_TOBII_G3, true, begin, row};
