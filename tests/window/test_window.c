/* @brief The window presenter as a user meets it, under a virtual X server the test starts itself (Xvfb on a free
 * free display number, killed at the end): a window run shows the Cornell box (red left wall,
 * green right wall in each eye of a screenshot of the window), survives a resize in the middle of the run, ends on
 * Esc with exit 0 and the summary, with zero validation messages; the mouse moves the gaze (xdotool mousemove to two
 * points: the overlay's gaze dot follows the cursor); a gaze run reports gaze-to-photon latency from the swapchain
 * clock; and the clear errors (no display, the mouse without a window). Skips, saying why, only when Xvfb, xdotool or
 * ImageMagick's import is not installed, or Xvfb does not start. Without a window manager Xvfb cannot minimise a
 * window, so the zero-size wait is not exercised here. argv[1]: the fovea binary. FV_WINDOW_SCREENSHOT=PATH keeps the mouse test's
 * screenshot there (the README's docs/img/window.png). */
#include <cjson/cJSON.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <X11/Xlib.h>
#include <stb_image.h>

#include "fv_test.h"

static const char *g_fovea;
static pid_t g_xvfb = -1;
static pid_t g_child = -1; /* the fovea run in flight: killed when a test failed before it exited */
static int g_display = -1;
static char g_skip[256];

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec / 1e9;
}

static void sleep_s(double s)
{
    struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
    }
}

static bool on_path(const char *prog)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", prog);
    return system(cmd) == 0;
}

/* Start Xvfb on a free display number (tried from a per-process start, skipping those whose lock or socket exists;
 * another server taking the same number at once makes ours exit, and the next number is tried), wait until its
 * socket exists. */
static int start_xvfb(void **state)
{
    (void)state;
    const char *need[] = {"Xvfb", "xdotool", "import"};
    for (size_t i = 0; i < 3; i++)
        if (!on_path(need[i])) {
            snprintf(g_skip, sizeof g_skip, "%s is not installed (Debian: xvfb xdotool imagemagick; "
                     "tools/install-deps.sh)", need[i]);
            return 0;
        }
    for (int attempt = 0; attempt < 40; attempt++) {
        int n = 100 + (int)(((unsigned)getpid() * 7u + (unsigned)attempt * 37u) % 800u);
        char lock[64], sock[64];
        snprintf(lock, sizeof lock, "/tmp/.X%d-lock", n);
        snprintf(sock, sizeof sock, "/tmp/.X11-unix/X%d", n);
        if (access(lock, F_OK) == 0 || access(sock, F_OK) == 0) continue;
        pid_t pid = fork();
        if (pid == 0) {
            char disp[16];
            snprintf(disp, sizeof disp, ":%d", n);
            int devnull = open("/dev/null", O_WRONLY);
            if (devnull >= 0) {
                dup2(devnull, 1);
                dup2(devnull, 2);
            }
            execlp("Xvfb", "Xvfb", disp, "-screen", "0", "1280x800x24", "-nolisten", "tcp", "-noreset", (char *)NULL);
            _exit(127);
        }
        if (pid < 0) break;
        double t0 = now_s();
        bool up = false, died = false;
        while (!up && !died && now_s() - t0 < 15.0) {
            int st;
            died = waitpid(pid, &st, WNOHANG) == pid;
            up = !died && access(sock, F_OK) == 0;
            if (!up && !died) sleep_s(0.05);
        }
        if (up) {
            g_xvfb = pid;
            g_display = n;
            return 0;
        }
        if (!died) {
            kill(pid, SIGTERM);
            waitpid(pid, NULL, 0);
        }
    }
    snprintf(g_skip, sizeof g_skip, "Xvfb did not start on any of 40 display numbers");
    return 0;
}

static void kill_child(void)
{
    if (g_child > 0) {
        kill(-g_child, SIGKILL); /* its process group (fv_test_spawn) */
        waitpid(g_child, NULL, 0);
    }
    g_child = -1;
}

