/* @brief The frame sample list (see fv_frame_samples.h). */
#include "fv_frame_samples.h"

#include <string.h>

void fv_frame_samples_init(fv_frame_samples *s, fv_vk *vk, uint32_t slots, uint32_t capacity)
{
    memset(s, 0, sizeof *s);
    s->vk = vk;
    s->slots = slots;
    s->capacity = capacity;
}

fv_result fv_frame_samples_reserve(fv_frame_samples *s)
{
    if (!s || !s->vk) return FV_ERR_INVALID_ARG;
    for (uint32_t i = 0; i < s->slots; i++) {
        if (s->list[i].buffer) continue;
        VkDeviceSize size = FV_GPU_LIST_HEADER_BYTES + (VkDeviceSize)s->capacity * 4u;
        FV_TRY(fv_vk_buffer_create(s->vk, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, FV_VK_MEM_READBACK,
                                   "frame sample list", &s->list[i]));
        memset(s->list[i].mapped, 0, FV_GPU_LIST_HEADER_BYTES);
        FV_TRY(fv_vk_buffer_flush(s->vk, &s->list[i]));
        FV_TRY(fv_vk_buffer_create(s->vk, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                                   FV_VK_MEM_DEVICE, "frame sample list dispatch", &s->indirect[i]));
    }
    return FV_OK;
}

void fv_frame_samples_fini(fv_frame_samples *s)
{
    if (!s || !s->vk) return;
    for (uint32_t i = 0; i < FV_MAX_FRAMES_IN_FLIGHT; i++) {
        fv_vk_buffer_destroy(s->vk, &s->list[i]);
        fv_vk_buffer_destroy(s->vk, &s->indirect[i]);
    }
    s->active = false;
}

uint32_t fv_frame_samples_count(fv_frame_samples *s, uint32_t slot)
{
    if (!s || slot >= s->slots || !s->list[slot].buffer) return 0;
    if (fv_vk_buffer_invalidate(s->vk, &s->list[slot]) != FV_OK) return 0;
    uint32_t count;
    memcpy(&count, s->list[slot].mapped, sizeof count);
    return count <= s->capacity ? count : s->capacity;
}
