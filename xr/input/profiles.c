/* @brief Interaction profiles (OpenXR 1.0, "Interaction Profile Paths", and XR_EXT_eye_gaze_interaction) with their
   component allowlists, the top-level user paths, the suggested-binding resolver ("Suggested Bindings": implicit
   /click, /value, /pose and the /x,/y pair of a vector2f parent) and the localized names of sources. */
#include <stdio.h>
#include <string.h>

#include "xr_input_internal.h"

#define L XRI_USER_BIT(XRI_USER_HAND_LEFT)
#define R XRI_USER_BIT(XRI_USER_HAND_RIGHT)
#define HANDS (L | R)
#define HEAD XRI_USER_BIT(XRI_USER_HEAD)
#define PAD XRI_USER_BIT(XRI_USER_GAMEPAD)
#define EYES XRI_USER_BIT(XRI_USER_EYES_EXT)
#define N(a) (uint32_t)(sizeof(a) / sizeof((a)[0]))

static const struct {
    const char *path;
    const char *localized;
} users[XRI_USER_COUNT] = {
    [XRI_USER_HEAD] = {"/user/head", "Head"},
    [XRI_USER_HAND_LEFT] = {"/user/hand/left", "Left Hand"},
    [XRI_USER_HAND_RIGHT] = {"/user/hand/right", "Right Hand"},
    [XRI_USER_GAMEPAD] = {"/user/gamepad", "Gamepad"},
    [XRI_USER_TREADMILL] = {"/user/treadmill", "Treadmill"},
    [XRI_USER_EYES_EXT] = {"/user/eyes_ext", "Eyes"},
};

const char *xri_user_str(xri_user u) { return users[u].path; }
const char *xri_user_localized(xri_user u) { return users[u].localized; }

size_t xri_user_match(const char *s, bool eye_gaze_ext, xri_user *out)
{
    for (int u = 0; u < XRI_USER_COUNT; u++) {
        if (u == XRI_USER_EYES_EXT && !eye_gaze_ext) continue;
        size_t n = strlen(users[u].path);
        if (strncmp(s, users[u].path, n) == 0 && (s[n] == '\0' || s[n] == '/')) {
            *out = (xri_user)u;
            return n;
        }
    }
    return 0;
}

