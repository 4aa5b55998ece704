/* @brief Helpers shared by the fv_xr_input tests: paths, action sets, actions and suggested bindings that must
   succeed (each fails the test with the call and its XrResult otherwise). */
#ifndef TEST_XR_INPUT_UTIL_H
#define TEST_XR_INPUT_UTIL_H

#include "fv_xr_input.h"

/** xrStringToPath that must succeed. */
XrPath xri_test_path(fv_xr_input *in, const char *s);
XrResult xri_test_try_set(fv_xr_input *in, const char *name, const char *lname, uint32_t priority, XrActionSet *out);
/** An action set named name, localized "Set <name>". */
XrActionSet xri_test_set(fv_xr_input *in, const char *name, uint32_t priority);
XrResult xri_test_try_action(fv_xr_input *in, XrActionSet set, const char *name, const char *lname, XrActionType t,
                             uint32_t nsub, const XrPath *sub, XrAction *out);
/** An action named name, localized "Action <name>". */
XrAction xri_test_action(fv_xr_input *in, XrActionSet set, const char *name, XrActionType t, uint32_t nsub,
                         const XrPath *sub);
/** xrSuggestInteractionProfileBindings with n bindings acts[i] -> paths[i] (at most 32); returns its result. */
XrResult xri_test_suggest(fv_xr_input *in, const char *profile, uint32_t n, const XrAction *acts,
                          const char *const *paths);
/** One binding that must be accepted. */
void xri_test_suggest_one(fv_xr_input *in, const char *profile, XrAction a, const char *path);

#endif
