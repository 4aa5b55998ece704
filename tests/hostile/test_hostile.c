/* @brief The hostile-input corpus: files and URIs built to hurt (lengths and counts no file can hold, floods of one
 * error, nesting past the parser's limit, NULs and invalid UTF-8 in names, directories, pipes, truncations), written
 * by the test into its temp dir and given to every fovea command that reads a file or URI. Each case must end
 * within its time limit with a clear message naming the input, exit non-zero when the input is unusable, never
 * print a sanitizer report (in the sanitizer build this runs its sanitized fovea), never flood stderr, and, with
 * --json, print strictly valid UTF-8 JSON (checked here and by python3's json module). */
#include <cjson/cJSON.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "fv_test.h"

#define CASE_LIMIT_S 25   /* per case, under ASan+UBSan on a loaded 2-core machine */
#define GPU_LIMIT_S 60    /* a case that brings up lavapipe */
#define MAX_STDERR_LINES 40 /* a flood of one error is summarised long before this */

/* FV_HOSTILE_KEEP_GOING=1: report every failing case and go on (to list what an older fovea gets wrong) */
static bool g_keep_going;
static int g_failed;
#define FAIL_CASE(...)                                                                                                 \
    do {                                                                                                               \
        if (!g_keep_going) fail_msg(__VA_ARGS__);                                                                      \
        print_message("FAILED CASE: ");                                                                                \
        print_message(__VA_ARGS__);                                                                                    \
        print_message("\n");                                                                                           \
        g_failed++;                                                                                                    \
        return;                                                                                                        \
    } while (0)

static const char *g_fovea;
static const char *g_dir; /* the corpus: every case runs in it, so inputs are named as a user would */
static int g_cases;
static double g_seconds;

enum { EXPECT_FAIL = 0, EXPECT_OK = 1, EXPECT_USAGE = 2 };
enum { F_GPU = 1, F_JSON = 2 };

static const char *write_bytes(const char *name, const void *data, size_t n) { return fv_test_write_file(name, data, n); }
static void write_text(const char *name, const char *text) { (void)write_bytes(name, text, strlen(text)); }

/* The length of a valid UTF-8 sequence at p, or 0 (overlongs, surrogates, > U+10FFFF and stray bytes are invalid). */
static size_t utf8_seq(const unsigned char *p, size_t n)
{
    if (p[0] < 0x80) return 1;
    size_t len = p[0] >= 0xC2 && p[0] <= 0xDF ? 2 : p[0] >= 0xE0 && p[0] <= 0xEF ? 3 : p[0] >= 0xF0 && p[0] <= 0xF4 ? 4 : 0;
    if (!len || n < len) return 0;
    uint32_t cp = p[0] & (len == 2 ? 0x1Fu : len == 3 ? 0x0Fu : 0x07u);
    for (size_t i = 1; i < len; i++) {
        if ((p[i] & 0xC0u) != 0x80u) return 0;
        cp = cp << 6 | (p[i] & 0x3Fu);
    }
    static const uint32_t min[5] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < min[len] || cp > 0x10FFFFu || (cp >= 0xD800u && cp <= 0xDFFFu)) return 0;
    return len;
}

/* Strict: the whole of stdout is one JSON text in valid UTF-8, with no \u0000 and no lone surrogate escapes. */
static void assert_strict_json(const char *label, const char *out)
{
    const unsigned char *p = (const unsigned char *)out;
    size_t n = strlen(out);
    if (n >= sizeof(((fv_test_cmd *)0)->out) - 1) FAIL_CASE("%s: stdout over 64 KiB, not checked whole", label);
    for (size_t i = 0; i < n;) {
        size_t k = utf8_seq(p + i, n - i);
        if (!k) FAIL_CASE("%s: stdout byte %zu (0x%02x) is not valid UTF-8:\n%.600s", label, i, p[i], out);
        i += k;
    }
    if (strstr(out, "\\u0000")) FAIL_CASE("%s: JSON holds \\u0000", label);
    const char *end = NULL;
    cJSON *j = cJSON_ParseWithOpts(out, &end, 1);
    if (!j) FAIL_CASE("%s: stdout is not one JSON text (stops at byte %td):\n%.600s", label, end ? end - out : -1, out);
    cJSON_Delete(j);
    /* and an independent strict parser: python3's json on the bytes decoded as strict UTF-8 */
    const char *copy = fv_test_write_file("json_check.txt", out, n);
    char args[1400];
    snprintf(args, sizeof args,
             "-c 'import json,sys\n"
             "def walk(v):\n"
             "    if isinstance(v,str): v.encode(\"utf-8\",\"strict\")\n"
             "    elif isinstance(v,dict): [walk(k) or walk(x) for k,x in v.items()]\n"
             "    elif isinstance(v,list): [walk(x) for x in v]\n"
             "walk(json.loads(open(sys.argv[1],\"rb\").read().decode(\"utf-8\",\"strict\")))' '%s'", copy);
    fv_test_cmd *py = malloc(sizeof *py);
    fv_test_run_cmd(py, NULL, "/usr/bin/python3", args);
    int py_rc = py->exit_code;
    char py_err[600];
    size_t pl = strlen(py->err) < sizeof py_err - 1 ? strlen(py->err) : sizeof py_err - 1;
    memcpy(py_err, py->err, pl);
    py_err[pl] = '\0';
    free(py);
    if (py_rc != 0) FAIL_CASE("%s: python3's json refuses stdout:\n%s\n%.600s", label, py_err, out);
}

