/* @brief The shading pass (see shade.h). */
#include "shade.h"

#include <stdio.h>
#include <string.h>

#include "shade_comp.spv.h"

#define MOD "shade"

_Static_assert(sizeof(struct fv_shade_push) == 32, "fv_shade_push layout");

uint64_t fv_shade_pixels_all(const fv_shade *sh) { return (uint64_t)sh->width * sh->height * 2u; }

VkDispatchIndirectCommand fv_shade_list_dispatch(uint32_t count)
{
    uint32_t groups = (uint32_t)(((uint64_t)count + FV_SHADE_GROUP_SIZE - 1) / FV_SHADE_GROUP_SIZE);
    VkDispatchIndirectCommand c = {groups < FV_SHADE_LIST_GROUPS_X ? groups : FV_SHADE_LIST_GROUPS_X,
                                   (groups + FV_SHADE_LIST_GROUPS_X - 1) / FV_SHADE_LIST_GROUPS_X, 1};
    if (groups == 0) c.x = c.y = 0;
    return c;
}

fv_result fv_shade_init(fv_shade *sh, fv_vk *vk, const fv_gbuffer *gb, uint32_t frames_in_flight)
{
    memset(sh, 0, sizeof *sh);
    if (!vk || !gb || !frames_in_flight || frames_in_flight > FV_SHADE_MAX_SLOTS) return FV_ERR_INVALID_ARG;
    sh->vk = vk;
    sh->width = gb->width;
    sh->height = gb->height;
    sh->slots = frames_in_flight;
    fv_result res = FV_OK;
    fv_vk_image_desc cd = {.width = sh->width, .height = sh->height, .layers = 2,
                           .format = VK_FORMAT_R32G32B32A32_SFLOAT, /* full float: 16-bit storage would cost up to 1e-3 */
                           .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                    VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                           .name = "linear colour (rgba32f)"};
    res = fv_vk_image_create(vk, &cd, &sh->color);
    if (res == FV_OK) res = fv_vk_image_set_layout(vk, &sh->color, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
    if (res == FV_OK) res = fv_vk_sampler_create(vk, false, false, "shade nearest sampler", &sh->nearest);
    if (res == FV_OK)
        res = fv_vk_buffer_create(vk, FV_SHADE_LIST_HEADER_BYTES + 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                  FV_VK_MEM_UPLOAD, "shade empty pixel list", &sh->empty_list);
    if (res != FV_OK) goto fail;
    memset(sh->empty_list.mapped, 0, FV_SHADE_LIST_HEADER_BYTES + 4);
    res = fv_vk_buffer_flush(vk, &sh->empty_list);
    if (res != FV_OK) goto fail;

    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorSetLayoutBinding b[9] = {
        {FV_SHADE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, cs, NULL},
        {FV_SHADE_BINDING_LIGHTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
        {FV_SHADE_BINDING_MATERIALS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
        {FV_SHADE_BINDING_DEPTH, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_SHADE_BINDING_NORMAL, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_SHADE_BINDING_ALBEDO, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_SHADE_BINDING_MATERIAL, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_SHADE_BINDING_COLOR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        {FV_SHADE_BINDING_PIXELS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
    };
    res = fv_vk_set_layout(vk, b, 9, "shade set", &sh->set_layout);
    if (res == FV_OK)
        res = fv_vk_pipeline_layout(vk, &sh->set_layout, 1, sizeof(struct fv_shade_push), cs, "shade layout",
                                    &sh->layout);
    uint32_t mode_all = FV_SHADE_MODE_ALL, mode_list = FV_SHADE_MODE_LIST;
    if (res == FV_OK)
        res = fv_vk_compute_pipeline(vk, fv_spv_shade_comp, sizeof fv_spv_shade_comp, sh->layout, &mode_all, 1,
                                     "shade (all pixels)", &sh->pipeline_all);
    if (res == FV_OK)
        res = fv_vk_compute_pipeline(vk, fv_spv_shade_comp, sizeof fv_spv_shade_comp, sh->layout, &mode_list, 1,
                                     "shade (pixel list)", &sh->pipeline_list);
    VkDescriptorPoolSize sizes[4] = {
        {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frames_in_flight},
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3 * frames_in_flight},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4 * frames_in_flight},
        {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, frames_in_flight},
    };
    if (res == FV_OK) res = fv_vk_descriptor_pool(vk, sizes, 4, frames_in_flight, "shade pool", &sh->pool);
    for (uint32_t i = 0; res == FV_OK && i < frames_in_flight; i++) {
        char name[32];
        snprintf(name, sizeof name, "shade set %u", i);
        res = fv_vk_descriptor_set(vk, sh->pool, sh->set_layout, name, &sh->sets[i]);
        if (res != FV_OK) break;
        VkDescriptorType cis = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        fv_vk_write_image(vk, sh->sets[i], FV_SHADE_BINDING_DEPTH, cis, gb->depth.view, sh->nearest,
                          FV_GBUFFER_DEPTH_LAYOUT);
        fv_vk_write_image(vk, sh->sets[i], FV_SHADE_BINDING_NORMAL, cis, gb->normal.view, sh->nearest,
                          FV_GBUFFER_COLOR_LAYOUT);
        fv_vk_write_image(vk, sh->sets[i], FV_SHADE_BINDING_ALBEDO, cis, gb->albedo.view, sh->nearest,
                          FV_GBUFFER_COLOR_LAYOUT);
        fv_vk_write_image(vk, sh->sets[i], FV_SHADE_BINDING_MATERIAL, cis, gb->material.view, sh->nearest,
                          FV_GBUFFER_COLOR_LAYOUT);
        fv_vk_write_image(vk, sh->sets[i], FV_SHADE_BINDING_COLOR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, sh->color.view,
                          VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        fv_shade_bind_list(sh, i, VK_NULL_HANDLE, 0, 0);
    }
    if (res == FV_OK) return FV_OK;
fail:
    FV_ERROR(MOD, "shading pass could not be created: %s", fv_result_str(res));
    fv_shade_fini(sh);
    return res;
}

void fv_shade_fini(fv_shade *sh)
{
    if (!sh || !sh->vk) return;
    fv_vk *vk = sh->vk;
    if (sh->pool) vkDestroyDescriptorPool(vk->device, sh->pool, NULL);
    if (sh->pipeline_all) vkDestroyPipeline(vk->device, sh->pipeline_all, NULL);
    if (sh->pipeline_list) vkDestroyPipeline(vk->device, sh->pipeline_list, NULL);
    if (sh->layout) vkDestroyPipelineLayout(vk->device, sh->layout, NULL);
    if (sh->set_layout) vkDestroyDescriptorSetLayout(vk->device, sh->set_layout, NULL);
    if (sh->nearest) vkDestroySampler(vk->device, sh->nearest, NULL);
    fv_vk_buffer_destroy(vk, &sh->empty_list);
    fv_vk_image_destroy(vk, &sh->color);
    memset(sh, 0, sizeof *sh);
}

void fv_shade_bind_frame(fv_shade *sh, uint32_t slot, VkBuffer frame_buffer, VkDeviceSize frame_offset,
                         VkDeviceSize lights_offset, VkDeviceSize lights_range, VkBuffer materials)
{
    if (slot >= sh->slots) return;
    fv_vk_write_buffer(sh->vk, sh->sets[slot], FV_SHADE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                       frame_buffer, frame_offset, sizeof(fv_gpu_frame));
    fv_vk_write_buffer(sh->vk, sh->sets[slot], FV_SHADE_BINDING_LIGHTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                       frame_buffer, lights_offset, lights_range);
    fv_vk_write_buffer(sh->vk, sh->sets[slot], FV_SHADE_BINDING_MATERIALS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                       materials, 0, VK_WHOLE_SIZE);
}

void fv_shade_bind_list(fv_shade *sh, uint32_t slot, VkBuffer list, VkDeviceSize offset, VkDeviceSize range)
{
    if (slot >= sh->slots) return;
    if (!list) {
        list = sh->empty_list.buffer;
        offset = 0;
        range = VK_WHOLE_SIZE;
    }
    fv_vk_write_buffer(sh->vk, sh->sets[slot], FV_SHADE_BINDING_PIXELS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, list,
                       offset, range);
}

void fv_shade_record(fv_shade *sh, VkCommandBuffer cmd, const fv_shade_inputs *in)
{
    fv_vk_label_begin(sh->vk, cmd, in->mode == FV_SHADE_MODE_LIST ? "shade (pixel list)" : "shade (all pixels)");
    /* The colour image was last read by the previous frame's present pass or a readback, and written by the
     * previous shading: wait for both before writing (write-after-read and write-after-write). */
    VkImageMemoryBarrier before = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
        .oldLayout = VK_IMAGE_LAYOUT_GENERAL,
        .newLayout = VK_IMAGE_LAYOUT_GENERAL,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = sh->color.image,
        .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 2},
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, NULL, 0, NULL, 1, &before);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, sh->layout, 0, 1, &sh->sets[in->slot], 0, NULL);
    struct fv_shade_push pc;
    memset(&pc, 0, sizeof pc);
    pc.tiles_x = (sh->width + FV_SHADE_GROUP_X - 1) / FV_SHADE_GROUP_X;
    pc.tiles_y = (sh->height + FV_SHADE_GROUP_Y - 1) / FV_SHADE_GROUP_Y;
    pc.tile_count = pc.tiles_x * pc.tiles_y * 2u;
    pc.tiles_per_stripe = (pc.tile_count + FV_SHADE_STRIPES - 1) / FV_SHADE_STRIPES;
    uint32_t total = pc.tiles_per_stripe * FV_SHADE_STRIPES;
    uint32_t max_x = sh->vk->props.limits.maxComputeWorkGroupCount[0];
    pc.groups_x = total < max_x ? total : max_x;
    if (in->mode == FV_SHADE_MODE_LIST) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, sh->pipeline_list);
        vkCmdPushConstants(cmd, sh->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
        if (in->indirect) vkCmdDispatchIndirect(cmd, in->indirect, in->indirect_offset);
    } else {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, sh->pipeline_all);
        vkCmdPushConstants(cmd, sh->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, pc.groups_x, (total + pc.groups_x - 1) / pc.groups_x, 1);
    }
    VkImageMemoryBarrier after = before;
    after.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    after.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, NULL, 0, NULL, 1,
                         &after);
    fv_vk_label_end(sh->vk, cmd);
}
