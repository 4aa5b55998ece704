/* @brief Helpers shared by the files of render/scene (not part of the public API). */
#ifndef FV_SCENE_INTERNAL_H
#define FV_SCENE_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fv_scene.h"

/** Copy a NUL-terminated name into a fixed buffer. One that does not fit is cut visibly: before a UTF-8 character
 *  that does not fit whole, then "..." (paths are never cut: their loaders refuse what does not fit). */
void fv_scene_copy_name(char *dst, size_t cap, const char *src);
/** Quaternion of the rotation whose columns are the local +x, +y, +z axes in world space (orthonormal). */

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

/** Model-file pre-checks (scene_precheck.c): the counts and list lengths a file declares against what its bytes can
 *  hold and the FV_SCENE_MAX_* limits, before assimp allocates for them. */
typedef enum fv_scene_precheck_format {
    FV_SCENE_PRECHECK_NONE = 0, /* no pre-check for this format */
    FV_SCENE_PRECHECK_PLY,      /* ascii and binary (both endians): element counts, every list length, face indices */
    FV_SCENE_PRECHECK_OBJ,      /* vertex and index counts, material libraries (through the callback) */
    FV_SCENE_PRECHECK_OFF,      /* vertex and face counts against the file size */
} fv_scene_precheck_format;
/** A file the model refers to (an OBJ mtllib name, as written); false (after logging why) refuses the model. */
typedef bool (*fv_scene_precheck_ref_fn)(void *user, const char *origin, size_t line, const char *name);
/** The pre-check for a model file: by extension (.ply, .obj, .off), and for an extension assimp does not claim, by
 *  content (head: the first bytes), as assimp picks its reader. */
fv_scene_precheck_format fv_scene_precheck_format_of(const char *path, const uint8_t *head, size_t n);
/** Pure check of a file's bytes (no I/O; ref may be NULL: references are not checked). Errors name origin and the
 *  header line, element or item. FV_OK also for bytes that are not of this format (assimp reports those). */
FV_MUST_CHECK fv_result fv_scene_precheck_bytes(const char *origin, fv_scene_precheck_format format,
                                                const uint8_t *bytes, size_t len, fv_scene_precheck_ref_fn ref,
                                                void *user);
/** Map the file (size bytes, a regular file) and run its pre-check; OBJ material libraries must be regular files
 *  of at most 64 MiB. */
FV_MUST_CHECK fv_result fv_scene_precheck_file(const char *path, uint64_t size);

#endif
