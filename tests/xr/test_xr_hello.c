/* @brief Debian's hello_xr (libopenxr-utils) on fovea's OpenXR runtime, headless: found by the OpenXR loader through
 * the generated manifest (XR_RUNTIME_JSON), with the OpenXR core-validation layer and the Vulkan validation layer
 * (hello_xr enables it; fovea's compositor device with FOVEA_VALIDATION=1), for FOVEA_XR_FRAMES frames through the
 * whole session life cycle, the runtime ending the session. hello_xr quits at the end of stdin: stdin stays open
 * until the runtime has destroyed the session, then it is closed. Asserts: exit status 0, no validation message
 * (either layer, or the compositor's counter), the frame counts, the state sequence, and the composited stereo frame
 * read back (lens circles, hello_xr's clear colour inside them, its cubes, black outside, both eyes drawn).
 * argv[1] = hello_xr, argv[2] = the runtime manifest. */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <stb/stb_image.h>

#include "fv_test.h"

static const char *g_hello_xr, *g_manifest;

#define FRAMES 24
#define SCALE "0.1" /* the generic HMD's 1440 x 1453 per eye -> 144 x 145 */
#define EYE_W 144
#define EYE_H 145
#define RUN_TIMEOUT_S 150

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static bool exists(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0;
}

/* Run hello_xr with `graphics`; returns its exit status; the log, stats and PNG land in dir. */
static int run_hello(const char *graphics, const char *dir, char *log_path, size_t log_size)
{
    char stats[1200], cmd_env[64];
    snprintf(stats, sizeof stats, "%s/stats.json", dir);
    snprintf(log_path, log_size, "%s/hello_xr.log", dir);
    unlink(stats);
    int in[2];
    assert_int_equal(pipe(in), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        dup2(in[0], 0);
        close(in[1]);
        int fd = open(log_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd < 0) _exit(126);
        dup2(fd, 1);
        dup2(fd, 2);
        setenv("XR_RUNTIME_JSON", g_manifest, 1);
        setenv("XR_ENABLE_API_LAYERS", "XR_APILAYER_LUNARG_core_validation", 1);
        setenv("FOVEA_VALIDATION", "1", 1);
        setenv("FOVEA_XR_SCALE", SCALE, 1);
        snprintf(cmd_env, sizeof cmd_env, "%d", FRAMES);
        setenv("FOVEA_XR_FRAMES", cmd_env, 1);
        setenv("FOVEA_XR_STATS", stats, 1);
        setenv("FOVEA_XR_OUT", dir, 1);
        unsetenv("FOVEA_XR_GAZE");
        unsetenv("DISPLAY"); /* headless */
        execl(g_hello_xr, g_hello_xr, "-g", graphics, "-v", (char *)NULL);
        _exit(127);
    }
    close(in[0]);
    /* stdin stays open while the session runs; the runtime writes the statistics when the session is destroyed */
    double t0 = now_s();
    int status = 0;
    pid_t done = 0;
    while (!exists(stats) && now_s() - t0 < RUN_TIMEOUT_S) {
        done = waitpid(pid, &status, WNOHANG);
        if (done == pid) break;
        usleep(50000);
    }
    close(in[1]); /* end of stdin: hello_xr quits */
    if (done != pid) {
        while (now_s() - t0 < RUN_TIMEOUT_S + 30 && (done = waitpid(pid, &status, WNOHANG)) == 0) usleep(50000);
        if (done == 0) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            fail_msg("hello_xr -g %s did not finish in %d s (log: %s)", graphics, RUN_TIMEOUT_S, log_path);
        }
    }
    if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
    return WEXITSTATUS(status);
}

/* A number from the runtime's statistics JSON ("key": value). */
static double stat_num(const char *json, const char *key)
{
    char k[128];
    snprintf(k, sizeof k, "\"%s\": ", key);
    const char *p = strstr(json, k);
    if (!p) fail_msg("statistics lack %s:\n%s", key, json);
    return strtod(p + strlen(k), NULL);
}

/* Lines of the log that a validation layer (OpenXR core validation, Khronos Vulkan validation) or hello_xr's
 * error log wrote. */
static int validation_lines(const char *log, char *first, size_t first_size)
{
    int n = 0;
    first[0] = 0;
    const char *p = log;
    while (*p) {
        const char *e = strchr(p, '\n');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        char line[1024];
        snprintf(line, sizeof line, "%.*s", (int)(len < sizeof line - 1 ? len : sizeof line - 1), p);
        if (strstr(line, "VUID-") || strstr(line, "Validation Error") || strstr(line, "[Error") ||
            strstr(line, "[Warning") || strstr(line, "XR_ERROR") || strstr(line, "fovea: error")) {
            if (!n) snprintf(first, first_size, "%s", line);
            n++;
        }
        p = e ? e + 1 : p + len;
    }
    return n;
}