static int count_lines(const char *s)
{
    int n = 0;
    for (; *s; s++) n += *s == '\n';
    return n;
}

/* Run `fovea ARGS` in the corpus dir and check the rules. `names` is the input the messages must name (NULL: not
 * checked); each of the NULL-terminated `needles` must be in stderr; `absent` (may be NULL) must not be. */
static fv_test_cmd res;

static void check_case(const char *args, int expect, int flags, const char *names, const char *const *needles,
                       const char *absent)
{
    char env[2048], prog[2048];
    int limit = (flags & F_GPU) ? GPU_LIMIT_S : CASE_LIMIT_S;
    /* lavapipe leaks at exit: leak detection off for the commands that bring it up, on for the others */
    snprintf(env, sizeof env,
             "cd '%s' && ASAN_OPTIONS=detect_leaks=%d:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1",
             g_dir, (flags & F_GPU) ? 0 : 1);
    snprintf(prog, sizeof prog, "timeout -k 5 %d '%s'", limit, g_fovea);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    fv_test_run_cmd(&res, env, prog, args);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double secs = (double)(t1.tv_sec - t0.tv_sec) + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-9;
    g_cases++;
    g_seconds += secs;
    const char *e = res.err;
    if (res.exit_code == 124 || res.exit_code == 137)
        FAIL_CASE("fovea %s: still running after the %d s limit (overload)\nstderr:\n%.2000s", args, limit, e);
    if (strstr(e, "Sanitizer") || strstr(e, "runtime error:"))
        FAIL_CASE("fovea %s: sanitizer report:\n%.4000s", args, e);
    if (res.exit_code >= 128) FAIL_CASE("fovea %s: killed by signal %d\n%.2000s", args, res.exit_code - 128, e);
    if (expect == EXPECT_OK && res.exit_code != 0) FAIL_CASE("fovea %s: exit %d, expected 0\n%.2000s", args, res.exit_code, e);
    if (expect == EXPECT_FAIL && (res.exit_code == 0 || res.exit_code == 2))
        FAIL_CASE("fovea %s: exit %d, expected 1 (unusable input)\n%.2000s", args, res.exit_code, e);
    if (expect == EXPECT_USAGE && res.exit_code != 2) FAIL_CASE("fovea %s: exit %d, expected 2\n%.2000s", args, res.exit_code, e);
    int lines = count_lines(e);
    if (lines > MAX_STDERR_LINES || strlen(e) >= sizeof res.err - 1)
        FAIL_CASE("fovea %s: %d lines on stderr (a flood):\n%.3000s", args, lines, e);
    if (names && !strstr(e, names)) FAIL_CASE("fovea %s: the message does not name '%s':\n%.2000s", args, names, e);
    for (; needles && *needles; needles++)
        if (!strstr(e, *needles) && !strstr(res.out, *needles))
            FAIL_CASE("fovea %s: expected \"%s\" in:\n%.3000s%.1000s", args, *needles, e, res.out);
    if (absent && (strstr(e, absent) || strstr(res.out, absent)))
        FAIL_CASE("fovea %s: \"%s\" should not appear:\n%.2000s%.1000s", args, absent, e, res.out);
    if (flags & F_JSON) assert_strict_json(args, res.out);
}

