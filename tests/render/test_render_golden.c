/* @brief Golden-image regression test of the whole renderer (issue 6): the built-in Cornell box and a glTF, an OBJ
 * and a PLY scene from shared/data, two frames each, against images captured from the renderer before the refactor
 * (tests/render/golden/), with the validation layer forced on and zero messages allowed.
 *
 * Per scene, 96 x 80 per eye: frame 0 (time 0, the scene's head) and frame 1 (time 1/90 s, the head yawed 0.5 deg
 * and moved right by 1 % of its distance to the scene centre, so that the motion vectors are not all zero: none of
 * these scenes animates). Compared: the side-by-side sRGB RGBA8 image of both frames (PNG), and of frame 1 the
 * linear colour and the motion vectors of both eyes (gzip'd little-endian float32 with a 16-byte header "FVF1",
 * width, height, channels as uint32 LE).
 *
 * The tone curve: the golden PNGs are the linear colour through the pre-refactor display mapping (exposure 1, clamp
 * to [0,1], sRGB). The display now uses a tone curve (render/present/fv_tone_curve.h), which changes the display image
 * but not the linear colour. So the PNGs are compared with the linear colour of both frames encoded on the CPU the
 * old way (clamp + sRGB; within 1 level: CPU and GPU round the sRGB power differently), which checks the renderer's
 * colour exactly as before; and the display image the GPU wrote is compared, separately, with the same linear
 * colour through the tone curve on the CPU (within 1 level), which checks the present pass. A renderer change fails
 * the first; a tone curve or present change fails the second. A data view (normal) is checked to stay untouched by
 * the curve (clamp + sRGB).
 *
 * Tolerance: on lavapipe (llvmpipe) RGBA8 bit-identical and every float within |a - b| <= 1e-6 * max(1, |b|). The
 * golden files are specific to llvmpipe: on any other device the test says so and compares loosely (RGBA8 within 2
 * levels, floats within 1e-3 * max(1, |b|)). A failure names the scene, image, eye, worst pixel and its values.
 *
 * FV_GOLDEN_WRITE=DIR writes the files into DIR instead (then reads them back and compares, to check the files). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <stb_image.h>
#include <stb_image_write.h>
#include <zlib.h>

#include "fovea_config.h"
#include "fv_renderer.h"
#include "fv_scene.h"
#include "fv_metrics.h"
#include "fv_test.h"
#include "fv_tone_curve.h"
#include "gpu_test.h"

#define W 96
#define H 80
#define GOLDEN_DIR FV_SOURCE_DIR "/tests/render/golden"
#define EXACT_REL 1e-6
#define LOOSE_REL 1e-3
#define LOOSE_LEVELS 2

FV_GPU_TEST_GROUP_MOTION(W, H) /* the tests read the motion vectors back */

/* ---- files ----------------------------------------------------------------------------------------------------- */

static const char *golden_path(const char *dir, const char *scene, const char *what)
{
    static char buf[4][1024];
    static int slot;
    char *p = buf[slot];
    slot = (slot + 1) % 4;
    snprintf(p, 1024, "%s/%s_%s", dir, scene, what);
    return p;
}

static void put_u32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static void write_floats(const char *path, const float *v, uint32_t w, uint32_t h, uint32_t c)
{
    size_t n = (size_t)w * h * c;
    uint8_t *bytes = malloc(16 + n * 4);
    assert_non_null(bytes);
    memcpy(bytes, "FVF1", 4);
    put_u32(bytes + 4, w);
    put_u32(bytes + 8, h);
    put_u32(bytes + 12, c);
    for (size_t i = 0; i < n; i++) {
        uint32_t u;
        memcpy(&u, &v[i], 4);
        put_u32(bytes + 16 + 4 * i, u);
    }
    gzFile f = gzopen(path, "wb9");
    if (!f) fail_msg("cannot write %s: %s", path, strerror(errno));
    int ok = gzwrite(f, bytes, (unsigned)(16 + n * 4)) == (int)(16 + n * 4);
    ok = gzclose(f) == Z_OK && ok;
    free(bytes);
    if (!ok) fail_msg("short write of %s", path);
}

