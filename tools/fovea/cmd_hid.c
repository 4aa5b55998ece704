/* @brief `fovea hid`: parse a HID report descriptor (what a user runs first when a tracker misbehaves) and decode
 * reports with it; `--bench N` measures reports decoded per second. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "fv_clock.h"
#include "fv_hid_descriptor.h"
#include "fv_hid_eyetracker.h"
#include "fv_log.h"

static const char *USAGE =
    "usage: fovea hid parse FILE [--json]\n"
    "       fovea hid decode DESCRIPTOR REPORTS [--json] [--type input|feature] [--vid-pid VID:PID]\n"
    "                        [--screen WxH] [--bench N]\n"
    "  FILE, DESCRIPTOR: a report descriptor as hex text (\"05 12 09 01 ...\", '#' comments) or raw bytes.\n"
    "  REPORTS: one report per line in hex (\"label: 10 40 42 ...\" allowed), or one raw report.\n"
    "  --type      report type when the ID is declared as both (default: input if declared as input)\n"
    "  --vid-pid   apply the quirks of this device (hex, e.g. 1209:0001)\n"
    "  --screen    calibrated screen size in mm for gaze rays (default: from a Configuration report in REPORTS)\n"
    "  --bench N   decode the first report N times and print reports decoded per second\n";

#define MAX_FILE (1u << 20)
#define MAX_REPORTS 4096

typedef struct blob {
    uint8_t *bytes;
    size_t len;
} blob;

static char *read_file(const char *path, size_t *out_len) { return fv_cli_read_file("hid", path, MAX_FILE, out_len); }

static bool looks_like_text(const char *s, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == 0 || (c < 32 && c != '\n' && c != '\r' && c != '\t') || c > 126) return false;
    }
    return n > 0;
}

/* A descriptor file: hex text or raw bytes. */
static bool load_descriptor(const char *path, uint8_t *out, size_t cap, size_t *out_len)
{
    size_t n;
    char *text = read_file(path, &n);
    if (!text) return false;
    bool ok;
    if (looks_like_text(text, n)) {
        ok = fv_hid_hex_decode(path, text, n, out, cap, out_len) == FV_OK;
    } else {
        ok = n <= cap;
        if (ok) {
            memcpy(out, text, n);
            *out_len = n;
        } else {
            fprintf(stderr, "fovea hid: %s: larger than %zu bytes\n", path, cap);
        }
    }
    free(text);
    return ok;
}

/* Report lines: each non-empty, non-comment line is one report ("label: hex" allowed). Raw files are one report. */
static blob *load_reports(const char *path, size_t *out_count)
{
    size_t n;
    char *text = read_file(path, &n);
    if (!text) return NULL;
    blob *list = calloc(MAX_REPORTS, sizeof *list);
    size_t count = 0;
    bool ok = list != NULL;
    if (ok && !looks_like_text(text, n)) {
        list[0].bytes = malloc(n ? n : 1);
        ok = list[0].bytes != NULL;
        if (ok) {
            memcpy(list[0].bytes, text, n);
            list[0].len = n;
            count = 1;
        }
    } else if (ok) {
        size_t line_no = 0;
        for (char *line = text; ok && line && *line;) {
            char *nl = strchr(line, '\n');
            if (nl) *nl = '\0';
            line_no++;
            char *hex = strrchr(line, ':');
            hex = hex ? hex + 1 : line;
            char *hash = strchr(hex, '#');
            if (hash) *hash = '\0';
            bool blank = strspn(hex, " \t\r") == strlen(hex) || line[0] == '#';
            if (!blank) {
                if (count >= MAX_REPORTS) {
                    fprintf(stderr, "fovea hid: %s: more than %d reports\n", path, MAX_REPORTS);
                    ok = false;
                    break;
                }
                uint8_t buf[FV_HID_MAX_REPORT_BYTES + 1];
                size_t len;
                /* positions in messages count in the file: path:LINE:COLUMN */
                if (fv_hid_hex_decode_at(path, line_no, (size_t)(hex - line) + 1, hex, strlen(hex), buf, sizeof buf,
                                         &len) != FV_OK) {
                    ok = false;
                    break;
                }
                list[count].bytes = malloc(len ? len : 1);
                if (!list[count].bytes) {
                    ok = false;
                    break;
                }
                memcpy(list[count].bytes, buf, len);
                list[count].len = len;
                count++;
            }
            line = nl ? nl + 1 : NULL;
        }
    }
    free(text);
    if (!ok || count == 0) {
        if (ok) fprintf(stderr, "fovea hid: %s: no reports\n", path);
        for (size_t i = 0; list && i < count; i++) free(list[i].bytes);
        free(list);
        return NULL;
    }
    *out_count = count;
    return list;
}

