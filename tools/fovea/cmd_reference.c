/* @brief `fovea reference`: render a scene's two eyes on the CPU with the reference renderer (render/reference:
 * model mode = fovea's shading with exact shadows, path mode = path-traced ground truth) from exactly the stereo
 * views `fovea run` draws, and write linear PFM + sRGB PNG images and a summary (text or JSON). Optional cache of
 * finished images keyed by the scene's content and every setting. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stb_image_write.h>

#include "cli.h"
#include "cli_interrupt.h"
#include "cli_progress.h"
#include "tool_image.h"
#include "fv_knobs.h"
#include "fv_clock.h"
#include "fv_image_io.h"
#include "fv_log.h"
#include "fv_reference.h"
#include "fv_renderer.h"
#include "fv_scene.h"

#define MOD "reference"

static const char *USAGE_FMT =
    "usage: fovea reference [--scene NAME|FILE] [--quality PRESET] [--set NAME=VALUE]... [--view NAME]\n"
    "                       [--exposure X] [--hmd PROFILE|FILE|none] [--eye-size WxH] [--layout sbs|eyes]\n"
    "                       [--mode model|path] [--spp N] [--bounces N] [--seed N] [--out DIR] [--aa]\n"
    "                       [--threads N] [--time S] [--cache DIR] [--json]\n"
    "  The image `fovea run` draws with the same options, rendered on the CPU in double with exact visibility:\n"
    "  the scene, view, quality, exposure, HMD (frusta and lens) and size options are parsed by the same code as\n"
    "  run's, and every term of the GPU's model at those settings is rendered (direct light, emission, ambient,\n"
    "  the exact one-bounce VPL sum when gi.enabled, the exact dipole sum when sss.enabled).\n"
    "%s%s"
    "  --mode      model: fovea's shading formulas per pixel centre with exact shadow rays (default);\n"
    "              path: path-traced ground truth (area lights from emissive surfaces, bounces)\n"
    "  --spp       samples per pixel (default 1 for model, 64 for path; 1..1048576); model mode only uses more\n"
    "              than one with --aa\n"
    "  --bounces   path mode: indirect bounces (0 = direct light only; default 8; 0..1024)\n"
    "  --seed      random seed (default 1); the images are identical for any --threads\n"
    "  --view      the reference renders color, direct, shadow, albedo, normal, depth, gi and sss (gi and sss:\n"
    "              model mode)\n"
    "  --out       write frame_00000.pfm (linear float, undistorted, before exposure) and frame_00000.png (as\n"
    "              `fovea run` writes it: exposure, tone curve, sRGB and, with an HMD lens, through the lens),\n"
    "              and frame_00000.json (the settings, read by `fovea compare`) into DIR\n"
    "  --aa        jitter the samples inside each pixel (default: pixel centres, as the GPU's G-buffer)\n"
    "  --threads   worker threads (default: every CPU)\n"
    "  --time      scene time in seconds for animations (default 0, the first frame of fovea run)\n"
    "  --cache     reuse an earlier result for the same scene content and settings from DIR (created if missing)\n"
    "  --json      print the summary as one JSON object on stdout (and nothing else there)\n";

static const char *usage_text(void)
{
    static char text[8192];
    if (!text[0]) snprintf(text, sizeof text, USAGE_FMT, FV_TOOL_IMAGE_USAGE, RUN_HMD_USAGE);
    return text;
}
#define USAGE usage_text()

typedef struct ref_opts {
    fv_tool_image img; /* what the image shows: parsed as `fovea run` parses it (tool_image.h) */
    fv_reference_desc desc;
    bool spp_set, json;
    double time_s;
    const char *out_dir, *cache_dir;
} ref_opts;

