/* @brief glTF 2.0 import on files written at run time into the test's temp dir: KHR_lights_punctual lights
 * (point, spot cone half-angles, directional, candela -> W/sr, range and its validation), a camera becoming the
 * head (yfov), a .glb against its equivalent .gltf, textures embedded as a data: URI, in a bufferView and in a
 * .glb's BIN chunk, an external PNG next to the .gltf, and a missing PNG that falls back to the base colour with a
 * warning naming it. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>

#include "fv_scene.h"
#include "fv_test.h"

/* glTF candela and lux to W/sr and W/m^2 (fv_light in fv_scene.h). */
#define LM_PER_W FV_SCENE_LUMENS_PER_WATT

/* ---- bytes ------------------------------------------------------------------------------------------------ */

typedef struct bytes {
    unsigned char *p;
    size_t n, cap;
} bytes;

static void put(bytes *b, const void *src, size_t n)
{
    if (b->n + n > b->cap) {
        size_t cap = b->cap ? b->cap : 256;
        while (cap < b->n + n) cap *= 2;
        unsigned char *p = realloc(b->p, cap);
        assert_non_null(p);
        b->p = p;
        b->cap = cap;
    }
    if (n) memcpy(b->p + b->n, src, n);
    b->n += n;
}

static void put_u32le(bytes *b, uint32_t v)
{
    unsigned char le[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16),
                           (unsigned char)(v >> 24)};
    put(b, le, 4);
}

static void pad4(bytes *b, unsigned char fill)
{
    while (b->n % 4) put(b, &fill, 1);
}

static void bytes_free(bytes *b)
{
    free(b->p);
    memset(b, 0, sizeof *b);
}

/* printf into a fresh malloc'd string. */
static char *fmt(const char *f, ...)
{
    va_list ap;
    va_start(ap, f);
    int n = vsnprintf(NULL, 0, f, ap);
    va_end(ap);
    assert_true(n >= 0);
    char *s = malloc((size_t)n + 1);
    assert_non_null(s);
    va_start(ap, f);
    vsnprintf(s, (size_t)n + 1, f, ap);
    va_end(ap);
    return s;
}

static char *base64(const unsigned char *p, size_t n)
{
    static const char a[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char *s = malloc((n + 2) / 3 * 4 + 1);
    assert_non_null(s);
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)p[i] << 16 | (i + 1 < n ? (uint32_t)p[i + 1] << 8 : 0) | (i + 2 < n ? p[i + 2] : 0);
        s[o++] = a[v >> 18 & 63];
        s[o++] = a[v >> 12 & 63];
        s[o++] = i + 1 < n ? a[v >> 6 & 63] : '=';
        s[o++] = i + 2 < n ? a[v & 63] : '=';
    }
    s[o] = '\0';
    return s;
}

/* ---- the test image: 4x2 RGBA, every texel distinct, one half transparent --------------------------------- */

#define TEX_W 4
#define TEX_H 2

static void texel(int x, int y, unsigned char out[4])
{
    out[0] = (unsigned char)(10 + 60 * x);
    out[1] = (unsigned char)(30 + 150 * y);
    out[2] = (unsigned char)(250 - 50 * x - 20 * y);
    out[3] = (x == 3 && y == 1) ? 128 : 255;
}

static void image_pixels(unsigned char px[TEX_W * TEX_H * 4])
{
    for (int y = 0; y < TEX_H; y++)
        for (int x = 0; x < TEX_W; x++) texel(x, y, &px[(y * TEX_W + x) * 4]);
}

static void png_sink(void *ctx, void *data, int size) { put(ctx, data, (size_t)size); }

static void make_png(bytes *out)
{
    unsigned char px[TEX_W * TEX_H * 4];
    image_pixels(px);
    assert_true(stbi_write_png_to_func(png_sink, out, TEX_W, TEX_H, 4, px, TEX_W * 4) != 0);
}

