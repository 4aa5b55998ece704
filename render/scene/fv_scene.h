/* @brief The in-memory scene: meshes, nodes with (animated) transforms, materials with an optional translucency
 * block, textures, lights, cameras, the head pose and IPD. Units: world space is metres after `unit_scale_m`
 * is applied by the loaders (positions are stored in metres). Right-handed, +y up.
 * Ownership: an fv_scene owns every array it points to; fv_scene_destroy frees them. Not thread-safe. */
#ifndef FV_SCENE_H
#define FV_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fv_math.h"
#include "fv_result.h"

#define FV_SCENE_NAME_MAX 64
#define FV_SCENE_PATH_MAX 512
/** Hard limits that protect against hostile files ("a huge count"). */
#define FV_SCENE_MAX_VERTICES (64u * 1024u * 1024u)
#define FV_SCENE_MAX_INDICES (192u * 1024u * 1024u)
#define FV_SCENE_MAX_ITEMS 65536u /* meshes, nodes, materials, lights, textures each */
#define FV_SCENE_MAX_TEXTURE_DIM 16384u
/** The largest |coordinate| in metres of any position a scene holds or makes: world-space vertices at t = 0, node
 *  translations and animation amplitudes, light, camera and head positions; and the largest node scale factor.
 *  1000 km: a float's step there is 6 cm, further out nothing draws sensibly (the GPU's depth and shading lose
 *  their precision; Embree refuses rays past 1.8e18). Loaders refuse a scene beyond it, naming the item. */
#define FV_SCENE_MAX_COORD_M 1.0e6
/** Absorption and reduced scattering coefficients (mm^-1) are 0 or in [FV_SCENE_SIGMA_MIN_PER_MM,
 *  FV_SCENE_SIGMA_MAX_PER_MM]. Below the minimum (a mean free path over 1 km) nothing scatters at any scene's scale,
 *  and the GPU's float dipole squares depths of 1/sigma (up to 2700 times that for its virtual source): the minimum
 *  keeps them far inside the float range. A denormal (a float below 1.2e-38) is far below it and refused as such,
 *  not read as 0. The maximum is a mean free path of 1 nm. */
#define FV_SCENE_SIGMA_MIN_PER_MM 1e-6
#define FV_SCENE_SIGMA_MAX_PER_MM 1e6
/** Lights every pixel sums: the shade pass and the reference's model mode loop over all of a scene's lights (no
 *  culling), so a frame costs lights x pixels light evaluations. Past this many lights that is over 3e8 a frame at
 *  720x800 per eye, seconds a frame on a CPU rasteriser: fv_scene_warn_cost says so in one line with the estimate.
 *  The limit stays FV_SCENE_MAX_ITEMS (an offline reference render may want many lights), which is about 7.5e10
 *  evaluations a frame at the default size (~500 s a frame on lavapipe). The other per-pixel loops are capped by
 *  constants and knobs, not by the scene: shadow maps, GI's reflective shadow maps and SSS maps serve the first 4, 2
 *  and 4 lights, at most 7 SSS maps. */
#define FV_SCENE_LIGHTS_WARN 256
/** Interpupillary distance used when nothing says otherwise, and the largest accepted (millimetres). */
#define FV_SCENE_DEFAULT_IPD_MM 63.0f
#define FV_SCENE_MAX_IPD_MM 100.0f
/** Luminous efficacy used to turn glTF's photometric light units into fv_light's radiometric ones (lm/W, the
 *  555 nm peak; 1366 cd -> 2 W/sr, 2049 lux -> 3 W/m^2). */
#define FV_SCENE_LUMENS_PER_WATT 683.0f

typedef struct fv_mesh {
    char name[FV_SCENE_NAME_MAX];
    uint32_t vertex_count;
    uint32_t index_count; /* a multiple of 3: triangle list */
    fv_vec3 *positions;   /* vertex_count, object space, metres */
    fv_vec3 *normals;     /* vertex_count, unit; generated (area-weighted) when the file has none */
    fv_vec2 *texcoords;   /* vertex_count, or NULL; origin at the image's top-left (glTF convention) */
    uint32_t *indices;    /* index_count, each < vertex_count (validated) */
    uint32_t material;    /* index into fv_scene.materials */
    fv_vec3 bounds_min, bounds_max; /* object space */
} fv_mesh;

