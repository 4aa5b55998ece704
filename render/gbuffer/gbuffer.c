/* @brief The stereo G-buffer pass (see gbuffer.h). */
#include "gbuffer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gbuffer_frag.spv.h"
#include "gbuffer_surface_frag.spv.h"
#include "gbuffer_interface.h"
#include "gbuffer_mask.h"
#include "gbuffer_vert.spv.h"

#define MOD "gbuffer"
#define TARGETS 6 /* at most: the motion target only when asked for (FV_GBUFFER_VARIANT_MOTION), the surface target
                   * only while foveation runs (FV_GBUFFER_VARIANT_SURFACE) */
#define MOTION 4   /* targets[]: the motion target's slot (its colour location, FV_GBUFFER_OUT_MOTION, + 1) */

static const fv_image_id targets[TARGETS] = {FV_IMAGE_DEPTH, FV_IMAGE_NORMAL, FV_IMAGE_ALBEDO, FV_IMAGE_MATERIAL,
                                             FV_IMAGE_MOTION, FV_IMAGE_SURFACE};

#define COLOR_LAYOUT VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL
#define DEPTH_LAYOUT VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL
#define ATTACH_STAGES                                                                                                  \
    (VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |                     \
     VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT)
/* What the render pass's external dependencies cover: earlier reads (before) and later reads (after). */
#define READER_STAGES                                                                                                  \
    (VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT)

typedef struct gbuffer {
    fv_vk *vk;
    fv_scene_gpu *scene;
    fv_images *images;
    uint32_t width, height;
    bool multiview;
    const fv_vk_image *img[TARGETS];
    VkRenderPass render_pass;
    VkFramebuffer framebuffer;        /* multiview: all layers */
    VkFramebuffer eye_framebuffer[2]; /* per-eye passes: one layer each */
    VkImageView eye_views[2][TARGETS];
    VkPipelineLayout layout;
    VkPipeline pipeline;
    bool masked;        /* the hidden-area mask is drawn (FV_GBUFFER_VARIANT_MASK) */
    uint32_t n;         /* target slots: TARGETS with the surface target (FV_GBUFFER_VARIANT_SURFACE), else one fewer */
    bool drawn[TARGETS]; /* per slot: the target is an attachment (else its colour location is unused) */
    uint32_t attachments; /* the drawn ones */
    gbuffer_mask mask;
} gbuffer;

static void gbuffer_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    uint32_t draws = 0;
    uint64_t triangles = 0;
    const fv_scene *s = ctx->scene;
    for (uint32_t i = 0; s && i < s->node_count; i++) {
        const fv_node *n = &s->nodes[i];
        if (n->mesh < 0 || (uint32_t)n->mesh >= s->mesh_count) continue;
        draws++;
        triangles += s->meshes[n->mesh].index_count / 3;
    }
    out->enabled = true;
    out->variant = (gbuffer_mask_wanted(ctx->quality) ? FV_GBUFFER_VARIANT_MASK : 0u) |
                   (ctx->quality->fovea.enabled ? FV_GBUFFER_VARIANT_SURFACE : 0u) |
                   (ctx->motion_target ? FV_GBUFFER_VARIANT_MOTION : 0u);
    snprintf(out->reason, sizeof out->reason, "always: stereo G-buffer, %s (%llu triangle%s in %u draw%s)%s%s",
             ctx->multiview ? "both eyes in one multiview pass" : (ctx->multiview_why ? ctx->multiview_why : "one pass per eye"),
             (unsigned long long)triangles, triangles == 1 ? "" : "s", draws, draws == 1 ? "" : "s",
             out->variant & FV_GBUFFER_VARIANT_MASK ? "; hidden-area mask of the HMD lens" : "",
             out->variant & FV_GBUFFER_VARIANT_MOTION ? "; motion vectors kept for read-back" : "");
}

