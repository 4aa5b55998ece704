/* @brief The gaze lands where the eye looks, whatever the head does (issue 23): scene file -> gaze driver -> frame
 * loop -> renderer -> image. A fixed gaze in the head frame (yaw 10, pitch 5) with the scene's head turned in yaw,
 * pitched, rolled, and moved by a recorded head pose: the frame log's eye-space gaze is the head-frame gaze in both
 * eyes, and the `gaze` debug view's peak sits on the pixel the CPU projects that direction to (within 1 px), in
 * both eyes. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>

#include "fovea/fv_frame_input.h"
#include "fv_test.h"

static const char *g_fovea;

#define EYE_W 64
#define EYE_H 64
#define YAW 10.0
#define PITCH 5.0

static fv_vec3 dir_deg(double yaw, double pitch)
{
    double y = yaw * FV_PI / 180.0, p = pitch * FV_PI / 180.0;
    return fv_v3((float)(cos(p) * sin(y)), (float)sin(p), (float)(-cos(p) * cos(y)));
}

/* Where an eye-space direction pierces the eye's image (pixel units, x right, y down, pixel centres at +0.5), in
 * double, from the frustum fovea draws an eye with (fv_eye_views_build at this size; the head pose plays no part). */
static void cpu_pixel(int eye, fv_vec3 d, double *px, double *py)
{
    fv_eye_view v[2];
    fv_eye_views_build(NULL, 0.05f, 100.0f, EYE_W, EYE_H, v);
    double xt = d.x / -d.z, yt = d.y / -d.z;
    *px = (xt - v[eye].tan_left) / ((double)v[eye].tan_right - v[eye].tan_left) * EYE_W;
    *py = (v[eye].tan_up - yt) / ((double)v[eye].tan_up - v[eye].tan_down) * EYE_H;
}

/* The red peak of one eye of a side-by-side gaze view: the red-weighted centroid of the pixels within 10% of the
 * brightest red (sub-pixel), in pixel units as cpu_pixel. */
static void red_peak(const unsigned char *px, int w, int h, int x0, double *cx, double *cy)
{
    int best = 0;
    for (int y = 0; y < h; y++)
        for (int x = x0; x < x0 + w / 2; x++)
            if (px[((size_t)y * w + x) * 3] > best) best = px[((size_t)y * w + x) * 3];
    double sx = 0, sy = 0, sw = 0;
    for (int y = 0; y < h; y++)
        for (int x = x0; x < x0 + w / 2; x++) {
            int r = px[((size_t)y * w + x) * 3];
            if (r < best * 0.9) continue;
            sx += r * (x - x0 + 0.5);
            sy += r * (y + 0.5);
            sw += r;
        }
    if (best < 64 || sw <= 0) fail_msg("no red peak in the gaze view (brightest red %d)", best);
    *cx = sx / sw;
    *cy = sy / sw;
}

/* Column `name` of every data row of a frame log, as numbers; returns the count. */
static int log_column(const char *text, const char *name, double *out, int cap)
{
    const char *nl = strchr(text, '\n');
    if (!nl) fail_msg("frame log has no header");
    int col = -1, k = 0;
    for (const char *p = text; p < nl; k++) {
        size_t n = strcspn(p, ",\n");
        if (n == strlen(name) && !strncmp(p, name, n)) col = k;
        p += n + (p[n] == ',' ? 1 : 0);
        if (p[-1] != ',') break;
    }
    if (col < 0) fail_msg("frame log has no column %s", name);
    int rows = 0;
    for (const char *line = nl + 1; *line && rows < cap; rows++) {
        const char *p = line;
        for (int c = 0; c < col; c++) p += strcspn(p, ",\n") + 1;
        out[rows] = strtod(p, NULL);
        line += strcspn(line, "\n");
        if (*line) line++;
    }
    return rows;
}

/* Run the gaze view with a fixed gaze; check the frame log and the image. */
static void check_run(const char *what, const char *scene_json, const char *gaze_uri, const char *extra)
{
    char scene[1024], dir[1024], log[1024], args[4096];
    snprintf(scene, sizeof scene, "%s", fv_test_write_file("seam.scene.json", scene_json, strlen(scene_json)));
    snprintf(dir, sizeof dir, "%s", fv_test_tmp("seam_out"));
    snprintf(log, sizeof log, "%s", fv_test_tmp("seam_frames.csv"));
    snprintf(args, sizeof args,
             "run --scene '%s' --gaze '%s' --frames 4 --eye-size %dx%d --view gaze --hmd none --out '%s' "
             "--frame-log '%s' %s",
             scene, gaze_uri, EYE_W, EYE_H, dir, log, extra ? extra : "");
    static fv_test_cmd r;
    fv_test_run_cmd(&r, "FOVEA_VALIDATION=1", g_fovea, args);
    if (r.exit_code != 0) fail_msg("%s: fovea %s exited %d:\n%s", what, args, r.exit_code, r.err);
    char *text = fv_test_read_file(log, NULL);
    static const char *const cols[4] = {"left_gaze_yaw_deg", "left_gaze_pitch_deg", "right_gaze_yaw_deg",
                                        "right_gaze_pitch_deg"};
    for (int c = 0; c < 4; c++) {
        double v[16];
        int n = log_column(text, cols[c], v, 16);
        assert_int_equal(n, 4);
        for (int i = 0; i < n; i++)
            if (fabs(v[i] - (c % 2 == 0 ? YAW : PITCH)) > 0.01)
                fail_msg("%s: frame %d: %s = %.4f, want %.1f (the gaze turned with the head)", what, i, cols[c], v[i],
                         c % 2 == 0 ? YAW : PITCH);
    }
    free(text);
    char png[1100];
    snprintf(png, sizeof png, "%s/frame_00003.png", dir);
    int w = 0, h = 0, ch = 0;
    unsigned char *px = stbi_load(png, &w, &h, &ch, 3);
    if (!px) fail_msg("%s: cannot read %s", what, png);
    assert_int_equal(w, 2 * EYE_W);
    assert_int_equal(h, EYE_H);
    for (int e = 0; e < 2; e++) {
        double gx, gy, ex, ey;
        red_peak(px, w, h, e * EYE_W, &gx, &gy);
        cpu_pixel(e, dir_deg(YAW, PITCH), &ex, &ey);
        print_message("%s: eye %d: peak (%.2f, %.2f), CPU (%.2f, %.2f)\n", what, e, gx, gy, ex, ey);
        if (fabs(gx - ex) > 1.0 || fabs(gy - ey) > 1.0)
            fail_msg("%s: eye %d: the gaze view's peak (%.2f, %.2f) is not within 1 px of (%.2f, %.2f)", what, e, gx,
                     gy, ex, ey);
    }
    stbi_image_free(px);
}

