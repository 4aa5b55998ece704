/* @brief HMD profiles from JSON (cJSON): built-in ones embedded from hmd/NAME.json at build time, or any file. Every
 * error names the file, the field and the reason; a profile is only returned after its lens validated. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_file.h"
#include "fv_hmd.h"
#include "fv_json_scan.h"
#include "hmd_builtin.h"
#include "hmd_internal.h"

#define MAX_FILE_BYTES (1u << 20) /* a profile is a few kB; anything past 1 MiB is not one */
#define FOV_TOLERANCE 0.01        /* the fov tangents agree with the lens geometry within 1% */

#define say fv_hmd_say

const char *const *fv_hmd_builtin_names(void) { return fv_hmd_builtin_name_list; }

typedef struct ctx {
    const char *origin;
    char *err;
    size_t err_size;
} ctx;

/* A number at obj.key (path names it); false (error said) when missing, not a number or out of [lo, hi]. */
static bool number(const ctx *c, const cJSON *obj, const char *key, const char *path, double lo, double hi,
                   double *out)
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!it) {
        say(c->err, c->err_size, "%s: %s: missing (a number in [%g, %g])", c->origin, path, lo, hi);
        return false;
    }
    if (!cJSON_IsNumber(it) || !isfinite(it->valuedouble)) {
        say(c->err, c->err_size, "%s: %s: not a finite number", c->origin, path);
        return false;
    }
    if (it->valuedouble < lo || it->valuedouble > hi) {
        say(c->err, c->err_size, "%s: %s: %g is not in [%g, %g]", c->origin, path, it->valuedouble, lo, hi);
        return false;
    }
    *out = it->valuedouble;
    return true;
}

static bool object(const ctx *c, const cJSON *obj, const char *key, const char *path, const cJSON **out)
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!cJSON_IsObject(it)) {
        say(c->err, c->err_size, "%s: %s: %s", c->origin, path, it ? "not an object" : "missing (an object)");
        return false;
    }
    *out = it;
    return true;
}

static bool text(const ctx *c, const cJSON *obj, const char *key, const char *path, char *out, size_t out_size)
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!cJSON_IsString(it) || !it->valuestring[0]) {
        say(c->err, c->err_size, "%s: %s: %s", c->origin, path, it ? "not a non-empty string" : "missing (a string)");
        return false;
    }
    size_t n = strlen(it->valuestring);
    if (out && n >= out_size) { /* never cut silently */
        say(c->err, c->err_size, "%s: %s: %zu bytes, more than the %zu-byte limit", c->origin, path, n, out_size - 1);
        return false;
    }
    if (out) memcpy(out, it->valuestring, n + 1);
    return true;
}

static bool array(const ctx *c, const cJSON *obj, const char *key, const char *path, int n, double lo, double hi,
                  float *out)
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!cJSON_IsArray(it) || cJSON_GetArraySize(it) != n) {
        say(c->err, c->err_size, "%s: %s: %s (an array of %d numbers)", c->origin, path,
            it ? "not an array of the right length" : "missing", n);
        return false;
    }
    for (int i = 0; i < n; i++) {
        const cJSON *v = cJSON_GetArrayItem(it, i);
        if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble) || v->valuedouble < lo || v->valuedouble > hi) {
            say(c->err, c->err_size, "%s: %s[%d]: not a finite number in [%g, %g]", c->origin, path, i, lo, hi);
            return false;
        }
        out[i] = (float)v->valuedouble;
    }
    return true;
}

/* The sources object names where each group of values comes from (a citation, or how an unpublished value was
 * chosen). Every group must be there. */
static bool sources(const ctx *c, const cJSON *root)
{
    static const char *const keys[] = {"panel", "refresh_hz", "lens_geometry", "eye_to_screen", "k", "aberration",
                                       "visible_radius", "fov"};
    const cJSON *s;
    if (!object(c, root, "sources", "sources", &s)) return false;
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        char path[64];
        snprintf(path, sizeof path, "sources.%s", keys[i]);
        if (!text(c, s, keys[i], path, NULL, 0)) return false;
    }
    return true;
}

