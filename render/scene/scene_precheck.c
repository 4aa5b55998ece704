/* @brief Model-file pre-checks, before assimp sees a file: what the file claims (PLY element counts and list
 * lengths, OBJ element counts, OFF counts) against what its bytes can hold and the FV_SCENE_MAX_* limits, so that
 * the importer never allocates for more than the file contains ("a 187-byte PLY whose face claims 2^32-1 indices").
 * The checks are pure functions on the file's bytes (fv_scene_precheck_bytes); files a model refers to (OBJ
 * mtllib) go through a callback. fv_scene_precheck_file maps the file and checks those references on disk. */
#include <assimp/cimport.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fv_file.h"
#include "fv_log.h"
#include "fv_scene.h"
#include "scene_internal.h"

#define PLY_MAX_HEADER_BYTES (1u << 20)
#define PLY_MAX_ELEMENTS 64
#define PLY_MAX_PROPERTIES 64 /* per element */
#define OBJ_MAX_MTL_BYTES (64u * 1024u * 1024u)

/* ---- a cursor over lines of the bytes ---- */

typedef struct span {
    const uint8_t *p;
    size_t n;
} span;

/* The next line of b starting at *off (without its "\n" or "\r\n"); false at the end. */
static bool next_line(const uint8_t *b, size_t len, size_t *off, span *out)
{
    if (*off >= len) return false;
    const uint8_t *start = b + *off;
    const uint8_t *nl = memchr(start, '\n', len - *off);
    size_t n = nl ? (size_t)(nl - start) : len - *off;
    *off += n + (nl ? 1u : 0u);
    if (n && start[n - 1] == '\r') n--;
    out->p = start;
    out->n = n;
    return true;
}

