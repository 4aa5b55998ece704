/* @brief PNG (stb_image) and PFM readers on byte spans, the PFM writer, and the file around them. Every header field
 * is checked before anything is allocated: dimensions against the limits, then the pixel bytes against the size. */
#include "fv_image_io.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>

#include "fv_log.h"

#define MOD "quality"

static const uint8_t k_png_magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

static fv_result check_dims(const char *name, uint64_t w, uint64_t h)
{
    if (w == 0 || h == 0) {
        FV_ERROR(MOD, "%s: bad header: image is %llux%llu", name, (unsigned long long)w, (unsigned long long)h);
        return FV_ERR_PARSE;
    }
    if (w > FV_IMAGE_MAX_SIDE_PX || h > FV_IMAGE_MAX_SIDE_PX || w * h > FV_IMAGE_MAX_PIXELS) {
        FV_ERROR(MOD, "%s: dimensions %llux%llu over the limit (%u per side, %u pixels)", name, (unsigned long long)w,
                 (unsigned long long)h, FV_IMAGE_MAX_SIDE_PX, FV_IMAGE_MAX_PIXELS);
        return FV_ERR_RANGE;
    }
    return FV_OK;
}

fv_result fv_rgb_image_init(fv_rgb_image *img, uint32_t width, uint32_t height, fv_image_kind kind)
{
    memset(img, 0, sizeof *img);
    FV_TRY(check_dims("image", width, height));
    img->rgb = calloc((size_t)width * height * 3, sizeof(float));
    if (!img->rgb) {
        FV_ERROR(MOD, "out of memory for a %ux%u image", width, height);
        return FV_ERR_NO_MEMORY;
    }
    img->width = width;
    img->height = height;
    img->kind = kind;
    img->file_channels = 3;
    return FV_OK;
}

void fv_rgb_image_fini(fv_rgb_image *img)
{
    if (!img) return;
    free(img->rgb);
    memset(img, 0, sizeof *img);
}

const char *fv_image_kind_str(fv_image_kind kind)
{
    switch (kind) {
    case FV_IMAGE_KIND_SRGB8: return "PNG";
    case FV_IMAGE_KIND_LINEAR: return "PFM";
    }
    return "unknown";
}

/* ---- PFM ---- */