static fv_result create_render_pass(gbuffer *gb)
{
    fv_vk *vk = gb->vk;
    VkAttachmentDescription att[TARGETS];
    uint32_t index[TARGETS], na = 0; /* per slot: its attachment, or unused */
    for (uint32_t i = 0; i < gb->n; i++) {
        index[i] = gb->drawn[i] ? na : VK_ATTACHMENT_UNUSED;
        if (gb->drawn[i]) att[na++] = fv_vk_attachment_cleared(gb->img[i]->format, i == 0 ? DEPTH_LAYOUT : COLOR_LAYOUT);
    }
    VkAttachmentReference depth_ref = {0, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkAttachmentReference color_refs[TARGETS - 1];
    for (uint32_t i = 0; i < gb->n - 1; i++)
        color_refs[i] = (VkAttachmentReference){index[i + 1], VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub = {
        .pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS,
        .colorAttachmentCount = gb->n - 1,
        .pColorAttachments = color_refs,
        .pDepthStencilAttachment = &depth_ref,
    };
    VkSubpassDependency deps[2] = {
        /* Write-after-read: earlier reads of these images (shading in compute or fragment shaders, readbacks) are
         * done before this frame clears them. Execution dependency only; the layout transition from UNDEFINED
         * discards the old contents. Readers at other stages get a barrier from the image table. */
        {.srcSubpass = VK_SUBPASS_EXTERNAL,
         .dstSubpass = 0,
         .srcStageMask = READER_STAGES,
         .dstStageMask = ATTACH_STAGES,
         .srcAccessMask = 0,
         .dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                          VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT},
        /* Read-after-write: later passes read the G-buffer in compute or fragment shaders; transfers read it back. */
        {.srcSubpass = 0,
         .dstSubpass = VK_SUBPASS_EXTERNAL,
         .srcStageMask = ATTACH_STAGES,
         .dstStageMask = READER_STAGES,
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
        .attachmentCount = na,
        .pAttachments = att,
        .subpassCount = 1,
        .pSubpasses = &sub,
        .dependencyCount = 2,
        .pDependencies = deps,
    };
    FV_VK_CHECK(vkCreateRenderPass(vk->device, &ci, NULL, &gb->render_pass));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_RENDER_PASS, gb->render_pass, "gbuffer render pass (%s)",
               gb->multiview ? "multiview 0b11" : "one eye");
    VkFramebufferCreateInfo fi = {
        .sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
        .renderPass = gb->render_pass,
        .attachmentCount = na,
        .width = gb->width,
        .height = gb->height,
        .layers = 1, /* multiview: the view mask selects the layers; per eye: one layer */
    };
    if (gb->multiview) {
        VkImageView views[TARGETS];
        for (uint32_t i = 0, k = 0; i < gb->n; i++)
            if (gb->drawn[i]) views[k++] = gb->img[i]->view;
        fi.pAttachments = views;
        FV_VK_CHECK(vkCreateFramebuffer(vk->device, &fi, NULL, &gb->framebuffer));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_FRAMEBUFFER, gb->framebuffer, "gbuffer framebuffer (both eyes)");
        return FV_OK;
    }
    for (uint32_t e = 0; e < 2; e++) {
        for (uint32_t i = 0, k = 0; i < gb->n; i++) {
            if (!gb->drawn[i]) continue;
            VkImageViewCreateInfo vi = {
                .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
                .image = gb->img[i]->image,
                .viewType = VK_IMAGE_VIEW_TYPE_2D,
                .format = gb->img[i]->format,
                .subresourceRange = {gb->img[i]->aspect, 0, 1, e, 1},
            };
            FV_VK_CHECK(vkCreateImageView(vk->device, &vi, NULL, &gb->eye_views[e][k]));
            FV_VK_NAME(vk, VK_OBJECT_TYPE_IMAGE_VIEW, gb->eye_views[e][k], "gbuffer attachment %u eye %u", i, e);
            k++;
        }
        fi.pAttachments = gb->eye_views[e];
        FV_VK_CHECK(vkCreateFramebuffer(vk->device, &fi, NULL, &gb->eye_framebuffer[e]));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_FRAMEBUFFER, gb->eye_framebuffer[e], "gbuffer framebuffer (eye %u)", e);
    }
    return FV_OK;
}

