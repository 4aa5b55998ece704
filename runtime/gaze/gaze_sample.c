/* @brief fv_gaze_sample helpers. */
#include "fovea/fv_gaze_sample.h"

#include <math.h>
#include <string.h>

static void eye_invalid(fv_eye_sample *e)
{
    e->origin_mm = fv_v3(NAN, NAN, NAN);
    e->direction = fv_v3(NAN, NAN, NAN);
    e->pupil_mm = NAN;
    e->openness = NAN;
    e->flags = 0;
}

void fv_gaze_sample_init_invalid(fv_gaze_sample *s, int64_t t_device_ns, int64_t t_host_ns)
{
    memset(s, 0, sizeof *s);
    s->t_device_ns = t_device_ns;
    s->t_host_ns = t_host_ns;
    eye_invalid(&s->eye[0]);
    eye_invalid(&s->eye[1]);
    eye_invalid(&s->combined);
    s->confidence = NAN;
    s->screen_point_mm = (fv_vec2){NAN, NAN};
    s->head_pos_mm = fv_v3(NAN, NAN, NAN);
    s->head_dir = fv_v3(NAN, NAN, NAN);
}
