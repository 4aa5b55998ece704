/* @brief Synchronisation and compute-pass helpers: one image barrier, and the pipeline objects of a compute pass
 * (own set layout after the shared sets, pipeline layout, variants by specialization constants, descriptor sets). */
#include <stdio.h>
#include <string.h>

#include "fv_vk.h"

#define MOD "vk"

void fv_vk_barrier_image(VkCommandBuffer cmd, const fv_vk_image *img, fv_vk_image_use from, fv_vk_image_use to)
{
    VkImageMemoryBarrier b = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
        .srcAccessMask = from.access,
        .dstAccessMask = to.access,
        .oldLayout = from.layout,
        .newLayout = to.layout,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = img->image,
        .subresourceRange = {img->aspect, 0, 1, 0, img->layers},
    };
    /* A zero source stage mask is not allowed: "nothing before" is the top of the pipe. */
    VkPipelineStageFlags src = from.stage ? from.stage : VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT;
    VkPipelineStageFlags dst = to.stage ? to.stage : VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT;
    vkCmdPipelineBarrier(cmd, src, dst, 0, 0, NULL, 0, NULL, 1, &b);
}

fv_result fv_vk_compute_init(fv_vk *vk, const fv_vk_compute_desc *d, fv_vk_compute *c)
{
    memset(c, 0, sizeof *c);
    uint32_t variants = d && d->variant_count ? d->variant_count : 1;
    uint32_t sets = d && d->set_count ? d->set_count : 1;
    if (!vk || !d || !d->code || variants > FV_VK_COMPUTE_MAX_VARIANTS || sets > FV_VK_COMPUTE_MAX_SETS ||
        d->shared_set_count > 3 || (d->spec_count && !d->spec)) {
        FV_ERROR(MOD, "compute pass %s: bad description", d && d->name ? d->name : "?");
        return FV_ERR_INVALID_ARG;
    }
    const char *name = d->name ? d->name : "compute";
    char label[96];
    snprintf(label, sizeof label, "%s set", name);
    fv_result res = fv_vk_set_layout(vk, d->bindings, d->binding_count, label, &c->set_layout);
    VkDescriptorSetLayout layouts[4];
    for (uint32_t i = 0; i < d->shared_set_count; i++) layouts[i] = d->shared_sets[i];
    layouts[d->shared_set_count] = c->set_layout;
    c->own_set = d->shared_set_count;
    c->push_bytes = d->push_bytes;
    snprintf(label, sizeof label, "%s layout", name);
    if (res == FV_OK)
        res = fv_vk_pipeline_layout(vk, layouts, d->shared_set_count + 1, d->push_bytes, VK_SHADER_STAGE_COMPUTE_BIT,
                                    label, &c->layout);
    if (d->lazy && d->variant_count) {
        c->code = d->code, c->code_size = d->code_size, c->spec = d->spec, c->spec_count = d->spec_count;
        c->lazy_variants = variants, c->name = name;
    }
    for (uint32_t v = 0; res == FV_OK && !d->lazy && v < variants; v++) {
        snprintf(label, sizeof label, variants > 1 ? "%s (variant %u)" : "%s", name, v);
        res = fv_vk_compute_pipeline(vk, d->code, d->code_size, c->layout, d->spec ? d->spec + v * d->spec_count : NULL,
                                     d->spec_count, label, &c->pipelines[v]);
        if (res == FV_OK) c->variant_count = v + 1;
    }
    /* Pool: every binding's descriptors, once per set. */
    VkDescriptorPoolSize sizes[16];
    uint32_t size_count = 0;
    for (uint32_t b = 0; b < d->binding_count; b++) {
        uint32_t k = 0;
        while (k < size_count && sizes[k].type != d->bindings[b].descriptorType) k++;
        if (k == size_count) {
            if (size_count == 16) {
                res = FV_ERR_INVALID_ARG;
                break;
            }
            sizes[size_count++] = (VkDescriptorPoolSize){d->bindings[b].descriptorType, 0};
        }
        sizes[k].descriptorCount += d->bindings[b].descriptorCount * sets;
    }
    snprintf(label, sizeof label, "%s pool", name);
    if (res == FV_OK && size_count) res = fv_vk_descriptor_pool(vk, sizes, size_count, sets, label, &c->pool);
    for (uint32_t i = 0; res == FV_OK && c->pool && i < sets; i++) {
        snprintf(label, sizeof label, "%s set %u", name, i);
        res = fv_vk_descriptor_set(vk, c->pool, c->set_layout, label, &c->sets[i]);
        if (res == FV_OK) c->set_count = i + 1;
    }
    if (res != FV_OK) {
        FV_ERROR(MOD, "compute pass %s could not be created: %s", name, fv_result_str(res));
        fv_vk_compute_fini(vk, c);
    }
    return res;
}

