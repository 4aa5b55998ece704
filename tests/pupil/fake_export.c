/* @brief The Pupil Core export as Capture's gaze messages (see fake_export.h). */
#include "fake_export.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_test.h"

void pk_init(pk *k)
{
    msgpack_sbuffer_init(&k->sb);
    msgpack_packer_init(&k->p, &k->sb, msgpack_sbuffer_write);
}
void pk_str(pk *k, const char *s)
{
    msgpack_pack_str(&k->p, strlen(s));
    msgpack_pack_str_body(&k->p, s, strlen(s));
}
void pk_vec(pk *k, const double *v, int n)
{
    msgpack_pack_array(&k->p, (size_t)n);
    for (int i = 0; i < n; i++) msgpack_pack_double(&k->p, v[i]);
}
unsigned char *pk_take(pk *k, size_t *len)
{
    *len = k->sb.size;
    unsigned char *b = malloc(k->sb.size ? k->sb.size : 1);
    if (k->sb.size) memcpy(b, k->sb.data, k->sb.size);
    msgpack_sbuffer_destroy(&k->sb);
    return b;
}

/* The pupil diameter Capture would attach (the export has none): a deterministic, plausible value per row and eye. */
double fake_diameter_mm(size_t i, int id) { return 3.0 + 0.5 * id + 0.001 * (double)(i % 100); }

static bool parse_fields(char *line, char **f, int cap, int *n)
{
    *n = 0;
    for (char *p = line;;) {
        if (*n >= cap) return false;
        f[(*n)++] = p;
        char *c = strchr(p, ',');
        if (!c) break;
        *c = '\0';
        p = c + 1;
    }
    char *nl = strpbrk(f[*n - 1], "\r\n");
    if (nl) *nl = '\0';
    return true;
}

static bool num3(char **f, int at, double v[3])
{
    for (int k = 0; k < 3; k++) {
        if (!f[at + k][0]) return false;
        v[k] = strtod(f[at + k], NULL);
    }
    return true;
}

/* Rows of gaze_positions.csv, by the column names of its header. */
row *fake_export_rows(size_t *out_n)
{
    FILE *fp = fopen(fv_test_data("gaze/pupil_core/gaze_positions.csv"), "r");
    assert_non_null(fp);
    static char line[8192];
    char *f[64];
    int n;
    assert_non_null(fgets(line, sizeof line, fp));
    assert_true(parse_fields(line, f, 64, &n));
    const char *want[] = {"gaze_timestamp", "confidence", "norm_pos_x", "base_data", "gaze_point_3d_x",
                          "eye_center0_3d_x", "gaze_normal0_x", "eye_center1_3d_x", "gaze_normal1_x"};
    int col[9];
    for (int w = 0; w < 9; w++) {
        col[w] = -1;
        for (int i = 0; i < n; i++)
            if (strcmp(f[i], want[w]) == 0) col[w] = i;
        assert_true(col[w] >= 0);
    }
    size_t cap = 4096, count = 0;
    row *rows = calloc(cap, sizeof *rows);
    while (fgets(line, sizeof line, fp) && count < cap) {
        assert_true(parse_fields(line, f, 64, &n));
        row *r = &rows[count];
        r->ts = strtod(f[col[0]], NULL);
        r->conf = strtod(f[col[1]], NULL);
        r->norm[0] = strtod(f[col[2]], NULL);
        r->norm[1] = strtod(f[col[2] + 1], NULL);
        /* base_data: "329367.890963-0 329367.904825-1": pupil timestamps and eye ids */
        for (char *tok = f[col[3]]; *tok && r->base_n < 2;) {
            char *end;
            double t = strtod(tok, &end);
            if (end == tok || *end != '-') break;
            r->base_ts[r->base_n] = t;
            r->base_id[r->base_n] = (int)strtol(end + 1, &end, 10);
            r->base_n++;
            while (*end == ' ') end++;
            tok = end;
        }
        r->have_p3 = num3(f, col[4], r->p3);
        for (int e = 0; e < 2; e++)
            r->have_eye[e] = num3(f, col[5 + 2 * e], r->c[e]) && num3(f, col[6 + 2 * e], r->n[e]);
        count++;
    }
    fclose(fp);
    *out_n = count;
    return rows;
}

