/* @brief `fovea run` and friends as a new user meets them (issue 12): the head follows a recording's head pose, the
 * per-frame log and its statistics, unknown scenes, options without effect, forced multiview, files that
 * hold no gaze, the same tracker latency in run and latency, what "wall per frame" is, the example scenes, and
 * `fovea devices` listing a Pupil Capture that answers. Each test fails if its rough edge comes back. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <stb_image.h>

#include "fake_capture.h"
#include "fake_export.h"
#include "fv_clock.h"
#include "fovea_config.h"
#include "fv_test.h"

static const char *g_fovea;

static fv_test_cmd *run(const char *env, const char *args)
{
    static fv_test_cmd res;
    fv_test_run_cmd(&res, env, g_fovea, args);
    return &res;
}

static cJSON *json_of(const fv_test_cmd *r, const char *what)
{
    cJSON *j = cJSON_Parse(r->out);
    if (!j) fail_msg("%s: stdout is not JSON (exit %d):\n%s\nstderr:\n%s", what, r->exit_code, r->out, r->err);
    return j;
}

static double num_at(const cJSON *j, const char *a, const char *b, const char *c)
{
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(j, a);
    if (b) x = cJSON_GetObjectItemCaseSensitive(x, b);
    if (c) x = cJSON_GetObjectItemCaseSensitive(x, c);
    if (!cJSON_IsNumber(x)) fail_msg("no number at %s.%s.%s", a, b ? b : "", c ? c : "");
    return x->valuedouble;
}

/* ---- a CSV with a header, read by column name ---- */

typedef struct csv {
    char *text;
    char **cells; /* rows x cols */
    int cols, rows;
    char *names[128];
} csv;

