/* @brief Runtime version string. */
#include "fovea_config.h"

const char *fv_runtime_version(void);
const char *fv_runtime_version(void) { return FV_VERSION_STRING; }