#define FIXED "fixed:yaw_deg=10,pitch_deg=5"

static void a_turned_head_does_not_turn_the_gaze(void **state)
{
    (void)state;
    check_run("yaw 30",
              "{\"head\": {\"position_m\": [0, 0.27, 1.1], \"look_at_m\": [-0.635, 0.27, 0]},"
              " \"objects\": [{\"model\": \"builtin:cornell\"}]}",
              FIXED, NULL);
}

static void a_pitched_head_does_not_pitch_the_gaze(void **state)
{
    (void)state;
    check_run("pitch -25",
              "{\"head\": {\"position_m\": [0, 0.4, 1.1], \"look_at_m\": [0, -0.11, 0]},"
              " \"objects\": [{\"model\": \"builtin:cornell\"}]}",
              FIXED, NULL);
}

static void a_rolled_head_does_not_roll_the_gaze(void **state)
{
    (void)state;
    check_run("roll 35, yaw -20",
              "{\"head\": {\"position_m\": [0, 0.27, 1.1], \"look_at_m\": [0.4, 0.27, 0], \"roll_deg\": 35},"
              " \"objects\": [{\"model\": \"builtin:cornell\"}]}",
              FIXED, NULL);
}

/* A recording whose eyes hold yaw 10 / pitch 5 in the head while its head turns 0 -> 60 degrees in yaw: the
 * scene's head (itself turned) follows the recording (--head trace), the gaze stays put in the eyes. */
static void a_head_moved_by_a_recording_does_not_move_the_gaze(void **state)
{
    (void)state;
    char *trace = malloc(1 << 20);
    size_t n = (size_t)snprintf(trace, 1 << 20,
                                "fovea-trace 1\n# rate_hz: 120\n"
                                "t_device_ns,flags,seq,l_flags,l_dir_x,l_dir_y,l_dir_z,r_flags,r_dir_x,r_dir_y,"
                                "r_dir_z,c_flags,c_dir_x,c_dir_y,c_dir_z,head_x_mm,head_y_mm,head_z_mm,head_dir_x,"
                                "head_dir_y,head_dir_z\n");
    fv_vec3 g = dir_deg(YAW, PITCH);
    for (int i = 0; i < 1200; i++) { /* 10 s at 120 Hz */
        double head_yaw = 60.0 * i / 1200.0 * FV_PI / 180.0;
        n += (size_t)snprintf(trace + n, (1 << 20) - n,
                              "%lld,2,%d,2,%.9f,%.9f,%.9f,2,%.9f,%.9f,%.9f,2,%.9f,%.9f,%.9f,0,0,0,%.9f,0,%.9f\n",
                              (long long)i * 8333333LL, i, g.x, g.y, g.z, g.x, g.y, g.z, g.x, g.y, g.z,
                              sin(head_yaw), -cos(head_yaw));
    }
    const char *path = fv_test_write_file("seam_head.trace", trace, n);
    free(trace);
    char uri[1200];
    snprintf(uri, sizeof uri, "trace:%s?speed=4", path);
    check_run("recorded head from a turned scene head",
              "{\"head\": {\"position_m\": [0, 0.27, 1.1], \"look_at_m\": [0.3, 0.5, 0]},"
              " \"objects\": [{\"model\": \"builtin:cornell\"}]}",
              uri, "--head trace");
    /* and the head did move: the frame log's forward turned */
    char *text = fv_test_read_file(fv_test_tmp("seam_frames.csv"), NULL);
    double fx[16];
    int rows = log_column(text, "head_fwd_x", fx, 16);
    assert_int_equal(rows, 4);
    if (!(fabs(fx[rows - 1] - fx[0]) > 0.02)) fail_msg("the recorded head did not move the scene's head");
    free(text);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s PATH_TO_FOVEA\n", argv[0]);
        return 2;
    }
    g_fovea = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_turned_head_does_not_turn_the_gaze),
        cmocka_unit_test(a_pitched_head_does_not_pitch_the_gaze),
        cmocka_unit_test(a_rolled_head_does_not_roll_the_gaze),
        cmocka_unit_test(a_head_moved_by_a_recording_does_not_move_the_gaze),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
