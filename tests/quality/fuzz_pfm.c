/* @brief libFuzzer target for the PFM reader in memory (fv_image_io_read_pfm). Checks: no crash or sanitizer report;
 * a decoded image is within the limits, re-encodes and decodes to the same bits; comparing it with itself and with
 * a changed copy yields no NaN metric (non-finite pixels are refused, not measured). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fv_image_io.h"
#include "fv_log.h"
#include "fv_metrics.h"

static void quiet(void *user, fv_log_level level, const char *module, const char *file, int line, const char *msg)
{
    (void)user, (void)level, (void)module, (void)file, (void)line;
    volatile size_t n = strlen(msg); /* touch the message: a bad format or overread shows under ASan */
    (void)n;
}

static void check_stats(const fv_metrics_stats *s)
{
    if (isnan(s->psnr_db) || isnan(s->ssim) || isnan(s->mismatch) || isnan(s->rel_mean) || isnan(s->rel_p99) ||
        isnan(s->rel_max))
        __builtin_trap();
    if (s->psnr_db < 0.0 && isinf(s->psnr_db)) __builtin_trap();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fv_log_set_sink(quiet, NULL);
    fv_rgb_image img;
    if (fv_image_io_read_pfm(data, size, "fuzz", &img) != FV_OK) {
        if (img.rgb || img.width || img.height) __builtin_trap(); /* zeroed on failure */
        return 0;
    }
    size_t n = (size_t)img.width * img.height;
    if (!img.rgb || img.width > FV_IMAGE_MAX_SIDE_PX || img.height > FV_IMAGE_MAX_SIDE_PX || n > FV_IMAGE_MAX_PIXELS)
        __builtin_trap();
    uint8_t *enc;
    size_t enc_size;
    if (fv_image_io_encode_pfm(&img, &enc, &enc_size) != FV_OK) __builtin_trap();
    fv_rgb_image back;
    if (fv_image_io_read_pfm(enc, enc_size, "re-encoded", &back) != FV_OK) __builtin_trap();
    if (back.width != img.width || back.height != img.height || memcmp(back.rgb, img.rgb, n * 3 * sizeof(float)))
        __builtin_trap();
    free(enc);
    /* change one value of the copy so the metrics see a difference */
    back.rgb[n * 3 / 2] = isfinite(back.rgb[n * 3 / 2]) ? back.rgb[n * 3 / 2] * 0.5f + 0.25f : 0.0f;
    fv_metrics_desc d = {.mismatch_threshold = 0.01};
    fv_metrics_report rep;
    fv_result r = fv_metrics_compare(&img, &img, &d, &rep);
    if (r == FV_OK) {
        check_stats(&rep.all);
        if (rep.all.psnr_db != INFINITY || rep.all.mismatch != 0.0) __builtin_trap();
    }
    if (fv_metrics_compare(&img, &back, &d, &rep) == FV_OK) check_stats(&rep.all);
    fv_rgb_image_fini(&back);
    fv_rgb_image_fini(&img);
    return 0;
}
