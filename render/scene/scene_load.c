/* @brief fv_scene_load: one entry point for built-in names, `*.scene.json` files and model files. */
#include <string.h>
#include <strings.h>

#include "fv_log.h"
#include "fv_scene.h"

static bool ends_with_nocase(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcasecmp(s + n - k, suffix) == 0;
}

fv_result fv_scene_load(const char *name_or_path, fv_scene **out_scene)
{
    if (!out_scene) return FV_ERR_INVALID_ARG;
    *out_scene = NULL;
    if (!name_or_path || !*name_or_path) {
        FV_ERROR("scene", "no scene name or path given");
        return FV_ERR_INVALID_ARG;
    }
    const char *name = name_or_path;
    if (!strncmp(name, "builtin:", 8)) return fv_scene_builtin(name + 8, out_scene);
    for (const char *const *b = fv_scene_builtin_names(); *b; b++)
        if (!strcmp(name, *b)) return fv_scene_builtin(name, out_scene);
    if (ends_with_nocase(name, ".scene.json")) return fv_scene_load_json_file(name, out_scene);
    return fv_scene_import(name, 0.0f, out_scene);
}
