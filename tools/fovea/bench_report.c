/* @brief `fovea bench`'s outputs: bench.json, bench.csv, the Pareto front, gnuplot plots (see bench_report.h). */
#include "bench_report.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"
#include "cli_interrupt.h"
#include "fv_log.h"

#define MOD "bench"

double fv_bench_plot_error(const fv_bench_result *r, const fv_bench_point *p, const char **out_label)
{
    if (!r->has_reference && !r->has_exact) {
        if (out_label) *out_label = "1 - SSIM vs full resolution of the same model (GPU)";
        return p->has_vs_full ? 1.0 - p->vs_full.all.ssim : p->quality.fovea.enabled ? NAN : 0.0;
    }
    if (out_label)
        *out_label = !r->has_reference          ? "1 - SSIM vs the exact preset (GPU)"
                     : strcmp(r->reference_mode, "path") == 0 ? "1 - SSIM vs the CPU reference (path)"
                                                               : "1 - SSIM vs the CPU reference (model)";
    const fv_metrics_report *m = r->has_reference ? &p->vs_reference : &p->vs_exact;
    return 1.0 - m->all.ssim;
}

size_t fv_bench_pareto(const double *x, const double *y, size_t n, bool *out_front)
{
    size_t count = 0;
    for (size_t i = 0; i < n; i++) {
        bool on = !isnan(x[i]) && !isnan(y[i]);
        for (size_t j = 0; j < n && on; j++) {
            if (j == i || isnan(x[j]) || isnan(y[j])) continue;
            if (x[j] <= x[i] && y[j] <= y[i] && (x[j] < x[i] || y[j] < y[i])) on = false;
        }
        out_front[i] = on;
        count += on;
    }
    return count;
}

/* ---- JSON ---------------------------------------------------------------------------------------------------- */

static void ms_json(cJSON *o, const char *key, const fv_bench_ms *ms)
{
    cJSON *e = cJSON_AddObjectToObject(o, key);
    fv_cli_json_number(e, "median_ms", ms->median_ms);
    fv_cli_json_number(e, "p95_ms", ms->p95_ms);
}

static void error_json(cJSON *o, const char *key, const fv_metrics_report *m)
{
    cJSON *e = cJSON_AddObjectToObject(o, key);
    fv_cli_json_number(e, "psnr_db", m->all.psnr_db); /* null when infinite: identical sRGB values */
    fv_cli_json_number(e, "ssim", m->all.ssim);
    fv_cli_json_number(e, "rel_mean", m->all.rel_mean);
    if (!m->has_bands) return;
    cJSON *bands = cJSON_AddArrayToObject(e, "bands");
    for (int k = 0; k < FV_METRICS_BANDS; k++) {
        cJSON *b = cJSON_CreateObject();
        cJSON_AddNumberToObject(b, "from_deg", fv_metrics_band_edges_deg[k]);
        cJSON_AddNumberToObject(b, "to_deg", fv_metrics_band_edges_deg[k + 1]);
        cJSON_AddNumberToObject(b, "pixels", (double)m->band[k].pixels);
        fv_cli_json_number(b, "psnr_db", m->band[k].psnr_db);
        fv_cli_json_number(b, "ssim", m->band[k].ssim);
        fv_cli_json_number(b, "rel_mean", m->band[k].rel_mean);
        cJSON_AddItemToArray(bands, b);
    }
}

static void timings_json(cJSON *o, const fv_bench_point *p)
{
    cJSON *passes = cJSON_AddObjectToObject(o, "passes");
    for (uint32_t i = 0; i < p->pass_count; i++) ms_json(passes, p->pass_name[i], &p->pass[i]);
    ms_json(o, "frame_ms", &p->frame);
    cJSON_AddNumberToObject(o, "frames_timed", (double)p->frames_timed);
}

/* The point's value of sweep s: as the knob table formats it, or the preset's name. */
static const char *sweep_value(const fv_bench_sweep *s, const fv_bench_point *p, char *buf, size_t size)
{
    if (!s->knob) return p->preset;
    return fv_knob_format(s->knob, &p->quality, buf, size);
}