static void free_reports(blob *list, size_t count)
{
    for (size_t i = 0; i < count; i++) free(list[i].bytes);
    free(list);
}

static void usage_text(uint32_t usage, char *buf, size_t cap)
{
    if (usage == 0) {
        snprintf(buf, cap, "(no usage)");
        return;
    }
    const char *page = fv_hid_usage_page_name((uint16_t)(usage >> 16));
    const char *name = fv_hid_usage_name(usage);
    if (name) snprintf(buf, cap, "%s: %s", page ? page : "?", name);
    else snprintf(buf, cap, "%s: 0x%04x", page ? page : "page 0x?", usage & 0xFFFFu);
    if (!page) snprintf(buf, cap, "0x%04x:0x%04x%s%s", usage >> 16, usage & 0xFFFFu, name ? " " : "", name ? name : "");
}

/* The unit, with the everyday name when it is one (cm e-4 = um, s e-6 = us). */
static const char *unit_text(const fv_hid_field *f, char *buf, size_t cap)
{
    fv_hid_unit_format(f->unit, f->unit_exponent, buf, cap);
    double k;
    size_t n = strlen(buf);
    if (fv_hid_unit_length_to_mm(f->unit, f->unit_exponent, &k) && fabs(k - 1e-3) < 1e-12)
        snprintf(buf + n, cap - n, " (um)");
    else if (fv_hid_unit_length_to_mm(f->unit, f->unit_exponent, &k) && fabs(k - 1.0) < 1e-12)
        snprintf(buf + n, cap - n, " (mm)");
    else if (fv_hid_unit_time_to_ns(f->unit, f->unit_exponent, &k) && fabs(k - 1e3) < 1e-9)
        snprintf(buf + n, cap - n, " (us)");
    else if (f->unit == 0xF001 && f->unit_exponent == 0)
        snprintf(buf + n, cap - n, " (Hz)");
    return buf;
}

static void flags_text(uint16_t f, char *buf, size_t cap)
{
    snprintf(buf, cap, "%s,%s,%s%s%s", (f & FV_HID_FLAG_CONSTANT) ? "Cnst" : "Data",
             (f & FV_HID_FLAG_VARIABLE) ? "Var" : "Arr", (f & FV_HID_FLAG_RELATIVE) ? "Rel" : "Abs",
             (f & FV_HID_FLAG_NULL_STATE) ? ",Null" : "", (f & FV_HID_FLAG_WRAP) ? ",Wrap" : "");
}

static cJSON *field_json(const fv_hid_descriptor *d, const fv_hid_field *f)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "bit_offset", f->bit_offset);
    cJSON_AddNumberToObject(o, "bit_size", f->bit_size);
    cJSON_AddNumberToObject(o, "count", f->count);
    cJSON_AddBoolToObject(o, "padding", f->usage_ranges == 0);
    cJSON_AddBoolToObject(o, "constant", (f->flags & FV_HID_FLAG_CONSTANT) != 0);
    cJSON_AddBoolToObject(o, "variable", (f->flags & FV_HID_FLAG_VARIABLE) != 0);
    cJSON_AddBoolToObject(o, "relative", (f->flags & FV_HID_FLAG_RELATIVE) != 0);
    cJSON *us = cJSON_AddArrayToObject(o, "usages");
    for (uint32_t r = 0; r < f->usage_ranges; r++) {
        const fv_hid_usage_range *u = &d->usages[f->usage_first + r];
        cJSON *ju = cJSON_CreateObject();
        cJSON_AddNumberToObject(ju, "page", u->min >> 16);
        const char *pn = fv_hid_usage_page_name((uint16_t)(u->min >> 16));
        fv_cli_json_add_string(ju, "page_name", pn ? pn : "");
        cJSON_AddNumberToObject(ju, "min", u->min & 0xFFFFu);
        cJSON_AddNumberToObject(ju, "max", u->max & 0xFFFFu);
        const char *un = u->min == u->max ? fv_hid_usage_name(u->min) : NULL;
        fv_cli_json_add_string(ju, "name", un ? un : "");
        cJSON_AddItemToArray(us, ju);
    }
    cJSON_AddNumberToObject(o, "logical_min", (double)f->logical_min);
    cJSON_AddNumberToObject(o, "logical_max", (double)f->logical_max);
    cJSON_AddNumberToObject(o, "physical_min", (double)f->physical_min);
    cJSON_AddNumberToObject(o, "physical_max", (double)f->physical_max);
    char unit[64];
    fv_cli_json_add_string(o, "unit", unit_text(f, unit, sizeof unit));
    cJSON_AddNumberToObject(o, "unit_code", f->unit);
    cJSON_AddNumberToObject(o, "unit_exponent", f->unit_exponent);
    cJSON_AddNumberToObject(o, "descriptor_offset", f->item_offset);
    return o;
}

