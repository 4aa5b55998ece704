/* @brief The shadow pass (see shadow.h). */
#include "shadow.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_shadow_math.h"
#include "shadow_frag.spv.h"
#include "shadow_vert.spv.h"

#define MOD "shadow"
#define PUSH_BYTES 80 /* { uint draw, view, pad, pad; mat4 view_proj } */
#define DEPTH_STAGES (VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT)
#define READER_STAGES (VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT)

typedef struct light_entry {
    uint32_t kind;      /* FV_SHADOW_KIND_* */
    uint32_t first_map; /* its first layer */
    uint32_t max_maps;  /* layers reserved */
} light_entry;

typedef struct light_range {
    bool valid;
    uint32_t splits;
    double near_m, far_m, splits_m[FV_SHADOW_SPLITS_MAX + 1];
} light_range;

typedef struct slot_maps {
    uint32_t count;                          /* maps drawn this frame (layers 0..count-1 may be sparse) */
    bool used[FV_SHADOW_MAX_MAPS];
    fv_mat4 view_proj[FV_SHADOW_MAX_MAPS];
} slot_maps;

typedef struct shadow {
    fv_vk *vk;
    fv_scene_gpu *scene;
    fv_images *images;
    fv_shade_inputs *inputs;
    uint32_t res, splits_max, layers;
    bool shared;
    light_entry light[FV_SHADOW_MAX_LIGHTS];
    uint32_t light_count;
    fv_image_id map_id;
    const fv_vk_image *map;
    VkRenderPass render_pass;
    VkImageView layer_view[FV_SHADOW_MAX_MAPS];
    VkFramebuffer framebuffer[FV_SHADOW_MAX_MAPS];
    VkPipelineLayout layout;
    VkPipeline pipeline;
    slot_maps slot[FV_MAX_FRAMES_IN_FLIGHT];
    light_range last[FV_SHADOW_MAX_LIGHTS]; /* the cascades of the last prepared frame, for details */
} shadow;

static const char *plural(uint64_t n) { return n == 1 ? "" : "s"; }

static const char *filter_name(fv_shadow_filter f)
{
    return f == FV_SHADOW_FILTER_PCF5 ? "pcf5" : (f == FV_SHADOW_FILTER_PCF3 ? "pcf3" : "no filter");
}

/* The one rule the plan and init share: the maps a light of `type` (FV_LIGHT_* == FV_GPU_LIGHT_*) gets, appended
 * after `*layers` while they fit. */
static light_entry entry_for(uint32_t type, const fv_quality_shadow *q, uint32_t *layers)
{
    light_entry e = {.kind = FV_SHADOW_KIND_NONE};
    uint32_t kind = type == FV_GPU_LIGHT_DIRECTIONAL ? FV_SHADOW_KIND_CASCADES
                    : type == FV_GPU_LIGHT_SPOT      ? FV_SHADOW_KIND_PERSPECTIVE
                                                     : FV_SHADOW_KIND_CUBE;
    uint32_t want = kind == FV_SHADOW_KIND_CASCADES ? q->splits * (q->stereo_shared ? 1u : 2u)
                    : kind == FV_SHADOW_KIND_PERSPECTIVE ? 1u
                                                          : 6u;
    if (*layers + want <= FV_SHADOW_MAX_MAPS) {
        e = (light_entry){.kind = kind, .first_map = *layers, .max_maps = want};
        *layers += want;
    }
    return e;
}

/* What the plan sees: how many lights of each type, and the layers their maps take. */
static uint32_t layout_lights(const fv_scene *s, const fv_quality_shadow *q, uint32_t *out_layers, uint32_t counts[3])
{
    uint32_t n = 0, layers = 0;
    counts[0] = counts[1] = counts[2] = 0;
    uint32_t lights = s ? s->light_count : 0;
    for (uint32_t l = 0; l < lights; l++) {
        fv_light_type t = s->lights[l].type;
        if ((unsigned)t < 3) counts[t]++;
        if (l >= FV_SHADOW_MAX_LIGHTS) continue;
        (void)entry_for((uint32_t)t, q, &layers);
        n++;
    }
    *out_layers = layers;
    return n;
}

