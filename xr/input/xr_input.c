/* @brief fv_xr_input: OpenXR 1.0's action system ("Input and Haptics" chapter): action sets, actions, suggested
   bindings, attachment, xrSyncActions snapshots with active sets, subaction filters and priorities, state queries,
   bound sources, localized names, haptics and pose bindings. Pure: no clock (times come in), no I/O but the log. */
#include <math.h>
#include <stdio.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "xr_input_internal.h"

#define XRI_PROFILE_MAX 16
#define XRI_DEFAULT_MAX_PATHS 262144u
#define XRI_MAX_ACTION_SETS 4096u
#define XRI_MAX_ACTIONS_PER_SET 4096u
/* Boolean actions bound to a scalar: pressed above 0.5, released below 0.4 (the spec asks for a threshold with
   hysteresis and leaves the numbers to the runtime). */
#define XRI_PRESS 0.5f
#define XRI_RELEASE 0.4f

#define KIND_SET 1u
#define KIND_ACTION 2u

typedef struct xri_action_set xri_action_set;

typedef struct xri_action {
    uint64_t handle;
    bool handle_alive; /* xrDestroyAction ends the handle, not the action (spec: spaces and priorities use it) */
    xri_action_set *set;
    XrActionType type;
    char name[XR_MAX_ACTION_NAME_SIZE];
    char lname[XR_MAX_LOCALIZED_ACTION_NAME_SIZE];
    uint32_t sub_count;
    XrPath sub[XRI_USER_COUNT];
    xri_user sub_user[XRI_USER_COUNT];
} xri_action;

struct xri_action_set {
    uint64_t handle;
    bool handle_alive;
    char name[XR_MAX_ACTION_SET_NAME_SIZE];
    char lname[XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE];
    uint32_t priority;
    bool ever_attached;    /* immutable from its first attachment on */
    uint32_t session_refs; /* sessions it is attached to: the set lives while any holds it */
    xri_action **actions;
    uint32_t action_count, action_cap;
};

typedef struct xri_binding {
    xri_action *action;
    XrPath binding; /* as suggested */
    xri_user user;
    xri_resolved res;
    XrPath source; /* the physical source: the resolved component, or the suggested parent for a vector2f */
    const char *comp;   /* the profile component read first (comp[0]); NULL when the binding feeds nothing */
    uint16_t ident_len; /* length of its "/input/<identifier>" part: the input source, for priorities */
    bool is_input;
} xri_binding;

typedef struct xri_profile_bindings {
    xri_binding *b;
    uint32_t count;
} xri_profile_bindings;

typedef struct xri_session_node {
    fv_xr_input_session *s;
    struct xri_session_node *next;
} xri_session_node;

struct fv_xr_input {
    bool eye_gaze_ext;
    uint32_t serial;
    uint64_t next_id;
    xri_path_table paths;
    xri_action_set **sets;
    uint32_t set_count, set_cap;
    xri_profile_bindings prof[XRI_PROFILE_MAX];
    XrPath user_path[XRI_USER_COUNT];
    XrPath profile_path[XRI_PROFILE_MAX];
    uint32_t profile_count;
    const xri_profile *profile_table;
    xri_session_node *sessions;
    xri_map objs; /* handle value -> xri_action_set / xri_action */
};

/* The state of one action seen through one subaction filter, as of the last sync. */
typedef struct xri_slot {
    bool active;
    bool b;
    float f;
    XrVector2f v;
    bool changed;
    XrTime last_change;
    xri_user pose_user;  /* the pose source chosen (the first suggested, used consistently) */
    const char *pose_sub; /* its component in the profile table ("/input/grip/pose"); NULL: none */
} xri_slot;

typedef struct xri_binding_ref {
    uint8_t profile;
    uint32_t index;
} xri_binding_ref;

typedef struct xri_session_action {
    xri_action *a;
    xri_slot *slot; /* a->sub_count + 1 slots: one per subaction path, the last for XR_NULL_PATH (all) */
    xri_binding_ref *binds; /* its bindings in the session's snapshot */
    uint32_t bind_count;
} xri_session_action;

struct fv_xr_input_session {
    fv_xr_input *in;
    bool attached;
    xri_action_set **sets;
    uint32_t set_count;
    xri_session_action *acts;
    uint32_t act_count;
    xri_profile_bindings prof[XRI_PROFILE_MAX]; /* the bindings of the attached sets, frozen at attach */
    uint8_t *live[XRI_PROFILE_MAX];             /* per binding, this sync: takes part (see mark_live) */
    xri_map act_index;                          /* action handle value -> index into acts, + 1 */
    int current[XRI_USER_COUNT]; /* profile index per top-level user path, -1 none */
    bool profile_changed;
    bool have_pending;
    fv_xr_input_devices pending; /* from update_profiles, applied at the next sync (values not kept) */
};

_Static_assert(sizeof(void *) == 8 || sizeof(XrAction) == 8, "handles carry 64-bit values");

static atomic_uint instance_serial = 1;

/* ------------------------------------------------------------------------------------------------------------ */
/* Handles                                                                                                      */

static uint64_t make_handle(fv_xr_input *in, unsigned kind)
{
    uint64_t id = ++in->next_id;
    return ((uint64_t)in->serial << 40) | ((uint64_t)kind << 36) | (id & 0xFFFFFFFFFull);
}

static uint64_t set_value(XrActionSet h) { return (uint64_t)(uintptr_t)h; }
static uint64_t action_value(XrAction h) { return (uint64_t)(uintptr_t)h; }
static XrActionSet set_handle(uint64_t v) { return (XrActionSet)(uintptr_t)v; }
static XrAction action_handle(uint64_t v) { return (XrAction)(uintptr_t)v; }

/* A live action set handle of this instance, or NULL. */
static xri_action_set *find_set(const fv_xr_input *in, XrActionSet h)
{
    uint64_t v = set_value(h);
    if (v == 0 || (v >> 40) != in->serial || ((v >> 36) & 0xF) != KIND_SET) return NULL;
    xri_action_set *set = xri_map_get(&in->objs, v);
    return set && set->handle_alive ? set : NULL;
}