static bool fov_eye(const ctx *c, const cJSON *fov, const char *eye_key, const fv_lens *l, int eye, fv_hmd_fov *out)
{
    const cJSON *o;
    char path[64];
    snprintf(path, sizeof path, "fov.%s", eye_key);
    if (!object(c, fov, eye_key, path, &o)) return false;
    static const char *const names[4] = {"tan_left", "tan_right", "tan_up", "tan_down"};
    double w = l->viewport_m[0], h = l->viewport_m[1], cx = l->centre_m[eye][0], cy = l->centre_m[eye][1];
    double geo[4] = {cx * l->tan_per_m, (w - cx) * l->tan_per_m, cy * l->tan_per_m, (h - cy) * l->tan_per_m};
    static const char *const why[4] = {"lens centre to the viewport's left edge", "lens centre to its right edge",
                                       "lens centre to its top edge", "lens centre to its bottom edge"};
    float *dst[4] = {&out->tan_left, &out->tan_right, &out->tan_up, &out->tan_down};
    for (int i = 0; i < 4; i++) {
        double v;
        snprintf(path, sizeof path, "fov.%s.%s", eye_key, names[i]);
        if (!number(c, o, names[i], path, 1e-3, 20.0, &v)) return false;
        if (fabs(v - geo[i]) > FOV_TOLERANCE * geo[i]) {
            say(c->err, c->err_size,
                "%s: %s: %g disagrees with the lens geometry's %.6g (%s / lens.eye_to_screen_m) by more than %g%%",
                c->origin, path, v, geo[i], why[i], FOV_TOLERANCE * 100);
            return false;
        }
        *dst[i] = (float)v;
    }
    return true;
}

