/* @brief The distortion pass on a Vulkan device (validation on, any message fails) against a CPU evaluation of the
 * same lens model (fv_lens_panel_to_tan in double, bilinear in linear light as Vulkan filters): on a checkerboard,
 * the position every edge pixel samples is within 0.1 px of the CPU's in each colour channel, flat pixels agree,
 * pixels whose ray leaves the rendered image are black; zero coefficients reproduce the input. The pass runs alone:
 * the test writes the display image itself, records the pass from its table entry and reads the display back. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "distort.h"
#include "fv_hmd.h"
#include "fv_test.h"

#define W 128u
#define H 112u
#define CHECK 8u /* checker squares, px */

static fv_vk *g_vk;

static int setup(void **state)
{
    (void)state;
    fv_vk_desc d = {.validation = 1};
    if (fv_vk_create(&d, &g_vk) != FV_OK) {
        const char *ci = getenv("CI");
        return ci && strcmp(ci, "true") == 0 ? -1 : 0;
    }
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    if (!g_vk) return 0;
    uint32_t n = fv_vk_validation_messages(g_vk);
    fv_vk_destroy(&g_vk);
    return n ? -1 : 0;
}

static double srgb_decode(double c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }

/* The checkerboard of layer `eye`, channel c: 0 or 1 (eye 1 is offset by half a square so the eyes differ). */
static double board(uint32_t eye, int x, int y)
{
    int s = (int)CHECK, o = eye ? s / 2 : 0;
    return (((x + o) / s + y / s) & 1) ? 1.0 : 0.0;
}

/* Vulkan's bilinear filter with clamp-to-edge at uv over the W x H board (linear light). */
static double bilinear(uint32_t eye, double u, double v)
{
    double x = u * W - 0.5, y = v * H - 0.5;
    double x0 = floor(x), y0 = floor(y), fx = x - x0, fy = y - y0;
    double s = 0;
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
            int xi = (int)x0 + i, yi = (int)y0 + j;
            xi = xi < 0 ? 0 : xi >= (int)W ? (int)W - 1 : xi;
            yi = yi < 0 ? 0 : yi >= (int)H ? (int)H - 1 : yi;
            s += (i ? fx : 1 - fx) * (j ? fy : 1 - fy) * board(eye, xi, yi);
        }
    return s;
}

/* Run the pass once on the board with this lens and frustum; returns both layers' RGBA8 (caller frees). */
static uint8_t *run_pass(const fv_lens *lens, const fv_hmd_fov fov[2])
{
    fv_images images;
    assert_int_equal(fv_images_init(&images, g_vk, W, H), FV_OK);
    /* The test fills the display image by upload, which the renderer never does: the one usage it adds. */
    images.slot[FV_IMAGE_DISPLAY].usage |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    const fv_vk_image *display;
    assert_int_equal(fv_images_get(&images, FV_IMAGE_DISPLAY, &display), FV_OK);
    uint8_t *px = malloc((size_t)W * H * 4);
    for (uint32_t e = 0; e < 2; e++) {
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                uint8_t b = board(e, (int)x, (int)y) ? 255 : 0;
                uint8_t *q = px + 4 * ((size_t)y * W + x);
                q[0] = q[1] = q[2] = b;
                q[3] = 255;
            }
        assert_int_equal(fv_vk_upload_image(g_vk, &images.slot[FV_IMAGE_DISPLAY].img, e, px, (size_t)W * H * 4,
                                            VK_IMAGE_LAYOUT_GENERAL),
                         FV_OK);
    }
    /* The upload waited for the GPU; the table only needs to know the layout it left. */
    images.slot[FV_IMAGE_DISPLAY].layout = VK_IMAGE_LAYOUT_GENERAL;
    images.slot[FV_IMAGE_DISPLAY].visible = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;

    fv_frame_input in;
    memset(&in, 0, sizeof in);
    in.quality = fv_quality_default();
    in.quality.fovea.enabled = false; /* full resolution (foveation has its own tests) */
    in.quality.distort.lens = *lens;
    for (int e = 0; e < 2; e++) {
        /* as fv_eye_views_build_fov writes them: signed, left and down negative */
        in.eye[e].tan_left = -fov[e].tan_left;
        in.eye[e].tan_right = fov[e].tan_right;
        in.eye[e].tan_up = fov[e].tan_up;
        in.eye[e].tan_down = -fov[e].tan_down;
    }
    fv_plan_context ctx = {.quality = &in.quality};
    fv_plan_entry entry;
    memset(&entry, 0, sizeof entry);
    fv_distort_pass.plan(&ctx, &entry);
    assert_true(entry.enabled);
    fv_pass_env env = {.vk = g_vk, .images = &images, .width = W, .height = H, .slots = 1, .plan = &entry};
    void *state = NULL;
    assert_int_equal(fv_distort_pass.init(&env, &state), FV_OK);
    VkCommandBuffer cmd;
    assert_int_equal(fv_vk_oneshot_begin(g_vk, "test distort", &cmd), FV_OK);
    fv_pass_counters counters;
    memset(&counters, 0, sizeof counters);
    fv_pass_frame f = {.cmd = cmd, .slot = 0, .input = &in, .images = &images, .counters = &counters};
    fv_distort_pass.record(state, &f);
    assert_int_equal(fv_vk_oneshot_end(g_vk, cmd), FV_OK);
    assert_int_equal(counters.dispatches, 1);
    uint8_t *out = malloc((size_t)W * H * 4 * 2);
    for (uint32_t e = 0; e < 2; e++)
        assert_int_equal(fv_images_read(&images, FV_IMAGE_DISPLAY, e, out + (size_t)e * W * H * 4,
                                        (size_t)W * H * 4, 0, (size_t)W * 4),
                         FV_OK);
    fv_distort_pass.fini(state);
    fv_images_fini(&images);
    free(px);
    return out;
}

