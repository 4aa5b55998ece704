/* @brief Writes binary seeds for the HID fuzzers from the shared hex data: the two Microsoft descriptors, and
 * [mode][descriptor length LE16][descriptor][report] inputs for every synthetic and captured report.
 * usage: hid_fuzz_seeds SHARED_DATA_DIR OUT_DIR */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_hid_descriptor.h"

static size_t load(const char *dir, const char *name, char *text, size_t cap)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/hid/%s", dir, name);
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    size_t n = fread(text, 1, cap - 1, f);
    fclose(f);
    text[n] = '\0';
    return n;
}

static int write_bin(const char *dir, const char *name, const uint8_t *a, size_t an, const uint8_t *b, size_t bn)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f) return 1;
    fwrite(a, 1, an, f);
    if (bn) fwrite(b, 1, bn, f);
    return fclose(f) != 0;
}

int main(int argc, char **argv)
{
    if (argc != 3) return 2;
    static char text[1 << 16];
    static const char *descs[2] = {"ms-gazehid-vhidmini-eye-tracker.rdesc.hex", "ms-dmf-virtualeyegaze.rdesc.hex"};
    uint8_t desc[2][1024];
    size_t dn[2];
    int rc = 0;
    for (int i = 0; i < 2; i++) {
        size_t n = load(argv[1], descs[i], text, sizeof text);
        if (!n || fv_hid_hex_decode(descs[i], text, n, desc[i], sizeof desc[i], &dn[i]) != FV_OK) return 1;
        char name[64];
        snprintf(name, sizeof name, "descriptor_%d.bin", i);
        rc |= write_bin(argv[2], name, desc[i], dn[i], NULL, 0);
    }
    /* reports: every line of the synthetic file, and the captured capabilities report */
    uint8_t reports[16][128];
    size_t rn[16], count = 0;
    size_t n = load(argv[1], "SYNTHETIC-eye-tracker-reports.txt", text, sizeof text);
    for (char *line = strtok(n ? text : NULL, "\n"); line && count < 15; line = strtok(NULL, "\n")) {
        char *colon = strrchr(line, ':');
        if (line[0] == '#' || !colon) continue;
        if (fv_hid_hex_decode("synthetic", colon + 1, strlen(colon + 1), reports[count], 128, &rn[count]) == FV_OK)
            count++;
    }
    n = load(argv[1], "ms-gazehid-capabilities-feature-report.hex", text, sizeof text);
    if (n && fv_hid_hex_decode("caps", text, n, reports[count], 128, &rn[count]) == FV_OK) count++;
    for (size_t r = 0; r < count; r++) {
        for (int i = 0; i < 2; i++) {
            uint8_t head[3 + 1024];
            head[0] = (uint8_t)(2 | (r & 1));
            head[1] = (uint8_t)(dn[i] & 0xFF);
            head[2] = (uint8_t)(dn[i] >> 8);
            memcpy(head + 3, desc[i], dn[i]);
            char name[64];
            snprintf(name, sizeof name, "report_%zu_%d.bin", r, i);
            rc |= write_bin(argv[2], name, head, 3 + dn[i], reports[r], rn[r]);
        }
    }
    return rc;
}