static int parse_args(int argc, char **argv, ref_opts *o)
{
    *o = (ref_opts){.json = false};
    fv_tool_image_defaults(&o->img);
    o->desc = (fv_reference_desc){.mode = FV_REFERENCE_MODEL, .view = FV_REFERENCE_VIEW_COLOR, .bounces = 8,
                                  .seed = 1};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = NULL;
        int r;
        int64_t n;
        if (fv_cli_is_help(a)) {
            fputs(USAGE, stdout);
            return -1;
        }
#define OPT(name) FV_CLI_OPT("reference", USAGE, name)
#define NUMBER(name, lo, hi)                                                                                           \
    if (!fv_cli_parse_i64(v, lo, hi, &n))                                                                              \
        return fv_cli_usage_error("reference", USAGE, "%s: '%s' is not a whole number in %lld..%lld", name, v,      \
                                  (long long)(lo), (long long)(hi));
        if ((r = OPT("--mode")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_reference_mode_parse(v, &o->desc.mode))
                return fv_cli_usage_error("reference", USAGE, "--mode: '%s' is not one of model, path", v);
            continue;
        }
        if ((r = OPT("--spp")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            NUMBER("--spp", 1, FV_REFERENCE_MAX_SPP);
            o->desc.spp = (uint32_t)n;
            o->spp_set = true;
            continue;
        }
        if ((r = OPT("--bounces")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            NUMBER("--bounces", 0, FV_REFERENCE_MAX_BOUNCES);
            o->desc.bounces = (uint32_t)n;
            continue;
        }
        if ((r = OPT("--seed")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            NUMBER("--seed", 0, INT64_MAX);
            o->desc.seed = (uint64_t)n;
            continue;
        }
        if ((r = OPT("--threads")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            NUMBER("--threads", 1, 1024);
            o->desc.threads = (uint32_t)n;
            continue;
        }
        if ((r = OPT("--time")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_cli_parse_f64(v, 0, 1e6, &o->time_s))
                return fv_cli_usage_error("reference", USAGE, "--time: '%s' is not a number in 0..1e6", v);
            continue;
        }
        if ((r = OPT("--out")) == -2) return FV_EXIT_USAGE;
        else if (r) { o->out_dir = v; continue; }
        if ((r = OPT("--cache")) == -2) return FV_EXIT_USAGE;
        else if (r) { o->cache_dir = v; continue; }
#undef NUMBER
#undef OPT
        if ((r = fv_tool_image_option(&o->img, argc, argv, &i, "reference", USAGE)) == FV_EXIT_USAGE) return r;
        else if (r) continue;
        if (strcmp(a, "--aa") == 0) { o->desc.aa = true; continue; }
        if (strcmp(a, "--json") == 0) { o->json = true; continue; }
        return fv_cli_usage_error("reference", USAGE, "unknown option '%s'", a);
    }
    if (!o->spp_set) o->desc.spp = o->desc.mode == FV_REFERENCE_PATH ? 64 : 1;
    if (o->img.run.budget || o->img.run.budget_scale > 0)
        return fv_cli_usage_error("reference", USAGE, "--budget and --budget-scale pace `fovea run`'s frames; the "
                                  "reference renders one image (drop them)");
    int built = fv_tool_image_finish(&o->img, "reference", USAGE);
    if (built != 0) return built;
    const char *view = fv_debug_view_name(o->img.run.view);
    if (!fv_reference_view_parse(view, &o->desc.view))
        return fv_cli_usage_error("reference", USAGE, "--view %s: the reference has no such view (it renders color, "
                                  "direct, shadow, albedo, normal, depth, gi, sss)", view);
    if (o->desc.mode == FV_REFERENCE_PATH && (o->desc.view == FV_REFERENCE_VIEW_GI || o->desc.view == FV_REFERENCE_VIEW_SSS))
        return fv_cli_usage_error("reference", USAGE, "--view %s is a term of the model: it needs --mode model", view);
    o->desc.eye_width = o->img.run.eye_w;
    o->desc.eye_height = o->img.run.eye_h;
    o->desc.gi = o->img.quality.gi.enabled; /* the GPU's model at these settings: GI when it is on */
    return 0;
}

/* ---- progress (cli_progress.h: at a terminal after 2 s, or FOVEA_PROGRESS) ---------------------------------- */

static void on_progress(void *user, uint64_t done, uint64_t total)
{
    fv_progress_set_total(user, (int64_t)total);
    fv_progress_update(user, -1, (int64_t)done, -1.0); /* the CPU's work: no GPU time */
}

/* ---- the cache key: the scene's content and every setting (FNV-1a, 64 bit) ----------------------------------- */

typedef struct hasher { uint64_t h; } hasher;

static void hash_bytes(hasher *k, const void *data, size_t n)
{
    const uint8_t *p = data;
    for (size_t i = 0; i < n; i++) k->h = (k->h ^ p[i]) * 0x100000001b3ull;
}
#define HASH(k, v) hash_bytes((k), &(v), sizeof(v))

static uint64_t cache_key(const fv_scene *s, const ref_opts *o, const fv_frame_input *in)
{
    hasher k = {0xcbf29ce484222325ull};
    static const char version[] = "fovea-reference-cache 2";
    hash_bytes(&k, version, sizeof version);
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        const fv_mesh *m = &s->meshes[i];
        HASH(&k, m->vertex_count);
        HASH(&k, m->index_count);
        HASH(&k, m->material);
        if (m->positions) hash_bytes(&k, m->positions, m->vertex_count * sizeof *m->positions);
        if (m->normals) hash_bytes(&k, m->normals, m->vertex_count * sizeof *m->normals);
        if (m->texcoords) hash_bytes(&k, m->texcoords, m->vertex_count * sizeof *m->texcoords);
        if (m->indices) hash_bytes(&k, m->indices, m->index_count * sizeof *m->indices);
    }
    for (uint32_t i = 0; i < s->node_count; i++) {
        const fv_node *n = &s->nodes[i];
        HASH(&k, n->mesh), HASH(&k, n->parent), HASH(&k, n->translation_m), HASH(&k, n->rotation);
        HASH(&k, n->scale), HASH(&k, n->anim);
    }
    for (uint32_t i = 0; i < s->material_count; i++) {
        HASH(&k, s->materials[i].base_color), HASH(&k, s->materials[i].base_color_texture);
        HASH(&k, s->materials[i].emissive);
    }
    for (uint32_t i = 0; i < s->texture_count; i++) {
        const fv_texture *t = &s->textures[i];
        HASH(&k, t->width), HASH(&k, t->height);
        if (t->rgba8) hash_bytes(&k, t->rgba8, (size_t)t->width * t->height * 4);
    }
    for (uint32_t i = 0; i < s->light_count; i++) {
        const fv_light *l = &s->lights[i];
        HASH(&k, l->type), HASH(&k, l->position_m), HASH(&k, l->direction), HASH(&k, l->color);
        HASH(&k, l->intensity), HASH(&k, l->range_m), HASH(&k, l->inner_cone_rad), HASH(&k, l->outer_cone_rad);
    }
    HASH(&k, s->head.position_m), HASH(&k, s->head.orientation), HASH(&k, s->head.ipd_mm), HASH(&k, s->ambient);
    const fv_reference_desc *d = &o->desc;
    HASH(&k, d->mode), HASH(&k, d->view), HASH(&k, d->spp), HASH(&k, d->bounces), HASH(&k, d->seed);
    HASH(&k, d->eye_width), HASH(&k, d->eye_height), HASH(&k, d->aa), HASH(&k, d->shadow_light), HASH(&k, o->time_s);
    HASH(&k, d->gi);
    size_t nk = 0; /* every knob's value (GI and SSS settings change the image) */
    const fv_knob *knobs = fv_knobs(&nk);
    for (size_t i = 0; i < nk; i++) {
        fv_knob_value v = fv_knob_get(&knobs[i], &in->quality);
        if (knobs[i].type == FV_KNOB_BOOL) HASH(&k, v.b);
        else if (knobs[i].type == FV_KNOB_FLOAT) HASH(&k, v.f);
        else HASH(&k, v.i);
    }
    for (int e = 0; e < 2; e++) /* the views: the HMD's frusta */
        HASH(&k, in->eye[e].tan_left), HASH(&k, in->eye[e].tan_right), HASH(&k, in->eye[e].tan_up),
            HASH(&k, in->eye[e].tan_down), HASH(&k, in->eye[e].pos_world), HASH(&k, in->eye[e].view);
    return k.h;
}

/* ---- images -------------------------------------------------------------------------------------------------- */

/* Write one image: base.pfm (linear, w x h, undistorted), base.png (png: the display values, already through the
 * lens) and base.json (the settings). */
static fv_result write_image(const ref_opts *o, const char *base, const float *rgb, const uint8_t *png, uint32_t w,
                             uint32_t h, bool sbs)
{
    char path[1200];
    fv_rgb_image img = {.width = w, .height = h, .kind = FV_IMAGE_KIND_LINEAR, .file_channels = 3,
                        .rgb = (float *)rgb};
    snprintf(path, sizeof path, "%s.pfm", base);
    FV_TRY(fv_image_io_write_pfm(path, &img));
    snprintf(path, sizeof path, "%s.png", base);
    if (!stbi_write_png(path, (int)w, (int)h, 3, png, (int)(w * 3))) {
        FV_ERROR(MOD, "%s: cannot write PNG", path);
        return FV_ERR_IO;
    }
    fv_tool_image_meta m = fv_tool_image_meta_of(&o->img, "fovea reference", sbs);
    (void)fv_tool_image_write_meta(path, &m);
    return FV_OK;
}

/* The two eyes as `fovea run` writes its frame (present pass: exposure, tone curve, sRGB; distort pass: the lens),
 * side by side or one file each. */
static fv_result write_frame(const ref_opts *o, const fv_frame_input *in, const float *eye_rgb[2], const float *sbs,
                             uint32_t w, uint32_t h)
{
    size_t n = (size_t)w * h * 3;
    uint8_t *disp = malloc(n), *panel = malloc(2 * n), *both = malloc(2 * n);
    fv_result res = disp && panel && both ? FV_OK : FV_ERR_NO_MEMORY;
    bool tone = fv_tool_image_radiance_view(o->img.run.view);
    for (int e = 0; res == FV_OK && e < 2; e++) {
        for (size_t i = 0; i < n; i++) disp[i] = fv_tool_image_srgb8(eye_rgb[e][i], o->img.run.exposure, tone);
        fv_tool_image_lens_srgb8(in, e, disp, w, h, panel + (size_t)e * n);
    }
    char base[1100];
    if (res == FV_OK && o->img.run.sbs) {
        for (uint32_t y = 0; y < h; y++)
            for (int e = 0; e < 2; e++)
                memcpy(&both[((size_t)y * 2 * w + (size_t)e * w) * 3], &panel[(size_t)e * n + (size_t)y * w * 3], (size_t)w * 3);
        snprintf(base, sizeof base, "%s/frame_00000", o->out_dir);
        res = write_image(o, base, sbs, both, 2 * w, h, true);
    } else {
        for (int e = 0; res == FV_OK && e < 2; e++) {
            snprintf(base, sizeof base, "%s/frame_00000_%s", o->out_dir, e ? "right" : "left");
            res = write_image(o, base, eye_rgb[e], panel + (size_t)e * n, w, h, false);
        }
    }
    free(disp);
    free(panel);
    free(both);
    return res;
}

/* Both eyes side by side (2W x H) from the two eye images. */
static void join_sbs(const float *left, const float *right, uint32_t w, uint32_t h, float *out)
{
    for (uint32_t y = 0; y < h; y++) {
        memcpy(&out[((size_t)y * 2 * w) * 3], &left[(size_t)y * w * 3], (size_t)w * 3 * sizeof *out);
        memcpy(&out[((size_t)y * 2 * w + w) * 3], &right[(size_t)y * w * 3], (size_t)w * 3 * sizeof *out);
    }
}

static void split_sbs(const float *sbs, uint32_t w, uint32_t h, float *left, float *right)
{
    for (uint32_t y = 0; y < h; y++) {
        memcpy(&left[(size_t)y * w * 3], &sbs[((size_t)y * 2 * w) * 3], (size_t)w * 3 * sizeof *left);
        memcpy(&right[(size_t)y * w * 3], &sbs[((size_t)y * 2 * w + w) * 3], (size_t)w * 3 * sizeof *right);
    }
}

/* A cached result for this key: true when it was read and has the right size. */
static bool cache_load(const char *path, uint32_t w, uint32_t h, float *left, float *right)
{
    if (access(path, R_OK) != 0) return false;
    fv_rgb_image img;
    memset(&img, 0, sizeof img);
    if (FV_FAILED(fv_image_io_read(path, &img))) return false;
    bool ok = img.kind == FV_IMAGE_KIND_LINEAR && img.width == 2 * w && img.height == h;
    if (ok) split_sbs(img.rgb, w, h, left, right);
    else FV_WARN(MOD, "%s: cached image is %ux%u, not %ux%u; rendering again", path, img.width, img.height, 2 * w, h);
    fv_rgb_image_fini(&img);
    return ok;
}

int fv_cmd_reference(int argc, char **argv)
{
    ref_opts o;
    int pr = parse_args(argc, argv, &o);
    if (pr == -1) return FV_EXIT_OK;
    if (pr != 0) return pr;

    int exit_code = FV_EXIT_FAIL;
    fv_scene *scene = NULL;
    uint32_t w = o.desc.eye_width, h = o.desc.eye_height;
    size_t eye_floats = (size_t)w * h * 3;
    float *left = malloc(eye_floats * sizeof *left), *right = malloc(eye_floats * sizeof *right);
    float *sbs = malloc(2 * eye_floats * sizeof *sbs);
    char cache_path[1200] = "";
    bool cached = false;
    if (!left || !right || !sbs) {
        FV_ERROR(MOD, "out of memory for %ux%u per eye", w, h);
        goto done;
    }
    if (o.out_dir && !fv_cli_output_dir("reference", "--out", o.out_dir)) goto done;
    if (o.cache_dir && !fv_cli_output_dir("reference", "--cache", o.cache_dir)) goto done;
    if (FV_FAILED(fv_scene_load(o.img.run.scene, &scene))) {
        fprintf(stderr, "fovea reference: cannot load scene '%s' (see the messages above)\n", o.img.run.scene);
        goto done;
    }

    /* The views of `fovea run`'s frame 0, built by the same code (tool_image.c): near/far from the bounds at load
     * time, the scene's head, the HMD's frusta when one is named, gaze ahead, the quality of the options. */
    fv_frame_input in;
    fv_tool_image_frame_input(&o.img, scene, NULL, 0, o.time_s, &in);

    if (o.cache_dir) {
        snprintf(cache_path, sizeof cache_path, "%s/reference_%016llx.pfm", o.cache_dir,
                 (unsigned long long)cache_key(scene, &o, &in));
        cached = cache_load(cache_path, w, h, left, right);
    }
    fv_progress *prog = cached ? NULL : fv_progress_start("fovea reference", "tile", 0);
    if (prog) {
        o.desc.progress = on_progress;
        o.desc.progress_user = prog;
    }
    fv_reference_stats st;
    memset(&st, 0, sizeof st);
    int64_t t0 = fv_time_monotonic_ns();
    o.desc.cancelled = fv_cli_interrupted; /* Ctrl-C (cli_interrupt.h) stops the workers between tiles */
    if (!cached) {
        fv_result res = fv_reference_render(scene, &in, &o.desc, left, right, &st);
        fv_progress_stop(&prog);
        if (res == FV_ERR_CANCELLED) {
            printf("fovea reference: interrupted (Ctrl-C) after %.2f s and %.3g rays; no image written\n",
                   (double)(fv_time_monotonic_ns() - t0) / 1e9, (double)st.rays);
            exit_code = FV_EXIT_INTERRUPTED;
            goto done;
        }
        if (FV_FAILED(res)) {
            fprintf(stderr, "fovea reference: rendering failed: %s\n", fv_result_str(res));
            goto done;
        }
    }
    double seconds = (double)(fv_time_monotonic_ns() - t0) / 1e9;
    if (!cached) { /* the pixels the GPU never shades (hidden-area mask), before the cache holds them */
        fv_tool_image_mask_linear(&in, 0, left, w, h);
        fv_tool_image_mask_linear(&in, 1, right, w, h);
    }
    join_sbs(left, right, w, h, sbs);
    if (o.cache_dir && !cached) {
        fv_rgb_image img = {.width = 2 * w, .height = h, .kind = FV_IMAGE_KIND_LINEAR, .file_channels = 3, .rgb = sbs};
        if (FV_FAILED(fv_image_io_write_pfm(cache_path, &img))) FV_WARN(MOD, "%s: could not cache the result", cache_path);
    }
    if (o.out_dir) {
        const float *eye_rgb[2] = {left, right};
        if (FV_FAILED(write_frame(&o, &in, eye_rgb, sbs, w, h))) goto done;
    }
    const char *name = scene->name[0] ? scene->name : o.img.run.scene;
    if (o.json) {
        cJSON *j = cJSON_CreateObject();
        fv_cli_json_add_string(j, "scene", name);
        fv_cli_json_add_string(j, "source", scene->source);
        fv_cli_json_add_string(j, "mode", fv_reference_mode_name(o.desc.mode));
        fv_cli_json_add_string(j, "view", fv_reference_view_name(o.desc.view));
        cJSON_AddNumberToObject(j, "spp", o.desc.spp);
        cJSON_AddNumberToObject(j, "bounces", o.desc.bounces);
        cJSON_AddNumberToObject(j, "seed", (double)o.desc.seed);
        cJSON_AddBoolToObject(j, "aa", o.desc.aa);
        cJSON_AddNumberToObject(j, "eye_width", w);
        cJSON_AddNumberToObject(j, "eye_height", h);
        cJSON_AddNumberToObject(j, "time_s", o.time_s);
        cJSON_AddNumberToObject(j, "seconds", seconds);
        cJSON_AddBoolToObject(j, "cached", cached);
        cJSON_AddNumberToObject(j, "threads", st.threads);
        cJSON_AddNumberToObject(j, "rays", (double)st.rays);
        cJSON_AddNumberToObject(j, "primary_rays", (double)st.primary_rays);
        cJSON_AddNumberToObject(j, "shadow_rays", (double)st.shadow_rays);
        cJSON_AddNumberToObject(j, "bounce_rays", (double)st.bounce_rays);
        cJSON_AddNumberToObject(j, "samples", (double)st.samples);
        cJSON_AddNumberToObject(j, "nonfinite_samples", (double)st.nonfinite_samples);
        cJSON_AddNumberToObject(j, "triangles", st.triangles);
        cJSON_AddNumberToObject(j, "skipped_triangles", st.skipped_triangles);
        cJSON_AddNumberToObject(j, "emissive_triangles", st.emissive_triangles);
        cJSON_AddNumberToObject(j, "lights", scene->light_count);
        if (o.out_dir) fv_cli_json_add_string(j, "out", o.out_dir);
        if (o.cache_dir) fv_cli_json_add_string(j, "cache_file", cache_path);
        int printed = fv_cli_json_print(j, false);
        cJSON_Delete(j);
        if (printed != FV_EXIT_OK) goto done;
    } else if (cached) {
        printf("fovea reference: scene '%s', %s mode, %s view, %ux%u per eye: from the cache (%s)\n", name,
               fv_reference_mode_name(o.desc.mode), fv_reference_view_name(o.desc.view), w, h, cache_path);
    } else {
        printf("fovea reference: scene '%s', %s mode, %s view, %u spp", name, fv_reference_mode_name(o.desc.mode),
               fv_reference_view_name(o.desc.view), o.desc.spp);
        if (o.desc.mode == FV_REFERENCE_PATH) printf(", %u bounces", o.desc.bounces);
        printf(", seed %llu, %ux%u per eye, %u threads: %.2f s\n", (unsigned long long)o.desc.seed, w, h, st.threads,
               seconds);
        printf("  rays: %.3g (%.3g primary, %.3g shadow, %.3g bounce), %.2f Mrays/s; %u triangles (%u left out), "
               "%u emissive\n",
               (double)st.rays, (double)st.primary_rays, (double)st.shadow_rays, (double)st.bounce_rays,
               seconds > 0 ? (double)st.rays / seconds / 1e6 : 0.0, st.triangles, st.skipped_triangles,
               st.emissive_triangles);
    }
    if (o.out_dir && !o.json) printf("  images: %s/\n", o.out_dir);
    exit_code = FV_EXIT_OK;
done:
    fv_scene_destroy(&scene);
    free(left);
    free(right);
    free(sbs);
    return exit_code;
}