static int stop_xvfb(void **state)
{
    (void)state;
    kill_child();
    if (g_xvfb > 0) {
        kill(g_xvfb, SIGTERM);
        int st;
        waitpid(g_xvfb, &st, 0);
    }
    g_xvfb = -1;
    return 0;
}

#define NEED_XVFB()                                                                                                    \
    do {                                                                                                               \
        if (g_display < 0) {                                                                                           \
            print_message("skipped: %s\n", g_skip);                                                                    \
            skip();                                                                                                    \
        }                                                                                                              \
    } while (0)

/* Run a shell command with DISPLAY set, at most 30 s (past it the test fails naming it); its first line of output
 * into out (may be NULL). Returns the exit code. */
static int xsh(char *out, size_t out_size, const char *fmt, ...) FV_PRINTF(3, 4);
static int xsh(char *out, size_t out_size, const char *fmt, ...)
{
    char cmd[1024], path[512];
    int n = snprintf(cmd, sizeof cmd, "DISPLAY=:%d ", g_display);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd + n, sizeof cmd - (size_t)n, fmt, ap);
    va_end(ap);
    snprintf(path, sizeof path, "%s", fv_test_tmp("xsh.out"));
    const char *argv[] = {"/bin/sh", "-c", cmd, NULL};
    int rc = fv_test_wait(fv_test_spawn(argv, path, "/dev/null"), 30.0, cmd);
    char line[512] = "";
    FILE *f = fopen(path, "r");
    if (f) {
        if (!fgets(line, sizeof line, f)) line[0] = '\0';
        fclose(f);
    }
    line[strcspn(line, "\n")] = '\0';
    if (out) snprintf(out, out_size, "%s", line);
    return rc;
}

/* fovea in the background with DISPLAY and validation on, stdout/stderr to files, in its own process group. */
static pid_t spawn_fovea(const char *args, const char *out_path, const char *err_path)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "exec env DISPLAY=:%d FOVEA_VALIDATION=1 %s run %s", g_display, g_fovea, args);
    kill_child(); /* one left by a failed test */
    const char *argv[] = {"/bin/sh", "-c", cmd, NULL};
    g_child = fv_test_spawn(argv, out_path, err_path);
    return g_child;
}

/* Wait for a child at most `seconds`; its exit code, or -1 after killing its process group on timeout. */
static int wait_child(pid_t pid, double seconds)
{
    double t0 = now_s();
    for (;;) {
        int st;
        pid_t r = waitpid(pid, &st, WNOHANG);
        if (r == pid) {
            if (pid == g_child) g_child = -1;
            return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
        }
        if (now_s() - t0 > seconds) {
            kill(-pid, SIGKILL);
            waitpid(pid, &st, 0);
            if (pid == g_child) g_child = -1;
            return -1;
        }
        sleep_s(0.05);
    }
}

/* Wait for fovea to exit (at most `seconds`); fail with its stderr unless it exited 0. */
static void expect_exit_0(pid_t pid, const char *err_path, double seconds)
{
    int rc = wait_child(pid, seconds);
    if (rc != 0) {
        char *e = fv_test_read_file(err_path, NULL);
        fail_msg("fovea exited %d; stderr:\n%s", rc, e);
    }
}

/* The id of fovea's window, once it is mapped (at most 60 s: lavapipe starts slowly under load). */
static unsigned long wait_window(pid_t pid)
{
    char line[128];
    double t0 = now_s();
    while (now_s() - t0 < 60.0) {
        if (xsh(line, sizeof line, "xdotool search --onlyvisible --name '^fovea' 2>/dev/null") == 0 && line[0])
            return strtoul(line, NULL, 10);
        int st;
        if (waitpid(pid, &st, WNOHANG) == pid) {
            g_child = -1;
            fail_msg("fovea exited before its window appeared");
        }
        sleep_s(0.1);
    }
    fail_msg("no fovea window within 60 s");
    return 0;
}

/* The window's title until it reports frames (the title is set every half second once frames are drawn). */
static void wait_frames(unsigned long win, double seconds)
{
    char title[256];
    double t0 = now_s();
    while (now_s() - t0 < seconds) {
        if (xsh(title, sizeof title, "xdotool getwindowname %lu", win) == 0 && strstr(title, "fps")) return;
        sleep_s(0.1);
    }
    fail_msg("the window's title never reported a frame rate (last: '%s')", title);
}

