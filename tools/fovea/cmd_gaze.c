/* @brief `fovea gaze eval`: evaluate the gaze pipeline on a device (the simulated eye, against its ground truth;
 * a recording, against its own later samples): saccade detection F1, angular error at photon time with and
 * without prediction for several horizons, and the pipeline's cost per sample. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include <cjson/cJSON.h>

#include "bench_report.h"
#include "cli.h"
#include "fv_clock.h"
#include "fv_gaze_pipeline.h"
#include "fv_log.h"
#include "fv_sim_eval.h"
#include "fv_trace_driver.h"
#include "fv_app_drivers.h"

static const char g_usage[] =
    "usage: fovea gaze eval --gaze URI [--seconds S] [--json] [--plot DIR] [--bench] [--accuracy-deg D]\n"
    "                       [--min-cutoff HZ] [--beta B] [--saccade-on DEG_S] [--saccade-off DEG_S]\n"
    "                       [--tune KEY=VALUE]...\n"
    "  Runs the gaze pipeline over URI on a simulated clock (deterministic) and reports:\n"
    "  - saccade detection precision/recall/F1 (sim: URIs, event matching against the ground truth),\n"
    "  - mean and 95th-percentile angular error at photon time (newest sample's receipt + 0/10/20/40/60 ms) for\n"
    "    the prediction, the latest filtered sample and the latest raw sample, against the raw future sample and\n"
    "    against a zero-phase smoothing of the samples (and, for sim:, the true gaze), with the share of truths\n"
    "    inside the predicted uncertainty radius,\n"
    "  - with --plot DIR, gaze_timeline.png and gaze_error.png drawn by gnuplot (data and scripts beside them),\n"
    "  - with --bench, the pipeline's cost per sample (push + one predict) in ns.\n"
    "  Without --min-cutoff/--beta the 1-euro filter is set from the tracker's noise, measured online.\n"
    "  URI examples: sim:seed=1   sim:seed=3,rate_hz=250,precision_deg=0.3   trace:rec.csv\n"
    "  sim: keys: seed rate_hz jitter_us latency_ms transport_jitter_ms dropout eye_loss precision_deg\n"
    "             accuracy_deg blink_per_min pursuit_prob microsaccades skew_ppm device_offset_s ipd_mm\n"
    "             vmax_deg_s c_deg main_seq_spread ts_bits\n"
    "  --seconds S   device time to evaluate (default: 60 for sim:, the whole recording otherwise; at most 3600)\n"
    "  --tune KEY=VALUE  set one of the predictor's tuned constants (select_ses onset2_sds onset_sds shrink_sds\n"
    "                mid_window_ms score_memory score_min speed_bin_scale slow_saccade_deg_s blend fallback_min\n"
    "                fallback_memory fallback); see\n"
    "                tools/gaze_loro.py and docs/gaze.md for their cross-validation\n";

static const char *const g_truth_title[FV_SIM_EVAL_TRUTHS] = {
    "the raw future sample", "the zero-phase smoothing of the samples", "the true gaze"};

static void print_text(const char *uri, const fv_sim_eval_result *r)
{
    printf("gaze eval: %s\n", uri);
    printf("  samples %llu over %.1f s (%.1f Hz; %s), invalid %llu, one-eye %llu, rejected %llu, clock skew %.1f ppm\n",
           (unsigned long long)r->samples, r->seconds, r->rate_hz, r->whole ? "the whole stream" : "cut at --seconds",
           (unsigned long long)r->invalid, (unsigned long long)r->one_eye, (unsigned long long)r->rejected,
           r->skew_ppm);
    if (isfinite(r->noise_deg))
        printf("  tracker noise %.3f deg RMS per axis (online, fixations) -> 1-euro f_cmin %.2f Hz, beta %.3f/deg\n",
               r->noise_deg, r->filter_min_cutoff_hz, r->filter_beta);
    if (r->has_truth) {
        printf("  saccades: %llu true = TP %llu + FN %llu (+%llu hidden by blinks); detected %llu = TP %llu + FP %llu "
               "(+%llu overlapping a blink, not scored)\n",
               (unsigned long long)r->true_saccades, (unsigned long long)r->tp, (unsigned long long)r->fn,
               (unsigned long long)r->true_saccades_hidden, (unsigned long long)r->det_saccades,
               (unsigned long long)r->tp, (unsigned long long)r->fp, (unsigned long long)r->det_in_blink);
        printf("  saccade detection: precision %.3f recall %.3f F1 %.3f\n", r->precision, r->recall, r->f1);
    } else {
        printf("  detected: %llu saccades, %llu pursuits (no ground truth)\n", (unsigned long long)r->det_saccades,
               (unsigned long long)r->det_pursuits);
    }
    printf("  blinks: %llu in the recording (as `fovea trace info` counts them); the pipeline held gaze through %llu "
           "runs of invalid samples\n",
           (unsigned long long)r->recorded_blinks, (unsigned long long)r->det_blinks);
    for (int t = r->has_truth ? FV_SIM_EVAL_TRUTH_TRUE : FV_SIM_EVAL_TRUTH_SMOOTHED; t >= 0; t--) {
        printf("  angular error at photon time (deg) against %s\n", g_truth_title[t]);
        printf("    %-8s %-19s %-19s %-17s\n", "horizon", "predicted", "latest filtered", "latest sample");
        printf("    %-8s %-19s %-19s %-17s\n", "", "mean / p95 (in r)", "mean / p95 (in r)", "mean / p95");
        for (int h = 0; h < FV_SIM_EVAL_HORIZONS; h++) {
            const fv_sim_eval_error *e = &r->err[t][0][h], *f = &r->err[t][1][h], *l = &r->err[t][2][h];
            char a[40], b[40], c[32], hz[16];
            snprintf(hz, sizeof hz, "%d ms", r->horizon_ms[h]);
            snprintf(a, sizeof a, "%.3f / %.3f (%2.0f%%)", e->mean_deg, e->p95_deg, 100.0 * e->inside_radius);
            snprintf(b, sizeof b, "%.3f / %.3f (%2.0f%%)", f->mean_deg, f->p95_deg, 100.0 * f->inside_radius);
            snprintf(c, sizeof c, "%.3f / %.3f", l->mean_deg, l->p95_deg);
            printf("    %-8s %-19s %-19s %-17s\n", hz, a, b, c);
        }
    }
    printf("  (in r) = share of truths inside the predicted uncertainty radius; mean radius at 20 ms: %.2f deg\n",
           r->mean_uncertainty_deg);
    printf("  smoothed truth: local quadratic fit over +-%.1f ms of valid samples\n", r->smooth_half_ms);
    const fv_gaze_pipeline_stats *ps = &r->pipeline;
    if (ps->predictions)
        printf("  prediction: %s at the end; %.1f%% of the predictions fell back to the latest sample, where the "
               "predictor's choices had not beaten it on this device's own later samples (chosen - latest error at "
               "the end %+.4f deg; %llu switches)\n",
               ps->fallback ? "fallen back to the latest sample (it cannot help on this device)" : "on",
               100.0 * (double)ps->fallback_predictions / (double)ps->predictions, ps->fallback_margin_deg,
               (unsigned long long)ps->fallback_switches);
    if (r->ns_per_sample > 0.0) printf("  pipeline cost: %.0f ns per sample (push + predict)\n", r->ns_per_sample);
}

static cJSON *err_json(const fv_sim_eval_error *e)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "mean_deg", e->mean_deg);
    cJSON_AddNumberToObject(o, "p95_deg", e->p95_deg);
    cJSON_AddNumberToObject(o, "n", (double)e->n);
    if (isfinite(e->inside_radius)) cJSON_AddNumberToObject(o, "inside_radius", e->inside_radius);
    return o;
}

static int print_json(const char *uri, const fv_sim_eval_result *r, const fv_gaze_validity_counts *validity,
                      const char *why)
{
    cJSON *o = cJSON_CreateObject();
    if (!o) return FV_EXIT_FAIL;
    fv_cli_json_add_string(o, "uri", uri);
    if (validity) {
        cJSON *v = cJSON_AddObjectToObject(o, "impossible_gaze");
        cJSON_AddNumberToObject(v, "repaired", (double)fv_gaze_validity_total(validity, true));
        cJSON_AddNumberToObject(v, "dropped", (double)fv_gaze_validity_total(validity, false));
        fv_cli_json_add_string(v, "why", why);
    }
    cJSON_AddBoolToObject(o, "ground_truth", r->has_truth);
    cJSON_AddNumberToObject(o, "samples", (double)r->samples);
    cJSON_AddNumberToObject(o, "seconds", r->seconds);
    cJSON_AddBoolToObject(o, "whole_recording", r->whole);
    cJSON_AddNumberToObject(o, "rate_hz", r->rate_hz);
    cJSON_AddNumberToObject(o, "invalid", (double)r->invalid);
    cJSON_AddNumberToObject(o, "one_eye", (double)r->one_eye);
    cJSON_AddNumberToObject(o, "rejected", (double)r->rejected);
    cJSON_AddNumberToObject(o, "clock_skew_ppm", r->skew_ppm);
    if (isfinite(r->noise_deg)) {
        cJSON *nz = cJSON_AddObjectToObject(o, "noise");
        cJSON_AddNumberToObject(nz, "sigma_deg", r->noise_deg);
        cJSON_AddNumberToObject(nz, "filter_min_cutoff_hz", r->filter_min_cutoff_hz);
        cJSON_AddNumberToObject(nz, "filter_beta", r->filter_beta);
    }
    cJSON *pr = cJSON_AddObjectToObject(o, "prediction");
    cJSON_AddBoolToObject(pr, "fallback", r->pipeline.fallback);
    cJSON_AddNumberToObject(pr, "fallback_share", r->pipeline.predictions ? (double)r->pipeline.fallback_predictions /
                                                                              (double)r->pipeline.predictions : 0.0);
    cJSON_AddNumberToObject(pr, "fallback_switches", (double)r->pipeline.fallback_switches);
    cJSON_AddNumberToObject(pr, "margin_deg", r->pipeline.fallback_margin_deg);
    cJSON *s = cJSON_AddObjectToObject(o, "saccades");
    cJSON_AddNumberToObject(s, "detected", (double)r->det_saccades);
    if (r->has_truth) {
        cJSON_AddNumberToObject(s, "true", (double)r->true_saccades);
        cJSON_AddNumberToObject(s, "hidden_by_blinks", (double)r->true_saccades_hidden);
        cJSON_AddNumberToObject(s, "detected_in_blinks", (double)r->det_in_blink);
        cJSON_AddNumberToObject(s, "tp", (double)r->tp);
        cJSON_AddNumberToObject(s, "fp", (double)r->fp);
        cJSON_AddNumberToObject(s, "fn", (double)r->fn);
        cJSON_AddNumberToObject(s, "precision", r->precision);
        cJSON_AddNumberToObject(s, "recall", r->recall);
        cJSON_AddNumberToObject(s, "f1", r->f1);
        cJSON_AddNumberToObject(s, "match_tolerance_ms", FV_SIM_EVAL_MATCH_TOL_MS);
    }
    cJSON_AddNumberToObject(o, "detected_pursuits", (double)r->det_pursuits);
    cJSON *b = cJSON_AddObjectToObject(o, "blinks");
    cJSON_AddNumberToObject(b, "recorded", (double)r->recorded_blinks);
    cJSON_AddNumberToObject(b, "held_invalid_runs", (double)r->det_blinks);
    cJSON_AddNumberToObject(o, "smooth_half_ms", r->smooth_half_ms);
    cJSON *hs = cJSON_AddArrayToObject(o, "horizons");
    for (int h = 0; h < FV_SIM_EVAL_HORIZONS; h++) {
        cJSON *e = cJSON_CreateObject();
        cJSON_AddNumberToObject(e, "horizon_ms", r->horizon_ms[h]);
        /* the primary truth (sim: the true gaze; recordings: the raw future sample), as before */
        cJSON_AddItemToObject(e, "predicted", err_json(&r->predicted[h]));
        cJSON_AddItemToObject(e, "latest_filtered", err_json(&r->filtered[h]));
        cJSON_AddItemToObject(e, "latest_sample", err_json(&r->latest[h]));
        for (int t = 0; t < FV_SIM_EVAL_TRUTHS; t++) {
            if (t == FV_SIM_EVAL_TRUTH_TRUE && !r->has_truth) continue;
            cJSON *tj = cJSON_AddObjectToObject(e, fv_sim_eval_truth_name((fv_sim_eval_truth)t));
            for (int m = 0; m < FV_SIM_EVAL_METHODS; m++)
                cJSON_AddItemToObject(tj, fv_sim_eval_method_name((fv_sim_eval_method)m), err_json(&r->err[t][m][h]));
        }
        cJSON_AddItemToArray(hs, e);
    }
    cJSON_AddNumberToObject(o, "mean_uncertainty_deg_20ms", r->mean_uncertainty_deg);
    if (r->ns_per_sample > 0.0) cJSON_AddNumberToObject(o, "ns_per_sample", r->ns_per_sample);
    int rc = fv_cli_json_print(o, true);
    cJSON_Delete(o);
    return rc;
}

