/* @brief The `fovea` command as a user runs it: exit codes, one-line usage errors, clear messages for malformed
 * input, the JSON summary on stdout, PNG output of real model files, and zero validation messages. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <stb_image.h>

#include "fovea_config.h"
#include "fovea/fv_frame_input.h"
#include "fv_test.h"

static const char *g_fovea;

typedef fv_test_cmd run_result;

/* Run `fovea ARGS` with an optional environment prefix. */
static run_result *run(const char *env, const char *args)
{
    static run_result res;
    fv_test_run_cmd(&res, env, g_fovea, args);
    return &res;
}

#define assert_contains fv_assert_contains

static int count_lines(const char *s)
{
    int n = 0;
    for (; *s; s++) n += *s == '\n';
    return n;
}

static void version_and_help_exit_zero(void **state)
{
    (void)state;
    run_result *r = run(NULL, "--version");
    assert_int_equal(r->exit_code, 0);
    assert_contains(r->out, "fovea ");
    r = run(NULL, "--help");
    assert_int_equal(r->exit_code, 0);
    assert_contains(r->out, "run");
    r = run(NULL, "run --help");
    assert_int_equal(r->exit_code, 0);
    assert_contains(r->out, "--eye-size");
}

static void unknown_command_and_bad_options_exit_2_with_one_line_error(void **state)
{
    (void)state;
    run_result *r = run(NULL, "frobnicate");
    assert_int_equal(r->exit_code, 2);
    assert_contains(r->err, "unknown command 'frobnicate'");
    const char *bad[][2] = {
        {"run --bogus", "unknown option '--bogus'"},
        {"run --frames abc", "--frames: 'abc'"},
        {"run --frames 0", "--frames: '0'"},
        {"run --frames", "needs a value"},
        {"run --eye-size 64", "--eye-size: '64'"},
        {"run --eye-size 0x64", "--eye-size: '0x64'"},
        {"run --save sometimes", "--save: 'sometimes'"},
        {"run --layout tb", "--layout: 'tb'"},
        {"run --hz 0", "--hz: '0'"},
        {"run --view depht", "--view: 'depht' is not one of color, normal, gaze, direct, shadow, cascade, albedo, depth, samples"},
        {"run --exposure 0", "--exposure: '0' is not a number in 1e-6..1e6"},
        {"run --exposure nan", "--exposure: 'nan'"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        r = run(NULL, bad[i][0]);
        if (r->exit_code != 2) fail_msg("'%s' exited %d, not 2", bad[i][0], r->exit_code);
        assert_contains(r->err, bad[i][1]);
        assert_contains(r->err, "usage: fovea run");
        /* The first line is the error, one line; the usage follows. */
        assert_true(strncmp(r->err, "fovea run: ", 11) == 0);
    }
}

static void missing_scene_file_exits_1_naming_the_file(void **state)
{
    (void)state;
    run_result *r = run(NULL, "run --scene /nonexistent/dir/model.obj --eye-size 32x32");
    assert_int_equal(r->exit_code, 1);
    assert_contains(r->err, "/nonexistent/dir/model.obj");
    r = run(NULL, "run --scene no-such-builtin --eye-size 32x32");
    assert_int_equal(r->exit_code, 1);
    assert_contains(r->err, "no-such-builtin");
}

static void malformed_scene_json_names_the_field(void **state)
{
    (void)state;
    const char *json = "{\"objects\":[{\"model\":\"builtin:cornell\"},{\"model\":\"builtin:cornell\","
                       "\"material\":{\"translucency\":{\"sigma_a_per_mm\":[0.1,-2,0.3],"
                       "\"sigma_s_prime_per_mm\":[1,1,1],\"eta\":1.3}}}]}";
    const char *path = fv_test_write_file("bad.scene.json", json, strlen(json));
    char args[1200];
    snprintf(args, sizeof args, "run --scene %s --eye-size 32x32", path);
    run_result *r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    assert_contains(r->err, "bad.scene.json");
    assert_contains(r->err, "sigma_a_per_mm[1]");

    const char *broken = "{\"objects\": [ {\"model\": }";
    path = fv_test_write_file("broken.scene.json", broken, strlen(broken));
    snprintf(args, sizeof args, "run --scene %s --eye-size 32x32", path);
    r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    assert_contains(r->err, "broken.scene.json");
}

static void json_summary_is_the_only_stdout(void **state)
{
    (void)state;
    run_result *r = run("FOVEA_VALIDATION=1", "run --frames 3 --eye-size 64x64 --json --explain");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    assert_int_equal(count_lines(r->out), 1);
    cJSON *j = cJSON_Parse(r->out);
    assert_non_null(j);
    assert_int_equal((int)cJSON_GetObjectItem(j, "frames")->valuedouble, 3);
    assert_int_equal((int)cJSON_GetObjectItem(j, "frames_timed")->valuedouble, 3); /* every frame's GPU time */
    assert_int_equal((int)cJSON_GetObjectItem(j, "validation_messages")->valuedouble, 0);
    cJSON *passes = cJSON_GetObjectItem(j, "passes");
    assert_true(cJSON_IsArray(passes) && cJSON_GetArraySize(passes) >= 2);
    cJSON *p;
    cJSON_ArrayForEach(p, passes)
    {
        double med = cJSON_GetObjectItem(p, "gpu_ms_median")->valuedouble;
        assert_true(med >= 0 && med < 60000);
    }
    assert_true(cJSON_IsArray(cJSON_GetObjectItem(j, "plan")));
    cJSON_Delete(j);
    /* Validation on, and the layer said nothing. */
    assert_null(strstr(r->err, "VUID"));
    assert_null(strstr(r->err, "validation"));
    /* Without --view the debug pass is off and not timed (the other half of the next test, checked on this run). */
    assert_null(strstr(r->out, "\"name\":\"debug\""));
    assert_contains(r->out, "off — no debug view asked for");
}

/* The quality options reach the plan and the JSON summary; the debug pass runs with its own timings and counters. */
static void debug_view_option_switches_the_debug_pass_on(void **state)
{
    (void)state;
    run_result *r = run("FOVEA_VALIDATION=1", "run --frames 2 --eye-size 64x64 --json --explain --view gaze "
                                              "--exposure 2");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    cJSON *j = cJSON_Parse(r->out);
    assert_non_null(j);
    cJSON *q = cJSON_GetObjectItem(j, "quality");
    assert_non_null(q);
    assert_string_equal(cJSON_GetObjectItem(q, "debug_view")->valuestring, "gaze");
    assert_float_equal(cJSON_GetObjectItem(q, "exposure")->valuedouble, 2.0, 1e-9);
    bool debug_planned = false, debug_timed = false;
    cJSON *e;
    cJSON_ArrayForEach(e, cJSON_GetObjectItem(j, "plan"))
    {
        const char *pass = cJSON_GetObjectItem(e, "pass")->valuestring;
        if (strcmp(pass, "debug") == 0) debug_planned = cJSON_IsTrue(cJSON_GetObjectItem(e, "enabled"));
        if (strcmp(pass, "present") == 0) assert_non_null(strstr(cJSON_GetObjectItem(e, "reason")->valuestring, "exposure 2"));
    }
    cJSON_ArrayForEach(e, cJSON_GetObjectItem(j, "passes"))
    {
        const char *pass = cJSON_GetObjectItem(e, "name")->valuestring;
        if (strcmp(pass, "debug") == 0) debug_timed = cJSON_GetObjectItem(e, "dispatches")->valuedouble == 1;
        if (strcmp(pass, "shade") == 0)
            assert_int_equal((int)cJSON_GetObjectItem(e, "pixels_shaded")->valuedouble, 64 * 64 * 2);
    }
    assert_true(debug_planned);
    assert_true(debug_timed);
    cJSON_Delete(j);
    /* Without the option the debug pass is off and not timed: checked on the run of the test above, which has the
     * same options but --view (one device start less). */
}

/* The shadow pass reports what it decided: near/far and the m + 1 split distances, increasing, first = near and
 * last = far; the Sponza scene file (sun over the atrium of ../shared/data) renders with it, validation clean. */
static void shadowed_scenes_report_their_splits(void **state)
{
    (void)state;
    run_result *r = run("FOVEA_VALIDATION=1", "run --scene pillars --frames 2 --eye-size 64x64 --json --explain "
                                              "--set shadow.splits=3 --set shadow.lambda=1");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    cJSON *j = cJSON_Parse(r->out);
    assert_non_null(j);
    const cJSON *shadow = NULL, *e;
    cJSON_ArrayForEach(e, cJSON_GetObjectItem(j, "plan"))
        if (strcmp(cJSON_GetObjectItem(e, "pass")->valuestring, "shadow") == 0) shadow = e;
    assert_non_null(shadow);
    assert_true(cJSON_IsTrue(cJSON_GetObjectItem(shadow, "enabled")));
    const cJSON *d = cJSON_GetObjectItem(shadow, "details");
    assert_non_null(d);
    double n = cJSON_GetObjectItem(d, "light0.near_m")->valuedouble, f = cJSON_GetObjectItem(d, "light0.far_m")->valuedouble;
    const cJSON *splits = cJSON_GetObjectItem(d, "light0.splits_m");
    assert_int_equal(cJSON_GetArraySize(splits), 4);
    assert_true(n > 0 && f > 100.0 * n); /* pillars: a deep scene */
    double prev = 0;
    for (int i = 0; i < 4; i++) {
        double c = cJSON_GetArrayItem(splits, i)->valuedouble;
        assert_true(c > prev);
        if (i == 1) assert_float_equal(c, n * pow(f / n, 1.0 / 3.0), 1e-6 * c); /* lambda 1: logarithmic */
        prev = c;
    }
    assert_float_equal(cJSON_GetArrayItem(splits, 0)->valuedouble, n, 1e-9);
    assert_float_equal(cJSON_GetArrayItem(splits, 3)->valuedouble, f, 1e-9);
    cJSON_Delete(j);

    r = run("FOVEA_VALIDATION=1", "run --scene " FV_SOURCE_DIR "/scenes/sponza-sun.scene.json --frames 1 "
                                  "--eye-size 64x64 --explain");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    assert_contains(r->out, "1 directional: 4 splits (lambda 0.5) shared by both eyes");
    assert_contains(r->out, "validation messages: 0");
}

/* The summary's foveation stages: a stage that did not run reads "-", in the times and in the ratios to present
 * (never "0.0x": absent, not free); the JSON has null for it. */
static void summary_marks_a_stage_that_did_not_run(void **state)
{
    (void)state;
    run_result *r = run(NULL, "run --frames 2 --eye-size 32x32 --hmd none --set fovea.temporal=0");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    assert_contains(r->out, " temporal - reconstruction ");
    assert_contains(r->out, "vs present: map ");
    assert_contains(r->out, " temporal -, reconstruction ");
    assert_null(strstr(r->out, "temporal 0.0x"));
    r = run(NULL, "run --frames 2 --eye-size 32x32 --hmd none");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    assert_null(strstr(r->out, "temporal -")); /* temporal reuse on: its figures */
}

/* sss.mode=exact over a map whose sum passes llvmpipe's loop limit: said once at start and in the plan, on llvmpipe
 * only (the sum is cut short there: a wedge of the sphere went dark at 256 px, silently); 128 px is not, nor may it
 * stop short where the light grazes (its fine samples are walked within a receiver's near field only: the marble
 * bunny's sum had passed the limit, test_cli_parity). */
static void exact_sss_past_llvmpipes_loop_limit_is_said(void **state)
{
    (void)state;
    run_result *r = run(NULL, "run --scene cornell-translucent --frames 1 --eye-size 16x16 --hmd none --explain "
                              "--set sss.mode=exact --set sss.map_size=256");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    bool llvmpipe = strstr(r->out, "on llvmpipe") != NULL;
    if (llvmpipe) {
        assert_contains(r->err, "sss.mode=exact over a 256 px map: llvmpipe ends a shader's loops after 65535");
        assert_contains(r->out, "exact: CUT SHORT here");
    } else {
        assert_null(strstr(r->err, "loops after"));
    }
    r = run(NULL, "run --scene cornell-translucent --frames 1 --eye-size 16x16 --hmd none --explain "
                  "--set sss.mode=exact --set sss.map_size=128");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    assert_null(strstr(r->err, "loops after"));
    assert_null(strstr(r->out, "CUT SHORT"));
    assert_null(strstr(r->out, "may stop short"));
    if (llvmpipe) assert_contains(r->out, "dipole exact: every sample");
}

/* Renders a file to a side-by-side PNG and checks its size and that something was drawn in both halves. */
static void render_file_to_png(const char *scene, const char *tag)
{
    char dir[1024], args[3000];
    snprintf(dir, sizeof dir, "%s", fv_test_tmp(tag));
    snprintf(args, sizeof args, "run --scene %s --frames 3 --eye-size 96x80 --out %s", scene, dir);
    run_result *r = run("FOVEA_VALIDATION=1", args);
    if (r->exit_code != 0) fail_msg("%s: exit %d; stderr:\n%s", scene, r->exit_code, r->err);
    char png[1200];
    snprintf(png, sizeof png, "%s/frame_00002.png", dir);
    int w = 0, h = 0, c = 0;
    unsigned char *px = stbi_load(png, &w, &h, &c, 4);
    if (!px) fail_msg("%s: no PNG at %s", scene, png);
    assert_int_equal(w, 192);
    assert_int_equal(h, 80);
    /* Framed sensibly: in each eye, the central half of the image is not one flat colour. */
    for (int eye = 0; eye < 2; eye++) {
        int lo = 255 * 3, hi = 0;
        for (int y = h / 4; y < 3 * h / 4; y++)
            for (int x = w / 8; x < 3 * w / 8; x++) {
                const unsigned char *q = px + 4 * ((size_t)y * (size_t)w + (size_t)(x + eye * w / 2));
                int s = q[0] + q[1] + q[2];
                if (s < lo) lo = s;
                if (s > hi) hi = s;
            }
        if (hi - lo < 30) fail_msg("%s: eye %d centre is flat (%d..%d): not framed or not lit", scene, eye, lo, hi);
    }
    stbi_image_free(px);
    assert_null(strstr(r->err, "VUID"));
}

static void renders_gltf_cornell_box(void **state)
{
    (void)state;
    render_file_to_png(fv_test_data("scenes/cornell_box_gltf/cornellBox.gltf"), "gltf");
}

static void renders_embree_obj_cornell_box(void **state)
{
    (void)state;
    render_file_to_png(fv_test_data("scenes/cornell_box/cornell_box_embree.obj"), "obj");
}

static void renders_stanford_bunny_ply(void **state)
{
    (void)state;
    render_file_to_png(fv_test_data("scenes/bunny/bun_zipper.ply"), "ply");
}

static void eyes_layout_writes_one_png_per_eye(void **state)
{
    (void)state;
    char dir[1024], args[2000];
    snprintf(dir, sizeof dir, "%s", fv_test_tmp("eyes"));
    snprintf(args, sizeof args, "run --frames 2 --eye-size 48x40 --out %s --layout eyes --save every", dir);
    run_result *r = run(NULL, args);
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    const char *names[] = {"frame_00000_left.png", "frame_00000_right.png", "frame_00001_left.png",
                           "frame_00001_right.png"};
    for (int i = 0; i < 4; i++) {
        char png[1200];
        snprintf(png, sizeof png, "%s/%s", dir, names[i]);
        int w = 0, h = 0, c = 0;
        assert_true(stbi_info(png, &w, &h, &c));
        assert_int_equal(w, 48);
        assert_int_equal(h, 40);
    }
}

/* --gaze runs go through the frame loop: every recording replays, and the summary carries gaze-to-photon latency. */
static void gaze_runs_replay_every_recording_with_latency(void **state)
{
    (void)state;
    const char *uris[] = {
        "sim:seed=1",
        "trace:%s/gaze/htc_vive_pro_eye_sranipal/TESTNA01_2D_Fist3.csv",
        "trace:%s/gaze/htc_vive_pro_eye_sranipal/TESTNA10_360VR_Fist3.csv",
        "trace:%s/gaze/tobii_pro_glasses3/gazedata.gz",
        "trace:%s/gaze/pupil_core/gaze_positions.csv",
        "trace:%s/gaze/pupil_invisible/gaze.csv",
        "trace:%s/gaze/pico_neo3_pro/boxing_VR.tsv",
    };
    const char *root = getenv("FV_SHARED_DATA_DIR");
    for (size_t i = 0; i < sizeof uris / sizeof uris[0]; i++) {
        char uri[1200], args[1600];
        snprintf(uri, sizeof uri, uris[i], root);
        snprintf(args, sizeof args, "run --gaze '%s' --frames 12 --eye-size 32x32 --json", uri);
        run_result *r = run("FOVEA_VALIDATION=1", args);
        if (r->exit_code != 0) fail_msg("%s: exit %d; stderr:\n%s", uri, r->exit_code, r->err);
        cJSON *j = cJSON_Parse(r->out);
        if (!j) fail_msg("%s: stdout is not JSON:\n%s", uri, r->out);
        cJSON *g = cJSON_GetObjectItem(j, "gaze"), *l = cJSON_GetObjectItem(j, "latency");
        assert_non_null(g);
        assert_non_null(l);
        assert_true(cJSON_GetObjectItem(g, "samples")->valuedouble > 0);
        double p50 = cJSON_GetObjectItem(l, "gaze_to_photon_ms_p50")->valuedouble;
        double with = cJSON_GetObjectItem(l, "frames_with_gaze")->valuedouble;
        /* At least one refresh and scan-out stand between a sample and its photons; far less than a second. */
        if (!(with > 0 && p50 > 5.0 && p50 < 1000.0)) fail_msg("%s: gaze-to-photon p50 %.3f ms over %.0f frames", uri, p50, with);
        assert_int_equal((int)cJSON_GetObjectItem(j, "validation_messages")->valuedouble, 0);
        cJSON_Delete(j);
    }
}

/* Recording from a tracker that does not answer says so in words, what was not recorded, and what to do (issue 28
 * item 6: it printed FV_ERR_NOT_FOUND alone). Port 1: nothing listens there. */
static void trace_record_from_an_absent_tracker_says_what_to_do(void **state)
{
    (void)state;
    char args[512];
    const char *out = fv_test_tmp("absent.trace");
    unlink(out);
    snprintf(args, sizeof args, "trace record pupil:127.0.0.1:1 '%s' --seconds 1", out);
    run_result *r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    assert_contains(r->err, "fovea trace: record: no eye tracker at 'pupil:127.0.0.1:1'");
    assert_contains(r->err, "nothing was recorded");
    assert_contains(r->err, "Pupil Capture");
    assert_contains(r->err, "fovea devices");
    assert_null(strstr(r->err, "failed (FV_ERR")); /* not the bare code */
    assert_int_not_equal(access(out, F_OK), 0);  /* no file left behind */
}

static void unknown_gaze_scheme_fails_naming_known_ones(void **state)
{
    (void)state;
    run_result *r = run(NULL, "run --gaze bogus:thing --frames 1 --eye-size 16x16");
    assert_int_equal(r->exit_code, 1);
    assert_contains(r->err, "unknown URI scheme 'bogus'");
    assert_contains(r->err, "trace");
}

static double jnum(const cJSON *o, const char *key)
{
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!cJSON_IsNumber(x)) fail_msg("JSON has no number \"%s\"", key);
    return x->valuedouble;
}

