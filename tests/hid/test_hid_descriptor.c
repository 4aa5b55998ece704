/* @brief HID report-descriptor parser: Microsoft's page-0x12 descriptors against Windows' own parse, item semantics
 * (push/pop, ranges, extended usages, signed ranges, long items) and malformed descriptors. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_hid_descriptor.h"
#include "fv_hid_eyetracker.h"
#include "fv_test.h"
#include "hid_test_util.h"

static fv_hid_descriptor *g_desc;

static int setup(void **state)
{
    (void)state;
    g_desc = calloc(1, sizeof *g_desc);
    return g_desc ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    free(g_desc);
    return 0;
}

/* ---- Windows caps comparison ---- */

typedef struct win_cap {
    int type; /* FV_HID_REPORT_* */
    unsigned report_id, bit_size, report_count, usage, exponent_nibble;
    uint32_t logical_min, logical_max;
} win_cap;

/* Expand our fields into Windows-style value caps: one cap per usage of each main item, listed in reverse usage
 * order within the item (as hidparse lists them); one usage over N elements is one cap with ReportCount N; padding
 * (no usage) makes no cap. */
static size_t our_caps(const fv_hid_descriptor *d, int type, win_cap *out, size_t cap)
{
    size_t n = 0;
    for (uint32_t fi = 0; fi < d->field_count; fi++) {
        const fv_hid_field *f = &d->fields[fi];
        if (f->type != type || f->usage_ranges == 0) continue;
        uint32_t k = f->usage_total < f->count ? f->usage_total : f->count;
        size_t first = n;
        for (uint32_t i = 0; i < k && n < cap; i++, n++) {
            win_cap *c = &out[n];
            c->type = type;
            c->report_id = f->report_id;
            c->bit_size = f->bit_size;
            c->report_count = (i == k - 1) ? f->count - (k - 1) : 1;
            c->usage = fv_hid_field_usage(d, f, i) & 0xFFFFu;
            c->exponent_nibble = (unsigned)f->unit_exponent & 0xFu;
            c->logical_min = (uint32_t)f->logical_min;
            c->logical_max = (uint32_t)f->logical_max;
        }
        for (size_t a = first, b = n - 1; a < b; a++, b--) {
            win_cap t = out[a];
            out[a] = out[b];
            out[b] = t;
        }
    }
    return n;
}

