/* @brief The GI pass (see gi.h). */
#include "gi.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gi_build_comp.spv.h"
#include "fv_gi_math.h"
#include "gi_interface.h"
#include "gi_rsm_frag.spv.h"
#include "gi_rsm_vert.spv.h"

#define MOD "gi"
#define RSM_TARGETS 3
#define ATTACH_STAGES                                                                                                  \
    (VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |                     \
     VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT)
#define READER_STAGES (VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT)
#define BUILD_QUERIES 4 /* per slot: before the RSM, after it, after the pyramid, after the cut */
#define QUERY_STATS 4   /* per slot: after the gather's stats were copied back (every frame) */
#define QUERIES 5

_Static_assert(sizeof(fv_gi_header) <= 256, "the header fits the shading inputs' 256-byte dummy buffer");
_Static_assert(FV_GI_CUT == FV_GI_MODE_CUT && FV_GI_TRAVERSE == FV_GI_MODE_TRAVERSE && FV_GI_BOUND == FV_GI_MODE_BOUND &&
                   FV_GI_RSM_SAMPLING == FV_GI_MODE_RSM_SAMPLING && FV_GI_EXACT == FV_GI_MODE_EXACT,
               "gi.mode values agree between C and GLSL");

/* What a rebuild depends on: when this changes, the RSM, the tree and the cut are made again. */
typedef struct build_key {
    fv_quality_gi q;
    fv_gpu_light light[FV_GI_MAX_LIGHTS];
    double time_s; /* animated scenes only (0 otherwise) */
    fv_vec3 bmin, bmax;
} build_key;

typedef struct gi {
    fv_vk *vk;
    fv_scene_gpu *scene;
    fv_shade_inputs *inputs;
    uint32_t slots;
    uint32_t n, levels, lights;     /* RSM side, tree levels, lights with an RSM */
    uint32_t light_index[FV_GI_MAX_LIGHTS]; /* scene light of each RSM layer */
    uint32_t kind[FV_GI_MAX_LIGHTS];
    uint32_t nodes_per_light;
    fv_vk_image rsm[RSM_TARGETS], depth;
    VkImageView layer_view[FV_GI_MAX_LIGHTS][RSM_TARGETS + 1];
    VkFramebuffer framebuffer[FV_GI_MAX_LIGHTS];
    VkRenderPass render_pass;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    fv_vk_compute build;
    VkSampler nearest;
    fv_vk_buffer nodes, header, scan;
    fv_vk_buffer readback[FV_MAX_FRAMES_IN_FLIGHT]; /* the header after a rebuild (cut counts) */
    fv_vk_buffer stats[FV_MAX_FRAMES_IN_FLIGHT];    /* fv_gi_stats the shading passes count into (device) */
    fv_vk_buffer stats_readback[FV_MAX_FRAMES_IN_FLIGHT];
    VkQueryPool queries;
    bool built_in_slot[FV_MAX_FRAMES_IN_FLIGHT];
    bool counted_in_slot[FV_MAX_FRAMES_IN_FLIGHT]; /* the slot's frame copies its stats back */
    uint64_t counted_seq[FV_MAX_FRAMES_IN_FLIGHT];  /* which frame (frames_counted at its end) */
    uint64_t frames_counted, measured_seq;
    bool animated;
    /* this frame's decision (prepare -> record) */
    bool have_key, rebuild;
    build_key key;
    fv_gi_header host;                 /* the header as the host writes it at a rebuild */
    struct fv_gi_rsm_push push[FV_GI_MAX_LIGHTS];
    uint32_t candidates;               /* cut candidates per light */
    /* what the last completed rebuild reported */
    double stage_ms[3];                /* rsm, pyramid, cut */
    uint32_t cut_clusters, lit_vpls;
    uint64_t rebuilds;
    /* what the newest frame read back measured: clusters (nodes, samples) per pixel that ran the gather */
    bool measured;
    double per_pixel_mean, per_pixel_max, gathered_pixels;
} gi;

static const char *plural(uint64_t n) { return n == 1 ? "" : "s"; }

static const char *mode_name(fv_gi_mode m)
{
    static const char *const names[] = {"cut", "traverse", "bound", "rsm_sampling", "exact"};
    return (unsigned)m < 5 ? names[m] : "?";
}

static uint32_t candidates_for(uint32_t n, uint32_t start, uint32_t limit)
{
    uint32_t c = 0;
    for (uint32_t k = limit; k <= start; k++) c += (n >> k) * (n >> k);
    return c;
}

/* The lights that get an RSM: spot and directional ones, in scene order, at most FV_GI_MAX_LIGHTS. Also counted:
 * the point lights (no cube RSM is built: no indirect light from them) and the spot or directional lights beyond
 * the first FV_GI_MAX_LIGHTS (no RSM either). */
static uint32_t gi_lights_of_scene(const fv_scene *s, uint32_t *out_points, uint32_t *out_beyond)
{
    uint32_t n = 0, points = 0, beyond = 0;
    for (uint32_t l = 0; s && l < s->light_count; l++) {
        if (s->lights[l].type == FV_LIGHT_POINT) points++;
        else if (n < FV_GI_MAX_LIGHTS) n++;
        else beyond++;
    }
    *out_points = points;
    *out_beyond = beyond;
    return n;
}

