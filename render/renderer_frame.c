/* @brief The renderer's frame constants: the runtime's frame input (views, eyes, gaze, pupil, times, exposure) as
 * the GPU frame block every pass reads, with the previous frame's view-projections for motion vectors; the check that
 * an input's matrices are finite; a frame input built from a head. */
#include <math.h>
#include <string.h>

#include "renderer_internal.h"

static fv_gpu_mat4 to_gpu(const fv_mat4 *m)
{
    fv_gpu_mat4 g;
    memcpy(g.m, m->m, sizeof g.m);
    return g;
}

/* The frame constants the runtime's input gives: views, eyes, gaze, pupil, times, quality. */
void fv_renderer_frame_constants(fv_renderer *r, const fv_frame_input *in, fv_gpu_frame *fr, fv_mat4 vp[2])
{
    memset(fr, 0, sizeof *fr);
    for (int e = 0; e < 2; e++) {
        vp[e] = fv_mat4_mul(&in->eye[e].proj, &in->eye[e].view);
        fv_mat4 inv;
        (void)fv_mat4_invert(&vp[e], &inv); /* identity when singular: positions then stay finite */
        fr->view_proj[e] = to_gpu(&vp[e]);
        fr->prev_view_proj[e] = to_gpu(r->have_prev ? &r->prev_view_proj[e] : &vp[e]);
        fr->inv_view_proj[e] = to_gpu(&inv);
        fv_vec3 p = in->eye[e].pos_world;
        fr->eye_pos[e] = (fv_gpu_vec4){p.x, p.y, p.z, 1.0f};
        const fv_eye_view *v = &in->eye[e];
        fr->eye_tan[e] = (fv_gpu_vec4){v->tan_left, v->tan_right, v->tan_up, v->tan_down};
        double step = fmin(fabs((double)v->tan_right - v->tan_left) / r->desc.eye_width,
                           fabs((double)v->tan_down - v->tan_up) / r->desc.eye_height);
        float angle = (float)(2.0 * atan(0.5 * step));
        if (e == 0) fr->pixel_angle.x = isfinite(angle) ? angle : 0.0f;
        else fr->pixel_angle.y = isfinite(angle) ? angle : 0.0f;
        /* Gaze: a valid, finite, non-zero direction is normalised; anything else is "no gaze" (straight ahead). */
        const fv_eye_gaze *g = &in->gaze[e];
        fv_vec3 d = fv_v3(0, 0, 0);
        if (g->valid && fv_v3_isfinite(g->dir_eye)) {
            /* Scale by the largest component first, so that neither huge nor tiny directions over/underflow. */
            float m = fmaxf(fabsf(g->dir_eye.x), fmaxf(fabsf(g->dir_eye.y), fabsf(g->dir_eye.z)));
            if (m > 0.0f) d = fv_v3_normalize_or(fv_v3_scale(g->dir_eye, 1.0f / m), fv_v3(0, 0, 0));
        }
        bool valid = fv_v3_len(d) > 0.5f;
        if (!valid) d = fv_v3(0, 0, -1);
        fr->gaze_dir[e] = (fv_gpu_vec4){d.x, d.y, d.z, valid ? 1.0f : 0.0f};
        float u = isfinite(g->uncertainty_deg) ? fv_clampf((float)fv_deg_to_rad(g->uncertainty_deg), 0.0f, (float)FV_PI)
                                               : (float)FV_PI;
        /* A human pupil is 1.5 to 9 mm: anything outside (0, FV_GPU_PUPIL_MAX_MM] is unknown (0). */
        float pupil = isfinite(in->pupil_mm) && in->pupil_mm > 0.0f && in->pupil_mm <= FV_GPU_PUPIL_MAX_MM ? in->pupil_mm
                                                                                                         : 0.0f;
        fr->gaze_info[e] = (fv_gpu_vec4){valid ? u : (float)FV_PI, pupil, 0.0f, 0.0f};
    }
    fr->counts = (fv_gpu_uvec4){0, r->desc.eye_width, r->desc.eye_height, (uint32_t)in->frame_id};
    fr->time = (fv_gpu_vec4){(float)(isfinite(in->time_s) ? in->time_s : 0.0), 0.0f, 0.0f, 0.0f};
    uint64_t photon = in->t_photon_ns > 0 ? (uint64_t)in->t_photon_ns : 0u;
    fr->photon = (fv_gpu_uvec4){(uint32_t)photon, (uint32_t)(photon >> 32), (uint32_t)in->quality.debug_view, 0};
    fr->quality = (fv_gpu_vec4){in->quality.exposure, 0.0f, 0.0f, 0.0f};
}

bool fv_renderer_frame_input_ok(const fv_frame_input *in)
{
    for (int e = 0; e < 2; e++)
        for (int c = 0; c < 4; c++)
            for (int k = 0; k < 4; k++)
                if (!isfinite(in->eye[e].view.m[c][k]) || !isfinite(in->eye[e].proj.m[c][k])) return false;
    return fv_v3_isfinite(in->eye[0].pos_world) && fv_v3_isfinite(in->eye[1].pos_world);
}

fv_result fv_renderer_frame_input(const fv_renderer *r, const fv_head *head, uint64_t frame_id, double time_s,
                                  fv_frame_input *out)
{
    if (!r || !out) return FV_ERR_INVALID_ARG;
    if (!r->scene_loaded) return FV_ERR_STATE;
    const fv_head *h = head ? head : &r->head;
    float n = 0, f = 0;
    if (r->has_bounds) fv_frame_near_far_from_bounds(h, r->bounds_min, r->bounds_max, &n, &f);
    fv_frame_input_from_head(h, n, f, r->desc.eye_width, r->desc.eye_height, frame_id, time_s, out);
    return FV_OK;
}
