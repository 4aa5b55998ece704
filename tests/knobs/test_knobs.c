/* @brief The knob table (runtime/knobs/fv_knobs.h, generated from fv_knob_list.h): every row well formed, every preset
 * in range, balanced is fv_quality_default(), NAME=VALUE errors name the knob, the value and the range, format -> set
 * round trips, sanitising brings each refused knob back to balanced, each group's equality sees its knobs. */
#include "fv_knobs.h" /* first: the header compiles on its own */

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_test.h"

static const char *const PRESETS[] = {"fast", "balanced", "high", "exact"};

static fv_quality preset(const char *name)
{
    fv_quality q;
    char err[256];
    if (FV_FAILED(fv_quality_preset(name, &q, err, sizeof err))) fail_msg("preset %s: %s", name, err);
    return q;
}

static void assert_one_line(const char *s)
{
    if (!*s || strchr(s, '\n')) fail_msg("not one non-empty line: \"%s\"", s);
}

static void table_rows_are_well_formed(void **state)
{
    (void)state;
    size_t n = 0;
    const fv_knob *k = fv_knobs(&n);
    size_t gi = 0;
    for (size_t i = 0; i < n; i++) gi += strncmp(k[i].name, "gi.", 3) == 0;
    assert_int_equal(gi, 12); /* gi.*: enabled, mode, rsm_size, start_level, limit_level, two thresholds, samples,
                               * bound_fraction, average, refine, rate */
    for (size_t i = 0; i < n; i++) {
        const fv_knob *r = &k[i];
        if (!r->name || !strchr(r->name, '.') || !r->doc || !*r->doc || strchr(r->doc, '\n') || !r->unit)
            fail_msg("row %zu (%s): name, doc or unit missing", i, r->name ? r->name : "?");
        assert_ptr_equal(fv_knob_find(r->name), r);
        for (size_t j = 0; j < i; j++) assert_string_not_equal(k[j].name, r->name);
        if (!(r->min <= r->max)) fail_msg("%s: min %g > max %g", r->name, r->min, r->max);
        assert_true(r->offset + r->size <= sizeof(fv_quality));
        assert_int_equal(r->size, r->type == FV_KNOB_BOOL ? 1 : 4);
        switch (r->type) {
        case FV_KNOB_BOOL: assert_true(r->min == 0 && r->max == 1 && !r->choices); break;
        case FV_KNOB_ENUM:
            assert_non_null(r->choices);
            assert_true(r->min == 0 && r->max == (double)r->choice_count - 1);
            break;
        case FV_KNOB_INT: /* stored as uint32_t */
            assert_true(r->min >= 0 && r->max <= 4294967295.0 && r->min == floor(r->min) && r->max == floor(r->max));
            if (r->pow2) {
                int e;
                assert_true(frexp(r->min, &e) == 0.5 && frexp(r->max, &e) == 0.5);
            }
            break;
        case FV_KNOB_FLOAT: assert_true(isfinite(r->min) && isfinite(r->max)); break;
        }
    }
    assert_null(fv_knob_find("shadow"));
    assert_null(fv_knob_find(""));
    assert_null(fv_knob_find(NULL));
    assert_null(fv_knob_find("SHADOW.SPLITS"));
}

/* The shadow pass's knobs as the lead reads them: names, types and preset values of the issue. */
static void shadow_knobs_have_the_agreed_presets(void **state)
{
    (void)state;
    fv_quality f = preset("fast"), b = preset("balanced"), h = preset("high"), x = preset("exact");
    assert_true(f.shadow.enabled && b.shadow.enabled && h.shadow.enabled && x.shadow.enabled);
    assert_int_equal(f.shadow.splits, 2);
    assert_int_equal(b.shadow.splits, 4);
    assert_int_equal(h.shadow.splits, 4);
    assert_int_equal(x.shadow.splits, 8);
    assert_true(f.shadow.lambda == 0.5f && b.shadow.lambda == 0.5f && h.shadow.lambda == 0.5f);
    assert_true(x.shadow.lambda == 0.75f);
    assert_int_equal(f.shadow.resolution_px, 1024);
    assert_int_equal(b.shadow.resolution_px, 2048);
    assert_int_equal(h.shadow.resolution_px, 4096);
    assert_int_equal(x.shadow.resolution_px, 4096);
    assert_int_equal(f.shadow.filter, FV_SHADOW_FILTER_NONE);
    assert_int_equal(b.shadow.filter, FV_SHADOW_FILTER_PCF3);
    assert_int_equal(h.shadow.filter, FV_SHADOW_FILTER_PCF5);
    assert_int_equal(x.shadow.filter, FV_SHADOW_FILTER_NONE);
    assert_true(f.shadow.bias_texels == 1.5f && b.shadow.bias_texels == 1.5f && h.shadow.bias_texels == 1.5f);
    assert_true(x.shadow.bias_texels == 1.0f);
    assert_true(f.shadow.stereo_shared && b.shadow.stereo_shared && h.shadow.stereo_shared);
    assert_false(x.shadow.stereo_shared);
    /* exact says what it uses where the exact version is not possible: the filter's binary visibility, at least. */
    assert_non_null(fv_knob_find("shadow.filter")->exact_note);
    assert_non_null(strstr(fv_knob_find("shadow.filter")->exact_note, "binary"));
    /* Presets keep the view settings at their defaults. */
    assert_true(x.exposure == 1.0f && x.debug_view == FV_DEBUG_VIEW_NONE);
}