typedef struct shot {
    int w, h;
    unsigned char *px;
} shot;

static shot screenshot(unsigned long win, const char *name)
{
    const char *png = fv_test_tmp(name);
    char cmd_out[128];
    int rc = xsh(cmd_out, sizeof cmd_out, "import -window %lu %s 2>&1", win, png);
    assert_int_equal(rc, 0);
    shot s = {0};
    int c = 0;
    s.px = stbi_load(png, &s.w, &s.h, &c, 3);
    if (!s.px) fail_msg("cannot read the screenshot %s", png);
    return s;
}

static const unsigned char *at(const shot *s, int x, int y) { return s->px + ((size_t)y * s->w + x) * 3; }

/* Mean colour over a box of the screenshot. */
static void mean_rgb(const shot *s, int x0, int y0, int x1, int y1, double out[3])
{
    double sum[3] = {0, 0, 0};
    int n = 0;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++, n++)
            for (int c = 0; c < 3; c++) sum[c] += at(s, x, y)[c];
    for (int c = 0; c < 3; c++) out[c] = n ? sum[c] / n : 0;
}

/* Each eye's image (both side by side, centred at the eye aspect, eye_w:eye_h) shows the red left wall and the
 * green right wall: the mean over a strip at 15-22% and at 80-87% of the image's width (middle rows; outside the
 * box is black) is dominated by that colour (1.3 times and 25 levels above either other channel: the walls'
 * shading varies with the lighting). */
static bool cornell_ok(const shot *s, int eye_w, int eye_h, char *why, size_t why_size)
{
    double sc = fmin(s->w / (2.0 * eye_w), (double)s->h / eye_h);
    int dw = (int)floor(eye_w * sc), dh = (int)floor(eye_h * sc);
    int x0 = (s->w - 2 * dw) / 2, y0 = (s->h - dh) / 2;
    for (int e = 0; e < 2; e++) {
        int ex = x0 + e * dw;
        double red[3], green[3];
        mean_rgb(s, ex + dw * 15 / 100, y0 + dh * 40 / 100, ex + dw * 22 / 100, y0 + dh * 60 / 100, red);
        mean_rgb(s, ex + dw * 80 / 100, y0 + dh * 40 / 100, ex + dw * 87 / 100, y0 + dh * 60 / 100, green);
        double red_rest = fmax(red[1], red[2]), green_rest = fmax(green[0], green[2]);
        if (!(red[0] > 1.3 * red_rest && red[0] - red_rest > 25)) {
            snprintf(why, why_size, "eye %d: left wall is not red: mean rgb %.0f %.0f %.0f", e, red[0], red[1], red[2]);
            return false;
        }
        if (!(green[1] > 1.3 * green_rest && green[1] - green_rest > 25)) {
            snprintf(why, why_size, "eye %d: right wall is not green: mean rgb %.0f %.0f %.0f", e, green[0], green[1],
                     green[2]);
            return false;
        }
    }
    return true;
}

/* Screenshots until the window shows the Cornell box at its current size (a loaded machine may take seconds for the
 * first frame after a resize), at most `seconds`; returns the last one's size. */
static void expect_cornell(unsigned long win, const char *name, int eye_w, int eye_h, double seconds, int *out_w,
                           int *out_h)
{
    char why[160] = "no screenshot";
    double t0 = now_s();
    for (;;) {
        shot s = screenshot(win, name);
        bool ok = cornell_ok(&s, eye_w, eye_h, why, sizeof why);
        *out_w = s.w;
        *out_h = s.h;
        stbi_image_free(s.px);
        if (ok) return;
        if (now_s() - t0 > seconds) fail_msg("%s: %s", name, why);
        sleep_s(0.5);
    }
}

static cJSON *read_json(const char *path)
{
    char *text = fv_test_read_file(path, NULL);
    cJSON *j = cJSON_Parse(text);
    if (!j) fail_msg("not JSON: %s", text);
    free(text);
    return j;
}