static fv_result parse_root(const ctx *c, const cJSON *root, fv_hmd_profile *p)
{
    if (!cJSON_IsObject(root)) {
        say(c->err, c->err_size, "%s: not a JSON object", c->origin);
        return FV_ERR_PARSE;
    }
    char format[32];
    if (!text(c, root, "format", "format", format, sizeof format)) return FV_ERR_PARSE;
    if (strcmp(format, "fovea-hmd 1") != 0) {
        say(c->err, c->err_size, "%s: format: '%s' is not \"fovea-hmd 1\"", c->origin, format);
        return FV_ERR_PARSE;
    }
    if (!text(c, root, "name", "name", p->name, sizeof p->name)) return FV_ERR_PARSE;
    if (!text(c, root, "description", "description", p->description, sizeof p->description)) return FV_ERR_PARSE;
    if (!sources(c, root)) return FV_ERR_PARSE;

    const cJSON *panel, *lens, *fov;
    if (!object(c, root, "panel", "panel", &panel) || !object(c, root, "lens", "lens", &lens) ||
        !object(c, root, "fov", "fov", &fov))
        return FV_ERR_PARSE;
    double wpx, hpx, wm, hm, hz;
    if (!number(c, panel, "width_px", "panel.width_px", 2, 16384, &wpx) ||
        !number(c, panel, "height_px", "panel.height_px", 1, 16384, &hpx) ||
        !number(c, panel, "width_m", "panel.width_m", 1e-3, 10, &wm) ||
        !number(c, panel, "height_m", "panel.height_m", 1e-3, 10, &hm) ||
        !number(c, panel, "refresh_hz", "panel.refresh_hz", 1, 1000, &hz))
        return FV_ERR_RANGE;
    if (wpx != floor(wpx) || hpx != floor(hpx) || ((uint32_t)wpx & 1u)) {
        say(c->err, c->err_size, "%s: panel.width_px/height_px: %g x %g is not whole pixels with an even width "
            "(two eyes side by side)", c->origin, wpx, hpx);
        return FV_ERR_RANGE;
    }
    p->panel_width_px = (uint32_t)wpx;
    p->panel_height_px = (uint32_t)hpx;
    p->panel_width_m = (float)wm;
    p->panel_height_m = (float)hm;
    p->refresh_hz = (float)hz;

    fv_lens *l = &p->lens;
    memset(l, 0, sizeof *l);
    l->valid = true;
    l->viewport_m[0] = (float)(wm / 2.0);
    l->viewport_m[1] = (float)hm;
    double sep, vpos, n;
    if (!number(c, lens, "separation_m", "lens.separation_m", 1e-4, wm, &sep) ||
        !number(c, lens, "vertical_position_m", "lens.vertical_position_m", 1e-4, hm, &vpos) ||
        !number(c, lens, "eye_to_screen_m", "lens.eye_to_screen_m", 1e-4, 10, &n))
        return FV_ERR_RANGE;
    if (!(sep / 2.0 < wm / 2.0 && sep / 2.0 > 0.0)) {
        say(c->err, c->err_size, "%s: lens.separation_m: %g puts the lens centres outside their eyes' halves of a "
            "%g m panel", c->origin, sep, wm);
        return FV_ERR_RANGE;
    }
    /* OpenHMD's convention: the lens centres sit separation_m apart about the panel's middle, vertical_position_m
     * above its bottom edge; here in each eye's viewport, from its top-left corner. */
    l->centre_m[0][0] = (float)(wm / 2.0 - sep / 2.0);
    l->centre_m[1][0] = (float)(sep / 2.0);
    l->centre_m[0][1] = l->centre_m[1][1] = (float)(hm - vpos);
    l->tan_per_m = (float)(1.0 / n);
    const cJSON *ws = cJSON_GetObjectItemCaseSensitive(lens, "warp_scale_m");
    if (ws) {
        double w;
        if (!number(c, lens, "warp_scale_m", "lens.warp_scale_m", 1e-4, 10, &w)) return FV_ERR_RANGE;
        l->warp_m = (float)w;
    } else {
        /* OpenHMD: the calibration radius is the lens centre's distance to the farther side edge of its viewport */
        l->warp_m = fmaxf(l->centre_m[0][0], l->centre_m[1][0]);
    }
    if (!array(c, lens, "k", "lens.k", FV_LENS_K, -1e3, 1e3, l->k)) return FV_ERR_RANGE;
    if (!array(c, lens, "aberration", "lens.aberration", 3, 0.5, 2.0, l->aberration)) return FV_ERR_RANGE;
    double vis;
    if (!number(c, lens, "visible_radius", "lens.visible_radius", 0, 100, &vis)) return FV_ERR_RANGE;
    l->visible_r = (float)vis;
    char why[FV_HMD_TEXT_MAX];
    fv_result res = fv_lens_validate(l, why, sizeof why);
    if (res != FV_OK) {
        say(c->err, c->err_size, "%s: %s", c->origin, why);
        return FV_ERR_RANGE;
    }
    if (!fov_eye(c, fov, "left", l, 0, &p->fov[0]) || !fov_eye(c, fov, "right", l, 1, &p->fov[1]))
        return FV_ERR_RANGE;
    return FV_OK;
}

