/* @brief `fovea compare A B` as a user runs it: known PSNR on PNG pairs, identical images (PSNR null in JSON), PFM
 * relative error, eccentricity bands of a side-by-side stereo image, and one-line errors: usage (exit 2), unreadable
 * or truncated files, mismatched sizes, PNG against PFM, NaN pixels, images smaller than the SSIM window (exit 1);
 * FIFOs, devices and directories refused without waiting or reading; images over the memory budget or the size
 * limits refused from their headers. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stb_image_write.h>

#include "fv_test.h"

static const char *g_fovea;

static fv_test_cmd *run(const char *args)
{
    static fv_test_cmd res;
    fv_test_run_cmd(&res, NULL, g_fovea, args);
    return &res;
}

static int count_lines(const char *s)
{
    int n = 0;
    for (; *s; s++) n += *s == '\n';
    return n;
}

/* A w x h RGB PNG under the test's temp dir with values v(x, y, c) = (x * 7 + y * 3 + c * 50 + offset) % 200. */
static const char *png(const char *name, int w, int h, int offset)
{
    uint8_t *px = malloc((size_t)w * h * 3);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++) px[(y * w + x) * 3 + c] = (uint8_t)((x * 7 + y * 3 + c * 50) % 200 + offset);
    const char *path = fv_test_tmp(name);
    assert_true(stbi_write_png(path, w, h, 3, px, w * 3) != 0);
    free(px);
    return path;
}

/* A w x h colour PFM (little-endian, rows bottom to top) with value scale * (1 + (x + y + c) % 5); one value NaN
 * at pixel (nan_x, 0) when nan_x >= 0. */
static const char *pfm(const char *name, int w, int h, float scale, int nan_x)
{
    size_t n = (size_t)w * h * 3;
    float *px = malloc(n * sizeof(float));
    for (int fy = 0; fy < h; fy++) /* file row fy is image row h - 1 - fy */
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++)
                px[((size_t)fy * w + x) * 3 + c] = scale * (float)(1 + (x + (h - 1 - fy) + c) % 5);
    if (nan_x >= 0) px[((size_t)(h - 1) * w + nan_x) * 3] = NAN;
    char head[64];
    int hn = snprintf(head, sizeof head, "PF\n%d %d\n-1.0\n", w, h);
    char *bytes = malloc((size_t)hn + n * 4);
    memcpy(bytes, head, (size_t)hn);
    memcpy(bytes + hn, px, n * 4); /* the host is little-endian (x86-64, arm64) */
    const char *path = fv_test_write_file(name, bytes, (size_t)hn + n * 4);
    free(px);
    free(bytes);
    return path;
}

static cJSON *json_of(const fv_test_cmd *r)
{
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    assert_int_equal(count_lines(r->out), 1);
    const char *never[] = {":nan", ":-nan", ":inf", ":-inf", "Infinity", "NaN"};
    for (size_t i = 0; i < sizeof never / sizeof never[0]; i++) assert_null(strstr(r->out, never[i]));
    cJSON *j = cJSON_Parse(r->out);
    if (!j) fail_msg("stdout is not JSON:\n%s", r->out);
    return j;
}

/* `fovea compare A B --json EXTRA`: its one JSON object (the caller deletes it). */
static cJSON *compare_json(const char *a, const char *b, const char *extra)
{
    char args[2400];
    snprintf(args, sizeof args, "compare %s %s --json %s", a, b, extra);
    return json_of(run(args));
}

/* `fovea compare A B EXTRA` as text: its stdout, after exit 0. */
static const char *compare_text(const char *a, const char *b, const char *extra)
{
    char args[2400];
    snprintf(args, sizeof args, "compare %s %s %s", a, b, extra);
    fv_test_cmd *r = run(args);
    if (r->exit_code != 0) fail_msg("'%s' exited %d:\n%s", args, r->exit_code, r->err);
    return r->out;
}

static double num(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItem(o, key);
    if (!cJSON_IsNumber(v)) fail_msg("'%s' is not a number", key);
    return v->valuedouble;
}

