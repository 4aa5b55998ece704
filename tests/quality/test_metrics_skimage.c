/* @brief fovea's PSNR and SSIM agree with scikit-image to 1e-4 on image pairs written to files (noise, blur, shifts,
 * gradients, constants, the smallest size, odd sizes, a stereo pair, a linear HDR PFM): fovea reads the PNG/PFM
 * files, Debian's /usr/bin/python3 (numpy, skimage: tools/install-deps.sh) reads the same pixels and computes
 * peak_signal_noise_ratio(data_range=1) and structural_similarity(gaussian_weights=True, sigma=1.5,
 * use_sample_covariance=False, data_range=1) on luma. A missing Python or skimage fails the test. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <stb_image_write.h>

#include "fv_image_io.h"
#include "fv_metrics.h"
#include "fv_test.h"

#define PYTHON "/usr/bin/python3"
#define TOL 1e-4

static const char g_script[] =
    "import sys, warnings\n"
    "import numpy as np\n"
    "from skimage.metrics import peak_signal_noise_ratio, structural_similarity\n"
    "warnings.simplefilter('ignore')\n"
    "def srgb(x):\n"
    "    x = np.clip(x, 0.0, 1.0)\n"
    "    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)\n"
    "def read_pfm(path):\n"
    "    data = open(path, 'rb').read()\n"
    "    magic, dims, scale, px = data.split(b'\\n', 3)\n"
    "    assert magic == b'PF'\n"
    "    w, h = (int(t) for t in dims.split())\n"
    "    a = np.frombuffer(px, dtype='<f4' if float(scale) < 0 else '>f4').reshape(h, w, 3)\n"
    "    return srgb(np.flipud(a).astype(np.float64))\n"
    "def read(kind, w, h, path):\n"
    "    if kind == 'pfm':\n"
    "        return read_pfm(path)\n"
    "    return np.fromfile(path, dtype=np.uint8).reshape(h, w, 3).astype(np.float64) / 255.0\n"
    "for line in open(sys.argv[1]):\n"
    "    name, kind, w, h, pa, pb = line.split()\n"
    "    a, b = read(kind, int(w), int(h), pa), read(kind, int(w), int(h), pb)\n"
    "    psnr = peak_signal_noise_ratio(a, b, data_range=1)\n"
    "    luma = lambda x: 0.299 * x[..., 0] + 0.587 * x[..., 1] + 0.114 * x[..., 2]\n"
    "    ssim = structural_similarity(luma(a), luma(b), gaussian_weights=True, sigma=1.5,\n"
    "                                 use_sample_covariance=False, data_range=1)\n"
    "    print(name, repr(float(psnr)), repr(float(ssim)))\n";

static uint32_t g_rng = 7u;
static double rnd(void) /* [0, 1) */
{
    g_rng = g_rng * 1664525u + 1013904223u;
    return (double)(g_rng >> 8) / 16777216.0;
}
static double gauss(void) { return sqrt(-2.0 * log(1.0 - rnd())) * cos(6.283185307179586 * rnd()); }
static double clamp01(double v) { return v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v; }

typedef enum pair_kind { NOISE, BLUR, SHIFT, GRADIENTS, RANDOM, STEREO, CONSTANT, HDR, SALT } pair_kind;

typedef struct pair {
    const char *name;
    pair_kind kind;
    uint32_t w, h;
    bool pfm;
} pair;

static const pair g_pairs[] = {
    {"noise_64x48", NOISE, 64, 48, false},
    {"blur_37x23", BLUR, 37, 23, false},
    {"shift_40x32", SHIFT, 40, 32, false},
    {"gradients_33x17", GRADIENTS, 33, 17, false},
    {"random_11x11", RANDOM, 11, 11, false},
    {"stereo_128x64", STEREO, 128, 64, false},
    {"constant_20x15", CONSTANT, 20, 15, false},
    {"hdr_29x31_pfm", HDR, 29, 31, true},
    {"salt_13x97", SALT, 13, 97, false},
};