cJSON *fv_bench_json(const fv_bench_result *r)
{
    cJSON *j = cJSON_CreateObject();
    if (!j) return NULL;
    fv_cli_json_add_string(j, "scene", r->scene);
    fv_cli_json_add_string(j, "device", r->device);
    cJSON_AddNumberToObject(j, "eye_width", r->eye_width);
    cJSON_AddNumberToObject(j, "eye_height", r->eye_height);
    fv_cli_json_add_string(j, "preset", r->preset);
    cJSON_AddNumberToObject(j, "frames", r->frames);
    cJSON_AddNumberToObject(j, "warmup_frames", r->warmup_frames);
    if (r->has_gaze) {
        cJSON *g = cJSON_AddObjectToObject(j, "gaze");
        cJSON_AddNumberToObject(g, "yaw_deg", r->gaze_deg[0]);
        cJSON_AddNumberToObject(g, "pitch_deg", r->gaze_deg[1]);
    } else {
        cJSON_AddNullToObject(j, "gaze");
    }
    cJSON *ref = cJSON_AddObjectToObject(j, "reference");
    fv_cli_json_add_string(ref, "mode", r->reference_mode);
    if (r->has_reference) {
        cJSON_AddNumberToObject(ref, "spp", r->reference_spp);
        if (strcmp(r->reference_mode, "path") == 0) cJSON_AddNumberToObject(ref, "bounces", r->reference_bounces);
        cJSON_AddNumberToObject(ref, "seconds", r->reference_s);
    }
    const char *label;
    (void)fv_bench_plot_error(r, &r->exact, &label);
    fv_cli_json_add_string(j, "plot_error", label);
    cJSON *sw = cJSON_AddArrayToObject(j, "sweeps");
    for (size_t s = 0; s < r->plan->sweep_count; s++)
        cJSON_AddItemToArray(sw, fv_cli_json_string(r->plan->sweeps[s].name));
    cJSON *ex = r->has_exact ? cJSON_AddObjectToObject(j, "exact") : NULL;
    if (!r->has_exact) cJSON_AddNullToObject(j, "exact");
    else timings_json(ex, &r->exact);
    if (ex && r->has_reference) error_json(ex, "vs_reference", &r->exact.vs_reference); /* the GPU model's floor */
    cJSON *pts = cJSON_AddArrayToObject(j, "points");
    for (size_t i = 0; i < r->point_count; i++) {
        const fv_bench_point *p = &r->points[i];
        cJSON *o = cJSON_CreateObject();
        cJSON *k = cJSON_AddObjectToObject(o, "knobs");
        for (size_t s = 0; s < r->plan->sweep_count; s++) {
            const fv_bench_sweep *sweep = &r->plan->sweeps[s];
            cJSON_AddItemToObject(k, sweep->name, sweep->knob ? fv_tool_knob_json(sweep->knob, &p->quality)
                                                              : fv_cli_json_string(p->preset));
        }
        fv_cli_json_add_string(o, "preset", p->preset);
        cJSON_AddBoolToObject(o, "is_preset", p->is_preset);
        timings_json(o, p);
        error_json(o, "vs_exact", &p->vs_exact);
        if (r->has_reference) error_json(o, "vs_reference", &p->vs_reference);
        else cJSON_AddNullToObject(o, "vs_reference");
        if (p->has_vs_full) {
            error_json(o, "vs_full_resolution", &p->vs_full);
            cJSON *vf = cJSON_GetObjectItem(o, "vs_full_resolution");
            fv_cli_json_number(vf, "full_frame_ms", p->vs_full_frame_ms);
            fv_cli_json_number(vf, "full_shade_ms", p->vs_full_shade_ms);
            cJSON *eyes = cJSON_AddArrayToObject(o, "fovea_eyes");
            for (int e = 0; e < 2; e++) {
                cJSON *je = cJSON_CreateObject();
                fv_cli_json_number(je, "sampled_fraction", p->sampled_fraction[e]);
                fv_cli_json_number(je, "cache_hit_fraction", p->cache_hit_fraction[e]);
                cJSON_AddItemToArray(eyes, je);
            }
        }
        cJSON_AddItemToArray(pts, o);
    }
    cJSON_AddNumberToObject(j, "validation_messages", r->validation_messages);
    return j;
}

/* ---- CSV ----------------------------------------------------------------------------------------------------- */

/* The pass names of every point, in order of first appearance. */
static uint32_t pass_union(const fv_bench_result *r, char names[][FV_PASS_ID_MAX], uint32_t cap)
{
    uint32_t n = 0;
    for (size_t i = 0; i < r->point_count; i++)
        for (uint32_t p = 0; p < r->points[i].pass_count; p++) {
            bool seen = false;
            for (uint32_t k = 0; k < n && !seen; k++) seen = strcmp(names[k], r->points[i].pass_name[p]) == 0;
            if (!seen && n < cap) snprintf(names[n++], FV_PASS_ID_MAX, "%s", r->points[i].pass_name[p]);
        }
    return n;
}

