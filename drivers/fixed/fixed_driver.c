/* @brief The "fixed" driver (see fv_fixed_driver.h). */
#include "fv_fixed_driver.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"

#define MOD "fixed"
#define URI_MAX 256

typedef struct key {
    const char *name;
    size_t off;
    double min, max;
    const char *unit;
} key;

static const key g_keys[] = {
    {"yaw_deg", offsetof(fv_fixed_desc, yaw_deg), -89, 89, "degrees (positive to the right)"},
    {"pitch_deg", offsetof(fv_fixed_desc, pitch_deg), -89, 89, "degrees (positive up)"},
    {"vergence_m", offsetof(fv_fixed_desc, vergence_m), 0.05, 1000, "metres"},
    {"rate_hz", offsetof(fv_fixed_desc, rate_hz), 1, 2000, "Hz"},
    {"ipd_mm", offsetof(fv_fixed_desc, ipd_mm), 40, 90, "mm"},
    {"pupil_mm", offsetof(fv_fixed_desc, pupil_mm), 1, 9, "mm"},
};
#define KEY_COUNT (sizeof g_keys / sizeof g_keys[0])

fv_result fv_fixed_parse_uri(const char *uri, fv_fixed_desc *out)
{
    if (!out) return FV_ERR_INVALID_ARG;
    *out = (fv_fixed_desc){.rate_hz = 120.0, .ipd_mm = 63.0, .pupil_mm = 4.0};
    if (!uri || strncmp(uri, "fixed:", 6) != 0) {
        FV_ERROR(MOD, "'%.60s': not a fixed: URI", uri ? uri : "(null)");
        return FV_ERR_PARSE;
    }
    char buf[URI_MAX];
    if (strlen(uri + 6) >= sizeof buf) {
        FV_ERROR(MOD, "'%.40s...': URI longer than %zu characters", uri, sizeof buf - 1);
        return FV_ERR_PARSE;
    }
    strcpy(buf, uri + 6);
    bool seen[KEY_COUNT] = {false};
    char *save = NULL;
    for (char *tok = strtok_r(buf, ",&?", &save); tok; tok = strtok_r(NULL, ",&?", &save)) {
        char *eq = strchr(tok, '=');
        if (!eq) {
            FV_ERROR(MOD, "'%s': option '%s' is not key=value (keys: yaw_deg, pitch_deg, vergence_m, rate_hz, "
                     "ipd_mm, pupil_mm)", uri, tok);
            return FV_ERR_PARSE;
        }
        *eq = '\0';
        size_t k = 0;
        while (k < KEY_COUNT && strcmp(g_keys[k].name, tok) != 0) k++;
        if (k == KEY_COUNT) {
            FV_ERROR(MOD, "'%s': unknown key '%s' (keys: yaw_deg, pitch_deg, vergence_m, rate_hz, ipd_mm, pupil_mm)",
                     uri, tok);
            return FV_ERR_PARSE;
        }
        if (seen[k]) {
            FV_ERROR(MOD, "'%s': key '%s' given twice", uri, tok);
            return FV_ERR_PARSE;
        }
        seen[k] = true;
        const char *v = eq + 1;
        char *end = NULL;
        errno = 0;
        double x = strtod(v, &end);
        if (!*v || end == v || *end || errno == ERANGE) {
            FV_ERROR(MOD, "'%s': %s='%s' is not a number", uri, tok, v);
            return FV_ERR_PARSE;
        }
        if (!(x >= g_keys[k].min && x <= g_keys[k].max)) {
            FV_ERROR(MOD, "'%s': %s=%s is outside %g..%g %s", uri, tok, v, g_keys[k].min, g_keys[k].max,
                     g_keys[k].unit);
            return FV_ERR_RANGE;
        }
        *(double *)((char *)out + g_keys[k].off) = x;
    }
    return FV_OK;
}

static fv_vec3 dir_of(double yaw_deg, double pitch_deg)
{
    double y = yaw_deg * FV_PI / 180.0, p = pitch_deg * FV_PI / 180.0;
    return fv_v3((float)(sin(y) * cos(p)), (float)sin(p), (float)(-cos(y) * cos(p)));
}

void fv_fixed_sample(const fv_fixed_desc *d, fv_gaze_sample *out)
{
    fv_gaze_sample_init_invalid(out, 0, 0);
    fv_vec3 c = dir_of(d->yaw_deg, d->pitch_deg);
    double half = d->ipd_mm / 2.0;
    for (int e = 0; e < 2; e++) {
        fv_eye_sample *s = &out->eye[e];
        double x = e == FV_EYE_LEFT ? -half : half;
        s->origin_mm = fv_v3((float)x, 0.0f, 0.0f);
        if (d->vergence_m > 0.0) {
            /* towards the fixation point on the cyclopean ray (from the midpoint), in double */
            double D = d->vergence_m * 1000.0;
            double t[3] = {c.x * D - x, c.y * D, c.z * D};
            double n = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
            s->direction = fv_v3((float)(t[0] / n), (float)(t[1] / n), (float)(t[2] / n));
        } else {
            s->direction = c;
        }
        s->pupil_mm = (float)d->pupil_mm;
        s->openness = 1.0f;
        s->flags = FV_EYE_ORIGIN_VALID | FV_EYE_DIRECTION_VALID | FV_EYE_PUPIL_VALID | FV_EYE_OPENNESS_VALID;
    }
    out->combined.origin_mm = fv_v3(0, 0, 0);
    out->combined.direction = c;
    out->combined.pupil_mm = (float)d->pupil_mm;
    out->combined.openness = 1.0f;
    out->combined.flags = out->eye[0].flags;
    out->confidence = 1.0f;
}

