/* @brief The shading pass (see shade.h). */
#include "shade.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shade_atomic_comp.spv.h"
#include "shade_comp.spv.h"
#include "shade_interface.h"

#define MOD "shade"

_Static_assert(sizeof(struct fv_shade_push) == 32, "fv_shade_push layout");
_Static_assert(FV_SHADE_GROUP_SIZE == FV_GPU_LIST_GROUP_SIZE, "list dispatches count FV_GPU_LIST_GROUP_SIZE pixels");
_Static_assert(FV_SHADE_BINDING_NORMAL == FV_SHADE_BINDING_DEPTH + 1 && FV_SHADE_BINDING_ALBEDO == FV_SHADE_BINDING_DEPTH + 2 &&
                   FV_SHADE_BINDING_MATERIAL == FV_SHADE_BINDING_DEPTH + 3,
               "fv_images_bind_gbuffer writes depth, normal, albedo, material in a row");

typedef struct shade {
    fv_vk *vk;
    uint32_t width, height, slots;
    fv_vk_compute cs;
    VkSampler nearest;
    fv_vk_buffer empty_list;                    /* a list with count 0, bound while no list is given */
    VkBuffer bound_list[FV_MAX_FRAMES_IN_FLIGHT]; /* what each slot's set points at */
} shade;

static const char *plural(uint64_t n) { return n == 1 ? "" : "s"; }

static void shade_plan(const fv_plan_context *ctx, fv_plan_entry *out)
{
    const fv_scene *s = ctx->scene;
    uint32_t by_type[3] = {0, 0, 0}, emissive = 0;
    for (uint32_t l = 0; s && l < s->light_count; l++)
        if ((unsigned)s->lights[l].type < 3) by_type[s->lights[l].type]++;
    /* Materials that some drawn mesh uses. */
    for (uint32_t m = 0; s && m < s->material_count; m++) {
        bool used = false;
        for (uint32_t i = 0; i < s->node_count && !used; i++) {
            const fv_node *n = &s->nodes[i];
            used = n->mesh >= 0 && (uint32_t)n->mesh < s->mesh_count && s->meshes[n->mesh].material == m;
        }
        fv_vec3 e = s->materials[m].emissive;
        if (used && (e.x > 0 || e.y > 0 || e.z > 0)) emissive++;
    }
    uint32_t lights = by_type[0] + by_type[1] + by_type[2];
    bool ambient = s && (s->ambient.x > 0 || s->ambient.y > 0 || s->ambient.z > 0);
    char what[120];
    int n = snprintf(what, sizeof what, "direct lighting from %u light%s (%u point, %u spot, %u directional)", lights,
                     plural(lights), by_type[FV_LIGHT_POINT], by_type[FV_LIGHT_SPOT], by_type[FV_LIGHT_DIRECTIONAL]);
    if (emissive && n > 0 && (size_t)n < sizeof what)
        n += snprintf(what + n, sizeof what - (size_t)n, " + %u emissive material%s", emissive, plural(emissive));
    if (ambient && n > 0 && (size_t)n < sizeof what) snprintf(what + n, sizeof what - (size_t)n, " + ambient");
    out->enabled = true;
    snprintf(out->reason, sizeof out->reason, "%s%s", what,
             (!lights && !emissive && !ambient) ? " — nothing emits light: black" : "");
}

static void shade_fini(void *state)
{
    shade *sh = state;
    if (!sh) return;
    fv_vk_compute_fini(sh->vk, &sh->cs);
    if (sh->nearest) vkDestroySampler(sh->vk->device, sh->nearest, NULL);
    fv_vk_buffer_destroy(sh->vk, &sh->empty_list);
    free(sh);
}

static void bind_list(shade *sh, uint32_t slot, VkBuffer list, VkDeviceSize offset, VkDeviceSize range)
{
    if (!list) {
        list = sh->empty_list.buffer;
        offset = 0;
        range = VK_WHOLE_SIZE;
    }
    if (sh->bound_list[slot] == list && list == sh->empty_list.buffer) return;
    fv_vk_write_buffer(sh->vk, sh->cs.sets[slot], FV_SHADE_BINDING_PIXELS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, list,
                       offset, range);
    sh->bound_list[slot] = list;
}

