/* @brief What a rendering command measures (see run_measure.h). */
#include "run_measure.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli.h"
#include "fv_clock.h"
#include "fv_stats.h"

fv_result fv_measure_init(fv_measure *m, size_t frames)
{
    memset(m, 0, sizeof *m);
    m->cap = frames;
    m->last_timed = UINT64_MAX;
    m->cpu_ms = calloc(frames ? frames : 1, sizeof *m->cpu_ms);
    m->wall_ms = calloc(frames ? frames : 1, sizeof *m->wall_ms);
    m->frame_gpu_ms = calloc(frames ? frames : 1, sizeof *m->frame_gpu_ms);
    if (!m->cpu_ms || !m->wall_ms || !m->frame_gpu_ms) {
        fv_measure_fini(m);
        return FV_ERR_NO_MEMORY;
    }
    return FV_OK;
}

void fv_measure_fini(fv_measure *m)
{
    if (!m) return;
    free(m->cpu_ms);
    free(m->wall_ms);
    free(m->frame_gpu_ms);
    for (uint32_t i = 0; i < FV_MAX_PASSES; i++) free(m->passes[i].ms);
    memset(m, 0, sizeof *m);
}

int64_t fv_measure_thread_cpu_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (int64_t)ts.tv_sec * FV_NS_PER_S + ts.tv_nsec;
}

void fv_measure_cpu(fv_measure *m, double ms)
{
    if (m->drawn < m->cap) m->cpu_ms[m->drawn] = ms;
    m->drawn++;
}

void fv_measure_run_wall(fv_measure *m, double ms, size_t frames)
{
    m->run_wall_ms = ms;
    m->run_frames = frames;
}

double fv_measure_gpu_ms_sum(const fv_measure *m)
{
    double sum = 0.0;
    size_t n = m->measured < m->cap ? m->measured : m->cap;
    for (size_t i = 0; i < n; i++)
        if (isfinite(m->frame_gpu_ms[i])) sum += m->frame_gpu_ms[i];
    return sum;
}

void fv_measure_wall(fv_measure *m, double ms)
{
    if (m->walled < m->cap) m->wall_ms[m->walled] = ms;
    m->walled++;
}

/* Record one frame's GPU timings and counters. */
static bool record(fv_measure *m, const fv_render_stats *rs)
{
    if (m->measured >= m->cap) return true;
    m->frame_gpu_ms[m->measured] = rs->frame_gpu_ms;
    for (uint32_t p = 0; p < rs->pass_count && p < FV_MAX_PASSES; p++) {
        fv_pass_series *ps = &m->passes[p];
        if (!ps->ms) {
            ps->ms = calloc(m->cap, sizeof *ps->ms);
            if (!ps->ms) return false;
            snprintf(ps->name, sizeof ps->name, "%s", rs->pass_name[p]);
            if (p + 1 > m->pass_count) m->pass_count = p + 1;
        }
        if (ps->n < m->cap) ps->ms[ps->n++] = rs->pass_gpu_ms[p];
        ps->last = rs->pass_counters[p];
    }
    m->last_stats = *rs;
    m->measured++;
    return true;
}

bool fv_measure_take(fv_measure *m, const fv_renderer *r)
{
    fv_render_stats newest, rs;
    if (fv_renderer_stats(r, &newest) != FV_OK) return true;
    if (m->last_timed != UINT64_MAX && newest.frame_id <= m->last_timed) return true;
    uint64_t first = m->last_timed == UINT64_MAX ? 0 : m->last_timed + 1;
    if (newest.frame_id - first >= FV_RENDERER_STATS_HISTORY) first = newest.frame_id - FV_RENDERER_STATS_HISTORY + 1;
    for (uint64_t id = first; id <= newest.frame_id; id++)
        if (fv_renderer_frame_stats(r, id, &rs) == FV_OK && !record(m, &rs)) return false;
    m->last_timed = newest.frame_id;
    return true;
}

void fv_measure_skip(fv_measure *m, const fv_renderer *r)
{
    fv_render_stats newest;
    if (fv_renderer_stats(r, &newest) == FV_OK) m->last_timed = newest.frame_id;
}

