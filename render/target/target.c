/* @brief The headless and files targets, and reading the display image back (see fv_target.h). */
#include "fv_target.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>

#include "fv_image_io.h"

#define MOD "target"

fv_result fv_target_read_display(fv_images *images, uint32_t width, uint32_t height, bool sbs, int eye, uint8_t *out,
                                 size_t out_size)
{
    size_t row = (size_t)width * 4;
    if (!images || !out) return FV_ERR_INVALID_ARG;
    if (sbs) {
        if (out_size < 2 * row * height) {
            FV_ERROR(MOD, "side-by-side readback needs %zu bytes, got %zu", 2 * row * height, out_size);
            return FV_ERR_INVALID_ARG;
        }
        for (uint32_t e = 0; e < 2; e++) FV_TRY(fv_images_read(images, FV_IMAGE_DISPLAY, e, out, out_size, e * row, 2 * row));
        return FV_OK;
    }
    if (eye < 0 || eye > 1 || out_size < row * height) {
        FV_ERROR(MOD, "eye readback: eye %d, %zu bytes (needs %zu)", eye, out_size, row * height);
        return FV_ERR_INVALID_ARG;
    }
    return fv_images_read(images, FV_IMAGE_DISPLAY, (uint32_t)eye, out, out_size, 0, row);
}

/* ---- headless ------------------------------------------------------------------------------------------------- */

static const fv_target_ops headless_ops = {.name = "headless"};
static fv_target headless = {.ops = &headless_ops};

fv_target *fv_target_headless(void) { return &headless; }

void fv_target_destroy(fv_target **t)
{
    if (!t || !*t) return;
    if ((*t)->ops && (*t)->ops->destroy) (*t)->ops->destroy(*t);
    *t = NULL;
}

/* ---- files ---------------------------------------------------------------------------------------------------- */

typedef struct files_target {
    fv_target base;
    fv_target_files_desc desc;
    char dir[1024];
    bool have_frame;
    fv_target_frame last; /* the last frame's hand-over (for SAVE_LAST): images, size, frame id */
} files_target;

/* The linear colour of one eye (eye >= 0) or both side by side (eye < 0) as a PFM. */
static fv_result write_pfm(const fv_target_frame *f, int eye, const char *path)
{
    uint32_t w = f->width, h = f->height, eyes = eye < 0 ? 2u : 1u;
    fv_rgb_image img;
    FV_TRY(fv_rgb_image_init(&img, w * eyes, h, FV_IMAGE_KIND_LINEAR));
    float *rgba = malloc((size_t)w * h * 4 * sizeof *rgba);
    fv_result res = rgba ? FV_OK : FV_ERR_NO_MEMORY;
    for (uint32_t e = 0; res == FV_OK && e < eyes; e++) {
        uint32_t layer = eye < 0 ? e : (uint32_t)eye;
        res = fv_images_read(f->images, FV_IMAGE_COLOR, layer, rgba, (size_t)w * h * 16, 0, (size_t)w * 16);
        for (uint32_t y = 0; res == FV_OK && y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                for (int c = 0; c < 3; c++)
                    img.rgb[((size_t)y * w * eyes + e * w + x) * 3 + c] = rgba[((size_t)y * w + x) * 4 + c];
    }
    if (res == FV_OK) res = fv_image_io_write_pfm(path, &img);
    free(rgba);
    fv_rgb_image_fini(&img);
    return res;
}

static fv_result write_frame(files_target *ft, const fv_target_frame *f)
{
    size_t bytes = (size_t)f->width * 2 * f->height * 4;
    uint8_t *buf = malloc(bytes);
    if (!buf) return FV_ERR_NO_MEMORY;
    char path[1200];
    fv_result res = FV_OK;
    if (ft->desc.side_by_side) {
        res = fv_target_read_display(f->images, f->width, f->height, true, 0, buf, bytes);
        snprintf(path, sizeof path, "%s/frame_%05llu.png", ft->dir, (unsigned long long)f->frame_id);
        if (res == FV_OK && !stbi_write_png(path, (int)(2 * f->width), (int)f->height, 4, buf, (int)(2 * f->width * 4))) {
            FV_ERROR(MOD, "%s: cannot write PNG", path);
            res = FV_ERR_IO;
        }
        if (res == FV_OK && ft->desc.linear_pfm) {
            snprintf(path, sizeof path, "%s/frame_%05llu.pfm", ft->dir, (unsigned long long)f->frame_id);
            res = write_pfm(f, -1, path);
        }
    } else {
        static const char *names[2] = {"left", "right"};
        for (int eye = 0; eye < 2 && res == FV_OK; eye++) {
            res = fv_target_read_display(f->images, f->width, f->height, false, eye, buf, bytes);
            snprintf(path, sizeof path, "%s/frame_%05llu_%s.png", ft->dir, (unsigned long long)f->frame_id, names[eye]);
            if (res == FV_OK && !stbi_write_png(path, (int)f->width, (int)f->height, 4, buf, (int)(f->width * 4))) {
                FV_ERROR(MOD, "%s: cannot write PNG", path);
                res = FV_ERR_IO;
            }
            if (res == FV_OK && ft->desc.linear_pfm) {
                snprintf(path, sizeof path, "%s/frame_%05llu_%s.pfm", ft->dir, (unsigned long long)f->frame_id,
                         names[eye]);
                res = write_pfm(f, eye, path);
            }
        }
    }
    free(buf);
    return res;
}

static fv_result files_end(fv_target *t, const fv_target_frame *f)
{
    files_target *ft = (files_target *)t;
    ft->last = *f;
    ft->last.cmd = VK_NULL_HANDLE;
    ft->have_frame = true;
    return ft->desc.save == FV_TARGET_SAVE_EVERY ? write_frame(ft, f) : FV_OK;
}

static void files_destroy(fv_target *t) { free(t); }

static const fv_target_ops files_ops = {.name = "files", .end = files_end, .destroy = files_destroy};

fv_result fv_target_files_create(const fv_target_files_desc *desc, fv_target **out)
{
    if (!desc || !desc->dir || !out) return FV_ERR_INVALID_ARG;
    if (strlen(desc->dir) >= sizeof ((files_target *)0)->dir) {
        FV_ERROR(MOD, "--out %.60s...: the path is longer than %zu bytes", desc->dir, sizeof ((files_target *)0)->dir - 1);
        return FV_ERR_RANGE;
    }
    files_target *ft = calloc(1, sizeof *ft);
    if (!ft) return FV_ERR_NO_MEMORY;
    ft->base.ops = &files_ops;
    ft->desc = *desc;
    snprintf(ft->dir, sizeof ft->dir, "%s", desc->dir);
    ft->desc.dir = ft->dir;
    *out = &ft->base;
    return FV_OK;
}

fv_result fv_target_files_flush(fv_target *t)
{
    if (!t || t->ops != &files_ops) return FV_ERR_INVALID_ARG;
    files_target *ft = (files_target *)t;
    if (!ft->have_frame) return FV_ERR_STATE;
    return write_frame(ft, &ft->last);
}

const char *fv_target_files_dir(const fv_target *t)
{
    return t && t->ops == &files_ops ? ((const files_target *)t)->dir : NULL;
}