static double texture(uint32_t x, uint32_t y, int c)
{
    return 0.5 + 0.3 * sin(0.7 * x + 1.3 * c) * cos(0.45 * y) + 0.15 * sin(0.11 * x * y + c);
}

/* Fill a and b (w*h*3 doubles, row-major) for one pair. */
static void generate(const pair *p, double *a, double *b)
{
    uint32_t w = p->w, h = p->h;
    size_t n = (size_t)w * h * 3;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            for (int c = 0; c < 3; c++) {
                size_t i = ((size_t)y * w + x) * 3 + (size_t)c;
                switch (p->kind) {
                case NOISE: a[i] = texture(x, y, c); b[i] = clamp01(a[i] + 0.05 * gauss()); break;
                case BLUR: case RANDOM: case SALT: a[i] = rnd(); b[i] = rnd(); break;
                case SHIFT: a[i] = texture(x, y, c); b[i] = texture((x + 1) % w, (y + 2) % h, c); break;
                case GRADIENTS: a[i] = (x + 0.5) / w; b[i] = (y + 0.5) / h * (c + 1) / 3.0; break;
                case STEREO: {
                    uint32_t ex = x % (w / 2);
                    a[i] = ((ex / 4 + y / 4) % 2) ? 0.8 : 0.2 + 0.1 * c;
                    b[i] = clamp01(a[i] + 0.02 * gauss());
                    break;
                }
                case CONSTANT: a[i] = 0.5; b[i] = 0.55; break;
                case HDR: a[i] = 3.0 * rnd() - 0.2; b[i] = a[i] * 1.1 + 0.01 * gauss(); break;
                }
            }
    if (p->kind == BLUR) /* b: a 3x3 box blur of a, edges clamped */
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                for (int c = 0; c < 3; c++) {
                    double s = 0.0;
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            long yy = (long)y + dy, xx = (long)x + dx;
                            yy = yy < 0 ? 0 : yy >= (long)h ? (long)h - 1 : yy;
                            xx = xx < 0 ? 0 : xx >= (long)w ? (long)w - 1 : xx;
                            s += a[((size_t)yy * w + (size_t)xx) * 3 + (size_t)c];
                        }
                    b[((size_t)y * w + x) * 3 + (size_t)c] = s / 9.0;
                }
    if (p->kind == SALT) /* b: a with one value in twenty replaced */
        for (size_t i = 0; i < n; i++) b[i] = rnd() < 0.05 ? rnd() : a[i];
}

/* Write one image: a PNG for fovea and its raw bytes for Python (8-bit pairs), or one PFM for both. */
static void write_image(const pair *p, const double *v, const char *base, char *fovea_path, char *py_path)
{
    size_t n = (size_t)p->w * p->h * 3;
    if (p->pfm) {
        fv_rgb_image img;
        assert_int_equal(fv_rgb_image_init(&img, p->w, p->h, FV_IMAGE_KIND_LINEAR), FV_OK);
        for (size_t i = 0; i < n; i++) img.rgb[i] = (float)v[i];
        snprintf(fovea_path, 1024, "%s.pfm", fv_test_tmp(base));
        assert_int_equal(fv_image_io_write_pfm(fovea_path, &img), FV_OK);
        fv_rgb_image_fini(&img);
        snprintf(py_path, 1024, "%s", fovea_path);
        return;
    }
    uint8_t *u8 = malloc(n);
    for (size_t i = 0; i < n; i++) u8[i] = (uint8_t)lround(clamp01(v[i]) * 255.0);
    snprintf(fovea_path, 1024, "%s.png", fv_test_tmp(base));
    assert_true(stbi_write_png(fovea_path, (int)p->w, (int)p->h, 3, u8, (int)p->w * 3) != 0);
    snprintf(py_path, 1024, "%s.u8", fv_test_tmp(base));
    FILE *f = fopen(py_path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(u8, 1, n, f), n);
    fclose(f);
    free(u8);
}

