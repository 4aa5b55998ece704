/* @brief The scene on the GPU (see fv_scene_gpu.h): upload of meshes, materials, textures and lights, the draw list,
 * the per-frame data behind the shared set, and drawing the scene from any view. */
#include "fv_scene_gpu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MOD "scene_gpu"

typedef struct vertex {
    float position[3];
    float normal[3];
    float texcoord[2];
} vertex;
_Static_assert(sizeof(vertex) == 32, "vertex layout");

static const VkVertexInputBindingDescription vertex_binding = {0, sizeof(vertex), VK_VERTEX_INPUT_RATE_VERTEX};
static const VkVertexInputAttributeDescription vertex_attributes[3] = {
    {FV_SCENE_ATTR_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(vertex, position)},
    {FV_SCENE_ATTR_NORMAL, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(vertex, normal)},
    {FV_SCENE_ATTR_TEXCOORD, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(vertex, texcoord)},
};

void fv_scene_gpu_vertex_input(const VkVertexInputBindingDescription **out_binding,
                               const VkVertexInputAttributeDescription **out_attributes, uint32_t *out_attribute_count)
{
    *out_binding = &vertex_binding;
    *out_attributes = vertex_attributes;
    *out_attribute_count = 3;
}

static VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }

static float finite_or(float v, float fallback) { return isfinite(v) ? v : fallback; }

static fv_gpu_mat4 to_gpu(const fv_mat4 *m)
{
    fv_gpu_mat4 g;
    memcpy(g.m, m->m, sizeof g.m);
    return g;
}

/* ---- init / fini ---------------------------------------------------------------------------------------------- */

