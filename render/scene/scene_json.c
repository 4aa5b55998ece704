/* @brief `*.scene.json` (cJSON): compose built-in scenes and model files with per-object transforms, material
 * overrides (translucency presets or coefficients), animations, lights and the head pose. Format: docs/scene-file.md.
 * Every problem is reported with the file, the JSON path and the reason; parsing goes on to report them all, then
 * the load fails. Unknown keys are warnings. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "fv_file.h"
#include "fv_json_scan.h"
#include "fv_log.h"
#include "fv_scene.h"
#include "scene_internal.h"

#define JPATH_MAX 256
#define MAX_SCENE_FILE_BYTES (16u * 1024u * 1024u)
/* JSON values (numbers, strings, arrays, objects...) a scene file may hold: each costs cJSON ~80 bytes, so a 16 MiB
 * file of "0," would take 650 MB before any check. 65536 objects with every field set stay under it. */
#define MAX_JSON_VALUES (4u * 1024u * 1024u)

typedef struct jctx {
    const char *origin;   /* file name for messages */
    const char *base_dir; /* model paths resolve against this ("" = current directory) */
    bool allow_files;
    bool full; /* the scene reached a FV_SCENE_MAX_* limit: later objects are not loaded */
    int errors;
} jctx;

#define JERR(c, path, ...)                                                                                             \
    do {                                                                                                               \
        char msg_[1200];                                                                                               \
        if (snprintf(msg_, sizeof msg_, __VA_ARGS__) < 0) msg_[0] = '\0';                                              \
        FV_ERROR("scene", "%s: %s: %s", (c)->origin, (path), msg_);                                                    \
        (c)->errors++;                                                                                                 \
    } while (0)

static void jpath(char *out, const char *parent, const char *key)
{
    int n = (parent && *parent) ? snprintf(out, JPATH_MAX, "%s.%s", parent, key) : snprintf(out, JPATH_MAX, "%s", key);
    if (n < 0) out[0] = '\0'; /* a path longer than JPATH_MAX is cut; it is only a message */
}

static const char *type_name(const cJSON *j)
{
    if (!j) return "nothing";
    if (cJSON_IsNumber(j)) return "a number";
    if (cJSON_IsString(j)) return "a string";
    if (cJSON_IsArray(j)) return "an array";
    if (cJSON_IsObject(j)) return "an object";
    if (cJSON_IsBool(j)) return "a boolean";
    if (cJSON_IsNull(j)) return "null";
    return "an unknown value";
}

/* Warn about keys this object does not know. `known` is NULL-terminated. */
static void check_keys(jctx *c, const cJSON *obj, const char *path, const char *const *known)
{
    const cJSON *it;
    cJSON_ArrayForEach(it, obj)
    {
        bool ok = false;
        for (const char *const *k = known; *k; k++)
            if (it->string && !strcmp(it->string, *k)) ok = true;
        if (!ok) {
            char p[JPATH_MAX];
            jpath(p, path, it->string ? it->string : "?");
            FV_WARN("scene", "%s: %s: unknown key; ignored", c->origin, p);
        }
    }
}

/* NUM_COORD: a position in metres, |v| <= FV_SCENE_MAX_COORD_M; NUM_SIZE: a scale factor in (0, that bound]. */
/* NUM_SIGMA: a translucency coefficient, fv_translucency_coefficient_problem's range (checked on the double, before
 * a denormal would turn into a float 0). */
enum { NUM_ANY = 0, NUM_NONNEG = 1, NUM_POSITIVE = 2, NUM_COORD = 3, NUM_SIZE = 4, NUM_SIGMA = 5 };

static bool check_number(jctx *c, const cJSON *j, const char *path, int rule, float *out)
{
    if (!cJSON_IsNumber(j)) {
        JERR(c, path, "expected a number, got %s", type_name(j));
        return false;
    }
    double v = j->valuedouble;
    if (!isfinite(v)) {
        JERR(c, path, "%g is not a finite number", v);
        return false;
    }
    if (fabs(v) > 3.0e38) { /* finite, but not as a float */
        JERR(c, path, "%g is beyond the float range (+-3e+38)", v);
        return false;
    }
    const char *why = rule == NUM_SIGMA ? fv_translucency_coefficient_problem(v) : NULL;
    if (why) {
        JERR(c, path, "%g %s", v, why);
        return false;
    }
    if (rule == NUM_NONNEG && v < 0) {
        JERR(c, path, "%g is negative; it must be >= 0", v);
        return false;
    }
    if ((rule == NUM_POSITIVE || rule == NUM_SIZE) && !(v > 0)) {
        JERR(c, path, "%g must be > 0", v);
        return false;
    }
    if ((rule == NUM_COORD || rule == NUM_SIZE) && fabs(v) > FV_SCENE_MAX_COORD_M) {
        if (rule == NUM_COORD)
            JERR(c, path, "%g m is outside -%g..%g m, the bound of a position (no renderer keeps precision past it)", v,
                 FV_SCENE_MAX_COORD_M, FV_SCENE_MAX_COORD_M);
        else
            JERR(c, path, "%g is more than %g, the largest scale (no renderer keeps precision past it)", v,
                 FV_SCENE_MAX_COORD_M);
        return false;
    }
    *out = (float)v;
    return true;
}

