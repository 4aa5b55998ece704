/* @brief The stereo G-buffer pass (multiview) and the scene's GPU copy (see gbuffer.h). */
#include "gbuffer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gbuffer_frag.spv.h"
#include "gbuffer_interface.h"
#include "gbuffer_vert.spv.h"

#define MOD "gbuffer"

typedef struct vertex {
    float position[3];
    float normal[3];
    float texcoord[2];
} vertex;
_Static_assert(sizeof(vertex) == 32, "vertex layout");

static fv_result create_images(fv_gbuffer *gb)
{
    fv_vk *vk = gb->vk;
    VkImageUsageFlags color = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                              VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    /* Octahedral normals: 16-bit snorm keeps ~3e-5 per component (half floats would give ~5e-4 near +-1). */
    VkFormat normal_format = VK_FORMAT_R16G16_SNORM;
    if (!fv_vk_format_supports(vk, normal_format,
                               VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT))
        normal_format = VK_FORMAT_R32G32_SFLOAT;
    struct {
        fv_vk_image *img;
        VkFormat format;
        VkImageUsageFlags usage;
        const char *name;
    } list[] = {
        {&gb->depth, VK_FORMAT_D32_SFLOAT,
         VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
         "gbuffer depth"},
        {&gb->normal, normal_format, color, "gbuffer normal (oct)"},
        {&gb->albedo, VK_FORMAT_R8G8B8A8_SRGB, color, "gbuffer albedo"},
        {&gb->material, VK_FORMAT_R16_UINT, color, "gbuffer material id"},
        {&gb->motion, VK_FORMAT_R16G16_SFLOAT, color, "gbuffer motion"},
    };
    for (size_t i = 0; i < sizeof list / sizeof list[0]; i++) {
        fv_vk_image_desc d = {.width = gb->width, .height = gb->height, .layers = 2, .format = list[i].format,
                              .usage = list[i].usage, .name = list[i].name};
        FV_TRY(fv_vk_image_create(vk, &d, list[i].img));
    }
    return FV_OK;
}

