/* @brief HID report-descriptor parser (HID 1.11 §5.8, §6.2.2): items → fields, collections and report layouts. */
#include "fv_hid_descriptor.h"

#include <stdio.h>
#include <string.h>

#include "fv_log.h"

#define MOD "hid"
#define PI_D 3.14159265358979323846
#define MAX_LOCAL_USAGES 64 /* usage items (or ranges) before one main item */

/* Global item state (§6.2.2.7), saved and restored by Push/Pop. Raw values are kept with their sizes so that the
 * sign of Logical/Physical Maximum can be decided at the main item, once the minimum is known. */
typedef struct global_state {
    uint16_t usage_page;
    uint32_t logical_min_raw, logical_max_raw, physical_min_raw, physical_max_raw;
    uint8_t logical_min_size, logical_max_size, physical_min_size, physical_max_size;
    int8_t unit_exponent;
    uint32_t unit;
    uint32_t report_size;
    uint32_t report_count;
    uint32_t report_id;
} global_state;

typedef struct local_state {
    fv_hid_usage_range usages[MAX_LOCAL_USAGES];
    uint32_t usage_count;
    bool have_min, have_max;     /* a Usage Minimum / Maximum waiting for its pair */
    uint32_t range_min, range_max;
    uint32_t min_offset;         /* byte offset of the pending Usage Minimum */
    int delimiter_depth;         /* inside an open Delimiter set */
    uint32_t delimiter_usages;   /* usages seen in the current set (only the first is kept) */
} local_state;

typedef struct parser {
    const uint8_t *bytes;
    size_t size;
    fv_hid_descriptor *d;
    global_state global;
    global_state stack[FV_HID_MAX_PUSH_DEPTH];
    int stack_depth;
    local_state local;
    int16_t open[FV_HID_MAX_COLLECTION_DEPTH]; /* indices of open collections */
    int depth;
    uint32_t first_idless_main; /* offset of the first main item with no report ID (UINT32_MAX: none) */
} parser;

static int64_t sign_extend(uint32_t raw, unsigned size_bytes)
{
    switch (size_bytes) {
    case 1: return (int8_t)(uint8_t)raw;
    case 2: return (int16_t)(uint16_t)raw;
    case 4: return (int32_t)raw;
    default: return 0;
    }
}

/* Resolve a min/max pair. Both are signed as the spec says; when that gives max < min and the maximum only went
 * negative by sign extension (a common descriptor bug: Logical Maximum 255 written as one byte), the maximum is read
 * unsigned instead. The minimum stays signed, as Linux and Windows read it. */
static void resolve_range(uint32_t min_raw, uint8_t min_size, uint32_t max_raw, uint8_t max_size, int64_t *out_min,
                          int64_t *out_max)
{
    int64_t lo = sign_extend(min_raw, min_size);
    int64_t hi = sign_extend(max_raw, max_size);
    if (hi < lo && max_size > 0) {
        int64_t hi_u = (int64_t)(max_size == 4 ? max_raw : (max_raw & ((1u << (8 * max_size)) - 1u)));
        if (hi_u >= lo) hi = hi_u;
    }
    *out_min = lo;
    *out_max = hi;
}

static fv_result fail(parser *p, fv_result r, size_t offset, const char *fmt, const char *detail, uint32_t a,
                      uint32_t b)
{
    char reason[160];
    snprintf(reason, sizeof reason, fmt, a, b);
    FV_ERROR(MOD, "report descriptor byte %zu (of %zu): %s%s", offset, p->size, reason, detail ? detail : "");
    return r;
}

static fv_hid_report *get_report(parser *p, uint8_t type, uint8_t id, size_t offset, fv_result *out_r)
{
    fv_hid_descriptor *d = p->d;
    for (uint32_t i = 0; i < d->report_count; i++)
        if (d->reports[i].type == type && d->reports[i].id == id) return &d->reports[i];
    if (d->report_count >= FV_HID_MAX_REPORTS) {
        *out_r = fail(p, FV_ERR_UNSUPPORTED, offset, "more than %u reports (fovea's limit)", NULL,
                      FV_HID_MAX_REPORTS, 0);
        return NULL;
    }
    fv_hid_report *r = &d->reports[d->report_count++];
    memset(r, 0, sizeof *r);
    r->type = type;
    r->id = id;
    return r;
}

