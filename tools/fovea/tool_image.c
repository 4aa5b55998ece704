/* @brief What an image shows, one description for run, reference and bench (see tool_image.h). */
#include "tool_image.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "fv_hmd.h"
#include "fv_log.h"
#include "fv_tone_curve.h"

void fv_tool_image_defaults(fv_tool_image *o)
{
    memset(o, 0, sizeof *o);
    fv_app_run_defaults(&o->run);
    o->hmd.run = &o->run;
}

/* "+1ev" / "-2EV": stops, 2^EV; otherwise a linear scale. */
static bool parse_exposure(const char *v, double *out)
{
    size_t vl = strlen(v);
    if (vl > 2 && (strcmp(v + vl - 2, "ev") == 0 || strcmp(v + vl - 2, "EV") == 0)) {
        char num[32] = "";
        if (vl - 2 >= sizeof num) return false;
        snprintf(num, sizeof num, "%.*s", (int)(vl - 2), v);
        double ev;
        if (!fv_cli_parse_f64(num, -19.9, 19.9, &ev)) return false;
        *out = exp2(ev);
        return true;
    }
    return fv_cli_parse_f64(v, 1e-6, 1e6, out);
}

int fv_tool_image_option(fv_tool_image *o, int argc, char **argv, int *i, const char *cmd, const char *usage)
{
    const char *v = NULL;
    int r;
#define OPT(name) ((r = fv_cli_option(argc, argv, i, name, &v)) < 0 ? (fv_cli_usage_error(cmd, usage, "option %s needs a value", name), -2) : r)
    if ((r = OPT("--scene")) == -2) return FV_EXIT_USAGE;
    else if (r) {
        o->run.scene = v;
        return 1;
    }
    if ((r = OPT("--eye-size")) == -2) return FV_EXIT_USAGE;
    else if (r) {
        if (!fv_cli_parse_size(v, FV_APP_RUN_MAX_EYE_SIZE, &o->run.eye_w, &o->run.eye_h))
            return fv_cli_usage_error(cmd, usage, "--eye-size: '%s' is not WxH with each in 1..%u", v,
                                      FV_APP_RUN_MAX_EYE_SIZE);
        return 1;
    }
    if ((r = OPT("--layout")) == -2) return FV_EXIT_USAGE;
    else if (r) {
        if (strcmp(v, "sbs") == 0) o->run.sbs = true;
        else if (strcmp(v, "eyes") == 0) o->run.sbs = false;
        else return fv_cli_usage_error(cmd, usage, "--layout: '%s' is not one of sbs, eyes", v);
        o->layout_given = true;
        return 1;
    }
    if ((r = OPT("--view")) == -2) return FV_EXIT_USAGE;
    else if (r) {
        char names[512] = "";
        for (int k = 0; k < FV_DEBUG_VIEW_COUNT; k++) {
            if (strcmp(v, fv_debug_view_name((fv_debug_view)k)) == 0) {
                o->run.view = (fv_debug_view)k;
                return 1;
            }
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", k ? ", " : "",
                     fv_debug_view_name((fv_debug_view)k));
        }
        return fv_cli_usage_error(cmd, usage, "--view: '%s' is not one of %s", v, names);
    }
    if ((r = OPT("--exposure")) == -2) return FV_EXIT_USAGE;
    else if (r) {
        double x;
        size_t vl = strlen(v);
        bool stops = vl > 2 && (strcmp(v + vl - 2, "ev") == 0 || strcmp(v + vl - 2, "EV") == 0);
        if (!parse_exposure(v, &x))
            return stops ? fv_cli_usage_error(cmd, usage, "--exposure: '%s' is not a number of stops in -19.9..19.9 "
                                              "followed by EV", v)
                         : fv_cli_usage_error(cmd, usage, "--exposure: '%s' is not a number in 1e-6..1e6 (a linear "
                                              "scale) or stops such as +1EV", v);
        o->run.exposure = (float)x;
        return 1;
    }
#undef OPT
    if ((r = run_hmd_option(&o->hmd, argc, argv, i, usage)) != 0) return r;
    return fv_tool_quality_option(&o->run.quality, argc, argv, i, cmd, usage);
}

int fv_tool_image_finish(fv_tool_image *o, const char *cmd, const char *usage)
{
    char err[512];
    int failed;
    if (FV_FAILED(fv_app_run_quality(&o->run, &o->quality, &failed, err, sizeof err)))
        return fv_cli_usage_error(cmd, usage, "%s: %s", failed < 0 ? "--quality" : "--set", err);
    return run_hmd_load(&o->hmd, &o->quality);
}