static void assert_texture_is_the_test_image(const fv_texture *t)
{
    assert_int_equal(t->width, TEX_W);
    assert_int_equal(t->height, TEX_H);
    assert_non_null(t->rgba8);
    static const int probe[][2] = {{0, 0}, {3, 0}, {1, 1}, {3, 1}}; /* corners, a middle one, the translucent one */
    for (size_t i = 0; i < sizeof probe / sizeof probe[0]; i++) {
        int x = probe[i][0], y = probe[i][1];
        unsigned char want[4];
        texel(x, y, want);
        const unsigned char *got = &t->rgba8[(y * TEX_W + x) * 4];
        if (memcmp(got, want, 4) != 0)
            fail_msg("%s texel (%d,%d) is %u,%u,%u,%u, want %u,%u,%u,%u", t->source, x, y, got[0], got[1], got[2],
                     got[3], want[0], want[1], want[2], want[3]);
    }
}

/* ---- geometry: one quad (2 triangles) with texture coordinates, drawn by two nodes ------------------------- */

static const float quad_pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
static const float quad_uv[8] = {0.0f, 1.0f, 1.0f, 1.0f, 1.0f, 0.0f, 0.25f, 0.0f}; /* glTF: origin top left */
static const uint16_t quad_idx[6] = {0, 1, 2, 0, 2, 3};
#define GEOM_BYTES 92u /* 48 positions + 32 uvs + 12 indices; a multiple of 4, so an image can follow */

static void put_geometry(bytes *b)
{
    put(b, quad_pos, sizeof quad_pos);
    put(b, quad_uv, sizeof quad_uv);
    put(b, quad_idx, sizeof quad_idx);
    assert_int_equal(b->n % 4, 0);
}

#define GEOM_VIEWS                                                                                                     \
    "{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48,\"target\":34962},"                                              \
    "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":32,\"target\":34962},"                                             \
    "{\"buffer\":0,\"byteOffset\":80,\"byteLength\":12,\"target\":34963}"
#define GEOM_ACCESSORS                                                                                                 \
    "\"accessors\":["                                                                                                  \
    "{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[-1,-1,0],\"max\":[1,1,0]},"       \
    "{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},"                                         \
    "{\"bufferView\":2,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]"
#define QUAD_MESH                                                                                                      \
    "\"meshes\":[{\"name\":\"quad\",\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},"               \
    "\"indices\":2,\"material\":0}]}]"
#define ASSET "\"asset\":{\"version\":\"2.0\",\"generator\":\"fovea test_scene_gltf\"}"

static char *data_uri(const char *mime, const unsigned char *p, size_t n)
{
    char *b64 = base64(p, n);
    char *s = fmt("data:%s;base64,%s", mime, b64);
    free(b64);
    return s;
}

/* A textured-quad glTF document: `images` is the images array body, `image_view` an extra bufferView (or ""),
 * `buffer` the buffers array body. Material base colour (0.8, 0.6, 0.4) times texture 0. */
static char *textured_json(const char *images, const char *image_view, const char *buffer)
{
    return fmt("{" ASSET ",\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
               "\"nodes\":[{\"name\":\"left\",\"mesh\":0},{\"name\":\"right\",\"mesh\":0,\"translation\":[3,0,0]}],"
               QUAD_MESH ","
               "\"materials\":[{\"name\":\"painted\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.8,0.6,0.4,1],"
               "\"baseColorTexture\":{\"index\":0},\"metallicFactor\":0}}],"
               "\"samplers\":[{\"magFilter\":9728,\"minFilter\":9728}],"
               "\"textures\":[{\"sampler\":0,\"source\":0}],\"images\":[%s],"
               "\"bufferViews\":[" GEOM_VIEWS "%s],\"buffers\":[%s]," GEOM_ACCESSORS "}",
               images, image_view, buffer);
}

/* Assemble a binary glTF: header, JSON chunk (space padded), BIN chunk (zero padded). */
static const char *write_glb(const char *name, const char *json, const bytes *bin)
{
    bytes j = {0}, g = {0};
    put(&j, json, strlen(json));
    pad4(&j, ' ');
    bytes b = {0};
    put(&b, bin->p, bin->n);
    pad4(&b, 0);
    put(&g, "glTF", 4);
    put_u32le(&g, 2);
    put_u32le(&g, (uint32_t)(12 + 8 + j.n + 8 + b.n));
    put_u32le(&g, (uint32_t)j.n);
    put_u32le(&g, 0x4E4F534Au); /* "JSON" */
    put(&g, j.p, j.n);
    put_u32le(&g, (uint32_t)b.n);
    put_u32le(&g, 0x004E4942u); /* "BIN\0" */
    put(&g, b.p, b.n);
    const char *path = fv_test_write_file(name, g.p, g.n);
    bytes_free(&j);
    bytes_free(&b);
    bytes_free(&g);
    return path;
}

