/* @brief fv_xr_input: the path table (OpenXR 1.0 "Well-Formed Path Strings", xrStringToPath, xrPathToString) and
   xrSuggestInteractionProfileBindings (the core interaction profiles' component lists, per-profile validation, the
   implicit components of "Suggested Bindings"). Each test is one rule of the spec, named by its behaviour. */
/* fv_xr_input.h first: the public header compiles on its own. */
#include "fv_xr_input.h"
#include "fv_test.h"
#include "test_xr_input_util.h"

#include <stdio.h>
#include <stdlib.h>

static fv_xr_input *make(bool gaze)
{
    fv_xr_input_desc d = {.eye_gaze_ext_enabled = gaze};
    fv_xr_input *in = NULL;
    assert_int_equal(fv_xr_input_create(&d, &in), XR_SUCCESS);
    return in;
}

#define P xri_test_path

static XrResult s2p(fv_xr_input *in, const char *s)
{
    XrPath p = 12345;
    return fv_xr_input_string_to_path(in, s, &p);
}

/* ---- Path table ---- */

static void same_string_gives_same_atom_and_round_trips(void **st)
{
    (void)st;
    fv_xr_input *in = make(false);
    XrPath a = P(in, "/user/hand/left/input/select/click");
    XrPath b = P(in, "/user/hand/right/input/select/click");
    assert_int_not_equal(a, XR_NULL_PATH);
    assert_int_not_equal(a, b);
    for (int i = 0; i < 3; i++) assert_int_equal(P(in, "/user/hand/left/input/select/click"), a);
    char buf[XR_MAX_PATH_LENGTH];
    uint32_t n = 0;
    assert_int_equal(fv_xr_input_path_to_string(in, a, sizeof buf, &n, buf), XR_SUCCESS);
    assert_string_equal(buf, "/user/hand/left/input/select/click");
    assert_int_equal(n, strlen(buf) + 1); /* the count includes the terminator */
    fv_xr_input_destroy(&in);
    assert_null(in);
}

static void well_formed_paths_are_accepted(void **st)
{
    (void)st;
    fv_xr_input *in = make(false);
    const char *ok[] = {"/a", "/a-b_c.d/0", "/a/.b", "/a/b..c", "/.a", "/a./b", "/0/1/2", "/user/hand/left",
                        "/interaction_profiles/khr/simple_controller", "/x/...a"};
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++)
        if (s2p(in, ok[i]) != XR_SUCCESS) fail_msg("\"%s\" refused", ok[i]);
    fv_xr_input_destroy(&in);
}

static void each_malformed_path_rule_gives_path_format_invalid(void **st)
{
    (void)st;
    fv_xr_input *in = make(false);
    fv_test_log_capture_begin();
    const char *bad[] = {
        "",              /* must start with a single '/' */
        "a/b",           /* no leading slash */
        "/",             /* ends with '/' */
        "/a/",           /* trailing slash */
        "//a",           /* two adjacent slashes at the start */
        "/a//b",         /* two adjacent slashes */
        "/a/./b",        /* slashes separated only by periods */
        "/a/../b",       /* ditto */
        "/a/.../b",      /* ditto */
        "/a/.",          /* only periods after the last slash */
        "/a/..",         /* ditto */
        "/..",           /* ditto */
        "/A",            /* upper case */
        "/a b",          /* space */
        "/a\tb",         /* control character */
        "/a\\b",         /* backslash */
        "/a?b",          /* query character */
        "/caf\xc3\xa9",  /* non-ASCII (UTF-8 e-acute) */
        "/a\x7f",        /* DEL */
        "/user/hand/left/input/trigger:click",
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        XrPath p = 777;
        XrResult r = fv_xr_input_string_to_path(in, bad[i], &p);
        if (r != XR_ERROR_PATH_FORMAT_INVALID) fail_msg("\"%s\" gave %d, not XR_ERROR_PATH_FORMAT_INVALID", bad[i], r);
    }
    fv_assert_log_contains("two adjacent '/'");
    fv_assert_log_contains("made only of '.'");
    fv_assert_log_contains("must not end with '/'");
    fv_test_log_capture_end();
    fv_xr_input_destroy(&in);
}

