/* @brief libFuzzer target: the scene-file parser on arbitrary bytes. Model files are refused (only built-ins load)
 * so a run never reads files outside the corpus; everything else (JSON paths, types, presets, lights, head) is
 * exercised. Any crash, sanitizer report or leak fails the test. */
#include <stddef.h>
#include <stdint.h>

#include "fv_log.h"
#include "fv_scene.h"
#include "scene_internal.h"

static void quiet(void *user, fv_log_level level, const char *module, const char *file, int line, const char *msg)
{
    (void)user, (void)level, (void)module, (void)file, (void)line, (void)msg;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fv_log_set_sink(quiet, NULL);
    fv_scene *s = NULL;
    if (fv_scene_parse_json((const char *)data, size, "/nonexistent", "fuzz.scene.json", false, &s) == FV_OK) {
        if (fv_scene_validate(s) != FV_OK) __builtin_trap(); /* a loaded scene is always valid */
        fv_vec3 lo, hi;
        (void)fv_scene_world_bounds(s, 1.5, &lo, &hi);
        (void)fv_scene_triangle_count(s);
    }
    fv_scene_destroy(&s);
    return 0;
}