static fv_result create_pipeline(gbuffer *gb)
{
    fv_vk *vk = gb->vk;
    VkDescriptorSetLayout sets[2] = {gb->scene->set_layout, gb->scene->texture_layout};
    FV_TRY(fv_vk_pipeline_layout(vk, sets, 2, FV_SCENE_DRAW_PUSH_BYTES,
                                 VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, "gbuffer layout",
                                 &gb->layout));
    const VkVertexInputBindingDescription *bind;
    const VkVertexInputAttributeDescription *attrs;
    uint32_t attr_count;
    fv_scene_gpu_vertex_input(&bind, &attrs, &attr_count);
    uint32_t use_multiview = gb->multiview ? 1u : 0u;
    fv_vk_graphics_desc gd = {
        .vert = fv_spv_gbuffer_vert,
        .vert_size = sizeof fv_spv_gbuffer_vert,
        .frag = gb->n == TARGETS ? fv_spv_gbuffer_surface_frag : fv_spv_gbuffer_frag,
        .frag_size = gb->n == TARGETS ? sizeof fv_spv_gbuffer_surface_frag : sizeof fv_spv_gbuffer_frag,
        .bindings = bind,
        .binding_count = 1,
        .attributes = attrs,
        .attribute_count = attr_count,
        .layout = gb->layout,
        .render_pass = gb->render_pass,
        .color_attachments = gb->n - 1,
        .depth_test = true,
        .cull = VK_CULL_MODE_NONE, /* file winding is not trusted; the fragment shader faces normals to the eye */
        .spec = &use_multiview,
        .spec_count = 1,
        .name = gb->multiview ? "gbuffer pipeline (multiview)" : "gbuffer pipeline (per eye)",
    };
    return fv_vk_graphics_pipeline(vk, &gd, &gb->pipeline);
}

static void gbuffer_fini(void *state)
{
    gbuffer *gb = state;
    if (!gb) return;
    fv_vk *vk = gb->vk;
    if (gb->pipeline) vkDestroyPipeline(vk->device, gb->pipeline, NULL);
    if (gb->layout) vkDestroyPipelineLayout(vk->device, gb->layout, NULL);
    if (gb->framebuffer) vkDestroyFramebuffer(vk->device, gb->framebuffer, NULL);
    for (int e = 0; e < 2; e++) {
        if (gb->eye_framebuffer[e]) vkDestroyFramebuffer(vk->device, gb->eye_framebuffer[e], NULL);
        for (int i = 0; i < TARGETS; i++)
            if (gb->eye_views[e][i]) vkDestroyImageView(vk->device, gb->eye_views[e][i], NULL);
    }
    if (gb->render_pass) vkDestroyRenderPass(vk->device, gb->render_pass, NULL);
    gbuffer_mask_fini(&gb->mask);
    free(gb);
}

static fv_result gbuffer_init(const fv_pass_env *env, void **out_state)
{
    gbuffer *gb = calloc(1, sizeof *gb);
    if (!gb) return FV_ERR_NO_MEMORY;
    gb->vk = env->vk;
    gb->scene = env->scene;
    gb->images = env->images;
    gb->width = env->width;
    gb->height = env->height;
    gb->multiview = env->multiview;
    fv_result res = FV_OK;
    uint32_t variant = env->plan ? env->plan->variant : 0u;
    gb->masked = (variant & FV_GBUFFER_VARIANT_MASK) != 0;
    gb->n = variant & FV_GBUFFER_VARIANT_SURFACE ? TARGETS : TARGETS - 1; /* the surface target is the last */
    for (uint32_t i = 0; i < gb->n; i++) {
        gb->drawn[i] = i != MOTION || (variant & FV_GBUFFER_VARIANT_MOTION);
        gb->attachments += gb->drawn[i];
    }
    for (uint32_t i = 0; res == FV_OK && i < gb->n; i++)
        if (gb->drawn[i]) res = fv_images_get(env->images, targets[i], &gb->img[i]);
    if (res == FV_OK) res = create_render_pass(gb);
    if (res == FV_OK) res = create_pipeline(gb);
    if (res == FV_OK && gb->masked)
        res = gbuffer_mask_init(&gb->mask, env->vk, gb->render_pass, gb->multiview, env->slots, env->width,
                                env->height, gb->n - 1);
    if (res != FV_OK) {
        FV_ERROR(MOD, "G-buffer %ux%u x2 could not be created: %s", env->width, env->height, fv_result_str(res));
        gbuffer_fini(gb);
        return res;
    }
    *out_state = gb;
    return FV_OK;
}