static int print_json(cJSON *root)
{
    int rc = fv_cli_json_print(root, true);
    cJSON_Delete(root);
    return rc;
}

static int cmd_parse(const char *path, bool json)
{
    uint8_t bytes[FV_HID_MAX_DESCRIPTOR_BYTES];
    size_t n;
    if (!load_descriptor(path, bytes, sizeof bytes, &n)) return FV_EXIT_FAIL;
    fv_hid_descriptor *d = calloc(1, sizeof *d);
    if (!d) return FV_EXIT_FAIL;
    if (fv_hid_descriptor_parse(bytes, n, d) != FV_OK) {
        fprintf(stderr, "fovea hid parse: %s: not a valid report descriptor (see the error above)\n", path);
        free(d);
        return FV_EXIT_FAIL;
    }
    bool et = fv_hid_is_eye_tracker(d);
    if (json) {
        cJSON *root = cJSON_CreateObject();
        fv_cli_json_add_string(root, "file", path);
        cJSON_AddNumberToObject(root, "bytes", (double)n);
        cJSON_AddNumberToObject(root, "items", d->item_count);
        cJSON_AddNumberToObject(root, "long_items_skipped", d->long_items);
        cJSON_AddBoolToObject(root, "report_ids", d->uses_report_ids);
        cJSON_AddBoolToObject(root, "eye_tracker", et);
        cJSON *cols = cJSON_AddArrayToObject(root, "collections");
        for (uint32_t i = 0; i < d->collection_count; i++) {
            const fv_hid_collection *c = &d->collections[i];
            cJSON *o = cJSON_CreateObject();
            fv_cli_json_add_string(o, "type", fv_hid_collection_type_name(c->type));
            cJSON_AddNumberToObject(o, "usage_page", c->usage >> 16);
            cJSON_AddNumberToObject(o, "usage", c->usage & 0xFFFFu);
            const char *un = fv_hid_usage_name(c->usage);
            fv_cli_json_add_string(o, "name", un ? un : "");
            cJSON_AddNumberToObject(o, "parent", c->parent);
            cJSON_AddNumberToObject(o, "descriptor_offset", c->item_offset);
            cJSON_AddItemToArray(cols, o);
        }
        cJSON *reps = cJSON_AddArrayToObject(root, "reports");
        for (uint32_t r = 0; r < d->report_count; r++) {
            const fv_hid_report *rep = &d->reports[r];
            cJSON *o = cJSON_CreateObject();
            cJSON_AddNumberToObject(o, "id", rep->id);
            fv_cli_json_add_string(o, "type", fv_hid_report_type_name(rep->type));
            cJSON_AddNumberToObject(o, "byte_length", (double)fv_hid_report_byte_length(d, rep));
            cJSON_AddNumberToObject(o, "bit_length", rep->bit_length);
            cJSON *fs = cJSON_AddArrayToObject(o, "fields");
            for (uint32_t i = 0; i < d->field_count; i++) {
                const fv_hid_field *f = &d->fields[i];
                if (f->type == rep->type && f->report_id == rep->id) cJSON_AddItemToArray(fs, field_json(d, f));
            }
            cJSON_AddItemToArray(reps, o);
        }
        free(d);
        return print_json(root);
    }
    printf("%s: %zu bytes, %u items (%u long items skipped), %u collections, %u reports%s%s\n", path, n,
           d->item_count, d->long_items, d->collection_count, d->report_count,
           d->uses_report_ids ? ", report IDs" : "", et ? ", eye tracker (usage page 0x12)" : "");
    printf("max report lengths: input %zu, output %zu, feature %zu bytes\n",
           fv_hid_descriptor_max_report_length(d, FV_HID_REPORT_INPUT),
           fv_hid_descriptor_max_report_length(d, FV_HID_REPORT_OUTPUT),
           fv_hid_descriptor_max_report_length(d, FV_HID_REPORT_FEATURE));
    printf("collections:\n");
    for (uint32_t i = 0; i < d->collection_count; i++) {
        const fv_hid_collection *c = &d->collections[i];
        char u[96];
        usage_text(c->usage, u, sizeof u);
        printf("  %*s[%u] %s %s (byte %u)\n", 2 * c->depth, "", i, fv_hid_collection_type_name(c->type), u,
               c->item_offset);
    }
    for (uint32_t r = 0; r < d->report_count; r++) {
        const fv_hid_report *rep = &d->reports[r];
        printf("report 0x%02x %s: %zu bytes (%u bits of payload)\n", rep->id, fv_hid_report_type_name(rep->type),
               fv_hid_report_byte_length(d, rep), rep->bit_length);
        for (uint32_t i = 0; i < d->field_count; i++) {
            const fv_hid_field *f = &d->fields[i];
            if (f->type != rep->type || f->report_id != rep->id) continue;
            char fl[32], unit[64];
            flags_text(f->flags, fl, sizeof fl);
            if (f->usage_ranges == 0) {
                printf("  bit %4u  %3u x %-2u  padding (%u bits) [%s]\n", f->bit_offset, f->count, f->bit_size,
                       f->count * f->bit_size, fl);
                continue;
            }
            printf("  bit %4u  %3u x %-2u  ", f->bit_offset, f->count, f->bit_size);
            for (uint32_t k = 0; k < f->usage_ranges; k++) {
                const fv_hid_usage_range *u = &d->usages[f->usage_first + k];
                char a[96];
                usage_text(u->min, a, sizeof a);
                if (u->min == u->max) printf("%s%s", k ? ", " : "", a);
                else printf("%s%s .. 0x%04x", k ? ", " : "", a, u->max & 0xFFFFu);
            }
            const fv_hid_collection *c = &d->collections[f->collection];
            const char *cn = fv_hid_usage_name(c->usage);
            printf("%s%s%s  logical %lld..%lld", cn ? " (in " : "", cn ? cn : "", cn ? ")" : "",
                   (long long)f->logical_min, (long long)f->logical_max);
            if (f->physical_min != f->logical_min || f->physical_max != f->logical_max)
                printf("  physical %lld..%lld", (long long)f->physical_min, (long long)f->physical_max);
            printf("  unit %s  [%s]\n", unit_text(f, unit, sizeof unit), fl);
        }
    }
    free(d);
    return FV_EXIT_OK;
}

