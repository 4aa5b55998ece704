/* @brief The renderer's frame input for a scene head: near/far from the scene bounds, the eye views from the one
 * builder (fv_eye_views_build), gaze straight ahead, default quality. */
#include <math.h>
#include <string.h>

#include "fv_renderer.h"

void fv_frame_near_far_from_bounds(const fv_head *head, fv_vec3 bounds_min, fv_vec3 bounds_max, float *out_near_m,
                                   float *out_far_m)
{
    float n = 0.0f, f = 0.0f;
    if (head && fv_v3_isfinite(bounds_min) && fv_v3_isfinite(bounds_max) && fv_v3_isfinite(head->position_m)) {
        fv_vec3 c = fv_v3_scale(fv_v3_add(bounds_min, bounds_max), 0.5f);
        double r = 0.5 * fv_v3_len(fv_v3_sub(bounds_max, bounds_min));
        double d = fv_v3_len(fv_v3_sub(c, head->position_m));
        if (isfinite(r) && isfinite(d)) {
            double ipd_m = isfinite(head->ipd_mm) ? fabs((double)head->ipd_mm) * 1e-3 : 0.0;
            double fd = (d + r + ipd_m) * 1.05 + 1e-3;
            /* Outside the bounding sphere: near just in front of it; inside: a small fraction of its size. */
            double nd = d - r - ipd_m > 0.0 ? 0.9 * (d - r - ipd_m) : 0.005 * (r > 0 ? r : 1.0);
            if (nd > fd * 0.5) nd = fd * 0.5;
            n = (float)nd;
            f = (float)fd;
        }
    }
    fv_near_far_sanitize(&n, &f);
    if (out_near_m) *out_near_m = n;
    if (out_far_m) *out_far_m = f;
}

void fv_frame_input_from_head(const fv_head *head, float near_m, float far_m, uint32_t eye_width,
                              uint32_t eye_height, uint64_t frame_id, double time_s, fv_frame_input *out)
{
    memset(out, 0, sizeof *out);
    out->frame_id = frame_id;
    out->time_s = isfinite(time_s) ? time_s : 0.0;
    out->pupil_mm = NAN;
    out->quality = fv_quality_default();
    out->head = (fv_head_pose){.position_m = head ? head->position_m : fv_v3(0, 0, 0),
                               .orientation = head ? head->orientation : fv_quat_identity(),
                               .ipd_mm = head ? head->ipd_mm : FV_DEFAULT_IPD_MM};
    fv_eye_views_build(&out->head, near_m, far_m, eye_width ? eye_width : 1, eye_height ? eye_height : 1, out->eye);
    for (int e = 0; e < 2; e++) {
        out->gaze[e].valid = true;
        out->gaze[e].dir_eye = fv_v3(0, 0, -1);
        out->gaze[e].uncertainty_deg = 0.0f;
    }
}
