/* @brief HMD profiles and the lens model (runtime/hmd): the built-in profiles load and agree with their geometry, zero
 * coefficients are the identity, forward and inverse agree, a folding polynomial and every malformed field are refused
 * with the file and field named, extremes stay finite, and the hidden-area mask covers only pixels no panel pixel
 * shows (rasterised here on the CPU from the same triangles the G-buffer draws). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_hmd.h"
#include "fv_test.h"

static fv_hmd_profile load(const char *name)
{
    fv_hmd_profile p;
    char err[512] = "";
    fv_result r = fv_hmd_profile_load(name, &p, err, sizeof err);
    if (r != FV_OK) fail_msg("%s: %s (%s)", name, fv_result_str(r), err);
    return p;
}

/* tangent -> uv of a frustum (y down) */
static void tan_to_uv(const fv_hmd_fov *f, double tx, double ty, double *u, double *v)
{
    *u = (tx + f->tan_left) / ((double)f->tan_left + f->tan_right);
    *v = (f->tan_up - ty) / ((double)f->tan_up + f->tan_down);
}

static void builtin_profiles_load_and_match_their_geometry(void **state)
{
    (void)state;
    const char *const *names = fv_hmd_builtin_names();
    int n = 0;
    for (; names[n]; n++) {
        fv_hmd_profile p = load(names[n]);
        assert_string_equal(p.name, names[n]);
        assert_true(p.refresh_hz >= 60.0f && p.refresh_hz <= 240.0f);
        assert_true(p.lens.valid);
        char err[256];
        assert_int_equal(fv_lens_validate(&p.lens, err, sizeof err), FV_OK);
        /* the lens centre is where each eye's frustum looks straight ahead (tangent 0) */
        for (int e = 0; e < 2; e++) {
            double tx, ty, u, v;
            fv_lens_panel_to_tan(&p.lens, e, 1, p.lens.centre_m[e][0] / p.lens.viewport_m[0],
                                 p.lens.centre_m[e][1] / p.lens.viewport_m[1], &tx, &ty);
            assert_true(fabs(tx) < 1e-6 && fabs(ty) < 1e-6); /* float centre / viewport */
            tan_to_uv(&p.fov[e], 0, 0, &u, &v);
            assert_true(fabs(u - p.lens.centre_m[e][0] / p.lens.viewport_m[0]) < 0.01);
            assert_true(fabs(v - p.lens.centre_m[e][1] / p.lens.viewport_m[1]) < 0.01);
        }
        /* mirrored eyes: the left eye's outer (left) side is the right eye's outer (right) side */
        assert_true(fabsf(p.fov[0].tan_left - p.fov[1].tan_right) < 1e-5f);
    }
    assert_true(n >= 3);
    fv_hmd_profile g = load("generic");
    /* generic's field of view is fovea's default one (fv_frame_input.h FV_HMD_FOV_*) */
    assert_true(fabs(atan(g.fov[0].tan_left) * 180 / M_PI - 50.0) < 0.01);
    assert_true(fabs(atan(g.fov[0].tan_right) * 180 / M_PI - 42.0) < 0.01);
    assert_true(fabs(atan(g.fov[0].tan_up) * 180 / M_PI - 45.0) < 0.01);
    assert_true(fabs(atan(g.fov[0].tan_down) * 180 / M_PI - 48.0) < 0.01);
}

static fv_lens identity_lens(fv_hmd_profile *p)
{
    *p = load("htc-vive");
    fv_lens l = p->lens;
    l.k[0] = 1.0f;
    l.k[1] = l.k[2] = l.k[3] = 0.0f;
    l.aberration[0] = l.aberration[1] = l.aberration[2] = 1.0f;
    return l;
}