static void clear_local(local_state *l) { memset(l, 0, sizeof *l); }

static fv_result add_local_usage(parser *p, size_t offset, uint32_t min, uint32_t max)
{
    local_state *l = &p->local;
    if (l->delimiter_depth > 0 && l->delimiter_usages++ > 0) return FV_OK; /* alternates of a set: keep the first */
    if (l->usage_count >= MAX_LOCAL_USAGES)
        return fail(p, FV_ERR_UNSUPPORTED, offset, "more than %u usages before one main item (fovea's limit)", NULL,
                    MAX_LOCAL_USAGES, 0);
    l->usages[l->usage_count].min = min;
    l->usages[l->usage_count].max = max;
    l->usage_count++;
    return FV_OK;
}

/* A 1- or 2-byte usage takes the Usage Page in effect now; a 4-byte one carries its page (an extended usage). */
static uint32_t extended_usage(const parser *p, uint32_t data, unsigned size)
{
    if (size == 4) return data;
    return ((uint32_t)p->global.usage_page << 16) | (data & 0xFFFFu);
}

static fv_result main_field(parser *p, size_t offset, uint8_t type, uint32_t data)
{
    fv_hid_descriptor *d = p->d;
    global_state *g = &p->global;
    local_state *l = &p->local;
    fv_result r = FV_OK;

    if (l->have_min != l->have_max)
        return fail(p, FV_ERR_PARSE, offset,
                    l->have_min ? "main item follows a Usage Minimum (byte %u) without a Usage Maximum"
                                : "main item follows a Usage Maximum without a Usage Minimum",
                    NULL, l->min_offset, 0);
    if (l->delimiter_depth != 0)
        return fail(p, FV_ERR_PARSE, offset, "main item inside an open Delimiter set", NULL, 0, 0);

    bool has_usage = l->usage_count > 0;
    if (g->report_count > 0 && g->report_size == 0 && has_usage)
        return fail(p, FV_ERR_PARSE, offset, "Report Size is 0 for a field with %u usage(s) (Report Count %u)",
                    NULL, l->usage_count, g->report_count);
    if (g->report_size > 32 && has_usage && g->report_count > 0)
        return fail(p, FV_ERR_PARSE, offset,
                    "Report Size %u bits for a field with usages (at most 32: one value per usage)", NULL,
                    g->report_size, 0);
    if (g->report_size > 256)
        return fail(p, FV_ERR_PARSE, offset, "Report Size %u bits exceeds 256", NULL, g->report_size, 0);
    uint64_t bits = (uint64_t)g->report_size * g->report_count;
    if (g->report_count > FV_HID_MAX_REPORT_BYTES * 8u || bits > FV_HID_MAX_REPORT_BYTES * 8u)
        return fail(p, FV_ERR_PARSE, offset, "Report Count %u x Report Size %u exceeds the 4096-byte report limit",
                    NULL, g->report_count, g->report_size);

    uint8_t id = (uint8_t)g->report_id;
    if (id == 0 && p->first_idless_main == UINT32_MAX) p->first_idless_main = (uint32_t)offset;
    fv_hid_report *rep = get_report(p, type, id, offset, &r);
    if (!rep) return r;
    if ((uint64_t)rep->bit_length + bits > FV_HID_MAX_REPORT_BYTES * 8u)
        return fail(p, FV_ERR_PARSE, offset, "report 0x%02x grows past %u bytes", NULL, id, FV_HID_MAX_REPORT_BYTES);

    if (g->report_count > 0 && g->report_size > 0) {
        if (d->field_count >= FV_HID_MAX_FIELDS)
            return fail(p, FV_ERR_UNSUPPORTED, offset, "more than %u fields (fovea's limit)", NULL,
                        FV_HID_MAX_FIELDS, 0);
        if (d->usage_count + l->usage_count > FV_HID_MAX_USAGE_RANGES)
            return fail(p, FV_ERR_UNSUPPORTED, offset, "more than %u usage ranges (fovea's limit)", NULL,
                        FV_HID_MAX_USAGE_RANGES, 0);
        fv_hid_field *f = &d->fields[d->field_count++];
        memset(f, 0, sizeof *f);
        f->item_offset = (uint32_t)offset;
        f->type = type;
        f->report_id = id;
        f->flags = (uint16_t)(data & 0x1FFu);
        f->collection = p->depth > 0 ? (uint16_t)p->open[p->depth - 1] : 0;
        f->usage_first = (uint16_t)d->usage_count;
        f->usage_ranges = (uint16_t)l->usage_count;
        uint64_t total = 0;
        for (uint32_t i = 0; i < l->usage_count; i++) {
            d->usages[d->usage_count++] = l->usages[i];
            total += (uint64_t)(l->usages[i].max - l->usages[i].min) + 1u;
        }
        f->usage_total = total > UINT32_MAX ? UINT32_MAX : (uint32_t)total;
        f->bit_offset = rep->bit_length;
        f->bit_size = g->report_size;
        f->count = g->report_count;
        resolve_range(g->logical_min_raw, g->logical_min_size, g->logical_max_raw, g->logical_max_size,
                      &f->logical_min, &f->logical_max);
        if (g->physical_min_raw == 0 && g->physical_max_raw == 0) {
            f->physical_min = f->logical_min;
            f->physical_max = f->logical_max;
        } else {
            resolve_range(g->physical_min_raw, g->physical_min_size, g->physical_max_raw, g->physical_max_size,
                          &f->physical_min, &f->physical_max);
        }
        f->unit = g->unit;
        f->unit_exponent = g->unit_exponent;
        rep->field_count++;
    }
    rep->bit_length += (uint32_t)bits;
    clear_local(l);
    return FV_OK;
}

