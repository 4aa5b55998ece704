/* @brief `fovea run`: load a scene, render N stereo frames (headless), optionally follow a gaze device, save PNGs,
 * and print one summary (per-pass GPU time median/p95, CPU time per frame, memory) as text or JSON. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <stb_image_write.h>

#include "cli.h"
#include "fv_clock.h"
#include "fv_log.h"
#include "fv_renderer.h"
#include "fv_scene.h"
#include "run_gaze.h"

static const char *USAGE =
    "usage: fovea run [--scene NAME|FILE] [--frames N] [--eye-size WxH] [--out DIR]\n"
    "                 [--save last|every|none] [--layout sbs|eyes] [--gaze URI [--hz HZ]] [--explain] [--json]\n"
    "  --scene     built-in scene name (cornell, cornell-translucent) or a file: *.scene.json, .gltf/.glb, .obj, .ply\n"
    "              (default cornell)\n"
    "  --frames    frames to render (default 1; 1..1000000)\n"
    "  --eye-size  per-eye render size (default 720x800)\n"
    "  --out       write PNGs into DIR (created if missing); without it images stay on the GPU\n"
    "  --save      which frames to write with --out (default last)\n"
    "  --layout    sbs: one side-by-side stereo image per frame (default); eyes: one image per eye\n"
    "  --gaze      follow an eye tracker or recording (hid:auto, trace:FILE, sim:seed=1); frames then run through\n"
    "              the frame loop, paced by a display, with one gaze-to-photon latency record per frame\n"
    "              (default: no tracker, gaze straight ahead, frames as fast as the GPU allows)\n"
    "  --hz        refresh rate of the (simulated) display that paces --gaze runs (default 90; 1..1000)\n"
    "  --explain   print the frame plan (which passes run and why)\n"
    "  --json      print the summary as one JSON object on stdout (and nothing else on stdout)\n";

typedef enum { SAVE_LAST, SAVE_EVERY, SAVE_NONE } save_mode;

typedef struct run_opts {
    const char *scene;
    int64_t frames;
    uint32_t eye_w, eye_h;
    const char *out_dir;
    save_mode save;
    bool sbs;
    const char *gaze_uri;
    double hz;
    bool explain, json;
} run_opts;

static int parse_args(int argc, char **argv, run_opts *o)
{
    *o = (run_opts){.scene = "cornell", .frames = 1, .eye_w = 720, .eye_h = 800, .save = SAVE_LAST, .sbs = true,
                    .hz = 90};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = NULL;
        int r;
        if (fv_cli_is_help(a)) {
            fputs(USAGE, stdout);
            return -1;
        }
#define OPT(name)                                                                                                      \
    ((r = fv_cli_option(argc, argv, &i, name, &v)) < 0                                                                 \
         ? (fv_cli_usage_error("run", USAGE, "option %s needs a value", name), -2)                                     \
         : r)
        if ((r = OPT("--scene")) == -2) return FV_EXIT_USAGE;
        else if (r) { o->scene = v; continue; }
        if ((r = OPT("--frames")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_cli_parse_i64(v, 1, 1000000, &o->frames))
                return fv_cli_usage_error("run", USAGE, "--frames: '%s' is not a whole number in 1..1000000", v);
            continue;
        }
        if ((r = OPT("--eye-size")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_cli_parse_size(v, 8192, &o->eye_w, &o->eye_h))
                return fv_cli_usage_error("run", USAGE, "--eye-size: '%s' is not WxH with each in 1..8192", v);
            continue;
        }
        if ((r = OPT("--out")) == -2) return FV_EXIT_USAGE;
        else if (r) { o->out_dir = v; continue; }
        if ((r = OPT("--save")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (strcmp(v, "last") == 0) o->save = SAVE_LAST;
            else if (strcmp(v, "every") == 0) o->save = SAVE_EVERY;
            else if (strcmp(v, "none") == 0) o->save = SAVE_NONE;
            else return fv_cli_usage_error("run", USAGE, "--save: '%s' is not one of last, every, none", v);
            continue;
        }
        if ((r = OPT("--layout")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (strcmp(v, "sbs") == 0) o->sbs = true;
            else if (strcmp(v, "eyes") == 0) o->sbs = false;
            else return fv_cli_usage_error("run", USAGE, "--layout: '%s' is not one of sbs, eyes", v);
            continue;
        }
        if ((r = OPT("--gaze")) == -2) return FV_EXIT_USAGE;
        else if (r) { o->gaze_uri = v; continue; }
        if ((r = OPT("--hz")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_cli_parse_f64(v, 1, 1000, &o->hz))
                return fv_cli_usage_error("run", USAGE, "--hz: '%s' is not a number in 1..1000", v);
            continue;
        }
#undef OPT
        if (strcmp(a, "--explain") == 0) { o->explain = true; continue; }
        if (strcmp(a, "--json") == 0) { o->json = true; continue; }
        return fv_cli_usage_error("run", USAGE, "unknown option '%s'", a);
    }
    return 0;
}

/* CPU time of the calling thread (recording and submitting; lavapipe's own worker threads and fence waits are
 * not counted), ns. */