static void zero_coefficients_are_the_identity(void **state)
{
    (void)state;
    fv_hmd_profile p;
    fv_lens l = identity_lens(&p);
    char err[256];
    assert_int_equal(fv_lens_validate(&l, err, sizeof err), FV_OK);
    for (int e = 0; e < 2; e++)
        for (int c = 0; c < 3; c++)
            for (int i = 0; i <= 10; i++)
                for (int j = 0; j <= 10; j++) {
                    double u = i / 10.0, v = j / 10.0, tx, ty, su, sv, bu, bv;
                    fv_lens_panel_to_tan(&l, e, c, u, v, &tx, &ty);
                    tan_to_uv(&p.fov[e], tx, ty, &su, &sv);
                    /* the profile's fov is rounded to 6 digits: 1e-5 of the image */
                    if (fabs(su - u) > 1e-5 || fabs(sv - v) > 1e-5)
                        fail_msg("eye %d ch %d (%g, %g) -> (%g, %g)", e, c, u, v, su, sv);
                    assert_true(fv_lens_tan_to_panel(&l, e, c, tx, ty, &bu, &bv));
                    assert_true(fabs(bu - u) < 1e-9 && fabs(bv - v) < 1e-9);
                }
    /* nothing is hidden when the panel is the rendered image */
    double hidden = 1, masked = 1;
    fv_lens_hidden_fraction(&l, 0, &p.fov[0], 64, 64, FV_LENS_MASK_SEGMENTS, fv_lens_mask_margin(&p.fov[0], 64, 64),
                            &hidden, &masked);
    assert_true(hidden == 0.0);
    assert_true(masked == 0.0);
}

static void inverse_undoes_forward_within_1e9(void **state)
{
    (void)state;
    const char *const *names = fv_hmd_builtin_names();
    for (int n = 0; names[n]; n++) {
        fv_hmd_profile p = load(names[n]);
        double worst = 0;
        uint32_t seed = 12345;
        for (int i = 0; i < 20000; i++) {
            seed = seed * 1664525u + 1013904223u;
            double u = (seed >> 8) / 16777216.0;
            seed = seed * 1664525u + 1013904223u;
            double v = (seed >> 8) / 16777216.0;
            int e = i & 1, c = i % 3;
            double tx, ty, bu, bv;
            fv_lens_panel_to_tan(&p.lens, e, c, u, v, &tx, &ty);
            double qx = (u * p.lens.viewport_m[0] - p.lens.centre_m[e][0]) / p.lens.warp_m;
            double qy = (v * p.lens.viewport_m[1] - p.lens.centre_m[e][1]) / p.lens.warp_m;
            if (sqrt(qx * qx + qy * qy) > fv_lens_r_max(&p.lens)) continue; /* beyond the visible radius */
            assert_true(fv_lens_tan_to_panel(&p.lens, e, c, tx, ty, &bu, &bv));
            worst = fmax(worst, fmax(fabs(bu - u), fabs(bv - v)));
        }
        if (worst > 1e-9) fail_msg("%s: inverse off by %g", names[n], worst);
    }
}

static const char *vive_text(size_t *len)
{
    static char path[1024];
    snprintf(path, sizeof path, "%s/hmd/htc-vive.json", FV_SOURCE_DIR);
    return fv_test_read_file(path, len);
}

/* The Vive profile with one substring replaced, parsed; returns the error text. */
static const char *parse_edited(const char *from, const char *to, fv_result want)
{
    static char err[512];
    size_t len;
    char *text = (char *)vive_text(&len);
    char *at = strstr(text, from);
    if (!at) fail_msg("'%s' not in the Vive profile", from);
    size_t out_len = len - strlen(from) + strlen(to);
    char *out = malloc(out_len + 1);
    size_t pre = (size_t)(at - text);
    memcpy(out, text, pre);
    memcpy(out + pre, to, strlen(to));
    memcpy(out + pre + strlen(to), at + strlen(from), len - pre - strlen(from));
    out[out_len] = 0;
    fv_hmd_profile p;
    memset(&p, 0x5a, sizeof p);
    err[0] = 0;
    fv_result r = fv_hmd_profile_parse(out, out_len, "edited.json", &p, err, sizeof err);
    free(out);
    free(text);
    if (r != want) fail_msg("'%s' -> '%s': %s, want %s (%s)", from, to, fv_result_str(r), fv_result_str(want), err);
    assert_true(strncmp(err, "edited.json", 11) == 0);
    return err;
}