static void record_pass(gbuffer *gb, const fv_pass_frame *f, VkFramebuffer fb, uint32_t eye)
{
    VkCommandBuffer cmd = f->cmd;
    VkClearValue clears[TARGETS];
    memset(clears, 0, sizeof clears);
    clears[0].depthStencil.depth = 1.0f;
    VkRenderPassBeginInfo bi = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
        .renderPass = gb->render_pass,
        .framebuffer = fb,
        .renderArea = {{0, 0}, {gb->width, gb->height}},
        .clearValueCount = gb->attachments,
        .pClearValues = clears,
    };
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    VkViewport vp = {0, 0, (float)gb->width, (float)gb->height, 0.0f, 1.0f};
    VkRect2D sc = {{0, 0}, {gb->width, gb->height}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
    if (gb->masked) {
        /* First, at depth 0: the pixels the lens never shows, so no scene fragment there passes the depth test. */
        uint32_t t = gbuffer_mask_record(&gb->mask, cmd, f->slot, gb->multiview ? -1 : (int)eye);
        f->counters->draws += t ? 1 : 0;
        f->counters->triangles += t;
    }
    if (gb->scene->loaded && gb->scene->draw_count) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, gb->pipeline);
        uint32_t n = fv_scene_gpu_record_draws(gb->scene, cmd, gb->layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                                       f->slot, eye);
        uint32_t views = gb->multiview ? 2u : 1u;
        f->counters->draws += n;
        f->counters->triangles += gb->scene->triangle_count * views;
    }
    vkCmdEndRenderPass(cmd);
}

static void gbuffer_record(void *state, const fv_pass_frame *f)
{
    gbuffer *gb = state;
    /* Earlier users of the targets that the render pass's own dependency does not wait for get a barrier first. */
    for (uint32_t i = 0; i < gb->n; i++)
        if (gb->drawn[i])
            fv_images_render_pass(f->images, f->cmd, targets[i], READER_STAGES,
                              (fv_vk_image_use){i == 0 ? DEPTH_LAYOUT : COLOR_LAYOUT, ATTACH_STAGES,
                                                i == 0 ? VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT
                                                       : VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT},
                              READER_STAGES);
    if (gb->multiview) {
        fv_vk_label_begin(gb->vk, f->cmd, "gbuffer (multiview, both eyes)");
        record_pass(gb, f, gb->framebuffer, 0);
        fv_vk_label_end(gb->vk, f->cmd);
        return;
    }
    for (uint32_t e = 0; e < 2; e++) {
        fv_vk_label_begin(gb->vk, f->cmd, e == 0 ? "gbuffer (left eye)" : "gbuffer (right eye)");
        record_pass(gb, f, gb->eye_framebuffer[e], e);
        fv_vk_label_end(gb->vk, f->cmd);
    }
}

static void gbuffer_prepare(void *state, const fv_pass_frame *f)
{
    gbuffer *gb = state;
    if (gb->masked) gbuffer_mask_prepare(&gb->mask, f->slot, f->input);
}

static uint32_t gbuffer_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    gbuffer *gb = state;
    if (!gb->masked || cap < 1) return 0;
    memset(out, 0, sizeof *out);
    snprintf(out->key, sizeof out->key, "mask.fraction");
    out->value[0] = gb->mask.fraction[0];
    out->value[1] = gb->mask.fraction[1];
    out->count = 2;
    return 1;
}

const fv_pass fv_gbuffer_pass = {
    .id = "gbuffer",
    .plan = gbuffer_plan,
    .init = gbuffer_init,
    .prepare = gbuffer_prepare,
    .record = gbuffer_record,
    .fini = gbuffer_fini,
    .details = gbuffer_details,
};