static void every_preset_is_within_every_knobs_range(void **state)
{
    (void)state;
    char err[512];
    for (int p = 0; p < FV_QUALITY_PRESET_COUNT; p++) {
        assert_string_equal(fv_quality_preset_name((fv_quality_preset_id)p), PRESETS[p]);
        fv_quality q = preset(PRESETS[p]);
        if (FV_FAILED(fv_quality_validate(&q, err, sizeof err))) fail_msg("preset %s: %s", PRESETS[p], err);
        assert_string_equal(err, "");
    }
    assert_null(fv_quality_preset_name(FV_QUALITY_PRESET_COUNT));
    assert_null(fv_quality_preset_name((fv_quality_preset_id)-1));
    assert_string_equal(fv_quality_preset_names(), "fast, balanced, high, exact");
}

/* One source of truth: the table's balanced column is fv_quality_default(). */
static void balanced_is_fv_quality_default(void **state)
{
    (void)state;
    size_t n = 0;
    const fv_knob *k = fv_knobs(&n);
    fv_quality d = fv_quality_default(), b = preset("balanced");
    assert_true(fv_quality_equal(&d, &b));
    for (size_t i = 0; i < n; i++) {
        char x[48], y[48];
        fv_knob_format(&k[i], &d, x, sizeof x);
        fv_knob_format(&k[i], &b, y, sizeof y);
        if (strcmp(x, y) != 0) fail_msg("%s: balanced %s, fv_quality_default() %s", k[i].name, y, x);
    }
    assert_int_equal(fv_quality_validate(&d, NULL, 0), FV_OK);
}

static void unknown_preset_names_the_allowed_ones(void **state)
{
    (void)state;
    fv_quality q = preset("high"), before = q;
    char err[256];
    assert_int_equal(fv_quality_preset("bogus", &q, err, sizeof err), FV_ERR_NOT_FOUND);
    assert_true(fv_quality_equal(&q, &before));
    assert_one_line(err);
    fv_assert_contains(err, "'bogus'");
    fv_assert_contains(err, "fast, balanced, high, exact");
    assert_int_equal(fv_quality_preset("Fast", &q, NULL, 0), FV_ERR_NOT_FOUND);
    assert_int_equal(fv_quality_preset("", &q, err, sizeof err), FV_ERR_NOT_FOUND);
    assert_int_equal(fv_quality_preset(NULL, &q, err, sizeof err), FV_ERR_NOT_FOUND);
    assert_int_equal(fv_quality_preset("fast", NULL, err, sizeof err), FV_ERR_INVALID_ARG);
}

static void good_assignments_apply_in_order(void **state)
{
    (void)state;
    fv_quality q = fv_quality_default();
    char err[256];
    const char *good[] = {"shadow.splits=3", "shadow.splits=8", "shadow.filter=pcf5", "shadow.enabled=off",
                          "shadow.stereo_shared=false", "shadow.lambda=1", "shadow.resolution=256",
                          "shadow.resolution=4096", "shadow.bias=10", "shadow.bias=0"};
    for (size_t i = 0; i < sizeof good / sizeof good[0]; i++)
        if (FV_FAILED(fv_quality_set(&q, good[i], err, sizeof err))) fail_msg("%s: %s", good[i], err);
    assert_int_equal(q.shadow.splits, 8); /* the later one wins */
    assert_int_equal(q.shadow.filter, FV_SHADOW_FILTER_PCF5);
    assert_false(q.shadow.enabled);
    assert_false(q.shadow.stereo_shared);
    assert_true(q.shadow.lambda == 1.0f);
    assert_int_equal(q.shadow.resolution_px, 4096);
    assert_true(q.shadow.bias_texels == 0.0f);
    const char *yes[] = {"on", "true", "1"}, *no[] = {"off", "false", "0"};
    for (int i = 0; i < 3; i++) {
        char a[64];
        snprintf(a, sizeof a, "shadow.enabled=%s", yes[i]);
        assert_int_equal(fv_quality_set(&q, a, NULL, 0), FV_OK);
        assert_true(q.shadow.enabled);
        snprintf(a, sizeof a, "shadow.enabled=%s", no[i]);
        assert_int_equal(fv_quality_set(&q, a, NULL, 0), FV_OK);
        assert_false(q.shadow.enabled);
    }
    /* A value that underflows to zero is zero, which is in range. */
    assert_int_equal(fv_quality_set(&q, "shadow.bias=1e-400", err, sizeof err), FV_OK);
    assert_true(q.shadow.bias_texels == 0.0f);
    assert_int_equal(fv_quality_validate(&q, err, sizeof err), FV_OK);
}