static double num(const cJSON *j, const char *a, const char *b)
{
    const cJSON *o = cJSON_GetObjectItemCaseSensitive(j, a);
    if (b) o = cJSON_GetObjectItemCaseSensitive(o, b);
    if (!cJSON_IsNumber(o)) fail_msg("JSON has no number %s%s%s", a, b ? "." : "", b ? b : "");
    return o->valuedouble;
}

/* What a window manager's close button sends: a WM_DELETE_WINDOW client message. */
static void close_like_a_window_manager(unsigned long win)
{
    char name[32];
    snprintf(name, sizeof name, ":%d", g_display);
    Display *dpy = XOpenDisplay(name);
    assert_non_null(dpy);
    XEvent ev;
    memset(&ev, 0, sizeof ev);
    ev.xclient.type = ClientMessage;
    ev.xclient.window = (Window)win;
    ev.xclient.message_type = XInternAtom(dpy, "WM_PROTOCOLS", False);
    ev.xclient.format = 32;
    ev.xclient.data.l[0] = (long)XInternAtom(dpy, "WM_DELETE_WINDOW", False);
    ev.xclient.data.l[1] = CurrentTime;
    assert_int_not_equal(XSendEvent(dpy, (Window)win, False, NoEventMask, &ev), 0);
    XFlush(dpy);
    XCloseDisplay(dpy);
}

/* Wait until the window's title contains `want`. */
static void wait_title(unsigned long win, const char *want, double seconds)
{
    char title[256] = "";
    double t0 = now_s();
    while (now_s() - t0 < seconds) {
        if (xsh(title, sizeof title, "xdotool getwindowname %lu", win) == 0 && strstr(title, want)) return;
        sleep_s(0.1);
    }
    fail_msg("the window's title never said '%s' (last: '%s')", want, title);
}

static void press_escape(unsigned long win)
{
    assert_int_equal(xsh(NULL, 0, "xdotool windowfocus %lu sleep 0.2 key Escape", win), 0);
}

static void window_run_shows_the_cornell_box_survives_a_resize_and_closes_on_esc(void **state)
{
    (void)state;
    NEED_XVFB();
    char out[512], err[512]; /* fv_test_tmp's buffers rotate: keep copies */
    snprintf(out, sizeof out, "%s", fv_test_tmp("run1.json"));
    snprintf(err, sizeof err, "%s", fv_test_tmp("run1.err"));
    pid_t pid = spawn_fovea("--present window --eye-size 128x128 --window 512x256 --hmd none --json", out, err);
    /* --hmd none: undistorted, so the walls are where cornell_ok looks (the mouse test keeps the lens) */
    unsigned long win = wait_window(pid);
    wait_frames(win, 60.0);
    int w = 0, h = 0;
    expect_cornell(win, "before_resize.png", 128, 128, 30.0, &w, &h); /* takes screenshots until it shows the box */
    assert_int_equal(w, 512);
    assert_int_equal(h, 256);
    /* resize in the middle of the run: a new swapchain, the eyes re-laid out at their aspect */
    assert_int_equal(xsh(NULL, 0, "xdotool windowsize --sync %lu 360 300", win), 0);
    expect_cornell(win, "after_resize.png", 128, 128, 30.0, &w, &h);
    assert_int_equal(w, 360);
    assert_int_equal(h, 300);
    press_escape(win);
    expect_exit_0(pid, err, 60.0);
    cJSON *j = read_json(out);
    assert_int_equal((int)num(j, "validation_messages", NULL), 0);
    assert_true(num(j, "frames", NULL) >= 2);
    assert_true(num(j, "present", "presents") >= 2);
    assert_true(num(j, "present", "swapchains") >= 2); /* the resize made a new one */
    assert_int_equal((int)num(j, "present", "width"), 360);
    assert_true(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(j, "present"),
                                                                "closed_by_user")));
    cJSON_Delete(j);
}

static int cmp_int(const void *a, const void *b) { return *(const int *)a - *(const int *)b; }

