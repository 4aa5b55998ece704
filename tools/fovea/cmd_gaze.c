/* @brief `fovea gaze eval`: evaluate the gaze pipeline on a device (the simulated eye, against its ground truth;
 * a recording, against its own later samples): saccade detection F1, angular error at photon time with and
 * without prediction for several horizons, and the pipeline's cost per sample. */
#include <stdio.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "fv_clock.h"
#include "fv_gaze_pipeline.h"
#include "fv_log.h"
#include "fv_sim_eval.h"
#include "tool_devices.h"

static const char g_usage[] =
    "usage: fovea gaze eval --gaze URI [--seconds S] [--json] [--bench] [--accuracy-deg D] [--min-cutoff HZ]\n"
    "                       [--beta B] [--saccade-on DEG_S] [--saccade-off DEG_S]\n"
    "  Runs the gaze pipeline over URI on a simulated clock (deterministic) and reports:\n"
    "  - saccade detection precision/recall/F1 (sim: URIs, event matching against the ground truth),\n"
    "  - mean and 95th-percentile angular error at photon time (newest sample's receipt + 0/10/20/40 ms) for the\n"
    "    prediction, the latest filtered sample and the latest raw sample (sim: against the true gaze;\n"
    "    recordings such as trace:FILE: against the later samples themselves),\n"
    "  - with --bench, the pipeline's cost per sample (push + one predict) in ns.\n"
    "  URI examples: sim:seed=1   sim:seed=3,rate_hz=250,precision_deg=0.3   trace:rec.csv\n"
    "  sim: keys: seed rate_hz jitter_us latency_ms transport_jitter_ms dropout eye_loss precision_deg\n"
    "             accuracy_deg blink_per_min pursuit_prob microsaccades skew_ppm device_offset_s ipd_mm\n"
    "             vmax_deg_s c_deg main_seq_spread ts_bits\n"
    "  --seconds S   device time to evaluate (default 60, at most 3600)\n";

static void print_text(const char *uri, const fv_sim_eval_result *r)
{
    printf("gaze eval: %s\n", uri);
    printf("  samples %llu over %.1f s (%.1f Hz), invalid %llu, one-eye %llu, rejected %llu, clock skew %.1f ppm\n",
           (unsigned long long)r->samples, r->seconds, r->rate_hz, (unsigned long long)r->invalid,
           (unsigned long long)r->one_eye, (unsigned long long)r->rejected, r->skew_ppm);
    if (r->has_truth) {
        printf("  saccades: %llu true (+%llu hidden by blinks), detected %llu: TP %llu FP %llu FN %llu\n",
               (unsigned long long)r->true_saccades, (unsigned long long)r->true_saccades_hidden,
               (unsigned long long)r->det_saccades, (unsigned long long)r->tp, (unsigned long long)r->fp,
               (unsigned long long)r->fn);
        printf("  saccade detection: precision %.3f recall %.3f F1 %.3f\n", r->precision, r->recall, r->f1);
    } else {
        printf("  detected: %llu saccades, %llu pursuits, %llu blinks (no ground truth: errors are vs later "
               "samples)\n",
               (unsigned long long)r->det_saccades, (unsigned long long)r->det_pursuits,
               (unsigned long long)r->det_blinks);
    }
    printf("  angular error at photon time (deg)   %-17s %-17s %-17s\n", "predicted", "latest filtered",
           "latest sample");
    printf("  %-36s %-17s %-17s %-17s\n", "horizon", "mean / p95", "mean / p95", "mean / p95");
    for (int h = 0; h < FV_SIM_EVAL_HORIZONS; h++) {
        char a[32], b[32], c[32], hz[32];
        snprintf(hz, sizeof hz, "%d ms", r->horizon_ms[h]);
        snprintf(a, sizeof a, "%.3f / %.3f", r->predicted[h].mean_deg, r->predicted[h].p95_deg);
        snprintf(b, sizeof b, "%.3f / %.3f", r->filtered[h].mean_deg, r->filtered[h].p95_deg);
        snprintf(c, sizeof c, "%.3f / %.3f", r->latest[h].mean_deg, r->latest[h].p95_deg);
        printf("  %-36s %-17s %-17s %-17s\n", hz, a, b, c);
    }
    printf("  mean uncertainty radius at 20 ms: %.2f deg\n", r->mean_uncertainty_deg);
    if (r->ns_per_sample > 0.0) printf("  pipeline cost: %.0f ns per sample (push + predict)\n", r->ns_per_sample);
}

