/* @brief libFuzzer target: the model-file pre-checks (PLY ascii/binary, OBJ, OFF; the format found from the content
 * as for a file whose extension assimp does not know) on arbitrary bytes, then, for bytes the pre-check accepts,
 * assimp's import of them from memory. The pre-check's promise is that assimp never allocates more than a small
 * multiple of what the file holds: the run's malloc limit (512 MB for inputs of at most 64 KiB) turns a broken
 * promise into a failure. References to other files (OBJ mtllib) are refused, so a run reads no file. Leaks are
 * checked in the pre-check, not inside assimp. */
#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <sanitizer/lsan_interface.h>
#include <stddef.h>
#include <stdint.h>

#include "fv_log.h"
#include "fv_scene.h"
#include "scene_internal.h"

static void quiet(void *user, fv_log_level level, const char *module, const char *file, int line, const char *msg)
{
    (void)user, (void)level, (void)module, (void)file, (void)line, (void)msg;
}

static bool no_references(void *user, const char *origin, size_t line, const char *name)
{
    (void)user, (void)origin, (void)line, (void)name;
    return false;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fv_log_set_sink(quiet, NULL);
    fv_scene_precheck_format fmt = fv_scene_precheck_format_of("fuzz", data, size < 256 ? size : 256);
    if (fv_scene_precheck_bytes("fuzz", fmt, data, size, no_references, NULL) != FV_OK) return 0;
    static const char *const hints[] = {"", "ply", "obj", "off"};
    if (fmt == FV_SCENE_PRECHECK_NONE || size == 0) return 0;
    /* assimp (not ours, not instrumented) leaks on some malformed files: its allocations are not leak-checked; the
     * malloc limit still applies to them */
    __lsan_disable();
    const struct aiScene *s = aiImportFileFromMemory((const char *)data, (unsigned)size,
                                                     aiProcess_Triangulate | aiProcess_ValidateDataStructure,
                                                     hints[fmt]);
    aiReleaseImport(s);
    __lsan_enable();
    return 0;
}
