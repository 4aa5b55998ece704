/* @brief Eye and Head Trackers page (0x12) → fv_gaze_sample, capabilities, configuration, status, mode request.
 * Usage IDs and report meanings from HUTRR74 (as listed in MSREnable/GazeHid inc/Tracker.h). */
#include "fv_hid_eyetracker.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fv_log.h"

#define MOD "hid"
/* An error about one report: a device can send the same bad report at its full rate, so each call site logs through
 * its own rate limit (5 lines per 30 s, then a summary with the count). */
#define REPORT_ERROR(...)                                                                                              \
    do {                                                                                                               \
        static fv_log_ratelimit rl_ = FV_LOG_RATELIMIT_INIT(5, 30);                                                    \
        FV_ERROR_RL(&rl_, MOD, __VA_ARGS__);                                                                           \
    } while (0)

/* The quirks table. Page 0x12 has no pupil usage, so a vendor that sends pupil diameter in a vendor usage is listed
 * here by VID/PID. Entries need no code. */
static const fv_hid_quirk g_quirks[] = {
    /* fovea's virtual HID eye tracker (sim/vhid): pid.codes test VID/PID, fovea's documented pupil extension. */
    {0x1209, 0x0001, "fovea virtual HID eye tracker", {FV_HID_FOVEA_USAGE_PUPIL_LEFT, FV_HID_FOVEA_USAGE_PUPIL_RIGHT},
     0.0f, true},
    /* Microsoft's reference VHIDMINI eye tracker (MSREnable/GazeHid): standard page 0x12, no pupil. */
    {0xDEED, 0xFEED, "Microsoft GazeHid virtual eye tracker", {0, 0}, 0.0f, true},
};

const fv_hid_quirk *fv_hid_quirk_find(uint16_t vid, uint16_t pid)
{
    for (size_t i = 0; i < sizeof g_quirks / sizeof g_quirks[0]; i++)
        if (g_quirks[i].vid == vid && g_quirks[i].pid == pid) return &g_quirks[i];
    return NULL;
}

const fv_hid_quirk *fv_hid_quirk_table(size_t *out_count)
{
    *out_count = sizeof g_quirks / sizeof g_quirks[0];
    return g_quirks;
}

bool fv_hid_is_eye_tracker(const fv_hid_descriptor *d)
{
    for (uint32_t i = 0; i < d->collection_count; i++) {
        const fv_hid_collection *c = &d->collections[i];
        if (c->parent < 0 && c->type == 1 && c->usage == FV_HID_ET(0x01)) return true;
    }
    return false;
}

static const fv_hid_ref NO_REF = {-1, 0};

/* Usage of the nearest enclosing collection that is one of the page-0x12 position groups (0x24..0x28) or fovea's
 * pupil collection; 0 when none. */
static uint32_t group_of(const fv_hid_descriptor *d, const fv_hid_field *f)
{
    int c = d->collection_count ? f->collection : -1;
    for (int guard = 0; c >= 0 && guard < FV_HID_MAX_COLLECTION_DEPTH + 1; guard++) {
        uint32_t u = d->collections[c].usage;
        if ((u >= FV_HID_ET(0x24) && u <= FV_HID_ET(0x28)) || u == FV_HID_FOVEA_USAGE_PUPIL) return u;
        c = d->collections[c].parent;
    }
    return 0;
}

static void set_ref(fv_hid_ref *r, uint32_t field, uint32_t index)
{
    if (r->field >= 0) return; /* first declaration wins */
    r->field = (int16_t)field;
    r->index = (uint16_t)index;
}