/* The yellow gaze dot of the overlay in the window, over [x0, x1): the centroid of the overlay's yellow (255, 230,
 * 26) within 6 px of the median of all such pixels (chromatic aberration fringes of bright edges can be yellowish
 * too: the median ignores them). False when there is none. */
static bool find_dot(const shot *s, int x0, int x1, double *out_x, double *out_y)
{
    int cap = 4096, n = 0;
    int *xs = malloc(sizeof(int) * (size_t)cap), *ys = malloc(sizeof(int) * (size_t)cap);
    assert_true(xs && ys);
    for (int y = 0; y < s->h; y++)
        for (int x = x0; x < x1 && n < cap; x++) {
            const unsigned char *p = at(s, x, y);
            if (p[0] > 235 && p[1] > 208 && p[1] < 250 && p[2] < 70) {
                xs[n] = x;
                ys[n] = y;
                n++;
            }
        }
    bool found = false;
    if (n >= 3) {
        int *sx = malloc(sizeof(int) * (size_t)n), *sy = malloc(sizeof(int) * (size_t)n);
        assert_true(sx && sy);
        memcpy(sx, xs, sizeof(int) * (size_t)n);
        memcpy(sy, ys, sizeof(int) * (size_t)n);
        qsort(sx, (size_t)n, sizeof(int), cmp_int);
        qsort(sy, (size_t)n, sizeof(int), cmp_int);
        int mx = sx[n / 2], my = sy[n / 2];
        double cx = 0, cy = 0;
        int m = 0;
        for (int k = 0; k < n; k++)
            if (abs(xs[k] - mx) <= 6 && abs(ys[k] - my) <= 6) {
                cx += xs[k];
                cy += ys[k];
                m++;
            }
        if (m >= 3) {
            *out_x = cx / m;
            *out_y = cy / m;
            found = true;
        }
        free(sx);
        free(sy);
    }
    free(xs);
    free(ys);
    return found;
}

static void keys_change_the_frame_and_the_close_button_ends_the_run(void **state)
{
    (void)state;
    NEED_XVFB();
    char out[512], err[512]; /* fv_test_tmp's buffers rotate: keep copies */
    snprintf(out, sizeof out, "%s", fv_test_tmp("keys.json"));
    snprintf(err, sizeof err, "%s", fv_test_tmp("keys.err"));
    pid_t pid = spawn_fovea("--present window --eye-size 64x64 --json", out, err);
    unsigned long win = wait_window(pid);
    wait_frames(win, 60.0);
    shot before = screenshot(win, "keys_color_view.png");
    double c0[3], c1[3];
    mean_rgb(&before, 0, 0, before.w, before.h, c0);
    stbi_image_free(before.px);
    /* V: the next view (normal), shown in the title and on screen; H: shadows off (the title says keys changed it) */
    assert_int_equal(xsh(NULL, 0, "xdotool windowfocus %lu sleep 0.2 key V sleep 0.2 key H", win), 0);
    wait_title(win, "view normal", 30.0);
    wait_title(win, "keys changed it", 30.0);
    /* the frames after the key show the normal view (a loaded machine may take a few seconds per frame) */
    double diff = 0.0, t0 = now_s();
    for (bool first = true; diff < 30.0 && now_s() - t0 < 30.0; first = false) {
        if (!first) sleep_s(0.5); /* the next screenshot, if this one still showed the colour view */
        shot after = screenshot(win, "keys_normal_view.png");
        mean_rgb(&after, 0, 0, after.w, after.h, c1);
        stbi_image_free(after.px);
        diff = fabs(c1[0] - c0[0]) + fabs(c1[1] - c0[1]) + fabs(c1[2] - c0[2]);
    }
    if (diff < 30.0)
        fail_msg("the normal view looks like the colour view: mean rgb %.0f %.0f %.0f vs %.0f %.0f %.0f", c1[0], c1[1],
                 c1[2], c0[0], c0[1], c0[2]);
    close_like_a_window_manager(win);
    expect_exit_0(pid, err, 60.0);
    cJSON *j = read_json(out);
    assert_int_equal((int)num(j, "validation_messages", NULL), 0);
    assert_true(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(j, "present"),
                                                                "closed_by_user")));
    cJSON_Delete(j);
}

