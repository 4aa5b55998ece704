/* @brief The renderer's post chain (see fv_post_chain.h). */
#include "fv_post_chain.h"

#include <stdlib.h>

#include "distort.h"
#include "fv_pass.h"
#include "fv_plan.h"

/* The post passes of the pass table (frame_plan.c), in its order: those after the present pass that read and write
 * the display image alone (no scene, no shading inputs, no sample list). */
static const fv_pass *const g_post_passes[] = {&fv_distort_pass};
#define POST_COUNT (sizeof g_post_passes / sizeof g_post_passes[0])

struct fv_post_chain {
    fv_plan_entry plan[POST_COUNT];
    void *state[POST_COUNT]; /* NULL: planned off */
    fv_images *images;
    uint32_t count;
};

fv_result fv_post_chain_create(fv_vk *vk, fv_images *images, uint32_t w, uint32_t h, const fv_quality *q,
                               fv_post_chain **out)
{
    *out = NULL;
    fv_post_chain *pc = calloc(1, sizeof *pc);
    if (!pc) return FV_ERR_NO_MEMORY;
    pc->images = images;
    fv_plan_context ctx = {.quality = q, .target = "headless"};
    for (uint32_t k = 0; k < POST_COUNT; k++) {
        g_post_passes[k]->plan(&ctx, &pc->plan[k]);
        if (!pc->plan[k].enabled) continue;
        fv_pass_env env = {.vk = vk, .images = images, .width = w, .height = h, .slots = 1, .plan = &pc->plan[k]};
        fv_result res = g_post_passes[k]->init(&env, &pc->state[k]);
        if (res != FV_OK) {
            pc->state[k] = NULL;
            fv_post_chain_destroy(&pc);
            return res;
        }
        pc->count++;
    }
    *out = pc;
    return FV_OK;
}

uint32_t fv_post_chain_count(const fv_post_chain *pc) { return pc ? pc->count : 0; }
uint32_t fv_post_chain_planned(const fv_post_chain *pc) { return pc ? (uint32_t)POST_COUNT : 0; }

const char *fv_post_chain_pass_id(const fv_post_chain *pc, uint32_t k)
{
    return pc && k < POST_COUNT ? g_post_passes[k]->id : "";
}

const char *fv_post_chain_reason(const fv_post_chain *pc, uint32_t k)
{
    return pc && k < POST_COUNT ? pc->plan[k].reason : "";
}

void fv_post_chain_record(fv_post_chain *pc, VkCommandBuffer cmd, const fv_frame_input *in, fv_vk_timer *timer,
                          uint32_t slot)
{
    if (!pc) return;
    for (uint32_t k = 0; k < POST_COUNT; k++) {
        if (!pc->state[k]) continue;
        fv_pass_counters counters = {0};
        fv_pass_frame pf = {.cmd = cmd, .slot = 0, .input = in, .images = pc->images, .counters = &counters};
        int tp = timer ? fv_vk_timer_begin(timer, cmd, slot, g_post_passes[k]->id) : -1;
        g_post_passes[k]->record(pc->state[k], &pf);
        if (timer) fv_vk_timer_end(timer, cmd, slot, tp);
    }
}

void fv_post_chain_destroy(fv_post_chain **ppc)
{
    if (!ppc || !*ppc) return;
    fv_post_chain *pc = *ppc;
    for (uint32_t k = POST_COUNT; k-- > 0;)
        if (pc->state[k]) g_post_passes[k]->fini(pc->state[k]);
    free(pc);
    *ppc = NULL;
}