static int64_t thread_cpu_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (int64_t)ts.tv_sec * FV_NS_PER_S + ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Percentile by the nearest-rank method on a sorted copy. */
static double percentile(const double *v, size_t n, double p)
{
    if (n == 0) return NAN;
    double *s = malloc(n * sizeof *s);
    if (!s) return NAN;
    memcpy(s, v, n * sizeof *s);
    qsort(s, n, sizeof *s, cmp_double);
    size_t k = (size_t)ceil(p / 100.0 * (double)n);
    if (k < 1) k = 1;
    if (k > n) k = n;
    double r = s[k - 1];
    free(s);
    return r;
}

static int ensure_dir(const char *dir)
{
    if (mkdir(dir, 0755) == 0 || errno == EEXIST) {
        struct stat st;
        if (stat(dir, &st) == 0 && S_ISDIR(st.st_mode)) return 0;
    }
    FV_ERROR("run", "--out %s: cannot create directory (%s)", dir, strerror(errno ? errno : ENOTDIR));
    return -1;
}

static fv_result save_frame(fv_renderer *r, const run_opts *o, uint64_t frame, uint8_t *buf, size_t buf_size)
{
    char path[1200];
    if (o->sbs) {
        FV_TRY(fv_renderer_read_rgba8(r, true, 0, buf, buf_size));
        snprintf(path, sizeof path, "%s/frame_%05llu.png", o->out_dir, (unsigned long long)frame);
        if (!stbi_write_png(path, (int)(2 * o->eye_w), (int)o->eye_h, 4, buf, (int)(2 * o->eye_w * 4))) {
            FV_ERROR("run", "%s: cannot write PNG", path);
            return FV_ERR_IO;
        }
        return FV_OK;
    }
    static const char *names[2] = {"left", "right"};
    for (int eye = 0; eye < 2; eye++) {
        FV_TRY(fv_renderer_read_rgba8(r, false, eye, buf, buf_size));
        snprintf(path, sizeof path, "%s/frame_%05llu_%s.png", o->out_dir, (unsigned long long)frame, names[eye]);
        if (!stbi_write_png(path, (int)o->eye_w, (int)o->eye_h, 4, buf, (int)(o->eye_w * 4))) {
            FV_ERROR("run", "%s: cannot write PNG", path);
            return FV_ERR_IO;
        }
    }
    return FV_OK;
}

static void print_plan(FILE *f, const fv_frame_plan *plan)
{
    fprintf(f, "frame plan:\n");
    for (uint32_t i = 0; i < plan->count; i++)
        fprintf(f, "  %-3s %-12s %s\n", plan->entries[i].enabled ? "on" : "off", plan->entries[i].pass,
                plan->entries[i].reason);
}

typedef struct pass_series {
    char name[24];
    double *ms; /* one per measured frame */
    size_t n;
} pass_series;

/* Everything one run measures. */
typedef struct run_state {
    const run_opts *o;
    fv_renderer *r;
    double *cpu_ms, *frame_gpu_ms;
    size_t drawn;    /* frames drawn */
    size_t measured; /* frames whose GPU timings were taken */
    uint64_t last_timed;
    pass_series passes[FV_MAX_PASSES];
    uint32_t pass_count;
    fv_render_stats last_stats;
} run_state;

/* Record one frame's GPU timings. */
static bool record_stats(run_state *st, const fv_render_stats *rs)
{
    size_t cap = (size_t)st->o->frames;
    if (st->measured >= cap) return true;
    st->frame_gpu_ms[st->measured] = rs->frame_gpu_ms;
    for (uint32_t p = 0; p < rs->pass_count && p < FV_MAX_PASSES; p++) {
        pass_series *ps = &st->passes[p];
        if (!ps->ms) {
            ps->ms = calloc(cap, sizeof *ps->ms);
            if (!ps->ms) return false;
            snprintf(ps->name, sizeof ps->name, "%s", rs->pass_name[p]);
            if (p + 1 > st->pass_count) st->pass_count = p + 1;
        }
        if (ps->n < cap) ps->ms[ps->n++] = rs->pass_gpu_ms[p];
    }
    st->last_stats = *rs;
    st->measured++;
    return true;
}