/* Issue 3's target, end to end: saccade F1 >= 0.9 on the simulated eye, and prediction lowers the p95 error at a
 * 20 ms horizon compared with the latest sample. */
static void gaze_eval_meets_f1_and_prediction_targets(void **state)
{
    (void)state;
    run_result *r = run(NULL, "gaze eval --gaze sim:seed=1 --json");
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    cJSON *j = cJSON_Parse(r->out);
    assert_non_null(j);
    double f1 = jnum(cJSON_GetObjectItem(j, "saccades"), "f1");
    if (!(f1 >= 0.9)) fail_msg("saccade F1 %.3f < 0.9", f1);
    bool seen = false;
    const cJSON *h;
    cJSON_ArrayForEach(h, cJSON_GetObjectItem(j, "horizons"))
    {
        if (jnum(h, "horizon_ms") != 20) continue;
        double pred = jnum(cJSON_GetObjectItem(h, "predicted"), "p95_deg");
        double latest = jnum(cJSON_GetObjectItem(h, "latest_sample"), "p95_deg");
        if (!(pred < latest)) fail_msg("p95 at 20 ms: predicted %.3f deg, latest sample %.3f deg", pred, latest);
        seen = true;
    }
    assert_true(seen);
    cJSON_Delete(j);
    r = run(NULL, "gaze eval --gaze sim:seed=1,rate_hz=99999");
    assert_int_equal(r->exit_code, 1);
    assert_contains(r->err, "rate_hz");
}