static fv_test_cmd *check(const char *args, int expect, int flags, const char *names, const char *const *needles,
                          const char *absent)
{
    check_case(args, expect, flags, names, needles, absent);
    return &res;
}

#define NEEDLES(...) ((const char *const[]){__VA_ARGS__, NULL})

/* Each command of `templates` (NULL-terminated; "%s" stands for the input) on one unusable input: it must fail,
 * naming the input, and say `needle` (may be NULL). */
static void check_commands(const char *const *templates, const char *input, const char *needle)
{
    for (; *templates; templates++) {
        char args[512];
        snprintf(args, sizeof args, *templates, input);
        check(args, EXPECT_FAIL, 0, input, needle ? NEEDLES(needle) : NULL, NULL);
    }
}

/* ---- scene files ------------------------------------------------------------------------------------------ */

/* A binary PLY triangle whose one face declares `count` indices. */
static void ply_with_list(const char *name, bool big_endian, uint32_t count)
{
    char b[512];
    int n = snprintf(b, sizeof b,
                     "ply\nformat binary_%s_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n",
                     big_endian ? "big" : "little");
    const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t words[13];
    for (int i = 0; i < 9; i++) memcpy(&words[i], &v[i], 4);
    words[9] = count, words[10] = 0, words[11] = 1, words[12] = 2;
    for (int i = 0; i < 13; i++)
        for (int k = 0; k < 4; k++) b[n++] = (char)(words[i] >> (big_endian ? 24 - 8 * k : 8 * k));
    write_bytes(name, b, (size_t)n);
}

static char *objects_json(const char *item, size_t count)
{
    size_t il = strlen(item);
    char *s = malloc(32 + count * (il + 1));
    size_t o = (size_t)sprintf(s, "{\"objects\":[");
    for (size_t i = 0; i < count; i++) {
        if (i) s[o++] = ',';
        memcpy(s + o, item, il);
        o += il;
    }
    sprintf(s + o, "]}");
    return s;
}