static void num(cJSON *o, const char *k, double v)
{
    if (isfinite(v)) cJSON_AddNumberToObject(o, k, v);
    else cJSON_AddNullToObject(o, k);
}

/* An integer field the decoder gives as -1 when it is absent or outside its logical range: null in JSON. */
static void int_or_null(cJSON *o, const char *k, int64_t v)
{
    if (v >= 0) cJSON_AddNumberToObject(o, k, (double)v);
    else cJSON_AddNullToObject(o, k);
}

/* The same two cases in text: the number, or "unknown" (absent, or out of the field's logical range). */
static const char *mm_text(char *buf, size_t cap, double v)
{
    if (isfinite(v)) snprintf(buf, cap, "%.3f mm", v);
    else snprintf(buf, cap, "unknown");
    return buf;
}

static const char *int_text(char *buf, size_t cap, const char *fmt, int64_t v)
{
    if (v >= 0) snprintf(buf, cap, fmt, (long long)v);
    else snprintf(buf, cap, "unknown");
    return buf;
}

static void vec3_json(cJSON *o, const char *k, fv_vec3 v, bool valid)
{
    if (!valid) {
        cJSON_AddNullToObject(o, k);
        return;
    }
    cJSON *a = cJSON_AddArrayToObject(o, k);
    cJSON_AddItemToArray(a, cJSON_CreateNumber(v.x));
    cJSON_AddItemToArray(a, cJSON_CreateNumber(v.y));
    cJSON_AddItemToArray(a, cJSON_CreateNumber(v.z));
}

static cJSON *sample_json(const fv_gaze_sample *s)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "t_device_ns", (double)s->t_device_ns);
    if (s->flags & FV_GAZE_SCREEN_POINT_VALID) {
        cJSON *a = cJSON_AddArrayToObject(o, "screen_point_mm");
        cJSON_AddItemToArray(a, cJSON_CreateNumber(s->screen_point_mm.x));
        cJSON_AddItemToArray(a, cJSON_CreateNumber(s->screen_point_mm.y));
    } else {
        cJSON_AddNullToObject(o, "screen_point_mm");
    }
    const char *names[3] = {"left", "right", "combined"};
    for (int e = 0; e < 3; e++) {
        const fv_eye_sample *es = e < 2 ? &s->eye[e] : &s->combined;
        cJSON *j = cJSON_AddObjectToObject(o, names[e]);
        vec3_json(j, "origin_mm", es->origin_mm, es->flags & FV_EYE_ORIGIN_VALID);
        vec3_json(j, "direction", es->direction, es->flags & FV_EYE_DIRECTION_VALID);
        num(j, "pupil_mm", (es->flags & FV_EYE_PUPIL_VALID) ? es->pupil_mm : NAN);
    }
    vec3_json(o, "head_pos_mm", s->head_pos_mm, s->flags & FV_GAZE_HEAD_VALID);
    vec3_json(o, "head_dir", s->head_dir, s->flags & FV_GAZE_HEAD_VALID);
    return o;
}