#define PLOT_SECONDS 5.0 /* the timeline shows the first 5 s (the data file holds all of it) */

/* DIR/gaze_error.csv: one row per horizon, mean and p95 of every method against every truth. */
static bool write_error_csv(const char *path, const fv_sim_eval_result *r)
{
    FILE *f = fopen(path, "w");
    if (!f) return false;
    fputs("horizon_ms", f);
    for (int t = 0; t < FV_SIM_EVAL_TRUTHS; t++)
        for (int m = 0; m < FV_SIM_EVAL_METHODS; m++)
            fprintf(f, ",%s_%s_mean,%s_%s_p95", fv_sim_eval_truth_name((fv_sim_eval_truth)t),
                    fv_sim_eval_method_name((fv_sim_eval_method)m), fv_sim_eval_truth_name((fv_sim_eval_truth)t),
                    fv_sim_eval_method_name((fv_sim_eval_method)m));
    fputc('\n', f);
    for (int h = 0; h < FV_SIM_EVAL_HORIZONS; h++) {
        fprintf(f, "%d", r->horizon_ms[h]);
        for (int t = 0; t < FV_SIM_EVAL_TRUTHS; t++)
            for (int m = 0; m < FV_SIM_EVAL_METHODS; m++) {
                const fv_sim_eval_error *e = &r->err[t][m][h];
                if (e->n == 0) fputs(",NaN,NaN", f);
                else fprintf(f, ",%.5f,%.5f", e->mean_deg, e->p95_deg);
            }
        fputc('\n', f);
    }
    return fclose(f) == 0;
}