/* Khronos Simple Controller */
static const xri_component simple[] = {
    {"/input/select/click", 0}, {"/input/menu/click", 0}, {"/input/grip/pose", 0},
    {"/input/aim/pose", 0},     {"/output/haptic", 0},
};
/* Google Daydream Controller */
static const xri_component daydream[] = {
    {"/input/select/click", 0},   {"/input/trackpad/x", 0},     {"/input/trackpad/y", 0},
    {"/input/trackpad/click", 0}, {"/input/trackpad/touch", 0}, {"/input/grip/pose", 0},
    {"/input/aim/pose", 0},
};
/* HTC Vive Controller */
static const xri_component vive[] = {
    {"/input/system/click", 0},   {"/input/squeeze/click", 0},  {"/input/menu/click", 0},
    {"/input/trigger/click", 0},  {"/input/trigger/value", 0},  {"/input/trackpad/x", 0},
    {"/input/trackpad/y", 0},     {"/input/trackpad/click", 0}, {"/input/trackpad/touch", 0},
    {"/input/grip/pose", 0},      {"/input/aim/pose", 0},       {"/output/haptic", 0},
};
/* HTC Vive Pro (the headset's buttons) */
static const xri_component vive_pro[] = {
    {"/input/system/click", 0},
    {"/input/volume_up/click", 0},
    {"/input/volume_down/click", 0},
    {"/input/mute_mic/click", 0},
};
/* Microsoft Mixed Reality Motion Controller */
static const xri_component wmr[] = {
    {"/input/menu/click", 0},       {"/input/squeeze/click", 0},  {"/input/trigger/value", 0},
    {"/input/thumbstick/x", 0},     {"/input/thumbstick/y", 0},   {"/input/thumbstick/click", 0},
    {"/input/trackpad/x", 0},       {"/input/trackpad/y", 0},     {"/input/trackpad/click", 0},
    {"/input/trackpad/touch", 0},   {"/input/grip/pose", 0},      {"/input/aim/pose", 0},
    {"/output/haptic", 0},
};
/* Microsoft Xbox Controller */
static const xri_component xbox[] = {
    {"/input/menu/click", 0},
    {"/input/view/click", 0},
    {"/input/a/click", 0},
    {"/input/b/click", 0},
    {"/input/x/click", 0},
    {"/input/y/click", 0},
    {"/input/dpad_down/click", 0},
    {"/input/dpad_right/click", 0},
    {"/input/dpad_up/click", 0},
    {"/input/dpad_left/click", 0},
    {"/input/shoulder_left/click", 0},
    {"/input/shoulder_right/click", 0},
    {"/input/thumbstick_left/click", 0},
    {"/input/thumbstick_right/click", 0},
    {"/input/trigger_left/value", 0},
    {"/input/trigger_right/value", 0},
    {"/input/thumbstick_left/x", 0},
    {"/input/thumbstick_left/y", 0},
    {"/input/thumbstick_right/x", 0},
    {"/input/thumbstick_right/y", 0},
    {"/output/haptic_left", 0},
    {"/output/haptic_right", 0},
    {"/output/haptic_left_trigger", 0},
    {"/output/haptic_right_trigger", 0},
};
/* Oculus Go Controller */
static const xri_component go[] = {
    {"/input/system/click", 0},   {"/input/trigger/click", 0}, {"/input/back/click", 0},
    {"/input/trackpad/x", 0},     {"/input/trackpad/y", 0},    {"/input/trackpad/click", 0},
    {"/input/trackpad/touch", 0}, {"/input/grip/pose", 0},     {"/input/aim/pose", 0},
};
/* Oculus Touch Controller */
static const xri_component touch[] = {
    {"/input/x/click", L},          {"/input/x/touch", L},          {"/input/y/click", L},
    {"/input/y/touch", L},          {"/input/menu/click", L},       {"/input/a/click", R},
    {"/input/a/touch", R},          {"/input/b/click", R},          {"/input/b/touch", R},
    {"/input/system/click", R},     {"/input/squeeze/value", 0},    {"/input/trigger/value", 0},
    {"/input/trigger/touch", 0},    {"/input/thumbstick/x", 0},     {"/input/thumbstick/y", 0},
    {"/input/thumbstick/click", 0}, {"/input/thumbstick/touch", 0}, {"/input/thumbrest/touch", 0},
    {"/input/grip/pose", 0},        {"/input/aim/pose", 0},         {"/output/haptic", 0},
};
/* Valve Index Controller */
static const xri_component index_ctl[] = {
    {"/input/system/click", 0},     {"/input/system/touch", 0},     {"/input/a/click", 0},
    {"/input/a/touch", 0},          {"/input/b/click", 0},          {"/input/b/touch", 0},
    {"/input/squeeze/value", 0},    {"/input/squeeze/force", 0},    {"/input/trigger/click", 0},
    {"/input/trigger/value", 0},    {"/input/trigger/touch", 0},    {"/input/thumbstick/x", 0},
    {"/input/thumbstick/y", 0},     {"/input/thumbstick/click", 0}, {"/input/thumbstick/touch", 0},
    {"/input/trackpad/x", 0},       {"/input/trackpad/y", 0},       {"/input/trackpad/force", 0},
    {"/input/trackpad/touch", 0},   {"/input/grip/pose", 0},        {"/input/aim/pose", 0},
    {"/output/haptic", 0},
};
/* XR_EXT_eye_gaze_interaction */
static const xri_component eye_gaze[] = {
    {"/input/gaze_ext/pose", 0},
};

static const xri_profile profiles[] = {
    {"/interaction_profiles/khr/simple_controller", "Simple Controller", HANDS, false, simple, N(simple)},
    {"/interaction_profiles/google/daydream_controller", "Daydream Controller", HANDS, false, daydream,
     N(daydream)},
    {"/interaction_profiles/htc/vive_controller", "Vive Controller", HANDS, false, vive, N(vive)},
    {"/interaction_profiles/htc/vive_pro", "Vive Pro", HEAD, false, vive_pro, N(vive_pro)},
    {"/interaction_profiles/microsoft/motion_controller", "Mixed Reality Motion Controller", HANDS, false, wmr,
     N(wmr)},
    {"/interaction_profiles/microsoft/xbox_controller", "Xbox Controller", PAD, false, xbox, N(xbox)},
    {"/interaction_profiles/oculus/go_controller", "Oculus Go Controller", HANDS, false, go, N(go)},
    {"/interaction_profiles/oculus/touch_controller", "Oculus Touch Controller", HANDS, false, touch, N(touch)},
    {"/interaction_profiles/valve/index_controller", "Index Controller", HANDS, false, index_ctl, N(index_ctl)},
    {"/interaction_profiles/ext/eye_gaze_interaction", "Eye Gaze", EYES, true, eye_gaze, N(eye_gaze)},
};