fv_result fv_scene_gpu_init(fv_scene_gpu *sg, fv_vk *vk, uint32_t frames_in_flight)
{
    memset(sg, 0, sizeof *sg);
    if (!vk || !frames_in_flight || frames_in_flight > FV_MAX_FRAMES_IN_FLIGHT) return FV_ERR_INVALID_ARG;
    sg->vk = vk;
    sg->slots = frames_in_flight;
    VkShaderStageFlags all = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT | VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorSetLayoutBinding b[FV_SCENE_BINDING_COUNT] = {
        {FV_SCENE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, all, NULL},
        {FV_SCENE_BINDING_LIGHTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, all, NULL},
        {FV_SCENE_BINDING_MATERIALS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, all, NULL},
        {FV_SCENE_BINDING_DRAWS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, all, NULL},
    };
    fv_result res = fv_vk_set_layout(vk, b, FV_SCENE_BINDING_COUNT, "scene set (frame, lights, materials, draws)",
                                     &sg->set_layout);
    VkDescriptorSetLayoutBinding tex_b = {FV_SCENE_BINDING_BASE_COLOR, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1,
                                          VK_SHADER_STAGE_FRAGMENT_BIT, NULL};
    if (res == FV_OK) res = fv_vk_set_layout(vk, &tex_b, 1, "scene texture set", &sg->texture_layout);
    VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frames_in_flight},
                                     {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3 * frames_in_flight}};
    if (res == FV_OK) res = fv_vk_descriptor_pool(vk, sizes, 2, frames_in_flight, "scene set pool", &sg->pool);
    for (uint32_t i = 0; res == FV_OK && i < frames_in_flight; i++) {
        char name[40];
        snprintf(name, sizeof name, "scene set %u", i);
        res = fv_vk_descriptor_set(vk, sg->pool, sg->set_layout, name, &sg->sets[i]);
    }
    if (res == FV_OK) res = fv_vk_sampler_create(vk, true, true, "scene base colour sampler", &sg->texture_sampler);
    if (res == FV_OK) {
        fv_vk_image_desc wd = {.width = 1, .height = 1, .layers = 1, .format = VK_FORMAT_R8G8B8A8_SRGB,
                               .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                               .name = "white texture"};
        res = fv_vk_image_create(vk, &wd, &sg->white);
        const uint8_t white[4] = {255, 255, 255, 255};
        if (res == FV_OK)
            res = fv_vk_upload_image(vk, &sg->white, 0, white, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
    if (res != FV_OK) {
        FV_ERROR(MOD, "scene GPU state could not be created: %s", fv_result_str(res));
        fv_scene_gpu_fini(sg);
    }
    return res;
}

void fv_scene_gpu_unload(fv_scene_gpu *sg)
{
    if (!sg || !sg->vk) return;
    fv_vk *vk = sg->vk;
    fv_vk_buffer_destroy(vk, &sg->vertices);
    fv_vk_buffer_destroy(vk, &sg->indices);
    fv_vk_buffer_destroy(vk, &sg->materials);
    for (uint32_t i = 0; i < sg->texture_count; i++) fv_vk_image_destroy(vk, &sg->textures[i]);
    free(sg->textures);
    if (sg->texture_pool) vkDestroyDescriptorPool(vk->device, sg->texture_pool, NULL);
    free(sg->texture_sets);
    free(sg->meshes);
    free(sg->anim.nodes);
    free(sg->anim.meshes);
    free(sg->draws);
    free(sg->lights);
    for (uint32_t i = 0; i < FV_MAX_FRAMES_IN_FLIGHT; i++) fv_vk_buffer_destroy(vk, &sg->upload[i]);
    sg->textures = NULL;
    sg->texture_count = 0;
    sg->texture_pool = VK_NULL_HANDLE;
    sg->texture_sets = NULL;
    sg->meshes = NULL;
    sg->mesh_count = sg->material_count = 0;
    memset(&sg->anim, 0, sizeof sg->anim);
    sg->draws = NULL;
    sg->draw_count = 0;
    sg->triangle_count = 0;
    sg->lights = NULL;
    sg->light_count = 0;
    sg->loaded = false;
}

void fv_scene_gpu_fini(fv_scene_gpu *sg)
{
    if (!sg || !sg->vk) return;
    fv_vk *vk = sg->vk;
    fv_scene_gpu_unload(sg);
    fv_vk_image_destroy(vk, &sg->white);
    if (sg->texture_sampler) vkDestroySampler(vk->device, sg->texture_sampler, NULL);
    if (sg->pool) vkDestroyDescriptorPool(vk->device, sg->pool, NULL);
    if (sg->set_layout) vkDestroyDescriptorSetLayout(vk->device, sg->set_layout, NULL);
    if (sg->texture_layout) vkDestroyDescriptorSetLayout(vk->device, sg->texture_layout, NULL);
    memset(sg, 0, sizeof *sg);
}

/* ---- upload --------------------------------------------------------------------------------------------------- */

static fv_result upload_meshes(fv_scene_gpu *sg, const fv_scene *s)
{
    uint64_t total_v = 0, total_i = 0;
    for (uint32_t m = 0; m < s->mesh_count; m++) {
        total_v += s->meshes[m].vertex_count;
        total_i += s->meshes[m].index_count;
    }
    if (total_v > INT32_MAX || total_i > UINT32_MAX / 2) {
        FV_ERROR(MOD, "%s: %llu vertices / %llu indices exceed what one draw buffer holds", s->source,
                 (unsigned long long)total_v, (unsigned long long)total_i);
        return FV_ERR_RANGE;
    }
    sg->meshes = calloc(s->mesh_count ? s->mesh_count : 1, sizeof *sg->meshes);
    vertex *verts = malloc((total_v ? total_v : 1) * sizeof *verts);
    uint32_t *idx = malloc((total_i ? total_i : 1) * sizeof *idx);
    fv_result res = FV_OK;
    if (!sg->meshes || !verts || !idx) {
        res = FV_ERR_NO_MEMORY;
        goto done;
    }
    sg->mesh_count = s->mesh_count;
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
        sg->meshes[m] = (fv_scene_gpu_mesh){.first_index = ibase, .index_count = count, .vertex_offset = (int32_t)vbase};
        vbase += mesh->vertex_count;
        ibase += count;
    }
    res = fv_vk_buffer_create(sg->vk, (total_v ? total_v : 1) * sizeof(vertex),
                              VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, FV_VK_MEM_DEVICE,
                              "scene vertices", &sg->vertices);
    if (res == FV_OK)
        res = fv_vk_buffer_create(sg->vk, (ibase ? ibase : 1) * sizeof(uint32_t),
                                  VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                  FV_VK_MEM_DEVICE, "scene indices", &sg->indices);
    if (res == FV_OK) res = fv_vk_upload_buffer(sg->vk, &sg->vertices, 0, verts, total_v * sizeof(vertex));
    if (res == FV_OK) res = fv_vk_upload_buffer(sg->vk, &sg->indices, 0, idx, (VkDeviceSize)ibase * sizeof(uint32_t));
done:
    free(verts);
    free(idx);
    return res;
}

