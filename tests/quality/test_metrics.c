/* @brief render/quality: PFM and PNG reading (every malformed-header reason, limits before allocation, byte order and
 * row order), PSNR/SSIM/relative error/mismatch on constructed images with known answers, NaN/Inf refused with the
 * pixel named, images smaller than the SSIM window refused as skimage does, extreme values, eccentricity bands. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <stb_image_write.h>
#include <zlib.h>

#include "fv_image_io.h"
#include "fv_metrics.h"
#include "fv_test.h"

static uint32_t g_rng = 12345u;
static double rnd(void) /* [0, 1) */
{
    g_rng = g_rng * 1664525u + 1013904223u;
    return (double)(g_rng >> 8) / 16777216.0;
}

/* A zeroed w x h image. */
static fv_rgb_image blank(uint32_t w, uint32_t h, fv_image_kind kind)
{
    fv_rgb_image img;
    assert_int_equal(fv_rgb_image_init(&img, w, h, kind), FV_OK);
    return img;
}

/* A w x h image of this kind with random values: 8-bit steps k / 255 for sRGB, [0, 2) for linear. */
static fv_rgb_image make(uint32_t w, uint32_t h, fv_image_kind kind)
{
    fv_rgb_image img = blank(w, h, kind);
    for (size_t i = 0; i < (size_t)w * h * 3; i++)
        img.rgb[i] = kind == FV_IMAGE_KIND_SRGB8 ? (float)floor(rnd() * 256.0) / 255.0f : (float)(rnd() * 2.0);
    return img;
}

static fv_rgb_image copy_of(const fv_rgb_image *src)
{
    fv_rgb_image img = blank(src->width, src->height, src->kind);
    memcpy(img.rgb, src->rgb, (size_t)src->width * src->height * 3 * sizeof(float));
    return img;
}

static fv_metrics_report compare_ok(const fv_rgb_image *a, const fv_rgb_image *b, const fv_metrics_desc *d)
{
    fv_metrics_desc zero = {0};
    fv_metrics_report rep;
    fv_result r = fv_metrics_compare(a, b, d ? d : &zero, &rep);
    if (r != FV_OK) fail_msg("compare failed: %s", fv_result_str(r));
    return rep;
}

/* ---- PFM ---- */

/* A PFM in memory: header text then raw bytes. */
static size_t pfm_bytes(uint8_t *buf, const char *header, const void *px, size_t px_size)
{
    size_t n = strlen(header);
    memcpy(buf, header, n);
    if (px_size) memcpy(buf + n, px, px_size);
    return n + px_size;
}

static void pfm_rows_run_bottom_to_top_and_scale_sign_gives_byte_order(void **state)
{
    (void)state;
    /* 1x2 grey, little-endian: the first row in the file is the bottom row */
    float le[2] = {0.25f, 0.75f};
    uint8_t buf[256];
    size_t n = pfm_bytes(buf, "Pf\n1 2\n-1.0\n", le, sizeof le);
    fv_rgb_image img;
    assert_int_equal(fv_image_io_read_pfm(buf, n, "grey.pfm", &img), FV_OK);
    assert_int_equal(img.width, 1);
    assert_int_equal(img.height, 2);
    assert_int_equal(img.file_channels, 1);
    assert_int_equal(img.kind, FV_IMAGE_KIND_LINEAR);
    assert_true(img.rgb[0] == 0.75f && img.rgb[1] == 0.75f && img.rgb[2] == 0.75f); /* top row */
    assert_true(img.rgb[3] == 0.25f);
    fv_rgb_image_fini(&img);
    fv_rgb_image_fini(&img); /* twice is safe */

    /* 2x1 colour, big-endian (scale > 0): 1.0f is 3f 80 00 00 */
    uint8_t be[24] = {0};
    for (int i = 0; i < 6; i++) be[i * 4] = 0x3f, be[i * 4 + 1] = 0x80;
    be[20] = 0x40, be[21] = 0x00; /* the last value: 2.0f */
    n = pfm_bytes(buf, "PF 2 1 1\n", be, sizeof be);
    assert_int_equal(fv_image_io_read_pfm(buf, n, "be.pfm", &img), FV_OK);
    assert_true(img.rgb[0] == 1.0f && img.rgb[4] == 1.0f && img.rgb[5] == 2.0f);
    fv_rgb_image_fini(&img);
}