void fv_tool_image_frame_input(const fv_tool_image *o, const fv_scene *scene, const fv_head *head, uint64_t frame_id,
                               double time_s, fv_frame_input *out)
{
    const fv_head *h = head ? head : &scene->head;
    fv_vec3 bmin, bmax;
    float near_m = 0, far_m = 0;
    if (fv_scene_world_bounds(scene, 0.0, &bmin, &bmax)) fv_frame_near_far_from_bounds(h, bmin, bmax, &near_m, &far_m);
    fv_frame_input_from_head(h, near_m, far_m, o->run.eye_w, o->run.eye_h, frame_id, time_s, out);
    run_hmd_views(&o->hmd, out);
    out->quality = o->quality;
}

/* The lens an image was made with: a built-in profile (or a byte-identical copy of one) by its name, a file by its
 * path. */
static const char *lens_label(const run_hmd *h, const fv_app_run *r)
{
    if (h->have && !strncmp(h->profile.origin, "builtin:", 8)) return h->profile.name;
    return r->hmd ? r->hmd : "generic";
}

fv_tool_image_meta fv_tool_image_meta_of(const fv_tool_image *o, const char *producer, bool sbs_file)
{
    bool lens = o->quality.distort.lens.valid && o->quality.distort.enabled;
    const fv_app_run *r = &o->run;
    return (fv_tool_image_meta){.producer = producer, .scene = r->scene, .eye_w = r->eye_w, .eye_h = r->eye_h,
                                .sbs = sbs_file, .view = fv_debug_view_name(r->view), .exposure = r->exposure,
                                .lens = !o->quality.distort.lens.valid ? "none" : lens_label(&o->hmd, r),
                                .lens_applied_png = lens, .quality = fv_app_quality_choice_preset(&r->quality)};
}

/* The settings file of an image: its path with the extension replaced by .json; false when it does not fit. */
static bool meta_path(const char *image_path, char *path, size_t size)
{
    size_t n = strlen(image_path);
    const char *dot = strrchr(image_path, '.');
    if (dot && strchr(dot, '/') == NULL) n = (size_t)(dot - image_path);
    if (n + 6 > size) return false;
    snprintf(path, size, "%.*s.json", (int)n, image_path);
    return true;
}

int fv_tool_image_write_meta(const char *image_path, const fv_tool_image_meta *m)
{
    char path[4096];
    if (!meta_path(image_path, path, sizeof path)) {
        FV_WARN("image", "%s: path too long for its settings file", image_path);
        return -1;
    }
    cJSON *j = cJSON_CreateObject();
    fv_cli_json_add_string(j, "producer", m->producer);
    fv_cli_json_add_string(j, "scene", m->scene);
    cJSON_AddNumberToObject(j, "eye_width", m->eye_w);
    cJSON_AddNumberToObject(j, "eye_height", m->eye_h);
    fv_cli_json_add_string(j, "layout", m->sbs ? "sbs" : "eye");
    fv_cli_json_add_string(j, "view", m->view);
    cJSON_AddNumberToObject(j, "exposure", m->exposure);
    fv_cli_json_add_string(j, "lens", m->lens);
    fv_cli_json_add_string(j, "png", m->lens_applied_png ? "panel (through the lens)" : "undistorted");
    fv_cli_json_add_string(j, "pfm", "undistorted linear");
    fv_cli_json_add_string(j, "quality", m->quality);
    char *text = fv_cli_json_text(j, true);
    cJSON_Delete(j);
    FILE *f = text ? fopen(path, "w") : NULL;
    int ok = f && fputs(text, f) >= 0 && fputc('\n', f) != EOF;
    if (f && fclose(f) != 0) ok = 0;
    free(text);
    if (!ok) {
        FV_WARN("image", "%s: cannot write the image's settings (%s)", path, strerror(errno));
        return -1;
    }
    return 0;
}

bool fv_tool_image_radiance_view(fv_debug_view v)
{
    return v == FV_DEBUG_VIEW_NONE || v == FV_DEBUG_VIEW_DIRECT || v == FV_DEBUG_VIEW_GI || v == FV_DEBUG_VIEW_SSS;
}

