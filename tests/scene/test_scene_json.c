/* @brief `*.scene.json`: composing built-ins and model files, overrides, animation, lights, head; and every kind of
 * bad input reported with the file, the JSON path and the reason. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fovea_config.h"
#include "fv_scene.h"
#include "fv_test.h"

#define SEED_DIR FV_SOURCE_DIR "/tests/scene/seeds" /* the fuzzer's seeds, used here as examples */

static char *read_text(const char *path) { return fv_test_read_file(path, NULL); }

static const fv_mesh *mesh_named(const fv_scene *s, const char *name)
{
    for (uint32_t i = 0; i < s->mesh_count; i++)
        if (!strcmp(s->meshes[i].name, name)) return &s->meshes[i];
    return NULL;
}

static void bunny_in_marble_inside_the_cornell_box(void **state)
{
    (void)state;
    char *text = read_text(SEED_DIR "/bunny.scene.json");
    /* the seed's model path is "../bunny/bun_zipper.ply": resolve it from the shared Cornell folder */
    char base[1024];
    snprintf(base, sizeof base, "%s", fv_test_data("scenes/cornell_box"));
    fv_scene *s = NULL;
    fv_test_log_capture_begin();
    fv_result r = fv_scene_load_json_buffer(text, strlen(text), base, "bunny.scene.json", &s);
    if (r != FV_OK) fail_msg("%s; log:\n%s", fv_result_str(r), fv_test_log_text());
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_WARN), 0);
    fv_test_log_capture_end();
    free(text);
    assert_string_equal(s->name, "bunny in box");
    assert_int_equal(fv_scene_triangle_count(s), 32 + 69451);
    assert_true(fv_scene_has_translucency(s));
    assert_true(fv_scene_is_animated(s));
    /* bunny material took the marble preset; the box's walls did not */
    const fv_mesh *red = mesh_named(s, "left_wall_red");
    assert_non_null(red);
    assert_false(s->materials[red->material].translucency.enabled);
    const fv_mesh *bunny = &s->meshes[s->mesh_count - 1];
    assert_int_equal(bunny->index_count, 69451 * 3);
    assert_string_equal(s->materials[bunny->material].translucency.preset, "Marble");
    /* head from the file, IPD 63, looking towards -z */
    assert_true(s->head.from_file);
    assert_float_equal(s->head.position_m.z, 1.1f, 1e-6f);
    assert_float_equal(s->head.ipd_mm, 63.0f, 0.0f);
    /* the cornell spot plus the file's spot; no default light */
    assert_int_equal(s->light_count, 2);
    assert_float_equal(s->lights[1].outer_cone_rad, (float)fv_deg_to_rad(60.0), 1e-6f);
    /* The bunny's root node carries translate/scale/rotate and the spin: find the node drawing the bunny. */
    int32_t bn = -1;
    for (uint32_t i = 0; i < s->node_count; i++)
        if (s->nodes[i].mesh == (int32_t)(s->mesh_count - 1)) bn = (int32_t)i;
    assert_true(bn >= 0);
    const fv_node *root = &s->nodes[s->nodes[bn].parent];
    assert_string_equal(root->name, "bunny");
    assert_float_equal(root->scale.x, 1.5f, 0.0f);
    assert_int_equal(root->anim.kind, FV_ANIM_ROTATE);
    assert_float_equal(root->anim.rate_rad_s, (float)fv_deg_to_rad(30.0), 1e-6f);
    /* after 3 s the bunny has turned 90 degrees about +y around its node origin */
    fv_mat4 w0 = fv_scene_node_world(s, (uint32_t)bn, 0.0), w3 = fv_scene_node_world(s, (uint32_t)bn, 3.0);
    fv_vec3 a = fv_mat4_mul_dir(&w0, fv_v3(1, 0, 0)), b = fv_mat4_mul_dir(&w3, fv_v3(1, 0, 0));
    assert_float_equal(fv_v3_dot(a, b), 0.0f, 1e-4f);
    fv_scene_destroy(&s);
}