typedef struct bad_case {
    const char *assignment;
    fv_result want;
    const char *says[3]; /* substrings the one-line message must hold */
} bad_case;

static void bad_assignments_name_the_knob_the_value_and_the_range(void **state)
{
    (void)state;
    const bad_case cases[] = {
        {"shadow.splits=0", FV_ERR_RANGE, {"shadow.splits", "'0'", "1..8"}},
        {"shadow.splits=9", FV_ERR_RANGE, {"shadow.splits", "'9'", "1..8"}},
        {"shadow.splits=-1", FV_ERR_RANGE, {"shadow.splits", "'-1'", "1..8"}},
        {"shadow.splits=abc", FV_ERR_PARSE, {"shadow.splits", "'abc'", "a whole number in 1..8"}},
        {"shadow.splits=2.5", FV_ERR_PARSE, {"shadow.splits", "'2.5'", "whole number"}},
        {"shadow.splits=4.0", FV_ERR_PARSE, {"shadow.splits", "'4.0'", "1..8"}},
        {"shadow.splits=0x4", FV_ERR_PARSE, {"shadow.splits", "'0x4'", "1..8"}},
        {"shadow.splits= 3", FV_ERR_PARSE, {"shadow.splits", "' 3'", "1..8"}},
        {"shadow.splits=3 ", FV_ERR_PARSE, {"shadow.splits", "'3 '", "1..8"}},
        {"shadow.splits=99999999999999999999", FV_ERR_RANGE, {"shadow.splits", "99999999999999999999", "1..8"}},
        {"shadow.splits=-99999999999999999999", FV_ERR_RANGE, {"shadow.splits", "'-9999", "1..8"}},
        {"shadow.splits=4294967300", FV_ERR_RANGE, {"shadow.splits", "'4294967300'", "1..8"}}, /* 4 mod 2^32 */
        {"shadow.splits=", FV_ERR_PARSE, {"shadow.splits", "empty value", "1..8"}},
        {"shadow.splits", FV_ERR_PARSE, {"'shadow.splits'", "NAME=VALUE", ""}},
        {"", FV_ERR_PARSE, {"''", "NAME=VALUE", ""}},
        {"shadow.splitz=2", FV_ERR_NOT_FOUND, {"unknown knob 'shadow.splitz'", "shadow.splits", "shadow.filter"}},
        {"=3", FV_ERR_NOT_FOUND, {"unknown knob ''", "shadow.splits", ""}},
        {"shadow.resolution=1000", FV_ERR_RANGE, {"shadow.resolution", "'1000'", "a power of two in 256..4096 px"}},
        {"shadow.resolution=128", FV_ERR_RANGE, {"shadow.resolution", "'128'", "256..4096"}},
        {"shadow.resolution=8192", FV_ERR_RANGE, {"shadow.resolution", "'8192'", "256..4096"}},
        {"shadow.resolution=0", FV_ERR_RANGE, {"shadow.resolution", "'0'", "power of two"}},
        {"shadow.filter=gauss", FV_ERR_PARSE, {"shadow.filter", "'gauss'", "one of none, pcf3, pcf5"}},
        {"shadow.filter=1", FV_ERR_PARSE, {"shadow.filter", "'1'", "none, pcf3, pcf5"}},
        {"shadow.filter=PCF3", FV_ERR_PARSE, {"shadow.filter", "'PCF3'", "none, pcf3, pcf5"}},
        {"shadow.enabled=yes", FV_ERR_PARSE, {"shadow.enabled", "'yes'", "on, off"}},
        {"shadow.lambda=nan", FV_ERR_PARSE, {"shadow.lambda", "'nan'", "a number in 0..1"}},
        {"shadow.lambda=NaN", FV_ERR_PARSE, {"shadow.lambda", "'NaN'", "0..1"}},
        {"shadow.lambda=inf", FV_ERR_RANGE, {"shadow.lambda", "'inf'", "0..1"}},
        {"shadow.lambda=-infinity", FV_ERR_RANGE, {"shadow.lambda", "'-infinity'", "0..1"}},
        {"shadow.lambda=1.0000001", FV_ERR_RANGE, {"shadow.lambda", "'1.0000001'", "0..1"}},
        {"shadow.lambda=-0.5", FV_ERR_RANGE, {"shadow.lambda", "'-0.5'", "0..1"}},
        {"shadow.lambda=1e999", FV_ERR_RANGE, {"shadow.lambda", "'1e999'", "0..1"}},
        {"shadow.lambda=0.5x", FV_ERR_PARSE, {"shadow.lambda", "'0.5x'", "0..1"}},
        {"shadow.bias=10.5", FV_ERR_RANGE, {"shadow.bias", "'10.5'", "a number in 0..10 texels"}},
        {"shadow.bias=-1", FV_ERR_RANGE, {"shadow.bias", "'-1'", "0..10 texels"}},
        {"shadow.bias=1e308", FV_ERR_RANGE, {"shadow.bias", "'1e308'", "0..10"}},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const bad_case *c = &cases[i];
        fv_quality q = preset("fast"), before = q;
        char err[512];
        fv_result r = fv_quality_set(&q, c->assignment, err, sizeof err);
        if (r != c->want) fail_msg("'%s': %s, not %s (%s)", c->assignment, fv_result_str(r), fv_result_str(c->want), err);
        if (!fv_quality_equal(&q, &before)) fail_msg("'%s' changed the quality", c->assignment);
        assert_one_line(err);
        for (int s = 0; s < 3; s++)
            if (!strstr(err, c->says[s])) fail_msg("'%s': \"%s\" is not in \"%s\"", c->assignment, c->says[s], err);
        assert_int_equal(fv_quality_set(&q, c->assignment, NULL, 0), c->want); /* no message buffer: same verdict */
    }
}