static bool is_blank(uint8_t c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

/* The next whitespace-separated token of a line; false when none is left. */
static bool next_token(span *line, span *tok)
{
    size_t i = 0;
    while (i < line->n && is_blank(line->p[i])) i++;
    size_t s = i;
    while (i < line->n && !is_blank(line->p[i])) i++;
    tok->p = line->p + s;
    tok->n = i - s;
    line->p += i;
    line->n -= i;
    return tok->n > 0;
}

static bool tok_is(span t, const char *word) { return t.n == strlen(word) && !memcmp(t.p, word, t.n); }

/* A token as a printable C string for messages (cut, control bytes as '?'). */
static const char *tok_str(span t, char *buf, size_t cap)
{
    size_t n = t.n < cap - 1 ? t.n : cap - 1;
    for (size_t i = 0; i < n; i++) buf[i] = (t.p[i] >= 0x20 && t.p[i] < 0x7f) ? (char)t.p[i] : '?';
    buf[n] = '\0';
    return buf;
}

/* A decimal count (no sign, no exponent); false on anything else or overflow past 2^63. */
static bool tok_count(span t, uint64_t *out)
{
    if (t.n == 0 || t.n > 19) return false;
    uint64_t v = 0;
    for (size_t i = 0; i < t.n; i++) {
        if (t.p[i] < '0' || t.p[i] > '9') return false;
        v = v * 10u + (uint64_t)(t.p[i] - '0');
    }
    *out = v;
    return true;
}

/* ---- PLY ---- */

typedef enum ply_type { PLY_NONE = 0, PLY_I8, PLY_U8, PLY_I16, PLY_U16, PLY_I32, PLY_U32, PLY_F32, PLY_F64 } ply_type;

static ply_type ply_type_of(span t)
{
    static const struct {
        const char *name;
        ply_type type;
    } names[] = {{"char", PLY_I8},    {"int8", PLY_I8},     {"uchar", PLY_U8},   {"uint8", PLY_U8},
                 {"short", PLY_I16},  {"int16", PLY_I16},   {"ushort", PLY_U16}, {"uint16", PLY_U16},
                 {"int", PLY_I32},    {"int32", PLY_I32},   {"uint", PLY_U32},   {"uint32", PLY_U32},
                 {"float", PLY_F32},  {"float32", PLY_F32}, {"double", PLY_F64}, {"float64", PLY_F64}};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (tok_is(t, names[i].name)) return names[i].type;
    return PLY_NONE;
}

static size_t ply_size(ply_type t)
{
    static const size_t sizes[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[t];
}

typedef struct ply_property {
    char name[32];
    ply_type type;       /* the value, or a list's items */
    ply_type count_type; /* PLY_NONE: not a list */
} ply_property;

typedef struct ply_element {
    char name[32];
    uint64_t count;
    int line;
    unsigned property_count;
    ply_property props[PLY_MAX_PROPERTIES];
} ply_element;

typedef enum ply_format { PLY_ASCII, PLY_LE, PLY_BE } ply_format;

typedef struct ply_header {
    ply_format format;
    unsigned element_count;
    ply_element elements[PLY_MAX_ELEMENTS];
    size_t body; /* offset of the first byte after the header */
} ply_header;

/* Read a list count of type t at p (endianness e); false when it is negative or not a whole number. */
static bool ply_read_count(const uint8_t *p, ply_type t, ply_format e, uint64_t *out)
{
    uint8_t b[8];
    size_t n = ply_size(t);
    for (size_t i = 0; i < n; i++) b[i] = e == PLY_BE ? p[n - 1 - i] : p[i];
    uint64_t u = 0;
    for (size_t i = n; i-- > 0;) u = u << 8 | b[i];
    switch (t) {
    case PLY_I8: *out = (uint64_t)(int64_t)(int8_t)u; return (int8_t)u >= 0;
    case PLY_I16: *out = (uint64_t)(int64_t)(int16_t)u; return (int16_t)u >= 0;
    case PLY_I32: *out = (uint64_t)(int64_t)(int32_t)u; return (int32_t)u >= 0;
    case PLY_U8: case PLY_U16: case PLY_U32: *out = u; return true;
    case PLY_F32: {
        float f;
        uint32_t w = (uint32_t)u;
        memcpy(&f, &w, sizeof f);
        if (!(f >= 0.0f && f < 1.8e19f)) return false;
        *out = (uint64_t)f;
        return true;
    }
    case PLY_F64: {
        double d;
        memcpy(&d, &u, sizeof d);
        if (!(d >= 0.0 && d < 1.8e19)) return false;
        *out = (uint64_t)d;
        return true;
    }
    case PLY_NONE: break;
    }
    return false;
}

static fv_result ply_header_parse(const char *origin, const uint8_t *b, size_t len, ply_header *h)
{
    memset(h, 0, sizeof *h);
    size_t off = 0;
    span line, t;
    int lineno = 0;
    bool have_format = false;
    char a[40], c[40];
    while (next_line(b, len, &off, &line)) {
        lineno++;
        if (off > PLY_MAX_HEADER_BYTES) {
            FV_ERROR("scene", "%s: PLY header is longer than %u bytes (no end_header); refused", origin,
                     PLY_MAX_HEADER_BYTES);
            return FV_ERR_RANGE;
        }
        span rest = line;
        if (!next_token(&rest, &t)) continue;
        if (lineno == 1) {
            if (!tok_is(t, "ply")) return FV_ERR_UNSUPPORTED; /* not a PLY: assimp says what it is */
            continue;
        }
        if (tok_is(t, "end_header")) {
            if (!have_format) {
                FV_ERROR("scene", "%s: PLY header has no format line", origin);
                return FV_ERR_PARSE;
            }
            h->body = off;
            return FV_OK;
        }
        if (tok_is(t, "comment") || tok_is(t, "obj_info")) continue;
        if (tok_is(t, "format")) {
            if (!next_token(&rest, &t)) t.n = 0;
            if (tok_is(t, "ascii")) h->format = PLY_ASCII;
            else if (tok_is(t, "binary_little_endian")) h->format = PLY_LE;
            else if (tok_is(t, "binary_big_endian")) h->format = PLY_BE;
            else {
                FV_ERROR("scene", "%s: PLY header line %d: unknown format '%s' (ascii, binary_little_endian, "
                         "binary_big_endian)", origin, lineno, tok_str(t, a, sizeof a));
                return FV_ERR_PARSE;
            }
            have_format = true;
            continue;
        }
        if (tok_is(t, "element")) {
            span name, count;
            if (!next_token(&rest, &name) || !next_token(&rest, &count)) {
                FV_ERROR("scene", "%s: PLY header line %d: 'element' needs a name and a count", origin, lineno);
                return FV_ERR_PARSE;
            }
            if (h->element_count == PLY_MAX_ELEMENTS) {
                FV_ERROR("scene", "%s: PLY header line %d: more than %d elements", origin, lineno, PLY_MAX_ELEMENTS);
                return FV_ERR_RANGE;
            }
            ply_element *e = &h->elements[h->element_count++];
            tok_str(name, e->name, sizeof e->name);
            e->line = lineno;
            if (!tok_count(count, &e->count)) {
                FV_ERROR("scene", "%s: PLY header line %d: element '%s' count '%s' is not a number", origin, lineno,
                         e->name, tok_str(count, c, sizeof c));
                return FV_ERR_PARSE;
            }
            if (e->count > len) {
                FV_ERROR("scene", "%s: PLY header line %d: element '%s' claims %llu items but the file has only %llu "
                         "bytes", origin, lineno, e->name, (unsigned long long)e->count, (unsigned long long)len);
                return FV_ERR_PARSE;
            }
            uint64_t limit = !strcmp(e->name, "vertex") ? FV_SCENE_MAX_VERTICES
                             : !strcmp(e->name, "face")  ? FV_SCENE_MAX_INDICES / 3u
                                                         : FV_SCENE_MAX_INDICES;
            if (e->count > limit) {
                FV_ERROR("scene", "%s: PLY header line %d: element '%s' count %llu exceeds the limit %llu", origin,
                         lineno, e->name, (unsigned long long)e->count, (unsigned long long)limit);
                return FV_ERR_RANGE;
            }
            continue;
        }
        if (tok_is(t, "property")) {
            if (h->element_count == 0) {
                FV_ERROR("scene", "%s: PLY header line %d: 'property' before any 'element'", origin, lineno);
                return FV_ERR_PARSE;
            }
            ply_element *e = &h->elements[h->element_count - 1];
            if (e->property_count == PLY_MAX_PROPERTIES) {
                FV_ERROR("scene", "%s: PLY header line %d: element '%s' has more than %d properties", origin, lineno,
                         e->name, PLY_MAX_PROPERTIES);
                return FV_ERR_RANGE;
            }
            ply_property *p = &e->props[e->property_count];
            span ty, name;
            if (!next_token(&rest, &ty)) ty.n = 0;
            if (tok_is(ty, "list")) {
                span ct, it;
                if (!next_token(&rest, &ct) || !next_token(&rest, &it) || !next_token(&rest, &name)) {
                    FV_ERROR("scene", "%s: PLY header line %d: 'property list' needs a count type, an item type and "
                             "a name", origin, lineno);
                    return FV_ERR_PARSE;
                }
                p->count_type = ply_type_of(ct);
                p->type = ply_type_of(it);
                if (!p->count_type || !p->type) {
                    FV_ERROR("scene", "%s: PLY header line %d: unknown type '%s' (char, uchar, short, ushort, int, "
                             "uint, float, double or their int8..float64 names)", origin, lineno,
                             tok_str(p->count_type ? it : ct, a, sizeof a));
                    return FV_ERR_PARSE;
                }
            } else {
                p->type = ply_type_of(ty);
                if (!p->type || !next_token(&rest, &name)) {
                    FV_ERROR("scene", "%s: PLY header line %d: property type '%s' is unknown or the name is missing "
                             "(char, uchar, short, ushort, int, uint, float, double)", origin, lineno,
                             tok_str(ty, a, sizeof a));
                    return FV_ERR_PARSE;
                }
            }
            tok_str(name, p->name, sizeof p->name);
            e->property_count++;
            continue;
        }
        /* The PLY header has no other keywords; assimp's parser can spin forever on one it does not know (a fuzzed
         * "element`" line), so an unknown keyword is refused here. */
        FV_ERROR("scene", "%s: PLY header line %d: unknown keyword '%s' (format, element, property, comment, obj_info, "
                 "end_header)", origin, lineno, tok_str(t, a, sizeof a));
        return FV_ERR_PARSE;
    }
    FV_ERROR("scene", "%s: PLY header has no end_header line", origin);
    return FV_ERR_PARSE;
}

static fv_result ply_ends_inside(const char *origin, const ply_element *e, uint64_t item)
{
    FV_ERROR("scene", "%s: PLY file ends inside element '%s' item %llu of %llu (header line %d)", origin, e->name,
             (unsigned long long)item, (unsigned long long)e->count, e->line);
    return FV_ERR_PARSE;
}

static fv_result ply_list_too_long(const char *origin, const ply_element *e, uint64_t item, const ply_property *p,
                                   uint64_t n, uint64_t need_bytes, uint64_t remain)
{
    FV_ERROR("scene", "%s: PLY element '%s' item %llu: list '%s' claims %llu entries (at least %llu bytes) but only "
             "%llu bytes of the file remain", origin, e->name, (unsigned long long)item, p->name,
             (unsigned long long)n, (unsigned long long)need_bytes, (unsigned long long)remain);
    return FV_ERR_PARSE;
}

/* Indices a face list of n entries becomes once triangulated. */
static uint64_t face_indices(uint64_t n) { return n >= 3 ? (n - 2) * 3u : 0; }

/* A face with no vertex at all: assimp 5.2's triangulation aborts the process on one (an ai_assert). */
static fv_result ply_empty_face(const char *origin, const ply_element *e, uint64_t item, const ply_property *p)
{
    FV_ERROR("scene", "%s: PLY element '%s' item %llu: list '%s' is empty (a face needs vertices)", origin, e->name,
             (unsigned long long)item, p->name);
    return FV_ERR_PARSE;
}

static fv_result ply_check_indices(const char *origin, uint64_t total)
{
    if (total <= FV_SCENE_MAX_INDICES) return FV_OK;
    FV_ERROR("scene", "%s: PLY faces make %llu triangle indices, over the limit %u", origin,
             (unsigned long long)total, FV_SCENE_MAX_INDICES);
    return FV_ERR_RANGE;
}

static fv_result ply_walk_binary(const char *origin, const ply_header *h, const uint8_t *b, size_t len)
{
    size_t off = h->body;
    uint64_t indices = 0;
    for (unsigned k = 0; k < h->element_count; k++) {
        const ply_element *e = &h->elements[k];
        bool is_face = !strcmp(e->name, "face");
        uint64_t stride = 0;
        bool lists = false;
        for (unsigned i = 0; i < e->property_count; i++) {
            lists |= e->props[i].count_type != PLY_NONE;
            stride += ply_size(e->props[i].type);
        }
        if (!lists) { /* fixed size: one check for the whole element */
            uint64_t remain = len - off;
            if (stride && e->count > remain / stride) return ply_ends_inside(origin, e, remain / stride);
            off += (size_t)(e->count * stride);
            continue;
        }
        for (uint64_t item = 0; item < e->count; item++) {
            for (unsigned i = 0; i < e->property_count; i++) {
                const ply_property *p = &e->props[i];
                size_t sz = ply_size(p->count_type ? p->count_type : p->type);
                if (len - off < sz) return ply_ends_inside(origin, e, item);
                if (!p->count_type) {
                    off += sz;
                    continue;
                }
                uint64_t n;
                if (!ply_read_count(b + off, p->count_type, h->format, &n)) {
                    FV_ERROR("scene", "%s: PLY element '%s' item %llu: list '%s' has a negative or non-integer "
                             "length", origin, e->name, (unsigned long long)item, p->name);
                    return FV_ERR_PARSE;
                }
                off += sz;
                uint64_t remain = len - off, isz = ply_size(p->type);
                if (n > remain / isz) return ply_list_too_long(origin, e, item, p, n, n * isz, remain);
                off += (size_t)(n * isz);
                if (is_face && n == 0) return ply_empty_face(origin, e, item, p);
                if (is_face) {
                    indices += face_indices(n);
                    FV_TRY(ply_check_indices(origin, indices));
                }
            }
        }
    }
    return FV_OK;
}

static fv_result ply_walk_ascii(const char *origin, const ply_header *h, const uint8_t *b, size_t len)
{
    span rest = {b + h->body, len - h->body}, t;
    uint64_t indices = 0;
    char buf[40];
    for (unsigned k = 0; k < h->element_count; k++) {
        const ply_element *e = &h->elements[k];
        bool is_face = !strcmp(e->name, "face");
        for (uint64_t item = 0; item < e->count; item++) {
            for (unsigned i = 0; i < e->property_count; i++) {
                const ply_property *p = &e->props[i];
                if (!next_token(&rest, &t)) return ply_ends_inside(origin, e, item);
                if (!p->count_type) continue;
                uint64_t n;
                if (!tok_count(t, &n)) {
                    FV_ERROR("scene", "%s: PLY element '%s' item %llu: list '%s' length '%s' is not a non-negative "
                             "integer", origin, e->name, (unsigned long long)item, p->name, tok_str(t, buf, sizeof buf));
                    return FV_ERR_PARSE;
                }
                /* every entry takes at least one digit and one blank */
                if (n > (rest.n + 1) / 2) return ply_list_too_long(origin, e, item, p, n, n * 2 - 1, rest.n);
                for (uint64_t j = 0; j < n; j++)
                    if (!next_token(&rest, &t)) return ply_ends_inside(origin, e, item);
                if (is_face && n == 0) return ply_empty_face(origin, e, item, p);
                if (is_face) {
                    indices += face_indices(n);
                    FV_TRY(ply_check_indices(origin, indices));
                }
            }
        }
    }
    return FV_OK;
}

static fv_result ply_check(const char *origin, const uint8_t *b, size_t len)
{
    ply_header *h = malloc(sizeof *h);
    if (!h) return FV_ERR_NO_MEMORY;
    fv_result r = ply_header_parse(origin, b, len, h);
    if (r == FV_OK) r = h->format == PLY_ASCII ? ply_walk_ascii(origin, h, b, len) : ply_walk_binary(origin, h, b, len);
    free(h);
    return r == FV_ERR_UNSUPPORTED ? FV_OK : r;
}

/* ---- OBJ ---- */

static fv_result obj_check(const char *origin, const uint8_t *b, size_t len, fv_scene_precheck_ref_fn ref, void *user)
{
    uint64_t v = 0, vt = 0, vn = 0, indices = 0;
    size_t off = 0, lineno = 0;
    span line, t;
    while (next_line(b, len, &off, &line)) {
        lineno++;
        span rest = line;
        if (!next_token(&rest, &t)) continue;
        if (tok_is(t, "v")) v++;
        else if (tok_is(t, "vt")) vt++;
        else if (tok_is(t, "vn")) vn++;
        else if (tok_is(t, "f") || tok_is(t, "l") || tok_is(t, "p")) {
            bool face = tok_is(t, "f");
            uint64_t n = 0;
            while (next_token(&rest, &t)) n++;
            indices += face ? face_indices(n) : n;
        } else if (tok_is(t, "mtllib") && ref) {
            while (next_token(&rest, &t)) {
                char name[FV_SCENE_PATH_MAX];
                if (t.n >= sizeof name) {
                    FV_ERROR("scene", "%s:%zu: mtllib name is longer than %d bytes", origin, lineno,
                             FV_SCENE_PATH_MAX - 1);
                    return FV_ERR_RANGE;
                }
                memcpy(name, t.p, t.n);
                name[t.n] = '\0';
                if (!ref(user, origin, lineno, name)) return FV_ERR_IO;
            }
        }
        if (v > FV_SCENE_MAX_VERTICES || vt > FV_SCENE_MAX_VERTICES || vn > FV_SCENE_MAX_VERTICES) {
            FV_ERROR("scene", "%s:%zu: more than %u vertices (or texture coordinates or normals); refused", origin,
                     lineno, FV_SCENE_MAX_VERTICES);
            return FV_ERR_RANGE;
        }
        if (indices > FV_SCENE_MAX_INDICES) {
            FV_ERROR("scene", "%s:%zu: the faces so far make more than %u triangle indices; refused", origin, lineno,
                     FV_SCENE_MAX_INDICES);
            return FV_ERR_RANGE;
        }
    }
    return FV_OK;
}

/* ---- OFF ---- */

static fv_result off_check(const char *origin, const uint8_t *b, size_t len)
{
    size_t off = 0;
    span line, t;
    uint64_t counts[2];
    int have = 0, lineno = 0;
    char buf[40];
    while (have < 2 && next_line(b, len, &off, &line)) {
        lineno++;
        span rest = line;
        while (have < 2 && next_token(&rest, &t)) {
            if (t.p[0] == '#') break; /* a comment */
            if (lineno == 1 && have == 0 && t.n >= 3 && !memcmp(t.p + t.n - 3, "OFF", 3)) continue; /* [ST][C][N]OFF */
            if (!tok_count(t, &counts[have])) {
                FV_ERROR("scene", "%s: OFF line %d: '%s' is not a vertex or face count", origin, lineno,
                         tok_str(t, buf, sizeof buf));
                return FV_ERR_PARSE;
            }
            have++;
        }
    }
    if (have < 2) return FV_OK; /* assimp reports it */
    /* the smallest vertex is "0 0 0\n" (6 bytes), the smallest face "1 0\n" (4) */
    if (counts[0] > len / 6 || counts[1] > len / 4) {
        FV_ERROR("scene", "%s: OFF header claims %llu vertices and %llu faces but the file has only %llu bytes", origin,
                 (unsigned long long)counts[0], (unsigned long long)counts[1], (unsigned long long)len);
        return FV_ERR_PARSE;
    }
    if (counts[0] > FV_SCENE_MAX_VERTICES) {
        FV_ERROR("scene", "%s: OFF header: %llu vertices exceed the limit %u", origin, (unsigned long long)counts[0],
                 FV_SCENE_MAX_VERTICES);
        return FV_ERR_RANGE;
    }
    return FV_OK;
}

/* ---- entry points ---- */

fv_result fv_scene_precheck_bytes(const char *origin, fv_scene_precheck_format format, const uint8_t *bytes,
                                  size_t len, fv_scene_precheck_ref_fn ref, void *user)
{
    if (!bytes && len) return FV_ERR_INVALID_ARG;
    if (!origin) origin = "<buffer>";
    switch (format) {
    case FV_SCENE_PRECHECK_PLY: return ply_check(origin, bytes, len);
    case FV_SCENE_PRECHECK_OBJ: return obj_check(origin, bytes, len, ref, user);
    case FV_SCENE_PRECHECK_OFF: return off_check(origin, bytes, len);
    case FV_SCENE_PRECHECK_NONE: break;
    }
    return FV_OK;
}

static bool has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), k = strlen(ext);
    return n >= k && strcasecmp(path + n - k, ext) == 0;
}

