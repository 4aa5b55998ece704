/* @brief Image files for the quality metrics: PNG (8-bit grey/RGB/RGBA, read as sRGB values in [0,1]) and PFM (the
 * Portable Float Map: linear float32, read and written). Decoding works on byte spans (the fuzzer's entry point);
 * fv_image_io_read adds the file around it. Errors are logged once, naming the file and the reason. */
#ifndef FV_IMAGE_IO_H
#define FV_IMAGE_IO_H

#include <stddef.h>
#include <stdint.h>

#include "fv_result.h"

/** The largest image side and pixel count a reader accepts, checked from the header before anything is allocated. */
#define FV_IMAGE_MAX_SIDE_PX 16384u
#define FV_IMAGE_MAX_PIXELS (1u << 26) /* 64 Mpx: 768 MiB of float RGB */
/** The largest file fv_image_io_read reads (bytes). */
#define FV_IMAGE_MAX_FILE_BYTES ((size_t)1 << 30)

/** What the values of an image are. */
typedef enum fv_image_kind {
    FV_IMAGE_KIND_SRGB8 = 1,  /* from an 8-bit PNG: sRGB-encoded values k / 255 in [0, 1] */
    FV_IMAGE_KIND_LINEAR = 2, /* from a PFM: linear floats, as stored (NaN and Inf are kept) */
} fv_image_kind;

/** An RGB float image, rows top to bottom, 3 floats per pixel. The caller embeds it; fv_rgb_image_fini frees. */
typedef struct fv_rgb_image {
    uint32_t width, height;
    fv_image_kind kind;
    uint32_t file_channels; /* channels in the file: 1 grey (replicated to RGB), 3 RGB, 4 RGBA (alpha dropped) */
    float *rgb;             /* width * height * 3 floats, owned */
} fv_rgb_image;

/** Allocate a zeroed w x h image of this kind (file_channels 3). FV_ERR_RANGE over the limits above. */
FV_MUST_CHECK fv_result fv_rgb_image_init(fv_rgb_image *img, uint32_t width, uint32_t height, fv_image_kind kind);
/** Free the pixels and zero the struct; safe on a zeroed struct, after a failed read and twice. */
void fv_rgb_image_fini(fv_rgb_image *img);

/** "PNG" or "PFM" for a kind. */
const char *fv_image_kind_str(fv_image_kind kind);

/** Decode a PFM from memory ("PF" colour / "Pf" grey, width height, scale: < 0 little-endian, > 0 big-endian,
 *  rows bottom to top). `name` names the input in messages. FV_ERR_PARSE (bad header, truncated, wrong size,
 *  non-finite or zero scale) or FV_ERR_RANGE (dimensions over the limits); *out is zeroed on failure. */
FV_MUST_CHECK fv_result fv_image_io_read_pfm(const void *data, size_t size, const char *name, fv_rgb_image *out);
/** Decode an 8-bit PNG from memory through stb_image (grey, grey+alpha, RGB, RGBA; alpha dropped). FV_ERR_PARSE,
 *  FV_ERR_UNSUPPORTED (16-bit) or FV_ERR_RANGE (dimensions over the limits, checked before decoding). */
FV_MUST_CHECK fv_result fv_image_io_read_png(const void *data, size_t size, const char *name, fv_rgb_image *out);
/** Read a PNG or PFM file, told apart by content (the PNG signature, "PF"/"Pf"). FV_ERR_IO / FV_ERR_NOT_FOUND
 *  when it cannot be read, FV_ERR_PARSE when it is neither format, else as the decoders. */
FV_MUST_CHECK fv_result fv_image_io_read(const char *path, fv_rgb_image *out);

/** Encode as a colour PFM: "PF\n<w> <h>\n-1\n", little-endian float32 RGB, rows bottom to top. *out_data is
 *  malloc'ed (caller frees). */
FV_MUST_CHECK fv_result fv_image_io_encode_pfm(const fv_rgb_image *img, uint8_t **out_data, size_t *out_size);
/** Write fv_image_io_encode_pfm's bytes to `path`. */
FV_MUST_CHECK fv_result fv_image_io_write_pfm(const char *path, const fv_rgb_image *img);

#endif