static void help_lists_the_options_and_the_command(void **state)
{
    (void)state;
    fv_test_cmd *r = run("compare --help");
    assert_int_equal(r->exit_code, 0);
    const char *want[] = {"usage: fovea compare A B", "--gaze X,Y", "--gaze-deg YAW,PITCH", "--threshold", "--layout",
                          "null in JSON", "max(|B|, 1e-3)", "smaller than 11x11", "sbs when the width is even"};
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) fv_assert_contains(r->out, want[i]);
    r = run("--help");
    fv_assert_contains(r->out, "compare");
}

static void a_known_offset_gives_the_known_psnr_as_text_and_json(void **state)
{
    (void)state;
    char a[1024], b[1024];
    snprintf(a, sizeof a, "%s", png("off_a.png", 37, 23, 0));
    snprintf(b, sizeof b, "%s", png("off_b.png", 37, 23, 10));
    cJSON *j = compare_json(a, b, "");
    double want = 20.0 * log10(255.0 / 10.0);
    if (fabs(num(j, "psnr_db") - want) > 1e-4) fail_msg("psnr %.6f, want %.6f", num(j, "psnr_db"), want);
    assert_true(num(j, "mismatch") == 1.0);
    assert_true(num(j, "ssim") > 0.9 && num(j, "ssim") < 1.0);
    assert_string_equal(cJSON_GetObjectItem(j, "layout")->valuestring, "mono"); /* odd width */
    assert_string_equal(cJSON_GetObjectItem(j, "kind")->valuestring, "png");
    assert_null(cJSON_GetObjectItem(j, "rel_error"));
    assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItem(j, "bands")), 5);
    cJSON_Delete(j);
    const char *out = compare_text(a, b, "--threshold 0.05");
    fv_assert_contains(out, "psnr dB");
    fv_assert_contains(out, "28.131"); /* 20 log10(25.5) */
    fv_assert_contains(out, "0-5 deg");
    fv_assert_contains(out, "30-180 deg");
}

static void identical_images_report_null_psnr_never_inf(void **state)
{
    (void)state;
    char a[1024];
    snprintf(a, sizeof a, "%s", png("same.png", 24, 16, 0));
    cJSON *j = compare_json(a, a, "");
    assert_true(cJSON_IsNull(cJSON_GetObjectItem(j, "psnr_db")));
    assert_true(cJSON_IsTrue(cJSON_GetObjectItem(j, "psnr_infinite")));
    assert_true(num(j, "ssim") == 1.0);
    assert_true(num(j, "mismatch") == 0.0);
    cJSON_Delete(j);
    fv_assert_contains(compare_text(a, a, ""), "inf");
}

static void stereo_bands_cover_both_eyes_around_the_gaze(void **state)
{
    (void)state;
    char a[1024], b[1024];
    snprintf(a, sizeof a, "%s", png("sbs_a.png", 128, 64, 0));
    snprintf(b, sizeof b, "%s", png("sbs_b.png", 128, 64, 3));
    const char *gazes[] = {"--gaze 32,32", "--gaze-deg 10,-5", ""};
    for (size_t g = 0; g < 3; g++) {
        cJSON *j = compare_json(a, b, gazes[g]);
        assert_string_equal(cJSON_GetObjectItem(j, "layout")->valuestring, "sbs");
        assert_true(num(j, "eyes") == 2 && num(j, "eye_width") == 64);
        cJSON *bands = cJSON_GetObjectItem(j, "bands");
        double px = 0, ssim_px = 0;
        for (int k = 0; k < cJSON_GetArraySize(bands); k++) {
            px += num(cJSON_GetArrayItem(bands, k), "pixels");
            ssim_px += num(cJSON_GetArrayItem(bands, k), "ssim_pixels");
        }
        assert_true(px == 128 * 64);
        assert_true(ssim_px == 2 * 54 * 54);
        assert_true(num(cJSON_GetArrayItem(bands, 0), "pixels") > 0);
        cJSON *gz = cJSON_GetObjectItem(j, "gaze");
        if (g == 1) assert_true(fabs(num(gz, "yaw_deg") - 10.0) < 1e-4 && fabs(num(gz, "pitch_deg") + 5.0) < 1e-4);
        if (g == 2) assert_true(num(gz, "yaw_deg") == 0.0 && num(gz, "pitch_deg") == 0.0);
        cJSON_Delete(j);
    }
    cJSON *j = compare_json(a, b, "--layout mono");
    assert_true(num(j, "eyes") == 1);
    cJSON_Delete(j);
}