static void csv_num(FILE *f, double v)
{
    if (isnan(v)) fputs(",", f);
    else if (isinf(v)) fputs(v > 0 ? ",inf" : ",-inf", f);
    else fprintf(f, ",%.6g", v);
}

fv_result fv_bench_write_csv(const fv_bench_result *r, const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        FV_ERROR(MOD, "%s: cannot write (%s)", path, strerror(errno));
        return FV_ERR_IO;
    }
    char passes[FV_MAX_PASSES * 2][FV_PASS_ID_MAX];
    uint32_t np = pass_union(r, passes, FV_MAX_PASSES * 2);
    for (size_t s = 0; s < r->plan->sweep_count; s++) fprintf(f, "%s,", r->plan->sweeps[s].name);
    fputs("frame_ms_median,frame_ms_p95", f);
    for (uint32_t k = 0; k < np; k++) fprintf(f, ",%s_median_ms", passes[k]);
    fputs(",exact_psnr_db,exact_ssim,exact_rel_mean,reference_psnr_db,reference_ssim,reference_rel_mean", f);
    fputs(",full_psnr_db,full_ssim,full_frame_ms,full_shade_ms,sampled_fraction_left,sampled_fraction_right", f);
    for (int k = 0; k < FV_METRICS_BANDS; k++)
        fprintf(f, ",full_psnr_db_%g_%g_deg", fv_metrics_band_edges_deg[k], fv_metrics_band_edges_deg[k + 1]);
    fputc('\n', f);
    for (size_t i = 0; i < r->point_count; i++) {
        const fv_bench_point *p = &r->points[i];
        char buf[48];
        for (size_t s = 0; s < r->plan->sweep_count; s++)
            fprintf(f, "%s,", sweep_value(&r->plan->sweeps[s], p, buf, sizeof buf));
        fprintf(f, "%.6g,%.6g", p->frame.median_ms, p->frame.p95_ms);
        for (uint32_t k = 0; k < np; k++) {
            double v = NAN;
            for (uint32_t q = 0; q < p->pass_count; q++)
                if (strcmp(p->pass_name[q], passes[k]) == 0) v = p->pass[q].median_ms;
            csv_num(f, v);
        }
        const fv_metrics_stats *e = &p->vs_exact.all, *ref = &p->vs_reference.all;
        csv_num(f, e->psnr_db), csv_num(f, e->ssim), csv_num(f, e->rel_mean);
        if (r->has_reference) csv_num(f, ref->psnr_db), csv_num(f, ref->ssim), csv_num(f, ref->rel_mean);
        else fputs(",,,", f);
        if (p->has_vs_full) {
            csv_num(f, p->vs_full.all.psnr_db), csv_num(f, p->vs_full.all.ssim);
            csv_num(f, p->vs_full_frame_ms), csv_num(f, p->vs_full_shade_ms);
            csv_num(f, p->sampled_fraction[0]), csv_num(f, p->sampled_fraction[1]);
            for (int k = 0; k < FV_METRICS_BANDS; k++) csv_num(f, p->vs_full.has_bands ? p->vs_full.band[k].psnr_db : NAN);
        } else {
            for (int k = 0; k < 6 + FV_METRICS_BANDS; k++) fputc(',', f);
        }
        fputc('\n', f);
    }
    if (fclose(f) != 0) {
        FV_ERROR(MOD, "%s: cannot write (%s)", path, strerror(errno));
        return FV_ERR_IO;
    }
    return FV_OK;
}

/* ---- plots --------------------------------------------------------------------------------------------------- */

/* Run gnuplot with these arguments, its stdout and stderr on our stderr (stdout may carry --json), or silenced.
 * Returns its exit status; 127 when it could not be started. */
static int run_gnuplot(const char *const args[], bool quiet)
{
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) return 127;
    if (pid == 0) {
        fv_cli_interrupt_child(); /* gnuplot gets Ctrl-C as usual */
        int fd = quiet ? open("/dev/null", O_WRONLY) : dup(STDERR_FILENO);
        if (fd >= 0) {
            dup2(fd, STDOUT_FILENO);
            if (quiet) dup2(fd, STDERR_FILENO);
            close(fd);
        }
        execvp("gnuplot", (char *const *)args);
        _exit(127);
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return 127;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 126;
}

