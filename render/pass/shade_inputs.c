/* @brief The shading inputs (see fv_shade_inputs.h). */
#include "fv_shade_inputs.h"

#include <stdio.h>
#include <string.h>

#define MOD "shade_inputs"

/* Technique bindings 2.. come in groups of SLOT_BUFFERS buffers then SLOT_IMAGES images. */
static bool shade_inputs_is_buffer(uint32_t binding)
{
    return binding >= 2 && (binding - 2) % (FV_SHADE_INPUTS_SLOT_BUFFERS + FV_SHADE_INPUTS_SLOT_IMAGES) <
                               FV_SHADE_INPUTS_SLOT_BUFFERS;
}
/* Buffer FV_SHADE_INPUTS_SLOT_STATS of each technique: its per-slot stats. */
static bool shade_inputs_is_stats(uint32_t binding)
{
    return binding >= 2 && (binding - 2) % (FV_SHADE_INPUTS_SLOT_BUFFERS + FV_SHADE_INPUTS_SLOT_IMAGES) ==
                               FV_SHADE_INPUTS_SLOT_STATS;
}
_Static_assert(FV_SHADE_INPUTS_SLOT_STATS < FV_SHADE_INPUTS_SLOT_BUFFERS, "the stats buffer is a technique buffer");
_Static_assert(FV_SHADE_INPUTS_BINDING_GI_IMAGE0 == FV_SHADE_INPUTS_BINDING_GI_BUFFER0 + FV_SHADE_INPUTS_SLOT_BUFFERS &&
                   FV_SHADE_INPUTS_BINDING_SSS_BUFFER0 == FV_SHADE_INPUTS_BINDING_GI_IMAGE0 + FV_SHADE_INPUTS_SLOT_IMAGES &&
                   FV_SHADE_INPUTS_BINDING_SSS_IMAGE0 == FV_SHADE_INPUTS_BINDING_SSS_BUFFER0 + FV_SHADE_INPUTS_SLOT_BUFFERS &&
                   FV_SHADE_INPUTS_BINDING_COUNT == FV_SHADE_INPUTS_BINDING_SSS_IMAGE0 + FV_SHADE_INPUTS_SLOT_IMAGES,
               "technique slots: buffers then images, GI then SSS");

