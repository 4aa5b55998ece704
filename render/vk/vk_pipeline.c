/* @brief Vulkan pipelines and descriptors: shader modules from embedded SPIR-V, set and pipeline layouts, compute
 * and graphics pipelines, descriptor pools, sets and writes. */
#include <string.h>

#include "fv_vk.h"

#define MOD "vk"

fv_result fv_vk_shader_module(fv_vk *vk, const uint32_t *code, size_t size_bytes, const char *name,
                              VkShaderModule *out)
{
    if (!code || size_bytes < 20 || size_bytes % 4 || code[0] != 0x07230203u) {
        FV_ERROR(MOD, "%s: not SPIR-V (%zu bytes)", name, size_bytes);
        return FV_ERR_INVALID_ARG;
    }
    VkShaderModuleCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO, .codeSize = size_bytes,
                                   .pCode = code};
    FV_VK_CHECK(vkCreateShaderModule(vk->device, &ci, NULL, out));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_SHADER_MODULE, *out, "%s", name);
    return FV_OK;
}

fv_result fv_vk_set_layout(fv_vk *vk, const VkDescriptorSetLayoutBinding *bindings, uint32_t count, const char *name,
                           VkDescriptorSetLayout *out)
{
    VkDescriptorSetLayoutCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
                                          .bindingCount = count, .pBindings = bindings};
    FV_VK_CHECK(vkCreateDescriptorSetLayout(vk->device, &ci, NULL, out));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, *out, "%s", name);
    return FV_OK;
}

fv_result fv_vk_pipeline_layout(fv_vk *vk, const VkDescriptorSetLayout *sets, uint32_t set_count, uint32_t push_bytes,
                                VkShaderStageFlags push_stages, const char *name, VkPipelineLayout *out)
{
    VkPushConstantRange pr = {.stageFlags = push_stages, .offset = 0, .size = push_bytes};
    VkPipelineLayoutCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = set_count,
        .pSetLayouts = sets,
        .pushConstantRangeCount = push_bytes ? 1 : 0,
        .pPushConstantRanges = push_bytes ? &pr : NULL,
    };
    FV_VK_CHECK(vkCreatePipelineLayout(vk->device, &ci, NULL, out));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_PIPELINE_LAYOUT, *out, "%s", name);
    return FV_OK;
}

fv_result fv_vk_compute_pipeline(fv_vk *vk, const uint32_t *code, size_t size_bytes, VkPipelineLayout layout,
                                 const uint32_t *spec, uint32_t spec_count, const char *name, VkPipeline *out)
{
    VkShaderModule mod;
    FV_TRY(fv_vk_shader_module(vk, code, size_bytes, name, &mod));
    VkSpecializationMapEntry entries[16];
    if (spec_count > 16) spec_count = 16;
    for (uint32_t i = 0; i < spec_count; i++)
        entries[i] = (VkSpecializationMapEntry){.constantID = i, .offset = i * 4, .size = 4};
    VkSpecializationInfo si = {.mapEntryCount = spec_count, .pMapEntries = entries, .dataSize = spec_count * 4u,
                               .pData = spec};
    VkComputePipelineCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
        .stage = {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                  .stage = VK_SHADER_STAGE_COMPUTE_BIT,
                  .module = mod,
                  .pName = "main",
                  .pSpecializationInfo = spec_count ? &si : NULL},
        .layout = layout,
    };
    VkResult r = vkCreateComputePipelines(vk->device, vk->pipeline_cache, 1, &ci, NULL, out);
    vk->pipelines_created++;
    vkDestroyShaderModule(vk->device, mod, NULL);
    if (r < 0) return fv_vk_fail(r, "vkCreateComputePipelines", __FILE__, __LINE__);
    FV_VK_NAME(vk, VK_OBJECT_TYPE_PIPELINE, *out, "%s", name);
    return FV_OK;
}

