/* @brief Following a tracker's recorded head pose (see fv_head_follow.h). */
#include "fv_head_follow.h"

#include <math.h>

bool fv_head_follow_delta(fv_head_follow *h, const fv_gaze_sample *s, fv_quat *out_dq, fv_vec3 *out_dp_m)
{
    if (!s || !(s->flags & FV_GAZE_HEAD_VALID)) return false;
    fv_vec3 p = s->head_pos_mm, f = s->head_dir;
    if (!fv_v3_isfinite(p) || fabsf(p.x) > FV_HEAD_FOLLOW_LIMIT_MM || fabsf(p.y) > FV_HEAD_FOLLOW_LIMIT_MM ||
        fabsf(p.z) > FV_HEAD_FOLLOW_LIMIT_MM || !fv_v3_isfinite(f) || !(fv_v3_len(f) > 1e-6f))
        return false;
    fv_quat q = fv_quat_look_along(f);
    if (!h->have_ref) {
        h->have_ref = true;
        h->ref_pos_mm = p;
        h->ref_q = q;
        h->ref_seq = s->seq;
    }
    /* relative to the first pose, in that pose's frame: rotation q0^-1 q, translation q0^-1 (p - p0) */
    fv_quat inv0 = {-h->ref_q.x, -h->ref_q.y, -h->ref_q.z, h->ref_q.w};
    fv_quat dq = fv_quat_normalize(fv_quat_mul(inv0, q));
    fv_vec3 dp_m = fv_v3_scale(fv_quat_rotate(inv0, fv_v3_sub(p, h->ref_pos_mm)), 1e-3f);
    if (!fv_v3_isfinite(dp_m) || !isfinite(dq.w)) return false;
    *out_dq = dq;
    *out_dp_m = dp_m;
    return true;
}