/* Optional number member: absent leaves *out alone and returns true. */
static bool opt_number(jctx *c, const cJSON *obj, const char *parent, const char *key, int rule, float *out)
{
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!j) return true;
    char p[JPATH_MAX];
    jpath(p, parent, key);
    return check_number(c, j, p, rule, out);
}

static bool parse_vec(jctx *c, const cJSON *j, const char *path, int n, int rule, float *out)
{
    if (!cJSON_IsArray(j)) {
        JERR(c, path, "expected an array of %d numbers, got %s", n, type_name(j));
        return false;
    }
    int count = cJSON_GetArraySize(j);
    if (count != n) {
        JERR(c, path, "expected %d numbers, got %d", n, count);
        return false;
    }
    bool ok = true;
    for (int i = 0; i < n; i++) {
        char p[JPATH_MAX];
        snprintf(p, sizeof p, "%s[%d]", path, i);
        if (!check_number(c, cJSON_GetArrayItem(j, i), p, rule, &out[i])) ok = false;
    }
    return ok;
}

static bool opt_vec3(jctx *c, const cJSON *obj, const char *parent, const char *key, int rule, fv_vec3 *out)
{
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!j) return true;
    char p[JPATH_MAX];
    jpath(p, parent, key);
    float v[3];
    if (!parse_vec(c, j, p, 3, rule, v)) return false;
    *out = fv_v3(v[0], v[1], v[2]);
    return true;
}

static bool opt_string(jctx *c, const cJSON *obj, const char *parent, const char *key, const char **out)
{
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!j) return true;
    if (!cJSON_IsString(j) || !j->valuestring) {
        char p[JPATH_MAX];
        jpath(p, parent, key);
        JERR(c, p, "expected a string, got %s", type_name(j));
        return false;
    }
    *out = j->valuestring;
    return true;
}

static bool expect_object(jctx *c, const cJSON *j, const char *path)
{
    if (cJSON_IsObject(j)) return true;
    JERR(c, path, "expected an object, got %s", type_name(j));
    return false;
}

/* ---- pieces ----------------------------------------------------------------------------------------------- */

static void parse_translucency(jctx *c, const cJSON *j, const char *path, fv_translucency *out)
{
    static const char *const keys[] = {"preset", "sigma_a_per_mm", "sigma_s_prime_per_mm", "eta", NULL};
    if (!expect_object(c, j, path)) return;
    check_keys(c, j, path, keys);
    int before = c->errors;
    fv_translucency t;
    memset(&t, 0, sizeof t);
    const char *preset = NULL;
    opt_string(c, j, path, "preset", &preset);
    if (preset) {
        if (fv_translucency_preset(preset, &t) < 0) {
            char p[JPATH_MAX];
            jpath(p, path, "preset");
            char known[256] = "";
            for (const char *const *n = fv_translucency_preset_names(); *n; n++) {
                strncat(known, *n, sizeof known - strlen(known) - 1);
                if (n[1]) strncat(known, ", ", sizeof known - strlen(known) - 1);
            }
            JERR(c, p, "unknown preset '%s' (known: %s)", preset, known);
            return;
        }
    } else {
        t.eta = 1.3f;
        if (!cJSON_GetObjectItemCaseSensitive(j, "sigma_a_per_mm") ||
            !cJSON_GetObjectItemCaseSensitive(j, "sigma_s_prime_per_mm")) {
            JERR(c, path, "needs a \"preset\" or both \"sigma_a_per_mm\" and \"sigma_s_prime_per_mm\"");
            return;
        }
    }
    /* Coefficients given next to a preset override it. */
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(j, "sigma_a_per_mm");
    const cJSON *s = cJSON_GetObjectItemCaseSensitive(j, "sigma_s_prime_per_mm");
    char p[JPATH_MAX];
    if (a) {
        jpath(p, path, "sigma_a_per_mm");
        parse_vec(c, a, p, 3, NUM_SIGMA, t.sigma_a_per_mm);
    }
    if (s) {
        jpath(p, path, "sigma_s_prime_per_mm");
        if (parse_vec(c, s, p, 3, NUM_SIGMA, t.sigma_s_prime_per_mm) &&
            !(t.sigma_s_prime_per_mm[0] > 0 || t.sigma_s_prime_per_mm[1] > 0 || t.sigma_s_prime_per_mm[2] > 0))
            JERR(c, p, "all three are zero; a translucent material must scatter");
    }
    opt_number(c, j, path, "eta", NUM_POSITIVE, &t.eta);
    if (preset && (a || s)) t.preset[0] = '\0'; /* no longer the preset's values */
    if (c->errors != before) return;
    t.enabled = true;
    *out = t;
}

