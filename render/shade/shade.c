/* @brief The shading pass (see shade.h). */
#include "shade.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shade_atomic_comp.spv.h"
#include "shade_comp.spv.h"
#include "fv_gi_interface.glsl"
#include "shade_interface.h"

#define MOD "shade"

_Static_assert(sizeof(struct fv_shade_push) == 32, "fv_shade_push layout");
_Static_assert(FV_SHADE_GROUP_SIZE == FV_GPU_LIST_GROUP_SIZE, "list dispatches count FV_GPU_LIST_GROUP_SIZE pixels");
_Static_assert(FV_SHADE_BINDING_NORMAL == FV_SHADE_BINDING_DEPTH + 1 && FV_SHADE_BINDING_ALBEDO == FV_SHADE_BINDING_DEPTH + 2 &&
                   FV_SHADE_BINDING_MATERIAL == FV_SHADE_BINDING_DEPTH + 3,
               "fv_images_bind_gbuffer writes depth, normal, albedo, material in a row");

/* Pipelines specialised per feature set (fv_gpu.h FV_SPEC_ID_*): GI mode or off, SSS, shadows, the GI rate. */
#define SHADE_GI_KEYS (FV_GI_EXACT + 3) /* any, off, and each mode */
#define SHADE_RATES 4                   /* per pixel, 2, 4, 8 (render/gi_gather) */
#define SHADE_SPECS 5                   /* constant ids 0..FV_SPEC_ID_GI_RATE */
#define SHADE_VARIANTS (SHADE_GI_KEYS * 2 * 2 * SHADE_RATES)
_Static_assert(FV_SPEC_ID_GI_RATE == SHADE_SPECS - 1, "spec[] holds every id");

typedef struct shade {
    fv_vk *vk;
    uint32_t width, height, slots;
    fv_vk_compute cs;                 /* layout and sets; its pipelines are the variants below, made on first use */
    const uint32_t *code;
    size_t code_size;
    VkPipeline variant[SHADE_VARIANTS];
    bool variant_failed[SHADE_VARIANTS];
    uint32_t variants_made;
    int32_t last_spec[4]; /* what the last recorded frame's pipeline has compiled in: GI mode, SSS, shadows, rate */
    bool have_last;
    bool translucent; /* the scene has a translucent material that a drawn mesh uses: the dipole may be needed */
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
    /* variant 1: a drawn mesh is translucent, so the pipelines keep the dipole's code (with sss.enabled); a scene
     * that changes this starts the pass again */
    out->variant = fv_scene_has_translucency(s) ? 1u : 0u;
    snprintf(out->reason, sizeof out->reason, "%s%s", what,
             (!lights && !emissive && !ambient) ? " — nothing emits light: black" : "");
}

static void shade_fini(void *state)
{
    shade *sh = state;
    if (!sh) return;
    for (uint32_t v = 0; v < SHADE_VARIANTS; v++)
        if (sh->variant[v]) vkDestroyPipeline(sh->vk->device, sh->variant[v], NULL);
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
    sh->translucent = env->plan && env->plan->variant == 1u; /* shade_plan */
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
                             .push_bytes = sizeof(struct fv_shade_push), .lazy = true};
    sh->code = cd.code;
    sh->code_size = cd.code_size;
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

/* The feature set a frame's quality leaves on, as the specialisation constants' values (constant id i = spec[i]; id 0
 * unused here) and an index into the variants. Off is decided from the knobs only: a technique that is on but finds
 * nothing to do (GI without a spot light) keeps its code and returns early from its header, as before. */
static uint32_t variant_of(const fv_quality *q, bool translucent, uint32_t spec[SHADE_SPECS])
{
    int32_t gi = !q->gi.enabled ? FV_SPEC_GI_OFF : (uint32_t)q->gi.mode <= FV_GI_EXACT ? (int32_t)q->gi.mode
                                                                                           : FV_SPEC_GI_ANY;
    bool sss = q->sss.enabled && translucent, shadows = q->shadow.enabled;
    spec[0] = 0;
    spec[FV_SPEC_ID_GI_MODE] = (uint32_t)gi;
    spec[FV_SPEC_ID_SSS] = sss;
    spec[FV_SPEC_ID_SHADOWS] = shadows;
    /* the upsample of the reduced-rate gather only where GI is on at a reduced rate: else not in the pipeline */
    uint32_t r = gi == FV_SPEC_GI_OFF ? 1u : fv_gi_rate_factor((uint32_t)q->gi.rate);
    spec[FV_SPEC_ID_GI_RATE] = r;
    uint32_t rate = r == 8u ? 3u : r == 4u ? 2u : r == 2u ? 1u : 0u;
    return (((uint32_t)(gi - FV_SPEC_GI_ANY) * 2u + (sss ? 1u : 0u)) * 2u + (shadows ? 1u : 0u)) * SHADE_RATES + rate;
}