/* Coefficients are per mm in the scene model; world space is metres, so the GPU gets them per metre. */
static float per_m(float per_mm) { return isfinite(per_mm) && per_mm > 0.0f ? per_mm * 1000.0f : 0.0f; }

static fv_result upload_materials(fv_scene_gpu *sg, const fv_scene *s)
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
        const fv_translucency *t = &m.translucency;
        mats[i].info = (fv_gpu_uvec4){tex_ok ? (uint32_t)m.base_color_texture : 0xffffffffu, t->enabled ? 1u : 0u, 0, 0};
        float eta = t->enabled && isfinite(t->eta) && t->eta > 0.0f ? t->eta : 1.0f;
        if (t->enabled) {
            mats[i].sigma_a = (fv_gpu_vec4){per_m(t->sigma_a_per_mm[0]), per_m(t->sigma_a_per_mm[1]),
                                            per_m(t->sigma_a_per_mm[2]), eta};
            mats[i].sigma_s = (fv_gpu_vec4){per_m(t->sigma_s_prime_per_mm[0]), per_m(t->sigma_s_prime_per_mm[1]),
                                            per_m(t->sigma_s_prime_per_mm[2]), 0.0f};
        } else {
            mats[i].sigma_a = (fv_gpu_vec4){0, 0, 0, 1.0f};
        }
    }
    sg->material_count = n;
    fv_result res = fv_vk_buffer_create(sg->vk, n * sizeof *mats,
                                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                        FV_VK_MEM_DEVICE, "scene materials", &sg->materials);
    if (res == FV_OK) res = fv_vk_upload_buffer(sg->vk, &sg->materials, 0, mats, n * sizeof *mats);
    free(mats);
    return res;
}