/* Frames complete in order (frames in flight overlap): take the timings of every frame that completed since the
 * last call, each once. */
static bool take_stats(run_state *st)
{
    fv_render_stats newest, rs;
    if (fv_renderer_stats(st->r, &newest) != FV_OK) return true;
    if (st->last_timed != UINT64_MAX && newest.frame_id <= st->last_timed) return true;
    uint64_t first = st->last_timed == UINT64_MAX ? 0 : st->last_timed + 1;
    if (newest.frame_id - first >= FV_RENDERER_STATS_HISTORY) first = newest.frame_id - FV_RENDERER_STATS_HISTORY + 1;
    for (uint64_t id = first; id <= newest.frame_id; id++)
        if (fv_renderer_frame_stats(st->r, id, &rs) == FV_OK && !record_stats(st, &rs)) return false;
    st->last_timed = newest.frame_id;
    return true;
}

/* Draw one frame: views from the scene's head, gaze as given (the frame loop's prediction) or straight ahead.
 * With times (a frame-loop frame), wait for the GPU so that its end is known on the host clock. */
static fv_result draw_frame(run_state *st, fv_frame_input *in, bool keep_gaze, fv_frame_render_times *times)
{
    fv_frame_input base;
    double time_s = (double)in->frame_id / (st->o->hz > 0 ? st->o->hz : 90.0); /* scene time at the refresh rate */
    FV_TRY(fv_renderer_frame_input(st->r, NULL, in->frame_id, time_s, &base));
    if (keep_gaze) {
        in->eye[0] = base.eye[0];
        in->eye[1] = base.eye[1];
        in->time_s = time_s;
    } else {
        *in = base;
    }
    int64_t c0 = thread_cpu_ns();
    fv_result res = fv_renderer_draw(st->r, in);
    if (st->drawn < (size_t)st->o->frames) st->cpu_ms[st->drawn] = (double)(thread_cpu_ns() - c0) / 1e6;
    st->drawn++;
    if (FV_FAILED(res)) {
        fprintf(stderr, "fovea run: frame %llu failed (see the messages above)\n", (unsigned long long)in->frame_id);
        return res;
    }
    if (times) {
        times->t_submit_ns = fv_time_monotonic_ns();
        FV_TRY(fv_renderer_finish(st->r));
        int64_t t_end = fv_time_monotonic_ns();
        if (!take_stats(st)) return FV_ERR_NO_MEMORY;
        /* The GPU ran this frame's work for frame_gpu_ms before the fence was seen signalled. */
        int64_t gpu_ns = (int64_t)(st->last_stats.frame_gpu_ms * 1e6);
        times->t_gpu_end_ns = t_end;
        times->t_gpu_begin_ns = t_end - gpu_ns > times->t_submit_ns ? t_end - gpu_ns : times->t_submit_ns;
        return FV_OK;
    }
    return take_stats(st) ? FV_OK : FV_ERR_NO_MEMORY;
}

static fv_result render_cb(void *user, fv_frame_input *in, fv_frame_render_times *out_times)
{
    return draw_frame(user, in, true, out_times);
}

