/* @brief libFuzzer target: arbitrary bytes become a stream of gaze samples (every field, NaN/Inf and absurd times
 * included) and prediction targets; the pipeline must never crash, and every prediction must stay finite. The
 * first bytes also drive the sim: URI parser. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fv_gaze_pipeline.h"
#include "fv_log.h"
#include "fv_sim_driver.h"

static void check(const fv_gaze_prediction *pr)
{
    bool ok = fv_v3_isfinite(pr->combined_dir_head) && fv_v3_isfinite(pr->dir_head[0]) &&
              fv_v3_isfinite(pr->dir_head[1]) && isfinite(pr->uncertainty_deg) && pr->uncertainty_deg > 0.0f &&
              (isnan(pr->pupil_mm) || isfinite(pr->pupil_mm));
    if (!ok) abort();
}

static void discard(void *user, fv_log_level level, const char *module, const char *file, int line, const char *msg)
{
    (void)user, (void)level, (void)module, (void)file, (void)line, (void)msg;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fv_log_set_sink(discard, NULL); /* bad URIs are expected: keep the fuzzer's output readable */
    if (size > 0 && data[0] < 32) {
        /* a sim: URI */
        char uri[300] = "sim:";
        size_t n = size - 1 < 280 ? size - 1 : 280;
        memcpy(uri + 4, data + 1, n);
        uri[4 + n] = '\0';
        fv_sim_eye_desc d;
        unsigned bits;
        if (fv_sim_driver_parse_uri(uri, &d, &bits) == FV_OK) {
            fv_sim_eye *eye = NULL;
            if (fv_sim_eye_create(&d, &eye) == FV_OK) {
                for (int i = 0; i < 64; i++) {
                    fv_gaze_sample s;
                    fv_sim_truth t;
                    if (fv_sim_eye_next(eye, &s, &t) != FV_OK) abort();
                }
                fv_sim_eye_destroy(&eye);
            }
        }
        return 0;
    }
    fv_gaze_pipeline_desc desc = {0};
    desc.disable_prediction = size > 0 && (data[0] & 1);
    fv_gaze_pipeline *p = NULL;
    if (fv_gaze_pipeline_create(&desc, &p) != FV_OK) return 0;
    const size_t rec = sizeof(fv_gaze_sample) + sizeof(int64_t);
    for (size_t off = 1; off + rec <= size; off += rec) {
        fv_gaze_sample s;
        int64_t target;
        memcpy(&s, data + off, sizeof s);
        memcpy(&target, data + off + sizeof s, sizeof target);
        (void)fv_gaze_pipeline_push(p, &s);
        fv_gaze_prediction pr;
        fv_gaze_pipeline_predict(p, target, &pr);
        check(&pr);
        fv_gaze_pipeline_predict(p, s.t_host_ns, &pr);
        check(&pr);
    }
    fv_gaze_pipeline_destroy(&p);
    return 0;
}
