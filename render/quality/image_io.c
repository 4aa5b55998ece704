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
#include <zlib.h>

#include "fv_file.h"
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
        FV_ERROR(MOD, "%s: too large: dimensions %llux%llu over the limit (%u per side, %u pixels)", name,
                 (unsigned long long)w, (unsigned long long)h, FV_IMAGE_MAX_SIDE_PX, FV_IMAGE_MAX_PIXELS);
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

/* A PFM's header and size: everything but the pixels is checked. *out_pos: where the pixels start; *out_little:
 * their byte order (both may be NULL). */
static fv_result pfm_header(const uint8_t *d, size_t size, const char *name, fv_image_info *out, size_t *out_pos,
                            bool *out_little)
{
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
    *out = (fv_image_info){.width = (uint32_t)w, .height = (uint32_t)h, .file_channels = ch,
                           .kind = FV_IMAGE_KIND_LINEAR};
    if (out_pos) *out_pos = pos;
    if (out_little) *out_little = scale < 0.0;
    return FV_OK;
}

fv_result fv_image_io_read_pfm(const void *data, size_t size, const char *name, fv_rgb_image *out)
{
    memset(out, 0, sizeof *out);
    if (!name) name = "PFM";
    fv_image_info info;
    size_t pos;
    bool little;
    FV_TRY(pfm_header(data, size, name, &info, &pos, &little));
    uint64_t w = info.width, h = info.height;
    uint32_t ch = info.file_channels;
    FV_TRY(fv_rgb_image_init(out, info.width, info.height, FV_IMAGE_KIND_LINEAR));
    out->file_channels = ch;
    const uint8_t *px = (const uint8_t *)data + pos;
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

static uint32_t load_be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | (uint32_t)p[3];
}

/* The bytes of filtered rows a PNG's image data inflates to, as stb_image sizes them: one filter byte a row, and for
 * Adam7 the seven passes' rows. */
static uint64_t png_raw_bytes(uint64_t w, uint64_t h, uint64_t bits_per_px, bool interlaced)
{
    if (!interlaced) return ((w * bits_per_px + 7) / 8 + 1) * h;
    static const uint64_t x0[7] = {0, 4, 0, 2, 0, 1, 0}, y0[7] = {0, 0, 4, 0, 2, 0, 1};
    static const uint64_t dx[7] = {8, 8, 4, 4, 2, 2, 1}, dy[7] = {8, 8, 8, 4, 4, 2, 2};
    uint64_t n = 0;
    for (int p = 0; p < 7; p++) {
        uint64_t pw = w > x0[p] ? (w - x0[p] + dx[p] - 1) / dx[p] : 0;
        uint64_t ph = h > y0[p] ? (h - y0[p] + dy[p] - 1) / dy[p] : 0;
        if (pw && ph) n += ((pw * bits_per_px + 7) / 8 + 1) * ph;
    }
    return n;
}

/* The image data (the IDAT chunks) may not inflate to more than the header's rows: stb_image would grow its buffer
 * for whatever comes (a 1 MB file can inflate to 1 GB). Inflated here into a small buffer, only counted. A stream
 * zlib cannot read is left to stb_image to report. */
static fv_result png_check_inflated(const uint8_t *d, size_t size, const char *name, uint64_t w, uint64_t h)
{
    static const uint8_t channels[7] = {1, 0, 3, 1, 2, 0, 4};
    uint64_t depth = d[24], ct = d[25];
    if (ct > 6 || channels[ct] == 0) return FV_OK; /* stb_image names a bad colour type */
    uint64_t cap = png_raw_bytes(w, h, depth * channels[ct], d[28] == 1);
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit(&z) != Z_OK) return FV_OK;
    uint8_t out[16384];
    uint64_t total = 0;
    int zr = Z_OK;
    for (size_t pos = 8; pos + 12 <= size && zr == Z_OK && total <= cap;) {
        uint32_t len = load_be32(d + pos);
        if (len > size - pos - 12) break;
        if (memcmp(d + pos + 4, "IDAT", 4) == 0) {
            z.next_in = (Bytef *)(uintptr_t)(d + pos + 8);
            z.avail_in = len;
            while (z.avail_in > 0 && zr == Z_OK && total <= cap) {
                z.next_out = out;
                z.avail_out = sizeof out;
                zr = inflate(&z, Z_NO_FLUSH);
                total += sizeof out - z.avail_out;
                if (zr == Z_BUF_ERROR && z.avail_out != 0) break; /* no progress: wants more input */
            }
            if (zr == Z_BUF_ERROR) zr = Z_OK;
        }
        pos += (size_t)len + 12;
    }
    inflateEnd(&z);
    if (total <= cap) return FV_OK;
    FV_ERROR(MOD, "%s: bad image data: it inflates to more than the %llu bytes of a %llux%llu image's rows", name,
             (unsigned long long)cap, (unsigned long long)w, (unsigned long long)h);
    return FV_ERR_PARSE;
}

/* The PNG's size and channels from its IHDR chunk (bytes 8..32), read here so that an image over the limits is
 * called too large (stb_image refuses some itself and then only says "unknown image type"); then stb's own header
 * check. */