static void scene_file_on_disk_resolves_models_relative_to_itself(void **state)
{
    (void)state;
    char json[2048];
    snprintf(json, sizeof json,
             "{\"objects\":[{\"model\":\"%s\",\"unit_scale_m\":0.002,\"material\":{\"base_color\":[0.1,0.2,0.3]}},"
             "{\"model\":\"teapot.obj\",\"translate_m\":[0,0,-5],\"scale\":[1,2,1]}]}",
             fv_test_data("scenes/cornell_box/cornell_box_embree.obj"));
    const char *teapot = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    fv_test_write_file("teapot.obj", teapot, strlen(teapot));
    const char *path = fv_test_write_file("relative.scene.json", json, strlen(json));
    fv_scene *s = NULL;
    fv_test_log_capture_begin();
    fv_result r = fv_scene_load(path, &s);
    if (r != FV_OK) fail_msg("%s; log:\n%s", fv_result_str(r), fv_test_log_text());
    fv_test_log_capture_end();
    assert_int_equal(fv_scene_triangle_count(s), 36 + 1);
    /* override applied to every material of the first model */
    assert_float_equal(s->materials[0].base_color.z, 0.3f, 1e-6f);
    fv_vec3 lo, hi;
    assert_true(fv_scene_world_bounds(s, 0, &lo, &hi));
    assert_float_equal(hi.x, 1.112f, 0.01f); /* 556 units x 0.002 m */
    assert_float_equal(lo.z, -5.0f, 1e-5f);
    assert_false(s->head.from_file); /* framed */
    assert_true(s->light_count >= 1);  /* default light(s) */
    fv_scene_destroy(&s);
}

static void seed_with_every_light_type_and_animation_loads(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    fv_test_log_capture_begin();
    fv_result r = fv_scene_load(SEED_DIR "/lights.scene.json", &s);
    if (r != FV_OK) fail_msg("%s; log:\n%s", fv_result_str(r), fv_test_log_text());
    fv_test_log_capture_end();
    /* "lights": false dropped the translucent box's spot; the second box keeps its own */
    assert_int_equal(s->light_count, 1 + 3);
    assert_int_equal(s->lights[1].type, FV_LIGHT_POINT);
    assert_int_equal(s->lights[2].type, FV_LIGHT_DIRECTIONAL);
    assert_float_equal(s->lights[2].direction.z, -(float)sqrt(0.5), 1e-6f);
    assert_int_equal(s->lights[3].type, FV_LIGHT_SPOT);
    assert_float_equal(s->lights[3].direction.y, -(float)sqrt(0.5), 1e-6f);
    assert_true(fv_scene_has_translucency(s));
    const fv_material *m = &s->materials[0];
    assert_true(m->translucency.enabled);
    assert_float_equal(m->translucency.sigma_s_prime_per_mm[2], 3.0f, 0.0f);
    assert_float_equal(m->base_color.x, 0.9f, 1e-6f);
    assert_float_equal(s->ambient.x, 0.01f, 1e-6f);
    assert_true(fv_scene_is_animated(s));
    fv_scene_destroy(&s);
}

/* Parse `json` from memory; it must fail and the log must hold every needle. */
static void expect_error(const char *json, const char *const *needles)
{
    fv_scene *s = NULL;
    fv_test_log_capture_begin();
    fv_result r = fv_scene_load_json_buffer(json, strlen(json), "/nonexistent", "bad.scene.json", &s);
    if (r >= 0) fail_msg("loaded but should fail: %s", json);
    assert_null(s);
    fv_assert_log_contains("bad.scene.json");
    for (; *needles; needles++) fv_assert_log_contains(*needles);
    fv_test_log_capture_end();
}

static void invalid_json_reports_line_and_column(void **state)
{
    (void)state;
    const char *n1[] = {"line 3 column 14: invalid JSON (unexpected '\"')", NULL};
    expect_error("{\n  \"objects\": [\n    {\"model\" \"builtin:cornell\"}\n  ]\n}", n1);
    const char *n2[] = {"invalid JSON (unexpected end of the text)", NULL};
    expect_error("{\"objects\": [", n2);
    const char *n3[] = {"(root): expected an object, got an array", NULL};
    expect_error("[1,2]", n3);
    const char *n4[] = {"line 1 column 1: invalid JSON", NULL};
    expect_error("", n4);
}

static void unknown_preset_names_the_path_and_lists_the_known_ones(void **state)
{
    (void)state;
    const char *n[] = {"objects[1].material.translucency.preset: unknown preset 'jade'", "Marble", "Skin1", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\"},{\"model\":\"builtin:cornell\","
                 "\"material\":{\"translucency\":{\"preset\":\"jade\"}}}]}",
                 n);
}

