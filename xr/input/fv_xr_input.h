/* @brief fovea's OpenXR action system (pure: no Vulkan, no clock, no I/O beyond the log, no threads): the path
   table, interaction profiles, action sets, actions, suggested bindings, attachment, the xrSyncActions snapshot,
   bound sources, localized names, haptics and pose bindings.

   The contract with xr/ (issue 14). Changes to the contract's signatures: none. Additions: fields at the END of
   fv_xr_input_desc (max_paths) and fv_xr_input_devices (time, hand_profiles, values: zero = as before), the type
   fv_xr_input_value, and the functions after the contract ones: fv_xr_input_sync_unfocused, fv_xr_input_is_attached,
   fv_xr_input_deactivate, fv_xr_input_owns_handle.

   NOTE to xr-core (xr-input, 01:52 UTC): two additions for xr_input_entry.c: call fv_xr_input_deactivate(s->input)
   when a session stops running (xrEndSession, loss) so state queries read inactive as the spec requires, and let
   instance_of_session_less() pick the live instance for which fv_xr_input_owns_handle(inst->input, handle) is true
   (today a second instance's action sets get XR_ERROR_HANDLE_INVALID). Delete this note when done.

   Rules the runtime (xr/) keeps, because they need the session state this library does not see:
   - xrSyncActions on a session that is not FOCUSED: call fv_xr_input_sync_unfocused (XR_SESSION_NOT_FOCUSED).
   - xrGetActionState* / haptics while the session is not running: the spec wants isActive false and haptics
     suppressed: call fv_xr_input_deactivate when the session stops running (xrEndSession, loss), and suppress
     haptics there yourself (fovea has no haptic device today).
   - XrEventDataInteractionProfileChanged: only for running sessions; the profile changes inside a sync (the spec:
     "Interaction profile selection changes must only happen when xrSyncActions is called"), so ask
     fv_xr_input_take_profile_changed after each fv_xr_input_sync / _sync_unfocused.
   - XR_ERROR_HANDLE_INVALID for the XrInstance / XrSession handles themselves.

   Handle lifetime (spec, xrDestroyAction / xrDestroyActionSet): destroying a handle invalidates the handle only;
   the action's state lives on while a session has its set attached, so action spaces stay locatable and
   fv_xr_input_pose_source accepts an action whose handle was destroyed.

   Choices the spec leaves to the runtime: a boolean action bound to a scalar is pressed above 0.5 and released
   below 0.4 (per action and subaction filter); the pose source is the first suggested binding that is live; a pose
   action bound to the eye gaze is active while a gaze source is present (a blink or lost tracking keeps it active:
   the runtime clears the location's TRACKED bits); attached sets keep the suggested bindings they had at attach;
   an action declared with subaction paths ignores its bindings under other top-level paths. */
#ifndef FV_XR_INPUT_H
#define FV_XR_INPUT_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_openxr.h" /* <openxr/openxr.h> + what 1.0.20 lacks */

/* Per XrInstance: the path table, interaction profiles (all of OpenXR 1.0's core profiles plus
   ext/eye_gaze_interaction when that extension is enabled), action sets, actions, suggested bindings.
   Per XrSession: attached action sets, current interaction profile per top-level user path, the state snapshot.
   Not thread-safe: the runtime serialises calls (one mutex per instance). Handles XrActionSet/XrAction are
   allocated and validated here (XR_ERROR_HANDLE_INVALID for a stale or foreign handle). */
typedef struct fv_xr_input fv_xr_input;
typedef struct fv_xr_input_session fv_xr_input_session;

typedef struct fv_xr_input_desc {
    bool eye_gaze_ext_enabled;
    uint32_t max_paths; /* XR_ERROR_PATH_COUNT_EXCEEDED past this many path atoms; 0 = 262144 */
} fv_xr_input_desc;
/** One per XrInstance. desc may be NULL (no extension enabled). */
XrResult fv_xr_input_create(const fv_xr_input_desc *desc, fv_xr_input **out);
/** Destroys its action sets, actions and any session still alive (those pointers become invalid). */
void fv_xr_input_destroy(fv_xr_input **in);

