/* @brief libFuzzer target: the page-0x12 report decoders on arbitrary report bytes, with the first input byte choosing
 * one of the shared descriptors (Microsoft GazeHid, Microsoft DMF) or fovea's virtual tracker layout (same as GazeHid
 * plus pupils, exercised through the quirk). Outputs must stay finite where flagged valid. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fv_hid_descriptor.h"
#include "fv_hid_eyetracker.h"
#include "fv_log.h"

/* Microsoft's 340-byte GazeHid descriptor is loaded from the seeds' first line by the seed itself: the fuzzer input is
 * [selector][descriptor length lo/hi][descriptor bytes][report bytes], so seeds carry real descriptors. */
static void quiet(void *user, fv_log_level level, const char *module, const char *file, int line, const char *msg)
{
    (void)user, (void)level, (void)module, (void)file, (void)line, (void)msg;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static fv_hid_descriptor d;
    fv_log_set_sink(quiet, NULL);
    if (size < 3) return 0;
    uint8_t mode = data[0];
    size_t dlen = (size_t)data[1] | (size_t)data[2] << 8;
    if (dlen > size - 3) return 0;
    const uint8_t *desc = data + 3, *rep = data + 3 + dlen;
    size_t rlen = size - 3 - dlen;
    if (fv_hid_descriptor_parse(desc, dlen, &d) != FV_OK) return 0;
    fv_hid_eyetracker_map m;
    const fv_hid_quirk *q = (mode & 1) ? fv_hid_quirk_find(0x1209, 0x0001) : NULL;
    if (fv_hid_eyetracker_map_init(&d, q, &m) != FV_OK) return 0;
    fv_hid_screen_config sc;
    fv_hid_screen_config_defaults(&sc);
    sc.width_mm = (mode & 2) ? 527.0f : 0.0f;
    sc.height_mm = (mode & 2) ? 296.0f : 0.0f;
    fv_gaze_sample s;
    if (fv_hid_eyetracker_decode_tracking(&d, &m, &sc, rep, rlen, &s) == FV_OK) {
        for (int e = 0; e < 2; e++) {
            if ((s.eye[e].flags & FV_EYE_DIRECTION_VALID) && !fv_v3_isfinite(s.eye[e].direction)) abort();
            if ((s.eye[e].flags & FV_EYE_ORIGIN_VALID) && !fv_v3_isfinite(s.eye[e].origin_mm)) abort();
            if ((s.eye[e].flags & FV_EYE_PUPIL_VALID) && !isfinite(s.eye[e].pupil_mm)) abort();
        }
        if ((s.flags & FV_GAZE_HEAD_VALID) && !fv_v3_isfinite(s.head_dir)) abort();
    }
    fv_hid_capabilities c;
    fv_hid_configuration g;
    fv_hid_status st;
    (void)fv_hid_eyetracker_decode_capabilities(&d, &m, rep, rlen, &c);
    (void)fv_hid_eyetracker_decode_configuration(&d, &m, rep, rlen, &g);
    (void)fv_hid_eyetracker_decode_status(&d, &m, FV_HID_REPORT_INPUT, rep, rlen, &st);
    (void)fv_hid_eyetracker_decode_status(&d, &m, FV_HID_REPORT_FEATURE, rep, rlen, &st);
    uint8_t out[64];
    size_t n;
    (void)fv_hid_eyetracker_encode_mode_request(&d, &m, mode & 7u, out, sizeof out, &n);
    return 0;
}
