/* @brief The "mouse" driver (see fv_mouse_driver.h): the pointer state, the cursor-to-gaze geometry and the device. */
#include "fv_mouse_driver.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fovea/fv_frame_input.h"
#include "fv_fixed_driver.h"
#include "fv_log.h"

#define MOD "mouse"

/* ---- the pointer: written by the window's thread, read by the device's reader thread -------------------------- */

static pthread_mutex_t g_lock = PTHREAD_MUTEX_INITIALIZER;
static struct {
    bool attached;
    uint64_t generation; /* bumped by every attach: a device opened on an earlier window is lost */
    fv_mouse_views views;
    bool have_cursor;
    int eye;
    float u, v;
    int64_t t_ns;
} g_pointer;

void fv_mouse_pointer_attach(const fv_mouse_views *views)
{
    pthread_mutex_lock(&g_lock);
    g_pointer.attached = views != NULL;
    g_pointer.generation++;
    if (views) g_pointer.views = *views;
    g_pointer.have_cursor = false;
    pthread_mutex_unlock(&g_lock);
}

void fv_mouse_pointer_detach(void)
{
    pthread_mutex_lock(&g_lock);
    g_pointer.attached = false;
    pthread_mutex_unlock(&g_lock);
}

void fv_mouse_pointer_move(int eye, float u, float v, int64_t t_ns)
{
    if (eye < 0 || eye > 1 || !isfinite(u) || !isfinite(v)) return;
    pthread_mutex_lock(&g_lock);
    g_pointer.have_cursor = true;
    g_pointer.eye = eye;
    g_pointer.u = u;
    g_pointer.v = v;
    g_pointer.t_ns = t_ns;
    pthread_mutex_unlock(&g_lock);
}

/* ---- geometry ------------------------------------------------------------------------------------------------- */

static float finite_or(float x, float fallback) { return isfinite(x) ? x : fallback; }

/* A fixed gaze at that point, as a mouse sees it: no pupil, no eyelid. */
static void sample_at(const fv_fixed_desc *fd, fv_gaze_sample *out)
{
    fv_fixed_sample(fd, out);
    uint32_t keep = FV_EYE_ORIGIN_VALID | FV_EYE_DIRECTION_VALID;
    fv_eye_sample *eyes[3] = {&out->eye[0], &out->eye[1], &out->combined};
    for (int e = 0; e < 3; e++) {
        eyes[e]->flags &= keep;
        eyes[e]->pupil_mm = NAN;
        eyes[e]->openness = NAN;
    }
}

void fv_mouse_gaze(const fv_mouse_views *views, int eye, float u, float v, double vergence_m, fv_gaze_sample *out)
{
    eye = eye == 1 ? 1 : 0;
    u = isfinite(u) ? fminf(fmaxf(u, 0.0f), 1.0f) : 0.5f;
    v = isfinite(v) ? fminf(fmaxf(v, 0.0f), 1.0f) : 0.5f;
    if (!(vergence_m >= 0.05 && vergence_m <= 1000.0)) vergence_m = 1.5;
    double ipd = views ? finite_or(views->ipd_mm, FV_DEFAULT_IPD_MM) : FV_DEFAULT_IPD_MM;
    if (!(ipd >= 0.0 && ipd <= FV_MAX_IPD_MM)) ipd = FV_DEFAULT_IPD_MM;
    /* The eye's ray through the pixel, in its frame (-z forward, y up; the image's v runs down), scaled so that it
     * reaches z = -D: the fixation point, then in the head frame (the eye sits at -+ipd/2 on x). */
    double tl = views ? finite_or(views->tan_left[eye], -1.0f) : -1.0, tr = views ? finite_or(views->tan_right[eye], 1.0f) : 1.0;
    double tu = views ? finite_or(views->tan_up[eye], 1.0f) : 1.0, td = views ? finite_or(views->tan_down[eye], -1.0f) : -1.0;
    double D = vergence_m; /* metres */
    fv_eye_in_head eyes[2]; /* the inverse of the one seam between gaze and views (fv_eye_gaze_from_head) */
    fv_eyes_in_head((float)ipd, eyes);
    fv_vec3 p = fv_eye_point_to_head(&eyes[eye], fv_v3((float)((tl + (tr - tl) * u) * D),
                                                      (float)((tu + (td - tu) * v) * D), (float)-D));
    double px = p.x * 1000.0, py = p.y * 1000.0, pz = p.z * 1000.0; /* mm */
    double dist = sqrt(px * px + py * py + pz * pz);
    /* Both eyes look at that point: the same geometry as a fixed gaze at that point's direction and distance. */
    fv_fixed_desc fd = {.yaw_deg = atan2(px, -pz) * 180.0 / FV_PI,
                        .pitch_deg = asin(fmax(-1.0, fmin(1.0, py / dist))) * 180.0 / FV_PI,
                        .vergence_m = dist / 1000.0,
                        .rate_hz = 1.0,
                        .ipd_mm = ipd,
                        .pupil_mm = NAN};
    sample_at(&fd, out);
}