static void descriptors_match_windows_hidparse_caps(void **state)
{
    (void)state;
    uint8_t bytes[1024];
    size_t n = hid_test_load_hex("ms-gazehid-vhidmini-eye-tracker.rdesc.hex", bytes, sizeof bytes);
    assert_int_equal(n, 340);
    assert_int_equal(fv_hid_descriptor_parse(bytes, n, g_desc), FV_OK);

    char *text = hid_test_read_text(fv_test_data("hid/ms-gazehid-windows-hidparse-caps.txt"), NULL);
    win_cap want[64];
    size_t want_n = 0;
    unsigned in_len = 0, out_len = 99, feat_len = 0, nodes = 0, caps_in = 0, caps_feat = 0;
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        const char *s;
        if ((s = strstr(line, "Report Lengths: Input 0x"))) {
            assert_int_equal(sscanf(s, "Report Lengths: Input 0x%x (%*u) Output %u Feature 0x%x", &in_len, &out_len,
                                    &feat_len),
                             3);
        }
        if ((s = strstr(line, "Link Collection Nodes "))) assert_int_equal(sscanf(s, "Link Collection Nodes %u", &nodes), 1);
        if ((s = strstr(line, "Value caps "))) assert_int_equal(sscanf(s, "Value caps %u input, %u feature", &caps_in, &caps_feat), 2);
        if (line[0] == '#') continue;
        char kind[16];
        unsigned idx;
        win_cap c;
        if (sscanf(line, "%15s Val#%u | 0x%x | 0x%x | 0x%x | 0x%x | 0x%x | 0x%x..0x%x", kind, &idx, &c.report_id,
                   &c.bit_size, &c.report_count, &c.usage, &c.exponent_nibble, &c.logical_min, &c.logical_max) != 9)
            continue;
        c.type = strcmp(kind, "Input") == 0 ? FV_HID_REPORT_INPUT : FV_HID_REPORT_FEATURE;
        assert_true(want_n < 64);
        want[want_n++] = c;
    }
    free(text);
    assert_int_equal(want_n, 26);
    assert_int_equal(caps_in + caps_feat, want_n);

    /* Report lengths and the collection tree */
    assert_int_equal(fv_hid_descriptor_max_report_length(g_desc, FV_HID_REPORT_INPUT), in_len);
    assert_int_equal(fv_hid_descriptor_max_report_length(g_desc, FV_HID_REPORT_OUTPUT), out_len);
    assert_int_equal(fv_hid_descriptor_max_report_length(g_desc, FV_HID_REPORT_FEATURE), feat_len);
    assert_int_equal(g_desc->collection_count, nodes);
    assert_true(g_desc->uses_report_ids);

    win_cap got[64];
    size_t got_n = our_caps(g_desc, FV_HID_REPORT_INPUT, got, 64);
    assert_int_equal(got_n, caps_in);
    got_n += our_caps(g_desc, FV_HID_REPORT_FEATURE, got + got_n, 64 - got_n);
    assert_int_equal(got_n, want_n);
    for (size_t i = 0; i < want_n; i++) {
        const win_cap *w = &want[i], *g = &got[i];
        if (w->type != g->type || w->report_id != g->report_id || w->bit_size != g->bit_size ||
            w->report_count != g->report_count || w->usage != g->usage || w->exponent_nibble != g->exponent_nibble ||
            w->logical_min != g->logical_min || w->logical_max != g->logical_max)
            fail_msg("cap %zu differs: windows id 0x%x bits %u count %u usage 0x%x exp 0x%x %08x..%08x; fovea id 0x%x "
                     "bits %u count %u usage 0x%x exp 0x%x %08x..%08x",
                     i, w->report_id, w->bit_size, w->report_count, w->usage, w->exponent_nibble, w->logical_min,
                     w->logical_max, g->report_id, g->bit_size, g->report_count, g->usage, g->exponent_nibble,
                     g->logical_min, g->logical_max);
    }

    /* The quirks this descriptor is known for */
    const fv_hid_report *tracking = fv_hid_descriptor_find_report(g_desc, FV_HID_REPORT_INPUT, 0x10);
    assert_non_null(tracking);
    assert_int_equal(tracking->bit_length, 64 * 8); /* 8 timestamp bytes + 14 int32, 6 of them padding */
    int padding = 0;
    for (uint32_t i = 0; i < g_desc->field_count; i++)
        if (g_desc->fields[i].usage_ranges == 0) {
            padding++;
            assert_int_equal(g_desc->fields[i].count * g_desc->fields[i].bit_size, 6 * 32);
            assert_int_equal(g_desc->fields[i].bit_offset, 64 + 8 * 32);
        }
    assert_int_equal(padding, 1);
    assert_non_null(fv_hid_descriptor_find_report(g_desc, FV_HID_REPORT_INPUT, 0x13));
    assert_non_null(fv_hid_descriptor_find_report(g_desc, FV_HID_REPORT_FEATURE, 0x13));
    /* Units: µs on the timestamp, µm on positions, Hz on sampling frequency */
    double k;
    const fv_hid_field *ts = &g_desc->fields[0];
    assert_true(fv_hid_unit_time_to_ns(ts->unit, ts->unit_exponent, &k));
    assert_true(fabs(k - 1000.0) < 1e-9);
    const fv_hid_field *gx = &g_desc->fields[1];
    assert_true(fv_hid_unit_length_to_mm(gx->unit, gx->unit_exponent, &k));
    assert_true(fabs(k - 1e-3) < 1e-15);
    char buf[64];
    assert_string_equal(fv_hid_unit_format(gx->unit, gx->unit_exponent, buf, sizeof buf), "cm e-4");
    assert_string_equal(fv_hid_unit_format(0xF001, 0, buf, sizeof buf), "s^-1");
}

static void dmf_descriptor_adds_head_pose_in_the_same_65_bytes(void **state)
{
    (void)state;
    uint8_t bytes[1024];
    size_t n = hid_test_load_hex("ms-dmf-virtualeyegaze.rdesc.hex", bytes, sizeof bytes);
    assert_int_equal(n, 366);
    assert_int_equal(fv_hid_descriptor_parse(bytes, n, g_desc), FV_OK);
    assert_int_equal(fv_hid_descriptor_max_report_length(g_desc, FV_HID_REPORT_INPUT), 65);
    assert_int_equal(fv_hid_descriptor_max_report_length(g_desc, FV_HID_REPORT_FEATURE), 22);
    assert_int_equal(g_desc->collection_count, 14);
    fv_hid_eyetracker_map m;
    assert_int_equal(fv_hid_eyetracker_map_init(g_desc, NULL, &m), FV_OK);
    for (int a = 0; a < 3; a++) {
        assert_true(m.head_pos[a].field >= 0);
        assert_true(m.head_rot[a].field >= 0);
    }
    assert_int_equal(m.tracking_id, 0x10);
}