static void print_vec(const char *label, fv_vec3 v, bool valid)
{
    if (valid) printf(" %s (%.4f, %.4f, %.4f)", label, v.x, v.y, v.z);
    else printf(" %s invalid", label);
}

static void print_sample(const fv_gaze_sample *s)
{
    printf("  t_device %.6f s", (double)s->t_device_ns * 1e-9);
    if (s->flags & FV_GAZE_SCREEN_POINT_VALID)
        printf(", screen point (%.3f, %.3f) mm\n", s->screen_point_mm.x, s->screen_point_mm.y);
    else
        printf(", screen point invalid\n");
    const char *names[3] = {"left", "right", "combined"};
    for (int e = 0; e < 3; e++) {
        const fv_eye_sample *es = e < 2 ? &s->eye[e] : &s->combined;
        printf("  %-8s", names[e]);
        print_vec("origin_mm", es->origin_mm, es->flags & FV_EYE_ORIGIN_VALID);
        print_vec("dir", es->direction, es->flags & FV_EYE_DIRECTION_VALID);
        if (es->flags & FV_EYE_PUPIL_VALID) printf(" pupil %.3f mm", es->pupil_mm);
        printf("\n");
    }
    if (s->flags & FV_GAZE_HEAD_VALID) {
        printf("  head    ");
        print_vec("pos_mm", s->head_pos_mm, true);
        print_vec("dir", s->head_dir, true);
        printf("\n");
    }
}

/* Generic dump of every field value of one report (any usage page). */
static void dump_fields(const fv_hid_descriptor *d, fv_hid_report_type type, const uint8_t *rep, size_t len,
                        cJSON *jarr)
{
    uint8_t id = d->uses_report_ids ? rep[0] : 0;
    size_t skip = d->uses_report_ids ? 1u : 0u;
    for (uint32_t i = 0; i < d->field_count; i++) {
        const fv_hid_field *f = &d->fields[i];
        if (f->type != type || f->report_id != id || f->usage_ranges == 0) continue;
        uint32_t n = f->count > 64 ? 64 : f->count;
        for (uint32_t k = 0; k < n; k++) {
            int64_t v;
            if (fv_hid_field_read(f, k, rep + skip, len - skip, &v) != FV_OK) continue;
            uint32_t u = (f->flags & FV_HID_FLAG_VARIABLE) ? fv_hid_field_usage(d, f, k) : 0;
            char name[96] = "array";
            if (u) usage_text(u, name, sizeof name);
            bool in = fv_hid_field_in_range(f, v);
            if (jarr) {
                cJSON *o = cJSON_CreateObject();
                fv_cli_json_add_string(o, "usage", name);
                cJSON_AddNumberToObject(o, "value", (double)v);
                cJSON_AddBoolToObject(o, "in_range", in);
                cJSON_AddItemToArray(jarr, o);
            } else {
                printf("  %-48s %lld%s\n", name, (long long)v, in ? "" : "  (out of logical range: no data)");
            }
        }
    }
}

