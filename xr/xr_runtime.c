/* @brief The loader's entry into fovea's OpenXR runtime: xrNegotiateLoaderRuntimeInterface (the one exported symbol)
 * and xrGetInstanceProcAddr. */
#include <string.h>

#include "fv_openxr.h"

#define FV_XR_EXPORT __attribute__((visibility("default")))

static XRAPI_ATTR XrResult XRAPI_CALL get_instance_proc_addr(XrInstance instance, const char *name,
                                                             PFN_xrVoidFunction *function)
{
    if (!function) return XR_ERROR_VALIDATION_FAILURE;
    *function = NULL;
    if (!name) return XR_ERROR_VALIDATION_FAILURE;
    return XR_ERROR_FUNCTION_UNSUPPORTED;
}

FV_XR_EXPORT XRAPI_ATTR XrResult XRAPI_CALL xrNegotiateLoaderRuntimeInterface(const XrNegotiateLoaderInfo *info,
                                                                              XrNegotiateRuntimeRequest *req)
{
    if (!info || !req) return XR_ERROR_INITIALIZATION_FAILED;
    if (info->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO ||
        info->structVersion != XR_LOADER_INFO_STRUCT_VERSION || info->structSize != sizeof *info)
        return XR_ERROR_INITIALIZATION_FAILED;
    if (req->structType != XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST ||
        req->structVersion != XR_RUNTIME_INFO_STRUCT_VERSION || req->structSize != sizeof *req)
        return XR_ERROR_INITIALIZATION_FAILED;
    if (info->minInterfaceVersion > XR_CURRENT_LOADER_RUNTIME_VERSION ||
        info->maxInterfaceVersion < XR_CURRENT_LOADER_RUNTIME_VERSION)
        return XR_ERROR_INITIALIZATION_FAILED;
    /* The runtime implements OpenXR 1.0 (patch 20 of the headers it is built with). */
    if (XR_VERSION_MAJOR(info->minApiVersion) > 1 || XR_VERSION_MAJOR(info->maxApiVersion) < 1)
        return XR_ERROR_INITIALIZATION_FAILED;
    req->runtimeInterfaceVersion = XR_CURRENT_LOADER_RUNTIME_VERSION;
    req->runtimeApiVersion = XR_CURRENT_API_VERSION;
    req->getInstanceProcAddr = get_instance_proc_addr;
    return XR_SUCCESS;
}