/* Percentile of a series (sorted in place: the order of a finished series does not matter). */
static double pct(double *v, size_t n, double p) { return fv_percentile_f64(v, n, p); }

static size_t held(size_t count, size_t cap) { return count < cap ? count : cap; }

void fv_measure_add_json(const fv_measure *mc, cJSON *j)
{
    fv_measure *m = (fv_measure *)mc; /* percentiles sort the series in place */
    cJSON_AddNumberToObject(j, "frames_timed", (double)m->measured);
    cJSON *jp = cJSON_AddArrayToObject(j, "passes");
    for (uint32_t p = 0; p < m->pass_count; p++) {
        fv_pass_series *ps = &m->passes[p];
        cJSON *e = cJSON_CreateObject();
        fv_cli_json_add_string(e, "name", ps->name);
        cJSON_AddNumberToObject(e, "gpu_ms_median", pct(ps->ms, ps->n, 50));
        cJSON_AddNumberToObject(e, "gpu_ms_p95", pct(ps->ms, ps->n, 95));
        cJSON_AddNumberToObject(e, "draws", (double)ps->last.draws);
        cJSON_AddNumberToObject(e, "triangles", (double)ps->last.triangles);
        cJSON_AddNumberToObject(e, "pixels_shaded", (double)ps->last.pixels_shaded);
        cJSON_AddNumberToObject(e, "dispatches", (double)ps->last.dispatches);
        cJSON_AddItemToArray(jp, e);
    }
    cJSON_AddNumberToObject(j, "frame_gpu_ms_median", pct(m->frame_gpu_ms, m->measured, 50));
    cJSON_AddNumberToObject(j, "frame_gpu_ms_p95", pct(m->frame_gpu_ms, m->measured, 95));
    cJSON_AddNumberToObject(j, "cpu_ms_per_frame_median", pct(m->cpu_ms, held(m->drawn, m->cap), 50));
    cJSON_AddNumberToObject(j, "cpu_ms_per_frame_p95", pct(m->cpu_ms, held(m->drawn, m->cap), 95));
    /* the loop's time per frame until the frame was submitted (frames in flight: the GPU finishes them later) */
    cJSON_AddNumberToObject(j, "wall_ms_per_frame_median", pct(m->wall_ms, held(m->walled, m->cap), 50));
    if (m->run_frames) /* completed: the run's elapsed time to its last frame done, per frame */
        cJSON_AddNumberToObject(j, "wall_ms_per_completed_frame", m->run_wall_ms / (double)m->run_frames);
    cJSON_AddNumberToObject(j, "pixels_shaded_last_frame", (double)m->last_stats.pixels_shaded);
    cJSON_AddNumberToObject(j, "peak_device_memory_mib", (double)m->last_stats.peak_device_memory_bytes / 1048576.0);
}

void fv_measure_print(const fv_measure *mc, FILE *f)
{
    fv_measure *m = (fv_measure *)mc;
    fprintf(f, "  %-14s %10s %10s   (GPU time over %zu timed frame%s)\n", "pass", "median ms", "p95 ms", m->measured,
            m->measured == 1 ? "" : "s");
    for (uint32_t p = 0; p < m->pass_count; p++) {
        fv_pass_series *ps = &m->passes[p];
        fprintf(f, "  %-14s %10.3f %10.3f", ps->name, pct(ps->ms, ps->n, 50), pct(ps->ms, ps->n, 95));
        if (ps->last.draws) fprintf(f, "   %llu draws", (unsigned long long)ps->last.draws);
        if (ps->last.pixels_shaded) fprintf(f, "   %llu px shaded", (unsigned long long)ps->last.pixels_shaded);
        fputc('\n', f);
    }
    fprintf(f, "  %-14s %10.3f %10.3f\n", "frame (GPU)", pct(m->frame_gpu_ms, m->measured, 50),
            pct(m->frame_gpu_ms, m->measured, 95));
    fprintf(f, "  %-14s %10.3f %10.3f   (record + submit, this thread)\n", "CPU per frame",
            pct(m->cpu_ms, held(m->drawn, m->cap), 50), pct(m->cpu_ms, held(m->drawn, m->cap), 95));
    fprintf(f, "  %-14s %10.3f %10.3f   (the run loop's time per frame until it was submitted: CPU work, waits "
            "for an earlier frame or the display, PNG writing)\n", "loop per frame",
            pct(m->wall_ms, held(m->walled, m->cap), 50), pct(m->wall_ms, held(m->walled, m->cap), 95));
    if (m->run_frames)
        fprintf(f, "  %-14s %10.3f %10s   (completed: %.2f s from the first frame to the last one done, / %zu)\n",
                "wall per frame", m->run_wall_ms / (double)m->run_frames, "", m->run_wall_ms / 1e3, m->run_frames);
}

