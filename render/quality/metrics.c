/* @brief PSNR, SSIM, relative error and mismatch, per image and per eccentricity band, in double precision. SSIM
 * follows Wang et al. 2004 (eq. 13) as scikit-image 0.19 computes it: scipy.ndimage.gaussian_filter (sigma 1.5,
 * truncate 3.5, mode 'reflect', axis 0 then axis 1), population covariances, the map cropped by 5 before its mean. */
#include "fv_metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_stats.h"

#define MOD "quality"

const double fv_metrics_band_edges_deg[FV_METRICS_BANDS + 1] = {0.0, 5.0, 10.0, 20.0, 30.0, 180.0};

double fv_metrics_linear_to_srgb(double x)
{
    if (!(x > 0.0)) return 0.0; /* negative and NaN */
    if (x >= 1.0) return 1.0;
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

/* Pixel i's three sRGB values in [0, 1]. */
static void pixel_srgb(const fv_rgb_image *img, size_t i, double out[3])
{
    const float *p = img->rgb + i * 3;
    for (int c = 0; c < 3; c++)
        out[c] = img->kind == FV_IMAGE_KIND_LINEAR ? fv_metrics_linear_to_srgb(p[c]) : (double)p[c];
}

static double luma_of(const double s[3]) { return 0.299 * s[0] + 0.587 * s[1] + 0.114 * s[2]; }

void fv_metrics_srgb_values(const fv_rgb_image *img, double *out)
{
    size_t n = (size_t)img->width * img->height;
    for (size_t i = 0; i < n; i++) pixel_srgb(img, i, out + i * 3);
}

void fv_metrics_luma(const double *srgb, size_t n_px, double *out_luma)
{
    for (size_t i = 0; i < n_px; i++) out_luma[i] = luma_of(srgb + i * 3);
}

double fv_metrics_mse(const double *a, const double *b, size_t n)
{
    if (n == 0) return NAN;
    double s = 0.0;
    for (size_t i = 0; i < n; i++) s += (a[i] - b[i]) * (a[i] - b[i]);
    return s / (double)n;
}

double fv_metrics_psnr_db(double mse)
{
    if (isnan(mse)) return NAN;
    if (mse <= 0.0) return INFINITY;
    return 10.0 * log10(1.0 / mse);
}

/* ---- SSIM ---- */

/* scipy.ndimage._gaussian_kernel1d: exp(-x^2 / (2 sigma^2)) for x in [-r, r], normalised to sum 1. */
static void gaussian_kernel(double k[FV_METRICS_SSIM_WIN])
{
    double sum = 0.0, s2 = FV_METRICS_SSIM_SIGMA * FV_METRICS_SSIM_SIGMA;
    for (int j = 0; j < FV_METRICS_SSIM_WIN; j++) {
        double x = (double)(j - FV_METRICS_SSIM_RADIUS);
        k[j] = exp(-0.5 / s2 * x * x);
        sum += k[j];
    }
    for (int j = 0; j < FV_METRICS_SSIM_WIN; j++) k[j] /= sum;
}

/* scipy's mode 'reflect' (d c b a | a b c d | d c b a): the edge sample repeats; period 2n for any offset. */
static size_t reflect(long i, size_t n)
{
    long p = 2 * (long)n;
    i %= p;
    if (i < 0) i += p;
    return (size_t)(i < (long)n ? i : p - 1 - i);
}

/* The filter's taps: its weights and, for each output row/column i, the reflected source index of tap j at
 * ry[i + j] / rx[i + j] (tables of h + 2r and w + 2r entries). */
typedef struct taps {
    double k[FV_METRICS_SSIM_WIN];
    size_t *rx, *ry;
} taps;

/* Separable Gaussian of a w x h image (row stride `stride`) into out (dense): axis 0 (down the columns) into tmp,
 * then axis 1 (along the rows), as scipy's gaussian_filter orders its 1-D passes. */
static void gaussian_filter(const double *in, size_t stride, uint32_t w, uint32_t h, const taps *t, double *tmp,
                            double *out)
{
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            double s = 0.0;
            for (int j = 0; j < FV_METRICS_SSIM_WIN; j++) s += t->k[j] * in[t->ry[y + j] * stride + x];
            tmp[(size_t)y * w + x] = s;
        }
    for (uint32_t y = 0; y < h; y++) {
        const double *row = tmp + (size_t)y * w;
        for (uint32_t x = 0; x < w; x++) {
            double s = 0.0;
            for (int j = 0; j < FV_METRICS_SSIM_WIN; j++) s += t->k[j] * row[t->rx[x + j]];
            out[(size_t)y * w + x] = s;
        }
    }
}

