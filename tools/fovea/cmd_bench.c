/* @brief `fovea bench`: the speed/accuracy trade as curves. For each point of the cross product of --sweep knobs,
 * render N frames of the same views, take each pass's GPU time (median, p95) and measure the image against the exact
 * preset on the GPU and against the CPU reference; write bench.json, bench.csv and one time-against-error plot per
 * swept knob with its Pareto front. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench_report.h"
#include "bench_sweep.h"
#include "cli.h"
#include "cli_interrupt.h"
#include "cli_progress.h"
#include "tool_image.h"
#include "fv_clock.h"
#include "fv_log.h"
#include "fv_metrics.h"
#include "fv_reference.h"
#include "fv_renderer.h"
#include "fv_scene.h"
#include "fv_stats.h"
#include "run_hmd.h"
#include "run_measure.h"
#include "tool_knobs.h"

#define MOD "bench"
#define WARMUP_FRAMES 2u

/* The usage; %s: the preset names, %d: the point cap. */
static const char *USAGE_FMT =
    "usage: fovea bench --sweep NAME=V1,V2,... [--sweep ...] [--scene NAME|FILE] [--quality PRESET]\n"
    "                   [--set NAME=VALUE]... [--frames N] [--eye-size WxH] [--gaze-deg YAW,PITCH]\n"
    "                   [--reference model|path|none] [--spp N] [--out DIR] [--hmd PROFILE|FILE] [--json]\n"
    "                   [--baseline-set NAME=VALUE]...\n"
    "                   [--bounces N]\n"
    "                   [--exact on|off]\n"
    "  --sweep     a knob and the values to try (repeatable); the points are the cross product of the sweeps\n"
    "              (at most %d). NAME=VALUE is checked as --set checks it; `fovea knobs` lists the knobs.\n"
    "              The pseudo-knob `preset` sweeps the presets: --sweep preset=%s\n"
    "  --scene     as fovea run (default cornell)\n"
    "  --quality   the preset every point starts from: %s (default balanced)\n"
    "  --set       one knob after the preset (repeatable); each point's sweep values come last\n"
    "  --frames    frames per point (default 10; 3..100000): the first 2 warm up and are not timed; every frame\n"
    "              has the same views (scene time 0) and waits for the one before\n"
    "  --eye-size  per-eye size (default 720x800; at least 11x11, the SSIM window)\n"
    "  --gaze-deg  the gaze in the head frame, degrees (yaw positive right, pitch positive up): given to the\n"
    "              renderer, and the errors are also given per eccentricity band around it\n"
    "  --reference the CPU reference to measure against, rendered once: model (default: fovea's shading with\n"
    "              exact visibility), path (path-traced ground truth, --spp samples, --bounces) or none\n"
    "  --spp       samples per pixel of the path reference (default 64; 1..1048576)\n"
    "  --bounces   indirect bounces of the path reference (default 8; 0..1024; 1 = the one-bounce truth of GI)\n"
    "  --out       where bench.json, bench.csv and pareto_<knob>.png go (default out/bench; created)\n"
    "  --json      print bench.json as one JSON object on stdout (and nothing else there)\n"
    "  --baseline-set  measure every point against the --quality preset (with --set) plus this knob (repeatable)\n"
    "              instead of the exact preset, e.g. interp.enabled=0: the trade of one technique alone\n"
    "  --hmd       distort and mask every point for this HMD's lens (fovea run --hmd; default none: undistorted)\n"
    "  --exact     off: skip the `exact` preset on the GPU (its GI alone takes minutes a frame at 720x800 on a\n"
    "              CPU); the vs_exact errors are then null (default on)\n"
    "  Foveated points (fovea.enabled) are also measured against full-resolution shading of the same model (their\n"
    "  knobs with fovea.enabled off; per eccentricity band with --gaze-deg; bands_<knob>.png).\n"
    "  Every point is also measured against the `exact` preset on the GPU (same scene, views and size). Errors:\n"
    "  psnr_db and ssim on the sRGB values (as fovea compare), rel_mean on the linear values; both eyes side by\n"
    "  side. The plots show frame time against 1 - SSIM vs the reference (vs exact with --reference none).\n";

static const char *usage_text(void)
{
    static char text[4096];
    if (!text[0]) {
        char names[128];
        snprintf(names, sizeof names, "%s", fv_quality_preset_names());
        for (char *c = names; *c; c++) /* "fast, balanced" -> "fast,balanced" for the example */
            if (*c == ' ') memmove(c, c + 1, strlen(c));
        snprintf(text, sizeof text, USAGE_FMT, FV_BENCH_MAX_POINTS, names, fv_quality_preset_names());
    }
    return text;
}
#define USAGE usage_text()

typedef enum ref_kind { REF_MODEL, REF_PATH, REF_NONE } ref_kind;