/* ---- foveation ---------------------------------------------------------------------------------------------- */

static const char *const FOVEA_STAGE[5][2] = {{"map", "fovea"}, {"compaction", "compact"}, {"shading", "shade"},
                                               {"temporal", "temporal"}, {"reconstruction", "reconstruct"}};

/* Median GPU ms of a pass series by name; NAN when it did not run. */
static double pass_median(fv_measure *m, const char *name)
{
    for (uint32_t p = 0; p < m->pass_count; p++)
        if (strcmp(m->passes[p].name, name) == 0 && m->passes[p].n) return pct(m->passes[p].ms, m->passes[p].n, 50);
    return NAN;
}

static bool detail_of(const fv_renderer *r, const char *pass, const char *key, fv_pass_detail *out)
{
    fv_pass_detail d[8];
    uint32_t n = fv_renderer_pass_details(r, pass, d, 8);
    for (uint32_t i = 0; i < n; i++)
        if (strcmp(d[i].key, key) == 0) {
            *out = d[i];
            return true;
        }
    return false;
}

static void add_ms_or_null(cJSON *o, const char *key, double v)
{
    if (isfinite(v)) cJSON_AddNumberToObject(o, key, v);
    else cJSON_AddNullToObject(o, key);
}

/* The cost model of foveation (issue 25): each stage's median GPU ms over the present pass's (a tonemap of the same
 * 2 x W x H pixels, the cheapest full-screen pass), i.e. its work per pixel in present passes (out[0..4], the
 * stages of FOVEA_STAGE); out[5] = the passes that exist only for foveation (all but shading) together. NAN where a
 * pass did not run (a temporal pass that is off counts 0 in the sum) or there is no present pass. */
static void fovea_cost_vs_present(fv_measure *m, double out[6])
{
    double present = pass_median(m, "present"), sum = 0;
    for (int s = 0; s < 6; s++) out[s] = NAN;
    if (!(present > 0)) return;
    for (int s = 0; s < 5; s++) {
        out[s] = pass_median(m, FOVEA_STAGE[s][1]) / present;
        if (s != 2 && isfinite(out[s])) sum += out[s]; /* shading is what foveation saves, not its overhead */
    }
    out[5] = sum;
}