static const char *write_text(const char *name, char *owned_json)
{
    const char *path = fv_test_write_file(name, owned_json, strlen(owned_json));
    free(owned_json);
    return path;
}

/* Warnings an import gives for what it adjusts on purpose (one line each): a light added to a file without one,
 * the head moved to show what the file's camera framed. Any other warning is unexpected. */
static int expected_adjustments(const char *log)
{
    int n = 0;
    for (const char *p = log; (p = strstr(p, "no light in the file; added")); p++) n++;
    for (const char *p = log; (p = strstr(p, "frames the model for a")); p++) n++;
    return n;
}

/* Load a file that must import without an error or a warning (other than the adjustments above). */
static fv_scene *load_clean(const char *path)
{
    fv_scene *s = NULL;
    fv_test_log_capture_begin();
    fv_result r = fv_scene_load(path, &s);
    if (r != FV_OK) fail_msg("%s: %s; log:\n%s", path, fv_result_str(r), fv_test_log_text());
    if (fv_test_log_count(FV_LOG_LEVEL_WARN) != expected_adjustments(fv_test_log_text()))
        fail_msg("%s: unexpected warnings:\n%s", path, fv_test_log_text());
    fv_test_log_capture_end();
    assert_non_null(s);
    assert_int_equal(fv_scene_validate(s), FV_OK);
    return s;
}

static void assert_v3_near(fv_vec3 got, fv_vec3 want, float tol, const char *what)
{
    if (!(fabsf(got.x - want.x) <= tol && fabsf(got.y - want.y) <= tol && fabsf(got.z - want.z) <= tol))
        fail_msg("%s is (%.6f, %.6f, %.6f), want (%.6f, %.6f, %.6f) within %g", what, (double)got.x, (double)got.y,
                 (double)got.z, (double)want.x, (double)want.y, (double)want.z, (double)tol);
}

static const fv_material *material_named(const fv_scene *s, const char *name)
{
    for (uint32_t i = 0; i < s->material_count; i++)
        if (!strcmp(s->materials[i].name, name)) return &s->materials[i];
    fail_msg("no material '%s'", name);
    return NULL;
}

/* The textured quad as imported: 4 triangles drawn, material 'painted' with its factor and the test image, and
 * every vertex's texture coordinate as written (top-left origin kept). */
static void assert_textured_quad(const fv_scene *s, const char *want_source_suffix)
{
    assert_int_equal(fv_scene_triangle_count(s), 4);
    const fv_material *m = material_named(s, "painted");
    assert_v3_near(m->base_color, fv_v3(0.8f, 0.6f, 0.4f), 1e-6f, "base colour");
    assert_true(m->base_color_texture >= 0);
    assert_true((uint32_t)m->base_color_texture < s->texture_count);
    const fv_texture *t = &s->textures[m->base_color_texture];
    size_t ls = strlen(t->source), lw = strlen(want_source_suffix);
    if (ls < lw || strcmp(t->source + ls - lw, want_source_suffix))
        fail_msg("texture source '%s' does not end with '%s'", t->source, want_source_suffix);
    assert_texture_is_the_test_image(t);
    assert_int_equal(s->mesh_count, 1);
    const fv_mesh *mesh = &s->meshes[0];
    assert_int_equal(mesh->material, (uint32_t)(m - s->materials));
    assert_int_equal(mesh->vertex_count, 4);
    assert_non_null(mesh->texcoords);
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        int k = -1;
        for (int q = 0; q < 4; q++)
            if (mesh->positions[v].x == quad_pos[q * 3] && mesh->positions[v].y == quad_pos[q * 3 + 1]) k = q;
        assert_true(k >= 0);
        assert_float_equal(mesh->texcoords[v].x, quad_uv[k * 2], 1e-6f);
        assert_float_equal(mesh->texcoords[v].y, quad_uv[k * 2 + 1], 1e-6f);
    }
}

/* ---- lights ----------------------------------------------------------------------------------------------- */