fv_result fv_shade_inputs_init(fv_shade_inputs *si, fv_vk *vk, uint32_t slots)
{
    memset(si, 0, sizeof *si);
    if (!vk || !slots || slots > FV_MAX_FRAMES_IN_FLIGHT) return FV_ERR_INVALID_ARG;
    si->vk = vk;
    si->slots = slots;
    si->shadow_map = FV_IMAGE_MAX;
    VkShaderStageFlags st = VK_SHADER_STAGE_COMPUTE_BIT | VK_SHADER_STAGE_FRAGMENT_BIT | VK_SHADER_STAGE_VERTEX_BIT;
    VkDescriptorSetLayoutBinding b[FV_SHADE_INPUTS_BINDING_COUNT] = {
        {FV_SHADE_INPUTS_BINDING_SHADOW, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, st, NULL},
        {FV_SHADE_INPUTS_BINDING_SHADOW_MAP, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, st, NULL},
    };
    uint32_t buffers = 1, images = 1;
    for (uint32_t i = 0; i < FV_SHADE_INPUTS_BINDING_COUNT; i++) {
        si->bound_image[i] = FV_IMAGE_MAX;
        if (i < 2) continue;
        bool buf = shade_inputs_is_buffer(i);
        b[i] = (VkDescriptorSetLayoutBinding){
            i, buf ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, st, NULL};
        if (buf) buffers++;
        else images++;
    }
    fv_result res = fv_vk_set_layout(vk, b, FV_SHADE_INPUTS_BINDING_COUNT, "shading inputs set", &si->layout);
    VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffers * slots},
                                     {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, images * slots}};
    if (res == FV_OK) res = fv_vk_descriptor_pool(vk, sizes, 2, slots, "shading inputs pool", &si->pool);
    if (res == FV_OK) res = fv_vk_sampler_create(vk, false, false, "shadow map sampler (nearest)", &si->nearest);
    if (res == FV_OK) res = fv_vk_sampler_create(vk, true, false, "technique sampler (linear)", &si->linear);
    if (res == FV_OK)
        res = fv_vk_buffer_create(vk, 256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, FV_VK_MEM_UPLOAD,
                                  "no technique buffer (zeros)", &si->dummy_buffer);
    if (res == FV_OK) {
        memset(si->dummy_buffer.mapped, 0, 256);
        res = fv_vk_buffer_flush(vk, &si->dummy_buffer);
    }
    if (res == FV_OK) {
        fv_vk_image_desc d = {.width = 1, .height = 1, .layers = 1, .array = true, .format = VK_FORMAT_R32G32B32A32_SFLOAT,
                              .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                              .name = "no technique image (zero)"};
        res = fv_vk_image_create(vk, &d, &si->dummy_array);
        const float zero[4] = {0};
        if (res == FV_OK)
            res = fv_vk_upload_image(vk, &si->dummy_array, 0, zero, sizeof zero, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
    if (res == FV_OK) {
        fv_vk_image_desc d = {.width = 1, .height = 1, .layers = 1, .array = true, .format = VK_FORMAT_R32_SFLOAT,
                              .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                              .name = "no shadow map (depth 1)"};
        res = fv_vk_image_create(vk, &d, &si->dummy);
        const float one = 1.0f;
        if (res == FV_OK) res = fv_vk_upload_image(vk, &si->dummy, 0, &one, sizeof one, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
    for (uint32_t i = 0; res == FV_OK && i < slots; i++) {
        char name[48];
        snprintf(name, sizeof name, "shadow block slot %u", i);
        res = fv_vk_buffer_create(vk, sizeof(fv_gpu_shadow), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, FV_VK_MEM_UPLOAD, name,
                                  &si->shadow[i]);
        if (res != FV_OK) break;
        memset(si->shadow[i].mapped, 0, sizeof(fv_gpu_shadow));
        /* Stats buffers: written (atomics) by shading passes that count a technique's work, so one per slot (frames in
         * flight never share one); the dummy is never written (the technique's code checks its header first). */
        snprintf(name, sizeof name, "no technique stats slot %u", i);
        res = fv_vk_buffer_create(vk, 256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, FV_VK_MEM_DEVICE, name,
                                  &si->dummy_stats[i]);
        if (res != FV_OK) break;
        snprintf(name, sizeof name, "shading inputs set %u", i);
        res = fv_vk_descriptor_set(vk, si->pool, si->layout, name, &si->sets[i]);
        if (res != FV_OK) break;
        fv_vk_write_buffer(vk, si->sets[i], FV_SHADE_INPUTS_BINDING_SHADOW, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                           si->shadow[i].buffer, 0, sizeof(fv_gpu_shadow));
        res = fv_vk_buffer_flush(vk, &si->shadow[i]);
    }
    if (res == FV_OK) fv_shade_inputs_bind_shadow_map(si, NULL, FV_IMAGE_MAX);
    for (uint32_t i = 2; res == FV_OK && i < FV_SHADE_INPUTS_BINDING_COUNT; i++)
        res = shade_inputs_is_buffer(i) ? fv_shade_inputs_bind_buffer(si, i, VK_NULL_HANDLE, 0, 0)
                                        : fv_shade_inputs_bind_image(si, NULL, i, FV_IMAGE_MAX, false);
    if (res != FV_OK) {
        FV_ERROR(MOD, "shading inputs could not be created: %s", fv_result_str(res));
        fv_shade_inputs_fini(si);
    }
    return res;
}

void fv_shade_inputs_fini(fv_shade_inputs *si)
{
    if (!si || !si->vk) return;
    fv_vk *vk = si->vk;
    for (uint32_t i = 0; i < FV_MAX_FRAMES_IN_FLIGHT; i++) {
        fv_vk_buffer_destroy(vk, &si->shadow[i]);
        fv_vk_buffer_destroy(vk, &si->dummy_stats[i]);
    }
    fv_vk_image_destroy(vk, &si->dummy);
    fv_vk_image_destroy(vk, &si->dummy_array);
    fv_vk_buffer_destroy(vk, &si->dummy_buffer);
    if (si->nearest) vkDestroySampler(vk->device, si->nearest, NULL);
    if (si->linear) vkDestroySampler(vk->device, si->linear, NULL);
    if (si->pool) vkDestroyDescriptorPool(vk->device, si->pool, NULL);
    if (si->layout) vkDestroyDescriptorSetLayout(vk->device, si->layout, NULL);
    memset(si, 0, sizeof *si);
}

fv_gpu_shadow *fv_shade_inputs_shadow(fv_shade_inputs *si, uint32_t slot)
{
    return si && slot < si->slots ? (fv_gpu_shadow *)si->shadow[slot].mapped : NULL;
}

void fv_shade_inputs_begin_frame(fv_shade_inputs *si, uint32_t slot)
{
    fv_gpu_shadow *s = fv_shade_inputs_shadow(si, slot);
    if (s) memset(&s->counts, 0, sizeof s->counts);
}

fv_result fv_shade_inputs_end_frame(fv_shade_inputs *si, uint32_t slot)
{
    if (!si || slot >= si->slots) return FV_ERR_INVALID_ARG;
    return fv_vk_buffer_flush(si->vk, &si->shadow[slot]);
}

void fv_shade_inputs_bind_shadow_map(fv_shade_inputs *si, const fv_images *images, fv_image_id id)
{
    const fv_vk_image *img = images && id != FV_IMAGE_MAX ? fv_images_image(images, id) : NULL;
    si->shadow_map = img ? id : FV_IMAGE_MAX;
    for (uint32_t i = 0; i < si->slots; i++)
        fv_vk_write_image(si->vk, si->sets[i], FV_SHADE_INPUTS_BINDING_SHADOW_MAP,
                          VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, img ? img->view : si->dummy.view, si->nearest,
                          img ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

VkDescriptorSet fv_shade_inputs_set(const fv_shade_inputs *si, uint32_t slot)
{
    return si && slot < si->slots ? si->sets[slot] : VK_NULL_HANDLE;
}

fv_result fv_shade_inputs_bind_buffer(fv_shade_inputs *si, uint32_t binding, VkBuffer buffer, VkDeviceSize offset,
                                     VkDeviceSize range)
{
    if (!si || !si->vk || binding >= FV_SHADE_INPUTS_BINDING_COUNT || !shade_inputs_is_buffer(binding))
        return FV_ERR_INVALID_ARG;
    bool dummy = buffer == VK_NULL_HANDLE;
    if (shade_inputs_is_stats(binding)) {
        for (uint32_t i = 0; dummy && i < si->slots; i++)
            FV_TRY(fv_shade_inputs_bind_stats(si, binding, i, VK_NULL_HANDLE, 0, 0));
        return dummy ? FV_OK : FV_ERR_INVALID_ARG;
    }
    for (uint32_t i = 0; i < si->slots; i++)
        fv_vk_write_buffer(si->vk, si->sets[i], binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                           dummy ? si->dummy_buffer.buffer : buffer, dummy ? 0 : offset,
                           dummy ? 256 : (range ? range : VK_WHOLE_SIZE));
    return FV_OK;
}

fv_result fv_shade_inputs_bind_stats(fv_shade_inputs *si, uint32_t binding, uint32_t slot, VkBuffer buffer,
                                    VkDeviceSize offset, VkDeviceSize range)
{
    if (!si || !si->vk || binding >= FV_SHADE_INPUTS_BINDING_COUNT || !shade_inputs_is_stats(binding) ||
        slot >= si->slots)
        return FV_ERR_INVALID_ARG;
    bool dummy = buffer == VK_NULL_HANDLE;
    fv_vk_write_buffer(si->vk, si->sets[slot], binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                       dummy ? si->dummy_stats[slot].buffer : buffer, dummy ? 0 : offset,
                       dummy ? 256 : (range ? range : VK_WHOLE_SIZE));
    return FV_OK;
}

fv_result fv_shade_inputs_bind_image(fv_shade_inputs *si, const fv_images *images, uint32_t binding, fv_image_id id,
                                    bool linear)
{
    if (!si || !si->vk || binding < 2 || binding >= FV_SHADE_INPUTS_BINDING_COUNT || shade_inputs_is_buffer(binding))
        return FV_ERR_INVALID_ARG;
    const fv_vk_image *img = images && id != FV_IMAGE_MAX ? fv_images_image(images, id) : NULL;
    if (id != FV_IMAGE_MAX && !img) return FV_ERR_INVALID_ARG;
    si->bound_image[binding] = img ? id : FV_IMAGE_MAX;
    for (uint32_t i = 0; i < si->slots; i++)
        fv_vk_write_image(si->vk, si->sets[i], binding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                          img ? img->view : si->dummy_array.view, linear ? si->linear : si->nearest,
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    return FV_OK;
}

void fv_shade_inputs_use(const fv_shade_inputs *si, fv_images *images, VkCommandBuffer cmd, VkPipelineStageFlags stage)
{
    if (!si) return;
    if (si->shadow_map != FV_IMAGE_MAX)
        fv_images_use(images, cmd, si->shadow_map,
                      (fv_vk_image_use){VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL, stage, VK_ACCESS_SHADER_READ_BIT});
    for (uint32_t i = 2; i < FV_SHADE_INPUTS_BINDING_COUNT; i++)
        if (si->bound_image[i] != FV_IMAGE_MAX)
            fv_images_use(images, cmd, si->bound_image[i],
                          (fv_vk_image_use){VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, stage, VK_ACCESS_SHADER_READ_BIT});
}