void fv_measure_add_fovea_json(const fv_measure *mc, const fv_renderer *r, cJSON *j)
{
    fv_measure *m = (fv_measure *)mc;
    if (!isfinite(pass_median(m, "fovea"))) return;
    cJSON *jf = cJSON_AddObjectToObject(j, "fovea");
    fv_pass_detail frac, split, hits, reused;
    bool have = detail_of(r, "compact", "sampled_fraction", &frac);
    /* without temporal reuse (fovea.temporal=0) nothing is cached: null */
    bool have_hits = detail_of(r, "temporal", "cache_hit_fraction", &hits);
    bool have_reused = detail_of(r, "temporal", "reused_fraction", &reused);
    cJSON *eyes = cJSON_AddArrayToObject(jf, "eyes");
    for (int e = 0; e < 2; e++) {
        cJSON *je = cJSON_CreateObject();
        add_ms_or_null(je, "sampled_fraction", have ? frac.value[e] : NAN);
        add_ms_or_null(je, "cache_hit_fraction", have_hits ? hits.value[e] : NAN);
        add_ms_or_null(je, "reused_fraction", have_reused ? reused.value[e] : NAN);
        cJSON_AddItemToArray(eyes, je);
    }
    cJSON *js = cJSON_AddObjectToObject(jf, "stage_gpu_ms");
    for (int s = 0; s < 5; s++) add_ms_or_null(js, FOVEA_STAGE[s][0], pass_median(m, FOVEA_STAGE[s][1]));
    double cost[6];
    fovea_cost_vs_present(m, cost);
    cJSON *jc = cJSON_AddObjectToObject(jf, "stage_cost_vs_present");
    for (int s = 0; s < 5; s++) add_ms_or_null(jc, FOVEA_STAGE[s][0], cost[s]);
    add_ms_or_null(jc, "overhead", cost[5]);
    if (detail_of(r, "reconstruct", "stage_gpu_ms_voronoi_fill", &split)) {
        add_ms_or_null(js, "reconstruction_voronoi_last", split.value[0]);
        add_ms_or_null(js, "reconstruction_fill_last", split.value[1]);
    }
}

void fv_measure_print_fovea(const fv_measure *mc, const fv_renderer *r, FILE *f)
{
    fv_measure *m = (fv_measure *)mc;
    if (!isfinite(pass_median(m, "fovea"))) return;
    fv_pass_detail frac, split, hits, reused;
    if (detail_of(r, "compact", "sampled_fraction", &frac)) {
        fprintf(f, "  fovea: sampled fraction %.2f%% (left), %.2f%% (right)", 100.0 * frac.value[0],
                100.0 * frac.value[1]);
        if (detail_of(r, "temporal", "cache_hit_fraction", &hits) &&
            detail_of(r, "temporal", "reused_fraction", &reused))
            fprintf(f, "; cache hits %.2f%% / %.2f%%, reused for unshaded pixels %.2f%% / %.2f%%\n",
                    100.0 * hits.value[0], 100.0 * hits.value[1], 100.0 * reused.value[0], 100.0 * reused.value[1]);
        else
            fprintf(f, "; cache hits: no temporal reuse (fovea.temporal=0)\n");
    }
    fprintf(f, "  fovea stages (median GPU ms):");
    for (int s = 0; s < 5; s++) {
        double v = pass_median(m, FOVEA_STAGE[s][1]);
        if (isfinite(v)) fprintf(f, " %s %.3f", FOVEA_STAGE[s][0], v);
        else fprintf(f, " %s -", FOVEA_STAGE[s][0]);
    }
    if (detail_of(r, "reconstruct", "stage_gpu_ms_voronoi_fill", &split))
        fprintf(f, " (voronoi %.3f + fill %.3f)", split.value[0], split.value[1]);
    double cost[6];
    fovea_cost_vs_present(m, cost);
    if (isfinite(cost[5])) { /* a stage that did not run: "-", as above (not 0x: it is not free, it is absent) */
        static const int shown[4] = {0, 1, 3, 4};
        fprintf(f, "; vs present:");
        for (int k = 0; k < 4; k++) {
            int s = shown[k];
            if (isfinite(cost[s])) fprintf(f, " %s %.1fx,", FOVEA_STAGE[s][0], cost[s]);
            else fprintf(f, " %s -,", FOVEA_STAGE[s][0]);
        }
        fprintf(f, " overhead %.1fx", cost[5]);
    }
    fputc('\n', f);
}

/* ---- one-bounce GI ---------------------------------------------------------------------------------------------- */

static double gi_detail(const fv_renderer *r, const char *key, uint32_t k)
{
    fv_pass_detail d[12];
    uint32_t n = fv_renderer_pass_details(r, "gi", d, 12);
    for (uint32_t i = 0; i < n; i++)
        if (strcmp(d[i].key, key) == 0) return k < d[i].count ? d[i].value[k] : NAN;
    return NAN;
}

