/* @brief Benchmark of fv_xr_input's per-frame work: one xrSyncActions and one state query per action and hand, for
 * hello_xr's action set and for larger synthetic apps (N actions on both hands, bound in five profiles, with Touch
 * controllers present and values changing every frame). Prints the median and p95 over repeated runs of
 * microseconds per frame. Not a test: timing is measured here, never asserted.
 * Usage: bench_xr_input [frames=2000] [repeats=7] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fv_xr_input.h"

#define LEFT "/user/hand/left"
#define RIGHT "/user/hand/right"

static double now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e6 + (double)ts.tv_nsec * 1e-3;
}

static XrPath P(fv_xr_input *in, const char *s)
{
    XrPath p = XR_NULL_PATH;
    if (fv_xr_input_string_to_path(in, s, &p) != XR_SUCCESS) {
        fprintf(stderr, "bad path %s\n", s);
        exit(1);
    }
    return p;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* One app: n float actions on both hands, each bound in five profiles (components cycling), one pose action. */
typedef struct app {
    fv_xr_input *in;
    fv_xr_input_session *s;
    XrActionSet set;
    XrAction *acts;
    uint32_t n;
    XrPath hands[2];
} app;

static void build(app *a, uint32_t n)
{
    memset(a, 0, sizeof *a);
    a->n = n;
    fv_xr_input_desc d = {0};
    if (fv_xr_input_create(&d, &a->in) != XR_SUCCESS || fv_xr_input_session_create(a->in, &a->s) != XR_SUCCESS) exit(1);
    XrActionSetCreateInfo si = {.type = XR_TYPE_ACTION_SET_CREATE_INFO, .actionSetName = "gameplay",
                                .localizedActionSetName = "Gameplay"};
    if (fv_xr_input_create_action_set(a->in, &si, &a->set) != XR_SUCCESS) exit(1);
    a->hands[0] = P(a->in, LEFT);
    a->hands[1] = P(a->in, RIGHT);
    a->acts = calloc(n, sizeof *a->acts);
    for (uint32_t i = 0; i < n; i++) {
        XrActionCreateInfo ci = {.type = XR_TYPE_ACTION_CREATE_INFO, .actionType = XR_ACTION_TYPE_FLOAT_INPUT,
                                 .countSubactionPaths = 2, .subactionPaths = a->hands};
        snprintf(ci.actionName, sizeof ci.actionName, "a%u", i);
        snprintf(ci.localizedActionName, sizeof ci.localizedActionName, "A %u", i);
        if (fv_xr_input_create_action(a->in, a->set, &ci, &a->acts[i]) != XR_SUCCESS) exit(1);
    }
    static const struct {
        const char *profile;
        const char *comps[4];
    } prof[5] = {
        {"/interaction_profiles/khr/simple_controller", {"/input/select/click", "/input/menu/click", NULL, NULL}},
        {"/interaction_profiles/oculus/touch_controller",
         {"/input/squeeze/value", "/input/trigger/value", "/input/thumbstick/x", "/input/thumbstick/y"}},
        {"/interaction_profiles/htc/vive_controller", {"/input/trigger/value", "/input/trackpad/x", NULL, NULL}},
        {"/interaction_profiles/valve/index_controller",
         {"/input/squeeze/force", "/input/trigger/value", "/input/trackpad/x", "/input/thumbstick/y"}},
        {"/interaction_profiles/microsoft/motion_controller",
         {"/input/trigger/value", "/input/thumbstick/x", "/input/trackpad/y", NULL}},
    };
    XrActionSuggestedBinding *b = calloc(2 * (size_t)n, sizeof *b);
    for (int p = 0; p < 5; p++) {
        int nc = 0;
        while (nc < 4 && prof[p].comps[nc]) nc++;
        for (uint32_t i = 0; i < n; i++) {
            for (int h = 0; h < 2; h++) {
                char path[128];
                snprintf(path, sizeof path, "%s%s", h ? RIGHT : LEFT, prof[p].comps[i % (uint32_t)nc]);
                b[2 * i + h] = (XrActionSuggestedBinding){a->acts[i], P(a->in, path)};
            }
        }
        XrInteractionProfileSuggestedBinding sb = {.type = XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING,
                                                   .interactionProfile = P(a->in, prof[p].profile),
                                                   .countSuggestedBindings = 2 * n,
                                                   .suggestedBindings = b};
        if (fv_xr_input_suggest_bindings(a->in, &sb) != XR_SUCCESS) exit(1);
    }
    free(b);
    XrSessionActionSetsAttachInfo ai = {.type = XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO, .countActionSets = 1,
                                        .actionSets = &a->set};
    if (fv_xr_input_attach(a->s, &ai) != XR_SUCCESS) exit(1);
}