/* What the plan says of the lights GI leaves out ("" when none), put after the count of those with an RSM. */
static void left_out(uint32_t points, uint32_t beyond, char *out, size_t cap)
{
    out[0] = '\0';
    if (points && beyond)
        snprintf(out, cap, " (left out: %u point, no cube RSM; %u beyond %u)", points, beyond, FV_GI_MAX_LIGHTS);
    else if (points)
        snprintf(out, cap, " (%u point light%s left out: no cube RSM)", points, plural(points));
    else if (beyond)
        snprintf(out, cap, " (left out: %u beyond the first %u)", beyond, FV_GI_MAX_LIGHTS);
}

static void gi_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    const fv_scene *s = ctx->scene;
    const fv_quality_gi *q = &ctx->quality->gi;
    uint32_t lights = s ? s->light_count : 0;
    out->enabled = false;
    if (!lights) {
        snprintf(out->reason, sizeof out->reason, "off — no lights");
        return;
    }
    if (!q->enabled) {
        snprintf(out->reason, sizeof out->reason, "off — gi.enabled is false: no indirect light");
        return;
    }
    uint32_t points = 0, beyond = 0;
    uint32_t n = gi_lights_of_scene(s, &points, &beyond);
    if (!n) {
        snprintf(out->reason, sizeof out->reason,
                 "off — only point lights (%u): the RSM is per spot or directional light, a point light's would be a "
                 "cube (6 faces), not built; direct light only", points);
        return;
    }
    char rest[96];
    left_out(points, beyond, rest, sizeof rest);
    uint32_t size = q->rsm_size ? q->rsm_size : 1;
    uint32_t start, limit;
    fv_gi_tree_levels(size, q, &start, &limit);
    out->enabled = true;
    out->variant = fv_gi_log2(size) | (n << 4);
    bool animated = fv_scene_is_animated(s);
    char limit_txt[32], what[512];
    if (limit == 0) snprintf(limit_txt, sizeof limit_txt, "leaf");
    else snprintf(limit_txt, sizeof limit_txt, "%ux%u", size >> limit, size >> limit);
    snprintf(what, sizeof what,
             "%u light%s%s: RSM %upx (%u VPLs each), cut at %s from %ux%u (depth %.2g, normal %.2g), %s; rebuilt %s",
             n, plural(n), rest, size, size * size, limit_txt, size >> start, size >> start,
             (double)q->depth_threshold, (double)q->normal_threshold, mode_name(q->mode),
             animated ? "every frame (animated)" : rest[0] ? "on change" : "when a light or the scene moves");
    size_t len = strlen(what);
    if (len >= sizeof out->reason) len = sizeof out->reason - 1;
    memcpy(out->reason, what, len);
    out->reason[len] = '\0';
}

/* ---- light views -------------------------------------------------------------------------------------------- */

/* One light's RSM view as the RSM shaders get it. */
static void light_view(const fv_gpu_light *L, uint32_t kind, uint32_t n, fv_vec3 bmin, fv_vec3 bmax,
                       struct fv_gi_rsm_push *out)
{
    fv_gi_view v;
    fv_gi_light_view(L, kind, n, bmin, bmax, &v);
    memset(out, 0, sizeof *out);
    memcpy(out->view_proj.m, v.view_proj.m, sizeof out->view_proj.m);
    out->params = (fv_gpu_vec4){v.params[0], v.params[1], v.params[2], v.params[3]};
    out->origin = (fv_gpu_vec4){v.origin[0], v.origin[1], v.origin[2], 0.0f};
    out->ids = (fv_gpu_uvec4){0, 0, 0, kind};
}

/* ---- init / fini -------------------------------------------------------------------------------------------- */

static void gi_fini(void *state)
{
    gi *g = state;
    if (!g) return;
    fv_vk *vk = g->vk;
    /* the GPU is idle: shading goes back to the dummies (GI off at the cost of one load) */
    if (fv_shade_inputs_bind_buffer(g->inputs, FV_GI_BINDING_HEADER, VK_NULL_HANDLE, 0, 0) != FV_OK ||
        fv_shade_inputs_bind_buffer(g->inputs, FV_GI_BINDING_NODES, VK_NULL_HANDLE, 0, 0) != FV_OK ||
        fv_shade_inputs_bind_buffer(g->inputs, FV_GI_BINDING_STATS, VK_NULL_HANDLE, 0, 0) != FV_OK)
        FV_ERROR(MOD, "the GI slots of the shading inputs could not be reset to the dummies");
    if (g->queries) vkDestroyQueryPool(vk->device, g->queries, NULL);
    fv_vk_compute_fini(vk, &g->build);
    if (g->nearest) vkDestroySampler(vk->device, g->nearest, NULL);
    if (g->pipeline) vkDestroyPipeline(vk->device, g->pipeline, NULL);
    if (g->layout) vkDestroyPipelineLayout(vk->device, g->layout, NULL);
    for (uint32_t l = 0; l < FV_GI_MAX_LIGHTS; l++) {
        if (g->framebuffer[l]) vkDestroyFramebuffer(vk->device, g->framebuffer[l], NULL);
        for (uint32_t i = 0; i <= RSM_TARGETS; i++)
            if (g->layer_view[l][i]) vkDestroyImageView(vk->device, g->layer_view[l][i], NULL);
    }
    if (g->render_pass) vkDestroyRenderPass(vk->device, g->render_pass, NULL);
    for (uint32_t i = 0; i < RSM_TARGETS; i++) fv_vk_image_destroy(vk, &g->rsm[i]);
    fv_vk_image_destroy(vk, &g->depth);
    fv_vk_buffer_destroy(vk, &g->nodes);
    fv_vk_buffer_destroy(vk, &g->header);
    fv_vk_buffer_destroy(vk, &g->scan);
    for (uint32_t i = 0; i < FV_MAX_FRAMES_IN_FLIGHT; i++) {
        fv_vk_buffer_destroy(vk, &g->readback[i]);
        fv_vk_buffer_destroy(vk, &g->stats[i]);
        fv_vk_buffer_destroy(vk, &g->stats_readback[i]);
    }
    free(g);
}