static unsigned parse_material(jctx *c, const cJSON *j, const char *path, fv_material *out)
{
    static const char *const keys[] = {"base_color", "emissive", "translucency", NULL};
    if (!expect_object(c, j, path)) return 0;
    check_keys(c, j, path, keys);
    unsigned mask = 0;
    if (cJSON_GetObjectItemCaseSensitive(j, "base_color")) {
        if (opt_vec3(c, j, path, "base_color", NUM_NONNEG, &out->base_color)) {
            out->base_color = fv_v3_min(out->base_color, fv_v3(1, 1, 1));
            mask |= FV_MERGE_BASE_COLOR;
        }
    }
    if (cJSON_GetObjectItemCaseSensitive(j, "emissive")) {
        if (opt_vec3(c, j, path, "emissive", NUM_NONNEG, &out->emissive)) mask |= FV_MERGE_EMISSIVE;
    }
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(j, "translucency");
    if (t) {
        char p[JPATH_MAX];
        jpath(p, path, "translucency");
        if (cJSON_IsFalse(t) || cJSON_IsNull(t)) {
            memset(&out->translucency, 0, sizeof out->translucency);
            out->translucency.eta = 1.0f;
            mask |= FV_MERGE_TRANSLUCENCY;
        } else {
            int before = c->errors;
            parse_translucency(c, t, p, &out->translucency);
            if (c->errors == before) mask |= FV_MERGE_TRANSLUCENCY;
        }
    }
    return mask;
}

static void parse_animation(jctx *c, const cJSON *j, const char *path, fv_animation *out)
{
    static const char *const keys[] = {"rotate", "bob", "pulse", NULL};
    if (!expect_object(c, j, path)) return;
    check_keys(c, j, path, keys);
    int kinds = 0;
    char p[JPATH_MAX];
    const cJSON *r = cJSON_GetObjectItemCaseSensitive(j, "rotate");
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(j, "bob");
    const cJSON *u = cJSON_GetObjectItemCaseSensitive(j, "pulse");
    kinds = (r != NULL) + (b != NULL) + (u != NULL);
    if (kinds > 1) {
        JERR(c, path, "give one of \"rotate\", \"bob\" or \"pulse\", not %d", kinds);
        return;
    }
    float phase_deg = 0.0f;
    if (r) {
        static const char *const rk[] = {"axis", "deg_per_s", NULL};
        jpath(p, path, "rotate");
        if (!expect_object(c, r, p)) return;
        check_keys(c, r, p, rk);
        fv_vec3 axis = fv_v3(0, 1, 0);
        float rate = 0;
        opt_vec3(c, r, p, "axis", NUM_ANY, &axis);
        if (!(fv_v3_len(axis) > 1e-6f)) {
            char q[JPATH_MAX];
            jpath(q, p, "axis");
            JERR(c, q, "the axis is zero");
        }
        if (!cJSON_GetObjectItemCaseSensitive(r, "deg_per_s")) JERR(c, p, "missing \"deg_per_s\"");
        opt_number(c, r, p, "deg_per_s", NUM_ANY, &rate);
        out->kind = FV_ANIM_ROTATE;
        out->axis = fv_v3_normalize_or(axis, fv_v3(0, 1, 0));
        out->rate_rad_s = (float)fv_deg_to_rad(rate);
    } else if (b) {
        static const char *const bk[] = {"amplitude_m", "freq_hz", "phase_deg", NULL};
        jpath(p, path, "bob");
        if (!expect_object(c, b, p)) return;
        check_keys(c, b, p, bk);
        out->kind = FV_ANIM_BOB;
        out->amplitude_m = fv_v3(0, 0.05f, 0);
        out->freq_hz = 0.5f;
        opt_vec3(c, b, p, "amplitude_m", NUM_COORD, &out->amplitude_m);
        opt_number(c, b, p, "freq_hz", NUM_NONNEG, &out->freq_hz);
        opt_number(c, b, p, "phase_deg", NUM_ANY, &phase_deg);
    } else if (u) {
        static const char *const uk[] = {"amplitude", "freq_hz", "phase_deg", NULL};
        jpath(p, path, "pulse");
        if (!expect_object(c, u, p)) return;
        check_keys(c, u, p, uk);
        out->kind = FV_ANIM_PULSE;
        float amp = 0.1f;
        out->freq_hz = 0.5f;
        opt_number(c, u, p, "amplitude", NUM_NONNEG, &amp);
        if (amp >= 1.0f) {
            char q[JPATH_MAX];
            jpath(q, p, "amplitude");
            JERR(c, q, "%g must be < 1 (the object would turn inside out)", (double)amp);
        }
        out->amplitude_m = fv_v3(amp, 0, 0);
        opt_number(c, u, p, "freq_hz", NUM_NONNEG, &out->freq_hz);
        opt_number(c, u, p, "phase_deg", NUM_ANY, &phase_deg);
    }
    out->phase_rad = (float)fv_deg_to_rad(fmod(phase_deg, 360.0));
}

