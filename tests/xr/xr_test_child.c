/* @brief The child side of the xr tests' fork/exec (see xr_test_child.h). */
#include "xr_test_child.h"

#include <fcntl.h>
#include <stdlib.h>
#include <unistd.h>

void xr_test_child_env(const char *log_path, const char *manifest, bool layer, const char *scale, const char *stats)
{
    setpgid(0, 0); /* its own process group: the parent's time limit ends it and what it started (fv_test_wait) */
    int fd = open(log_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) _exit(126);
    dup2(fd, 1);
    dup2(fd, 2);
    setenv("XR_RUNTIME_JSON", manifest, 1);
    if (layer) setenv("XR_ENABLE_API_LAYERS", "XR_APILAYER_LUNARG_core_validation", 1);
    else unsetenv("XR_ENABLE_API_LAYERS");
    setenv("FOVEA_VALIDATION", "1", 1);
    setenv("FOVEA_XR_SCALE", scale, 1);
    setenv("FOVEA_XR_STATS", stats, 1);
}