static void negative_and_non_finite_coefficients_are_errors(void **state)
{
    (void)state;
    const char *n[] = {"objects[0].material.translucency.sigma_a_per_mm[1]: -0.5 is negative", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\",\"material\":{\"translucency\":"
                 "{\"sigma_a_per_mm\":[0.1,-0.5,0.1],\"sigma_s_prime_per_mm\":[1,1,1]}}}]}",
                 n);
    const char *inf[] = {"objects[0].material.translucency.eta: inf is not a finite number", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\",\"material\":{\"translucency\":"
                 "{\"preset\":\"marble\",\"eta\":1e999}}}]}",
                 inf);
    const char *zero[] = {"sigma_s_prime_per_mm: all three are zero", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\",\"material\":{\"translucency\":"
                 "{\"sigma_a_per_mm\":[0,0,0],\"sigma_s_prime_per_mm\":[0,0,0]}}}]}",
                 zero);
    /* a denormal (of double: 1e-310, which a float would read as 0; of float: 1e-40) is a tiny positive number
     * below the smallest coefficient, and said so with the range; above the largest likewise */
    const char *tiny[] = {"sigma_a_per_mm[0]: 1e-310 is below the smallest positive coefficient, 1e-06 mm^-1 (a "
                          "coefficient is 0 or in 1e-06..1e+06 mm^-1",
                          "sigma_s_prime_per_mm[1]: 1e-40 is below the smallest positive coefficient",
                          "sigma_s_prime_per_mm[2]: 2e+06 is more than the largest coefficient, 1e+06 mm^-1", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\",\"material\":{\"translucency\":"
                 "{\"sigma_a_per_mm\":[1e-310,0,0],\"sigma_s_prime_per_mm\":[1,1e-40,2e6]}}}]}",
                 tiny);
    const char *big[] = {"translucency.eta: 1e+300 is beyond the float range (+-3e+38)", NULL}; /* not "not finite" */
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\",\"material\":{\"translucency\":"
                 "{\"preset\":\"marble\",\"eta\":1e300}}}]}",
                 big);
    const char *eta[] = {"translucency.eta: 0 must be > 0", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\",\"material\":{\"translucency\":"
                 "{\"preset\":\"skin1\",\"eta\":0}}}]}",
                 eta);
}

static void wrong_types_name_what_was_expected_and_found(void **state)
{
    (void)state;
    const char *n1[] = {"objects[0].translate_m: expected an array of 3 numbers, got a string", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\",\"translate_m\":\"far\"}]}", n1);
    const char *n2[] = {"objects[0].scale: expected a number, got a boolean", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\",\"scale\":true}]}", n2);
    const char *n3[] = {"objects: expected an array, got an object", NULL};
    expect_error("{\"objects\":{}}", n3);
    const char *n4[] = {"lights[0].cone_deg: expected 2 numbers, got 3", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\"}],\"lights\":[{\"type\":\"spot\",\"cone_deg\":[1,2,3]}]}",
                 n4);
    const char *n5[] = {"lights[0].type: unknown light type 'laser'", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\"}],\"lights\":[{\"type\":\"laser\"}]}", n5);
    const char *n6[] = {"objects[0].model: missing", NULL};
    expect_error("{\"objects\":[{}]}", n6);
    const char *n7[] = {"objects: is empty", NULL};
    expect_error("{\"objects\":[]}", n7);
    const char *n8[] = {"head.ipd_mm: -63 must be > 0", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\"}],\"head\":{\"ipd_mm\":-63}}", n8);
    const char *n9[] = {"objects[0].animate: give one of", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\",\"animate\":{\"rotate\":{\"deg_per_s\":1},"
                 "\"bob\":{}}}]}",
                 n9);
    const char *n10[] = {"objects[0].scale[1]: 0 must be > 0", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\",\"scale\":[1,0,1]}]}", n10);
}