static fv_quat euler_xyz_deg(fv_vec3 deg)
{
    /* Rotate about x, then y, then z (fixed parent axes): q = qz * qy * qx. */
    fv_quat qx = fv_quat_axis_angle(fv_v3(1, 0, 0), (float)fv_deg_to_rad(fmod(deg.x, 360.0)));
    fv_quat qy = fv_quat_axis_angle(fv_v3(0, 1, 0), (float)fv_deg_to_rad(fmod(deg.y, 360.0)));
    fv_quat qz = fv_quat_axis_angle(fv_v3(0, 0, 1), (float)fv_deg_to_rad(fmod(deg.z, 360.0)));
    return fv_quat_normalize(fv_quat_mul(qz, fv_quat_mul(qy, qx)));
}

/* Resolve a model path against the scene file's folder; false (after the error, naming the field) when the
 * result does not fit FV_SCENE_PATH_MAX: a cut path could name another file that exists. */
static bool resolve_path(jctx *c, const char *field, const char *model, char *out, size_t cap)
{
    bool relative = model[0] != '/' && c->base_dir && c->base_dir[0];
    int n = relative ? snprintf(out, cap, "%s/%s", c->base_dir, model) : snprintf(out, cap, "%s", model);
    if (n >= 0 && (size_t)n < cap) return true;
    JERR(c, field, "the model path is %d bytes%s, more than the %zu-byte limit ('%.60s...')", n,
         relative ? " once joined to the scene file's folder" : "", cap - 1, model);
    return false;
}