static void messages_fit_any_buffer(void **state)
{
    (void)state;
    char huge[2048], err[512], tiny[8];
    memset(huge, '9', sizeof huge);
    memcpy(huge, "shadow.lambda=", 14);
    huge[sizeof huge - 1] = '\0';
    fv_quality q = fv_quality_default();
    assert_int_equal(fv_quality_set(&q, huge, err, sizeof err), FV_ERR_RANGE); /* 9...9 overflows: inf */
    assert_one_line(err);
    assert_true(strlen(err) < 200); /* the value is quoted cut short */
    memcpy(huge, "shadow.splits=", 14);
    assert_int_equal(fv_quality_set(&q, huge, tiny, sizeof tiny), FV_ERR_RANGE);
    assert_int_equal(strlen(tiny), sizeof tiny - 1);
    assert_int_equal(fv_quality_set(&q, "shadow.splits=0", err, 1), FV_ERR_RANGE);
    assert_string_equal(err, "");
    memset(huge, 'x', sizeof huge - 1);
    assert_int_equal(fv_quality_set(&q, huge, err, sizeof err), FV_ERR_PARSE); /* no '=' */
    assert_int_equal(fv_quality_set(&q, huge, tiny, sizeof tiny), FV_ERR_PARSE);
    huge[1500] = '=';
    assert_int_equal(fv_quality_set(&q, huge, err, sizeof err), FV_ERR_NOT_FOUND);
    assert_one_line(err);
    assert_int_equal(fv_quality_set(NULL, "shadow.splits=3", err, sizeof err), FV_ERR_INVALID_ARG);
    assert_int_equal(fv_quality_set(&q, NULL, err, sizeof err), FV_ERR_INVALID_ARG);
}

/* Set one knob's text on q, failing the test with the message. */
static void set_text(fv_quality *q, const fv_knob *k, const char *text)
{
    char a[128], err[512];
    snprintf(a, sizeof a, "%s=%s", k->name, text);
    if (FV_FAILED(fv_quality_set(q, a, err, sizeof err))) fail_msg("'%s' does not read back: %s", a, err);
}

