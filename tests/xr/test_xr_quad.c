/* @brief Quad views with gaze-driven insets (XR_VARJO_quad_views + XR_VARJO_foveated_rendering) on fovea's runtime:
 * our Vulkan2 app xr_quad_app (blue wide views, red insets, the same world pattern in both) runs headless through
 * the OpenXR loader with the core-validation layer, the Vulkan validation layer on its device and fovea's compositor
 * device (FOVEA_VALIDATION=1), the lens distortion off (FOVEA_XR_DISTORT=0: the composite is the display image in
 * tangent space), every composite written (FOVEA_XR_OUT_ALL=1). From each composited frame read back:
 *  - fixed: gaze: the red inset is centred on the fixed direction in both eyes;
 *  - sim: gaze: in every frame the inset is centred where the app was told it is (its located inset view), that is
 *    on the gaze predicted to the frame's display time, and it moves with the gaze across frames;
 *  - the blend band: from the inset's inside to the wide view the red share falls over several pixels, without a
 *    step (a hard edge would jump in one pixel);
 *  - no gaze source: supportsFoveatedRendering is false, the wide views are at the display's density (twice the
 *    foveated ones'), and the insets sit at the centre of the field of view;
 *  - an app that enables neither extension is offered stereo only.
 * Zero validation messages from either layer or the compositor's device. argv[1] = xr_quad_app, argv[2] = manifest. */
#include <fcntl.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stb/stb_image.h>

#include "fv_test.h"
#include "xr_test_child.h"

static const char *g_app, *g_manifest;

#define SCALE "0.2" /* the generic HMD's 1440 x 1453 per eye -> 288 x 291 */
#define MAX_FRAMES 64

typedef struct frame_row {
    int n, composited, tracked;
    double gx, gy;    /* the rendering gaze as tangents in VIEW (NaN when not located) */
    double inset[4];  /* the left inset's fov: left, right, up, down (rad) */
    double wide[2][4]; /* the wide views' fov (= the display eyes'), left and right */
} frame_row;

typedef struct run {
    char dir[1024];
    char *log;
    frame_row rows[MAX_FRAMES];
    int nrows;
} run;

/* Run the app; its output goes to dir/app.log; every composite to dir/frame_NNNNN.png. */
static int run_app(run *r, const char *name, const char *gaze, int frames, bool stereo_only)
{
    snprintf(r->dir, sizeof r->dir, "%s", fv_test_tmp(name));
    mkdir(r->dir, 0755);
    char log_path[1200], stats[1200], nf[32];
    snprintf(log_path, sizeof log_path, "%s/app.log", r->dir);
    snprintf(stats, sizeof stats, "%s/stats.json", r->dir);
    snprintf(nf, sizeof nf, "%d", frames);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        xr_test_child_env(log_path, g_manifest, true, SCALE, stats);
        setenv("FOVEA_XR_DISTORT", "0", 1);
        setenv("FOVEA_XR_OUT", r->dir, 1);
        setenv("FOVEA_XR_OUT_ALL", "1", 1);
        if (*gaze) setenv("FOVEA_XR_GAZE", gaze, 1);
        else unsetenv("FOVEA_XR_GAZE");
        unsetenv("FOVEA_XR_FRAMES");
        unsetenv("DISPLAY");
        if (stereo_only) execl(g_app, g_app, "--stereo-only", (char *)NULL);
        else execl(g_app, g_app, "--frames", nf, (char *)NULL);
        _exit(127);
    }
    int code = fv_test_wait(pid, fv_test_cmd_limit_s(), g_app); /* fails the case, naming the app, past the limit */
    r->log = fv_test_read_file(log_path, NULL);
    r->nrows = 0;
    for (const char *p = r->log; p && (p = strstr(p, "frame,")) != NULL; p++) {
        if (p != r->log && p[-1] != '\n') continue;
        frame_row *f = &r->rows[r->nrows];
        char gx[32], gy[32];
        if (sscanf(p, "frame,%d,composited,%d,tracked,%d,gaze_tx,%31[^,],gaze_ty,%31[^,],inset_left,%lf,%lf,%lf,%lf,"
                      "wide_left,%lf,%lf,%lf,%lf,wide_right,%lf,%lf,%lf,%lf",
                   &f->n, &f->composited, &f->tracked, gx, gy, &f->inset[0], &f->inset[1], &f->inset[2],
                   &f->inset[3], &f->wide[0][0], &f->wide[0][1], &f->wide[0][2], &f->wide[0][3], &f->wide[1][0],
                   &f->wide[1][1], &f->wide[1][2], &f->wide[1][3]) == 17 &&
            r->nrows < MAX_FRAMES) {
            f->gx = strtod(gx, NULL);
            f->gy = strtod(gy, NULL);
            r->nrows++;
        }
    }
    return code;
}