static void missing_model_file_and_unknown_builtin_are_errors(void **state)
{
    (void)state;
    const char *n[] = {"objects[0].model: model file '/nonexistent/nothing.ply' cannot be opened", NULL};
    expect_error("{\"objects\":[{\"model\":\"nothing.ply\"}]}", n);
    const char *b[] = {"objects[0].model: 'builtin:sponza' is not a built-in scene", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:sponza\"}]}", b);
    /* a model file that exists but the importer rejects */
    const char *junk = fv_test_write_file("junk.ply", "not a ply at all", 16);
    char json[1024];
    snprintf(json, sizeof json, "{\"objects\":[{\"model\":\"%s\"}]}", junk);
    const char *j[] = {"junk.ply: the importer rejected the file", "objects[0].model: model file", NULL};
    expect_error(json, j);
    /* missing scene file */
    fv_scene *s = NULL;
    fv_test_log_capture_begin();
    assert_int_equal(fv_scene_load(fv_test_tmp("absent.scene.json"), &s), FV_ERR_NOT_FOUND);
    fv_assert_log_contains("absent.scene.json: cannot open scene file");
    fv_test_log_capture_end();
}

static void several_errors_are_all_reported_and_unknown_keys_warn(void **state)
{
    (void)state;
    fv_scene *s = NULL;
    const char *json = "{\"objects\":[{\"model\":\"builtin:cornell\",\"colour\":[1,0,0],"
                       "\"material\":{\"translucency\":{\"preset\":\"nope\"}}},"
                       "{\"model\":\"builtin:cornell\",\"translate_m\":[0,\"x\",0]}],\"extra\":1}";
    fv_test_log_capture_begin();
    assert_int_equal(fv_scene_load_json_buffer(json, strlen(json), NULL, "multi.scene.json", &s), FV_ERR_PARSE);
    fv_assert_log_contains("warn scene: multi.scene.json: objects[0].colour: unknown key; ignored");
    fv_assert_log_contains("warn scene: multi.scene.json: extra: unknown key");
    fv_assert_log_contains("objects[0].material.translucency.preset: unknown preset 'nope'");
    fv_assert_log_contains("objects[1].translate_m[1]: expected a number, got a string");
    fv_assert_log_contains("2 problems; the scene is not loaded");
    fv_test_log_capture_end();
    assert_null(s);
    /* Unknown keys alone are only warnings: the scene loads. */
    const char *ok = "{\"objects\":[{\"model\":\"builtin:cornell\",\"shiny\":true}]}";
    fv_test_log_capture_begin();
    assert_int_equal(fv_scene_load_json_buffer(ok, strlen(ok), NULL, "warn.scene.json", &s), FV_OK);
    fv_assert_log_contains("objects[0].shiny: unknown key");
    fv_test_log_capture_end();
    assert_true(s->head.from_file); /* the built-in's head is kept */
    fv_scene_destroy(&s);
}

static void buffer_without_terminator_and_embedded_nul_are_safe(void **state)
{
    (void)state;
    /* exact-length buffer (no NUL after it: ASan would see a read past the end) */
    const char src[] = "{\"objects\":[{\"model\":\"builtin:cornell\"}]}";
    char *exact = malloc(sizeof src - 1);
    memcpy(exact, src, sizeof src - 1);
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load_json_buffer(exact, sizeof src - 1, NULL, NULL, &s), FV_OK);
    fv_scene_destroy(&s);
    /* truncated by one byte */
    fv_test_log_capture_begin();
    assert_int_equal(fv_scene_load_json_buffer(exact, sizeof src - 2, NULL, NULL, &s), FV_ERR_PARSE);
    fv_assert_log_contains("<buffer>: line 1 column");
    fv_test_log_capture_end();
    free(exact);
    const char nul[] = "{\"objects\":[{\"model\":\"builtin:\0cornell\"}]}";
    fv_test_log_capture_begin();
    assert_true(fv_scene_load_json_buffer(nul, sizeof nul - 1, NULL, NULL, &s) < 0);
    fv_test_log_capture_end();
    assert_null(s);
}

/* Build `{"objects":[ITEM,ITEM,...]}` with n copies of item (caller frees). */
static char *repeat_objects(const char *item, size_t n, const char *tail)
{
    size_t il = strlen(item), tl = strlen(tail);
    char *buf = malloc(32 + n * (il + 1) + tl);
    size_t o = (size_t)sprintf(buf, "{\"objects\":[");
    for (size_t i = 0; i < n; i++) {
        if (i) buf[o++] = ',';
        memcpy(buf + o, item, il);
        o += il;
    }
    o += (size_t)sprintf(buf + o, "]%s}", tail);
    return buf;
}

static int log_lines(void)
{
    int n = 0;
    for (const char *p = fv_test_log_text(); *p; p++) n += *p == '\n';
    return n;
}