const xri_profile *xri_profiles(uint32_t *out_count)
{
    *out_count = N(profiles);
    return profiles;
}

const xri_profile *xri_profile_find(const char *s, bool eye_gaze_ext)
{
    for (uint32_t i = 0; i < N(profiles); i++) {
        if (profiles[i].needs_eye_gaze_ext && !eye_gaze_ext) continue;
        if (strcmp(profiles[i].path, s) == 0) return &profiles[i];
    }
    return NULL;
}

static bool comp_on_user(const xri_profile *p, const xri_component *c, xri_user u)
{
    uint32_t mask = c->user_mask ? c->user_mask : p->user_mask;
    return (mask & XRI_USER_BIT(u)) != 0;
}

int xri_profile_component(const xri_profile *p, xri_user u, const char *sub, size_t n)
{
    for (uint32_t i = 0; i < p->comp_count; i++) {
        const xri_component *c = &p->comps[i];
        if (strlen(c->sub) == n && memcmp(c->sub, sub, n) == 0 && comp_on_user(p, c, u)) return (int)i;
    }
    return -1;
}

xri_kind xri_component_kind(const char *sub)
{
    if (strncmp(sub, "/output/", 8) == 0) return XRI_KIND_HAPTIC;
    const char *last = strrchr(sub, '/');
    last = last ? last + 1 : sub;
    if (strcmp(last, "click") == 0 || strcmp(last, "touch") == 0) return XRI_KIND_BOOL;
    if (strcmp(last, "pose") == 0) return XRI_KIND_POSE;
    return XRI_KIND_FLOAT; /* value, force, twist, x, y */
}

/* The child component parent + "/" + leaf, or -1. */
static int child(const xri_profile *p, xri_user u, const char *parent, const char *leaf)
{
    char buf[XR_MAX_PATH_LENGTH];
    int n = snprintf(buf, sizeof buf, "%s/%s", parent, leaf);
    if (n < 0 || (size_t)n >= sizeof buf) return -1;
    return xri_profile_component(p, u, buf, (size_t)n);
}

XrResult xri_resolve_binding(const xri_profile *p, xri_user u, const char *sub, XrActionType t, xri_resolved *out)
{
    memset(out, 0, sizeof *out);
    size_t n = strlen(sub);
    int exact = xri_profile_component(p, u, sub, n);
    if (exact >= 0) {
        xri_kind k = xri_component_kind(p->comps[exact].sub);
        bool feeds = false;
        switch (t) {
        case XR_ACTION_TYPE_BOOLEAN_INPUT: /* a scalar is thresholded */
        case XR_ACTION_TYPE_FLOAT_INPUT:   /* a boolean reads 0.0 or 1.0 */
            feeds = k == XRI_KIND_BOOL || k == XRI_KIND_FLOAT;
            break;
        case XR_ACTION_TYPE_POSE_INPUT: feeds = k == XRI_KIND_POSE; break;
        case XR_ACTION_TYPE_VIBRATION_OUTPUT: feeds = k == XRI_KIND_HAPTIC; break;
        default: feeds = false; /* vector2f needs the parent of /x and /y */
        }
        if (feeds) {
            out->count = 1;
            out->comp[0] = (int16_t)exact;
        }
        return XR_SUCCESS;
    }
    /* A parent path ("/input/trigger"): valid when some component of this user lies under it. It names an input
       source, so it holds an identifier: "/input" alone is not one. */
    if (strncmp(sub, "/input/", 7) != 0 || n <= 7) return XR_ERROR_PATH_UNSUPPORTED;
    bool is_parent = false;
    for (uint32_t i = 0; i < p->comp_count && !is_parent; i++) {
        const char *c = p->comps[i].sub;
        is_parent = strncmp(c, sub, n) == 0 && c[n] == '/' && comp_on_user(p, &p->comps[i], u);
    }
    if (!is_parent || n == 0) return XR_ERROR_PATH_UNSUPPORTED;
    int a = -1, b = -1;
    switch (t) {
    case XR_ACTION_TYPE_BOOLEAN_INPUT:
        a = child(p, u, sub, "click");
        if (a < 0) a = child(p, u, sub, "value");
        break;
    case XR_ACTION_TYPE_FLOAT_INPUT:
        a = child(p, u, sub, "value");
        if (a < 0) a = child(p, u, sub, "click");
        break;
    case XR_ACTION_TYPE_VECTOR2F_INPUT:
        a = child(p, u, sub, "x");
        b = child(p, u, sub, "y");
        if (b < 0) a = -1;
        break;
    case XR_ACTION_TYPE_POSE_INPUT: a = child(p, u, sub, "pose"); break;
    default: break;
    }
    if (a >= 0) {
        out->comp[0] = (int16_t)a;
        out->count = 1;
        if (b >= 0) {
            out->comp[1] = (int16_t)b;
            out->count = 2;
        }
    }
    return XR_SUCCESS;
}