static void format_then_set_round_trips_exactly(void **state)
{
    (void)state;
    size_t n = 0;
    const fv_knob *k = fv_knobs(&n);
    for (int p = 0; p < FV_QUALITY_PRESET_COUNT; p++) {
        fv_quality src = preset(PRESETS[p]), dst = preset(PRESETS[(p + 1) % FV_QUALITY_PRESET_COUNT]);
        for (size_t i = 0; i < n; i++) {
            char text[48];
            set_text(&dst, &k[i], fv_knob_format(&k[i], &src, text, sizeof text));
        }
        if (!fv_quality_equal(&src, &dst)) fail_msg("preset %s does not survive format -> set", PRESETS[p]);
    }
    /* Every float in range survives, the awkward ones included: walk bit patterns of [0, max]. */
    const fv_knob *floats[] = {fv_knob_find("shadow.lambda"), fv_knob_find("shadow.bias")};
    for (int f = 0; f < 2; f++) {
        float lo = (float)floats[f]->min, hi = (float)floats[f]->max;
        float samples[] = {lo, hi, nextafterf(hi, lo), nextafterf(lo, hi), FLT_MIN, 0.1f, 1.0f / 3.0f, 2.0f / 3.0f};
        fv_quality q = fv_quality_default(), back = q;
        for (uint32_t s = 0; s < 20000 + sizeof samples / sizeof samples[0]; s++) {
            float v;
            if (s < sizeof samples / sizeof samples[0]) v = samples[s];
            else {
                uint32_t bits = (uint32_t)((s * 2654435761u) % 0x7f800000u); /* a spread of finite positives */
                memcpy(&v, &bits, sizeof v);
                if (!(v >= lo && v <= hi)) continue;
            }
            memcpy((unsigned char *)&q + floats[f]->offset, &v, sizeof v);
            char text[48];
            fv_knob_format(floats[f], &q, text, sizeof text);
            set_text(&back, floats[f], text);
            float got = fv_knob_get(floats[f], &back).f;
            if (got != v) fail_msg("%s: %.9g formats as '%s', reads back as %.9g", floats[f]->name, (double)v, text,
                                   (double)got);
        }
    }
    char text[48];
    fv_quality q = fv_quality_default();
    assert_string_equal(fv_knob_format(fv_knob_find("shadow.bias"), &q, text, sizeof text), "1.5");
    assert_string_equal(fv_knob_format(fv_knob_find("shadow.filter"), &q, text, sizeof text), "pcf3");
    assert_string_equal(fv_knob_format(fv_knob_find("shadow.enabled"), &q, text, sizeof text), "on");
    assert_string_equal(fv_knob_format(fv_knob_find("shadow.resolution"), &q, text, sizeof text), "2048");
    q.shadow.bias_texels = 10.0f;
    assert_string_equal(fv_knob_format(fv_knob_find("shadow.bias"), &q, text, sizeof text), "10");
    assert_string_equal(fv_knob_format(NULL, &q, text, sizeof text), "");
}

static void ranges_read_as_the_table_says(void **state)
{
    (void)state;
    char r[96];
    assert_string_equal(fv_knob_format_range(fv_knob_find("shadow.splits"), r, sizeof r), "1..8");
    assert_string_equal(fv_knob_format_range(fv_knob_find("shadow.resolution"), r, sizeof r), "256..4096, powers of two");
    assert_string_equal(fv_knob_format_range(fv_knob_find("shadow.lambda"), r, sizeof r), "0..1");
    assert_string_equal(fv_knob_format_range(fv_knob_find("shadow.bias"), r, sizeof r), "0..10");
    assert_string_equal(fv_knob_format_range(fv_knob_find("shadow.filter"), r, sizeof r), "none|pcf3|pcf5");
    assert_string_equal(fv_knob_format_range(fv_knob_find("shadow.enabled"), r, sizeof r), "on|off");
    assert_string_equal(fv_knob_type_name(FV_KNOB_ENUM), "enum");
}