static void a_flood_of_one_error_is_summarised_and_limits_come_before_the_work(void **state)
{
    (void)state;
    /* 200,000 objects: refused at once by the count, one line, no object loaded */
    char *json = repeat_objects("{\"model\":\"builtin:cornell\",\"bogus\":1}", 200000, "");
    fv_scene *s = NULL;
    fv_test_log_capture_begin();
    assert_int_equal(fv_scene_load_json_buffer(json, strlen(json), NULL, "flood.scene.json", &s), FV_ERR_PARSE);
    fv_assert_log_contains("flood.scene.json: objects: 200000 objects is more than the limit of 65536; none is loaded");
    if (log_lines() > 4) fail_msg("%d log lines:\n%.2000s", log_lines(), fv_test_log_text());
    fv_test_log_capture_end();
    free(json);
    /* 3000 objects with the same two mistakes: 8 of each shown, then one summary line each */
    json = repeat_objects("{\"model\":\"builtin:cornell\",\"scale\":-1,\"shiny\":true}", 3000, "");
    fv_test_log_capture_begin();
    assert_int_equal(fv_scene_load_json_buffer(json, strlen(json), NULL, "same.scene.json", &s), FV_ERR_PARSE);
    fv_assert_log_contains("objects[7].scale: -1 must be > 0");
    fv_assert_log_contains("same.scene.json: ... and 2,992 more like: same.scene.json: objects[0].scale: -1 must be > 0");
    fv_assert_log_contains("same.scene.json: ... and 2,992 more like: same.scene.json: objects[0].shiny: unknown key");
    fv_assert_log_contains("same.scene.json: 3000 problems; the scene is not loaded");
    if (strstr(fv_test_log_text(), "objects[8].scale")) fail_msg("the 9th error was shown");
    if (log_lines() > 20) fail_msg("%d log lines", log_lines());
    fv_test_log_capture_end();
    free(json);
    /* lights: the count first too */
    size_t n = 70000;
    char *lights = malloc(64 + n * 2);
    size_t o = (size_t)sprintf(lights, "{\"objects\":[{\"model\":\"builtin:cornell\"}],\"lights\":[");
    for (size_t i = 0; i < n; i++) o += (size_t)sprintf(lights + o, "%s0", i ? "," : "");
    sprintf(lights + o, "]}");
    fv_test_log_capture_begin();
    assert_int_equal(fv_scene_load_json_buffer(lights, strlen(lights), NULL, "lights.scene.json", &s), FV_ERR_PARSE);
    fv_assert_log_contains("lights: 70000 lights is more than the limit of 65536");
    if (log_lines() > 4) fail_msg("%d log lines", log_lines());
    fv_test_log_capture_end();
    free(lights);
}

static void nesting_values_and_nul_characters_are_refused_with_the_reason(void **state)
{
    (void)state;
    /* deeper than cJSON's limit: say so (it used to say "unexpected '['") */
    size_t depth = 1200;
    char *deep = malloc(2 * depth + 32);
    size_t o = (size_t)sprintf(deep, "{\"objects\":");
    for (size_t i = 0; i < depth; i++) deep[o++] = '[';
    for (size_t i = 0; i < depth; i++) deep[o++] = ']';
    sprintf(deep + o, "}");
    const char *d[] = {"line 1 column 1011: invalid JSON: nested deeper than 1000 levels (the parser's limit)", NULL};
    expect_error(deep, d);
    free(deep);
    /* a value count no scene needs, refused before cJSON builds a tree of it */
    size_t n = 5u * 1024u * 1024u;
    char *vals = malloc(2 * n + 64);
    o = (size_t)sprintf(vals, "{\"objects\":[{\"model\":\"builtin:cornell\"}],\"x\":[");
    for (size_t i = 0; i < n; i++) {
        vals[o++] = '0';
        vals[o++] = ',';
    }
    sprintf(vals + o - 1, "]}");
    const char *v[] = {"JSON values, more than the 4194304 a scene file may hold", NULL};
    expect_error(vals, v);
    free(vals);
    /* \u0000 would cut a name silently: refused, with its position */
    const char *nul = "{\"name\": \"evil\\u0000tail\",\n \"objects\": [{\"model\": \"builtin:cornell\"}]}";
    const char *z[] = {"line 1 column 15: a string holds \\u0000 (a NUL character)", NULL};
    expect_error(nul, z);
    /* an escaped backslash before u0000 is not a NUL */
    const char *fine = "{\"name\": \"a\\\\u0000\", \"objects\": [{\"model\": \"builtin:cornell\"}]}";
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load_json_buffer(fine, strlen(fine), NULL, NULL, &s), FV_OK);
    assert_string_equal(s->name, "a\\u0000");
    fv_scene_destroy(&s);
}