fv_result fv_hid_eyetracker_map_init(const fv_hid_descriptor *d, const fv_hid_quirk *quirk, fv_hid_eyetracker_map *m)
{
    memset(m, 0, sizeof *m);
    m->quirk = quirk;
    fv_hid_ref *refs[] = {&m->timestamp, &m->gaze[0], &m->gaze[1], &m->eye[0][0], &m->eye[0][1], &m->eye[0][2],
                          &m->eye[1][0], &m->eye[1][1], &m->eye[1][2], &m->head_pos[0], &m->head_pos[1],
                          &m->head_pos[2], &m->head_rot[0], &m->head_rot[1], &m->head_rot[2], &m->pupil[0],
                          &m->pupil[1], &m->quality, &m->min_distance, &m->optimum_distance, &m->max_distance,
                          &m->max_screen_width, &m->max_screen_height, &m->display_manufacturer,
                          &m->display_product, &m->display_serial, &m->display_date, &m->calibrated_width,
                          &m->calibrated_height, &m->status_config[0], &m->status_config[1],
                          &m->status_frequency[0], &m->status_frequency[1], &m->mode_request};
    for (size_t i = 0; i < sizeof refs / sizeof refs[0]; i++) *refs[i] = NO_REF;

    bool is_et = fv_hid_is_eye_tracker(d);
    if (!is_et && !(quirk && quirk->eye_tracker)) {
        uint16_t page = d->collection_count ? (uint16_t)(d->collections[0].usage >> 16) : 0;
        FV_ERROR(MOD, "not an eye tracker: no top-level Eye Tracker application collection (usage page 0x12, usage "
                      "0x01); the first collection is on page 0x%04x (%s)",
                 page, fv_hid_usage_page_name(page) ? fv_hid_usage_page_name(page) : "unknown");
        return FV_ERR_UNSUPPORTED;
    }

    for (uint32_t fi = 0; fi < d->field_count; fi++) {
        const fv_hid_field *f = &d->fields[fi];
        if (!(f->flags & FV_HID_FLAG_VARIABLE) || f->usage_ranges == 0) continue;
        uint32_t group = group_of(d, f);
        uint32_t n = f->count < f->usage_total ? f->count : f->usage_total;
        for (uint32_t i = 0; i < n; i++) {
            uint32_t u = fv_hid_field_usage(d, f, i);
            bool in = f->type == FV_HID_REPORT_INPUT, feat = f->type == FV_HID_REPORT_FEATURE;
            if (in && u == FV_HID_ET(0x20)) set_ref(&m->timestamp, fi, i);
            if (in && u >= FV_HID_ET(0x21) && u <= FV_HID_ET(0x23)) {
                unsigned axis = (unsigned)(u - FV_HID_ET(0x21));
                if (group == FV_HID_ET(0x24) && axis < 2) set_ref(&m->gaze[axis], fi, i);
                if (group == FV_HID_ET(0x25)) set_ref(&m->eye[0][axis], fi, i);
                if (group == FV_HID_ET(0x26)) set_ref(&m->eye[1][axis], fi, i);
                if (group == FV_HID_ET(0x27)) set_ref(&m->head_pos[axis], fi, i);
            }
            if (in && u >= FV_HID_ET(0x29) && u <= FV_HID_ET(0x2B) && group == FV_HID_ET(0x28))
                set_ref(&m->head_rot[u - FV_HID_ET(0x29)], fi, i);
            for (int e = 0; e < 2; e++) {
                bool vendor = u == (e == 0 ? FV_HID_FOVEA_USAGE_PUPIL_LEFT : FV_HID_FOVEA_USAGE_PUPIL_RIGHT);
                bool quirked = quirk && quirk->pupil_usage[e] && u == quirk->pupil_usage[e];
                if (in && (vendor || quirked)) set_ref(&m->pupil[e], fi, i);
            }
            if (feat) {
                switch (u) {
                case FV_HID_ET(0x100): set_ref(&m->quality, fi, i); break;
                case FV_HID_ET(0x101): set_ref(&m->min_distance, fi, i); break;
                case FV_HID_ET(0x102): set_ref(&m->optimum_distance, fi, i); break;
                case FV_HID_ET(0x103): set_ref(&m->max_distance, fi, i); break;
                case FV_HID_ET(0x104): set_ref(&m->max_screen_width, fi, i); break;
                case FV_HID_ET(0x105): set_ref(&m->max_screen_height, fi, i); break;
                case FV_HID_ET(0x200): set_ref(&m->display_manufacturer, fi, i); break;
                case FV_HID_ET(0x201): set_ref(&m->display_product, fi, i); break;
                case FV_HID_ET(0x202): set_ref(&m->display_serial, fi, i); break;
                case FV_HID_ET(0x203): set_ref(&m->display_date, fi, i); break;
                case FV_HID_ET(0x204): set_ref(&m->calibrated_width, fi, i); break;
                case FV_HID_ET(0x205): set_ref(&m->calibrated_height, fi, i); break;
                case FV_HID_ET(0x400): set_ref(&m->mode_request, fi, i); break;
                default: break;
                }
            }
            if (u == FV_HID_ET(0x301)) set_ref(&m->status_config[in ? 1 : 0], fi, i);
            if (u == FV_HID_ET(0x300)) set_ref(&m->status_frequency[in ? 1 : 0], fi, i);
        }
    }
    if (m->timestamp.field < 0 || m->gaze[0].field < 0 || m->gaze[1].field < 0) {
        FV_ERROR(MOD, "eye tracker descriptor has no Tracking Data input with %s", m->timestamp.field < 0
                                                                                       ? "a Sensor Timestamp (0x20)"
                                                                                       : "a Gaze Point X/Y (0x24)");
        return FV_ERR_UNSUPPORTED;
    }
    m->tracking_id = d->fields[m->timestamp.field].report_id;
    /* Every tracking value must come from the same report as the timestamp. */
    fv_hid_ref *track[] = {&m->gaze[0], &m->gaze[1], &m->eye[0][0], &m->eye[0][1], &m->eye[0][2], &m->eye[1][0],
                           &m->eye[1][1], &m->eye[1][2], &m->head_pos[0], &m->head_pos[1], &m->head_pos[2],
                           &m->head_rot[0], &m->head_rot[1], &m->head_rot[2], &m->pupil[0], &m->pupil[1]};
    for (size_t i = 0; i < sizeof track / sizeof track[0]; i++) {
        if (track[i]->field >= 0 && d->fields[track[i]->field].report_id != m->tracking_id) {
            FV_WARN(MOD, "eye tracker field at descriptor byte %u is in report 0x%02x, not the tracking report 0x%02x; "
                         "ignored",
                    d->fields[track[i]->field].item_offset, d->fields[track[i]->field].report_id, m->tracking_id);
            *track[i] = NO_REF;
        }
    }
    if (m->gaze[0].field < 0 || m->gaze[1].field < 0) {
        FV_ERROR(MOD, "eye tracker Gaze Point is not in the tracking report 0x%02x", m->tracking_id);
        return FV_ERR_UNSUPPORTED;
    }
    return FV_OK;
}