static fv_result item_main(parser *p, size_t offset, unsigned tag, uint32_t data)
{
    fv_hid_descriptor *d = p->d;
    switch (tag) {
    case 0x8: return main_field(p, offset, FV_HID_REPORT_INPUT, data);
    case 0x9: return main_field(p, offset, FV_HID_REPORT_OUTPUT, data);
    case 0xB: return main_field(p, offset, FV_HID_REPORT_FEATURE, data);
    case 0xA: { /* Collection */
        if (p->depth >= FV_HID_MAX_COLLECTION_DEPTH)
            return fail(p, FV_ERR_PARSE, offset, "collections nested deeper than %u", NULL,
                        FV_HID_MAX_COLLECTION_DEPTH, 0);
        if (d->collection_count >= FV_HID_MAX_COLLECTIONS)
            return fail(p, FV_ERR_UNSUPPORTED, offset, "more than %u collections (fovea's limit)", NULL,
                        FV_HID_MAX_COLLECTIONS, 0);
        fv_hid_collection *c = &d->collections[d->collection_count];
        c->usage = p->local.usage_count > 0 ? p->local.usages[0].min : (p->local.have_min ? p->local.range_min : 0);
        c->item_offset = (uint32_t)offset;
        c->parent = p->depth > 0 ? p->open[p->depth - 1] : -1;
        c->type = (uint8_t)data;
        c->depth = (uint8_t)p->depth;
        p->open[p->depth++] = (int16_t)d->collection_count;
        d->collection_count++;
        clear_local(&p->local);
        return FV_OK;
    }
    case 0xC: /* End Collection */
        if (p->depth == 0) return fail(p, FV_ERR_PARSE, offset, "End Collection without an open Collection", NULL, 0, 0);
        p->depth--;
        clear_local(&p->local);
        return FV_OK;
    default:
        FV_DEBUG(MOD, "report descriptor byte %zu: reserved main item tag 0x%x ignored", offset, tag);
        clear_local(&p->local);
        return FV_OK;
    }
}

