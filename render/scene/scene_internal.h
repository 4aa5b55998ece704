/* @brief Helpers shared by the files of render/scene (not part of the public API). */
#ifndef FV_SCENE_INTERNAL_H
#define FV_SCENE_INTERNAL_H

#include <stddef.h>

#include "fv_scene.h"

/** Copy a NUL-terminated string into a fixed buffer, truncating. */
void fv_scene_copy_name(char *dst, size_t cap, const char *src);
/** Quaternion of the rotation whose columns are the local +x, +y, +z axes in world space (orthonormal). */
fv_quat fv_scene_quat_from_basis(fv_vec3 right, fv_vec3 up, fv_vec3 back);

/** What scene_merge does to every item it copies from src into dst. */
typedef struct fv_scene_merge_desc {
    const fv_node *root;            /* node that parents src's root nodes (its TRS and animation); NULL: none */
    const fv_material *override;    /* when set, every merged material takes its fields where override_mask says */
    unsigned override_mask;         /* FV_MERGE_BASE_COLOR | FV_MERGE_TRANSLUCENCY | FV_MERGE_EMISSIVE */
    bool take_lights;               /* copy src's lights (moved by root's static transform) */
} fv_scene_merge_desc;

enum { FV_MERGE_BASE_COLOR = 1u, FV_MERGE_TRANSLUCENCY = 2u, FV_MERGE_EMISSIVE = 4u };

/** Move src's meshes, textures, materials, nodes and lights into dst (indices remapped). src keeps its arrays
 *  but loses mesh/texture ownership (its pointers are cleared); destroy it afterwards. */
FV_MUST_CHECK fv_result fv_scene_merge(fv_scene *dst, fv_scene *src, const fv_scene_merge_desc *desc);

/** fv_scene_import with a choice: default_lights false leaves a file with no light unlit (a scene file composing
 *  several models adds one default light for the whole scene instead). */
FV_MUST_CHECK fv_result fv_scene_import_ex(const char *path, float unit_scale_m, bool default_lights,
                                           fv_scene **out_scene);
/** Add the default light(s) for a scene with none: spots at emissive surfaces, else a point light above the head.
 *  Logs an info line naming origin. */
FV_MUST_CHECK fv_result fv_scene_add_default_lights(fv_scene *s, const char *origin);
/** Scene-file parser; allow_model_files false refuses every non-builtin model (the fuzzer uses this). */
FV_MUST_CHECK fv_result fv_scene_parse_json(const char *json, size_t len, const char *base_dir, const char *origin,
                                            bool allow_model_files, fv_scene **out_scene);

#endif
