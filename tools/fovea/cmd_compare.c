/* @brief `fovea compare A B`: image metrics of A against the reference B (PSNR, SSIM, mismatch, relative error of
 * linear images), over the whole image and per eccentricity band around a gaze, as text or one JSON object. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "tool_image.h"
#include "fovea/fv_frame_input.h"
#include "fv_file.h"
#include "fv_image_io.h"
#include "fv_log.h"
#include "fv_metrics.h"

static const char g_usage[] =
    "usage: fovea compare A B [--gaze X,Y | --gaze-deg YAW,PITCH] [--threshold T] [--layout sbs|mono]\n"
    "                         [--max-memory-mib M] [--json]\n"
    "  Compares image A with the reference B: both PNG (8-bit, read as sRGB in [0,1]; alpha ignored) or both PFM\n"
    "  (linear float), of the same size. Images `fovea run` and `fovea reference` wrote carry their settings in a\n"
    "  .json beside them: when both do and their eye size, layout, view or lens differ (or the exposure, for\n"
    "  PNGs), the comparison is refused (exit 2); one without it is compared with a warning.\n"
    "  psnr      dB over the three sRGB channels, data range 1 (scikit-image's peak_signal_noise_ratio);\n"
    "            identical sRGB values: 'inf' in text, null in JSON (\"psnr_infinite\": true)\n"
    "  ssim      on luma Y' = 0.299 R' + 0.587 G' + 0.114 B', Gaussian window sigma 1.5 (11x11), K1 0.01, K2 0.03,\n"
    "            population covariances, border of 5 cropped (scikit-image's structural_similarity); images\n"
    "            smaller than 11x11 are refused, as scikit-image refuses them\n"
    "  PFM values are sRGB-encoded and clamped to [0,1] for psnr and ssim, and also give the relative error\n"
    "  |A - B| / max(|B|, 1e-3) over every channel value: mean, p99 (nearest rank), max. A NaN or Inf value in\n"
    "  either file is refused, naming the pixel.\n"
    "  mismatch  fraction of pixels where a channel differs by more than T (in the files' own values: sRGB [0,1]\n"
    "            for PNG, linear for PFM)\n"
    "  bands     each metric per eccentricity band (0-5, 5-10, 10-20, 20-30, 30-180 deg from the gaze ray), the\n"
    "            pixels' rays from the views `fovea run` renders (identity head, IPD 63 mm, the per-eye size);\n"
    "            a stereo image's band SSIM comes from each eye's own map\n"
    "  --layout    sbs: two eyes side by side (left | right, 2W x H, as `fovea run` writes); mono: one view, the\n"
    "              left eye's. Default: sbs when the width is even, mono when it is odd\n"
    "  --gaze X,Y  the gaze ray passes through pixel (X, Y) of the left eye (0,0 = top-left pixel); both eyes look\n"
    "              in that direction\n"
    "  --gaze-deg YAW,PITCH  the gaze direction in the head frame, degrees: yaw positive right, pitch positive up\n"
    "              (default: straight ahead, 0,0)\n"
    "  --threshold T  mismatch threshold, >= 0 (default 0: any difference)\n"
    "  --max-memory-mib M  the memory budget of the comparison, MiB (default 1024): both files' bytes, both\n"
    "              decoded images (12 bytes a pixel each; a PNG's decoder 9 more), the eccentricity map (4) and\n"
    "              the metrics' scratch (80 bytes a pixel; PFM 128). Weighed from the files' headers before any\n"
    "              pixel is decoded: about 126 bytes a pixel for PNGs (1024 MiB: 8.5 Mpx, e.g. 2 x 2048x2048),\n"
    "              180 for PFMs. Larger images are refused, naming the estimate and the budget\n"
    "  --json      print one JSON object on stdout\n"
    "  Only regular files are read (a FIFO, device or directory is refused, never waited on), each of at most\n"
    "  1 GiB and the budget; images of at most 16384 pixels a side and 64 Mpx.\n"
    "  Exit status: 0 compared, 1 a file unreadable or the two not comparable, 2 bad command line.\n";

typedef enum gaze_from { GAZE_DEFAULT, GAZE_PIXEL, GAZE_DEG } gaze_from;
typedef enum layout { LAYOUT_AUTO, LAYOUT_SBS, LAYOUT_MONO } layout;

typedef struct compare_opts {
    const char *path[2];
    gaze_from gaze;
    double gaze_v[2]; /* pixel X,Y or yaw,pitch degrees */
    double threshold;
    layout layout;
    bool json;
    uint64_t budget_bytes;
} compare_opts;