const char *fv_gnuplot_terminal(const char *what_remains)
{
    const char *probe_cairo[] = {"gnuplot", "-e", "set terminal pngcairo", NULL};
    int rc = run_gnuplot(probe_cairo, true);
    if (rc == 127) {
        FV_WARN("plot", "gnuplot not found: no plots (%s; Debian: gnuplot-nox)", what_remains);
        return NULL;
    }
    if (rc == 0) return "pngcairo";
    const char *probe_png[] = {"gnuplot", "-e", "set terminal png", NULL};
    if (run_gnuplot(probe_png, true) != 0) {
        FV_WARN("plot", "gnuplot has neither the pngcairo nor the png terminal: no plots");
        return NULL;
    }
    return "png";
}

int fv_gnuplot_script(const char *script)
{
    const char *draw[] = {"gnuplot", script, NULL};
    return run_gnuplot(draw, false);
}

/* A string for a gnuplot single-quoted literal: ' doubled. */
static void gp_quoted(FILE *f, const char *s)
{
    fputc('\'', f);
    for (; *s; s++) {
        if (*s == '\'') fputc('\'', f);
        fputc(*s, f);
    }
    fputc('\'', f);
}

void fv_gnuplot_quoted(FILE *f, const char *s) { gp_quoted(f, s); }

/* A string inside a gnuplot double-quoted literal: backslash and double quote escaped. */
static void gp_escaped(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '"' || *s == '\\') fputc('\\', f);
        fputc(*s, f);
    }
}

/* The point's values of every sweep but `skip` ("lambda=0.5 filter=pcf3": the name after its last dot), its label on
 * the plot of knob `skip`. */
static void point_label(const fv_bench_result *r, const fv_bench_point *p, size_t skip, char *out, size_t size)
{
    size_t len = 0;
    out[0] = '\0';
    for (size_t s = 0; s < r->plan->sweep_count && len + 1 < size; s++) {
        if (s == skip) continue;
        char buf[48];
        const char *name = r->plan->sweeps[s].name, *dot = strrchr(name, '.');
        len += (size_t)snprintf(out + len, size - len, "%s%s=%s", len ? " " : "", dot ? dot + 1 : name,
                                sweep_value(&r->plan->sweeps[s], p, buf, sizeof buf));
    }
}