/* Read a float file written by write_floats; fails the test unless it holds w x h x c values. Caller frees. */
static float *read_floats(const char *path, uint32_t w, uint32_t h, uint32_t c)
{
    gzFile f = gzopen(path, "rb");
    if (!f) fail_msg("cannot open golden file %s: %s (write it with FV_GOLDEN_WRITE=DIR)", path, strerror(errno));
    uint8_t hdr[16];
    if (gzread(f, hdr, 16) != 16 || memcmp(hdr, "FVF1", 4) != 0) {
        gzclose(f);
        fail_msg("%s: not an FVF1 float file", path);
    }
    uint32_t fw = get_u32(hdr + 4), fh = get_u32(hdr + 8), fc = get_u32(hdr + 12);
    if (fw != w || fh != h || fc != c) {
        gzclose(f);
        fail_msg("%s holds %ux%ux%u, the test renders %ux%ux%u", path, fw, fh, fc, w, h, c);
    }
    size_t n = (size_t)w * h * c;
    uint8_t *bytes = malloc(n * 4 + 1);
    float *v = malloc(n * sizeof *v);
    assert_non_null(bytes);
    assert_non_null(v);
    int got = gzread(f, bytes, (unsigned)(n * 4 + 1)); /* one more: trailing data is an error */
    gzclose(f);
    if (got != (int)(n * 4)) {
        free(bytes);
        free(v);
        fail_msg("%s: %d data bytes, expected %zu", path, got, n * 4);
    }
    for (size_t i = 0; i < n; i++) {
        uint32_t u = get_u32(bytes + 4 * i);
        memcpy(&v[i], &u, 4);
    }
    free(bytes);
    return v;
}

static void write_png(const char *path, const uint8_t *rgba, uint32_t w, uint32_t h)
{
    if (!stbi_write_png(path, (int)w, (int)h, 4, rgba, (int)(w * 4))) fail_msg("cannot write %s", path);
}

static uint8_t *read_png(const char *path, uint32_t w, uint32_t h)
{
    int fw = 0, fh = 0, comp = 0;
    uint8_t *p = stbi_load(path, &fw, &fh, &comp, 4);
    if (!p) fail_msg("cannot read golden image %s: %s (write it with FV_GOLDEN_WRITE=DIR)", path, stbi_failure_reason());
    if (fw != (int)w || fh != (int)h) {
        stbi_image_free(p);
        fail_msg("%s is %dx%d, the test renders %ux%u", path, fw, fh, w, h);
    }
    return p;
}

/* ---- comparison ------------------------------------------------------------------------------------------------ */

typedef struct tolerance {
    int levels; /* RGBA8: max |a - b| per channel */
    double rel; /* floats: |a - b| <= rel * max(1, |b|) */
} tolerance;

/* RGBA8 side-by-side image (2W x H): every channel within tol->levels; otherwise report the worst pixel. */
static void compare_rgba8(const char *scene, const char *what, const uint8_t *got, const uint8_t *want,
                          const tolerance *tol)
{
    size_t bad = 0, worst_i = 0;
    int worst = -1;
    for (size_t i = 0; i < (size_t)2 * W * H * 4; i++) {
        int d = abs((int)got[i] - (int)want[i]);
        if (d > tol->levels) bad++;
        if (d > worst) {
            worst = d;
            worst_i = i;
        }
    }
    if (!bad) return;
    size_t px = worst_i / 4, sx = px % (2 * W), y = px / (2 * W);
    const uint8_t *g = got + px * 4, *e = want + px * 4;
    fail_msg("%s %s: %zu of %d channel values differ by more than %d; worst: eye %zu pixel (%zu,%zu) "
             "got (%u,%u,%u,%u) want (%u,%u,%u,%u)",
             scene, what, bad, 2 * W * H * 4, tol->levels, sx / W, sx % W, y, g[0], g[1], g[2], g[3], e[0], e[1],
             e[2], e[3]);
}