/* The Microsoft reference descriptor parses to the layout Windows reports (input report 0x10: 65 bytes), and a
 * report decodes into a sample. */
static void hid_parse_and_decode_the_reference_tracker(void **state)
{
    (void)state;
    char args[2048];
    snprintf(args, sizeof args, "hid parse %s --json", fv_test_data("hid/ms-gazehid-vhidmini-eye-tracker.rdesc.hex"));
    run_result *r = run(NULL, args);
    if (r->exit_code != 0) fail_msg("exit %d; stderr:\n%s", r->exit_code, r->err);
    cJSON *j = cJSON_Parse(r->out);
    assert_non_null(j);
    assert_true(cJSON_IsTrue(cJSON_GetObjectItem(j, "eye_tracker")));
    bool found = false;
    const cJSON *rep;
    cJSON_ArrayForEach(rep, cJSON_GetObjectItem(j, "reports"))
    {
        const cJSON *type = cJSON_GetObjectItem(rep, "type");
        if (jnum(rep, "id") == 0x10 && cJSON_IsString(type) && strcmp(type->valuestring, "input") == 0) {
            assert_int_equal((int)jnum(rep, "byte_length"), 65);
            found = true;
        }
    }
    assert_true(found);
    cJSON_Delete(j);
    snprintf(args, sizeof args, "hid decode %s %s", fv_test_data("hid/ms-gazehid-vhidmini-eye-tracker.rdesc.hex"),
             fv_test_data("hid/SYNTHETIC-eye-tracker-reports.txt"));
    r = run(NULL, args);
    if (r->exit_code != 0) fail_msg("decode exit %d; stderr:\n%s", r->exit_code, r->err);
    const char *garbage = "05 12 09 01 a1 01 c0 c0 c0\n"; /* collection underflow */
    const char *path = fv_test_write_file("bad.rdesc.hex", garbage, strlen(garbage));
    snprintf(args, sizeof args, "hid parse %s", path);
    r = run(NULL, args);
    assert_int_equal(r->exit_code, 1);
    assert_contains(r->err, "byte");
}

