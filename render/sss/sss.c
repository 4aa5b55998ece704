/* @brief The subsurface-scattering pass (see sss.h). */
#include "sss.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_sss_interface.h"
#include "fv_sss_math.h"
#include "sss_build_comp.spv.h"
#include "sss_map_frag.spv.h"
#include "sss_map_vert.spv.h"

#define MOD "sss"
#define MAP_FORMAT VK_FORMAT_R32G32B32A32_SFLOAT
#define FRAG_STAGES (VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT)
#define READERS (VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT)

_Static_assert(FV_SSS_GPU_MAX_LAYERS == FV_SSS_MAX_LAYERS, "one header entry per map");

typedef struct layer_view {
    bool valid;
    fv_sss_view view;
} layer_view;

typedef struct sss {
    fv_vk *vk;
    fv_scene_gpu *scene;
    const fv_scene *model;
    fv_shade_inputs *inputs;
    uint32_t size, leaf, count;        /* the fine map's side, its leaf level log2(size), maps */
    uint32_t sub;                      /* sub-levels of the fine map below the nominal texels (fv_sss_sub_levels) */
    fv_sss_pair pair[FV_SSS_MAX_LAYERS];
    uint32_t nodes_per_map;
    fv_vk_image map[FV_SSS_MAP_TARGETS], depth;
    VkImageView layer_view[FV_SSS_MAX_LAYERS][FV_SSS_MAP_TARGETS];
    VkFramebuffer framebuffer[FV_SSS_MAX_LAYERS];
    VkRenderPass render_pass;
    VkPipelineLayout map_layout;
    VkPipeline map_pipeline;
    fv_vk_compute build;
    VkSampler nearest;
    fv_vk_buffer nodes, header;
    layer_view views[FV_MAX_FRAMES_IN_FLIGHT][FV_SSS_MAX_LAYERS];
    float cutoff_fraction;              /* sss.cutoff the radii below were derived for (< 0: none yet) */
    float cutoff_m[FV_SSS_MAX_LAYERS];  /* each map's material's cutoff radius (m; 0 = none) */
    float flat_m[FV_SSS_MAX_LAYERS];    /* and its flat radius (m, fv_sss_flat_radius_m) */
    fv_gpu_sss blk[FV_MAX_FRAMES_IN_FLIGHT];
} sss;

static const char *plural(uint64_t n) { return n == 1 ? "" : "s"; }

static uint32_t log2u(uint32_t v)
{
    uint32_t l = 0;
    while ((1u << (l + 1)) <= v && l < 31) l++;
    return l;
}

/* The loop iterations of the exact sum over a size x size map (nominal texels), but for the near field: one loop
 * (fv_sss_gather.glsl), one iteration per texel. A texel left at its fine samples is one disk of its area beyond the
 * receiver's near field; within it its 16 fine samples add 16, and the footprint quadrature near the receiver its
 * own (20 a footprint within 4 half-diagonals), which the plan cannot count (how much of the near field grazes the
 * light). */
/* The near field's share, held free under the limit: its texels left at their fine samples (footprints stretched at
 * most 1/FV_SSS_MIN_COS = 10x, so a cluster's reach is a couple of texels and the near field a few texels plus the
 * material's flat radius: tens of grazing texels, 16 iterations each) and the quadrature of the footprints within 4
 * half-diagonals of the receiver (20 each): a few thousand at most; this leaves about 4x room. */
#define FV_SSS_NEAR_ITERATIONS 16384u

static uint64_t exact_iterations(uint32_t size)
{
    return (uint64_t)size * size;
}