/* One eye's float image (W x H x c): each value within tol->rel * max(1, |want|); NaN matches only NaN. */
static void compare_floats(const char *scene, const char *what, int eye, const float *got, const float *want,
                           uint32_t c, const tolerance *tol)
{
    size_t n = (size_t)W * H * c, bad = 0, worst_i = 0;
    double worst = -1;
    for (size_t i = 0; i < n; i++) {
        double a = got[i], b = want[i], err;
        if (isnan(a) || isnan(b)) err = isnan(a) && isnan(b) ? 0 : INFINITY;
        else if (a == b) err = 0; /* equal infinities too */
        else err = fabs(a - b) / fmax(1.0, fabs(b));
        if (!(err <= tol->rel)) bad++;
        if (err > worst) {
            worst = err;
            worst_i = i;
        }
    }
    if (!bad) return;
    size_t px = worst_i / c;
    const float *g = got + px * c, *e = want + px * c;
    char gs[160] = "", es[160] = "";
    for (uint32_t k = 0; k < c; k++) {
        size_t lg = strlen(gs), le = strlen(es);
        snprintf(gs + lg, sizeof gs - lg, "%s%.9g", k ? "," : "", (double)g[k]);
        snprintf(es + le, sizeof es - le, "%s%.9g", k ? "," : "", (double)e[k]);
    }
    fail_msg("%s %s eye %d: %zu of %zu values off by more than %g * max(1,|want|); worst: pixel (%zu,%zu) "
             "channel %zu, error %.3g: got (%s) want (%s)",
             scene, what, eye, bad, n, tol->rel, px % W, px / W, worst_i % c, worst, gs, es);
}

/* The side-by-side RGBA8 image (2W x H) of both eyes' linear colour (W x H x 4 each), encoded on the CPU: the old
 * mapping (clamp + sRGB) or the present pass's (tone curve + sRGB); exposure 1. */
static void encode_sbs(float *const linear[2], bool tone, uint8_t *out)
{
    for (int eye = 0; eye < 2; eye++)
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                const float *p = linear[eye] + ((size_t)y * W + x) * 4;
                uint8_t *o = out + ((size_t)y * 2 * W + (size_t)eye * W + x) * 4;
                for (int c = 0; c < 3; c++) {
                    float v = tone ? fv_tone_reinhard_ext(fv_tone_sanitize(p[c])) : p[c];
                    o[c] = (uint8_t)(fv_metrics_linear_to_srgb(v) * 255.0 + 0.5);
                }
                o[3] = 255;
            }
}

/* ---- the scenes -------------------------------------------------------------------------------------------------- */

typedef struct golden_scene {
    const char *name;   /* file-name prefix in golden/ */
    const char *source; /* built-in name, or a path under shared/data */
    bool shared;
    float closer;       /* 0 = the scene's head; else move the head along its line to the bounds centre to this
                           fraction of its distance, so that a small-looking model fills more of the 96 x 80 pixels */
} golden_scene;

/* Frame 1's head: the scene's head yawed 0.5 deg about world +y and moved right by 1 % of its distance to the centre
 * of the scene bounds, so that frame 1 has camera motion (rotation and depth-dependent parallax). */
static fv_head moved_head(const fv_scene *s)
{
    fv_head h = s->head;
    fv_vec3 lo, hi;
    float dist = 1.0f;
    if (fv_scene_world_bounds(s, 0.0, &lo, &hi)) {
        fv_vec3 centre = fv_v3_scale(fv_v3_add(lo, hi), 0.5f);
        fv_vec3 d = {centre.x - h.position_m.x, centre.y - h.position_m.y, centre.z - h.position_m.z};
        dist = sqrtf(d.x * d.x + d.y * d.y + d.z * d.z);
    }
    fv_vec3 right = fv_quat_rotate(h.orientation, fv_v3(1, 0, 0));
    h.position_m = fv_v3_add(h.position_m, fv_v3_scale(right, 0.01f * dist));
    h.orientation = fv_quat_mul(fv_quat_axis_angle(fv_v3(0, 1, 0), (float)fv_deg_to_rad(0.5)), h.orientation);
    return h;
}