static void validate_reports_each_broken_rule(void **state)
{
    (void)state;
    char err[1024];
    fv_quality q = fv_quality_default();
    q.shadow.splits = 0;
    q.shadow.resolution_px = 1000;
    q.shadow.lambda = NAN;
    q.shadow.bias_texels = INFINITY;
    uint32_t seven = 7, nine = 9;
    memcpy(&q.shadow.filter, &seven, sizeof seven);
    nine = FV_DEBUG_VIEW_COUNT + 2; /* no view (9 became one: prob) */
    memcpy(&q.debug_view, &nine, sizeof nine);
    q.exposure = 0.0f;
    unsigned char two = 2;
    memcpy(&q.shadow.stereo_shared, &two, 1); /* a byte that is no bool */
    assert_int_equal(fv_quality_validate(&q, err, sizeof err), FV_ERR_RANGE);
    assert_one_line(err);
    const char *says[] = {"exposure", "debug_view", "shadow.splits = 0", "shadow.resolution = 1000",
                          "power of two", "shadow.lambda = nan", "shadow.bias = inf", "shadow.filter = 7",
                          "none, pcf3, pcf5", "shadow.stereo_shared holds byte 2", "; "};
    for (size_t i = 0; i < sizeof says / sizeof says[0]; i++) fv_assert_contains(err, says[i]);
    assert_null(strstr(err, "shadow.enabled"));
    /* One broken rule at a time, every knob: its name is the message. */
    size_t n = 0;
    const fv_knob *k = fv_knobs(&n);
    for (size_t i = 0; i < n; i++) {
        if (k[i].type == FV_KNOB_BOOL) continue;
        fv_quality one = fv_quality_default();
        unsigned char *p = (unsigned char *)&one + k[i].offset;
        if (k[i].type == FV_KNOB_FLOAT) {
            float v = (float)k[i].max * 2.0f + 1.0f;
            memcpy(p, &v, sizeof v);
        } else {
            uint32_t v = (uint32_t)k[i].max + 1u;
            memcpy(p, &v, sizeof v);
        }
        assert_int_equal(fv_quality_validate(&one, err, sizeof err), FV_ERR_RANGE);
        if (strncmp(err, k[i].name, strlen(k[i].name)) != 0) fail_msg("%s: \"%s\"", k[i].name, err);
        assert_null(strstr(err, "; "));
    }
    assert_int_equal(fv_quality_validate(NULL, err, sizeof err), FV_ERR_INVALID_ARG);
    q = fv_quality_default();
    q.exposure = 1e-30f;
    assert_int_equal(fv_quality_validate(&q, NULL, 0), FV_OK);
}

static const char *const GROUPS[] = {"shadow", "fovea", "distort", "gi", "sss", "interp"};

/* fv_quality_<group>_equal (fv_quality.h) by the group's name. */
static bool group_equal(const char *group, const fv_quality *a, const fv_quality *b)
{
    if (!strcmp(group, "shadow")) return fv_quality_shadow_equal(&a->shadow, &b->shadow);
    if (!strcmp(group, "fovea")) return fv_quality_fovea_equal(&a->fovea, &b->fovea);
    if (!strcmp(group, "distort")) return fv_quality_distort_equal(&a->distort, &b->distort);
    if (!strcmp(group, "gi")) return fv_quality_gi_equal(&a->gi, &b->gi);
    if (!strcmp(group, "sss")) return fv_quality_sss_equal(&a->sss, &b->sss);
    if (!strcmp(group, "interp")) return fv_quality_interp_equal(&a->interp, &b->interp);
    fail_msg("no group %s", group);
    return false;
}

/* Every knob belongs to one of the groups above (a new group needs its equality here). */
static void every_knob_is_in_a_group(void **state)
{
    (void)state;
    size_t n = 0;
    const fv_knob *k = fv_knobs(&n);
    for (size_t i = 0; i < n; i++) {
        bool found = false;
        for (size_t g = 0; g < sizeof GROUPS / sizeof GROUPS[0]; g++)
            found = found || (strncmp(k[i].name, GROUPS[g], strlen(GROUPS[g])) == 0 && k[i].name[strlen(GROUPS[g])] == '.');
        if (!found) fail_msg("%s: no group", k[i].name);
    }
}

/* The renderer draws with fv_quality_sanitize's result: every knob the table refuses, one at a time, takes its
 * balanced value and nothing else changes (the renderer's hand checks covered 15 of the knobs: gi.rsm_size = 3 or
 * sss.map_size = 0 reached the passes); good values stay; a zeroed quality becomes a valid one. */
static void sanitize_brings_each_refused_knob_back_to_balanced(void **state)
{
    (void)state;
    size_t n = 0;
    const fv_knob *k = fv_knobs(&n);
    const fv_quality d = fv_quality_default();
    for (size_t i = 0; i < n; i++) {
        for (int how = 0; how < 3; how++) {
            fv_quality one = d;
            unsigned char *p = (unsigned char *)&one + k[i].offset;
            if (k[i].type == FV_KNOB_BOOL) {
                if (how) continue;
                unsigned char two = 2;
                memcpy(p, &two, 1);
            } else if (k[i].type == FV_KNOB_FLOAT) {
                float v = how == 0 ? (float)k[i].max * 2.0f + 1.0f : how == 1 ? (float)k[i].min - 1.0f : NAN;
                memcpy(p, &v, sizeof v);
            } else {
                uint32_t v = how == 0 ? (uint32_t)k[i].max + 1u : how == 1 ? UINT32_MAX : (uint32_t)k[i].min * 3u;
                if (how == 2 && (!k[i].pow2 || v > k[i].max)) continue; /* a whole number that is no power of two */
                if (how == 1 && k[i].min == 0 && k[i].type == FV_KNOB_ENUM) v = k[i].choice_count;
                memcpy(p, &v, sizeof v);
            }
            if (fv_quality_validate(&one, NULL, 0) != FV_ERR_RANGE) fail_msg("%s (case %d): not refused", k[i].name, how);
            fv_quality_sanitize(&one);
            if (memcmp(&one, &d, sizeof d) != 0) fail_msg("%s (case %d): not back to its balanced value", k[i].name, how);
            assert_int_equal(fv_quality_validate(&one, NULL, 0), FV_OK);
        }
    }
    for (size_t i = 0; i < sizeof PRESETS / sizeof PRESETS[0]; i++) { /* good values stay */
        fv_quality q = preset(PRESETS[i]), before = q;
        fv_quality_sanitize(&q);
        assert_memory_equal(&q, &before, sizeof q);
    }
    fv_quality z;
    memset(&z, 0, sizeof z);
    fv_quality_sanitize(&z);
    assert_int_equal(fv_quality_validate(&z, NULL, 0), FV_OK);
    assert_true(z.exposure == 1.0f && z.shadow.splits == d.shadow.splits && z.gi.rsm_size == d.gi.rsm_size);
    fv_quality_sanitize(NULL);
}

