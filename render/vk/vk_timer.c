/* @brief Per-pass GPU timestamps: one query range per frame in flight, two timestamps per pass. */
#include <stdio.h>
#include <string.h>

#include "fv_vk.h"

#define MOD "vk"
#define PER_SLOT (2u * FV_VK_TIMER_MAX_PASSES)

fv_result fv_vk_timer_init(fv_vk_timer *t, fv_vk *vk, uint32_t slots)
{
    memset(t, 0, sizeof *t);
    if (slots == 0 || slots > FV_MAX_FRAMES_IN_FLIGHT) return FV_ERR_INVALID_ARG;
    t->slots = slots;
    t->supported = vk->info.timestamps;
    if (!t->supported) {
        FV_WARN(MOD, "%s has no compute/graphics timestamps: per-pass GPU times will be missing", vk->info.name);
        return FV_OK;
    }
    t->period_ns = vk->props.limits.timestampPeriod;
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(vk->phys, &n, NULL);
    VkQueueFamilyProperties q[64];
    if (n > 64) n = 64;
    vkGetPhysicalDeviceQueueFamilyProperties(vk->phys, &n, q);
    uint32_t bits = vk->queue_family < n ? q[vk->queue_family].timestampValidBits : 64;
    t->valid_mask = bits >= 64 ? UINT64_MAX : ((UINT64_C(1) << bits) - 1);
    VkQueryPoolCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                                .queryType = VK_QUERY_TYPE_TIMESTAMP,
                                .queryCount = PER_SLOT * slots};
    FV_VK_CHECK(vkCreateQueryPool(vk->device, &ci, NULL, &t->pool));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_QUERY_POOL, t->pool, "pass timestamps (%u frames in flight)", slots);
    return FV_OK;
}

void fv_vk_timer_fini(fv_vk_timer *t, fv_vk *vk)
{
    if (!t) return;
    if (t->pool && vk) vkDestroyQueryPool(vk->device, t->pool, NULL);
    t->pool = VK_NULL_HANDLE;
    t->supported = false;
}

void fv_vk_timer_reset(fv_vk_timer *t, VkCommandBuffer cmd, uint32_t slot)
{
    if (slot >= t->slots) return;
    t->pass_count[slot] = 0;
    if (!t->pool) return;
    vkCmdResetQueryPool(cmd, t->pool, slot * PER_SLOT, PER_SLOT);
}

int fv_vk_timer_begin(fv_vk_timer *t, VkCommandBuffer cmd, uint32_t slot, const char *name)
{
    if (slot >= t->slots || t->pass_count[slot] >= FV_VK_TIMER_MAX_PASSES) return -1;
    uint32_t p = t->pass_count[slot]++;
    snprintf(t->names[slot][p], FV_VK_TIMER_NAME_MAX, "%s", name);
    if (t->pool) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, t->pool, slot * PER_SLOT + 2 * p);
    return (int)p;
}

void fv_vk_timer_end(fv_vk_timer *t, VkCommandBuffer cmd, uint32_t slot, int pass)
{
    if (pass < 0 || slot >= t->slots || !t->pool) return;
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, t->pool, slot * PER_SLOT + 2 * (uint32_t)pass + 1);
}

uint32_t fv_vk_timer_collect(fv_vk_timer *t, fv_vk *vk, uint32_t slot, double *out_ms,
                             char (*out_names)[FV_VK_TIMER_NAME_MAX], uint32_t cap, double *out_total_ms)
{
    if (out_total_ms) *out_total_ms = 0.0;
    if (slot >= t->slots) return 0;
    uint32_t n = t->pass_count[slot];
    if (n > cap) n = cap;
    for (uint32_t i = 0; i < n; i++) {
        if (out_names) memcpy(out_names[i], t->names[slot][i], FV_VK_TIMER_NAME_MAX);
        if (out_ms) out_ms[i] = 0.0;
    }
    if (!t->pool || n == 0) return n;
    uint64_t q[PER_SLOT];
    VkResult r = vkGetQueryPoolResults(vk->device, t->pool, slot * PER_SLOT, 2 * n, sizeof q, q, sizeof q[0],
                                       VK_QUERY_RESULT_64_BIT);
    if (r != VK_SUCCESS) {
        if (r < 0) (void)fv_vk_fail(r, "vkGetQueryPoolResults", __FILE__, __LINE__);
        else FV_WARN(MOD, "timestamps of frame slot %u not ready (%s)", slot, fv_vk_result_str(r));
        return n;
    }
    uint64_t first = UINT64_MAX, last = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint64_t a = q[2 * i] & t->valid_mask, b = q[2 * i + 1] & t->valid_mask;
        uint64_t d = b >= a ? b - a : (b + t->valid_mask + 1 - a) & t->valid_mask; /* wrapped counter */
        if (out_ms) out_ms[i] = (double)d * t->period_ns * 1e-6;
        if (a < first) first = a;
        if (b > last) last = b;
    }
    if (out_total_ms && last >= first) *out_total_ms = (double)(last - first) * t->period_ns * 1e-6;
    return n;
}
