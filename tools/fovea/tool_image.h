/* @brief What an image shows, one description for `fovea run`, `fovea reference` and `fovea bench` (issue 24): the
 * options that change the image (--scene, --eye-size, --layout, --quality, --set, --view, --exposure, --hmd) are
 * parsed here, once, so that a new one cannot reach one command and not the others; and the frame input of a scene
 * time (views, head, HMD frusta, quality) is built here from it. The settings also travel with every image written
 * (fv_tool_image_write_meta: a JSON side file), and `fovea compare` refuses images whose settings disagree. */
#ifndef FV_TOOL_IMAGE_H
#define FV_TOOL_IMAGE_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_renderer.h"
#include "fv_scene.h"
#include "run_hmd.h"
#include "tool_knobs.h"

/** The lines of --help for the options here. */
#define FV_TOOL_IMAGE_USAGE                                                                                            \
    "  --scene     built-in scene name (cornell, cornell-translucent, pillars) or a file: *.scene.json, .gltf/.glb,\n" \
    "              .obj, .ply (default cornell)\n"                                                                     \
    "  --eye-size  per-eye size (default 720x800)\n"                                                                   \
    "  --layout    sbs: one side-by-side stereo image per frame (default); eyes: one image per eye\n"                  \
    "  --quality   the speed/accuracy preset (default balanced; exact: every shortcut off); `fovea knobs`\n"          \
    "  --set       set one knob after the preset, e.g. shadow.splits=3 (repeatable, applied in order)\n"              \
    "  --view      what the image shows (default color); `fovea run --help` lists the views\n"                        \
    "  --exposure  linear scale of the colour before tonemapping (default 1; 1e-6..1e6), or stops: +2EV = 4\n"

typedef struct fv_tool_image {
    fv_app_run run;     /* the description of the run (runtime/app): scene, size, layout, quality, view, exposure, HMD,
                           gaze, head, budget; its defaults and limits */
    bool layout_given;
    run_hmd hmd;        /* the HMD profile loaded for run.hmd, and the budget's controller (its run: &run) */
    fv_quality quality; /* fv_tool_image_finish: the preset, the --set knobs, the lens, then the view settings */
} fv_tool_image;

/** The defaults (fv_app_run_defaults): cornell, 720x800, side by side, balanced, color, exposure 1, the generic HMD.
 *  The image is not copied afterwards (its hmd points at its run). */
void fv_tool_image_defaults(fv_tool_image *o);
/** Take one of the options above (and --hmd, --budget, --budget-scale: run_hmd_option) at argv[*i]: 0 when it is
 *  none of them, 1 when taken (*i advanced past its value), FV_EXIT_USAGE after the one-line error and the usage. */
int fv_tool_image_option(fv_tool_image *o, int argc, char **argv, int *i, const char *cmd, const char *usage);
/** After the options: the quality (preset, --set, the HMD's lens, view, exposure). 0, or the exit code after one
 *  line on stderr. */
int fv_tool_image_finish(fv_tool_image *o, const char *cmd, const char *usage);

/** The frame input of the scene at time_s without a GPU, as `fovea run` draws its frames: the scene's head (or
 *  `head`), near/far from the scene's bounds at load, the HMD's frusta when one was named, gaze ahead, o->quality. */
void fv_tool_image_frame_input(const fv_tool_image *o, const fv_scene *scene, const fv_head *head, uint64_t frame_id,
                               double time_s, fv_frame_input *out);

/** The display's 8-bit sRGB value of a linear value, as the present pass makes it: times the exposure, sanitised,
 *  the tone curve for radiance views (color, direct, gi, sss; `tone`), clamped, sRGB-encoded, rounded. */
uint8_t fv_tool_image_srgb8(float linear, float exposure, bool tone);
/** Whether a view is radiance (the tone curve applies) as the present pass decides. */
bool fv_tool_image_radiance_view(fv_debug_view v);
/** The distort pass on the CPU (render/distort/distort.comp), for one eye's display image (w x h sRGB 8-bit RGB, rows
 *  top to bottom): what the panel shows through the lens of in->quality (each channel's ray through the radial
 *  polynomial and its aberration scale, looked up bilinearly in linear light with clamp to edge; black outside the
 *  image and beyond the lens's visible radius). Copies src when there is no lens or distort.enabled is off. */
void fv_tool_image_lens_srgb8(const fv_frame_input *in, int eye, const uint8_t *src, uint32_t w, uint32_t h,
                              uint8_t *out);

/** The G-buffer's hidden-area mask on the CPU (render/gbuffer/gbuffer_mask.c): with distort.enabled, distort.mask
 *  and a lens, the pixels of one eye's w x h linear RGB image whose centres the mask's triangles cover
 *  (fv_lens_hidden_mesh, the renderer's segments and margin) become 0, as the GPU never shades them. */
void fv_tool_image_mask_linear(const fv_frame_input *in, int eye, float *rgb, uint32_t w, uint32_t h);

/** What an image file holds, written beside it as BASE.json (BASE = the image's path without .png/.pfm) so that a
 *  comparison can check both sides show the same thing. */
typedef struct fv_tool_image_meta {
    const char *producer; /* "fovea run", "fovea reference" */
    const char *scene;
    uint32_t eye_w, eye_h;
    bool sbs;              /* both eyes side by side (else one eye) */
    const char *view;      /* fv_debug_view_name */
    float exposure;
    const char *lens;      /* the HMD profile's name, or "none" */
    bool lens_applied_png; /* the PNG went through the lens (panel image); the PFM never does */
    const char *quality;   /* the preset name */
} fv_tool_image_meta;
/** The meta of an image these options produce. */
fv_tool_image_meta fv_tool_image_meta_of(const fv_tool_image *o, const char *producer, bool sbs_file);
/** Write meta as the JSON side file of image path `image_path` (its .png or .pfm replaced by .json). 0 or -1 after a
 *  warning (the image stands without it). */
int fv_tool_image_write_meta(const char *image_path, const fv_tool_image_meta *m);

/** Whether images a and b (paths of .png or .pfm files) were made with settings that can be compared: when both have
 *  a settings side file, the eye size, layout, view and lens must agree (and the exposure for PNGs, which it
 *  changes); the quality may differ (that is what a comparison measures). 1: comparable (or a side file is missing:
 *  *note then says which, for a warning); 0: they disagree, *why says how (one line). */
int fv_tool_image_comparable(const char *a, const char *b, char *why, size_t why_size, char *note, size_t note_size);

#endif