/* xrStringToPath / xrPathToString (the whole spec's path syntax rules: XR_ERROR_PATH_FORMAT_INVALID,
   XR_ERROR_PATH_INVALID, XR_ERROR_PATH_COUNT_EXCEEDED, two-call idiom with XR_ERROR_SIZE_INSUFFICIENT) */
XrResult fv_xr_input_string_to_path(fv_xr_input *in, const char *str, XrPath *out);
XrResult fv_xr_input_path_to_string(fv_xr_input *in, XrPath path, uint32_t capacity, uint32_t *count_out, char *buf);

XrResult fv_xr_input_create_action_set(fv_xr_input *in, const XrActionSetCreateInfo *info, XrActionSet *out);
XrResult fv_xr_input_destroy_action_set(fv_xr_input *in, XrActionSet set);
XrResult fv_xr_input_create_action(fv_xr_input *in, XrActionSet set, const XrActionCreateInfo *info, XrAction *out);
XrResult fv_xr_input_destroy_action(fv_xr_input *in, XrAction action);
XrResult fv_xr_input_suggest_bindings(fv_xr_input *in, const XrInteractionProfileSuggestedBinding *b);

/** One component value of a present device, named by its full binding path in the device's interaction
 *  profile ("/user/hand/left/input/trigger/value"). click/touch: 0 or 1; value/force: 0..1; x, y, twist: -1..1
 *  (clamped; NaN reads 0). A component of a present device that is not listed reads its rest state 0. */
typedef struct fv_xr_input_value {
    const char *path;
    float value;
    XrTime changed_time; /* when the device saw this value change; 0: unknown (devices.time is used) */
} fv_xr_input_value;

/* What fovea's devices provide right now; the runtime fills it before each sync. */
typedef struct fv_xr_input_devices {
    bool eye_gaze_present; /* a gaze source is open: the eye-gaze profile may become current */
    bool eye_gaze_tracked; /* the newest prediction is valid (not a blink, not lost) */
    bool hands_present[2]; /* controllers (none in fovea today: false) */
    /* values of controller components could follow here; none today */
    XrTime time;                   /* the runtime's XrTime of this state: lastChangeTime of a change without its own */
    const char *hand_profiles[2];  /* interaction profile path each hand's device is (NULL: none in particular) */
    const fv_xr_input_value *values; /* value_count component values (borrowed for the call) */
    uint32_t value_count;
} fv_xr_input_devices;

/** One per XrSession (the runtime owns the XrSession handle). */
XrResult fv_xr_input_session_create(fv_xr_input *in, fv_xr_input_session **out);
void fv_xr_input_session_destroy(fv_xr_input_session **s);
XrResult fv_xr_input_attach(fv_xr_input_session *s, const XrSessionActionSetsAttachInfo *info);
/* Called by the runtime when the session first becomes focused / when devices change: picks the current
   interaction profile per top-level path from the suggested bindings and the devices. The choice takes effect at
   the next sync (fv_xr_input_sync, which also re-picks from the devices it is given, or _sync_unfocused): the spec
   allows profile changes only inside xrSyncActions. Per hand: the device's own profile (hand_profiles) when the
   app suggested it, else khr/simple_controller (emulated) when suggested, else the first suggested hand profile;
   /user/eyes_ext: ext/eye_gaze_interaction while a gaze source is present; other paths: none (no devices). */
void fv_xr_input_update_profiles(fv_xr_input_session *s, const fv_xr_input_devices *dev);
XrResult fv_xr_input_get_current_interaction_profile(fv_xr_input_session *s, XrPath top_level_user_path,
                                                     XrInteractionProfileState *out);
/* true once after the current profile of any top-level path changed (the runtime queues
   XrEventDataInteractionProfileChanged). */
