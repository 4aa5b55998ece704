/* @brief Seeds of fuzz_pupil_decode, written to the folder argv[1]: messages of the real Pupil Core export
 * (FV_SHARED_DATA_DIR) as Capture sends them (binocular 3D, monocular 3D, 2D), and the hostile payloads (the 5-byte
 * map32 that asked for 192 GiB among them). A seed file is the topic's index byte, then the payload. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fake_export.h"

static int write_seed(const char *dir, const char *name, const char *topic, const unsigned char *p, size_t len)
{
    unsigned char t = 0;
    while (t < FAKE_FUZZ_TOPICS && strcmp(fake_fuzz_topic(t), topic) != 0) t++;
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.bin", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(&t, 1, 1, f) != 1 || fwrite(p, 1, len, f) != len || fclose(f) != 0) {
        fprintf(stderr, "pupil_fuzz_seeds: cannot write %s\n", path);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: pupil_fuzz_seeds DIR\n");
        return 2;
    }
    int rc = 0;
    size_t n;
    row *rows = fake_export_rows(&n);
    /* the first row as Capture sends it from both eyes, from eye 0 only, and from the 2D pipeline */
    const char *names[] = {"bino", "mono", "2d"};
    for (int k = 0; k < 3; k++) {
        row r = rows[0];
        r.have_eye[0] = r.have_eye[0] && k < 2;
        r.have_eye[1] = r.have_eye[1] && k < 1;
        fake_msg m;
        fake_row_message(&r, 0, &m);
        rc |= write_seed(argv[1], names[k], m.topic, m.payload, m.len);
        free(m.payload);
    }
    free(rows);
    for (size_t i = 0; i < FAKE_HOSTILE_COUNT; i++) {
        unsigned char buf[256];
        const char *name;
        size_t len = fake_hostile_payload(i, buf, sizeof buf, &name, NULL);
        rc |= write_seed(argv[1], name, "gaze.3d.01.", buf, len);
    }
    return rc;
}
