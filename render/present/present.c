/* @brief The present pass (see present.h). */
#include "present.h"

#include <string.h>

#include "present_comp.spv.h"

#define MOD "present"

_Static_assert(sizeof(struct fv_present_push) == 16, "fv_present_push layout");

fv_result fv_present_init(fv_present *pr, fv_vk *vk, const fv_vk_image *linear, uint32_t tonemap)
{
    memset(pr, 0, sizeof *pr);
    if (!vk || !linear || linear->layers != 2) return FV_ERR_INVALID_ARG;
    pr->vk = vk;
    pr->linear = linear;
    pr->width = linear->width;
    pr->height = linear->height;
    pr->exposure = 1.0f;
    fv_vk_image_desc od = {.width = pr->width, .height = pr->height, .layers = 2, .format = VK_FORMAT_R8G8B8A8_UNORM,
                           .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                    VK_IMAGE_USAGE_SAMPLED_BIT,
                           .name = "present output (sRGB rgba8)"};
    fv_result res = fv_vk_image_create(vk, &od, &pr->output);
    if (res == FV_OK) res = fv_vk_image_set_layout(vk, &pr->output, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
    VkDescriptorSetLayoutBinding b[2] = {
        {FV_PRESENT_BINDING_LINEAR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {FV_PRESENT_BINDING_OUTPUT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    if (res == FV_OK) res = fv_vk_set_layout(vk, b, 2, "present set", &pr->set_layout);
    if (res == FV_OK)
        res = fv_vk_pipeline_layout(vk, &pr->set_layout, 1, sizeof(struct fv_present_push),
                                    VK_SHADER_STAGE_COMPUTE_BIT, "present layout", &pr->layout);
    if (res == FV_OK)
        res = fv_vk_compute_pipeline(vk, fv_spv_present_comp, sizeof fv_spv_present_comp, pr->layout, &tonemap, 1,
                                     "present (tonemap + sRGB)", &pr->pipeline);
    VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 2};
    if (res == FV_OK) res = fv_vk_descriptor_pool(vk, &size, 1, 1, "present pool", &pr->pool);
    if (res == FV_OK) res = fv_vk_descriptor_set(vk, pr->pool, pr->set_layout, "present set", &pr->set);
    if (res != FV_OK) {
        FV_ERROR(MOD, "present pass could not be created: %s", fv_result_str(res));
        fv_present_fini(pr);
        return res;
    }
    fv_vk_write_image(vk, pr->set, FV_PRESENT_BINDING_LINEAR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, linear->view,
                      VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    fv_vk_write_image(vk, pr->set, FV_PRESENT_BINDING_OUTPUT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, pr->output.view,
                      VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
    return FV_OK;
}

void fv_present_fini(fv_present *pr)
{
    if (!pr || !pr->vk) return;
    fv_vk *vk = pr->vk;
    if (pr->pool) vkDestroyDescriptorPool(vk->device, pr->pool, NULL);
    if (pr->pipeline) vkDestroyPipeline(vk->device, pr->pipeline, NULL);
    if (pr->layout) vkDestroyPipelineLayout(vk->device, pr->layout, NULL);
    if (pr->set_layout) vkDestroyDescriptorSetLayout(vk->device, pr->set_layout, NULL);
    fv_vk_image_destroy(vk, &pr->output);
    memset(pr, 0, sizeof *pr);
}

void fv_present_record(fv_present *pr, VkCommandBuffer cmd)
{
    fv_vk_label_begin(pr->vk, cmd, "present (tonemap + sRGB)");
    /* The output was last read by a readback (transfer) or written by the previous present: wait for both. */
    VkImageMemoryBarrier before = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
        .oldLayout = VK_IMAGE_LAYOUT_GENERAL,
        .newLayout = VK_IMAGE_LAYOUT_GENERAL,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = pr->output.image,
        .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 2},
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, NULL, 0, NULL, 1, &before);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pr->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pr->layout, 0, 1, &pr->set, 0, NULL);
    struct fv_present_push pc = {.exposure = pr->exposure, .width = pr->width, .height = pr->height};
    vkCmdPushConstants(cmd, pr->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
    vkCmdDispatch(cmd, (pr->width + FV_PRESENT_GROUP_X - 1) / FV_PRESENT_GROUP_X,
                  (pr->height + FV_PRESENT_GROUP_Y - 1) / FV_PRESENT_GROUP_Y, 2);
    VkImageMemoryBarrier after = before;
    after.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_SHADER_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, NULL, 0, NULL, 1,
                         &after);
    fv_vk_label_end(pr->vk, cmd);
}

fv_result fv_present_read_rgba8(fv_present *pr, bool sbs, int eye, uint8_t *out, size_t out_size)
{
    size_t row = (size_t)pr->width * 4;
    if (!out) return FV_ERR_INVALID_ARG;
    if (sbs) {
        if (out_size < 2 * row * pr->height) {
            FV_ERROR(MOD, "side-by-side readback needs %zu bytes, got %zu", 2 * row * pr->height, out_size);
            return FV_ERR_INVALID_ARG;
        }
        for (uint32_t e = 0; e < 2; e++)
            FV_TRY(fv_vk_read_image(pr->vk, &pr->output, e, VK_IMAGE_LAYOUT_GENERAL,
                                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, out, out_size,
                                    e * row, 2 * row));
        return FV_OK;
    }
    if (eye < 0 || eye > 1 || out_size < row * pr->height) {
        FV_ERROR(MOD, "eye readback: eye %d, %zu bytes (needs %zu)", eye, out_size, row * pr->height);
        return FV_ERR_INVALID_ARG;
    }
    return fv_vk_read_image(pr->vk, &pr->output, (uint32_t)eye, VK_IMAGE_LAYOUT_GENERAL,
                            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, out, out_size, 0, row);
}