#define DEFAULT_BUDGET_MIB 1024
#define MAX_BUDGET_MIB (1024 * 1024)

/* Errors from the library, each one line: "fovea compare: <reason>". */
static void error_sink(void *user, fv_log_level level, const char *module, const char *file, int line, const char *msg)
{
    (void)user, (void)module, (void)file, (void)line;
    if (level <= FV_LOG_LEVEL_WARN) fprintf(stderr, "fovea compare: %s\n", msg);
}

static int parse_args(int argc, char **argv, compare_opts *o, bool *out_help)
{
    *o = (compare_opts){.threshold = 0.0, .budget_bytes = (uint64_t)DEFAULT_BUDGET_MIB << 20};
    *out_help = false;
    int npos = 0;
    for (int i = 1; i < argc; i++) {
        const char *v = NULL;
        int m;
        if (fv_cli_is_help(argv[i])) {
            *out_help = true;
            return FV_EXIT_OK;
        } else if (strcmp(argv[i], "--json") == 0) {
            o->json = true;
        } else if ((m = fv_cli_option(argc, argv, &i, "--gaze-deg", &v)) != 0) {
            if (o->gaze == GAZE_PIXEL) return fv_cli_usage_error("compare", g_usage, "--gaze and --gaze-deg exclude each other");
            if (m < 0 || !fv_cli_parse_f64_pair(v, -180.0, 180.0, o->gaze_v) || fabs(o->gaze_v[1]) > 90.0)
                return fv_cli_usage_error("compare", g_usage,
                                          "--gaze-deg: '%s' is not YAW,PITCH in degrees (yaw -180..180, pitch -90..90)",
                                          m < 0 ? "" : v);
            o->gaze = GAZE_DEG;
        } else if ((m = fv_cli_option(argc, argv, &i, "--gaze", &v)) != 0) {
            if (o->gaze == GAZE_DEG) return fv_cli_usage_error("compare", g_usage, "--gaze and --gaze-deg exclude each other");
            if (m < 0 || !fv_cli_parse_f64_pair(v, 0.0, (double)FV_IMAGE_MAX_SIDE_PX, o->gaze_v))
                return fv_cli_usage_error("compare", g_usage, "--gaze: '%s' is not a pixel position X,Y",
                                          m < 0 ? "" : v);
            o->gaze = GAZE_PIXEL;
        } else if ((m = fv_cli_option(argc, argv, &i, "--threshold", &v)) != 0) {
            if (m < 0 || !fv_cli_parse_f64(v, 0.0, 3.4e38, &o->threshold))
                return fv_cli_usage_error("compare", g_usage, "--threshold: '%s' is not a number >= 0", m < 0 ? "" : v);
        } else if ((m = fv_cli_option(argc, argv, &i, "--max-memory-mib", &v)) != 0) {
            int64_t mib;
            if (m < 0 || !fv_cli_parse_i64(v, 1, MAX_BUDGET_MIB, &mib))
                return fv_cli_usage_error("compare", g_usage, "--max-memory-mib: '%s' is not a whole number in 1..%d",
                                          m < 0 ? "" : v, MAX_BUDGET_MIB);
            o->budget_bytes = (uint64_t)mib << 20;
        } else if ((m = fv_cli_option(argc, argv, &i, "--layout", &v)) != 0) {
            if (m < 0 || (strcmp(v, "sbs") != 0 && strcmp(v, "mono") != 0))
                return fv_cli_usage_error("compare", g_usage, "--layout: '%s' is not one of sbs, mono", m < 0 ? "" : v);
            o->layout = strcmp(v, "sbs") == 0 ? LAYOUT_SBS : LAYOUT_MONO;
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            return fv_cli_usage_error("compare", g_usage, "unknown option '%s'", argv[i]);
        } else {
            if (npos == 2) return fv_cli_usage_error("compare", g_usage, "one image too many: '%s'", argv[i]);
            o->path[npos++] = argv[i];
        }
    }
    if (npos < 2) return fv_cli_usage_error("compare", g_usage, "needs two images, A and B");
    return FV_EXIT_OK;
}