static const struct {
    const char *id;
    const char *name;
} id_names[] = {
    {"a", "A Button"},
    {"b", "B Button"},
    {"x", "X Button"},
    {"y", "Y Button"},
    {"mute_mic", "Mute Microphone"},
    {"volume_up", "Volume Up"},
    {"volume_down", "Volume Down"},
    {"gaze_ext", "Eye Gaze"},
    {"haptic", "Haptics"},
    {"trackpad", "Trackpad"},
    {"thumbstick", "Thumbstick"},
    {"thumbrest", "Thumbrest"},
};

static const struct {
    const char *comp;
    const char *name;
} comp_names[] = {
    {"click", ""}, {"touch", "Touch"}, {"value", ""},        {"force", "Force"},
    {"twist", "Twist"}, {"x", "X Axis"},    {"y", "Y Axis"},      {"pose", "Pose"},
};

static void append(char *buf, size_t cap, const char *word)
{
    size_t n = strlen(buf);
    if (!word[0] || n + 1 >= cap) return;
    snprintf(buf + n, cap - n, "%s%s", n ? " " : "", word);
}

/* "shoulder_left" -> "Left Shoulder"; "dpad_up" -> "D-Pad Up"; "menu" -> "Menu". */
static void identifier_name(const char *id, size_t n, char *buf, size_t cap)
{
    char tmp[XR_MAX_PATH_LENGTH];
    if (n >= sizeof tmp) n = sizeof tmp - 1;
    memcpy(tmp, id, n);
    tmp[n] = '\0';
    for (size_t i = 0; i < sizeof id_names / sizeof id_names[0]; i++) {
        if (strcmp(tmp, id_names[i].id) == 0) {
            append(buf, cap, id_names[i].name);
            return;
        }
    }
    /* A trailing location (left, right, upper, lower and their pairs) goes first, as people say it. */
    static const char *const locations[] = {"_left_upper", "_left_lower", "_right_upper", "_right_lower",
                                            "_left",       "_right",      "_upper",       "_lower"};
    char loc[32] = "";
    for (size_t i = 0; i < sizeof locations / sizeof locations[0]; i++) {
        size_t ln = strlen(locations[i]);
        if (n > ln && strcmp(tmp + n - ln, locations[i]) == 0) {
            snprintf(loc, sizeof loc, "%s", locations[i] + 1);
            tmp[n - ln] = '\0';
            break;
        }
    }
    char words[XR_MAX_PATH_LENGTH + 32];
    size_t w = 0;
    bool cap_next = true;
    const char *parts[2] = {loc, tmp};
    for (int k = 0; k < 2; k++) {
        if (!parts[k][0]) continue;
        if (w) words[w++] = ' ';
        cap_next = true;
        for (const char *c = parts[k]; *c && w + 2 < sizeof words; c++) {
            if (*c == '_') {
                words[w++] = ' ';
                cap_next = true;
                continue;
            }
            char ch = *c;
            if (cap_next && ch >= 'a' && ch <= 'z') ch = (char)(ch - 'a' + 'A');
            words[w++] = ch;
            cap_next = false;
        }
    }
    words[w] = '\0';
    append(buf, cap, words);
}

void xri_component_localized(const char *sub, char *buf, size_t cap)
{
    /* sub is "/input/<identifier>[/<component>]" or "/output/<identifier>" */
    const char *rest = NULL;
    if (strncmp(sub, "/input/", 7) == 0) rest = sub + 7;
    if (strncmp(sub, "/output/", 8) == 0) rest = sub + 8;
    if (!rest || !rest[0]) return;
    const char *slash = strchr(rest, '/');
    size_t idn = slash ? (size_t)(slash - rest) : strlen(rest);
    if (strncmp(rest, "dpad_", 5) == 0) {
        append(buf, cap, "D-Pad");
        identifier_name(rest + 5, idn - 5, buf, cap);
    } else {
        identifier_name(rest, idn, buf, cap);
    }
    if (slash) {
        for (size_t i = 0; i < sizeof comp_names / sizeof comp_names[0]; i++) {
            if (strcmp(slash + 1, comp_names[i].comp) == 0) {
                append(buf, cap, comp_names[i].name);
                return;
            }
        }
        identifier_name(slash + 1, strlen(slash + 1), buf, cap);
    }
}