static fv_result shade_init(const fv_pass_env *env, void **out_state)
{
    shade *sh = calloc(1, sizeof *sh);
    if (!sh) return FV_ERR_NO_MEMORY;
    sh->vk = env->vk;
    sh->width = env->width;
    sh->height = env->height;
    sh->slots = env->slots;
    fv_vk *vk = env->vk;
    const fv_vk_image *color;
    fv_result res = fv_images_get_gbuffer(env->images);
    if (res == FV_OK) res = fv_images_get(env->images, FV_IMAGE_COLOR, &color);
    if (res == FV_OK) res = fv_vk_sampler_create(vk, false, false, "shade nearest sampler", &sh->nearest);
    if (res == FV_OK)
        res = fv_vk_buffer_create(vk, FV_GPU_LIST_HEADER_BYTES + 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                  FV_VK_MEM_UPLOAD, "shade empty pixel list", &sh->empty_list);
    if (res == FV_OK) {
        memset(sh->empty_list.mapped, 0, FV_GPU_LIST_HEADER_BYTES + 4);
        res = fv_vk_buffer_flush(vk, &sh->empty_list);
    }
    VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
    VkDescriptorSetLayoutBinding b[FV_SHADE_BINDING_COUNT] = {
        {FV_SHADE_BINDING_DEPTH, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_SHADE_BINDING_NORMAL, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_SHADE_BINDING_ALBEDO, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_SHADE_BINDING_MATERIAL, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, cs, NULL},
        {FV_SHADE_BINDING_COLOR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, cs, NULL},
        {FV_SHADE_BINDING_PIXELS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, cs, NULL},
    };
    /* The GI gather's work is counted per subgroup where compute shaders have arithmetic subgroup operations (one
     * set of atomics per subgroup), else per pixel (shade_atomic.comp: no subgroup capability in its SPIR-V). */
    VkPhysicalDeviceSubgroupProperties sg = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &sg};
    vkGetPhysicalDeviceProperties2(vk->phys, &p2);
    bool subgroups = (sg.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                     (sg.supportedOperations & VK_SUBGROUP_FEATURE_BASIC_BIT) &&
                     (sg.supportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT);
    /* FOVEA_SHADE_SUBGROUPS=0 takes the per-pixel path where subgroups exist (tests/gi runs it on lavapipe). */
    const char *force = getenv("FOVEA_SHADE_SUBGROUPS");
    if (force && strcmp(force, "0") == 0) subgroups = false;
    if (!subgroups)
        FV_INFO(MOD, "%s: GI work counted with atomics per pixel",
                force && strcmp(force, "0") == 0 ? "FOVEA_SHADE_SUBGROUPS=0"
                                                 : "no arithmetic subgroup operations in compute shaders");
    VkDescriptorSetLayout shared[2] = {env->scene->set_layout, env->shade_inputs->layout};
    _Static_assert(FV_SCENE_SET == 0 && FV_SHADE_INPUTS_SET == 1 && FV_SHADE_SET == 2, "shade's set order");
    fv_vk_compute_desc cd = {.name = "shade", .code = subgroups ? fv_spv_shade_comp : fv_spv_shade_atomic_comp,
                             .code_size = subgroups ? sizeof fv_spv_shade_comp : sizeof fv_spv_shade_atomic_comp,
                             .shared_sets = shared, .shared_set_count = 2, .bindings = b,
                             .binding_count = FV_SHADE_BINDING_COUNT, .set_count = env->slots,
                             .push_bytes = sizeof(struct fv_shade_push)};
    if (res == FV_OK) res = fv_vk_compute_init(vk, &cd, &sh->cs);
    for (uint32_t i = 0; res == FV_OK && i < env->slots; i++) {
        VkDescriptorSet set = sh->cs.sets[i];
        fv_images_bind_gbuffer(env->images, set, FV_SHADE_BINDING_DEPTH, sh->nearest);
        fv_vk_write_image(vk, set, FV_SHADE_BINDING_COLOR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, color->view,
                          VK_NULL_HANDLE, VK_IMAGE_LAYOUT_GENERAL);
        bind_list(sh, i, VK_NULL_HANDLE, 0, 0);
    }
    if (res != FV_OK) {
        FV_ERROR(MOD, "shading pass could not be created: %s", fv_result_str(res));
        shade_fini(sh);
        return res;
    }
    *out_state = sh;
    return FV_OK;
}

static void shade_record(void *state, const fv_pass_frame *f)
{
    shade *sh = state;
    VkCommandBuffer cmd = f->cmd;
    const fv_pixel_list *list = f->pixels;
    fv_vk_label_begin(sh->vk, cmd, list ? "shade (pixel list)" : "shade (all pixels)");
    VkPipelineStageFlags cs = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    fv_images *im = f->images;
    fv_images_use_gbuffer(im, cmd, cs);
    fv_shade_inputs_use(f->shade_inputs, im, cmd, cs);
    fv_images_use(im, cmd, FV_IMAGE_COLOR, (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, cs, VK_ACCESS_SHADER_WRITE_BIT});

    /* The pixel binding of this slot's set: the GPU is done with the slot when its frame is recorded. */
    if (list) bind_list(sh, f->slot, list->buffer, list->offset, list->range);
    else bind_list(sh, f->slot, VK_NULL_HANDLE, 0, 0);

    struct fv_shade_push pc;
    memset(&pc, 0, sizeof pc);
    pc.tiles_x = (sh->width + FV_SHADE_GROUP_X - 1) / FV_SHADE_GROUP_X;
    pc.tiles_y = (sh->height + FV_SHADE_GROUP_Y - 1) / FV_SHADE_GROUP_Y;
    pc.tile_count = pc.tiles_x * pc.tiles_y * 2u;
    pc.tiles_per_stripe = (pc.tile_count + FV_SHADE_STRIPES - 1) / FV_SHADE_STRIPES;
    uint32_t total = pc.tiles_per_stripe * FV_SHADE_STRIPES;
    uint32_t max_x = sh->vk->props.limits.maxComputeWorkGroupCount[0];
    pc.groups_x = total < max_x ? total : max_x;
    pc.mode = list ? FV_SHADE_MODE_LIST : FV_SHADE_MODE_ALL;
    VkDescriptorSet shared[2] = {f->scene_set, fv_shade_inputs_set(f->shade_inputs, f->slot)};
    fv_vk_compute_bind(&sh->cs, cmd, 0, shared, 2, f->slot, &pc);
    if (list) {
        if (list->indirect) vkCmdDispatchIndirect(cmd, list->indirect, list->indirect_offset);
        if (list->count_on_gpu) f->counters->gpu_lists++; /* the renderer adds the list's size after the frame */
        else f->counters->pixels_shaded += list->host_count;
    } else {
        vkCmdDispatch(cmd, pc.groups_x, (total + pc.groups_x - 1) / pc.groups_x, 1);
        f->counters->pixels_shaded += (uint64_t)sh->width * sh->height * 2u;
    }
    f->counters->dispatches++;
    fv_vk_label_end(sh->vk, cmd);
}

const fv_pass fv_shade_pass = {
    .id = "shade",
    .flags = FV_PASS_REPLAYS_ON_PIXELS,
    .plan = shade_plan,
    .init = shade_init,
    .record = shade_record,
    .fini = shade_fini,
};