static void sss_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    const fv_scene *s = ctx->scene;
    const fv_quality_sss *q = &ctx->quality->sss;
    uint32_t translucent = fv_sss_translucent_materials(s, NULL, 0);
    if (!translucent) {
        out->enabled = false;
        snprintf(out->reason, sizeof out->reason, "off — no translucent material");
        return;
    }
    if (!q->enabled) {
        out->enabled = false;
        snprintf(out->reason, sizeof out->reason, "off — sss.enabled is false: %u translucent material%s shaded as "
                 "opaque", translucent, plural(translucent));
        return;
    }
    fv_sss_pair pairs[FV_SSS_MAX_LAYERS];
    uint32_t wanted = 0, n = fv_sss_pairs(s, pairs, &wanted);
    if (!n) {
        out->enabled = false;
        snprintf(out->reason, sizeof out->reason, "off — %u translucent material%s but no light", translucent,
                 plural(translucent));
        return;
    }
    uint32_t size = q->map_size_px >= 16 && q->map_size_px <= 512 ? q->map_size_px : 128;
    uint32_t leaf = log2u(size);
    uint32_t limit = q->limit_level < leaf ? q->limit_level : leaf;
    uint32_t start = q->start_level < limit ? q->start_level : limit;
    out->enabled = true;
    out->variant = leaf | (n << 4);
    char cut[72];
    if (q->mode == FV_SSS_MODE_EXACT)
        snprintf(cut, sizeof cut, "exact: every sample");
    else
        snprintf(cut, sizeof cut, "cut, levels %u..%u (%u x %u), distance scale %.3g/m", start % 16u, limit % 16u,
                 1u << (limit % 16u), 1u << (limit % 16u), (double)q->distance_scale);
    uint32_t loop_limit = ctx->device ? ctx->device->shader_loop_limit : 0u;
    /* Under the limit by the texels, the near field still adds its fine samples and quadrature: a map that leaves
     * less than FV_SSS_NEAR_ITERATIONS under the limit says so (128 px: 16384 + 16384 fit; from 256 px the texels
     * alone pass it: cut short). */
    if (q->mode == FV_SSS_MODE_EXACT && loop_limit && fv_sss_sub_levels(size) &&
        exact_iterations(size) + FV_SSS_NEAR_ITERATIONS > loop_limit)
        snprintf(cut, sizeof cut, "exact: every sample; llvmpipe may stop short where the light grazes");
    if (q->mode == FV_SSS_MODE_EXACT && loop_limit && exact_iterations(size) > loop_limit) {
        snprintf(cut, sizeof cut, "exact: CUT SHORT here (the device's loop limit)");
        static uint32_t warned; /* once per map size in a process: plans are made again on every setting change */
        if (warned != size) {
            warned = size;
            /* the one device with a limit is llvmpipe (fv_vk_device_info.shader_loop_limit) */
            FV_WARN(MOD, "sss.mode=exact over a %u px map: llvmpipe ends a shader's loops after %u iterations and "
                    "this sum takes %llu, so every pixel's sum leaves part of the map out on this device (a GPU has "
                    "no such limit); use sss.map_size 128 or the hierarchy", size, loop_limit,
                    (unsigned long long)exact_iterations(size));
        }
    }
    uint32_t sub = fv_sss_sub_levels(size);
    char fine[40] = "";
    if (sub) snprintf(fine, sizeof fine, " (%upx where the light grazes)", size << sub);
    int len = snprintf(out->reason, sizeof out->reason, "%u translucent material%s: %u light-view map%s of %upx%s%s, "
                       "dipole %s", translucent, plural(translucent), n, plural(n), size, fine,
                       wanted > n ? " (more light x material pairs left out)" : "", cut);
    if (len >= (int)sizeof out->reason) out->reason[sizeof out->reason - 2] = '~'; /* cut short: say so */
}