static const fv_light *light_named(const fv_scene *s, const char *name)
{
    for (uint32_t i = 0; i < s->light_count; i++)
        if (!strcmp(s->lights[i].name, name)) return &s->lights[i];
    fail_msg("no light '%s'", name);
    return NULL;
}

static void khr_lights_punctual_keep_type_pose_cone_half_angles_and_intensity_in_w_per_sr(void **state)
{
    (void)state;
    bytes geom = {0};
    put_geometry(&geom);
    char *buf = data_uri("application/octet-stream", geom.p, geom.n);
    /* The sun travels along (0, -0.6, -0.8): the node's -z turned about x by asin(-0.6). */
    double th = asin(-0.6);
    char *json = fmt(
        "{" ASSET ",\"extensionsUsed\":[\"KHR_lights_punctual\"],"
        "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":["
        "{\"name\":\"bulb\",\"type\":\"point\",\"color\":[1,0.5,0.25],\"intensity\":1366,\"range\":4.5},"
        "{\"name\":\"torch\",\"type\":\"spot\",\"color\":[0.2,1,0.6],\"intensity\":3415,\"range\":12,"
        "\"spot\":{\"innerConeAngle\":0.3,\"outerConeAngle\":0.6}},"
        "{\"name\":\"sun\",\"type\":\"directional\",\"color\":[1,1,1],\"intensity\":2049,\"range\":7},"
        "{\"name\":\"grey\",\"type\":\"point\",\"color\":[0.5,0.5,0.5],\"intensity\":683},"
        "{\"name\":\"plain\",\"type\":\"spot\",\"intensity\":683,\"spot\":{}}]}},"
        "\"scene\":0,\"scenes\":[{\"nodes\":[0,1,2,3,5,6]}],\"nodes\":["
        "{\"name\":\"quad\",\"mesh\":0},"
        "{\"name\":\"BulbNode\",\"translation\":[1,2,3],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
        "{\"name\":\"TorchNode\",\"translation\":[0,3,0],\"rotation\":[-0.70710678118654752,0,0,0.70710678118654752],"
        "\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}},"
        "{\"name\":\"SunNode\",\"rotation\":[%.17g,0,0,%.17g],\"extensions\":{\"KHR_lights_punctual\":{\"light\":2}}},"
        "{\"name\":\"GreyNode\",\"translation\":[-2,1,0],\"extensions\":{\"KHR_lights_punctual\":{\"light\":3}}},"
        "{\"name\":\"LampRig\",\"translation\":[0,0,-5],\"children\":[4]},"
        "{\"name\":\"PlainNode\",\"translation\":[0,1,0],\"extensions\":{\"KHR_lights_punctual\":{\"light\":4}}}],"
        QUAD_MESH ",\"materials\":[{\"name\":\"grey\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.5,0.5,0.5,1]}}],"
        "\"bufferViews\":[" GEOM_VIEWS "],\"buffers\":[{\"byteLength\":%u,\"uri\":\"%s\"}]," GEOM_ACCESSORS "}",
        sin(th / 2), cos(th / 2), GEOM_BYTES, buf);
    free(buf);
    bytes_free(&geom);
    fv_scene *s = load_clean(write_text("lights.gltf", json));
    assert_int_equal(s->light_count, 5); /* no default light added */

    const fv_light *l = light_named(s, "BulbNode");
    assert_int_equal(l->type, FV_LIGHT_POINT);
    assert_v3_near(l->position_m, fv_v3(1, 2, 3), 1e-5f, "bulb position");
    assert_v3_near(l->color, fv_v3(1, 0.5f, 0.25f), 1e-6f, "bulb colour");
    assert_float_equal(l->intensity, 1366.0f / LM_PER_W, 1e-5f); /* 1366 cd = 2 W/sr */
    assert_float_equal(l->range_m, 4.5f, 1e-6f);                  /* glTF range, metres */

    l = light_named(s, "TorchNode");
    assert_int_equal(l->type, FV_LIGHT_SPOT);
    assert_v3_near(l->position_m, fv_v3(0, 3, 0), 1e-5f, "torch position");
    assert_v3_near(l->direction, fv_v3(0, -1, 0), 1e-5f, "torch direction");
    /* glTF cone angles are half-angles from the axis, as fv_light's */
    assert_float_equal(l->inner_cone_rad, 0.3f, 1e-6f);
    assert_float_equal(l->outer_cone_rad, 0.6f, 1e-6f);
    assert_v3_near(l->color, fv_v3(0.2f, 1, 0.6f), 1e-6f, "torch colour");
    assert_float_equal(l->intensity, 5.0f, 1e-5f);
    assert_float_equal(l->range_m, 12.0f, 1e-6f);

    l = light_named(s, "SunNode");
    assert_int_equal(l->type, FV_LIGHT_DIRECTIONAL);
    assert_v3_near(l->direction, fv_v3(0, -0.6f, -0.8f), 1e-5f, "sun direction");
    assert_v3_near(l->color, fv_v3(1, 1, 1), 1e-6f, "sun colour");
    assert_float_equal(l->intensity, 3.0f, 1e-5f); /* 2049 lux = 3 W/m^2 */
    assert_float_equal(l->range_m, 0.0f, 0.0f);    /* glTF range is for point and spot lights only */

    /* Under a translated parent; assimp folds intensity into the colour, so only colour x intensity survives:
     * it comes back as a unit-peak colour and the scale. */
    l = light_named(s, "GreyNode");
    assert_int_equal(l->type, FV_LIGHT_POINT);
    assert_v3_near(l->position_m, fv_v3(-2, 1, -5), 1e-5f, "grey position");
    assert_v3_near(fv_v3_scale(l->color, l->intensity), fv_v3(0.5f, 0.5f, 0.5f), 1e-6f, "grey colour x intensity");
    assert_float_equal(fmaxf(l->color.x, fmaxf(l->color.y, l->color.z)), 1.0f, 1e-6f);
    assert_float_equal(l->range_m, 0.0f, 0.0f); /* no range: infinite */

    /* An empty "spot" block: the glTF defaults, inner 0 and outer pi/4; no colour: white. */
    l = light_named(s, "PlainNode");
    assert_int_equal(l->type, FV_LIGHT_SPOT);
    assert_v3_near(l->position_m, fv_v3(0, 1, 0), 1e-5f, "plain position");
    assert_v3_near(l->direction, fv_v3(0, 0, -1), 1e-6f, "plain direction");
    assert_float_equal(l->inner_cone_rad, 0.0f, 1e-6f);
    assert_float_equal(l->outer_cone_rad, (float)(FV_PI / 4), 1e-6f);
    assert_v3_near(l->color, fv_v3(1, 1, 1), 1e-6f, "plain colour");
    assert_float_equal(l->intensity, 1.0f, 1e-5f);
    fv_scene_destroy(&s);
}

/* A glTF light range that is not > 0 is ignored (infinite) with a warning naming the file and the light index; a
 * valid one is scaled by the unit scale with everything else. */
static void gltf_light_range_not_above_zero_warns_and_a_valid_one_follows_the_unit_scale(void **state)
{
    (void)state;
    bytes geom = {0};
    put_geometry(&geom);
    char *buf = data_uri("application/octet-stream", geom.p, geom.n);
    char *json = fmt(
        "{" ASSET ",\"extensionsUsed\":[\"KHR_lights_punctual\"],"
        "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":["
        "{\"name\":\"neg\",\"type\":\"point\",\"intensity\":683,\"range\":-2},"
        "{\"name\":\"zero\",\"type\":\"spot\",\"intensity\":683,\"range\":0,\"spot\":{}},"
        "{\"name\":\"good\",\"type\":\"point\",\"intensity\":683,\"range\":250}]}},"
        "\"scene\":0,\"scenes\":[{\"nodes\":[0,1,2,3]}],\"nodes\":["
        "{\"name\":\"quad\",\"mesh\":0},"
        "{\"name\":\"NegNode\",\"translation\":[0,1,0],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
        "{\"name\":\"ZeroNode\",\"translation\":[0,2,0],\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}},"
        "{\"name\":\"GoodNode\",\"translation\":[0,3,0],\"extensions\":{\"KHR_lights_punctual\":{\"light\":2}}}],"
        QUAD_MESH ",\"materials\":[{\"name\":\"grey\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.5,0.5,0.5,1]}}],"
        "\"bufferViews\":[" GEOM_VIEWS "],\"buffers\":[{\"byteLength\":%u,\"uri\":\"%s\"}]," GEOM_ACCESSORS "}",
        GEOM_BYTES, buf);
    free(buf);
    bytes_free(&geom);
    const char *path = write_text("light_range.gltf", json);

    fv_scene *s = NULL;
    fv_test_log_capture_begin();
    fv_result r = fv_scene_load(path, &s);
    if (r != FV_OK) fail_msg("%s: %s; log:\n%s", path, fv_result_str(r), fv_test_log_text());
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_WARN), 2);
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_ERROR), 0);
    fv_assert_log_contains("light_range.gltf");
    fv_assert_log_contains("KHR_lights_punctual light 0");
    fv_assert_log_contains("KHR_lights_punctual light 1");
    if (strstr(fv_test_log_text(), "light 2")) fail_msg("valid range warned about:\n%s", fv_test_log_text());
    fv_test_log_capture_end();
    assert_int_equal(s->light_count, 3);
    assert_float_equal(light_named(s, "NegNode")->range_m, 0.0f, 0.0f);
    assert_float_equal(light_named(s, "ZeroNode")->range_m, 0.0f, 0.0f);
    assert_float_equal(light_named(s, "GoodNode")->range_m, 250.0f, 1e-4f);
    assert_int_equal(fv_scene_validate(s), FV_OK);
    fv_scene_destroy(&s);

    /* File in centimetres: 250 units of range are 2.5 m, as the light's position is scaled. */
    fv_test_log_capture_begin();
    r = fv_scene_import(path, 0.01f, &s);
    if (r != FV_OK) fail_msg("%s: %s; log:\n%s", path, fv_result_str(r), fv_test_log_text());
    fv_test_log_capture_end();
    const fv_light *l = light_named(s, "GoodNode");
    assert_float_equal(l->range_m, 2.5f, 1e-5f);
    assert_v3_near(l->position_m, fv_v3(0, 0.03f, 0), 1e-6f, "scaled light position");
    assert_int_equal(fv_scene_validate(s), FV_OK);
    fv_scene_destroy(&s);
}