static fv_result upload_textures(fv_scene_gpu *sg, const fv_scene *s)
{
    fv_vk *vk = sg->vk;
    sg->textures = calloc(s->texture_count ? s->texture_count : 1, sizeof *sg->textures);
    sg->texture_sets = calloc(s->texture_count + 1, sizeof *sg->texture_sets);
    if (!sg->textures || !sg->texture_sets) return FV_ERR_NO_MEMORY;
    VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, s->texture_count + 1};
    FV_TRY(fv_vk_descriptor_pool(vk, &size, 1, s->texture_count + 1, "scene texture pool", &sg->texture_pool));
    for (uint32_t t = 0; t <= s->texture_count; t++) {
        VkImageView view = sg->white.view;
        if (t < s->texture_count) {
            const fv_texture *tex = &s->textures[t];
            sg->texture_count = t + 1;
            if (tex->rgba8 && tex->width && tex->height && tex->width <= FV_SCENE_MAX_TEXTURE_DIM &&
                tex->height <= FV_SCENE_MAX_TEXTURE_DIM) {
                char name[96];
                snprintf(name, sizeof name, "texture %u (%.60s)", t, tex->source);
                fv_vk_image_desc d = {.width = tex->width, .height = tex->height, .layers = 1,
                                      .format = VK_FORMAT_R8G8B8A8_SRGB,
                                      .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                      .name = name};
                FV_TRY(fv_vk_image_create(vk, &d, &sg->textures[t]));
                FV_TRY(fv_vk_upload_image(vk, &sg->textures[t], 0, tex->rgba8, (size_t)tex->width * tex->height * 4,
                                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
                view = sg->textures[t].view;
            } else {
                FV_WARN(MOD, "%s: texture %u (%s) has no pixels; using the base colour alone", s->source, t,
                        tex->source);
            }
        }
        char name[48];
        snprintf(name, sizeof name, t < s->texture_count ? "texture set %u" : "white texture set", t);
        FV_TRY(fv_vk_descriptor_set(vk, sg->texture_pool, sg->texture_layout, name, &sg->texture_sets[t]));
        fv_vk_write_image(vk, sg->texture_sets[t], FV_SCENE_BINDING_BASE_COLOR, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                          view, sg->texture_sampler, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
    return FV_OK;
}

static fv_gpu_light to_gpu_light(const fv_light *l)
{
    fv_gpu_light g;
    memset(&g, 0, sizeof g);
    fv_vec3 p = fv_v3_isfinite(l->position_m) ? l->position_m : fv_v3(0, 0, 0);
    fv_vec3 d = fv_v3_normalize_or(l->direction, fv_v3(0, -1, 0));
    float range = isfinite(l->range_m) && l->range_m > 0 ? l->range_m : 0.0f;
    float intensity = isfinite(l->intensity) && l->intensity > 0 ? l->intensity : 0.0f;
    fv_vec3 c = l->color;
    c = fv_v3(isfinite(c.x) && c.x > 0 ? c.x : 0, isfinite(c.y) && c.y > 0 ? c.y : 0, isfinite(c.z) && c.z > 0 ? c.z : 0);
    uint32_t type = (unsigned)l->type <= FV_LIGHT_DIRECTIONAL ? (uint32_t)l->type : FV_GPU_LIGHT_POINT;
    float outer = isfinite(l->outer_cone_rad) ? fv_clampf(l->outer_cone_rad, 0.0f, (float)FV_PI / 2) : (float)FV_PI / 4;
    float inner = isfinite(l->inner_cone_rad) ? fv_clampf(l->inner_cone_rad, 0.0f, outer) : 0.0f;
    g.position_range = (fv_gpu_vec4){p.x, p.y, p.z, range};
    g.direction_type = (fv_gpu_vec4){d.x, d.y, d.z, (float)type};
    g.intensity = (fv_gpu_vec4){c.x * intensity, c.y * intensity, c.z * intensity, 0.0f};
    g.cone = (fv_gpu_vec4){cosf(inner), cosf(outer), 0.0f, 0.0f};
    return g;
}

/* The draw list (a draw per node with a mesh), the lights, and the per-slot upload buffers behind the sets. */
static fv_result build_frame_data(fv_scene_gpu *sg, const fv_scene *scene)
{
    uint32_t draws = 0;
    for (uint32_t i = 0; i < scene->node_count; i++)
        if (scene->nodes[i].mesh >= 0 && (uint32_t)scene->nodes[i].mesh < scene->mesh_count) draws++;
    sg->anim.nodes = malloc((scene->node_count ? scene->node_count : 1) * sizeof *sg->anim.nodes);
    sg->draws = calloc(draws ? draws : 1, sizeof *sg->draws);
    sg->lights = calloc(scene->light_count ? scene->light_count : 1, sizeof *sg->lights);
    if (!sg->anim.nodes || !sg->draws || !sg->lights) return FV_ERR_NO_MEMORY;
    memcpy(sg->anim.nodes, scene->nodes, scene->node_count * sizeof *scene->nodes);
    sg->anim.node_count = scene->node_count;
    /* Mesh headers without their data: what world bounds at any time need (fv_scene_world_bounds). */
    sg->anim.meshes = malloc((scene->mesh_count ? scene->mesh_count : 1) * sizeof *sg->anim.meshes);
    if (!sg->anim.meshes) return FV_ERR_NO_MEMORY;
    for (uint32_t m = 0; m < scene->mesh_count; m++) {
        sg->anim.meshes[m] = scene->meshes[m];
        sg->anim.meshes[m].positions = sg->anim.meshes[m].normals = NULL;
        sg->anim.meshes[m].texcoords = NULL;
        sg->anim.meshes[m].indices = NULL;
    }
    sg->anim.mesh_count = scene->mesh_count;
    for (uint32_t i = 0; i < scene->node_count; i++) {
        const fv_node *n = &scene->nodes[i];
        if (n->mesh < 0 || (uint32_t)n->mesh >= scene->mesh_count) continue;
        uint32_t mat = scene->meshes[n->mesh].material;
        if (mat >= sg->material_count) mat = 0;
        int32_t tex = mat < scene->material_count ? scene->materials[mat].base_color_texture : -1;
        sg->draws[sg->draw_count++] = (fv_scene_gpu_draw){.node = i, .mesh = (uint32_t)n->mesh, .material = mat,
                                                          .texture = tex};
        sg->triangle_count += sg->meshes[n->mesh].index_count / 3;
    }
    for (uint32_t l = 0; l < scene->light_count; l++) sg->lights[l] = to_gpu_light(&scene->lights[l]);
    sg->light_count = scene->light_count;
    sg->ambient = fv_v3_isfinite(scene->ambient) ? fv_v3_max(scene->ambient, fv_v3(0, 0, 0)) : fv_v3(0, 0, 0);

    VkDeviceSize a = sg->vk->props.limits.minUniformBufferOffsetAlignment;
    if (sg->vk->props.limits.minStorageBufferOffsetAlignment > a) a = sg->vk->props.limits.minStorageBufferOffsetAlignment;
    if (a < 16) a = 16;
    VkDeviceSize lights_bytes = (sg->light_count ? sg->light_count : 1) * sizeof(fv_gpu_light);
    VkDeviceSize draws_bytes = (sg->draw_count ? sg->draw_count : 1) * sizeof(fv_gpu_draw);
    sg->lights_offset = align_up(sizeof(fv_gpu_frame), a);
    sg->draws_offset = align_up(sg->lights_offset + lights_bytes, a);
    sg->upload_size = sg->draws_offset + draws_bytes;
    for (uint32_t i = 0; i < sg->slots; i++) {
        char name[48];
        snprintf(name, sizeof name, "frame slot %u data", i);
        FV_TRY(fv_vk_buffer_create(sg->vk, sg->upload_size,
                                   VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                   FV_VK_MEM_UPLOAD, name, &sg->upload[i]));
        memset(sg->upload[i].mapped, 0, sg->upload_size);
        VkBuffer b = sg->upload[i].buffer;
        fv_vk_write_buffer(sg->vk, sg->sets[i], FV_SCENE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, b, 0,
                           sizeof(fv_gpu_frame));
        fv_vk_write_buffer(sg->vk, sg->sets[i], FV_SCENE_BINDING_LIGHTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, b,
                           sg->lights_offset, lights_bytes);
        fv_vk_write_buffer(sg->vk, sg->sets[i], FV_SCENE_BINDING_MATERIALS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                           sg->materials.buffer, 0, VK_WHOLE_SIZE);
        fv_vk_write_buffer(sg->vk, sg->sets[i], FV_SCENE_BINDING_DRAWS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, b,
                           sg->draws_offset, draws_bytes);
    }
    return FV_OK;
}

fv_result fv_scene_gpu_load(fv_scene_gpu *sg, const fv_scene *scene)
{
    if (!sg || !sg->vk || !scene) return FV_ERR_INVALID_ARG;
    fv_scene_gpu_unload(sg);
    fv_result res = upload_meshes(sg, scene);
    if (res == FV_OK) res = upload_materials(sg, scene);
    if (res == FV_OK) res = upload_textures(sg, scene);
    if (res == FV_OK) res = build_frame_data(sg, scene);
    if (res != FV_OK) {
        FV_ERROR(MOD, "%s: uploading the scene failed: %s", scene->source, fv_result_str(res));
        fv_scene_gpu_unload(sg);
        return res;
    }
    sg->loaded = true;
    sg->load_count++;
    return FV_OK;
}

/* ---- per frame ------------------------------------------------------------------------------------------------ */

static fv_mat4 normal_matrix(const fv_mat4 *model)
{
    fv_mat4 inv;
    if (!fv_mat4_invert(model, &inv)) return *model;
    return fv_mat4_transpose(&inv);
}

fv_result fv_scene_gpu_write_frame(fv_scene_gpu *sg, uint32_t slot, const fv_gpu_frame *frame, double t_s,
                                   double t_prev_s)
{
    if (!sg || !frame || slot >= sg->slots) return FV_ERR_INVALID_ARG;
    if (!sg->loaded) return FV_ERR_STATE;
    uint8_t *base = sg->upload[slot].mapped;
    fv_gpu_frame fr = *frame;
    fr.ambient = (fv_gpu_vec4){sg->ambient.x, sg->ambient.y, sg->ambient.z, 0.0f};
    fr.counts.x = sg->light_count;
    memcpy(base, &fr, sizeof fr);
    if (sg->light_count) memcpy(base + sg->lights_offset, sg->lights, sg->light_count * sizeof(fv_gpu_light));
    fv_gpu_draw *d = (fv_gpu_draw *)(base + sg->draws_offset);
    for (uint32_t i = 0; i < sg->draw_count; i++) {
        const fv_scene_gpu_draw *dr = &sg->draws[i];
        fv_mat4 m = fv_scene_node_world(&sg->anim, dr->node, t_s);
        fv_mat4 pm = fv_scene_node_world(&sg->anim, dr->node, t_prev_s);
        fv_mat4 nm = normal_matrix(&m);
        d[i].model = to_gpu(&m);
        d[i].prev_model = to_gpu(&pm);
        d[i].normal_matrix = to_gpu(&nm);
        d[i].info = (fv_gpu_uvec4){dr->material, dr->texture >= 0 ? (uint32_t)dr->texture : 0xffffffffu, 0, 0};
    }
    return fv_vk_buffer_flush(sg->vk, &sg->upload[slot]);
}

bool fv_scene_gpu_world_bounds(const fv_scene_gpu *sg, double t_s, fv_vec3 *out_min, fv_vec3 *out_max)
{
    return sg && sg->loaded && fv_scene_world_bounds(&sg->anim, t_s, out_min, out_max);
}

VkDescriptorSet fv_scene_gpu_set(const fv_scene_gpu *sg, uint32_t slot)
{
    return sg && slot < sg->slots ? sg->sets[slot] : VK_NULL_HANDLE;
}

uint32_t fv_scene_gpu_record_draws(const fv_scene_gpu *sg, VkCommandBuffer cmd, VkPipelineLayout layout,
                           VkShaderStageFlags push_stages, uint32_t slot, uint32_t view)
{
    if (!sg || !sg->loaded || !sg->draw_count || slot >= sg->slots) return 0;
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, FV_SCENE_SET, 1, &sg->sets[slot], 0, NULL);
    VkDeviceSize zero = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &sg->vertices.buffer, &zero);
    vkCmdBindIndexBuffer(cmd, sg->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
    int32_t bound_texture = -2;
    uint32_t recorded = 0;
    for (uint32_t d = 0; d < sg->draw_count; d++) {
        const fv_scene_gpu_draw *dr = &sg->draws[d];
        if (dr->mesh >= sg->mesh_count || sg->meshes[dr->mesh].index_count == 0) continue;
        int32_t tex = dr->texture >= 0 && (uint32_t)dr->texture < sg->texture_count ? dr->texture : -1;
        if (tex != bound_texture) {
            uint32_t set = tex >= 0 ? (uint32_t)tex : sg->texture_count;
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, FV_SCENE_TEXTURE_SET, 1,
                                    &sg->texture_sets[set], 0, NULL);
            bound_texture = tex;
        }
        uint32_t push[2] = {d, view};
        vkCmdPushConstants(cmd, layout, push_stages, 0, sizeof push, push);
        const fv_scene_gpu_mesh *m = &sg->meshes[dr->mesh];
        vkCmdDrawIndexed(cmd, m->index_count, 1, m->first_index, m->vertex_offset, 0);
        recorded++;
    }
    return recorded;
}