/* skimage raises ValueError("win_size exceeds image extent") there; so do we. */
static fv_result window_fits(const char *name, uint32_t w, uint32_t h)
{
    if (w >= FV_METRICS_SSIM_WIN && h >= FV_METRICS_SSIM_WIN) return FV_OK;
    FV_ERROR(MOD, "%s: %ux%u is smaller than the %dx%d SSIM window (scikit-image refuses it too)", name, w, h,
             FV_METRICS_SSIM_WIN, FV_METRICS_SSIM_WIN);
    return FV_ERR_RANGE;
}

fv_result fv_metrics_ssim_map(const double *a, const double *b, uint32_t w, uint32_t h, size_t stride,
                              double *out_map)
{
    if (!a || !b || !out_map || stride < w) return FV_ERR_INVALID_ARG;
    FV_TRY(window_fits("SSIM", w, h));
    size_t n = (size_t)w * h;
    const long r = FV_METRICS_SSIM_RADIUS;
    double *buf = malloc(n * 7 * sizeof(double));
    taps t = {.rx = malloc(((size_t)w + 2 * r) * sizeof(size_t)), .ry = malloc(((size_t)h + 2 * r) * sizeof(size_t))};
    if (!buf || !t.rx || !t.ry) {
        FV_ERROR(MOD, "SSIM: out of memory for a %ux%u image", w, h);
        free(buf);
        free(t.rx);
        free(t.ry);
        return FV_ERR_NO_MEMORY;
    }
    gaussian_kernel(t.k);
    for (long i = 0; i < (long)w + 2 * r; i++) t.rx[i] = reflect(i - r, w);
    for (long i = 0; i < (long)h + 2 * r; i++) t.ry[i] = reflect(i - r, h);
    double *ux = buf, *uy = buf + n, *uxx = buf + 2 * n, *uyy = buf + 3 * n, *uxy = buf + 4 * n;
    double *prod = buf + 5 * n, *tmp = buf + 6 * n;
    gaussian_filter(a, stride, w, h, &t, tmp, ux);
    gaussian_filter(b, stride, w, h, &t, tmp, uy);
    const double *src[3][2] = {{a, a}, {b, b}, {a, b}};
    double *dst[3] = {uxx, uyy, uxy};
    for (int m = 0; m < 3; m++) {
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                size_t i = (size_t)y * stride + x;
                prod[(size_t)y * w + x] = src[m][0][i] * src[m][1][i];
            }
        gaussian_filter(prod, w, w, h, &t, tmp, dst[m]);
    }
    const double c1 = (FV_METRICS_SSIM_K1 * 1.0) * (FV_METRICS_SSIM_K1 * 1.0); /* (K1 * data_range)^2 */
    const double c2 = (FV_METRICS_SSIM_K2 * 1.0) * (FV_METRICS_SSIM_K2 * 1.0);
    for (size_t i = 0; i < n; i++) {
        double vx = uxx[i] - ux[i] * ux[i], vy = uyy[i] - uy[i] * uy[i], vxy = uxy[i] - ux[i] * uy[i];
        double a1 = 2.0 * ux[i] * uy[i] + c1, a2 = 2.0 * vxy + c2;
        double b1 = ux[i] * ux[i] + uy[i] * uy[i] + c1, b2 = vx + vy + c2;
        out_map[i] = (a1 * a2) / (b1 * b2);
    }
    free(buf);
    free(t.rx);
    free(t.ry);
    return FV_OK;
}

/* Sum of a dense w x h SSIM map (w, h >= the window) inside skimage's crop(S, pad), pad = (win_size - 1) // 2, and
 * the count of pixels summed. */
static double cropped_sum(const double *map, uint32_t w, uint32_t h, uint64_t *out_count)
{
    const uint32_t pad = FV_METRICS_SSIM_RADIUS;
    double s = 0.0;
    for (uint32_t y = pad; y < h - pad; y++)
        for (uint32_t x = pad; x < w - pad; x++) s += map[(size_t)y * w + x];
    *out_count = (uint64_t)(w - 2 * pad) * (h - 2 * pad);
    return s;
}

