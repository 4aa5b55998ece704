/* @brief libFuzzer target for fv_xr_input: the input bytes drive a sequence of action-system calls (paths, sets,
   actions, bindings, attach, sync with hostile device values, queries, haptics, spaces, destroys, sessions) on one
   instance, stale and garbage handles included. Beyond ASan/UBSan it checks what every call must keep: states are
   finite and in range, an inactive action reads zero with lastChangeTime 0, results are XrResult codes the spec
   lists for the call. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_xr_input.h"

typedef struct reader {
    const uint8_t *p;
    size_t n;
} reader;

static uint8_t byte(reader *r)
{
    if (r->n == 0) return 0;
    r->n--;
    return *r->p++;
}

static float any_float(reader *r)
{
    uint32_t u = (uint32_t)byte(r) | (uint32_t)byte(r) << 8 | (uint32_t)byte(r) << 16 | (uint32_t)byte(r) << 24;
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static const char *const users[] = {"/user/hand/left", "/user/hand/right", "/user/head", "/user/gamepad",
                                    "/user/eyes_ext", "/user/treadmill", "/user", "/user/hand/left/input"};
static const char *const comps[] = {"/input/select/click", "/input/menu/click", "/input/grip/pose", "/input/aim/pose",
                                    "/output/haptic", "/input/trigger/value", "/input/trigger", "/input/thumbstick",
                                    "/input/thumbstick/x", "/input/squeeze/value", "/input/squeeze", "/input/a/click",
                                    "/input/x/click", "/input/gaze_ext/pose", "/input/trackpad", "/output/haptic_left",
                                    "/input/dpad_up/click", "", "/input", "/input/b/touch"};
static const char *const profiles[] = {
    "/interaction_profiles/khr/simple_controller",  "/interaction_profiles/oculus/touch_controller",
    "/interaction_profiles/valve/index_controller", "/interaction_profiles/htc/vive_controller",
    "/interaction_profiles/ext/eye_gaze_interaction", "/interaction_profiles/microsoft/xbox_controller",
    "/interaction_profiles/htc/vive_pro",           "/interaction_profiles/acme/none"};
#define N(a) (sizeof(a) / sizeof((a)[0]))

static XrPath path_of(fv_xr_input *in, const char *s)
{
    XrPath p = XR_NULL_PATH;
    if (fv_xr_input_string_to_path(in, s, &p) != XR_SUCCESS) return XR_NULL_PATH;
    return p;
}

/* A path from the tables (user + component), or garbage. */
static XrPath some_path(fv_xr_input *in, reader *r)
{
    uint8_t k = byte(r);
    if (k == 0) return XR_NULL_PATH;
    if (k == 1) return (XrPath)byte(r) * 7919u; /* maybe never handed out */
    char buf[300];
    snprintf(buf, sizeof buf, "%s%s", users[byte(r) % N(users)], k & 2 ? comps[byte(r) % N(comps)] : "");
    return path_of(in, buf);
}

static void check_common(XrBool32 active, XrBool32 changed, XrTime t)
{
    if (active > 1 || changed > 1) abort();
    if (!active && (changed || t != 0)) abort();
}