void fv_hid_screen_config_defaults(fv_hid_screen_config *c)
{
    memset(c, 0, sizeof *c);
    c->screen_center_head_mm = fv_v3(0.0f, 0.0f, -650.0f);
    c->tracker_to_head = fv_quat_identity();
    c->default_eye_head_mm[FV_EYE_LEFT] = fv_v3(-32.0f, 0.0f, 0.0f);
    c->default_eye_head_mm[FV_EYE_RIGHT] = fv_v3(32.0f, 0.0f, 0.0f);
}

fv_result fv_hid_report_check(const fv_hid_descriptor *d, fv_hid_report_type type, const uint8_t *report,
                              size_t len, const fv_hid_report **out_report)
{
    uint8_t id = 0;
    if (d->uses_report_ids) {
        if (len < 1) {
            REPORT_ERROR("empty %s report", fv_hid_report_type_name(type));
            return FV_ERR_PROTOCOL;
        }
        id = report[0];
    }
    const fv_hid_report *r = fv_hid_descriptor_find_report(d, type, id);
    if (!r) {
        REPORT_ERROR("%s report with ID 0x%02x (%zu bytes): the descriptor declares no such %s report",
                     fv_hid_report_type_name(type), id, len, fv_hid_report_type_name(type));
        return FV_ERR_PROTOCOL;
    }
    size_t want = fv_hid_report_byte_length(d, r);
    if (len < want) {
        REPORT_ERROR("%s report 0x%02x is %zu bytes, the descriptor declares %zu", fv_hid_report_type_name(type), id,
                     len, want);
        return FV_ERR_PROTOCOL;
    }
    if (out_report) *out_report = r;
    return FV_OK;
}

