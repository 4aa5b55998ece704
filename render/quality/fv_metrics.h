/* @brief Image quality metrics in double precision: PSNR and SSIM as scikit-image computes them, relative error of
 * linear images, the fraction of mismatched pixels, each over the whole image and per eccentricity band around a
 * gaze direction. Pure functions on caller-owned arrays (fv_metrics_compare allocates its own scratch and frees
 * it); thread-safe on distinct data. */
#ifndef FV_METRICS_H
#define FV_METRICS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fovea/fv_frame_input.h"
#include "fv_image_io.h"
#include "fv_result.h"

/** SSIM constants (Wang et al. 2004; skimage's structural_similarity with gaussian_weights=True, sigma=1.5,
 *  use_sample_covariance=False, data_range=1): a Gaussian truncated at 3.5 sigma, radius int(3.5 * 1.5 + 0.5) = 5,
 *  an 11x11 window; the SSIM map is averaged after cropping (11 - 1) / 2 = 5 pixels off every side. */
#define FV_METRICS_SSIM_SIGMA 1.5
#define FV_METRICS_SSIM_RADIUS 5
#define FV_METRICS_SSIM_WIN (2 * FV_METRICS_SSIM_RADIUS + 1)
#define FV_METRICS_SSIM_K1 0.01
#define FV_METRICS_SSIM_K2 0.03
/** Default eps of the relative error |a - b| / max(|b|, eps) of linear images. */
#define FV_METRICS_REL_EPS 1e-3
/** Eccentricity bands (degrees from the gaze ray): [0,5) [5,10) [10,20) [20,30) [30,180]. */
#define FV_METRICS_BANDS 5
extern const double fv_metrics_band_edges_deg[FV_METRICS_BANDS + 1];

/** sRGB encoding of a linear value, clamped to [0, 1] (NaN -> 0). IEC 61966-2-1. */
double fv_metrics_linear_to_srgb(double linear);
/** The image's values as sRGB in [0, 1], 3 per pixel, into out (w*h*3): PNG values as read; linear values
 *  sRGB-encoded and clamped (fv_metrics_linear_to_srgb). */
void fv_metrics_srgb_values(const fv_rgb_image *img, double *out);
/** Luma Y' = 0.299 R' + 0.587 G' + 0.114 B' of n pixels of sRGB values (3 per pixel) into out_luma (n). */
void fv_metrics_luma(const double *srgb, size_t n_px, double *out_luma);

/** Mean squared difference of n values. NaN when n == 0. */
double fv_metrics_mse(const double *a, const double *b, size_t n);
/** PSNR in dB for data range 1: 10 log10(1 / mse) (skimage's peak_signal_noise_ratio(a, b, data_range=1)).
 *  +INFINITY when mse == 0 (identical), NaN when mse is NaN. */
double fv_metrics_psnr_db(double mse);

/** SSIM map of two w x h luma images (row stride `stride` values, >= w) into out_map (w*h, dense): the
 *  Gaussian-weighted local statistics with scipy's mode='reflect' borders, exactly as skimage. FV_ERR_RANGE when
 *  w or h is smaller than the 11-pixel window (skimage raises there too), FV_ERR_NO_MEMORY. */
FV_MUST_CHECK fv_result fv_metrics_ssim_map(const double *a, const double *b, uint32_t w, uint32_t h, size_t stride,
                                            double *out_map);
/** Mean SSIM of two w x h dense luma images: the map's mean after cropping 5 pixels off every side. */
FV_MUST_CHECK fv_result fv_metrics_ssim(const double *a, const double *b, uint32_t w, uint32_t h, double *out_ssim);

/** Unit gaze direction from yaw (positive right) and pitch (positive up) in degrees, in the head frame (+x right,
 *  +y up, -z forward): (sin yaw cos pitch, sin pitch, -cos yaw cos pitch). */
fv_vec3 fv_metrics_gaze_dir_from_deg(double yaw_deg, double pitch_deg);
/** Unit view-space ray through pixel position (x_px, y_px) of a w x h view: u = (x + 0.5) / w, v = (y + 0.5) / h,
 *  (mix(tan_left, tan_right, u), mix(tan_up, tan_down, v), -1), normalised. */
fv_vec3 fv_metrics_view_ray(const fv_eye_view *view, uint32_t w, uint32_t h, double x_px, double y_px);
/** Each pixel's eccentricity: the angle in degrees between its view ray (fv_metrics_view_ray at the pixel centre)
 *  and gaze_dir_eye (any length but zero, in the eye's view space), into out_deg[y * out_stride + x]. */
void fv_metrics_eccentricity_deg(const fv_eye_view *view, fv_vec3 gaze_dir_eye, uint32_t w, uint32_t h,
                                 float *out_deg, size_t out_stride);

/** Metrics of one set of pixels. NaN marks what does not apply (no pixels; rel_* of sRGB images; SSIM with no
 *  pixel of the cropped map). psnr_db is +INFINITY when the pixels are identical. */
typedef struct fv_metrics_stats {
    uint64_t pixels;
    double psnr_db;
    double ssim;
    uint64_t ssim_pixels;       /* pixels of the cropped SSIM map(s) averaged */
    double mismatch;            /* fraction of pixels with |a - b| > threshold in any channel */
    uint64_t mismatch_pixels;
    double rel_mean, rel_p99, rel_max; /* linear images: |a - b| / max(|b|, eps) over every channel value */
} fv_metrics_stats;

typedef struct fv_metrics_desc {
    const char *name_a, *name_b; /* names in messages (NULL: "A", "B") */
    double mismatch_threshold;   /* >= 0, in the images' own values (sRGB [0,1] for PNG, linear for PFM) */
    double rel_eps;              /* 0: FV_METRICS_REL_EPS */
    /** Optional per-pixel eccentricity (w*h, rows top first), e.g. from fv_metrics_eccentricity_deg: enables bands. */
    const float *ecc_deg;
    /** 0 or 1: one view; 2: two views side by side (width even). Bands then take their SSIM from each eye's own
     *  map (cropped at that eye's borders), so that nothing leaks across the seam. */
    uint32_t eyes;
} fv_metrics_desc;

typedef struct fv_metrics_report {
    fv_metrics_stats all;        /* the whole image (its SSIM over the whole image, as skimage on the file) */
    bool has_bands;
    fv_metrics_stats band[FV_METRICS_BANDS];
    double rel_eps;              /* the eps used */
} fv_metrics_report;

/** Compare A with B (B is the reference of the relative error). A and B must have the same size and kind, and
 *  every value must be finite: a NaN or Inf is refused (FV_ERR_RANGE) and the log names the image, pixel (x, y
 *  from the top left) and channel. Images smaller than the SSIM window are refused (FV_ERR_RANGE), as skimage does.
 *  PSNR and SSIM use the sRGB values (fv_metrics_srgb_values). Scratch: fv_metrics_compare_bytes. */
FV_MUST_CHECK fv_result fv_metrics_compare(const fv_rgb_image *a, const fv_rgb_image *b, const fv_metrics_desc *desc,
                                           fv_metrics_report *out);
/** The most scratch memory fv_metrics_compare holds at once for two w x h images (linear: PFM; bands: with an
 *  eccentricity map): 80 bytes a pixel, 104 for linear images, 128 for linear images with bands. Weigh it before
 *  decoding the images. */
uint64_t fv_metrics_compare_bytes(uint32_t w, uint32_t h, bool linear, bool bands);

#endif