static void capabilities_feature_report_decodes_quality_and_distances(void **state)
{
    (void)state;
    uint8_t bytes[1024], rep[64];
    size_t n = hid_test_load_hex("ms-gazehid-vhidmini-eye-tracker.rdesc.hex", bytes, sizeof bytes);
    assert_int_equal(fv_hid_descriptor_parse(bytes, n, g_desc), FV_OK);
    fv_hid_eyetracker_map m;
    assert_int_equal(fv_hid_eyetracker_map_init(g_desc, NULL, &m), FV_OK);
    size_t rn = hid_test_load_hex("ms-gazehid-capabilities-feature-report.hex", rep, sizeof rep);
    assert_int_equal(rn, 22);
    fv_hid_capabilities caps;
    assert_int_equal(fv_hid_eyetracker_decode_capabilities(g_desc, &m, rep, rn, &caps), FV_OK);
    assert_int_equal(caps.tracker_quality, 1);
    /* 50000 / 65000 / 90000 µm */
    assert_true(caps.min_distance_mm == 50.0);
    assert_true(caps.optimum_distance_mm == 65.0);
    assert_true(caps.max_distance_mm == 90.0);
    assert_true(caps.max_screen_width_mm == 0.0 && caps.max_screen_height_mm == 0.0);
}

static void draft_page_0x11_descriptor_is_not_an_eye_tracker(void **state)
{
    (void)state;
    uint8_t bytes[1024];
    size_t n = hid_test_load_hex("ms-gazehid-vhidmini-eye-tracker.rdesc.hex", bytes, sizeof bytes);
    /* The same layout declared on usage page 0x11 (not the assigned page 0x12). */
    assert_int_equal(bytes[0], 0x05);
    assert_int_equal(bytes[1], 0x12);
    bytes[1] = 0x11;
    assert_int_equal(fv_hid_descriptor_parse(bytes, n, g_desc), FV_OK);
    assert_false(fv_hid_is_eye_tracker(g_desc));
    fv_hid_eyetracker_map m;
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_eyetracker_map_init(g_desc, NULL, &m), FV_ERR_UNSUPPORTED);
    fv_test_log_capture_end();
    fv_assert_log_contains("not an eye tracker");
    fv_assert_log_contains("page 0x0011");
}