/** Subsurface scattering parameters (dipole, Jensen et al. 2001). Coefficients per RGB in mm^-1. */
typedef struct fv_translucency {
    bool enabled;
    float sigma_a_per_mm[3];       /* absorption, >= 0 */
    float sigma_s_prime_per_mm[3]; /* reduced scattering, >= 0, not all zero */
    float eta;                     /* relative index of refraction, > 0 (1.0 allowed) */
    char preset[32];               /* preset name it came from, or "" */
} fv_translucency;

typedef struct fv_material {
    char name[FV_SCENE_NAME_MAX];
    fv_vec3 base_color;         /* linear RGB albedo factor, [0,1] */
    int32_t base_color_texture; /* index into textures, or -1 */
    fv_vec3 emissive;           /* linear RGB emitted radiance factor (W/(m^2 sr)-ish); 0 when none */
    fv_translucency translucency;
} fv_material;

typedef struct fv_texture {
    char source[FV_SCENE_PATH_MAX]; /* file path or "embedded:N" */
    uint32_t width, height;
    uint8_t *rgba8; /* width*height*4, sRGB-encoded as in the file */
} fv_texture;

typedef enum fv_light_type {
    FV_LIGHT_POINT = 0,
    FV_LIGHT_SPOT = 1,
    FV_LIGHT_DIRECTIONAL = 2,
} fv_light_type;

typedef struct fv_light {
    char name[FV_SCENE_NAME_MAX];
    fv_light_type type;
    fv_vec3 position_m;  /* world; unused for directional */
    fv_vec3 direction;   /* world, unit, the way the light travels; unused for point */
    fv_vec3 color;       /* linear RGB, [0,1]-ish */
    float intensity;     /* point/spot: radiant intensity (W/sr); directional: irradiance (W/m^2). glTF
                          * (KHR_lights_punctual) candela and lux are divided by FV_SCENE_LUMENS_PER_WATT */
    float range_m;       /* 0 = infinite */
    float inner_cone_rad, outer_cone_rad; /* spot: full intensity inside inner, zero outside outer */
} fv_light;

typedef enum fv_anim_kind {
    FV_ANIM_NONE = 0,
    FV_ANIM_ROTATE = 1, /* rotate about `axis` through the node origin at `rate` rad/s */
    FV_ANIM_BOB = 2,    /* translate by amplitude_m * sin(2 pi freq_hz t + phase_rad) */
    FV_ANIM_PULSE = 3,  /* scale by 1 + amplitude (x component) * sin(2 pi freq_hz t + phase_rad): a deforming object */
} fv_anim_kind;

typedef struct fv_animation {
    fv_anim_kind kind;
    fv_vec3 axis;
    float rate_rad_s;
    fv_vec3 amplitude_m;
    float freq_hz;
    float phase_rad;
} fv_animation;

typedef struct fv_node {
    char name[FV_SCENE_NAME_MAX];
    int32_t mesh;     /* index into meshes, or -1 for a transform-only node */
    int32_t parent;   /* index into nodes (< this node's index), or -1 */
    fv_vec3 translation_m;
    fv_quat rotation;
    fv_vec3 scale;
    fv_animation anim; /* applied after the static TRS, in the node's parent frame */
} fv_node;

typedef struct fv_camera {
    char name[FV_SCENE_NAME_MAX];
    fv_vec3 position_m;
    fv_quat orientation; /* camera looks down its local -z, +y up */
    float yfov_rad;      /* 0 = use the HMD default */
    float near_m, far_m; /* 0 = automatic from scene bounds */
} fv_camera;

/** The viewer: a head pose (the point between the eyes) plus the interpupillary distance. */
typedef struct fv_head {
    fv_vec3 position_m;
    fv_quat orientation; /* head looks down its local -z */
    float ipd_mm;        /* default 63 */
    bool from_file;      /* set by a camera or the scene file; false = framed automatically from the bounds */
} fv_head;