static void folding_profile_is_refused(void **state)
{
    (void)state;
    /* d(r) = 1 - 0.9 r^2: r d(r) turns back at r = 0.61, inside the panel */
    const char *e = parse_edited("\"k\": [\n      0.508021,\n      0.663824,\n      -1.490242,\n      1.318397\n    ]",
                                 "\"k\": [1, 0, -0.9, 0]", FV_ERR_RANGE);
    fv_assert_contains(e, "lens.k");
    fv_assert_contains(e, "folds");
    /* a lens that folds only beyond what the panel shows is fine: the same polynomial, a small visible radius */
    fv_hmd_profile p = load("htc-vive");
    p.lens.k[0] = 1;
    p.lens.k[1] = 0;
    p.lens.k[2] = -0.9f;
    p.lens.k[3] = 0;
    char err[256];
    assert_int_equal(fv_lens_validate(&p.lens, err, sizeof err), FV_ERR_RANGE);
    p.lens.visible_r = 0.5f;
    assert_int_equal(fv_lens_validate(&p.lens, err, sizeof err), FV_OK);
    /* d(0) <= 0 */
    p.lens.k[0] = 0;
    assert_int_equal(fv_lens_validate(&p.lens, err, sizeof err), FV_ERR_RANGE);
    fv_assert_contains(err, "lens.k[0]");
}

static void malformed_fields_are_named(void **state)
{
    (void)state;
    fv_assert_contains(parse_edited("\"refresh_hz\": 90", "\"refresh_hz\": 0", FV_ERR_RANGE), "panel.refresh_hz");
    fv_assert_contains(parse_edited("\"refresh_hz\": 90", "\"refresh_hz\": \"90\"", FV_ERR_RANGE),
                       "panel.refresh_hz: not a finite number");
    fv_assert_contains(parse_edited("\"width_px\": 2160", "\"width_px\": 2161", FV_ERR_RANGE), "even width");
    fv_assert_contains(parse_edited("\"aberration\": [", "\"aberration\": [3, ", FV_ERR_RANGE), "lens.aberration");
    fv_assert_contains(parse_edited("\"separation_m\": 0.056", "\"separation_m\": 0.2", FV_ERR_RANGE),
                       "lens.separation_m");
    fv_assert_contains(parse_edited("\"tan_up\": 1.560003", "\"tan_up\": 1.2", FV_ERR_RANGE),
                       "fov.left.tan_up: 1.2 disagrees with the lens geometry");
    fv_assert_contains(parse_edited("\"visible_radius\": \"", "\"visible_radiux\": \"", FV_ERR_PARSE),
                       "sources.visible_radius: missing");
    fv_assert_contains(parse_edited("\"format\": \"fovea-hmd 1\"", "\"format\": \"fovea-hmd 2\"", FV_ERR_PARSE),
                       "format");
    const char *e = parse_edited("\"panel\": {", "\"panel\": {,", FV_ERR_PARSE);
    fv_assert_contains(e, "not valid JSON");
    fv_assert_contains(e, "edited.json:5:");
    char err[512];
    fv_hmd_profile p;
    assert_int_equal(fv_hmd_profile_load("/nonexistent/x.json", &p, err, sizeof err), FV_ERR_NOT_FOUND);
    fv_assert_contains(err, "no such HMD profile (built-in: generic, htc-vive, oculus-rift-dk2)");
    assert_int_equal(fv_hmd_profile_load(FV_SOURCE_DIR "/hmd", &p, err, sizeof err), FV_ERR_IO);
    fv_assert_contains(err, "not a regular file");
    assert_int_equal(fv_hmd_profile_load("", &p, err, sizeof err), FV_ERR_INVALID_ARG);
    const char *empty = fv_test_write_file("empty.json", "", 0);
    assert_int_equal(fv_hmd_profile_load(empty, &p, err, sizeof err), FV_ERR_PARSE);
    fv_assert_contains(err, "empty.json:1: not valid JSON");
}

/* cJSON gives up past 1000 levels of nesting without saying why: the error says the nesting is too deep, with the
 * limit, the file, line and column. A name that does not fit is refused, not cut. */