static fv_result create_rsm(gi *g)
{
    fv_vk *vk = g->vk;
    static const char *const names[RSM_TARGETS] = {"gi rsm flux", "gi rsm position", "gi rsm normal"};
    for (uint32_t i = 0; i < RSM_TARGETS; i++) {
        fv_vk_image_desc d = {.width = g->n, .height = g->n, .layers = g->lights, .array = true,
                              .format = VK_FORMAT_R32G32B32A32_SFLOAT,
                              .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                       VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                              .name = names[i]};
        FV_TRY(fv_vk_image_create(vk, &d, &g->rsm[i]));
        /* readable before the first build (the build set samples every layer) */
        FV_TRY(fv_vk_image_set_layout(vk, &g->rsm[i], VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
    }
    fv_vk_image_desc dd = {.width = g->n, .height = g->n, .layers = g->lights, .array = true,
                           .format = VK_FORMAT_D32_SFLOAT, .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                           .name = "gi rsm depth"};
    FV_TRY(fv_vk_image_create(vk, &dd, &g->depth));
    VkAttachmentDescription att[RSM_TARGETS + 1];
    for (uint32_t i = 0; i < RSM_TARGETS; i++)
        att[i] = fv_vk_attachment_cleared(g->rsm[i].format, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    att[RSM_TARGETS] = fv_vk_attachment_cleared(VK_FORMAT_D32_SFLOAT, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    att[RSM_TARGETS].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    VkAttachmentReference color_refs[RSM_TARGETS];
    for (uint32_t i = 0; i < RSM_TARGETS; i++) color_refs[i] = (VkAttachmentReference){i, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depth_ref = {RSM_TARGETS, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub = {.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS,
                                .colorAttachmentCount = RSM_TARGETS, .pColorAttachments = color_refs,
                                .pDepthStencilAttachment = &depth_ref};
    VkSubpassDependency deps[2] = {
        /* Write-after-read and write-after-write: the previous build's leaf stage read these images in compute, and
         * the previous render pass instance wrote them; clear only after both. */
        {.srcSubpass = VK_SUBPASS_EXTERNAL, .dstSubpass = 0,
         .srcStageMask = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | ATTACH_STAGES, .dstStageMask = ATTACH_STAGES,
         .srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
         .dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                          VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT},
        /* Read-after-write: the leaf stage reads the RSM in compute. */
        {.srcSubpass = 0, .dstSubpass = VK_SUBPASS_EXTERNAL, .srcStageMask = ATTACH_STAGES,
         .dstStageMask = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
         .srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
         .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT},
    };
    VkRenderPassCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO, .attachmentCount = RSM_TARGETS + 1,
                                 .pAttachments = att, .subpassCount = 1, .pSubpasses = &sub, .dependencyCount = 2,
                                 .pDependencies = deps};
    FV_VK_CHECK(vkCreateRenderPass(vk->device, &ci, NULL, &g->render_pass));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_RENDER_PASS, g->render_pass, "gi rsm render pass");
    for (uint32_t l = 0; l < g->lights; l++) {
        for (uint32_t i = 0; i <= RSM_TARGETS; i++) {
            const fv_vk_image *img = i < RSM_TARGETS ? &g->rsm[i] : &g->depth;
            VkImageViewCreateInfo vi = {.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO, .image = img->image,
                                        .viewType = VK_IMAGE_VIEW_TYPE_2D, .format = img->format,
                                        .subresourceRange = {img->aspect, 0, 1, l, 1}};
            FV_VK_CHECK(vkCreateImageView(vk->device, &vi, NULL, &g->layer_view[l][i]));
            FV_VK_NAME(vk, VK_OBJECT_TYPE_IMAGE_VIEW, g->layer_view[l][i], "gi rsm attachment %u light %u", i, l);
        }
        VkFramebufferCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO, .renderPass = g->render_pass,
                                      .attachmentCount = RSM_TARGETS + 1, .pAttachments = g->layer_view[l],
                                      .width = g->n, .height = g->n, .layers = 1};
        FV_VK_CHECK(vkCreateFramebuffer(vk->device, &fi, NULL, &g->framebuffer[l]));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_FRAMEBUFFER, g->framebuffer[l], "gi rsm framebuffer light %u", l);
    }
    VkDescriptorSetLayout sets[2] = {g->scene->set_layout, g->scene->texture_layout};
    FV_TRY(fv_vk_pipeline_layout(vk, sets, 2, sizeof(struct fv_gi_rsm_push),
                                 VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, "gi rsm layout", &g->layout));
    const VkVertexInputBindingDescription *bind;
    const VkVertexInputAttributeDescription *attrs;
    uint32_t attr_count;
    fv_scene_gpu_vertex_input(&bind, &attrs, &attr_count);
    fv_vk_graphics_desc gd = {.vert = fv_spv_gi_rsm_vert, .vert_size = sizeof fv_spv_gi_rsm_vert,
                              .frag = fv_spv_gi_rsm_frag, .frag_size = sizeof fv_spv_gi_rsm_frag, .bindings = bind,
                              .binding_count = 1, .attributes = attrs, .attribute_count = attr_count,
                              .layout = g->layout, .render_pass = g->render_pass, .color_attachments = RSM_TARGETS,
                              .depth_test = true, .cull = VK_CULL_MODE_NONE, .name = "gi rsm"};
    return fv_vk_graphics_pipeline(vk, &gd, &g->pipeline);
}

static fv_result create_tree(gi *g)
{
    fv_vk *vk = g->vk;
    g->nodes_per_light = fv_gi_nodes_for(g->n);
    uint64_t nodes = (uint64_t)g->nodes_per_light * g->lights;
    uint64_t blocks = (nodes + FV_GI_BUILD_GROUP - 1) / FV_GI_BUILD_GROUP + 1;
    FV_TRY(fv_vk_buffer_create(vk, nodes * sizeof(fv_gi_node), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                               VK_BUFFER_USAGE_TRANSFER_SRC_BIT, FV_VK_MEM_DEVICE, "gi nodes", &g->nodes));
    /* the cut's room, then every node's walk record (fv_gi_cluster) */
    FV_TRY(fv_vk_buffer_create(vk, sizeof(fv_gi_header) + sizeof(fv_gi_cluster) * 2 * nodes,
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                               FV_VK_MEM_DEVICE, "gi header and cut", &g->header));
    FV_TRY(fv_vk_buffer_create(vk, 4 * (nodes + blocks), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, FV_VK_MEM_DEVICE,
                               "gi scan", &g->scan));
    for (uint32_t i = 0; i < g->slots; i++) {
        char name[40];
        snprintf(name, sizeof name, "gi header readback %u", i);
        FV_TRY(fv_vk_buffer_create(vk, sizeof(fv_gi_header), VK_BUFFER_USAGE_TRANSFER_DST_BIT, FV_VK_MEM_READBACK, name,
                                   &g->readback[i]));
        snprintf(name, sizeof name, "gi stats slot %u", i);
        FV_TRY(fv_vk_buffer_create(vk, sizeof(fv_gi_stats), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                   FV_VK_MEM_DEVICE, name, &g->stats[i]));
        snprintf(name, sizeof name, "gi stats readback %u", i);
        FV_TRY(fv_vk_buffer_create(vk, sizeof(fv_gi_stats), VK_BUFFER_USAGE_TRANSFER_DST_BIT, FV_VK_MEM_READBACK, name,
                                   &g->stats_readback[i]));
    }
    FV_TRY(fv_vk_sampler_create(vk, false, false, "gi rsm sampler (nearest)", &g->nearest));
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorSetLayoutBinding b[FV_GI_BUILD_BINDING_COUNT] = {
        {FV_GI_BUILD_BINDING_FLUX, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_GI_BUILD_BINDING_POS, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_GI_BUILD_BINDING_NORMAL, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_GI_BUILD_BINDING_NODES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
        {FV_GI_BUILD_BINDING_HEADER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
        {FV_GI_BUILD_BINDING_SCAN, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
    };
    fv_vk_compute_desc cd = {.name = "gi build", .code = fv_spv_gi_build_comp, .code_size = sizeof fv_spv_gi_build_comp,
                             .bindings = b, .binding_count = FV_GI_BUILD_BINDING_COUNT, .set_count = 1,
                             .push_bytes = sizeof(struct fv_gi_build_push)};
    FV_TRY(fv_vk_compute_init(vk, &cd, &g->build));
    VkDescriptorSet set = g->build.sets[0];
    for (uint32_t i = 0; i < RSM_TARGETS; i++)
        fv_vk_write_image(vk, set, FV_GI_BUILD_BINDING_FLUX + i, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                          g->rsm[i].view, g->nearest, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    fv_vk_write_buffer(vk, set, FV_GI_BUILD_BINDING_NODES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g->nodes.buffer, 0,
                       VK_WHOLE_SIZE);
    fv_vk_write_buffer(vk, set, FV_GI_BUILD_BINDING_HEADER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g->header.buffer, 0,
                       VK_WHOLE_SIZE);
    fv_vk_write_buffer(vk, set, FV_GI_BUILD_BINDING_SCAN, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, g->scan.buffer, 0,
                       VK_WHOLE_SIZE);
    if (vk->info.timestamps) {
        VkQueryPoolCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                                    .queryType = VK_QUERY_TYPE_TIMESTAMP, .queryCount = QUERIES * g->slots};
        FV_VK_CHECK(vkCreateQueryPool(vk->device, &qi, NULL, &g->queries));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_QUERY_POOL, g->queries, "gi stage timestamps");
    }
    return FV_OK;
}

static fv_result gi_init(const fv_pass_env *env, void **out_state)
{
    gi *g = calloc(1, sizeof *g);
    if (!g) return FV_ERR_NO_MEMORY;
    g->vk = env->vk;
    g->scene = env->scene;
    g->inputs = env->shade_inputs;
    g->slots = env->slots;
    uint32_t v = env->plan ? env->plan->variant : 8;
    g->n = 1u << (v & 15u);
    g->levels = fv_gi_log2(g->n) + 1;
    for (uint32_t l = 0; l < g->scene->light_count && g->lights < FV_GI_MAX_LIGHTS; l++) {
        uint32_t type = (uint32_t)(g->scene->lights[l].direction_type.w + 0.5f);
        if (type == FV_GPU_LIGHT_POINT) continue;
        g->light_index[g->lights] = l;
        g->kind[g->lights++] = type == FV_GPU_LIGHT_SPOT ? FV_GI_KIND_SPOT : FV_GI_KIND_DIRECTIONAL;
    }
    g->animated = fv_scene_is_animated(&g->scene->anim);
    fv_result res = g->lights ? FV_OK : FV_ERR_STATE;
    if (res == FV_OK) res = create_rsm(g);
    if (res == FV_OK) res = create_tree(g);
    if (res == FV_OK) res = fv_shade_inputs_bind_buffer(g->inputs, FV_GI_BINDING_HEADER, g->header.buffer, 0, VK_WHOLE_SIZE);
    if (res == FV_OK) res = fv_shade_inputs_bind_buffer(g->inputs, FV_GI_BINDING_NODES, g->nodes.buffer, 0, VK_WHOLE_SIZE);
    for (uint32_t i = 0; res == FV_OK && i < g->slots; i++)
        res = fv_shade_inputs_bind_stats(g->inputs, FV_GI_BINDING_STATS, i, g->stats[i].buffer, 0, sizeof(fv_gi_stats));
    if (res != FV_OK) {
        FV_ERROR(MOD, "GI (%u light%s, RSM %upx) could not be created: %s", g->lights, plural(g->lights), g->n,
                 fv_result_str(res));
        gi_fini(g);
        return res;
    }
    *out_state = g;
    return FV_OK;
}

/* ---- per frame ---------------------------------------------------------------------------------------------- */

/* What the rebuild recorded in `slot` reported (cut counts, stage times). `settled`: the slot's fence has signalled
 * (prepare); otherwise (details, e.g. after the last frame) only when its last timestamp is available, which comes
 * after the readback copy. */
static void collect(gi *g, uint32_t slot, bool settled)
{
    if (!g->built_in_slot[slot]) return;
    uint64_t t[BUILD_QUERIES];
    VkResult r = g->queries ? vkGetQueryPoolResults(g->vk->device, g->queries, slot * QUERIES, BUILD_QUERIES, sizeof t,
                                                    t, sizeof t[0], VK_QUERY_RESULT_64_BIT)
                            : VK_NOT_READY;
    if (!settled && r != VK_SUCCESS) return;
    g->built_in_slot[slot] = false;
    if (fv_vk_buffer_invalidate(g->vk, &g->readback[slot]) == FV_OK) {
        const fv_gi_header *h = g->readback[slot].mapped;
        g->cut_clusters = h->counts.w;
        g->lit_vpls = h->opts.z;
    }
    if (r != VK_SUCCESS) return;
    double period = g->vk->info.timestamp_period_ns > 0 ? g->vk->info.timestamp_period_ns : 1.0;
    for (int i = 0; i < 3; i++) g->stage_ms[i] = t[i + 1] >= t[i] ? (double)(t[i + 1] - t[i]) * period * 1e-6 : 0.0;
}

/* What the shading passes counted in the slot's last frame (fv_gi_stats, copied back at its end), kept when it is the
 * newest frame read so far. `settled` as for collect. */
static void collect_stats(gi *g, uint32_t slot, bool settled)
{
    if (!g->counted_in_slot[slot]) return;
    uint64_t t;
    VkResult r = g->queries ? vkGetQueryPoolResults(g->vk->device, g->queries, slot * QUERIES + QUERY_STATS, 1,
                                                    sizeof t, &t, sizeof t, VK_QUERY_RESULT_64_BIT)
                            : VK_NOT_READY;
    if (!settled && r != VK_SUCCESS) return;
    g->counted_in_slot[slot] = false;
    if (g->counted_seq[slot] < g->measured_seq || fv_vk_buffer_invalidate(g->vk, &g->stats_readback[slot]) != FV_OK)
        return;
    const fv_gi_stats *st = g->stats_readback[slot].mapped;
    double sum = (double)st->counts.x + 4294967296.0 * (double)st->counts.y, pixels = (double)st->counts.w;
    g->measured_seq = g->counted_seq[slot];
    g->measured = true;
    g->per_pixel_mean = pixels > 0 ? sum / pixels : 0.0; /* no pixel ran the gather: none summed */
    g->per_pixel_max = (double)st->counts.z;
    g->gathered_pixels = pixels;
}

static bool key_equal(const build_key *a, const build_key *b)
{
    return fv_quality_gi_equal(&a->q, &b->q) && memcmp(a->light, b->light, sizeof a->light) == 0 &&
           a->time_s == b->time_s && memcmp(&a->bmin, &b->bmin, sizeof a->bmin) == 0 &&
           memcmp(&a->bmax, &b->bmax, sizeof a->bmax) == 0;
}

static void gi_prepare(void *state, const fv_pass_frame *f)
{
    gi *g = state;
    collect(g, f->slot, true);
    collect_stats(g, f->slot, true);
    build_key k;
    memset(&k, 0, sizeof k);
    k.q = f->input->quality.gi;
    k.q.enabled = true;
    for (uint32_t l = 0; l < g->lights; l++)
        if (g->light_index[l] < g->scene->light_count) k.light[l] = g->scene->lights[g->light_index[l]];
    k.time_s = g->animated ? f->input->time_s : 0.0;
    if (!fv_scene_gpu_world_bounds(g->scene, f->input->time_s, &k.bmin, &k.bmax)) k.bmin = k.bmax = fv_v3(0, 0, 0);
    g->rebuild = !g->have_key || !key_equal(&k, &g->key);
    if (!g->rebuild) return;
    g->key = k;
    g->have_key = true;
    const fv_quality_gi *q = &k.q;
    uint32_t start, limit;
    fv_gi_tree_levels(g->n, q, &start, &limit);
    g->candidates = candidates_for(g->n, start, limit);
    fv_gi_header *h = &g->host;
    memset(h, 0, sizeof *h);
    h->counts = (fv_gpu_uvec4){1, (uint32_t)q->mode, g->lights, 0};
    h->tree = (fv_gpu_uvec4){g->n, g->levels, start, limit};
    float refine2 = q->refine > 0.0f && q->refine <= 1.0f ? q->refine * q->refine : 0.0f; /* NaN: off */
    uint32_t refine_bits;
    memcpy(&refine_bits, &refine2, sizeof refine_bits);
    h->opts = (fv_gpu_uvec4){q->samples ? q->samples : 1, g->nodes_per_light, 0, refine_bits};
    h->params = (fv_gpu_vec4){q->depth_threshold, q->normal_threshold, q->bound_fraction, (float)g->n * 1.41421356f};
    /* the gather rate (render/gi_gather): 1, 2 or 4 as its pass; anything else gathers per pixel */
    h->rate = (fv_gpu_uvec4){fv_gi_rate_factor((uint32_t)q->rate), 0, 0, 0};
    for (uint32_t l = 0; l < g->lights; l++) {
        light_view(&k.light[l], g->kind[l], g->n, k.bmin, k.bmax, &g->push[l]);
        g->push[l].ids.z = g->light_index[l];
        memcpy(h->light[l].view_proj.m, g->push[l].view_proj.m, sizeof h->light[l].view_proj.m);
        h->light[l].info = (fv_gpu_uvec4){g->kind[l], l * g->nodes_per_light, 0, 0};
    }
}

static void global_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags src_access,
                           VkPipelineStageFlags dst, VkAccessFlags dst_access)
{
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = src_access,
                          .dstAccessMask = dst_access};
    vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &mb, 0, NULL, 0, NULL);
}

#define RW (VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT)
#define CS VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT

static void dispatch(gi *g, VkCommandBuffer cmd, struct fv_gi_build_push *pc, uint32_t items, fv_pass_counters *c)
{
    uint32_t groups = (items + FV_GI_BUILD_GROUP - 1) / FV_GI_BUILD_GROUP;
    if (!groups) groups = 1;
    uint32_t gx = groups < 65535u ? groups : 65535u;
    uint32_t gy = (groups + gx - 1) / gx;
    pc->scan.w = items;
    fv_vk_compute_bind(&g->build, cmd, 0, NULL, 0, 0, pc);
    vkCmdDispatch(cmd, gx, gy, 1);
    c->dispatches++;
}

static void timestamp(gi *g, VkCommandBuffer cmd, uint32_t slot, uint32_t i)
{
    if (g->queries) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, g->queries, slot * QUERIES + i);
}