/* The run's geometry: eyes, per-eye size, gaze direction and each pixel's eccentricity. */
typedef struct geometry {
    uint32_t eyes, eye_w, eye_h;
    fv_vec3 dir_head;
    double yaw_deg, pitch_deg;
    float *ecc_deg;
} geometry;

static int build_geometry(const compare_opts *o, const fv_rgb_image *a, geometry *g)
{
    memset(g, 0, sizeof *g);
    bool even = a->width % 2 == 0;
    if (o->layout == LAYOUT_SBS && !even) {
        fprintf(stderr, "fovea compare: --layout sbs needs an even width; %s is %ux%u\n", o->path[0], a->width,
                a->height);
        return FV_EXIT_FAIL;
    }
    g->eyes = o->layout == LAYOUT_MONO || !even ? 1 : 2;
    g->eye_w = a->width / g->eyes;
    g->eye_h = a->height;
    fv_eye_view views[2];
    fv_eye_views_build(NULL, 0.05f, 100.0f, g->eye_w, g->eye_h, views); /* as `fovea run`: identity head */
    g->dir_head = fv_v3(0.0f, 0.0f, -1.0f);
    if (o->gaze == GAZE_DEG) {
        g->dir_head = fv_metrics_gaze_dir_from_deg(o->gaze_v[0], o->gaze_v[1]);
    } else if (o->gaze == GAZE_PIXEL) {
        if (o->gaze_v[0] >= g->eye_w || o->gaze_v[1] >= g->eye_h)
            return fv_cli_usage_error("compare", g_usage, "--gaze: (%g, %g) is outside the left eye (%ux%u)",
                                      o->gaze_v[0], o->gaze_v[1], g->eye_w, g->eye_h);
        g->dir_head = fv_metrics_view_ray(&views[0], g->eye_w, g->eye_h, o->gaze_v[0], o->gaze_v[1]);
    }
    g->yaw_deg = fv_rad_to_deg(atan2(g->dir_head.x, -g->dir_head.z));
    g->pitch_deg = fv_rad_to_deg(asin(fmax(-1.0, fmin(1.0, g->dir_head.y))));
    g->ecc_deg = malloc((size_t)a->width * a->height * sizeof(float));
    if (!g->ecc_deg) {
        fprintf(stderr, "fovea compare: out of memory\n");
        return FV_EXIT_FAIL;
    }
    /* The head is the identity, so each eye's view space is the head frame moved: the direction holds for both. */
    for (uint32_t e = 0; e < g->eyes; e++)
        fv_metrics_eccentricity_deg(&views[e], g->dir_head, g->eye_w, g->eye_h, g->ecc_deg + e * g->eye_w, a->width);
    return FV_EXIT_OK;
}

/* ---- output ---- */

static void stats_json(cJSON *o, const fv_metrics_stats *s, bool linear, double eps)
{
    cJSON_AddNumberToObject(o, "pixels", (double)s->pixels);
    fv_cli_json_number(o, "psnr_db", s->psnr_db);
    cJSON_AddBoolToObject(o, "psnr_infinite", isinf(s->psnr_db));
    fv_cli_json_number(o, "ssim", s->ssim);
    cJSON_AddNumberToObject(o, "ssim_pixels", (double)s->ssim_pixels);
    fv_cli_json_number(o, "mismatch", s->mismatch);
    cJSON_AddNumberToObject(o, "mismatch_pixels", (double)s->mismatch_pixels);
    if (!linear) return;
    cJSON *r = cJSON_AddObjectToObject(o, "rel_error");
    cJSON_AddNumberToObject(r, "eps", eps);
    fv_cli_json_number(r, "mean", s->rel_mean);
    fv_cli_json_number(r, "p99", s->rel_p99);
    fv_cli_json_number(r, "max", s->rel_max);
}