typedef struct fv_scene {
    char name[FV_SCENE_NAME_MAX];
    char source[FV_SCENE_PATH_MAX]; /* file it came from, or "builtin:cornell" */
    float unit_scale_m;             /* metres per file unit applied at load (1 = file in metres) */
    fv_mesh *meshes;
    uint32_t mesh_count;
    fv_node *nodes;
    uint32_t node_count;
    fv_material *materials;
    uint32_t material_count;
    fv_texture *textures;
    uint32_t texture_count;
    fv_light *lights;
    uint32_t light_count;
    fv_camera *cameras;
    uint32_t camera_count;
    fv_head head;
    fv_vec3 ambient; /* constant ambient radiance (0 by default) */
} fv_scene;

/* ---- building ---------------------------------------------------------------------------------------------- */
/** Create an empty scene (head at origin, IPD 63 mm, unit scale 1). */
FV_MUST_CHECK fv_result fv_scene_create(const char *name, fv_scene **out_scene);
void fv_scene_destroy(fv_scene **scene);
/** Append and return the index (or a negative fv_result cast, via out). Arrays grow; pointers into them may move. */
FV_MUST_CHECK fv_result fv_scene_add_material(fv_scene *s, const fv_material *m, uint32_t *out_index);
/** Takes ownership of mesh->positions/normals/texcoords/indices (they must come from malloc), even on failure. */
FV_MUST_CHECK fv_result fv_scene_add_mesh(fv_scene *s, fv_mesh *mesh, uint32_t *out_index);
FV_MUST_CHECK fv_result fv_scene_add_node(fv_scene *s, const fv_node *n, uint32_t *out_index);
FV_MUST_CHECK fv_result fv_scene_add_light(fv_scene *s, const fv_light *l, uint32_t *out_index);
FV_MUST_CHECK fv_result fv_scene_add_camera(fv_scene *s, const fv_camera *c, uint32_t *out_index);
/** Takes ownership of tex->rgba8 (malloc'd), even on failure. */
FV_MUST_CHECK fv_result fv_scene_add_texture(fv_scene *s, fv_texture *tex, uint32_t *out_index);
/** A default material/node/light value (white Lambert, identity TRS, ...). */
fv_material fv_material_default(void);
fv_node fv_node_default(void);

/* ---- queries ----------------------------------------------------------------------------------------------- */
/** World matrix of a node at time t_s (animations and parents applied). */
fv_mat4 fv_scene_node_world(const fv_scene *s, uint32_t node, double t_s);
/** True when any node animates (the renderer then needs per-frame transforms and motion vectors). */
bool fv_scene_is_animated(const fv_scene *s);
/** True when any material referenced by a drawn mesh is translucent. */
bool fv_scene_has_translucency(const fv_scene *s);
/** World bounds at time t_s over every drawn node; false when the scene has nothing to draw. */
bool fv_scene_world_bounds(const fv_scene *s, double t_s, fv_vec3 *out_min, fv_vec3 *out_max);
/** Grow [lo, hi] by the world-space box of node `node`'s mesh bounds at time t_s (its 8 corners; non-finite corners
 *  skipped). `any` says whether lo/hi already hold a box; returns whether they do afterwards. */
bool fv_scene_node_bounds_grow(const fv_scene *s, uint32_t node, double t_s, fv_vec3 *lo, fv_vec3 *hi, bool any);
/** Total triangles over drawn nodes. */
uint64_t fv_scene_triangle_count(const fv_scene *s);
/** Check every invariant (indices in range, finite values, parents before children...). Logs each broken rule
 *  with the scene source and the item; returns FV_ERR_PARSE if any is broken. */
FV_MUST_CHECK fv_result fv_scene_validate(const fv_scene *s);
/** Check every position and size against FV_SCENE_MAX_COORD_M (non-finite ones fail too): node translations,
 *  scales and animation amplitudes, each drawn node's world bounds at t = 0, lights, cameras and the head. Logs each
 *  item beyond it (source, item, value, bound; at most 16 lines) and returns FV_ERR_RANGE, else FV_OK. Part of
 *  fv_scene_validate; renderers run it on scenes they did not load. */