static fv_result item_global(parser *p, size_t offset, unsigned tag, uint32_t data, unsigned size)
{
    global_state *g = &p->global;
    switch (tag) {
    case 0x0:
        if (data > 0xFFFFu)
            return fail(p, FV_ERR_PARSE, offset, "Usage Page 0x%x does not fit 16 bits", NULL, data, 0);
        g->usage_page = (uint16_t)data;
        return FV_OK;
    case 0x1: g->logical_min_raw = data; g->logical_min_size = (uint8_t)size; return FV_OK;
    case 0x2: g->logical_max_raw = data; g->logical_max_size = (uint8_t)size; return FV_OK;
    case 0x3: g->physical_min_raw = data; g->physical_min_size = (uint8_t)size; return FV_OK;
    case 0x4: g->physical_max_raw = data; g->physical_max_size = (uint8_t)size; return FV_OK;
    case 0x5: /* Unit Exponent: a 4-bit two's-complement nibble (§6.2.2.7); some devices write a full signed byte */
        if (data <= 0xFu)
            g->unit_exponent = (int8_t)(data >= 8 ? (int)data - 16 : (int)data);
        else {
            int64_t e = sign_extend(data, size);
            if (e < -16 || e > 15)
                return fail(p, FV_ERR_PARSE, offset, "Unit Exponent 0x%x out of range", NULL, data, 0);
            g->unit_exponent = (int8_t)e;
        }
        return FV_OK;
    case 0x6: g->unit = data; return FV_OK;
    case 0x7: g->report_size = data; return FV_OK;
    case 0x8:
        if (data == 0 || data > 255)
            return fail(p, FV_ERR_PARSE, offset, "Report ID %u (must be 1..255)", NULL, data, 0);
        g->report_id = data;
        p->d->uses_report_ids = true;
        return FV_OK;
    case 0x9: g->report_count = data; return FV_OK;
    case 0xA:
        if (p->stack_depth >= FV_HID_MAX_PUSH_DEPTH)
            return fail(p, FV_ERR_PARSE, offset, "Push nested deeper than %u", NULL, FV_HID_MAX_PUSH_DEPTH, 0);
        p->stack[p->stack_depth++] = *g;
        return FV_OK;
    case 0xB:
        if (p->stack_depth == 0) return fail(p, FV_ERR_PARSE, offset, "Pop without a matching Push", NULL, 0, 0);
        *g = p->stack[--p->stack_depth];
        return FV_OK;
    default:
        return fail(p, FV_ERR_PARSE, offset, "reserved global item tag 0x%x", NULL, tag, 0);
    }
}

static fv_result item_local(parser *p, size_t offset, unsigned tag, uint32_t data, unsigned size)
{
    local_state *l = &p->local;
    switch (tag) {
    case 0x0: {
        uint32_t u = extended_usage(p, data, size);
        return add_local_usage(p, offset, u, u);
    }
    case 0x1:
        if (l->have_min) return fail(p, FV_ERR_PARSE, offset, "second Usage Minimum before a Usage Maximum", NULL, 0, 0);
        l->have_min = true;
        l->range_min = extended_usage(p, data, size);
        l->min_offset = (uint32_t)offset;
        break;
    case 0x2:
        if (l->have_max) return fail(p, FV_ERR_PARSE, offset, "second Usage Maximum before a Usage Minimum", NULL, 0, 0);
        l->have_max = true;
        l->range_max = extended_usage(p, data, size);
        break;
    case 0xA: /* Delimiter: 1 opens a set of alternative usages, 0 closes it */
        if (data == 1) {
            if (l->delimiter_depth) return fail(p, FV_ERR_PARSE, offset, "nested Delimiter open", NULL, 0, 0);
            l->delimiter_depth = 1;
            l->delimiter_usages = 0;
        } else if (data == 0) {
            if (!l->delimiter_depth) return fail(p, FV_ERR_PARSE, offset, "Delimiter close without open", NULL, 0, 0);
            l->delimiter_depth = 0;
        } else {
            return fail(p, FV_ERR_PARSE, offset, "Delimiter value %u (must be 0 or 1)", NULL, data, 0);
        }
        return FV_OK;
    default: /* designators and strings: accepted, not used */
        return FV_OK;
    }
    if (l->have_min && l->have_max) {
        uint32_t lo = l->range_min, hi = l->range_max;
        l->have_min = l->have_max = false;
        if ((lo >> 16) != (hi >> 16))
            return fail(p, FV_ERR_PARSE, offset, "usage range spans pages 0x%04x..0x%04x", NULL, lo >> 16, hi >> 16);
        if (hi < lo)
            return fail(p, FV_ERR_PARSE, offset, "Usage Maximum 0x%x below Usage Minimum 0x%x", NULL, hi & 0xFFFFu,
                        lo & 0xFFFFu);
        return add_local_usage(p, offset, lo, hi);
    }
    return FV_OK;
}