/* The GI plan entry's reason when GI was asked for (gi.enabled) but left some or all lights out (point lights: no
 * cube RSM); NULL otherwise. */
static const char *gi_left_out(const fv_renderer *r)
{
    const fv_plan_entry *e = fv_frame_plan_find(fv_renderer_plan(r), "gi");
    if (!e || strstr(e->reason, "gi.enabled")) return NULL;
    return !e->enabled || strstr(e->reason, "left out") ? e->reason : NULL;
}

void fv_measure_add_gi_json(const fv_measure *mc, const fv_renderer *r, cJSON *j)
{
    fv_measure *m = (fv_measure *)mc;
    const char *why = gi_left_out(r);
    if (!isfinite(pass_median(m, "gi"))) {
        if (why) fv_cli_json_add_string(cJSON_AddObjectToObject(j, "gi"), "off", why);
        return;
    }
    cJSON *jg = cJSON_AddObjectToObject(j, "gi");
    if (why) fv_cli_json_add_string(jg, "left_out", why);
    add_ms_or_null(jg, "clusters_per_pixel_mean", gi_detail(r, "clusters_per_pixel", 0));
    add_ms_or_null(jg, "clusters_per_pixel_max", gi_detail(r, "clusters_per_pixel", 1));
    add_ms_or_null(jg, "gather_pixels", gi_detail(r, "clusters_per_pixel", 2));
    add_ms_or_null(jg, "cut_clusters", gi_detail(r, "cut_clusters", 0));
    add_ms_or_null(jg, "lit_vpls", gi_detail(r, "lit_vpls", 0));
    add_ms_or_null(jg, "rebuilds", gi_detail(r, "rebuilds", 0));
    cJSON *js = cJSON_AddObjectToObject(jg, "stage_gpu_ms");
    add_ms_or_null(js, "rsm", gi_detail(r, "rsm_ms", 0));
    add_ms_or_null(js, "pyramid", gi_detail(r, "pyramid_ms", 0));
    add_ms_or_null(js, "cut", gi_detail(r, "cut_ms", 0));
    add_ms_or_null(js, "gather_in_shade", pass_median(m, "shade"));
    /* gi.rate below full: the per-block gather is its own pass (null when it did not run) */
    add_ms_or_null(js, "gather_pass", pass_median(m, "gi_gather"));
}

void fv_measure_print_gi(const fv_measure *mc, const fv_renderer *r, FILE *f)
{
    fv_measure *m = (fv_measure *)mc;
    const char *why = gi_left_out(r);
    if (!isfinite(pass_median(m, "gi"))) {
        if (why) fprintf(f, "  gi: %s\n", why); /* asked for, not run: say why (e.g. only point lights) */
        return;
    }
    if (why) fprintf(f, "  gi plan: %s\n", why);
    double mean = gi_detail(r, "clusters_per_pixel", 0), max = gi_detail(r, "clusters_per_pixel", 1);
    double pixels = gi_detail(r, "clusters_per_pixel", 2);
    if (isfinite(mean))
        fprintf(f, "  gi: %.1f clusters per pixel (mean), %.0f (max), measured over the last frame's %.0f gathering "
                   "pixels;", mean, max, pixels);
    else fprintf(f, "  gi: clusters per pixel not measured (no frame read back);");
    fprintf(f, " cut %.0f of %.0f lit VPLs; last rebuild (GPU ms): rsm %.3f, pyramid %.3f, cut %.3f; ",
            gi_detail(r, "cut_clusters", 0), gi_detail(r, "lit_vpls", 0), gi_detail(r, "rsm_ms", 0),
            gi_detail(r, "pyramid_ms", 0), gi_detail(r, "cut_ms", 0));
    double block_pass = pass_median(m, "gi_gather");
    if (isfinite(block_pass))
        fprintf(f, "gathered per block by gi_gather (median %.3f ms), upsampled inside shade (median %.3f ms)\n",
                block_pass, pass_median(m, "shade"));
    else fprintf(f, "gathered per pixel inside shade (median %.3f ms)\n", pass_median(m, "shade"));
}