fv_result fv_hmd_profile_parse(const char *json, size_t len, const char *origin, fv_hmd_profile *out, char *err,
                               size_t err_size)
{
    if (!json || !out) return FV_ERR_INVALID_ARG;
    ctx c = {.origin = origin ? origin : "(profile)", .err = err, .err_size = err_size};
    fv_json_scan scan; /* cJSON gives up past its nesting limit without saying so: check it first */
    fv_json_scan_text(json, len, CJSON_NESTING_LIMIT, &scan);
    if (scan.too_deep_at != SIZE_MAX) {
        int line, col;
        fv_text_line_col(json, scan.too_deep_at, &line, &col);
        say(err, err_size, "%s:%d:%d: not valid JSON: nested deeper than %d levels (the JSON parser's limit)",
            c.origin, line, col, CJSON_NESTING_LIMIT);
        return FV_ERR_PARSE;
    }
    cJSON *root = cJSON_ParseWithLength(json, len);
    if (!root) {
        const char *at = cJSON_GetErrorPtr();
        long off = at && at >= json && at <= json + len ? (long)(at - json) : -1;
        unsigned line = 1;
        for (long i = 0; i < off; i++) line += json[i] == '\n';
        say(err, err_size, "%s:%u: not valid JSON (near byte %ld)", c.origin, line, off);
        return FV_ERR_PARSE;
    }
    fv_hmd_profile p;
    memset(&p, 0, sizeof p);
    size_t olen = strlen(c.origin); /* a label: a long path keeps its end (the file name) after "..." */
    if (olen < sizeof p.origin) memcpy(p.origin, c.origin, olen + 1);
    else snprintf(p.origin, sizeof p.origin, "...%s", c.origin + olen - (sizeof p.origin - 4));
    fv_result res = parse_root(&c, root, &p);
    cJSON_Delete(root);
    if (res == FV_OK) *out = p;
    return res;
}

static fv_result load_builtin(size_t i, fv_hmd_profile *out, char *err, size_t err_size)
{
    char origin[FV_HMD_TEXT_MAX];
    snprintf(origin, sizeof origin, "builtin:%s (hmd/%s.json)", fv_hmd_builtin_name_list[i], fv_hmd_builtin_name_list[i]);
    const char *json = (const char *)fv_hmd_builtin_text[i];
    return fv_hmd_profile_parse(json, strlen(json), origin, out, err, err_size);
}

fv_result fv_hmd_profile_load(const char *name_or_path, fv_hmd_profile *out, char *err, size_t err_size)
{
    if (!name_or_path || !name_or_path[0] || !out) {
        say(err, err_size, "no HMD profile named");
        return FV_ERR_INVALID_ARG;
    }
    for (size_t i = 0; fv_hmd_builtin_name_list[i]; i++)
        if (strcmp(fv_hmd_builtin_name_list[i], name_or_path) == 0) return load_builtin(i, out, err, err_size);
    char *buf;
    size_t n;
    char why[FV_FILE_ERR_MAX];
    fv_result res = fv_file_read(name_or_path, NULL, MAX_FILE_BYTES, &buf, &n, why, sizeof why);
    if (res == FV_ERR_NOT_FOUND) {
        char names[256] = "";
        for (size_t i = 0; fv_hmd_builtin_name_list[i]; i++)
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i ? ", " : "",
                     fv_hmd_builtin_name_list[i]);
        const char *cause = strstr(why, "cannot open: "); /* the system's reason, after fv_file's words */
        say(err, err_size, "%s: no such HMD profile (built-in: %s) or file (%s)", name_or_path, names,
            cause ? cause + strlen("cannot open: ") : strerror(ENOENT));
        return res;
    }
    if (res != FV_OK) {
        say(err, err_size, "%s%s", why, res == FV_ERR_RANGE ? ": not an HMD profile" : "");
        return res;
    }
    /* A byte-identical copy of a built-in profile is that profile, origin included (issue 28: a copy of
     * hmd/generic.json was labelled by its path, and `fovea compare` refused it against `--hmd generic`). */
    for (size_t i = 0; fv_hmd_builtin_name_list[i]; i++) {
        const char *json = (const char *)fv_hmd_builtin_text[i];
        if (strlen(json) == n && memcmp(json, buf, n) == 0) {
            free(buf);
            return load_builtin(i, out, err, err_size);
        }
    }
    res = fv_hmd_profile_parse(buf, n, name_or_path, out, err, err_size);
    free(buf);
    return res;
}