fv_result fv_hid_descriptor_parse(const uint8_t *bytes, size_t size, fv_hid_descriptor *out)
{
    if (!out || (!bytes && size)) return FV_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    parser p;
    memset(&p, 0, sizeof p);
    p.bytes = bytes;
    p.size = size;
    p.d = out;
    p.first_idless_main = UINT32_MAX;
    out->size = (uint32_t)size;
    if (size == 0) {
        FV_ERROR(MOD, "report descriptor is empty");
        return FV_ERR_PARSE;
    }
    if (size > FV_HID_MAX_DESCRIPTOR_BYTES) {
        FV_ERROR(MOD, "report descriptor of %zu bytes exceeds the %u-byte limit", size, FV_HID_MAX_DESCRIPTOR_BYTES);
        return FV_ERR_PARSE;
    }

    size_t i = 0;
    while (i < size) {
        uint8_t prefix = bytes[i];
        if (prefix == 0xFE) { /* long item: 0xFE bDataSize bLongItemTag data... (§6.2.2.3); none are defined */
            if (size - i < 3)
                return fail(&p, FV_ERR_PARSE, i, "long item header truncated (%u of 3 bytes)", NULL,
                            (uint32_t)(size - i), 0);
            size_t n = bytes[i + 1];
            if (size - i - 3 < n)
                return fail(&p, FV_ERR_PARSE, i, "long item needs %u data bytes, only %u left", NULL, (uint32_t)n,
                            (uint32_t)(size - i - 3));
            out->long_items++;
            i += 3 + n;
            continue;
        }
        static const unsigned sizes[4] = {0, 1, 2, 4};
        unsigned n = sizes[prefix & 3u];
        unsigned type = (prefix >> 2) & 3u;
        unsigned tag = prefix >> 4;
        if (size - i - 1 < n)
            return fail(&p, FV_ERR_PARSE, i, "truncated item 0x%02x: needs %u data bytes", NULL, prefix, n);
        uint32_t data = 0;
        for (unsigned k = 0; k < n; k++) data |= (uint32_t)bytes[i + 1 + k] << (8 * k);
        fv_result r;
        switch (type) {
        case 0: r = item_main(&p, i, tag, data); break;
        case 1: r = item_global(&p, i, tag, data, n); break;
        case 2: r = item_local(&p, i, tag, data, n); break;
        default: r = fail(&p, FV_ERR_PARSE, i, "reserved item type 3 (prefix 0x%02x)", NULL, prefix, 0); break;
        }
        if (FV_FAILED(r)) return r;
        out->item_count++;
        i += 1 + n;
    }
    if (p.depth > 0) {
        const fv_hid_collection *c = &out->collections[p.open[p.depth - 1]];
        return fail(&p, FV_ERR_PARSE, size, "descriptor ends with %u collection(s) open (innermost opened at byte %u)",
                    NULL, (uint32_t)p.depth, c->item_offset);
    }
    if (out->uses_report_ids && p.first_idless_main != UINT32_MAX)
        return fail(&p, FV_ERR_PARSE, p.first_idless_main,
                    "main item has no Report ID although the descriptor declares report IDs", NULL, 0, 0);
    if (out->field_count == 0) {
        FV_ERROR(MOD, "report descriptor (%zu bytes) declares no report fields", size);
        return FV_ERR_PARSE;
    }
    return FV_OK;
}

const fv_hid_report *fv_hid_descriptor_find_report(const fv_hid_descriptor *d, fv_hid_report_type type, uint8_t id)
{
    for (uint32_t i = 0; i < d->report_count; i++)
        if (d->reports[i].type == type && d->reports[i].id == id) return &d->reports[i];
    return NULL;
}