static void check_scene(const golden_scene *gs)
{
    FV_NEED_GPU(g_r);
    const char *write_dir = getenv("FV_GOLDEN_WRITE");
    if (write_dir && !*write_dir) write_dir = NULL;
    const char *dev = fv_renderer_device_name(g_r);
    bool llvmpipe = dev && strstr(dev, "llvmpipe");
    tolerance tol = llvmpipe ? (tolerance){0, EXACT_REL} : (tolerance){LOOSE_LEVELS, LOOSE_REL};
    if (!llvmpipe && !write_dir)
        print_message("NOTE: device \"%s\" is not llvmpipe and the golden files are llvmpipe's: comparing %s loosely "
                      "(RGBA8 within %d levels, floats within %g * max(1,|want|))\n",
                      dev ? dev : "?", gs->name, LOOSE_LEVELS, LOOSE_REL);
    if (write_dir && !llvmpipe)
        print_message("WARNING: writing golden files from \"%s\"; the test expects llvmpipe's\n", dev ? dev : "?");

    fv_scene *s = NULL;
    const char *src = gs->shared ? fv_test_data(gs->source) : gs->source;
    if (fv_scene_load(src, &s) != FV_OK) fail_msg("cannot load scene %s", src);
    fv_vec3 lo, hi;
    if (gs->closer > 0 && fv_scene_world_bounds(s, 0.0, &lo, &hi)) {
        fv_vec3 centre = fv_v3_scale(fv_v3_add(lo, hi), 0.5f), p = s->head.position_m;
        s->head.position_m = fv_v3_add(centre, fv_v3_scale(fv_v3(p.x - centre.x, p.y - centre.y, p.z - centre.z),
                                                           gs->closer));
    }
    assert_int_equal(fv_renderer_load_scene(g_r, s), FV_OK);

    size_t sbs_size = (size_t)2 * W * H * 4;
    uint8_t *sbs[2] = {malloc(sbs_size), malloc(sbs_size)};
    float *linear[2] = {malloc((size_t)W * H * 4 * sizeof(float)), malloc((size_t)W * H * 4 * sizeof(float))};
    float *motion[2] = {malloc((size_t)W * H * 2 * sizeof(float)), malloc((size_t)W * H * 2 * sizeof(float))};
    for (int i = 0; i < 2; i++) {
        assert_non_null(sbs[i]);
        assert_non_null(linear[i]);
        assert_non_null(motion[i]);
    }

    float *lin0[2] = {malloc((size_t)W * H * 4 * sizeof(float)), malloc((size_t)W * H * 4 * sizeof(float))};
    uint8_t *cpu = malloc(sbs_size);
    assert_non_null(lin0[0]);
    assert_non_null(lin0[1]);
    assert_non_null(cpu);
    fv_head h1 = moved_head(s);
    for (uint64_t id = 0; id < 2; id++) {
        fv_frame_input in;
        assert_int_equal(fv_renderer_frame_input(g_r, id ? &h1 : NULL, id, (double)id / 90.0, &in), FV_OK);
        /* The golden images are those of the renderer before shadows (e8eeb98): the same model with them off. */
        in.quality.shadow.enabled = false;
        /* ... and every pixel shaded: the golden images predate foveation (render/fovea), which is on by default. */
        in.quality.fovea.enabled = false;
        /* ... and direct light only: they predate one-bounce GI (render/gi, on by default; tests/gi checks it). */
        in.quality.gi.enabled = false;
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        assert_int_equal(fv_renderer_read_rgba8(g_r, true, 0, sbs[id], sbs_size), FV_OK);
        if (id == 0)
            for (int eye = 0; eye < 2; eye++)
                assert_int_equal(fv_renderer_read_linear(g_r, eye, lin0[eye], (size_t)W * H * 4), FV_OK);
    }
    for (int eye = 0; eye < 2; eye++) {
        assert_int_equal(fv_renderer_read_linear(g_r, eye, linear[eye], (size_t)W * H * 4), FV_OK);
        assert_int_equal(fv_renderer_read_motion(g_r, eye, motion[eye], (size_t)W * H * 2), FV_OK);
    }
    static const char *const sbs_name[2] = {"frame0_sbs.png", "frame1_sbs.png"};
    static const char *const lin_name[2] = {"frame1_linear_eye0.f32.gz", "frame1_linear_eye1.f32.gz"};
    static const char *const mot_name[2] = {"frame1_motion_eye0.f32.gz", "frame1_motion_eye1.f32.gz"};

    if (write_dir) {
        mkdir(write_dir, 0755);
        for (int i = 0; i < 2; i++) {
            encode_sbs(i == 0 ? lin0 : linear, false, cpu); /* the golden PNGs keep the old display mapping */
            write_png(golden_path(write_dir, gs->name, sbs_name[i]), cpu, 2 * W, H);
            write_floats(golden_path(write_dir, gs->name, lin_name[i]), linear[i], W, H, 4);
            write_floats(golden_path(write_dir, gs->name, mot_name[i]), motion[i], W, H, 2);
        }
        print_message("wrote %s golden files to %s (device \"%s\")\n", gs->name, write_dir, dev ? dev : "?");
    }
    /* Compare against the golden files (the ones just written, in write mode: a check of the files themselves). */
    const char *dir = write_dir ? write_dir : GOLDEN_DIR;
    tolerance enc = {tol.levels > 1 ? tol.levels : 1, tol.rel}; /* CPU vs GPU sRGB rounding */
    for (int i = 0; i < 2; i++) {
        char what[96];
        uint8_t *want = read_png(golden_path(dir, gs->name, sbs_name[i]), 2 * W, H);
        encode_sbs(i == 0 ? lin0 : linear, false, cpu);
        snprintf(what, sizeof what, "%s (linear colour, clamp + sRGB)", sbs_name[i]);
        compare_rgba8(gs->name, what, cpu, want, &enc);
        stbi_image_free(want);
        /* the display image: the same linear colour through the tone curve */
        encode_sbs(i == 0 ? lin0 : linear, true, cpu);
        snprintf(what, sizeof what, "frame %d display (tone curve + sRGB)", i);
        compare_rgba8(gs->name, what, sbs[i], cpu, &enc);
    }
    for (int eye = 0; eye < 2; eye++) {
        float *want = read_floats(golden_path(dir, gs->name, lin_name[eye]), W, H, 4);
        compare_floats(gs->name, "frame 1 linear colour", eye, linear[eye], want, 4, &tol);
        free(want);
        want = read_floats(golden_path(dir, gs->name, mot_name[eye]), W, H, 2);
        compare_floats(gs->name, "frame 1 motion", eye, motion[eye], want, 2, &tol);
        free(want);
    }
    /* a data view (the normal view) is not tone-mapped: its display is its [0,1] values, clamped, as before */
    {
        fv_frame_input in;
        assert_int_equal(fv_renderer_frame_input(g_r, &h1, 2, 2.0 / 90.0, &in), FV_OK);
        in.quality.shadow.enabled = false;
        in.quality.fovea.enabled = false;
        in.quality.gi.enabled = false;
        in.quality.debug_view = FV_DEBUG_VIEW_NORMAL;
        assert_int_equal(fv_renderer_draw(g_r, &in), FV_OK);
        assert_int_equal(fv_renderer_read_rgba8(g_r, true, 0, sbs[0], sbs_size), FV_OK);
        for (int eye = 0; eye < 2; eye++)
            assert_int_equal(fv_renderer_read_linear(g_r, eye, lin0[eye], (size_t)W * H * 4), FV_OK);
        encode_sbs(lin0, false, cpu);
        compare_rgba8(gs->name, "normal view display (clamp + sRGB, no tone curve)", sbs[0], cpu, &enc);
    }
    free(cpu);
    for (int i = 0; i < 2; i++) {
        free(lin0[i]);
        free(sbs[i]);
        free(linear[i]);
        free(motion[i]);
    }
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(g_r), 0);
}