static void too_deep_nesting_and_too_long_text_are_named(void **state)
{
    (void)state;
    size_t depth = 1001, len = 2 * depth + 64;
    char *deep = malloc(len);
    size_t n = (size_t)snprintf(deep, len, "{\"format\": \"fovea-hmd 1\",\n\"x\": ");
    for (size_t i = 0; i < depth; i++) deep[n++] = '[';
    for (size_t i = 0; i < depth; i++) deep[n++] = ']';
    deep[n++] = '}';
    const char *path = fv_test_write_file("deep.json", deep, n);
    free(deep);
    char err[512];
    fv_hmd_profile p;
    assert_int_equal(fv_hmd_profile_load(path, &p, err, sizeof err), FV_ERR_PARSE);
    fv_assert_contains(err, "deep.json:2:");
    fv_assert_contains(err, "nested deeper than 1000 levels");
    /* 1000 levels is within cJSON's limit: then the missing fields are what is wrong */
    deep = malloc(len);
    n = (size_t)snprintf(deep, len, "{\"x\": ");
    for (size_t i = 0; i < 999; i++) deep[n++] = '[';
    for (size_t i = 0; i < 999; i++) deep[n++] = ']';
    deep[n++] = '}';
    assert_int_equal(fv_hmd_profile_parse(deep, n, "ok.json", &p, err, sizeof err), FV_ERR_PARSE);
    fv_assert_contains(err, "ok.json: format: missing");
    free(deep);
    char name[FV_HMD_NAME_MAX + 8], to[FV_HMD_NAME_MAX + 32];
    memset(name, 'n', sizeof name - 1);
    name[sizeof name - 1] = '\0';
    snprintf(to, sizeof to, "\"name\": \"%s\"", name);
    const char *e = parse_edited("\"name\": \"htc-vive\"", to, FV_ERR_PARSE);
    fv_assert_contains(e, "edited.json: name: 71 bytes, more than the 63-byte limit");
}

static void extremes_stay_finite(void **state)
{
    (void)state;
    fv_hmd_profile p = load("generic");
    double u, v, tx, ty;
    assert_false(fv_lens_tan_to_panel(&p.lens, 0, 0, NAN, 0, &u, &v));
    assert_false(fv_lens_tan_to_panel(&p.lens, 0, 0, INFINITY, 1, &u, &v));
    assert_false(fv_lens_tan_to_panel(&p.lens, 1, 2, 1e30, -1e30, &u, &v));
    assert_false(fv_lens_tan_visible(&p.lens, 0, 1e6, 0));
    assert_true(fv_lens_tan_visible(&p.lens, 0, 0, 0));
    assert_true(fv_lens_tan_to_panel(&p.lens, 0, 1, 0, 0, &u, &v));
    assert_true(isfinite(u) && isfinite(v));
    double corners[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    for (int i = 0; i < 4; i++) {
        fv_lens_panel_to_tan(&p.lens, 1, 2, corners[i][0], corners[i][1], &tx, &ty);
        assert_true(isfinite(tx) && isfinite(ty));
    }
    /* out-of-range eye and channel are clamped, not read out of bounds */
    fv_lens_panel_to_tan(&p.lens, 7, -3, 0.5, 0.5, &tx, &ty);
    assert_true(isfinite(tx) && isfinite(ty));
    /* a far-out-of-range mesh request is clamped to 1024 segments and stays finite */
    uint32_t n = fv_lens_hidden_mesh(&p.lens, 0, &p.fov[0], 1u << 30, 0.01, 0.0f, NULL, 0);
    assert_true(n > 0 && n <= 6u * 1024u);
    float *xyz = malloc(sizeof(float) * 3 * n);
    assert_int_equal(fv_lens_hidden_mesh(&p.lens, 0, &p.fov[0], 1u << 30, 0.01, 0.0f, xyz, n), n);
    for (uint32_t i = 0; i < 3 * n; i++) assert_true(isfinite(xyz[i]) && fabsf(xyz[i]) < 100.0f);
    free(xyz);
    char err[256];
    fv_lens bad = p.lens;
    bad.warp_m = NAN;
    assert_int_equal(fv_lens_validate(&bad, err, sizeof err), FV_ERR_RANGE);
    bad = p.lens;
    bad.centre_m[1][0] = -1;
    assert_int_equal(fv_lens_validate(&bad, err, sizeof err), FV_ERR_RANGE);
    fv_assert_contains(err, "right eye's centre x");
}

static bool in_triangle(const float *a, const float *b, const float *c, double x, double y)
{
    double d1 = (x - b[0]) * (a[1] - b[1]) - (a[0] - b[0]) * (y - b[1]);
    double d2 = (x - c[0]) * (b[1] - c[1]) - (b[0] - c[0]) * (y - c[1]);
    double d3 = (x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1]);
    bool neg = d1 < 0 || d2 < 0 || d3 < 0, pos = d1 > 0 || d2 > 0 || d3 > 0;
    return !(neg && pos);
}