/* No validation message: the core-validation layer, the app's Vulkan layer, fovea's compositor device. */
static void assert_clean(const run *r)
{
    fv_assert_contains(r->log, "Core Validation output type");
    if (strstr(r->log, "VUID-") || strstr(r->log, "Validation Error") || strstr(r->log, "[Error") ||
        strstr(r->log, "[Warning") || strstr(r->log, "XR_ERROR") || strstr(r->log, "fovea: error") ||
        strstr(r->log, "Vulkan validation:"))
        fail_msg("validation or error output:\n%s", r->log);
    fv_assert_contains(r->log, "vk_validation_messages,0");
    char stats_path[1200];
    snprintf(stats_path, sizeof stats_path, "%s/stats.json", r->dir);
    char *stats = fv_test_read_file(stats_path, NULL);
    fv_assert_contains(stats, "\"validation_messages\": 0,");
    free(stats);
}

static double srgb_decode(unsigned char v)
{
    double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* The red share R / (R + B) of a composite pixel, in linear units (the pattern's brightness cancels). */
static double red_share(const unsigned char *px, int w, int x, int y)
{
    const unsigned char *p = px + 4 * ((size_t)y * (size_t)w + (size_t)x);
    double r = srgb_decode(p[0]), b = srgb_decode(p[2]);
    return r + b > 1e-6 ? r / (r + b) : 0.0;
}

typedef struct inset_seen {
    double cx, cy; /* centroid of the pixels more red than blue, px */
    int count;
} inset_seen;

static inset_seen find_inset(const unsigned char *px, int w, int h, int eye)
{
    int ew = w / 2;
    inset_seen s = {0, 0, 0};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < ew; x++)
            if (red_share(px, w, eye * ew + x, y) > 0.5) {
                s.cx += x + 0.5;
                s.cy += y + 0.5;
                s.count++;
            }
    if (s.count) {
        s.cx /= s.count;
        s.cy /= s.count;
    }
    return s;
}

/* A tangent direction as a pixel of the display eye (fov = the wide view's; y down). */
static void tan_to_px(const double wide[4], double tx, double ty, int ew, int h, double *out_x, double *out_y)
{
    double l = tan(wide[0]), r = tan(wide[1]), u = tan(wide[2]), d = tan(wide[3]);
    *out_x = (tx - l) / (r - l) * ew;
    *out_y = (u - ty) / (u - d) * h;
}

static unsigned char *load_composite(const run *r, int k, int *w, int *h)
{
    char png[1200];
    snprintf(png, sizeof png, "%s/frame_%05d.png", r->dir, k);
    int c = 0;
    unsigned char *px = stbi_load(png, w, h, &c, 4);
    if (!px) fail_msg("no composite %s", png);
    return px;
}

/* The blend band on the row through the inset's centre, going right: the red share falls from the inside (> 0.9)
 * to the wide view (< 0.1) over >= 3 pixels, never rising and never jumping by more than 0.45 between neighbours. */
static void check_band(const unsigned char *px, int w, int eye, const inset_seen *s)
{
    int ew = w / 2, y = (int)s->cy, x = (int)s->cx;
    while (x < ew - 1 && red_share(px, w, eye * ew + x, y) > 0.9) x++;
    int mid = 0;
    double prev = red_share(px, w, eye * ew + x - 1, y), max_step = 0;
    for (; x < ew; x++) {
        double v = red_share(px, w, eye * ew + x, y);
        assert_true(v <= prev + 0.02);
        max_step = fmax(max_step, prev - v);
        prev = v;
        if (v < 0.1) break;
        mid++;
    }
    print_message("  blend band (eye %d): %d px of intermediate red share, largest step %.2f\n", eye, mid, max_step);
    assert_true(mid >= 3);
    assert_true(max_step < 0.45);
}

static void fixed_gaze_insets_land_at_the_fixed_direction(void **state)
{
    (void)state;
    run r;
    int rc = run_app(&r, "quad_fixed", "fixed:yaw_deg=12,pitch_deg=6,rate_hz=250", 8, false);
    if (rc != 0) fail_msg("xr_quad_app exited %d:\n%s", rc, r.log);
    assert_clean(&r);
    fv_assert_contains(r.log, "view_configs,QUAD_VARJO,STEREO");
    fv_assert_contains(r.log, "supports_foveated_rendering,1");
    assert_int_equal(r.nrows, 8);
    /* the fixed direction (yaw right, pitch up; (0, 0) = -z) as tangents */
    double y = 12 * M_PI / 180, p = 6 * M_PI / 180;
    double tx = tan(y), ty = tan(p) / cos(y);
    int k = 0, checked = 0;
    for (int i = 0; i < r.nrows; i++) {
        const frame_row *f = &r.rows[i];
        if (!f->composited) continue;
        int w, h;
        unsigned char *px = load_composite(&r, k++, &w, &h);
        if (f->tracked) {
            /* the inset the runtime located is centred (in angle) on the fixed direction */
            double cx = 0.5 * (f->inset[0] + f->inset[1]), cy = 0.5 * (f->inset[2] + f->inset[3]);
            print_message("frame %d: the located inset's centre %.3f, %.3f deg, the fixed gaze %.3f, %.3f deg\n", f->n,
                          cx * 180 / M_PI, cy * 180 / M_PI, atan(tx) * 180 / M_PI, atan(ty) * 180 / M_PI);
            assert_true(fabs(cx - atan(tx)) < 0.05 * M_PI / 180 && fabs(cy - atan(ty)) < 0.05 * M_PI / 180);
            /* its radius from the MAR model: the generic HMD's centre pixel is 0.0832 deg, the wide views at half
             * density 0.1665 deg, resolved from e_w = (0.1665 - 1/48) / 0.022 = 6.62 deg; plus the uncertainty
             * (0.5..10 deg), over 1 - 1/4 for the blend band: 9.49..22.2 deg */
            double rx = 0.5 * (f->inset[1] - f->inset[0]) * 180 / M_PI;
            double ry = 0.5 * (f->inset[2] - f->inset[3]) * 180 / M_PI;
            print_message("frame %d: inset radius %.2f x %.2f deg\n", f->n, rx, ry);
            assert_true(fabs(rx - ry) < 1e-3 && rx > 9.45 && rx < 22.25);
            for (int eye = 0; eye < 2; eye++) {
                inset_seen s = find_inset(px, w, h, eye);
                /* ... and the composite shows it there: its centre in the display's tangent space */
                double ex, ey;
                tan_to_px(f->wide[eye], 0.5 * (tan(f->inset[0]) + tan(f->inset[1])),
                          0.5 * (tan(f->inset[2]) + tan(f->inset[3])), w / 2, h, &ex, &ey);
                print_message("frame %d eye %d: inset seen at (%.1f, %.1f) px over %d px, located at (%.1f, %.1f)\n",
                              f->n, eye, s.cx, s.cy, s.count, ex, ey);
                assert_true(s.count > 50);
                assert_true(fabs(s.cx - ex) < 1.5 && fabs(s.cy - ey) < 1.5);
                check_band(px, w, eye, &s);
            }
            checked++;
        }
        stbi_image_free(px);
    }
    assert_true(checked >= 5);
    free(r.log);
}

static void sim_gaze_insets_follow_the_predicted_gaze(void **state)
{
    (void)state;
    run r;
    /* smooth pursuits after every gaze shift, no blinks: the eye keeps moving */
    int rc = run_app(&r, "quad_sim",
                     "sim:seed=7,rate_hz=250,pursuit_prob=1,blink_per_min=0,dropout=0,eye_loss=0,precision_deg=0.02",
                     24, false);
    if (rc != 0) fail_msg("xr_quad_app exited %d:\n%s", rc, r.log);
    assert_clean(&r);
    int k = 0, checked = 0, on_gaze = 0;
    double x_min = 1e9, x_max = -1e9, y_min = 1e9, y_max = -1e9;
    for (int i = 0; i < r.nrows; i++) {
        const frame_row *f = &r.rows[i];
        if (!f->composited) continue;
        int w, h;
        unsigned char *px = load_composite(&r, k++, &w, &h);
        inset_seen s = find_inset(px, w, h, 0);
        /* where the runtime told the app its inset is (the inset view it rendered), and where the gaze is */
        double ix, iy;
        tan_to_px(f->wide[0], 0.5 * (tan(f->inset[0]) + tan(f->inset[1])), 0.5 * (tan(f->inset[2]) + tan(f->inset[3])),
                  w / 2, h, &ix, &iy);
        /* the located inset's centre (in angle) against the rendering gaze the app located just before, at the same
         * display time (a gaze sample arriving between the two calls may move the prediction a little) */
        double err_deg = hypot(0.5 * (f->inset[0] + f->inset[1]) - atan(f->gx),
                               0.5 * (f->inset[2] + f->inset[3]) - atan(f->gy)) * 180 / M_PI;
        print_message("frame %d: tracked %d, inset seen at (%.1f, %.1f) px, located at (%.1f, %.1f); %.2f deg from the "
                      "gaze\n", f->n, f->tracked, s.cx, s.cy, ix, iy, err_deg);
        assert_true(s.count > 50);
        assert_true(fabs(s.cx - ix) < 1.5 && fabs(s.cy - iy) < 1.5); /* the composite puts the inset where it is */
        /* the inset follows the gaze (up to where it is kept inside the wide view) */
        bool inside = f->inset[0] > f->wide[0][0] + 1e-3 && f->inset[1] < f->wide[0][1] - 1e-3 &&
                      f->inset[2] < f->wide[0][2] - 1e-3 && f->inset[3] > f->wide[0][3] + 1e-3;
        if (f->tracked && inside && isfinite(err_deg)) {
            checked++;
            on_gaze += err_deg < 0.5;
        }
        x_min = fmin(x_min, s.cx);
        x_max = fmax(x_max, s.cx);
        y_min = fmin(y_min, s.cy);
        y_max = fmax(y_max, s.cy);
        stbi_image_free(px);
    }
    double moved = hypot(x_max - x_min, y_max - y_min);
    print_message("sim: %d composites, %d with a tracked gaze, %d of them within 0.5 deg of it; the inset moved over "
                  "%.1f px\n", k, checked, on_gaze, moved);
    assert_true(checked >= 10);
    assert_true(on_gaze >= checked * 8 / 10);
    assert_true(moved > 5.0);
    free(r.log);
}

/* The view sizes the app was given (the log's `view,V,WxH`). */
static void view_size(const run *r, int v, int *w, int *h)
{
    char key[32];
    snprintf(key, sizeof key, "\nview,%d,", v);
    const char *p = strstr(r->log, key);
    if (!p || sscanf(p + strlen(key), "%dx%d", w, h) != 2) fail_msg("no view %d size in the log:\n%s", v, r->log);
}

static void no_gaze_source_centred_insets_full_density_wide_views(void **state)
{
    (void)state;
    run r;
    int rc = run_app(&r, "quad_no_gaze", "", 5, false);
    if (rc != 0) fail_msg("xr_quad_app exited %d:\n%s", rc, r.log);
    assert_clean(&r);
    fv_assert_contains(r.log, "supports_foveated_rendering,0");
    /* the wide views at the display's density (the foveated run's are at half of it), the insets as before */
    int ww, wh, iw, ih;
    view_size(&r, 0, &ww, &wh);
    view_size(&r, 2, &iw, &ih);
    print_message("no gaze: wide %dx%d, inset %dx%d\n", ww, wh, iw, ih);
    assert_int_equal(ww, 288);
    assert_int_equal(wh, 291);
    run f;
    rc = run_app(&f, "quad_fixed_sizes", "fixed:yaw_deg=0,pitch_deg=0", 1, false);
    if (rc != 0) fail_msg("xr_quad_app exited %d:\n%s", rc, f.log);
    int fw, fh, fiw, fih;
    view_size(&f, 0, &fw, &fh);
    view_size(&f, 2, &fiw, &fih);
    print_message("foveated: wide %dx%d, inset %dx%d\n", fw, fh, fiw, fih);
    assert_true(abs(2 * fw - ww) <= 1 && abs(2 * fh - wh) <= 1);
    assert_true(fiw == iw && fih == ih && iw > 16 && iw < ww / 2);
    free(f.log);
    /* the insets sit at the centre of the field of view, and the composite shows them there */
    int k = 0;
    for (int i = 0; i < r.nrows; i++) {
        const frame_row *fr = &r.rows[i];
        if (!fr->composited) continue;
        assert_false(fr->tracked);
        assert_true(fabs(fr->inset[0] + fr->inset[1]) < 1e-4 && fabs(fr->inset[2] + fr->inset[3]) < 1e-4);
        int w, h;
        unsigned char *px = load_composite(&r, k++, &w, &h);
        inset_seen s = find_inset(px, w, h, 0);
        double ex, ey;
        tan_to_px(fr->wide[0], 0.0, 0.0, w / 2, h, &ex, &ey);
        print_message("frame %d: inset seen at (%.1f, %.1f), the centre of the view at (%.1f, %.1f)\n", fr->n, s.cx,
                      s.cy, ex, ey);
        assert_true(fabs(s.cx - ex) < 1.5 && fabs(s.cy - ey) < 1.5);
        stbi_image_free(px);
    }
    assert_true(k >= 3);
    free(r.log);
}

static void without_the_extensions_an_app_sees_stereo_only(void **state)
{
    (void)state;
    run r;
    int rc = run_app(&r, "quad_stereo_only", "fixed:yaw_deg=0,pitch_deg=0", 1, true);
    if (rc != 0) fail_msg("xr_quad_app --stereo-only exited %d:\n%s", rc, r.log);
    fv_assert_contains(r.log, "view_configs,STEREO\n");
    fv_assert_contains(r.log, "quad_views_without_extension,refused");
    free(r.log);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: %s XR_QUAD_APP MANIFEST\n", argv[0]);
        return 2;
    }
    g_app = argv[1];
    g_manifest = argv[2];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fixed_gaze_insets_land_at_the_fixed_direction),
        cmocka_unit_test(sim_gaze_insets_follow_the_predicted_gaze),
        cmocka_unit_test(no_gaze_source_centred_insets_full_density_wide_views),
        cmocka_unit_test(without_the_extensions_an_app_sees_stereo_only),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