int fv_cmd_run(int argc, char **argv)
{
    run_opts o;
    int pr = parse_args(argc, argv, &o);
    if (pr == -1) return FV_EXIT_OK;
    if (pr != 0) return pr;

    int exit_code = FV_EXIT_FAIL;
    fv_scene *scene = NULL;
    fv_renderer *r = NULL;
    uint8_t *img = NULL;
    double *wall_ms = NULL;
    run_state st;
    memset(&st, 0, sizeof st);
    st.o = &o;
    st.last_timed = UINT64_MAX;
    run_gaze gaze;
    memset(&gaze, 0, sizeof gaze);
    bool gaze_open = false;

    if (o.out_dir && o.save != SAVE_NONE && ensure_dir(o.out_dir) != 0) goto done;
    if (FV_FAILED(fv_scene_load(o.scene, &scene))) {
        fprintf(stderr, "fovea run: cannot load scene '%s' (see the messages above)\n", o.scene);
        goto done;
    }
    fv_renderer_desc desc = {.eye_width = o.eye_w, .eye_height = o.eye_h};
    if (FV_FAILED(fv_renderer_create(&desc, &r))) {
        fprintf(stderr, "fovea run: cannot create the renderer (see the messages above)\n");
        goto done;
    }
    st.r = r;
    if (FV_FAILED(fv_renderer_load_scene(r, scene))) {
        fprintf(stderr, "fovea run: cannot upload scene '%s'\n", o.scene);
        goto done;
    }
    if (o.explain) print_plan(o.json ? stderr : stdout, fv_renderer_plan(r));

    size_t img_size = (size_t)o.eye_w * 2 * o.eye_h * 4;
    img = malloc(img_size);
    st.cpu_ms = calloc((size_t)o.frames, sizeof *st.cpu_ms);
    wall_ms = calloc((size_t)o.frames, sizeof *wall_ms);
    st.frame_gpu_ms = calloc((size_t)o.frames, sizeof *st.frame_gpu_ms);
    if (!img || !st.cpu_ms || !wall_ms || !st.frame_gpu_ms) {
        FV_ERROR("run", "out of memory for %lld frames of %ux%u", (long long)o.frames, o.eye_w, o.eye_h);
        goto done;
    }
    if (o.gaze_uri) {
        fv_frame_input first;
        if (FV_FAILED(fv_renderer_frame_input(r, NULL, 0, 0.0, &first))) goto done;
        gaze_open = true;
        if (FV_FAILED(run_gaze_open(&gaze, o.gaze_uri, o.hz, (size_t)o.frames, render_cb, &st, first.eye))) {
            fprintf(stderr, "fovea run: cannot open gaze source '%s' (see the messages above)\n", o.gaze_uri);
            goto done;
        }
    }

    bool tty = isatty(STDERR_FILENO);
    int64_t t_start = fv_time_monotonic_ns(), t_last_progress = t_start;
    for (int64_t f = 0; f < o.frames; f++) {
        int64_t t0 = fv_time_monotonic_ns();
        if (o.gaze_uri) {
            if (FV_FAILED(run_gaze_step(&gaze))) goto done;
        } else {
            fv_frame_input in;
            memset(&in, 0, sizeof in);
            in.frame_id = (uint64_t)f;
            if (FV_FAILED(draw_frame(&st, &in, false, NULL))) goto done;
        }
        wall_ms[f] = (double)(fv_time_monotonic_ns() - t0) / 1e6;
        bool save_now = o.out_dir && (o.save == SAVE_EVERY || (o.save == SAVE_LAST && f == o.frames - 1));
        if (save_now && FV_FAILED(save_frame(r, &o, (uint64_t)f, img, img_size))) goto done;
        if (tty && fv_time_monotonic_ns() - t_start > FV_NS_PER_S &&
            fv_time_monotonic_ns() - t_last_progress > 200 * FV_NS_PER_MS) {
            t_last_progress = fv_time_monotonic_ns();
            fprintf(stderr, "\rfovea run: frame %lld/%lld", (long long)f + 1, (long long)o.frames);
        }
    }
    if (FV_FAILED(fv_renderer_finish(r)) || !take_stats(&st)) goto done;
    if (tty && fv_time_monotonic_ns() - t_start > FV_NS_PER_S) fprintf(stderr, "\r%*s\r", 40, "");
    double wall_s = (double)(fv_time_monotonic_ns() - t_start) / 1e9;
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    uint32_t vmsg = fv_renderer_validation_messages(r);
    pass_series *passes = st.passes;
    uint32_t pass_count = st.pass_count;
    size_t measured = st.measured;
    double *frame_gpu_ms = st.frame_gpu_ms, *cpu_ms = st.cpu_ms;
    fv_render_stats last_stats = st.last_stats;

    if (o.json) {
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "scene", scene->name[0] ? scene->name : o.scene);
        cJSON_AddStringToObject(j, "device", fv_renderer_device_name(r));
        cJSON_AddNumberToObject(j, "frames", (double)o.frames);
        cJSON_AddNumberToObject(j, "frames_timed", (double)measured);
        cJSON_AddNumberToObject(j, "eye_width", o.eye_w);
        cJSON_AddNumberToObject(j, "eye_height", o.eye_h);
        cJSON_AddNumberToObject(j, "triangles", (double)fv_scene_triangle_count(scene));
        cJSON *jp = cJSON_AddArrayToObject(j, "passes");
        for (uint32_t p = 0; p < pass_count; p++) {
            cJSON *e = cJSON_CreateObject();
            cJSON_AddStringToObject(e, "name", passes[p].name);
            cJSON_AddNumberToObject(e, "gpu_ms_median", percentile(passes[p].ms, passes[p].n, 50));
            cJSON_AddNumberToObject(e, "gpu_ms_p95", percentile(passes[p].ms, passes[p].n, 95));
            cJSON_AddItemToArray(jp, e);
        }
        cJSON_AddNumberToObject(j, "frame_gpu_ms_median", percentile(frame_gpu_ms, measured, 50));
        cJSON_AddNumberToObject(j, "frame_gpu_ms_p95", percentile(frame_gpu_ms, measured, 95));
        cJSON_AddNumberToObject(j, "cpu_ms_per_frame_median", percentile(cpu_ms, (size_t)o.frames, 50));
        cJSON_AddNumberToObject(j, "cpu_ms_per_frame_p95", percentile(cpu_ms, (size_t)o.frames, 95));
        cJSON_AddNumberToObject(j, "wall_ms_per_frame_median", percentile(wall_ms, (size_t)o.frames, 50));
        cJSON_AddNumberToObject(j, "pixels_shaded_last_frame", (double)last_stats.pixels_shaded);
        cJSON_AddNumberToObject(j, "peak_device_memory_mib", (double)last_stats.peak_device_memory_bytes / 1048576.0);
        cJSON_AddNumberToObject(j, "peak_host_rss_mib", (double)ru.ru_maxrss / 1024.0);
        cJSON_AddNumberToObject(j, "wall_s", wall_s);
        cJSON_AddNumberToObject(j, "validation_messages", vmsg);
        if (o.explain) {
            const fv_frame_plan *plan = fv_renderer_plan(r);
            cJSON *pl = cJSON_AddArrayToObject(j, "plan");
            for (uint32_t i = 0; i < plan->count; i++) {
                cJSON *e = cJSON_CreateObject();
                cJSON_AddStringToObject(e, "pass", plan->entries[i].pass);
                cJSON_AddBoolToObject(e, "enabled", plan->entries[i].enabled);
                cJSON_AddStringToObject(e, "reason", plan->entries[i].reason);
                cJSON_AddItemToArray(pl, e);
            }
        }
        if (o.gaze_uri) run_gaze_add_json(&gaze, j);
        char *text = cJSON_PrintUnformatted(j);
        if (text) puts(text);
        cJSON_free(text);
        cJSON_Delete(j);
    } else {
        printf("fovea run: scene '%s' on %s, %lld frame%s at %ux%u per eye (%llu triangles), %.2f s\n",
               scene->name[0] ? scene->name : o.scene, fv_renderer_device_name(r), (long long)o.frames,
               o.frames == 1 ? "" : "s", o.eye_w, o.eye_h, (unsigned long long)fv_scene_triangle_count(scene),
               wall_s);
        printf("  %-14s %10s %10s   (GPU time over %zu timed frame%s)\n", "pass", "median ms", "p95 ms", measured,
               measured == 1 ? "" : "s");
        for (uint32_t p = 0; p < pass_count; p++)
            printf("  %-14s %10.3f %10.3f\n", passes[p].name, percentile(passes[p].ms, passes[p].n, 50),
                   percentile(passes[p].ms, passes[p].n, 95));
        printf("  %-14s %10.3f %10.3f\n", "frame (GPU)", percentile(frame_gpu_ms, measured, 50),
               percentile(frame_gpu_ms, measured, 95));
        printf("  %-14s %10.3f %10.3f   (record + submit, this thread)\n", "CPU per frame",
               percentile(cpu_ms, (size_t)o.frames, 50), percentile(cpu_ms, (size_t)o.frames, 95));
        printf("  %-14s %10.3f %10.3f\n", "wall per frame", percentile(wall_ms, (size_t)o.frames, 50),
               percentile(wall_ms, (size_t)o.frames, 95));
        printf("  memory: %.1f MiB device (peak), %.1f MiB host RSS (peak); validation messages: %u\n",
               (double)last_stats.peak_device_memory_bytes / 1048576.0, (double)ru.ru_maxrss / 1024.0, vmsg);
        if (o.gaze_uri) run_gaze_print(&gaze, stdout);
        if (o.out_dir && o.save != SAVE_NONE) printf("  images: %s/\n", o.out_dir);
    }
    if (vmsg > 0) {
        fprintf(stderr, "fovea run: %u Vulkan validation message%s (see above)\n", vmsg, vmsg == 1 ? "" : "s");
        goto done;
    }
    exit_code = FV_EXIT_OK;
done:
    if (gaze_open) run_gaze_close(&gaze);
    free(img);
    free(st.cpu_ms);
    free(wall_ms);
    free(st.frame_gpu_ms);
    for (uint32_t i = 0; i < FV_MAX_PASSES; i++) free(st.passes[i].ms);
    fv_renderer_destroy(&r);
    fv_scene_destroy(&scene);
    return exit_code;
}