/* Rasterise the mask's triangles over pixel centres (as the G-buffer does) and check every covered pixel is hidden,
 * and that the mask covers nearly all hidden pixels. */
static void check_mask(const char *name, int eye, uint32_t w, uint32_t h, double min_cover)
{
    fv_hmd_profile p = load(name);
    const fv_hmd_fov *f = &p.fov[eye];
    double margin = fv_lens_mask_margin(f, w, h);
    uint32_t n = fv_lens_hidden_mesh(&p.lens, eye, f, FV_LENS_MASK_SEGMENTS, margin, 1.0f, NULL, 0);
    float *xyz = malloc(sizeof(float) * 3 * (n ? n : 1));
    assert_int_equal(fv_lens_hidden_mesh(&p.lens, eye, f, FV_LENS_MASK_SEGMENTS, margin, 1.0f, xyz, n), n);
    for (uint32_t i = 0; i < n; i++) assert_true(xyz[3 * i + 2] == 1.0f); /* the tag */
    double px_x = ((double)f->tan_left + f->tan_right) / w, px_y = ((double)f->tan_up + f->tan_down) / h;
    uint64_t hidden = 0, covered = 0, wrong = 0, deep_hidden = 0;
    /* rasterise: each triangle over the pixel centres of its bounding box */
    bool *cover = calloc((size_t)w * h, 1);
    for (uint32_t t = 0; t + 2 < n; t += 3) {
        const float *a = xyz + 3 * t, *b = a + 3, *c = a + 6;
        double x0 = fmin(a[0], fmin(b[0], c[0])), x1 = fmax(a[0], fmax(b[0], c[0]));
        double y0 = fmin(a[1], fmin(b[1], c[1])), y1 = fmax(a[1], fmax(b[1], c[1]));
        int px0 = (int)fmax(0, floor((x0 + 1) / 2 * w - 0.5)), px1 = (int)fmin(w - 1, ceil((x1 + 1) / 2 * w - 0.5));
        int py0 = (int)fmax(0, floor((y0 + 1) / 2 * h - 0.5)), py1 = (int)fmin(h - 1, ceil((y1 + 1) / 2 * h - 0.5));
        for (int y = py0; y <= py1; y++)
            for (int x = px0; x <= px1; x++)
                if (in_triangle(a, b, c, 2.0 * (x + 0.5) / w - 1.0, 2.0 * (y + 0.5) / h - 1.0))
                    cover[(size_t)y * w + x] = true;
    }
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            double tx = -f->tan_left + (x + 0.5) / w * ((double)f->tan_left + f->tan_right);
            double ty = f->tan_up - (y + 0.5) / h * ((double)f->tan_up + f->tan_down);
            bool vis = fv_lens_tan_visible(&p.lens, eye, tx, ty);
            bool cov = cover[(size_t)y * w + x];
            hidden += !vis;
            covered += cov;
            /* a masked texel is never a bilinear tap of a visible sample: its neighbours within a texel are hidden */
            bool near = vis;
            for (int dy = -1; dy <= 1 && cov && !near; dy++)
                for (int dx = -1; dx <= 1 && !near; dx++)
                    near = fv_lens_tan_visible(&p.lens, eye, tx + dx * px_x, ty + dy * px_y);
            wrong += cov && near;
            /* deep: hidden with nothing visible within 2.5 texels (beyond the mask's 1.5-texel margin) */
            bool deep = !vis;
            for (int k = 0; k < 16 && deep; k++) {
                double a = k * M_PI / 8;
                deep = !fv_lens_tan_visible(&p.lens, eye, tx + 2.5 * cos(a) * px_x, ty + 2.5 * sin(a) * px_y);
            }
            deep_hidden += deep;
        }
    free(xyz);
    free(cover);
    double fh = (double)hidden / (w * h), fc = (double)covered / (w * h);
    double fh2, fm2;
    fv_lens_hidden_fraction(&p.lens, eye, f, w, h, FV_LENS_MASK_SEGMENTS, margin, &fh2, &fm2);
    print_message("%s eye %d %ux%u: hidden %.4f, masked %.4f (fraction: %.4f / %.4f), %u triangles\n", name, eye, w, h,
                  fh, fc, fh2, fm2, n / 3);
    if (wrong) fail_msg("%s eye %d: %llu masked pixels within a texel of a visible one", name, eye,
                        (unsigned long long)wrong);
    assert_true(fabs(fh - fh2) < 1e-12);
    assert_true(fabs(fc - fm2) < 2.0 / (w * h) + 0.002); /* edges of triangles vs the chord test */
    double fd = (double)deep_hidden / (w * h);
    print_message("  hidden beyond 2.5 texels of anything visible: %.4f\n", fd);
    if (fd > 0 && fc < min_cover * fd)
        fail_msg("%s eye %d: the mask covers %.4f; %.4f is hidden by more than 2.5 texels", name, eye, fc, fd);
}