fv_result fv_metrics_ssim(const double *a, const double *b, uint32_t w, uint32_t h, double *out_ssim)
{
    *out_ssim = NAN;
    FV_TRY(window_fits("SSIM", w, h));
    double *map = malloc((size_t)w * h * sizeof(double));
    if (!map) return FV_ERR_NO_MEMORY;
    fv_result r = fv_metrics_ssim_map(a, b, w, h, w, map);
    uint64_t count;
    if (r == FV_OK) *out_ssim = cropped_sum(map, w, h, &count) / (double)count;
    free(map);
    return r;
}

/* ---- gaze and eccentricity ---- */

fv_vec3 fv_metrics_gaze_dir_from_deg(double yaw_deg, double pitch_deg)
{
    double y = fv_deg_to_rad(yaw_deg), p = fv_deg_to_rad(pitch_deg);
    return fv_v3((float)(sin(y) * cos(p)), (float)sin(p), (float)(-cos(y) * cos(p)));
}

static void view_ray_d(const fv_eye_view *v, double u, double t, double out[3])
{
    out[0] = v->tan_left + (v->tan_right - v->tan_left) * u;
    out[1] = v->tan_up + (v->tan_down - v->tan_up) * t;
    out[2] = -1.0;
}

fv_vec3 fv_metrics_view_ray(const fv_eye_view *view, uint32_t w, uint32_t h, double x_px, double y_px)
{
    double r[3];
    view_ray_d(view, (x_px + 0.5) / (double)w, (y_px + 0.5) / (double)h, r);
    double len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    return fv_v3((float)(r[0] / len), (float)(r[1] / len), (float)(r[2] / len));
}

void fv_metrics_eccentricity_deg(const fv_eye_view *view, fv_vec3 gaze_dir_eye, uint32_t w, uint32_t h,
                                 float *out_deg, size_t out_stride)
{
    const double g[3] = {gaze_dir_eye.x, gaze_dir_eye.y, gaze_dir_eye.z};
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            double r[3];
            view_ray_d(view, (x + 0.5) / (double)w, (y + 0.5) / (double)h, r);
            /* atan2(|r x g|, r . g): accurate near 0 and 180 degrees, no normalisation needed */
            double cx = r[1] * g[2] - r[2] * g[1], cy = r[2] * g[0] - r[0] * g[2], cz = r[0] * g[1] - r[1] * g[0];
            double dot = r[0] * g[0] + r[1] * g[1] + r[2] * g[2];
            out_deg[(size_t)y * out_stride + x] = (float)fv_rad_to_deg(atan2(sqrt(cx * cx + cy * cy + cz * cz), dot));
        }
}

/* ---- compare ---- */

static int band_of(float ecc_deg)
{
    if (!(ecc_deg >= 0.0f) || ecc_deg > 180.0f) return -1; /* NaN or outside: in no band */
    for (int k = 0; k < FV_METRICS_BANDS - 1; k++)
        if (ecc_deg < fv_metrics_band_edges_deg[k + 1]) return k;
    return FV_METRICS_BANDS - 1;
}

static fv_result check_finite(const fv_rgb_image *img, const char *name)
{
    size_t n = (size_t)img->width * img->height * 3;
    for (size_t i = 0; i < n; i++) {
        if (isfinite(img->rgb[i])) continue;
        size_t px = i / 3;
        FV_ERROR(MOD, "%s: pixel (%zu, %zu) channel %c is %s: non-finite values are refused", name,
                 px % img->width, px / img->width, "RGB"[i % 3], isnan(img->rgb[i]) ? "NaN" : "Inf");
        return FV_ERR_RANGE;
    }
    return FV_OK;
}

static void stats_reset(fv_metrics_stats *s)
{
    memset(s, 0, sizeof *s);
    s->psnr_db = s->ssim = s->mismatch = s->rel_mean = s->rel_p99 = s->rel_max = NAN;
}

/* Sums of one set of pixels while the image is scanned. */
typedef struct acc {
    uint64_t pixels, mismatch, ssim_pixels;
    double sse, rel_sum, rel_max, ssim_sum;
} acc;

static void stats_finish(const acc *a, bool linear, fv_metrics_stats *s)
{
    stats_reset(s);
    s->pixels = a->pixels;
    s->mismatch_pixels = a->mismatch;
    s->ssim_pixels = a->ssim_pixels;
    if (a->ssim_pixels) s->ssim = a->ssim_sum / (double)a->ssim_pixels;
    if (!a->pixels) return;
    s->psnr_db = fv_metrics_psnr_db(a->sse / (3.0 * (double)a->pixels));
    s->mismatch = (double)a->mismatch / (double)a->pixels;
    if (linear) {
        s->rel_mean = a->rel_sum / (3.0 * (double)a->pixels);
        s->rel_max = a->rel_max;
    }
}