static int decode_one(const fv_hid_descriptor *d, const fv_hid_eyetracker_map *m, bool et,
                      const fv_hid_screen_config *screen, const blob *b, size_t index, int forced_type, cJSON *jarr)
{
    if (b->len == 0) return FV_EXIT_FAIL;
    uint8_t id = d->uses_report_ids ? b->bytes[0] : 0;
    fv_hid_report_type type;
    if (forced_type >= 0) type = (fv_hid_report_type)forced_type;
    else if (fv_hid_descriptor_find_report(d, FV_HID_REPORT_INPUT, id)) type = FV_HID_REPORT_INPUT;
    else type = FV_HID_REPORT_FEATURE;
    if (fv_hid_report_check(d, type, b->bytes, b->len, NULL) != FV_OK) {
        fprintf(stderr, "fovea hid decode: report %zu skipped (see the error above)\n", index + 1);
        return FV_EXIT_FAIL;
    }
    cJSON *jo = jarr ? cJSON_CreateObject() : NULL;
    if (jo) {
        cJSON_AddNumberToObject(jo, "index", (double)index + 1);
        cJSON_AddNumberToObject(jo, "id", id);
        fv_cli_json_add_string(jo, "type", fv_hid_report_type_name(type));
        cJSON_AddNumberToObject(jo, "bytes", (double)b->len);
        cJSON_AddItemToArray(jarr, jo);
    } else {
        printf("report %zu: ID 0x%02x %s, %zu bytes\n", index + 1, id, fv_hid_report_type_name(type), b->len);
    }
    fv_result r = FV_ERR_UNSUPPORTED;
    if (et && type == FV_HID_REPORT_INPUT && id == m->tracking_id) {
        fv_gaze_sample s;
        r = fv_hid_eyetracker_decode_tracking(d, m, screen, b->bytes, b->len, &s);
        if (r == FV_OK) {
            if (jo) cJSON_AddItemToObject(jo, "sample", sample_json(&s));
            else print_sample(&s);
        }
    } else if (et) {
        fv_hid_capabilities caps;
        fv_hid_configuration cfg;
        fv_hid_status st;
        int saved = fv_log_enabled("hid", FV_LOG_LEVEL_ERROR);
        (void)saved;
        if (type == FV_HID_REPORT_FEATURE && m->quality.field >= 0 && id == d->fields[m->quality.field].report_id &&
            (r = fv_hid_eyetracker_decode_capabilities(d, m, b->bytes, b->len, &caps)) == FV_OK) {
            if (jo) {
                cJSON *c = cJSON_AddObjectToObject(jo, "capabilities");
                int_or_null(c, "tracker_quality", caps.tracker_quality);
                num(c, "min_distance_mm", caps.min_distance_mm);
                num(c, "optimum_distance_mm", caps.optimum_distance_mm);
                num(c, "max_distance_mm", caps.max_distance_mm);
                num(c, "max_screen_width_mm", caps.max_screen_width_mm);
                num(c, "max_screen_height_mm", caps.max_screen_height_mm);
            } else {
                char q[24], a[24], b[24], c[24], w[24], h[24];
                printf("  capabilities: tracker quality %s, tracking distance min %s / optimum %s / max %s, "
                       "max screen %s x %s\n",
                       int_text(q, sizeof q, "%lld", caps.tracker_quality), mm_text(a, sizeof a, caps.min_distance_mm),
                       mm_text(b, sizeof b, caps.optimum_distance_mm), mm_text(c, sizeof c, caps.max_distance_mm),
                       mm_text(w, sizeof w, caps.max_screen_width_mm), mm_text(h, sizeof h, caps.max_screen_height_mm));
            }
        } else if (type == FV_HID_REPORT_FEATURE && m->calibrated_width.field >= 0 &&
                   id == d->fields[m->calibrated_width.field].report_id &&
                   (r = fv_hid_eyetracker_decode_configuration(d, m, b->bytes, b->len, &cfg)) == FV_OK) {
            if (jo) {
                cJSON *c = cJSON_AddObjectToObject(jo, "configuration");
                int_or_null(c, "display_manufacturer", cfg.display_manufacturer);
                int_or_null(c, "display_product", cfg.display_product);
                int_or_null(c, "display_serial", cfg.display_serial);
                num(c, "calibrated_width_mm", cfg.calibrated_width_mm);
                num(c, "calibrated_height_mm", cfg.calibrated_height_mm);
            } else {
                char vid[24], pid[24], ser[24], w[24], h[24];
                printf("  configuration: display %s:%s serial %s, calibrated screen %s x %s\n",
                       int_text(vid, sizeof vid, "0x%04llx", cfg.display_manufacturer),
                       int_text(pid, sizeof pid, "0x%04llx", cfg.display_product),
                       int_text(ser, sizeof ser, "%lld", cfg.display_serial),
                       mm_text(w, sizeof w, cfg.calibrated_width_mm), mm_text(h, sizeof h, cfg.calibrated_height_mm));
            }
        } else if (m->status_config[type == FV_HID_REPORT_INPUT].field >= 0 &&
                   id == d->fields[m->status_config[type == FV_HID_REPORT_INPUT].field].report_id &&
                   (r = fv_hid_eyetracker_decode_status(d, m, type, b->bytes, b->len, &st)) == FV_OK) {
            static const char *names[] = {"reserved", "ready", "configuring", "screen setup needed",
                                          "user calibration needed"};
            const char *sn = st.configuration_status >= 0 && st.configuration_status <= 4
                                 ? names[st.configuration_status]
                                 : "unknown";
            if (jo) {
                cJSON *c = cJSON_AddObjectToObject(jo, "status");
                int_or_null(c, "configuration_status", st.configuration_status);
                fv_cli_json_add_string(c, "configuration_status_name", sn);
                num(c, "sampling_frequency_hz", st.sampling_frequency_hz);
            } else {
                char fq[24];
                if (isfinite(st.sampling_frequency_hz)) snprintf(fq, sizeof fq, "%.1f Hz", st.sampling_frequency_hz);
                else snprintf(fq, sizeof fq, "unknown");
                if (st.configuration_status >= 0)
                    printf("  status: %s (%d), sampling frequency %s\n", sn, st.configuration_status, fq);
                else
                    printf("  status: unknown, sampling frequency %s\n", fq);
            }
        } else {
            r = FV_ERR_UNSUPPORTED;
        }
    }
    if (r == FV_ERR_UNSUPPORTED) {
        dump_fields(d, type, b->bytes, b->len, jo ? cJSON_AddArrayToObject(jo, "fields") : NULL);
        r = FV_OK;
    }
    return r == FV_OK ? FV_EXIT_OK : FV_EXIT_FAIL;
}

