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

#include "cli.h"
#include "fv_clock.h"
#include "fv_log.h"
#include "fv_renderer.h"
#include "fv_scene.h"
#include "fv_target.h"
#include "run_gaze.h"
#include "run_measure.h"
#include "tool_knobs.h"

/* The usage; %s: the preset names from the knob table. */
static const char *USAGE_FMT =
    "usage: fovea run [--scene NAME|FILE] [--frames N] [--eye-size WxH] [--out DIR]\n"
    "                 [--save last|every|none] [--layout sbs|eyes] [--gaze URI [--hz HZ]]\n"
    "                 [--quality PRESET] [--set NAME=VALUE]...\n"
    "                 [--view NAME] [--exposure X] [--float] [--explain] [--json]\n"
    "  --scene     built-in scene name (cornell, cornell-translucent, pillars) or a file: *.scene.json, .gltf/.glb,\n"
    "              .obj, .ply\n"
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
    "  --quality   the speed/accuracy preset: %s (default balanced; exact: every shortcut off)\n"
    "  --set       set one knob after the preset, e.g. shadow.splits=3 (repeatable, applied in order);\n"
    "              `fovea knobs` lists the knobs, their ranges and their presets\n"
    "  --view      what the image shows (default color): direct (direct light only), shadow (light 0's\n"
    "              visibility), cascade (which of light 0's shadow maps), albedo, normal, depth (the G-buffer's),\n"
    "              gaze (each eye's predicted gaze as the GPU receives it)\n"
    "  --exposure  linear scale of the colour before tonemapping (default 1; 1e-6..1e6)\n"
    "  --float     with --out, also write the linear colour (or --view) as PFM beside each PNG, to compare with\n"
    "              `fovea reference` in linear units (`fovea compare`)\n"
    "  --explain   print the frame plan (which passes run and why)\n"
    "  --json      print the summary as one JSON object on stdout (and nothing else on stdout)\n";

static const char *usage_text(void)
{
    static char text[4096];
    if (!text[0]) snprintf(text, sizeof text, USAGE_FMT, fv_quality_preset_names());
    return text;
}
#define USAGE usage_text()

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
    fv_tool_quality tq;       /* --quality and --set, applied after parsing */
    float exposure;           /* --exposure and --view: view settings, not knobs */
    fv_debug_view debug_view;
    fv_quality quality;       /* the preset, the --set knobs, then the view settings */
    bool explain, json, float_out;
} run_opts;