static void push_pop_ranges_extended_usages_and_signed_ranges(void **state)
{
    (void)state;
    const uint8_t d[] = {
        0x05, 0x01,                   /* Usage Page (Generic Desktop) */
        0x09, 0x02, 0xA1, 0x01,       /* Usage (Mouse), Collection (Application) */
        0x75, 0x08, 0x95, 0x01,       /* Report Size 8, Count 1 */
        0xA4,                         /* Push */
        0x75, 0x10, 0x95, 0x02,       /* Report Size 16, Count 2 */
        0x15, 0x81, 0x25, 0x7F,       /* Logical -127..127 */
        0x09, 0x30, 0x09, 0x31, 0x81, 0x02, /* X, Y Input (Data,Var,Abs) */
        0xB4,                         /* Pop: size 8, count 1, logical 0..0 */
        0xFE, 0x02, 0x10, 0xAA, 0xBB, /* a long item, skipped */
        0x15, 0x00, 0x25, 0xFF,       /* Logical 0..255 written with a one-byte maximum */
        0x05, 0x09, 0x19, 0x01, 0x29, 0x08, /* Buttons 1..8 */
        0x95, 0x08, 0x75, 0x01, 0x25, 0x01, 0x81, 0x02,
        0x0B, 0x38, 0x00, 0x01, 0x00, /* extended usage 0x0001:0x0038 (Wheel) while the page is Buttons */
        0x75, 0x08, 0x95, 0x01, 0x15, 0x81, 0x25, 0x7F, 0x81, 0x06,
        0x55, 0x0E, 0x65, 0x14,       /* exponent -2, English rotation (degrees) */
        0x09, 0x05, 0x75, 0x04, 0x95, 0x02, 0x15, 0x00, 0x25, 0x0F, 0x81, 0x03,
        0xC0,
    };
    assert_int_equal(fv_hid_descriptor_parse(d, sizeof d, g_desc), FV_OK);
    assert_int_equal(g_desc->long_items, 1);
    assert_int_equal(g_desc->field_count, 4);
    const fv_hid_field *xy = &g_desc->fields[0], *btn = &g_desc->fields[1], *wheel = &g_desc->fields[2];
    assert_int_equal(xy->bit_size, 16);
    assert_int_equal(xy->count, 2);
    assert_int_equal(xy->logical_min, -127);
    assert_int_equal(xy->logical_max, 127);
    assert_int_equal(fv_hid_field_usage(g_desc, xy, 1), 0x00010031);
    assert_int_equal(btn->bit_offset, 32);
    assert_int_equal(btn->bit_size, 1);
    assert_int_equal(btn->usage_total, 8);
    assert_int_equal(fv_hid_field_usage(g_desc, btn, 3), 0x00090004);
    assert_int_equal(wheel->bit_offset, 40);
    assert_int_equal(fv_hid_field_usage(g_desc, wheel, 0), 0x00010038);
    assert_true(wheel->flags & FV_HID_FLAG_RELATIVE);
    const fv_hid_field *c = &g_desc->fields[3];
    assert_int_equal(c->unit_exponent, -2);
    assert_true(c->flags & FV_HID_FLAG_CONSTANT);
    double k;
    assert_true(fv_hid_unit_angle_to_rad(c->unit, c->unit_exponent, &k));
    assert_true(fabs(k - 0.01 * 3.14159265358979323846 / 180.0) < 1e-12);
    /* The Pop restored logical 0..0 then 0..255 (one-byte 0xFF read unsigned since the minimum is 0) */
    assert_int_equal(btn->logical_max, 1);
    /* Bits: 0x8001 = -32767 in 16 bits signed, buttons 0b101, wheel -1 */
    const uint8_t payload[] = {0x01, 0x80, 0x05, 0x00, 0x05, 0xFF, 0x00};
    int64_t v;
    assert_int_equal(fv_hid_field_read(xy, 0, payload, sizeof payload, &v), FV_OK);
    assert_int_equal(v, -32767);
    assert_int_equal(fv_hid_field_read(btn, 2, payload, sizeof payload, &v), FV_OK);
    assert_int_equal(v, 1);
    assert_int_equal(fv_hid_field_read(btn, 1, payload, sizeof payload, &v), FV_OK);
    assert_int_equal(v, 0);
    assert_int_equal(fv_hid_field_read(wheel, 0, payload, sizeof payload, &v), FV_OK);
    assert_int_equal(v, -1);
    assert_int_equal(fv_hid_field_read(wheel, 0, payload, 5, &v), FV_ERR_PROTOCOL); /* short payload */
    uint8_t out[7] = {0};
    assert_int_equal(fv_hid_field_write(xy, 1, -2, out, sizeof out), FV_OK);
    assert_int_equal(out[2], 0xFE);
    assert_int_equal(out[3], 0xFF);
    assert_int_equal(fv_hid_field_read(xy, 1, out, sizeof out, &v), FV_OK);
    assert_int_equal(v, -2);
}

typedef struct bad_case {
    const char *what;
    uint8_t bytes[48];
    size_t len;
    const char *needle; /* must appear in the error */
} bad_case;