static void csv_load(csv *c, const char *path, bool skip_comments)
{
    memset(c, 0, sizeof *c);
    c->text = fv_test_read_file(path, NULL);
    int cap = 1 << 16;
    c->cells = calloc((size_t)cap * 64, sizeof *c->cells);
    char *save = NULL;
    bool header = true;
    for (char *line = strtok_r(c->text, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        if (skip_comments && (line[0] == '#' || strncmp(line, "fovea-trace", 11) == 0)) continue;
        char *f[128];
        int n = 0;
        for (char *p = line;; p++) {
            f[n++] = p;
            p = strchr(p, ',');
            if (!p || n == 128) break;
            *p = '\0';
        }
        if (header) {
            c->cols = n;
            memcpy(c->names, f, sizeof(char *) * (size_t)n);
            header = false;
            if (n > 64) fail_msg("%s: %d columns", path, n);
            continue;
        }
        if (n != c->cols) fail_msg("%s: row %d has %d fields, the header %d", path, c->rows + 2, n, c->cols);
        if (c->rows >= cap) break;
        memcpy(&c->cells[(size_t)c->rows * 64], f, sizeof(char *) * (size_t)n);
        c->rows++;
    }
}

static int csv_col(const csv *c, const char *name)
{
    for (int i = 0; i < c->cols; i++)
        if (strcmp(c->names[i], name) == 0) return i;
    fail_msg("no column '%s'", name);
    return -1;
}

static const char *cell(const csv *c, int row, const char *name) { return c->cells[(size_t)row * 64 + csv_col(c, name)]; }
static double cellf(const csv *c, int row, const char *name) { return strtod(cell(c, row, name), NULL); }

static void csv_free(csv *c)
{
    free(c->text);
    free(c->cells);
}

static double angle_between(const double a[3], const double b[3])
{
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double c = d / (la * lb);
    return acos(c > 1 ? 1 : c < -1 ? -1 : c);
}

/* ---- head pose from a recording ---- */

/* `fovea run --gaze trace:<SRanipal> --save every --out DIR`: the cameras move as the recording's head does. The
 * frame log says which recorded sample moved each frame's head; between frame 0 and frame N the camera turns by the
 * angle between the recorded head directions of those samples and moves by the distance between their positions. */
static void head_follows_the_recorded_head_pose(void **state)
{
    (void)state;
    char rec[1024], conv[1024], dir[1024], log[1024], args[4096];
    snprintf(rec, sizeof rec, "%s", fv_test_data("gaze/htc_vive_pro_eye_sranipal/TESTNA01_2D_Fist3.csv"));
    snprintf(conv, sizeof conv, "%s", fv_test_tmp("sranipal.fovea.csv"));
    snprintf(dir, sizeof dir, "%s", fv_test_tmp("head"));
    snprintf(log, sizeof log, "%s", fv_test_tmp("head_frames.csv"));
    snprintf(args, sizeof args, "trace convert '%s' '%s'", rec, conv);
    fv_test_cmd *r = run(NULL, args);
    if (r->exit_code != 0) fail_msg("convert: %s", r->err);
    snprintf(args, sizeof args, "run --gaze 'trace:%s?speed=2' --frames 40 --eye-size 48x48 --save every --out '%s' "
             "--frame-log '%s'", rec, dir, log);
    r = run("FOVEA_VALIDATION=1", args);
    if (r->exit_code != 0) fail_msg("run: exit %d\n%s", r->exit_code, r->err);

    csv t, f;
    csv_load(&t, conv, true);
    csv_load(&f, log, false);
    assert_int_equal(f.rows, 40);
    /* the recorded pose by sample sequence number */
    int moved = 0, checked = 0, ref_row = -1;
    double ref_fwd[3], ref_pos[3], ref_rec_dir[3], ref_rec_pos[3];
    for (int i = 0; i < f.rows; i++) {
        assert_string_equal(cell(&f, i, "head_source"), "trace");
        const char *seq_s = cell(&f, i, "head_sample_seq");
        if (!seq_s[0]) continue;
        long long seq = atoll(seq_s);
        int k = -1;
        for (int j = 0; j < t.rows && k < 0; j++)
            if (atoll(cell(&t, j, "seq")) == seq) k = j;
        if (k < 0) fail_msg("frame %d: head sample %lld is not in the recording", i, seq);
        double fwd[3] = {cellf(&f, i, "head_fwd_x"), cellf(&f, i, "head_fwd_y"), cellf(&f, i, "head_fwd_z")};
        double pos[3] = {cellf(&f, i, "head_x_m"), cellf(&f, i, "head_y_m"), cellf(&f, i, "head_z_m")};
        double rdir[3] = {cellf(&t, k, "head_dir_x"), cellf(&t, k, "head_dir_y"), cellf(&t, k, "head_dir_z")};
        double rpos[3] = {cellf(&t, k, "head_x_mm"), cellf(&t, k, "head_y_mm"), cellf(&t, k, "head_z_mm")};
        if (ref_row < 0) {
            ref_row = i;
            memcpy(ref_fwd, fwd, sizeof fwd);
            memcpy(ref_pos, pos, sizeof pos);
            memcpy(ref_rec_dir, rdir, sizeof rdir);
            memcpy(ref_rec_pos, rpos, sizeof rpos);
            continue;
        }
        double cam_turn = angle_between(ref_fwd, fwd), rec_turn = angle_between(ref_rec_dir, rdir);
        double cam_move = sqrt(pow(pos[0] - ref_pos[0], 2) + pow(pos[1] - ref_pos[1], 2) + pow(pos[2] - ref_pos[2], 2));
        double rec_move = 1e-3 * sqrt(pow(rpos[0] - ref_rec_pos[0], 2) + pow(rpos[1] - ref_rec_pos[1], 2) +
                                      pow(rpos[2] - ref_rec_pos[2], 2));
        if (fabs(cam_turn - rec_turn) > 2e-3)
            fail_msg("frame %d: the camera turned %.4f rad, the recorded head %.4f rad", i, cam_turn, rec_turn);
        if (fabs(cam_move - rec_move) > 1e-4)
            fail_msg("frame %d: the camera moved %.5f m, the recorded head %.5f m", i, cam_move, rec_move);
        checked++;
        if (cam_turn > 0.5 * 3.14159265 / 180.0) moved++;
    }
    assert_true(ref_row >= 0 && ref_row < 10); /* the first frames follow the tracker as soon as it delivers */
    assert_true(checked >= 20); /* most frames carried a recorded head pose */
    assert_true(moved >= 5);    /* and the head did move (the recording turns by ~10 degrees in its first seconds) */
    /* the images show it: the last frame is not the first one */
    char p0[1200], p1[1200];
    snprintf(p0, sizeof p0, "%s/frame_00000.png", dir);
    snprintf(p1, sizeof p1, "%s/frame_00039.png", dir);
    int w, h, c, w1, h1;
    unsigned char *a = stbi_load(p0, &w, &h, &c, 3), *b = stbi_load(p1, &w1, &h1, &c, 3);
    assert_non_null(a);
    assert_non_null(b);
    assert_true(w == w1 && h == h1);
    long diff = 0;
    for (long i = 0; i < (long)w * h * 3; i++) diff += abs((int)a[i] - (int)b[i]);
    assert_true(diff > (long)w * h); /* > 1 level per pixel on average */
    stbi_image_free(a);
    stbi_image_free(b);
    csv_free(&t);
    csv_free(&f);

    /* --head scene: the recording's head pose is ignored */
    snprintf(args, sizeof args, "run --gaze 'trace:%s?speed=2' --frames 20 --eye-size 16x16 --head scene --frame-log '%s'",
             rec, log);
    r = run(NULL, args);
    if (r->exit_code != 0) fail_msg("run --head scene: exit %d\n%s", r->exit_code, r->err);
    csv_load(&f, log, false);
    for (int i = 1; i < f.rows; i++) {
        assert_string_equal(cell(&f, i, "head_sample_seq"), "");
        assert_true(cellf(&f, i, "head_fwd_x") == cellf(&f, 0, "head_fwd_x"));
    }
    csv_free(&f);
}

/* ---- the per-frame log ---- */

static void frame_log_has_every_frame_and_latency_reads_it(void **state)
{
    (void)state;
    char log[1024], args[2048];
    snprintf(log, sizeof log, "%s", fv_test_tmp("sim_frames.csv"));
    snprintf(args, sizeof args, "run --gaze sim:seed=3 --frames 30 --eye-size 16x16 --json --frame-log '%s'", log);
    fv_test_cmd *r = run(NULL, args);
    if (r->exit_code != 0) fail_msg("run: exit %d\n%s", r->exit_code, r->err);
    cJSON *jr = json_of(r, "run");
    double with = num_at(jr, "latency", "frames_with_gaze", NULL), p50 = num_at(jr, "latency", "gaze_to_photon_ms_p50", NULL);
    /* for sim_tracker_latency_is_the_same_in_run_and_latency: the simulated tracker's default latency is 4 ms */
    assert_true(fabs(num_at(jr, "latency", "stage_mean_ms", "tracker") - 4.0) < 1e-6);
    cJSON_Delete(jr);
    csv f;
    csv_load(&f, log, false);
    assert_int_equal(f.rows, 30);
    /* units in the header, one row per frame in order, times that follow each other */
    const char *want[] = {"frame_id", "t_sample_device_ns", "t_latch_ns", "t_gpu_end_ns", "t_present_ns", "t_photon_ns",
                          "left_gaze_yaw_deg", "right_gaze_pitch_deg", "uncertainty_deg", "gpu_ms", "cpu_ms",
                          "gaze_to_photon_ms", "pupil_mm"};
    for (size_t k = 0; k < sizeof want / sizeof want[0]; k++) (void)csv_col(&f, want[k]);
    for (int i = 0; i < f.rows; i++) {
        assert_int_equal(atoi(cell(&f, i, "frame_id")), i);
        long long latch = atoll(cell(&f, i, "t_latch_ns")), submit = atoll(cell(&f, i, "t_submit_ns"));
        long long end = atoll(cell(&f, i, "t_gpu_end_ns")), photon = atoll(cell(&f, i, "t_photon_ns"));
        assert_true(latch > 0 && latch <= submit && submit <= end && end <= photon);
        double gpu = cellf(&f, i, "gpu_ms"), unc = cellf(&f, i, "uncertainty_deg");
        assert_true(isfinite(gpu) && gpu > 0 && isfinite(unc) && unc >= 0);
        if (atoi(cell(&f, i, "has_gaze"))) {
            assert_string_equal(cell(&f, i, "left_gaze_valid"), "1");
            double yaw = cellf(&f, i, "left_gaze_yaw_deg");
            assert_true(isfinite(yaw) && fabs(yaw) < 90);
        }
    }
    csv_free(&f);
    /* fovea latency --frame-log: the same numbers as the run's own summary */
    snprintf(args, sizeof args, "latency --frame-log '%s' --json", log);
    r = run(NULL, args);
    if (r->exit_code != 0) fail_msg("latency --frame-log: exit %d\n%s", r->exit_code, r->err);
    cJSON *jl = json_of(r, "latency --frame-log");
    assert_true(num_at(jl, "frames", NULL, NULL) == 30);
    assert_true(num_at(jl, "frames_with_gaze", NULL, NULL) == with);
    if (fabs(num_at(jl, "gaze_to_photon_ms", "p50", NULL) - p50) > 1e-3)
        fail_msg("p50 %.6f from the log, %.6f from the run", num_at(jl, "gaze_to_photon_ms", "p50", NULL), p50);
    assert_true(num_at(jl, "gpu_ms", "frames", NULL) == 30);
    cJSON_Delete(jl);
    snprintf(args, sizeof args, "latency --frame-log '%s'", log);
    r = run(NULL, args);
    assert_int_equal(r->exit_code, 0);
    fv_assert_contains(r->out, "gaze-to-photon  p50");
    fv_assert_contains(r->out, "GPU per frame");

    /* bad input: file:line, the column and why; nonsense combinations are refused */
    static const char bad_text[] = "frame_id,has_gaze,t_sample_capture_ns,t_photon_ns,t_vsync_ns\n"
                                   "0,1,100,200,150\n1,2,100,200,150\n";
    const char *bad = fv_test_write_file("bad_frames.csv", bad_text, strlen(bad_text));
    snprintf(args, sizeof args, "latency --frame-log '%s'", bad);
    r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    fv_assert_contains(r->err, "bad_frames.csv:3: column 'has_gaze' is 2, not 0 or 1");
    const char *gazedata = fv_test_data("gaze/pupil_core/gaze_positions.csv");
    snprintf(args, sizeof args, "latency --frame-log '%s'", gazedata);
    r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    fv_assert_contains(r->err, "no column 'frame_id': not a frame log");
    r = run(NULL, "latency --frame-log x.csv --gaze sim:seed=1");
    assert_int_equal(r->exit_code, 2);
    r = run(NULL, "latency --frame-log x.csv --hz 60");
    assert_int_equal(r->exit_code, 2);
    fv_assert_contains(r->err, "--hz sets up the simulation and has no effect with --frame-log");
}

/* ---- unknown scenes, and no empty output folder ---- */

static bool exists(const char *p)
{
    struct stat sb;
    return stat(p, &sb) == 0;
}

static void unknown_scene_names_what_there_is_and_leaves_no_folder(void **state)
{
    (void)state;
    char out[1024], args[2048];
    snprintf(out, sizeof out, "%s/never/made", fv_test_tmp("noscene"));
    snprintf(args, sizeof args, "run --scene nosuch --out '%s'", out);
    fv_test_cmd *r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    fv_assert_contains(r->err, "--scene 'nosuch': no built-in scene and no file of that name");
    fv_assert_contains(r->err, "cornell, cornell-translucent, pillars");
    fv_assert_contains(r->err, "sponza-sun.scene.json");
    fv_assert_contains(r->err, "bunny-in-the-box.scene.json");
    assert_false(exists(fv_test_tmp("noscene")));
    /* a scene file that fails to load after --out was made: the folder goes again */
    static const char bad_scene[] = "{\"objects\": 3}";
    const char *badjson = fv_test_write_file("bad.scene.json", bad_scene, strlen(bad_scene));
    snprintf(args, sizeof args, "run --scene '%s' --out '%s'", badjson, out);
    r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    assert_false(exists(fv_test_tmp("noscene")));
    /* a folder that was there stays */
    char keep[1024];
    snprintf(keep, sizeof keep, "%s", fv_test_tmp("keep"));
    mkdir(keep, 0755);
    snprintf(args, sizeof args, "run --scene nosuch --out '%s'", keep);
    r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    assert_true(exists(keep));
}

/* ---- options that would do nothing ---- */

static void options_without_effect_are_refused(void **state)
{
    (void)state;
    const char *cases[][2] = {
        {"run --hz 60", "--hz is the refresh rate of the display that paces --gaze runs"},
        {"run --save every", "--save picks the frames that --out writes; without --out nothing is saved"},
        {"run --layout eyes", "--layout is the layout of the images --out writes"},
        {"run --float", "--float writes PFM files beside the PNGs of --out"},
        {"run --head trace", "--head chooses the head of a --gaze run"},
        {"run --head sideways --gaze sim:seed=1", "--head: 'sideways' is not one of trace, scene, fixed"},
        {"run --gaze sim:seed=1 --hz 60 --present window", "--hz has no effect with --present window"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        fv_test_cmd *r = run(NULL, cases[i][0]);
        if (r->exit_code != 2) fail_msg("'%s' exited %d, not 2:\n%s", cases[i][0], r->exit_code, r->err);
        assert_true(strncmp(r->err, "fovea run: ", 11) == 0);
        fv_assert_contains(fv_test_first_line(r->err), cases[i][1]); /* the reason is the first line */
    }
}

static void forced_multiview_on_lavapipe_warns_once(void **state)
{
    (void)state;
    fv_test_cmd *r = run("FOVEA_MULTIVIEW=1", "run --frames 3 --eye-size 16x16");
    assert_int_equal(r->exit_code, 0);
    const char *needle = "mis-clips the second view";
    const char *first = strstr(r->err, needle);
    if (!first) fail_msg("no warning:\n%s", r->err);
    assert_null(strstr(first + 1, needle));
    /* without FOVEA_MULTIVIEW no warning: checked on the plain run of wall_per_frame_says_what_it_measures */
}

/* ---- files that hold no gaze ---- */

static void files_without_gaze_say_what_they_are(void **state)
{
    (void)state;
    char args[2048];
    snprintf(args, sizeof args, "trace info '%s'", fv_test_data("gaze/pupil_core/fixations.csv"));
    fv_test_cmd *r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    fv_assert_contains(r->err, "this is a Pupil Player fixations export");
    fv_assert_contains(r->err, "read gaze_positions.csv beside it");
    snprintf(args, sizeof args, "trace info '%s'", fv_test_data("gaze/tobii_pro_glasses3/eventdata.gz"));
    r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    fv_assert_contains(r->err, "no gaze samples in 18 lines: this is a Tobii Pro Glasses 3 event file");
    fv_assert_contains(r->err, "read gazedata.gz");
    /* a header and no rows is no recording either */
    static const char header_only[] = "gaze_timestamp,confidence,norm_pos_x,norm_pos_y\n";
    const char *empty = fv_test_write_file("header_only.csv", header_only, strlen(header_only));
    snprintf(args, sizeof args, "trace info '%s'", empty);
    r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    fv_assert_contains(r->err, "no gaze samples: a pupil-core header and no data rows");
    /* and the real recordings still play */
    snprintf(args, sizeof args, "trace info '%s'", fv_test_data("gaze/tobii_pro_glasses3/gazedata.gz"));
    assert_int_equal(run(NULL, args)->exit_code, 0);
}

/* ---- the simulated tracker's latency ---- */

static void sim_tracker_latency_is_the_same_in_run_and_latency(void **state)
{
    (void)state;
    fv_test_cmd *r = run(NULL, "run --gaze sim:seed=1,latency_ms=12 --frames 15 --eye-size 16x16 --json");
    if (r->exit_code != 0) fail_msg("run: %s", r->err);
    cJSON *j = json_of(r, "run");
    double in_run = num_at(j, "latency", "stage_mean_ms", "tracker");
    cJSON_Delete(j);
    r = run(NULL, "latency --gaze sim:seed=1,latency_ms=12 --frames 60 --json");
    j = json_of(r, "latency");
    double in_latency = num_at(j, "stages", "tracker", "mean_ms");
    cJSON_Delete(j);
    assert_true(fabs(in_run - 12.0) < 1e-6);
    assert_true(fabs(in_latency - 12.0) < 1e-6);
    /* and its default (4 ms) when the URI does not say: checked on the run of
     * frame_log_has_every_frame_and_latency_reads_it (sim:seed=3, no latency_ms) */
}

static void wall_per_frame_says_what_it_measures(void **state)
{
    (void)state;
    fv_test_cmd *r = run(NULL, "run --frames 2 --eye-size 16x16");
    assert_int_equal(r->exit_code, 0);
    /* the loop's time until a frame was submitted, and the completed frames' wall time: two labelled figures */
    const char *l = strstr(r->out, "loop per frame");
    if (!l) fail_msg("no 'loop per frame' line:\n%s", r->out);
    fv_assert_contains(fv_test_first_line(l), "until it was submitted");
    const char *w = strstr(r->out, "wall per frame");
    if (!w) fail_msg("no 'wall per frame' line:\n%s", r->out);
    fv_assert_contains(fv_test_first_line(w), "(completed: ");
    /* and, for forced_multiview_on_lavapipe_warns_once: a run without FOVEA_MULTIVIEW does not warn */
    assert_null(strstr(r->err, "mis-clips the second view"));
}

/* --exposure keeps one meaning (a linear scale); stops are another way to write it */
static void exposure_in_stops_is_the_same_scale(void **state)
{
    (void)state;
    /* "+2ev" (4) is checked on the run of bright_surfaces_are_not_flat_white */
    const char *cases[][2] = {{"-1EV", "0.5"}, {"0EV", "1"}, {"3", "3"}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char args[256];
        snprintf(args, sizeof args, "run --frames 1 --eye-size 16x16 --json --exposure %s", cases[i][0]);
        fv_test_cmd *r = run(NULL, args);
        if (r->exit_code != 0) fail_msg("%s: exit %d\n%s", args, r->exit_code, r->err);
        cJSON *j = json_of(r, args);
        double e = num_at(j, "quality", "exposure", NULL);
        cJSON_Delete(j);
        if (fabs(e - atof(cases[i][1])) > 1e-6) fail_msg("--exposure %s gave %g, not %s", cases[i][0], e, cases[i][1]);
    }
    fv_test_cmd *r = run(NULL, "run --exposure 30EV");
    assert_int_equal(r->exit_code, 2);
    fv_assert_contains(r->err, "is not a number of stops in -19.9..19.9");
}

/* The tone curve keeps bright surfaces graded: at +2 EV a fifth of the Cornell box is brighter than display white in
 * some channel (its linear colour, the PFM, times 4 is above 1), which a clamp turned into 255; through the curve
 * only what passes the white point (4, the light itself) reaches 255. Fails if the clamp came back. */
static void bright_surfaces_are_not_flat_white(void **state)
{
    (void)state;
    char dir[1024], args[4096], path[1200];
    snprintf(dir, sizeof dir, "%s", fv_test_tmp("tone"));
    snprintf(args, sizeof args, "run --scene %s/scenes/cornell-gltf.scene.json --frames 1 --eye-size 64x64 "
             "--exposure +2ev --float --out '%s' --json", FV_SOURCE_DIR, dir);
    fv_test_cmd *r = run(NULL, args);
    if (r->exit_code != 0) fail_msg("exit %d\n%s", r->exit_code, r->err);
    /* for exposure_in_stops_is_the_same_scale: +2ev (lower case) is the linear scale 4 */
    cJSON *j = json_of(r, args);
    double e = num_at(j, "quality", "exposure", NULL);
    cJSON_Delete(j);
    if (fabs(e - 4.0) > 1e-6) fail_msg("--exposure +2ev gave %g, not 4", e);
    snprintf(path, sizeof path, "%s/frame_00000.pfm", dir);
    FILE *f = fopen(path, "rb");
    if (!f) fail_msg("no %s", path);
    int w = 0, h = 0;
    double scale = 0.0;
    char magic[3] = "";
    assert_int_equal(fscanf(f, "%2s %d %d %lf", magic, &w, &h, &scale), 4);
    fgetc(f);
    assert_string_equal(magic, "PF");
    assert_true(w == 128 && h == 64 && scale < 0.0);
    float *lin = malloc((size_t)w * h * 3 * sizeof *lin);
    assert_non_null(lin);
    assert_int_equal(fread(lin, sizeof *lin * 3, (size_t)w * h, f), (size_t)w * h);
    fclose(f);
    long over = 0, white = 0;
    for (long i = 0; i < (long)w * h; i++)
        over += 4.0f * fmaxf(lin[3 * i], fmaxf(lin[3 * i + 1], lin[3 * i + 2])) > 1.0f;
    free(lin);
    snprintf(path, sizeof path, "%s/frame_00000.png", dir);
    int pw, ph, pc;
    unsigned char *px = stbi_load(path, &pw, &ph, &pc, 3);
    if (!px) fail_msg("no %s", path);
    for (long i = 0; i < (long)pw * ph; i++) white += px[3 * i] == 255 || px[3 * i + 1] == 255 || px[3 * i + 2] == 255;
    stbi_image_free(px);
    print_message("+2 EV: %ld of %d px above display white in linear, %ld px with a channel at 255\n", over, w * h, white);
    assert_true(over > (long)w * h / 10);
    if (!(white * 4 < over)) fail_msg("%ld px at 255 for %ld above display white: bright surfaces clip", white, over);
}

/* ---- the example scenes ---- */

static void example_scenes_render(void **state)
{
    (void)state;
    const char *scenes[] = {"bunny-in-the-box", "sponza-atrium", "cornell-gltf"};
    for (size_t i = 0; i < 3; i++) {
        char dir[1024], args[4096], png[1200];
        snprintf(dir, sizeof dir, "%s", fv_test_tmp(scenes[i]));
        snprintf(args, sizeof args, "run --scene %s/scenes/%s.scene.json --frames 2 --eye-size 64x64 --out '%s'",
                 FV_SOURCE_DIR, scenes[i], dir);
        fv_test_cmd *r = run("FOVEA_VALIDATION=1", args);
        if (r->exit_code != 0) fail_msg("%s: exit %d\n%s", scenes[i], r->exit_code, r->err);
        assert_null(strstr(r->err, "error"));
        snprintf(png, sizeof png, "%s/frame_00001.png", dir);
        int w, h, c;
        unsigned char *px = stbi_load(png, &w, &h, &c, 3);
        if (!px) fail_msg("%s: no %s", scenes[i], png);
        assert_int_equal(w, 128);
        /* framed and lit: each eye's image has bright and dark parts, and is not mostly black */
        for (int eye = 0; eye < 2; eye++) {
            int lo = 765, hi = 0;
            long lit = 0;
            for (int y = 0; y < h; y++)
                for (int x = 0; x < w / 2; x++) {
                    const unsigned char *q = px + 3 * ((size_t)y * (size_t)w + (size_t)(x + eye * w / 2));
                    int s = q[0] + q[1] + q[2];
                    if (s < lo) lo = s;
                    if (s > hi) hi = s;
                    lit += s > 60;
                }
            if (hi - lo < 100 || lit < (long)(w / 2) * h / 3)
                fail_msg("%s: eye %d: range %d..%d, %ld of %d px lit", scenes[i], eye, lo, hi, lit, w / 2 * h);
        }
        stbi_image_free(px);
    }
}

/* ---- fovea devices lists a Pupil Capture that answers ---- */

static void devices_lists_pupil_capture_when_it_answers(void **state)
{
    (void)state;
    fake_capture f;
    assert_int_equal(fake_capture_start(&f, 0, 0), 0);
    char env[128];
    snprintf(env, sizeof env, "FOVEA_PUPIL_REMOTE=127.0.0.1:%d", f.remote_port);
    fv_test_cmd *r = run(env, "devices --json");
    fake_capture_stop(&f);
    if (r->exit_code != 0) fail_msg("devices: exit %d\n%s", r->exit_code, r->err);
    char want[64];
    snprintf(want, sizeof want, "pupil:127.0.0.1:%d", f.remote_port);
    fv_assert_contains(r->out, want);
    fv_assert_contains(r->out, "Pupil Capture 3.5.fake");
    /* gone: not listed */
    r = run(env, "devices --json");
    assert_int_equal(r->exit_code, 0);
    assert_null(strstr(r->out, want));
}

/* `fovea run --gaze pupil:` against a fake Capture replaying the Pupil Core export in real time: gaze reaches the
 * frames through the live driver. */
static void run_follows_a_live_pupil_capture(void **state)
{
    (void)state;
    size_t n;
    row *rows = fake_export_rows(&n);
    /* the 7 s export three times over (each pass 8 s later), so that a slow start on a loaded machine still has
     * live gaze for its frames; the run stops the replay when it is done */
    enum { PASSES = 3 };
    fake_msg *script = calloc(n * PASSES, sizeof *script);
    int64_t pass_ns = (int64_t)llround((rows[n - 1].ts - rows[0].ts + 1.0) * 1e9);
    for (size_t k = 0; k < PASSES; k++)
        for (size_t i = 0; i < n; i++) {
            row later = rows[i]; /* the same datum, k passes later in Pupil time */
            later.ts += (double)k * (double)pass_ns * 1e-9;
            for (int b = 0; b < later.base_n; b++) later.base_ts[b] += (double)k * (double)pass_ns * 1e-9;
            fake_row_message(&later, i, &script[k * n + i]);
        }
    fake_capture f;
    assert_int_equal(fake_capture_start(&f, 0, script[0].due_pupil_ns - 100 * FV_NS_PER_MS), 0);
    assert_int_equal(fake_capture_play(&f, script, n * PASSES), 0);
    char args[256];
    snprintf(args, sizeof args, "run --gaze pupil:127.0.0.1:%d --frames 60 --eye-size 16x16 --json", f.remote_port);
    fv_test_cmd *r = run(NULL, args);
    fake_capture_stop(&f);
    if (r->exit_code != 0) fail_msg("run: exit %d\n%s", r->exit_code, r->err);
    cJSON *j = json_of(r, "run --gaze pupil:");
    double samples = num_at(j, "gaze", "samples", NULL), with = num_at(j, "latency", "frames_with_gaze", NULL);
    cJSON_Delete(j);
    if (!(samples > 50 && with > 10)) fail_msg("%.0f samples, %.0f frames with gaze", samples, with);
    for (size_t i = 0; i < n * PASSES; i++) free(script[i].payload);
    free(script);
    free(rows);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s PATH_TO_FOVEA\n", argv[0]);
        return 2;
    }
    g_fovea = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(options_without_effect_are_refused),
        cmocka_unit_test(unknown_scene_names_what_there_is_and_leaves_no_folder),
        cmocka_unit_test(files_without_gaze_say_what_they_are),
        cmocka_unit_test(devices_lists_pupil_capture_when_it_answers),
        cmocka_unit_test(run_follows_a_live_pupil_capture),
        cmocka_unit_test(wall_per_frame_says_what_it_measures),
        cmocka_unit_test(exposure_in_stops_is_the_same_scale),
        cmocka_unit_test(bright_surfaces_are_not_flat_white),
        cmocka_unit_test(forced_multiview_on_lavapipe_warns_once),
        cmocka_unit_test(sim_tracker_latency_is_the_same_in_run_and_latency),
        cmocka_unit_test(frame_log_has_every_frame_and_latency_reads_it),
        cmocka_unit_test(head_follows_the_recorded_head_pose),
        cmocka_unit_test(example_scenes_render),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
