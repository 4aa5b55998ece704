/* @brief fovea's OpenXR declarations: Debian's <openxr/openxr.h> (1.0.20) plus what it lacks, each declared from
   the OpenXR specification with its extension number and guarded by #ifndef. Shared by xr/ and xr/input/:
   additive edits only. Vulkan types come with it (XR_KHR_vulkan_enable/enable2 in <openxr/openxr_platform.h>). */
#ifndef FV_OPENXR_H
#define FV_OPENXR_H

#include <stddef.h>
#include <stdint.h>
#include <time.h>

#include <vulkan/vulkan.h>
#ifndef XR_USE_GRAPHICS_API_VULKAN
#define XR_USE_GRAPHICS_API_VULKAN 1
#endif
#ifndef XR_USE_TIMESPEC
#define XR_USE_TIMESPEC 1
#endif
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

/* ---- Loader <-> runtime negotiation (OpenXR loader specification, "Runtime Interface Negotiation"). Not an
 * extension: the loader's loader_interfaces.h declares it, and Debian's 1.0.20 packages do not install it. */
#ifndef XR_CURRENT_LOADER_RUNTIME_VERSION
typedef enum XrLoaderInterfaceStructs {
    XR_LOADER_INTERFACE_STRUCT_UNINTIALIZED = 0,
    XR_LOADER_INTERFACE_STRUCT_LOADER_INFO = 1,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST = 2,
    XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST = 3,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO = 4,
    XR_LOADER_INTERFACE_STRUCT_API_LAYER_NEXT_INFO = 5,
    XR_LOADER_INTERFACE_STRUCTS_MAX_ENUM = 0x7FFFFFFF
} XrLoaderInterfaceStructs;

#define XR_LOADER_INFO_STRUCT_VERSION 1
typedef struct XrNegotiateLoaderInfo {
    XrLoaderInterfaceStructs structType; /* XR_LOADER_INTERFACE_STRUCT_LOADER_INFO */
    uint32_t structVersion;              /* XR_LOADER_INFO_STRUCT_VERSION */
    size_t structSize;                   /* sizeof(XrNegotiateLoaderInfo) */
    uint32_t minInterfaceVersion;
    uint32_t maxInterfaceVersion;
    XrVersion minApiVersion;
    XrVersion maxApiVersion;
} XrNegotiateLoaderInfo;

#define XR_CURRENT_LOADER_RUNTIME_VERSION 1
#define XR_RUNTIME_INFO_STRUCT_VERSION 1
typedef struct XrNegotiateRuntimeRequest {
    XrLoaderInterfaceStructs structType; /* XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST */
    uint32_t structVersion;              /* XR_RUNTIME_INFO_STRUCT_VERSION */
    size_t structSize;                   /* sizeof(XrNegotiateRuntimeRequest) */
    uint32_t runtimeInterfaceVersion;    /* out: the loader interface version the runtime speaks */
    XrVersion runtimeApiVersion;         /* out: the OpenXR API version the runtime implements */
    PFN_xrGetInstanceProcAddr getInstanceProcAddr; /* out */
} XrNegotiateRuntimeRequest;

typedef XrResult(XRAPI_PTR *PFN_xrNegotiateLoaderRuntimeInterface)(const XrNegotiateLoaderInfo *loaderInfo,
                                                                   XrNegotiateRuntimeRequest *runtimeRequest);
#endif

/* ---- XR_VARJO_quad_views (extension 38) and XR_VARJO_foveated_rendering (extension 122, revision 2 with
 * XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO): Debian's 1.0.20 header has both; nothing to declare here. */

/* ---- XR_EXT_local_floor (extension 427): a gravity-aligned space at floor level below LOCAL. */
#ifndef XR_EXT_local_floor
#define XR_EXT_local_floor 1
#define XR_EXT_local_floor_SPEC_VERSION 1
#define XR_EXT_LOCAL_FLOOR_EXTENSION_NAME "XR_EXT_local_floor"
#define XR_REFERENCE_SPACE_TYPE_LOCAL_FLOOR_EXT ((XrReferenceSpaceType)1000426000)
#endif

#endif /* FV_OPENXR_H */