fv_scene_precheck_format fv_scene_precheck_format_of(const char *path, const uint8_t *head, size_t n)
{
    if (has_ext(path, ".ply")) return FV_SCENE_PRECHECK_PLY;
    if (has_ext(path, ".obj")) return FV_SCENE_PRECHECK_OBJ;
    if (has_ext(path, ".off")) return FV_SCENE_PRECHECK_OFF;
    /* assimp picks by extension and, for one no importer claims, by content: check what the content could be */
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash + 1 : path, '.');
    if (dot && aiIsExtensionSupported(dot)) return FV_SCENE_PRECHECK_NONE;
    if (n >= 4 && !memcmp(head, "ply", 3) && (head[3] == '\n' || head[3] == '\r')) return FV_SCENE_PRECHECK_PLY;
    size_t i = 0;
    while (i < n && is_blank(head[i])) i++;
    for (size_t k = i; k < n && k < i + 4; k++)
        if (k + 3 <= n && !memcmp(head + k, "OFF", 3)) return FV_SCENE_PRECHECK_OFF;
    return FV_SCENE_PRECHECK_OBJ; /* assimp's OBJ reader takes any text with "v "/"f " lines */
}

typedef struct ref_ctx {
    char dir[FV_SCENE_PATH_MAX];
} ref_ctx;