static void gp_file(FILE *f, const char *dir, const char *name)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    fv_gnuplot_quoted(f, path);
}

/* gaze_timeline.png (gaze, prediction, truth, uncertainty band, saccade flags) and gaze_error.png (error against
 * horizon), from gaze_timeline.csv and gaze_error.csv, by a script written beside them. */
static int plot(const char *dir, const char *uri, const fv_sim_eval_result *r, int horizon_ms)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/gaze_error.csv", dir);
    if (!write_error_csv(path, r)) {
        fprintf(stderr, "fovea gaze: cannot write %s: %s\n", path, strerror(errno));
        return FV_EXIT_FAIL;
    }
    const char *terminal = fv_gnuplot_terminal("gaze_timeline.csv and gaze_error.csv are written");
    if (!terminal) return FV_EXIT_OK;
    snprintf(path, sizeof path, "%s/gaze_plots.gp", dir);
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "fovea gaze: cannot write %s: %s\n", path, strerror(errno));
        return FV_EXIT_FAIL;
    }
    const char *truth = r->has_truth ? "true gaze" : "smoothed truth";
    char title[600];
    snprintf(title, sizeof title, "%s", uri);
    for (char *c = title; *c; c++)
        if (*c == '"' || *c == '\\' || *c == '\'' || *c == '_' || *c == '@' || *c == '^' || *c == '{' || *c == '}')
            *c = ' ';
    fprintf(f, "# fovea gaze eval --plot (gnuplot %s)\nset terminal %s size 960,640 font ',9'\n", terminal, terminal);
    fputs("set datafile separator ','\nset key top left horizontal font ',8'\n" /* NaN (no data) breaks a line */
          "set grid\nset lmargin 9\n", f);
    fputs("set output ", f);
    gp_file(f, dir, "gaze_timeline.png");
    fprintf(f, "\nset multiplot layout 3,1 title \"%s: first %.0f s; prediction and %s at +%d ms\"\n", title,
            PLOT_SECONDS, truth, horizon_ms);
    fprintf(f, "set xrange [0:%g]\nset format x ''\n", PLOT_SECONDS);
    const char *axes[2][2] = {{"yaw (deg)", "2"}, {"pitch (deg)", "3"}};
    for (int a = 0; a < 2; a++) {
        int raw = a == 0 ? 2 : 3, pr = raw + 2, tr = raw + 4;
        fprintf(f, "set ylabel '%s'\nplot ", axes[a][0]);
        gp_file(f, dir, "gaze_timeline.csv");
        fprintf(f,
                " u 1:($%d-$10):($%d+$10) w filledcurves fs solid 0.25 noborder lc rgb '#9fb8e0' t 'uncertainty', "
                "'' u 1:%d w p pt 7 ps 0.35 lc rgb '#606060' t 'sample', '' u 1:%d w l lw 1.6 lc rgb '#d04020' "
                "t '%s', '' u 1:%d w l lw 1.2 lc rgb '#2050c0' t 'predicted'\n",
                pr, pr, raw, tr, truth, pr);
    }
    fputs("set format x '%g'\nset xlabel 'time (s)'\nset ylabel 'deg'\nset yrange [0:*]\nplot ", f);
    gp_file(f, dir, "gaze_timeline.csv");
    fputs(" u 1:10 w l lc rgb '#2050c0' t 'uncertainty radius', '' u 1:($9*4) w steps lc rgb '#d08000' "
          "t 'saccade flag'\nunset multiplot\nunset output\n",
          f);
    fputs("set output ", f);
    gp_file(f, dir, "gaze_error.png");
    fprintf(f, "\nset terminal %s size 800,420 font ',9'\nset autoscale\nset yrange [0:*]\nset xrange [0:60]\n"
               "set xlabel 'horizon (ms)'\nset ylabel 'angular error (deg)'\nset xtics (0,10,20,40,60)\n"
               "set key top left vertical\nset multiplot layout 1,2 title \"%s\"\n",
            terminal, title);
    const int off = r->has_truth ? 2 * FV_SIM_EVAL_METHODS * 2 : FV_SIM_EVAL_METHODS * 2; /* true / smoothed */
    for (int q = 0; q < 2; q++) {
        fprintf(f, "set title '%s against the %s'\nplot ", q ? "p95" : "mean", r->has_truth ? "true gaze" : "smoothing");
        const char *names[3] = {"predicted", "latest filtered", "latest sample"};
        for (int m = 0; m < FV_SIM_EVAL_METHODS; m++) {
            if (m) fputs(", ", f);
            gp_file(f, dir, "gaze_error.csv");
            fprintf(f, " u 1:%d w lp lw 1.5 t '%s'", 2 + off + 2 * m + q, names[m]);
            fputs(", ", f);
            gp_file(f, dir, "gaze_error.csv");
            fprintf(f, " u 1:%d w lp dt 2 t '%s vs raw'", 2 + 2 * m + q, names[m]);
        }
        fputc('\n', f);
    }
    fputs("unset multiplot\nunset output\n", f);
    if (fclose(f) != 0) {
        fprintf(stderr, "fovea gaze: cannot write %s\n", path);
        return FV_EXIT_FAIL;
    }
    int rc = fv_gnuplot_script(path);
    if (rc != 0) FV_WARN("gaze", "gnuplot %s failed (exit %d): plots may be missing", path, rc);
    return FV_EXIT_OK;
}