/* A barrier on the whole of one small buffer. */
static void buffer_barrier(VkCommandBuffer cmd, VkBuffer b, VkPipelineStageFlags src, VkAccessFlags src_access,
                           VkPipelineStageFlags dst, VkAccessFlags dst_access)
{
    VkBufferMemoryBarrier bb = {.sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER, .srcAccessMask = src_access,
                                .dstAccessMask = dst_access, .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED, .buffer = b, .size = VK_WHOLE_SIZE};
    vkCmdPipelineBarrier(cmd, src, dst, 0, 0, NULL, 1, &bb, 0, NULL);
}

static void gi_record(void *state, const fv_pass_frame *f)
{
    gi *g = state;
    VkCommandBuffer cmd = f->cmd;
    /* The slot's stats start at zero each frame, before any shading pass counts into them (compute atomics). The
     * slot's last frame wrote them in shading and read them in its copy back: both finish before the clear. */
    VkBuffer stats = g->stats[f->slot].buffer;
    buffer_barrier(cmd, stats, CS | VK_PIPELINE_STAGE_TRANSFER_BIT,
                   VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                   VK_ACCESS_TRANSFER_WRITE_BIT);
    vkCmdFillBuffer(cmd, stats, 0, sizeof(fv_gi_stats), 0);
    buffer_barrier(cmd, stats, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, CS, RW);
    if (g->queries) vkCmdResetQueryPool(cmd, g->queries, f->slot * QUERIES + QUERY_STATS, 1);
    if (!g->rebuild) return;
    g->rebuild = false;
    fv_vk_label_begin(g->vk, cmd, "gi rebuild (rsm, pyramid, cut)");
    if (g->queries) vkCmdResetQueryPool(cmd, g->queries, f->slot * QUERIES, BUILD_QUERIES);
    timestamp(g, cmd, f->slot, 0);
    /* Earlier frames' shading read the header and the nodes (compute, fragment) and earlier builds wrote them:
     * wait for both before the header is rewritten and the tree rebuilt. */
    global_barrier(cmd, READER_STAGES | VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_TRANSFER_BIT | CS, VK_ACCESS_TRANSFER_WRITE_BIT | RW);
    vkCmdUpdateBuffer(cmd, g->header.buffer, 0, sizeof g->host, &g->host);
    for (uint32_t l = 0; l < g->lights; l++) {
        VkClearValue clears[RSM_TARGETS + 1];
        memset(clears, 0, sizeof clears);
        clears[RSM_TARGETS].depthStencil.depth = 1.0f;
        VkRenderPassBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO, .renderPass = g->render_pass,
                                    .framebuffer = g->framebuffer[l], .renderArea = {{0, 0}, {g->n, g->n}},
                                    .clearValueCount = RSM_TARGETS + 1, .pClearValues = clears};
        vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
        VkViewport vp = {0, 0, (float)g->n, (float)g->n, 0.0f, 1.0f};
        VkRect2D sc = {{0, 0}, {g->n, g->n}};
        vkCmdSetViewport(cmd, 0, 1, &vp);
        vkCmdSetScissor(cmd, 0, 1, &sc);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, g->pipeline);
        VkShaderStageFlags st = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
        vkCmdPushConstants(cmd, g->layout, st, 0, sizeof g->push[l], &g->push[l]);
        uint32_t n = fv_scene_gpu_record_draws(g->scene, cmd, g->layout, st, f->slot, l);
        f->counters->draws += n;
        f->counters->triangles += g->scene->triangle_count;
        vkCmdEndRenderPass(cmd);
    }
    timestamp(g, cmd, f->slot, 1);
    /* The header update (transfer) is read and completed by the build's compute stages. */
    global_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, CS, RW);
    const fv_quality_gi *q = &g->key.q;
    struct fv_gi_build_push pc;
    memset(&pc, 0, sizeof pc);
    pc.ids = (fv_gpu_uvec4){FV_GI_STAGE_LEAF, 0, g->n, g->levels};
    pc.tree = (fv_gpu_uvec4){g->host.tree.z, g->host.tree.w, g->lights, g->nodes_per_light};
    pc.params = (fv_gpu_vec4){q->depth_threshold, q->normal_threshold, q->average == FV_GI_AVERAGE_PLAIN ? 1.0f : 0.0f,
                              0};
    uint32_t all = g->candidates * g->lights;
    pc.scan = (fv_gpu_uvec4){g->candidates, all, (all + FV_GI_BUILD_GROUP - 1) / FV_GI_BUILD_GROUP, 0};
    dispatch(g, cmd, &pc, g->n * g->n * g->lights, f->counters);
    for (uint32_t k = 0; k + 1 < g->levels; k++) {
        /* each level reads the one below it */
        global_barrier(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT, CS, RW);
        pc.ids.x = FV_GI_STAGE_REDUCE;
        pc.ids.y = k;
        uint32_t s = g->n >> (k + 1);
        dispatch(g, cmd, &pc, s * s * g->lights, f->counters);
    }
    global_barrier(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT, CS, RW);
    pc.ids.x = FV_GI_STAGE_WALK; /* reads the finished pyramid; the cut's stages do not read what it writes */
    dispatch(g, cmd, &pc, g->nodes_per_light * g->lights, f->counters);
    global_barrier(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT, CS, RW);
    timestamp(g, cmd, f->slot, 2);
    pc.ids.x = FV_GI_STAGE_SCAN_LOCAL;
    dispatch(g, cmd, &pc, pc.scan.z * FV_GI_BUILD_GROUP, f->counters);
    global_barrier(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT, CS, RW);
    pc.ids.x = FV_GI_STAGE_SCAN_BLOCKS;
    dispatch(g, cmd, &pc, FV_GI_BUILD_GROUP, f->counters);
    global_barrier(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT, CS, RW);
    pc.ids.x = FV_GI_STAGE_SCATTER;
    dispatch(g, cmd, &pc, all, f->counters);
    /* Shading (compute or fragment) reads the header, the cut and the nodes; the host reads the cut counts. */
    global_barrier(cmd, CS, VK_ACCESS_SHADER_WRITE_BIT, READER_STAGES | VK_PIPELINE_STAGE_TRANSFER_BIT,
                   VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
    VkBufferCopy copy = {0, 0, sizeof(fv_gi_header)};
    vkCmdCopyBuffer(cmd, g->header.buffer, g->readback[f->slot].buffer, 1, &copy);
    VkMemoryBarrier host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                            .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &host, 0, NULL, 0, NULL);
    timestamp(g, cmd, f->slot, 3);
    g->built_in_slot[f->slot] = true;
    g->rebuilds++;
    fv_vk_label_end(g->vk, cmd);
}

