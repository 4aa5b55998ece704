/* @brief fv_xr_input: action sets, actions, attachment, xrSyncActions snapshots, state queries, bound sources,
   localized names, haptics, action spaces, interaction-profile selection and eye gaze, and a hello_xr-like sequence.
   Each test is one rule of the OpenXR 1.0 spec ("Input and Haptics"), named by its behaviour. */
#include "fv_test.h"
#include "fv_xr_input.h"
#include "test_xr_input_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define LEFT "/user/hand/left"
#define RIGHT "/user/hand/right"
#define SIMPLE "/interaction_profiles/khr/simple_controller"
#define TOUCH "/interaction_profiles/oculus/touch_controller"
#define INDEX "/interaction_profiles/valve/index_controller"
#define VIVE "/interaction_profiles/htc/vive_controller"
#define WMR "/interaction_profiles/microsoft/motion_controller"
#define GAZE "/interaction_profiles/ext/eye_gaze_interaction"

typedef struct fx {
    fv_xr_input *in;
    fv_xr_input_session *s;
} fx;

static fx make(bool gaze)
{
    fx f = {0};
    fv_xr_input_desc d = {.eye_gaze_ext_enabled = gaze};
    assert_int_equal(fv_xr_input_create(&d, &f.in), XR_SUCCESS);
    assert_int_equal(fv_xr_input_session_create(f.in, &f.s), XR_SUCCESS);
    return f;
}

static void done(fx *f)
{
    fv_xr_input_session_destroy(&f->s);
    assert_null(f->s);
    fv_xr_input_destroy(&f->in);
}

#define P xri_test_path
#define try_set xri_test_try_set
#define make_set xri_test_set
#define try_action xri_test_try_action
#define make_action xri_test_action
#define suggest xri_test_suggest
#define suggest_one xri_test_suggest_one

static XrResult attach(fx *f, uint32_t n, const XrActionSet *sets)
{
    XrSessionActionSetsAttachInfo ai = {.type = XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO, .countActionSets = n,
                                        .actionSets = sets};
    return fv_xr_input_attach(f->s, &ai);
}

/* A device state: both hands present (as khr/simple_controller unless told), values from a list. */
typedef struct dev_state {
    fv_xr_input_devices d;
    fv_xr_input_value v[16];
} dev_state;

static dev_state hands(XrTime t)
{
    dev_state ds;
    memset(&ds, 0, sizeof ds);
    ds.d.hands_present[0] = ds.d.hands_present[1] = true;
    ds.d.time = t;
    ds.d.values = ds.v;
    return ds;
}

static void set_value(dev_state *ds, const char *path, float v, XrTime changed)
{
    for (uint32_t i = 0; i < ds->d.value_count; i++) {
        if (strcmp(ds->v[i].path, path) == 0) {
            ds->v[i].value = v;
            ds->v[i].changed_time = changed;
            return;
        }
    }
    assert_true(ds->d.value_count < 16);
    ds->v[ds->d.value_count++] = (fv_xr_input_value){path, v, changed};
    ds->d.values = ds->v;
}

static XrResult sync_sets(fx *f, uint32_t n, const XrActiveActionSet *as, const dev_state *ds)
{
    XrActionsSyncInfo si = {.type = XR_TYPE_ACTIONS_SYNC_INFO, .countActiveActionSets = n, .activeActionSets = as};
    return fv_xr_input_sync(f->s, &si, ds ? &ds->d : NULL);
}

static XrResult sync1(fx *f, XrActionSet set, const dev_state *ds)
{
    XrActiveActionSet as = {set, XR_NULL_PATH};
    return sync_sets(f, 1, &as, ds);
}

static XrActionStateBoolean get_bool(fx *f, XrAction a, XrPath sub)
{
    XrActionStateGetInfo g = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = a, .subactionPath = sub};
    XrActionStateBoolean st = {.type = XR_TYPE_ACTION_STATE_BOOLEAN};
    assert_int_equal(fv_xr_input_get_boolean(f->s, &g, &st), XR_SUCCESS);
    return st;
}

static XrActionStateFloat get_float(fx *f, XrAction a, XrPath sub)
{
    XrActionStateGetInfo g = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = a, .subactionPath = sub};
    XrActionStateFloat st = {.type = XR_TYPE_ACTION_STATE_FLOAT};
    assert_int_equal(fv_xr_input_get_float(f->s, &g, &st), XR_SUCCESS);
    assert_true(isfinite(st.currentState));
    return st;
}

static XrActionStateVector2f get_vec(fx *f, XrAction a, XrPath sub)
{
    XrActionStateGetInfo g = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = a, .subactionPath = sub};
    XrActionStateVector2f st = {.type = XR_TYPE_ACTION_STATE_VECTOR2F};
    assert_int_equal(fv_xr_input_get_vector2f(f->s, &g, &st), XR_SUCCESS);
    assert_true(isfinite(st.currentState.x) && isfinite(st.currentState.y));
    return st;
}

static XrResult get_float_r(fx *f, XrAction a, XrPath sub)
{
    XrActionStateGetInfo g = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = a, .subactionPath = sub};
    XrActionStateFloat st = {.type = XR_TYPE_ACTION_STATE_FLOAT};
    return fv_xr_input_get_float(f->s, &g, &st);
}

static XrPath current_profile(fx *f, const char *user)
{
    XrInteractionProfileState st = {.type = XR_TYPE_INTERACTION_PROFILE_STATE};
    assert_int_equal(fv_xr_input_get_current_interaction_profile(f->s, P(f->in, user), &st), XR_SUCCESS);
    return st.interactionProfile;
}

static uint32_t bound_sources(fx *f, XrAction a, XrPath *out, uint32_t cap)
{
    XrBoundSourcesForActionEnumerateInfo e = {.type = XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO, .action = a};
    uint32_t n = 0;
    assert_int_equal(fv_xr_input_enumerate_bound_sources(f->s, &e, 0, &n, NULL), XR_SUCCESS);
    if (cap) {
        assert_true(n <= cap);
        uint32_t m = 0;
        assert_int_equal(fv_xr_input_enumerate_bound_sources(f->s, &e, cap, &m, out), XR_SUCCESS);
        assert_int_equal(m, n);
    }
    return n;
}

static void quiet(void) { fv_log_set_level("xr_input", FV_LOG_LEVEL_ERROR); }
static void loud(void) { fv_log_set_level("xr_input", FV_LOG_LEVEL_WARN); }

/* ---- Action sets and actions: names ---- */