static fv_result create_render_pass(fv_gbuffer *gb)
{
    fv_vk *vk = gb->vk;
    VkAttachmentDescription att[5];
    const fv_vk_image *imgs[5] = {&gb->depth, &gb->normal, &gb->albedo, &gb->material, &gb->motion};
    for (int i = 0; i < 5; i++) {
        att[i] = (VkAttachmentDescription){
            .format = imgs[i]->format,
            .samples = VK_SAMPLE_COUNT_1_BIT,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
            .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
            .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
            .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
            .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
            .finalLayout = i == 0 ? FV_GBUFFER_DEPTH_LAYOUT : FV_GBUFFER_COLOR_LAYOUT,
        };
    }
    VkAttachmentReference depth_ref = {0, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkAttachmentReference color_refs[4];
    for (uint32_t i = 0; i < 4; i++) color_refs[i] = (VkAttachmentReference){i + 1, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub = {
        .pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS,
        .colorAttachmentCount = 4,
        .pColorAttachments = color_refs,
        .pDepthStencilAttachment = &depth_ref,
    };
    VkPipelineStageFlags attach_stages = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                         VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                         VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    VkSubpassDependency deps[2] = {
        /* Write-after-read: the previous frame's shading (compute) and any readback (transfer) must be done
         * reading these images before this frame clears them. Execution dependency only; the layout transition
         * from UNDEFINED discards the old contents. */
        {.srcSubpass = VK_SUBPASS_EXTERNAL,
         .dstSubpass = 0,
         .srcStageMask = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                         VK_PIPELINE_STAGE_TRANSFER_BIT,
         .dstStageMask = attach_stages,
         .srcAccessMask = 0,
         .dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                          VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT},
        /* Read-after-write: shading passes (compute, or fragment) read the G-buffer; transfers may read it back. */
        {.srcSubpass = 0,
         .dstSubpass = VK_SUBPASS_EXTERNAL,
         .srcStageMask = attach_stages,
         .dstStageMask = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                         VK_PIPELINE_STAGE_TRANSFER_BIT,
         .srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
         .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT},
    };
    uint32_t view_mask = 0x3u, correlation = 0x3u; /* both eyes in one pass; the views are spatially correlated */
    VkRenderPassMultiviewCreateInfo mv = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_MULTIVIEW_CREATE_INFO,
        .subpassCount = 1,
        .pViewMasks = &view_mask,
        .correlationMaskCount = 1,
        .pCorrelationMasks = &correlation,
    };
    VkRenderPassCreateInfo ci = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO,
        .pNext = gb->multiview ? &mv : NULL,
        .attachmentCount = 5,
        .pAttachments = att,
        .subpassCount = 1,
        .pSubpasses = &sub,
        .dependencyCount = 2,
        .pDependencies = deps,
    };
    FV_VK_CHECK(vkCreateRenderPass(vk->device, &ci, NULL, &gb->render_pass));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_RENDER_PASS, gb->render_pass, "gbuffer render pass (%s)",
               gb->multiview ? "multiview 0b11" : "one eye");
    fv_vk_image *imgs_all[5] = {&gb->depth, &gb->normal, &gb->albedo, &gb->material, &gb->motion};
    VkFramebufferCreateInfo fi = {
        .sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
        .renderPass = gb->render_pass,
        .attachmentCount = 5,
        .width = gb->width,
        .height = gb->height,
        .layers = 1, /* multiview: the view mask selects the layers; per eye: one layer */
    };
    if (gb->multiview) {
        VkImageView views[5] = {gb->depth.view, gb->normal.view, gb->albedo.view, gb->material.view, gb->motion.view};
        fi.pAttachments = views;
        FV_VK_CHECK(vkCreateFramebuffer(vk->device, &fi, NULL, &gb->framebuffer));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_FRAMEBUFFER, gb->framebuffer, "gbuffer framebuffer (both eyes)");
        return FV_OK;
    }
    for (uint32_t e = 0; e < 2; e++) {
        for (int i = 0; i < 5; i++) {
            VkImageViewCreateInfo vi = {
                .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
                .image = imgs_all[i]->image,
                .viewType = VK_IMAGE_VIEW_TYPE_2D,
                .format = imgs_all[i]->format,
                .subresourceRange = {imgs_all[i]->aspect, 0, 1, e, 1},
            };
            FV_VK_CHECK(vkCreateImageView(vk->device, &vi, NULL, &gb->eye_views[e][i]));
            FV_VK_NAME(vk, VK_OBJECT_TYPE_IMAGE_VIEW, gb->eye_views[e][i], "gbuffer attachment %d eye %u", i, e);
        }
        fi.pAttachments = gb->eye_views[e];
        FV_VK_CHECK(vkCreateFramebuffer(vk->device, &fi, NULL, &gb->eye_framebuffer[e]));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_FRAMEBUFFER, gb->eye_framebuffer[e], "gbuffer framebuffer (eye %u)", e);
    }
    return FV_OK;
}