static void shadow_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    const fv_quality_shadow *q = &ctx->quality->shadow;
    const fv_scene *s = ctx->scene;
    uint32_t lights = s ? s->light_count : 0;
    if (!lights) {
        out->enabled = false;
        snprintf(out->reason, sizeof out->reason, "off — no lights");
        return;
    }
    if (!q->enabled) {
        out->enabled = false;
        snprintf(out->reason, sizeof out->reason, "off — shadow.enabled is false: %u light%s unshadowed", lights,
                 plural(lights));
        return;
    }
    uint32_t layers = 0, counts[3];
    layout_lights(s, q, &layers, counts);
    out->enabled = true;
    /* Re-initialise when what the maps are made of changes (size, layers); the rest is read per frame. */
    uint32_t res_log2 = 0;
    while ((1u << res_log2) < q->resolution_px && res_log2 < 31) res_log2++;
    out->variant = res_log2 | (layers << 5) | ((uint32_t)q->stereo_shared << 12) | (q->splits << 13);
    char what[FV_PASS_REASON_MAX];
    int n = 0;
    what[0] = '\0';
    if (counts[FV_LIGHT_DIRECTIONAL]) {
        /* How deep the scene is from the head: a shallow range deserves fewer splits (decided per frame too). */
        fv_vec3 bmin, bmax;
        uint32_t m = q->splits;
        double dn = 0, df = 0;
        if (fv_scene_world_bounds(s, 0.0, &bmin, &bmax)) {
            fv_head_pose head = {.position_m = s->head.position_m, .orientation = s->head.orientation,
                                 .ipd_mm = s->head.ipd_mm};
            fv_eye_view eyes[2];
            float near_m, far_m; /* the planes the renderer will use for this head (fv_renderer_frame_input) */
            fv_near_far_from_bounds(&head, bmin, bmax, &near_m, &far_m);
            fv_eye_views_build(&head, near_m, far_m, 0, 0, eyes);
            if (fv_shadow_depth_range(&eyes[0].view, bmin, bmax, near_m, far_m, &dn, &df))
                m = fv_shadow_splits_for_range(dn, df, q->splits);
        }
        if (m < q->splits)
            n += snprintf(what + n, sizeof what - (size_t)n, "%u directional: %u of %u splits (depth %.2g-%.3g m is "
                          "shallow), lambda %.2g%s", counts[FV_LIGHT_DIRECTIONAL], m, q->splits, dn, df,
                          (double)q->lambda, q->stereo_shared ? ", shared by both eyes" : ", per eye");
        else
            n += snprintf(what + n, sizeof what - (size_t)n, "%u directional: %u split%s (lambda %.2g)%s",
                          counts[FV_LIGHT_DIRECTIONAL], q->splits, plural(q->splits), (double)q->lambda,
                          q->stereo_shared ? " shared by both eyes" : " per eye");
    }
    if (counts[FV_LIGHT_SPOT] && n >= 0 && (size_t)n < sizeof what)
        n += snprintf(what + n, sizeof what - (size_t)n, "%s%u spot: one perspective map%s", n ? "; " : "",
                      counts[FV_LIGHT_SPOT], counts[FV_LIGHT_SPOT] == 1 ? "" : " each");
    if (counts[FV_LIGHT_POINT] && n >= 0 && (size_t)n < sizeof what)
        n += snprintf(what + n, sizeof what - (size_t)n, "%s%u point: a cube map%s (6 faces)", n ? "; " : "",
                      counts[FV_LIGHT_POINT], counts[FV_LIGHT_POINT] == 1 ? "" : " each");
    if (lights > FV_SHADOW_MAX_LIGHTS && n >= 0 && (size_t)n < sizeof what)
        snprintf(what + n, sizeof what - (size_t)n, "; lights past %d unshadowed", FV_SHADOW_MAX_LIGHTS);
    snprintf(out->reason, sizeof out->reason, "%s — %u map%s of %upx, %s", what, layers, plural(layers),
             q->resolution_px, filter_name(q->filter));
}