/* After the frame's shading: the stats the shading passes counted -> the slot's readback buffer, for the host after
 * the slot's fence (collect_stats); the timestamp after the copy tells details() it is done. */
static void gi_record_end(void *state, const fv_pass_frame *f)
{
    gi *g = state;
    VkCommandBuffer cmd = f->cmd;
    buffer_barrier(cmd, g->stats[f->slot].buffer, CS, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                   VK_ACCESS_TRANSFER_READ_BIT);
    VkBufferCopy copy = {0, 0, sizeof(fv_gi_stats)};
    vkCmdCopyBuffer(cmd, g->stats[f->slot].buffer, g->stats_readback[f->slot].buffer, 1, &copy);
    buffer_barrier(cmd, g->stats_readback[f->slot].buffer, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    timestamp(g, cmd, f->slot, QUERY_STATS);
    g->counted_in_slot[f->slot] = true;
    g->counted_seq[f->slot] = ++g->frames_counted;
}

/* Clusters (or tree nodes, or samples) summed per pixel that ran the gather in the newest frame read back: the mean,
 * the most, and the pixels, as the shading passes counted them on the GPU (fv_gi_stats), in every mode. NaN before
 * any frame was read back. */
static void clusters_per_pixel(const gi *g, double *out_mean, double *out_max, double *out_pixels)
{
    *out_mean = g->measured ? g->per_pixel_mean : NAN;
    *out_max = g->measured ? g->per_pixel_max : NAN;
    *out_pixels = g->measured ? g->gathered_pixels : NAN;
}

static uint32_t gi_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    gi *g = state;
    for (uint32_t s = 0; s < g->slots; s++) {
        collect(g, s, false);
        collect_stats(g, s, false);
    }
    const char *keys[] = {"rsm_ms", "pyramid_ms", "cut_ms", "cut_clusters", "lit_vpls", "rebuilds", "rsm_size", "lights"};
    double vals[] = {g->stage_ms[0], g->stage_ms[1], g->stage_ms[2], (double)g->cut_clusters, (double)g->lit_vpls,
                     (double)g->rebuilds, (double)g->n, (double)g->lights};
    uint32_t n = 0;
    for (uint32_t i = 0; i < sizeof vals / sizeof vals[0] && n < cap; i++, n++) {
        snprintf(out[n].key, sizeof out[n].key, "%s", keys[i]);
        out[n].value[0] = vals[i];
        out[n].count = 1;
    }
    if (n < cap) {
        snprintf(out[n].key, sizeof out[n].key, "clusters_per_pixel");
        clusters_per_pixel(g, &out[n].value[0], &out[n].value[1], &out[n].value[2]);
        out[n++].count = 3;
    }
    return n;
}