/* The gaze datum Capture publishes for this row: binocular 3D, monocular 3D, or 2D. */
void fake_row_message(const row *r, size_t i, fake_msg *m)
{
    memset(m, 0, sizeof *m);
    pk k;
    pk_init(&k);
    bool bino = r->have_eye[0] && r->have_eye[1], mono = !bino && (r->have_eye[0] || r->have_eye[1]);
    int mono_id = r->have_eye[0] ? 0 : 1, id2d = r->base_n ? r->base_id[0] : 0;
    if (bino) snprintf(m->topic, sizeof m->topic, "gaze.3d.01.");
    else if (mono) snprintf(m->topic, sizeof m->topic, "gaze.3d.%d.", mono_id);
    else snprintf(m->topic, sizeof m->topic, "gaze.2d.%d.", id2d);
    int keys = 5 + (r->have_p3 && (bino || mono) ? 1 : 0) + (bino || mono ? 2 : 0);
    msgpack_pack_map(&k.p, (size_t)keys);
    pk_str(&k, "topic");
    pk_str(&k, m->topic);
    pk_str(&k, "norm_pos");
    pk_vec(&k, r->norm, 2);
    pk_str(&k, "confidence");
    msgpack_pack_double(&k.p, r->conf);
    pk_str(&k, "timestamp");
    msgpack_pack_double(&k.p, r->ts);
    if (r->have_p3 && (bino || mono)) {
        pk_str(&k, "gaze_point_3d");
        pk_vec(&k, r->p3, 3);
    }
    if (bino) {
        pk_str(&k, "eye_centers_3d");
        msgpack_pack_map(&k.p, 2);
        for (int e = 0; e < 2; e++) {
            msgpack_pack_int(&k.p, e);
            pk_vec(&k, r->c[e], 3);
        }
        pk_str(&k, "gaze_normals_3d");
        msgpack_pack_map(&k.p, 2);
        for (int e = 0; e < 2; e++) {
            msgpack_pack_int(&k.p, e);
            pk_vec(&k, r->n[e], 3);
        }
    } else if (mono) {
        pk_str(&k, "eye_center_3d");
        pk_vec(&k, r->c[mono_id], 3);
        pk_str(&k, "gaze_normal_3d");
        pk_vec(&k, r->n[mono_id], 3);
    }
    pk_str(&k, "base_data");
    msgpack_pack_array(&k.p, (size_t)r->base_n);
    for (int b = 0; b < r->base_n; b++) {
        char t[32];
        snprintf(t, sizeof t, "pupil.%d.3d", r->base_id[b]);
        msgpack_pack_map(&k.p, 6);
        pk_str(&k, "topic");
        pk_str(&k, t);
        pk_str(&k, "id");
        msgpack_pack_int(&k.p, r->base_id[b]);
        pk_str(&k, "timestamp");
        msgpack_pack_double(&k.p, r->base_ts[b]);
        pk_str(&k, "confidence");
        msgpack_pack_double(&k.p, r->conf);
        pk_str(&k, "diameter");
        msgpack_pack_double(&k.p, 30.0);
        pk_str(&k, "diameter_3d");
        msgpack_pack_double(&k.p, fake_diameter_mm(i, r->base_id[b]));
    }
    m->payload = pk_take(&k, &m->len);
    m->due_pupil_ns = (int64_t)llround(r->ts * 1e9);
}


size_t fake_hostile_payload(size_t i, unsigned char *buf, size_t cap, const char **name, const char **phrase)
{
    static const struct {
        const char *name, *bytes, *phrase;
        size_t len;
    } fixed[] = {
        {"map32", "\xdf\xff\xff\xff\xff", "a map of 4294967295 entries at offset 0, 0 bytes left", 5},
        {"array32", "\xdd\xff\xff\xff\xff", "an array of 4294967295 elements at offset 0, 0 bytes left", 5},
        {"str32", "\xdb\xff\xff\xff\xff", "a string of 4294967295 bytes at offset 0", 5},
        {"bin32", "\xc6\xff\xff\xff\xff", "binary data of 4294967295 bytes at offset 0", 5},
        {"ext32", "\xc9\xff\xff\xff\xff\x01", "an extension of 4294967295 bytes at offset 0", 6},
        {"field_array32", "\x81\xa9timestamp\xdd\x7f\xff\xff\xff",
         "an array of 2147483647 elements at offset 11, 0 bytes left", 16},
        {"map32_header_cut", "\xdf\xff\xff", "truncated after 3 bytes (a header of 5 bytes at offset 0)", 3},
    };
    const size_t nfixed = sizeof fixed / sizeof fixed[0];
    size_t len = 0;
    const char *nm = NULL, *ph = NULL;
    if (i < nfixed) {
        memcpy(buf, fixed[i].bytes, fixed[i].len);
        len = fixed[i].len, nm = fixed[i].name, ph = fixed[i].phrase;
    } else if (i == nfixed) { /* map16 of 65535 entries followed by 100 bytes */
        buf[0] = 0xde, buf[1] = 0xff, buf[2] = 0xff;
        memset(buf + 3, 0, 100);
        len = 103, nm = "map16_100", ph = "a map of 65535 entries at offset 0, 100 bytes left";
    } else if (i == nfixed + 1) { /* arrays nested 17 deep (msgpack-c itself goes to 32) */
        memset(buf, 0x91, 17);
        buf[17] = 0x00;
        len = 18, nm = "deep17", ph = "nests deeper than 16 levels (at offset 16)";
    } else { /* a gaze datum whose base_data nests 200 deep */
        size_t n = 0;
        buf[n++] = 0x81;
        buf[n++] = 0xa9;
        memcpy(buf + n, "base_data", 9), n += 9;
        while (n < 211 && n < cap - 1) buf[n++] = 0x91;
        buf[n++] = 0xc0;
        len = n, nm = "deep200", ph = "nests deeper than 16 levels";
    }
    if (name) *name = nm;
    if (phrase) *phrase = ph;
    return len;
}
