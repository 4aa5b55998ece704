/* @brief The renderer's frame input for a scene head: near/far from the scene bounds, the eye views from the one
 * builder (fv_eye_views_build), gaze straight ahead, default quality. */
#include <math.h>
#include <string.h>

#include "fv_renderer.h"

void fv_frame_near_far_from_bounds(const fv_head *head, fv_vec3 bounds_min, fv_vec3 bounds_max, float *out_near_m,
                                   float *out_far_m)
{
    fv_head_pose pose = {.position_m = head ? head->position_m : fv_v3(NAN, NAN, NAN),
                         .orientation = head ? head->orientation : fv_quat_identity(),
                         .ipd_mm = head ? head->ipd_mm : FV_DEFAULT_IPD_MM};
    fv_near_far_from_bounds(head ? &pose : NULL, bounds_min, bounds_max, out_near_m, out_far_m);
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