static fv_result read_buffer(fv_vk *vk, const fv_vk_buffer *src, VkDeviceSize offset, void *out, VkDeviceSize size)
{
    if (!size) return FV_OK;
    fv_vk_buffer rb;
    FV_TRY(fv_vk_buffer_create(vk, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, FV_VK_MEM_READBACK, "gi test readback", &rb));
    VkCommandBuffer cmd;
    fv_result res = fv_vk_oneshot_begin(vk, "gi test readback", &cmd);
    if (res == FV_OK) {
        /* the frame's writes were made visible to transfer reads at the end of the rebuild; the GPU is idle */
        VkBufferCopy c = {offset, 0, size};
        vkCmdCopyBuffer(cmd, src->buffer, rb.buffer, 1, &c);
        VkMemoryBarrier host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                                .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &host, 0, NULL, 0, NULL);
        res = fv_vk_oneshot_end(vk, cmd);
    }
    if (res == FV_OK) res = fv_vk_buffer_invalidate(vk, &rb);
    if (res == FV_OK) memcpy(out, rb.mapped, size);
    fv_vk_buffer_destroy(vk, &rb);
    return res;
}

fv_result fv_gi_read_tree(void *state, fv_gi_header *out_header, fv_gi_node *out_nodes, size_t node_cap,
                          uint32_t *out_cut, size_t cut_cap, uint32_t *out_nodes_per_light)
{
    gi *g = state;
    if (!g) return FV_ERR_INVALID_ARG;
    if (out_nodes_per_light) *out_nodes_per_light = g->nodes_per_light;
    uint64_t nodes = (uint64_t)g->nodes_per_light * g->lights;
    if (out_header) FV_TRY(read_buffer(g->vk, &g->header, 0, out_header, sizeof *out_header));
    if (out_nodes)
        FV_TRY(read_buffer(g->vk, &g->nodes, 0, out_nodes, (node_cap < nodes ? node_cap : nodes) * sizeof(fv_gi_node)));
    if (out_cut) {
        size_t n = cut_cap < nodes ? cut_cap : nodes;
        fv_gi_cluster *c = n ? calloc(n, sizeof *c) : NULL;
        if (n && !c) return FV_ERR_NO_MEMORY;
        fv_result res = read_buffer(g->vk, &g->header, sizeof(fv_gi_header), c, n * sizeof *c);
        /* each entry names its walk record (fv_gi_cluster); back to the node's index in the tree */
        for (size_t i = 0; res == FV_OK && i < n; i++) {
            uint64_t w = (uint64_t)c[i].normal.w;
            uint64_t rel = w >= nodes ? w - nodes : 0, l = rel / g->nodes_per_light;
            out_cut[i] = (uint32_t)(l * g->nodes_per_light +
                                    fv_gi_walk_node(g->n, (uint32_t)(rel - l * g->nodes_per_light)));
        }
        free(c);
        FV_TRY(res);
    }
    return FV_OK;
}

fv_result fv_gi_read_walk(void *state, fv_gi_cluster *out, size_t cap)
{
    gi *g = state;
    if (!g || !out) return FV_ERR_INVALID_ARG;
    uint64_t nodes = (uint64_t)g->nodes_per_light * g->lights;
    size_t n = cap < nodes ? cap : nodes;
    return n ? read_buffer(g->vk, &g->header, sizeof(fv_gi_header) + nodes * sizeof(fv_gi_cluster), out,
                           n * sizeof *out)
             : FV_OK;
}

const fv_pass fv_gi_pass = {
    .id = "gi",
    .plan = gi_plan,
    .init = gi_init,
    .prepare = gi_prepare,
    .record = gi_record,
    .record_end = gi_record_end,
    .fini = gi_fini,
    .details = gi_details,
};