/* Read a referenced value; false when absent, unreadable or outside the logical range. */
static bool read_ref(const fv_hid_descriptor *d, fv_hid_ref ref, const uint8_t *payload, size_t plen,
                     int64_t *out_logical)
{
    if (ref.field < 0) return false;
    const fv_hid_field *f = &d->fields[ref.field];
    int64_t v;
    if (fv_hid_field_read(f, ref.index, payload, plen, &v) != FV_OK) return false;
    if (!fv_hid_field_in_range(f, v)) return false;
    *out_logical = v;
    return true;
}

/* A length value in mm; page-0x12 lengths without a unit are taken as µm (what the usage page specifies). */
static bool read_length_mm(const fv_hid_descriptor *d, fv_hid_ref ref, const uint8_t *payload, size_t plen,
                           double unitless_mm, double *out_mm)
{
    int64_t v;
    if (!read_ref(d, ref, payload, plen, &v)) return false;
    const fv_hid_field *f = &d->fields[ref.field];
    double k;
    if (!fv_hid_unit_length_to_mm(f->unit, f->unit_exponent, &k)) {
        if (unitless_mm <= 0.0) return false;
        k = unitless_mm;
    }
    double mm = fv_hid_field_physical(f, v) * k;
    if (!isfinite(mm)) return false;
    *out_mm = mm;
    return true;
}

static const uint8_t *payload_of(const fv_hid_descriptor *d, const uint8_t *report, size_t len, size_t *out_plen)
{
    size_t skip = d->uses_report_ids ? 1u : 0u;
    *out_plen = len - skip;
    return report + skip;
}

/* The Sensor Timestamp: a value array of N elements (8 x 8 bits in Microsoft's descriptors) is one little-endian
 * integer; a single element is the value itself. Returns the raw count and its width in bits. */
static bool read_timestamp(const fv_hid_descriptor *d, const fv_hid_eyetracker_map *m, const uint8_t *payload,
                           size_t plen, uint64_t *out_raw, unsigned *out_bits)
{
    const fv_hid_field *f = &d->fields[m->timestamp.field];
    if (f->usage_total == 1 && f->count > 1) {
        uint64_t bits = (uint64_t)f->count * f->bit_size;
        if (bits > 64) bits = 64;
        uint64_t raw = 0;
        unsigned shift = 0;
        for (uint32_t i = 0; i < f->count && shift < 64; i++) {
            int64_t v;
            if (fv_hid_field_read(f, i, payload, plen, &v) != FV_OK) return false;
            uint64_t mask = f->bit_size >= 64 ? ~(uint64_t)0 : (((uint64_t)1 << f->bit_size) - 1u);
            raw |= ((uint64_t)v & mask) << shift;
            shift += f->bit_size;
        }
        *out_raw = raw;
        *out_bits = (unsigned)bits;
        return true;
    }
    int64_t v;
    if (fv_hid_field_read(f, m->timestamp.index, payload, plen, &v) != FV_OK) return false;
    *out_raw = (uint64_t)v & (f->bit_size >= 64 ? ~(uint64_t)0 : (((uint64_t)1 << f->bit_size) - 1u));
    *out_bits = f->bit_size;
    return true;
}

static fv_vec3 tracker_to_head(const fv_hid_screen_config *s, fv_vec3 p_tracker)
{
    return fv_v3_add(s->screen_center_head_mm, fv_quat_rotate(s->tracker_to_head, p_tracker));
}