#define MAXH 24

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int once;
    if (!once) {
        fv_log_set_level("xr_input", FV_LOG_LEVEL_ERROR); /* the library warns on every bad call */
        once = 1;
    }
    reader r = {data, size};
    fv_xr_input_desc d = {.eye_gaze_ext_enabled = byte(&r) & 1, .max_paths = 64 + byte(&r)};
    fv_xr_input *in = NULL;
    if (fv_xr_input_create(&d, &in) != XR_SUCCESS) return 0;
    fv_xr_input_session *sess[2] = {NULL, NULL};
    XrActionSet sets[MAXH] = {0};
    XrAction acts[MAXH] = {0};
    unsigned nsets = 0, nacts = 0;
    fv_xr_input_value vals[8];
    const char *val_paths[8] = {"/user/hand/left/input/select/click",  "/user/hand/right/input/trigger/value",
                                "/user/hand/left/input/thumbstick/x",  "/user/hand/left/input/thumbstick/y",
                                "/user/hand/right/input/squeeze/value", "/user/hand/left/input/trackpad/x",
                                "/user/hand/right/input/a/click",       NULL};
    for (int steps = 0; steps < 200 && r.n > 0; steps++) {
        uint8_t op = byte(&r) % 16;
        fv_xr_input_session *s = sess[byte(&r) & 1];
        switch (op) {
        case 0: { /* a raw path string of odd characters */
            char buf[300];
            size_t n = byte(&r);
            static const char alpha[] = "/ab._-0A \\\x01\xc3\xa9/";
            for (size_t i = 0; i < n && i < sizeof buf - 1; i++) buf[i] = alpha[byte(&r) % (sizeof alpha - 1)];
            buf[n < sizeof buf - 1 ? n : sizeof buf - 1] = '\0';
            XrPath p;
            XrResult res = fv_xr_input_string_to_path(in, buf, &p);
            if (res == XR_SUCCESS) {
                char back[300];
                uint32_t m;
                if (fv_xr_input_path_to_string(in, p, sizeof back, &m, back) != XR_SUCCESS || strcmp(back, buf))
                    abort();
            } else if (res != XR_ERROR_PATH_FORMAT_INVALID && res != XR_ERROR_PATH_COUNT_EXCEEDED) {
                abort();
            }
            break;
        }
        case 1: { /* action set */
            if (nsets == MAXH) break;
            char name[XR_MAX_ACTION_SET_NAME_SIZE], lname[16];
            snprintf(name, sizeof name, "s%u", byte(&r) % 8u);
            snprintf(lname, sizeof lname, "S %u", byte(&r) % 8u);
            XrActionSetCreateInfo ci = {.type = XR_TYPE_ACTION_SET_CREATE_INFO, .priority = byte(&r) % 3u};
            memcpy(ci.actionSetName, name, sizeof name);
            memcpy(ci.localizedActionSetName, lname, sizeof lname);
            if (fv_xr_input_create_action_set(in, &ci, &sets[nsets]) == XR_SUCCESS) nsets++;
            break;
        }
        case 2: { /* action */
            if (nacts == MAXH || nsets == 0) break;
            XrActionCreateInfo ci = {.type = XR_TYPE_ACTION_CREATE_INFO};
            snprintf(ci.actionName, sizeof ci.actionName, "a%u", byte(&r) % 16u);
            snprintf(ci.localizedActionName, sizeof ci.localizedActionName, "A %u", byte(&r) % 16u);
            static const XrActionType t[] = {XR_ACTION_TYPE_BOOLEAN_INPUT, XR_ACTION_TYPE_FLOAT_INPUT,
                                             XR_ACTION_TYPE_VECTOR2F_INPUT, XR_ACTION_TYPE_POSE_INPUT,
                                             XR_ACTION_TYPE_VIBRATION_OUTPUT, (XrActionType)9};
            ci.actionType = t[byte(&r) % N(t)];
            XrPath sub[3];
            ci.countSubactionPaths = byte(&r) % 4u;
            for (uint32_t i = 0; i < ci.countSubactionPaths; i++) sub[i] = path_of(in, users[byte(&r) % N(users)]);
            ci.subactionPaths = ci.countSubactionPaths ? sub : NULL;
            XrActionSet set = sets[byte(&r) % nsets];
            if (fv_xr_input_create_action(in, set, &ci, &acts[nacts]) == XR_SUCCESS) nacts++;
            break;
        }
        case 3: { /* suggested bindings */
            XrActionSuggestedBinding b[6];
            uint32_t n = 1 + byte(&r) % 6u;
            for (uint32_t i = 0; i < n; i++) {
                b[i].action = nacts ? acts[byte(&r) % nacts] : (XrAction)(uintptr_t)byte(&r);
                b[i].binding = some_path(in, &r);
            }
            XrInteractionProfileSuggestedBinding sb = {.type = XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING,
                                                       .interactionProfile =
                                                           path_of(in, profiles[byte(&r) % N(profiles)]),
                                                       .countSuggestedBindings = n,
                                                       .suggestedBindings = b};
            (void)fv_xr_input_suggest_bindings(in, &sb);
            break;
        }
        case 4: { /* attach */
            if (!s || nsets == 0) break;
            XrActionSet list[4];
            uint32_t n = 1 + byte(&r) % 4u;
            for (uint32_t i = 0; i < n; i++) list[i] = sets[byte(&r) % nsets];
            XrSessionActionSetsAttachInfo ai = {.type = XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO,
                                                .countActionSets = n,
                                                .actionSets = list};
            (void)fv_xr_input_attach(s, &ai);
            break;
        }
        case 5:
        case 6: { /* sync, with hostile device values */
            if (!s) break;
            XrActiveActionSet as[4];
            uint32_t n = nsets ? byte(&r) % 5u : 0;
            for (uint32_t i = 0; i < n; i++) {
                as[i].actionSet = sets[byte(&r) % nsets];
                as[i].subactionPath = byte(&r) & 1 ? XR_NULL_PATH : path_of(in, users[byte(&r) % N(users)]);
            }
            fv_xr_input_devices dev = {.eye_gaze_present = byte(&r) & 1, .hands_present = {byte(&r) & 1, byte(&r) & 1},
                                       .time = (XrTime)byte(&r) << 20};
            static const char *const hp[] = {NULL, "/interaction_profiles/oculus/touch_controller",
                                             "/interaction_profiles/valve/index_controller", "/not/a/profile"};
            dev.hand_profiles[0] = hp[byte(&r) % 4];
            dev.hand_profiles[1] = hp[byte(&r) % 4];
            uint32_t nv = byte(&r) % 8u;
            for (uint32_t i = 0; i < nv; i++) {
                vals[i].path = val_paths[byte(&r) % 8];
                vals[i].value = any_float(&r);
                vals[i].changed_time = byte(&r);
            }
            dev.values = vals;
            dev.value_count = nv;
            XrActionsSyncInfo si = {.type = XR_TYPE_ACTIONS_SYNC_INFO, .countActiveActionSets = n,
                                    .activeActionSets = n ? as : NULL};
            if (op == 5) {
                (void)fv_xr_input_sync(s, &si, &dev);
            } else {
                fv_xr_input_update_profiles(s, &dev);
                XrResult res = fv_xr_input_sync_unfocused(s, &si);
                if (res == XR_SUCCESS) abort(); /* never plain success when unfocused */
            }
            (void)fv_xr_input_take_profile_changed(s);
            break;
        }
        case 7: { /* state queries of every type, on any action */
            if (!s || nacts == 0) break;
            XrActionStateGetInfo g = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = acts[byte(&r) % nacts],
                                      .subactionPath = byte(&r) & 1 ? XR_NULL_PATH : some_path(in, &r)};
            XrActionStateBoolean sb = {.type = XR_TYPE_ACTION_STATE_BOOLEAN};
            if (fv_xr_input_get_boolean(s, &g, &sb) == XR_SUCCESS) {
                check_common(sb.isActive, sb.changedSinceLastSync, sb.lastChangeTime);
                if (sb.currentState > 1 || (!sb.isActive && sb.currentState)) abort();
            }
            XrActionStateFloat sf = {.type = XR_TYPE_ACTION_STATE_FLOAT};
            if (fv_xr_input_get_float(s, &g, &sf) == XR_SUCCESS) {
                check_common(sf.isActive, sf.changedSinceLastSync, sf.lastChangeTime);
                if (!isfinite(sf.currentState) || fabsf(sf.currentState) > 1.0f) abort();
                if (!sf.isActive && sf.currentState != 0.0f) abort();
            }
            XrActionStateVector2f sv = {.type = XR_TYPE_ACTION_STATE_VECTOR2F};
            if (fv_xr_input_get_vector2f(s, &g, &sv) == XR_SUCCESS) {
                check_common(sv.isActive, sv.changedSinceLastSync, sv.lastChangeTime);
                if (!isfinite(sv.currentState.x) || !isfinite(sv.currentState.y)) abort();
                if (fabsf(sv.currentState.x) > 1.0f || fabsf(sv.currentState.y) > 1.0f) abort();
            }
            XrActionStatePose sp = {.type = XR_TYPE_ACTION_STATE_POSE};
            if (fv_xr_input_get_pose(s, &g, &sp) == XR_SUCCESS && sp.isActive > 1) abort();
            fv_xr_pose_source ps = fv_xr_input_pose_source(s, g.action, g.subactionPath);
            if ((int)ps < FV_XR_POSE_NONE || ps > FV_XR_POSE_RIGHT_AIM) abort();
            break;
        }
        case 8: /* destroy an action handle (maybe twice) */
            if (nacts) (void)fv_xr_input_destroy_action(in, acts[byte(&r) % nacts]);
            break;
        case 9: /* destroy a set handle (maybe twice) */
            if (nsets) (void)fv_xr_input_destroy_action_set(in, sets[byte(&r) % nsets]);
            break;
        case 10: { /* bound sources, two calls */
            if (!s || nacts == 0) break;
            XrBoundSourcesForActionEnumerateInfo e = {.type = XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO,
                                                      .action = acts[byte(&r) % nacts]};
            uint32_t n = 0;
            if (fv_xr_input_enumerate_bound_sources(s, &e, 0, &n, NULL) == XR_SUCCESS && n > 0) {
                XrPath *src = calloc(n, sizeof *src);
                uint32_t m = 0;
                if (src && fv_xr_input_enumerate_bound_sources(s, &e, n, &m, src) != XR_SUCCESS) abort();
                if (src && m != n) abort();
                free(src);
            }
            break;
        }
        case 11: { /* localized names */
            if (!s) break;
            XrInputSourceLocalizedNameGetInfo g = {.type = XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO,
                                                   .sourcePath = some_path(in, &r),
                                                   .whichComponents = byte(&r) % 9u};
            char buf[256];
            uint32_t n = 0;
            if (fv_xr_input_get_localized_name(s, &g, sizeof buf, &n, buf) == XR_SUCCESS && strlen(buf) + 1 != n)
                abort();
            break;
        }
        case 12: { /* haptics */
            if (!s || nacts == 0) break;
            XrHapticActionInfo h = {.type = XR_TYPE_HAPTIC_ACTION_INFO, .action = acts[byte(&r) % nacts],
                                    .subactionPath = byte(&r) & 1 ? XR_NULL_PATH : some_path(in, &r)};
            XrHapticVibration v = {.type = byte(&r) & 1 ? XR_TYPE_HAPTIC_VIBRATION : XR_TYPE_ACTION_STATE_FLOAT,
                                   .duration = (XrDuration)(int8_t)byte(&r),
                                   .frequency = any_float(&r),
                                   .amplitude = any_float(&r)};
            (void)fv_xr_input_apply_haptic(s, &h, (const XrHapticBaseHeader *)&v);
            (void)fv_xr_input_stop_haptic(s, &h);
            break;
        }
        case 13: { /* action spaces */
            if (nacts == 0) break;
            XrActionSpaceCreateInfo ci = {.type = XR_TYPE_ACTION_SPACE_CREATE_INFO, .action = acts[byte(&r) % nacts],
                                          .subactionPath = some_path(in, &r),
                                          .poseInActionSpace = {.orientation = {any_float(&r), 0, 0, any_float(&r)}}};
            (void)fv_xr_input_check_action_space(in, &ci);
            break;
        }
        case 14: { /* sessions come and go */
            int k = byte(&r) & 1;
            if (sess[k])
                fv_xr_input_session_destroy(&sess[k]);
            else
                (void)fv_xr_input_session_create(in, &sess[k]);
            break;
        }
        default: { /* current profiles */
            if (!s) break;
            XrInteractionProfileState st = {.type = XR_TYPE_INTERACTION_PROFILE_STATE};
            (void)fv_xr_input_get_current_interaction_profile(s, some_path(in, &r), &st);
            break;
        }
        }
    }
    if (byte(&r) & 1) fv_xr_input_session_destroy(&sess[0]); /* else the instance frees it */
    fv_xr_input_destroy(&in);
    return 0;
}
