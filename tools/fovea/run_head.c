/* @brief The head a gaze-driven `fovea run` follows (see run_head.h). */
#include "run_head.h"

#include <math.h>
#include <string.h>

#define HEAD_POS_LIMIT_MM 1.0e5 /* 100 m of head travel: beyond it a pose is broken */

bool run_head_mode_parse(const char *s, run_head_mode *out)
{
    static const char *const names[] = {"trace", "scene", "fixed"};
    for (int i = 0; i < 3; i++)
        if (strcmp(s, names[i]) == 0) {
            *out = (run_head_mode)i;
            return true;
        }
    return false;
}

const char *run_head_mode_name(run_head_mode m)
{
    return m == RUN_HEAD_SCENE ? "scene" : m == RUN_HEAD_FIXED ? "fixed" : "trace";
}

/* The orientation looking along dir with +y up and no roll (the scene's own look-at); false for no direction. */
static bool quat_from_forward(fv_vec3 dir, fv_quat *out)
{
    if (!fv_v3_isfinite(dir) || !(fv_v3_len(dir) > 1e-6f)) return false;
    fv_head tmp;
    fv_scene_head_look_at(&tmp, fv_v3(0, 0, 0), dir);
    *out = tmp.orientation;
    return true;
}

static fv_quat quat_conj(fv_quat q) { return (fv_quat){-q.x, -q.y, -q.z, q.w}; }

void run_head_apply(run_head *h, const fv_gaze_sample *s, const fv_head *scene, fv_head *out)
{
    *out = *scene;
    h->applied = false;
    if (h->mode != RUN_HEAD_TRACE || !s || !(s->flags & FV_GAZE_HEAD_VALID)) return;
    fv_quat q;
    fv_vec3 p = s->head_pos_mm;
    if (!fv_v3_isfinite(p) || fabsf(p.x) > HEAD_POS_LIMIT_MM || fabsf(p.y) > HEAD_POS_LIMIT_MM ||
        fabsf(p.z) > HEAD_POS_LIMIT_MM || !quat_from_forward(s->head_dir, &q))
        return;
    if (!h->have_ref) {
        h->have_ref = true;
        h->ref_pos_mm = p;
        h->ref_q = q;
        h->ref_seq = s->seq;
    }
    /* relative to the first pose, in that pose's frame: rotation q0^-1 q, translation q0^-1 (p - p0) */
    fv_quat inv0 = quat_conj(h->ref_q);
    fv_quat dq = fv_quat_normalize(fv_quat_mul(inv0, q));
    fv_vec3 dp_m = fv_v3_scale(fv_quat_rotate(inv0, fv_v3_sub(p, h->ref_pos_mm)), 1e-3f);
    /* applied to the scene's head: in its frame */
    out->position_m = fv_v3_add(scene->position_m, fv_quat_rotate(scene->orientation, dp_m));
    out->orientation = fv_quat_normalize(fv_quat_mul(scene->orientation, dq));
    if (!fv_v3_isfinite(out->position_m) || !isfinite(out->orientation.w)) {
        *out = *scene;
        return;
    }
    h->applied = true;
    h->seq = s->seq;
    h->frames_moved++;
}