static fv_result validate(const fv_rgb_image *a, const fv_rgb_image *b, const fv_metrics_desc *d, const char *na,
                          const char *nb)
{
    if (!a || !b || !a->rgb || !b->rgb || !d) return FV_ERR_INVALID_ARG;
    if (a->kind != b->kind) {
        FV_ERROR(MOD, "%s is a %s and %s is a %s: compare images of the same kind", na, fv_image_kind_str(a->kind),
                 nb, fv_image_kind_str(b->kind));
        return FV_ERR_INVALID_ARG;
    }
    if (a->width != b->width || a->height != b->height) {
        FV_ERROR(MOD, "%s is %ux%u but %s is %ux%u: the sizes differ", na, a->width, a->height, nb, b->width,
                 b->height);
        return FV_ERR_INVALID_ARG;
    }
    if (!(d->mismatch_threshold >= 0.0) || !isfinite(d->mismatch_threshold) || !(d->rel_eps >= 0.0) ||
        !isfinite(d->rel_eps) || d->eyes > 2 || (d->eyes == 2 && a->width % 2 != 0)) {
        FV_ERROR(MOD, "compare: bad settings (threshold %g, eps %g, %u eyes for width %u)", d->mismatch_threshold,
                 d->rel_eps, d->eyes, a->width);
        return FV_ERR_INVALID_ARG;
    }
    FV_TRY(check_finite(a, na));
    return check_finite(b, nb);
}

/* Add each band's SSIM from a dense map of one view at columns [x0, x0 + w) of the image. */
static void band_ssim(const double *map, uint32_t w, uint32_t h, uint32_t x0, uint32_t image_w, const float *ecc,
                      acc *bands)
{
    const uint32_t pad = FV_METRICS_SSIM_RADIUS;
    if (w < FV_METRICS_SSIM_WIN || h < FV_METRICS_SSIM_WIN) return;
    for (uint32_t y = pad; y < h - pad; y++)
        for (uint32_t x = pad; x < w - pad; x++) {
            int k = band_of(ecc[(size_t)y * image_w + x0 + x]);
            if (k < 0) continue;
            bands[k].ssim_sum += map[(size_t)y * w + x];
            bands[k].ssim_pixels++;
        }
}

/* Luma of columns [x0, x0 + w) of an image into a dense w x h array. */
static void luma_rect(const fv_rgb_image *img, uint32_t x0, uint32_t w, double *out)
{
    for (uint32_t y = 0; y < img->height; y++)
        for (uint32_t x = 0; x < w; x++) {
            double s[3];
            pixel_srgb(img, (size_t)y * img->width + x0 + x, s);
            out[(size_t)y * w + x] = luma_of(s);
        }
}

/* The bands' SSIM: from the whole image's map for one view, from each eye's own map for two. */
static fv_result bands_ssim(const fv_rgb_image *a, const fv_rgb_image *b, const fv_metrics_desc *d, double *ya,
                            double *yb, double *map, acc *bands)
{
    uint32_t w = a->width, h = a->height;
    if (d->eyes < 2) {
        band_ssim(map, w, h, 0, w, d->ecc_deg, bands);
        return FV_OK;
    }
    uint32_t ew = w / 2;
    if (ew < FV_METRICS_SSIM_WIN) return FV_OK; /* an eye smaller than the window: no band SSIM */
    for (uint32_t e = 0; e < 2; e++) {
        luma_rect(a, e * ew, ew, ya);
        luma_rect(b, e * ew, ew, yb);
        FV_TRY(fv_metrics_ssim_map(ya, yb, ew, h, ew, map));
        band_ssim(map, ew, h, e * ew, w, d->ecc_deg, bands);
    }
    return FV_OK;
}

/* Each band's p99 relative error: its values gathered into scratch (rel keeps pixel order). */
static void bands_rel_p99(const double *rel, const float *ecc, size_t n, double *scratch, fv_metrics_stats *band)
{
    for (int k = 0; k < FV_METRICS_BANDS; k++) {
        size_t m = 0;
        for (size_t i = 0; i < n; i++)
            if (band_of(ecc[i]) == k) {
                memcpy(scratch + m, rel + i * 3, 3 * sizeof(double));
                m += 3;
            }
        if (m) band[k].rel_p99 = fv_percentile_f64(scratch, m, 99.0);
    }
}