static void parse_object(jctx *c, fv_scene *dst, const cJSON *o, int index, float default_unit, bool *have_head,
                         fv_head *model_head)
{
    static const char *const keys[] = {"name", "model", "translate_m", "rotate_deg", "scale", "unit_scale_m",
                                       "material", "animate", "lights", NULL};
    char path[JPATH_MAX], p[JPATH_MAX];
    snprintf(path, sizeof path, "objects[%d]", index);
    if (!expect_object(c, o, path)) return;
    check_keys(c, o, path, keys);
    int before = c->errors;
    const char *model = NULL, *name = NULL;
    opt_string(c, o, path, "model", &model);
    opt_string(c, o, path, "name", &name);
    jpath(p, path, "model");
    if (!model && !cJSON_GetObjectItemCaseSensitive(o, "model")) JERR(c, p, "missing (a model file or \"builtin:NAME\")");
    if (model && !model[0]) JERR(c, p, "is empty (a model file or \"builtin:NAME\")");

    fv_node root = fv_node_default();
    fv_scene_copy_name(root.name, sizeof root.name, name ? name : (model ? model : path));
    opt_vec3(c, o, path, "translate_m", NUM_COORD, &root.translation_m);
    fv_vec3 rot = fv_v3(0, 0, 0);
    if (opt_vec3(c, o, path, "rotate_deg", NUM_ANY, &rot)) root.rotation = euler_xyz_deg(rot);
    const cJSON *sc = cJSON_GetObjectItemCaseSensitive(o, "scale");
    jpath(p, path, "scale");
    if (cJSON_IsArray(sc)) {
        opt_vec3(c, o, path, "scale", NUM_SIZE, &root.scale);
    } else if (sc) {
        float k;
        if (check_number(c, sc, p, NUM_SIZE, &k)) root.scale = fv_v3(k, k, k);
    }
    float unit = default_unit;
    opt_number(c, o, path, "unit_scale_m", NUM_SIZE, &unit);
    fv_material ov = fv_material_default();
    unsigned mask = 0;
    const cJSON *mat = cJSON_GetObjectItemCaseSensitive(o, "material");
    if (mat) {
        jpath(p, path, "material");
        mask = parse_material(c, mat, p, &ov);
    }
    const cJSON *anim = cJSON_GetObjectItemCaseSensitive(o, "animate");
    if (anim) {
        jpath(p, path, "animate");
        parse_animation(c, anim, p, &root.anim);
    }
    bool take_lights = true;
    const cJSON *tl = cJSON_GetObjectItemCaseSensitive(o, "lights");
    if (tl) {
        jpath(p, path, "lights");
        if (!cJSON_IsBool(tl))
            JERR(c, p, "expected a boolean (keep the model's lights), got %s", type_name(tl));
        else
            take_lights = cJSON_IsTrue(tl);
    }
    if (c->errors != before || !model) return;

    /* Load the model. */
    fv_scene *src = NULL;
    fv_result r;
    jpath(p, path, "model");
    if (!strncmp(model, "builtin:", 8)) {
        r = fv_scene_builtin(model + 8, &src);
        if (r < 0) {
            JERR(c, p, "'%s' is not a built-in scene", model);
            return;
        }
    } else {
        char full[FV_SCENE_PATH_MAX];
        if (!resolve_path(c, p, model, full, sizeof full)) return;
        if (!c->allow_files) {
            JERR(c, p, "model files are not allowed here ('%s')", full);
            return;
        }
        struct stat st;
        if (stat(full, &st) != 0) {
            JERR(c, p, "model file '%s' cannot be opened: %s", full, strerror(errno));
            return;
        }
        r = fv_scene_import_ex(full, unit, false, &src);
        if (r < 0) {
            JERR(c, p, "model file '%s' could not be loaded (%s; see above)", full, fv_result_str(r));
            return;
        }
    }
    if (src->head.from_file && !*have_head) {
        fv_mat4 w = fv_mat4_trs(root.translation_m, root.rotation, root.scale);
        *model_head = src->head;
        model_head->position_m = fv_mat4_mul_point(&w, src->head.position_m);
        model_head->orientation = fv_quat_normalize(fv_quat_mul(root.rotation, src->head.orientation));
        *have_head = true;
    }
    fv_scene_merge_desc md;
    memset(&md, 0, sizeof md);
    md.root = &root;
    md.override = mask ? &ov : NULL;
    md.override_mask = mask;
    md.take_lights = take_lights;
    r = fv_scene_merge(dst, src, &md);
    fv_scene_destroy(&src);
    if (r == FV_ERR_RANGE) c->full = true;
    if (r < 0) JERR(c, path, "could not add the object (%s)", fv_result_str(r));
}

static void parse_light(jctx *c, fv_scene *dst, const cJSON *j, int index)
{
    static const char *const keys[] = {"name", "type", "position_m", "direction", "look_at_m", "color", "intensity",
                                       "range_m", "cone_deg", NULL};
    char path[JPATH_MAX], p[JPATH_MAX];
    snprintf(path, sizeof path, "lights[%d]", index);
    if (!expect_object(c, j, path)) return;
    check_keys(c, j, path, keys);
    int before = c->errors;
    fv_light l;
    memset(&l, 0, sizeof l);
    snprintf(l.name, sizeof l.name, "light%d", index);
    const char *type = NULL, *name = NULL;
    opt_string(c, j, path, "name", &name);
    if (name) fv_scene_copy_name(l.name, sizeof l.name, name);
    opt_string(c, j, path, "type", &type);
    jpath(p, path, "type");
    if (!type) {
        if (!cJSON_GetObjectItemCaseSensitive(j, "type")) JERR(c, p, "missing (\"point\", \"spot\" or \"directional\")");
        return;
    }
    if (!strcmp(type, "point"))
        l.type = FV_LIGHT_POINT;
    else if (!strcmp(type, "spot"))
        l.type = FV_LIGHT_SPOT;
    else if (!strcmp(type, "directional"))
        l.type = FV_LIGHT_DIRECTIONAL;
    else {
        JERR(c, p, "unknown light type '%s' (point, spot, directional)", type);
        return;
    }
    l.color = fv_v3(1, 1, 1);
    l.intensity = 1.0f;
    l.direction = fv_v3(0, -1, 0);
    l.inner_cone_rad = (float)fv_deg_to_rad(30.0);
    l.outer_cone_rad = (float)fv_deg_to_rad(45.0);
    opt_vec3(c, j, path, "position_m", NUM_COORD, &l.position_m);
    opt_vec3(c, j, path, "color", NUM_NONNEG, &l.color);
    opt_number(c, j, path, "intensity", NUM_NONNEG, &l.intensity);
    opt_number(c, j, path, "range_m", NUM_NONNEG, &l.range_m);
    const cJSON *dir = cJSON_GetObjectItemCaseSensitive(j, "direction");
    const cJSON *at = cJSON_GetObjectItemCaseSensitive(j, "look_at_m");
    if (dir && at) JERR(c, path, "give \"direction\" or \"look_at_m\", not both");
    fv_vec3 d = l.direction;
    if (dir && opt_vec3(c, j, path, "direction", NUM_ANY, &d) && !(fv_v3_len(d) > 1e-6f)) {
        jpath(p, path, "direction");
        JERR(c, p, "the direction is zero");
    }
    fv_vec3 target;
    if (at && opt_vec3(c, j, path, "look_at_m", NUM_COORD, &target)) {
        d = fv_v3_sub(target, l.position_m);
        if (!(fv_v3_len(d) > 1e-6f)) {
            jpath(p, path, "look_at_m");
            JERR(c, p, "the target is at the light's position");
        }
    }
    l.direction = fv_v3_normalize_or(d, fv_v3(0, -1, 0));
    const cJSON *cone = cJSON_GetObjectItemCaseSensitive(j, "cone_deg");
    if (cone) {
        jpath(p, path, "cone_deg");
        float v[2];
        if (parse_vec(c, cone, p, 2, NUM_NONNEG, v)) {
            if (!(v[0] <= v[1] && v[1] <= 90.0f))
                JERR(c, p, "needs 0 <= inner <= outer <= 90 degrees (half-angles from the axis), got [%g, %g]",
                     (double)v[0], (double)v[1]);
            l.inner_cone_rad = (float)fv_deg_to_rad(v[0]);
            l.outer_cone_rad = (float)fv_deg_to_rad(v[1]);
        }
    }
    if (c->errors != before) return;
    if (fv_scene_add_light(dst, &l, NULL) < 0) JERR(c, path, "could not add the light");
}

