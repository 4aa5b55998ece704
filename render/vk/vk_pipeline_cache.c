/* @brief The pipeline cache on disk (see fv_vk.h: fv_vk_pipeline_cache_open / _save): pipelines compiled by an earlier
 * run on the same device and driver are not compiled again. The file is Vulkan's own cache data; its header
 * (VkPipelineCacheHeaderVersionOne) is checked against this device before the driver sees it, and a corrupt or
 * foreign file is ignored with one warning line. Written back atomically (a temporary file renamed over it). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fv_file.h"
#include "fv_log.h"
#include "fv_vk.h"

#define MOD "vk"
#define CACHE_MAX_BYTES ((size_t)256 << 20)

/* mkdir -p of the directory part of path */
static void make_parent_dirs(const char *path)
{
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (!slash || slash == dir) return;
    *slash = '\0';
    for (char *p = dir + 1; *p; p++) {
        if (*p != '/') continue;
        *p = '\0';
        mkdir(dir, 0755);
        *p = '/';
    }
    mkdir(dir, 0755);
}

/* The file: $FOVEA_PIPELINE_CACHE (a path; "off" or "0": none), else $XDG_CACHE_HOME/fovea/, else ~/.cache/fovea/,
 * one file per vendor, device and driver version. false: no cache. */
static bool cache_path(const fv_vk *vk, char *out, size_t size)
{
    const char *env = getenv("FOVEA_PIPELINE_CACHE");
    if (env && (!strcmp(env, "off") || !strcmp(env, "0"))) return false;
    int n;
    if (env && *env) {
        n = snprintf(out, size, "%s", env);
    } else {
        const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
        char base[768];
        if (xdg && xdg[0] == '/') snprintf(base, sizeof base, "%s/fovea", xdg);
        else if (home && home[0] == '/') snprintf(base, sizeof base, "%s/.cache/fovea", home);
        else return false;
        n = snprintf(out, size, "%s/pipelines-%04x-%04x-%08x.bin", base, vk->props.vendorID, vk->props.deviceID,
                     vk->props.driverVersion);
    }
    return n > 0 && (size_t)n < size;
}

/* Why data is not this device's cache, or NULL when its header matches. */
static const char *foreign(const fv_vk *vk, const unsigned char *data, size_t len)
{
    if (len < 16 + VK_UUID_SIZE) return "shorter than a cache header";
    uint32_t f[4];
    memcpy(f, data, sizeof f); /* header size, version, vendor, device (little-endian on every host fovea runs on) */
    if (f[0] < 16 + VK_UUID_SIZE || f[0] > len) return "its header size is wrong";
    if (f[1] != VK_PIPELINE_CACHE_HEADER_VERSION_ONE) return "an unknown header version";
    if (f[2] != vk->props.vendorID || f[3] != vk->props.deviceID) return "made by another device";
    if (memcmp(data + 16, vk->props.pipelineCacheUUID, VK_UUID_SIZE) != 0) return "made by another driver version";
    return NULL;
}

void fv_vk_pipeline_cache_open(fv_vk *vk)
{
    vk->pipeline_cache = VK_NULL_HANDLE;
    vk->pipeline_cache_path[0] = '\0';
    if (!cache_path(vk, vk->pipeline_cache_path, sizeof vk->pipeline_cache_path)) return;
    char *data = NULL, why[FV_FILE_ERR_MAX];
    size_t len = 0;
    const char *bad = NULL;
    if (access(vk->pipeline_cache_path, F_OK) == 0) {
        if (fv_file_read(vk->pipeline_cache_path, "pipeline cache", CACHE_MAX_BYTES, &data, &len, why, sizeof why) !=
            FV_OK)
            bad = why;
        else
            bad = foreign(vk, (const unsigned char *)data, len);
        if (bad) {
            FV_WARN(MOD, "%s: ignored (%s); pipelines are compiled afresh", vk->pipeline_cache_path, bad);
            free(data);
            data = NULL;
            len = 0;
        }
    }
    VkPipelineCacheCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO, .initialDataSize = len,
                                    .pInitialData = data};
    VkResult r = vkCreatePipelineCache(vk->device, &ci, NULL, &vk->pipeline_cache);
    if (r < 0 && data) { /* the driver refused the data after all: start empty */
        FV_WARN(MOD, "%s: ignored (the driver refused it: %d); pipelines are compiled afresh",
                vk->pipeline_cache_path, (int)r);
        ci.initialDataSize = 0;
        ci.pInitialData = NULL;
        r = vkCreatePipelineCache(vk->device, &ci, NULL, &vk->pipeline_cache);
    }
    if (r < 0) vk->pipeline_cache = VK_NULL_HANDLE;
    vk->pipeline_cache_loaded_bytes = len;
    free(data);
}

void fv_vk_pipeline_cache_save(fv_vk *vk)
{
    if (!vk->pipeline_cache) return;
    size_t size = 0;
    void *data = NULL;
    if (vk->pipelines_created && vkGetPipelineCacheData(vk->device, vk->pipeline_cache, &size, NULL) >= 0 && size &&
        size <= CACHE_MAX_BYTES && (data = malloc(size)) &&
        vkGetPipelineCacheData(vk->device, vk->pipeline_cache, &size, data) >= 0) {
        char tmp[1100];
        snprintf(tmp, sizeof tmp, "%s.%ld.tmp", vk->pipeline_cache_path, (long)getpid());
        make_parent_dirs(vk->pipeline_cache_path);
        FILE *f = fopen(tmp, "wb");
        bool ok = f && fwrite(data, 1, size, f) == size;
        if (f && fclose(f) != 0) ok = false;
        if (ok && rename(tmp, vk->pipeline_cache_path) != 0) ok = false;
        if (!ok) {
            FV_WARN(MOD, "%s: the pipeline cache could not be written (%s)", vk->pipeline_cache_path, strerror(errno));
            unlink(tmp);
        }
    }
    free(data);
    vkDestroyPipelineCache(vk->device, vk->pipeline_cache, NULL);
    vk->pipeline_cache = VK_NULL_HANDLE;
}