static void equal_sees_every_knob_and_view_setting(void **state)
{
    (void)state;
    fv_quality a = fv_quality_default(), b = a;
    assert_true(fv_quality_equal(&a, &b));
    size_t n = 0;
    const fv_knob *k = fv_knobs(&n);
    fv_quality x = preset("exact");
    for (size_t i = 0; i < n; i++) {
        fv_quality c = a;
        char text[48];
        fv_knob_format(&k[i], &x, text, sizeof text);
        if (strcmp(text, fv_knob_format(&k[i], &a, (char[48]){0}, 48)) == 0) { /* same in both: take another */
            fv_quality f = preset("fast");
            fv_knob_format(&k[i], &f, text, sizeof text);
            if (k[i].type == FV_KNOB_BOOL) /* the other value of a bool */
                snprintf(text, sizeof text, "%s",
                         strcmp(fv_knob_format(&k[i], &a, (char[48]){0}, 48), "on") == 0 ? "off" : "on");
        }
        if (k[i].type == FV_KNOB_ENUM && k[i].choice_count == 1) continue; /* one choice: nothing else to set */
        if (k[i].type == FV_KNOB_ENUM && strcmp(text, fv_knob_format(&k[i], &a, (char[48]){0}, 48)) == 0)
            for (size_t v = 0; v < k[i].choice_count; v++) /* every preset agrees: any other choice */
                if (strcmp(k[i].choices[v], text) != 0) {
                    snprintf(text, sizeof text, "%s", k[i].choices[v]);
                    break;
                }
        if ((k[i].type == FV_KNOB_INT || k[i].type == FV_KNOB_FLOAT) &&
            strcmp(text, fv_knob_format(&k[i], &a, (char[48]){0}, 48)) == 0) { /* every preset agrees: the range's end */
            fv_quality lo = a, hi = a;
            char lo_text[48], hi_text[48];
            snprintf(lo_text, sizeof lo_text, k[i].type == FV_KNOB_INT ? "%.0f" : "%.9g", k[i].min);
            snprintf(hi_text, sizeof hi_text, k[i].type == FV_KNOB_INT ? "%.0f" : "%.9g", k[i].max);
            set_text(&lo, &k[i], lo_text);
            set_text(&hi, &k[i], hi_text);
            snprintf(text, sizeof text, "%s",
                     strcmp(fv_knob_format(&k[i], &lo, (char[48]){0}, 48), fv_knob_format(&k[i], &a, (char[48]){0}, 48))
                         ? lo_text : hi_text);
        }
        set_text(&c, &k[i], text);
        if (fv_quality_equal(&a, &c)) fail_msg("%s=%s is not seen as a difference", k[i].name, text);
        /* the group's own equality (a pass's cache key) sees it too, and no other group's does */
        for (size_t g = 0; g < sizeof GROUPS / sizeof GROUPS[0]; g++) {
            bool mine = strncmp(k[i].name, GROUPS[g], strlen(GROUPS[g])) == 0 && k[i].name[strlen(GROUPS[g])] == '.';
            if (group_equal(GROUPS[g], &a, &c) == mine)
                fail_msg("%s=%s: fv_quality_%s_equal says %s", k[i].name, text, GROUPS[g], mine ? "equal" : "differs");
        }
    }
    b.exposure = 2.0f;
    assert_false(fv_quality_equal(&a, &b));
    b = a;
    b.debug_view = FV_DEBUG_VIEW_GAZE;
    assert_false(fv_quality_equal(&a, &b));
    b = a;
    b.overlay = true; /* the overlay view setting (render/overlay): the plan must run again */
    assert_false(fv_quality_equal(&a, &b));
    b = a;
    b.shadow.lambda = NAN;
    assert_false(fv_quality_equal(&b, &b)); /* NaN: never equal, so a caller re-checks it */
    assert_true(fv_quality_equal(NULL, NULL));
    assert_false(fv_quality_equal(&a, NULL));
}