static void make_scene_corpus(void)
{
    ply_with_list("list_2e32.ply", false, 0xFFFFFFFFu);
    ply_with_list("list_4e8_be.ply", true, 400000000u);
    ply_with_list("triangle.ply", false, 3);
    write_text("list_ascii.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                 "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                 "0 0 0\n1 0 0\n0 1 0\n4294967295 0 1 2\n");
    write_text("cut.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 20\nproperty float x\n"
                          "property float y\nproperty float z\nend_header\nshort");
    write_text("huge.off", "OFF\n400000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    write_text("empty.ply", "");
    unsigned char junk[700];
    uint32_t x = 7;
    for (size_t i = 0; i < sizeof junk; i++) junk[i] = (unsigned char)((x = x * 1103515245u + 12345u) >> 16);
    write_bytes("junk.glb", junk, sizeof junk);
    write_bytes("junk.obj", junk, sizeof junk);
    mkdir(fv_test_tmp("adir.scene.json"), 0755);
    mkdir(fv_test_tmp("mtl_is_dir"), 0755);
    write_text("mtl_dir.obj", "mtllib mtl_is_dir\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    /* 200,000 objects: refused by the count before any is loaded (was: 112,351 lines, 18.7 s, 714 MB) */
    char *many = objects_json("{\"model\":\"nothere.ply\",\"junk\":1}", 200000);
    write_text("many.scene.json", many);
    free(many);
    /* 3000 objects with the same mistake: a few shown, then "... and N more" */
    char *same = objects_json("{\"model\":\"builtin:cornell\",\"scale\":-1}", 3000);
    write_text("same.scene.json", same);
    free(same);
    /* nesting past cJSON's limit */
    char *deep = malloc(4096);
    size_t o = (size_t)sprintf(deep, "{\"objects\":");
    for (int i = 0; i < 1500; i++) deep[o++] = '[';
    deep[o] = '\0';
    write_text("deep.scene.json", deep);
    free(deep);
    write_text("nul.scene.json", "{\"name\":\"ab\\u0000cd\",\"objects\":[{\"model\":\"builtin:cornell\"}]}");
    write_text("bad_utf8.scene.json", "{\"name\":\"bad \xff\xfe name \xc0\xaf\",\"objects\":[{\"model\":\"builtin:cornell\"}]}");
    write_text("truncated.scene.json", "{\"objects\":[{\"model\":\"builtin:cor");
    /* neighbours: a list in an element fovea does not use, a count type that is signed, no format, no end */
    write_text("list_other.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                 "property float z\nelement extra 1\nproperty list uint uint data\nend_header\n"
                                 "0 0 0\n1 0 0\n0 1 0\n3000000000 1\n");
    write_text("no_format.ply", "ply\nelement vertex 1\nproperty float x\nend_header\n1\n");
    write_text("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n");
    write_text("bad_type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n1\n");
    /* a scene file whose model is the hostile PLY: the model's message, then the scene's */
    write_text("wraps_ply.scene.json", "{\"objects\":[{\"model\":\"list_2e32.ply\"}]}");
    const char *fifo = fv_test_tmp("model.fifo.obj");
    unlink(fifo);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    write_text("wraps_fifo.scene.json", "{\"objects\":[{\"model\":\"model.fifo.obj\"}]}");
    /* more values than any scene needs (a 16 MiB file of "0," would take ~650 MB of cJSON nodes) */
    size_t n = 4500000;
    char *vals = malloc(2 * n + 64);
    size_t v = (size_t)sprintf(vals, "{\"objects\":[{\"model\":\"builtin:cornell\"}],\"pad\":[");
    for (size_t i = 0; i < n; i++) vals[v++] = '0', vals[v++] = ',';
    sprintf(vals + v - 1, "]}");
    write_text("values.scene.json", vals);
    free(vals);
    char *lights = malloc(70000 * 3 + 64);
    v = (size_t)sprintf(lights, "{\"objects\":[{\"model\":\"builtin:cornell\"}],\"lights\":[");
    for (size_t i = 0; i < 70000; i++) v += (size_t)sprintf(lights + v, "%s{}", i ? "," : "");
    sprintf(lights + v, "]}");
    write_text("lights.scene.json", lights);
    free(lights);
}

static void scene_inputs_fail_fast_naming_the_file(void **state)
{
    (void)state;
    make_scene_corpus();
    static const struct {
        const char *file;
        const char *needle;
    } cases[] = {
        {"list_2e32.ply", "list 'vertex_indices' claims 4294967295 entries"},
        {"list_4e8_be.ply", "claims 400000000 entries"},
        {"list_ascii.ply", "claims 4294967295 entries"},
        {"cut.ply", "ends inside element 'vertex'"},
        {"huge.off", "OFF header claims 400000000 vertices"},
        {"empty.ply", "empty.ply"},
        {"junk.glb", "junk.glb"},
        {"junk.obj", "junk.obj"},
        {"adir.scene.json", "not a regular file"},
        {"missing.ply", "No such file"},
        {"mtl_dir.obj", "mtllib 'mtl_is_dir' is not a regular file"},
        {"many.scene.json", "200000 objects is more than the limit of 65536"},
        {"same.scene.json", "... and 2,992 more like"},
        {"deep.scene.json", "nested deeper than 1000 levels (the parser's limit)"},
        {"nul.scene.json", "a string holds \\u0000 (a NUL character)"},
        {"list_other.ply", "list 'data' claims 3000000000 entries"},
        {"no_format.ply", "PLY header has no format line"},
        {"no_end.ply", "PLY header has no end_header line"},
        {"bad_type.ply", "property type 'float128' is unknown"},
        {"wraps_ply.scene.json", "claims 4294967295 entries"},
        {"wraps_fifo.scene.json", "not a regular file"},
        {"model.fifo.obj", "not a regular file"},
        {"values.scene.json", "JSON values, more than the 4194304 a scene file may hold"},
        {"lights.scene.json", "70000 lights is more than the limit of 65536"},
        {"truncated.scene.json", "line 1 column 22: invalid JSON (the text ends inside the string"},
    };
    /* run refuses the scene before it brings up the GPU */
    const char *const commands[] = {"run --scene '%s' --frames 1 --eye-size 16x16",
                                    "reference --scene '%s' --eye-size 16x16 --spp 1", NULL};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) check_commands(commands, cases[i].file, cases[i].needle);
}

/* ---- --json output from hostile names --------------------------------------------------------------------- */

/* A 12x12 PFM (colour, little-endian). */
static void write_pfm(const char *name, float v)
{
    char head[32];
    int hn = snprintf(head, sizeof head, "PF\n12 12\n-1.0\n");
    size_t n = (size_t)hn + 12 * 12 * 3 * sizeof(float);
    char *b = malloc(n);
    memcpy(b, head, (size_t)hn);
    for (int i = 0; i < 12 * 12 * 3; i++) {
        float f = v + (float)(i % 7) * 0.01f;
        memcpy(b + hn + (size_t)i * sizeof f, &f, sizeof f);
    }
    write_bytes(name, b, n);
    free(b);
}

static void every_json_output_is_valid_utf8_whatever_the_names(void **state)
{
    (void)state;
    make_scene_corpus();
    /* a raw 0xFF byte (and an overlong '/') in a scene name, and in file names */
    const char *ff_ply = "tri\xff\xfe.ply";
    ply_with_list(ff_ply, false, 3);
    check("reference --scene bad_utf8.scene.json --eye-size 16x16 --spp 1 --json", EXPECT_OK, F_JSON, NULL, NULL, NULL);
    check("reference --scene 'tri\xff\xfe.ply' --eye-size 16x16 --spp 1 --json", EXPECT_OK, F_JSON, NULL, NULL, NULL);
    check("run --scene bad_utf8.scene.json --frames 1 --eye-size 16x16 --json", EXPECT_OK, F_GPU | F_JSON, NULL, NULL,
          NULL);
    write_pfm("a\xff.pfm", 0.5f);
    write_pfm("b\xc3.pfm", 0.25f);
    check("compare 'a\xff.pfm' 'b\xc3.pfm' --json", EXPECT_OK, F_JSON, NULL, NULL, NULL);
    /* a trace recorded here, under a name with invalid UTF-8 */
    check("trace record sim:seed=1 'rec\xff.csv' --seconds 0.3 --sim-clock", EXPECT_OK, 0, NULL, NULL, NULL);
    check("trace info 'rec\xff.csv' --json", EXPECT_OK, F_JSON, NULL, NULL, NULL);
    check("gaze eval --gaze 'trace:rec\xff.csv' --seconds 0.3 --json", EXPECT_OK, F_JSON, NULL, NULL, NULL);
    check("latency --gaze 'trace:rec\xff.csv' --frames 20 --json", EXPECT_OK, F_JSON, NULL, NULL, NULL);
    const char *desc = fv_test_data("hid/ms-gazehid-vhidmini-eye-tracker.rdesc.hex");
    char *text = fv_test_read_file(desc, NULL);
    write_text("desc\xff.hex", text);
    free(text);
    write_text("cfg.txt", "cfg: 12 ac 10 c4 a0 ff ff ff ff 1c 1e 98 0a ff ff ff 7f ff ff ff 7f\n");
    check("hid parse 'desc\xff.hex' --json", EXPECT_OK, F_JSON, NULL, NULL, NULL);
    fv_test_cmd *r = check("hid decode 'desc\xff.hex' cfg.txt --json", EXPECT_OK, F_JSON, NULL, NULL, NULL);
    if (!strstr(r->out, "\"display_serial\":\tnull")) {
        if (!g_keep_going) fail_msg("display_serial is not null:\n%s", r->out);
        print_message("FAILED CASE: hid decode --json: display_serial is not null\n");
        g_failed++;
    }
    check("knobs --json", EXPECT_OK, F_JSON, NULL, NULL, NULL);
    check("devices --json", EXPECT_OK, F_JSON, NULL, NULL, NULL);
}

/* ---- HID files -------------------------------------------------------------------------------------------- */

static void hid_files_get_clear_messages(void **state)
{
    (void)state;
    const char *desc = fv_test_data("hid/ms-gazehid-vhidmini-eye-tracker.rdesc.hex");
    char *text = fv_test_read_file(desc, NULL);
    write_text("desc.hex", text);
    free(text);
    mkdir(fv_test_tmp("hid_dir"), 0755);
    write_text("hid_empty.hex", "");
    write_text("unclosed.hex", "05 12 09 01 a1 01 05 12\n");
    size_t big = (2u << 20);
    char *zeros = calloc(1, big);
    write_bytes("hid_big.bin", zeros, big);
    free(zeros);
    const char *fifo = fv_test_tmp("hid.fifo");
    unlink(fifo);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    write_text("reports.txt", "a: 10 40\n\n# comment\n\n\nb: 10 4g\n");
    write_text("cfg.txt", "cfg: 12 ac 10 c4 a0 ff ff ff ff 1c 1e 98 0a ff ff ff 7f ff ff ff 7f\n");
    write_text("track.txt", "t1: 10 40 42 0f 00 00 00 00 00 4c 05 04 00 1a 43 02 00 e8 86 ff ff e0 2e 00 00 e0 75 09 00 "
                            "18 79 00 00 e0 2e 00 00 e0 75 09 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 "
                            "00 00 00 00 00 00\n");
    /* was "report descriptor is empty" */
    check("hid parse hid_dir", EXPECT_FAIL, 0, "hid_dir", NEEDLES("is a directory"), "is empty");
    check("hid parse hid_missing.hex", EXPECT_FAIL, 0, "hid_missing.hex", NEEDLES("No such file"), NULL);
    check("hid parse hid_empty.hex", EXPECT_FAIL, 0, "hid_empty.hex", NULL, NULL);
    check("hid parse unclosed.hex", EXPECT_FAIL, 0, "unclosed.hex", NULL, NULL);
    check("hid parse hid_big.bin", EXPECT_FAIL, 0, "hid_big.bin", NEEDLES("larger than"), NULL);
    check("hid parse hid.fifo", EXPECT_FAIL, 0, "hid.fifo", NEEDLES("not a regular file"), NULL);
    check("hid decode desc.hex hid_dir", EXPECT_FAIL, 0, "hid_dir", NEEDLES("is a directory"), NULL);
    check("hid decode hid_dir reports.txt", EXPECT_FAIL, 0, "hid_dir", NEEDLES("is a directory"), NULL);
    char *many = malloc(5000 * 8 + 1);
    size_t o = 0;
    for (int i = 0; i < 5000; i++) o += (size_t)sprintf(many + o, "10 40\n");
    write_text("many_reports.txt", many);
    free(many);
    check("hid decode desc.hex many_reports.txt", EXPECT_FAIL, 0, "many_reports.txt", NEEDLES("more than 4096 reports"),
          NULL);
    /* positions count in the file (was "reports.txt (line 6):1:5") */
    check("hid decode desc.hex reports.txt", EXPECT_FAIL, 0, "reports.txt",
          NEEDLES("reports.txt:6:7: expected a two-digit hex byte, found '4g'"), "(line");
    /* absent or out-of-range values say so in text (was "serial -1, calibrated screen nan x nan mm") */
    check("hid decode desc.hex cfg.txt", EXPECT_OK, 0, NULL,
          NEEDLES("serial unknown, calibrated screen unknown x unknown"), "nan");
    /* the usage says 1..1e9 and 1e9-style counts are taken; past it, refused with the range */
    check("hid decode desc.hex track.txt --bench 1e2", EXPECT_OK, 0, NULL, NEEDLES("decoded 100 tracking reports"), NULL);
    check("hid decode desc.hex cfg.txt --bench 2e9", EXPECT_USAGE, 0, NULL, NEEDLES("--bench needs a count in 1..1e9"),
          NULL);
    unlink(fifo);
}

/* ---- traces and gaze URIs --------------------------------------------------------------------------------- */

static void trace_files_and_gaze_uris_get_clear_messages(void **state)
{
    (void)state;
    check("trace record sim:seed=1 rec.csv --seconds 0.3 --sim-clock", EXPECT_OK, 0, NULL, NULL, NULL);
    char *rec = fv_test_read_file(fv_test_tmp("rec.csv"), NULL);
    /* header and one sample: lines 1-5 are the magic, metadata and the column header */
    char *p = rec;
    for (int i = 0; i < 6 && p; i++) p = strchr(p, '\n') ? strchr(p, '\n') + 1 : NULL;
    assert_non_null(p);
    write_bytes("one.csv", rec, (size_t)(p - rec));
    free(rec);
    mkdir(fv_test_tmp("trace_dir"), 0755);
    unsigned char junk[600];
    uint32_t x = 3;
    for (size_t i = 0; i < sizeof junk; i++) junk[i] = (unsigned char)((x = x * 1103515245u + 12345u) >> 16);
    write_bytes("junk.csv", junk, sizeof junk);
    write_bytes("junk.csv.gz", "\x1f\x8b\x08\x00garbage-not-deflate", 24);
    size_t n = (2u << 20);
    char *line = malloc(n + 32);
    int h = sprintf(line, "fovea-trace 1\n");
    memset(line + h, '7', n);
    line[h + n] = '\n';
    write_bytes("longline.csv", line, (size_t)h + n + 1);
    free(line);
    const char *bad[] = {"trace_dir", "trace_missing.csv", "junk.csv", "junk.csv.gz", "longline.csv"};
    const char *const readers[] = {"trace info '%s'", "trace convert '%s' out.csv",
                                   "gaze eval --gaze 'trace:%s' --seconds 0.3", "latency --gaze 'trace:%s' --frames 20",
                                   NULL};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) check_commands(readers, bad[i], NULL);
    check("trace convert rec.csv no/such/dir/out.csv", EXPECT_FAIL, 0, "no/such/dir/out.csv", NULL, NULL);
    check("run --gaze trace:trace_missing.csv --frames 1 --eye-size 16x16", EXPECT_FAIL, F_GPU, "trace_missing.csv",
          NULL, NULL);
    /* one sample that no frame can use: the message agrees with device.samples (was "delivered no gaze sample") */
    check("latency --gaze trace:one.csv --frames 20", EXPECT_FAIL, 0, "one.csv",
          NEEDLES("delivered 1 gaze sample, but none of the 20 frames had live gaze"), "delivered no gaze sample");
    /* sim: errors blame only what the user set, once */
    check("gaze eval --gaze sim:rate_hz=100000 --seconds 0.3", EXPECT_FAIL, 0, "rate_hz", NEEDLES("rate_hz = 100000"),
          "jitter_us");
    fv_test_cmd *r = check("latency --gaze sim:ts_bits=5 --frames 10", EXPECT_FAIL, 0, "ts_bits=5", NULL, NULL);
    const char *first = strstr(r->err, "ts_bits=5 must be");
    if (!first || strstr(first + 1, "ts_bits=5 must be")) {
        if (!g_keep_going) fail_msg("the ts_bits error is not printed once:\n%s", r->err);
        print_message("FAILED CASE: latency --gaze sim:ts_bits=5: the error is not printed once\n");
        g_failed++;
    }
    check("gaze eval --gaze sim:bogus=1", EXPECT_FAIL, 0, "bogus", NEEDLES("unknown key"), NULL);
    const char *uris[] = {"trace:", "bogus:x", "hid:/nonexistent/hidraw9", "usb:zzzz:1", "sim:seed=1,rate_hz=nan"};
    const char *const gaze[] = {"gaze eval --gaze '%s' --seconds 0.3", "latency --gaze '%s' --frames 10", NULL};
    for (size_t i = 0; i < sizeof uris / sizeof uris[0]; i++) check_commands(gaze, uris[i], NULL);
    check("run --gaze sim:rate_hz=100000 --frames 1 --eye-size 16x16", EXPECT_FAIL, F_GPU, "rate_hz", NULL, "jitter_us");
}