/* ---- device ---- */

typedef struct fixed_device {
    fv_device base; /* first member */
    fv_fixed_desc desc;
    fv_gaze_sample sample;
    const fv_clock *clock;
    int64_t origin_ns;
    uint64_t next; /* index of the next sample; sample k is due at origin + k / rate */
} fixed_device;

static const fv_device_ops g_fixed_ops;

static fv_result probe(fv_device_info *out, size_t cap, size_t *out_count)
{
    if (cap >= 1 && out) {
        memset(&out[0], 0, sizeof out[0]);
        snprintf(out[0].uri, sizeof out[0].uri, "fixed:yaw_deg=0,pitch_deg=0");
        snprintf(out[0].name, sizeof out[0].name, "fovea fixed gaze");
        snprintf(out[0].driver, sizeof out[0].driver, "fixed");
        snprintf(out[0].detail, sizeof out[0].detail,
                 "always available; a constant gaze (keys: yaw_deg, pitch_deg, vergence_m, rate_hz, ipd_mm, pupil_mm)");
    }
    *out_count = 1;
    return FV_OK;
}

static int64_t due_ns(const fixed_device *d, uint64_t k)
{
    return d->origin_ns + (int64_t)((double)k * 1e9 / d->desc.rate_hz);
}

static fv_result fixed_open(const char *uri, const fv_device_open_desc *desc, fv_device **out_dev)
{
    if (!out_dev) return FV_ERR_INVALID_ARG;
    *out_dev = NULL;
    fv_fixed_desc fd;
    FV_TRY(fv_fixed_parse_uri(uri, &fd));
    fixed_device *d = calloc(1, sizeof *d);
    if (!d) return FV_ERR_NO_MEMORY;
    d->desc = fd;
    fv_fixed_sample(&fd, &d->sample);
    d->base.ops = &g_fixed_ops;
    snprintf(d->base.info.uri, sizeof d->base.info.uri, "%s", uri);
    snprintf(d->base.info.name, sizeof d->base.info.name, "fovea fixed gaze");
    snprintf(d->base.info.driver, sizeof d->base.info.driver, "fixed");
    if (fd.vergence_m > 0.0)
        snprintf(d->base.info.detail, sizeof d->base.info.detail, "yaw %g°, pitch %g°, vergence %g m, %g Hz",
                 fd.yaw_deg, fd.pitch_deg, fd.vergence_m, fd.rate_hz);
    else
        snprintf(d->base.info.detail, sizeof d->base.info.detail, "yaw %g°, pitch %g°, parallel, %g Hz", fd.yaw_deg,
                 fd.pitch_deg, fd.rate_hz);
    d->base.nominal_rate_hz = fd.rate_hz;
    d->clock = desc && desc->clock ? desc->clock : fv_clock_monotonic();
    d->origin_ns = fv_clock_now_ns(d->clock);
    *out_dev = &d->base;
    return FV_OK;
}

static fv_result fixed_read(fv_device *dev, fv_gaze_sample *out, size_t cap, size_t *out_count, int timeout_ms)
{
    fixed_device *d = (fixed_device *)dev;
    *out_count = 0;
    if (!out || cap == 0) return FV_ERR_INVALID_ARG;
    bool waited = false;
    for (;;) {
        int64_t now = fv_clock_now_ns(d->clock);
        /* a reader that fell far behind gets the newest samples, not a backlog */
        uint64_t due = (uint64_t)((double)(now - d->origin_ns) * d->desc.rate_hz / 1e9) + 1u;
        if (due > d->next + cap) d->next = due - cap;
        while (*out_count < cap && due_ns(d, d->next) <= now) {
            fv_gaze_sample *s = &out[*out_count];
            *s = d->sample;
            int64_t t = due_ns(d, d->next);
            s->t_device_ns = t - d->origin_ns;
            s->t_host_ns = t;
            s->flags |= FV_GAZE_HOST_TIME_VALID;
            s->seq = d->next++;
            (*out_count)++;
        }
        if (*out_count > 0) return FV_OK;
        if (waited || timeout_ms <= 0) return FV_TIMEOUT;
        int64_t until = now + (int64_t)timeout_ms * FV_NS_PER_MS, next = due_ns(d, d->next);
        d->clock->sleep_until_ns(d->clock, next < until ? next : until);
        waited = true;
    }
}

static void fixed_close(fv_device *dev) { free(dev); }

static const fv_device_ops g_fixed_ops = {fixed_read, fixed_close};

const fv_driver fv_fixed_driver = {
    .scheme = "fixed",
    .summary = "a fixed gaze for both eyes (fixed:yaw_deg=10,pitch_deg=-5[,vergence_m=...])",
    .probe = probe,
    .open = fixed_open,
};