static int cmd_decode(const char *dpath, const char *rpath, bool json, int forced_type, const char *vidpid,
                      const char *screen_arg, int64_t bench)
{
    uint8_t bytes[FV_HID_MAX_DESCRIPTOR_BYTES];
    size_t n;
    if (!load_descriptor(dpath, bytes, sizeof bytes, &n)) return FV_EXIT_FAIL;
    fv_hid_descriptor *d = calloc(1, sizeof *d);
    if (!d) return FV_EXIT_FAIL;
    int rc = FV_EXIT_OK;
    size_t count = 0;
    blob *reports = NULL;
    if (fv_hid_descriptor_parse(bytes, n, d) != FV_OK) {
        fprintf(stderr, "fovea hid decode: %s: not a valid report descriptor\n", dpath);
        rc = FV_EXIT_FAIL;
        goto done;
    }
    const fv_hid_quirk *quirk = NULL;
    if (vidpid) {
        unsigned vid, pid;
        char extra;
        if (sscanf(vidpid, "%x:%x%c", &vid, &pid, &extra) != 2 || vid > 0xFFFF || pid > 0xFFFF) {
            rc = fv_cli_usage_error("hid", USAGE, "--vid-pid '%s': expected hex VID:PID", vidpid);
            goto done;
        }
        quirk = fv_hid_quirk_find((uint16_t)vid, (uint16_t)pid);
        if (!quirk) fprintf(stderr, "fovea hid decode: note: %04x:%04x is not in the quirks table\n", vid, pid);
    }
    fv_hid_eyetracker_map m;
    bool et = fv_hid_is_eye_tracker(d) || (quirk && quirk->eye_tracker);
    if (et && fv_hid_eyetracker_map_init(d, quirk, &m) != FV_OK) et = false;
    fv_hid_screen_config screen;
    fv_hid_screen_config_defaults(&screen);
    if (screen_arg) {
        uint32_t w, h;
        if (!fv_cli_parse_size(screen_arg, 100000, &w, &h)) {
            rc = fv_cli_usage_error("hid", USAGE, "--screen '%s': expected WxH in millimetres", screen_arg);
            goto done;
        }
        screen.width_mm = (float)w;
        screen.height_mm = (float)h;
    }
    reports = load_reports(rpath, &count);
    if (!reports) {
        rc = FV_EXIT_FAIL;
        goto done;
    }
    /* Without --screen, a Configuration report among the inputs gives the calibrated size. */
    for (size_t i = 0; et && !screen_arg && i < count; i++) {
        fv_hid_configuration cfg;
        uint8_t id = d->uses_report_ids && reports[i].len ? reports[i].bytes[0] : 0;
        if (m.calibrated_width.field < 0 || id != d->fields[m.calibrated_width.field].report_id) continue;
        fv_log_set_level("hid", FV_LOG_LEVEL_ERROR);
        if (fv_hid_eyetracker_decode_configuration(d, &m, reports[i].bytes, reports[i].len, &cfg) == FV_OK &&
            cfg.calibrated_width_mm > 0 && cfg.calibrated_height_mm > 0) {
            screen.width_mm = (float)cfg.calibrated_width_mm;
            screen.height_mm = (float)cfg.calibrated_height_mm;
        }
    }
    if (bench > 0) {
        const blob *b = &reports[0];
        fv_gaze_sample s;
        uint64_t ok = 0;
        bool tracking = et && b->len && (!d->uses_report_ids || b->bytes[0] == m.tracking_id);
        int64_t t0 = fv_time_monotonic_ns();
        for (int64_t i = 0; i < bench; i++) {
            if (tracking) {
                ok += fv_hid_eyetracker_decode_tracking(d, &m, &screen, b->bytes, b->len, &s) == FV_OK;
            } else {
                const fv_hid_report *rep;
                if (fv_hid_report_check(d, FV_HID_REPORT_INPUT, b->bytes, b->len, &rep) != FV_OK) break;
                size_t skip = d->uses_report_ids ? 1u : 0u;
                bool all_read = true;
                for (uint32_t f = 0; f < d->field_count; f++) {
                    int64_t v;
                    const fv_hid_field *fd = &d->fields[f];
                    if (fd->report_id == rep->id && fd->type == rep->type && fd->usage_ranges)
                        all_read &= fv_hid_field_read(fd, 0, b->bytes + skip, b->len - skip, &v) == FV_OK;
                }
                ok += all_read;
            }
        }
        double secs = (double)(fv_time_monotonic_ns() - t0) * 1e-9;
        double rate = secs > 0 ? (double)ok / secs : 0.0;
        if (json) {
            cJSON *root = cJSON_CreateObject();
            fv_cli_json_add_string(root, "what", tracking ? "tracking report -> fv_gaze_sample" : "generic fields");
            cJSON_AddNumberToObject(root, "reports", (double)ok);
            cJSON_AddNumberToObject(root, "seconds", secs);
            cJSON_AddNumberToObject(root, "reports_per_second", rate);
            rc = print_json(root);
        } else {
            printf("decoded %llu %s reports in %.3f ms: %.0f reports/s (%.1f ns per report)\n",
                   (unsigned long long)ok, tracking ? "tracking" : "input", secs * 1e3, rate,
                   ok ? secs * 1e9 / (double)ok : 0.0);
        }
        if (ok != (uint64_t)bench) rc = FV_EXIT_FAIL;
        goto done;
    }
    cJSON *root = json ? cJSON_CreateObject() : NULL;
    cJSON *arr = root ? cJSON_AddArrayToObject(root, "reports") : NULL;
    if (root) cJSON_AddBoolToObject(root, "eye_tracker", et);
    for (size_t i = 0; i < count; i++)
        if (decode_one(d, &m, et, &screen, &reports[i], i, forced_type, arr) != FV_EXIT_OK) rc = FV_EXIT_FAIL;
    if (root && print_json(root) != FV_EXIT_OK) rc = FV_EXIT_FAIL;
done:
    if (reports) free_reports(reports, count);
    free(d);
    return rc;
}