/* ---- images ----------------------------------------------------------------------------------------------- */

static void image_files_get_clear_messages(void **state)
{
    (void)state;
    write_pfm("ok.pfm", 0.5f);
    write_text("huge.pfm", "PF\n100000 100000\n-1.0\nabcd");
    write_text("neg.pfm", "PF\n-5 12\n-1.0\n");
    write_text("junk.png", "\x89PNG\r\n\x1a\nnot really");
    mkdir(fv_test_tmp("img_dir"), 0755);
    const char *bad[] = {"huge.pfm", "neg.pfm", "junk.png", "img_dir", "img_missing.png"};
    const char *const compare[] = {"compare '%s' ok.pfm", "compare ok.pfm '%s' --json", NULL};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) check_commands(compare, bad[i], NULL);
}

static int teardown(void **state)
{
    (void)state;
    print_message("hostile corpus: %d cases in %.1f s%s\n", g_cases, g_seconds, g_keep_going ? "" : ", all passed");
    if (g_failed) print_message("%d cases FAILED\n", g_failed);
    return g_failed ? -1 : 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_hostile PATH_TO_FOVEA\n");
        return 2;
    }
    g_fovea = argv[1];
    g_keep_going = getenv("FV_HOSTILE_KEEP_GOING") && atoi(getenv("FV_HOSTILE_KEEP_GOING")) != 0;
    g_dir = strdup(fv_test_tmp(""));
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(scene_inputs_fail_fast_naming_the_file),
        cmocka_unit_test(every_json_output_is_valid_utf8_whatever_the_names),
        cmocka_unit_test(hid_files_get_clear_messages),
        cmocka_unit_test(trace_files_and_gaze_uris_get_clear_messages),
        cmocka_unit_test(image_files_get_clear_messages),
    };
    return cmocka_run_group_tests(tests, NULL, teardown);
}