fv_result fv_hid_eyetracker_decode_tracking(const fv_hid_descriptor *d, const fv_hid_eyetracker_map *m,
                                            const fv_hid_screen_config *screen, const uint8_t *report, size_t len,
                                            fv_gaze_sample *out)
{
    const fv_hid_report *r;
    FV_TRY(fv_hid_report_check(d, FV_HID_REPORT_INPUT, report, len, &r));
    if (r->id != m->tracking_id) {
        REPORT_ERROR("input report 0x%02x is not Tracking Data (0x%02x)", r->id, m->tracking_id);
        return FV_ERR_PROTOCOL;
    }
    size_t plen;
    const uint8_t *payload = payload_of(d, report, len, &plen);
    fv_gaze_sample_init_invalid(out, 0, 0);

    uint64_t raw_ts;
    unsigned ts_bits;
    if (!read_timestamp(d, m, payload, plen, &raw_ts, &ts_bits)) return FV_ERR_PROTOCOL;
    const fv_hid_field *tf = &d->fields[m->timestamp.field];
    double k_ns;
    if (!fv_hid_unit_time_to_ns(tf->unit, tf->unit_exponent, &k_ns)) k_ns = 1000.0; /* page 0x12: µs */
    double t_ns = (double)raw_ts * k_ns;
    if (!(t_ns < 9.2e18)) {
        REPORT_ERROR("tracking report: Sensor Timestamp %llu does not fit a 64-bit nanosecond time",
                     (unsigned long long)raw_ts);
        return FV_ERR_PROTOCOL;
    }
    int64_t k_int = (int64_t)llround(k_ns);
    if (k_int >= 1 && fabs(k_ns - (double)k_int) < 1e-9)
        out->t_device_ns = (int64_t)raw_ts * k_int; /* exact for µs counters */
    else
        out->t_device_ns = (int64_t)t_ns;

    double gx, gy;
    bool gaze_ok = read_length_mm(d, m->gaze[0], payload, plen, 1e-3, &gx) &&
                   read_length_mm(d, m->gaze[1], payload, plen, 1e-3, &gy);
    if (gaze_ok) {
        out->screen_point_mm = (fv_vec2){(float)gx, (float)gy};
        out->flags |= FV_GAZE_SCREEN_POINT_VALID;
    }

    fv_vec3 eye_head[2];
    bool eye_ok[2];
    for (int e = 0; e < 2; e++) {
        double p[3];
        eye_ok[e] = true;
        for (int a = 0; a < 3; a++) eye_ok[e] = eye_ok[e] && read_length_mm(d, m->eye[e][a], payload, plen, 1e-3, &p[a]);
        eye_head[e] = eye_ok[e] ? tracker_to_head(screen, fv_v3((float)p[0], (float)p[1], (float)p[2]))
                                : screen->default_eye_head_mm[e];
        if (eye_ok[e] && !fv_v3_isfinite(eye_head[e])) {
            eye_ok[e] = false;
            eye_head[e] = screen->default_eye_head_mm[e];
        }
        if (eye_ok[e]) {
            out->eye[e].origin_mm = eye_head[e];
            out->eye[e].flags |= FV_EYE_ORIGIN_VALID;
        }
        double pupil;
        if (read_length_mm(d, m->pupil[e], payload, plen, m->quirk ? m->quirk->pupil_unitless_mm : 0.0, &pupil) &&
            pupil > 0.0 && pupil < 100.0) {
            out->eye[e].pupil_mm = (float)pupil;
            out->eye[e].flags |= FV_EYE_PUPIL_VALID;
        }
    }

    /* Rays: from each eye to the gaze point on the screen plane (one binocular point: both eyes converge on it). */
    bool dir_ok = gaze_ok && screen->width_mm > 0.0f && screen->height_mm > 0.0f;
    fv_vec3 target = fv_v3(0, 0, 0);
    if (dir_ok) {
        fv_vec3 p_tracker = fv_v3((float)(gx - 0.5 * screen->width_mm), (float)(0.5 * screen->height_mm - gy), 0.0f);
        target = tracker_to_head(screen, p_tracker);
        dir_ok = fv_v3_isfinite(target);
    }
    const fv_vec3 nan3 = fv_v3(NAN, NAN, NAN);
    for (int e = 0; e < 2 && dir_ok; e++) {
        fv_vec3 dir = fv_v3_normalize_or(fv_v3_sub(target, eye_head[e]), nan3);
        if (fv_v3_isfinite(dir)) {
            out->eye[e].direction = dir;
            out->eye[e].flags |= FV_EYE_DIRECTION_VALID;
        }
    }
    fv_vec3 mid = fv_v3_scale(fv_v3_add(eye_head[0], eye_head[1]), 0.5f);
    if (eye_ok[0] && eye_ok[1]) {
        out->combined.origin_mm = mid;
        out->combined.flags |= FV_EYE_ORIGIN_VALID;
    }
    if (dir_ok) {
        fv_vec3 dir = fv_v3_normalize_or(fv_v3_sub(target, mid), nan3);
        if (fv_v3_isfinite(dir)) {
            out->combined.direction = dir;
            out->combined.flags |= FV_EYE_DIRECTION_VALID;
        }
    }
    int pupils = 0;
    float pupil_sum = 0.0f;
    for (int e = 0; e < 2; e++)
        if (out->eye[e].flags & FV_EYE_PUPIL_VALID) {
            pupils++;
            pupil_sum += out->eye[e].pupil_mm;
        }
    if (pupils) {
        out->combined.pupil_mm = pupil_sum / (float)pupils;
        out->combined.flags |= FV_EYE_PUPIL_VALID;
    }

    /* Head pose (tracker frame), when the descriptor has it. */
    double hp[3], hr[3];
    bool head_ok = true;
    for (int a = 0; a < 3; a++) head_ok = head_ok && read_length_mm(d, m->head_pos[a], payload, plen, 1e-3, &hp[a]);
    for (int a = 0; a < 3 && head_ok; a++) {
        int64_t v;
        if (!read_ref(d, m->head_rot[a], payload, plen, &v)) {
            head_ok = false;
            break;
        }
        const fv_hid_field *f = &d->fields[m->head_rot[a].field];
        double k;
        /* A rotation unit is honoured; Microsoft's DMF descriptor inherits the µm length unit for its rotations, so any
         * other unit is read as micro-degrees (documented in docs/hid.md). */
        if (!fv_hid_unit_angle_to_rad(f->unit, f->unit_exponent, &k)) k = 1e-6 * (3.14159265358979323846 / 180.0);
        hr[a] = fv_hid_field_physical(f, v) * k;
        head_ok = isfinite(hr[a]);
    }
    if (head_ok) {
        out->head_pos_mm = fv_v3((float)hp[0], (float)hp[1], (float)hp[2]);
        fv_quat q = fv_quat_mul(fv_quat_axis_angle(fv_v3(0, 0, 1), (float)hr[2]),
                                fv_quat_mul(fv_quat_axis_angle(fv_v3(0, 1, 0), (float)hr[1]),
                                            fv_quat_axis_angle(fv_v3(1, 0, 0), (float)hr[0])));
        out->head_dir = fv_v3_normalize_or(fv_quat_rotate(q, fv_v3(0, 0, -1)), fv_v3(0, 0, -1));
        if (fv_v3_isfinite(out->head_pos_mm)) out->flags |= FV_GAZE_HEAD_VALID;
        else {
            out->head_pos_mm = nan3;
            out->head_dir = nan3;
        }
    }
    return FV_OK;
}