static fv_result create_targets(shadow *sh)
{
    fv_vk *vk = sh->vk;
    VkAttachmentDescription att = fv_vk_attachment_cleared(sh->map->format, VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
    VkAttachmentReference ref = {0, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub = {.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS, .pDepthStencilAttachment = &ref};
    VkSubpassDependency deps[2] = {
        /* Write-after-read: the previous frame's shading read this layer; discard and clear it after that. */
        {.srcSubpass = VK_SUBPASS_EXTERNAL, .dstSubpass = 0, .srcStageMask = READER_STAGES, .dstStageMask = DEPTH_STAGES,
         .srcAccessMask = 0,
         .dstAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT},
        /* Read-after-write: shading samples the map in compute (or fragment) shaders. */
        {.srcSubpass = 0, .dstSubpass = VK_SUBPASS_EXTERNAL, .srcStageMask = DEPTH_STAGES, .dstStageMask = READER_STAGES,
         .srcAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, .dstAccessMask = VK_ACCESS_SHADER_READ_BIT},
    };
    VkRenderPassCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO, .attachmentCount = 1,
                                 .pAttachments = &att, .subpassCount = 1, .pSubpasses = &sub, .dependencyCount = 2,
                                 .pDependencies = deps};
    FV_VK_CHECK(vkCreateRenderPass(vk->device, &ci, NULL, &sh->render_pass));
    FV_VK_NAME(vk, VK_OBJECT_TYPE_RENDER_PASS, sh->render_pass, "shadow map render pass");
    for (uint32_t i = 0; i < sh->layers; i++) {
        VkImageViewCreateInfo vi = {.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO, .image = sh->map->image,
                                    .viewType = VK_IMAGE_VIEW_TYPE_2D, .format = sh->map->format,
                                    .subresourceRange = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, i, 1}};
        FV_VK_CHECK(vkCreateImageView(vk->device, &vi, NULL, &sh->layer_view[i]));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_IMAGE_VIEW, sh->layer_view[i], "shadow map %u", i);
        VkFramebufferCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO, .renderPass = sh->render_pass,
                                      .attachmentCount = 1, .pAttachments = &sh->layer_view[i], .width = sh->res,
                                      .height = sh->res, .layers = 1};
        FV_VK_CHECK(vkCreateFramebuffer(vk->device, &fi, NULL, &sh->framebuffer[i]));
        FV_VK_NAME(vk, VK_OBJECT_TYPE_FRAMEBUFFER, sh->framebuffer[i], "shadow map %u framebuffer", i);
    }
    VkDescriptorSetLayout sets[2] = {sh->scene->set_layout, sh->scene->texture_layout};
    FV_TRY(fv_vk_pipeline_layout(vk, sets, 2, PUSH_BYTES, VK_SHADER_STAGE_VERTEX_BIT, "shadow layout", &sh->layout));
    const VkVertexInputBindingDescription *bind;
    const VkVertexInputAttributeDescription *attrs;
    uint32_t attr_count;
    fv_scene_gpu_vertex_input(&bind, &attrs, &attr_count);
    fv_vk_graphics_desc gd = {.vert = fv_spv_shadow_vert, .vert_size = sizeof fv_spv_shadow_vert,
                              .frag = fv_spv_shadow_frag, .frag_size = sizeof fv_spv_shadow_frag, .bindings = bind,
                              .binding_count = 1, .attributes = attrs, .attribute_count = 1 /* position only */,
                              .layout = sh->layout, .render_pass = sh->render_pass, .color_attachments = 0,
                              .depth_test = true, .depth_bias = true, .cull = VK_CULL_MODE_NONE,
                              .name = "shadow casters"};
    return fv_vk_graphics_pipeline(vk, &gd, &sh->pipeline);
}