static int print_json(const compare_opts *o, const fv_rgb_image *a, const geometry *g, const fv_metrics_report *rep)
{
    bool linear = a->kind == FV_IMAGE_KIND_LINEAR;
    cJSON *j = cJSON_CreateObject();
    if (!j) return FV_EXIT_FAIL;
    fv_cli_json_add_string(j, "a", o->path[0]);
    fv_cli_json_add_string(j, "b", o->path[1]);
    fv_cli_json_add_string(j, "kind", linear ? "pfm" : "png");
    cJSON_AddNumberToObject(j, "width", a->width);
    cJSON_AddNumberToObject(j, "height", a->height);
    fv_cli_json_add_string(j, "layout", g->eyes == 2 ? "sbs" : "mono");
    cJSON_AddNumberToObject(j, "eyes", g->eyes);
    cJSON_AddNumberToObject(j, "eye_width", g->eye_w);
    cJSON_AddNumberToObject(j, "eye_height", g->eye_h);
    cJSON_AddNumberToObject(j, "threshold", o->threshold);
    cJSON *gz = cJSON_AddObjectToObject(j, "gaze");
    fv_cli_json_add_string(gz, "from", o->gaze == GAZE_PIXEL ? "pixel" : o->gaze == GAZE_DEG ? "deg" : "default");
    if (o->gaze == GAZE_PIXEL) {
        cJSON_AddNumberToObject(gz, "x_px", o->gaze_v[0]);
        cJSON_AddNumberToObject(gz, "y_px", o->gaze_v[1]);
    }
    cJSON_AddNumberToObject(gz, "yaw_deg", g->yaw_deg);
    cJSON_AddNumberToObject(gz, "pitch_deg", g->pitch_deg);
    const double d[3] = {g->dir_head.x, g->dir_head.y, g->dir_head.z};
    cJSON_AddItemToObject(gz, "dir_head", cJSON_CreateDoubleArray(d, 3));
    stats_json(j, &rep->all, linear, rep->rel_eps);
    cJSON *bands = cJSON_AddArrayToObject(j, "bands");
    for (int k = 0; k < FV_METRICS_BANDS; k++) {
        cJSON *b = cJSON_CreateObject();
        cJSON_AddNumberToObject(b, "from_deg", fv_metrics_band_edges_deg[k]);
        cJSON_AddNumberToObject(b, "to_deg", fv_metrics_band_edges_deg[k + 1]);
        stats_json(b, &rep->band[k], linear, rep->rel_eps);
        cJSON_AddItemToArray(bands, b);
    }
    int rc = fv_cli_json_print(j, false);
    cJSON_Delete(j);
    return rc;
}

static void print_row(const char *label, const fv_metrics_stats *s, bool linear)
{
    char p[32], q[32], m[32], r0[32], r1[32], r2[32];
    printf("  %-9s %10llu %9s %9s %9s", label, (unsigned long long)s->pixels,
           fv_cli_format_number(p, sizeof p, "%.3f", s->psnr_db), fv_cli_format_number(q, sizeof q, "%.5f", s->ssim),
           fv_cli_format_number(m, sizeof m, "%.4f", s->mismatch));
    if (linear)
        printf(" %10s %10s %10s", fv_cli_format_number(r0, sizeof r0, "%.4g", s->rel_mean),
               fv_cli_format_number(r1, sizeof r1, "%.4g", s->rel_p99),
               fv_cli_format_number(r2, sizeof r2, "%.4g", s->rel_max));
    printf("\n");
}

static void print_text(const compare_opts *o, const fv_rgb_image *a, const geometry *g, const fv_metrics_report *rep)
{
    bool linear = a->kind == FV_IMAGE_KIND_LINEAR;
    printf("compare: %s vs %s (reference)\n", o->path[0], o->path[1]);
    printf("  %ux%u %s, %s", a->width, a->height, fv_image_kind_str(a->kind),
           g->eyes == 2 ? "side-by-side stereo" : "one view");
    printf(" (%u eye%s of %ux%u); gaze yaw %.2f pitch %.2f deg; mismatch: a channel differs by more than %g\n",
           g->eyes, g->eyes == 2 ? "s" : "", g->eye_w, g->eye_h, g->yaw_deg, g->pitch_deg, o->threshold);
    printf("  %-9s %10s %9s %9s %9s", "pixels", "count", "psnr dB", "ssim", "mismatch");
    if (linear) printf(" %10s %10s %10s", "rel mean", "rel p99", "rel max");
    printf("\n");
    print_row("all", &rep->all, linear);
    for (int k = 0; k < FV_METRICS_BANDS; k++) {
        char label[32];
        snprintf(label, sizeof label, "%g-%g deg", fv_metrics_band_edges_deg[k], fv_metrics_band_edges_deg[k + 1]);
        print_row(label, &rep->band[k], linear);
    }
    if (linear) printf("  relative error: |A - B| / max(|B|, %g) over every channel value\n", rep->rel_eps);
}

