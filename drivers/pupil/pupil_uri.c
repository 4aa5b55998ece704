/* @brief pupil: URIs: "pupil:HOST[:PORT][?k=v&...]" with the scene camera model and the confidence floor. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_pupil_driver.h"

#define MOD "pupil"
#define KNOWN "fx, fy, cx, cy, width, height (scene camera, px), min_confidence, timeout_ms"

fv_pupil_camera fv_pupil_camera_default(void)
{
    return (fv_pupil_camera){1280.0, 720.0, 800.0, 800.0, 640.0, 360.0};
}

static bool parse_num(const char *s, double lo, double hi, double *out)
{
    char *end = NULL;
    double v = strtod(s, &end);
    if (end == s || *end || !isfinite(v) || v < lo || v > hi) return false;
    *out = v;
    return true;
}

static fv_result parse_host_port(const char *uri, const char *p, size_t len, fv_pupil_uri *u)
{
    const char *host = p, *colon = NULL;
    size_t hlen = len;
    if (len && p[0] == '[') { /* [v6addr]:port */
        const char *rb = memchr(p, ']', len);
        if (!rb) {
            FV_ERROR(MOD, "'%s': '[' without ']' in the host", uri);
            return FV_ERR_INVALID_ARG;
        }
        host = p + 1;
        hlen = (size_t)(rb - host);
        if (rb + 1 < p + len) {
            if (rb[1] != ':') {
                FV_ERROR(MOD, "'%s': expected ':PORT' after ']'", uri);
                return FV_ERR_INVALID_ARG;
            }
            colon = rb + 1;
        }
    } else {
        colon = memchr(p, ':', len);
        if (colon) hlen = (size_t)(colon - p);
    }
    if (hlen == 0) {
        host = "127.0.0.1";
        hlen = strlen(host);
    }
    if (hlen >= sizeof u->host) {
        FV_ERROR(MOD, "'%.64s...': host name too long", uri);
        return FV_ERR_INVALID_ARG;
    }
    for (size_t i = 0; i < hlen; i++) {
        char c = host[i];
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '-' ||
              c == '_' || c == ':')) {
            FV_ERROR(MOD, "'%s': host '%.*s' has a character that is not allowed in a host name", uri, (int)hlen,
                     host);
            return FV_ERR_INVALID_ARG;
        }
    }
    memcpy(u->host, host, hlen);
    u->host[hlen] = '\0';
    if (colon) {
        size_t plen = (size_t)(p + len - colon - 1);
        char port[16];
        double v;
        if (plen == 0 || plen >= sizeof port) {
            FV_ERROR(MOD, "'%s': port must be a number in 1..65535", uri);
            return FV_ERR_INVALID_ARG;
        }
        memcpy(port, colon + 1, plen);
        port[plen] = '\0';
        if (!parse_num(port, 1, 65535, &v) || v != floor(v)) {
            FV_ERROR(MOD, "'%s': port '%s' must be a number in 1..65535", uri, port);
            return FV_ERR_INVALID_ARG;
        }
        u->port = (int)v;
    }
    return FV_OK;
}

fv_result fv_pupil_uri_parse(const char *uri, fv_pupil_uri *u)
{
    memset(u, 0, sizeof *u);
    u->port = FV_PUPIL_DEFAULT_PORT;
    u->camera = fv_pupil_camera_default();
    u->min_confidence = 0.6;
    u->timeout_ms = 1000;
    const char *rest = uri;
    if (strncmp(rest, "pupil:", 6) != 0) {
        FV_ERROR(MOD, "'%s': not a pupil: URI (pupil:HOST[:PORT])", uri);
        return FV_ERR_INVALID_ARG;
    }
    rest += 6;
    if (strncmp(rest, "//", 2) == 0) rest += 2;
    const char *q = strchr(rest, '?');
    FV_TRY(parse_host_port(uri, rest, q ? (size_t)(q - rest) : strlen(rest), u));
    bool have_w = false, have_h = false, have_cx = false, have_cy = false, have_fy = false;
    for (const char *p = q ? q + 1 : ""; *p;) {
        const char *amp = strchr(p, '&');
        size_t len = amp ? (size_t)(amp - p) : strlen(p);
        const char *eq = memchr(p, '=', len);
        char key[32], val[64];
        size_t klen = eq ? (size_t)(eq - p) : len, vlen = eq ? len - klen - 1 : 0;
        if (!eq || klen == 0 || klen >= sizeof key || vlen == 0 || vlen >= sizeof val) {
            FV_ERROR(MOD, "'%s': malformed option '%.*s' (use KEY=VALUE; known: %s)", uri, (int)len, p, KNOWN);
            return FV_ERR_INVALID_ARG;
        }
        memcpy(key, p, klen);
        key[klen] = '\0';
        memcpy(val, eq + 1, vlen);
        val[vlen] = '\0';
        double v;
        fv_pupil_camera *c = &u->camera;
        struct {
            const char *name;
            double *dst;
            double lo, hi;
            bool *have;
        } nums[] = {
            {"fx", &c->fx_px, 1.0, 1e5, NULL},       {"fy", &c->fy_px, 1.0, 1e5, &have_fy},
            {"cx", &c->cx_px, 0.0, 1e5, &have_cx},   {"cy", &c->cy_px, 0.0, 1e5, &have_cy},
            {"width", &c->width_px, 1.0, 1e5, &have_w}, {"height", &c->height_px, 1.0, 1e5, &have_h},
            {"min_confidence", &u->min_confidence, -1.0, 1.0, NULL},
        };
        bool done = false;
        for (size_t i = 0; i < sizeof nums / sizeof nums[0]; i++) {
            if (strcmp(key, nums[i].name) != 0) continue;
            if (!parse_num(val, nums[i].lo, nums[i].hi, &v)) {
                FV_ERROR(MOD, "'%s': %s '%s' must be a number in [%g, %g]", uri, key, val, nums[i].lo, nums[i].hi);
                return FV_ERR_INVALID_ARG;
            }
            *nums[i].dst = v;
            if (nums[i].have) *nums[i].have = true;
            done = true;
        }
        if (!done && strcmp(key, "timeout_ms") == 0) {
            if (!parse_num(val, 1, 60000, &v) || v != floor(v)) {
                FV_ERROR(MOD, "'%s': timeout_ms '%s' must be an integer in [1, 60000]", uri, val);
                return FV_ERR_INVALID_ARG;
            }
            u->timeout_ms = (int)v;
            done = true;
        }
        if (!done) {
            FV_ERROR(MOD, "'%s': unknown option '%s' (known: %s)", uri, key, KNOWN);
            return FV_ERR_INVALID_ARG;
        }
        p += len + (amp ? 1 : 0);
    }
    fv_pupil_camera *c = &u->camera;
    if (!have_fy) c->fy_px = c->fx_px; /* square pixels */
    if (have_w && !have_cx) c->cx_px = 0.5 * c->width_px;
    if (have_h && !have_cy) c->cy_px = 0.5 * c->height_px;
    if (c->cx_px > c->width_px || c->cy_px > c->height_px) {
        FV_ERROR(MOD, "'%s': the principal point (%g, %g) px lies outside the %gx%g px image", uri, c->cx_px, c->cy_px,
                 c->width_px, c->height_px);
        return FV_ERR_INVALID_ARG;
    }
    return FV_OK;
}