static void psnr_and_ssim_agree_with_scikit_image(void **state)
{
    (void)state;
    enum { N = sizeof g_pairs / sizeof g_pairs[0] };
    double psnr[N], ssim[N];
    char manifest[1 << 14] = "";
    for (size_t k = 0; k < N; k++) {
        const pair *p = &g_pairs[k];
        size_t n = (size_t)p->w * p->h * 3;
        double *a = malloc(n * sizeof(double)), *b = malloc(n * sizeof(double));
        generate(p, a, b);
        char base[128], fa[1024], fb[1024], pa[1024], pb[1024];
        snprintf(base, sizeof base, "%s_a", p->name);
        write_image(p, a, base, fa, pa);
        snprintf(base, sizeof base, "%s_b", p->name);
        write_image(p, b, base, fb, pb);
        free(a);
        free(b);
        fv_rgb_image ia, ib;
        assert_int_equal(fv_image_io_read(fa, &ia), FV_OK);
        assert_int_equal(fv_image_io_read(fb, &ib), FV_OK);
        fv_metrics_desc d = {.name_a = fa, .name_b = fb};
        fv_metrics_report rep;
        assert_int_equal(fv_metrics_compare(&ia, &ib, &d, &rep), FV_OK);
        psnr[k] = rep.all.psnr_db;
        ssim[k] = rep.all.ssim;
        fv_rgb_image_fini(&ia);
        fv_rgb_image_fini(&ib);
        size_t len = strlen(manifest);
        snprintf(manifest + len, sizeof manifest - len, "%s %s %u %u %s %s\n", p->name, p->pfm ? "pfm" : "png", p->w,
                 p->h, pa, pb);
    }
    char man_path[1024], script_path[1024], args[2200];
    snprintf(man_path, sizeof man_path, "%s", fv_test_write_file("pairs.txt", manifest, strlen(manifest)));
    snprintf(script_path, sizeof script_path, "%s", fv_test_write_file("skimage_check.py", g_script, strlen(g_script)));
    snprintf(args, sizeof args, "%s %s", script_path, man_path);
    static fv_test_cmd res;
    fv_test_run_cmd(&res, NULL, PYTHON, args);
    if (res.exit_code != 0)
        fail_msg(PYTHON " with numpy and skimage is needed (python3-numpy python3-skimage, tools/install-deps.sh); "
                 "exit %d:\n%s", res.exit_code, res.err);
    double worst_psnr = 0.0, worst_ssim = 0.0;
    const char *line = res.out;
    for (size_t k = 0; k < N; k++) {
        char name[128];
        double sk_psnr, sk_ssim;
        if (sscanf(line, "%127s %lf %lf", name, &sk_psnr, &sk_ssim) != 3 || strcmp(name, g_pairs[k].name) != 0)
            fail_msg("unexpected output from skimage at pair %zu:\n%s", k, res.out);
        double dp = fabs(psnr[k] - sk_psnr), ds = fabs(ssim[k] - sk_ssim);
        print_message("%-16s psnr %.9f dB (skimage %.9f, |d| %.2e)  ssim %.9f (skimage %.9f, |d| %.2e)\n", name,
                      psnr[k], sk_psnr, dp, ssim[k], sk_ssim, ds);
        if (!(dp <= TOL) || !(ds <= TOL)) fail_msg("%s differs from skimage by more than %g", name, TOL);
        worst_psnr = fmax(worst_psnr, dp);
        worst_ssim = fmax(worst_ssim, ds);
        line = strchr(line, '\n');
        assert_non_null(line);
        line++;
    }
    print_message("largest difference from skimage over %d pairs: psnr %.2e dB, ssim %.2e\n", (int)N, worst_psnr,
                  worst_ssim);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(psnr_and_ssim_agree_with_scikit_image),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