bool fv_xr_input_take_profile_changed(fv_xr_input_session *s);
/* The runtime calls this only while the session is FOCUSED (otherwise it returns XR_SESSION_NOT_FOCUSED
   itself and all actions read inactive: see fv_xr_input_sync_unfocused). */
XrResult fv_xr_input_sync(fv_xr_input_session *s, const XrActionsSyncInfo *info, const fv_xr_input_devices *dev);
XrResult fv_xr_input_get_boolean(fv_xr_input_session *s, const XrActionStateGetInfo *g, XrActionStateBoolean *out);
XrResult fv_xr_input_get_float(fv_xr_input_session *s, const XrActionStateGetInfo *g, XrActionStateFloat *out);
XrResult fv_xr_input_get_vector2f(fv_xr_input_session *s, const XrActionStateGetInfo *g, XrActionStateVector2f *out);
XrResult fv_xr_input_get_pose(fv_xr_input_session *s, const XrActionStateGetInfo *g, XrActionStatePose *out);
XrResult fv_xr_input_enumerate_bound_sources(fv_xr_input_session *s, const XrBoundSourcesForActionEnumerateInfo *e,
                                             uint32_t capacity, uint32_t *count_out, XrPath *sources);
XrResult fv_xr_input_get_localized_name(fv_xr_input_session *s, const XrInputSourceLocalizedNameGetInfo *g,
                                        uint32_t capacity, uint32_t *count_out, char *buf);
XrResult fv_xr_input_apply_haptic(fv_xr_input_session *s, const XrHapticActionInfo *h, const XrHapticBaseHeader *fb);
XrResult fv_xr_input_stop_haptic(fv_xr_input_session *s, const XrHapticActionInfo *h);

/* Action spaces: xrCreateActionSpace validates through this (XR_ERROR_ACTION_TYPE_MISMATCH,
   XR_ERROR_PATH_UNSUPPORTED for a subaction path not declared on the action, XR_ERROR_HANDLE_INVALID);
   locating asks which physical pose the action is bound to now. */
typedef enum fv_xr_pose_source {
    FV_XR_POSE_NONE = 0, /* unbound or inactive: the space is not located */
    FV_XR_POSE_EYE_GAZE, /* /user/eyes_ext/input/gaze_ext/pose */
    FV_XR_POSE_LEFT_GRIP,
    FV_XR_POSE_LEFT_AIM,
    FV_XR_POSE_RIGHT_GRIP,
    FV_XR_POSE_RIGHT_AIM,
} fv_xr_pose_source;
XrResult fv_xr_input_check_action_space(fv_xr_input *in, const XrActionSpaceCreateInfo *info);
fv_xr_pose_source fv_xr_input_pose_source(fv_xr_input_session *s, XrAction action, XrPath subaction_path);

/* ---- Added to the contract ---- */

/** xrSyncActions while the session is not FOCUSED: validates info exactly as fv_xr_input_sync does (so
 *  XR_ERROR_ACTIONSET_NOT_ATTACHED, XR_ERROR_PATH_UNSUPPORTED, ... still come first), then makes every action of
 *  the session read inactive and returns XR_SESSION_NOT_FOCUSED. */
XrResult fv_xr_input_sync_unfocused(fv_xr_input_session *s, const XrActionsSyncInfo *info);
/** Every action of the session reads inactive (zero state, no change, lastChangeTime 0) until the next sync: for a
 *  session that stops running. */
void fv_xr_input_deactivate(fv_xr_input_session *s);
/** True when handle_value is a live XrActionSet or XrAction of this instance: lets a runtime with several instances
 *  find the one an xrCreateAction / xrDestroyAction* handle belongs to. */
bool fv_xr_input_owns_handle(const fv_xr_input *in, uint64_t handle_value);
/** True once xrAttachSessionActionSets succeeded on this session. */
bool fv_xr_input_is_attached(const fv_xr_input_session *s);

#endif /* FV_XR_INPUT_H */