static void long_names_are_cut_visibly_between_utf8_characters(void **state)
{
    (void)state;
    /* 59 ASCII bytes, a 3-byte character, 2 more: 64 bytes do not fit the 64-byte name (63 and a NUL). The cut is
     * visible: 60 bytes then "...", and before the character that would not fit whole: 59 a's then "..." */
    char json[512], name[80];
    memset(name, 'a', 59);
    strcpy(name + 59, "\xe2\x82\xac" "bb");
    snprintf(json, sizeof json, "{\"name\":\"%s\",\"objects\":[{\"model\":\"builtin:cornell\"}]}", name);
    fv_scene *s = NULL;
    assert_int_equal(fv_scene_load_json_buffer(json, strlen(json), NULL, NULL, &s), FV_OK);
    assert_int_equal(strlen(s->name), 62);
    assert_string_equal(s->name + 59, "...");
    fv_scene_destroy(&s);
    /* 63 bytes fit whole */
    memset(name, 'b', 63);
    name[63] = '\0';
    snprintf(json, sizeof json, "{\"name\":\"%s\",\"objects\":[{\"model\":\"builtin:cornell\"}]}", name);
    assert_int_equal(fv_scene_load_json_buffer(json, strlen(json), NULL, NULL, &s), FV_OK);
    assert_string_equal(s->name, name);
    fv_scene_destroy(&s);
}

/* A model path that does not fit FV_SCENE_PATH_MAX was cut, and the cut named another file that exists: it loaded
 * that file. Now the path is refused, naming the field, its length and the limit. An empty model says so. */
static void long_model_paths_are_refused_not_cut_and_empty_ones_named(void **state)
{
    (void)state;
    const char *tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const char *file = fv_test_write_file("cut_target.obj", tri, strlen(tri));
    const char *slash = strrchr(file, '/');
    char prefix[FV_SCENE_PATH_MAX + 1], model[FV_SCENE_PATH_MAX + 64], json[FV_SCENE_PATH_MAX + 256];
    /* "<dir>/././.../cut_target.obj" of exactly FV_SCENE_PATH_MAX - 1 bytes: what the cut would leave */
    size_t dir_len = (size_t)(slash - file), name_len = strlen(slash);
    size_t pad = FV_SCENE_PATH_MAX - 1 - dir_len - name_len;
    assert_true(pad >= 2);
    memcpy(prefix, file, dir_len);
    size_t n = dir_len;
    if (pad % 2) prefix[n++] = '/';
    for (size_t i = 0; i < pad / 2; i++, n += 2) memcpy(prefix + n, "/.", 2);
    memcpy(prefix + n, slash, name_len + 1);
    assert_int_equal(strlen(prefix), FV_SCENE_PATH_MAX - 1);
    snprintf(model, sizeof model, "%s/../missing.obj", prefix);
    snprintf(json, sizeof json, "{\"objects\":[{\"model\":\"%s\"}]}", model);
    char want[160];
    snprintf(want, sizeof want, "objects[0].model: the model path is %zu bytes, more than the %d-byte limit",
             strlen(model), FV_SCENE_PATH_MAX - 1);
    const char *cut[] = {want, NULL};
    expect_error(json, cut);
    /* the same for a relative path joined to the scene file's folder */
    snprintf(json, sizeof json, "{\"objects\":[{\"model\":\"%s\"}]}", prefix + 1);
    const char *joined[] = {"objects[0].model: the model path is", "once joined to the scene file's folder", NULL};
    expect_error(json, joined);
    const char *empty[] = {"objects[0].model: is empty (a model file or \"builtin:NAME\")", NULL};
    expect_error("{\"objects\":[{\"model\":\"\"}]}", empty);
}

/* A head at 1e20 m loaded, and `fovea reference` then aborted inside Embree: every position and size that becomes
 * geometry is checked against FV_SCENE_MAX_COORD_M, naming the field, the value and the bound. Within the bound per
 * field but beyond it once composed (a model moved to the edge), the loader's check names the node. */
