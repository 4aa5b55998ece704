/* @brief libFuzzer target: the HID report-descriptor parser, then the page-0x12 map and the generic field reader on
 * whatever parsed. No crash, no sanitizer report, no out-of-bounds read. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "fv_hid_descriptor.h"
#include "fv_hid_eyetracker.h"
#include "fv_log.h"

static void quiet(void *user, fv_log_level level, const char *module, const char *file, int line, const char *msg)
{
    (void)user, (void)level, (void)module, (void)file, (void)line, (void)msg;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static fv_hid_descriptor d;
    fv_log_set_sink(quiet, NULL);
    if (fv_hid_descriptor_parse(data, size, &d) != FV_OK) return 0;
    /* Read every element of every field from a zero payload of each report's declared size. */
    static uint8_t payload[FV_HID_MAX_REPORT_BYTES];
    for (uint32_t i = 0; i < d.field_count; i++) {
        const fv_hid_field *f = &d.fields[i];
        const fv_hid_report *r = fv_hid_descriptor_find_report(&d, (fv_hid_report_type)f->type, f->report_id);
        if (!r) abort(); /* every field belongs to a report */
        size_t plen = (r->bit_length + 7u) / 8u;
        if (plen > sizeof payload) abort();
        uint32_t n = f->count < 64 ? f->count : 64;
        for (uint32_t k = 0; k < n; k++) {
            int64_t v;
            if (f->bit_size <= 32 && fv_hid_field_read(f, k, payload, plen, &v) != FV_OK) abort();
            (void)fv_hid_field_usage(&d, f, k);
        }
        (void)fv_hid_field_physical(f, f->logical_max);
    }
    fv_hid_eyetracker_map m;
    (void)fv_hid_eyetracker_map_init(&d, NULL, &m);
    return 0;
}