void fv_vk_compute_fini(fv_vk *vk, fv_vk_compute *c)
{
    if (!vk || !c) return;
    if (c->pool) vkDestroyDescriptorPool(vk->device, c->pool, NULL);
    for (uint32_t v = 0; v < FV_VK_COMPUTE_MAX_VARIANTS; v++)
        if (c->pipelines[v]) vkDestroyPipeline(vk->device, c->pipelines[v], NULL);
    if (c->layout) vkDestroyPipelineLayout(vk->device, c->layout, NULL);
    if (c->set_layout) vkDestroyDescriptorSetLayout(vk->device, c->set_layout, NULL);
    memset(c, 0, sizeof *c);
}

VkPipeline fv_vk_compute_lazy(fv_vk *vk, fv_vk_compute *c, uint32_t variant)
{
    if (!vk || !c || variant >= c->lazy_variants) return VK_NULL_HANDLE;
    if (!c->pipelines[variant] && !(c->lazy_failed & (1u << variant))) {
        char label[96];
        snprintf(label, sizeof label, "%s (variant %u)", c->name, variant);
        if (fv_vk_compute_pipeline(vk, c->code, c->code_size, c->layout, c->spec ? c->spec + variant * c->spec_count : NULL,
                                   c->spec_count, label, &c->pipelines[variant]) != FV_OK) {
            FV_ERROR(MOD, "%s: the pipeline could not be made; the pass skips the frames that need it", label);
            c->lazy_failed |= 1u << variant;
            c->pipelines[variant] = VK_NULL_HANDLE;
        }
    }
    return c->pipelines[variant];
}

void fv_vk_compute_bind(const fv_vk_compute *c, VkCommandBuffer cmd, uint32_t variant, const VkDescriptorSet *shared,
                        uint32_t shared_count, uint32_t set_index, const void *push)
{
    if (variant >= c->variant_count) variant = 0;
    fv_vk_compute_bind_pipeline(c, cmd, c->pipelines[variant], shared, shared_count, set_index, push);
}

void fv_vk_compute_bind_pipeline(const fv_vk_compute *c, VkCommandBuffer cmd, VkPipeline pipeline,
                                 const VkDescriptorSet *shared, uint32_t shared_count, uint32_t set_index,
                                 const void *push)
{
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    VkDescriptorSet sets[4];
    uint32_t n = 0;
    for (uint32_t i = 0; i < shared_count && i < c->own_set; i++) sets[n++] = shared[i];
    if (set_index < c->set_count) sets[n++] = c->sets[set_index];
    if (n) vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, c->layout, 0, n, sets, 0, NULL);
    if (push && c->push_bytes) vkCmdPushConstants(cmd, c->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, c->push_bytes, push);
}

void fv_vk_barrier_memory(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags src_access,
                          VkPipelineStageFlags dst, VkAccessFlags dst_access)
{
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = src_access,
                          .dstAccessMask = dst_access};
    vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &mb, 0, NULL, 0, NULL);
}
