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
#include "cli_interrupt.h"
#include "cli_progress.h"
#include "fv_app_interactive.h"
#include "fv_vk.h"
#include "fv_clock.h"
#include "fv_log.h"
#include "fv_mouse_driver.h"
#include "fv_renderer.h"
#include "fv_scene.h"
#include "fv_target.h"
#include "fv_window.h"
#include "run_gaze.h"
#include "run_measure.h"
#include "fv_knobs.h"
#include "tool_knobs.h"
#include "tool_image.h"
#include <dirent.h>
#include "fovea_config.h"
#include "run_frame_log.h"
#include "run_head.h"
#include "run_hmd.h"

/* The usage; %s: the preset names from the knob table. */
static const char *USAGE_FMT =
    "usage: fovea run [--scene NAME|FILE] [--frames N] [--eye-size WxH] [--out DIR]\n"
    "                 [--save last|every|none] [--layout sbs|eyes] [--gaze URI [--hz HZ]]\n"
    "                 [--quality PRESET] [--set NAME=VALUE]...\n"
    "                 [--view NAME] [--exposure X] [--float] [--explain] [--json]\n"
    "                 [--present headless|window|auto] [--window WxH] [--present-mode fifo|mailbox|immediate]\n"
    "                 [--overlay] [--head trace|scene|fixed] [--predict on|off] [--frame-log FILE.csv]\n"
    "                 [--hmd PROFILE|FILE|none] [--budget auto|off] [--budget-scale X]\n"
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
    "              (default: no tracker, gaze straight ahead, frames as fast as the GPU allows);\n"
    "              mouse:[vergence_m=1.5] in a window: the cursor is the gaze point of both eyes\n"
    "  --hz        refresh rate of the (simulated) display that paces --gaze runs (default 90; 1..1000;\n"
    "              in a window the swapchain paces them)\n"
    "  --quality   the speed/accuracy preset: %s (default balanced; exact: every shortcut off)\n"
    "  --set       set one knob after the preset, e.g. shadow.splits=3 (repeatable, applied in order);\n"
    "              `fovea knobs` lists the knobs, their ranges and their presets\n"
    "  --view      what the image shows (default color): %s\n"
    "              (direct: direct light only; shadow: light 0's visibility; cascade: which of light 0's shadow\n"
    "              maps; albedo, normal, depth: the G-buffer's; gaze: each eye's predicted gaze as the GPU\n"
    "              receives it; samples, prob, voronoi: foveation's mask, probability, reconstruction; gi,\n"
    "              clusters: indirect light, the GI cut; sss: the subsurface term; interp: interpolation levels)\n"
    "  --exposure  linear scale of the colour before tonemapping (default 1; 1e-6..1e6), or the same in stops:\n"
    "              -1EV = 0.5, +2EV = 4; the tone curve (Reinhard extended, white point 4) keeps surfaces up to\n"
    "              4x display white graded; mid-grey 0.18 shows as sRGB 109\n"

    "  --float     with --out, also write the linear colour (or --view) as PFM beside each PNG, to compare with\n"
    "              `fovea reference` in linear units (`fovea compare`)\n"
    "  --explain   print the frame plan (which passes run and why)\n"
    "  --json      print the summary as one JSON object on stdout (and nothing else on stdout)\n"
    "  --present   where frames go: headless (default: they stay on the GPU, or --out), window (a window showing\n"
    "              both eyes side by side, paced by its swapchain; --gaze runs then use its display clock),\n"
    "              auto (window when DISPLAY or WAYLAND_DISPLAY is set, else headless). In a window, Esc or\n"
    "              closing it ends the run with the summary; without --frames it runs until then (at most 108000\n"
    "              frames); keys: F fovea.enabled, G gi.enabled, H shadow.enabled, V next --view, O the overlay\n"
    "  --window    window size in screen px (default: the --hmd profile's panel, else both eyes at --eye-size;\n"
    "              scaled to fit the screen)\n"
    "  --present-mode  fifo (default, vsync), mailbox, immediate (an error when the surface lacks it)\n"
    "  --overlay   draw the predicted gaze point, its uncertainty ring and (with fovea.enabled) the foveal\n"
    "              boundary into the image\n"
;

/* The options of the head pose and the frame log (a string literal may hold at most 4095 characters in ISO C). */
static const char *USAGE_HEAD_LOG =
    "  --head      with --gaze, the head the cameras follow: trace (default: the scene's head moved by the\n"
    "              tracker's recorded head pose, relative to its first pose; SRanipal, Pico, fovea traces), scene\n"
    "              (the scene's head; the tracker's pose is ignored), fixed (the scene's head at time 0, held)\n"
    "  --predict   with --gaze: on (default: predicted to each frame's photon time) or off (the latest filtered\n"
    "              sample: the baseline, or to check geometry alone)\n"
    "  --frame-log write one CSV row per frame to FILE: frame id, sample times, latch, predicted gaze per eye,\n"
    "              uncertainty, GPU/CPU ms, present and photon times, the head; `fovea latency --frame-log FILE`\n"
    "              summarises it. Ctrl-C ends a run after the frame in flight, with the summary (exit 130)\n";

static const char *usage_text(void)
{
    static char text[16384];
    if (!text[0]) {
        char views[256] = ""; /* every view, from the one table (fv_debug_view_name) */
        for (int k = 0; k < FV_DEBUG_VIEW_COUNT; k++)
            snprintf(views + strlen(views), sizeof views - strlen(views), "%s%s", k ? ", " : "",
                     fv_debug_view_name((fv_debug_view)k));
        snprintf(text, sizeof text, USAGE_FMT, fv_quality_preset_names(), views);
        snprintf(text + strlen(text), sizeof text - strlen(text), "%s", RUN_HMD_USAGE);
        snprintf(text + strlen(text), sizeof text - strlen(text), "%s", USAGE_HEAD_LOG);
    }
    return text;
}
#define USAGE usage_text()