const char *fv_shade_variant_name(const fv_quality *q, bool translucent, char *buf, size_t size)
{
    uint32_t spec[SHADE_SPECS];
    (void)variant_of(q, translucent, spec);
    int32_t gi = (int32_t)spec[FV_SPEC_ID_GI_MODE];
    snprintf(buf, size, "gi=%s sss=%s shadows=%s gi_rate=%u",
             gi == FV_SPEC_GI_OFF ? "off" : gi == FV_SPEC_GI_ANY ? "any" : (const char *[]){"cut", "traverse", "bound", "rsm_sampling", "exact"}[gi],
             spec[FV_SPEC_ID_SSS] ? "on" : "off", spec[FV_SPEC_ID_SHADOWS] ? "on" : "off", spec[FV_SPEC_ID_GI_RATE]);
    return buf;
}

/* The pipeline of the frame's feature set, made on first use; VK_NULL_HANDLE after a failure (logged once). */
static VkPipeline pipeline_for(shade *sh, const fv_quality *q)
{
    uint32_t spec[SHADE_SPECS];
    uint32_t v = variant_of(q, sh->translucent, spec);
    if (v >= SHADE_VARIANTS) return VK_NULL_HANDLE;
    if (!sh->variant[v] && !sh->variant_failed[v]) {
        char name[112], what[80];
        snprintf(name, sizeof name, "shade (%s)", fv_shade_variant_name(q, sh->translucent, what, sizeof what));
        if (FV_FAILED(fv_vk_compute_pipeline(sh->vk, sh->code, sh->code_size, sh->cs.layout, spec, SHADE_SPECS, name,
                                             &sh->variant[v]))) {
            FV_ERROR(MOD, "%s: the pipeline could not be made; those frames stay unshaded", name);
            sh->variant_failed[v] = true;
            sh->variant[v] = VK_NULL_HANDLE;
        }
        sh->variants_made++;
    }
    sh->last_spec[0] = (int32_t)spec[FV_SPEC_ID_GI_MODE];
    sh->last_spec[1] = (int32_t)spec[FV_SPEC_ID_SSS];
    sh->last_spec[2] = (int32_t)spec[FV_SPEC_ID_SHADOWS];
    sh->last_spec[3] = (int32_t)spec[FV_SPEC_ID_GI_RATE];
    sh->have_last = true;
    return sh->variant[v];
}

static uint32_t shade_details(void *state, fv_pass_detail *out, uint32_t cap)
{
    shade *sh = state;
    uint32_t n = 0;
    /* what the running pipeline has compiled in (-1 GI off, -2 every mode chosen at run time, else the mode) */
    if (sh->have_last) {
        n = fv_pass_detail_add(out, n, cap, "compiled_gi_mode_sss_shadows", 3, sh->last_spec[0], sh->last_spec[1],
                               sh->last_spec[2]);
        /* the GI rate compiled in: 1 the per-pixel gather alone, 2, 4 or 8 the upsample of render/gi_gather */
        n = fv_pass_detail_add(out, n, cap, "compiled_gi_rate", 1, sh->last_spec[3], 0, 0);
    }
    return fv_pass_detail_add(out, n, cap, "pipelines_made", 1, sh->variants_made, 0, 0);
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
    fv_quality q = f->input ? f->input->quality : fv_quality_default();
    VkPipeline pipe = pipeline_for(sh, &q);
    if (!pipe) {
        fv_vk_label_end(sh->vk, cmd);
        return;
    }
    fv_vk_compute_bind_pipeline(&sh->cs, cmd, pipe, shared, 2, f->slot, &pc);
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
    .details = shade_details,
};