/* The action of handle h, live or not (alive_only: only a live handle). */
static xri_action *find_action(const fv_xr_input *in, XrAction h, bool alive_only)
{
    uint64_t v = action_value(h);
    if (v == 0 || (v >> 40) != in->serial || ((v >> 36) & 0xF) != KIND_ACTION) return NULL;
    xri_action *a = xri_map_get(&in->objs, v);
    return a && (!alive_only || a->handle_alive) ? a : NULL;
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Strings                                                                                                      */

/* NUL-terminated within cap bytes and valid UTF-8. */
static bool utf8_string_ok(const char *s, size_t cap)
{
    const unsigned char *p = (const unsigned char *)s;
    size_t n = strnlen(s, cap);
    if (n == cap) return false;
    for (size_t i = 0; i < n;) {
        unsigned c = p[i];
        size_t len = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
        if (len == 0 || i + len > n) return false;
        uint32_t cp = len == 1 ? c : c & (0x7Fu >> len);
        for (size_t k = 1; k < len; k++) {
            if ((p[i + k] & 0xC0) != 0x80) return false;
            cp = (cp << 6) | (p[i + k] & 0x3F);
        }
        static const uint32_t min_cp[5] = {0, 0, 0x80, 0x800, 0x10000};
        if (cp < min_cp[len] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
        i += len;
    }
    return true;
}

/* The name rules shared by action sets and actions (xrCreateActionSet / xrCreateAction). */
static XrResult check_names(const char *fn, const char *name, size_t name_cap, const char *lname, size_t lname_cap)
{
    const char *why = NULL;
    if (strnlen(name, name_cap) == name_cap) {
        FV_WARN(XRI_LOG, "%s: the name is not NUL-terminated within its %zu bytes", fn, name_cap);
        return XR_ERROR_VALIDATION_FAILURE;
    }
    if (!utf8_string_ok(lname, lname_cap)) {
        FV_WARN(XRI_LOG, "%s: the localized name is not a NUL-terminated UTF-8 string within its %zu bytes", fn,
                lname_cap);
        return XR_ERROR_VALIDATION_FAILURE;
    }
    if (name[0] == '\0') {
        FV_WARN(XRI_LOG, "%s: the name is empty", fn);
        return XR_ERROR_NAME_INVALID;
    }
    if (lname[0] == '\0') {
        FV_WARN(XRI_LOG, "%s: the localized name of \"%s\" is empty", fn, name);
        return XR_ERROR_LOCALIZED_NAME_INVALID;
    }
    if (!xri_name_component_ok(name, &why)) {
        FV_WARN(XRI_LOG, "%s: name \"%.*s\": %s", fn, 64, name, why);
        return XR_ERROR_PATH_FORMAT_INVALID;
    }
    return XR_SUCCESS;
}

/* The identifier part ("/input/trigger") of a component: the length up to its third '/'. */
static size_t identifier_len(const char *sub)
{
    int slashes = 0;
    for (size_t i = 0; sub[i]; i++)
        if (sub[i] == '/' && ++slashes == 3) return i;
    return strlen(sub);
}

/* Two-call idiom for a string (count includes the terminator). */
static XrResult write_string(const char *str, uint32_t capacity, uint32_t *count_out, char *buf)
{
    if (!count_out || (capacity > 0 && !buf)) return XR_ERROR_VALIDATION_FAILURE;
    size_t need = strlen(str) + 1;
    *count_out = (uint32_t)need;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < need) return XR_ERROR_SIZE_INSUFFICIENT;
    memcpy(buf, str, need);
    return XR_SUCCESS;
}

/* The top-level user path an XrPath names exactly, or false. */
static bool user_of_path(const fv_xr_input *in, XrPath p, xri_user *out)
{
    for (int u = 0; u < XRI_USER_COUNT; u++) {
        if (u == XRI_USER_EYES_EXT && !in->eye_gaze_ext) continue;
        if (in->user_path[u] == p) {
            *out = (xri_user)u;
            return true;
        }
    }
    return false;
}

static int profile_index(const fv_xr_input *in, const xri_profile *p) { return (int)(p - in->profile_table); }

/* ------------------------------------------------------------------------------------------------------------ */
/* Instance                                                                                                     */

XrResult fv_xr_input_create(const fv_xr_input_desc *desc, fv_xr_input **out)
{
    if (!out) return XR_ERROR_VALIDATION_FAILURE;
    *out = NULL;
    fv_xr_input *in = calloc(1, sizeof *in);
    if (!in) return XR_ERROR_OUT_OF_MEMORY;
    in->eye_gaze_ext = desc && desc->eye_gaze_ext_enabled;
    uint32_t max = desc && desc->max_paths ? desc->max_paths : XRI_DEFAULT_MAX_PATHS;
    in->serial = atomic_fetch_add(&instance_serial, 1) & 0xFFFFFFu;
    if (in->serial == 0) in->serial = atomic_fetch_add(&instance_serial, 1) & 0xFFFFFFu;
    /* The runtime's own atoms (top-level paths, profiles) come first and count against max_paths too. */
    xri_paths_init(&in->paths, max + XRI_USER_COUNT + XRI_PROFILE_MAX);
    in->profile_table = xri_profiles(&in->profile_count);
    XrResult r = XR_SUCCESS;
    for (int u = 0; u < XRI_USER_COUNT && r == XR_SUCCESS; u++) {
        const char *s = xri_user_str((xri_user)u);
        r = xri_paths_intern(&in->paths, s, strlen(s), &in->user_path[u]);
    }
    for (uint32_t i = 0; i < in->profile_count && r == XR_SUCCESS; i++) {
        const char *s = in->profile_table[i].path;
        r = xri_paths_intern(&in->paths, s, strlen(s), &in->profile_path[i]);
    }
    in->paths.max = (uint64_t)in->paths.count + max > UINT32_MAX ? UINT32_MAX : in->paths.count + max;
    if (r != XR_SUCCESS) {
        fv_xr_input_destroy(&in);
        return r;
    }
    *out = in;
    return XR_SUCCESS;
}

static void free_set(fv_xr_input *in, xri_action_set *set);
static void free_attachment(fv_xr_input_session *s);

void fv_xr_input_destroy(fv_xr_input **pin)
{
    if (!pin || !*pin) return;
    fv_xr_input *in = *pin;
    while (in->sessions) {
        fv_xr_input_session *s = in->sessions->s;
        fv_xr_input_session_destroy(&s);
    }
    while (in->set_count) free_set(in, in->sets[in->set_count - 1]);
    free(in->sets);
    for (int p = 0; p < XRI_PROFILE_MAX; p++) free(in->prof[p].b);
    xri_map_fini(&in->objs);
    xri_paths_fini(&in->paths);
    free(in);
    *pin = NULL;
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Paths                                                                                                        */

XrResult fv_xr_input_string_to_path(fv_xr_input *in, const char *str, XrPath *out)
{
    if (!in) return XR_ERROR_HANDLE_INVALID;
    if (!str || !out) return XR_ERROR_VALIDATION_FAILURE;
    size_t n = strnlen(str, XR_MAX_PATH_LENGTH);
    const char *why = NULL;
    if (!xri_path_well_formed(str, n, &why) || str[n] != '\0') {
        if (!why) why = "longer than XR_MAX_PATH_LENGTH (256 bytes with the terminator)";
        FV_WARN(XRI_LOG, "xrStringToPath(\"%.64s%s\"): not a well-formed path: %s", str, n > 64 ? "..." : "", why);
        *out = XR_NULL_PATH;
        return XR_ERROR_PATH_FORMAT_INVALID;
    }
    XrResult r = xri_paths_intern(&in->paths, str, n, out);
    if (r == XR_ERROR_PATH_COUNT_EXCEEDED)
        FV_WARN(XRI_LOG, "xrStringToPath(\"%s\"): the instance holds its limit of %u paths", str, in->paths.max);
    if (r != XR_SUCCESS) *out = XR_NULL_PATH;
    return r;
}

XrResult fv_xr_input_path_to_string(fv_xr_input *in, XrPath path, uint32_t capacity, uint32_t *count_out, char *buf)
{
    if (!in) return XR_ERROR_HANDLE_INVALID;
    if (!count_out || (capacity > 0 && !buf)) return XR_ERROR_VALIDATION_FAILURE;
    const char *s = xri_paths_str(&in->paths, path);
    if (!s) return XR_ERROR_PATH_INVALID;
    return write_string(s, capacity, count_out, buf);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Action sets and actions                                                                                      */

XrResult fv_xr_input_create_action_set(fv_xr_input *in, const XrActionSetCreateInfo *info, XrActionSet *out)
{
    if (!in) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_ACTION_SET_CREATE_INFO) {
        FV_WARN(XRI_LOG, "xrCreateActionSet: createInfo is NULL or not XR_TYPE_ACTION_SET_CREATE_INFO, or actionSet "
                         "is NULL");
        return XR_ERROR_VALIDATION_FAILURE;
    }
    XrResult r = check_names("xrCreateActionSet", info->actionSetName, sizeof info->actionSetName,
                             info->localizedActionSetName, sizeof info->localizedActionSetName);
    if (r != XR_SUCCESS) return r;
    for (uint32_t i = 0; i < in->set_count; i++) {
        const xri_action_set *o = in->sets[i];
        if (!o->handle_alive) continue; /* a destroyed set's names are free again */
        if (strcmp(o->name, info->actionSetName) == 0) {
            FV_WARN(XRI_LOG, "xrCreateActionSet: actionSetName \"%s\" is taken", info->actionSetName);
            return XR_ERROR_NAME_DUPLICATED;
        }
    }
    for (uint32_t i = 0; i < in->set_count; i++) {
        const xri_action_set *o = in->sets[i];
        if (o->handle_alive && strcmp(o->lname, info->localizedActionSetName) == 0) {
            FV_WARN(XRI_LOG, "xrCreateActionSet: localizedActionSetName \"%s\" is taken", info->localizedActionSetName);
            return XR_ERROR_LOCALIZED_NAME_DUPLICATED;
        }
    }
    if (in->set_count >= XRI_MAX_ACTION_SETS) {
        FV_WARN(XRI_LOG, "xrCreateActionSet: the instance holds its limit of %u action sets", XRI_MAX_ACTION_SETS);
        return XR_ERROR_LIMIT_REACHED;
    }
    if (in->set_count == in->set_cap) {
        uint32_t cap = in->set_cap ? in->set_cap * 2 : 8;
        xri_action_set **sets = realloc(in->sets, cap * sizeof *sets);
        if (!sets) return XR_ERROR_OUT_OF_MEMORY;
        in->sets = sets;
        in->set_cap = cap;
    }
    xri_action_set *set = calloc(1, sizeof *set);
    if (!set) return XR_ERROR_OUT_OF_MEMORY;
    set->handle = make_handle(in, KIND_SET);
    set->handle_alive = true;
    memcpy(set->name, info->actionSetName, sizeof set->name);
    memcpy(set->lname, info->localizedActionSetName, sizeof set->lname);
    set->priority = info->priority;
    if (!xri_map_put(&in->objs, set->handle, set)) {
        free(set);
        return XR_ERROR_OUT_OF_MEMORY;
    }
    in->sets[in->set_count++] = set;
    *out = set_handle(set->handle);
    return XR_SUCCESS;
}

/* Drops every suggested binding of action a (or of any action of set when a is NULL). */
static void drop_bindings(fv_xr_input *in, const xri_action_set *set, const xri_action *a)
{
    for (int p = 0; p < XRI_PROFILE_MAX; p++) {
        xri_profile_bindings *pb = &in->prof[p];
        uint32_t w = 0;
        for (uint32_t i = 0; i < pb->count; i++) {
            bool drop = a ? pb->b[i].action == a : pb->b[i].action->set == set;
            if (!drop) pb->b[w++] = pb->b[i];
        }
        pb->count = w;
    }
}

static void free_action(fv_xr_input *in, xri_action_set *set, uint32_t k)
{
    xri_map_del(&in->objs, set->actions[k]->handle);
    free(set->actions[k]);
    memmove(&set->actions[k], &set->actions[k + 1], (set->action_count - k - 1) * sizeof set->actions[0]);
    set->action_count--;
}

static void free_set(fv_xr_input *in, xri_action_set *set)
{
    drop_bindings(in, set, NULL);
    while (set->action_count) free_action(in, set, set->action_count - 1);
    xri_map_del(&in->objs, set->handle);
    free(set->actions);
    for (uint32_t i = 0; i < in->set_count; i++) {
        if (in->sets[i] == set) {
            memmove(&in->sets[i], &in->sets[i + 1], (in->set_count - i - 1) * sizeof in->sets[0]);
            in->set_count--;
            break;
        }
    }
    free(set);
}

XrResult fv_xr_input_destroy_action_set(fv_xr_input *in, XrActionSet h)
{
    if (!in) return XR_ERROR_HANDLE_INVALID;
    xri_action_set *set = find_set(in, h);
    if (!set) return XR_ERROR_HANDLE_INVALID;
    set->handle_alive = false;
    for (uint32_t k = 0; k < set->action_count; k++) set->actions[k]->handle_alive = false;
    /* The spec keeps an attached set's resources (its actions still take part in priorities and back action
       spaces) until no session holds it. */
    if (set->session_refs == 0) free_set(in, set);
    return XR_SUCCESS;
}

static bool subaction_allowed(const fv_xr_input *in, xri_user u)
{
    /* xrCreateAction's list: /user/head, /user/hand/left, /user/hand/right, /user/gamepad, and the paths
       extensions append (/user/eyes_ext for XR_EXT_eye_gaze_interaction). /user/treadmill is not on it. */
    switch (u) {
    case XRI_USER_HEAD:
    case XRI_USER_HAND_LEFT:
    case XRI_USER_HAND_RIGHT:
    case XRI_USER_GAMEPAD: return true;
    case XRI_USER_EYES_EXT: return in->eye_gaze_ext;
    default: return false;
    }
}

XrResult fv_xr_input_create_action(fv_xr_input *in, XrActionSet h, const XrActionCreateInfo *info, XrAction *out)
{
    if (!in) return XR_ERROR_HANDLE_INVALID;
    xri_action_set *set = find_set(in, h);
    if (!set) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_ACTION_CREATE_INFO) {
        FV_WARN(XRI_LOG, "xrCreateAction: createInfo is NULL or not XR_TYPE_ACTION_CREATE_INFO, or action is NULL");
        return XR_ERROR_VALIDATION_FAILURE;
    }
    switch (info->actionType) {
    case XR_ACTION_TYPE_BOOLEAN_INPUT:
    case XR_ACTION_TYPE_FLOAT_INPUT:
    case XR_ACTION_TYPE_VECTOR2F_INPUT:
    case XR_ACTION_TYPE_POSE_INPUT:
    case XR_ACTION_TYPE_VIBRATION_OUTPUT: break;
    default:
        FV_WARN(XRI_LOG, "xrCreateAction: actionType %d is not an XrActionType", (int)info->actionType);
        return XR_ERROR_VALIDATION_FAILURE;
    }
    if (info->countSubactionPaths > 0 && !info->subactionPaths) {
        FV_WARN(XRI_LOG, "xrCreateAction: countSubactionPaths is %u but subactionPaths is NULL",
                info->countSubactionPaths);
        return XR_ERROR_VALIDATION_FAILURE;
    }
    if (set->ever_attached) {
        FV_WARN(XRI_LOG, "xrCreateAction: action set \"%s\" is attached to a session and can no longer change",
                set->name);
        return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
    }
    XrResult r = check_names("xrCreateAction", info->actionName, sizeof info->actionName, info->localizedActionName,
                             sizeof info->localizedActionName);
    if (r != XR_SUCCESS) return r;
    for (uint32_t k = 0; k < set->action_count; k++) {
        const xri_action *o = set->actions[k];
        if (o->handle_alive && strcmp(o->name, info->actionName) == 0) {
            FV_WARN(XRI_LOG, "xrCreateAction: actionName \"%s\" is taken in action set \"%s\"", info->actionName,
                    set->name);
            return XR_ERROR_NAME_DUPLICATED;
        }
    }
    for (uint32_t k = 0; k < set->action_count; k++) {
        const xri_action *o = set->actions[k];
        if (o->handle_alive && strcmp(o->lname, info->localizedActionName) == 0) {
            FV_WARN(XRI_LOG, "xrCreateAction: localizedActionName \"%s\" is taken in action set \"%s\"",
                    info->localizedActionName, set->name);
            return XR_ERROR_LOCALIZED_NAME_DUPLICATED;
        }
    }
    xri_action tmp = {0};
    for (uint32_t i = 0; i < info->countSubactionPaths; i++) {
        XrPath p = info->subactionPaths[i];
        const char *s = xri_paths_str(&in->paths, p);
        if (!s) {
            FV_WARN(XRI_LOG, "xrCreateAction \"%s\": subactionPaths[%u] is not a path of this instance",
                    info->actionName, i);
            return XR_ERROR_PATH_INVALID;
        }
        xri_user u;
        if (!user_of_path(in, p, &u) || !subaction_allowed(in, u)) {
            FV_WARN(XRI_LOG, "xrCreateAction \"%s\": subactionPaths[%u] \"%s\" is not a subaction path (allowed: "
                             "/user/head, /user/hand/left, /user/hand/right, /user/gamepad%s)",
                    info->actionName, i, s, in->eye_gaze_ext ? ", /user/eyes_ext" : "");
            return XR_ERROR_PATH_UNSUPPORTED;
        }
        for (uint32_t k = 0; k < tmp.sub_count; k++) {
            if (tmp.sub[k] == p) {
                FV_WARN(XRI_LOG, "xrCreateAction \"%s\": subactionPaths[%u] \"%s\" appears twice", info->actionName,
                        i, s);
                return XR_ERROR_PATH_UNSUPPORTED;
            }
        }
        tmp.sub[tmp.sub_count] = p;
        tmp.sub_user[tmp.sub_count] = u;
        tmp.sub_count++;
    }
    if (set->action_count >= XRI_MAX_ACTIONS_PER_SET) {
        FV_WARN(XRI_LOG, "xrCreateAction: action set \"%s\" holds its limit of %u actions", set->name,
                XRI_MAX_ACTIONS_PER_SET);
        return XR_ERROR_LIMIT_REACHED;
    }
    if (set->action_count == set->action_cap) {
        uint32_t cap = set->action_cap ? set->action_cap * 2 : 8;
        xri_action **acts = realloc(set->actions, cap * sizeof *acts);
        if (!acts) return XR_ERROR_OUT_OF_MEMORY;
        set->actions = acts;
        set->action_cap = cap;
    }
    xri_action *a = malloc(sizeof *a);
    if (!a) return XR_ERROR_OUT_OF_MEMORY;
    *a = tmp;
    a->handle = make_handle(in, KIND_ACTION);
    a->handle_alive = true;
    a->set = set;
    a->type = info->actionType;
    memcpy(a->name, info->actionName, sizeof a->name);
    memcpy(a->lname, info->localizedActionName, sizeof a->lname);
    if (!xri_map_put(&in->objs, a->handle, a)) {
        free(a);
        return XR_ERROR_OUT_OF_MEMORY;
    }
    set->actions[set->action_count++] = a;
    *out = action_handle(a->handle);
    return XR_SUCCESS;
}

XrResult fv_xr_input_destroy_action(fv_xr_input *in, XrAction h)
{
    if (!in) return XR_ERROR_HANDLE_INVALID;
    xri_action *a = find_action(in, h, true);
    if (!a) return XR_ERROR_HANDLE_INVALID;
    a->handle_alive = false;
    xri_action_set *set = a->set;
    if (set->session_refs == 0 && !set->ever_attached) {
        /* Nothing can use it any more: free it now, with its suggested bindings. */
        drop_bindings(in, NULL, a);
        for (uint32_t k = 0; k < set->action_count; k++) {
            if (set->actions[k] == a) {
                free_action(in, set, k);
                break;
            }
        }
    }
    return XR_SUCCESS;
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Suggested bindings                                                                                           */

XrResult fv_xr_input_suggest_bindings(fv_xr_input *in, const XrInteractionProfileSuggestedBinding *sb)
{
    if (!in) return XR_ERROR_HANDLE_INVALID;
    if (!sb || sb->type != XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING || sb->countSuggestedBindings == 0 ||
        !sb->suggestedBindings) {
        FV_WARN(XRI_LOG, "xrSuggestInteractionProfileBindings: suggestedBindings is NULL, not "
                         "XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING, or has no bindings");
        return XR_ERROR_VALIDATION_FAILURE;
    }
    const char *ps = xri_paths_str(&in->paths, sb->interactionProfile);
    if (!ps) {
        FV_WARN(XRI_LOG, "xrSuggestInteractionProfileBindings: interactionProfile is not a path of this instance");
        return XR_ERROR_PATH_INVALID;
    }
    const xri_profile *prof = xri_profile_find(ps, in->eye_gaze_ext);
    if (!prof) {
        bool gaze = xri_profile_find(ps, true) != NULL;
        FV_WARN(XRI_LOG, "xrSuggestInteractionProfileBindings: \"%s\" is not an interaction profile of this runtime%s",
                ps, gaze ? " (it needs XR_EXT_eye_gaze_interaction enabled)" : "");
        return XR_ERROR_PATH_UNSUPPORTED;
    }
    uint32_t n = sb->countSuggestedBindings;
    xri_binding *list = calloc(n, sizeof *list);
    if (!list) return XR_ERROR_OUT_OF_MEMORY;
    uint32_t count = 0;
    XrResult r = XR_SUCCESS;
    for (uint32_t i = 0; i < n && r == XR_SUCCESS; i++) {
        const XrActionSuggestedBinding *b = &sb->suggestedBindings[i];
        xri_action *a = find_action(in, b->action, true);
        if (!a) {
            FV_WARN(XRI_LOG, "xrSuggestInteractionProfileBindings(%s): suggestedBindings[%u].action is not a live "
                             "action", ps, i);
            r = XR_ERROR_HANDLE_INVALID;
            break;
        }
        const char *bs = xri_paths_str(&in->paths, b->binding);
        if (!bs) {
            FV_WARN(XRI_LOG, "xrSuggestInteractionProfileBindings(%s): suggestedBindings[%u].binding is not a path of "
                             "this instance", ps, i);
            r = XR_ERROR_PATH_INVALID;
            break;
        }
        xri_user u;
        size_t un = xri_user_match(bs, in->eye_gaze_ext, &u);
        if (un == 0 || !(prof->user_mask & XRI_USER_BIT(u))) {
            FV_WARN(XRI_LOG, "xrSuggestInteractionProfileBindings(%s): suggestedBindings[%u].binding \"%s\" is not under "
                             "a top-level user path of this profile", ps, i, bs);
            r = XR_ERROR_PATH_UNSUPPORTED;
            break;
        }
        xri_resolved res;
        if (xri_resolve_binding(prof, u, bs + un, a->type, &res) != XR_SUCCESS) {
            FV_WARN(XRI_LOG, "xrSuggestInteractionProfileBindings(%s): suggestedBindings[%u].binding \"%s\" is not an "
                             "input or output of this profile", ps, i, bs);
            r = XR_ERROR_PATH_UNSUPPORTED;
            break;
        }
        if (a->set->ever_attached) {
            FV_WARN(XRI_LOG, "xrSuggestInteractionProfileBindings(%s): action \"%s\" belongs to action set \"%s\", "
                             "which is attached to a session", ps, a->name, a->set->name);
            r = XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
            break;
        }
        bool dup = false;
        for (uint32_t k = 0; k < count && !dup; k++) dup = list[k].action == a && list[k].binding == b->binding;
        if (dup) continue;
        xri_binding *nb = &list[count];
        nb->action = a;
        nb->binding = b->binding;
        nb->user = u;
        nb->res = res;
        nb->source = b->binding;
        if (res.count > 0) {
            nb->comp = prof->comps[res.comp[0]].sub;
            nb->is_input = strncmp(nb->comp, "/input/", 7) == 0;
            nb->ident_len = (uint16_t)identifier_len(nb->comp);
        }
        if (res.count == 1) {
            /* The physical source is the resolved component ("/input/trigger" -> ".../trigger/value"). */
            char full[XR_MAX_PATH_LENGTH * 2];
            int fn = snprintf(full, sizeof full, "%s%s", xri_user_str(u), prof->comps[res.comp[0]].sub);
            if (fn > 0 && (size_t)fn < XR_MAX_PATH_LENGTH) r = xri_paths_intern(&in->paths, full, (size_t)fn, &nb->source);
        }
        count++;
    }
    if (r != XR_SUCCESS) {
        free(list);
        return r;
    }
    /* A second call for the same profile replaces the first one's bindings. */
    xri_profile_bindings *pb = &in->prof[profile_index(in, prof)];
    free(pb->b);
    pb->b = list;
    pb->count = count;
    return XR_SUCCESS;
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Sessions                                                                                                     */

XrResult fv_xr_input_session_create(fv_xr_input *in, fv_xr_input_session **out)
{
    if (!in) return XR_ERROR_HANDLE_INVALID;
    if (!out) return XR_ERROR_VALIDATION_FAILURE;
    fv_xr_input_session *s = calloc(1, sizeof *s);
    xri_session_node *node = calloc(1, sizeof *node);
    if (!s || !node) {
        free(s);
        free(node);
        return XR_ERROR_OUT_OF_MEMORY;
    }
    s->in = in;
    for (int u = 0; u < XRI_USER_COUNT; u++) s->current[u] = -1;
    node->s = s;
    node->next = in->sessions;
    in->sessions = node;
    *out = s;
    return XR_SUCCESS;
}

void fv_xr_input_session_destroy(fv_xr_input_session **ps)
{
    if (!ps || !*ps) return;
    fv_xr_input_session *s = *ps;
    fv_xr_input *in = s->in;
    for (xri_session_node **n = &in->sessions; *n; n = &(*n)->next) {
        if ((*n)->s == s) {
            xri_session_node *dead = *n;
            *n = dead->next;
            free(dead);
            break;
        }
    }
    for (uint32_t i = 0; i < s->set_count; i++) {
        xri_action_set *set = s->sets[i];
        set->session_refs--;
        if (set->session_refs == 0 && !set->handle_alive) free_set(in, set);
    }
    free_attachment(s);
    free(s);
    *ps = NULL;
}

bool fv_xr_input_is_attached(const fv_xr_input_session *s) { return s && s->attached; }

/* Frees what attach built (safe on a partial build); the set references are the caller's. */
static void free_attachment(fv_xr_input_session *s)
{
    for (uint32_t i = 0; i < s->act_count; i++) {
        free(s->acts[i].slot);
        free(s->acts[i].binds);
    }
    free(s->acts);
    s->acts = NULL;
    s->act_count = 0;
    for (int p = 0; p < XRI_PROFILE_MAX; p++) {
        free(s->prof[p].b);
        s->prof[p] = (xri_profile_bindings){0};
        free(s->live[p]);
        s->live[p] = NULL;
    }
    xri_map_fini(&s->act_index);
    free(s->sets);
    s->sets = NULL;
    s->set_count = 0;
}

static XrResult build_attachment(fv_xr_input_session *s, const XrSessionActionSetsAttachInfo *info)
{
    fv_xr_input *in = s->in;
    s->sets = calloc(info->countActionSets, sizeof *s->sets);
    if (!s->sets) return XR_ERROR_OUT_OF_MEMORY;
    uint32_t act_count = 0;
    for (uint32_t i = 0; i < info->countActionSets; i++) {
        xri_action_set *set = find_set(in, info->actionSets[i]);
        bool dup = false;
        for (uint32_t k = 0; k < s->set_count && !dup; k++) dup = s->sets[k] == set;
        if (dup) continue;
        s->sets[s->set_count++] = set;
        act_count += set->action_count;
    }
    s->acts = calloc(act_count ? act_count : 1, sizeof *s->acts);
    if (!s->acts) return XR_ERROR_OUT_OF_MEMORY;
    for (uint32_t i = 0; i < s->set_count; i++) {
        for (uint32_t k = 0; k < s->sets[i]->action_count; k++) {
            xri_session_action *sa = &s->acts[s->act_count];
            sa->a = s->sets[i]->actions[k];
            sa->slot = calloc(sa->a->sub_count + 1, sizeof *sa->slot);
            if (!sa->slot) return XR_ERROR_OUT_OF_MEMORY;
            s->act_count++;
            if (!xri_map_put(&s->act_index, sa->a->handle, (void *)(uintptr_t)s->act_count))
                return XR_ERROR_OUT_OF_MEMORY;
        }
    }
    /* The attached sets are immutable from now on: this session keeps their suggested bindings as they are, and
       each action the list of its own. */
    for (int p = 0; p < XRI_PROFILE_MAX; p++) {
        const xri_profile_bindings *pb = &in->prof[p];
        if (pb->count == 0) continue;
        s->prof[p].b = malloc(pb->count * sizeof *pb->b);
        s->live[p] = calloc(pb->count, 1);
        if (!s->prof[p].b || !s->live[p]) return XR_ERROR_OUT_OF_MEMORY;
        for (uint32_t i = 0; i < pb->count; i++) {
            uintptr_t ai = (uintptr_t)xri_map_get(&s->act_index, pb->b[i].action->handle);
            if (ai == 0) continue; /* an action of a set not attached here */
            s->prof[p].b[s->prof[p].count++] = pb->b[i];
            s->acts[ai - 1].bind_count++;
        }
    }
    for (uint32_t i = 0; i < s->act_count; i++) {
        xri_session_action *sa = &s->acts[i];
        if (sa->bind_count == 0) continue;
        sa->binds = malloc(sa->bind_count * sizeof *sa->binds);
        if (!sa->binds) return XR_ERROR_OUT_OF_MEMORY;
        sa->bind_count = 0;
    }
    for (int p = 0; p < XRI_PROFILE_MAX; p++) {
        for (uint32_t i = 0; i < s->prof[p].count; i++) {
            uintptr_t ai = (uintptr_t)xri_map_get(&s->act_index, s->prof[p].b[i].action->handle);
            xri_session_action *sa = &s->acts[ai - 1];
            sa->binds[sa->bind_count++] = (xri_binding_ref){(uint8_t)p, i};
        }
    }
    return XR_SUCCESS;
}

XrResult fv_xr_input_attach(fv_xr_input_session *s, const XrSessionActionSetsAttachInfo *info)
{
    if (!s) return XR_ERROR_HANDLE_INVALID;
    fv_xr_input *in = s->in;
    if (!info || info->type != XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO || info->countActionSets == 0 ||
        !info->actionSets) {
        FV_WARN(XRI_LOG, "xrAttachSessionActionSets: attachInfo is NULL, not XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO, "
                         "or holds no action set");
        return XR_ERROR_VALIDATION_FAILURE;
    }
    if (s->attached) {
        FV_WARN(XRI_LOG, "xrAttachSessionActionSets: this session already has its action sets (once per session)");
        return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
    }
    for (uint32_t i = 0; i < info->countActionSets; i++) {
        if (!find_set(in, info->actionSets[i])) {
            FV_WARN(XRI_LOG, "xrAttachSessionActionSets: actionSets[%u] is not a live action set", i);
            return XR_ERROR_HANDLE_INVALID;
        }
    }
    XrResult r = build_attachment(s, info);
    if (r != XR_SUCCESS) {
        free_attachment(s);
        return r;
    }
    for (uint32_t i = 0; i < s->set_count; i++) {
        s->sets[i]->ever_attached = true;
        s->sets[i]->session_refs++;
    }
    s->attached = true;
    return XR_SUCCESS;
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Interaction profile selection                                                                                */

/* Whether the app suggested bindings of profile p for actions attached to this session, on user u. */
static bool profile_suggested(const fv_xr_input_session *s, int p, xri_user u)
{
    const fv_xr_input *in = s->in;
    return (in->profile_table[p].user_mask & XRI_USER_BIT(u)) && s->prof[p].count > 0;
}

static void select_profiles(fv_xr_input_session *s, const fv_xr_input_devices *dev)
{
    fv_xr_input *in = s->in;
    int next[XRI_USER_COUNT];
    for (int u = 0; u < XRI_USER_COUNT; u++) next[u] = -1;
    if (s->attached && dev) {
        for (int h = 0; h < 2; h++) {
            xri_user u = h == 0 ? XRI_USER_HAND_LEFT : XRI_USER_HAND_RIGHT;
            if (!dev->hands_present[h]) continue;
            const xri_profile *own = dev->hand_profiles[h] ? xri_profile_find(dev->hand_profiles[h], false) : NULL;
            int own_i = own ? profile_index(in, own) : -1;
            if (own_i >= 0 && profile_suggested(s, own_i, u)) {
                next[u] = own_i;
                continue;
            }
            if (profile_suggested(s, 0, u)) { /* khr/simple_controller: any controller can stand in for it */
                next[u] = 0;
                continue;
            }
            for (uint32_t p = 0; p < in->profile_count && next[u] < 0; p++)
                if (profile_suggested(s, (int)p, u)) next[u] = (int)p;
        }
        if (in->eye_gaze_ext && dev->eye_gaze_present) {
            const xri_profile *gaze = xri_profile_find("/interaction_profiles/ext/eye_gaze_interaction", true);
            int gi = profile_index(in, gaze);
            if (profile_suggested(s, gi, XRI_USER_EYES_EXT)) next[XRI_USER_EYES_EXT] = gi;
        }
    }
    for (int u = 0; u < XRI_USER_COUNT; u++) {
        if (next[u] != s->current[u]) {
            s->current[u] = next[u];
            s->profile_changed = true;
        }
    }
}

void fv_xr_input_update_profiles(fv_xr_input_session *s, const fv_xr_input_devices *dev)
{
    if (!s || !dev) return;
    s->pending = *dev;
    s->pending.values = NULL; /* borrowed for the call only */
    s->pending.value_count = 0;
    for (int h = 0; h < 2; h++) s->pending.hand_profiles[h] = NULL;
    /* hand_profiles are borrowed too; remember them by the table's own strings */
    for (int h = 0; h < 2; h++) {
        const xri_profile *p = dev->hand_profiles[h] ? xri_profile_find(dev->hand_profiles[h], false) : NULL;
        s->pending.hand_profiles[h] = p ? p->path : NULL;
    }
    s->have_pending = true;
}

bool fv_xr_input_take_profile_changed(fv_xr_input_session *s)
{
    if (!s || !s->profile_changed) return false;
    s->profile_changed = false;
    return true;
}

XrResult fv_xr_input_get_current_interaction_profile(fv_xr_input_session *s, XrPath top, XrInteractionProfileState *out)
{
    if (!s) return XR_ERROR_HANDLE_INVALID;
    fv_xr_input *in = s->in;
    if (!out || out->type != XR_TYPE_INTERACTION_PROFILE_STATE) {
        FV_WARN(XRI_LOG, "xrGetCurrentInteractionProfile: interactionProfile is NULL or not "
                         "XR_TYPE_INTERACTION_PROFILE_STATE");
        return XR_ERROR_VALIDATION_FAILURE;
    }
    if (!s->attached) {
        FV_WARN(XRI_LOG, "xrGetCurrentInteractionProfile: xrAttachSessionActionSets was not called on this session");
        return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    }
    const char *ts = xri_paths_str(&in->paths, top);
    if (!ts) return XR_ERROR_PATH_INVALID;
    xri_user u;
    if (!user_of_path(in, top, &u)) {
        FV_WARN(XRI_LOG, "xrGetCurrentInteractionProfile: \"%s\" is not a top-level user path", ts);
        return XR_ERROR_PATH_UNSUPPORTED;
    }
    out->interactionProfile = s->current[u] >= 0 ? in->profile_path[s->current[u]] : XR_NULL_PATH;
    return XR_SUCCESS;
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Sync                                                                                                         */

static xri_session_action *session_action(const fv_xr_input_session *s, const xri_action *a)
{
    uintptr_t i = (uintptr_t)xri_map_get(&s->act_index, a->handle);
    return i ? &s->acts[i - 1] : NULL;
}

/* Validates an XrActionsSyncInfo; fills active[set index][user] (true when that set is active on that user). */
static XrResult check_sync_info(const fv_xr_input_session *s, const XrActionsSyncInfo *info, bool (*active)[XRI_USER_COUNT])
{
    const fv_xr_input *in = s->in;
    if (!info || info->type != XR_TYPE_ACTIONS_SYNC_INFO || (info->countActiveActionSets > 0 && !info->activeActionSets)) {
        FV_WARN(XRI_LOG, "xrSyncActions: syncInfo is NULL, not XR_TYPE_ACTIONS_SYNC_INFO, or activeActionSets is "
                         "NULL with a non-zero count");
        return XR_ERROR_VALIDATION_FAILURE;
    }
    for (uint32_t i = 0; i < info->countActiveActionSets; i++) {
        const XrActiveActionSet *as = &info->activeActionSets[i];
        const xri_action_set *set = find_set(in, as->actionSet);
        if (!set) {
            FV_WARN(XRI_LOG, "xrSyncActions: activeActionSets[%u].actionSet is not a live action set", i);
            return XR_ERROR_HANDLE_INVALID;
        }
        uint32_t si = 0;
        while (si < s->set_count && s->sets[si] != set) si++;
        if (si == s->set_count) {
            FV_WARN(XRI_LOG, "xrSyncActions: action set \"%s\" is not attached to this session", set->name);
            return XR_ERROR_ACTIONSET_NOT_ATTACHED;
        }
        if (as->subactionPath == XR_NULL_PATH) {
            if (active)
                for (int u = 0; u < XRI_USER_COUNT; u++) active[si][u] = true;
            continue;
        }
        const char *ps = xri_paths_str(&in->paths, as->subactionPath);
        if (!ps) {
            FV_WARN(XRI_LOG, "xrSyncActions: activeActionSets[%u].subactionPath is not a path of this instance", i);
            return XR_ERROR_PATH_INVALID;
        }
        bool declared = false;
        xri_user du = XRI_USER_HEAD;
        for (uint32_t k = 0; k < set->action_count && !declared; k++) {
            const xri_action *a = set->actions[k];
            for (uint32_t j = 0; j < a->sub_count && !declared; j++) {
                declared = a->sub[j] == as->subactionPath;
                du = a->sub_user[j];
            }
        }
        if (!declared) {
            FV_WARN(XRI_LOG, "xrSyncActions: activeActionSets[%u].subactionPath \"%s\" is declared by no action of "
                             "action set \"%s\"", i, ps, set->name);
            return XR_ERROR_PATH_UNSUPPORTED;
        }
        if (active) active[si][du] = true;
    }
    return XR_SUCCESS;
}

static float finite_clamp(float v, float lo, float hi)
{
    if (!(v == v) || isinf(v)) return isinf(v) ? (v > 0 ? hi : lo) : 0.0f;
    return v < lo ? lo : v > hi ? hi : v;
}

/* The device value of a source path (full string), and whether the device providing it is present. */
typedef struct xri_reading {
    bool present;
    float v;
    XrTime t;
} xri_reading;

static bool user_present(const fv_xr_input_devices *dev, xri_user u)
{
    switch (u) {
    case XRI_USER_HAND_LEFT: return dev->hands_present[0];
    case XRI_USER_HAND_RIGHT: return dev->hands_present[1];
    case XRI_USER_EYES_EXT: return dev->eye_gaze_present;
    default: return false; /* no head buttons, gamepad or treadmill device in fovea */
    }
}

static xri_reading read_component(const fv_xr_input_devices *dev, xri_user u, const char *sub)
{
    xri_reading r = {user_present(dev, u), 0.0f, 0};
    if (!r.present) return r;
    const char *us = xri_user_str(u);
    size_t un = strlen(us);
    bool signed_axis = false;
    const char *last = strrchr(sub, '/');
    if (last) signed_axis = strcmp(last, "/x") == 0 || strcmp(last, "/y") == 0 || strcmp(last, "/twist") == 0;
    for (uint32_t i = 0; i < dev->value_count; i++) {
        const char *p = dev->values[i].path;
        if (!p || strncmp(p, us, un) != 0 || strcmp(p + un, sub) != 0) continue;
        r.v = finite_clamp(dev->values[i].value, signed_axis ? -1.0f : 0.0f, 1.0f);
        r.t = dev->values[i].changed_time;
    }
    return r;
}

typedef struct xri_sync_ctx {
    fv_xr_input_session *s;
    const fv_xr_input_devices *dev;
    bool (*active)[XRI_USER_COUNT];
} xri_sync_ctx;

static int set_index(const fv_xr_input_session *s, const xri_action_set *set)
{
    for (uint32_t i = 0; i < s->set_count; i++)
        if (s->sets[i] == set) return (int)i;
    return -1;
}

static bool action_has_user(const xri_action *a, xri_user u)
{
    if (a->sub_count == 0) return true;
    for (uint32_t j = 0; j < a->sub_count; j++)
        if (a->sub_user[j] == u) return true;
    return false;
}


/* Marks which bindings take part in this sync (s->live): its profile is current on its user, its set is attached
   and active on that user, it feeds its action's type, and no active set of higher priority uses the same input
   source (same user, identifier and location: the spec's "same input source" even across components). Once per
   sync: O(bindings) plus, per current profile, the pairs of input bindings on one user. */
static void mark_live(const xri_sync_ctx *c)
{
    fv_xr_input_session *s = c->s;
    for (int p = 0; p < XRI_PROFILE_MAX; p++) {
        const xri_profile_bindings *pb = &s->prof[p];
        uint8_t *live = s->live[p];
        for (uint32_t i = 0; i < pb->count; i++) {
            const xri_binding *b = &pb->b[i];
            int si = set_index(s, b->action->set);
            live[i] = s->current[b->user] == p && b->res.count > 0 && si >= 0 && c->active[si][b->user] &&
                      action_has_user(b->action, b->user);
        }
        /* Only a binding below the highest priority among active sets can be hidden: the usual app (one priority)
           skips the pairwise pass. */
        uint32_t top = 0;
        for (uint32_t i = 0; i < pb->count; i++)
            if ((live[i] & 1) && pb->b[i].action->set->priority > top) top = pb->b[i].action->set->priority;
        for (uint32_t i = 0; i < pb->count; i++) {
            const xri_binding *b = &pb->b[i];
            if (!(live[i] & 1) || !b->is_input || b->action->set->priority == top) continue;
            for (uint32_t j = 0; j < pb->count; j++) {
                const xri_binding *o = &pb->b[j];
                if (!(live[j] & 1) || !o->is_input || o->user != b->user ||
                    o->action->set->priority <= b->action->set->priority || o->ident_len != b->ident_len ||
                    strncmp(o->comp, b->comp, b->ident_len) != 0)
                    continue;
                live[i] |= 2; /* hidden by a higher-priority set (bit 0 stays: others still compare with it) */
                break;
            }
        }
        for (uint32_t i = 0; i < pb->count; i++) live[i] = live[i] == 1;
    }
}

static void compute_slot(const xri_sync_ctx *c, xri_session_action *sa, uint32_t slot_i)
{
    const fv_xr_input_session *s = c->s;
    const fv_xr_input *in = s->in;
    const xri_action *a = sa->a;
    xri_slot *slot = &sa->slot[slot_i];
    bool any_user = slot_i == a->sub_count;
    xri_user only = any_user ? XRI_USER_HEAD : a->sub_user[slot_i];

    bool active = false, bv = false;
    float fv = 0.0f;
    XrVector2f vv = {0.0f, 0.0f};
    XrTime t = 0;
    const char *pose_sub = NULL;
    xri_user pose_user = XRI_USER_HEAD;
    for (uint32_t n = 0; n < sa->bind_count; n++) {
        int p = sa->binds[n].profile;
        uint32_t i = sa->binds[n].index;
        const xri_profile *prof = &in->profile_table[p];
        {
            const xri_binding *b = &s->prof[p].b[i];
            if ((!any_user && b->user != only) || !s->live[p][i]) continue;
            xri_reading r0 = read_component(c->dev, b->user, prof->comps[b->res.comp[0]].sub);
            if (!r0.present) continue;
            active = true;
            if (r0.t > t) t = r0.t;
            switch (a->type) {
            case XR_ACTION_TYPE_BOOLEAN_INPUT: {
                xri_kind k = xri_component_kind(prof->comps[b->res.comp[0]].sub);
                bool on = k == XRI_KIND_BOOL ? r0.v >= 0.5f : r0.v > (slot->b ? XRI_RELEASE : XRI_PRESS);
                bv = bv || on; /* OR of all bound inputs */
                break;
            }
            case XR_ACTION_TYPE_FLOAT_INPUT:
                if (fabsf(r0.v) > fabsf(fv)) fv = r0.v; /* the largest absolute value */
                break;
            case XR_ACTION_TYPE_VECTOR2F_INPUT: {
                xri_reading r1 = read_component(c->dev, b->user, prof->comps[b->res.comp[1]].sub);
                if (r1.t > t) t = r1.t;
                if (r0.v * r0.v + r1.v * r1.v > vv.x * vv.x + vv.y * vv.y) { /* the longest vector */
                    vv.x = r0.v;
                    vv.y = r1.v;
                }
                break;
            }
            case XR_ACTION_TYPE_POSE_INPUT:
                if (!pose_sub) { /* one pose source, the first suggested, used consistently */
                    pose_sub = prof->comps[b->res.comp[0]].sub;
                    pose_user = b->user;
                }
                break;
            default: break;
            }
        }
    }
    bool value_changed = false;
    if (active) {
        switch (a->type) {
        case XR_ACTION_TYPE_BOOLEAN_INPUT: value_changed = bv != slot->b; break;
        case XR_ACTION_TYPE_FLOAT_INPUT: value_changed = fv != slot->f; break;
        case XR_ACTION_TYPE_VECTOR2F_INPUT: value_changed = vv.x != slot->v.x || vv.y != slot->v.y; break;
        default: break;
        }
    }
    /* changedSinceLastSync: false when there is no previous sync or the action was inactive for it. */
    slot->changed = active && slot->active && value_changed;
    if (!active) {
        slot->last_change = 0;
    } else if (!slot->active || value_changed) {
        slot->last_change = t ? t : c->dev->time;
    }
    slot->active = active;
    slot->b = active && bv;
    slot->f = active ? fv : 0.0f;
    slot->v = active ? vv : (XrVector2f){0.0f, 0.0f};
    slot->pose_sub = active ? pose_sub : NULL;
    slot->pose_user = pose_user;
}

static void clear_states(fv_xr_input_session *s)
{
    for (uint32_t i = 0; i < s->act_count; i++) {
        for (uint32_t j = 0; j <= s->acts[i].a->sub_count; j++) {
            xri_slot *slot = &s->acts[i].slot[j];
            memset(slot, 0, sizeof *slot);
        }
    }
}

XrResult fv_xr_input_sync(fv_xr_input_session *s, const XrActionsSyncInfo *info, const fv_xr_input_devices *dev)
{
    if (!s) return XR_ERROR_HANDLE_INVALID;
    bool(*active)[XRI_USER_COUNT] = calloc(s->set_count ? s->set_count : 1, sizeof *active);
    if (!active) return XR_ERROR_OUT_OF_MEMORY;
    XrResult r = check_sync_info(s, info, active);
    if (r != XR_SUCCESS) {
        free(active);
        return r;
    }
    fv_xr_input_devices none = {0};
    if (!dev) dev = s->have_pending ? &s->pending : &none;
    select_profiles(s, dev);
    s->have_pending = false;
    xri_sync_ctx c = {s, dev, active};
    mark_live(&c);
    for (uint32_t i = 0; i < s->act_count; i++)
        for (uint32_t j = 0; j <= s->acts[i].a->sub_count; j++) compute_slot(&c, &s->acts[i], j);
    free(active);
    return XR_SUCCESS;
}

void fv_xr_input_deactivate(fv_xr_input_session *s)
{
    if (s) clear_states(s);
}

bool fv_xr_input_owns_handle(const fv_xr_input *in, uint64_t v)
{
    if (!in) return false;
    if (((v >> 36) & 0xF) == KIND_SET) return find_set(in, set_handle(v)) != NULL;
    return find_action(in, action_handle(v), true) != NULL;
}

XrResult fv_xr_input_sync_unfocused(fv_xr_input_session *s, const XrActionsSyncInfo *info)
{
    if (!s) return XR_ERROR_HANDLE_INVALID;
    XrResult r = check_sync_info(s, info, NULL);
    if (r != XR_SUCCESS) return r;
    if (s->have_pending) {
        select_profiles(s, &s->pending);
        s->have_pending = false;
    }
    clear_states(s);
    return XR_SESSION_NOT_FOCUSED;
}

/* ------------------------------------------------------------------------------------------------------------ */
/* State queries                                                                                                */

/* The slot a query reads, after the spec's checks in order: handle, attachment, type, subaction path. */
static XrResult query_slot(fv_xr_input_session *s, const char *fn, XrAction h, XrPath sub, XrActionType want,
                           bool any_type, xri_session_action **out_sa, uint32_t *out_slot)
{
    fv_xr_input *in = s->in;
    xri_action *a = find_action(in, h, true);
    if (!a) {
        FV_WARN(XRI_LOG, "%s: action is not a live action of this instance", fn);
        return XR_ERROR_HANDLE_INVALID;
    }
    xri_session_action *sa = session_action(s, a);
    if (!sa) {
        FV_WARN(XRI_LOG, "%s: action \"%s\" is in action set \"%s\", which is not attached to this session", fn,
                a->name, a->set->name);
        return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    }
    if (!any_type && a->type != want) {
        FV_WARN(XRI_LOG, "%s: action \"%s\" has another type", fn, a->name);
        return XR_ERROR_ACTION_TYPE_MISMATCH;
    }
    uint32_t slot = a->sub_count;
    if (sub != XR_NULL_PATH) {
        const char *ps = xri_paths_str(&in->paths, sub);
        if (!ps) {
            FV_WARN(XRI_LOG, "%s: subactionPath is not a path of this instance", fn);
            return XR_ERROR_PATH_INVALID;
        }
        slot = UINT32_MAX;
        for (uint32_t j = 0; j < a->sub_count; j++)
            if (a->sub[j] == sub) slot = j;
        if (slot == UINT32_MAX) {
            FV_WARN(XRI_LOG, "%s: subactionPath \"%s\" was not declared when action \"%s\" was created", fn, ps,
                    a->name);
            return XR_ERROR_PATH_UNSUPPORTED;
        }
    }
    *out_sa = sa;
    *out_slot = slot;
    return XR_SUCCESS;
}

/* The common part of xrGetActionState*: structure checks, then query_slot. out is the state structure (its type
   first); NULL slot on error. */
static XrResult read_state(fv_xr_input_session *s, const XrActionStateGetInfo *g, const void *out,
                           XrStructureType out_type, XrActionType want, const char *fn, const xri_slot **slot)
{
    *slot = NULL;
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!g || g->type != XR_TYPE_ACTION_STATE_GET_INFO || !out || *(const XrStructureType *)out != out_type) {
        FV_WARN(XRI_LOG, "%s: getInfo or state is NULL or has the wrong structure type", fn);
        return XR_ERROR_VALIDATION_FAILURE;
    }
    xri_session_action *sa;
    uint32_t k;
    XrResult r = query_slot(s, fn, g->action, g->subactionPath, want, false, &sa, &k);
    if (r == XR_SUCCESS) *slot = &sa->slot[k];
    return r;
}

/* The fields every input state shares: an inactive action reads FALSE / 0 (compute_slot zeroes its value). */
#define FILL_COMMON(out, slot)                                                                                         \
    do {                                                                                                               \
        (out)->changedSinceLastSync = (slot)->changed ? XR_TRUE : XR_FALSE;                                            \
        (out)->lastChangeTime = (slot)->last_change;                                                                   \
        (out)->isActive = (slot)->active ? XR_TRUE : XR_FALSE;                                                         \
    } while (0)

XrResult fv_xr_input_get_boolean(fv_xr_input_session *s, const XrActionStateGetInfo *g, XrActionStateBoolean *out)
{
    const xri_slot *slot;
    XrResult r = read_state(s, g, out, XR_TYPE_ACTION_STATE_BOOLEAN, XR_ACTION_TYPE_BOOLEAN_INPUT,
                            "xrGetActionStateBoolean", &slot);
    if (r != XR_SUCCESS) return r;
    out->currentState = slot->b ? XR_TRUE : XR_FALSE;
    FILL_COMMON(out, slot);
    return XR_SUCCESS;
}

XrResult fv_xr_input_get_float(fv_xr_input_session *s, const XrActionStateGetInfo *g, XrActionStateFloat *out)
{
    const xri_slot *slot;
    XrResult r = read_state(s, g, out, XR_TYPE_ACTION_STATE_FLOAT, XR_ACTION_TYPE_FLOAT_INPUT, "xrGetActionStateFloat",
                            &slot);
    if (r != XR_SUCCESS) return r;
    out->currentState = slot->f;
    FILL_COMMON(out, slot);
    return XR_SUCCESS;
}

XrResult fv_xr_input_get_vector2f(fv_xr_input_session *s, const XrActionStateGetInfo *g, XrActionStateVector2f *out)
{
    const xri_slot *slot;
    XrResult r = read_state(s, g, out, XR_TYPE_ACTION_STATE_VECTOR2F, XR_ACTION_TYPE_VECTOR2F_INPUT,
                            "xrGetActionStateVector2f", &slot);
    if (r != XR_SUCCESS) return r;
    out->currentState = slot->v;
    FILL_COMMON(out, slot);
    return XR_SUCCESS;
}

XrResult fv_xr_input_get_pose(fv_xr_input_session *s, const XrActionStateGetInfo *g, XrActionStatePose *out)
{
    const xri_slot *slot;
    XrResult r = read_state(s, g, out, XR_TYPE_ACTION_STATE_POSE, XR_ACTION_TYPE_POSE_INPUT, "xrGetActionStatePose",
                            &slot);
    if (r != XR_SUCCESS) return r;
    out->isActive = slot->active ? XR_TRUE : XR_FALSE;
    return XR_SUCCESS;
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Bound sources and localized names                                                                            */

XrResult fv_xr_input_enumerate_bound_sources(fv_xr_input_session *s, const XrBoundSourcesForActionEnumerateInfo *e,
                                             uint32_t capacity, uint32_t *count_out, XrPath *sources)
{
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!e || e->type != XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO || !count_out || (capacity > 0 && !sources)) {
        FV_WARN(XRI_LOG, "xrEnumerateBoundSourcesForAction: enumerateInfo is NULL or of the wrong type, "
                         "sourceCountOutput is NULL, or sources is NULL with a non-zero capacity");
        return XR_ERROR_VALIDATION_FAILURE;
    }
    xri_session_action *sa;
    uint32_t k;
    XrResult r = query_slot(s, "xrEnumerateBoundSourcesForAction", e->action, XR_NULL_PATH, XR_ACTION_TYPE_BOOLEAN_INPUT,
                            true, &sa, &k);
    if (r != XR_SUCCESS) return r;
    /* Sources in the current profiles only (profiles change only at a sync, so this is stable between syncs). */
    uint32_t n = 0;
    XrPath found[64];
    XrPath *list = found;
    uint32_t list_cap = 64;
    for (uint32_t m = 0; m < sa->bind_count; m++) {
        int p = sa->binds[m].profile;
        {
            const xri_binding *b = &s->prof[p].b[sa->binds[m].index];
            if (b->res.count == 0 || s->current[b->user] != p || !action_has_user(sa->a, b->user)) continue;
            bool dup = false;
            for (uint32_t j = 0; j < n && !dup; j++) dup = list[j] == b->source;
            if (dup) continue;
            if (n == list_cap) {
                XrPath *bigger = malloc(list_cap * 2 * sizeof *bigger);
                if (!bigger) {
                    if (list != found) free(list);
                    return XR_ERROR_OUT_OF_MEMORY;
                }
                memcpy(bigger, list, n * sizeof *list);
                if (list != found) free(list);
                list = bigger;
                list_cap *= 2;
            }
            list[n++] = b->source;
        }
    }
    *count_out = n;
    r = XR_SUCCESS;
    if (capacity > 0) {
        if (capacity < n)
            r = XR_ERROR_SIZE_INSUFFICIENT;
        else
            memcpy(sources, list, n * sizeof *list);
    }
    if (list != found) free(list);
    return r;
}

XrResult fv_xr_input_get_localized_name(fv_xr_input_session *s, const XrInputSourceLocalizedNameGetInfo *g,
                                        uint32_t capacity, uint32_t *count_out, char *buf)
{
    if (!s) return XR_ERROR_HANDLE_INVALID;
    fv_xr_input *in = s->in;
    const XrInputSourceLocalizedNameFlags all = XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT |
                                                XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT |
                                                XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT;
    if (!g || g->type != XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO || g->whichComponents == 0 ||
        (g->whichComponents & ~all) || !count_out || (capacity > 0 && !buf)) {
        FV_WARN(XRI_LOG, "xrGetInputSourceLocalizedName: getInfo is NULL or of the wrong type, whichComponents is 0 or "
                         "has unknown bits, or an output is NULL");
        return XR_ERROR_VALIDATION_FAILURE;
    }
    if (!s->attached) {
        FV_WARN(XRI_LOG, "xrGetInputSourceLocalizedName: xrAttachSessionActionSets was not called on this session");
        return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    }
    const char *src = xri_paths_str(&in->paths, g->sourcePath);
    if (!src) return XR_ERROR_PATH_INVALID;
    xri_user u;
    size_t un = xri_user_match(src, in->eye_gaze_ext, &u);
    if (un == 0) {
        FV_WARN(XRI_LOG, "xrGetInputSourceLocalizedName: \"%s\" is not under a top-level user path", src);
        return XR_ERROR_PATH_UNSUPPORTED;
    }
    char name[256] = "";
    if (g->whichComponents & XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT) strcat(name, xri_user_localized(u));
    if ((g->whichComponents & XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT) && s->current[u] >= 0) {
        if (name[0]) strcat(name, " ");
        strcat(name, in->profile_table[s->current[u]].localized);
    }
    if ((g->whichComponents & XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT) && src[un] == '/') {
        char comp[128] = "";
        xri_component_localized(src + un, comp, sizeof comp);
        if (comp[0] && name[0]) strcat(name, " ");
        strncat(name, comp, sizeof name - strlen(name) - 1);
    }
    return write_string(name, capacity, count_out, buf);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Haptics                                                                                                      */

static XrResult haptic_checks(fv_xr_input_session *s, const XrHapticActionInfo *h, const char *fn)
{
    if (!h || h->type != XR_TYPE_HAPTIC_ACTION_INFO) {
        FV_WARN(XRI_LOG, "%s: hapticActionInfo is NULL or not XR_TYPE_HAPTIC_ACTION_INFO", fn);
        return XR_ERROR_VALIDATION_FAILURE;
    }
    xri_session_action *sa;
    uint32_t k;
    return query_slot(s, fn, h->action, h->subactionPath, XR_ACTION_TYPE_VIBRATION_OUTPUT, false, &sa, &k);
}

XrResult fv_xr_input_apply_haptic(fv_xr_input_session *s, const XrHapticActionInfo *h, const XrHapticBaseHeader *fb)
{
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!fb || fb->type != XR_TYPE_HAPTIC_VIBRATION) {
        FV_WARN(XRI_LOG, "xrApplyHapticFeedback: hapticFeedback is NULL or not XR_TYPE_HAPTIC_VIBRATION (the only "
                         "haptic event of OpenXR 1.0)");
        return XR_ERROR_VALIDATION_FAILURE;
    }
    XrResult r = haptic_checks(s, h, "xrApplyHapticFeedback");
    if (r != XR_SUCCESS) return r;
    /* fovea drives no haptic device: the spec lets the runtime ignore a request no device can play. Duration,
       frequency and amplitude are accepted as given (they "may be clamped"). */
    return XR_SUCCESS;
}

XrResult fv_xr_input_stop_haptic(fv_xr_input_session *s, const XrHapticActionInfo *h)
{
    if (!s) return XR_ERROR_HANDLE_INVALID;
    return haptic_checks(s, h, "xrStopHapticFeedback");
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Action spaces                                                                                                */

XrResult fv_xr_input_check_action_space(fv_xr_input *in, const XrActionSpaceCreateInfo *info)
{
    if (!in) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_ACTION_SPACE_CREATE_INFO) {
        FV_WARN(XRI_LOG, "xrCreateActionSpace: createInfo is NULL or not XR_TYPE_ACTION_SPACE_CREATE_INFO");
        return XR_ERROR_VALIDATION_FAILURE;
    }
    const xri_action *a = find_action(in, info->action, true);
    if (!a) {
        FV_WARN(XRI_LOG, "xrCreateActionSpace: action is not a live action of this instance");
        return XR_ERROR_HANDLE_INVALID;
    }
    if (a->type != XR_ACTION_TYPE_POSE_INPUT) {
        FV_WARN(XRI_LOG, "xrCreateActionSpace: action \"%s\" is not a pose action", a->name);
        return XR_ERROR_ACTION_TYPE_MISMATCH;
    }
    if (info->subactionPath != XR_NULL_PATH) {
        const char *ps = xri_paths_str(&in->paths, info->subactionPath);
        if (!ps) return XR_ERROR_PATH_INVALID;
        bool declared = false;
        for (uint32_t j = 0; j < a->sub_count; j++) declared = declared || a->sub[j] == info->subactionPath;
        if (!declared) {
            FV_WARN(XRI_LOG, "xrCreateActionSpace: subactionPath \"%s\" was not declared on action \"%s\"", ps, a->name);
            return XR_ERROR_PATH_UNSUPPORTED;
        }
    }
    const XrPosef *p = &info->poseInActionSpace;
    const float v[7] = {p->orientation.x, p->orientation.y, p->orientation.z, p->orientation.w,
                        p->position.x,    p->position.y,    p->position.z};
    for (int i = 0; i < 7; i++) {
        if (!isfinite(v[i])) {
            FV_WARN(XRI_LOG, "xrCreateActionSpace: poseInActionSpace holds a NaN or infinity");
            return XR_ERROR_POSE_INVALID;
        }
    }
    double n2 = (double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2] + (double)v[3] * v[3];
    if (fabs(n2 - 1.0) > 1e-2) {
        FV_WARN(XRI_LOG, "xrCreateActionSpace: poseInActionSpace.orientation is not a unit quaternion (|q|^2 = %g)", n2);
        return XR_ERROR_POSE_INVALID;
    }
    return XR_SUCCESS;
}

fv_xr_pose_source fv_xr_input_pose_source(fv_xr_input_session *s, XrAction h, XrPath subaction_path)
{
    if (!s) return FV_XR_POSE_NONE;
    fv_xr_input *in = s->in;
    const xri_action *a = find_action(in, h, false); /* a destroyed handle's space stays locatable */
    if (!a || a->type != XR_ACTION_TYPE_POSE_INPUT) return FV_XR_POSE_NONE;
    xri_session_action *sa = session_action(s, a);
    if (!sa) return FV_XR_POSE_NONE;
    uint32_t k = a->sub_count;
    if (subaction_path != XR_NULL_PATH) {
        k = UINT32_MAX;
        for (uint32_t j = 0; j < a->sub_count; j++)
            if (a->sub[j] == subaction_path) k = j;
        if (k == UINT32_MAX) return FV_XR_POSE_NONE;
    }
    const xri_slot *slot = &sa->slot[k];
    if (!slot->active || !slot->pose_sub) return FV_XR_POSE_NONE;
    const char *sub = slot->pose_sub;
    xri_user u = slot->pose_user;
    if (u == XRI_USER_EYES_EXT) return FV_XR_POSE_EYE_GAZE;
    bool aim = strcmp(sub, "/input/aim/pose") == 0;
    bool grip = strcmp(sub, "/input/grip/pose") == 0;
    if (u == XRI_USER_HAND_LEFT) return aim ? FV_XR_POSE_LEFT_AIM : grip ? FV_XR_POSE_LEFT_GRIP : FV_XR_POSE_NONE;
    if (u == XRI_USER_HAND_RIGHT)
        return aim ? FV_XR_POSE_RIGHT_AIM : grip ? FV_XR_POSE_RIGHT_GRIP : FV_XR_POSE_NONE;
    return FV_XR_POSE_NONE;
}
