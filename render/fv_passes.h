/* @brief The renderer's pass table (render/passes.c): every pass in frame order, and the plan built from it. Only
 * the renderer and the planning functions see the table; passes never do. */
#ifndef FV_PASSES_H
#define FV_PASSES_H

#include "fv_pass.h"

/** The table, in the order the passes record. */
const fv_pass *const *fv_pass_table(uint32_t *out_count);
/** Every entry's decision for a context (entries[i] belongs to table entry i). */
void fv_frame_plan_build_ctx(const fv_plan_context *ctx, fv_frame_plan *out);

#endif
