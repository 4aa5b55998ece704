/* @brief The head a gaze-driven `fovea run` follows (see run_head.h). */
#include "run_head.h"

#include <math.h>
#include <string.h>

void run_head_apply(run_head *h, const fv_quat *pdq, const fv_vec3 *pdp_m, uint64_t seq, const fv_head *scene,
                    fv_head *out)
{
    *out = *scene;
    h->applied = false;
    if (h->mode != FV_APP_HEAD_TRACE || !pdq || !pdp_m) return;
    fv_quat dq = *pdq;
    fv_vec3 dp_m = *pdp_m;
    /* applied to the scene's head: in its frame */
    out->position_m = fv_v3_add(scene->position_m, fv_quat_rotate(scene->orientation, dp_m));
    out->orientation = fv_quat_normalize(fv_quat_mul(scene->orientation, dq));
    if (!fv_v3_isfinite(out->position_m) || !isfinite(out->orientation.w)) {
        *out = *scene;
        return;
    }
    h->applied = true;
    h->seq = seq;
    h->frames_moved++;
}
