/* @brief Targets: where a drawn frame is shown, after the present pass has encoded it into the display image
 * (FV_IMAGE_DISPLAY). A target is an object with ops: `begin` before the frame is recorded (a swapchain acquires
 * its image here and asks the submit to wait for it), `record` at the end of the frame's commands (a swapchain
 * copies the display image to its image), `end` after the submit (a swapchain presents, waiting for the submit).
 * Built in: headless (the image stays on the GPU, read back on demand) and files (PNGs written from the display
 * image). A window presenter is one more target. The renderer owns one binary semaphore pair per frame slot for
 * these hand-overs. */
#ifndef FV_TARGET_H
#define FV_TARGET_H

#include <stdbool.h>

#include "fv_images.h"
#include "fv_vk.h"

typedef struct fv_target fv_target;

/** One frame's hand-over with a target. */
typedef struct fv_target_frame {
    fv_vk *vk;
    fv_images *images;      /* FV_IMAGE_DISPLAY holds the frame after the present pass */
    uint32_t width, height; /* per eye */
    uint32_t slot;
    uint64_t frame_id;
    VkCommandBuffer cmd;    /* record: the frame's command buffer, after every pass */
    VkSemaphore image_ready; /* the slot's semaphore a target signals when its image may be written (acquire) */
    VkSemaphore frame_done;  /* the slot's semaphore the submit signals when asked (for a present to wait on) */
} fv_target_frame;

typedef struct fv_target_ops {
    const char *name; /* "headless", "files", "window" */
    /** Before recording. *out_wait_ready: the submit waits for image_ready; *out_signal_done: the submit signals
     *  frame_done. NULL: nothing to do. */
    fv_result (*begin)(fv_target *t, const fv_target_frame *f, bool *out_wait_ready, bool *out_signal_done);
    /** Record the hand-over at the end of the frame's commands. NULL: nothing to do. */
    void (*record)(fv_target *t, const fv_target_frame *f);
    /** After the submit. NULL: nothing to do. */
    fv_result (*end)(fv_target *t, const fv_target_frame *f);
    void (*destroy)(fv_target *t);
    /** Before the renderer creates its device: what the target needs of it (a window: its surface's instance
     *  extensions and the callback that creates the surface; fv_vk_desc's presentation fields). NULL: nothing. */
    void (*configure_vk)(fv_target *t, fv_vk_desc *desc);
    /** The renderer's device is about to go (the GPU is idle): free everything made with it (a swapchain). NULL:
     *  nothing. */
    void (*detach)(fv_target *t, fv_vk *vk);
} fv_target_ops;

struct fv_target {
    const fv_target_ops *ops;
};

/** The headless target: the display image stays on the GPU. A static object; destroy does nothing. */
fv_target *fv_target_headless(void);

/** Which frames the files target writes. */
typedef enum fv_target_files_save { FV_TARGET_SAVE_EVERY = 0, FV_TARGET_SAVE_LAST = 1 } fv_target_files_save;

typedef struct fv_target_files_desc {
    const char *dir;        /* existing directory the PNGs go to */
    bool side_by_side;      /* true: frame_NNNNN.png (2W x H); false: frame_NNNNN_left.png and _right.png */
    fv_target_files_save save;
    bool linear_pfm;        /* also the linear colour (or view) as PFM, same name with .pfm (both eyes side by side
                             * or one file per eye, as the PNGs) */
} fv_target_files_desc;

/** The files target: every frame (SAVE_EVERY) is written as PNG after its submit; with SAVE_LAST, only what
 *  fv_target_files_flush writes (the last frame drawn). */
FV_MUST_CHECK fv_result fv_target_files_create(const fv_target_files_desc *desc, fv_target **out);
/** Write the last frame that went through the target (SAVE_LAST), after the GPU finished it. FV_ERR_STATE when no
 *  frame went through yet. */
FV_MUST_CHECK fv_result fv_target_files_flush(fv_target *t);
/** Directory of a files target (NULL for other targets). */
const char *fv_target_files_dir(const fv_target *t);
/** Destroy any target; sets *t to NULL. Safe on NULL. */
void fv_target_destroy(fv_target **t);

/** Read the display image as 8-bit RGBA: sbs = both eyes side by side (2W x H), else one eye (W x H). Submits and
 *  waits (the frame must have been submitted). */
FV_MUST_CHECK fv_result fv_target_read_display(fv_images *images, uint32_t width, uint32_t height, bool sbs, int eye,
                                               uint8_t *out, size_t out_size);

#endif