size_t fv_hid_report_byte_length(const fv_hid_descriptor *d, const fv_hid_report *r)
{
    return (r->bit_length + 7u) / 8u + (d->uses_report_ids ? 1u : 0u);
}

size_t fv_hid_descriptor_max_report_length(const fv_hid_descriptor *d, fv_hid_report_type type)
{
    size_t best = 0;
    for (uint32_t i = 0; i < d->report_count; i++) {
        if (d->reports[i].type != type) continue;
        size_t n = fv_hid_report_byte_length(d, &d->reports[i]);
        if (n > best) best = n;
    }
    return best;
}

uint32_t fv_hid_field_usage(const fv_hid_descriptor *d, const fv_hid_field *f, uint32_t index)
{
    if (f->usage_ranges == 0) return 0;
    uint32_t left = index;
    for (uint32_t i = 0; i < f->usage_ranges; i++) {
        const fv_hid_usage_range *r = &d->usages[f->usage_first + i];
        uint32_t n = r->max - r->min; /* span - 1 */
        if (left <= n) return r->min + left;
        left -= n + 1;
    }
    return d->usages[f->usage_first + f->usage_ranges - 1].max;
}

bool fv_hid_field_has_usage(const fv_hid_descriptor *d, const fv_hid_field *f, uint32_t usage)
{
    for (uint32_t i = 0; i < f->usage_ranges; i++) {
        const fv_hid_usage_range *r = &d->usages[f->usage_first + i];
        if (usage >= r->min && usage <= r->max) return true;
    }
    return false;
}

fv_result fv_hid_field_read(const fv_hid_field *f, uint32_t index, const uint8_t *payload, size_t payload_len,
                            int64_t *out_value)
{
    if (index >= f->count || f->bit_size == 0 || f->bit_size > 32) return FV_ERR_INVALID_ARG;
    uint64_t start = (uint64_t)f->bit_offset + (uint64_t)index * f->bit_size;
    if (start + f->bit_size > (uint64_t)payload_len * 8u) return FV_ERR_PROTOCOL;
    uint64_t v = 0;
    if ((start & 7u) == 0 && (f->bit_size & 7u) == 0) { /* byte-aligned: the common case */
        for (uint32_t b = 0; b < f->bit_size / 8u; b++) v |= (uint64_t)payload[(start >> 3) + b] << (8u * b);
    } else {
        for (uint32_t b = 0; b < f->bit_size; b++) {
            uint64_t bit = start + b;
            if (payload[bit >> 3] & (1u << (bit & 7u))) v |= (uint64_t)1 << b;
        }
    }
    if (f->logical_min < 0 && f->bit_size < 64 && (v >> (f->bit_size - 1)) & 1u)
        *out_value = (int64_t)v - ((int64_t)1 << f->bit_size);
    else
        *out_value = (int64_t)v;
    return FV_OK;
}

fv_result fv_hid_field_write(const fv_hid_field *f, uint32_t index, int64_t value, uint8_t *payload,
                             size_t payload_len)
{
    if (index >= f->count || f->bit_size == 0 || f->bit_size > 32) return FV_ERR_INVALID_ARG;
    uint64_t start = (uint64_t)f->bit_offset + (uint64_t)index * f->bit_size;
    if (start + f->bit_size > (uint64_t)payload_len * 8u) return FV_ERR_RANGE;
    uint64_t v = (uint64_t)value;
    for (uint32_t b = 0; b < f->bit_size; b++) {
        uint64_t bit = start + b;
        uint8_t mask = (uint8_t)(1u << (bit & 7u));
        if ((v >> b) & 1u)
            payload[bit >> 3] |= mask;
        else
            payload[bit >> 3] &= (uint8_t)~mask;
    }
    return FV_OK;
}

double fv_hid_field_physical(const fv_hid_field *f, int64_t logical)
{
    double lmin = (double)f->logical_min, lmax = (double)f->logical_max;
    double pmin = (double)f->physical_min, pmax = (double)f->physical_max;
    if (lmax == lmin || (pmin == lmin && pmax == lmax)) return (double)logical;
    return pmin + ((double)logical - lmin) * (pmax - pmin) / (lmax - lmin);
}