int fv_cmd_hid(int argc, char **argv)
{
    if (argc < 2 || fv_cli_is_help(argv[1])) {
        fputs(USAGE, argc < 2 ? stderr : stdout);
        return argc < 2 ? FV_EXIT_USAGE : FV_EXIT_OK;
    }
    const char *sub = argv[1];
    bool json = false;
    int forced_type = -1;
    const char *vidpid = NULL, *screen = NULL, *pos[2] = {NULL, NULL};
    int npos = 0;
    int64_t bench = 0;
    for (int i = 2; i < argc; i++) {
        const char *val;
        int o;
        if (fv_cli_is_help(argv[i])) {
            fputs(USAGE, stdout);
            return FV_EXIT_OK;
        }
        if (strcmp(argv[i], "--json") == 0) {
            json = true;
        } else if ((o = fv_cli_option(argc, argv, &i, "--type", &val)) != 0) {
            if (o < 0) return fv_cli_usage_error("hid", USAGE, "--type needs a value");
            if (strcmp(val, "input") == 0) forced_type = FV_HID_REPORT_INPUT;
            else if (strcmp(val, "feature") == 0) forced_type = FV_HID_REPORT_FEATURE;
            else if (strcmp(val, "output") == 0) forced_type = FV_HID_REPORT_OUTPUT;
            else return fv_cli_usage_error("hid", USAGE, "--type '%s': expected input, feature or output", val);
        } else if ((o = fv_cli_option(argc, argv, &i, "--vid-pid", &val)) != 0) {
            if (o < 0) return fv_cli_usage_error("hid", USAGE, "--vid-pid needs a value");
            vidpid = val;
        } else if ((o = fv_cli_option(argc, argv, &i, "--screen", &val)) != 0) {
            if (o < 0) return fv_cli_usage_error("hid", USAGE, "--screen needs a value");
            screen = val;
        } else if ((o = fv_cli_option(argc, argv, &i, "--bench", &val)) != 0) {
            if (o < 0 || !fv_cli_parse_i64(val, 1, INT64_C(1000000000), &bench))
                return fv_cli_usage_error("hid", USAGE, "--bench needs a count in 1..1e9");
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            return fv_cli_usage_error("hid", USAGE, "unknown option '%s'", argv[i]);
        } else {
            if (npos >= 2) return fv_cli_usage_error("hid", USAGE, "unexpected argument '%s'", argv[i]);
            pos[npos++] = argv[i];
        }
    }
    if (strcmp(sub, "parse") == 0) {
        if (npos != 1) return fv_cli_usage_error("hid", USAGE, "parse takes one FILE");
        if (vidpid || screen || bench || forced_type >= 0)
            return fv_cli_usage_error("hid", USAGE, "parse takes only --json");
        return cmd_parse(pos[0], json);
    }
    if (strcmp(sub, "decode") == 0) {
        if (npos != 2) return fv_cli_usage_error("hid", USAGE, "decode takes DESCRIPTOR and REPORTS");
        return cmd_decode(pos[0], pos[1], json, forced_type, vidpid, screen, bench);
    }
    return fv_cli_usage_error("hid", USAGE, "unknown subcommand '%s' (parse, decode)", sub);
}
