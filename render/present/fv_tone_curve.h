/* @brief The display tone curve, one definition for the present shader (GLSL) and for C (tests, tools).
 *
 * Reinhard extended with a white point (Reinhard, Stark, Shirley & Ferwerda, "Photographic tone reproduction for
 * digital images", SIGGRAPH 2002, eq. 4), applied per channel to the exposed linear colour x:
 *
 *     f(x) = x (1 + x / W^2) / (1 + x),   W = FV_TONE_WHITE = 4
 *
 * Why this curve: it has one parameter with a physical meaning (the linear value that reaches display white:
 * 4 = two stops of highlight headroom above the old clip point 1.0, so a lit surface up to 4x display white keeps its
 * gradation instead of clipping to flat white); its slope is 1 at black (shadows are not crushed or lifted, no toe
 * that shifts hues); it is monotonic with f(W) = 1, and has a closed-form inverse, so the linear colour can be read
 * back from the display value. ACES fitted (Narkowicz 2015) was the alternative: its toe raises contrast but
 * darkens shadows and shifts hues per channel, and mid-grey lands far from where a linear image puts it.
 * Where things land (exposure 1 = 0 EV, the default): linear 0.18 (mid-grey) -> 0.1543 (sRGB code 109 of 255, the
 * old clamp gave 118); 1.0 -> 0.531 (code 193); 2.0 -> 0.75 (code 225); 4.0 -> 1.0 (255).
 * Inputs that are not finite and >= 0 are sanitized first: NaN and negative -> 0, +Inf and anything above
 * FV_TONE_MAX_INPUT -> FV_TONE_MAX_INPUT (white), so the display is always finite. */
#ifndef FV_TONE_CURVE_H
#define FV_TONE_CURVE_H

#define FV_TONE_WHITE 4.0
#define FV_TONE_MAX_INPUT 65504.0 /* the largest half float: the curve is 1 long before */

#if defined(GL_core_profile) || defined(VULKAN) || defined(GL_SPIRV)
#define FV_TONE_FN
#define FV_TONE_F(x) float(x)
#else
#include <math.h>
#define FV_TONE_FN static inline
#define FV_TONE_F(x) ((float)(x))
#endif

/* NaN and negative -> 0, +Inf and huge -> FV_TONE_MAX_INPUT */
FV_TONE_FN float fv_tone_sanitize(float x)
{
    if (isnan(x) || !(x > 0.0f)) return 0.0f;
    return x < FV_TONE_F(FV_TONE_MAX_INPUT) ? x : FV_TONE_F(FV_TONE_MAX_INPUT);
}

/* Reinhard extended, white point FV_TONE_WHITE; x finite and >= 0 (sanitize first); result in [0, 1] below the white
 * point, above 1 beyond it (the sRGB encoding clamps) */
FV_TONE_FN float fv_tone_reinhard_ext(float x)
{
    const float w2 = FV_TONE_F(FV_TONE_WHITE * FV_TONE_WHITE);
    return x * (1.0f + x / w2) / (1.0f + x);
}

#endif
