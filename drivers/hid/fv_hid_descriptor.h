/* @brief Generic HID report-descriptor parser (HID 1.11 §6.2.2): a pure function on bytes, no I/O, no allocation.
 * It walks every short item (main, global, local), skips long items, keeps push/pop state, usage ranges, 32-bit
 * extended usages, signed logical/physical ranges, unit and unit exponent, report IDs and the collection tree, and
 * lays out every report bit by bit. Constant fields that carry usages are kept (page 0x12 trackers declare their data
 * Cnst), usage-less padding is kept as a padding field so its bits are counted, and one report ID may be declared as
 * both input and feature (they are separate reports). */
#ifndef FV_HID_DESCRIPTOR_H
#define FV_HID_DESCRIPTOR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fv_result.h"

/** Limits of fovea's parser (a descriptor beyond them is refused with FV_ERR_UNSUPPORTED, never truncated). */
#define FV_HID_MAX_FIELDS 256
#define FV_HID_MAX_USAGE_RANGES 512
#define FV_HID_MAX_COLLECTIONS 128
#define FV_HID_MAX_REPORTS 96
#define FV_HID_MAX_COLLECTION_DEPTH 16
#define FV_HID_MAX_PUSH_DEPTH 8
#define FV_HID_MAX_REPORT_BYTES 4096 /* payload bytes of one report (without the ID byte) */
#define FV_HID_MAX_DESCRIPTOR_BYTES 4096 /* the hidraw limit (HID_MAX_DESCRIPTOR_SIZE) */

/** Report types (the main item that declared the field). */
typedef enum fv_hid_report_type {
    FV_HID_REPORT_INPUT = 0,
    FV_HID_REPORT_OUTPUT = 1,
    FV_HID_REPORT_FEATURE = 2,
} fv_hid_report_type;

/** Main item data bits (HID 1.11 §6.2.2.5), as declared. */
enum fv_hid_main_flags {
    FV_HID_FLAG_CONSTANT = 1u << 0,   /* Cnst (vs Data) */
    FV_HID_FLAG_VARIABLE = 1u << 1,   /* Var (vs Array) */
    FV_HID_FLAG_RELATIVE = 1u << 2,   /* Rel (vs Abs) */
    FV_HID_FLAG_WRAP = 1u << 3,
    FV_HID_FLAG_NONLINEAR = 1u << 4,
    FV_HID_FLAG_NO_PREFERRED = 1u << 5,
    FV_HID_FLAG_NULL_STATE = 1u << 6,
    FV_HID_FLAG_VOLATILE = 1u << 7,   /* output/feature only */
    FV_HID_FLAG_BUFFERED_BYTES = 1u << 8,
};

/** An inclusive range of extended usages (page << 16 | id); a single usage has min == max. */
typedef struct fv_hid_usage_range {
    uint32_t min, max;
} fv_hid_usage_range;

/** One main item: `count` elements of `bit_size` bits at `bit_offset` in the report payload (after the ID byte). */
typedef struct fv_hid_field {
    uint32_t item_offset;  /* byte offset of the main item in the descriptor */
    uint8_t type;          /* fv_hid_report_type */
    uint8_t report_id;     /* 0 when the descriptor declares no report IDs */
    uint16_t flags;        /* fv_hid_main_flags */
    uint16_t collection;   /* index of the innermost enclosing collection */
    uint16_t usage_first;  /* index of the first range in fv_hid_descriptor.usages */
    uint16_t usage_ranges; /* number of ranges; 0 = padding (no usage) */
    uint32_t usage_total;  /* number of usages in those ranges */
    uint32_t bit_offset, bit_size, count;
    int64_t logical_min, logical_max;
    int64_t physical_min, physical_max; /* equal to logical when the descriptor gives 0..0 */
    uint32_t unit;                      /* HID unit code (§6.2.2.7) */
    int8_t unit_exponent;               /* power of ten */
} fv_hid_field;

/** One collection; the tree is given by parent indices (-1 for top level). */
typedef struct fv_hid_collection {
    uint32_t usage;       /* extended usage that preceded the Collection item (0 when none) */
    uint32_t item_offset; /* byte offset of the Collection item */
    int16_t parent;
    uint8_t type; /* 0 physical, 1 application, 2 logical, 3 report, 4 named array, 5 usage switch, 6 usage modifier */
    uint8_t depth;
} fv_hid_collection;

/** One report: an (ID, type) pair and its total payload size in bits. */
typedef struct fv_hid_report {
    uint8_t id;
    uint8_t type;
    uint16_t field_count; /* fields (padding included) that belong to it */
    uint32_t bit_length;
} fv_hid_report;

/** The parsed descriptor. Large (~40 KiB): allocate it, don't put it on a small stack. Plain data. */
typedef struct fv_hid_descriptor {
    fv_hid_field fields[FV_HID_MAX_FIELDS];
    fv_hid_usage_range usages[FV_HID_MAX_USAGE_RANGES];
    fv_hid_collection collections[FV_HID_MAX_COLLECTIONS];
    fv_hid_report reports[FV_HID_MAX_REPORTS];
    uint32_t field_count, usage_count, collection_count, report_count;
    bool uses_report_ids;  /* every report starts with its ID byte */
    uint32_t item_count;   /* short items parsed */
    uint32_t long_items;   /* long items skipped */
    uint32_t size;         /* descriptor bytes */
} fv_hid_descriptor;