static void positions_and_sizes_beyond_the_bound_are_refused(void **state)
{
    (void)state;
    const char *head[] = {"head.position_m[2]: 1e+20 m is outside -1e+06..1e+06 m, the bound of a position", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\"}],\"head\":{\"position_m\":[0,0,1e20]}}", head);
    const char *fields[] = {"objects[0].translate_m[0]: -2e+06 m is outside -1e+06..1e+06 m",
                            "objects[0].scale: 1e+07 is more than 1e+06, the largest scale",
                            "objects[1].unit_scale_m: 1e+09 is more than 1e+06",
                            "objects[1].animate.bob.amplitude_m[1]: 1e+08 m is outside",
                            "lights[0].position_m[1]: 3e+07 m is outside",
                            "lights[0].look_at_m[0]: 1e+30 m is outside",
                            "head.look_at_m[2]: -1e+07 m is outside", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\",\"translate_m\":[-2e6,0,0],\"scale\":1e7},"
                 "{\"model\":\"builtin:cornell\",\"unit_scale_m\":1e9,\"animate\":{\"bob\":{\"amplitude_m\":[0,1e8,0]}}}],"
                 "\"lights\":[{\"type\":\"spot\",\"position_m\":[0,3e7,0],\"look_at_m\":[1e30,0,0]}],"
                 "\"head\":{\"position_m\":[0,0,1],\"look_at_m\":[0,0,-1e7]}}",
                 fields);
    const char *composed[] = {"mesh '", "in world space (m): ", "is beyond the +-1e+06 m bound", NULL};
    expect_error("{\"objects\":[{\"model\":\"builtin:cornell\",\"translate_m\":[999999,0,0],\"scale\":1000}],"
                 "\"head\":{\"position_m\":[0,0,1]}}",
                 composed);
    /* the bounds themselves load */
    const char *ok = "{\"objects\":[{\"model\":\"builtin:cornell\",\"translate_m\":[-999000,0,0]}],"
                     "\"lights\":[{\"type\":\"point\",\"position_m\":[0,1e6,0]}],\"head\":{\"position_m\":[-1e6,0,1]}}";
    fv_scene *s = NULL;
    fv_test_log_capture_begin();
    fv_result r = fv_scene_load_json_buffer(ok, strlen(ok), NULL, "ok.scene.json", &s);
    if (r != FV_OK) fail_msg("%s; log:\n%s", fv_result_str(r), fv_test_log_text());
    fv_test_log_capture_end();
    assert_int_equal(fv_scene_check_extent(s), FV_OK);
    uint32_t last = s->light_count - 1; /* the file's light, after the built-in's own */
    s->lights[last].position_m.y = 1.0001e6f; /* a scene changed in code: the same check */
    fv_test_log_capture_begin();
    assert_int_equal(fv_scene_check_extent(s), FV_ERR_RANGE);
    char want[128];
    snprintf(want, sizeof want, "light %u 'light0': position (m): 1.0001e+06 is beyond the +-1e+06 m bound", last);
    fv_assert_log_contains(want);
    fv_test_log_capture_end();
    fv_scene_destroy(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bunny_in_marble_inside_the_cornell_box),
        cmocka_unit_test(scene_file_on_disk_resolves_models_relative_to_itself),
        cmocka_unit_test(seed_with_every_light_type_and_animation_loads),
        cmocka_unit_test(invalid_json_reports_line_and_column),
        cmocka_unit_test(unknown_preset_names_the_path_and_lists_the_known_ones),
        cmocka_unit_test(negative_and_non_finite_coefficients_are_errors),
        cmocka_unit_test(wrong_types_name_what_was_expected_and_found),
        cmocka_unit_test(missing_model_file_and_unknown_builtin_are_errors),
        cmocka_unit_test(several_errors_are_all_reported_and_unknown_keys_warn),
        cmocka_unit_test(buffer_without_terminator_and_embedded_nul_are_safe),
        cmocka_unit_test(a_flood_of_one_error_is_summarised_and_limits_come_before_the_work),
        cmocka_unit_test(nesting_values_and_nul_characters_are_refused_with_the_reason),
        cmocka_unit_test(long_names_are_cut_visibly_between_utf8_characters),
        cmocka_unit_test(long_model_paths_are_refused_not_cut_and_empty_ones_named),
        cmocka_unit_test(positions_and_sizes_beyond_the_bound_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
