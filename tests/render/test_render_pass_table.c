/* @brief Adding a pass is its folder and one line of a pass table (README, docs/architecture.md): the stamp pass of
 * the test build (tests/render/stamp_pass) runs in the renderer from one table line, is planned, started, recorded,
 * timed and read back by its declared image's name; placed before the pass that makes what it needs, or finding an
 * image it did not declare, the renderer refuses it with an error naming the passes (not a crash). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_passes.h"
#include "fv_test.h"
#include "gpu_test.h"
#include "stamp_pass.h"

/* The built-in table with `extra` inserted at index `at` (UINT32_MAX: at the end). */
static uint32_t table_with(const fv_pass *extra, uint32_t at, const fv_pass **out)
{
    uint32_t n = 0;
    const fv_pass *const *t = fv_pass_table(&n);
    assert_true(n < FV_MAX_PASSES);
    uint32_t k = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (i == at) out[k++] = extra;
        out[k++] = t[i];
    }
    if (at >= n) out[k++] = extra; /* the one table line */
    return k;
}

static fv_result create(const fv_pass *const *table, uint32_t n, fv_renderer **r)
{
    fv_renderer_desc d = {.eye_width = 16, .eye_height = 16, .validation = 1, .frames_in_flight = 2,
                          .pass_table = table, .pass_count = n};
    return fv_renderer_create(&d, r);
}

static void a_pass_added_by_one_table_line_runs(void **state)
{
    (void)state;
    const fv_pass *table[FV_MAX_PASSES];
    uint32_t n = table_with(&fv_stamp_pass, UINT32_MAX, table);
    fv_renderer *r = NULL;
    if (create(table, n, &r) != FV_OK) {
        if (getenv("CI") && !strcmp(getenv("CI"), "true")) fail_msg("no usable Vulkan device");
        skip();
    }
    fv_scene *s = fv_gpu_test_load_scene(r, "cornell");
    const fv_plan_entry *e = fv_frame_plan_find(fv_renderer_plan(r), "stamp");
    assert_non_null(e);
    assert_true(e->enabled);
    assert_string_equal(e->io, "makes test stamp; needs fovea mask (fovea)");
    uint64_t frame = 1;
    fv_quality q = fv_quality_default();
    fv_frame_input in = fv_gpu_test_frame_input(r, &frame, &q);
    in.quality.fovea.enabled = true; /* the frame input helper turns foveation off */
    assert_int_equal(fv_renderer_draw(r, &in), FV_OK);
    uint32_t *texels = calloc(16 * 16, sizeof *texels);
    assert_non_null(texels);
    for (int eye = 0; eye < 2; eye++) {
        assert_int_equal(fv_renderer_read_image(r, "test stamp", eye, texels, 16 * 16 * 4, 4), FV_OK);
        for (int i = 0; i < 16 * 16; i++)
            if (texels[i] != FV_STAMP_VALUE) fail_msg("eye %d texel %d: %#x", eye, i, texels[i]);
    }
    free(texels);
    fv_render_stats st;
    assert_int_equal(fv_renderer_stats(r, &st), FV_OK);
    bool timed = false;
    for (uint32_t i = 0; i < st.pass_count; i++)
        if (!strcmp(st.pass_name[i], "stamp")) timed = st.pass_counters[i].draws == 1;
    assert_true(timed); /* the last recorded pass has its timer and counters */
    fv_scene_destroy(&s);
    assert_int_equal(fv_renderer_validation_messages(r), 0);
    fv_renderer_destroy(&r);
}

static void a_pass_before_its_maker_or_with_an_undeclared_image_is_refused(void **state)
{
    (void)state;
    const fv_pass *table[FV_MAX_PASSES];
    uint32_t n = table_with(&fv_stamp_pass, UINT32_MAX, table);
    fv_renderer *r = NULL;
    if (create(table, n, &r) != FV_OK) skip(); /* no device (the test above says so under CI) */
    fv_renderer_destroy(&r);
    n = table_with(&fv_stamp_pass, 0, table); /* before the fovea pass that makes its "fovea mask" */
    fv_test_log_capture_begin();
    fv_result res = create(table, n, &r);
    fv_test_log_capture_end();
    assert_int_equal(res, FV_ERR_STATE);
    assert_null(r);
    fv_assert_log_contains("pass stamp needs image 'fovea mask' of pass fovea, but its maker records after it");

    n = table_with(&fv_stamp_sneak_pass, UINT32_MAX, table);
    fv_test_log_capture_begin();
    res = create(table, n, &r);
    fv_test_log_capture_end();
    assert_int_equal(res, FV_ERR_STATE);
    fv_assert_log_contains("pass sneak looks for image 'fovea prob', which its table entry does not declare");

    const fv_pass *const *t = fv_pass_table(&n);
    fv_renderer_desc d = {.eye_width = 16, .eye_height = 16, .pass_table = t, .pass_count = FV_MAX_PASSES + 1};
    fv_test_log_capture_begin();
    assert_int_equal(fv_renderer_create(&d, &r), FV_ERR_RANGE); /* refused before any device work */
    fv_test_log_capture_end();
    fv_assert_log_contains("a pass table of 25 entries: the renderer holds 1..24 (FV_MAX_PASSES)");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_pass_added_by_one_table_line_runs),
        cmocka_unit_test(a_pass_before_its_maker_or_with_an_undeclared_image_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