static bool parse_float_opt(const char *v, double lo, double hi, float *out)
{
    double d;
    if (!fv_cli_parse_f64(v, lo, hi, &d)) return false;
    *out = (float)d;
    return true;
}

static int cmd_eval(int argc, char **argv)
{
    const char *uri = NULL;
    double seconds = 0.0; /* sim: 60 s; otherwise the whole recording */
    bool json = false, do_bench = false;
    const char *plot_dir = NULL;
    fv_gaze_pipeline_desc pd = {0};
    for (int i = 1; i < argc; i++) {
        const char *v = NULL;
        int m;
        if (fv_cli_is_help(argv[i])) {
            fputs(g_usage, stdout);
            return FV_EXIT_OK;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = true;
        } else if (strcmp(argv[i], "--bench") == 0) {
            do_bench = true;
        } else if ((m = fv_cli_option(argc, argv, &i, "--plot", &v)) != 0) {
            if (m < 0 || !*v) return fv_cli_usage_error("gaze", g_usage, "--plot needs a folder");
            plot_dir = v;
        } else if ((m = fv_cli_option(argc, argv, &i, "--gaze", &v)) != 0) {
            if (m < 0) return fv_cli_usage_error("gaze", g_usage, "--gaze needs a URI");
            uri = v;
        } else if ((m = fv_cli_option(argc, argv, &i, "--seconds", &v)) != 0) {
            if (m < 0 || !fv_cli_parse_f64(v, 0.1, 3600.0, &seconds))
                return fv_cli_usage_error("gaze", g_usage, "--seconds needs a number in [0.1, 3600], got '%s'",
                                          m < 0 ? "" : v);
        } else if ((m = fv_cli_option(argc, argv, &i, "--accuracy-deg", &v)) != 0) {
            if (m < 0 || !parse_float_opt(v, 0.01, 20.0, &pd.accuracy_deg))
                return fv_cli_usage_error("gaze", g_usage, "--accuracy-deg needs a number in [0.01, 20]");
        } else if ((m = fv_cli_option(argc, argv, &i, "--min-cutoff", &v)) != 0) {
            if (m < 0 || !parse_float_opt(v, 0.01, 100.0, &pd.filter_min_cutoff_hz))
                return fv_cli_usage_error("gaze", g_usage, "--min-cutoff needs a frequency in [0.01, 100] Hz");
        } else if ((m = fv_cli_option(argc, argv, &i, "--beta", &v)) != 0) {
            if (m < 0 || !parse_float_opt(v, 1e-6, 100.0, &pd.filter_beta))
                return fv_cli_usage_error("gaze", g_usage, "--beta needs a number in (0, 100]");
        } else if ((m = fv_cli_option(argc, argv, &i, "--saccade-on", &v)) != 0) {
            if (m < 0 || !parse_float_opt(v, 1.0, 2000.0, &pd.saccade_on_deg_s))
                return fv_cli_usage_error("gaze", g_usage, "--saccade-on needs a speed in [1, 2000] deg/s");
        } else if ((m = fv_cli_option(argc, argv, &i, "--tune", &v)) != 0) {
            /* KEY=VALUE: one of the predictor's tuned constants (fv_gaze_tuning), for cross-validation */
            const char *eq = m > 0 ? strchr(v, '=') : NULL;
            char key[40];
            double val = 0.0;
            if (!eq || (size_t)(eq - v) >= sizeof key || !fv_cli_parse_f64(eq + 1, -1e6, 1e6, &val))
                return fv_cli_usage_error("gaze", g_usage, "--tune needs KEY=VALUE, got '%s'", m < 0 ? "" : v);
            snprintf(key, sizeof key, "%.*s", (int)(eq - v), v);
            fv_result tr = fv_gaze_tuning_set(&pd.tuning, key, val);
            if (tr == FV_ERR_NOT_FOUND) {
                char names[400] = "";
                for (int k = 0; fv_gaze_tuning_names[k]; k++)
                    snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", k ? " " : "",
                             fv_gaze_tuning_names[k]);
                return fv_cli_usage_error("gaze", g_usage, "--tune: unknown constant '%s' (one of: %s)", key, names);
            }
            if (tr != FV_OK)
                return fv_cli_usage_error("gaze", g_usage, "--tune %s: %g is out of range (positive; blend 1 or -1)",
                                          key, val);
        } else if ((m = fv_cli_option(argc, argv, &i, "--saccade-off", &v)) != 0) {
            if (m < 0 || !parse_float_opt(v, 1.0, 2000.0, &pd.saccade_off_deg_s))
                return fv_cli_usage_error("gaze", g_usage, "--saccade-off needs a speed in [1, 2000] deg/s");
        } else {
            return fv_cli_usage_error("gaze", g_usage, "unknown option '%s'", argv[i]);
        }
    }
    if (!uri) return fv_cli_usage_error("gaze", g_usage, "eval needs --gaze URI");
    if (pd.saccade_on_deg_s > 0 && pd.saccade_off_deg_s > pd.saccade_on_deg_s)
        return fv_cli_usage_error("gaze", g_usage, "--saccade-off must not exceed --saccade-on");
    fv_clock clock;
    fv_clock_sim_init(&clock, FV_NS_PER_S);
    fv_device_open_desc od = {.clock = &clock};
    fv_device *dev = NULL;
    fv_result r = fv_app_device_open(uri, &od, &dev);
    if (r != FV_OK) {
        fprintf(stderr, "fovea gaze: cannot open '%s': %s\n", uri, fv_result_str(r));
        return FV_EXIT_FAIL;
    }
    char timeline[4200];
    if (plot_dir) {
        if (strlen(plot_dir) > 4000 || (mkdir(plot_dir, 0777) != 0 && errno != EEXIST)) {
            fprintf(stderr, "fovea gaze: cannot create the plot folder '%s': %s\n", plot_dir,
                    strlen(plot_dir) > 4000 ? "name too long" : strerror(errno));
            fv_device_close(&dev);
            return FV_EXIT_FAIL;
        }
        snprintf(timeline, sizeof timeline, "%s/gaze_timeline.csv", plot_dir);
    }
    fv_sim_eval_desc ed = {.seconds = seconds, .pipeline = pd, .bench_repeats = do_bench ? 5 : 0,
                           .timeline_csv = plot_dir ? timeline : NULL};
    fv_sim_eval_result res;
    r = fv_sim_eval_run(dev, &clock, &ed, &res);
    /* blinks as `fovea trace info` counts them: the source's events when the format has them */
    uint64_t blink_events = fv_trace_device_blink_events(dev);
    if (r == FV_OK && blink_events > 0) res.recorded_blinks = blink_events;
    /* physically impossible gaze the reader repaired or marked invalid (the same rules make the truth) */
    const fv_trace_reader_stats *rs = fv_trace_device_reader_stats(dev);
    fv_gaze_validity_counts validity = {0};
    const bool have_validity = rs != NULL;
    if (rs) validity = rs->validity;
    fv_device_close(&dev);
    if (r != FV_OK) {
        fprintf(stderr, "fovea gaze: evaluating '%s' failed: %s\n", uri, fv_result_str(r));
        return FV_EXIT_FAIL;
    }
    if (plot_dir) {
        int prc = plot(plot_dir, uri, &res, 20);
        if (prc != FV_EXIT_OK) return prc;
    }
    char why[320];
    fv_gaze_validity_describe(&validity, why, sizeof why);
    if (json) return print_json(uri, &res, have_validity ? &validity : NULL, why);
    print_text(uri, &res);
    if (have_validity) printf("  impossible gaze (read as invalid, never scored): %s\n", why);
    return FV_EXIT_OK;
}

int fv_cmd_gaze(int argc, char **argv)
{
    if (argc < 2) return fv_cli_usage_error("gaze", g_usage, "missing subcommand (eval)");
    if (fv_cli_is_help(argv[1])) {
        fputs(g_usage, stdout);
        return FV_EXIT_OK;
    }
    if (strcmp(argv[1], "eval") == 0) return cmd_eval(argc - 1, argv + 1);
    return fv_cli_usage_error("gaze", g_usage, "unknown subcommand '%s'", argv[1]);
}