static fv_result png_info(const void *data, size_t size, const char *name, fv_image_info *out)
{
    const uint8_t *d = data;
    if (!data || size < sizeof k_png_magic || memcmp(data, k_png_magic, sizeof k_png_magic) != 0) {
        FV_ERROR(MOD, "%s: bad header: no PNG signature", name);
        return FV_ERR_PARSE;
    }
    if (size < 33 || load_be32(d + 8) != 13 || memcmp(d + 12, "IHDR", 4) != 0) {
        FV_ERROR(MOD, "%s: bad header: %s", name,
                 size < 33 ? "truncated before the end of IHDR" : "no IHDR chunk first");
        return FV_ERR_PARSE;
    }
    FV_TRY(check_dims(name, load_be32(d + 16), load_be32(d + 20)));
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
    FV_TRY(png_check_inflated(d, size, name, (uint64_t)w, (uint64_t)h));
    if (stbi_is_16_bit_from_memory(data, (int)size)) {
        FV_ERROR(MOD, "%s: a 16-bit PNG; only 8-bit PNGs are read", name);
        return FV_ERR_UNSUPPORTED;
    }
    *out = (fv_image_info){.width = (uint32_t)w, .height = (uint32_t)h, .file_channels = (uint32_t)comp,
                           .kind = FV_IMAGE_KIND_SRGB8};
    return FV_OK;
}

fv_result fv_image_io_read_png(const void *data, size_t size, const char *name, fv_rgb_image *out)
{
    memset(out, 0, sizeof *out);
    if (!name) name = "PNG";
    fv_image_info info;
    FV_TRY(png_info(data, size, name, &info));
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

/* ---- header only, and the memory a decode takes ---- */

static bool is_png(const uint8_t *d, size_t size)
{
    return size >= sizeof k_png_magic && memcmp(d, k_png_magic, sizeof k_png_magic) == 0;
}

static bool is_pfm(const uint8_t *d, size_t size) { return size >= 2 && d[0] == 'P' && (d[1] == 'F' || d[1] == 'f'); }

fv_result fv_image_io_info(const void *data, size_t size, const char *name, fv_image_info *out)
{
    memset(out, 0, sizeof *out);
    if (!name) name = "image";
    const uint8_t *d = data ? data : (const uint8_t *)"";
    if (!data) size = 0;
    if (is_png(d, size)) return png_info(d, size, name, out);
    if (is_pfm(d, size)) return pfm_header(d, size, name, out, NULL, NULL);
    FV_ERROR(MOD, "%s: %s", name, size == 0 ? "empty file" : "neither a PNG nor a PFM file");
    return FV_ERR_PARSE;
}

uint64_t fv_image_io_decode_bytes(const fv_image_info *info)
{
    uint64_t px = (uint64_t)info->width * info->height;
    uint64_t image = px * 3 * sizeof(float);
    if (info->kind == FV_IMAGE_KIND_LINEAR) return image; /* straight from the file's bytes into the image */
    /* stb_image: the inflated rows (up to 4 bytes a pixel, one filter byte a row), its 8-bit pixels of up to 4
     * channels, then the 3-channel copy it hands back while the float image is filled */
    return image + px * FV_IMAGE_PNG_DECODER_BYTES_PER_PX + info->height;
}

/* ---- files ---- */

void fv_image_file_fini(fv_image_file *f)
{
    if (!f) return;
    free(f->data);
    memset(f, 0, sizeof *f);
}

fv_result fv_image_io_load(const char *path, uint64_t max_file_bytes, fv_image_file *out)
{
    memset(out, 0, sizeof *out);
    char err[FV_FILE_ERR_MAX];
    size_t limit = max_file_bytes < FV_IMAGE_MAX_FILE_BYTES ? (size_t)max_file_bytes : FV_IMAGE_MAX_FILE_BYTES;
    fv_result r = fv_file_read(path, NULL, limit, &out->data, &out->size, err, sizeof err);
    if (r != FV_OK) {
        FV_ERROR(MOD, "%s", err);
        return r;
    }
    out->path = path;
    r = fv_image_io_info(out->data, out->size, path, &out->info);
    if (r != FV_OK) fv_image_file_fini(out);
    return r;
}

fv_result fv_image_io_decode(fv_image_file *f, fv_rgb_image *out)
{
    fv_result r = f->info.kind == FV_IMAGE_KIND_LINEAR ? fv_image_io_read_pfm(f->data, f->size, f->path, out)
                                                       : fv_image_io_read_png(f->data, f->size, f->path, out);
    free(f->data); /* the pixels are in out now: the file's bytes are not needed any more */
    f->data = NULL;
    f->size = 0;
    return r;
}

fv_result fv_image_io_check_budget(const char *what, uint64_t need, uint64_t budget, const char *hint)
{
    if (need <= budget) return FV_OK;
    FV_ERROR(MOD, "%s: too large to work on: it needs about %llu MiB, over the budget of %llu MiB%s%s", what,
             (unsigned long long)((need + (1u << 20) - 1) >> 20), (unsigned long long)(budget >> 20),
             hint ? " " : "", hint ? hint : "");
    return FV_ERR_RANGE;
}

fv_result fv_image_io_read(const char *path, fv_rgb_image *out)
{
    memset(out, 0, sizeof *out);
    fv_image_file f;
    FV_TRY(fv_image_io_load(path, FV_IMAGE_DECODE_BUDGET_BYTES, &f));
    char what[FV_FILE_ERR_MAX];
    snprintf(what, sizeof what, "%s (%ux%u %s)", path, f.info.width, f.info.height, fv_image_kind_str(f.info.kind));
    fv_result r = fv_image_io_check_budget(what, f.size + fv_image_io_decode_bytes(&f.info),
                                           FV_IMAGE_DECODE_BUDGET_BYTES, NULL);
    if (r == FV_OK) r = fv_image_io_decode(&f, out);
    fv_image_file_fini(&f);
    return r;
}