/* ---- URI ------------------------------------------------------------------------------------------------------- */

fv_result fv_mouse_parse_uri(const char *uri, fv_mouse_desc *out)
{
    *out = (fv_mouse_desc){.vergence_m = 1.5, .rate_hz = 250.0};
    if (!uri || strncmp(uri, "mouse:", 6) != 0) {
        FV_ERROR(MOD, "'%s': not a mouse: URI", uri ? uri : "(null)");
        return FV_ERR_PARSE;
    }
    char buf[256];
    if (strlen(uri + 6) >= sizeof buf) {
        FV_ERROR(MOD, "'%.40s...': URI longer than %zu characters", uri, sizeof buf - 1);
        return FV_ERR_RANGE;
    }
    snprintf(buf, sizeof buf, "%s", uri + 6);
    bool seen[2] = {false, false};
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",&?", &save); tok; tok = strtok_r(NULL, ",&?", &save)) {
        char *eq = strchr(tok, '=');
        if (!eq || eq == tok || !eq[1]) {
            FV_ERROR(MOD, "'%s': option '%s' is not key=value (keys: vergence_m, rate_hz)", uri, tok);
            return FV_ERR_PARSE;
        }
        *eq = '\0';
        const char *val = eq + 1;
        int k = strcmp(tok, "vergence_m") == 0 ? 0 : strcmp(tok, "rate_hz") == 0 ? 1 : -1;
        if (k < 0) {
            FV_ERROR(MOD, "'%s': unknown key '%s' (keys: vergence_m, rate_hz)", uri, tok);
            return FV_ERR_PARSE;
        }
        if (seen[k]) {
            FV_ERROR(MOD, "'%s': key '%s' given twice", uri, tok);
            return FV_ERR_PARSE;
        }
        seen[k] = true;
        char *end = NULL;
        double x = strtod(val, &end);
        if (!end || *end || !isfinite(x)) {
            FV_ERROR(MOD, "'%s': %s='%s' is not a number", uri, tok, val);
            return FV_ERR_PARSE;
        }
        double lo = k == 0 ? 0.05 : 1.0, hi = k == 0 ? 1000.0 : 2000.0;
        if (!(x >= lo && x <= hi)) {
            FV_ERROR(MOD, "'%s': %s=%s is outside %g..%g %s", uri, tok, val, lo, hi, k == 0 ? "m" : "Hz");
            return FV_ERR_RANGE;
        }
        if (k == 0) out->vergence_m = x;
        else out->rate_hz = x;
    }
    return FV_OK;
}

/* ---- the device ------------------------------------------------------------------------------------------------ */

typedef struct mouse_device {
    fv_device base; /* first member */
    fv_mouse_desc desc;
    const fv_clock *clock;
    uint64_t generation;
    int64_t origin_ns, next_ns; /* when the next sample is due */
    uint64_t seq;
} mouse_device;