/* Every number knob: the bounds its range text prints, fed back as values, are accepted; a value just outside each
 * bound is refused with FV_ERR_RANGE and a message that prints the same bounds (fovea.min_prob=0.01 used to be
 * refused as "'0.01' is not a number in 0.01..1": the float 0.01 is below the double 0.01). */
static void printed_bounds_are_accepted_and_just_outside_refused(void **state)
{
    (void)state;
    size_t n = 0;
    const fv_knob *k = fv_knobs(&n);
    size_t checked = 0;
    for (size_t i = 0; i < n; i++) {
        if (k[i].type != FV_KNOB_INT && k[i].type != FV_KNOB_FLOAT) continue;
        char range[128], lo[64], hi[64], a[256], err[512];
        fv_knob_format_range(&k[i], range, sizeof range);
        const char *dots = strstr(range, "..");
        assert_non_null(dots);
        snprintf(lo, sizeof lo, "%.*s", (int)(dots - range), range);
        snprintf(hi, sizeof hi, "%s", dots + 2);
        char *comma = strchr(hi, ',');
        if (comma) *comma = '\0';
        char bounds[140];
        snprintf(bounds, sizeof bounds, "%s..%s", lo, hi);
        const char *edge[2] = {lo, hi};
        for (int e = 0; e < 2; e++) {
            fv_quality q = fv_quality_default();
            snprintf(a, sizeof a, "%s=%s", k[i].name, edge[e]);
            if (FV_FAILED(fv_quality_set(&q, a, err, sizeof err))) fail_msg("%s refused: %s", a, err);
            assert_int_equal(fv_quality_validate(&q, err, sizeof err), FV_OK);
            char back[64];
            fv_knob_format(&k[i], &q, back, sizeof back);
            assert_string_equal(back, edge[e]); /* the stored value is the bound, printed the same way */
        }
        char out[2][64];
        if (k[i].type == FV_KNOB_FLOAT) {
            float flo = (float)strtod(lo, NULL), fhi = (float)strtod(hi, NULL);
            snprintf(out[0], sizeof out[0], "%.9g", (double)nextafterf(flo, -INFINITY));
            snprintf(out[1], sizeof out[1], "%.9g", (double)nextafterf(fhi, INFINITY));
        } else {
            long long ilo = strtoll(lo, NULL, 10), ihi = strtoll(hi, NULL, 10);
            snprintf(out[0], sizeof out[0], "%lld", k[i].pow2 ? ilo / 2 : ilo - 1);
            snprintf(out[1], sizeof out[1], "%lld", k[i].pow2 ? ihi * 2 : ihi + 1);
        }
        for (int e = 0; e < 2; e++) {
            fv_quality q = fv_quality_default();
            snprintf(a, sizeof a, "%s=%s", k[i].name, out[e]);
            fv_result r = fv_quality_set(&q, a, err, sizeof err);
            if (r != FV_ERR_RANGE) fail_msg("%s: %s, not FV_ERR_RANGE (%s)", a, fv_result_str(r), err);
            if (!strstr(err, bounds)) fail_msg("%s: message \"%s\" does not print the bounds %s", a, err, bounds);
        }
        checked++;
    }
    assert_true(checked > 10);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(table_rows_are_well_formed),
        cmocka_unit_test(shadow_knobs_have_the_agreed_presets),
        cmocka_unit_test(every_preset_is_within_every_knobs_range),
        cmocka_unit_test(balanced_is_fv_quality_default),
        cmocka_unit_test(unknown_preset_names_the_allowed_ones),
        cmocka_unit_test(good_assignments_apply_in_order),
        cmocka_unit_test(bad_assignments_name_the_knob_the_value_and_the_range),
        cmocka_unit_test(messages_fit_any_buffer),
        cmocka_unit_test(format_then_set_round_trips_exactly),
        cmocka_unit_test(ranges_read_as_the_table_says),
        cmocka_unit_test(printed_bounds_are_accepted_and_just_outside_refused),
        cmocka_unit_test(validate_reports_each_broken_rule),
        cmocka_unit_test(equal_sees_every_knob_and_view_setting),
        cmocka_unit_test(every_knob_is_in_a_group),
        cmocka_unit_test(sanitize_brings_each_refused_knob_back_to_balanced),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