static void path_length_limit_counts_the_terminator(void **st)
{
    (void)st;
    fv_xr_input *in = make(false);
    char s[XR_MAX_PATH_LENGTH + 2];
    s[0] = '/';
    memset(s + 1, 'a', sizeof s - 1);
    s[XR_MAX_PATH_LENGTH - 1] = '\0'; /* 255 characters + NUL = 256: the limit */
    assert_int_equal(s2p(in, s), XR_SUCCESS);
    s[XR_MAX_PATH_LENGTH - 1] = 'a';
    s[XR_MAX_PATH_LENGTH] = '\0'; /* 256 characters */
    fv_test_log_capture_begin();
    assert_int_equal(s2p(in, s), XR_ERROR_PATH_FORMAT_INVALID);
    fv_assert_log_contains("XR_MAX_PATH_LENGTH");
    fv_test_log_capture_end();
    /* A very long string is refused without being read past the limit (ASan watches the read). */
    size_t big = 1u << 20;
    char *huge = malloc(big + 1);
    assert_non_null(huge);
    huge[0] = '/';
    memset(huge + 1, 'b', big - 1);
    huge[big] = '\0';
    assert_int_equal(s2p(in, huge), XR_ERROR_PATH_FORMAT_INVALID);
    free(huge);
    fv_xr_input_destroy(&in);
}