uint64_t fv_metrics_compare_bytes(uint32_t w, uint32_t h, bool linear, bool bands)
{
    uint64_t n = (uint64_t)w * h, d = sizeof(double);
    uint64_t bytes = n * 3 * d;                                      /* luma of A and B, the SSIM map */
    bytes += n * 7 * d + ((uint64_t)w + (uint64_t)h + 4 * FV_METRICS_SSIM_RADIUS) * sizeof(size_t); /* SSIM */
    if (linear) bytes += n * 3 * d * (bands ? 2 : 1); /* relative errors, and their per-band copies */
    return bytes;
}

fv_result fv_metrics_compare(const fv_rgb_image *a, const fv_rgb_image *b, const fv_metrics_desc *desc,
                             fv_metrics_report *out)
{
    memset(out, 0, sizeof *out);
    stats_reset(&out->all);
    for (int k = 0; k < FV_METRICS_BANDS; k++) stats_reset(&out->band[k]);
    const char *na = desc && desc->name_a ? desc->name_a : "A", *nb = desc && desc->name_b ? desc->name_b : "B";
    FV_TRY(validate(a, b, desc, na, nb));
    uint32_t w = a->width, h = a->height;
    FV_TRY(window_fits(na, w, h));
    size_t n = (size_t)w * h;
    bool linear = a->kind == FV_IMAGE_KIND_LINEAR;
    double eps = desc->rel_eps > 0.0 ? desc->rel_eps : FV_METRICS_REL_EPS;
    out->rel_eps = eps;
    double *ya = malloc(n * sizeof(double)), *yb = malloc(n * sizeof(double)), *map = malloc(n * sizeof(double));
    double *rel = linear ? malloc(n * 3 * sizeof(double)) : NULL;
    double *scratch = linear && desc->ecc_deg ? malloc(n * 3 * sizeof(double)) : NULL;
    fv_result r = FV_ERR_NO_MEMORY;
    if (!ya || !yb || !map || (linear && !rel) || (linear && desc->ecc_deg && !scratch)) {
        FV_ERROR(MOD, "compare: out of memory for %ux%u images", w, h);
        goto done;
    }
    luma_rect(a, 0, w, ya);
    luma_rect(b, 0, w, yb);
    r = fv_metrics_ssim_map(ya, yb, w, h, w, map);
    if (r != FV_OK) goto done;

    acc all = {0}, bands[FV_METRICS_BANDS] = {{0}};
    all.ssim_sum = cropped_sum(map, w, h, &all.ssim_pixels);
    for (size_t i = 0; i < n; i++) {
        double sa[3], sb[3], sse = 0.0, diff = 0.0, rel_sum = 0.0, rel_max = 0.0;
        pixel_srgb(a, i, sa);
        pixel_srgb(b, i, sb);
        for (int c = 0; c < 3; c++) {
            sse += (sa[c] - sb[c]) * (sa[c] - sb[c]);
            double va = a->rgb[i * 3 + c], vb = b->rgb[i * 3 + c], d = fabs(va - vb);
            if (d > diff) diff = d;
            if (linear) {
                double e = d / fmax(fabs(vb), eps);
                rel[i * 3 + c] = e;
                rel_sum += e;
                rel_max = fmax(rel_max, e);
            }
        }
        bool mis = diff > desc->mismatch_threshold;
        int k = desc->ecc_deg ? band_of(desc->ecc_deg[i]) : -1;
        acc *targets[2] = {&all, k >= 0 ? &bands[k] : NULL};
        for (int t = 0; t < 2 && targets[t]; t++) {
            targets[t]->pixels++;
            targets[t]->sse += sse;
            targets[t]->mismatch += mis;
            targets[t]->rel_sum += rel_sum;
            targets[t]->rel_max = fmax(targets[t]->rel_max, rel_max);
        }
    }
    if (desc->ecc_deg) {
        r = bands_ssim(a, b, desc, ya, yb, map, bands);
        if (r != FV_OK) goto done;
    }
    stats_finish(&all, linear, &out->all);
    out->has_bands = desc->ecc_deg != NULL;
    for (int k = 0; k < FV_METRICS_BANDS && out->has_bands; k++) stats_finish(&bands[k], linear, &out->band[k]);
    if (linear) {
        if (desc->ecc_deg) bands_rel_p99(rel, desc->ecc_deg, n, scratch, out->band);
        out->all.rel_p99 = fv_percentile_f64(rel, n * 3, 99.0); /* sorts rel: last */
    }
    r = FV_OK;
done:
    free(ya);
    free(yb);
    free(map);
    free(rel);
    free(scratch);
    return r;
}
