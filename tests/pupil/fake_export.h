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

#endif