static cJSON *err_json(const fv_sim_eval_error *e)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "mean_deg", e->mean_deg);
    cJSON_AddNumberToObject(o, "p95_deg", e->p95_deg);
    cJSON_AddNumberToObject(o, "n", (double)e->n);
    return o;
}

static int print_json(const char *uri, const fv_sim_eval_result *r)
{
    cJSON *o = cJSON_CreateObject();
    if (!o) return FV_EXIT_FAIL;
    fv_cli_json_add_string(o, "uri", uri);
    cJSON_AddBoolToObject(o, "ground_truth", r->has_truth);
    cJSON_AddNumberToObject(o, "samples", (double)r->samples);
    cJSON_AddNumberToObject(o, "seconds", r->seconds);
    cJSON_AddNumberToObject(o, "rate_hz", r->rate_hz);
    cJSON_AddNumberToObject(o, "invalid", (double)r->invalid);
    cJSON_AddNumberToObject(o, "one_eye", (double)r->one_eye);
    cJSON_AddNumberToObject(o, "rejected", (double)r->rejected);
    cJSON_AddNumberToObject(o, "clock_skew_ppm", r->skew_ppm);
    cJSON *s = cJSON_AddObjectToObject(o, "saccades");
    cJSON_AddNumberToObject(s, "detected", (double)r->det_saccades);
    if (r->has_truth) {
        cJSON_AddNumberToObject(s, "true", (double)r->true_saccades);
        cJSON_AddNumberToObject(s, "hidden_by_blinks", (double)r->true_saccades_hidden);
        cJSON_AddNumberToObject(s, "tp", (double)r->tp);
        cJSON_AddNumberToObject(s, "fp", (double)r->fp);
        cJSON_AddNumberToObject(s, "fn", (double)r->fn);
        cJSON_AddNumberToObject(s, "precision", r->precision);
        cJSON_AddNumberToObject(s, "recall", r->recall);
        cJSON_AddNumberToObject(s, "f1", r->f1);
        cJSON_AddNumberToObject(s, "match_tolerance_ms", FV_SIM_EVAL_MATCH_TOL_MS);
    }
    cJSON_AddNumberToObject(o, "detected_pursuits", (double)r->det_pursuits);
    cJSON_AddNumberToObject(o, "detected_blinks", (double)r->det_blinks);
    cJSON *hs = cJSON_AddArrayToObject(o, "horizons");
    for (int h = 0; h < FV_SIM_EVAL_HORIZONS; h++) {
        cJSON *e = cJSON_CreateObject();
        cJSON_AddNumberToObject(e, "horizon_ms", r->horizon_ms[h]);
        cJSON_AddItemToObject(e, "predicted", err_json(&r->predicted[h]));
        cJSON_AddItemToObject(e, "latest_filtered", err_json(&r->filtered[h]));
        cJSON_AddItemToObject(e, "latest_sample", err_json(&r->latest[h]));
        cJSON_AddItemToArray(hs, e);
    }
    cJSON_AddNumberToObject(o, "mean_uncertainty_deg_20ms", r->mean_uncertainty_deg);
    if (r->ns_per_sample > 0.0) cJSON_AddNumberToObject(o, "ns_per_sample", r->ns_per_sample);
    int rc = fv_cli_json_print(o, true);
    cJSON_Delete(o);
    return rc;
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
    double seconds = 60.0;
    bool json = false, do_bench = false;
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
    fv_result r = fv_tool_device_open(uri, &od, &dev);
    if (r != FV_OK) {
        fprintf(stderr, "fovea gaze: cannot open '%s': %s\n", uri, fv_result_str(r));
        return FV_EXIT_FAIL;
    }
    fv_sim_eval_desc ed = {.seconds = seconds, .pipeline = pd, .bench_repeats = do_bench ? 5 : 0};
    fv_sim_eval_result res;
    r = fv_sim_eval_run(dev, &clock, &ed, &res);
    fv_device_close(&dev);
    if (r != FV_OK) {
        fprintf(stderr, "fovea gaze: evaluating '%s' failed: %s\n", uri, fv_result_str(r));
        return FV_EXIT_FAIL;
    }
    if (json) return print_json(uri, &res);
    print_text(uri, &res);
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