static void shadow_fini(void *state)
{
    shadow *sh = state;
    if (!sh) return;
    fv_vk *vk = sh->vk;
    fv_shade_inputs_bind_shadow_map(sh->inputs, sh->images, FV_IMAGE_MAX); /* the GPU is idle */
    if (sh->pipeline) vkDestroyPipeline(vk->device, sh->pipeline, NULL);
    if (sh->layout) vkDestroyPipelineLayout(vk->device, sh->layout, NULL);
    for (uint32_t i = 0; i < FV_SHADOW_MAX_MAPS; i++) {
        if (sh->framebuffer[i]) vkDestroyFramebuffer(vk->device, sh->framebuffer[i], NULL);
        if (sh->layer_view[i]) vkDestroyImageView(vk->device, sh->layer_view[i], NULL);
    }
    if (sh->render_pass) vkDestroyRenderPass(vk->device, sh->render_pass, NULL);
    if (sh->map) fv_images_release(sh->images, sh->map_id);
    free(sh);
}

static fv_result shadow_init(const fv_pass_env *env, void **out_state)
{
    shadow *sh = calloc(1, sizeof *sh);
    if (!sh) return FV_ERR_NO_MEMORY;
    sh->vk = env->vk;
    sh->scene = env->scene;
    sh->images = env->images;
    sh->inputs = env->shade_inputs;
    sh->map_id = FV_IMAGE_MAX;
    /* The layout the plan decided on (the variant): resolution, splits, sharing. */
    uint32_t v = env->plan ? env->plan->variant : 0;
    sh->res = 1u << (v & 31u);
    sh->shared = (v >> 12) & 1u;
    sh->splits_max = v >> 13;
    fv_quality_shadow q = {.splits = sh->splits_max, .stereo_shared = sh->shared};
    fv_result res = FV_OK;
    /* Which lights get maps: from the lights the scene uploaded (types only). */
    uint32_t layers = 0;
    for (uint32_t l = 0; l < sh->scene->light_count && l < FV_SHADOW_MAX_LIGHTS; l++)
        sh->light[sh->light_count++] = entry_for((uint32_t)(sh->scene->lights[l].direction_type.w + 0.5f), &q, &layers);
    sh->layers = layers ? layers : 1;
    fv_vk_image_desc d = {.width = sh->res, .height = sh->res, .layers = sh->layers, .array = true,
                          .format = VK_FORMAT_D32_SFLOAT,
                          .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                          .name = "shadow maps"};
    const fv_vk_image *img = NULL;
    res = fv_images_scratch(env->images, &d, &sh->map_id);
    if (res == FV_OK) {
        img = fv_images_image(env->images, sh->map_id);
        sh->map = img;
        /* Every layer starts readable (a layer not drawn in some frame is never sampled, but must be valid). */
        res = fv_vk_image_set_layout(env->vk, (fv_vk_image *)img, VK_IMAGE_LAYOUT_UNDEFINED,
                                     VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL);
    }
    if (res == FV_OK) res = create_targets(sh);
    if (res != FV_OK) {
        FV_ERROR(MOD, "shadow maps (%u x %upx) could not be created: %s", sh->layers, sh->res, fv_result_str(res));
        shadow_fini(sh);
        return res;
    }
    fv_shade_inputs_bind_shadow_map(sh->inputs, sh->images, sh->map_id);
    *out_state = sh;
    return FV_OK;
}

static void set_component(fv_gpu_vec4 *v, uint32_t k, float value)
{
    switch (k) {
    case 0: v->x = value; break;
    case 1: v->y = value; break;
    case 2: v->z = value; break;
    default: v->w = value; break;
    }
}