static void hidden_area_mask_covers_only_hidden_pixels(void **state)
{
    (void)state;
    check_mask("generic", 0, 96, 96, 0.98);
    check_mask("generic", 1, 180, 200, 0.99);
    check_mask("htc-vive", 0, 108, 120, 0.98);
    check_mask("htc-vive", 1, 360, 400, 0.99);
    check_mask("oculus-rift-dk2", 1, 96, 108, 0.98);
}

/* A byte-identical copy of every built-in profile's file loads as that profile, field by field (origin included:
 * issue 28 item 6); a copy that differs by one byte is a file of its own. */
static void a_copy_of_a_builtin_profile_is_that_profile(void **state)
{
    (void)state;
    for (const char *const *name = fv_hmd_builtin_names(); *name; name++) {
        char src[1024], err[512];
        snprintf(src, sizeof src, "%s/hmd/%s.json", FV_SOURCE_DIR, *name);
        size_t len = 0;
        char *text = fv_test_read_file(src, &len);
        char copy_name[128];
        snprintf(copy_name, sizeof copy_name, "copy-of-%s.json", *name);
        const char *copy = fv_test_write_file(copy_name, text, len);
        fv_hmd_profile a, b;
        memset(&a, 0xa5, sizeof a);
        memset(&b, 0x5a, sizeof b);
        assert_int_equal(fv_hmd_profile_load(*name, &a, err, sizeof err), FV_OK);
        assert_int_equal(fv_hmd_profile_load(copy, &b, err, sizeof err), FV_OK);
        assert_string_equal(a.name, b.name);
        assert_string_equal(a.origin, b.origin);
        assert_memory_equal(&a.lens, &b.lens, sizeof a.lens);
        assert_memory_equal(a.fov, b.fov, sizeof a.fov);
        assert_memory_equal(&a, &b, sizeof a); /* every field */
        /* One more byte (a trailing newline): the file's own profile, named by its path. */
        char *more = malloc(len + 1);
        assert_non_null(more);
        memcpy(more, text, len);
        more[len] = '\n';
        const char *other = fv_test_write_file(copy_name, more, len + 1);
        assert_int_equal(fv_hmd_profile_load(other, &b, err, sizeof err), FV_OK);
        fv_assert_contains(b.origin, "copy-of-");
        assert_memory_equal(&a.lens, &b.lens, sizeof a.lens);
        free(more);
        free(text);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(builtin_profiles_load_and_match_their_geometry),
        cmocka_unit_test(zero_coefficients_are_the_identity),
        cmocka_unit_test(inverse_undoes_forward_within_1e9),
        cmocka_unit_test(folding_profile_is_refused),
        cmocka_unit_test(malformed_fields_are_named),
        cmocka_unit_test(too_deep_nesting_and_too_long_text_are_named),
        cmocka_unit_test(extremes_stay_finite),
        cmocka_unit_test(hidden_area_mask_covers_only_hidden_pixels),
        cmocka_unit_test(a_copy_of_a_builtin_profile_is_that_profile),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
