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
/** The largest file fv_image_io_read reads (bytes): refused from its size, before a byte is read. */
#define FV_IMAGE_MAX_FILE_BYTES ((size_t)1 << 30)
/** The memory budget of reading one image with fv_image_io_read: the file's bytes plus fv_image_io_decode_bytes,
 *  checked from the header before any pixel is decoded (a 49 KB PNG may be 16384 x 16384 pixels). */
#define FV_IMAGE_DECODE_BUDGET_BYTES ((uint64_t)1 << 30)
/** stb_image's own buffers while it decodes a PNG, per pixel: the inflated rows (up to 4 bytes) and its 8-bit
 *  pixels (up to 4 channels), then the 3-channel copy it returns (1 more than 4 + 4: interlaced passes). */
#define FV_IMAGE_PNG_DECODER_BYTES_PER_PX 9u

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

/** What an image file's header says. */
typedef struct fv_image_info {
    uint32_t width, height;
    uint32_t file_channels;
    fv_image_kind kind;
} fv_image_info;

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
/** Decode an 8-bit PNG from memory through stb_image (grey, grey+alpha, RGB, RGBA; alpha dropped). FV_ERR_PARSE
 *  (also: image data that inflates to more than the header's rows, counted before stb_image decodes, which would
 *  hold all of it), FV_ERR_UNSUPPORTED (16-bit) or FV_ERR_RANGE (dimensions over the limits, from the IHDR chunk,
 *  before decoding). */
FV_MUST_CHECK fv_result fv_image_io_read_png(const void *data, size_t size, const char *name, fv_rgb_image *out);
/** The header of a PNG or PFM in memory (told apart by content), every field checked as the decoders check them
 *  (a PFM's size too) but no pixel decoded and nothing allocated. FV_ERR_RANGE names a too-large image's
 *  dimensions and the limit; FV_ERR_PARSE: neither format ("empty file" when size is 0), or a bad header. */
FV_MUST_CHECK fv_result fv_image_io_info(const void *data, size_t size, const char *name, fv_image_info *out);
/** The most memory decoding such an image holds at once, besides the file's bytes: the float RGB image, and for a
 *  PNG stb_image's buffers (FV_IMAGE_PNG_DECODER_BYTES_PER_PX). */
uint64_t fv_image_io_decode_bytes(const fv_image_info *info);
/** FV_OK when `need` bytes fit the budget; else FV_ERR_RANGE after one message: "<what>: too large to work on: it
 *  needs about N MiB, over the budget of B MiB[ <hint>]" (hint may be NULL). */
FV_MUST_CHECK fv_result fv_image_io_check_budget(const char *what, uint64_t need, uint64_t budget, const char *hint);

/** An image file read into memory with its header checked, to be decoded once the caller has weighed the cost. */
typedef struct fv_image_file {
    const char *path; /* borrowed */
    char *data;       /* the file's bytes (owned; NULL once decoded) */
    size_t size;
    fv_image_info info;
} fv_image_file;
/** Read a PNG or PFM file through fv_file_read (a regular file only: a FIFO, device or directory is refused
 *  without blocking or reading; a file over max_file_bytes or FV_IMAGE_MAX_FILE_BYTES is refused from its size)
 *  and check its header (fv_image_io_info). FV_ERR_NOT_FOUND, FV_ERR_IO, FV_ERR_RANGE, FV_ERR_PARSE. */
FV_MUST_CHECK fv_result fv_image_io_load(const char *path, uint64_t max_file_bytes, fv_image_file *out);
/** Decode a loaded file into *out and free its bytes (as fv_image_io_read_png / _pfm). */
FV_MUST_CHECK fv_result fv_image_io_decode(fv_image_file *f, fv_rgb_image *out);
/** Free a loaded file; safe on a zeroed struct and twice. */
void fv_image_file_fini(fv_image_file *f);

/** Read a PNG or PFM file: fv_image_io_load, then the file's bytes plus fv_image_io_decode_bytes weighed against
 *  FV_IMAGE_DECODE_BUDGET_BYTES before decoding. FV_ERR_IO / FV_ERR_NOT_FOUND when it cannot be read, FV_ERR_PARSE
 *  when it is neither format, FV_ERR_RANGE over a limit or the budget, else as the decoders. */
FV_MUST_CHECK fv_result fv_image_io_read(const char *path, fv_rgb_image *out);

/** Encode as a colour PFM: "PF\n<w> <h>\n-1\n", little-endian float32 RGB, rows bottom to top. *out_data is
 *  malloc'ed (caller frees). */
FV_MUST_CHECK fv_result fv_image_io_encode_pfm(const fv_rgb_image *img, uint8_t **out_data, size_t *out_size);
/** Write fv_image_io_encode_pfm's bytes to `path`. */
FV_MUST_CHECK fv_result fv_image_io_write_pfm(const char *path, const fv_rgb_image *img);

#endif