static double srgb_encode(double c)
{
    c = fmin(fmax(c, 0.0), 1.0);
    return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

static double srgb_decode(double e) { return e <= 0.04045 ? e / 12.92 : pow((e + 0.055) / 1.055, 2.4); }

uint8_t fv_tool_image_srgb8(float linear, float exposure, bool tone)
{
    if (!(isfinite(exposure) && exposure > 0.0f)) exposure = 1.0f;
    float x = fv_tone_sanitize(linear * exposure);
    double c = tone ? fv_tone_reinhard_ext(x) : x;
    return (uint8_t)(srgb_encode(c) * 255.0 + 0.5);
}

/* Bilinear lookup of channel ch of an sRGB 8-bit image at texture coordinates (s, t) in [0,1], in linear light,
 * clamp to edge (a sampler with linear filtering over an sRGB format). */
static double bilinear_linear(const uint8_t *img, uint32_t w, uint32_t h, double s, double t, int ch)
{
    double x = s * w - 0.5, y = t * h - 0.5;
    double x0f = floor(x), y0f = floor(y), fx = x - x0f, fy = y - y0f;
    long x0 = (long)x0f, y0 = (long)y0f;
    double acc = 0.0;
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
            long xi = x0 + i, yj = y0 + j;
            xi = xi < 0 ? 0 : xi >= (long)w ? (long)w - 1 : xi;
            yj = yj < 0 ? 0 : yj >= (long)h ? (long)h - 1 : yj;
            double wgt = (i ? fx : 1.0 - fx) * (j ? fy : 1.0 - fy);
            acc += wgt * srgb_decode(img[((size_t)yj * w + (size_t)xi) * 3 + (size_t)ch] / 255.0);
        }
    return acc;
}

/* A frustum extent the pass can divide by (distort.c's tan_or_1). */
static double extent_or_1(double t) { return isfinite(t) && t > 1e-6 && t < 1e6 ? t : 1.0; }

void fv_tool_image_lens_srgb8(const fv_frame_input *in, int eye, const uint8_t *src, uint32_t w, uint32_t h,
                              uint8_t *out)
{
    const fv_lens *l = &in->quality.distort.lens;
    if (!l->valid || !in->quality.distort.enabled) {
        memcpy(out, src, (size_t)w * h * 3);
        return;
    }
    eye = eye ? 1 : 0;
    const fv_eye_view *v = &in->eye[eye];
    double fl = extent_or_1(-v->tan_left), fr = extent_or_1(v->tan_right), fu = extent_or_1(v->tan_up),
           fd = extent_or_1(-v->tan_down);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            double u = (x + 0.5) / w, vv = (y + 0.5) / h;
            double qx = u * l->viewport_m[0] - l->centre_m[eye][0], qy = vv * l->viewport_m[1] - l->centre_m[eye][1];
            double r = sqrt(qx * qx + qy * qy) / l->warp_m;
            uint8_t *o = &out[((size_t)y * w + x) * 3];
            o[0] = o[1] = o[2] = 0;
            if (l->visible_r > 0 && r > l->visible_r) continue;
            for (int ch = 0; ch < 3; ch++) {
                double tx, ty; /* the ray this channel shows, tangents x right, y up */
                fv_lens_panel_to_tan(l, eye, ch, u, vv, &tx, &ty);
                double s = (tx + fl) / (fl + fr), t = (fu - ty) / (fu + fd);
                if (s >= 0.0 && s <= 1.0 && t >= 0.0 && t <= 1.0)
                    o[ch] = (uint8_t)(srgb_encode(bilinear_linear(src, w, h, s, t, ch)) * 255.0 + 0.5);
            }
        }
}

/* Twice the signed area of (a, b, p). */
static double edge(const float *a, const float *b, double px, double py)
{
    return ((double)b[0] - a[0]) * (py - a[1]) - ((double)b[1] - a[1]) * (px - a[0]);
}