static fv_result create_pipeline(fv_gbuffer *gb)
{
    fv_vk *vk = gb->vk;
    VkDescriptorSetLayoutBinding frame_b[3] = {
        {FV_GBUFFER_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1,
         VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {FV_GBUFFER_BINDING_DRAWS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
         VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {FV_GBUFFER_BINDING_MATERIALS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
    };
    FV_TRY(fv_vk_set_layout(vk, frame_b, 3, "gbuffer set 0 (frame)", &gb->frame_layout));
    VkDescriptorSetLayoutBinding tex_b = {FV_GBUFFER_BINDING_BASE_COLOR, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1,
                                          VK_SHADER_STAGE_FRAGMENT_BIT, NULL};
    FV_TRY(fv_vk_set_layout(vk, &tex_b, 1, "gbuffer set 1 (texture)", &gb->texture_layout));
    VkDescriptorSetLayout sets[2] = {gb->frame_layout, gb->texture_layout};
    FV_TRY(fv_vk_pipeline_layout(vk, sets, 2, 2 * sizeof(uint32_t),
                                 VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, "gbuffer layout",
                                 &gb->layout));
    VkVertexInputBindingDescription bind = {0, sizeof(vertex), VK_VERTEX_INPUT_RATE_VERTEX};
    VkVertexInputAttributeDescription attrs[3] = {
        {FV_GBUFFER_ATTR_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(vertex, position)},
        {FV_GBUFFER_ATTR_NORMAL, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(vertex, normal)},
        {FV_GBUFFER_ATTR_TEXCOORD, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(vertex, texcoord)},
    };
    uint32_t use_multiview = gb->multiview ? 1u : 0u;
    fv_vk_graphics_desc gd = {
        .vert = fv_spv_gbuffer_vert,
        .vert_size = sizeof fv_spv_gbuffer_vert,
        .frag = fv_spv_gbuffer_frag,
        .frag_size = sizeof fv_spv_gbuffer_frag,
        .bindings = &bind,
        .binding_count = 1,
        .attributes = attrs,
        .attribute_count = 3,
        .layout = gb->layout,
        .render_pass = gb->render_pass,
        .color_attachments = 4,
        .depth_test = true,
        .cull = VK_CULL_MODE_NONE, /* file winding is not trusted; the fragment shader faces normals to the eye */
        .spec = &use_multiview,
        .spec_count = 1,
        .name = gb->multiview ? "gbuffer pipeline (multiview)" : "gbuffer pipeline (per eye)",
    };
    FV_TRY(fv_vk_graphics_pipeline(vk, &gd, &gb->pipeline));
    FV_TRY(fv_vk_sampler_create(vk, true, true, "gbuffer base colour sampler", &gb->texture_sampler));
    VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, gb->slots},
                                     {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2 * gb->slots}};
    FV_TRY(fv_vk_descriptor_pool(vk, sizes, 2, gb->slots, "gbuffer frame pool", &gb->frame_pool));
    for (uint32_t i = 0; i < gb->slots; i++) {
        char name[48];
        snprintf(name, sizeof name, "gbuffer frame set %u", i);
        FV_TRY(fv_vk_descriptor_set(vk, gb->frame_pool, gb->frame_layout, name, &gb->frame_sets[i]));
    }
    return FV_OK;
}

fv_result fv_gbuffer_init(fv_gbuffer *gb, fv_vk *vk, const fv_gbuffer_desc *desc)
{
    memset(gb, 0, sizeof *gb);
    if (!vk || !desc || !desc->width || !desc->height || !desc->frames_in_flight ||
        desc->frames_in_flight > FV_GBUFFER_MAX_SLOTS)
        return FV_ERR_INVALID_ARG;
    gb->vk = vk;
    gb->width = desc->width;
    gb->height = desc->height;
    gb->slots = desc->frames_in_flight;
    gb->multiview = desc->multiview;
    fv_result res = create_images(gb);
    if (res == FV_OK) res = create_render_pass(gb);
    if (res == FV_OK) res = create_pipeline(gb);
    if (res == FV_OK) {
        fv_vk_image_desc wd = {.width = 1, .height = 1, .layers = 1, .format = VK_FORMAT_R8G8B8A8_SRGB,
                               .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                               .name = "white texture"};
        res = fv_vk_image_create(vk, &wd, &gb->white);
        const uint8_t white[4] = {255, 255, 255, 255};
        if (res == FV_OK) res = fv_vk_upload_image(vk, &gb->white, 0, white, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
    if (res != FV_OK) {
        FV_ERROR(MOD, "G-buffer %ux%u x2 could not be created: %s", desc->width, desc->height, fv_result_str(res));
        fv_gbuffer_fini(gb);
    }
    return res;
}

static void release_scene(fv_gbuffer *gb)
{
    fv_vk *vk = gb->vk;
    fv_vk_buffer_destroy(vk, &gb->vertices);
    fv_vk_buffer_destroy(vk, &gb->indices);
    fv_vk_buffer_destroy(vk, &gb->materials);
    for (uint32_t i = 0; i < gb->texture_count; i++) fv_vk_image_destroy(vk, &gb->textures[i]);
    free(gb->textures);
    gb->textures = NULL;
    gb->texture_count = 0;
    if (gb->texture_pool) vkDestroyDescriptorPool(vk->device, gb->texture_pool, NULL);
    gb->texture_pool = VK_NULL_HANDLE;
    free(gb->texture_sets);
    gb->texture_sets = NULL;
    free(gb->meshes);
    gb->meshes = NULL;
    gb->mesh_count = 0;
    gb->material_count = 0;
}

void fv_gbuffer_fini(fv_gbuffer *gb)
{
    if (!gb || !gb->vk) return;
    fv_vk *vk = gb->vk;
    release_scene(gb);
    fv_vk_image_destroy(vk, &gb->white);
    if (gb->frame_pool) vkDestroyDescriptorPool(vk->device, gb->frame_pool, NULL);
    if (gb->texture_sampler) vkDestroySampler(vk->device, gb->texture_sampler, NULL);
    if (gb->pipeline) vkDestroyPipeline(vk->device, gb->pipeline, NULL);
    if (gb->layout) vkDestroyPipelineLayout(vk->device, gb->layout, NULL);
    if (gb->frame_layout) vkDestroyDescriptorSetLayout(vk->device, gb->frame_layout, NULL);
    if (gb->texture_layout) vkDestroyDescriptorSetLayout(vk->device, gb->texture_layout, NULL);
    if (gb->framebuffer) vkDestroyFramebuffer(vk->device, gb->framebuffer, NULL);
    for (int e = 0; e < 2; e++) {
        if (gb->eye_framebuffer[e]) vkDestroyFramebuffer(vk->device, gb->eye_framebuffer[e], NULL);
        for (int i = 0; i < 5; i++)
            if (gb->eye_views[e][i]) vkDestroyImageView(vk->device, gb->eye_views[e][i], NULL);
    }
    if (gb->render_pass) vkDestroyRenderPass(vk->device, gb->render_pass, NULL);
    fv_vk_image_destroy(vk, &gb->depth);
    fv_vk_image_destroy(vk, &gb->normal);
    fv_vk_image_destroy(vk, &gb->albedo);
    fv_vk_image_destroy(vk, &gb->material);
    fv_vk_image_destroy(vk, &gb->motion);
    memset(gb, 0, sizeof *gb);
}

static float finite_or(float v, float fallback) { return isfinite(v) ? v : fallback; }

static fv_result upload_meshes(fv_gbuffer *gb, const fv_scene *s)
{
    uint64_t total_v = 0, total_i = 0;
    for (uint32_t m = 0; m < s->mesh_count; m++) {
        const fv_mesh *mesh = &s->meshes[m];
        total_v += mesh->vertex_count;
        total_i += mesh->index_count;
    }
    if (total_v > INT32_MAX || total_i > UINT32_MAX / 2) {
        FV_ERROR(MOD, "%s: %llu vertices / %llu indices exceed what one draw buffer holds", s->source,
                 (unsigned long long)total_v, (unsigned long long)total_i);
        return FV_ERR_RANGE;
    }
    gb->meshes = calloc(s->mesh_count ? s->mesh_count : 1, sizeof *gb->meshes);
    vertex *verts = malloc((total_v ? total_v : 1) * sizeof *verts);
    uint32_t *idx = malloc((total_i ? total_i : 1) * sizeof *idx);
    fv_result res = FV_OK;
    if (!gb->meshes || !verts || !idx) {
        res = FV_ERR_NO_MEMORY;
        goto done;
    }
    gb->mesh_count = s->mesh_count;
    uint32_t vbase = 0, ibase = 0;
    for (uint32_t m = 0; m < s->mesh_count; m++) {
        const fv_mesh *mesh = &s->meshes[m];
        for (uint32_t v = 0; v < mesh->vertex_count; v++) {
            vertex *o = &verts[vbase + v];
            fv_vec3 p = mesh->positions ? mesh->positions[v] : fv_v3(0, 0, 0);
            fv_vec3 n = mesh->normals ? mesh->normals[v] : fv_v3(0, 1, 0);
            fv_vec2 t = mesh->texcoords ? mesh->texcoords[v] : (fv_vec2){0, 0};
            o->position[0] = p.x, o->position[1] = p.y, o->position[2] = p.z;
            o->normal[0] = finite_or(n.x, 0), o->normal[1] = finite_or(n.y, 1), o->normal[2] = finite_or(n.z, 0);
            o->texcoord[0] = finite_or(t.x, 0), o->texcoord[1] = finite_or(t.y, 0);
        }
        uint32_t count = mesh->index_count - mesh->index_count % 3;
        for (uint32_t i = 0; i < count; i++) {
            if (mesh->indices[i] >= mesh->vertex_count) {
                FV_ERROR(MOD, "%s: mesh %u '%s': index %u is %u, past its %u vertices", s->source, m, mesh->name, i,
                         mesh->indices[i], mesh->vertex_count);
                res = FV_ERR_PARSE;
                goto done;
            }
            idx[ibase + i] = mesh->indices[i];
        }
        gb->meshes[m] = (fv_gbuffer_mesh){.first_index = ibase, .index_count = count, .vertex_offset = (int32_t)vbase};
        vbase += mesh->vertex_count;
        ibase += count;
    }
    res = fv_vk_buffer_create(gb->vk, (total_v ? total_v : 1) * sizeof(vertex),
                              VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, FV_VK_MEM_DEVICE,
                              "scene vertices", &gb->vertices);
    if (res == FV_OK)
        res = fv_vk_buffer_create(gb->vk, (ibase ? ibase : 1) * sizeof(uint32_t),
                                  VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                  FV_VK_MEM_DEVICE, "scene indices", &gb->indices);
    if (res == FV_OK) res = fv_vk_upload_buffer(gb->vk, &gb->vertices, 0, verts, total_v * sizeof(vertex));
    if (res == FV_OK) res = fv_vk_upload_buffer(gb->vk, &gb->indices, 0, idx, (VkDeviceSize)ibase * sizeof(uint32_t));
done:
    free(verts);
    free(idx);
    return res;
}

static fv_result upload_materials(fv_gbuffer *gb, const fv_scene *s)
{
    uint32_t n = s->material_count ? s->material_count : 1;
    fv_gpu_material *mats = calloc(n, sizeof *mats);
    if (!mats) return FV_ERR_NO_MEMORY;
    for (uint32_t i = 0; i < n; i++) {
        fv_material m = i < s->material_count ? s->materials[i] : fv_material_default();
        mats[i].base_color = (fv_gpu_vec4){fv_clampf(finite_or(m.base_color.x, 1), 0, 1),
                                           fv_clampf(finite_or(m.base_color.y, 1), 0, 1),
                                           fv_clampf(finite_or(m.base_color.z, 1), 0, 1), 1.0f};
        mats[i].emissive = (fv_gpu_vec4){fmaxf(finite_or(m.emissive.x, 0), 0), fmaxf(finite_or(m.emissive.y, 0), 0),
                                         fmaxf(finite_or(m.emissive.z, 0), 0), 0.0f};
        bool tex_ok = m.base_color_texture >= 0 && (uint32_t)m.base_color_texture < s->texture_count;
        mats[i].info = (fv_gpu_uvec4){tex_ok ? (uint32_t)m.base_color_texture : 0xffffffffu,
                                      m.translucency.enabled ? 1u : 0u, 0, 0};
    }
    gb->material_count = n;
    fv_result res = fv_vk_buffer_create(gb->vk, n * sizeof *mats,
                                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                        FV_VK_MEM_DEVICE, "scene materials", &gb->materials);
    if (res == FV_OK) res = fv_vk_upload_buffer(gb->vk, &gb->materials, 0, mats, n * sizeof *mats);
    free(mats);
    return res;
}

static fv_result upload_textures(fv_gbuffer *gb, const fv_scene *s)
{
    fv_vk *vk = gb->vk;
    gb->textures = calloc(s->texture_count ? s->texture_count : 1, sizeof *gb->textures);
    gb->texture_sets = calloc(s->texture_count + 1, sizeof *gb->texture_sets);
    if (!gb->textures || !gb->texture_sets) return FV_ERR_NO_MEMORY;
    VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, s->texture_count + 1};
    FV_TRY(fv_vk_descriptor_pool(vk, &size, 1, s->texture_count + 1, "gbuffer texture pool", &gb->texture_pool));
    for (uint32_t t = 0; t <= s->texture_count; t++) {
        VkImageView view = gb->white.view;
        if (t < s->texture_count) {
            const fv_texture *tex = &s->textures[t];
            gb->texture_count = t + 1;
            if (tex->rgba8 && tex->width && tex->height && tex->width <= FV_SCENE_MAX_TEXTURE_DIM &&
                tex->height <= FV_SCENE_MAX_TEXTURE_DIM) {
                char name[96];
                snprintf(name, sizeof name, "texture %u (%.60s)", t, tex->source);
                fv_vk_image_desc d = {.width = tex->width, .height = tex->height, .layers = 1,
                                      .format = VK_FORMAT_R8G8B8A8_SRGB,
                                      .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                      .name = name};
                FV_TRY(fv_vk_image_create(vk, &d, &gb->textures[t]));
                FV_TRY(fv_vk_upload_image(vk, &gb->textures[t], 0, tex->rgba8, (size_t)tex->width * tex->height * 4,
                                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
                view = gb->textures[t].view;
            } else {
                FV_WARN(MOD, "%s: texture %u (%s) has no pixels; using the base colour alone", s->source, t,
                        tex->source);
            }
        }
        char name[48];
        snprintf(name, sizeof name, t < s->texture_count ? "texture set %u" : "white texture set", t);
        FV_TRY(fv_vk_descriptor_set(vk, gb->texture_pool, gb->texture_layout, name, &gb->texture_sets[t]));
        fv_vk_write_image(vk, gb->texture_sets[t], FV_GBUFFER_BINDING_BASE_COLOR,
                          VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, view, gb->texture_sampler,
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
    return FV_OK;
}

fv_result fv_gbuffer_load_scene(fv_gbuffer *gb, const fv_scene *scene)
{
    if (!gb || !gb->vk || !scene) return FV_ERR_INVALID_ARG;
    release_scene(gb);
    fv_result res = upload_meshes(gb, scene);
    if (res == FV_OK) res = upload_materials(gb, scene);
    if (res == FV_OK) res = upload_textures(gb, scene);
    if (res != FV_OK) {
        FV_ERROR(MOD, "%s: uploading the scene failed: %s", scene->source, fv_result_str(res));
        release_scene(gb);
    }
    return res;
}

void fv_gbuffer_bind_frame(fv_gbuffer *gb, uint32_t slot, VkBuffer buffer, VkDeviceSize frame_offset,
                           VkDeviceSize draws_offset, VkDeviceSize draws_range)
{
    if (slot >= gb->slots) return;
    fv_vk_write_buffer(gb->vk, gb->frame_sets[slot], FV_GBUFFER_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                       buffer, frame_offset, sizeof(fv_gpu_frame));
    fv_vk_write_buffer(gb->vk, gb->frame_sets[slot], FV_GBUFFER_BINDING_DRAWS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                       buffer, draws_offset, draws_range);
    if (gb->materials.buffer)
        fv_vk_write_buffer(gb->vk, gb->frame_sets[slot], FV_GBUFFER_BINDING_MATERIALS,
                           VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, gb->materials.buffer, 0, VK_WHOLE_SIZE);
}

static void record_pass(fv_gbuffer *gb, VkCommandBuffer cmd, const fv_gbuffer_inputs *in, VkFramebuffer fb,
                        uint32_t eye)
{
    VkClearValue clears[5];
    memset(clears, 0, sizeof clears);
    clears[0].depthStencil.depth = 1.0f;
    VkRenderPassBeginInfo bi = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
        .renderPass = gb->render_pass,
        .framebuffer = fb,
        .renderArea = {{0, 0}, {gb->width, gb->height}},
        .clearValueCount = 5,
        .pClearValues = clears,
    };
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    VkViewport vp = {0, 0, (float)gb->width, (float)gb->height, 0.0f, 1.0f};
    VkRect2D sc = {{0, 0}, {gb->width, gb->height}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
    if (in->draw_count && gb->vertices.buffer && gb->materials.buffer) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, gb->pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, gb->layout, 0, 1, &gb->frame_sets[in->slot], 0,
                                NULL);
        VkDeviceSize zero = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &gb->vertices.buffer, &zero);
        vkCmdBindIndexBuffer(cmd, gb->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
        int32_t bound_texture = -2;
        for (uint32_t d = 0; d < in->draw_count; d++) {
            const fv_gbuffer_draw *dr = &in->draws[d];
            if (dr->mesh >= gb->mesh_count || gb->meshes[dr->mesh].index_count == 0) continue;
            int32_t tex = dr->texture >= 0 && (uint32_t)dr->texture < gb->texture_count ? dr->texture : -1;
            if (tex != bound_texture) {
                uint32_t set = tex >= 0 ? (uint32_t)tex : gb->texture_count;
                vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, gb->layout, 1, 1, &gb->texture_sets[set],
                                        0, NULL);
                bound_texture = tex;
            }
            uint32_t push[2] = {d, eye};
            vkCmdPushConstants(cmd, gb->layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                               sizeof push, push);
            const fv_gbuffer_mesh *m = &gb->meshes[dr->mesh];
            vkCmdDrawIndexed(cmd, m->index_count, 1, m->first_index, m->vertex_offset, 0);
        }
    }
    vkCmdEndRenderPass(cmd);
}

void fv_gbuffer_record(fv_gbuffer *gb, VkCommandBuffer cmd, const fv_gbuffer_inputs *in)
{
    if (gb->multiview) {
        fv_vk_label_begin(gb->vk, cmd, "gbuffer (multiview, both eyes)");
        record_pass(gb, cmd, in, gb->framebuffer, 0);
        fv_vk_label_end(gb->vk, cmd);
        return;
    }
    for (uint32_t e = 0; e < 2; e++) {
        fv_vk_label_begin(gb->vk, cmd, e == 0 ? "gbuffer (left eye)" : "gbuffer (right eye)");
        record_pass(gb, cmd, in, gb->eye_framebuffer[e], e);
        fv_vk_label_end(gb->vk, cmd);
    }
}