static void parse_head(jctx *c, fv_scene *s, const cJSON *j)
{
    static const char *const keys[] = {"position_m", "look_at_m", "roll_deg", "ipd_mm", NULL};
    if (!expect_object(c, j, "head")) return;
    check_keys(c, j, "head", keys);
    fv_vec3 pos = s->head.position_m, at = fv_v3(0, 0, 0);
    bool has_pos = cJSON_GetObjectItemCaseSensitive(j, "position_m") != NULL;
    bool has_at = cJSON_GetObjectItemCaseSensitive(j, "look_at_m") != NULL;
    bool ok = opt_vec3(c, j, "head", "position_m", NUM_COORD, &pos);
    ok = opt_vec3(c, j, "head", "look_at_m", NUM_COORD, &at) && ok;
    float ipd = s->head.ipd_mm;
    if (opt_number(c, j, "head", "ipd_mm", NUM_POSITIVE, &ipd) && ipd > FV_SCENE_MAX_IPD_MM)
        JERR(c, "head.ipd_mm", "%g mm is more than the %g mm limit", (double)ipd, (double)FV_SCENE_MAX_IPD_MM);
    s->head.ipd_mm = ipd;
    if (!ok) return;
    if (has_at && !has_pos) {
        JERR(c, "head.look_at_m", "needs \"position_m\" too");
        return;
    }
    if (has_pos && !has_at) at = fv_v3_add(pos, fv_v3(0, 0, -1));
    if (has_pos || has_at) {
        if (has_pos && has_at && !(fv_v3_len(fv_v3_sub(at, pos)) > 1e-6f))
            JERR(c, "head.look_at_m", "the target is at the head position");
        fv_scene_head_look_at(&s->head, pos, at);
        s->head.from_file = true;
    }
    float roll = 0.0f;
    if (opt_number(c, j, "head", "roll_deg", NUM_ANY, &roll) && !(roll >= -180.0f && roll <= 180.0f))
        JERR(c, "head.roll_deg", "%g is not in -180..180", (double)roll);
    else if (roll != 0.0f) /* about the line of sight: positive tilts the head's up toward its right (+x) */
        s->head.orientation = fv_quat_normalize(
            fv_quat_mul(s->head.orientation, fv_quat_axis_angle(fv_v3(0, 0, 1), (float)fv_deg_to_rad(-roll))));
}

static fv_result parse_json(jctx *cp, const char *json, size_t len, fv_scene **out_scene);