static void malformed_descriptors_fail_with_byte_offsets(void **state)
{
    (void)state;
    static const bad_case cases[] = {
        {"truncated short item", {0x05, 0x12, 0x09}, 3, "byte 2 "},
        {"truncated 4-byte item", {0x05, 0x12, 0x17, 0x80, 0x7b}, 5, "byte 2 "},
        {"truncated long item", {0x05, 0x01, 0xFE, 0x05, 0x00, 0x01}, 6, "byte 2 "},
        {"pop without push", {0x05, 0x01, 0xB4}, 3, "Pop without"},
        {"collection underflow", {0x05, 0x01, 0x09, 0x02, 0xC0}, 5, "byte 4 "},
        {"unclosed collection",
         {0x05, 0x01, 0x09, 0x02, 0xA1, 0x01, 0x75, 0x08, 0x95, 0x01, 0x09, 0x30, 0x81, 0x02},
         14,
         "opened at byte 4"},
        {"huge report count", {0x05, 0x01, 0x09, 0x30, 0x75, 0x08, 0x97, 0xFF, 0xFF, 0xFF, 0x00, 0x81, 0x02}, 13,
         "byte 11 "},
        {"report size 0 in a usage", {0x05, 0x01, 0x09, 0x30, 0x75, 0x00, 0x95, 0x01, 0x81, 0x02}, 10, "byte 8 "},
        {"report size 33 in a usage", {0x05, 0x01, 0x09, 0x30, 0x75, 0x21, 0x95, 0x01, 0x81, 0x02}, 10,
         "Report Size 33"},
        {"report id 0", {0x05, 0x01, 0x85, 0x00}, 4, "byte 2 "},
        {"reserved item type", {0x05, 0x01, 0x0C}, 3, "reserved item type"},
        {"usage minimum without maximum", {0x05, 0x09, 0x19, 0x01, 0x75, 0x01, 0x95, 0x03, 0x81, 0x02}, 10,
         "byte 8 "},
        {"report IDs used on some reports only",
         {0x05, 0x01, 0x09, 0x30, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02, 0x85, 0x01, 0x09, 0x31, 0x81, 0x02},
         16,
         "byte 8 "},
        {"empty descriptor", {0}, 0, "empty"},
        {"usage range across pages", {0x1B, 0x01, 0x00, 0x09, 0x00, 0x2B, 0x05, 0x00, 0x01, 0x00}, 10, "byte 5 "},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        fv_test_log_capture_begin();
        fv_result r = fv_hid_descriptor_parse(cases[i].bytes, cases[i].len, g_desc);
        fv_test_log_capture_end();
        if (r != FV_ERR_PARSE) fail_msg("%s: expected FV_ERR_PARSE, got %s", cases[i].what, fv_result_str(r));
        if (!strstr(fv_test_log_text(), cases[i].needle))
            fail_msg("%s: error lacks \"%s\": %s", cases[i].what, cases[i].needle, fv_test_log_text());
        assert_int_equal(fv_test_log_count(FV_LOG_LEVEL_ERROR), 1);
    }
    /* Nesting: 17 collections and 9 pushes overflow fovea's stacks, with the offending offset */
    uint8_t deep[64];
    for (int i = 0; i < 17; i++) {
        deep[2 * i] = 0xA1;
        deep[2 * i + 1] = 0x00;
    }
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_descriptor_parse(deep, 34, g_desc), FV_ERR_PARSE);
    fv_test_log_capture_end();
    fv_assert_log_contains("byte 32 ");
    fv_assert_log_contains("nested deeper");
    uint8_t pushes[9];
    memset(pushes, 0xA4, sizeof pushes);
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_descriptor_parse(pushes, sizeof pushes, g_desc), FV_ERR_PARSE);
    fv_test_log_capture_end();
    fv_assert_log_contains("byte 8 ");
}

static void hex_decoder_reports_line_and_column(void **state)
{
    (void)state;
    uint8_t out[8];
    size_t n;
    const char ok[] = "# comment\n0x05, 0x12\n09 01 # trailing\n";
    assert_int_equal(fv_hid_hex_decode("t", ok, strlen(ok), out, sizeof out, &n), FV_OK);
    assert_int_equal(n, 4);
    assert_int_equal(out[1], 0x12);
    assert_int_equal(out[3], 0x01);
    const char bad[] = "05 12\n09 0g\n";
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_hex_decode("x.hex", bad, strlen(bad), out, sizeof out, &n), FV_ERR_PARSE);
    fv_test_log_capture_end();
    fv_assert_log_contains("x.hex:2:4");
    /* one line of a longer file: positions count in the file, and the message shows the word found */
    const char line[] = " 10 4g";
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_hex_decode_at("r.txt", 16, 3, line, strlen(line), out, sizeof out, &n), FV_ERR_PARSE);
    fv_test_log_capture_end();
    fv_assert_log_contains("r.txt:16:7: expected a two-digit hex byte, found '4g'");
    assert_null(strstr(fv_test_log_text(), "(line"));
    const char many[] = "01 02 03 04 05 06 07 08 09";
    fv_test_log_capture_begin();
    assert_int_equal(fv_hid_hex_decode("m", many, strlen(many), out, sizeof out, &n), FV_ERR_RANGE);
    fv_test_log_capture_end();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(descriptors_match_windows_hidparse_caps, setup, teardown),
        cmocka_unit_test_setup_teardown(dmf_descriptor_adds_head_pose_in_the_same_65_bytes, setup, teardown),
        cmocka_unit_test_setup_teardown(capabilities_feature_report_decodes_quality_and_distances, setup, teardown),
        cmocka_unit_test_setup_teardown(draft_page_0x11_descriptor_is_not_an_eye_tracker, setup, teardown),
        cmocka_unit_test_setup_teardown(push_pop_ranges_extended_usages_and_signed_ranges, setup, teardown),
        cmocka_unit_test_setup_teardown(malformed_descriptors_fail_with_byte_offsets, setup, teardown),
        cmocka_unit_test(hex_decoder_reports_line_and_column),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