static fv_result mouse_read(fv_device *dev, fv_gaze_sample *out, size_t cap, size_t *out_count, int timeout_ms)
{
    mouse_device *d = (mouse_device *)dev;
    *out_count = 0;
    if (!out || cap == 0) return FV_ERR_INVALID_ARG;
    int64_t period = (int64_t)llround(1e9 / d->desc.rate_hz);
    int64_t now = fv_clock_now_ns(d->clock);
    if (d->next_ns > now) {
        int64_t wait = d->next_ns - now, limit = (int64_t)(timeout_ms > 0 ? timeout_ms : 0) * 1000000;
        if (wait > limit) {
            if (limit > 0) d->clock->sleep_until_ns(d->clock, now + limit);
            return FV_TIMEOUT;
        }
        d->clock->sleep_until_ns(d->clock, d->next_ns);
        now = fv_clock_now_ns(d->clock);
    }
    pthread_mutex_lock(&g_lock);
    bool attached = g_pointer.attached && g_pointer.generation == d->generation;
    fv_mouse_views views = g_pointer.views;
    bool have = g_pointer.have_cursor;
    int eye = g_pointer.eye;
    float u = g_pointer.u, v = g_pointer.v;
    pthread_mutex_unlock(&g_lock);
    if (!attached) {
        FV_WARN(MOD, "%s: the window is gone", d->base.info.uri);
        return FV_ERR_DEVICE_LOST;
    }
    /* One sample per read: the cursor as it is now (a reader that fell behind gets no backlog of old positions). */
    if (have) {
        fv_mouse_gaze(&views, eye, u, v, d->desc.vergence_m, &out[0]);
    } else { /* no cursor over the images yet: straight ahead at the vergence distance */
        fv_fixed_desc fd = {.vergence_m = d->desc.vergence_m, .rate_hz = 1.0, .ipd_mm = views.ipd_mm, .pupil_mm = NAN};
        sample_at(&fd, &out[0]);
    }
    out[0].t_device_ns = now - d->origin_ns;
    out[0].t_host_ns = now;
    out[0].flags |= FV_GAZE_HOST_TIME_VALID;
    out[0].seq = d->seq++;
    *out_count = 1;
    d->next_ns = (d->next_ns + period > now ? d->next_ns : now) + period;
    return FV_OK;
}

static void mouse_close(fv_device *dev) { free(dev); }

static const fv_device_ops g_mouse_ops = {.read = mouse_read, .close = mouse_close};

static fv_result mouse_probe(fv_device_info *out, size_t cap, size_t *out_count)
{
    if (cap >= 1 && out) {
        memset(&out[0], 0, sizeof out[0]);
        snprintf(out[0].uri, sizeof out[0].uri, "mouse:vergence_m=1.5");
        snprintf(out[0].name, sizeof out[0].name, "fovea window cursor");
        snprintf(out[0].driver, sizeof out[0].driver, "mouse");
        pthread_mutex_lock(&g_lock);
        bool attached = g_pointer.attached;
        pthread_mutex_unlock(&g_lock);
        snprintf(out[0].detail, sizeof out[0].detail,
                 "the cursor in fovea's window as the gaze point (keys: vergence_m, rate_hz); %s",
                 attached ? "a window is open" : "needs a window: fovea run --present window --gaze mouse:");
    }
    *out_count = 1;
    return FV_OK;
}

static fv_result mouse_open(const char *uri, const fv_device_open_desc *desc, fv_device **out_dev)
{
    if (!out_dev) return FV_ERR_INVALID_ARG;
    *out_dev = NULL;
    fv_mouse_desc md;
    FV_TRY(fv_mouse_parse_uri(uri, &md));
    pthread_mutex_lock(&g_lock);
    bool attached = g_pointer.attached;
    uint64_t generation = g_pointer.generation;
    pthread_mutex_unlock(&g_lock);
    if (!attached) {
        FV_ERROR(MOD, "'%s': the mouse is a gaze source only in a window: run with --present window (this program has "
                 "no window)", uri);
        return FV_ERR_UNSUPPORTED;
    }
    mouse_device *d = calloc(1, sizeof *d);
    if (!d) return FV_ERR_NO_MEMORY;
    d->base.ops = &g_mouse_ops;
    d->desc = md;
    d->generation = generation;
    d->clock = desc && desc->clock ? desc->clock : fv_clock_monotonic();
    d->origin_ns = d->next_ns = fv_clock_now_ns(d->clock);
    snprintf(d->base.info.uri, sizeof d->base.info.uri, "%s", uri);
    snprintf(d->base.info.name, sizeof d->base.info.name, "fovea window cursor");
    snprintf(d->base.info.driver, sizeof d->base.info.driver, "mouse");
    snprintf(d->base.info.detail, sizeof d->base.info.detail, "vergence %g m, %g Hz", md.vergence_m, md.rate_hz);
    d->base.nominal_rate_hz = md.rate_hz;
    *out_dev = &d->base;
    return FV_OK;
}

const fv_driver fv_mouse_driver = {
    .scheme = "mouse",
    .summary = "the cursor in fovea's window as the gaze point of both eyes (mouse:vergence_m=1.5)",
    .probe = mouse_probe,
    .open = mouse_open,
};