/* `fovea run --help` names every view of the one table (fv_debug_view_name), and the error for a wrong one too. */
static void help_lists_every_view_from_the_table(void **state)
{
    (void)state;
    run_result *r = run(NULL, "run --help");
    assert_int_equal(r->exit_code, 0);
    char *help = strdup(r->out);
    r = run(NULL, "run --view nosuch");
    assert_int_equal(r->exit_code, 2);
    for (int k = 0; k < FV_DEBUG_VIEW_COUNT; k++) {
        char word[64];
        snprintf(word, sizeof word, "%s%s", k ? ", " : ": ", fv_debug_view_name((fv_debug_view)k));
        assert_contains(help, word);
        assert_contains(r->err, fv_debug_view_name((fv_debug_view)k));
    }
    free(help);
}

/* The pipeline cache on disk (issue 25): written after a run with a header that names this device; a corrupt or
 * foreign file is ignored with one warning and replaced; off writes none. */
static void pipeline_cache_is_kept_and_a_bad_one_ignored(void **state)
{
    (void)state;
    char path[1024], env[1200];
    snprintf(path, sizeof path, "%s", fv_test_tmp("pipelines.bin"));
    unlink(path);
    snprintf(env, sizeof env, "FOVEA_PIPELINE_CACHE='%s'", path);
    run_result *r = run(env, "run --eye-size 16x16");
    assert_int_equal(r->exit_code, 0);
    size_t len = 0;
    char *data = fv_test_read_file(path, &len);
    assert_true(len >= 32);
    uint32_t h[4];
    memcpy(h, data, sizeof h);
    assert_int_equal(h[0], 32);
    assert_int_equal(h[1], 1); /* VK_PIPELINE_CACHE_HEADER_VERSION_ONE */
    free(data);
    static const char *const bad[] = {"not a cache at all", ""};
    for (int k = 0; k < 2; k++) {
        if (k == 0) fv_test_write_file("pipelines.bin", bad[0], strlen(bad[0]));
        else { /* a foreign device: the vendor id changed */
            data = fv_test_read_file(path, &len);
            data[8] ^= 0x5a;
            fv_test_write_file("pipelines.bin", data, len);
            free(data);
        }
        r = run(env, "run --eye-size 16x16");
        assert_int_equal(r->exit_code, 0);
        assert_contains(r->err, "pipelines.bin: ignored (");
        assert_int_equal(count_lines(r->err), 1);
        data = fv_test_read_file(path, &len); /* replaced by a good one */
        memcpy(h, data, sizeof h);
        assert_int_equal(h[0], 32);
        free(data);
    }
    unlink(path);
    r = run("FOVEA_PIPELINE_CACHE=off", "run --eye-size 16x16");
    assert_int_equal(r->exit_code, 0);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_cli PATH_TO_FOVEA\n");
        return 2;
    }
    g_fovea = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(version_and_help_exit_zero),
        cmocka_unit_test(unknown_command_and_bad_options_exit_2_with_one_line_error),
        cmocka_unit_test(missing_scene_file_exits_1_naming_the_file),
        cmocka_unit_test(malformed_scene_json_names_the_field),
        cmocka_unit_test(json_summary_is_the_only_stdout),
        cmocka_unit_test(debug_view_option_switches_the_debug_pass_on),
        cmocka_unit_test(shadowed_scenes_report_their_splits),
        cmocka_unit_test(summary_marks_a_stage_that_did_not_run),
        cmocka_unit_test(exact_sss_past_llvmpipes_loop_limit_is_said),
        cmocka_unit_test(renders_gltf_cornell_box),
        cmocka_unit_test(renders_embree_obj_cornell_box),
        cmocka_unit_test(renders_stanford_bunny_ply),
        cmocka_unit_test(eyes_layout_writes_one_png_per_eye),
        cmocka_unit_test(gaze_runs_replay_every_recording_with_latency),
        cmocka_unit_test(unknown_gaze_scheme_fails_naming_known_ones),
        cmocka_unit_test(trace_record_from_an_absent_tracker_says_what_to_do),
        cmocka_unit_test(gaze_eval_meets_f1_and_prediction_targets),
        cmocka_unit_test(hid_parse_and_decode_the_reference_tracker),
        cmocka_unit_test(pipeline_cache_is_kept_and_a_bad_one_ignored),
        cmocka_unit_test(help_lists_every_view_from_the_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