static void pfm_write_then_read_round_trips_every_bit(void **state)
{
    (void)state;
    fv_rgb_image a = make(7, 5, FV_IMAGE_KIND_LINEAR);
    a.rgb[0] = -3.5f, a.rgb[1] = FLT_MAX, a.rgb[2] = FLT_MIN / 4.0f, a.rgb[3] = NAN, a.rgb[4] = -INFINITY;
    const char *path = fv_test_tmp("round.pfm");
    assert_int_equal(fv_image_io_write_pfm(path, &a), FV_OK);
    size_t len;
    char *bytes = fv_test_read_file(path, &len);
    assert_true(strncmp(bytes, "PF\n7 5\n-1\n", 10) == 0);
    assert_int_equal(len, 10 + 7 * 5 * 12);
    free(bytes);
    fv_rgb_image b;
    assert_int_equal(fv_image_io_read(path, &b), FV_OK);
    assert_int_equal(b.width, 7);
    assert_int_equal(b.height, 5);
    assert_memory_equal(a.rgb, b.rgb, 7 * 5 * 3 * sizeof(float));
    fv_rgb_image_fini(&a);
    fv_rgb_image_fini(&b);
}

static void pfm_errors_name_the_file_and_the_reason(void **state)
{
    (void)state;
    float px[6] = {0};
    uint8_t buf[256];
    struct {
        const char *header;
        size_t px_size;
        fv_result r;
        const char *why;
    } cases[] = {
        {"P6\n1 1\n255\n", 3, FV_ERR_PARSE, "bad header: a PFM starts with"},
        {"PF", 0, FV_ERR_PARSE, "truncated"},
        {"PF\n2 1", 0, FV_ERR_PARSE, "truncated"},
        {"PF\n2 1\n-1.0", 0, FV_ERR_PARSE, "truncated"},
        {"PFX\n2 1\n-1\n", 24, FV_ERR_PARSE, "bad header"},
        {"PF\n-2 1\n-1\n", 24, FV_ERR_PARSE, "width '-2' and height '1' must be whole numbers"},
        {"PF\n2 1x\n-1\n", 24, FV_ERR_PARSE, "must be whole numbers"},
        {"PF\n0 1\n-1\n", 0, FV_ERR_PARSE, "bad header: image is 0x1"},
        {"PF\n2 1\nabc\n", 24, FV_ERR_PARSE, "scale 'abc' is not a number"},
        {"PF\n2 1\ninf\n", 24, FV_ERR_PARSE, "non-finite scale 'inf'"},
        {"PF\n2 1\nnan\n", 24, FV_ERR_PARSE, "non-finite scale 'nan'"},
        {"PF\n2 1\n1e999\n", 24, FV_ERR_PARSE, "non-finite scale"},
        {"PF\n2 1\n0\n", 24, FV_ERR_PARSE, "scale is 0"},
        {"PF\n2 1\n-1\n", 20, FV_ERR_PARSE, "truncated: 20 bytes of pixels, a 2x1 colour PFM needs 24"},
        {"Pf\n2 1\n-1\n", 12, FV_ERR_PARSE, "wrong size: 4 bytes after the pixels"},
        {"PF\n99999999 99999999\n-1\n", 0, FV_ERR_RANGE, "over the limit"}, /* before any allocation or size check */
        {"PF\n16385 1\n-1\n", 0, FV_ERR_RANGE, "dimensions 16385x1 over the limit"},
        {"PF\n12345678901 1\n-1\n", 0, FV_ERR_PARSE, "bad header"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        size_t n = pfm_bytes(buf, cases[i].header, px, cases[i].px_size);
        fv_rgb_image img;
        fv_test_log_capture_begin();
        fv_result r = fv_image_io_read_pfm(buf, n, "bad.pfm", &img);
        if (r != cases[i].r) fail_msg("case %zu (%s): %s", i, cases[i].header, fv_result_str(r));
        assert_null(img.rgb);
        fv_assert_log_contains("bad.pfm: ");
        fv_assert_log_contains(cases[i].why);
        fv_test_log_capture_end();
    }
}

static void image_files_that_cannot_be_read_are_named(void **state)
{
    (void)state;
    fv_rgb_image img;
    fv_test_log_capture_begin();
    assert_int_equal(fv_image_io_read("/nonexistent/x.pfm", &img), FV_ERR_NOT_FOUND);
    fv_assert_log_contains("/nonexistent/x.pfm: cannot open");
    const char *p = fv_test_write_file("text.pfm", "hello", 5);
    assert_int_equal(fv_image_io_read(p, &img), FV_ERR_PARSE);
    fv_assert_log_contains("text.pfm: neither a PNG nor a PFM file");
    p = fv_test_write_file("empty.png", "", 0);
    assert_int_equal(fv_image_io_read(p, &img), FV_ERR_PARSE);
    fv_assert_log_contains("empty.png: empty file");
    static const uint8_t png_head[16] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R'};
    p = fv_test_write_file("cut.png", png_head, sizeof png_head);
    assert_int_equal(fv_image_io_read(p, &img), FV_ERR_PARSE);
    fv_assert_log_contains("cut.png: bad header");
    /* what is not a regular file is named, not read (a directory was "empty file", /dev/zero read to 1 GiB) */
    const char *dir = fv_test_tmp("images.d");
    mkdir(dir, 0700);
    assert_int_equal(fv_image_io_read(dir, &img), FV_ERR_IO);
    fv_assert_log_contains("images.d: not a regular file: it is a directory");
    assert_int_equal(fv_image_io_read("/dev/zero", &img), FV_ERR_IO);
    fv_assert_log_contains("/dev/zero: not a regular file: it is a character device");
    fv_test_log_capture_end();
}

/* A PNG's header (signature, IHDR of w x h, colour type ct) and IEND: no pixels. */
static size_t png_header(uint8_t *b, uint32_t w, uint32_t h, uint8_t ct)
{
    static const uint8_t head[16] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R'};
    memcpy(b, head, 16);
    for (int i = 0; i < 4; i++) b[16 + i] = (uint8_t)(w >> (24 - 8 * i)), b[20 + i] = (uint8_t)(h >> (24 - 8 * i));
    memcpy(b + 24, (const uint8_t[]){8, ct, 0, 0, 0, 0, 0, 0, 0}, 9);
    memcpy(b + 33, "\0\0\0\0IEND\xae\x42\x60\x82", 12);
    return 45;
}

/* A 16x16 RGB PNG whose image data inflates to `raw` bytes of zero rows (784 is the exact size). */
static size_t png_inflating_to(uint8_t **out, size_t raw)
{
    uint8_t *zeros = calloc(raw, 1);
    uLongf zn = compressBound(raw);
    uint8_t *b = malloc(45 + 12 + zn);
    assert_true(zeros && b);
    png_header(b, 16, 16, 2);
    assert_int_equal(compress2(b + 33 + 8, &zn, zeros, raw, 9), Z_OK);
    for (int i = 0; i < 4; i++) b[33 + i] = (uint8_t)(zn >> (24 - 8 * i));
    memcpy(b + 37, "IDAT", 4);
    memset(b + 41 + zn, 0, 4); /* CRC, unchecked */
    memcpy(b + 45 + zn, "\0\0\0\0IEND\xae\x42\x60\x82", 12);
    free(zeros);
    *out = b;
    return 57 + zn;
}

/* Image data that inflates past the header's rows is refused before stb_image decodes it (it grew its buffer for
 * all of it: a 261 KB 16x16 PNG took 680 MB and compared). */
static void png_data_inflating_past_its_rows_is_refused(void **state)
{
    (void)state;
    uint8_t *b;
    fv_rgb_image img;
    size_t n = png_inflating_to(&b, 784);
    assert_int_equal(fv_image_io_read_png(b, n, "ok.png", &img), FV_OK);
    assert_int_equal(img.width, 16);
    fv_rgb_image_fini(&img);
    free(b);
    n = png_inflating_to(&b, 16u << 20);
    fv_test_log_capture_begin();
    assert_int_equal(fv_image_io_read_png(b, n, "bomb.png", &img), FV_ERR_PARSE);
    fv_assert_log_contains("bomb.png: bad image data: it inflates to more than the 784 bytes of a 16x16 image's rows");
    assert_null(img.rgb);
    fv_test_log_capture_end();
    free(b);
}

/* The header alone says size, kind and cost: too-large PNGs are called too large (stb_image refuses some of them
 * itself and said "unknown image type"), and the memory of a decode is known before decoding. */
static void headers_give_size_and_cost_before_decoding(void **state)
{
    (void)state;
    uint8_t b[64];
    fv_image_info info;
    size_t n = png_header(b, 4096, 4096, 2);
    assert_int_equal(fv_image_io_info(b, n, "h.png", &info), FV_OK);
    assert_int_equal(info.width, 4096);
    assert_int_equal(info.height, 4096);
    assert_int_equal(info.kind, FV_IMAGE_KIND_SRGB8);
    assert_int_equal(info.file_channels, 3);
    uint64_t px = 4096u * 4096u;
    assert_true(fv_image_io_decode_bytes(&info) == px * (12 + FV_IMAGE_PNG_DECODER_BYTES_PER_PX) + 4096);
    fv_test_log_capture_begin();
    n = png_header(b, 20000, 20000, 2);
    assert_int_equal(fv_image_io_info(b, n, "huge.png", &info), FV_ERR_RANGE);
    fv_assert_log_contains("huge.png: too large: dimensions 20000x20000 over the limit (16384 per side, 67108864 "
                           "pixels)");
    fv_rgb_image img;
    assert_int_equal(fv_image_io_read_png(b, n, "huge.png", &img), FV_ERR_RANGE);
    assert_null(strstr(fv_test_log_text(), "unknown image type"));
    n = png_header(b, 16384, 4096, 6); /* at the limits (side and pixels): stb_image's own check passes too */
    assert_int_equal(fv_image_io_info(b, n, "edge.png", &info), FV_OK);
    assert_int_equal(info.file_channels, 4);
    assert_int_equal(fv_image_io_check_budget("x", 100, 99, "(hint)"), FV_ERR_RANGE);
    fv_assert_log_contains("x: too large to work on: it needs about 1 MiB, over the budget of 0 MiB (hint)");
    assert_int_equal(fv_image_io_check_budget("x", 99, 99, NULL), FV_OK);
    fv_test_log_capture_end();
    /* a PFM's header, its size checked against the pixels it declares */
    static const char pfm_text[] = "PF\n2 1\n-1\n";
    uint8_t pfm[sizeof pfm_text - 1 + 24] = {0};
    memcpy(pfm, pfm_text, sizeof pfm_text - 1);
    assert_int_equal(fv_image_io_info(pfm, sizeof pfm, "p.pfm", &info), FV_OK);
    assert_int_equal(info.kind, FV_IMAGE_KIND_LINEAR);
    assert_true(fv_image_io_decode_bytes(&info) == 2 * 12);
    /* the metrics' scratch: 80 bytes a pixel for PNG, 128 for PFM with bands, plus the SSIM taps */
    uint64_t taps = (100 + 100 + 4 * FV_METRICS_SSIM_RADIUS) * sizeof(size_t);
    assert_true(fv_metrics_compare_bytes(100, 100, false, true) == 10000u * 80 + taps);
    assert_true(fv_metrics_compare_bytes(100, 100, true, true) == 10000u * 128 + taps);
    assert_true(fv_metrics_compare_bytes(100, 100, true, false) == 10000u * 104 + taps);
}

static void png_reads_as_srgb_values_with_alpha_dropped(void **state)
{
    (void)state;
    uint8_t rgba[2 * 2 * 4] = {0, 51, 255, 10, 1, 2, 3, 4, 254, 128, 7, 0, 9, 8, 7, 255};
    const char *p = fv_test_tmp("rgba.png");
    assert_true(stbi_write_png(p, 2, 2, 4, rgba, 8) != 0);
    fv_rgb_image img;
    assert_int_equal(fv_image_io_read(p, &img), FV_OK);
    assert_int_equal(img.kind, FV_IMAGE_KIND_SRGB8);
    assert_int_equal(img.file_channels, 4);
    for (int i = 0; i < 4; i++)
        for (int c = 0; c < 3; c++) assert_true(img.rgb[i * 3 + c] == (float)rgba[i * 4 + c] / 255.0f);
    fv_rgb_image_fini(&img);
    uint8_t grey[3] = {0, 100, 255};
    p = fv_test_tmp("grey.png");
    assert_true(stbi_write_png(p, 3, 1, 1, grey, 3) != 0);
    assert_int_equal(fv_image_io_read(p, &img), FV_OK);
    assert_true(img.rgb[3] == 100.0f / 255.0f && img.rgb[4] == img.rgb[3] && img.rgb[5] == img.rgb[3]);
    fv_rgb_image_fini(&img);
}

/* ---- metrics ---- */

static void identical_images_have_infinite_psnr_ssim_1_and_no_mismatch(void **state)
{
    (void)state;
    fv_rgb_image a = make(16, 13, FV_IMAGE_KIND_SRGB8), b = copy_of(&a);
    fv_metrics_report rep = compare_ok(&a, &b, NULL);
    assert_true(isinf(rep.all.psnr_db) && rep.all.psnr_db > 0);
    assert_true(rep.all.ssim == 1.0);
    assert_true(rep.all.mismatch == 0.0);
    assert_int_equal(rep.all.pixels, 16 * 13);
    assert_int_equal(rep.all.ssim_pixels, 6 * 3);
    assert_true(isnan(rep.all.rel_mean)); /* sRGB images have no relative error */
    assert_false(rep.has_bands);
    fv_rgb_image_fini(&a);
    fv_rgb_image_fini(&b);
}

static void constant_offsets_give_the_known_psnr(void **state)
{
    (void)state;
    const double offs[] = {0.1, 1.0 / 255.0, 0.5};
    const double want[] = {20.0, 20.0 * log10(255.0), 20.0 * log10(2.0)};
    for (int k = 0; k < 3; k++) {
        fv_rgb_image a = blank(20, 12, FV_IMAGE_KIND_SRGB8), b = blank(20, 12, FV_IMAGE_KIND_SRGB8);
        for (size_t i = 0; i < 20 * 12 * 3; i++) {
            a.rgb[i] = (float)(0.25 + 0.25 * rnd());
            b.rgb[i] = (float)(a.rgb[i] + offs[k]);
            a.rgb[i] = (float)(b.rgb[i] - offs[k]); /* the float difference is the offset to within rounding */
        }
        fv_metrics_report rep = compare_ok(&a, &b, NULL);
        if (fabs(rep.all.psnr_db - want[k]) > 1e-4) fail_msg("offset %g: psnr %.6f, want %.6f", offs[k],
                                                               rep.all.psnr_db, want[k]);
        assert_true(rep.all.mismatch == 1.0);
        fv_rgb_image_fini(&a);
        fv_rgb_image_fini(&b);
    }
    assert_true(fv_metrics_psnr_db(0.0) == INFINITY);
    assert_true(isnan(fv_metrics_psnr_db(NAN)));
    assert_true(fabs(fv_metrics_psnr_db(1e-4) - 40.0) < 1e-12);
}

static void mismatch_counts_pixels_over_the_threshold_in_any_channel(void **state)
{
    (void)state;
    fv_rgb_image a = make(12, 12, FV_IMAGE_KIND_LINEAR), b = copy_of(&a);
    b.rgb[0 * 3 + 1] += 0.5f;  /* pixel 0, G: over 0.25 */
    b.rgb[5 * 3 + 2] += 0.25f; /* under */
    b.rgb[9 * 3 + 0] += 0.1f;  /* under */
    fv_metrics_desc d = {.mismatch_threshold = 0.3};
    fv_metrics_report rep = compare_ok(&a, &b, &d);
    assert_int_equal(rep.all.mismatch_pixels, 1);
    assert_true(fabs(rep.all.mismatch - 1.0 / 144.0) < 1e-15);
    d.mismatch_threshold = 0.0;
    rep = compare_ok(&a, &b, &d);
    assert_int_equal(rep.all.mismatch_pixels, 3);
    fv_rgb_image_fini(&a);
    fv_rgb_image_fini(&b);
}

static void relative_error_uses_b_as_reference_with_eps(void **state)
{
    (void)state;
    fv_rgb_image a = blank(11, 11, FV_IMAGE_KIND_LINEAR), b = blank(11, 11, FV_IMAGE_KIND_LINEAR);
    size_t n = 11 * 11 * 3;
    for (size_t i = 0; i < n; i++) a.rgb[i] = b.rgb[i] = 1.0f;
    a.rgb[0] = 1.5f;  /* 0.5 relative to b = 1 */
    b.rgb[1] = 0.0f;  /* |1 - 0| / max(0, eps) */
    a.rgb[2] = -1.0f; /* 2 */
    a.rgb[3] = 4.0f;  /* 3 */
    fv_metrics_report rep = compare_ok(&a, &b, NULL);
    assert_true(rep.rel_eps == FV_METRICS_REL_EPS);
    assert_true(fabs(rep.all.rel_max - 1.0 / FV_METRICS_REL_EPS) < 1e-9);
    assert_true(fabs(rep.all.rel_mean - (0.5 + 1.0 / FV_METRICS_REL_EPS + 2.0 + 3.0) / (double)n) < 1e-12);
    assert_true(rep.all.rel_p99 == 0.5); /* nearest rank ceil(0.99 * 363) = 360 of 359 zeros, 0.5, 2, 3, 1000 */
    fv_metrics_desc d = {.rel_eps = 0.5};
    rep = compare_ok(&a, &b, &d);
    assert_true(rep.all.rel_max == 3.0);
    fv_rgb_image_fini(&a);
    fv_rgb_image_fini(&b);
}

static void nan_and_inf_inputs_are_refused_naming_the_pixel(void **state)
{
    (void)state;
    fv_rgb_image a = make(12, 11, FV_IMAGE_KIND_LINEAR), b = copy_of(&a);
    b.rgb[(2 * 12 + 3) * 3 + 1] = NAN;
    const char *path = fv_test_tmp("nan.pfm");
    assert_int_equal(fv_image_io_write_pfm(path, &b), FV_OK);
    fv_rgb_image_fini(&b);
    assert_int_equal(fv_image_io_read(path, &b), FV_OK); /* the reader keeps what the file holds */
    fv_metrics_desc d = {.name_a = "a.pfm", .name_b = "nan.pfm"};
    fv_metrics_report rep;
    fv_test_log_capture_begin();
    assert_int_equal(fv_metrics_compare(&a, &b, &d, &rep), FV_ERR_RANGE);
    fv_assert_log_contains("nan.pfm: pixel (3, 2) channel G is NaN: non-finite values are refused");
    assert_true(isnan(rep.all.psnr_db) && isnan(rep.all.ssim)); /* nothing computed, nothing finite-looking */
    a.rgb[(10 * 12 + 11) * 3 + 2] = -INFINITY;
    assert_int_equal(fv_metrics_compare(&a, &b, &d, &rep), FV_ERR_RANGE);
    fv_assert_log_contains("a.pfm: pixel (11, 10) channel B is Inf");
    fv_test_log_capture_end();
    fv_rgb_image_fini(&a);
    fv_rgb_image_fini(&b);
}

static void images_smaller_than_the_ssim_window_are_refused_like_skimage(void **state)
{
    (void)state;
    const uint32_t sizes[][2] = {{1, 1}, {10, 10}, {11, 10}, {10, 40}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        fv_rgb_image a = make(sizes[i][0], sizes[i][1], FV_IMAGE_KIND_SRGB8), b = copy_of(&a);
        fv_metrics_desc d = {0};
        fv_metrics_report rep;
        fv_test_log_capture_begin();
        assert_int_equal(fv_metrics_compare(&a, &b, &d, &rep), FV_ERR_RANGE);
        fv_assert_log_contains("smaller than the 11x11 SSIM window");
        double s, y[1] = {0};
        assert_int_equal(fv_metrics_ssim(y, y, sizes[i][0], sizes[i][1], &s), FV_ERR_RANGE);
        assert_true(isnan(s));
        fv_test_log_capture_end();
        fv_rgb_image_fini(&a);
        fv_rgb_image_fini(&b);
    }
    /* 11x11 is the smallest: the cropped map is one pixel */
    fv_rgb_image a = make(11, 11, FV_IMAGE_KIND_SRGB8), b = make(11, 11, FV_IMAGE_KIND_SRGB8);
    fv_metrics_report rep = compare_ok(&a, &b, NULL);
    assert_int_equal(rep.all.ssim_pixels, 1);
    assert_true(rep.all.ssim > -1.0 && rep.all.ssim < 1.0);
    fv_rgb_image_fini(&a);
    fv_rgb_image_fini(&b);
}

static void sizes_and_kinds_must_match(void **state)
{
    (void)state;
    fv_rgb_image a = make(12, 12, FV_IMAGE_KIND_SRGB8), b = make(12, 13, FV_IMAGE_KIND_SRGB8);
    fv_rgb_image c = make(12, 12, FV_IMAGE_KIND_LINEAR);
    fv_metrics_desc d = {.name_a = "a.png", .name_b = "b.png"};
    fv_metrics_report rep;
    fv_test_log_capture_begin();
    assert_int_equal(fv_metrics_compare(&a, &b, &d, &rep), FV_ERR_INVALID_ARG);
    fv_assert_log_contains("a.png is 12x12 but b.png is 12x13");
    d.name_b = "c.pfm";
    assert_int_equal(fv_metrics_compare(&a, &c, &d, &rep), FV_ERR_INVALID_ARG);
    fv_assert_log_contains("a.png is a PNG and c.pfm is a PFM");
    d.eyes = 2;
    d.name_b = "b";
    fv_rgb_image odd = make(13, 12, FV_IMAGE_KIND_SRGB8), odd2 = copy_of(&odd);
    assert_int_equal(fv_metrics_compare(&odd, &odd2, &d, &rep), FV_ERR_INVALID_ARG);
    fv_test_log_capture_end();
    fv_rgb_image_fini(&a);
    fv_rgb_image_fini(&b);
    fv_rgb_image_fini(&c);
    fv_rgb_image_fini(&odd);
    fv_rgb_image_fini(&odd2);
}

static void extreme_values_keep_every_metric_finite(void **state)
{
    (void)state;
    fv_rgb_image a = blank(12, 12, FV_IMAGE_KIND_LINEAR), b = blank(12, 12, FV_IMAGE_KIND_LINEAR);
    const float vals[] = {FLT_MAX, -FLT_MAX, FLT_MIN, FLT_TRUE_MIN, 0.0f, -0.0f, 1e30f, -1e-30f};
    for (size_t i = 0; i < 12 * 12 * 3; i++) {
        a.rgb[i] = vals[i % 8];
        b.rgb[i] = vals[(i * 5 + 3) % 8];
    }
    a.rgb[0] = FLT_MAX, b.rgb[0] = -FLT_MAX; /* the largest relative error: 2 */
    fv_metrics_desc d = {.mismatch_threshold = 1e300};
    fv_metrics_report rep = compare_ok(&a, &b, &d);
    assert_true(isfinite(rep.all.psnr_db) && isfinite(rep.all.ssim) && isfinite(rep.all.rel_mean));
    assert_true(isfinite(rep.all.rel_p99) && isfinite(rep.all.rel_max));
    assert_true(rep.all.ssim >= -1.0 && rep.all.ssim <= 1.0);
    assert_true(rep.all.rel_max >= 2.0);
    assert_true(rep.all.mismatch == 0.0); /* nothing differs by more than 1e300 */
    /* the sRGB encoding clamps: huge, negative, NaN */
    assert_true(fv_metrics_linear_to_srgb(1e300) == 1.0 && fv_metrics_linear_to_srgb(-5.0) == 0.0);
    assert_true(fv_metrics_linear_to_srgb(NAN) == 0.0 && fv_metrics_linear_to_srgb(0.0031308) < 0.0405);
    assert_true(fabs(fv_metrics_linear_to_srgb(0.5) - 0.735356983) < 1e-8);
    /* all-black against all-white (constant images: zero variance) */
    for (size_t i = 0; i < 12 * 12 * 3; i++) a.rgb[i] = 0.0f, b.rgb[i] = 1.0f;
    a.kind = b.kind = FV_IMAGE_KIND_SRGB8;
    rep = compare_ok(&a, &b, NULL);
    assert_true(rep.all.psnr_db == 0.0);
    assert_true(fabs(rep.all.ssim - 1e-4 / (1.0 + 1e-4)) < 1e-12); /* C1 / (1 + C1): only the luminance term */
    fv_rgb_image_fini(&a);
    fv_rgb_image_fini(&b);
}

/* ---- gaze, eccentricity and bands ---- */

static void gaze_from_degrees_points_right_up_and_forward(void **state)
{
    (void)state;
    fv_vec3 f = fv_metrics_gaze_dir_from_deg(0, 0), r = fv_metrics_gaze_dir_from_deg(90, 0);
    fv_vec3 u = fv_metrics_gaze_dir_from_deg(0, 90), m = fv_metrics_gaze_dir_from_deg(30, -20);
    assert_true(f.x == 0.0f && f.y == 0.0f && f.z == -1.0f);
    assert_true(fabsf(r.x - 1.0f) < 1e-7f && fabsf(r.z) < 1e-7f);
    assert_true(fabsf(u.y - 1.0f) < 1e-7f && fabsf(u.z) < 1e-7f);
    assert_true(m.x > 0 && m.y < 0 && m.z < 0 && fabsf(fv_v3_len(m) - 1.0f) < 1e-6f);
}

static void eccentricity_is_zero_at_the_gaze_pixel_and_the_angle_elsewhere(void **state)
{
    (void)state;
    fv_eye_view v[2];
    fv_eye_views_build(NULL, 0.05f, 100.0f, 64, 48, v);
    float ecc[64 * 48];
    fv_vec3 g = fv_metrics_view_ray(&v[0], 64, 48, 40, 10);
    fv_metrics_eccentricity_deg(&v[0], g, 64, 48, ecc, 64);
    assert_true(ecc[10 * 64 + 40] < 1e-3f);
    for (int i = 0; i < 64 * 48; i++) assert_true(ecc[i] >= 0.0f && ecc[i] <= 180.0f);
    /* straight ahead: a pixel's eccentricity is the angle of its ray from -z */
    fv_metrics_eccentricity_deg(&v[1], fv_v3(0, 0, -2), 64, 48, ecc, 64);
    double u = 0.5 / 64, t = 0.5 / 48;
    double x = v[1].tan_left + (v[1].tan_right - v[1].tan_left) * u, y = v[1].tan_up + (v[1].tan_down - v[1].tan_up) * t;
    double want = atan(sqrt(x * x + y * y)) * 180.0 / 3.14159265358979323846;
    assert_true(fabs(ecc[0] - want) < 1e-4);
    /* a gaze straight ahead from degrees matches the same */
    fv_metrics_eccentricity_deg(&v[1], fv_metrics_gaze_dir_from_deg(0, 0), 64, 48, ecc, 64);
    assert_true(fabs(ecc[0] - want) < 1e-4);
}

static void bands_split_the_pixels_and_take_ssim_from_each_eye(void **state)
{
    (void)state;
    const uint32_t ew = 40, h = 30, w = 2 * ew;
    fv_rgb_image a = make(w, h, FV_IMAGE_KIND_LINEAR), b = copy_of(&a);
    for (size_t i = 0; i < (size_t)w * h * 3; i++) b.rgb[i] += (float)(0.05 * (rnd() - 0.5));
    fv_eye_view v[2];
    fv_eye_views_build(NULL, 0.05f, 100.0f, ew, h, v);
    float *ecc = malloc((size_t)w * h * sizeof(float));
    fv_vec3 g = fv_metrics_view_ray(&v[0], ew, h, 20, 15);
    for (int e = 0; e < 2; e++) fv_metrics_eccentricity_deg(&v[e], g, ew, h, ecc + e * ew, w);
    fv_metrics_desc d = {.ecc_deg = ecc, .eyes = 2, .mismatch_threshold = 0.02};
    fv_metrics_report rep = compare_ok(&a, &b, &d);
    assert_true(rep.has_bands);
    uint64_t px = 0, ssim_px = 0, mis = 0;
    for (int k = 0; k < FV_METRICS_BANDS; k++) {
        px += rep.band[k].pixels;
        ssim_px += rep.band[k].ssim_pixels;
        mis += rep.band[k].mismatch_pixels;
        if (rep.band[k].pixels) {
            assert_true(isfinite(rep.band[k].psnr_db) && isfinite(rep.band[k].rel_p99));
            assert_true(rep.band[k].rel_p99 <= rep.band[k].rel_max);
        }
    }
    assert_int_equal(px, (uint64_t)w * h);
    assert_int_equal(ssim_px, 2 * (ew - 10) * (h - 10)); /* each eye cropped at its own borders */
    assert_int_equal(mis, rep.all.mismatch_pixels);
    assert_true(rep.band[0].pixels > 0 && rep.band[FV_METRICS_BANDS - 1].pixels > 0);
    /* one view: the bands' SSIM comes from the whole image's map */
    d.eyes = 1;
    rep = compare_ok(&a, &b, &d);
    ssim_px = 0;
    for (int k = 0; k < FV_METRICS_BANDS; k++) ssim_px += rep.band[k].ssim_pixels;
    assert_int_equal(ssim_px, (w - 10) * (h - 10));
    free(ecc);
    fv_rgb_image_fini(&a);
    fv_rgb_image_fini(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(pfm_rows_run_bottom_to_top_and_scale_sign_gives_byte_order),
        cmocka_unit_test(pfm_write_then_read_round_trips_every_bit),
        cmocka_unit_test(pfm_errors_name_the_file_and_the_reason),
        cmocka_unit_test(image_files_that_cannot_be_read_are_named),
        cmocka_unit_test(headers_give_size_and_cost_before_decoding),
        cmocka_unit_test(png_data_inflating_past_its_rows_is_refused),
        cmocka_unit_test(png_reads_as_srgb_values_with_alpha_dropped),
        cmocka_unit_test(identical_images_have_infinite_psnr_ssim_1_and_no_mismatch),
        cmocka_unit_test(constant_offsets_give_the_known_psnr),
        cmocka_unit_test(mismatch_counts_pixels_over_the_threshold_in_any_channel),
        cmocka_unit_test(relative_error_uses_b_as_reference_with_eps),
        cmocka_unit_test(nan_and_inf_inputs_are_refused_naming_the_pixel),
        cmocka_unit_test(images_smaller_than_the_ssim_window_are_refused_like_skimage),
        cmocka_unit_test(sizes_and_kinds_must_match),
        cmocka_unit_test(extreme_values_keep_every_metric_finite),
        cmocka_unit_test(gaze_from_degrees_points_right_up_and_forward),
        cmocka_unit_test(eccentricity_is_zero_at_the_gaze_pixel_and_the_angle_elsewhere),
        cmocka_unit_test(bands_split_the_pixels_and_take_ssim_from_each_eye),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