/** Parse `size` bytes into *out (overwritten). FV_ERR_PARSE for a malformed descriptor and FV_ERR_UNSUPPORTED beyond
 *  fovea's limits; either way one error is logged (module "hid") with the byte offset and the reason. Pure; thread-safe
 *  on distinct outputs. */
FV_MUST_CHECK fv_result fv_hid_descriptor_parse(const uint8_t *bytes, size_t size, fv_hid_descriptor *out);

/** The report with this type and ID, or NULL. */
const fv_hid_report *fv_hid_descriptor_find_report(const fv_hid_descriptor *d, fv_hid_report_type type, uint8_t id);
/** Bytes of the report on the wire: payload rounded up to whole bytes, plus the ID byte when IDs are used. */
size_t fv_hid_report_byte_length(const fv_hid_descriptor *d, const fv_hid_report *r);
/** The largest report of a type on the wire (what Windows calls the Input/Output/Feature report length); 0 if none. */
size_t fv_hid_descriptor_max_report_length(const fv_hid_descriptor *d, fv_hid_report_type type);

/** The `index`-th usage of the field's usage list (zero-based), the last one repeating past the end: for a Variable
 *  field the usage of element `index`; for an Array field the usage that array value `logical_min + index` selects.
 *  0 when the field has no usage. */
uint32_t fv_hid_field_usage(const fv_hid_descriptor *d, const fv_hid_field *f, uint32_t index);
/** True when `usage` is among the field's usages. */
bool fv_hid_field_has_usage(const fv_hid_descriptor *d, const fv_hid_field *f, uint32_t usage);

/** Read element `index` of the field from a report payload (the bytes after the ID byte): sign-extended when the
 *  logical minimum is negative. FV_ERR_PROTOCOL when the payload is too short for it. */
FV_MUST_CHECK fv_result fv_hid_field_read(const fv_hid_field *f, uint32_t index, const uint8_t *payload,
                                          size_t payload_len, int64_t *out_value);
/** Write element `index` of the field into a payload (the low bit_size bits of value). */
FV_MUST_CHECK fv_result fv_hid_field_write(const fv_hid_field *f, uint32_t index, int64_t value, uint8_t *payload,
                                           size_t payload_len);
/** True when value lies in the field's logical range (a value outside it means "no data", HID 1.11 §6.2.2.7). */
static inline bool fv_hid_field_in_range(const fv_hid_field *f, int64_t v)
{
    return v >= f->logical_min && v <= f->logical_max;
}
/** Logical value → physical value (linear map of the two ranges), before the unit exponent. Finite always. */
double fv_hid_field_physical(const fv_hid_field *f, int64_t logical);

/** Unit decoding. Each returns false when the unit is not of that kind. */
/** Length unit → factor from (physical value × 10^exponent) to millimetres (SI linear: cm; English linear: inch). */
bool fv_hid_unit_length_to_mm(uint32_t unit, int8_t exponent, double *out_factor);
/** Time unit (seconds, SI or English) → factor to nanoseconds, including the exponent. */
bool fv_hid_unit_time_to_ns(uint32_t unit, int8_t exponent, double *out_factor);
/** Rotation unit → factor to radians (SI rotation: rad; English rotation: degrees), including the exponent. */
bool fv_hid_unit_angle_to_rad(uint32_t unit, int8_t exponent, double *out_factor);
/** Human-readable unit ("cm e-4", "s e-6", "s^-1", "none") into buf. Returns buf. */
const char *fv_hid_unit_format(uint32_t unit, int8_t exponent, char *buf, size_t cap);

/** Names (static strings; NULL when unknown) of usage pages and usages. */
const char *fv_hid_usage_page_name(uint16_t page);
const char *fv_hid_usage_name(uint32_t extended_usage);
const char *fv_hid_report_type_name(fv_hid_report_type type);
const char *fv_hid_collection_type_name(uint8_t type);

/** Decode hex text ("05 12 09 01", "0x05,0x12", '#' comments) into bytes. FV_ERR_PARSE naming line and column of the
 *  first bad character; FV_ERR_RANGE when more than cap bytes. `what` names the source in the message. */
FV_MUST_CHECK fv_result fv_hid_hex_decode(const char *what, const char *text, size_t len, uint8_t *out, size_t cap,
                                          size_t *out_len);
/** fv_hid_hex_decode of text that starts at line `first_line`, column `first_col` (1-based) of the file `what`
 *  (one line of a longer file): messages read "what:LINE:COL", counted in the file. */
FV_MUST_CHECK fv_result fv_hid_hex_decode_at(const char *what, size_t first_line, size_t first_col, const char *text,
                                             size_t len, uint8_t *out, size_t cap, size_t *out_len);

#endif