typedef enum { SAVE_LAST, SAVE_EVERY, SAVE_NONE } save_mode;

/* Head samples after which a --head trace run whose head never moved says so. */
#define RUN_HEAD_CHECK_SAMPLES 64

/* A window run without --frames runs until the window is closed, for at most this many frames (30 min at 60 Hz). */
#define RUN_WINDOW_MAX_FRAMES 108000

typedef struct run_opts {
    fv_tool_image img;        /* the run (scene, size, layout, quality, view, exposure, HMD, --gaze, --head, budget) */
    int64_t frames;
    const char *out_dir;
    save_mode save;
    double hz;
    bool explain, json, float_out;
    bool window;              /* --present window (or auto with a display) */
    bool frames_given;
    uint32_t win_w, win_h;    /* --window; 0 = default */
    fv_window_present_mode present_mode;
    bool overlay;
    const char *frame_log;    /* --frame-log FILE.csv */
    bool no_predict, predict_given; /* --predict off: the latest filtered sample, no prediction (geometry alone) */
    bool head_given, hz_given, save_given; /* to refuse options that would have no effect */
    bool size_given;          /* --eye-size (a software device's interactive start keeps it) */
} run_opts;

static int parse_args(int argc, char **argv, run_opts *o)
{
    *o = (run_opts){.frames = 1, .save = SAVE_LAST, .hz = 90};
    fv_tool_image_defaults(&o->img);
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = NULL;
        int r;
        if (fv_cli_is_help(a)) {
            fputs(USAGE, stdout);
            fv_tool_knobs_help(stdout);
            return -1;
        }
#define OPT(name) FV_CLI_OPT("run", USAGE, name)
        if ((r = OPT("--frames")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_cli_parse_i64(v, 1, 1000000, &o->frames))
                return fv_cli_usage_error("run", USAGE, "--frames: '%s' is not a whole number in 1..1000000", v);
            o->frames_given = true;
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
            o->save_given = true;
            continue;
        }
        if ((r = OPT("--gaze")) == -2) return FV_EXIT_USAGE;
        else if (r) { o->img.run.gaze_uri = v; continue; }
        if ((r = OPT("--hz")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_cli_parse_f64(v, 1, 1000, &o->hz))
                return fv_cli_usage_error("run", USAGE, "--hz: '%s' is not a number in 1..1000", v);
            o->hz_given = true;
            continue;
        }
        if ((r = OPT("--present")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            const char *x11 = getenv("DISPLAY"), *wl = getenv("WAYLAND_DISPLAY");
            if (strcmp(v, "window") == 0) o->window = true;
            else if (strcmp(v, "headless") == 0) o->window = false;
            else if (strcmp(v, "auto") == 0) o->window = (x11 && *x11) || (wl && *wl);
            else return fv_cli_usage_error("run", USAGE, "--present: '%s' is not one of headless, window, auto", v);
            continue;
        }
        if ((r = OPT("--window")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_cli_parse_size(v, 16384, &o->win_w, &o->win_h))
                return fv_cli_usage_error("run", USAGE, "--window: '%s' is not WxH with each in 1..16384", v);
            continue;
        }
        if ((r = OPT("--present-mode")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_window_present_mode_parse(v, &o->present_mode))
                return fv_cli_usage_error("run", USAGE, "--present-mode: '%s' is not one of fifo, mailbox, immediate",
                                          v);
            continue;
        }
        if ((r = OPT("--head")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_app_head_parse(v, &o->img.run.head))
                return fv_cli_usage_error("run", USAGE, "--head: '%s' is not one of trace, scene, fixed", v);
            o->head_given = true;
            continue;
        }
        if ((r = OPT("--predict")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (strcmp(v, "on") == 0) o->no_predict = false;
            else if (strcmp(v, "off") == 0) o->no_predict = true;
            else return fv_cli_usage_error("run", USAGE, "--predict: '%s' is not one of on, off", v);
            o->predict_given = true;
            continue;
        }
        if ((r = OPT("--frame-log")) == -2) return FV_EXIT_USAGE;
        else if (r) { o->frame_log = v; continue; }
#undef OPT
        if (!strcmp(a, "--eye-size") || !strncmp(a, "--eye-size=", 11)) o->size_given = true;
        if ((r = fv_tool_image_option(&o->img, argc, argv, &i, "run", USAGE)) == FV_EXIT_USAGE) return r;
        else if (r) continue;
        if (strcmp(a, "--explain") == 0) { o->explain = true; continue; }
        if (strcmp(a, "--float") == 0) { o->float_out = true; continue; }
        if (strcmp(a, "--json") == 0) { o->json = true; continue; }
        if (strcmp(a, "--overlay") == 0) { o->overlay = true; continue; }
        return fv_cli_usage_error("run", USAGE, "unknown option '%s'", a);
    }
    if (o->img.run.budget_scale > 0 && !o->img.run.budget)
        return fv_cli_usage_error("run", USAGE, "--budget-scale scales the budget of --budget auto (add it or drop "
                                  "--budget-scale)");
    int built = fv_tool_image_finish(&o->img, "run", USAGE);
    if (built != 0) return built;
    o->img.quality.overlay = o->overlay;
    if (o->window && !o->frames_given) o->frames = RUN_WINDOW_MAX_FRAMES;
    if (!o->window && (o->win_w || o->present_mode != FV_WINDOW_FIFO))
        return fv_cli_usage_error("run", USAGE, "--window and --present-mode need --present window");
    if (o->window && o->out_dir)
        return fv_cli_usage_error("run", USAGE, "--out writes files from a headless run; it cannot be combined with "
                                  "--present window");
    /* Options that would have no effect are refused: the user meant something else. */
    if (o->hz_given && !o->img.run.gaze_uri)
        return fv_cli_usage_error("run", USAGE, "--hz is the refresh rate of the display that paces --gaze runs; "
                                  "without --gaze frames run unpaced (add --gaze URI or drop --hz)");
    if (o->hz_given && o->window)
        return fv_cli_usage_error("run", USAGE, "--hz has no effect with --present window: its swapchain paces the "
                                  "frames at the display's own rate");
    if (o->predict_given && !o->img.run.gaze_uri)
        return fv_cli_usage_error("run", USAGE, "--predict chooses how a --gaze run's gaze reaches the frame; "
                                  "without --gaze there is no gaze to predict");
    if (o->head_given && !o->img.run.gaze_uri)
        return fv_cli_usage_error("run", USAGE, "--head chooses the head of a --gaze run (the scene's or the "
                                  "tracker's); without --gaze the scene's head is used");
    if (o->save_given && !o->out_dir)
        return fv_cli_usage_error("run", USAGE, "--save picks the frames that --out writes; without --out nothing "
                                  "is saved (add --out DIR)");
    if (o->img.layout_given && !o->out_dir)
        return fv_cli_usage_error("run", USAGE, "--layout is the layout of the images --out writes; without --out "
                                  "there are none (add --out DIR)");
    if (o->float_out && (!o->out_dir || o->save == SAVE_NONE))
        return fv_cli_usage_error("run", USAGE, "--float writes PFM files beside the PNGs of --out; it needs --out "
                                  "DIR and a --save other than none");
    return 0;
}

static void print_plan(FILE *f, const fv_frame_plan *plan)
{
    fprintf(f, "frame plan:\n");
    for (uint32_t i = 0; i < plan->count; i++) {
        fprintf(f, "  %-3s %-12s %s\n", plan->entries[i].enabled ? "on" : "off", plan->entries[i].pass,
                plan->entries[i].reason);
        if (plan->entries[i].io[0]) fprintf(f, "                   images: %s\n", plan->entries[i].io); /* the graph */
    }
}

/* Everything one run measures. */
typedef struct run_state {
    const run_opts *o;
    fv_renderer *r;
    fv_measure m;
    fv_quality quality;       /* what frames are drawn with: the options', then what the window's keys changed */
    bool keys_changed;
    run_gaze *gaze;           /* the frame loop of a --gaze run (its newest head pose) */
    run_head head;            /* --head */
    fv_head scene_head;       /* the loaded scene's head */
    const fv_scene *scene;
    run_frame_row *rows;      /* --frame-log: one per frame drawn */
    run_hmd *hmd;             /* the options' HMD profile and frame budget */
    bool head_warned;         /* check_head_moves said it */
    size_t rows_n, rows_cap;
} run_state;

/* ---- in a window: keys and title ------------------------------------------------------------------------------ */

/* A key of the window (GLFW key codes: letters are their upper-case ASCII). F, G, H toggle the knobs that exist in
 * this build (fovea.enabled, gi.enabled, shadow.enabled), V steps to the next view, O toggles the overlay. */
static void window_key(run_state *st, int key)
{
    const char *knob = key == 'F' ? "fovea.enabled" : key == 'G' ? "gi.enabled" : key == 'H' ? "shadow.enabled" : NULL;
    if (knob) {
        const fv_knob *k = fv_knob_find(knob);
        if (!k || k->type != FV_KNOB_BOOL) {
            FV_INFO("run", "key %c: this build has no knob %s", key, knob);
            return;
        }
        bool on = !fv_knob_get(k, &st->quality).b;
        char set[64], err[160];
        snprintf(set, sizeof set, "%s=%s", knob, on ? "on" : "off");
        if (FV_FAILED(fv_quality_set(&st->quality, set, err, sizeof err))) {
            FV_WARN("run", "key %c: %s", key, err);
            return;
        }
        FV_INFO("run", "key %c: %s", key, set);
        st->keys_changed = true;
    } else if (key == 'V') {
        st->quality.debug_view = (fv_debug_view)(((unsigned)st->quality.debug_view + 1u) % FV_DEBUG_VIEW_COUNT);
        FV_INFO("run", "key V: view %s", fv_debug_view_name(st->quality.debug_view));
        st->keys_changed = true;
    } else if (key == 'O') {
        st->quality.overlay = !st->quality.overlay;
        FV_INFO("run", "key O: overlay %s", st->quality.overlay ? "on" : "off");
        st->keys_changed = true;
    }
}

/* The cursor is over the panel image, pre-distorted for the lens: the undistorted ray its panel point shows (green
 * channel) is what the mouse's gaze aims at, as the eye image's uv. Without a lens the two are the same. */
static void cursor_through_lens(const fv_quality *q, const fv_mouse_views *mv, int eye, float *u, float *v)
{
    if (!q->distort.enabled || !q->distort.lens.valid) return;
    double tx = 0.0, ty = 0.0;
    fv_lens_panel_to_tan(&q->distort.lens, eye, 1, *u, *v, &tx, &ty);
    double w = mv->tan_right[eye] - mv->tan_left[eye], h = mv->tan_up[eye] - mv->tan_down[eye];
    if (!(w > 0.0 && h > 0.0) || !isfinite(tx) || !isfinite(ty)) return;
    *u = (float)((tx - mv->tan_left[eye]) / w);
    *v = (float)((mv->tan_up[eye] - ty) / h);
}

/* The window title: frame rate over the last half second or more, the newest frame's GPU time, the preset. */
static void window_title(fv_window *w, const run_state *st, double fps)
{
    char title[192];
    snprintf(title, sizeof title, "fovea — %.1f fps, GPU %.2f ms, %s%s%s%s", fps, st->m.last_stats.frame_gpu_ms,
             fv_tool_quality_preset(&st->o->img.run.quality), st->keys_changed ? " (keys changed it)" : "",
             st->quality.debug_view ? ", view " : "",
             st->quality.debug_view ? fv_debug_view_name(st->quality.debug_view) : "");
    fv_window_set_title(w, title);
}

/* Draw one frame: views from the scene's head, gaze as given (the frame loop's prediction) or straight ahead.
 * With times (a frame-loop frame), wait for the GPU so that its end is known on the host clock. */
static fv_result draw_frame(run_state *st, fv_frame_input *in, bool keep_gaze, fv_frame_render_times *times)
{
    int64_t t_entry = fv_time_monotonic_ns();
    fv_frame_input base;
    double time_s = (double)in->frame_id / (st->o->hz > 0 ? st->o->hz : 90.0); /* scene time at the refresh rate */
    fv_head head = st->scene_head;
    const fv_head *hp = NULL;
    if (keep_gaze && st->gaze && st->gaze->loop) { /* --head: the scene's, or moved by the tracker's pose */
        fv_gaze_sample hs; /* the newest head sample (its sequence number for the frame log) */
        bool have = fv_frame_loop_newest_head(st->gaze->loop, &hs);
        fv_quat dq;
        fv_vec3 dp;
        bool moved = fv_app_tracker_head(st->gaze->tracker, &dq, &dp); /* the application layer's head pose */
        run_head_apply(&st->head, moved ? &dq : NULL, &dp, have ? hs.seq : 0, &st->scene_head, &head);
        hp = &head;
    }
    fv_tool_image_frame_input(&st->o->img, st->scene, hp, in->frame_id, time_s, &base);
    if (keep_gaze) {
        in->head = base.head;
        in->eye[0] = base.eye[0];
        in->eye[1] = base.eye[1];
        in->time_s = time_s;
    } else {
        *in = base;
    }
    run_hmd_budget_update(st->hmd, &st->m, in->frame_id, &st->quality);
    in->quality = st->quality;
    if (st->rows && st->rows_n < st->rows_cap) { /* --frame-log: what this frame was drawn with */
        run_frame_row *row = &st->rows[st->rows_n++];
        row->frame_id = in->frame_id;
        row->gaze[0] = in->gaze[0];
        row->gaze[1] = in->gaze[1];
        row->pupil_mm = keep_gaze ? in->pupil_mm : NAN;
        row->head = head;
        row->head_source = keep_gaze ? fv_app_head_name(st->head.mode) : "scene";
        row->head_recorded = hp && st->head.applied;
        row->head_seq = st->head.seq;
    }
    int64_t c0 = fv_measure_thread_cpu_ns();
    fv_result res = fv_renderer_draw(st->r, in);
    fv_measure_cpu(&st->m, (double)(fv_measure_thread_cpu_ns() - c0) / 1e6);
    if (FV_FAILED(res)) {
        fprintf(stderr, "fovea run: frame %llu failed (see the messages above)\n", (unsigned long long)in->frame_id);
        return res;
    }
    if (times) {
        int64_t t_returned = fv_time_monotonic_ns();
        FV_TRY(fv_renderer_finish(st->r));
        int64_t t_end = fv_time_monotonic_ns();
        if (!fv_measure_take(&st->m, st->r)) return FV_ERR_NO_MEMORY;
        /* The GPU ran this frame's work for frame_gpu_ms before the fence was seen signalled; a draw that waited for
         * the GPU inside it (a software device's present) returned after the GPU began (fv_frame_loop.h). */
        double gpu_ms = st->m.last_stats.frame_gpu_ms;
        fv_frame_times_from_fence(t_entry, t_returned, t_end, isfinite(gpu_ms) ? (int64_t)(gpu_ms * 1e6) : 0, times);
        return FV_OK;
    }
    return fv_measure_take(&st->m, st->r) ? FV_OK : FV_ERR_NO_MEMORY;
}

static fv_result render_cb(void *user, fv_frame_input *in, fv_frame_render_times *out_times)
{
    return draw_frame(user, in, true, out_times);
}

/* The settings beside every image --out wrote (tool_image.h: `fovea compare` checks them). */
static void write_image_settings(const run_opts *o, int64_t frames_done)
{
    fv_tool_image_meta m = fv_tool_image_meta_of(&o->img, "fovea run", o->img.run.sbs);
    for (int64_t f = o->save == SAVE_EVERY ? 0 : frames_done - 1; f >= 0 && f < frames_done; f++) {
        char path[4200];
        for (int e = 0; e < (o->img.run.sbs ? 1 : 2); e++) {
            snprintf(path, sizeof path, "%s/frame_%05lld%s.png", o->out_dir, (long long)f,
                     o->img.run.sbs ? "" : e ? "_right" : "_left");
            (void)fv_tool_image_write_meta(path, &m);
        }
    }
}

/* --scene names neither a built-in scene nor a file: say what there is (the built-ins and the scene files in the
 * source tree's scenes/). false after printing that. */
static bool scene_exists_or_say(const char *name)
{
    struct stat sb;
    if (!strncmp(name, "builtin:", 8) || stat(name, &sb) == 0) return true;
    int err = errno; /* why the file is not there ("No such file or directory") */
    for (const char *const *b = fv_scene_builtin_names(); *b; b++)
        if (!strcmp(name, *b)) return true;
    char builtins[256] = "", files[1024] = "";
    for (const char *const *b = fv_scene_builtin_names(); *b; b++)
        snprintf(builtins + strlen(builtins), sizeof builtins - strlen(builtins), "%s%s", builtins[0] ? ", " : "", *b);
    DIR *d = opendir(FV_SOURCE_DIR "/scenes");
    for (struct dirent *e; d && (e = readdir(d));) {
        size_t n = strlen(e->d_name);
        if (n > 11 && !strcmp(e->d_name + n - 11, ".scene.json"))
            snprintf(files + strlen(files), sizeof files - strlen(files), "%s%s", files[0] ? ", " : "", e->d_name);
    }
    if (d) closedir(d);
    fprintf(stderr, "fovea run: --scene '%s': no built-in scene and no file of that name (%s). Built-in scenes: %s; "
            "scene files in %s/scenes: %s (or any *.scene.json, glTF, OBJ or PLY file)\n", name, strerror(err),
            builtins, FV_SOURCE_DIR, files[0] ? files : "none");
    return false;
}

/* The outermost directory of path that does not exist yet: what creating path makes (to take away again when the
 * run fails before its first frame). "" when path exists. */
static void first_missing_dir(const char *path, char *out, size_t cap)
{
    out[0] = '\0';
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", path);
    for (;;) {
        struct stat sb;
        if (stat(buf, &sb) == 0) return;
        snprintf(out, cap, "%s", buf);
        char *slash = strrchr(buf, '/');
        while (slash && slash > buf && slash[1] == '\0') { /* trailing slashes */
            *slash = '\0';
            slash = strrchr(buf, '/');
        }
        if (!slash || slash == buf) return;
        *slash = '\0';
    }
}

/* Remove the (empty) directories from path up to and including top, which creating path made. */
static void remove_created_dirs(const char *path, const char *top)
{
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", path);
    size_t top_len = strlen(top);
    while (strlen(buf) >= top_len && top_len) {
        if (rmdir(buf) != 0 && errno != ENOENT) return; /* not empty: something was written there */
        if (strlen(buf) == top_len) return;
        char *slash = strrchr(buf, '/');
        if (!slash) return;
        *slash = '\0';
    }
}

/* --frame-log: the rows drawn, with the latency records of a --gaze run and the GPU/CPU times measured. */
static fv_result write_frame_log(run_state *st, const run_gaze *gaze, const char *path)
{
    for (size_t i = 0; i < st->rows_n; i++) {
        run_frame_row *row = &st->rows[i];
        row->lat = gaze && gaze->records && i < gaze->count ? &gaze->records[i] : NULL;
        row->gpu_ms = i < st->m.measured && i < st->m.cap ? st->m.frame_gpu_ms[i] : NAN;
        row->cpu_ms = i < st->m.drawn && i < st->m.cap ? st->m.cpu_ms[i] : NAN;
    }
    return run_frame_log_write(path, st->rows, st->rows_n);
}

/* A window or a --gaze run on a software (CPU) Vulkan device starts where it stays interactive, unless the user chose
 * the size or the budget (fv_app_interactive.h); one line says so and how to override it. */
static void software_start(run_opts *o)
{
    if (!o->window && !o->img.run.gaze_uri) return;
    if (o->size_given || o->img.hmd.budget_given) return;
    fv_vk_device_info devs[16];
    uint32_t n = 0;
    int chosen = -1;
    char why[256];
    if (FV_FAILED(fv_vk_list_devices(NULL, devs, 16, &n, &chosen, why, sizeof why)) || chosen < 0 ||
        (uint32_t)chosen >= n)
        return; /* the renderer says why when it is made */
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    double hz = o->img.run.gaze_uri && !o->window ? o->hz : o->img.hmd.have ? (double)o->img.hmd.profile.refresh_hz : 90.0;
    fv_app_interactive_in in = {.software = devs[chosen].type == VK_PHYSICAL_DEVICE_TYPE_CPU, .interactive = true,
                                .eye_w = o->img.run.eye_w, .eye_h = o->img.run.eye_h, .hz = hz,
                                .cpu_cores = cores > 0 ? (uint32_t)cores : 1};
    fv_app_interactive st;
    fv_app_interactive_start(&in, &st);
    if (!st.applied) return;
    o->img.run.eye_w = st.eye_w;
    o->img.run.eye_h = st.eye_h;
    o->img.run.budget = st.budget;
    o->img.run.budget_scale = st.budget_scale;
    fprintf(stderr, "fovea run: %s is %s\n", devs[chosen].name, st.line);
}

/* --head trace (the default) with a recording whose head pose never moves: say so once. A recording with no usable
 * head pose (the trace readers drop all-zero poses: a logger without head tracking writes zeros) or one that stays
 * the same follows nothing, and without a word the user cannot tell it from a head held still. */
static void check_head_moves(run_state *st, bool at_end)
{
    if (st->head_warned || st->head.mode != FV_APP_HEAD_TRACE || !st->gaze || !st->gaze->tracker ||
        strncmp(st->gaze->uri, "trace:", 6) != 0)
        return;
    fv_app_head_report hr;
    fv_app_tracker_head_report(st->gaze->tracker, &hr);
    fv_gaze_source_status ss;
    fv_gaze_source_get_status(fv_app_tracker_source(st->gaze->tracker), &ss);
    if (hr.moved > 0 || ss.delivered == 0 || (!at_end && ss.delivered < RUN_HEAD_CHECK_SAMPLES)) return;
    if (hr.usable == 0)
        FV_WARN("run", "--head trace: '%s' has no head pose in its %llu samples (its head columns are empty or all "
                "zero): the head does not move; --head scene uses the scene's head without following",
                st->gaze->uri, (unsigned long long)ss.delivered);
    else
        FV_WARN("run", "--head trace: the %llu head poses of '%s' are all the same: the head does not move",
                (unsigned long long)hr.usable, st->gaze->uri);
    st->head_warned = true;
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
    fv_window *window = NULL;
    fv_mouse_views mouse_views = {0}; /* the eyes the cursor is over (window runs) */
    bool closed = false;
    int64_t frames_done = 0;
    run_state st;
    memset(&st, 0, sizeof st);
    st.o = &o;
    st.quality = o.img.quality;
    st.hmd = &o.img.hmd;
    run_gaze gaze;
    memset(&gaze, 0, sizeof gaze);
    bool gaze_open = false;
    st.gaze = &gaze;
    st.head.mode = o.img.run.head;
    char out_created[4096] = ""; /* the directory --out made, removed again if no frame is drawn */
    bool interrupted = false;
    fv_progress *progress = NULL;
    if (o.frame_log) {
        st.rows_cap = (size_t)o.frames;
        st.rows = calloc(st.rows_cap, sizeof *st.rows);
        if (!st.rows) {
            FV_ERROR("run", "out of memory for the frame log of %lld frames", (long long)o.frames);
            return FV_EXIT_FAIL;
        }
    }
    if (!scene_exists_or_say(o.img.run.scene)) {
        free(st.rows);
        return FV_EXIT_FAIL;
    }
    /* The tracker first: a source that is not there fails the run before any rendering work. Only the mouse, a gaze
     * source made of the window's cursor, opens once the window is there. */
    bool gaze_after_window = o.img.run.gaze_uri && !strncmp(o.img.run.gaze_uri, "mouse:", 6);
    if (o.img.run.gaze_uri && !gaze_after_window) {
        gaze_open = true;
        if (FV_FAILED(run_gaze_open(&gaze, o.img.run.gaze_uri, o.no_predict))) goto done; /* one line said why */
    }
    software_start(&o);
    if (FV_FAILED(fv_measure_init(&st.m, (size_t)o.frames))) {
        FV_ERROR("run", "out of memory for %lld frames", (long long)o.frames);
        free(st.rows);
        return FV_EXIT_FAIL;
    }
    bool saving = o.out_dir && o.save != SAVE_NONE;
    if (saving) {
        first_missing_dir(o.out_dir, out_created, sizeof out_created);
        if (!fv_cli_output_dir("run", "--out", o.out_dir)) goto done;
        fv_target_files_desc fd = {.dir = o.out_dir, .side_by_side = o.img.run.sbs, .linear_pfm = o.float_out,
                                   .save = o.save == SAVE_EVERY ? FV_TARGET_SAVE_EVERY : FV_TARGET_SAVE_LAST};
        if (FV_FAILED(fv_target_files_create(&fd, &files))) goto done;
    }
    if (FV_FAILED(fv_scene_load(o.img.run.scene, &scene))) {
        fprintf(stderr, "fovea run: cannot load scene '%s' (see the messages above)\n", o.img.run.scene);
        goto done;
    }
    if (o.window) {
        fv_window_desc wd = {.width = o.win_w, .height = o.win_h, .eye_width = o.img.run.eye_w, .eye_height = o.img.run.eye_h,
                             .title = "fovea", .present_mode = o.present_mode};
        if (!o.win_w && o.img.hmd.have && o.img.run.hmd) { /* a named HMD: its panel, scaled to fit the screen */
            wd.width = o.img.hmd.profile.panel_width_px;
            wd.height = o.img.hmd.profile.panel_height_px;
            wd.fit_to_screen = true;
        }
        if (FV_FAILED(fv_window_create(&wd, &window))) {
            fprintf(stderr, "fovea run: cannot open a window (see the messages above)\n");
            goto done;
        }
    }
    fv_renderer_desc desc = {.eye_width = o.img.run.eye_w, .eye_height = o.img.run.eye_h,
                             .target = window ? fv_window_target(window) : files};
    if (FV_FAILED(fv_renderer_create(&desc, &r))) {
        fprintf(stderr, "fovea run: cannot create the renderer (see the messages above)\n");
        goto done;
    }
    st.r = r;
    st.scene_head = scene->head;
    st.scene = scene;
    { /* Forcing multiview where it is known to mis-clip the second view: say so, once */
        const char *mv = getenv("FOVEA_MULTIVIEW");
        bool forced_on = mv && *mv && strcmp(mv, "0") != 0 && strcmp(mv, "false") != 0 && strcmp(mv, "off") != 0;
        if (forced_on && strstr(fv_renderer_device_name(r), "llvmpipe"))
            FV_WARN("run", "FOVEA_MULTIVIEW=%s forces multiview on %s, whose multiview mis-clips the second view: "
                    "the right eye may be wrong (unset it to draw each eye in its own pass)", mv,
                    fv_renderer_device_name(r));
    }
    /* The quality first, so that the scene's passes start once, with the settings they will run with. */
    if (FV_FAILED(fv_renderer_set_quality(r, &o.img.quality))) goto done;
    if (FV_FAILED(fv_renderer_load_scene(r, scene))) {
        fprintf(stderr, "fovea run: cannot upload scene '%s'\n", o.img.run.scene);
        goto done;
    }
    if (o.explain) print_plan(o.json ? stderr : stdout, fv_renderer_plan(r));
    if (run_hmd_budget_start(&o.img.hmd, &o.img.quality, fv_tool_quality_preset(&o.img.run.quality),
                             o.img.run.gaze_uri ? o.hz : o.img.hmd.have ? (double)o.img.hmd.profile.refresh_hz : 90.0,
                             fv_renderer_plan(r)) != 0)
        goto done;
    if (window) { /* the cursor over the window is a gaze source (mouse:) with these eyes */
        fv_frame_input fi; /* the frusta the frames are drawn with */
        fv_tool_image_frame_input(&o.img, scene, NULL, 0, 0.0, &fi);
        mouse_views.ipd_mm = fi.head.ipd_mm;
        for (int e = 0; e < 2; e++) {
            mouse_views.tan_left[e] = fi.eye[e].tan_left;
            mouse_views.tan_right[e] = fi.eye[e].tan_right;
            mouse_views.tan_up[e] = fi.eye[e].tan_up;
            mouse_views.tan_down[e] = fi.eye[e].tan_down;
        }
        fv_mouse_pointer_attach(&mouse_views);
    }
    if (gaze_after_window) {
        gaze_open = true;
        if (FV_FAILED(run_gaze_open(&gaze, o.img.run.gaze_uri, o.no_predict))) goto done; /* one line said why */
    }
    if (o.img.run.gaze_uri) {
        fv_display *shown_on = window ? fv_window_display(window) : NULL; /* NULL: a simulated display */
        if (FV_FAILED(run_gaze_start(&gaze, shown_on, o.hz, (size_t)o.frames, render_cb, &st, scene->head.ipd_mm))) {
            fprintf(stderr, "fovea run: cannot start the frame loop of gaze source '%s' (see the messages above)\n",
                    o.img.run.gaze_uri);
            goto done;
        }
    }

    int64_t t_start = fv_time_monotonic_ns();
    progress = fv_progress_start("fovea run", "frame", o.frames == RUN_WINDOW_MAX_FRAMES && !o.frames_given ? 0 : o.frames);
    int64_t t_title = t_start, title_frames = 0;
    for (int64_t f = 0; f < o.frames; f++) {
        if (fv_cli_interrupted() && f > 0) { /* Ctrl-C (cli_interrupt.h); one during start-up: the first frame */
            interrupted = true;
            break;
        }
        if (window) {
            if (!fv_window_poll(window)) {
                closed = true;
                break;
            }
            for (int key; (key = fv_window_next_key(window)) != 0;) window_key(&st, key);
            int eye;
            float u, v;
            if (fv_window_cursor(window, &eye, &u, &v)) {
                cursor_through_lens(&st.quality, &mouse_views, eye, &u, &v);
                fv_mouse_pointer_move(eye, u, v, fv_time_monotonic_ns());
            }
            int64_t now = fv_time_monotonic_ns();
            if (now - t_title >= FV_NS_PER_S / 2) {
                window_title(window, &st, (double)title_frames * 1e9 / (double)(now - t_title));
                t_title = now;
                title_frames = 0;
            }
            title_frames++;
        }
        int64_t t0 = fv_time_monotonic_ns();
        if (o.img.run.gaze_uri) {
            if (FV_FAILED(run_gaze_step(&gaze))) goto done;
        } else {
            fv_frame_input in;
            memset(&in, 0, sizeof in);
            in.frame_id = (uint64_t)f;
            if (FV_FAILED(draw_frame(&st, &in, false, NULL))) goto done;
        }
        fv_measure_wall(&st.m, (double)(fv_time_monotonic_ns() - t0) / 1e6);
        frames_done = f + 1;
        fv_progress_update(progress, frames_done, (int64_t)st.m.measured, fv_measure_gpu_ms_sum(&st.m));
        check_head_moves(&st, false);
    }
    if (fv_cli_interrupted()) interrupted = true; /* during the last frame */
    if (interrupted)
        fprintf(stderr, "fovea run: interrupted (Ctrl-C) after %lld of %lld frames\n", (long long)frames_done,
                (long long)o.frames);
    if (FV_FAILED(fv_renderer_finish(r)) || !fv_measure_take(&st.m, r)) goto done;
    fv_measure_run_wall(&st.m, (double)(fv_time_monotonic_ns() - t_start) / 1e6, (size_t)frames_done);
    fv_progress_update(progress, frames_done, (int64_t)st.m.measured, fv_measure_gpu_ms_sum(&st.m));
    fv_progress_stop(&progress);
    check_head_moves(&st, true);
    if (o.frame_log && FV_FAILED(write_frame_log(&st, o.img.run.gaze_uri ? &gaze : NULL, o.frame_log))) goto done;
    if (files && o.save == SAVE_LAST && FV_FAILED(fv_target_files_flush(files))) goto done;
    if (files) write_image_settings(&o, frames_done);
    double wall_s = (double)(fv_time_monotonic_ns() - t_start) / 1e9;
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    uint32_t vmsg = fv_renderer_validation_messages(r);

    if (o.json) {
        cJSON *j = cJSON_CreateObject();
        fv_cli_json_add_string(j, "scene", scene->name[0] ? scene->name : o.img.run.scene);
        fv_cli_json_add_string(j, "device", fv_renderer_device_name(r));
        cJSON_AddNumberToObject(j, "frames", (double)frames_done);
        cJSON_AddNumberToObject(j, "eye_width", o.img.run.eye_w);
        cJSON_AddNumberToObject(j, "eye_height", o.img.run.eye_h);
        cJSON_AddNumberToObject(j, "triangles", (double)fv_scene_triangle_count(scene));
        fv_measure_add_json(&st.m, j);
        fv_measure_add_fovea_json(&st.m, r, j);
        fv_measure_add_gi_json(&st.m, r, j);
        cJSON_AddNumberToObject(j, "peak_host_rss_mib", (double)ru.ru_maxrss / 1024.0);
        cJSON_AddNumberToObject(j, "wall_s", wall_s);
        cJSON_AddNumberToObject(j, "validation_messages", vmsg);
        cJSON *jq = cJSON_AddObjectToObject(j, "quality");
        cJSON_AddNumberToObject(jq, "exposure", o.img.quality.exposure);
        fv_cli_json_add_string(jq, "debug_view", fv_debug_view_name(o.img.quality.debug_view));
        fv_tool_quality_add_json(jq, fv_tool_quality_preset(&o.img.run.quality), &o.img.quality);
        run_hmd_add_json(&o.img.hmd, r, j);
        if (o.explain) {
            const fv_frame_plan *plan = fv_renderer_plan(r);
            cJSON *pl = cJSON_AddArrayToObject(j, "plan");
            for (uint32_t i = 0; i < plan->count; i++) {
                cJSON *e = cJSON_CreateObject();
                fv_cli_json_add_string(e, "pass", plan->entries[i].pass);
                cJSON_AddBoolToObject(e, "enabled", plan->entries[i].enabled);
                fv_cli_json_add_string(e, "reason", plan->entries[i].reason);
                if (plan->entries[i].io[0]) fv_cli_json_add_string(e, "images", plan->entries[i].io);
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
        if (o.img.run.gaze_uri && window) snprintf(gaze.clock, sizeof gaze.clock, "swapchain: %s", fv_window_clock_name(window));
        if (o.img.run.gaze_uri) run_gaze_add_json(&gaze, j);
        if (window) {
            fv_window_stats ws;
            fv_window_get_stats(window, &ws);
            cJSON *jp = cJSON_AddObjectToObject(j, "present");
            fv_cli_json_add_string(jp, "target", "window");
            fv_cli_json_add_string(jp, "clock", fv_window_clock_name(window));
            cJSON_AddNumberToObject(jp, "refresh_hz", fv_window_display(window)->refresh_hz);
            cJSON_AddBoolToObject(jp, "refresh_measured", ws.refresh_measured);
            cJSON_AddNumberToObject(jp, "vsync_events", (double)ws.vsync_events);
            fv_cli_json_add_string(jp, "present_mode", ws.present_mode);
            cJSON_AddNumberToObject(jp, "presents", (double)ws.presents);
            cJSON_AddNumberToObject(jp, "skipped", (double)ws.skipped);
            cJSON_AddNumberToObject(jp, "swapchains", ws.swapchain_creations);
            cJSON_AddNumberToObject(jp, "out_of_date", ws.out_of_date);
            cJSON_AddNumberToObject(jp, "width", ws.width);
            cJSON_AddNumberToObject(jp, "height", ws.height);
            cJSON_AddBoolToObject(jp, "separate_present_queue", ws.separate_present_queue);
            cJSON_AddBoolToObject(jp, "closed_by_user", closed);
        } else {
            cJSON *jp = cJSON_AddObjectToObject(j, "present");
            fv_cli_json_add_string(jp, "target", saving ? "files" : "headless");
        }
        int printed = fv_cli_json_print(j, false);
        cJSON_Delete(j);
        if (printed != FV_EXIT_OK) goto done;
    } else {
        printf("fovea run: scene '%s' on %s, %lld frame%s at %ux%u per eye (%llu triangles), %.2f s\n",
               scene->name[0] ? scene->name : o.img.run.scene, fv_renderer_device_name(r), (long long)frames_done,
               frames_done == 1 ? "" : "s", o.img.run.eye_w, o.img.run.eye_h, (unsigned long long)fv_scene_triangle_count(scene),
               wall_s);
        fv_measure_print(&st.m, stdout);
        fv_measure_print_fovea(&st.m, r, stdout);
        fv_measure_print_gi(&st.m, r, stdout);
        fv_tool_quality_print(stdout, fv_tool_quality_preset(&o.img.run.quality), &o.img.quality);
        run_hmd_print(&o.img.hmd, r, stdout);
        printf("  memory: %.1f MiB device (peak), %.1f MiB host RSS (peak); validation messages: %u\n",
               (double)st.m.last_stats.peak_device_memory_bytes / 1048576.0, (double)ru.ru_maxrss / 1024.0, vmsg);
        if (o.img.run.gaze_uri && window) snprintf(gaze.clock, sizeof gaze.clock, "swapchain: %s", fv_window_clock_name(window));
        if (o.img.run.gaze_uri) run_gaze_print(&gaze, stdout);
        if (saving) printf("  images: %s/\n", o.out_dir);
        if (window) {
            fv_window_stats ws;
            fv_window_get_stats(window, &ws);
            printf("  window: %llu frames presented (%s, %ux%u, %u swapchain%s, %llu not shown), display clock: %s "
                   "at %.2f Hz (%s)%s\n", (unsigned long long)ws.presents, ws.present_mode, ws.width, ws.height,
                   ws.swapchain_creations, ws.swapchain_creations == 1 ? "" : "s", (unsigned long long)ws.skipped,
                   fv_window_clock_name(window), fv_window_display(window)->refresh_hz,
                   ws.refresh_measured ? "measured from the vsyncs" : "assumed: no present waited for a vsync",
                   closed ? "; closed by the user" : "");
        }
    }
    fflush(stdout); /* the summary is out even if a second Ctrl-C ends the process during the clean-up */
    if (vmsg > 0) {
        fprintf(stderr, "fovea run: %u Vulkan validation message%s (see above)\n", vmsg, vmsg == 1 ? "" : "s");
        goto done;
    }
    exit_code = interrupted ? FV_EXIT_INTERRUPTED : FV_EXIT_OK; /* 128 + SIGINT, as a shell reports it */
done:
    fv_progress_stop(&progress);
    if (exit_code != FV_EXIT_OK && exit_code != FV_EXIT_INTERRUPTED && frames_done == 0 && out_created[0])
        remove_created_dirs(o.out_dir, out_created);
    free(st.rows);
    if (gaze_open) run_gaze_close(&gaze);
    if (window) fv_mouse_pointer_detach();
    fv_measure_fini(&st.m);
    fv_renderer_destroy(&r);
    fv_window_destroy(&window); /* after the renderer: its swapchain went with the device */
    fv_target_destroy(&files);
    fv_scene_destroy(&scene);
    return exit_code;
}