static void path_to_string_uses_the_two_call_idiom(void **st)
{
    (void)st;
    fv_xr_input *in = make(false);
    XrPath p = P(in, "/user/gamepad");
    uint32_t n = 0;
    assert_int_equal(fv_xr_input_path_to_string(in, p, 0, &n, NULL), XR_SUCCESS);
    assert_int_equal(n, 14);
    char small[8] = "xxxxxxx";
    n = 0;
    assert_int_equal(fv_xr_input_path_to_string(in, p, sizeof small, &n, small), XR_ERROR_SIZE_INSUFFICIENT);
    assert_int_equal(n, 14);
    char exact[14];
    assert_int_equal(fv_xr_input_path_to_string(in, p, sizeof exact, &n, exact), XR_SUCCESS);
    assert_string_equal(exact, "/user/gamepad");
    /* a buffer capacity with a NULL buffer is a validation error */
    assert_int_equal(fv_xr_input_path_to_string(in, p, 4, &n, NULL), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(fv_xr_input_path_to_string(in, p, 0, NULL, NULL), XR_ERROR_VALIDATION_FAILURE);
    fv_xr_input_destroy(&in);
}

static void null_path_and_unknown_atoms_give_path_invalid(void **st)
{
    (void)st;
    fv_xr_input *in = make(false);
    uint32_t n;
    char buf[64];
    assert_int_equal(fv_xr_input_path_to_string(in, XR_NULL_PATH, sizeof buf, &n, buf), XR_ERROR_PATH_INVALID);
    assert_int_equal(fv_xr_input_path_to_string(in, 1000000, sizeof buf, &n, buf), XR_ERROR_PATH_INVALID);
    assert_int_equal(fv_xr_input_path_to_string(in, UINT64_MAX, sizeof buf, &n, buf), XR_ERROR_PATH_INVALID);
    fv_xr_input_destroy(&in);
}

static void path_count_exceeded_past_the_limit_but_known_paths_still_resolve(void **st)
{
    (void)st;
    fv_xr_input_desc d = {.max_paths = 4};
    fv_xr_input *in = NULL;
    assert_int_equal(fv_xr_input_create(&d, &in), XR_SUCCESS);
    XrPath first = P(in, "/p0");
    P(in, "/p1");
    P(in, "/p2");
    P(in, "/p3");
    fv_test_log_capture_begin();
    assert_int_equal(s2p(in, "/p4"), XR_ERROR_PATH_COUNT_EXCEEDED);
    fv_assert_log_contains("limit");
    fv_test_log_capture_end();
    assert_int_equal(P(in, "/p0"), first);                      /* not a new atom */
    assert_int_equal(s2p(in, "/user/hand/left"), XR_SUCCESS); /* the runtime's own paths exist already */
    fv_xr_input_destroy(&in);
}

static void null_arguments_are_validation_failures(void **st)
{
    (void)st;
    fv_xr_input *in = make(false);
    XrPath p;
    assert_int_equal(fv_xr_input_string_to_path(in, NULL, &p), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(fv_xr_input_string_to_path(in, "/a", NULL), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(fv_xr_input_string_to_path(NULL, "/a", &p), XR_ERROR_HANDLE_INVALID);
    assert_int_equal(fv_xr_input_create(NULL, NULL), XR_ERROR_VALIDATION_FAILURE);
    fv_xr_input_destroy(&in);
    fv_xr_input_destroy(&in); /* twice is harmless */
    fv_xr_input_destroy(NULL);
}

/* Random strings over an alphabet of allowed and forbidden characters: every accepted string round-trips to itself
   with a stable atom, every refused one is refused as a format error and never half-interned. */
static void random_strings_round_trip_or_are_refused(void **st)
{
    (void)st;
    fv_xr_input *in = make(false);
    static const char alphabet[] = "ab/./-_0A \x01\xff/";
    uint64_t rng = 42;
    int accepted = 0, refused = 0;
    for (int i = 0; i < 20000; i++) {
        char s[24];
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        int n = 1 + (int)((rng >> 33) % (sizeof s - 1));
        for (int k = 0; k < n; k++) {
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            s[k] = alphabet[(rng >> 33) % (sizeof alphabet - 1)];
        }
        if ((rng >> 20) & 1) s[0] = '/';
        s[n] = '\0';
        XrPath p = 99;
        fv_log_set_level("xr_input", FV_LOG_LEVEL_ERROR);
        XrResult r = fv_xr_input_string_to_path(in, s, &p);
        fv_log_set_level("xr_input", FV_LOG_LEVEL_WARN);
        if (r == XR_SUCCESS) {
            accepted++;
            char back[64];
            uint32_t m;
            assert_int_equal(fv_xr_input_path_to_string(in, p, sizeof back, &m, back), XR_SUCCESS);
            assert_string_equal(back, s);
            XrPath again;
            assert_int_equal(fv_xr_input_string_to_path(in, back, &again), XR_SUCCESS);
            assert_int_equal(again, p);
        } else {
            refused++;
            assert_int_equal(r, XR_ERROR_PATH_FORMAT_INVALID);
            assert_int_equal(p, XR_NULL_PATH);
        }
    }
    assert_true(accepted > 100);
    assert_true(refused > 100);
    fv_xr_input_destroy(&in);
}

/* ---- Suggested bindings ---- */

#define make_action xri_test_action
#define make_set xri_test_set
#define suggest xri_test_suggest

/* The component lists of OpenXR 1.0 "Interaction Profile Paths", typed out from the spec text (L: left hand only,
   R: right hand only, else every user path of the profile). */
typedef struct spec_profile {
    const char *path;
    const char *users[2];
    const char *comps[32];
} spec_profile;

static const spec_profile spec[] = {
    {"/interaction_profiles/khr/simple_controller",
     {"/user/hand/left", "/user/hand/right"},
     {"/input/select/click", "/input/menu/click", "/input/grip/pose", "/input/aim/pose", "/output/haptic"}},
    {"/interaction_profiles/google/daydream_controller",
     {"/user/hand/left", "/user/hand/right"},
     {"/input/select/click", "/input/trackpad/x", "/input/trackpad/y", "/input/trackpad/click",
      "/input/trackpad/touch", "/input/grip/pose", "/input/aim/pose"}},
    {"/interaction_profiles/htc/vive_controller",
     {"/user/hand/left", "/user/hand/right"},
     {"/input/system/click", "/input/squeeze/click", "/input/menu/click", "/input/trigger/click",
      "/input/trigger/value", "/input/trackpad/x", "/input/trackpad/y", "/input/trackpad/click",
      "/input/trackpad/touch", "/input/grip/pose", "/input/aim/pose", "/output/haptic"}},
    {"/interaction_profiles/htc/vive_pro",
     {"/user/head", NULL},
     {"/input/system/click", "/input/volume_up/click", "/input/volume_down/click", "/input/mute_mic/click"}},
    {"/interaction_profiles/microsoft/motion_controller",
     {"/user/hand/left", "/user/hand/right"},
     {"/input/menu/click", "/input/squeeze/click", "/input/trigger/value", "/input/thumbstick/x",
      "/input/thumbstick/y", "/input/thumbstick/click", "/input/trackpad/x", "/input/trackpad/y",
      "/input/trackpad/click", "/input/trackpad/touch", "/input/grip/pose", "/input/aim/pose", "/output/haptic"}},
    {"/interaction_profiles/microsoft/xbox_controller",
     {"/user/gamepad", NULL},
     {"/input/menu/click", "/input/view/click", "/input/a/click", "/input/b/click", "/input/x/click",
      "/input/y/click", "/input/dpad_down/click", "/input/dpad_right/click", "/input/dpad_up/click",
      "/input/dpad_left/click", "/input/shoulder_left/click", "/input/shoulder_right/click",
      "/input/thumbstick_left/click", "/input/thumbstick_right/click", "/input/trigger_left/value",
      "/input/trigger_right/value", "/input/thumbstick_left/x", "/input/thumbstick_left/y",
      "/input/thumbstick_right/x", "/input/thumbstick_right/y", "/output/haptic_left", "/output/haptic_right",
      "/output/haptic_left_trigger", "/output/haptic_right_trigger"}},
    {"/interaction_profiles/oculus/go_controller",
     {"/user/hand/left", "/user/hand/right"},
     {"/input/system/click", "/input/trigger/click", "/input/back/click", "/input/trackpad/x", "/input/trackpad/y",
      "/input/trackpad/click", "/input/trackpad/touch", "/input/grip/pose", "/input/aim/pose"}},
    {"/interaction_profiles/oculus/touch_controller",
     {"/user/hand/left", "/user/hand/right"},
     {"L/input/x/click", "L/input/x/touch", "L/input/y/click", "L/input/y/touch", "L/input/menu/click",
      "R/input/a/click", "R/input/a/touch", "R/input/b/click", "R/input/b/touch", "R/input/system/click",
      "/input/squeeze/value", "/input/trigger/value", "/input/trigger/touch", "/input/thumbstick/x",
      "/input/thumbstick/y", "/input/thumbstick/click", "/input/thumbstick/touch", "/input/thumbrest/touch",
      "/input/grip/pose", "/input/aim/pose", "/output/haptic"}},
    {"/interaction_profiles/valve/index_controller",
     {"/user/hand/left", "/user/hand/right"},
     {"/input/system/click", "/input/system/touch", "/input/a/click", "/input/a/touch", "/input/b/click",
      "/input/b/touch", "/input/squeeze/value", "/input/squeeze/force", "/input/trigger/click",
      "/input/trigger/value", "/input/trigger/touch", "/input/thumbstick/x", "/input/thumbstick/y",
      "/input/thumbstick/click", "/input/thumbstick/touch", "/input/trackpad/x", "/input/trackpad/y",
      "/input/trackpad/force", "/input/trackpad/touch", "/input/grip/pose", "/input/aim/pose", "/output/haptic"}},
    {"/interaction_profiles/ext/eye_gaze_interaction", {"/user/eyes_ext", NULL}, {"/input/gaze_ext/pose"}},
};

/* The action type each component suits. */
static XrActionType type_for(const char *comp)
{
    if (strncmp(comp, "/output/", 8) == 0) return XR_ACTION_TYPE_VIBRATION_OUTPUT;
    if (strstr(comp, "/pose")) return XR_ACTION_TYPE_POSE_INPUT;
    if (strstr(comp, "/click") || strstr(comp, "/touch")) return XR_ACTION_TYPE_BOOLEAN_INPUT;
    return XR_ACTION_TYPE_FLOAT_INPUT;
}

static void every_component_of_every_core_profile_is_accepted_on_its_user_paths(void **st)
{
    (void)st;
    fv_xr_input *in = make(true);
    XrActionSet set = make_set(in, "all", 0);
    XrAction by_type[8] = {0};
    by_type[XR_ACTION_TYPE_BOOLEAN_INPUT] = make_action(in, set, "b", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    by_type[XR_ACTION_TYPE_FLOAT_INPUT] = make_action(in, set, "f", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL);
    by_type[XR_ACTION_TYPE_POSE_INPUT] = make_action(in, set, "p", XR_ACTION_TYPE_POSE_INPUT, 0, NULL);
    XrAction haptic = make_action(in, set, "h", XR_ACTION_TYPE_VIBRATION_OUTPUT, 0, NULL);
    int checked = 0;
    for (size_t pi = 0; pi < sizeof spec / sizeof spec[0]; pi++) {
        for (int ui = 0; ui < 2 && spec[pi].users[ui]; ui++) {
            const char *user = spec[pi].users[ui];
            bool left = strcmp(user, "/user/hand/left") == 0;
            for (int ci = 0; ci < 32 && spec[pi].comps[ci]; ci++) {
                const char *c = spec[pi].comps[ci];
                bool only_l = c[0] == 'L', only_r = c[0] == 'R';
                if (only_l || only_r) c++;
                char full[XR_MAX_PATH_LENGTH];
                snprintf(full, sizeof full, "%s%s", user, c);
                XrActionType t = type_for(c);
                XrAction a = t == XR_ACTION_TYPE_VIBRATION_OUTPUT ? haptic : by_type[t];
                const char *paths[1] = {full};
                XrResult want = ((only_l && !left) || (only_r && left)) ? XR_ERROR_PATH_UNSUPPORTED : XR_SUCCESS;
                fv_log_set_level("xr_input", FV_LOG_LEVEL_ERROR);
                XrResult r = suggest(in, spec[pi].path, 1, &a, paths);
                fv_log_set_level("xr_input", FV_LOG_LEVEL_WARN);
                if (r != want) fail_msg("%s: %s gave %d, want %d", spec[pi].path, full, r, want);
                checked++;
            }
        }
    }
    assert_true(checked > 200);
    fv_xr_input_destroy(&in);
}

static void unknown_profiles_and_paths_outside_a_profile_are_path_unsupported(void **st)
{
    (void)st;
    fv_xr_input *in = make(false);
    XrActionSet set = make_set(in, "s", 0);
    XrAction b = make_action(in, set, "b", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    const char *click[] = {"/user/hand/left/input/select/click"};
    fv_test_log_capture_begin();
    assert_int_equal(suggest(in, "/interaction_profiles/acme/wand", 1, &b, click), XR_ERROR_PATH_UNSUPPORTED);
    assert_int_equal(suggest(in, "/interaction_profiles/khr/simple_controller/x", 1, &b, click),
                     XR_ERROR_PATH_UNSUPPORTED);
    assert_int_equal(suggest(in, "/user/hand/left", 1, &b, click), XR_ERROR_PATH_UNSUPPORTED);
    /* the eye-gaze profile exists only with its extension enabled */
    const char *gaze[] = {"/user/eyes_ext/input/gaze_ext/pose"};
    assert_int_equal(suggest(in, "/interaction_profiles/ext/eye_gaze_interaction", 1, &b, gaze),
                     XR_ERROR_PATH_UNSUPPORTED);
    fv_assert_log_contains("XR_EXT_eye_gaze_interaction");
    const char *bad[] = {
        "/user/head/input/select/click",              /* a user path the profile is not valid for */
        "/user/hand/left/input/trigger/value",        /* a component the profile does not have */
        "/user/hand/left/input/select/clicks",        /* a near miss */
        "/user/hand/left",                            /* no input subpath */
        "/user/hand/left/input",                      /* no identifier */
        "/user/hand/leftx/input/select/click",        /* not a top-level path */
        "/user/hand/left/input/select/click/extra",   /* below a component */
        "/user/hand/left/output/haptic/value",        /* below an output */
        "/user/eyes_ext/input/gaze_ext/pose",         /* extension path without the extension */
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        const char *one[1] = {bad[i]};
        XrResult r = suggest(in, "/interaction_profiles/khr/simple_controller", 1, &b, one);
        if (r != XR_ERROR_PATH_UNSUPPORTED) fail_msg("%s gave %d", bad[i], r);
    }
    fv_assert_log_contains("is not an input or output of this profile");
    fv_test_log_capture_end();
    fv_xr_input_destroy(&in);
}

static void a_bad_binding_rejects_the_whole_call(void **st)
{
    (void)st;
    fv_xr_input *in = make(false);
    XrActionSet set = make_set(in, "s", 0);
    XrAction b = make_action(in, set, "b", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    XrAction two[2] = {b, b};
    const char *paths[2] = {"/user/hand/left/input/select/click", "/user/hand/left/input/nope/click"};
    fv_test_log_capture_begin();
    assert_int_equal(suggest(in, "/interaction_profiles/khr/simple_controller", 2, two, paths),
                     XR_ERROR_PATH_UNSUPPORTED);
    fv_assert_log_contains("suggestedBindings[1]");
    fv_test_log_capture_end();
    fv_xr_input_destroy(&in);
}

static void suggest_validates_its_structure_and_handles(void **st)
{
    (void)st;
    fv_xr_input *in = make(false);
    XrActionSet set = make_set(in, "s", 0);
    XrAction b = make_action(in, set, "b", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    fv_test_log_capture_begin();
    assert_int_equal(fv_xr_input_suggest_bindings(in, NULL), XR_ERROR_VALIDATION_FAILURE);
    XrActionSuggestedBinding one = {b, P(in, "/user/hand/left/input/select/click")};
    XrInteractionProfileSuggestedBinding sb = {.type = XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING,
                                               .interactionProfile =
                                                   P(in, "/interaction_profiles/khr/simple_controller"),
                                               .countSuggestedBindings = 0,
                                               .suggestedBindings = &one};
    assert_int_equal(fv_xr_input_suggest_bindings(in, &sb), XR_ERROR_VALIDATION_FAILURE);
    sb.countSuggestedBindings = 1;
    sb.type = XR_TYPE_ACTION_CREATE_INFO;
    assert_int_equal(fv_xr_input_suggest_bindings(in, &sb), XR_ERROR_VALIDATION_FAILURE);
    sb.type = XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING;
    sb.suggestedBindings = NULL;
    assert_int_equal(fv_xr_input_suggest_bindings(in, &sb), XR_ERROR_VALIDATION_FAILURE);
    sb.suggestedBindings = &one;
    assert_int_equal(fv_xr_input_suggest_bindings(in, &sb), XR_SUCCESS);
    one.binding = 987654; /* never handed out */
    assert_int_equal(fv_xr_input_suggest_bindings(in, &sb), XR_ERROR_PATH_INVALID);
    one.binding = P(in, "/user/hand/left/input/select/click");
    sb.interactionProfile = XR_NULL_PATH;
    assert_int_equal(fv_xr_input_suggest_bindings(in, &sb), XR_ERROR_PATH_INVALID);
    sb.interactionProfile = P(in, "/interaction_profiles/khr/simple_controller");
    one.action = (XrAction)(uintptr_t)0xdeadbeefull;
    assert_int_equal(fv_xr_input_suggest_bindings(in, &sb), XR_ERROR_HANDLE_INVALID);
    one.action = b;
    assert_int_equal(fv_xr_input_destroy_action(in, b), XR_SUCCESS);
    assert_int_equal(fv_xr_input_suggest_bindings(in, &sb), XR_ERROR_HANDLE_INVALID);
    fv_test_log_capture_end();
    fv_xr_input_destroy(&in);
}

static void a_binding_of_an_unconvertible_type_is_accepted(void **st)
{
    (void)st;
    /* "If an input value cannot be converted to the type of the action, the value must be ignored" -- not an
       error: the runtime must accept every binding in the allowlist. */
    fv_xr_input *in = make(false);
    XrActionSet set = make_set(in, "s", 0);
    XrAction pose = make_action(in, set, "p", XR_ACTION_TYPE_POSE_INPUT, 0, NULL);
    XrAction vec = make_action(in, set, "v", XR_ACTION_TYPE_VECTOR2F_INPUT, 0, NULL);
    XrAction haptic = make_action(in, set, "h", XR_ACTION_TYPE_VIBRATION_OUTPUT, 0, NULL);
    XrAction acts[3] = {pose, vec, haptic};
    const char *paths[3] = {"/user/hand/left/input/trigger/value", "/user/hand/left/input/trackpad/x",
                            "/user/hand/left/input/grip/pose"};
    assert_int_equal(suggest(in, "/interaction_profiles/htc/vive_controller", 3, acts, paths), XR_SUCCESS);
    fv_xr_input_destroy(&in);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(same_string_gives_same_atom_and_round_trips),
        cmocka_unit_test(well_formed_paths_are_accepted),
        cmocka_unit_test(each_malformed_path_rule_gives_path_format_invalid),
        cmocka_unit_test(path_length_limit_counts_the_terminator),
        cmocka_unit_test(path_to_string_uses_the_two_call_idiom),
        cmocka_unit_test(null_path_and_unknown_atoms_give_path_invalid),
        cmocka_unit_test(path_count_exceeded_past_the_limit_but_known_paths_still_resolve),
        cmocka_unit_test(null_arguments_are_validation_failures),
        cmocka_unit_test(random_strings_round_trip_or_are_refused),
        cmocka_unit_test(every_component_of_every_core_profile_is_accepted_on_its_user_paths),
        cmocka_unit_test(unknown_profiles_and_paths_outside_a_profile_are_path_unsupported),
        cmocka_unit_test(a_bad_binding_rejects_the_whole_call),
        cmocka_unit_test(suggest_validates_its_structure_and_handles),
        cmocka_unit_test(a_binding_of_an_unconvertible_type_is_accepted),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
