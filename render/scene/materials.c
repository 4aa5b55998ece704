/* @brief Measured subsurface-scattering presets: the twelve materials of Jensen, Marschner, Levoy, Hanrahan,
 * "A Practical Model for Subsurface Light Transport", Proc. ACM SIGGRAPH 2001, pp. 511-518 (DOI
 * 10.1145/383259.383319), table of measured parameters (Fig. 5). Reduced scattering sigma_s' and absorption
 * sigma_a in mm^-1 per RGB channel, relative index of refraction eta. Transcribed from the team's
 * shared/data/materials/jensen2001.csv (see its PROVENANCE.md; tests/scene checks this table against it row by row).
 * eta: 1.5 for marble and 1.3 elsewhere, as the paper's table; only marble, the milks and skins were cross-checked. */
#include <ctype.h>
#include <math.h>
#include <string.h>

#include "fv_log.h"
#include "fv_scene.h"
#include "scene_internal.h"

typedef struct preset_row {
    const char *name;
    float sigma_s_prime_per_mm[3];
    float sigma_a_per_mm[3];
    float eta;
} preset_row;

static const preset_row g_presets[] = {
    {"Apple", {2.29f, 2.39f, 1.97f}, {0.0030f, 0.0034f, 0.046f}, 1.3f},
    {"Chicken1", {0.15f, 0.21f, 0.38f}, {0.015f, 0.077f, 0.19f}, 1.3f},
    {"Chicken2", {0.19f, 0.25f, 0.32f}, {0.018f, 0.088f, 0.20f}, 1.3f},
    {"Cream", {7.38f, 5.47f, 3.15f}, {0.0002f, 0.0028f, 0.0163f}, 1.3f},
    {"Ketchup", {0.18f, 0.07f, 0.03f}, {0.061f, 0.97f, 1.45f}, 1.3f},
    {"Marble", {2.19f, 2.62f, 3.00f}, {0.0021f, 0.0041f, 0.0071f}, 1.5f},
    {"Potato", {0.68f, 0.70f, 0.55f}, {0.0024f, 0.0090f, 0.12f}, 1.3f},
    {"Skimmilk", {0.70f, 1.22f, 1.90f}, {0.0014f, 0.0025f, 0.0142f}, 1.3f},
    {"Skin1", {0.74f, 0.88f, 1.01f}, {0.032f, 0.17f, 0.48f}, 1.3f},
    {"Skin2", {1.09f, 1.59f, 1.79f}, {0.013f, 0.070f, 0.145f}, 1.3f},
    {"Spectralon", {11.6f, 20.4f, 14.9f}, {0.00f, 0.00f, 0.00f}, 1.3f},
    {"Wholemilk", {2.55f, 3.21f, 3.77f}, {0.0011f, 0.0024f, 0.014f}, 1.3f},
};
#define PRESET_COUNT (sizeof g_presets / sizeof g_presets[0])

static const char *const g_preset_names[] = {"Apple", "Chicken1", "Chicken2", "Cream", "Ketchup", "Marble",
                                             "Potato", "Skimmilk", "Skin1", "Skin2", "Spectralon", "Wholemilk",
                                             NULL};
_Static_assert(sizeof g_preset_names / sizeof g_preset_names[0] == PRESET_COUNT + 1, "preset names match table");

const char *const *fv_translucency_preset_names(void) { return g_preset_names; }

static bool equal_nocase(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return false;
    return *a == *b;
}

fv_result fv_translucency_preset(const char *name, fv_translucency *out)
{
    if (!name || !out) return FV_ERR_INVALID_ARG;
    for (size_t i = 0; i < PRESET_COUNT; i++) {
        const preset_row *p = &g_presets[i];
        if (!equal_nocase(name, p->name)) continue;
        memset(out, 0, sizeof *out);
        out->enabled = true;
        memcpy(out->sigma_a_per_mm, p->sigma_a_per_mm, sizeof out->sigma_a_per_mm);
        memcpy(out->sigma_s_prime_per_mm, p->sigma_s_prime_per_mm, sizeof out->sigma_s_prime_per_mm);
        out->eta = p->eta;
        fv_scene_copy_name(out->preset, sizeof out->preset, p->name);
        return FV_OK;
    }
    return FV_ERR_NOT_FOUND;
}

const char *fv_translucency_coefficient_problem(double v)
{
    if (v == 0.0 || (v >= FV_SCENE_SIGMA_MIN_PER_MM && v <= FV_SCENE_SIGMA_MAX_PER_MM)) return NULL;
    if (isnan(v)) return "is not a number; a coefficient is 0 or in 1e-06..1e+06 mm^-1";
    if (v < 0) return "is negative; a coefficient is 0 or in 1e-06..1e+06 mm^-1";
    if (v < FV_SCENE_SIGMA_MIN_PER_MM)
        return "is below the smallest positive coefficient, 1e-06 mm^-1 (a coefficient is 0 or in 1e-06..1e+06 "
               "mm^-1: a mean free path over 1 km scatters nothing at a scene's scale, and the GPU's float dipole "
               "needs 1/sigma well inside the float range)";
    return "is more than the largest coefficient, 1e+06 mm^-1 (a coefficient is 0 or in 1e-06..1e+06 mm^-1)";
}