static int parse_args(int argc, char **argv, run_opts *o)
{
    *o = (run_opts){.scene = "cornell", .frames = 1, .eye_w = 720, .eye_h = 800, .save = SAVE_LAST, .sbs = true,
                    .hz = 90, .exposure = fv_quality_default().exposure,
                    .debug_view = fv_quality_default().debug_view};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = NULL;
        int r;
        if (fv_cli_is_help(a)) {
            fputs(USAGE, stdout);
            fv_tool_knobs_help(stdout);
            return -1;
        }
#define OPT(name) FV_CLI_OPT("run", USAGE, name)
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
        if ((r = OPT("--view")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            int found = -1;
            for (int k = 0; k < FV_DEBUG_VIEW_COUNT; k++)
                if (strcmp(v, fv_debug_view_name((fv_debug_view)k)) == 0) found = k;
            if (found < 0)
                return fv_cli_usage_error("run", USAGE,
                                          "--view: '%s' is not one of color, direct, shadow, cascade, albedo, normal, "
                                          "depth, gaze", v);
            o->debug_view = (fv_debug_view)found;
            continue;
        }
        if ((r = OPT("--exposure")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            double x;
            if (!fv_cli_parse_f64(v, 1e-6, 1e6, &x))
                return fv_cli_usage_error("run", USAGE, "--exposure: '%s' is not a number in 1e-6..1e6", v);
            o->exposure = (float)x;
            continue;
        }
#undef OPT
        if ((r = fv_tool_quality_option(&o->tq, argc, argv, &i, "run", USAGE)) == FV_EXIT_USAGE) return r;
        else if (r) continue;
        if (strcmp(a, "--explain") == 0) { o->explain = true; continue; }
        if (strcmp(a, "--float") == 0) { o->float_out = true; continue; }
        if (strcmp(a, "--json") == 0) { o->json = true; continue; }
        return fv_cli_usage_error("run", USAGE, "unknown option '%s'", a);
    }
    int built = fv_tool_quality_build(&o->tq, "run", USAGE, &o->quality);
    if (built != 0) return built;
    o->quality.exposure = o->exposure;
    o->quality.debug_view = o->debug_view;
    return 0;
}

static void print_plan(FILE *f, const fv_frame_plan *plan)
{
    fprintf(f, "frame plan:\n");
    for (uint32_t i = 0; i < plan->count; i++)
        fprintf(f, "  %-3s %-12s %s\n", plan->entries[i].enabled ? "on" : "off", plan->entries[i].pass,
                plan->entries[i].reason);
}

/* Everything one run measures. */
typedef struct run_state {
    const run_opts *o;
    fv_renderer *r;
    fv_measure m;
} run_state;

/* Draw one frame: views from the scene's head, gaze as given (the frame loop's prediction) or straight ahead.
 * With times (a frame-loop frame), wait for the GPU so that its end is known on the host clock. */
static fv_result draw_frame(run_state *st, fv_frame_input *in, bool keep_gaze, fv_frame_render_times *times)
{
    fv_frame_input base;
    double time_s = (double)in->frame_id / (st->o->hz > 0 ? st->o->hz : 90.0); /* scene time at the refresh rate */
    FV_TRY(fv_renderer_frame_input(st->r, NULL, in->frame_id, time_s, &base));
    if (keep_gaze) {
        in->head = base.head;
        in->eye[0] = base.eye[0];
        in->eye[1] = base.eye[1];
        in->time_s = time_s;
    } else {
        *in = base;
    }
    in->quality = st->o->quality;
    int64_t c0 = fv_measure_thread_cpu_ns();
    fv_result res = fv_renderer_draw(st->r, in);
    fv_measure_cpu(&st->m, (double)(fv_measure_thread_cpu_ns() - c0) / 1e6);
    if (FV_FAILED(res)) {
        fprintf(stderr, "fovea run: frame %llu failed (see the messages above)\n", (unsigned long long)in->frame_id);
        return res;
    }
    if (times) {
        times->t_submit_ns = fv_time_monotonic_ns();
        FV_TRY(fv_renderer_finish(st->r));
        int64_t t_end = fv_time_monotonic_ns();
        if (!fv_measure_take(&st->m, st->r)) return FV_ERR_NO_MEMORY;
        /* The GPU ran this frame's work for frame_gpu_ms before the fence was seen signalled. */
        int64_t gpu_ns = (int64_t)(st->m.last_stats.frame_gpu_ms * 1e6);
        times->t_gpu_end_ns = t_end;
        times->t_gpu_begin_ns = t_end - gpu_ns > times->t_submit_ns ? t_end - gpu_ns : times->t_submit_ns;
        return FV_OK;
    }
    return fv_measure_take(&st->m, st->r) ? FV_OK : FV_ERR_NO_MEMORY;
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
    fv_target *files = NULL;
    run_state st;
    memset(&st, 0, sizeof st);
    st.o = &o;
    run_gaze gaze;
    memset(&gaze, 0, sizeof gaze);
    bool gaze_open = false;

    if (FV_FAILED(fv_measure_init(&st.m, (size_t)o.frames))) {
        FV_ERROR("run", "out of memory for %lld frames", (long long)o.frames);
        return FV_EXIT_FAIL;
    }
    bool saving = o.out_dir && o.save != SAVE_NONE;
    if (saving) {
        if (!fv_cli_output_dir("run", "--out", o.out_dir)) goto done;
        fv_target_files_desc fd = {.dir = o.out_dir, .side_by_side = o.sbs, .linear_pfm = o.float_out,
                                   .save = o.save == SAVE_EVERY ? FV_TARGET_SAVE_EVERY : FV_TARGET_SAVE_LAST};
        if (FV_FAILED(fv_target_files_create(&fd, &files))) goto done;
    }
    if (FV_FAILED(fv_scene_load(o.scene, &scene))) {
        fprintf(stderr, "fovea run: cannot load scene '%s' (see the messages above)\n", o.scene);
        goto done;
    }
    fv_renderer_desc desc = {.eye_width = o.eye_w, .eye_height = o.eye_h, .target = files};
    if (FV_FAILED(fv_renderer_create(&desc, &r))) {
        fprintf(stderr, "fovea run: cannot create the renderer (see the messages above)\n");
        goto done;
    }
    st.r = r;
    /* The quality first, so that the scene's passes start once, with the settings they will run with. */
    if (FV_FAILED(fv_renderer_set_quality(r, &o.quality))) goto done;
    if (FV_FAILED(fv_renderer_load_scene(r, scene))) {
        fprintf(stderr, "fovea run: cannot upload scene '%s'\n", o.scene);
        goto done;
    }
    if (o.explain) print_plan(o.json ? stderr : stdout, fv_renderer_plan(r));
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
        fv_measure_wall(&st.m, (double)(fv_time_monotonic_ns() - t0) / 1e6);
        if (tty && fv_time_monotonic_ns() - t_start > FV_NS_PER_S &&
            fv_time_monotonic_ns() - t_last_progress > 200 * FV_NS_PER_MS) {
            t_last_progress = fv_time_monotonic_ns();
            fprintf(stderr, "\rfovea run: frame %lld/%lld", (long long)f + 1, (long long)o.frames);
        }
    }
    if (FV_FAILED(fv_renderer_finish(r)) || !fv_measure_take(&st.m, r)) goto done;
    if (files && o.save == SAVE_LAST && FV_FAILED(fv_target_files_flush(files))) goto done;
    if (tty && fv_time_monotonic_ns() - t_start > FV_NS_PER_S) fprintf(stderr, "\r%*s\r", 40, "");
    double wall_s = (double)(fv_time_monotonic_ns() - t_start) / 1e9;
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    uint32_t vmsg = fv_renderer_validation_messages(r);

    if (o.json) {
        cJSON *j = cJSON_CreateObject();
        fv_cli_json_add_string(j, "scene", scene->name[0] ? scene->name : o.scene);
        fv_cli_json_add_string(j, "device", fv_renderer_device_name(r));
        cJSON_AddNumberToObject(j, "frames", (double)o.frames);
        cJSON_AddNumberToObject(j, "eye_width", o.eye_w);
        cJSON_AddNumberToObject(j, "eye_height", o.eye_h);
        cJSON_AddNumberToObject(j, "triangles", (double)fv_scene_triangle_count(scene));
        fv_measure_add_json(&st.m, j);
        cJSON_AddNumberToObject(j, "peak_host_rss_mib", (double)ru.ru_maxrss / 1024.0);
        cJSON_AddNumberToObject(j, "wall_s", wall_s);
        cJSON_AddNumberToObject(j, "validation_messages", vmsg);
        cJSON *jq = cJSON_AddObjectToObject(j, "quality");
        cJSON_AddNumberToObject(jq, "exposure", o.quality.exposure);
        fv_cli_json_add_string(jq, "debug_view", fv_debug_view_name(o.quality.debug_view));
        fv_tool_quality_add_json(jq, fv_tool_quality_preset(&o.tq), &o.quality);
        if (o.explain) {
            const fv_frame_plan *plan = fv_renderer_plan(r);
            cJSON *pl = cJSON_AddArrayToObject(j, "plan");
            for (uint32_t i = 0; i < plan->count; i++) {
                cJSON *e = cJSON_CreateObject();
                fv_cli_json_add_string(e, "pass", plan->entries[i].pass);
                cJSON_AddBoolToObject(e, "enabled", plan->entries[i].enabled);
                fv_cli_json_add_string(e, "reason", plan->entries[i].reason);
                fv_pass_detail det[16];
                uint32_t nd = fv_renderer_pass_details(r, plan->entries[i].pass, det, 16);
                if (nd) {
                    cJSON *jd = cJSON_AddObjectToObject(e, "details");
                    for (uint32_t k = 0; k < nd; k++) {
                        if (det[k].count == 1 && !strstr(det[k].key, "splits_m")) {
                            cJSON_AddNumberToObject(jd, det[k].key, det[k].value[0]);
                            continue;
                        }
                        cJSON *arr = cJSON_AddArrayToObject(jd, det[k].key);
                        for (uint32_t v = 0; v < det[k].count; v++) cJSON_AddItemToArray(arr, cJSON_CreateNumber(det[k].value[v]));
                    }
                }
                cJSON_AddItemToArray(pl, e);
            }
        }
        if (o.gaze_uri) run_gaze_add_json(&gaze, j);
        int printed = fv_cli_json_print(j, false);
        cJSON_Delete(j);
        if (printed != FV_EXIT_OK) goto done;
    } else {
        printf("fovea run: scene '%s' on %s, %lld frame%s at %ux%u per eye (%llu triangles), %.2f s\n",
               scene->name[0] ? scene->name : o.scene, fv_renderer_device_name(r), (long long)o.frames,
               o.frames == 1 ? "" : "s", o.eye_w, o.eye_h, (unsigned long long)fv_scene_triangle_count(scene),
               wall_s);
        fv_measure_print(&st.m, stdout);
        fv_tool_quality_print(stdout, fv_tool_quality_preset(&o.tq), &o.quality);
        printf("  memory: %.1f MiB device (peak), %.1f MiB host RSS (peak); validation messages: %u\n",
               (double)st.m.last_stats.peak_device_memory_bytes / 1048576.0, (double)ru.ru_maxrss / 1024.0, vmsg);
        if (o.gaze_uri) run_gaze_print(&gaze, stdout);
        if (saving) printf("  images: %s/\n", o.out_dir);
    }
    if (vmsg > 0) {
        fprintf(stderr, "fovea run: %u Vulkan validation message%s (see above)\n", vmsg, vmsg == 1 ? "" : "s");
        goto done;
    }
    exit_code = FV_EXIT_OK;
done:
    if (gaze_open) run_gaze_close(&gaze);
    fv_measure_fini(&st.m);
    fv_renderer_destroy(&r);
    fv_target_destroy(&files);
    fv_scene_destroy(&scene);
    return exit_code;
}