/* An OBJ material library must be a regular file of sane size; a missing one is assimp's warning. */
static bool check_ref_on_disk(void *user, const char *origin, size_t line, const char *name)
{
    const ref_ctx *c = user;
    char full[2 * FV_SCENE_PATH_MAX];
    snprintf(full, sizeof full, "%s%s", name[0] == '/' ? "" : c->dir, name);
    struct stat st;
    if (stat(full, &st) != 0) return true;
    if (!S_ISREG(st.st_mode)) {
        FV_ERROR("scene", "%s:%zu: mtllib '%s' is not a regular file (%s); refused", origin, line, name,
                 S_ISDIR(st.st_mode) ? "a directory" : "a device, pipe or socket");
        return false;
    }
    if ((uint64_t)st.st_size > OBJ_MAX_MTL_BYTES) {
        FV_ERROR("scene", "%s:%zu: mtllib '%s' is %lld bytes, over the %u-byte limit for a material library", origin,
                 line, name, (long long)st.st_size, OBJ_MAX_MTL_BYTES);
        return false;
    }
    return true;
}

fv_result fv_scene_precheck_file(const char *path, uint64_t size)
{
    if (size == 0) return FV_OK; /* assimp reports an empty file */
    if (size > SIZE_MAX) return FV_ERR_RANGE;
    /* through fv_file: what is opened is looked at (a FIFO or device swapped in is refused, never waited on) and
     * may not have grown past the size the caller weighed */
    int fd;
    char why[FV_FILE_ERR_MAX];
    fv_result opened = fv_file_open(path, "model file", size, &fd, &size, why, sizeof why);
    if (opened != FV_OK) {
        FV_ERROR("scene", "%s", why);
        return opened;
    }
    if (size == 0) {
        close(fd);
        return FV_OK;
    }
    void *map = mmap(NULL, (size_t)size, PROT_READ, MAP_PRIVATE, fd, 0);
    close(fd);
    if (map == MAP_FAILED) {
        FV_ERROR("scene", "%s: cannot read model file: %s", path, strerror(errno));
        return FV_ERR_IO;
    }
    const uint8_t *b = map;
    fv_scene_precheck_format fmt = fv_scene_precheck_format_of(path, b, (size_t)(size < 256 ? size : 256));
    ref_ctx rc;
    memset(&rc, 0, sizeof rc);
    const char *slash = strrchr(path, '/');
    if (slash && (size_t)(slash - path + 1) < sizeof rc.dir) memcpy(rc.dir, path, (size_t)(slash - path + 1));
    fv_result r = fv_scene_precheck_bytes(path, fmt, b, (size_t)size, check_ref_on_disk, &rc);
    munmap(map, (size_t)size);
    return r;
}