/* The script of one plot: time against error, a series per value of sweep `s`, the Pareto front, the preset. */
static void plot_script(FILE *f, const fv_bench_result *r, size_t s, const char *terminal, const char *dir,
                        const double *x, const double *y, const bool *front)
{
    const fv_bench_sweep *sweep = &r->plan->sweeps[s];
    const char *label;
    (void)fv_bench_plot_error(r, &r->exact, &label);
    double ymin = INFINITY, ymax = 0;
    for (size_t i = 0; i < r->point_count; i++)
        if (isfinite(y[i])) ymin = fmin(ymin, y[i]), ymax = fmax(ymax, y[i]);
    bool logy = ymin > 0 && isfinite(ymin) && ymax / ymin > 20;
    double pad = fmax(fabs(ymax) * 0.1, 1e-3); /* one error for every point: an explicit range around it */
    bool flat = isfinite(ymin) && ymax - ymin <= 0;
    char path[1200];
    snprintf(path, sizeof path, "%s/pareto_%s.png", dir, sweep->name);
    fprintf(f, "reset\nset terminal %s size 900,600 font ',10'\nset output ", terminal);
    gp_quoted(f, path);
    char text[1024];
    /* Two lines: a double-quoted string, whose "\n" gnuplot reads as a line break. */
    fputs("\nset title \"", f);
    snprintf(text, sizeof text, "%s, %ux%u per eye, %s", r->scene, r->eye_width, r->eye_height, r->device);
    gp_escaped(f, text);
    fputs("\\n", f);
    snprintf(text, sizeof text, "%s swept; every other knob as the %s preset", sweep->name, r->preset);
    gp_escaped(f, text);
    fputc('"', f);
    snprintf(text, sizeof text, "frame time: median GPU ms over %u timed frames", r->frames - r->warmup_frames);
    fputs(" noenhanced\nset xlabel ", f);
    gp_quoted(f, text);
    fputs(" noenhanced\nset ylabel ", f);
    gp_quoted(f, label);
    fprintf(f, " noenhanced\nset grid\nset key inside top right box opaque noenhanced\n"
               "set offsets graph 0.02, graph 0.12, graph 0.4, graph 0.03\n%s", logy ? "set logscale y\n" : "");
    if (flat) fprintf(f, "set yrange [%.9g:%.9g]\n", fmax(0.0, ymin - pad), ymax + pad);
    /* The front, left to right. */
    fputs("$front << EOD\n", f);
    size_t order[FV_BENCH_MAX_POINTS], nf = 0;
    for (size_t i = 0; i < r->point_count && nf < FV_BENCH_MAX_POINTS; i++)
        if (front[i]) order[nf++] = i;
    for (size_t a = 1; a < nf; a++)
        for (size_t b = a; b > 0 && x[order[b]] < x[order[b - 1]]; b--) {
            size_t t = order[b];
            order[b] = order[b - 1], order[b - 1] = t;
        }
    for (size_t i = 0; i < nf; i++) fprintf(f, "%.9g %.9g\n", x[order[i]], y[order[i]]);
    fputs("EOD\n", f);
    bool labels = r->plan->sweep_count > 1 && r->point_count <= 32;
    for (size_t v = 0; v < sweep->value_count; v++) {
        fprintf(f, "$v%zu << EOD\n", v);
        for (size_t i = 0; i < r->point_count; i++) {
            if (r->points[i].value_index[s] != v || !isfinite(x[i]) || !isfinite(y[i])) continue;
            char lab[256];
            point_label(r, &r->points[i], s, lab, sizeof lab);
            fprintf(f, "%.9g %.9g \"%s\"\n", x[i], y[i], labels ? lab : "");
        }
        fputs("EOD\n", f);
    }
    fputs("$preset << EOD\n", f);
    bool any_preset = false;
    for (size_t i = 0; i < r->point_count; i++)
        if (r->points[i].is_preset && isfinite(x[i]) && isfinite(y[i])) {
            fprintf(f, "%.9g %.9g\n", x[i], y[i]);
            any_preset = true;
        }
    fputs("EOD\n", f);
    fprintf(f, "plot $front using 1:2 with lines lw 2 lc rgb '#404040' title 'Pareto front'");
    for (size_t v = 0; v < sweep->value_count; v++) {
        snprintf(text, sizeof text, "%s=%s", sweep->name, sweep->values[v]);
        fprintf(f, ", \\\n  $v%zu using 1:2 with points pt 7 ps 1.4 title ", v);
        gp_quoted(f, text);
        if (labels) fprintf(f, ", \\\n  $v%zu using 1:2:3 with labels offset 0.8,0.6 left font ',8' notitle", v);
    }
    if (any_preset) {
        snprintf(text, sizeof text, "the %s preset's own values", r->preset);
        fputs(", \\\n  $preset using 1:2 with points pt 6 ps 3.5 lw 2 lc rgb 'red' title ", f);
        gp_quoted(f, text);
    }
    fputs("\nunset output\n", f);
}

fv_result fv_bench_plot(const fv_bench_result *r, const char *dir, size_t *out_plots)
{
    *out_plots = 0;
    if (r->point_count == 0 || r->plan->sweep_count == 0) return FV_OK;
    const char *terminal = fv_gnuplot_terminal("bench.json and bench.csv are written");
    if (!terminal) return FV_ERR_UNSUPPORTED;
    int rc;
    double *x = malloc(r->point_count * sizeof *x), *y = malloc(r->point_count * sizeof *y);
    bool *front = malloc(r->point_count * sizeof *front);
    char script[1200];
    snprintf(script, sizeof script, "%s/bench_plots.gp", dir);
    FILE *f = x && y && front ? fopen(script, "w") : NULL;
    if (!f) {
        FV_WARN(MOD, "%s: cannot write the plot script (%s): no plots", script, strerror(errno ? errno : ENOMEM));
        free(x), free(y), free(front);
        return FV_ERR_IO;
    }
    for (size_t i = 0; i < r->point_count; i++) {
        x[i] = r->points[i].frame.median_ms;
        y[i] = fv_bench_plot_error(r, &r->points[i], NULL);
    }
    fv_bench_pareto(x, y, r->point_count, front);
    fprintf(f, "# fovea bench: time against error, one plot per swept knob (gnuplot %s)\n", terminal);
    for (size_t s = 0; s < r->plan->sweep_count; s++) plot_script(f, r, s, terminal, dir, x, y, front);
    free(x), free(y), free(front);
    if (fclose(f) != 0) {
        FV_WARN(MOD, "%s: cannot write the plot script: no plots", script);
        return FV_ERR_IO;
    }
    const char *draw[] = {"gnuplot", script, NULL};
    rc = run_gnuplot(draw, false);
    if (rc != 0) {
        FV_WARN(MOD, "gnuplot %s failed (exit %d): plots may be missing", script, rc);
        return FV_ERR_UNSUPPORTED;
    }
    *out_plots = r->plan->sweep_count;
    return FV_OK;
}