/* The maps of this frame: split distances and crops from the eyes and the scene bounds at this frame's time. */
static void shadow_prepare(void *state, const fv_pass_frame *f)
{
    shadow *sh = state;
    fv_gpu_shadow *blk = fv_shade_inputs_shadow(f->shade_inputs, f->slot);
    slot_maps *sm = &sh->slot[f->slot];
    memset(sm->used, 0, sizeof sm->used);
    sm->count = 0;
    if (!blk) return;
    memset(sh->last, 0, sizeof sh->last);
    const fv_quality_shadow *q = &f->input->quality.shadow;
    fv_vec3 bmin, bmax;
    if (!fv_scene_gpu_world_bounds(sh->scene, f->input->time_s, &bmin, &bmax)) return;
    const fv_eye_view *eye = f->input->eye;
    uint32_t radius = q->filter == FV_SHADOW_FILTER_PCF5 ? 2u : (q->filter == FV_SHADOW_FILTER_PCF3 ? 1u : 0u);
    for (uint32_t l = 0; l < sh->light_count; l++) {
        const light_entry *e = &sh->light[l];
        fv_gpu_shadow_light *g = &blk->light[l];
        memset(g, 0, sizeof *g);
        if (e->kind == FV_SHADOW_KIND_NONE) continue;
        const fv_gpu_light *L = &sh->scene->lights[l];
        fv_vec3 dir = fv_v3(L->direction_type.x, L->direction_type.y, L->direction_type.z);
        g->params = (fv_gpu_vec4){(float)radius, 1.0f / (float)sh->res, 0.0f, 0.0f};
        if (e->kind == FV_SHADOW_KIND_CUBE) {
            fv_vec3 pos = fv_v3(L->position_range.x, L->position_range.y, L->position_range.z);
            for (uint32_t face = 0; face < 6; face++) {
                sm->view_proj[e->first_map + face] = fv_shadow_cube_face(pos, face, bmin, bmax);
                sm->used[e->first_map + face] = true;
            }
            g->params.z = (float)fv_shadow_cube_texel_per_m(sh->res);
            g->info = (fv_gpu_uvec4){FV_SHADOW_KIND_CUBE, e->first_map, 6, 0};
            continue;
        }
        if (e->kind == FV_SHADOW_KIND_PERSPECTIVE) {
            fv_vec3 pos = fv_v3(L->position_range.x, L->position_range.y, L->position_range.z);
            float outer = acosf(fv_clampf(L->cone.y, -1.0f, 1.0f));
            sm->view_proj[e->first_map] = fv_shadow_spot(pos, dir, outer, bmin, bmax);
            sm->used[e->first_map] = true;
            g->params.z = (float)fv_shadow_spot_texel_per_m(outer, sh->res);
            g->info = (fv_gpu_uvec4){FV_SHADOW_KIND_PERSPECTIVE, e->first_map, 1, 0};
            continue;
        }
        /* Cascades: the visible depth range (both eyes), tightened to the scene, split by the practical scheme. */
        double n = INFINITY, fa = 0.0;
        for (int k = 0; k < 2; k++) {
            double ne, fe;
            if (!fv_shadow_depth_range(&eye[k].view, bmin, bmax, eye[k].near_m, eye[k].far_m, &ne, &fe)) continue;
            n = ne < n ? ne : n;
            fa = fe > fa ? fe : fa;
        }
        if (!(fa > n)) continue; /* nothing of the scene in view: no map */
        uint32_t m = fv_shadow_splits_for_range(n, fa, sh->splits_max);
        double c[FV_SHADOW_SPLITS_MAX + 1];
        m = fv_shadow_split_distances(n, fa, m, q->lambda, c);
        light_range *lr = &sh->last[l];
        lr->valid = true;
        lr->splits = m;
        lr->near_m = n;
        lr->far_m = fa;
        memcpy(lr->splits_m, c, (m + 1) * sizeof *c);
        fv_mat4 lv = fv_shadow_light_view(dir);
        uint32_t per_eye = sh->shared ? 0u : m;
        for (uint32_t i = 0; i < m; i++) {
            fv_vec3 pts[16];
            fv_shadow_slice_corners(&eye[0], c[i], c[i + 1], pts);
            fv_shadow_slice_corners(&eye[1], c[i], c[i + 1], pts + 8);
            double texel = 0.0, texel_k;
            if (sh->shared) {
                uint32_t map = e->first_map + i;
                sm->view_proj[map] = fv_shadow_crop_directional(&lv, pts, 16, bmin, bmax, sh->res, &texel);
                sm->used[map] = true;
            } else {
                for (uint32_t k = 0; k < 2; k++) {
                    uint32_t map = e->first_map + k * m + i;
                    sm->view_proj[map] = fv_shadow_crop_directional(&lv, pts + 8 * k, 8, bmin, bmax, sh->res, &texel_k);
                    sm->used[map] = true;
                    texel = texel_k > texel ? texel_k : texel;
                }
            }
            float far_i = (float)c[i + 1];
            set_component(&g->split_far[i / 4], i % 4, far_i);
            set_component(&g->split_texel[i / 4], i % 4, (float)texel);
        }
        g->info = (fv_gpu_uvec4){FV_SHADOW_KIND_CASCADES, e->first_map, m, per_eye};
    }
    for (uint32_t i = 0; i < sh->layers; i++)
        if (sm->used[i]) {
            memcpy(blk->map_view_proj[i].m, sm->view_proj[i].m, sizeof blk->map_view_proj[i].m);
            sm->count = i + 1;
        }
    blk->counts = (fv_gpu_uvec4){sh->light_count, sh->layers, sh->res, 0};
}