static void check_frame(const char *dir)
{
    char png[1200];
    snprintf(png, sizeof png, "%s/frame_%05d.png", dir, FRAMES - 2); /* frames 0..FRAMES-2 were composited */
    int w = 0, h = 0, c = 0;
    unsigned char *px = stbi_load(png, &w, &h, &c, 4);
    if (!px) fail_msg("no composited frame %s", png);
    assert_int_equal(w, 2 * EYE_W);
    assert_int_equal(h, EYE_H);
    int clear = 0, black = 0, other = 0, eye_clear[2] = {0, 0};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const unsigned char *p = px + 4 * ((size_t)y * (size_t)w + (size_t)x);
            /* hello_xr clears to DarkSlateGray (0.184, 0.310, 0.310) in linear units: sRGB-encoded 118, 150, 150 */
            if (abs(p[0] - 118) <= 6 && abs(p[1] - 150) <= 6 && abs(p[2] - 150) <= 6) {
                clear++;
                eye_clear[x >= EYE_W]++;
            } else if (p[0] < 4 && p[1] < 4 && p[2] < 4) {
                black++;
            } else {
                other++;
            }
        }
    /* the lens shows a disc per eye: most pixels are the clear colour, the corners beyond the lens are black, and
     * hello_xr's cubes are neither */
    double n = (double)w * h;
    print_message("frame: clear %.1f%%, black %.1f%%, other %.1f%% (left %d, right %d clear)\n", 100 * clear / n,
                  100 * black / n, 100 * other / n, eye_clear[0], eye_clear[1]);
    assert_true(clear > 0.5 * n);
    assert_true(black > 0.05 * n);
    assert_true(other > 0.002 * n);
    assert_true(eye_clear[0] > 0.25 * n && eye_clear[1] > 0.25 * n);
    /* black corners: outside each lens circle */
    const unsigned char *corner = px;
    assert_true(corner[0] < 4 && corner[1] < 4 && corner[2] < 4);
    stbi_image_free(px);
}

static void hello(const char *graphics)
{
    char dir[1024], log_path[1200], first[1024];
    snprintf(dir, sizeof dir, "%s", fv_test_tmp(graphics));
    mkdir(dir, 0755);
    double t0 = now_s();
    int rc = run_hello(graphics, dir, log_path, sizeof log_path);
    char *log = fv_test_read_file(log_path, NULL);
    print_message("hello_xr -g %s: exit %d in %.1f s\n", graphics, rc, now_s() - t0);
    if (rc != 0) fail_msg("hello_xr -g %s exited %d; log:\n%s", graphics, rc, log);
    int bad = validation_lines(log, first, sizeof first);
    if (bad) fail_msg("%d validation/error lines; the first: %s", bad, first);
    /* the layers really ran: the core-validation layer announces itself, hello_xr names its Vulkan layer */
    fv_assert_contains(log, "Core Validation output type");
    fv_assert_contains(log, "Inserted device layer \"VK_LAYER_KHRONOS_validation\"");
    char stats_path[1200];
    snprintf(stats_path, sizeof stats_path, "%s/stats.json", dir);
    char *stats = fv_test_read_file(stats_path, NULL);
    assert_int_equal((int)stat_num(stats, "frames_ended"), FRAMES);
    assert_int_equal((int)stat_num(stats, "frames_waited"), FRAMES);
    assert_int_equal((int)stat_num(stats, "frames_composited"), FRAMES - 1); /* frame 0 is not visible yet */
    assert_int_equal((int)stat_num(stats, "frames_discarded"), 0);
    assert_int_equal((int)stat_num(stats, "validation_messages"), 0);
    fv_assert_contains(stats, "\"states\": \"IDLE READY SYNCHRONIZED VISIBLE FOCUSED VISIBLE SYNCHRONIZED STOPPING "
                              "IDLE EXITING\"");
    /* hello_xr saw the same sequence */
    fv_assert_contains(log, "XR_SESSION_STATE_STOPPING->XR_SESSION_STATE_IDLE");
    fv_assert_contains(log, "XR_SESSION_STATE_IDLE->XR_SESSION_STATE_EXITING");
    check_frame(dir);
    free(stats);
    free(log);
}

static void hello_xr_vulkan2_headless_validation_clean(void **state)
{
    (void)state;
    hello("Vulkan2");
}

static void hello_xr_vulkan_headless_validation_clean(void **state)
{
    (void)state;
    hello("Vulkan");
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: %s HELLO_XR MANIFEST\n", argv[0]);
        return 2;
    }
    g_hello_xr = argv[1];
    g_manifest = argv[2];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hello_xr_vulkan2_headless_validation_clean),
        cmocka_unit_test(hello_xr_vulkan_headless_validation_clean),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