static double ref_mm(const fv_hid_descriptor *d, fv_hid_ref ref, const uint8_t *payload, size_t plen)
{
    double mm;
    return read_length_mm(d, ref, payload, plen, 1e-3, &mm) ? mm : NAN;
}

static int64_t ref_int(const fv_hid_descriptor *d, fv_hid_ref ref, const uint8_t *payload, size_t plen)
{
    int64_t v;
    return read_ref(d, ref, payload, plen, &v) ? v : -1;
}

static fv_result check_feature(const fv_hid_descriptor *d, fv_hid_report_type type, fv_hid_ref key,
                               const char *what, const uint8_t *report, size_t len)
{
    if (key.field < 0) {
        REPORT_ERROR("the descriptor declares no %s report", what);
        return FV_ERR_UNSUPPORTED;
    }
    const fv_hid_report *r;
    FV_TRY(fv_hid_report_check(d, type, report, len, &r));
    if (r->id != d->fields[key.field].report_id) {
        REPORT_ERROR("%s report 0x%02x is not the %s report (0x%02x)", fv_hid_report_type_name(type), r->id, what,
                     d->fields[key.field].report_id);
        return FV_ERR_PROTOCOL;
    }
    return FV_OK;
}

fv_result fv_hid_eyetracker_decode_capabilities(const fv_hid_descriptor *d, const fv_hid_eyetracker_map *m,
                                                const uint8_t *report, size_t len, fv_hid_capabilities *out)
{
    fv_hid_ref key = m->quality.field >= 0 ? m->quality : m->min_distance;
    FV_TRY(check_feature(d, FV_HID_REPORT_FEATURE, key, "Capabilities", report, len));
    size_t plen;
    const uint8_t *p = payload_of(d, report, len, &plen);
    out->tracker_quality = (int)ref_int(d, m->quality, p, plen);
    out->min_distance_mm = ref_mm(d, m->min_distance, p, plen);
    out->optimum_distance_mm = ref_mm(d, m->optimum_distance, p, plen);
    out->max_distance_mm = ref_mm(d, m->max_distance, p, plen);
    out->max_screen_width_mm = ref_mm(d, m->max_screen_width, p, plen);
    out->max_screen_height_mm = ref_mm(d, m->max_screen_height, p, plen);
    return FV_OK;
}