static void action_set_name_rules_give_their_errors(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s;
    fv_test_log_capture_begin();
    assert_int_equal(try_set(f.in, "", "Empty", 0, &s), XR_ERROR_NAME_INVALID);
    assert_int_equal(try_set(f.in, "ok", "", 0, &s), XR_ERROR_LOCALIZED_NAME_INVALID);
    assert_int_equal(try_set(f.in, "Bad Name", "B", 0, &s), XR_ERROR_PATH_FORMAT_INVALID);
    assert_int_equal(try_set(f.in, "a/b", "B", 0, &s), XR_ERROR_PATH_FORMAT_INVALID);
    assert_int_equal(try_set(f.in, "..", "B", 0, &s), XR_ERROR_PATH_FORMAT_INVALID);
    assert_int_equal(try_set(f.in, "caf\xc3\xa9", "B", 0, &s), XR_ERROR_PATH_FORMAT_INVALID);
    fv_assert_log_contains("xrCreateActionSet");
    fv_assert_log_contains("Bad Name");
    /* the localized name is UTF-8 for people: accents are fine, broken UTF-8 is not */
    assert_int_equal(try_set(f.in, "gameplay", "Spielmodus \xe2\x80\x93 \xc3\x9c", 0, &s), XR_SUCCESS);
    assert_int_equal(try_set(f.in, "x1", "bad \xc3", 0, &s), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(try_set(f.in, "x2", "overlong \xc0\xaf", 0, &s), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(try_set(f.in, "x3", "surrogate \xed\xa0\x80", 0, &s), XR_ERROR_VALIDATION_FAILURE);
    /* a name that fills its array without a terminator */
    XrActionSetCreateInfo si = {.type = XR_TYPE_ACTION_SET_CREATE_INFO};
    memset(si.actionSetName, 'a', sizeof si.actionSetName);
    strcpy(si.localizedActionSetName, "Full");
    assert_int_equal(fv_xr_input_create_action_set(f.in, &si, &s), XR_ERROR_VALIDATION_FAILURE);
    memset(si.localizedActionSetName, 'b', sizeof si.localizedActionSetName);
    si.actionSetName[0] = '\0';
    strcpy(si.actionSetName, "full");
    assert_int_equal(fv_xr_input_create_action_set(f.in, &si, &s), XR_ERROR_VALIDATION_FAILURE);
    /* the longest names that fit */
    memset(si.actionSetName, 'c', sizeof si.actionSetName - 1);
    si.actionSetName[sizeof si.actionSetName - 1] = '\0';
    memset(si.localizedActionSetName, 'd', sizeof si.localizedActionSetName - 1);
    si.localizedActionSetName[sizeof si.localizedActionSetName - 1] = '\0';
    assert_int_equal(fv_xr_input_create_action_set(f.in, &si, &s), XR_SUCCESS);
    /* structure checks */
    si.type = XR_TYPE_ACTION_CREATE_INFO;
    assert_int_equal(fv_xr_input_create_action_set(f.in, &si, &s), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(fv_xr_input_create_action_set(f.in, NULL, &s), XR_ERROR_VALIDATION_FAILURE);
    si.type = XR_TYPE_ACTION_SET_CREATE_INFO;
    assert_int_equal(fv_xr_input_create_action_set(f.in, &si, NULL), XR_ERROR_VALIDATION_FAILURE);
    fv_test_log_capture_end();
    done(&f);
}

static void duplicate_action_set_names_are_refused_until_the_other_is_destroyed(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet a, b;
    quiet();
    assert_int_equal(try_set(f.in, "menu", "Menu", 0, &a), XR_SUCCESS);
    assert_int_equal(try_set(f.in, "menu", "Other", 0, &b), XR_ERROR_NAME_DUPLICATED);
    assert_int_equal(try_set(f.in, "other", "Menu", 0, &b), XR_ERROR_LOCALIZED_NAME_DUPLICATED);
    assert_int_equal(fv_xr_input_destroy_action_set(f.in, a), XR_SUCCESS);
    assert_int_equal(try_set(f.in, "menu", "Menu", 0, &b), XR_SUCCESS);
    assert_int_not_equal((uintptr_t)a, (uintptr_t)b); /* handles are never reused */
    loud();
    done(&f);
}

static void action_names_follow_the_same_rules_within_their_set(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s1 = make_set(f.in, "one", 0), s2 = make_set(f.in, "two", 0);
    XrAction a, b;
    quiet();
    assert_int_equal(try_action(f.in, s1, "", "E", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL, &a), XR_ERROR_NAME_INVALID);
    assert_int_equal(try_action(f.in, s1, "e", "", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL, &a),
                     XR_ERROR_LOCALIZED_NAME_INVALID);
    assert_int_equal(try_action(f.in, s1, "Jump!", "J", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL, &a),
                     XR_ERROR_PATH_FORMAT_INVALID);
    assert_int_equal(try_action(f.in, s1, "jump", "Jump", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL, &a), XR_SUCCESS);
    assert_int_equal(try_action(f.in, s1, "jump", "Jump 2", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL, &b),
                     XR_ERROR_NAME_DUPLICATED);
    assert_int_equal(try_action(f.in, s1, "jump2", "Jump", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL, &b),
                     XR_ERROR_LOCALIZED_NAME_DUPLICATED);
    /* names are unique per action set, not per instance */
    assert_int_equal(try_action(f.in, s2, "jump", "Jump", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL, &b), XR_SUCCESS);
    /* a destroyed action frees its names */
    assert_int_equal(fv_xr_input_destroy_action(f.in, a), XR_SUCCESS);
    assert_int_equal(try_action(f.in, s1, "jump", "Jump", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL, &a), XR_SUCCESS);
    /* an action type that is not an XrActionType */
    assert_int_equal(try_action(f.in, s1, "odd", "Odd", (XrActionType)77, 0, NULL, &b), XR_ERROR_VALIDATION_FAILURE);
    loud();
    done(&f);
}

static void subaction_paths_must_be_distinct_top_level_user_paths(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction a;
    XrPath ok[4] = {P(f.in, "/user/head"), P(f.in, LEFT), P(f.in, RIGHT), P(f.in, "/user/gamepad")};
    assert_int_equal(try_action(f.in, s, "all", "All", XR_ACTION_TYPE_BOOLEAN_INPUT, 4, ok, &a), XR_SUCCESS);
    fv_test_log_capture_begin();
    const char *bad[] = {"/user/treadmill", "/user", "/user/hand", LEFT "/input/select/click", "/user/eyes_ext",
                         "/interaction_profiles/khr/simple_controller"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        XrPath p = P(f.in, bad[i]);
        char name[16];
        snprintf(name, sizeof name, "b%zu", i);
        XrResult r = try_action(f.in, s, name, name, XR_ACTION_TYPE_BOOLEAN_INPUT, 1, &p, &a);
        if (r != XR_ERROR_PATH_UNSUPPORTED) fail_msg("%s gave %d", bad[i], r);
    }
    XrPath dup[2] = {P(f.in, LEFT), P(f.in, LEFT)};
    assert_int_equal(try_action(f.in, s, "dup", "Dup", XR_ACTION_TYPE_BOOLEAN_INPUT, 2, dup, &a),
                     XR_ERROR_PATH_UNSUPPORTED);
    fv_assert_log_contains("appears twice");
    XrPath never = 424242;
    assert_int_equal(try_action(f.in, s, "inv", "Inv", XR_ACTION_TYPE_BOOLEAN_INPUT, 1, &never, &a),
                     XR_ERROR_PATH_INVALID);
    assert_int_equal(try_action(f.in, s, "nul", "Nul", XR_ACTION_TYPE_BOOLEAN_INPUT, 2, NULL, &a),
                     XR_ERROR_VALIDATION_FAILURE);
    fv_test_log_capture_end();
    done(&f);
    /* with XR_EXT_eye_gaze_interaction, /user/eyes_ext is a subaction path too */
    f = make(true);
    s = make_set(f.in, "s", 0);
    XrPath eyes = P(f.in, "/user/eyes_ext");
    assert_int_equal(try_action(f.in, s, "gaze", "Gaze", XR_ACTION_TYPE_POSE_INPUT, 1, &eyes, &a), XR_SUCCESS);
    done(&f);
}

/* ---- Handles ---- */

static void stale_foreign_and_garbage_handles_are_handle_invalid(void **st)
{
    (void)st;
    fx f = make(false);
    fx g = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    XrActionSet gs = make_set(g.in, "s", 0);
    XrAction ga = make_action(g.in, gs, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    XrAction b;
    quiet();
    /* another instance's handles */
    assert_int_equal(try_action(f.in, gs, "x", "X", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL, &b), XR_ERROR_HANDLE_INVALID);
    assert_int_equal(fv_xr_input_destroy_action(f.in, ga), XR_ERROR_HANDLE_INVALID);
    assert_int_equal(fv_xr_input_destroy_action_set(f.in, gs), XR_ERROR_HANDLE_INVALID);
    /* garbage and null */
    assert_int_equal(fv_xr_input_destroy_action(f.in, XR_NULL_HANDLE), XR_ERROR_HANDLE_INVALID);
    assert_int_equal(fv_xr_input_destroy_action(f.in, (XrAction)(uintptr_t)0x123456789abcull), XR_ERROR_HANDLE_INVALID);
    assert_int_equal(fv_xr_input_destroy_action_set(f.in, (XrActionSet)(uintptr_t)a), XR_ERROR_HANDLE_INVALID);
    /* destroyed handles, and destroying twice */
    assert_int_equal(fv_xr_input_destroy_action(f.in, a), XR_SUCCESS);
    assert_int_equal(fv_xr_input_destroy_action(f.in, a), XR_ERROR_HANDLE_INVALID);
    assert_int_equal(fv_xr_input_destroy_action_set(f.in, s), XR_SUCCESS);
    assert_int_equal(fv_xr_input_destroy_action_set(f.in, s), XR_ERROR_HANDLE_INVALID);
    assert_int_equal(try_action(f.in, s, "y", "Y", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL, &b), XR_ERROR_HANDLE_INVALID);
    loud();
    done(&g);
    done(&f);
}

static void destroying_a_set_destroys_its_action_handles(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    assert_int_equal(fv_xr_input_destroy_action_set(f.in, s), XR_SUCCESS);
    quiet();
    assert_int_equal(fv_xr_input_destroy_action(f.in, a), XR_ERROR_HANDLE_INVALID);
    loud();
    done(&f);
}

/* ---- Attachment ---- */

static void attach_is_once_per_session_and_freezes_the_sets(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0), other = make_set(f.in, "other", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    XrAction o = make_action(f.in, other, "o", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    fv_test_log_capture_begin();
    assert_int_equal(attach(&f, 0, &s), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(attach(&f, 1, NULL), XR_ERROR_VALIDATION_FAILURE);
    assert_false(fv_xr_input_is_attached(f.s));
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    assert_true(fv_xr_input_is_attached(f.s));
    assert_int_equal(attach(&f, 1, &other), XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
    /* an attached set is immutable: no new action, no new binding (in any session) */
    XrAction b;
    assert_int_equal(try_action(f.in, s, "b", "B", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL, &b),
                     XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
    const char *click[1] = {LEFT "/input/select/click"};
    assert_int_equal(suggest(f.in, SIMPLE, 1, &a, click), XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
    fv_assert_log_contains("attached");
    /* the unattached set still changes */
    assert_int_equal(try_action(f.in, other, "b", "B", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL, &b), XR_SUCCESS);
    assert_int_equal(suggest(f.in, SIMPLE, 1, &o, click), XR_SUCCESS);
    fv_test_log_capture_end();
    done(&f);
}

static void attach_refuses_a_destroyed_set(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    assert_int_equal(fv_xr_input_destroy_action_set(f.in, s), XR_SUCCESS);
    quiet();
    assert_int_equal(attach(&f, 1, &s), XR_ERROR_HANDLE_INVALID);
    loud();
    assert_false(fv_xr_input_is_attached(f.s));
    done(&f);
}

static void unattached_actions_give_actionset_not_attached(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0), other = make_set(f.in, "other", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL);
    XrAction o = make_action(f.in, other, "o", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL);
    quiet();
    /* before any attach */
    assert_int_equal(get_float_r(&f, a, XR_NULL_PATH), XR_ERROR_ACTIONSET_NOT_ATTACHED);
    XrInteractionProfileState ps = {.type = XR_TYPE_INTERACTION_PROFILE_STATE};
    assert_int_equal(fv_xr_input_get_current_interaction_profile(f.s, P(f.in, LEFT), &ps),
                     XR_ERROR_ACTIONSET_NOT_ATTACHED);
    XrInputSourceLocalizedNameGetInfo ln = {.type = XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO,
                                            .sourcePath = P(f.in, LEFT "/input/select/click"),
                                            .whichComponents = XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT};
    uint32_t n;
    assert_int_equal(fv_xr_input_get_localized_name(f.s, &ln, 0, &n, NULL), XR_ERROR_ACTIONSET_NOT_ATTACHED);
    assert_int_equal(sync1(&f, s, NULL), XR_ERROR_ACTIONSET_NOT_ATTACHED);
    /* after attaching the other set */
    assert_int_equal(attach(&f, 1, &other), XR_SUCCESS);
    assert_int_equal(get_float_r(&f, a, XR_NULL_PATH), XR_ERROR_ACTIONSET_NOT_ATTACHED);
    assert_int_equal(get_float_r(&f, o, XR_NULL_PATH), XR_SUCCESS);
    assert_int_equal(sync1(&f, s, NULL), XR_ERROR_ACTIONSET_NOT_ATTACHED);
    XrBoundSourcesForActionEnumerateInfo e = {.type = XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO, .action = a};
    assert_int_equal(fv_xr_input_enumerate_bound_sources(f.s, &e, 0, &n, NULL), XR_ERROR_ACTIONSET_NOT_ATTACHED);
    XrHapticActionInfo h = {.type = XR_TYPE_HAPTIC_ACTION_INFO, .action = a};
    assert_int_equal(fv_xr_input_stop_haptic(f.s, &h), XR_ERROR_ACTIONSET_NOT_ATTACHED);
    loud();
    done(&f);
}

/* ---- Types ---- */

static void queries_of_the_wrong_type_give_action_type_mismatch(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction b = make_action(f.in, s, "b", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    XrAction h = make_action(f.in, s, "h", XR_ACTION_TYPE_VIBRATION_OUTPUT, 0, NULL);
    XrAction p = make_action(f.in, s, "p", XR_ACTION_TYPE_POSE_INPUT, 0, NULL);
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    quiet();
    XrActionStateGetInfo g = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = b};
    XrActionStateFloat sf = {.type = XR_TYPE_ACTION_STATE_FLOAT};
    XrActionStateVector2f sv = {.type = XR_TYPE_ACTION_STATE_VECTOR2F};
    XrActionStatePose sp = {.type = XR_TYPE_ACTION_STATE_POSE};
    XrActionStateBoolean sb = {.type = XR_TYPE_ACTION_STATE_BOOLEAN};
    assert_int_equal(fv_xr_input_get_float(f.s, &g, &sf), XR_ERROR_ACTION_TYPE_MISMATCH);
    assert_int_equal(fv_xr_input_get_vector2f(f.s, &g, &sv), XR_ERROR_ACTION_TYPE_MISMATCH);
    assert_int_equal(fv_xr_input_get_pose(f.s, &g, &sp), XR_ERROR_ACTION_TYPE_MISMATCH);
    g.action = h;
    assert_int_equal(fv_xr_input_get_boolean(f.s, &g, &sb), XR_ERROR_ACTION_TYPE_MISMATCH);
    XrHapticActionInfo hi = {.type = XR_TYPE_HAPTIC_ACTION_INFO, .action = b};
    XrHapticVibration vib = {.type = XR_TYPE_HAPTIC_VIBRATION, .duration = XR_MIN_HAPTIC_DURATION,
                             .frequency = XR_FREQUENCY_UNSPECIFIED, .amplitude = 0.5f};
    assert_int_equal(fv_xr_input_apply_haptic(f.s, &hi, (const XrHapticBaseHeader *)&vib), XR_ERROR_ACTION_TYPE_MISMATCH);
    assert_int_equal(fv_xr_input_stop_haptic(f.s, &hi), XR_ERROR_ACTION_TYPE_MISMATCH);
    XrActionSpaceCreateInfo asi = {.type = XR_TYPE_ACTION_SPACE_CREATE_INFO, .action = b,
                                   .poseInActionSpace = {.orientation = {0, 0, 0, 1}}};
    assert_int_equal(fv_xr_input_check_action_space(f.in, &asi), XR_ERROR_ACTION_TYPE_MISMATCH);
    asi.action = p;
    assert_int_equal(fv_xr_input_check_action_space(f.in, &asi), XR_SUCCESS);
    /* and the state structure must be the one for the call */
    g.action = b;
    sb.type = XR_TYPE_ACTION_STATE_FLOAT;
    assert_int_equal(fv_xr_input_get_boolean(f.s, &g, &sb), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(fv_xr_input_get_boolean(f.s, &g, NULL), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(fv_xr_input_get_boolean(f.s, NULL, &sb), XR_ERROR_VALIDATION_FAILURE);
    loud();
    done(&f);
}

static void subaction_path_queries_must_name_a_declared_path(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrPath left = P(f.in, LEFT), right = P(f.in, RIGHT);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_FLOAT_INPUT, 1, &left);
    XrAction none = make_action(f.in, s, "none", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL);
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    quiet();
    assert_int_equal(get_float_r(&f, a, left), XR_SUCCESS);
    assert_int_equal(get_float_r(&f, a, XR_NULL_PATH), XR_SUCCESS);
    assert_int_equal(get_float_r(&f, a, right), XR_ERROR_PATH_UNSUPPORTED);
    assert_int_equal(get_float_r(&f, none, left), XR_ERROR_PATH_UNSUPPORTED);
    assert_int_equal(get_float_r(&f, a, 999999), XR_ERROR_PATH_INVALID);
    loud();
    done(&f);
}

/* ---- Sync ---- */

static void sync_validates_active_sets_and_subaction_paths(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrPath left = P(f.in, LEFT), right = P(f.in, RIGHT);
    make_action(f.in, s, "a", XR_ACTION_TYPE_FLOAT_INPUT, 1, &left);
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    fv_test_log_capture_begin();
    XrActiveActionSet as = {s, left};
    assert_int_equal(sync_sets(&f, 1, &as, NULL), XR_SUCCESS);
    as.subactionPath = right; /* declared by no action of the set */
    assert_int_equal(sync_sets(&f, 1, &as, NULL), XR_ERROR_PATH_UNSUPPORTED);
    fv_assert_log_contains("declared by no action");
    as.subactionPath = 31337;
    assert_int_equal(sync_sets(&f, 1, &as, NULL), XR_ERROR_PATH_INVALID);
    as.subactionPath = XR_NULL_PATH;
    as.actionSet = XR_NULL_HANDLE;
    assert_int_equal(sync_sets(&f, 1, &as, NULL), XR_ERROR_HANDLE_INVALID);
    assert_int_equal(sync_sets(&f, 1, NULL, NULL), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(sync_sets(&f, 0, NULL, NULL), XR_SUCCESS); /* no active set: legal, everything inactive */
    assert_int_equal(fv_xr_input_sync(f.s, NULL, NULL), XR_ERROR_VALIDATION_FAILURE);
    fv_test_log_capture_end();
    done(&f);
}

static void states_change_only_at_sync(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL);
    suggest_one(f.in, VIVE, a, LEFT "/input/trigger/value");
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(100);
    ds.d.hand_profiles[0] = VIVE;
    set_value(&ds, LEFT "/input/trigger/value", 0.25f, 0);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    XrActionStateFloat a1 = get_float(&f, a, XR_NULL_PATH);
    assert_true(a1.isActive);
    assert_float_equal(a1.currentState, 0.25f, 0);
    /* the device moves; the snapshot does not until the next sync */
    set_value(&ds, LEFT "/input/trigger/value", 0.75f, 0);
    XrActionStateFloat a2 = get_float(&f, a, XR_NULL_PATH);
    assert_float_equal(a2.currentState, 0.25f, 0);
    assert_int_equal(a2.lastChangeTime, a1.lastChangeTime);
    ds.d.time = 200;
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_float_equal(get_float(&f, a, XR_NULL_PATH).currentState, 0.75f, 0);
    done(&f);
}

static void changed_since_last_sync_and_last_change_time_follow_the_spec(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    suggest_one(f.in, SIMPLE, a, LEFT "/input/select/click");
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(1000);
    set_value(&ds, LEFT "/input/select/click", 1.0f, 0);
    /* first sync: no previous sync, so not "changed" */
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    XrActionStateBoolean b = get_bool(&f, a, XR_NULL_PATH);
    assert_true(b.isActive && b.currentState);
    assert_false(b.changedSinceLastSync);
    assert_int_equal(b.lastChangeTime, 1000);
    /* unchanged: not changed, the time stays */
    ds.d.time = 2000;
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    b = get_bool(&f, a, XR_NULL_PATH);
    assert_false(b.changedSinceLastSync);
    assert_int_equal(b.lastChangeTime, 1000);
    /* a falling edge, timed by the device when it knows */
    ds.d.time = 3000;
    set_value(&ds, LEFT "/input/select/click", 0.0f, 2900);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    b = get_bool(&f, a, XR_NULL_PATH);
    assert_true(b.changedSinceLastSync);
    assert_false(b.currentState);
    assert_int_equal(b.lastChangeTime, 2900);
    /* the action leaves the active sets: inactive, zero state, no change, time 0 */
    assert_int_equal(sync_sets(&f, 0, NULL, &ds), XR_SUCCESS);
    b = get_bool(&f, a, XR_NULL_PATH);
    assert_false(b.isActive || b.currentState || b.changedSinceLastSync);
    assert_int_equal(b.lastChangeTime, 0);
    /* back, with a new value: not "changed", as it was inactive at the previous sync */
    set_value(&ds, LEFT "/input/select/click", 1.0f, 0);
    ds.d.time = 4000;
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    b = get_bool(&f, a, XR_NULL_PATH);
    assert_true(b.isActive && b.currentState);
    assert_false(b.changedSinceLastSync);
    assert_int_equal(b.lastChangeTime, 4000);
    done(&f);
}

static void is_active_needs_a_binding_and_a_present_device(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction bound = make_action(f.in, s, "bound", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    XrAction unbound = make_action(f.in, s, "unbound", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    suggest_one(f.in, SIMPLE, bound, RIGHT "/input/menu/click");
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(5);
    ds.d.hands_present[1] = false;
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_false(get_bool(&f, bound, XR_NULL_PATH).isActive); /* the right hand is absent */
    ds.d.hands_present[1] = true;
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_true(get_bool(&f, bound, XR_NULL_PATH).isActive);
    assert_false(get_bool(&f, bound, XR_NULL_PATH).currentState); /* not reported: rest state */
    assert_false(get_bool(&f, unbound, XR_NULL_PATH).isActive);
    done(&f);
}

static void subaction_filters_select_the_devices_read(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrPath lr[2] = {P(f.in, LEFT), P(f.in, RIGHT)};
    XrAction grab = make_action(f.in, s, "grab", XR_ACTION_TYPE_FLOAT_INPUT, 2, lr);
    XrAction acts[2] = {grab, grab};
    const char *paths[2] = {LEFT "/input/squeeze/value", RIGHT "/input/squeeze/value"};
    assert_int_equal(suggest(f.in, TOUCH, 2, acts, paths), XR_SUCCESS);
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(10);
    ds.d.hand_profiles[0] = ds.d.hand_profiles[1] = TOUCH;
    set_value(&ds, LEFT "/input/squeeze/value", 0.2f, 0);
    set_value(&ds, RIGHT "/input/squeeze/value", 0.9f, 0);
    /* both hands */
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_float_equal(get_float(&f, grab, lr[0]).currentState, 0.2f, 0);
    assert_float_equal(get_float(&f, grab, lr[1]).currentState, 0.9f, 0);
    assert_float_equal(get_float(&f, grab, XR_NULL_PATH).currentState, 0.9f, 0);
    /* only the left hand's subaction path is active */
    XrActiveActionSet as = {s, lr[0]};
    assert_int_equal(sync_sets(&f, 1, &as, &ds), XR_SUCCESS);
    assert_true(get_float(&f, grab, lr[0]).isActive);
    assert_false(get_float(&f, grab, lr[1]).isActive);
    assert_float_equal(get_float(&f, grab, lr[1]).currentState, 0.0f, 0);
    assert_float_equal(get_float(&f, grab, XR_NULL_PATH).currentState, 0.2f, 0); /* only what is active */
    done(&f);
}

static void bindings_outside_the_declared_subaction_paths_are_ignored(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrPath left = P(f.in, LEFT);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 1, &left);
    XrAction acts[2] = {a, a};
    const char *paths[2] = {LEFT "/input/select/click", RIGHT "/input/select/click"};
    assert_int_equal(suggest(f.in, SIMPLE, 2, acts, paths), XR_SUCCESS);
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(1);
    set_value(&ds, RIGHT "/input/select/click", 1.0f, 0);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    XrActionStateBoolean b = get_bool(&f, a, XR_NULL_PATH);
    assert_true(b.isActive);      /* the left hand feeds it */
    assert_false(b.currentState); /* the right hand's press is not this action's */
    XrPath src[2];
    assert_int_equal(bound_sources(&f, a, src, 2), 1);
    assert_int_equal(src[0], P(f.in, LEFT "/input/select/click"));
    done(&f);
}

static void multiple_bindings_combine_by_or_largest_and_longest(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction b = make_action(f.in, s, "b", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    XrAction fl = make_action(f.in, s, "f", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL);
    XrAction v = make_action(f.in, s, "v", XR_ACTION_TYPE_VECTOR2F_INPUT, 0, NULL);
    XrAction acts[6] = {b, b, fl, fl, v, v};
    const char *paths[6] = {LEFT "/input/a/click",     LEFT "/input/b/click",     LEFT "/input/trigger/value",
                            LEFT "/input/thumbstick/x", LEFT "/input/thumbstick", LEFT "/input/trackpad"};
    assert_int_equal(suggest(f.in, INDEX, 6, acts, paths), XR_SUCCESS);
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(1);
    ds.d.hand_profiles[0] = INDEX;
    set_value(&ds, LEFT "/input/a/click", 0.0f, 0);
    set_value(&ds, LEFT "/input/b/click", 1.0f, 0);
    set_value(&ds, LEFT "/input/trigger/value", 0.5f, 0);
    set_value(&ds, LEFT "/input/thumbstick/x", -0.8f, 0);
    set_value(&ds, LEFT "/input/thumbstick/y", 0.0f, 0);
    set_value(&ds, LEFT "/input/trackpad/x", 0.5f, 0);
    set_value(&ds, LEFT "/input/trackpad/y", 0.5f, 0);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_true(get_bool(&f, b, XR_NULL_PATH).currentState);                   /* OR */
    assert_float_equal(get_float(&f, fl, XR_NULL_PATH).currentState, -0.8f, 0); /* largest |value| */
    XrActionStateVector2f vs = get_vec(&f, v, XR_NULL_PATH);                   /* longest: 0.8 > 0.707 */
    assert_float_equal(vs.currentState.x, -0.8f, 0);
    assert_float_equal(vs.currentState.y, 0.0f, 0);
    set_value(&ds, LEFT "/input/trackpad/x", 0.7f, 0);
    set_value(&ds, LEFT "/input/trackpad/y", -0.7f, 0);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    vs = get_vec(&f, v, XR_NULL_PATH); /* now the trackpad's 0.99 */
    assert_float_equal(vs.currentState.x, 0.7f, 0);
    assert_float_equal(vs.currentState.y, -0.7f, 0);
    assert_true(vs.changedSinceLastSync);
    done(&f);
}

static void boolean_from_a_scalar_uses_a_threshold_with_hysteresis(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction b = make_action(f.in, s, "b", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    /* /input/squeeze on Touch has no /click: a boolean reads /value through the threshold */
    suggest_one(f.in, TOUCH, b, LEFT "/input/squeeze");
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(1);
    ds.d.hand_profiles[0] = TOUCH;
    const float seq[] = {0.45f, 0.6f, 0.45f, 0.3f, 0.45f};
    const bool want[] = {false, true, true, false, false};
    for (int i = 0; i < 5; i++) {
        set_value(&ds, LEFT "/input/squeeze/value", seq[i], 0);
        assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
        if (get_bool(&f, b, XR_NULL_PATH).currentState != want[i]) fail_msg("step %d (%.2f)", i, seq[i]);
    }
    done(&f);
}

static void implicit_components_follow_the_suggested_binding_rules(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction b = make_action(f.in, s, "b", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    XrAction fl = make_action(f.in, s, "f", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL);
    XrAction v = make_action(f.in, s, "v", XR_ACTION_TYPE_VECTOR2F_INPUT, 0, NULL);
    XrAction p = make_action(f.in, s, "p", XR_ACTION_TYPE_POSE_INPUT, 0, NULL);
    XrAction nope = make_action(f.in, s, "nope", XR_ACTION_TYPE_POSE_INPUT, 0, NULL);
    XrAction acts[5] = {b, fl, v, p, nope};
    const char *paths[5] = {LEFT "/input/trigger", LEFT "/input/trigger", LEFT "/input/trackpad", LEFT "/input/grip",
                            LEFT "/input/trigger/value"};
    assert_int_equal(suggest(f.in, VIVE, 5, acts, paths), XR_SUCCESS);
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(1);
    ds.d.hand_profiles[0] = VIVE;
    set_value(&ds, LEFT "/input/trigger/click", 1.0f, 0);
    set_value(&ds, LEFT "/input/trigger/value", 0.3f, 0);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    XrPath src[4];
    /* boolean on a parent: /click when it exists */
    assert_int_equal(bound_sources(&f, b, src, 4), 1);
    assert_int_equal(src[0], P(f.in, LEFT "/input/trigger/click"));
    assert_true(get_bool(&f, b, XR_NULL_PATH).currentState);
    /* float on a parent: /value */
    assert_int_equal(bound_sources(&f, fl, src, 4), 1);
    assert_int_equal(src[0], P(f.in, LEFT "/input/trigger/value"));
    assert_float_equal(get_float(&f, fl, XR_NULL_PATH).currentState, 0.3f, 0);
    /* vector2f: the parent of /x and /y */
    assert_int_equal(bound_sources(&f, v, src, 4), 1);
    assert_int_equal(src[0], P(f.in, LEFT "/input/trackpad"));
    /* pose on a parent: /pose */
    assert_int_equal(bound_sources(&f, p, src, 4), 1);
    assert_int_equal(src[0], P(f.in, LEFT "/input/grip/pose"));
    /* a pose bound to a scalar is accepted and ignored: no source, inactive */
    assert_int_equal(bound_sources(&f, nope, NULL, 0), 0);
    done(&f);
    /* float on a parent without /value reads /click as 0 or 1 (simple controller /input/select) */
    f = make(false);
    s = make_set(f.in, "s", 0);
    fl = make_action(f.in, s, "f", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL);
    suggest_one(f.in, SIMPLE, fl, RIGHT "/input/select");
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    ds = hands(1);
    set_value(&ds, RIGHT "/input/select/click", 1.0f, 0);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_float_equal(get_float(&f, fl, XR_NULL_PATH).currentState, 1.0f, 0);
    done(&f);
}

static void higher_priority_sets_hide_the_same_input_source(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet hi = make_set(f.in, "hi", 1), lo = make_set(f.in, "lo", 0), lo2 = make_set(f.in, "lo2", 1);
    XrAction ha = make_action(f.in, hi, "ha", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    XrAction la = make_action(f.in, lo, "la", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL);
    XrAction other = make_action(f.in, lo, "other", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    XrAction same = make_action(f.in, lo2, "same", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL);
    XrAction acts[4] = {ha, la, other, same};
    /* trigger/click and trigger/value are the same input source (same identifier, other component) */
    const char *paths[4] = {LEFT "/input/trigger/click", LEFT "/input/trigger/value", LEFT "/input/menu/click",
                            LEFT "/input/trigger/value"};
    assert_int_equal(suggest(f.in, VIVE, 4, acts, paths), XR_SUCCESS);
    XrActionSet sets[3] = {hi, lo, lo2};
    assert_int_equal(attach(&f, 3, sets), XR_SUCCESS);
    dev_state ds = hands(1);
    ds.d.hand_profiles[0] = VIVE;
    set_value(&ds, LEFT "/input/trigger/value", 0.7f, 0);
    XrActiveActionSet all[3] = {{hi, XR_NULL_PATH}, {lo, XR_NULL_PATH}, {lo2, XR_NULL_PATH}};
    assert_int_equal(sync_sets(&f, 3, all, &ds), XR_SUCCESS);
    assert_true(get_bool(&f, ha, XR_NULL_PATH).isActive);
    assert_false(get_float(&f, la, XR_NULL_PATH).isActive);  /* hidden by the priority-1 set */
    assert_true(get_bool(&f, other, XR_NULL_PATH).isActive); /* another source: unaffected */
    assert_true(get_float(&f, same, XR_NULL_PATH).isActive); /* equal priority: processed together */
    /* without the high-priority set in the sync, the low one gets the source back */
    XrActiveActionSet only_lo = {lo, XR_NULL_PATH};
    assert_int_equal(sync_sets(&f, 1, &only_lo, &ds), XR_SUCCESS);
    assert_true(get_float(&f, la, XR_NULL_PATH).isActive);
    assert_float_equal(get_float(&f, la, XR_NULL_PATH).currentState, 0.7f, 0);
    done(&f);
}

static void hostile_device_values_never_give_nan_or_inf(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction fl = make_action(f.in, s, "f", XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL);
    XrAction v = make_action(f.in, s, "v", XR_ACTION_TYPE_VECTOR2F_INPUT, 0, NULL);
    XrAction acts[2] = {fl, v};
    const char *paths[2] = {LEFT "/input/trigger/value", LEFT "/input/thumbstick"};
    assert_int_equal(suggest(f.in, INDEX, 2, acts, paths), XR_SUCCESS);
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(1);
    ds.d.hand_profiles[0] = INDEX;
    const float hostile[] = {NAN, INFINITY, -INFINITY, 1e30f, -1e30f, 7.0f};
    const float expect[] = {0.0f, 1.0f, 0.0f, 1.0f, 0.0f, 1.0f};
    for (int i = 0; i < 6; i++) {
        set_value(&ds, LEFT "/input/trigger/value", hostile[i], 0);
        set_value(&ds, LEFT "/input/thumbstick/x", hostile[i], 0);
        set_value(&ds, LEFT "/input/thumbstick/y", -hostile[i], 0);
        assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
        assert_float_equal(get_float(&f, fl, XR_NULL_PATH).currentState, expect[i], 0);
        XrActionStateVector2f vs = get_vec(&f, v, XR_NULL_PATH);
        assert_true(fabsf(vs.currentState.x) <= 1.0f && fabsf(vs.currentState.y) <= 1.0f);
    }
    ds.d.value_count = 0;
    ds.d.values = NULL;
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_float_equal(get_float(&f, fl, XR_NULL_PATH).currentState, 0.0f, 0);
    done(&f);
}

static void unfocused_sync_validates_then_reads_everything_inactive(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0), other = make_set(f.in, "other", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    suggest_one(f.in, SIMPLE, a, LEFT "/input/select/click");
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(1);
    set_value(&ds, LEFT "/input/select/click", 1.0f, 0);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_true(get_bool(&f, a, XR_NULL_PATH).currentState);
    XrActiveActionSet as = {other, XR_NULL_PATH};
    XrActionsSyncInfo si = {.type = XR_TYPE_ACTIONS_SYNC_INFO, .countActiveActionSets = 1, .activeActionSets = &as};
    quiet();
    assert_int_equal(fv_xr_input_sync_unfocused(f.s, &si), XR_ERROR_ACTIONSET_NOT_ATTACHED);
    loud();
    as.actionSet = s;
    assert_int_equal(fv_xr_input_sync_unfocused(f.s, &si), XR_SESSION_NOT_FOCUSED);
    XrActionStateBoolean b = get_bool(&f, a, XR_NULL_PATH);
    assert_false(b.isActive || b.currentState || b.changedSinceLastSync);
    done(&f);
}

static void deactivate_makes_every_action_read_inactive_until_the_next_sync(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    suggest_one(f.in, SIMPLE, a, LEFT "/input/select/click");
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(7);
    set_value(&ds, LEFT "/input/select/click", 1.0f, 0);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_true(get_bool(&f, a, XR_NULL_PATH).currentState);
    fv_xr_input_deactivate(f.s); /* the session stopped running */
    XrActionStateBoolean b = get_bool(&f, a, XR_NULL_PATH);
    assert_false(b.isActive || b.currentState || b.changedSinceLastSync);
    assert_int_equal(b.lastChangeTime, 0);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_true(get_bool(&f, a, XR_NULL_PATH).isActive);
    fv_xr_input_deactivate(NULL);
    done(&f);
}

static void owns_handle_tells_the_instances_apart(void **st)
{
    (void)st;
    fx f = make(false), g = make(false);
    XrActionSet fs = make_set(f.in, "s", 0), gs = make_set(g.in, "s", 0);
    XrAction fa = make_action(f.in, fs, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    assert_true(fv_xr_input_owns_handle(f.in, (uint64_t)(uintptr_t)fs));
    assert_true(fv_xr_input_owns_handle(f.in, (uint64_t)(uintptr_t)fa));
    assert_false(fv_xr_input_owns_handle(g.in, (uint64_t)(uintptr_t)fs));
    assert_false(fv_xr_input_owns_handle(g.in, (uint64_t)(uintptr_t)fa));
    assert_true(fv_xr_input_owns_handle(g.in, (uint64_t)(uintptr_t)gs));
    assert_false(fv_xr_input_owns_handle(f.in, 0));
    assert_false(fv_xr_input_owns_handle(NULL, (uint64_t)(uintptr_t)fs));
    assert_int_equal(fv_xr_input_destroy_action(f.in, fa), XR_SUCCESS);
    assert_false(fv_xr_input_owns_handle(f.in, (uint64_t)(uintptr_t)fa)); /* a dead handle is nobody's */
    done(&g);
    done(&f);
}

/* ---- Interaction profiles ---- */

static void current_profile_follows_devices_and_changes_only_at_sync(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    suggest_one(f.in, SIMPLE, a, LEFT "/input/select/click");
    suggest_one(f.in, TOUCH, a, LEFT "/input/x/click");
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    assert_int_equal(current_profile(&f, LEFT), XR_NULL_PATH);
    assert_false(fv_xr_input_take_profile_changed(f.s));
    dev_state ds = hands(1);
    ds.d.hand_profiles[0] = TOUCH;
    fv_xr_input_update_profiles(f.s, &ds.d);
    assert_int_equal(current_profile(&f, LEFT), XR_NULL_PATH); /* not before a sync */
    assert_false(fv_xr_input_take_profile_changed(f.s));
    assert_int_equal(sync1(&f, s, NULL), XR_SUCCESS); /* uses the devices given to update_profiles */
    assert_int_equal(current_profile(&f, LEFT), P(f.in, TOUCH));
    /* the right hand's device is no suggested profile: khr/simple_controller stands in */
    assert_int_equal(current_profile(&f, RIGHT), P(f.in, SIMPLE));
    assert_true(fv_xr_input_take_profile_changed(f.s));
    assert_false(fv_xr_input_take_profile_changed(f.s)); /* once */
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_false(fv_xr_input_take_profile_changed(f.s)); /* nothing changed */
    /* the left controller goes away */
    ds.d.hands_present[0] = false;
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_int_equal(current_profile(&f, LEFT), XR_NULL_PATH);
    assert_true(fv_xr_input_take_profile_changed(f.s));
    /* paths with no device in fovea */
    assert_int_equal(current_profile(&f, "/user/head"), XR_NULL_PATH);
    assert_int_equal(current_profile(&f, "/user/gamepad"), XR_NULL_PATH);
    assert_int_equal(current_profile(&f, "/user/treadmill"), XR_NULL_PATH);
    quiet();
    XrInteractionProfileState ps = {.type = XR_TYPE_INTERACTION_PROFILE_STATE};
    assert_int_equal(fv_xr_input_get_current_interaction_profile(f.s, P(f.in, LEFT "/input"), &ps),
                     XR_ERROR_PATH_UNSUPPORTED);
    assert_int_equal(fv_xr_input_get_current_interaction_profile(f.s, P(f.in, "/user/eyes_ext"), &ps),
                     XR_ERROR_PATH_UNSUPPORTED); /* the extension is not enabled */
    assert_int_equal(fv_xr_input_get_current_interaction_profile(f.s, XR_NULL_PATH, &ps), XR_ERROR_PATH_INVALID);
    ps.type = XR_TYPE_ACTION_STATE_FLOAT;
    assert_int_equal(fv_xr_input_get_current_interaction_profile(f.s, P(f.in, LEFT), &ps),
                     XR_ERROR_VALIDATION_FAILURE);
    loud();
    done(&f);
}

static void only_profiles_the_app_suggested_become_current(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    suggest_one(f.in, INDEX, a, RIGHT "/input/a/click");
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(1);
    ds.d.hand_profiles[1] = TOUCH; /* not suggested, and no simple-controller bindings: the suggested one */
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_int_equal(current_profile(&f, RIGHT), P(f.in, INDEX));
    done(&f);
    /* no bindings at all: no profile */
    f = make(false);
    s = make_set(f.in, "s", 0);
    make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_int_equal(current_profile(&f, RIGHT), XR_NULL_PATH);
    assert_false(fv_xr_input_take_profile_changed(f.s));
    done(&f);
}

static void a_second_suggestion_replaces_the_first_for_that_profile(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    suggest_one(f.in, SIMPLE, a, LEFT "/input/select/click");
    suggest_one(f.in, SIMPLE, a, LEFT "/input/menu/click");
    /* a failing call leaves the last good one in place */
    const char *bad[1] = {LEFT "/input/trigger/value"};
    quiet();
    assert_int_equal(suggest(f.in, SIMPLE, 1, &a, bad), XR_ERROR_PATH_UNSUPPORTED);
    loud();
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(1);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    XrPath src[2];
    assert_int_equal(bound_sources(&f, a, src, 2), 1);
    assert_int_equal(src[0], P(f.in, LEFT "/input/menu/click"));
    done(&f);
}

static void bound_sources_use_the_two_call_idiom(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    XrAction acts[3] = {a, a, a};
    const char *paths[3] = {LEFT "/input/select/click", RIGHT "/input/select/click", LEFT "/input/select/click"};
    assert_int_equal(suggest(f.in, SIMPLE, 3, acts, paths), XR_SUCCESS); /* the repeat is one binding */
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(1);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    XrBoundSourcesForActionEnumerateInfo e = {.type = XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO, .action = a};
    uint32_t n = 0;
    assert_int_equal(fv_xr_input_enumerate_bound_sources(f.s, &e, 0, &n, NULL), XR_SUCCESS);
    assert_int_equal(n, 2);
    XrPath one[1] = {0};
    assert_int_equal(fv_xr_input_enumerate_bound_sources(f.s, &e, 1, &n, one), XR_ERROR_SIZE_INSUFFICIENT);
    assert_int_equal(n, 2);
    XrPath two[2];
    assert_int_equal(fv_xr_input_enumerate_bound_sources(f.s, &e, 2, &n, two), XR_SUCCESS);
    quiet();
    assert_int_equal(fv_xr_input_enumerate_bound_sources(f.s, &e, 2, NULL, two), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(fv_xr_input_enumerate_bound_sources(f.s, &e, 2, &n, NULL), XR_ERROR_VALIDATION_FAILURE);
    loud();
    /* no devices: no current profile, no source ("unbound" gives 0) */
    assert_int_equal(sync1(&f, s, NULL), XR_SUCCESS);
    assert_int_equal(bound_sources(&f, a, NULL, 0), 0);
    done(&f);
}

static void localized_names_hold_the_requested_parts(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    suggest_one(f.in, TOUCH, a, RIGHT "/input/a/click");
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    dev_state ds = hands(1);
    ds.d.hand_profiles[1] = TOUCH;
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    XrInputSourceLocalizedNameGetInfo g = {.type = XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO,
                                           .sourcePath = P(f.in, RIGHT "/input/a/click")};
    char buf[256];
    uint32_t n = 0;
    struct {
        XrInputSourceLocalizedNameFlags flags;
        const char *want;
    } cases[] = {
        {XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT, "Right Hand"},
        {XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT, "Oculus Touch Controller"},
        {XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT, "A Button"},
        {XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT | XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT |
             XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT,
         "Right Hand Oculus Touch Controller A Button"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        g.whichComponents = cases[i].flags;
        assert_int_equal(fv_xr_input_get_localized_name(f.s, &g, 0, &n, NULL), XR_SUCCESS);
        assert_int_equal(n, strlen(cases[i].want) + 1);
        assert_int_equal(fv_xr_input_get_localized_name(f.s, &g, sizeof buf, &n, buf), XR_SUCCESS);
        assert_string_equal(buf, cases[i].want);
    }
    char tiny[4];
    assert_int_equal(fv_xr_input_get_localized_name(f.s, &g, sizeof tiny, &n, tiny), XR_ERROR_SIZE_INSUFFICIENT);
    /* more components */
    const struct {
        const char *path;
        const char *want;
    } comps[] = {
        {LEFT "/input/thumbstick/x", "Thumbstick X Axis"},
        {LEFT "/input/trigger/value", "Trigger"},
        {LEFT "/input/thumbrest/touch", "Thumbrest Touch"},
        {"/user/gamepad/input/shoulder_left/click", "Left Shoulder"},
        {"/user/gamepad/input/dpad_up/click", "D-Pad Up"},
        {"/user/gamepad/output/haptic_left_trigger", "Haptic Left Trigger"},
        {"/user/head/input/mute_mic/click", "Mute Microphone"},
    };
    g.whichComponents = XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT;
    for (size_t i = 0; i < sizeof comps / sizeof comps[0]; i++) {
        g.sourcePath = P(f.in, comps[i].path);
        assert_int_equal(fv_xr_input_get_localized_name(f.s, &g, sizeof buf, &n, buf), XR_SUCCESS);
        if (strcmp(buf, comps[i].want) != 0) fail_msg("%s: \"%s\", want \"%s\"", comps[i].path, buf, comps[i].want);
    }
    quiet();
    g.whichComponents = 0;
    assert_int_equal(fv_xr_input_get_localized_name(f.s, &g, sizeof buf, &n, buf), XR_ERROR_VALIDATION_FAILURE);
    g.whichComponents = XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT;
    g.sourcePath = P(f.in, "/interaction_profiles/oculus/touch_controller");
    assert_int_equal(fv_xr_input_get_localized_name(f.s, &g, sizeof buf, &n, buf), XR_ERROR_PATH_UNSUPPORTED);
    g.sourcePath = 55555;
    assert_int_equal(fv_xr_input_get_localized_name(f.s, &g, sizeof buf, &n, buf), XR_ERROR_PATH_INVALID);
    loud();
    done(&f);
}

/* ---- Haptics ---- */

static void haptics_are_accepted_and_checked_without_a_device(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrPath lr[2] = {P(f.in, LEFT), P(f.in, RIGHT)};
    XrAction h = make_action(f.in, s, "h", XR_ACTION_TYPE_VIBRATION_OUTPUT, 2, lr);
    XrAction acts[2] = {h, h};
    const char *paths[2] = {LEFT "/output/haptic", RIGHT "/output/haptic"};
    assert_int_equal(suggest(f.in, SIMPLE, 2, acts, paths), XR_SUCCESS);
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    XrHapticActionInfo hi = {.type = XR_TYPE_HAPTIC_ACTION_INFO, .action = h};
    XrHapticVibration vib = {.type = XR_TYPE_HAPTIC_VIBRATION, .duration = 300000000, .frequency = 3000,
                             .amplitude = 0.5f};
    const XrHapticBaseHeader *fb = (const XrHapticBaseHeader *)&vib;
    assert_int_equal(fv_xr_input_apply_haptic(f.s, &hi, fb), XR_SUCCESS); /* no device: nothing to do */
    hi.subactionPath = lr[1];
    assert_int_equal(fv_xr_input_apply_haptic(f.s, &hi, fb), XR_SUCCESS);
    assert_int_equal(fv_xr_input_stop_haptic(f.s, &hi), XR_SUCCESS);
    /* extremes are accepted (the runtime may clamp) */
    vib.duration = XR_MIN_HAPTIC_DURATION;
    vib.frequency = XR_FREQUENCY_UNSPECIFIED;
    vib.amplitude = 7.0f;
    assert_int_equal(fv_xr_input_apply_haptic(f.s, &hi, fb), XR_SUCCESS);
    quiet();
    hi.subactionPath = P(f.in, "/user/gamepad");
    assert_int_equal(fv_xr_input_apply_haptic(f.s, &hi, fb), XR_ERROR_PATH_UNSUPPORTED);
    hi.subactionPath = XR_NULL_PATH;
    vib.type = XR_TYPE_ACTION_STATE_FLOAT;
    assert_int_equal(fv_xr_input_apply_haptic(f.s, &hi, fb), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(fv_xr_input_apply_haptic(f.s, &hi, NULL), XR_ERROR_VALIDATION_FAILURE);
    vib.type = XR_TYPE_HAPTIC_VIBRATION;
    assert_int_equal(fv_xr_input_apply_haptic(f.s, NULL, fb), XR_ERROR_VALIDATION_FAILURE);
    assert_int_equal(fv_xr_input_destroy_action(f.in, h), XR_SUCCESS);
    assert_int_equal(fv_xr_input_apply_haptic(f.s, &hi, fb), XR_ERROR_HANDLE_INVALID);
    loud();
    done(&f);
}

/* ---- Action spaces and poses ---- */

static void action_space_checks_type_subaction_path_and_pose(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrPath left = P(f.in, LEFT);
    XrAction p = make_action(f.in, s, "p", XR_ACTION_TYPE_POSE_INPUT, 1, &left);
    XrActionSpaceCreateInfo ci = {.type = XR_TYPE_ACTION_SPACE_CREATE_INFO, .action = p, .subactionPath = left,
                                  .poseInActionSpace = {.orientation = {0, 0, 0, 1}, .position = {0, 0, -1}}};
    assert_int_equal(fv_xr_input_check_action_space(f.in, &ci), XR_SUCCESS); /* no attach needed */
    quiet();
    ci.subactionPath = P(f.in, RIGHT);
    assert_int_equal(fv_xr_input_check_action_space(f.in, &ci), XR_ERROR_PATH_UNSUPPORTED);
    ci.subactionPath = 8888;
    assert_int_equal(fv_xr_input_check_action_space(f.in, &ci), XR_ERROR_PATH_INVALID);
    ci.subactionPath = XR_NULL_PATH;
    ci.poseInActionSpace.orientation = (XrQuaternionf){0, 0, 0, 2};
    assert_int_equal(fv_xr_input_check_action_space(f.in, &ci), XR_ERROR_POSE_INVALID);
    ci.poseInActionSpace.orientation = (XrQuaternionf){0, 0, 0, 0};
    assert_int_equal(fv_xr_input_check_action_space(f.in, &ci), XR_ERROR_POSE_INVALID);
    ci.poseInActionSpace.orientation = (XrQuaternionf){NAN, 0, 0, 1};
    assert_int_equal(fv_xr_input_check_action_space(f.in, &ci), XR_ERROR_POSE_INVALID);
    ci.poseInActionSpace.orientation = (XrQuaternionf){0, 0, 0, 1};
    ci.poseInActionSpace.position.x = INFINITY;
    assert_int_equal(fv_xr_input_check_action_space(f.in, &ci), XR_ERROR_POSE_INVALID);
    ci.poseInActionSpace.position.x = 0;
    ci.type = XR_TYPE_ACTION_CREATE_INFO;
    assert_int_equal(fv_xr_input_check_action_space(f.in, &ci), XR_ERROR_VALIDATION_FAILURE);
    ci.type = XR_TYPE_ACTION_SPACE_CREATE_INFO;
    assert_int_equal(fv_xr_input_destroy_action(f.in, p), XR_SUCCESS);
    assert_int_equal(fv_xr_input_check_action_space(f.in, &ci), XR_ERROR_HANDLE_INVALID);
    loud();
    done(&f);
}

static void pose_source_names_the_bound_pose_and_outlives_the_handle(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "s", 0);
    XrPath lr[2] = {P(f.in, LEFT), P(f.in, RIGHT)};
    XrAction p = make_action(f.in, s, "p", XR_ACTION_TYPE_POSE_INPUT, 2, lr);
    XrAction acts[3] = {p, p, p};
    const char *paths[3] = {LEFT "/input/grip/pose", RIGHT "/input/aim/pose", RIGHT "/input/grip/pose"};
    assert_int_equal(suggest(f.in, SIMPLE, 3, acts, paths), XR_SUCCESS);
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    assert_int_equal(fv_xr_input_pose_source(f.s, p, lr[0]), FV_XR_POSE_NONE); /* no sync yet */
    dev_state ds = hands(1);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_int_equal(fv_xr_input_pose_source(f.s, p, lr[0]), FV_XR_POSE_LEFT_GRIP);
    assert_int_equal(fv_xr_input_pose_source(f.s, p, lr[1]), FV_XR_POSE_RIGHT_AIM); /* the first suggested */
    assert_int_equal(fv_xr_input_pose_source(f.s, p, XR_NULL_PATH), FV_XR_POSE_LEFT_GRIP);
    assert_int_equal(fv_xr_input_pose_source(f.s, p, P(f.in, "/user/gamepad")), FV_XR_POSE_NONE);
    XrActionStateGetInfo g = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = p, .subactionPath = lr[1]};
    XrActionStatePose ps = {.type = XR_TYPE_ACTION_STATE_POSE};
    assert_int_equal(fv_xr_input_get_pose(f.s, &g, &ps), XR_SUCCESS);
    assert_true(ps.isActive);
    /* destroying the handles keeps the action: its spaces stay locatable, its set stays in the session */
    assert_int_equal(fv_xr_input_destroy_action_set(f.in, s), XR_SUCCESS);
    assert_int_equal(fv_xr_input_pose_source(f.s, p, lr[0]), FV_XR_POSE_LEFT_GRIP);
    quiet();
    assert_int_equal(sync1(&f, s, &ds), XR_ERROR_HANDLE_INVALID);
    loud();
    ds.d.hands_present[0] = false;
    assert_int_equal(sync_sets(&f, 0, NULL, &ds), XR_SUCCESS);
    assert_int_equal(fv_xr_input_pose_source(f.s, p, lr[0]), FV_XR_POSE_NONE); /* inactive: not located */
    done(&f); /* ASan: the kept set is freed with the last session */
}

static void eye_gaze_profile_is_current_only_while_a_gaze_source_is_open(void **st)
{
    (void)st;
    fx f = make(true);
    XrActionSet s = make_set(f.in, "gameplay", 0);
    XrAction gaze = make_action(f.in, s, "user_intent", XR_ACTION_TYPE_POSE_INPUT, 0, NULL);
    suggest_one(f.in, GAZE, gaze, "/user/eyes_ext/input/gaze_ext/pose");
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    XrActionSpaceCreateInfo ci = {.type = XR_TYPE_ACTION_SPACE_CREATE_INFO, .action = gaze,
                                  .poseInActionSpace = {.orientation = {0, 0, 0, 1}}};
    assert_int_equal(fv_xr_input_check_action_space(f.in, &ci), XR_SUCCESS);
    fv_xr_input_devices d = {0};
    XrActionsSyncInfo si = {.type = XR_TYPE_ACTIONS_SYNC_INFO, .countActiveActionSets = 1,
                            .activeActionSets = &(XrActiveActionSet){s, XR_NULL_PATH}};
    assert_int_equal(fv_xr_input_sync(f.s, &si, &d), XR_SUCCESS);
    assert_int_equal(current_profile(&f, "/user/eyes_ext"), XR_NULL_PATH);
    assert_int_equal(fv_xr_input_pose_source(f.s, gaze, XR_NULL_PATH), FV_XR_POSE_NONE);
    d.eye_gaze_present = true;
    d.eye_gaze_tracked = false; /* a blink: still bound and active; the runtime clears the tracked bits */
    assert_int_equal(fv_xr_input_sync(f.s, &si, &d), XR_SUCCESS);
    assert_int_equal(current_profile(&f, "/user/eyes_ext"), P(f.in, GAZE));
    assert_true(fv_xr_input_take_profile_changed(f.s));
    XrActionStateGetInfo g = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = gaze};
    XrActionStatePose ps = {.type = XR_TYPE_ACTION_STATE_POSE};
    assert_int_equal(fv_xr_input_get_pose(f.s, &g, &ps), XR_SUCCESS);
    assert_true(ps.isActive);
    assert_int_equal(fv_xr_input_pose_source(f.s, gaze, XR_NULL_PATH), FV_XR_POSE_EYE_GAZE);
    XrPath src[1];
    assert_int_equal(bound_sources(&f, gaze, src, 1), 1);
    assert_int_equal(src[0], P(f.in, "/user/eyes_ext/input/gaze_ext/pose"));
    d.eye_gaze_present = false; /* the source closes */
    assert_int_equal(fv_xr_input_sync(f.s, &si, &d), XR_SUCCESS);
    assert_int_equal(fv_xr_input_get_pose(f.s, &g, &ps), XR_SUCCESS);
    assert_false(ps.isActive);
    assert_true(fv_xr_input_take_profile_changed(f.s));
    done(&f);
}

/* ---- Sessions and lifetimes ---- */

static void sessions_are_independent_and_the_instance_frees_what_is_left(void **st)
{
    (void)st;
    fx f = make(false);
    fv_xr_input_session *s2 = NULL;
    assert_int_equal(fv_xr_input_session_create(f.in, &s2), XR_SUCCESS);
    XrActionSet s = make_set(f.in, "s", 0);
    XrAction a = make_action(f.in, s, "a", XR_ACTION_TYPE_BOOLEAN_INPUT, 0, NULL);
    suggest_one(f.in, SIMPLE, a, LEFT "/input/select/click");
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    XrSessionActionSetsAttachInfo ai = {.type = XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO, .countActionSets = 1,
                                        .actionSets = &s};
    assert_int_equal(fv_xr_input_attach(s2, &ai), XR_SUCCESS); /* the same set, another session */
    dev_state ds = hands(1);
    set_value(&ds, LEFT "/input/select/click", 1.0f, 0);
    assert_int_equal(sync1(&f, s, &ds), XR_SUCCESS);
    assert_true(get_bool(&f, a, XR_NULL_PATH).currentState);
    XrActionStateGetInfo g = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = a};
    XrActionStateBoolean b = {.type = XR_TYPE_ACTION_STATE_BOOLEAN};
    assert_int_equal(fv_xr_input_get_boolean(s2, &g, &b), XR_SUCCESS);
    assert_false(b.isActive); /* s2 has not synced */
    assert_int_equal(fv_xr_input_destroy_action_set(f.in, s), XR_SUCCESS);
    fv_xr_input_session_destroy(&f.s);
    fv_xr_input_destroy(&f.in); /* s2 is freed with the instance (ASan checks) */
}

static void many_actions_up_to_the_limit(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet s = make_set(f.in, "big", 0);
    XrAction a;
    char name[32], lname[32];
    int made = 0;
    XrResult r = XR_SUCCESS;
    quiet();
    for (int i = 0; i < 5000 && r == XR_SUCCESS; i++) {
        snprintf(name, sizeof name, "a%d", i);
        snprintf(lname, sizeof lname, "A %d", i);
        r = try_action(f.in, s, name, lname, XR_ACTION_TYPE_FLOAT_INPUT, 0, NULL, &a);
        if (r == XR_SUCCESS) made++;
    }
    loud();
    assert_int_equal(r, XR_ERROR_LIMIT_REACHED);
    assert_int_equal(made, 4096);
    assert_int_equal(attach(&f, 1, &s), XR_SUCCESS);
    assert_int_equal(sync1(&f, s, NULL), XR_SUCCESS);
    done(&f);
}

/* ---- hello_xr ---- */

/* The sequence Debian's hello_xr (OpenXR-SDK 1.0.20) runs: one "gameplay" set with grab_object (float),
   hand_pose (pose), vibrate_hand (vibration), quit_session (boolean), all on both hands; bindings for its five
   profiles; two action spaces before attaching; then a sync and the queries of every frame. */
static void hello_xr_sequence_succeeds(void **st)
{
    (void)st;
    fx f = make(false);
    XrActionSet set = make_set(f.in, "gameplay", 0);
    XrPath hp[2] = {P(f.in, LEFT), P(f.in, RIGHT)};
    XrAction grab = make_action(f.in, set, "grab_object", XR_ACTION_TYPE_FLOAT_INPUT, 2, hp);
    XrAction pose = make_action(f.in, set, "hand_pose", XR_ACTION_TYPE_POSE_INPUT, 2, hp);
    XrAction vib = make_action(f.in, set, "vibrate_hand", XR_ACTION_TYPE_VIBRATION_OUTPUT, 2, hp);
    XrAction quit = make_action(f.in, set, "quit_session", XR_ACTION_TYPE_BOOLEAN_INPUT, 2, hp);
    /* hello_xr's table: per profile the grab, pose and quit components (quit on Touch: the left menu only) */
    static const struct {
        const char *profile, *grab, *quit;
        bool quit_left_only;
    } hx[] = {
        {SIMPLE, "/input/select/click", "/input/menu/click", false},
        {TOUCH, "/input/squeeze/value", "/input/menu/click", true},
        {VIVE, "/input/trigger/value", "/input/menu/click", false},
        {INDEX, "/input/squeeze/force", "/input/b/click", false},
        {WMR, "/input/squeeze/click", "/input/menu/click", false},
    };
    for (size_t i = 0; i < sizeof hx / sizeof hx[0]; i++) {
        XrAction a[8] = {grab, grab, pose, pose, vib, vib, quit, quit};
        char p[8][XR_MAX_PATH_LENGTH];
        const char *pp[8];
        const char *comp[4] = {hx[i].grab, "/input/grip/pose", "/output/haptic", hx[i].quit};
        for (int k = 0; k < 8; k++) {
            snprintf(p[k], sizeof p[k], "%s%s", k % 2 ? RIGHT : LEFT, comp[k / 2]);
            pp[k] = p[k];
        }
        uint32_t n = hx[i].quit_left_only ? 7 : 8;
        if (xri_test_suggest(f.in, hx[i].profile, n, a, pp) != XR_SUCCESS) fail_msg("hello_xr's %s", hx[i].profile);
    }
    for (int h = 0; h < 2; h++) {
        XrActionSpaceCreateInfo ci = {.type = XR_TYPE_ACTION_SPACE_CREATE_INFO, .action = pose, .subactionPath = hp[h],
                                      .poseInActionSpace = {.orientation = {0, 0, 0, 1}}};
        assert_int_equal(fv_xr_input_check_action_space(f.in, &ci), XR_SUCCESS);
    }
    assert_int_equal(attach(&f, 1, &set), XR_SUCCESS);
    /* fovea today: no controllers. Every frame: sync, then per hand grab, pose, and quit. */
    fv_xr_input_devices none = {.eye_gaze_present = true};
    XrActiveActionSet as = {set, XR_NULL_PATH};
    XrActionsSyncInfo si = {.type = XR_TYPE_ACTIONS_SYNC_INFO, .countActiveActionSets = 1, .activeActionSets = &as};
    for (int frame = 0; frame < 3; frame++) {
        none.time = 1000 * (frame + 1);
        assert_int_equal(fv_xr_input_sync(f.s, &si, &none), XR_SUCCESS);
        for (int h = 0; h < 2; h++) {
            XrActionStateFloat g = get_float(&f, grab, hp[h]);
            assert_false(g.isActive);
            XrActionStateGetInfo gi = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = pose, .subactionPath = hp[h]};
            XrActionStatePose ps = {.type = XR_TYPE_ACTION_STATE_POSE};
            assert_int_equal(fv_xr_input_get_pose(f.s, &gi, &ps), XR_SUCCESS);
            assert_false(ps.isActive);
            assert_int_equal(fv_xr_input_pose_source(f.s, pose, hp[h]), FV_XR_POSE_NONE);
        }
        assert_false(get_bool(&f, quit, XR_NULL_PATH).isActive);
        assert_int_equal(current_profile(&f, LEFT), XR_NULL_PATH);
    }
    assert_false(fv_xr_input_take_profile_changed(f.s));
    /* with Touch controllers the same sequence reads them, and hello_xr's haptic call goes through */
    dev_state ds = hands(5000);
    ds.d.hand_profiles[0] = ds.d.hand_profiles[1] = TOUCH;
    set_value(&ds, RIGHT "/input/squeeze/value", 0.95f, 0);
    set_value(&ds, LEFT "/input/menu/click", 1.0f, 0);
    assert_int_equal(fv_xr_input_sync(f.s, &si, &ds.d), XR_SUCCESS);
    assert_true(fv_xr_input_take_profile_changed(f.s));
    assert_int_equal(current_profile(&f, RIGHT), P(f.in, TOUCH));
    assert_float_equal(get_float(&f, grab, hp[1]).currentState, 0.95f, 0);
    assert_true(get_bool(&f, quit, XR_NULL_PATH).currentState);
    assert_int_equal(fv_xr_input_pose_source(f.s, pose, hp[1]), FV_XR_POSE_RIGHT_GRIP);
    XrHapticActionInfo hi = {.type = XR_TYPE_HAPTIC_ACTION_INFO, .action = vib, .subactionPath = hp[1]};
    XrHapticVibration v = {.type = XR_TYPE_HAPTIC_VIBRATION, .amplitude = 0.5f, .duration = XR_MIN_HAPTIC_DURATION,
                           .frequency = XR_FREQUENCY_UNSPECIFIED};
    assert_int_equal(fv_xr_input_apply_haptic(f.s, &hi, (const XrHapticBaseHeader *)&v), XR_SUCCESS);
    /* hello_xr prints the grab action's sources by localized name */
    XrPath src[4];
    uint32_t n = bound_sources(&f, grab, src, 4);
    assert_int_equal(n, 2);
    XrInputSourceLocalizedNameGetInfo ln = {.type = XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO,
                                            .sourcePath = src[0],
                                            .whichComponents = XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT |
                                                               XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT |
                                                               XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT};
    char name[128];
    assert_int_equal(fv_xr_input_get_localized_name(f.s, &ln, sizeof name, &n, name), XR_SUCCESS);
    assert_string_equal(name, "Left Hand Oculus Touch Controller Squeeze");
    done(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(action_set_name_rules_give_their_errors),
        cmocka_unit_test(duplicate_action_set_names_are_refused_until_the_other_is_destroyed),
        cmocka_unit_test(action_names_follow_the_same_rules_within_their_set),
        cmocka_unit_test(subaction_paths_must_be_distinct_top_level_user_paths),
        cmocka_unit_test(stale_foreign_and_garbage_handles_are_handle_invalid),
        cmocka_unit_test(destroying_a_set_destroys_its_action_handles),
        cmocka_unit_test(attach_is_once_per_session_and_freezes_the_sets),
        cmocka_unit_test(attach_refuses_a_destroyed_set),
        cmocka_unit_test(unattached_actions_give_actionset_not_attached),
        cmocka_unit_test(queries_of_the_wrong_type_give_action_type_mismatch),
        cmocka_unit_test(subaction_path_queries_must_name_a_declared_path),
        cmocka_unit_test(sync_validates_active_sets_and_subaction_paths),
        cmocka_unit_test(states_change_only_at_sync),
        cmocka_unit_test(changed_since_last_sync_and_last_change_time_follow_the_spec),
        cmocka_unit_test(is_active_needs_a_binding_and_a_present_device),
        cmocka_unit_test(subaction_filters_select_the_devices_read),
        cmocka_unit_test(bindings_outside_the_declared_subaction_paths_are_ignored),
        cmocka_unit_test(multiple_bindings_combine_by_or_largest_and_longest),
        cmocka_unit_test(boolean_from_a_scalar_uses_a_threshold_with_hysteresis),
        cmocka_unit_test(implicit_components_follow_the_suggested_binding_rules),
        cmocka_unit_test(higher_priority_sets_hide_the_same_input_source),
        cmocka_unit_test(hostile_device_values_never_give_nan_or_inf),
        cmocka_unit_test(unfocused_sync_validates_then_reads_everything_inactive),
        cmocka_unit_test(deactivate_makes_every_action_read_inactive_until_the_next_sync),
        cmocka_unit_test(owns_handle_tells_the_instances_apart),
        cmocka_unit_test(current_profile_follows_devices_and_changes_only_at_sync),
        cmocka_unit_test(only_profiles_the_app_suggested_become_current),
        cmocka_unit_test(a_second_suggestion_replaces_the_first_for_that_profile),
        cmocka_unit_test(bound_sources_use_the_two_call_idiom),
        cmocka_unit_test(localized_names_hold_the_requested_parts),
        cmocka_unit_test(haptics_are_accepted_and_checked_without_a_device),
        cmocka_unit_test(action_space_checks_type_subaction_path_and_pose),
        cmocka_unit_test(pose_source_names_the_bound_pose_and_outlives_the_handle),
        cmocka_unit_test(eye_gaze_profile_is_current_only_while_a_gaze_source_is_open),
        cmocka_unit_test(sessions_are_independent_and_the_instance_frees_what_is_left),
        cmocka_unit_test(many_actions_up_to_the_limit),
        cmocka_unit_test(hello_xr_sequence_succeeds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