/* ---- camera ----------------------------------------------------------------------------------------------- */

static void gltf_camera_becomes_the_head_with_its_pose_and_yfov(void **state)
{
    (void)state;
    bytes geom = {0};
    put_geometry(&geom);
    char *buf = data_uri("application/octet-stream", geom.p, geom.n);
    bytes_free(&geom);
    /* yfov, aspectRatio (0 = left out: optional in glTF) */
    static const double cases[][2] = {{0.8, 1.5}, {1.2, 2.5}, {0.5, 0.0}, {1.0, 0.75}};
    const double yaw = fv_deg_to_rad(30.0);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        double yfov = cases[i][0], aspect = cases[i][1];
        char aspect_json[64] = "";
        if (aspect > 0) snprintf(aspect_json, sizeof aspect_json, "\"aspectRatio\":%.17g,", aspect);
        /* The camera sits under a translated rig, itself translated and turned 30 degrees about +y. */
        char *json = fmt("{" ASSET ",\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],\"nodes\":["
                         "{\"name\":\"quad\",\"mesh\":0},"
                         "{\"name\":\"Rig\",\"translation\":[0,1,0],\"children\":[2]},"
                         "{\"name\":\"Cam\",\"camera\":0,\"translation\":[0.5,0.5,4],\"rotation\":[0,%.17g,0,%.17g]}],"
                         "\"cameras\":[{\"name\":\"eye\",\"type\":\"perspective\",\"perspective\":{%s\"yfov\":%.17g,"
                         "\"znear\":0.05,\"zfar\":100}}]," QUAD_MESH ","
                         "\"materials\":[{\"name\":\"grey\"}],"
                         "\"bufferViews\":[" GEOM_VIEWS "],\"buffers\":[{\"byteLength\":%u,\"uri\":\"%s\"}],"
                         GEOM_ACCESSORS "}",
                         sin(yaw / 2), cos(yaw / 2), aspect_json, yfov, GEOM_BYTES, buf);
        char name[32];
        snprintf(name, sizeof name, "camera%zu.gltf", i);
        fv_scene *s = load_clean(write_text(name, json));
        assert_int_equal(s->camera_count, 1);
        assert_true(s->head.from_file);
        assert_v3_near(s->cameras[0].position_m, fv_v3(0.5f, 1.5f, 4.0f), 1e-5f, "camera position");
        fv_vec3 fwd = fv_quat_rotate(s->head.orientation, fv_v3(0, 0, -1));
        fv_vec3 up = fv_quat_rotate(s->head.orientation, fv_v3(0, 1, 0));
        assert_v3_near(fwd, fv_v3(-(float)sin(yaw), 0, -(float)cos(yaw)), 1e-5f, "head forward");
        assert_v3_near(up, fv_v3(0, 1, 0), 1e-5f, "head up");
        /* the head looks as the camera does, from the camera or from closer along its view (its field of view
         * honoured: the HMD's is wider) */
        fv_vec3 moved = fv_v3_sub(s->head.position_m, s->cameras[0].position_m);
        float along = fv_v3_dot(moved, fwd);
        assert_true(along >= -1e-5f);
        assert_v3_near(moved, fv_v3_scale(fwd, along), 1e-4f, "head on the camera's line of sight");
        if (fabs(s->cameras[0].yfov_rad - yfov) > 1e-4)
            fail_msg("case %zu (aspect %g): yfov %.6f, want %.6f", i, aspect, (double)s->cameras[0].yfov_rad, yfov);
        assert_float_equal(s->cameras[0].near_m, 0.05f, 1e-7f);
        assert_float_equal(s->cameras[0].far_m, 100.0f, 1e-4f);
        fv_scene_destroy(&s);
    }
    free(buf);
}