typedef struct bench_opts {
    fv_app_run run;       /* the description of the run (runtime/app), as `fovea run` has it: scene, eye size, HMD
                             (here "none" by default: no lens); its quality choice is the plan's (plan.tq) */
    fv_bench_plan plan;
    fv_quality base;      /* --quality then --set: what is_preset compares with */
    int64_t frames;
    bool has_gaze;
    double gaze_deg[2];
    ref_kind ref;
    int64_t spp;
    int64_t bounces; /* --bounces: the path reference's indirect bounces */
    const char *out_dir;
    bool json;
    bool no_exact;        /* --exact off */
    fv_lens lens;
    const char *baseline_sets[8]; /* --baseline-set: the baseline is o->base with these (none: the exact preset) */
    uint32_t baseline_count;
} bench_opts;

static int parse_args(int argc, char **argv, bench_opts *o)
{
    memset(o, 0, sizeof *o);
    fv_app_run_defaults(&o->run);
    o->run.hmd = "none"; /* --hmd: the lens every point (and exact) is drawn with */
    o->frames = 10;
    o->ref = REF_MODEL;
    o->spp = 64;
    o->bounces = 8;
    o->out_dir = "out/bench";
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = NULL;
        int r;
        if (fv_cli_is_help(a)) {
            fputs(USAGE, stdout);
            fv_tool_knobs_help(stdout);
            return -1;
        }
#define OPT(name) FV_CLI_OPT("bench", USAGE, name)
        if ((r = OPT("--sweep")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            char err[512];
            if (FV_FAILED(fv_bench_plan_add(&o->plan, v, err, sizeof err)))
                return fv_cli_usage_error("bench", USAGE, "--sweep: %s", err);
            const fv_bench_sweep *sw = &o->plan.sweeps[o->plan.sweep_count - 1];
            if (sw->dropped_count)
                fprintf(stderr, "fovea bench: warning: --sweep %s: %zu value%s repeat%s an earlier one and %s benched "
                        "once: %s\n", sw->name, sw->dropped_count, sw->dropped_count == 1 ? "" : "s",
                        sw->dropped_count == 1 ? "s" : "", sw->dropped_count == 1 ? "is" : "are", sw->dropped);
            continue;
        }
        if ((r = OPT("--scene")) == -2) return FV_EXIT_USAGE;
        else if (r) { o->run.scene = v; continue; }
        if ((r = OPT("--frames")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_cli_parse_i64(v, WARMUP_FRAMES + 1, 100000, &o->frames))
                return fv_cli_usage_error("bench", USAGE, "--frames: '%s' is not a whole number in %u..100000", v,
                                          WARMUP_FRAMES + 1);
            continue;
        }
        if ((r = OPT("--eye-size")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_cli_parse_size(v, FV_APP_RUN_MAX_EYE_SIZE, &o->run.eye_w, &o->run.eye_h) ||
                o->run.eye_w < FV_METRICS_SSIM_WIN || o->run.eye_h < FV_METRICS_SSIM_WIN)
                return fv_cli_usage_error("bench", USAGE, "--eye-size: '%s' is not WxH with each in %d..%u", v,
                                          FV_METRICS_SSIM_WIN, FV_APP_RUN_MAX_EYE_SIZE);
            continue;
        }
        if ((r = OPT("--gaze-deg")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_cli_parse_f64_pair(v, -180.0, 180.0, o->gaze_deg) || fabs(o->gaze_deg[1]) > 90.0)
                return fv_cli_usage_error("bench", USAGE,
                                          "--gaze-deg: '%s' is not YAW,PITCH in degrees (yaw -180..180, pitch -90..90)",
                                          v);
            o->has_gaze = true;
            continue;
        }
        if ((r = OPT("--reference")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (strcmp(v, "model") == 0) o->ref = REF_MODEL;
            else if (strcmp(v, "path") == 0) o->ref = REF_PATH;
            else if (strcmp(v, "none") == 0) o->ref = REF_NONE;
            else return fv_cli_usage_error("bench", USAGE, "--reference: '%s' is not one of model, path, none", v);
            continue;
        }
        if ((r = OPT("--spp")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_cli_parse_i64(v, 1, FV_REFERENCE_MAX_SPP, &o->spp))
                return fv_cli_usage_error("bench", USAGE, "--spp: '%s' is not a whole number in 1..%u", v,
                                          FV_REFERENCE_MAX_SPP);
            continue;
        }
        if ((r = OPT("--bounces")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (!fv_cli_parse_i64(v, 0, FV_REFERENCE_MAX_BOUNCES, &o->bounces))
                return fv_cli_usage_error("bench", USAGE, "--bounces: '%s' is not a whole number in 0..%u", v,
                                          FV_REFERENCE_MAX_BOUNCES);
            continue;
        }
        if ((r = OPT("--out")) == -2) return FV_EXIT_USAGE;
        else if (r) { o->out_dir = v; continue; }
        if ((r = OPT("--baseline-set")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            char err[512];
            fv_quality scratch = fv_quality_default();
            if (o->baseline_count >= sizeof o->baseline_sets / sizeof o->baseline_sets[0])
                return fv_cli_usage_error("bench", USAGE, "--baseline-set: at most %zu",
                                          sizeof o->baseline_sets / sizeof o->baseline_sets[0]);
            if (FV_FAILED(fv_quality_set(&scratch, v, err, sizeof err)))
                return fv_cli_usage_error("bench", USAGE, "--baseline-set: %s", err);
            o->baseline_sets[o->baseline_count++] = v;
            continue;
        }
        if ((r = OPT("--hmd")) == -2) return FV_EXIT_USAGE;
        else if (r) {
            if (run_hmd_lens("bench", v, &o->lens) != 0) return FV_EXIT_FAIL;
            o->run.hmd = v;
            continue;
        }
#undef OPT
        if ((r = fv_tool_quality_option(&o->plan.tq, argc, argv, &i, "bench", USAGE)) == FV_EXIT_USAGE) return r;
        else if (r) continue;
        if (strcmp(a, "--json") == 0) { o->json = true; continue; }
        if (strcmp(a, "--exact") == 0) {
            const char *x = i + 1 < argc ? argv[++i] : "";
            if (strcmp(x, "on") == 0) o->no_exact = false;
            else if (strcmp(x, "off") == 0) o->no_exact = true;
            else return fv_cli_usage_error("bench", USAGE, "--exact: '%s' is not on or off", x);
            continue;
        }
        return fv_cli_usage_error("bench", USAGE, "unknown option '%s'", a);
    }
    if (o->plan.sweep_count == 0)
        return fv_cli_usage_error("bench", USAGE,
                                  "needs at least one --sweep NAME=V1,V2,... (e.g. shadow.splits=1,2,4)");
    size_t n = fv_bench_plan_points(&o->plan);
    if (n > FV_BENCH_MAX_POINTS) {
        if (n == SIZE_MAX)
            return fv_cli_usage_error("bench", USAGE, "--sweep: the sweeps make more than %d points",
                                      FV_BENCH_MAX_POINTS);
        return fv_cli_usage_error("bench", USAGE,
                                  "--sweep: the sweeps make %zu points, more than %d; sweep fewer values", n,
                                  FV_BENCH_MAX_POINTS);
    }
    return fv_tool_quality_build(&o->plan.tq, "bench", USAGE, &o->base);
}

/* ---- rendering ----------------------------------------------------------------------------------------------- */

typedef struct bench_state {
    const bench_opts *o;
    fv_renderer *r;
    fv_frame_input views; /* frame 0's views and gaze: every frame draws these */
    uint64_t next_frame;  /* frame ids rise over the whole run */
    float *rgba;          /* one eye's read-back */
    bool tty;
    int64_t t_start_ns;
    fv_progress *prog;    /* the progress line (cli_progress.h) */
    double gpu_ms;        /* GPU time of the points' timed frames so far */
} bench_state;

/* Median and p95 of a finished series (sorted in place). */
static fv_bench_ms summarise(double *ms, size_t n)
{
    return (fv_bench_ms){fv_percentile_f64(ms, n, 50), fv_percentile_f64(ms, n, 95)};
}

/* Render the point's frames and read its last image (both eyes side by side, linear) into img. */
static fv_result bench_point(bench_state *st, const fv_quality *q, fv_bench_point *out, fv_rgb_image *img)
{
    const bench_opts *o = st->o;
    fv_measure m;
    FV_TRY(fv_measure_init(&m, (size_t)o->frames));
    fv_result res = fv_renderer_set_quality(st->r, q);
    for (int64_t f = 0; f < o->frames && !FV_FAILED(res); f++) {
        if (fv_cli_interrupted()) { /* Ctrl-C: the point is not finished, the caller reports the ones that are */
            res = FV_ERR_CANCELLED;
            break;
        }
        fv_frame_input in = st->views;
        in.frame_id = st->next_frame++;
        in.quality = *q;
        res = fv_renderer_draw(st->r, &in);
        if (!FV_FAILED(res)) res = fv_renderer_finish(st->r); /* frames do not overlap: each is timed alone */
        if (FV_FAILED(res)) break;
        if ((uint64_t)f + 1 == WARMUP_FRAMES) fv_measure_skip(&m, st->r);
        else if ((uint64_t)f >= WARMUP_FRAMES && !fv_measure_take(&m, st->r)) res = FV_ERR_NO_MEMORY;
    }
    if (!FV_FAILED(res)) {
        out->pass_count = m.pass_count;
        for (uint32_t p = 0; p < m.pass_count; p++) {
            snprintf(out->pass_name[p], sizeof out->pass_name[p], "%s", m.passes[p].name);
            out->pass[p] = summarise(m.passes[p].ms, m.passes[p].n);
        }
        out->frame = summarise(m.frame_gpu_ms, m.measured);
        out->frames_timed = m.measured;
    }
    st->gpu_ms += fv_measure_gpu_ms_sum(&m);
    fv_measure_fini(&m);
    for (int e = 0; e < 2; e++) out->sampled_fraction[e] = out->cache_hit_fraction[e] = NAN;
    fv_pass_detail d[8];
    uint32_t nd = q->fovea.enabled ? fv_renderer_pass_details(st->r, "compact", d, 8) : 0;
    for (uint32_t i = 0; i < nd; i++)
        if (strcmp(d[i].key, "sampled_fraction") == 0) out->sampled_fraction[0] = d[i].value[0], out->sampled_fraction[1] = d[i].value[1];
    nd = q->fovea.enabled ? fv_renderer_pass_details(st->r, "temporal", d, 8) : 0;
    for (uint32_t i = 0; i < nd; i++)
        if (strcmp(d[i].key, "cache_hit_fraction") == 0)
            out->cache_hit_fraction[0] = d[i].value[0], out->cache_hit_fraction[1] = d[i].value[1];
    uint32_t w = o->run.eye_w, h = o->run.eye_h;
    for (int eye = 0; eye < 2 && !FV_FAILED(res); eye++) {
        res = fv_renderer_read_linear(st->r, eye, st->rgba, (size_t)w * h * 4);
        for (uint32_t y = 0; y < h && !FV_FAILED(res); y++)
            for (uint32_t x = 0; x < w; x++) {
                const float *s = &st->rgba[((size_t)y * w + x) * 4];
                float *d = &img->rgb[((size_t)y * 2 * w + (size_t)eye * w + x) * 3];
                d[0] = s[0], d[1] = s[1], d[2] = s[2];
            }
    }
    return res;
}

/* The CPU reference's tiles, as the progress line's detail. */
static void reference_tiles(void *user, uint64_t done, uint64_t total)
{
    char line[96];
    snprintf(line, sizeof line, "the CPU reference: %llu/%llu tiles", (unsigned long long)done,
             (unsigned long long)total);
    fv_progress_detail(user, line);
}

/* The CPU reference of frame 0's views, both eyes side by side, into img; *out_s: its wall time; prog: the progress
 * line (NULL: none). */
static fv_result render_reference(const bench_opts *o, const fv_scene *scene, const fv_frame_input *views,
                                  const fv_quality *exact, fv_rgb_image *img, double *out_s, uint32_t *out_spp,
                                  uint32_t *out_bounces, fv_progress *prog)
{
    uint32_t w = o->run.eye_w, h = o->run.eye_h;
    /* model: the same model as the points' exact counterpart (its GI and SSS settings, its lens mask), so that the
     * error measures the knob and not a missing term; path: the ground truth, the model's own bias included */
    fv_frame_input in_exact = *views;
    in_exact.quality = *exact;
    const fv_frame_input *in = &in_exact;
    fv_reference_desc d = {.mode = o->ref == REF_PATH ? FV_REFERENCE_PATH : FV_REFERENCE_MODEL,
                           .view = FV_REFERENCE_VIEW_COLOR, .spp = o->ref == REF_PATH ? (uint32_t)o->spp : 1,
                           .bounces = (uint32_t)o->bounces, .seed = 1, .eye_width = w, .eye_height = h,
                           .gi = exact->gi.enabled};
    *out_spp = d.spp;
    *out_bounces = d.bounces;
    float *eyes = malloc((size_t)w * h * 3 * 2 * sizeof *eyes);
    if (!eyes) return FV_ERR_NO_MEMORY;
    fv_progress_phase(prog, "the CPU reference");
    if (prog) d.progress = reference_tiles, d.progress_user = prog;
    int64_t t0 = fv_time_monotonic_ns();
    d.cancelled = fv_cli_interrupted;
    fv_result res = fv_reference_render(scene, in, &d, eyes, eyes + (size_t)w * h * 3, NULL);
    *out_s = (double)(fv_time_monotonic_ns() - t0) / 1e9;
    for (int eye = 0; eye < 2 && !FV_FAILED(res); eye++) /* the pixels the GPU's lens mask never shades */
        fv_tool_image_mask_linear(in, eye, eyes + (size_t)eye * w * h * 3, w, h);
    for (int eye = 0; eye < 2 && !FV_FAILED(res); eye++)
        for (uint32_t y = 0; y < h; y++)
            memcpy(&img->rgb[((size_t)y * 2 * w + (size_t)eye * w) * 3], &eyes[((size_t)eye * h + y) * w * 3],
                   (size_t)w * 3 * sizeof *eyes);
    free(eyes);
    return res;
}

/* first: the points' phase begins (the time left is estimated from the points alone) */
static void progress(bench_state *st, size_t i, size_t n, const fv_bench_plan *plan, const fv_bench_point *p,
                     bool first)
{
    char line[512];
    int len = snprintf(line, sizeof line, "point %zu/%zu", i + 1, n);
    for (size_t s = 0; s < plan->sweep_count && len > 0 && (size_t)len < sizeof line; s++)
        len += snprintf(line + len, sizeof line - (size_t)len, " %s=%s", plan->sweeps[s].name,
                        plan->sweeps[s].values[p->value_index[s]]);
    fv_progress_update(st->prog, -1, (int64_t)i, st->gpu_ms);
    if (first) fv_progress_phase(st->prog, line);
    else fv_progress_detail(st->prog, line);
}

/* ---- output -------------------------------------------------------------------------------------------------- */

static void print_table(const fv_bench_result *res, const char *out_dir, size_t plots)
{
    const fv_bench_plan *plan = res->plan;
    printf("fovea bench: scene '%s' on %s, %ux%u per eye, preset %s, %zu point%s of %u frames (%u warm-up)\n",
           res->scene, res->device, res->eye_width, res->eye_height, res->preset, res->point_count,
           res->point_count == 1 ? "" : "s", res->frames, res->warmup_frames);
    if (!res->has_exact)
        printf("  reference: %s; %s: not rendered (--exact off)\n", res->reference_mode,
               strcmp(res->exact.preset, "exact") ? "the baseline (--baseline-set)" : "exact preset");
    else if (res->has_reference)
        printf("  reference: %s, %u spp, %.2f s; %s on the GPU: %.3f ms median, %.2f dB and SSIM %.5f vs "
               "the reference\n", res->reference_mode, res->reference_spp, res->reference_s,
               strcmp(res->exact.preset, "exact") ? "the baseline (--baseline-set)" : "exact preset",
               res->exact.frame.median_ms,
               res->exact.vs_reference.all.psnr_db, res->exact.vs_reference.all.ssim);
    else
        printf("  reference: none; %s on the GPU: %.3f ms median\n",
               strcmp(res->exact.preset, "exact") ? "the baseline (--baseline-set)" : "exact preset",
               res->exact.frame.median_ms);
    for (size_t s = 0; s < plan->sweep_count; s++)
        printf("  %-*s", (int)strlen(plan->sweeps[s].name), plan->sweeps[s].name);
    printf("  %9s %9s  %9s %9s", "frame ms", "p95 ms", "exact dB", "ssim");
    if (res->has_reference) printf("  %9s %9s %9s", "ref dB", "ssim", "rel mean");
    printf("\n");
    for (size_t i = 0; i < res->point_count; i++) {
        const fv_bench_point *p = &res->points[i];
        for (size_t s = 0; s < plan->sweep_count; s++)
            printf("  %-*s", (int)strlen(plan->sweeps[s].name), plan->sweeps[s].values[p->value_index[s]]);
        char a[32], b[32], c[32], d[32], e[32];
        printf("  %9.3f %9.3f  %9s %9s", p->frame.median_ms, p->frame.p95_ms,
               fv_cli_format_number(a, sizeof a, "%.2f", p->vs_exact.all.psnr_db),
               fv_cli_format_number(b, sizeof b, "%.5f", p->vs_exact.all.ssim));
        if (res->has_reference)
            printf("  %9s %9s %9s", fv_cli_format_number(c, sizeof c, "%.2f", p->vs_reference.all.psnr_db),
                   fv_cli_format_number(d, sizeof d, "%.5f", p->vs_reference.all.ssim),
                   fv_cli_format_number(e, sizeof e, "%.4g", p->vs_reference.all.rel_mean));
        printf("%s\n", p->is_preset ? "   <- the preset's own values" : "");
    }
    /* foveated points against full-resolution shading of the same model */
    bool any = false;
    for (size_t i = 0; i < res->point_count; i++) any = any || res->points[i].has_vs_full;
    if (any) {
        printf("  foveated vs full resolution (same model): sampled %%, cache hits %%, frame and shade time ratios,"
               " PSNR dB whole / per band (deg)");
        for (int k = 0; k < FV_METRICS_BANDS && res->has_gaze; k++)
            printf(" %g-%g", fv_metrics_band_edges_deg[k], fv_metrics_band_edges_deg[k + 1]);
        printf("\n");
    }
    for (size_t i = 0; any && i < res->point_count; i++) {
        const fv_bench_point *p = &res->points[i];
        if (!p->has_vs_full) continue;
        double shade = NAN;
        for (uint32_t k = 0; k < p->pass_count; k++)
            if (strcmp(p->pass_name[k], "shade") == 0) shade = p->pass[k].median_ms;
        char a[32];
        printf("  ");
        for (size_t s = 0; s < plan->sweep_count; s++)
            printf("%s=%s ", plan->sweeps[s].name, plan->sweeps[s].values[p->value_index[s]]);
        printf("| %.2f / %.2f | %.1f / %.1f | frame %.3f shade %.3f | %s", 100.0 * p->sampled_fraction[0],
               100.0 * p->sampled_fraction[1], 100.0 * p->cache_hit_fraction[0], 100.0 * p->cache_hit_fraction[1],
               p->frame.median_ms / p->vs_full_frame_ms, shade / p->vs_full_shade_ms,
               fv_cli_format_number(a, sizeof a, "%.2f", p->vs_full.all.psnr_db));
        for (int k = 0; k < FV_METRICS_BANDS && p->vs_full.has_bands; k++)
            printf(" %s", fv_cli_format_number(a, sizeof a, "%.2f", p->vs_full.band[k].psnr_db));
        printf("\n");
    }
    printf("  files: %s/bench.json, %s/bench.csv", out_dir, out_dir);
    if (plots) printf(", %zu plot%s (pareto_<knob>.png)", plots, plots == 1 ? "" : "s");
    printf("\n");
}

static fv_result write_json_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f || fputs(text, f) < 0 || fputc('\n', f) < 0) {
        if (f) fclose(f);
        FV_ERROR(MOD, "%s: cannot write (%s)", path, strerror(errno));
        return FV_ERR_IO;
    }
    if (fclose(f) != 0) {
        FV_ERROR(MOD, "%s: cannot write (%s)", path, strerror(errno));
        return FV_ERR_IO;
    }
    return FV_OK;
}

/* Full-resolution images of the same model as foveated points (their knobs with fovea.enabled off and the fovea
 * knobs at the preset's, which then change nothing): rendered once each, kept for the points that share them. */
#define FULL_CACHE 4
typedef struct full_cache {
    fv_quality quality[FULL_CACHE];
    fv_rgb_image img[FULL_CACHE];
    double frame_ms[FULL_CACHE], shade_ms[FULL_CACHE];
    int count, next;
} full_cache;

static fv_result vs_full_resolution(bench_state *st, full_cache *c, fv_bench_point *p, const fv_rgb_image *img,
                                    fv_metrics_desc *md)
{
    fv_quality q = p->quality;
    q.fovea = st->o->base.fovea;
    q.fovea.enabled = false;
    int k = -1;
    for (int i = 0; i < c->count && k < 0; i++)
        if (fv_quality_equal(&c->quality[i], &q)) k = i;
    if (k < 0) {
        k = c->count < FULL_CACHE ? c->count++ : c->next;
        c->next = (k + 1) % FULL_CACHE;
        if (!c->img[k].rgb) FV_TRY(fv_rgb_image_init(&c->img[k], img->width, img->height, FV_IMAGE_KIND_LINEAR));
        fv_bench_point fp;
        memset(&fp, 0, sizeof fp);
        c->quality[k] = q;
        fv_result res = bench_point(st, &q, &fp, &c->img[k]);
        if (FV_FAILED(res)) {
            c->count = k; /* not kept */
            return res;
        }
        c->frame_ms[k] = fp.frame.median_ms;
        c->shade_ms[k] = NAN;
        for (uint32_t i = 0; i < fp.pass_count; i++)
            if (strcmp(fp.pass_name[i], "shade") == 0) c->shade_ms[k] = fp.pass[i].median_ms;
    }
    md->name_b = "full resolution";
    FV_TRY(fv_metrics_compare(img, &c->img[k], md, &p->vs_full));
    p->has_vs_full = true;
    p->vs_full_frame_ms = c->frame_ms[k];
    p->vs_full_shade_ms = c->shade_ms[k];
    return FV_OK;
}

int fv_cmd_bench(int argc, char **argv)
{
    bench_opts o;
    int pr = parse_args(argc, argv, &o);
    if (pr == -1) return FV_EXIT_OK;
    if (pr != 0) return pr;

    int exit_code = FV_EXIT_FAIL;
    size_t n = fv_bench_plan_points(&o.plan);
    uint32_t w = o.run.eye_w, h = o.run.eye_h;
    fv_scene *scene = NULL;
    fv_renderer *r = NULL;
    fv_bench_point *points = calloc(n, sizeof *points);
    fv_rgb_image exact_img = {0}, ref_img = {0}, img = {0};
    float *ecc = NULL;
    full_cache full = {0};
    bench_state st = {.o = &o, .tty = isatty(STDERR_FILENO), .t_start_ns = fv_time_monotonic_ns()};
    st.rgba = malloc((size_t)w * h * 4 * sizeof *st.rgba);
    char err[512];
    if (!points || !st.rgba || FV_FAILED(fv_rgb_image_init(&exact_img, 2 * w, h, FV_IMAGE_KIND_LINEAR)) ||
        FV_FAILED(fv_rgb_image_init(&img, 2 * w, h, FV_IMAGE_KIND_LINEAR))) {
        FV_ERROR(MOD, "out of memory for %zu points at %ux%u per eye", n, w, h);
        goto done;
    }
    if (!fv_cli_make_dirs(o.out_dir)) {
        FV_ERROR(MOD, "--out %s: cannot create directory (%s)", o.out_dir, strerror(errno));
        goto done;
    }
    if (FV_FAILED(fv_scene_load(o.run.scene, &scene))) {
        fprintf(stderr, "fovea bench: cannot load scene '%s' (see the messages above)\n", o.run.scene);
        goto done;
    }
    fv_renderer_desc desc = {.eye_width = w, .eye_height = h};
    if (FV_FAILED(fv_renderer_create(&desc, &r))) {
        fprintf(stderr, "fovea bench: cannot create the renderer (see the messages above)\n");
        goto done;
    }
    st.r = r;
    fv_quality exact;
    if (FV_FAILED(fv_quality_preset("exact", &exact, err, sizeof err))) goto done;
    if (o.baseline_count) { /* --baseline-set: the preset (and --set) with these knobs instead */
        exact = o.base;
        for (uint32_t b = 0; b < o.baseline_count; b++)
            if (FV_FAILED(fv_quality_set(&exact, o.baseline_sets[b], err, sizeof err))) goto done;
    }
    exact.distort.lens = o.lens;
    o.base.distort.lens = o.lens; /* the preset's own point is still recognised */
    if (FV_FAILED(fv_renderer_set_quality(r, &exact))) goto done;
    if (FV_FAILED(fv_renderer_load_scene(r, scene))) {
        fprintf(stderr, "fovea bench: cannot upload scene '%s'\n", o.run.scene);
        goto done;
    }
    /* Frame 0's views (scene time 0), as `fovea run` and `fovea reference` see them; the gaze as given. */
    { /* frame 0's views built by the one description `run` and `reference` build theirs from (tool_image.c): the
       * scene's head, near/far from its bounds, a named HMD's frusta */
        fv_tool_image img;
        fv_tool_image_defaults(&img);
        img.run.scene = o.run.scene;
        img.run.eye_w = w;
        img.run.eye_h = h;
        fv_quality lens_q = exact;
        if (strcmp(o.run.hmd, "none") != 0) {
            img.run.hmd = o.run.hmd;
            if (run_hmd_load(&img.hmd, &lens_q) != 0) goto done;
        }
        img.quality = exact;
        fv_tool_image_frame_input(&img, scene, NULL, 0, 0.0, &st.views);
    }
    fv_vec3 gaze_dir = fv_metrics_gaze_dir_from_deg(o.gaze_deg[0], o.gaze_deg[1]);
    if (o.has_gaze) {
        fv_eye_in_head eyes[2]; /* the gaze is the head frame's; the eyes meet it by their poses in the head */
        fv_eyes_in_head(st.views.head.ipd_mm, eyes);
        for (int e = 0; e < 2; e++) st.views.gaze[e] = fv_eye_gaze_from_head(&eyes[e], gaze_dir, 0.0f);
        ecc = malloc((size_t)2 * w * h * sizeof *ecc);
        if (!ecc) goto done;
        for (int e = 0; e < 2; e++)
            fv_metrics_eccentricity_deg(&st.views.eye[e], st.views.gaze[e].dir_eye, w, h, ecc + (size_t)e * w, 2 * w);
    }

    fv_bench_result res = {.scene = scene->name[0] ? scene->name : o.run.scene, .device = fv_renderer_device_name(r),
                           .preset = fv_tool_quality_preset(&o.plan.tq), .eye_width = w, .eye_height = h,
                           .frames = (uint32_t)o.frames, .warmup_frames = WARMUP_FRAMES, .has_gaze = o.has_gaze,
                           .gaze_deg = {o.gaze_deg[0], o.gaze_deg[1]}, .has_reference = o.ref != REF_NONE,
                           .reference_mode = o.ref == REF_MODEL ? "model" : o.ref == REF_PATH ? "path" : "none",
                           .plan = &o.plan, .points = points, .point_count = n};
    res.exact.quality = exact;
    res.exact.preset = o.baseline_count ? "baseline" : "exact";
    res.has_exact = !o.no_exact;
    res.exact.frame = (fv_bench_ms){NAN, NAN};
    /* the line covers the baselines too: the exact preset and the CPU reference are often most of the time */
    st.prog = fv_progress_start("fovea bench", "point", (int64_t)n);
    if (res.has_exact) fv_progress_phase(st.prog, "the exact preset (the baseline)");
    fv_result er = res.has_exact ? bench_point(&st, &exact, &res.exact, &exact_img) : FV_OK;
    if (er == FV_ERR_CANCELLED) goto interrupted_early;
    if (FV_FAILED(er)) {
        fprintf(stderr, "fovea bench: rendering the exact preset failed (see the messages above)\n");
        goto done;
    }
    if (res.has_reference) {
        if (FV_FAILED(fv_rgb_image_init(&ref_img, 2 * w, h, FV_IMAGE_KIND_LINEAR))) goto done;
        fv_result rr = render_reference(&o, scene, &st.views, &exact, &ref_img, &res.reference_s, &res.reference_spp,
                                        &res.reference_bounces, st.prog);
        if (rr == FV_ERR_CANCELLED) goto interrupted_early;
        if (FV_FAILED(rr)) {
            fprintf(stderr, "fovea bench: the CPU reference failed: %s\n", fv_result_str(rr));
            goto done;
        }
    }
    fv_metrics_desc md = {.name_a = "point", .name_b = "reference", .ecc_deg = ecc, .eyes = 2};
    if (res.has_exact && res.has_reference &&
        FV_FAILED(fv_metrics_compare(&exact_img, &ref_img, &md, &res.exact.vs_reference)))
        goto done;
    for (size_t i = 0; i < n; i++) {
        fv_bench_point *p = &points[i];
        fv_bench_point_values(&o.plan, i, p->value_index);
        if (FV_FAILED(fv_bench_point_quality(&o.plan, i, &p->quality, &p->preset, err, sizeof err))) {
            fprintf(stderr, "fovea bench: point %zu: %s\n", i + 1, err);
            goto done;
        }
        p->quality.distort.lens = o.lens;
        p->is_preset = fv_quality_equal(&p->quality, &o.base);
        progress(&st, i, n, &o.plan, p, i == 0);
        fv_result pr = bench_point(&st, &p->quality, p, &img);
        if (pr == FV_ERR_CANCELLED) { /* Ctrl-C: report the points done */
            res.point_count = i;
            break;
        }
        if (FV_FAILED(pr)) {
            fprintf(stderr, "\nfovea bench: point %zu failed (see the messages above)\n", i + 1);
            goto done;
        }
        md.name_b = "exact";
        if (res.has_exact && FV_FAILED(fv_metrics_compare(&img, &exact_img, &md, &p->vs_exact))) goto done;
        if (!res.has_exact) p->vs_exact.all = (fv_metrics_stats){.psnr_db = NAN, .ssim = NAN, .rel_mean = NAN};
        if (p->quality.fovea.enabled && FV_FAILED(vs_full_resolution(&st, &full, p, &img, &md))) goto done;
        md.name_b = "reference";
        if (res.has_reference && FV_FAILED(fv_metrics_compare(&img, &ref_img, &md, &p->vs_reference))) goto done;
    }
    fv_progress_update(st.prog, -1, (int64_t)res.point_count, st.gpu_ms);
    fv_progress_stop(&st.prog);
    if (res.point_count < n)
        fprintf(stderr, "fovea bench: interrupted (Ctrl-C) after %zu of %zu points; the report has those\n",
                res.point_count, n);
    res.validation_messages = fv_renderer_validation_messages(r);

    char path[1200];
    cJSON *j = fv_bench_json(&res);
    char *pretty = fv_cli_json_text(j, true), *flat = o.json ? fv_cli_json_text(j, false) : NULL;
    cJSON_Delete(j);
    snprintf(path, sizeof path, "%s/bench.json", o.out_dir);
    fv_result wr = pretty && (!o.json || flat) ? write_json_file(path, pretty) : FV_ERR_NO_MEMORY;
    if (!FV_FAILED(wr) && o.json) puts(flat);
    free(pretty);
    free(flat);
    if (FV_FAILED(wr)) goto done;
    snprintf(path, sizeof path, "%s/bench.csv", o.out_dir);
    if (FV_FAILED(fv_bench_write_csv(&res, path))) goto done;
    size_t plots = 0;
    if (FV_FAILED(fv_bench_plot(&res, o.out_dir, &plots))) { /* warned; bench.json and bench.csv stand */ }
    size_t band_plots = 0;
    if (FV_FAILED(fv_bench_plot_bands(&res, o.out_dir, &band_plots))) { /* warned, as above */ }
    if (!o.json) print_table(&res, o.out_dir, plots);
    if (res.validation_messages > 0) {
        fprintf(stderr, "fovea bench: %u Vulkan validation message%s (see above)\n", res.validation_messages,
                res.validation_messages == 1 ? "" : "s");
        goto done;
    }
    exit_code = res.point_count < n ? FV_EXIT_INTERRUPTED : FV_EXIT_OK;
    goto done;
interrupted_early:
    fv_progress_stop(&st.prog); /* clears the line at a terminal */
    fprintf(stderr, "fovea bench: interrupted (Ctrl-C) before the first of %zu points; no report written\n", n);
    exit_code = FV_EXIT_INTERRUPTED;
done:
    fv_progress_stop(&st.prog);
    fv_renderer_destroy(&r);
    fv_scene_destroy(&scene);
    fv_rgb_image_fini(&exact_img);
    fv_rgb_image_fini(&ref_img);
    fv_rgb_image_fini(&img);
    for (int k = 0; k < FULL_CACHE; k++) fv_rgb_image_fini(&full.img[k]);
    free(ecc);
    free(st.rgba);
    free(points);
    return exit_code;
}