static void the_mouse_moves_the_gaze_and_the_overlay_follows(void **state)
{
    (void)state;
    NEED_XVFB();
    char out[512], err[512]; /* fv_test_tmp's buffers rotate: keep copies */
    snprintf(out, sizeof out, "%s", fv_test_tmp("mouse.json"));
    snprintf(err, sizeof err, "%s", fv_test_tmp("mouse.err"));
    /* 400x200: both 200x200 eyes at 1x; foveation on so that the foveal boundary is drawn too */
    pid_t pid = spawn_fovea("--present window --eye-size 200x200 --window 400x200 --gaze mouse:vergence_m=1.5 "
                            "--overlay --set fovea.enabled=on --json", out, err);
    unsigned long win = wait_window(pid);
    wait_frames(win, 60.0);
    const int pts[2][2] = {{60, 70}, {140, 140}}; /* window px, both in the left eye's image (x < 200) */
    double dots[2][2];
    for (int k = 0; k < 2; k++) {
        assert_int_equal(xsh(NULL, 0, "xdotool mousemove --window %lu %d %d", win, pts[k][0], pts[k][1]), 0);
        /* the gaze pipeline filters (1€) and predicts: wait until the dot settles on the cursor */
        bool ok = false;
        double t0 = now_s();
        while (!ok && now_s() - t0 < 30.0) {
            sleep_s(0.5);
            char name[32];
            snprintf(name, sizeof name, "mouse_%d.png", k);
            shot s = screenshot(win, name);
            double x, y;
            ok = find_dot(&s, 0, s.w / 2, &x, &y) && fabs(x - pts[k][0]) <= 4.0 && fabs(y - pts[k][1]) <= 4.0;
            if (ok) {
                dots[k][0] = x;
                dots[k][1] = y;
                /* the right eye sees the same point: its dot is in the right image, at about the same height */
                double rx, ry;
                assert_true(find_dot(&s, s.w / 2, s.w, &rx, &ry));
                assert_true(fabs(ry - y) <= 4.0);
                const char *keep = getenv("FV_WINDOW_SCREENSHOT");
                if (keep && *keep && k == 1) {
                    char cmd[1024];
                    snprintf(cmd, sizeof cmd, "cp %s %s", fv_test_tmp(name), keep);
                    (void)system(cmd);
                }
            }
            stbi_image_free(s.px);
        }
        if (!ok) fail_msg("the gaze dot did not reach the cursor at (%d, %d) within 30 s", pts[k][0], pts[k][1]);
    }
    assert_true(dots[1][0] - dots[0][0] > 60 && dots[1][1] - dots[0][1] > 50);
    press_escape(win);
    expect_exit_0(pid, err, 60.0);
    cJSON *j = read_json(out);
    assert_int_equal((int)num(j, "validation_messages", NULL), 0);
    assert_true(num(j, "latency", "frames_with_gaze") > 0);
    cJSON_Delete(j);
}

static void a_gaze_run_reports_latency_from_the_swapchain_clock(void **state)
{
    (void)state;
    NEED_XVFB();
    char out[512], err[512]; /* fv_test_tmp's buffers rotate: keep copies */
    snprintf(out, sizeof out, "%s", fv_test_tmp("latency.json"));
    snprintf(err, sizeof err, "%s", fv_test_tmp("latency.err"));
    pid_t pid = spawn_fovea("--present window --gaze sim:seed=1 --frames 40 --eye-size 64x64 --quality fast --json",
                            out, err);
    expect_exit_0(pid, err, 120.0);
    cJSON *j = read_json(out);
    assert_int_equal((int)num(j, "frames", NULL), 40);
    assert_int_equal((int)num(j, "validation_messages", NULL), 0);
    const cJSON *lat = cJSON_GetObjectItemCaseSensitive(j, "latency");
    const cJSON *clock = cJSON_GetObjectItemCaseSensitive(lat, "clock");
    assert_true(cJSON_IsString(clock));
    fv_assert_contains(clock->valuestring, "swapchain");
    double p50 = num(j, "latency", "gaze_to_photon_ms_p50");
    assert_true(isfinite(p50) && p50 > 0.0 && p50 < 2000.0);
    assert_true(num(j, "latency", "frames_with_gaze") > 0);
    const cJSON *pc = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(j, "present"), "clock");
    assert_true(cJSON_IsString(pc));
    cJSON_Delete(j);
}