static void sss_fini(void *state)
{
    sss *p = state;
    if (!p) return;
    fv_vk *vk = p->vk;
    /* The GPU is idle: shading reads the zero dummies again. */
    if (fv_shade_inputs_bind_buffer(p->inputs, FV_SSS_BINDING_HEADER, VK_NULL_HANDLE, 0, 0) != FV_OK ||
        fv_shade_inputs_bind_buffer(p->inputs, FV_SSS_BINDING_NODES, VK_NULL_HANDLE, 0, 0) != FV_OK)
        FV_ERROR(MOD, "the shading inputs' SSS slot could not be reset to its dummies");
    fv_vk_compute_fini(vk, &p->build);
    if (p->map_pipeline) vkDestroyPipeline(vk->device, p->map_pipeline, NULL);
    if (p->map_layout) vkDestroyPipelineLayout(vk->device, p->map_layout, NULL);
    for (uint32_t l = 0; l < FV_SSS_MAX_LAYERS; l++) {
        if (p->framebuffer[l]) vkDestroyFramebuffer(vk->device, p->framebuffer[l], NULL);
        for (int k = 0; k < FV_SSS_MAP_TARGETS; k++)
            if (p->layer_view[l][k]) vkDestroyImageView(vk->device, p->layer_view[l][k], NULL);
    }
    if (p->render_pass) vkDestroyRenderPass(vk->device, p->render_pass, NULL);
    if (p->nearest) vkDestroySampler(vk->device, p->nearest, NULL);
    for (int k = 0; k < FV_SSS_MAP_TARGETS; k++) fv_vk_image_destroy(vk, &p->map[k]);
    fv_vk_image_destroy(vk, &p->depth);
    fv_vk_buffer_destroy(vk, &p->nodes);
    fv_vk_buffer_destroy(vk, &p->header);
    free(p);
}

static fv_result create_render_pass(sss *p)
{
    fv_vk *vk = p->vk;
    enum { NT = FV_SSS_MAP_TARGETS };
    VkAttachmentDescription att[NT + 1];
    VkAttachmentReference color[NT];
    for (uint32_t k = 0; k < NT; k++) {
        att[k] = fv_vk_attachment_cleared(MAP_FORMAT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        /* Only the positions are cleared (area 0: no sample); the build reads the others only where a fragment
         * wrote the positions, and every fragment writes all five (the fine map is 16x the texels to clear). */
        if (k != FV_SSS_OUT_POS) {
            att[k].loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
            att[k].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        }
        color[k] = (VkAttachmentReference){k, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    }
    att[NT] = fv_vk_attachment_cleared(VK_FORMAT_D32_SFLOAT, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    VkAttachmentReference depth = {NT, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub = {.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS, .colorAttachmentCount = NT,
                                .pColorAttachments = color, .pDepthStencilAttachment = &depth};
    VkSubpassDependency deps[2] = {
        /* Before: the last build read the maps (write-after-read), and the previous map's render pass wrote the
         * shared depth image and its colour targets (write-after-write). */
        {.srcSubpass = VK_SUBPASS_EXTERNAL, .dstSubpass = 0,
         .srcStageMask = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                         FRAG_STAGES,
         .dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | FRAG_STAGES,
         .srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
         .dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_READ_BIT |
                          VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT},
        /* After: the build reads the maps. */
        {.srcSubpass = 0, .dstSubpass = VK_SUBPASS_EXTERNAL,
         .srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, .dstStageMask = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
         .srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, .dstAccessMask = VK_ACCESS_SHADER_READ_BIT},
    };
    VkRenderPassCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO, .attachmentCount = NT + 1,
                                 .pAttachments = att, .subpassCount = 1, .pSubpasses = &sub, .dependencyCount = 2,
                                 .pDependencies = deps};
    FV_VK_CHECK(vkCreateRenderPass(vk->device, &ci, NULL, &p->render_pass));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_RENDER_PASS, p->render_pass, "sss light-view map render pass");
    for (uint32_t l = 0; l < p->count; l++) {
        VkImageView views[NT + 1];
        for (int k = 0; k < NT; k++) {
            VkImageViewCreateInfo vi = {.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO, .image = p->map[k].image,
                                        .viewType = VK_IMAGE_VIEW_TYPE_2D, .format = MAP_FORMAT,
                                        .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, l, 1}};
            FV_VK_CHECK(vkCreateImageView(vk->device, &vi, NULL, &p->layer_view[l][k]));
            FV_VK_NAME(vk, VK_OBJECT_TYPE_IMAGE_VIEW, p->layer_view[l][k], "sss map %u target %d", l, k);
            views[k] = p->layer_view[l][k];
        }
        views[NT] = p->depth.view;
        VkFramebufferCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO, .renderPass = p->render_pass,
                                      .attachmentCount = NT + 1, .pAttachments = views, .width = p->size,
                                      .height = p->size, .layers = 1};
        FV_VK_CHECK(vkCreateFramebuffer(vk->device, &fi, NULL, &p->framebuffer[l]));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_FRAMEBUFFER, p->framebuffer[l], "sss map %u framebuffer", l);
    }
    return FV_OK;
}