static void shadow_record(void *state, const fv_pass_frame *f)
{
    shadow *sh = state;
    VkCommandBuffer cmd = f->cmd;
    const slot_maps *sm = &sh->slot[f->slot];
    fv_vk_label_begin(sh->vk, cmd, "shadow maps");
    /* The render passes' own dependencies wait for earlier reads by shading and make the maps visible to it. */
    fv_images_render_pass(f->images, cmd, sh->map_id, READER_STAGES,
                          (fv_vk_image_use){VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL, DEPTH_STAGES,
                                            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT},
                          READER_STAGES);
    float bias = f->input->quality.shadow.bias_texels;
    if (!(isfinite(bias) && bias >= 0.0f)) bias = 0.0f;
    for (uint32_t map = 0; map < sm->count; map++) {
        if (!sm->used[map]) continue;
        VkClearValue clear = {.depthStencil = {1.0f, 0}};
        VkRenderPassBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO, .renderPass = sh->render_pass,
                                    .framebuffer = sh->framebuffer[map], .renderArea = {{0, 0}, {sh->res, sh->res}},
                                    .clearValueCount = 1, .pClearValues = &clear};
        vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
        VkViewport vp = {0, 0, (float)sh->res, (float)sh->res, 0.0f, 1.0f};
        VkRect2D sc = {{0, 0}, {sh->res, sh->res}};
        vkCmdSetViewport(cmd, 0, 1, &vp);
        vkCmdSetScissor(cmd, 0, 1, &sc);
        /* Slope-scaled bias in texels of depth slope, plus shadow.constant_bias smallest resolvable steps. */
        vkCmdSetDepthBias(cmd, f->input->quality.shadow.constant_bias, 0.0f, bias);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, sh->pipeline);
        vkCmdPushConstants(cmd, sh->layout, VK_SHADER_STAGE_VERTEX_BIT, 16, 64, sm->view_proj[map].m);
        uint32_t n = fv_scene_gpu_record_draws(sh->scene, cmd, sh->layout, VK_SHADER_STAGE_VERTEX_BIT, f->slot, map);
        f->counters->draws += n;
        f->counters->triangles += sh->scene->triangle_count;
        vkCmdEndRenderPass(cmd);
    }
    fv_vk_label_end(sh->vk, cmd);
}

static uint32_t shadow_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    shadow *sh = state;
    uint32_t n = 0;
    for (uint32_t l = 0; l < FV_SHADOW_MAX_LIGHTS; l++) {
        const light_range *lr = &sh->last[l];
        if (!lr->valid || n + 3 > cap) continue;
        snprintf(out[n].key, sizeof out[n].key, "light%u.near_m", l);
        out[n].value[0] = lr->near_m;
        out[n++].count = 1;
        snprintf(out[n].key, sizeof out[n].key, "light%u.far_m", l);
        out[n].value[0] = lr->far_m;
        out[n++].count = 1;
        snprintf(out[n].key, sizeof out[n].key, "light%u.splits_m", l);
        memcpy(out[n].value, lr->splits_m, (lr->splits + 1) * sizeof(double));
        out[n++].count = lr->splits + 1;
    }
    return n;
}

const fv_pass fv_shadow_pass = {
    .id = "shadow",
    .plan = shadow_plan,
    .init = shadow_init,
    .prepare = shadow_prepare,
    .record = shadow_record,
    .fini = shadow_fini,
    .details = shadow_details,
    .makes = FV_PASS_NAMES("shadow maps"),
};
