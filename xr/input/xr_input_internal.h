/* @brief fv_xr_input internals shared by its files: the path table, the interaction-profile table and the binding
   resolver. Not installed; nothing outside xr/input includes it. */
#ifndef FV_XR_INPUT_INTERNAL_H
#define FV_XR_INPUT_INTERNAL_H

#include <stddef.h>

#include "fv_xr_input.h"

#define XRI_LOG "xr_input"

/* ---- Path table (path_table.c) ---- */

typedef struct xri_path_table {
    char **str;          /* str[i] is the string of XrPath i + 1 (owned) */
    uint32_t *len;       /* its length without the terminator */
    uint32_t count, cap; /* atoms in use, allocated */
    uint32_t *slot;      /* open-addressing hash: 0 = empty, else XrPath */
    uint32_t slot_cap;   /* power of two, kept over twice count */
    uint32_t max;        /* XR_ERROR_PATH_COUNT_EXCEEDED past this many atoms */
} xri_path_table;

void xri_paths_init(xri_path_table *t, uint32_t max_paths);
void xri_paths_fini(xri_path_table *t);
/** The spec's well-formed path rules (Semantic Paths, "Well-Formed Path Strings"); why names the broken rule. */
bool xri_path_well_formed(const char *s, size_t n, const char **why);
/** A path name component as in actionSetName / actionName: one level of a well-formed path. */
bool xri_name_component_ok(const char *s, const char **why);
/** Interns s (length n, already well-formed). XR_ERROR_PATH_COUNT_EXCEEDED / XR_ERROR_OUT_OF_MEMORY. */
XrResult xri_paths_intern(xri_path_table *t, const char *s, size_t n, XrPath *out);
/** The string of a live atom, or NULL for XR_NULL_PATH and any value never handed out. */
const char *xri_paths_str(const xri_path_table *t, XrPath p);
/** The atom of s when it is already interned, else XR_NULL_PATH (never allocates). */
XrPath xri_paths_find(const xri_path_table *t, const char *s, size_t n);

/* ---- Handle map (handle_map.c): 64-bit handle value -> pointer; keys 0 and UINT64_MAX are reserved ---- */

typedef struct xri_map {
    uint64_t *key;
    void **val;
    uint32_t cap, used, count; /* slots, slots not empty (with tombstones), live entries */
} xri_map;

bool xri_map_put(xri_map *m, uint64_t key, void *val); /* false: out of memory */
void *xri_map_get(const xri_map *m, uint64_t key);     /* NULL: absent */
void xri_map_del(xri_map *m, uint64_t key);
void xri_map_fini(xri_map *m);

/* ---- Top-level user paths and interaction profiles (profiles.c) ---- */

typedef enum xri_user {
    XRI_USER_HEAD = 0,
    XRI_USER_HAND_LEFT,
    XRI_USER_HAND_RIGHT,
    XRI_USER_GAMEPAD,
    XRI_USER_TREADMILL,
    XRI_USER_EYES_EXT, /* XR_EXT_eye_gaze_interaction (extension 31) */
    XRI_USER_COUNT,
} xri_user;
#define XRI_USER_BIT(u) (1u << (u))

/** The string of a top-level user path ("/user/hand/left"). */
const char *xri_user_str(xri_user u);
/** Matches the leading top-level user path of s; returns the length matched (0: none). Only paths the instance
 *  knows (eyes_ext only with the extension). */
size_t xri_user_match(const char *s, bool eye_gaze_ext, xri_user *out);

/** What a component path yields. */
typedef enum xri_kind {
    XRI_KIND_BOOL,  /* .../click, .../touch */
    XRI_KIND_FLOAT, /* .../value, .../force, .../twist, .../x, .../y */
    XRI_KIND_POSE,  /* .../pose */
    XRI_KIND_HAPTIC /* /output/... */
} xri_kind;

typedef struct xri_component {
    const char *sub;    /* "/input/trigger/value", "/output/haptic" */
    uint32_t user_mask; /* top-level paths it exists on (0: every path of the profile) */
} xri_component;

typedef struct xri_profile {
    const char *path;      /* "/interaction_profiles/khr/simple_controller" */
    const char *localized; /* "Simple Controller" */
    uint32_t user_mask;    /* the top-level paths the profile is valid for */
    bool needs_eye_gaze_ext;
    const xri_component *comps;
    uint32_t comp_count;
} xri_profile;

/** The profile table: OpenXR 1.0's core profiles and ext/eye_gaze_interaction. */
const xri_profile *xri_profiles(uint32_t *out_count);
/** The profile named by path string s, or NULL; eye gaze only with the extension. */
const xri_profile *xri_profile_find(const char *s, bool eye_gaze_ext);
/** Index of the profile component whose sub path equals sub[0..n), valid on user u; -1 if none. */
int xri_profile_component(const xri_profile *p, xri_user u, const char *sub, size_t n);
/** The kind of component sub (by its last segment; /output/... is haptic). */
xri_kind xri_component_kind(const char *sub);

/** The resolution of one suggested binding for one action type, per the spec's "Suggested Bindings" rules.
 *  comp[0] is the component read (for vector2f: the /x component, comp[1] the /y one); count 0: the binding is
 *  accepted but cannot feed this action type (ignored, as the spec says). */
typedef struct xri_resolved {
    uint8_t count;
    int16_t comp[2];
} xri_resolved;

/** Validates the binding's subpath sub (after the user path) against profile p on user u: XR_SUCCESS when it is a
 *  component of the profile or the parent (identifier) path of one; XR_ERROR_PATH_UNSUPPORTED otherwise. Fills
 *  *out with the components that feed an action of type t. */
XrResult xri_resolve_binding(const xri_profile *p, xri_user u, const char *sub, XrActionType t, xri_resolved *out);

/** The localized pieces for xrGetInputSourceLocalizedName. */
const char *xri_user_localized(xri_user u);
/** Writes the localized name of an input subpath ("/input/trigger/value" -> "Trigger"), at most cap bytes. */
void xri_component_localized(const char *sub, char *buf, size_t cap);

#endif /* FV_XR_INPUT_INTERNAL_H */