static fv_result create_pipelines(sss *p)
{
    fv_vk *vk = p->vk;
    VkDescriptorSetLayout sets[2] = {p->scene->set_layout, p->scene->texture_layout};
    FV_TRY(fv_vk_pipeline_layout(vk, sets, 2, sizeof(struct fv_sss_map_push),
                                 VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, "sss map layout",
                                 &p->map_layout));
    const VkVertexInputBindingDescription *bind;
    const VkVertexInputAttributeDescription *attrs;
    uint32_t attr_count;
    fv_scene_gpu_vertex_input(&bind, &attrs, &attr_count);
    fv_vk_graphics_desc gd = {.vert = fv_spv_sss_map_vert, .vert_size = sizeof fv_spv_sss_map_vert,
                              .frag = fv_spv_sss_map_frag, .frag_size = sizeof fv_spv_sss_map_frag, .bindings = bind,
                              .binding_count = 1, .attributes = attrs, .attribute_count = 2 /* position, normal */,
                              .layout = p->map_layout, .render_pass = p->render_pass, .color_attachments = FV_SSS_MAP_TARGETS,
                              .depth_test = true, .cull = VK_CULL_MODE_NONE, .name = "sss light-view map"};
    FV_TRY(fv_vk_graphics_pipeline(vk, &gd, &p->map_pipeline));
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorSetLayoutBinding b[FV_SSS_BUILD_BINDING_COUNT] = {
        {FV_SSS_BUILD_BINDING_POS, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_SSS_BUILD_BINDING_FLUX, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_SSS_BUILD_BINDING_NORMAL, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_SSS_BUILD_BINDING_NODES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
        {FV_SSS_BUILD_BINDING_EDGE_A, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_SSS_BUILD_BINDING_EDGE_B, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
    };
    VkDescriptorSetLayout shared = p->scene->set_layout;
    _Static_assert(FV_SSS_BUILD_SET == 1, "the build's own set follows the scene set");
    fv_vk_compute_desc cd = {.name = "sss build", .code = fv_spv_sss_build_comp, .code_size = sizeof fv_spv_sss_build_comp,
                             .shared_sets = &shared, .shared_set_count = 1, .bindings = b,
                             .binding_count = FV_SSS_BUILD_BINDING_COUNT, .set_count = 1,
                             .push_bytes = sizeof(struct fv_sss_build_push)};
    FV_TRY(fv_vk_compute_init(vk, &cd, &p->build));
    static const uint32_t binding[FV_SSS_MAP_TARGETS] = {FV_SSS_BUILD_BINDING_POS, FV_SSS_BUILD_BINDING_FLUX,
                                                         FV_SSS_BUILD_BINDING_NORMAL, FV_SSS_BUILD_BINDING_EDGE_A,
                                                         FV_SSS_BUILD_BINDING_EDGE_B};
    for (int k = 0; k < FV_SSS_MAP_TARGETS; k++)
        fv_vk_write_image(vk, p->build.sets[0], binding[k],
                          VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, p->map[k].view, p->nearest,
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    fv_vk_write_buffer(vk, p->build.sets[0], FV_SSS_BUILD_BINDING_NODES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                       p->nodes.buffer, 0, VK_WHOLE_SIZE);
    return FV_OK;
}

static fv_result sss_init(const fv_pass_env *env, void **out_state)
{
    if (!env->scene_model) return FV_ERR_INVALID_ARG;
    sss *p = calloc(1, sizeof *p);
    if (!p) return FV_ERR_NO_MEMORY;
    p->vk = env->vk;
    p->scene = env->scene;
    p->model = env->scene_model;
    p->inputs = env->shade_inputs;
    uint32_t v = env->plan ? env->plan->variant : 0;
    p->sub = fv_sss_sub_levels(1u << (v & 15u));
    p->leaf = (v & 15u) + p->sub; /* the fine map's */
    p->size = 1u << p->leaf;
    p->count = fv_sss_pairs(p->model, p->pair, NULL);
    p->cutoff_fraction = -1.0f;
    for (uint32_t l = 0; l < p->count; l++) /* a bisection per channel, once: the material's near field */
        p->flat_m[l] = (float)fmin(fv_sss_flat_radius_m(&p->model->materials[p->pair[l].material].translucency), 1e30);
    p->nodes_per_map = (uint32_t)(((1ull << (2 * (p->leaf + 1))) - 1) / 3);
    fv_result res = p->count && p->leaf >= 4 && p->leaf <= 10 ? FV_OK : FV_ERR_INVALID_ARG;
    static const char *const names[FV_SSS_MAP_TARGETS] = {"sss map positions+area", "sss map flux+depth",
                                                          "sss map normals", "sss map footprint edge a",
                                                          "sss map footprint edge b"};
    for (int k = 0; k < FV_SSS_MAP_TARGETS && res == FV_OK; k++) {
        fv_vk_image_desc d = {.width = p->size, .height = p->size, .layers = p->count, .array = true,
                              .format = MAP_FORMAT,
                              .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                              .name = names[k]};
        res = fv_vk_image_create(p->vk, &d, &p->map[k]);
    }
    if (res == FV_OK) {
        fv_vk_image_desc d = {.width = p->size, .height = p->size, .layers = 1, .format = VK_FORMAT_D32_SFLOAT,
                              .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, .name = "sss map depth"};
        res = fv_vk_image_create(p->vk, &d, &p->depth);
    }
    if (res == FV_OK)
        res = fv_vk_buffer_create(p->vk, (VkDeviceSize)p->count * p->nodes_per_map * sizeof(fv_gpu_sss_node),
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, FV_VK_MEM_DEVICE, "sss quad-tree nodes", &p->nodes);
    if (res == FV_OK)
        res = fv_vk_buffer_create(p->vk, sizeof(fv_gpu_sss),
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                  FV_VK_MEM_DEVICE, "sss header", &p->header);
    if (res == FV_OK) res = fv_vk_sampler_create(p->vk, false, false, "sss map sampler (nearest)", &p->nearest);
    if (res == FV_OK) res = create_render_pass(p);
    if (res == FV_OK) res = create_pipelines(p);
    /* The maps start readable (the build's descriptors name that layout even before the first frame draws them). */
    for (int k = 0; k < FV_SSS_MAP_TARGETS && res == FV_OK; k++)
        res = fv_vk_image_set_layout(p->vk, &p->map[k], VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    if (res == FV_OK) res = fv_shade_inputs_bind_buffer(p->inputs, FV_SSS_BINDING_HEADER, p->header.buffer, 0, VK_WHOLE_SIZE);
    if (res == FV_OK) res = fv_shade_inputs_bind_buffer(p->inputs, FV_SSS_BINDING_NODES, p->nodes.buffer, 0, VK_WHOLE_SIZE);
    if (res != FV_OK) {
        FV_ERROR(MOD, "subsurface scattering (%u map%s of %upx) could not be set up: %s", p->count, plural(p->count),
                 p->size, fv_result_str(res));
        sss_fini(p);
        return res;
    }
    *out_state = p;
    return FV_OK;
}

/* This frame's maps: each pair's view fitted to its material's bounds at the frame's time, and the header. */
static void sss_prepare(void *state, const fv_pass_frame *f)
{
    sss *p = state;
    layer_view *lv = p->views[f->slot];
    fv_gpu_sss *blk = &p->blk[f->slot];
    memset(blk, 0, sizeof *blk);
    memset(lv, 0, sizeof(layer_view) * FV_SSS_MAX_LAYERS);
    const fv_quality_sss *q = &f->input->quality.sss;
    fv_vec3 smin, smax;
    bool scene_ok = fv_scene_gpu_world_bounds(p->scene, f->input->time_s, &smin, &smax);
    uint32_t nominal = p->leaf - p->sub; /* the cut's levels are the nominal map's */
    uint32_t limit = q->limit_level < nominal ? q->limit_level : nominal;
    uint32_t start = q->start_level < limit ? q->start_level : limit;
    blk->counts = (fv_gpu_uvec4){p->count, q->mode == FV_SSS_MODE_EXACT ? FV_SSS_GPU_MODE_EXACT : FV_SSS_GPU_MODE_HIERARCHY,
                                 start, limit};
    float ds = q->distance_scale;
    blk->params = (fv_gpu_vec4){isfinite(ds) && ds > 0.0f ? ds : 0.0f, 0, 0, 0};
    float cut = isfinite(q->cutoff) && q->cutoff > 0.0f && q->cutoff < 1.0f ? q->cutoff : 0.0f;
    if (cut != p->cutoff_fraction) { /* a bisection per channel: only when the knob changes */
        for (uint32_t l = 0; l < p->count; l++)
            p->cutoff_m[l] = (float)fmin(fv_sss_cutoff_radius_m(&p->model->materials[p->pair[l].material].translucency,
                                                                cut), 1e30);
        p->cutoff_fraction = cut;
    }
    for (uint32_t l = 0; l < p->count; l++) {
        const fv_sss_pair *pr = &p->pair[l];
        fv_gpu_sss_layer *g = &blk->layer[l];
        g->info = (fv_gpu_uvec4){pr->material, pr->light, l * p->nodes_per_map, p->leaf | (p->sub << 8)};
        fv_vec3 omin, omax;
        if (!scene_ok || pr->light >= p->scene->light_count ||
            !fv_sss_material_bounds(p->model, pr->material, f->input->time_s, &omin, &omax))
            continue;
        const fv_gpu_light *L = &p->scene->lights[pr->light];
        uint32_t type = (uint32_t)(L->direction_type.w + 0.5f);
        fv_vec3 pos = fv_v3(L->position_range.x, L->position_range.y, L->position_range.z);
        fv_vec3 dir = fv_v3(L->direction_type.x, L->direction_type.y, L->direction_type.z);
        lv[l].valid = fv_sss_light_view(type, pos, dir, omin, omax, smin, smax, p->size, &lv[l].view);
        const fv_sss_view *vw = &lv[l].view;
        g->view = (fv_gpu_vec4){vw->perspective ? 1.0f : 0.0f, (float)(vw->perspective ? vw->tan_half : vw->texel_m),
                                p->cutoff_m[l], p->flat_m[l]};
    }
}

static void sss_record(void *state, const fv_pass_frame *f)
{
    sss *p = state;
    VkCommandBuffer cmd = f->cmd;
    const layer_view *lv = p->views[f->slot];
    fv_vk_label_begin(p->vk, cmd, "sss");
    /* The header: the previous frame's shading read it (write-after-read), then shading reads it again. */
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = VK_ACCESS_SHADER_READ_BIT,
                          .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT};
    vkCmdPipelineBarrier(cmd, READERS, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, NULL, 0, NULL);
    vkCmdUpdateBuffer(cmd, p->header.buffer, 0, sizeof(fv_gpu_sss), &p->blk[f->slot]);
    /* The maps: one render pass per (light, material) pair, every draw of the scene from the light. */
    for (uint32_t l = 0; l < p->count; l++) {
        VkClearValue clear[FV_SSS_MAP_TARGETS + 1];
        memset(clear, 0, sizeof clear); /* empty samples */
        clear[FV_SSS_MAP_TARGETS].depthStencil = (VkClearDepthStencilValue){1.0f, 0};
        VkRenderPassBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO, .renderPass = p->render_pass,
                                    .framebuffer = p->framebuffer[l], .renderArea = {{0, 0}, {p->size, p->size}},
                                    .clearValueCount = FV_SSS_MAP_TARGETS + 1, .pClearValues = clear};
        vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
        if (lv[l].valid) {
            VkViewport vp = {0, 0, (float)p->size, (float)p->size, 0.0f, 1.0f};
            VkRect2D sc = {{0, 0}, {p->size, p->size}};
            vkCmdSetViewport(cmd, 0, 1, &vp);
            vkCmdSetScissor(cmd, 0, 1, &sc);
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->map_pipeline);
            const fv_sss_view *vw = &lv[l].view;
            struct fv_sss_map_push push;
            memset(&push, 0, sizeof push);
            push.ids = (fv_gpu_uvec4){0, l, p->pair[l].material, p->pair[l].light};
            memcpy(push.view_proj.m, vw->view_proj.m, sizeof push.view_proj.m);
            push.view = p->blk[f->slot].layer[l].view;
            push.origin = (fv_gpu_vec4){vw->origin.x, vw->origin.y, vw->origin.z, 0};
            push.axis = (fv_gpu_vec4){vw->axis.x, vw->axis.y, vw->axis.z, (float)p->size};
            /* Our part of the push constants (after the scene's {draw, view}); the draws push their own part. */
            vkCmdPushConstants(cmd, p->map_layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 8,
                               sizeof push - 8, (const uint8_t *)&push + 8);
            uint32_t n = fv_scene_gpu_record_draws(p->scene, cmd, p->map_layout,
                                                   VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, f->slot, l);
            f->counters->draws += n;
            f->counters->triangles += p->scene->triangle_count;
        }
        vkCmdEndRenderPass(cmd);
    }
    /* The quad-tree, leaves to root. Before the leaves: the previous frame's shading read the nodes. */
    mb = (VkMemoryBarrier){.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = VK_ACCESS_SHADER_READ_BIT,
                           .dstAccessMask = VK_ACCESS_SHADER_WRITE_BIT};
    vkCmdPipelineBarrier(cmd, READERS, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &mb, 0, NULL, 0, NULL);
    VkDescriptorSet scene_set = f->scene_set;
    for (int32_t level = (int32_t)p->leaf; level >= 0; level--) {
        struct fv_sss_build_push bp = {.level = {(uint32_t)level, p->leaf, p->count, p->sub}};
        fv_vk_compute_bind(&p->build, cmd, 0, &scene_set, 1, 0, &bp);
        uint64_t items = (1ull << (2 * level)) * p->count;
        uint32_t groups = (uint32_t)((items + FV_SSS_BUILD_GROUP - 1) / FV_SSS_BUILD_GROUP);
        vkCmdDispatch(cmd, groups, 1, 1);
        f->counters->dispatches++;
        /* Each level reads the one written before it; the last is read by shading. */
        mb = (VkMemoryBarrier){.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
                               .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                             level ? VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT : READERS, 0, 1, &mb, 0, NULL, 0, NULL);
    }
    /* The header's update, visible to shading. */
    mb = (VkMemoryBarrier){.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                           .dstAccessMask = VK_ACCESS_SHADER_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, READERS, 0, 1, &mb, 0, NULL, 0, NULL);
    fv_vk_label_end(p->vk, cmd);
}

static uint32_t sss_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    sss *p = state;
    if (cap < 2) return 0;
    snprintf(out[0].key, sizeof out[0].key, "maps");
    out[0].value[0] = p->count;
    out[0].count = 1;
    snprintf(out[1].key, sizeof out[1].key, "map_size_px");
    out[1].value[0] = p->size >> p->sub; /* nominal (sss.map_size) */
    out[1].count = 1;
    return 2;
}

const fv_pass fv_sss_pass = {
    .id = "sss",
    .plan = sss_plan,
    .init = sss_init,
    .prepare = sss_prepare,
    .record = sss_record,
    .fini = sss_fini,
    .details = sss_details,
};