/* Ctrl-C in a window run: once frames are drawn, and in the first second after the window appears (start-up). */
static void ctrl_c_ends_a_window_run_with_its_summary(void **state)
{
    (void)state;
    NEED_XVFB();
    char out[512], err[512];
    snprintf(out, sizeof out, "%s", fv_test_tmp("ctrl_c_window.out"));
    snprintf(err, sizeof err, "%s", fv_test_tmp("ctrl_c_window.err"));
    for (int k = 0; k < 2; k++) {
        pid_t pid = spawn_fovea("--present window --frames 1000000 --eye-size 64x64 --quality fast", out, err);
        unsigned long win = wait_window(pid);
        if (k == 0) wait_frames(win, 60.0);
        else sleep_s((double)(getpid() % 1000) / 1000.0);
        kill(pid, SIGINT);
        int rc = wait_child(pid, 60.0);
        char *o = fv_test_read_file(out, NULL), *e = fv_test_read_file(err, NULL);
        if (rc != 130 || !strstr(o, "fovea run: scene") || !strstr(e, "interrupted (Ctrl-C) after"))
            fail_msg("window run %d: Ctrl-C gave exit %d (want 130 and the summary)\nstdout:\n%s\nstderr:\n%s", k, rc,
                     o, e);
        free(o);
        free(e);
    }
}

static void without_a_window_the_errors_say_why(void **state)
{
    (void)state;
    fv_test_cmd *r = calloc(1, sizeof *r);
    assert_non_null(r);
    fv_test_run_cmd(r, "env -u DISPLAY -u WAYLAND_DISPLAY", g_fovea, "run --present window --frames 1 --eye-size 16x16");
    assert_int_not_equal(r->exit_code, 0);
    fv_assert_contains(r->err, "no display");
    fv_test_run_cmd(r, "env -u DISPLAY -u WAYLAND_DISPLAY", g_fovea, "run --gaze mouse: --frames 1 --eye-size 16x16");
    assert_int_not_equal(r->exit_code, 0);
    fv_assert_contains(r->err, "--present window");
    /* auto without a display: headless, and it runs */
    fv_test_run_cmd(r, "env -u DISPLAY -u WAYLAND_DISPLAY", g_fovea, "run --present auto --frames 1 --eye-size 16x16");
    assert_int_equal(r->exit_code, 0);
    fv_test_run_cmd(r, NULL, g_fovea, "run --present-mode mailbox --frames 1");
    assert_int_not_equal(r->exit_code, 0);
    fv_assert_contains(r->err, "need --present window");
    fv_test_run_cmd(r, NULL, g_fovea, "run --present window --out /tmp --frames 1");
    assert_int_not_equal(r->exit_code, 0);
    fv_test_run_cmd(r, NULL, g_fovea, "run --gaze mouse:vergence_m=0 --frames 1");
    assert_int_not_equal(r->exit_code, 0);
    fv_assert_contains(r->err, "vergence_m");
    free(r);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_window FOVEA\n");
        return 2;
    }
    g_fovea = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ctrl_c_ends_a_window_run_with_its_summary),
        cmocka_unit_test(without_a_window_the_errors_say_why),
        cmocka_unit_test(window_run_shows_the_cornell_box_survives_a_resize_and_closes_on_esc),
        cmocka_unit_test(keys_change_the_frame_and_the_close_button_ends_the_run),
        cmocka_unit_test(the_mouse_moves_the_gaze_and_the_overlay_follows),
        cmocka_unit_test(a_gaze_run_reports_latency_from_the_swapchain_clock),
    };
    return cmocka_run_group_tests(tests, start_xvfb, stop_xvfb);
}