static void pfm_pairs_get_the_relative_error(void **state)
{
    (void)state;
    char a[1024], b[1024];
    snprintf(a, sizeof a, "%s", pfm("lin_a.pfm", 20, 12, 0.15f, -1));
    snprintf(b, sizeof b, "%s", pfm("lin_b.pfm", 20, 12, 0.1f, -1));
    cJSON *j = compare_json(a, b, "");
    cJSON *rel = cJSON_GetObjectItem(j, "rel_error");
    assert_non_null(rel);
    assert_true(fabs(num(rel, "mean") - 0.5) < 1e-6 && fabs(num(rel, "p99") - 0.5) < 1e-6);
    assert_true(fabs(num(rel, "max") - 0.5) < 1e-6 && num(rel, "eps") == 1e-3);
    assert_string_equal(cJSON_GetObjectItem(j, "kind")->valuestring, "pfm");
    assert_true(num(j, "psnr_db") > 10.0); /* values 0.1..0.5 stay inside the sRGB range */
    cJSON_Delete(j);
    fv_assert_contains(compare_text(a, b, ""), "rel p99");
}

static void usage_errors_exit_2_with_one_line(void **state)
{
    (void)state;
    char a[1024], args[2400];
    snprintf(a, sizeof a, "%s", png("u.png", 16, 16, 0));
    const char *bad[][2] = {
        {"", "needs two images"},
        {"A_", "needs two images"},
        {"A_ A_ A_", "one image too many"},
        {"A_ A_ --bogus", "unknown option '--bogus'"},
        {"A_ A_ --threshold -1", "--threshold: '-1'"},
        {"A_ A_ --threshold nan", "--threshold: 'nan'"},
        {"A_ A_ --threshold", "--threshold: ''"},
        {"A_ A_ --gaze 3", "--gaze: '3' is not a pixel position X,Y"},
        {"A_ A_ --gaze -1,2", "--gaze: '-1,2'"},
        {"A_ A_ --gaze-deg 200,0", "--gaze-deg: '200,0'"},
        {"A_ A_ --gaze-deg 0,95", "--gaze-deg: '0,95'"},
        {"A_ A_ --gaze 1,1 --gaze-deg 0,0", "exclude each other"},
        {"A_ A_ --layout tb", "--layout: 'tb' is not one of sbs, mono"},
        {"A_ A_ --gaze 8,3", "--gaze: (8, 3) is outside the left eye (8x16)"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char expanded[2048] = "";
        for (const char *p = bad[i][0]; *p; p++) { /* A_ stands for the PNG */
            if (p[0] == 'A' && p[1] == '_') {
                strncat(expanded, a, sizeof expanded - strlen(expanded) - 1);
                p++;
            } else {
                strncat(expanded, p, 1);
            }
        }
        snprintf(args, sizeof args, "compare %s", expanded);
        fv_test_cmd *r = run(args);
        if (r->exit_code != 2) fail_msg("'%s' exited %d, not 2:\n%s", args, r->exit_code, r->err);
        assert_true(strncmp(r->err, "fovea compare: ", 15) == 0);
        fv_assert_contains(r->err, bad[i][1]);
        fv_assert_contains(r->err, "usage: fovea compare");
        assert_int_equal(r->out[0], '\0');
    }
}

static void unreadable_or_incomparable_files_exit_1_with_one_line(void **state)
{
    (void)state;
    char p16[1024], p17[1024], p5[1024], f16[1024], fnan[1024], trunc[1024], text[1024], args[4400];
    snprintf(p16, sizeof p16, "%s", png("e16.png", 16, 16, 0));
    snprintf(p17, sizeof p17, "%s", png("e17.png", 17, 16, 0));
    snprintf(p5, sizeof p5, "%s", png("e5.png", 5, 5, 0));
    snprintf(f16, sizeof f16, "%s", pfm("e16.pfm", 16, 16, 1.0f, -1));
    snprintf(fnan, sizeof fnan, "%s", pfm("enan.pfm", 16, 16, 1.0f, 3));
    snprintf(trunc, sizeof trunc, "%s", fv_test_write_file("trunc.pfm", "PF\n16 16\n-1\n\1\2\3", 15));
    snprintf(text, sizeof text, "%s", fv_test_write_file("note.txt", "hello\n", 6));
    struct {
        const char *a, *b, *why;
    } cases[] = {
        {"/nonexistent/a.png", p16, "/nonexistent/a.png: cannot open"},
        {p16, p17, "is 16x16 but"},
        {p16, f16, "is a PNG and"},
        {p16, trunc, "trunc.pfm: truncated"},
        {p16, text, "note.txt: neither a PNG nor a PFM file"},
        {f16, fnan, "enan.pfm: pixel (3, 0) channel R is NaN"},
        {p5, p5, "smaller than the 11x11 SSIM window"},
        {p17, p17, "--layout sbs needs an even width"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(args, sizeof args, "compare %s %s%s", cases[i].a, cases[i].b, i == 7 ? " --layout sbs" : "");
        fv_test_cmd *r = run(args);
        if (r->exit_code != 1) fail_msg("case %zu exited %d, not 1:\n%s", i, r->exit_code, r->err);
        fv_assert_contains(r->err, cases[i].why);
        assert_true(strncmp(r->err, "fovea compare: ", 15) == 0);
        if (count_lines(r->err) != 1) fail_msg("case %zu: more than one line:\n%s", i, r->err);
        assert_int_equal(r->out[0], '\0');
    }
}

/* A PNG of only a signature, an IHDR of w x h RGB and IEND: its header says the size, no pixel follows. */
static const char *png_header_only(const char *name, uint32_t w, uint32_t h)
{
    uint8_t b[57] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R'};
    for (int i = 0; i < 4; i++) b[16 + i] = (uint8_t)(w >> (24 - 8 * i)), b[20 + i] = (uint8_t)(h >> (24 - 8 * i));
    b[24] = 8; /* bit depth */
    b[25] = 2; /* RGB; compression, filter, interlace 0; CRC (unchecked) 0 */
    memcpy(b + 33, "\0\0\0\0IEND\xae\x42\x60\x82", 12);
    return fv_test_write_file(name, b, 45);
}

/* What is not a regular file is refused by name before a byte is read: a FIFO without a writer (run under timeout:
 * exit 124 would be the hang), a character device (/dev/zero was read to 1 GiB), a directory (was "empty file"). */
static void files_that_are_no_images_are_refused_without_waiting_or_reading(void **state)
{
    (void)state;
    char fifo[1024], dir[1024], p16[1024], prog[1200], args[4400];
    snprintf(prog, sizeof prog, "timeout -k 5 20 '%s'", g_fovea);
    snprintf(fifo, sizeof fifo, "%s", fv_test_tmp("nowriter.png"));
    unlink(fifo);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    snprintf(dir, sizeof dir, "%s", fv_test_tmp("adir.png"));
    mkdir(dir, 0700);
    snprintf(p16, sizeof p16, "%s", png("r16.png", 16, 16, 0));
    struct {
        const char *a, *b, *why;
    } cases[] = {
        {fifo, p16, "nowriter.png: not a regular file: it is a FIFO"},
        {p16, fifo, "nowriter.png: not a regular file: it is a FIFO"},
        {"/dev/zero", p16, "/dev/zero: not a regular file: it is a character device"},
        {dir, p16, "adir.png: not a regular file: it is a directory"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        static fv_test_cmd r;
        snprintf(args, sizeof args, "compare '%s' '%s'", cases[i].a, cases[i].b);
        fv_test_run_cmd(&r, NULL, prog, args);
        if (r.exit_code != 1) fail_msg("case %zu exited %d, not 1:\n%s", i, r.exit_code, r.err);
        fv_assert_contains(r.err, cases[i].why);
        assert_true(strncmp(r.err, "fovea compare: ", 15) == 0);
        if (count_lines(r.err) != 1) fail_msg("case %zu: more than one line:\n%s", i, r.err);
    }
}

/* Images inside the size limits but over the memory budget are refused from their headers, before any pixel is
 * decoded, with the estimate and the budget (a 49 KB 4096x4096 PNG made compare take 1.7 GB); an image over the
 * size limits is called too large, not "unknown image type"; the budget is an option, documented in --help. */
static void images_over_the_memory_budget_are_refused_from_their_headers(void **state)
{
    (void)state;
    char big[1024], huge[1024], a[1024], b[1024], args[4400];
    snprintf(big, sizeof big, "%s", png_header_only("h4096.png", 4096, 4096));
    snprintf(huge, sizeof huge, "%s", png_header_only("h20000.png", 20000, 20000));
    snprintf(a, sizeof a, "%s", png("m512a.png", 512, 512, 0));
    snprintf(b, sizeof b, "%s", png("m512b.png", 512, 512, 3));
    struct {
        const char *a, *b, *extra, *why;
    } cases[] = {
        {big, big, "", "against"},
        {big, big, "", "(4096x4096 PNG): too large to work on: it needs about 2017 MiB, over the budget of 1024 MiB "
                       "(--max-memory-mib)"},
        {huge, a, "", "h20000.png: too large: dimensions 20000x20000 over the limit (16384 per side, 67108864 "
                      "pixels)"},
        {a, b, " --max-memory-mib 16", "m512a.png (512x512 PNG) against"},
        {a, b, " --max-memory-mib 16", "too large to work on: it needs about 32 MiB, over the budget of 16 MiB"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(args, sizeof args, "compare '%s' '%s'%s", cases[i].a, cases[i].b, cases[i].extra);
        fv_test_cmd *r = run(args);
        if (r->exit_code != 1) fail_msg("case %zu exited %d, not 1:\n%s", i, r->exit_code, r->err);
        fv_assert_contains(r->err, cases[i].why);
        assert_true(strncmp(r->err, "fovea compare: ", 15) == 0);
        if (count_lines(r->err) != 1) fail_msg("case %zu: more than one line:\n%s", i, r->err);
    }
    /* within a budget that holds them, the same pair compares */
    snprintf(args, sizeof args, "compare '%s' '%s' --max-memory-mib 40", a, b);
    fv_test_cmd *r = run(args);
    if (r->exit_code != 0) fail_msg("exit %d:\n%s", r->exit_code, r->err);
    fv_assert_contains(r->out, "512x512 PNG");
    r = run("compare --help");
    fv_assert_contains(r->out, "--max-memory-mib M");
    fv_assert_contains(r->out, "default 1024");
    r = run("compare a.png b.png --max-memory-mib 0");
    assert_int_equal(r->exit_code, 2);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s PATH_TO_FOVEA\n", argv[0]);
        return 2;
    }
    g_fovea = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(help_lists_the_options_and_the_command),
        cmocka_unit_test(a_known_offset_gives_the_known_psnr_as_text_and_json),
        cmocka_unit_test(identical_images_report_null_psnr_never_inf),
        cmocka_unit_test(stereo_bands_cover_both_eyes_around_the_gaze),
        cmocka_unit_test(pfm_pairs_get_the_relative_error),
        cmocka_unit_test(usage_errors_exit_2_with_one_line),
        cmocka_unit_test(unreadable_or_incomparable_files_exit_1_with_one_line),
        cmocka_unit_test(files_that_are_no_images_are_refused_without_waiting_or_reading),
        cmocka_unit_test(images_over_the_memory_budget_are_refused_from_their_headers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
