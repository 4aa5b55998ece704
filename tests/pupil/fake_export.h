/* @brief The real Pupil Core export (../shared/data/gaze/pupil_core/gaze_positions.csv) as the gaze messages Pupil
 * Capture publishes (msgpack maps: binocular 3D, monocular 3D or 2D datums, with pupil datums in base_data), for the
 * fake Capture of the tests, and small msgpack building helpers. */
#ifndef FV_TEST_FAKE_EXPORT_H
#define FV_TEST_FAKE_EXPORT_H

#include <stdbool.h>
#include <stddef.h>

#include <msgpack.h>

#include "fake_capture.h"

typedef struct pk {
    msgpack_sbuffer sb;
    msgpack_packer p;
} pk;
void pk_init(pk *k);
void pk_str(pk *k, const char *s);
void pk_vec(pk *k, const double *v, int n);
/** Hand the bytes over (caller frees) and free the packer's buffer. */
unsigned char *pk_take(pk *k, size_t *len);

/** One row of gaze_positions.csv. */
typedef struct row {
    double ts, conf, norm[2], p3[3], c[2][3], n[2][3];
    bool have_p3, have_eye[2];
    int base_id[2], base_n;
    double base_ts[2];
} row;
/** The pupil diameter the fake attaches to row i's pupil datum of eye id (the export has none): plausible, known. */
double fake_diameter_mm(size_t i, int id);
/** Every row of the export (caller frees); fails the test when the file cannot be read. */
row *fake_export_rows(size_t *out_n);
/** The gaze datum Capture would publish for row r (index i), due at the row's Pupil time. */
void fake_row_message(const row *r, size_t i, fake_msg *m);

/** Hostile msgpack payloads (a hostile-server probe's findings): headers whose counts and sizes the bytes cannot hold
 *  (the 5-byte map32 that asked msgpack-c for 192 GiB), nesting past the limit. Each with the phrase the decoder's
 *  reason must hold. For the unit test and the fuzzer's seeds. */
#define FAKE_HOSTILE_COUNT 10
/** Fill buf (cap >= 256) with hostile payload i; returns its length; name (a file name) and phrase may be NULL. */
size_t fake_hostile_payload(size_t i, unsigned char *buf, size_t cap, const char **name, const char **phrase);
/** Topics the fuzzer picks from by the input's first byte (modulo FAKE_FUZZ_TOPICS). */
#define FAKE_FUZZ_TOPICS 6u
static inline const char *fake_fuzz_topic(unsigned i)
{
    static const char *const topics[FAKE_FUZZ_TOPICS] = {"gaze.3d.01.", "gaze.3d.0.", "gaze.3d.1.",
                                                         "gaze.2d.0.",  "gaze.2d.1.", "pupil.0.3d"};
    return topics[i % FAKE_FUZZ_TOPICS];
}

#endif
