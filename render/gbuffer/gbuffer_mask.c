/* @brief The G-buffer's hidden-area mask (see gbuffer_mask.h). */
#include "gbuffer_mask.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "gbuffer_interface.h"
#include "gbuffer_mask_frag.spv.h"
#include "gbuffer_mask_surface_frag.spv.h"
#include "gbuffer_mask_vert.spv.h"

#define MOD "gbuffer"
#define MAX_VERTICES_PER_EYE (6u * FV_LENS_MASK_SEGMENTS)

bool gbuffer_mask_wanted(const fv_quality *q)
{
    return q->distort.enabled && q->distort.mask && q->distort.lens.valid;
}

fv_result gbuffer_mask_init(gbuffer_mask *m, fv_vk *vk, VkRenderPass render_pass, bool multiview, uint32_t slots,
                            uint32_t width, uint32_t height, uint32_t color_attachments)
{
    memset(m, 0, sizeof *m);
    m->vk = vk;
    m->width = width;
    m->height = height;
    m->multiview = multiview;
    m->slots = slots < 1 ? 1 : slots > FV_MAX_FRAMES_IN_FLIGHT ? FV_MAX_FRAMES_IN_FLIGHT : slots;
    FV_TRY(fv_vk_pipeline_layout(vk, NULL, 0, 0, 0, "gbuffer mask layout", &m->layout));
    VkVertexInputBindingDescription bind = {0, 3 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX};
    VkVertexInputAttributeDescription attr = {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0};
    uint32_t use_multiview = multiview ? 1u : 0u;
    fv_vk_graphics_desc gd = {
        .vert = fv_spv_gbuffer_mask_vert,
        .vert_size = sizeof fv_spv_gbuffer_mask_vert,
        .frag = color_attachments > FV_GBUFFER_OUT_SURFACE ? fv_spv_gbuffer_mask_surface_frag : fv_spv_gbuffer_mask_frag,
        .frag_size = color_attachments > FV_GBUFFER_OUT_SURFACE ? sizeof fv_spv_gbuffer_mask_surface_frag
                                                                 : sizeof fv_spv_gbuffer_mask_frag,
        .bindings = &bind,
        .binding_count = 1,
        .attributes = &attr,
        .attribute_count = 1,
        .layout = m->layout,
        .render_pass = render_pass,
        .color_attachments = color_attachments,
        .depth_test = true, /* depth 0 < the cleared 1: written; the scene's LESS test then fails there */
        .cull = VK_CULL_MODE_NONE,
        .spec = &use_multiview,
        .spec_count = 1,
        .name = "gbuffer hidden-area mask",
    };
    FV_TRY(fv_vk_graphics_pipeline(vk, &gd, &m->pipeline));
    for (uint32_t s = 0; s < m->slots; s++) {
        char name[48];
        snprintf(name, sizeof name, "gbuffer mask vertices (slot %u)", s);
        FV_TRY(fv_vk_buffer_create(vk, (VkDeviceSize)2 * MAX_VERTICES_PER_EYE * 3 * sizeof(float),
                                   VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, FV_VK_MEM_UPLOAD, name, &m->vertices[s]));
    }
    return FV_OK;
}

static bool same_fov(const fv_hmd_fov *a, const fv_hmd_fov *b)
{
    return a->tan_left == b->tan_left && a->tan_right == b->tan_right && a->tan_up == b->tan_up &&
           a->tan_down == b->tan_down;
}

void gbuffer_mask_prepare(gbuffer_mask *m, uint32_t slot, const fv_frame_input *in)
{
    if (slot >= m->slots || !in) return;
    fv_hmd_fov fov[2];
    for (int e = 0; e < 2; e++)
        fov[e] = (fv_hmd_fov){-in->eye[e].tan_left, in->eye[e].tan_right, in->eye[e].tan_up, -in->eye[e].tan_down};
    const fv_lens *l = &in->quality.distort.lens;
    if (m->built[slot] && fv_lens_equal(&m->lens[slot], l) && same_fov(&m->fov[slot][0], &fov[0]) &&
        same_fov(&m->fov[slot][1], &fov[1]))
        return;
    float *dst = m->vertices[slot].mapped;
    uint32_t at = 0;
    for (int e = 0; e < 2; e++) {
        m->count[slot][e] = 0;
        /* the lens axis (tangent 0) must be inside the frustum, which every HMD's is */
        bool finite = isfinite(fov[e].tan_left) && isfinite(fov[e].tan_right) && isfinite(fov[e].tan_up) &&
                      isfinite(fov[e].tan_down) && fov[e].tan_left > 0 && fov[e].tan_right > 0 &&
                      fov[e].tan_up > 0 && fov[e].tan_down > 0;
        if (!l->valid || !finite) continue; /* nothing masked rather than a wrong mask */
        double margin = fv_lens_mask_margin(&fov[e], m->width, m->height);
        uint32_t n = fv_lens_hidden_mesh(l, e, &fov[e], FV_LENS_MASK_SEGMENTS, margin, (float)e, dst + 3 * at,
                                         MAX_VERTICES_PER_EYE);
        n = n > MAX_VERTICES_PER_EYE ? MAX_VERTICES_PER_EYE : n;
        m->count[slot][e] = n;
        at += n;
        fv_lens_hidden_fraction(l, e, &fov[e], m->width, m->height, FV_LENS_MASK_SEGMENTS, margin, NULL,
                                &m->fraction[e]);
    }
    if (fv_vk_buffer_flush(m->vk, &m->vertices[slot]) != FV_OK) {
        m->count[slot][0] = m->count[slot][1] = 0;
        return;
    }
    m->built[slot] = true;
    m->lens[slot] = *l;
    m->fov[slot][0] = fov[0];
    m->fov[slot][1] = fov[1];
}

uint32_t gbuffer_mask_record(gbuffer_mask *m, VkCommandBuffer cmd, uint32_t slot, int eye)
{
    if (slot >= m->slots || !m->built[slot]) return 0;
    uint32_t n0 = m->count[slot][0], n1 = m->count[slot][1];
    uint32_t first = eye == 1 ? n0 : 0, count = eye < 0 ? n0 + n1 : eye == 0 ? n0 : n1;
    if (!count) return 0;
    VkDeviceSize offset = 0;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m->pipeline);
    vkCmdBindVertexBuffers(cmd, 0, 1, &m->vertices[slot].buffer, &offset);
    vkCmdDraw(cmd, count, 1, first, 0);
    return count / 3;
}

void gbuffer_mask_fini(gbuffer_mask *m)
{
    if (!m->vk) return;
    for (uint32_t s = 0; s < FV_MAX_FRAMES_IN_FLIGHT; s++) fv_vk_buffer_destroy(m->vk, &m->vertices[s]);
    if (m->pipeline) vkDestroyPipeline(m->vk->device, m->pipeline, NULL);
    if (m->layout) vkDestroyPipelineLayout(m->vk->device, m->layout, NULL);
    memset(m, 0, sizeof *m);
}