void fv_tool_image_mask_linear(const fv_frame_input *in, int eye, float *rgb, uint32_t w, uint32_t h)
{
    const fv_quality *q = &in->quality;
    if (!(q->distort.enabled && q->distort.mask && q->distort.lens.valid) || !w || !h) return;
    eye = eye ? 1 : 0;
    const fv_eye_view *v = &in->eye[eye];
    fv_hmd_fov fov = {-v->tan_left, v->tan_right, v->tan_up, -v->tan_down};
    if (!(isfinite(fov.tan_left) && isfinite(fov.tan_right) && isfinite(fov.tan_up) && isfinite(fov.tan_down) &&
          fov.tan_left > 0 && fov.tan_right > 0 && fov.tan_up > 0 && fov.tan_down > 0))
        return; /* the renderer masks nothing then either */
    double margin = fv_lens_mask_margin(&fov, w, h);
    uint32_t n = fv_lens_hidden_mesh(&q->distort.lens, eye, &fov, FV_LENS_MASK_SEGMENTS, margin, 0.0f, NULL, 0);
    float *xyz = n ? malloc((size_t)n * 3 * sizeof *xyz) : NULL;
    if (!xyz) return;
    n = fv_lens_hidden_mesh(&q->distort.lens, eye, &fov, FV_LENS_MASK_SEGMENTS, margin, 0.0f, xyz, n);
    for (uint32_t t = 0; t + 3 <= n; t += 3) {
        const float *a = &xyz[3 * t], *b = &xyz[3 * (t + 1)], *c = &xyz[3 * (t + 2)];
        /* the triangle's pixel box: NDC x = 2 (px + 0.5) / w - 1, y likewise (y down) */
        double lo_x = fmin(a[0], fmin(b[0], c[0])), hi_x = fmax(a[0], fmax(b[0], c[0]));
        double lo_y = fmin(a[1], fmin(b[1], c[1])), hi_y = fmax(a[1], fmax(b[1], c[1]));
        long x0 = (long)floor((lo_x + 1.0) * 0.5 * w - 0.5), x1 = (long)ceil((hi_x + 1.0) * 0.5 * w - 0.5);
        long y0 = (long)floor((lo_y + 1.0) * 0.5 * h - 0.5), y1 = (long)ceil((hi_y + 1.0) * 0.5 * h - 0.5);
        x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
        x1 = x1 >= (long)w ? (long)w - 1 : x1, y1 = y1 >= (long)h ? (long)h - 1 : y1;
        double area = edge(a, b, c[0], c[1]);
        if (area == 0.0) continue;
        for (long y = y0; y <= y1; y++)
            for (long x = x0; x <= x1; x++) {
                double px = 2.0 * (x + 0.5) / w - 1.0, py = 2.0 * (y + 0.5) / h - 1.0;
                double e0 = edge(a, b, px, py), e1 = edge(b, c, px, py), e2 = edge(c, a, px, py);
                bool inside = area > 0 ? (e0 >= 0 && e1 >= 0 && e2 >= 0) : (e0 <= 0 && e1 <= 0 && e2 <= 0);
                if (inside) rgb[((size_t)y * w + (size_t)x) * 3] = rgb[((size_t)y * w + (size_t)x) * 3 + 1] =
                                rgb[((size_t)y * w + (size_t)x) * 3 + 2] = 0.0f;
            }
    }
    free(xyz);
}

/* The settings beside an image, or NULL (no file, unreadable, not JSON). */
static cJSON *read_meta(const char *image_path)
{
    char path[4096];
    if (!meta_path(image_path, path, sizeof path)) return NULL;
    char *text = fv_cli_read_file("compare", path, 1 << 16, NULL);
    cJSON *j = text ? cJSON_Parse(text) : NULL;
    free(text);
    return j;
}

static bool is_png(const char *path)
{
    size_t n = strlen(path);
    return n >= 4 && (strcmp(path + n - 4, ".png") == 0 || strcmp(path + n - 4, ".PNG") == 0);
}

int fv_tool_image_comparable(const char *a, const char *b, char *why, size_t why_size, char *note, size_t note_size)
{
    if (why_size) why[0] = '\0';
    if (note_size) note[0] = '\0';
    char pa[4096], pb[4096];
    bool have_a = meta_path(a, pa, sizeof pa) && access(pa, F_OK) == 0;
    bool have_b = meta_path(b, pb, sizeof pb) && access(pb, F_OK) == 0;
    if (!have_a || !have_b) {
        if (have_a != have_b)
            snprintf(note, note_size, "%s has no settings file beside it: the two images' settings are not checked",
                     have_a ? b : a);
        return 1;
    }
    cJSON *ja = read_meta(a), *jb = read_meta(b);
    int ok = 1;
    if (!ja || !jb) {
        snprintf(why, why_size, "the settings beside %s cannot be read", !ja ? a : b);
        ok = 0;
    }
    static const char *const keys[] = {"eye_width", "eye_height", "layout", "view", "lens", "exposure", "png"};
    for (size_t i = 0; ok && i < sizeof keys / sizeof keys[0]; i++) {
        bool png_only = !strcmp(keys[i], "exposure") || !strcmp(keys[i], "png");
        if (png_only && !is_png(a)) continue; /* the PFMs hold the linear image before exposure and lens */
        const cJSON *x = cJSON_GetObjectItemCaseSensitive(ja, keys[i]), *y = cJSON_GetObjectItemCaseSensitive(jb, keys[i]);
        if (x && y && cJSON_Compare(x, y, true)) continue;
        char *sx = x ? fv_cli_json_text(x, false) : NULL, *sy = y ? fv_cli_json_text(y, false) : NULL;
        snprintf(why, why_size, "the images were made with different %s (%s: %s, %s: %s)", keys[i], a,
                 sx ? sx : "(none)", b, sy ? sy : "(none)");
        free(sx);
        free(sy);
        ok = 0;
    }
    cJSON_Delete(ja);
    cJSON_Delete(jb);
    return ok;
}
