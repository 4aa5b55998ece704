/* @brief Loading a scene into the renderer: the GPU copy (fv_scene_gpu) and the copy of the scene's structure that
 * planning reads (nodes, meshes without vertex data, materials, lights), and forgetting both. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "renderer_internal.h"

static void free_plan_scene(fv_renderer *r)
{
    free(r->plan_scene.nodes);
    free(r->plan_scene.meshes);
    free(r->plan_scene.materials);
    free(r->plan_scene.lights);
    memset(&r->plan_scene, 0, sizeof r->plan_scene);
}

void fv_renderer_release_scene(fv_renderer *r)
{
    fv_scene_gpu_unload(&r->scene);
    free_plan_scene(r);
    r->scene_loaded = false;
    r->have_prev = false;
    r->have_frame = false;
    memset(r->history_valid, 0, sizeof r->history_valid); /* frame ids may start over with the next scene */
}

/* What planning looks at: the scene's structure without vertex data or textures. */
static fv_result copy_plan_scene(fv_renderer *r, const fv_scene *s)
{
    fv_scene *p = &r->plan_scene;
    memset(p, 0, sizeof *p);
    snprintf(p->name, sizeof p->name, "%s", s->name);
    snprintf(p->source, sizeof p->source, "%s", s->source);
    p->unit_scale_m = s->unit_scale_m;
    p->head = s->head;
    p->ambient = s->ambient;
    p->nodes = malloc((s->node_count ? s->node_count : 1) * sizeof *p->nodes);
    p->meshes = malloc((s->mesh_count ? s->mesh_count : 1) * sizeof *p->meshes);
    p->materials = malloc((s->material_count ? s->material_count : 1) * sizeof *p->materials);
    p->lights = malloc((s->light_count ? s->light_count : 1) * sizeof *p->lights);
    if (!p->nodes || !p->meshes || !p->materials || !p->lights) return FV_ERR_NO_MEMORY;
    memcpy(p->nodes, s->nodes, s->node_count * sizeof *p->nodes);
    p->node_count = s->node_count;
    for (uint32_t m = 0; m < s->mesh_count; m++) {
        p->meshes[m] = s->meshes[m];
        p->meshes[m].positions = p->meshes[m].normals = NULL;
        p->meshes[m].texcoords = NULL;
        p->meshes[m].indices = NULL;
    }
    p->mesh_count = s->mesh_count;
    memcpy(p->materials, s->materials, s->material_count * sizeof *p->materials);
    p->material_count = s->material_count;
    memcpy(p->lights, s->lights, s->light_count * sizeof *p->lights);
    p->light_count = s->light_count;
    return FV_OK;
}

fv_result fv_renderer_load_scene(fv_renderer *r, const fv_scene *scene)
{
    if (!r || !scene) return FV_ERR_INVALID_ARG;
    fv_result res = fv_renderer_finish(r);
    if (res != FV_OK) return res;
    VkResult vr = vkDeviceWaitIdle(r->vk->device);
    if (vr < 0) return fv_vk_fail(vr, "vkDeviceWaitIdle", __FILE__, __LINE__);
    fv_renderer_release_scene(r);
    res = fv_scene_gpu_load(&r->scene, scene);
    if (res == FV_OK) res = copy_plan_scene(r, scene);
    if (res != FV_OK) goto fail;
    r->head = scene->head;
    r->has_bounds = fv_scene_world_bounds(scene, 0.0, &r->bounds_min, &r->bounds_max);
    r->scene_loaded = true;
    res = fv_renderer_plan_apply(r, &r->plan_quality);
    if (res != FV_OK) goto fail;
    FV_INFO(MOD, "%s: %u draws, %u lights, %llu triangles uploaded", scene->source, r->scene.draw_count,
            r->scene.light_count, (unsigned long long)fv_scene_triangle_count(scene));
    fv_scene_warn_cost(scene, r->desc.eye_width, r->desc.eye_height, "the shade pass");
    return FV_OK;
fail:
    FV_ERROR(MOD, "%s: loading the scene into the renderer failed: %s", scene->source, fv_result_str(res));
    fv_renderer_release_scene(r);
    return res;
}