/* ---- textures --------------------------------------------------------------------------------------------- */

static void png_embedded_as_a_data_uri_decodes_to_the_pixels_written(void **state)
{
    (void)state;
    bytes geom = {0}, png = {0};
    put_geometry(&geom);
    make_png(&png);
    char *img = data_uri("image/png", png.p, png.n);
    char *images = fmt("{\"uri\":\"%s\"}", img);
    char *buf = data_uri("application/octet-stream", geom.p, geom.n);
    char *buffer = fmt("{\"byteLength\":%zu,\"uri\":\"%s\"}", geom.n, buf);
    fv_scene *s = load_clean(write_text("embedded_uri.gltf", textured_json(images, "", buffer)));
    assert_textured_quad(s, "embedded:0");
    assert_int_equal(s->texture_count, 1);
    fv_scene_destroy(&s);
    free(img);
    free(images);
    free(buf);
    free(buffer);
    bytes_free(&geom);
    bytes_free(&png);
}

static void glb_with_an_embedded_png_loads_as_its_equivalent_gltf(void **state)
{
    (void)state;
    bytes bin = {0}, png = {0};
    put_geometry(&bin);
    make_png(&png);
    size_t png_offset = bin.n;
    put(&bin, png.p, png.n);
    pad4(&bin, 0);
    char *view = fmt(",{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}", png_offset, png.n);
    const char *images = "{\"bufferView\":3,\"mimeType\":\"image/png\"}";

    /* .gltf: the same bytes as a base64 buffer, the image in a bufferView of it */
    char *b64 = data_uri("application/octet-stream", bin.p, bin.n);
    char *buffer = fmt("{\"byteLength\":%zu,\"uri\":\"%s\"}", bin.n, b64);
    fv_scene *text = load_clean(write_text("embedded_view.gltf", textured_json(images, view, buffer)));
    assert_textured_quad(text, "embedded:0");

    /* .glb: no uri, the buffer is the BIN chunk */
    char *glb_buffer = fmt("{\"byteLength\":%zu}", bin.n);
    char *json = textured_json(images, view, glb_buffer);
    fv_scene *glb = load_clean(write_glb("embedded.glb", json, &bin));
    assert_textured_quad(glb, "embedded:0");

    assert_int_equal(fv_scene_triangle_count(glb), fv_scene_triangle_count(text));
    assert_int_equal(glb->material_count, text->material_count);
    assert_int_equal(glb->texture_count, text->texture_count);
    assert_int_equal(glb->node_count, text->node_count);
    const fv_material *mg = material_named(glb, "painted"), *mt = material_named(text, "painted");
    assert_v3_near(mg->base_color, mt->base_color, 0.0f, "glb base colour against gltf");
    assert_memory_equal(glb->textures[mg->base_color_texture].rgba8, text->textures[mt->base_color_texture].rgba8,
                        TEX_W * TEX_H * 4);
    fv_vec3 lo_g, hi_g, lo_t, hi_t;
    assert_true(fv_scene_world_bounds(glb, 0, &lo_g, &hi_g));
    assert_true(fv_scene_world_bounds(text, 0, &lo_t, &hi_t));
    assert_v3_near(lo_g, lo_t, 0.0f, "glb bounds min");
    assert_v3_near(hi_g, hi_t, 0.0f, "glb bounds max");
    assert_v3_near(hi_g, fv_v3(4, 1, 0), 1e-6f, "bounds max"); /* the second node at x + 3 */

    fv_scene_destroy(&text);
    fv_scene_destroy(&glb);
    free(json);
    free(glb_buffer);
    free(buffer);
    free(b64);
    free(view);
    bytes_free(&bin);
    bytes_free(&png);
}