static void checkerboard_matches_the_cpu_model_within_0p1_px(void **state)
{
    (void)state;
    if (!g_vk) skip();
    const char *profiles[] = {"generic", "oculus-rift-dk2"};
    for (int pi = 0; pi < 2; pi++) {
        fv_hmd_profile p;
        char err[256];
        assert_int_equal(fv_hmd_profile_load(profiles[pi], &p, err, sizeof err), FV_OK);
        uint8_t *out = run_pass(&p.lens, p.fov);
        double worst_px = 0, worst_flat = 0;
        uint64_t edges = 0, outside = 0, bad_black = 0;
        for (uint32_t e = 0; e < 2; e++)
            for (uint32_t y = 0; y < H; y++)
                for (uint32_t x = 0; x < W; x++)
                    for (int c = 0; c < 3; c++) {
                        double gpu = srgb_decode(out[(((size_t)e * H + y) * W + x) * 4 + (size_t)c] / 255.0);
                        double tx, ty;
                        fv_lens_panel_to_tan(&p.lens, (int)e, c, (x + 0.5) / W, (y + 0.5) / H, &tx, &ty);
                        const fv_hmd_fov *f = &p.fov[e];
                        double u = (tx + f->tan_left) / ((double)f->tan_left + f->tan_right);
                        double v = (f->tan_up - ty) / ((double)f->tan_up + f->tan_down);
                        double qx = (x + 0.5) / W * p.lens.viewport_m[0] - p.lens.centre_m[e][0];
                        double qy = (y + 0.5) / H * p.lens.viewport_m[1] - p.lens.centre_m[e][1];
                        bool beyond = p.lens.visible_r > 0 && sqrt(qx * qx + qy * qy) / p.lens.warp_m > p.lens.visible_r;
                        /* a sample within 1e-4 of the image's edge may land on either side in float */
                        double m = fmin(fmin(u, 1 - u), fmin(v, 1 - v));
                        if (fabs(m) < 1e-4) continue;
                        if (beyond || m < 0) {
                            outside++;
                            bad_black += gpu != 0.0;
                            continue;
                        }
                        double cpu = bilinear(e, u, v);
                        double h = 1e-3; /* gradient per source px */
                        double gx = (bilinear(e, u + h / W, v) - bilinear(e, u - h / W, v)) / (2 * h);
                        double gy = (bilinear(e, u, v + h / H) - bilinear(e, u, v - h / H)) / (2 * h);
                        double g = sqrt(gx * gx + gy * gy);
                        if (g >= 0.5) {
                            edges++;
                            worst_px = fmax(worst_px, fabs(gpu - cpu) / g);
                        } else {
                            worst_flat = fmax(worst_flat, fabs(gpu - cpu));
                        }
                    }
        print_message("%s: %llu edge samples, worst position error %.4f px; worst flat difference %.4f; %llu black "
                      "outside\n", profiles[pi], (unsigned long long)edges, worst_px, worst_flat,
                      (unsigned long long)outside);
        assert_true(edges > 1000);
        if (worst_px > 0.1) fail_msg("%s: an edge sample is %.4f px from the CPU model's", profiles[pi], worst_px);
        /* flat: bilinear weights of 8-bit precision and the 8-bit sRGB output step */
        if (worst_flat > 0.02) fail_msg("%s: a flat sample differs by %.4f", profiles[pi], worst_flat);
        assert_int_equal(bad_black, 0);
        if (pi == 0) assert_true(outside > 0); /* generic shows black past its visible radius */
        free(out);
    }
}

static void zero_coefficients_reproduce_the_input(void **state)
{
    (void)state;
    if (!g_vk) skip();
    fv_hmd_profile p;
    char err[256];
    assert_int_equal(fv_hmd_profile_load("htc-vive", &p, err, sizeof err), FV_OK);
    p.lens.k[0] = 1;
    p.lens.k[1] = p.lens.k[2] = p.lens.k[3] = 0;
    p.lens.aberration[0] = p.lens.aberration[1] = p.lens.aberration[2] = 1;
    uint8_t *out = run_pass(&p.lens, p.fov);
    uint32_t differ = 0;
    for (uint32_t e = 0; e < 2; e++)
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                uint8_t want = board(e, (int)x, (int)y) ? 255 : 0;
                const uint8_t *q = out + (((size_t)e * H + y) * W + x) * 4;
                for (int c = 0; c < 3; c++) differ += abs((int)q[c] - (int)want) > 1;
            }
    free(out);
    if (differ) fail_msg("%u samples differ from the input", differ);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(checkerboard_matches_the_cpu_model_within_0p1_px),
        cmocka_unit_test(zero_coefficients_reproduce_the_input),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