static const golden_scene g_cornell = {"cornell", "cornell", false, 0};
static const golden_scene g_gltf = {"gltf_cornell_box", "scenes/cornell_box_gltf/cornellBox.gltf", true, 0.55f};
static const golden_scene g_obj = {"obj_teapot", "scenes/teapot/teapot_lwjgl.obj", true, 0.6f};
static const golden_scene g_ply = {"ply_bunny", "scenes/bunny/bun_zipper_res3.ply", true, 0.8f};

static void builtin_cornell_matches_golden_images(void **state)
{
    (void)state;
    check_scene(&g_cornell);
}

static void gltf_cornell_box_matches_golden_images(void **state)
{
    (void)state;
    check_scene(&g_gltf);
}

static void obj_teapot_matches_golden_images(void **state)
{
    (void)state;
    check_scene(&g_obj);
}

static void ply_bunny_matches_golden_images(void **state)
{
    (void)state;
    check_scene(&g_ply);
}

int main(void)
{
    /* A fresh renderer per scene, so that no scene's result depends on which ran before it. */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(builtin_cornell_matches_golden_images, setup, teardown),
        cmocka_unit_test_setup_teardown(gltf_cornell_box_matches_golden_images, setup, teardown),
        cmocka_unit_test_setup_teardown(obj_teapot_matches_golden_images, setup, teardown),
        cmocka_unit_test_setup_teardown(ply_bunny_matches_golden_images, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