static void external_png_next_to_the_gltf_is_read_through_stb_image(void **state)
{
    (void)state;
    unsigned char px[TEX_W * TEX_H * 4];
    image_pixels(px);
    assert_true(stbi_write_png(fv_test_tmp("tex_checker.png"), TEX_W, TEX_H, 4, px, TEX_W * 4) != 0);
    bytes geom = {0};
    put_geometry(&geom);
    fv_test_write_file("quad.bin", geom.p, geom.n);
    char *buffer = fmt("{\"byteLength\":%zu,\"uri\":\"quad.bin\"}", geom.n);
    fv_scene *s = load_clean(
        write_text("external.gltf", textured_json("{\"uri\":\"tex_checker.png\"}", "", buffer)));
    assert_textured_quad(s, "/tex_checker.png");
    assert_int_equal(s->texture_count, 1);
    fv_scene_destroy(&s);
    free(buffer);
    bytes_free(&geom);
}

static void missing_png_warns_naming_it_and_keeps_the_base_colour(void **state)
{
    (void)state;
    bytes geom = {0};
    put_geometry(&geom);
    char *buf = data_uri("application/octet-stream", geom.p, geom.n);
    char *buffer = fmt("{\"byteLength\":%zu,\"uri\":\"%s\"}", geom.n, buf);
    const char *path =
        write_text("missing_tex.gltf", textured_json("{\"uri\":\"no_such_texture.png\"}", "", buffer));
    fv_scene *s = NULL;
    fv_test_log_capture_begin();
    fv_result r = fv_scene_load(path, &s);
    if (r != FV_OK) fail_msg("%s: %s; log:\n%s", path, fv_result_str(r), fv_test_log_text());
    fv_assert_log_contains("missing_tex.gltf");
    fv_assert_log_contains("no_such_texture.png");
    fv_assert_log_contains("using the base colour");
    assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_ERROR), 0);
    fv_test_log_capture_end();
    assert_int_equal(fv_scene_triangle_count(s), 4);
    assert_int_equal(s->texture_count, 0);
    const fv_material *m = material_named(s, "painted");
    assert_int_equal(m->base_color_texture, -1);
    assert_v3_near(m->base_color, fv_v3(0.8f, 0.6f, 0.4f), 1e-6f, "fallback base colour");
    fv_scene_destroy(&s);
    free(buf);
    free(buffer);
    bytes_free(&geom);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(khr_lights_punctual_keep_type_pose_cone_half_angles_and_intensity_in_w_per_sr),
        cmocka_unit_test(gltf_light_range_not_above_zero_warns_and_a_valid_one_follows_the_unit_scale),
        cmocka_unit_test(gltf_camera_becomes_the_head_with_its_pose_and_yfov),
        cmocka_unit_test(png_embedded_as_a_data_uri_decodes_to_the_pixels_written),
        cmocka_unit_test(glb_with_an_embedded_png_loads_as_its_equivalent_gltf),
        cmocka_unit_test(external_png_next_to_the_gltf_is_read_through_stb_image),
        cmocka_unit_test(missing_png_warns_naming_it_and_keeps_the_base_colour),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
