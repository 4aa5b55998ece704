/* @brief libFuzzer target for the Pupil Capture gaze decoder (fv_pupil_decode_gaze): the first byte picks the topic,
 * the rest is the msgpack payload. Checks: no crash, sanitizer report or allocation past the fuzzer's malloc limit
 * (a header claiming more than the payload holds must be refused before msgpack-c allocates); a refusal has a reason
 * and an all-invalid sample; a decoded sample is finite and unit-length where it says it is valid. Seeds: the real
 * export's messages and the hostile payloads (pupil_fuzz_seeds.c). */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "fake_export.h"
#include "fv_pupil_driver.h"

static void check_eye(const fv_eye_sample *e)
{
    if ((e->flags & FV_EYE_DIRECTION_VALID) &&
        (!fv_v3_isfinite(e->direction) || fabsf(fv_v3_len(e->direction) - 1.0f) > 1e-3f))
        __builtin_trap();
    if ((e->flags & FV_EYE_ORIGIN_VALID) && !fv_v3_isfinite(e->origin_mm)) __builtin_trap();
    if ((e->flags & FV_EYE_PUPIL_VALID) && !isfinite(e->pupil_mm)) __builtin_trap();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    const char *topic = fake_fuzz_topic(data[0]);
    fv_pupil_camera cam = fv_pupil_camera_default();
    fv_gaze_sample s;
    char why[160];
    fv_result r = fv_pupil_decode_gaze(topic, strlen(topic), data + 1, size - 1, &cam, 0.6, &s, why, sizeof why);
    if (r != FV_OK) {
        if (r != FV_ERR_PARSE || !why[0] || (s.combined.flags & FV_EYE_DIRECTION_VALID)) __builtin_trap();
        return 0;
    }
    if (!(s.confidence >= 0.0f && s.confidence <= 1.0f) || s.t_device_ns < 0) __builtin_trap();
    check_eye(&s.combined);
    check_eye(&s.eye[0]);
    check_eye(&s.eye[1]);
    return 0;
}
