/* @brief Names of fv_result codes. */
#include "fv_result.h"

const char *fv_result_str(fv_result r)
{
    switch (r) {
    case FV_OK: return "FV_OK";
    case FV_TIMEOUT: return "FV_TIMEOUT";
    case FV_NO_NEW_DATA: return "FV_NO_NEW_DATA";
    case FV_END_OF_STREAM: return "FV_END_OF_STREAM";
    case FV_ERR_INVALID_ARG: return "FV_ERR_INVALID_ARG";
    case FV_ERR_NO_MEMORY: return "FV_ERR_NO_MEMORY";
    case FV_ERR_IO: return "FV_ERR_IO";
    case FV_ERR_PROTOCOL: return "FV_ERR_PROTOCOL";
    case FV_ERR_PARSE: return "FV_ERR_PARSE";
    case FV_ERR_VULKAN: return "FV_ERR_VULKAN";
    case FV_ERR_DEVICE_LOST: return "FV_ERR_DEVICE_LOST";
    case FV_ERR_UNSUPPORTED: return "FV_ERR_UNSUPPORTED";
    case FV_ERR_NOT_FOUND: return "FV_ERR_NOT_FOUND";
    case FV_ERR_RANGE: return "FV_ERR_RANGE";
    case FV_ERR_STATE: return "FV_ERR_STATE";
    case FV_ERR_CANCELLED: return "FV_ERR_CANCELLED";
    }
    return "FV_RESULT_UNKNOWN";
}