fv_result fv_hid_eyetracker_decode_configuration(const fv_hid_descriptor *d, const fv_hid_eyetracker_map *m,
                                                 const uint8_t *report, size_t len, fv_hid_configuration *out)
{
    fv_hid_ref key = m->calibrated_width.field >= 0 ? m->calibrated_width : m->display_manufacturer;
    FV_TRY(check_feature(d, FV_HID_REPORT_FEATURE, key, "Configuration", report, len));
    size_t plen;
    const uint8_t *p = payload_of(d, report, len, &plen);
    out->display_manufacturer = ref_int(d, m->display_manufacturer, p, plen);
    out->display_product = ref_int(d, m->display_product, p, plen);
    out->display_serial = ref_int(d, m->display_serial, p, plen);
    out->display_date = ref_int(d, m->display_date, p, plen);
    out->calibrated_width_mm = ref_mm(d, m->calibrated_width, p, plen);
    out->calibrated_height_mm = ref_mm(d, m->calibrated_height, p, plen);
    return FV_OK;
}

fv_result fv_hid_eyetracker_decode_status(const fv_hid_descriptor *d, const fv_hid_eyetracker_map *m,
                                          fv_hid_report_type type, const uint8_t *report, size_t len,
                                          fv_hid_status *out)
{
    int k = type == FV_HID_REPORT_INPUT ? 1 : 0;
    fv_hid_ref key = m->status_config[k].field >= 0 ? m->status_config[k] : m->status_frequency[k];
    FV_TRY(check_feature(d, type, key, "Status", report, len));
    size_t plen;
    const uint8_t *p = payload_of(d, report, len, &plen);
    out->configuration_status = (int)ref_int(d, m->status_config[k], p, plen);
    int64_t v;
    out->sampling_frequency_hz = NAN;
    if (read_ref(d, m->status_frequency[k], p, plen, &v)) {
        const fv_hid_field *f = &d->fields[m->status_frequency[k].field];
        out->sampling_frequency_hz = fv_hid_field_physical(f, v); /* s^-1 (Hz) */
    }
    return FV_OK;
}

fv_result fv_hid_eyetracker_encode_mode_request(const fv_hid_descriptor *d, const fv_hid_eyetracker_map *m,
                                                unsigned mode, uint8_t *buf, size_t cap, size_t *out_len)
{
    if (m->mode_request.field < 0) {
        FV_ERROR(MOD, "the descriptor declares no Control report with a Device Mode Request");
        return FV_ERR_UNSUPPORTED;
    }
    const fv_hid_field *f = &d->fields[m->mode_request.field];
    const fv_hid_report *r = fv_hid_descriptor_find_report(d, FV_HID_REPORT_FEATURE, f->report_id);
    size_t n = r ? fv_hid_report_byte_length(d, r) : 0;
    if (!r || n > cap) return FV_ERR_RANGE;
    if (!fv_hid_field_in_range(f, (int64_t)mode)) {
        FV_ERROR(MOD, "Device Mode Request %u is outside the declared range %lld..%lld", mode,
                 (long long)f->logical_min, (long long)f->logical_max);
        return FV_ERR_RANGE;
    }
    memset(buf, 0, n);
    size_t skip = d->uses_report_ids ? 1u : 0u;
    if (skip) buf[0] = f->report_id;
    FV_TRY(fv_hid_field_write(f, m->mode_request.index, (int64_t)mode, buf + skip, n - skip));
    *out_len = n;
    return FV_OK;
}