static bool is_space(uint8_t c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

/* A header token: skip white space (at least one byte), then copy up to cap-1 non-space bytes, which must be followed
 * by white space. */
static bool pfm_token(const uint8_t *d, size_t size, size_t *pos, char *tok, size_t cap)
{
    size_t p = *pos, start;
    if (p < size && !is_space(d[p])) return false;
    while (p < size && is_space(d[p])) p++;
    start = p;
    while (p < size && !is_space(d[p])) p++;
    *pos = p; /* where it stopped: at the end of the input when truncated */
    if (p == start || p - start >= cap || p >= size) return false; /* a token must be followed by white space */
    memcpy(tok, d + start, p - start);
    tok[p - start] = '\0';
    return true;
}

static bool parse_dim(const char *tok, uint64_t *out)
{
    uint64_t v = 0;
    if (!*tok || strlen(tok) > 10) return false;
    for (const char *c = tok; *c; c++) {
        if (*c < '0' || *c > '9') return false;
        v = v * 10 + (uint64_t)(*c - '0');
    }
    *out = v;
    return true;
}

static float load_f32(const uint8_t *p, bool little)
{
    uint32_t u = little ? (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24
                        : (uint32_t)p[3] | (uint32_t)p[2] << 8 | (uint32_t)p[1] << 16 | (uint32_t)p[0] << 24;
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static void store_f32_le(uint8_t *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    p[0] = (uint8_t)u, p[1] = (uint8_t)(u >> 8), p[2] = (uint8_t)(u >> 16), p[3] = (uint8_t)(u >> 24);
}

fv_result fv_image_io_read_pfm(const void *data, size_t size, const char *name, fv_rgb_image *out)
{
    const uint8_t *d = data;
    memset(out, 0, sizeof *out);
    if (!name) name = "PFM";
    if (!d || size < 2 || d[0] != 'P' || (d[1] != 'F' && d[1] != 'f')) {
        FV_ERROR(MOD, "%s: bad header: a PFM starts with \"PF\" or \"Pf\"", name);
        return FV_ERR_PARSE;
    }
    uint32_t ch = d[1] == 'F' ? 3 : 1;
    char tw[16], th[16], ts[64];
    size_t pos = 2;
    if (!pfm_token(d, size, &pos, tw, sizeof tw) || !pfm_token(d, size, &pos, th, sizeof th) ||
        !pfm_token(d, size, &pos, ts, sizeof ts)) {
        FV_ERROR(MOD, "%s: %s: expected \"%s <width> <height> <scale>\" and one white-space byte", name,
                 pos >= size ? "truncated" : "bad header", ch == 3 ? "PF" : "Pf");
        return FV_ERR_PARSE;
    }
    uint64_t w, h;
    if (!parse_dim(tw, &w) || !parse_dim(th, &h)) {
        FV_ERROR(MOD, "%s: bad header: width '%s' and height '%s' must be whole numbers", name, tw, th);
        return FV_ERR_PARSE;
    }
    char *end = NULL;
    double scale = strtod(ts, &end);
    if (*end != '\0') {
        FV_ERROR(MOD, "%s: bad header: scale '%s' is not a number", name, ts);
        return FV_ERR_PARSE;
    }
    if (!isfinite(scale)) {
        FV_ERROR(MOD, "%s: bad header: non-finite scale '%s'", name, ts);
        return FV_ERR_PARSE;
    }
    if (scale == 0.0) {
        FV_ERROR(MOD, "%s: bad header: scale is 0 (its sign gives the byte order)", name);
        return FV_ERR_PARSE;
    }
    FV_TRY(check_dims(name, w, h));
    pos++; /* the one white-space byte after the scale (pfm_token guaranteed it is there) */
    size_t need = (size_t)w * (size_t)h * ch * 4u, have = size - pos;
    if (have < need) {
        FV_ERROR(MOD, "%s: truncated: %zu bytes of pixels, a %llux%llu %s PFM needs %zu", name, have,
                 (unsigned long long)w, (unsigned long long)h, ch == 3 ? "colour" : "grey", need);
        return FV_ERR_PARSE;
    }
    if (have > need) {
        FV_ERROR(MOD, "%s: wrong size: %zu bytes after the pixels of a %llux%llu PFM", name, have - need,
                 (unsigned long long)w, (unsigned long long)h);
        return FV_ERR_PARSE;
    }
    FV_TRY(fv_rgb_image_init(out, (uint32_t)w, (uint32_t)h, FV_IMAGE_KIND_LINEAR));
    out->file_channels = ch;
    bool little = scale < 0.0;
    const uint8_t *px = d + pos;
    for (uint64_t fy = 0; fy < h; fy++) { /* file rows run bottom to top */
        float *row = out->rgb + (size_t)(h - 1 - fy) * (size_t)w * 3;
        for (uint64_t x = 0; x < w; x++) {
            for (uint32_t c = 0; c < 3; c++) row[x * 3 + c] = load_f32(px + (ch == 3 ? c : 0) * 4, little);
            px += ch * 4;
        }
    }
    return FV_OK;
}

fv_result fv_image_io_encode_pfm(const fv_rgb_image *img, uint8_t **out_data, size_t *out_size)
{
    *out_data = NULL;
    *out_size = 0;
    if (!img || !img->rgb || img->width == 0 || img->height == 0) return FV_ERR_INVALID_ARG;
    char head[64];
    int n = snprintf(head, sizeof head, "PF\n%u %u\n-1\n", img->width, img->height);
    size_t px = (size_t)img->width * img->height * 3 * 4;
    uint8_t *buf = malloc((size_t)n + px);
    if (!buf) {
        FV_ERROR(MOD, "out of memory encoding a %ux%u PFM", img->width, img->height);
        return FV_ERR_NO_MEMORY;
    }
    memcpy(buf, head, (size_t)n);
    uint8_t *p = buf + n;
    for (uint32_t fy = 0; fy < img->height; fy++) {
        const float *row = img->rgb + (size_t)(img->height - 1 - fy) * img->width * 3;
        for (size_t i = 0; i < (size_t)img->width * 3; i++, p += 4) store_f32_le(p, row[i]);
    }
    *out_data = buf;
    *out_size = (size_t)n + px;
    return FV_OK;
}

fv_result fv_image_io_write_pfm(const char *path, const fv_rgb_image *img)
{
    uint8_t *buf;
    size_t size;
    FV_TRY(fv_image_io_encode_pfm(img, &buf, &size));
    FILE *f = fopen(path, "wb");
    bool ok = f && fwrite(buf, 1, size, f) == size;
    int err = errno;
    if (f && fclose(f) != 0) ok = false;
    free(buf);
    if (!ok) {
        FV_ERROR(MOD, "%s: cannot write: %s", path, strerror(err));
        return FV_ERR_IO;
    }
    return FV_OK;
}

/* ---- PNG ---- */

fv_result fv_image_io_read_png(const void *data, size_t size, const char *name, fv_rgb_image *out)
{
    memset(out, 0, sizeof *out);
    if (!name) name = "PNG";
    if (!data || size < sizeof k_png_magic || memcmp(data, k_png_magic, sizeof k_png_magic) != 0) {
        FV_ERROR(MOD, "%s: bad header: no PNG signature", name);
        return FV_ERR_PARSE;
    }
    if (size > INT_MAX) {
        FV_ERROR(MOD, "%s: %zu bytes is more than the PNG decoder reads", name, size);
        return FV_ERR_RANGE;
    }
    int w, h, comp;
    if (!stbi_info_from_memory(data, (int)size, &w, &h, &comp)) {
        FV_ERROR(MOD, "%s: bad header: %s", name, stbi_failure_reason());
        return FV_ERR_PARSE;
    }
    FV_TRY(check_dims(name, (uint64_t)w, (uint64_t)h));
    if (stbi_is_16_bit_from_memory(data, (int)size)) {
        FV_ERROR(MOD, "%s: a 16-bit PNG; only 8-bit PNGs are read", name);
        return FV_ERR_UNSUPPORTED;
    }
    int dw, dh, dc;
    stbi_uc *px = stbi_load_from_memory(data, (int)size, &dw, &dh, &dc, 3);
    if (!px) {
        FV_ERROR(MOD, "%s: cannot decode: %s", name, stbi_failure_reason());
        return FV_ERR_PARSE;
    }
    fv_result r = fv_rgb_image_init(out, (uint32_t)dw, (uint32_t)dh, FV_IMAGE_KIND_SRGB8);
    if (r == FV_OK) {
        out->file_channels = (uint32_t)dc;
        for (size_t i = 0; i < (size_t)dw * (size_t)dh * 3; i++) out->rgb[i] = (float)px[i] / 255.0f;
    }
    stbi_image_free(px);
    return r;
}

/* ---- files ---- */

static fv_result read_whole_file(const char *path, uint8_t **out_data, size_t *out_size)
{
    *out_data = NULL;
    *out_size = 0;
    FILE *f = fopen(path, "rb");
    if (!f) {
        int err = errno;
        FV_ERROR(MOD, "%s: cannot open: %s", path, strerror(err));
        return err == ENOENT ? FV_ERR_NOT_FOUND : FV_ERR_IO;
    }
    size_t cap = 1 << 16, n = 0;
    uint8_t *buf = malloc(cap);
    fv_result r = buf ? FV_OK : FV_ERR_NO_MEMORY;
    while (r == FV_OK) {
        if (n == cap) {
            if (cap >= FV_IMAGE_MAX_FILE_BYTES) {
                FV_ERROR(MOD, "%s: larger than %zu bytes", path, FV_IMAGE_MAX_FILE_BYTES);
                r = FV_ERR_RANGE;
                break;
            }
            uint8_t *nb = realloc(buf, cap * 2);
            if (!nb) {
                r = FV_ERR_NO_MEMORY;
                break;
            }
            buf = nb;
            cap *= 2;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0) {
            if (ferror(f)) {
                FV_ERROR(MOD, "%s: cannot read: %s", path, strerror(errno));
                r = FV_ERR_IO;
            }
            break;
        }
    }
    fclose(f);
    if (r == FV_ERR_NO_MEMORY) FV_ERROR(MOD, "%s: out of memory reading it", path);
    if (r != FV_OK) {
        free(buf);
        return r;
    }
    *out_data = buf;
    *out_size = n;
    return FV_OK;
}

fv_result fv_image_io_read(const char *path, fv_rgb_image *out)
{
    memset(out, 0, sizeof *out);
    uint8_t *data;
    size_t size;
    FV_TRY(read_whole_file(path, &data, &size));
    fv_result r;
    if (size >= sizeof k_png_magic && memcmp(data, k_png_magic, sizeof k_png_magic) == 0) {
        r = fv_image_io_read_png(data, size, path, out);
    } else if (size >= 2 && data[0] == 'P' && (data[1] == 'F' || data[1] == 'f')) {
        r = fv_image_io_read_pfm(data, size, path, out);
    } else {
        FV_ERROR(MOD, "%s: %s", path, size == 0 ? "empty file" : "neither a PNG nor a PFM file");
        r = FV_ERR_PARSE;
    }
    free(data);
    return r;
}