fv_result fv_scene_parse_json(const char *json, size_t len, const char *base_dir, const char *origin,
                              bool allow_model_files, fv_scene **out_scene)
{
    if (!out_scene) return FV_ERR_INVALID_ARG;
    *out_scene = NULL;
    jctx c = {origin && *origin ? origin : "<buffer>", base_dir ? base_dir : "", allow_model_files, false, 0};
    if (!json) {
        FV_ERROR("scene", "%s: no scene text", c.origin);
        return FV_ERR_INVALID_ARG;
    }
    if (strlen(c.origin) >= FV_SCENE_PATH_MAX) { /* the scene's source, and the folder its models resolve from */
        FV_ERROR("scene", "%.60s...: the scene file's path is %zu bytes, more than the %d-byte limit", c.origin,
                 strlen(c.origin), FV_SCENE_PATH_MAX - 1);
        return FV_ERR_RANGE;
    }
    /* Every message of the load (this file's and its model files') passes one budget: a few of each kind, then
     * one "... and N more" line each, then the count. */
    fv_log_budget budget;
    fv_log_budget_begin(&budget, c.origin, 0);
    fv_result r = parse_json(&c, json, len, out_scene);
    fv_log_budget_end(&budget);
    if (c.errors)
        FV_ERROR("scene", "%s: %d problem%s; the scene is not loaded", c.origin, c.errors, c.errors == 1 ? "" : "s");
    return r;
}

static fv_result parse_json(jctx *cp, const char *json, size_t len, fv_scene **out_scene)
{
    jctx c = *cp;
    fv_result r = FV_OK;
    cJSON *root = NULL;
    fv_scene *s = NULL;
    fv_json_scan scan;
    fv_json_scan_text(json, len, CJSON_NESTING_LIMIT, &scan);
    int line, col;
    if (scan.too_deep_at != SIZE_MAX) {
        fv_text_line_col(json, scan.too_deep_at, &line, &col);
        FV_ERROR("scene", "%s: line %d column %d: invalid JSON: nested deeper than %d levels (the parser's limit)",
                 c.origin, line, col, CJSON_NESTING_LIMIT);
        return FV_ERR_PARSE;
    }
    if (scan.values > MAX_JSON_VALUES) {
        FV_ERROR("scene", "%s: about %zu JSON values, more than the %u a scene file may hold", c.origin, scan.values,
                 MAX_JSON_VALUES);
        return FV_ERR_RANGE;
    }
    if (scan.nul_at != SIZE_MAX) {
        fv_text_line_col(json, scan.nul_at, &line, &col);
        FV_ERROR("scene", "%s: line %d column %d: a string holds \\u0000 (a NUL character)%s, which names and paths "
                 "cannot carry; remove it", c.origin, line, col, scan.nul_count > 1 ? ", the first of several" : "");
        return FV_ERR_PARSE;
    }
    const char *end = NULL;
    root = cJSON_ParseWithLengthOpts(json, len, &end, 0);
    if (!root) {
        size_t off = (end && end >= json && end <= json + len) ? (size_t)(end - json) : 0;
        fv_text_line_col(json, off, &line, &col);
        /* cJSON points at the token where parsing stopped; when nothing but blanks follows it, the text was cut. */
        bool cut = true;
        for (size_t i = off + 1; i < len && cut; i++)
            if (json[i] != ' ' && json[i] != '\t' && json[i] != '\r' && json[i] != '\n') cut = false;
        if (off < len && cut) {
            /* still "cut" only if the stopping token itself could continue (an opener, a comma, a colon...) */
            cut = strchr("[{,:\"", json[off]) != NULL || json[off] == ' ' || json[off] == '\n';
        }
        if (scan.open_string_at != SIZE_MAX && off >= scan.open_string_at) {
            int sl, sc;
            fv_text_line_col(json, scan.open_string_at, &sl, &sc);
            FV_ERROR("scene", "%s: line %d column %d: invalid JSON (the text ends inside the string that starts "
                     "there: a missing '\"')", c.origin, sl, sc);
        } else if (off >= len || cut)
            FV_ERROR("scene", "%s: line %d column %d: invalid JSON (unexpected end of the text)", c.origin, line, col);
        else if ((unsigned char)json[off] >= 0x20 && (unsigned char)json[off] < 0x7f)
            FV_ERROR("scene", "%s: line %d column %d: invalid JSON (unexpected '%c')", c.origin, line, col, json[off]);
        else
            FV_ERROR("scene", "%s: line %d column %d: invalid JSON (unexpected byte 0x%02x)", c.origin, line, col,
                     (unsigned)(unsigned char)json[off]);
        return FV_ERR_PARSE;
    }
    if (!cJSON_IsObject(root)) {
        JERR(&c, "(root)", "expected an object, got %s", type_name(root));
        r = FV_ERR_PARSE;
        goto fail;
    }
    static const char *const keys[] = {"name", "unit_scale_m", "head", "objects", "lights", "ambient", NULL};
    check_keys(&c, root, "", keys);
    const char *name = NULL;
    opt_string(&c, root, "", "name", &name);
    if (!name) {
        const char *slash = strrchr(c.origin, '/');
        name = slash ? slash + 1 : c.origin;
    }
    if ((r = fv_scene_create(name, &s)) < 0) goto fail;
    fv_scene_copy_name(s->source, sizeof s->source, c.origin);
    float unit = 0.0f; /* 0: each model file's units are guessed */
    opt_number(&c, root, "", "unit_scale_m", NUM_SIZE, &unit);
    s->unit_scale_m = unit > 0 ? unit : 1.0f;
    opt_vec3(&c, root, "", "ambient", NUM_NONNEG, &s->ambient);

    bool have_model_head = false;
    fv_head model_head;
    memset(&model_head, 0, sizeof model_head);
    const cJSON *objects = cJSON_GetObjectItemCaseSensitive(root, "objects");
    if (!objects) {
        JERR(&c, "objects", "missing (an array of objects to draw)");
    } else if (!cJSON_IsArray(objects)) {
        JERR(&c, "objects", "expected an array, got %s", type_name(objects));
    } else if ((unsigned)cJSON_GetArraySize(objects) > FV_SCENE_MAX_ITEMS) { /* the limit before the work */
        JERR(&c, "objects", "%d objects is more than the limit of %u; none is loaded", cJSON_GetArraySize(objects),
             FV_SCENE_MAX_ITEMS);
    } else {
        int i = 0, n = cJSON_GetArraySize(objects);
        const cJSON *o;
        cJSON_ArrayForEach(o, objects)
        {
            if (c.full) {
                char p[JPATH_MAX];
                snprintf(p, sizeof p, "objects[%d]", i);
                JERR(&c, p, "not loaded, nor the %d after it: the scene reached its limits (see above)", n - 1 - i);
                break;
            }
            parse_object(&c, s, o, i++, unit, &have_model_head, &model_head);
        }
        if (n == 0) JERR(&c, "objects", "is empty; nothing to draw");
    }
    const cJSON *lights = cJSON_GetObjectItemCaseSensitive(root, "lights");
    if (lights && !cJSON_IsArray(lights)) {
        JERR(&c, "lights", "expected an array, got %s", type_name(lights));
    } else if (lights && (unsigned)cJSON_GetArraySize(lights) > FV_SCENE_MAX_ITEMS) {
        JERR(&c, "lights", "%d lights is more than the limit of %u; none is loaded", cJSON_GetArraySize(lights),
             FV_SCENE_MAX_ITEMS);
    } else if (lights) {
        int i = 0;
        const cJSON *l;
        cJSON_ArrayForEach(l, lights) parse_light(&c, s, l, i++);
    }
    if (have_model_head) s->head = model_head;
    const cJSON *head = cJSON_GetObjectItemCaseSensitive(root, "head");
    if (head) parse_head(&c, s, head);
    if (c.errors) {
        r = FV_ERR_PARSE;
        goto fail;
    }
    if (!s->head.from_file) fv_scene_frame_head(s);
    if (s->light_count == 0 && (r = fv_scene_add_default_lights(s, c.origin)) < 0) goto fail;
    if ((r = fv_scene_validate(s)) < 0) goto fail;
    cJSON_Delete(root);
    *cp = c;
    *out_scene = s;
    return FV_OK;
fail:
    cJSON_Delete(root);
    fv_scene_destroy(&s);
    *cp = c;
    return r;
}