/* Unit code: nibble 0 system (1 SI linear, 2 SI rotation, 3 English linear, 4 English rotation), then signed 4-bit
 * exponents of length, mass, time, temperature, current, luminous intensity (HID 1.11 §6.2.2.7). */
static int unit_nibble(uint32_t unit, unsigned k)
{
    int v = (int)((unit >> (4 * k)) & 0xFu);
    return v >= 8 ? v - 16 : v;
}

static double pow10i(int e)
{
    double r = 1.0;
    for (int i = 0; i < (e < 0 ? -e : e); i++) r *= 10.0;
    return e < 0 ? 1.0 / r : r;
}

static bool unit_only(uint32_t unit, unsigned nibble, int exponent)
{
    for (unsigned k = 1; k < 8; k++) {
        int want = k == nibble ? exponent : 0;
        if (unit_nibble(unit, k) != want) return false;
    }
    return true;
}

bool fv_hid_unit_length_to_mm(uint32_t unit, int8_t exponent, double *out_factor)
{
    unsigned sys = unit & 0xFu;
    if (!unit_only(unit, 1, 1)) return false;
    if (sys == 1) *out_factor = 10.0 * pow10i(exponent);
    else if (sys == 3) *out_factor = 25.4 * pow10i(exponent);
    else return false;
    return true;
}

bool fv_hid_unit_time_to_ns(uint32_t unit, int8_t exponent, double *out_factor)
{
    unsigned sys = unit & 0xFu;
    if (sys == 0 || sys > 4 || !unit_only(unit, 3, 1)) return false;
    *out_factor = 1e9 * pow10i(exponent);
    return true;
}

bool fv_hid_unit_angle_to_rad(uint32_t unit, int8_t exponent, double *out_factor)
{
    unsigned sys = unit & 0xFu;
    if (!unit_only(unit, 1, 1)) return false;
    if (sys == 2) *out_factor = pow10i(exponent);
    else if (sys == 4) *out_factor = (PI_D / 180.0) * pow10i(exponent);
    else return false;
    return true;
}

const char *fv_hid_unit_format(uint32_t unit, int8_t exponent, char *buf, size_t cap)
{
    static const char *names[4][8] = {
        {"", "cm", "g", "s", "K", "A", "cd", "?"},
        {"", "rad", "g", "s", "K", "A", "cd", "?"},
        {"", "in", "slug", "s", "F", "A", "cd", "?"},
        {"", "deg", "slug", "s", "F", "A", "cd", "?"},
    };
    if (cap == 0) return buf;
    buf[0] = '\0';
    unsigned sys = unit & 0xFu;
    if (unit == 0) {
        snprintf(buf, cap, "none");
        return buf;
    }
    if (sys < 1 || sys > 4) {
        snprintf(buf, cap, "vendor/unknown 0x%x", unit);
        return buf;
    }
    size_t used = 0;
    for (unsigned k = 1; k < 8; k++) {
        int e = unit_nibble(unit, k);
        if (e == 0) continue;
        int n;
        if (e == 1)
            n = snprintf(buf + used, cap - used, "%s%s", used ? "*" : "", names[sys - 1][k]);
        else
            n = snprintf(buf + used, cap - used, "%s%s^%d", used ? "*" : "", names[sys - 1][k], e);
        if (n < 0 || (size_t)n >= cap - used) return buf;
        used += (size_t)n;
    }
    if (exponent != 0 && used < cap) snprintf(buf + used, cap - used, " e%d", exponent);
    return buf;
}

const char *fv_hid_report_type_name(fv_hid_report_type type)
{
    switch (type) {
    case FV_HID_REPORT_INPUT: return "input";
    case FV_HID_REPORT_OUTPUT: return "output";
    case FV_HID_REPORT_FEATURE: return "feature";
    }
    return "?";
}

const char *fv_hid_collection_type_name(uint8_t type)
{
    static const char *names[] = {"physical", "application", "logical", "report", "named array", "usage switch",
                                  "usage modifier"};
    if (type < sizeof names / sizeof names[0]) return names[type];
    return type >= 0x80 ? "vendor" : "reserved";
}