FV_MUST_CHECK fv_result fv_scene_check_extent(const fv_scene *s);
/** Light evaluations a frame of both eyes costs at eye_w x eye_h per eye: lights x pixels (saturated). */
uint64_t fv_scene_light_evaluations(const fv_scene *s, uint32_t eye_w, uint32_t eye_h);
/** When the scene has more than FV_SCENE_LIGHTS_WARN lights, log one warning line and return true: `who` (the
 *  renderer that pays), the lights, the per-frame estimate at this size and at the default 720x800, and what to
 *  change. Called when a renderer takes the scene. */
bool fv_scene_warn_cost(const fv_scene *s, uint32_t eye_w, uint32_t eye_h, const char *who);
/** Place the head so the whole scene is in view (used when a file has no camera): it looks at the centre of the
 *  world bounds along -z from the +z side (or along +z from the -z side when clearly more triangle area faces -z,
 *  as for a box open towards -z), far enough that the bounding sphere fits the narrowest half-angle of the HMD
 *  default field of view. Keeps the IPD; clears head.from_file. */
void fv_scene_frame_head(fv_scene *s);
/** Set head->position_m and an orientation looking from position_m at target_m with +y up (degenerate input
 *  falls back to a valid basis). Leaves the IPD and from_file alone. */
void fv_scene_head_look_at(fv_head *head, fv_vec3 position_m, fv_vec3 target_m);

/* ---- loading ----------------------------------------------------------------------------------------------- */
/** Load by name or path: a built-in name ("cornell", "cornell-translucent"), a `*.scene.json` file, or a model
 *  file assimp reads (.gltf/.glb/.obj/.ply ...). Errors name the file, the field and the reason. */
FV_MUST_CHECK fv_result fv_scene_load(const char *name_or_path, fv_scene **out_scene);
/** Names of the built-in scenes, NULL-terminated. */
const char *const *fv_scene_builtin_names(void);
/** Build a built-in scene by name ("cornell", "cornell-translucent"); FV_ERR_NOT_FOUND for another name. */
FV_MUST_CHECK fv_result fv_scene_builtin(const char *name, fv_scene **out_scene);
/** Import one model file through assimp (glTF 2.0, OBJ+MTL, PLY, ...). unit_scale_m > 0 forces metres per file
 *  unit; 0 guesses (bounds over 50 units: millimetres). The first camera becomes the head; no camera: framed. No
 *  light: a default light is added (logged at info). Validated before it is returned. */
FV_MUST_CHECK fv_result fv_scene_import(const char *path, float unit_scale_m, fv_scene **out_scene);
/** Parse a `*.scene.json` document from memory (see docs/scene-file.md). `origin` names it in messages (a path
 *  or "<buffer>"); model paths resolve against base_dir (NULL = current directory). len excludes any NUL. */
FV_MUST_CHECK fv_result fv_scene_load_json_buffer(const char *json, size_t len, const char *base_dir,
                                                  const char *origin, fv_scene **out_scene);
/** Read and parse a `*.scene.json` file; model paths resolve relative to the file's folder. */
FV_MUST_CHECK fv_result fv_scene_load_json_file(const char *path, fv_scene **out_scene);

/* ---- materials --------------------------------------------------------------------------------------------- */
/** Look up a measured material (Jensen et al. 2001) by case-insensitive name ("marble", "skin1"). Unknown name:
 *  FV_ERR_NOT_FOUND, not logged (the caller knows the context to name). */
FV_MUST_CHECK fv_result fv_translucency_preset(const char *name, fv_translucency *out);
/** Why v is not an accepted coefficient (one phrase naming the range "0 or 1e-06..1e+06 mm^-1"), or NULL when it
 *  is one. */
const char *fv_translucency_coefficient_problem(double v);
/** Names of the presets, NULL-terminated. */
const char *const *fv_translucency_preset_names(void);

#endif