/* ---- per-band error curves of foveated points ------------------------------------------------------------------ */

fv_result fv_bench_plot_bands(const fv_bench_result *r, const char *dir, size_t *out_plots)
{
    *out_plots = 0;
    bool any = false;
    for (size_t i = 0; i < r->point_count; i++) any = any || (r->points[i].has_vs_full && r->points[i].vs_full.has_bands);
    if (!any || r->plan->sweep_count == 0) return FV_OK;
    const char *terminal = fv_gnuplot_terminal("bench.json and bench.csv are written");
    if (!terminal) return FV_ERR_UNSUPPORTED;
    char script[1200], path[1200], text[1024];
    snprintf(script, sizeof script, "%s/bench_bands.gp", dir);
    FILE *f = fopen(script, "w");
    if (!f) {
        FV_WARN(MOD, "%s: cannot write the plot script (%s): no band plots", script, strerror(errno));
        return FV_ERR_IO;
    }
    fprintf(f, "# fovea bench: per-band PSNR against full resolution over frame time, one plot per swept knob\n");
    for (size_t s = 0; s < r->plan->sweep_count; s++) {
        const fv_bench_sweep *sweep = &r->plan->sweeps[s];
        snprintf(path, sizeof path, "%s/bands_%s.png", dir, sweep->name);
        fprintf(f, "reset\nset terminal %s size 900,600 font ',10'\nset output ", terminal);
        gp_quoted(f, path);
        fputs("\nset title \"", f);
        snprintf(text, sizeof text, "%s, %ux%u per eye, %s: %s swept (every other knob as %s); PSNR vs full resolution",
                 r->scene, r->eye_width, r->eye_height, r->device, sweep->name, r->preset);
        gp_escaped(f, text);
        fputs("\" noenhanced\nset xlabel 'frame time: median GPU ms' noenhanced\n"
              "set ylabel 'PSNR (dB) vs full resolution, per eccentricity band; 99 = identical' noenhanced\n"
              "set grid\nset key outside right noenhanced\nset offsets graph 0.05, graph 0.15, graph 0.05, graph 0.05\n",
              f);
        for (int k = 0; k < FV_METRICS_BANDS; k++) {
            fprintf(f, "$b%d << EOD\n", k);
            /* points in the order of the sweep's values, each labelled with its value */
            for (size_t v = 0; v < sweep->value_count; v++)
                for (size_t i = 0; i < r->point_count; i++) {
                    const fv_bench_point *p = &r->points[i];
                    if (p->value_index[s] != v || !p->has_vs_full || !p->vs_full.has_bands) continue;
                    double db = p->vs_full.band[k].psnr_db;
                    if (isnan(db) || !isfinite(p->frame.median_ms)) continue;
                    fprintf(f, "%.9g %.9g \"%s\"\n", p->frame.median_ms, isinf(db) ? 99.0 : db, sweep->values[v]);
                }
            fputs("EOD\n", f);
        }
        fputs("plot ", f);
        for (int k = 0; k < FV_METRICS_BANDS; k++) {
            snprintf(text, sizeof text, "%g-%g deg", fv_metrics_band_edges_deg[k], fv_metrics_band_edges_deg[k + 1]);
            fprintf(f, "%s$b%d using 1:2 with linespoints pt 7 title ", k ? ", \\\n  " : "", k);
            gp_quoted(f, text);
            fprintf(f, ", \\\n  $b%d using 1:2:3 with labels offset 0.6,0.6 left font ',8' notitle", k);
        }
        fputs("\nunset output\n", f);
    }
    if (fclose(f) != 0) {
        FV_WARN(MOD, "%s: cannot write the plot script: no band plots", script);
        return FV_ERR_IO;
    }
    const char *draw[] = {"gnuplot", script, NULL};
    int rc = run_gnuplot(draw, false);
    if (rc != 0) {
        FV_WARN(MOD, "gnuplot %s failed (exit %d): band plots may be missing", script, rc);
        return FV_ERR_UNSUPPORTED;
    }
    *out_plots = r->plan->sweep_count;
    return FV_OK;
}