fv_result fv_scene_load_json_buffer(const char *json, size_t len, const char *base_dir, const char *origin,
                                    fv_scene **out_scene)
{
    return fv_scene_parse_json(json, len, base_dir, origin, true, out_scene);
}

fv_result fv_scene_load_json_file(const char *path, fv_scene **out_scene)
{
    if (!out_scene) return FV_ERR_INVALID_ARG;
    *out_scene = NULL;
    if (!path) return FV_ERR_INVALID_ARG;
    char *buf;
    size_t n;
    char why[FV_FILE_ERR_MAX];
    fv_result rr = fv_file_read(path, "scene file", MAX_SCENE_FILE_BYTES, &buf, &n, why, sizeof why);
    if (rr != FV_OK) {
        FV_ERROR("scene", "%s%s", why, rr == FV_ERR_RANGE ? " for a scene file" : "");
        return rr;
    }
    char dir[FV_SCENE_PATH_MAX] = ".";
    const char *slash = strrchr(path, '/');
    if (slash) {
        size_t dl = (size_t)(slash - path);
        if (dl == 0) dl = 1; /* "/x.scene.json" */
        if (dl >= sizeof dir) dl = sizeof dir - 1;
        memcpy(dir, path, dl);
        dir[dl] = '\0';
    }
    fv_result r = fv_scene_parse_json(buf, n, dir, path, true, out_scene);
    free(buf);
    return r;
}
