/* @brief What `fovea bench` found, and its outputs: the bench.json object, bench.csv, the Pareto front of time
 * against error, and one gnuplot plot per swept knob (gnuplot run as a subprocess). One owner thread. */
#ifndef FV_BENCH_REPORT_H
#define FV_BENCH_REPORT_H

#include <stdbool.h>
#include <stdio.h>
#include <stddef.h>
#include <stdint.h>

#include "bench_sweep.h"
#include "fv_metrics.h"
#include "fv_renderer.h"

typedef struct cJSON cJSON;

/** Median and 95th percentile (nearest rank) of a GPU time over the timed frames. */
typedef struct fv_bench_ms {
    double median_ms, p95_ms;
} fv_bench_ms;

/** One benched quality: its timings and its error against the exact preset and the CPU reference. */
typedef struct fv_bench_point {
    size_t value_index[FV_BENCH_MAX_SWEEPS]; /* the value of each sweep */
    fv_quality quality;
    const char *preset;                      /* its preset (static storage) */
    bool is_preset;                          /* every knob as the base preset has it (marked on the plots) */
    uint32_t pass_count;
    char pass_name[FV_MAX_PASSES][FV_PASS_ID_MAX];
    fv_bench_ms pass[FV_MAX_PASSES];
    fv_bench_ms frame;
    size_t frames_timed;
    fv_metrics_report vs_exact, vs_reference; /* vs_reference: only with has_reference */
    bool has_vs_full;           /* fovea.enabled: measured against full-resolution shading of the same model */
    fv_metrics_report vs_full;  /* the same knobs with fovea.enabled off (per band around --gaze-deg) */
    double vs_full_frame_ms;    /* that full-resolution frame's median GPU ms (the whole-frame ratio's divisor) */
    double vs_full_shade_ms;    /* and its shade pass's */
    double sampled_fraction[2];   /* fovea.enabled: per eye, of the newest frame counted (NaN: unknown) */
    double cache_hit_fraction[2]; /* and the temporal reuse's cache hits (NaN: fovea.temporal=0) */
} fv_bench_point;

/** A whole bench run. The pointers are borrowed. */
typedef struct fv_bench_result {
    const char *scene, *device, *preset;
    uint32_t eye_width, eye_height;
    uint32_t frames, warmup_frames;
    bool has_gaze;
    double gaze_deg[2];              /* yaw, pitch */
    bool has_reference;
    const char *reference_mode;      /* "model", "path" or "none" */
    uint32_t reference_spp, reference_bounces;
    double reference_s;              /* wall time of the CPU reference */
    const fv_bench_plan *plan;
    fv_bench_point exact;            /* the exact preset on the GPU, the image every vs_exact is measured from */
    bool has_exact;                  /* false: --exact off (vs_exact errors are NaN) */
    const fv_bench_point *points;
    size_t point_count;
    uint32_t validation_messages;
} fv_bench_result;

/** The error the plots and the Pareto front use: 1 - SSIM against the reference, or against exact without one, or
 *  against full resolution of the same model without either (foveated points; 0 for the full-resolution ones).
 *  NaN when it is not known. *out_label (non-NULL) names it. */
double fv_bench_plot_error(const fv_bench_result *r, const fv_bench_point *p, const char **out_label);

/** Mark in out_front[i] whether point i lies on the Pareto front of (x, y), both smaller-is-better: no other point
 *  is at least as good in both and better in one. Points with a NaN are never on it. Returns the count on it. */
size_t fv_bench_pareto(const double *x, const double *y, size_t n, bool *out_front);

/** The bench.json object (caller deletes), or NULL when out of memory. */
cJSON *fv_bench_json(const fv_bench_result *r);

/** Write bench.csv: a header, then one row per point. FV_ERR_IO (logged) when it cannot be written. */
FV_MUST_CHECK fv_result fv_bench_write_csv(const fv_bench_result *r, const char *path);

/** The PNG terminal gnuplot has ("pngcairo", else "png"); NULL with a warning (naming what_remains, the outputs
 *  written anyway) when gnuplot is missing or has neither. Shared by every command that plots. */
const char *fv_gnuplot_terminal(const char *what_remains);
/** Run `gnuplot SCRIPT` (its output on stderr); its exit status, 127 when it could not be started. */
int fv_gnuplot_script(const char *script);
/** Write s as a gnuplot single-quoted string literal (a file name). */
void fv_gnuplot_quoted(FILE *f, const char *s);

/** Draw pareto_<knob>.png in dir for each swept knob with gnuplot (pngcairo, else png), from a script written to
 *  dir/bench_plots.gp. Without gnuplot (or when it fails): a warning and FV_ERR_UNSUPPORTED; the caller goes on.
 *  *out_plots receives the count drawn. */
fv_result fv_bench_plot(const fv_bench_result *r, const char *dir, size_t *out_plots);
/** With foveated points and a gaze: bands_<knob>.png in dir for each swept knob, the PSNR of every eccentricity band
 *  against full-resolution shading of the same model over frame time, from dir/bench_bands.gp. *out_plots: drawn. */
fv_result fv_bench_plot_bands(const fv_bench_result *r, const char *dir, size_t *out_plots);

#endif