fv_result fv_vk_graphics_pipeline(fv_vk *vk, const fv_vk_graphics_desc *d, VkPipeline *out)
{
    VkShaderModule vs = VK_NULL_HANDLE, fs = VK_NULL_HANDLE;
    fv_result res = fv_vk_shader_module(vk, d->vert, d->vert_size, d->name, &vs);
    if (res == FV_OK) res = fv_vk_shader_module(vk, d->frag, d->frag_size, d->name, &fs);
    if (res != FV_OK) {
        if (vs) vkDestroyShaderModule(vk->device, vs, NULL);
        return res;
    }
    VkSpecializationMapEntry entries[16];
    uint32_t spec_count = d->spec && d->spec_count <= 16 ? d->spec_count : 0;
    for (uint32_t i = 0; i < spec_count; i++)
        entries[i] = (VkSpecializationMapEntry){.constantID = i, .offset = i * 4, .size = 4};
    VkSpecializationInfo si = {.mapEntryCount = spec_count, .pMapEntries = entries, .dataSize = spec_count * 4u,
                               .pData = d->spec};
    VkPipelineShaderStageCreateInfo stages[2] = {
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, .stage = VK_SHADER_STAGE_VERTEX_BIT,
         .module = vs, .pName = "main", .pSpecializationInfo = spec_count ? &si : NULL},
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, .stage = VK_SHADER_STAGE_FRAGMENT_BIT,
         .module = fs, .pName = "main", .pSpecializationInfo = spec_count ? &si : NULL},
    };
    VkPipelineVertexInputStateCreateInfo vi = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO,
        .vertexBindingDescriptionCount = d->binding_count,
        .pVertexBindingDescriptions = d->bindings,
        .vertexAttributeDescriptionCount = d->attribute_count,
        .pVertexAttributeDescriptions = d->attributes,
    };
    VkPipelineInputAssemblyStateCreateInfo ia = {.sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
                                                 .topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST};
    VkPipelineViewportStateCreateInfo vp = {.sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
                                            .viewportCount = 1, .scissorCount = 1};
    VkPipelineRasterizationStateCreateInfo rs = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
        .polygonMode = VK_POLYGON_MODE_FILL,
        .cullMode = d->cull,
        .frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE,
        .depthBiasEnable = d->depth_bias,
        .lineWidth = 1.0f,
    };
    VkPipelineMultisampleStateCreateInfo ms = {.sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
                                               .rasterizationSamples = VK_SAMPLE_COUNT_1_BIT};
    VkPipelineDepthStencilStateCreateInfo ds = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO,
        .depthTestEnable = d->depth_test,
        .depthWriteEnable = d->depth_test,
        .depthCompareOp = VK_COMPARE_OP_LESS,
    };
    VkPipelineColorBlendAttachmentState blend[8];
    uint32_t nc = d->color_attachments > 8 ? 8 : d->color_attachments;
    for (uint32_t i = 0; i < nc; i++)
        blend[i] = (VkPipelineColorBlendAttachmentState){.colorWriteMask = 0xf};
    VkPipelineColorBlendStateCreateInfo cb = {.sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
                                              .attachmentCount = nc, .pAttachments = blend};
    VkDynamicState dyn[3] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR, VK_DYNAMIC_STATE_DEPTH_BIAS};
    VkPipelineDynamicStateCreateInfo dy = {.sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO,
                                           .dynamicStateCount = d->depth_bias ? 3u : 2u, .pDynamicStates = dyn};
    VkGraphicsPipelineCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO,
        .stageCount = 2,
        .pStages = stages,
        .pVertexInputState = &vi,
        .pInputAssemblyState = &ia,
        .pViewportState = &vp,
        .pRasterizationState = &rs,
        .pMultisampleState = &ms,
        .pDepthStencilState = &ds,
        .pColorBlendState = &cb,
        .pDynamicState = &dy,
        .layout = d->layout,
        .renderPass = d->render_pass,
        .subpass = 0,
    };
    VkResult r = vkCreateGraphicsPipelines(vk->device, vk->pipeline_cache, 1, &ci, NULL, out);
    vk->pipelines_created++;
    vkDestroyShaderModule(vk->device, vs, NULL);
    vkDestroyShaderModule(vk->device, fs, NULL);
    if (r < 0) return fv_vk_fail(r, "vkCreateGraphicsPipelines", __FILE__, __LINE__);
    FV_VK_NAME(vk, VK_OBJECT_TYPE_PIPELINE, *out, "%s", d->name);
    return FV_OK;
}

VkAttachmentDescription fv_vk_attachment_cleared(VkFormat format, VkImageLayout final_layout)
{
    return (VkAttachmentDescription){
        .format = format,
        .samples = VK_SAMPLE_COUNT_1_BIT,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
        .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
        .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
        .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
        .finalLayout = final_layout,
    };
}

fv_result fv_vk_descriptor_pool(fv_vk *vk, const VkDescriptorPoolSize *sizes, uint32_t size_count, uint32_t max_sets,
                                const char *name, VkDescriptorPool *out)
{
    VkDescriptorPoolCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO, .maxSets = max_sets,
                                     .poolSizeCount = size_count, .pPoolSizes = sizes};
    FV_VK_CHECK(vkCreateDescriptorPool(vk->device, &ci, NULL, out));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_DESCRIPTOR_POOL, *out, "%s", name);
    return FV_OK;
}

fv_result fv_vk_descriptor_set(fv_vk *vk, VkDescriptorPool pool, VkDescriptorSetLayout layout, const char *name,
                               VkDescriptorSet *out)
{
    VkDescriptorSetAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO, .descriptorPool = pool,
                                      .descriptorSetCount = 1, .pSetLayouts = &layout};
    FV_VK_CHECK(vkAllocateDescriptorSets(vk->device, &ai, out));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_DESCRIPTOR_SET, *out, "%s", name);
    return FV_OK;
}

void fv_vk_write_buffer(fv_vk *vk, VkDescriptorSet set, uint32_t binding, VkDescriptorType type, VkBuffer buffer,
                        VkDeviceSize offset, VkDeviceSize range)
{
    VkDescriptorBufferInfo bi = {.buffer = buffer, .offset = offset, .range = range};
    VkWriteDescriptorSet w = {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstSet = set, .dstBinding = binding,
                              .descriptorCount = 1, .descriptorType = type, .pBufferInfo = &bi};
    vkUpdateDescriptorSets(vk->device, 1, &w, 0, NULL);
}

void fv_vk_write_image(fv_vk *vk, VkDescriptorSet set, uint32_t binding, VkDescriptorType type, VkImageView view,
                       VkSampler sampler, VkImageLayout layout)
{
    VkDescriptorImageInfo ii = {.sampler = sampler, .imageView = view, .imageLayout = layout};
    VkWriteDescriptorSet w = {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstSet = set, .dstBinding = binding,
                              .descriptorCount = 1, .descriptorType = type, .pImageInfo = &ii};
    vkUpdateDescriptorSets(vk->device, 1, &w, 0, NULL);
}