static void destroy(app *a)
{
    fv_xr_input_session_destroy(&a->s);
    fv_xr_input_destroy(&a->in);
    free(a->acts);
}

/* frames frames of: sync (values changing), then one float query per action and hand; microseconds per frame. */
static double run(app *a, int frames, double *sink)
{
    static const char *const vals[4] = {LEFT "/input/squeeze/value", RIGHT "/input/trigger/value",
                                        LEFT "/input/thumbstick/x", RIGHT "/input/thumbstick/y"};
    fv_xr_input_value v[4];
    fv_xr_input_devices dev = {.hands_present = {true, true},
                               .hand_profiles = {"/interaction_profiles/oculus/touch_controller",
                                                 "/interaction_profiles/oculus/touch_controller"},
                               .values = v,
                               .value_count = 4};
    XrActiveActionSet as = {a->set, XR_NULL_PATH};
    XrActionsSyncInfo si = {.type = XR_TYPE_ACTIONS_SYNC_INFO, .countActiveActionSets = 1, .activeActionSets = &as};
    double t0 = now_us();
    for (int f = 0; f < frames; f++) {
        for (int k = 0; k < 4; k++) v[k] = (fv_xr_input_value){vals[k], (float)((f + k) % 10) * 0.1f, 0};
        dev.time = (XrTime)f * 11111111;
        if (fv_xr_input_sync(a->s, &si, &dev) != XR_SUCCESS) exit(1);
        for (uint32_t i = 0; i < a->n; i++) {
            for (int h = 0; h < 2; h++) {
                XrActionStateGetInfo g = {.type = XR_TYPE_ACTION_STATE_GET_INFO, .action = a->acts[i],
                                          .subactionPath = a->hands[h]};
                XrActionStateFloat st = {.type = XR_TYPE_ACTION_STATE_FLOAT};
                if (fv_xr_input_get_float(a->s, &g, &st) != XR_SUCCESS) exit(1);
                *sink += st.currentState;
            }
        }
    }
    return (now_us() - t0) / frames;
}

int main(int argc, char **argv)
{
    int frames = argc > 1 ? atoi(argv[1]) : 2000;
    int repeats = argc > 2 ? atoi(argv[2]) : 7;
    if (frames < 1 || repeats < 1 || repeats > 64) {
        fprintf(stderr, "usage: %s [frames>=1] [repeats 1..64]\n", argv[0]);
        return 2;
    }
    static const uint32_t sizes[] = {4, 64, 256, 1024};
    const int ns = (int)(sizeof sizes / sizeof sizes[0]);
    app apps[4];
    for (int k = 0; k < ns; k++) build(&apps[k], sizes[k]);
    double t[4][64], sink = 0;
    /* the sizes alternate within each repeat, so machine load hits them alike */
    for (int r = 0; r < repeats; r++)
        for (int k = 0; k < ns; k++) t[k][r] = run(&apps[k], sizes[k] >= 1024 ? frames / 8 + 1 : frames, &sink);
    printf("actions  bindings  us/frame median  p95 (sync + %s)\n", "one float query per action and hand");
    for (int k = 0; k < ns; k++) {
        qsort(t[k], (size_t)repeats, sizeof t[k][0], cmp_double);
        printf("%7u  %8u  %15.2f  %5.2f\n", sizes[k], sizes[k] * 10, t[k][repeats / 2],
               t[k][(repeats * 95 + 99) / 100 - 1]);
    }
    for (int k = 0; k < ns; k++) destroy(&apps[k]);
    return sink < 0 ? 1 : 0;
}