/* Read both files and weigh everything the comparison will hold against the budget, from their headers, before a
 * pixel is decoded; then decode them. */
static int read_images(const compare_opts *o, fv_rgb_image img[2])
{
    fv_image_file f[2] = {{0}};
    int rc = FV_EXIT_FAIL;
    if (fv_image_io_load(o->path[0], o->budget_bytes, &f[0]) != FV_OK ||
        fv_image_io_load(o->path[1], o->budget_bytes - f[0].size, &f[1]) != FV_OK)
        goto done;
    const fv_image_info *a = &f[0].info, *b = &f[1].info;
    uint64_t need = f[0].size + f[1].size + fv_image_io_decode_bytes(a) + fv_image_io_decode_bytes(b);
    if (a->width == b->width && a->height == b->height && a->kind == b->kind) /* else refused before the metrics */
        need += (uint64_t)a->width * a->height * sizeof(float) + /* the eccentricity map */
                fv_metrics_compare_bytes(a->width, a->height, a->kind == FV_IMAGE_KIND_LINEAR, true);
    char what[2 * FV_FILE_ERR_MAX];
    snprintf(what, sizeof what, "%s (%ux%u %s) against %s (%ux%u %s)", o->path[0], a->width, a->height,
             fv_image_kind_str(a->kind), o->path[1], b->width, b->height, fv_image_kind_str(b->kind));
    if (fv_image_io_check_budget(what, need, o->budget_bytes, "(--max-memory-mib)") != FV_OK) goto done;
    if (fv_image_io_decode(&f[0], &img[0]) != FV_OK || fv_image_io_decode(&f[1], &img[1]) != FV_OK) goto done;
    rc = FV_EXIT_OK;
done:
    fv_image_file_fini(&f[0]);
    fv_image_file_fini(&f[1]);
    return rc;
}

int fv_cmd_compare(int argc, char **argv)
{
    compare_opts o;
    bool help;
    int rc = parse_args(argc, argv, &o, &help);
    if (rc != FV_EXIT_OK) return rc;
    if (help) {
        fputs(g_usage, stdout);
        return FV_EXIT_OK;
    }
    { /* the settings beside the images (fovea run / reference write them): refuse a comparison of different things */
        char why[1024], note[1024];
        if (!fv_tool_image_comparable(o.path[0], o.path[1], why, sizeof why, note, sizeof note)) {
            fprintf(stderr, "fovea compare: %s\n", why);
            return FV_EXIT_USAGE;
        }
        if (note[0]) fprintf(stderr, "fovea compare: warning: %s\n", note);
    }
    fv_log_set_sink(error_sink, NULL);
    fv_rgb_image img[2] = {{0}};
    geometry g = {0};
    rc = FV_EXIT_FAIL;
    if (read_images(&o, img) != FV_EXIT_OK) goto done;
    fv_metrics_desc d = {.name_a = o.path[0], .name_b = o.path[1], .mismatch_threshold = o.threshold};
    bool same_size = img[0].width == img[1].width && img[0].height == img[1].height;
    if (same_size) { /* otherwise fv_metrics_compare says why they cannot be compared */
        rc = build_geometry(&o, &img[0], &g);
        if (rc != FV_EXIT_OK) goto done;
        d.ecc_deg = g.ecc_deg;
        d.eyes = g.eyes;
    }
    fv_metrics_report rep;
    rc = FV_EXIT_FAIL;
    if (fv_metrics_compare(&img[0], &img[1], &d, &rep) != FV_OK) goto done;
    if (o.json) {
        rc = print_json(&o, &img[0], &g, &rep);
    } else {
        print_text(&o, &img[0], &g, &rep);
        rc = FV_EXIT_OK;
    }
done:
    fv_log_set_sink(NULL, NULL);
    free(g.ecc_deg);
    fv_rgb_image_fini(&img[0]);
    fv_rgb_image_fini(&img[1]);
    return rc;
}
