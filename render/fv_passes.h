/* @brief The renderer's pass table (render/passes.c): every pass in frame order, and the plan built from it. Only
 * the renderer and the planning functions see the table; passes never do. */
#ifndef FV_PASSES_H
#define FV_PASSES_H

#include "fv_pass.h"

/** The table, in the order the passes record. */
const fv_pass *const *fv_pass_table(uint32_t *out_count);
/** Every entry's decision for a context (entries[i] belongs to table entry i). */
void fv_frame_plan_build_ctx(const fv_plan_context *ctx, fv_frame_plan *out);
/** The same for any table of count <= FV_MAX_PASSES entries (the renderer's, or a test's with a pass of its own);
 *  each entry's io says what it declares and which pass makes what it reads. */
void fv_frame_plan_build_table(const fv_pass *const *table, uint32_t count, const fv_plan_context *ctx,
                               fv_frame_plan *out);
/** Check a plan of `table` against the passes' declared images: every name an enabled pass needs is made by an
 *  enabled pass before it; every name it uses-if-made is made by some pass of the table, before it; no name is made
 *  by two passes. FV_OK, or FV_ERR_STATE with one line in err naming the passes, the image and what is wrong. */
FV_MUST_CHECK fv_result fv_frame_plan_check(const fv_pass *const *table, uint32_t count, const fv_frame_plan *plan,
                                            char *err, size_t err_size);

/** Whether table entry `reader` needs or uses-if-made an image that entry `maker` makes: a reader keeps views of
 *  those images, so it starts again whenever the maker starts, stops or starts again with another variant. */
bool fv_frame_plan_reads_from(const fv_pass *const *table, uint32_t reader, uint32_t maker);

#endif
