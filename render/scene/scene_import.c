/* @brief Model files through assimp's C API (glTF 2.0 .gltf/.glb with KHR_lights_punctual, OBJ+MTL, PLY, ...):
 * triangulated meshes, node hierarchy, materials (base colour, emissive, base colour texture via stb_image or
 * assimp's embedded textures), lights and the first camera. Units guessed (millimetres when the bounds exceed 50
 * units). Hostile files: scene_precheck.c checks what a PLY, OBJ or OFF file declares (element counts, list
 * lengths) against its size and the FV_SCENE_MAX_* limits before assimp sees it, and every mesh is checked again
 * here (indices, finite positions, counts). */
#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <stb_image.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fovea/fv_frame_input.h"
#include "fv_file.h"
#include "fv_log.h"
#include "fv_scene.h"
#include "scene_internal.h"

/* Bounds larger than this (in file units) are taken to be millimetres. */
#define MM_GUESS_EXTENT 50.0f
#define MAX_NODE_DEPTH 256
#define MAX_DEFAULT_EMITTER_LIGHTS 8

typedef struct import_ctx {
    const char *path;
    char dir[FV_SCENE_PATH_MAX];
    fv_scene *s;
    const struct aiScene *ai;
    int32_t *mesh_map;    /* ai mesh index -> fv mesh index or -1 */
    uint32_t *mat_map;    /* ai material index -> fv material index */
    bool is_gltf;
} import_ctx;

static bool has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), k = strlen(ext);
    return n >= k && strcasecmp(path + n - k, ext) == 0;
}

/* ---- pre-checks ------------------------------------------------------------------------------------------- */

/* glTF: assimp silently drops a texture whose image is missing; say so (the material keeps its base colour). */
static void gltf_check_json(const char *path, const cJSON *root)
{
    const cJSON *textures = cJSON_GetObjectItemCaseSensitive(root, "textures");
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(root, "images");
    int image_count = cJSON_IsArray(images) ? cJSON_GetArraySize(images) : 0;
    if (!cJSON_IsArray(textures)) return;
    int i = 0;
    const cJSON *t;
    cJSON_ArrayForEach(t, textures)
    {
        const cJSON *src = cJSON_GetObjectItemCaseSensitive(t, "source");
        if (cJSON_IsNumber(src) && (src->valuedouble < 0 || src->valuedouble >= image_count)) {
            FV_WARN("scene", "%s: textures[%d].source %g refers to a missing image (%s); it is ignored and materials "
                    "using it fall back to their base colour", path, i, src->valuedouble,
                    images ? "past the end of images" : "the file has no images array");
        }
        i++;
    }
}

static void gltf_precheck(const char *path)
{
    char *buf, why[FV_FILE_ERR_MAX];
    size_t n;
    if (fv_file_read(path, NULL, 64u * 1024u * 1024u, &buf, &n, why, sizeof why) != FV_OK) return; /* best effort */
    const char *json = buf;
    size_t json_len = n;
    if (n >= 20 && !memcmp(buf, "glTF", 4)) { /* GLB: 12-byte header, then the JSON chunk (length, "JSON") */
        uint32_t clen = (uint32_t)(unsigned char)buf[12] | (uint32_t)(unsigned char)buf[13] << 8 |
                        (uint32_t)(unsigned char)buf[14] << 16 | (uint32_t)(unsigned char)buf[15] << 24;
        if (memcmp(buf + 16, "JSON", 4) || clen > n - 20) {
            free(buf);
            return;
        }
        json = buf + 20;
        json_len = clen;
    }
    cJSON *root = cJSON_ParseWithLength(json, json_len);
    if (root) gltf_check_json(path, root);
    cJSON_Delete(root);
    free(buf);
}

/* ---- pieces ----------------------------------------------------------------------------------------------- */

static fv_vec3 v3_of(struct aiVector3D v) { return fv_v3(v.x, v.y, v.z); }

static float sane_unit(float x, float fallback)
{
    if (!isfinite(x)) return fallback;
    return fv_clampf(x, 0.0f, 1.0f);
}

static int32_t find_texture(const fv_scene *s, const char *source)
{
    for (uint32_t i = 0; i < s->texture_count; i++)
        if (!strcmp(s->textures[i].source, source)) return (int32_t)i;
    return -1;
}

/* The largest texture file read (a 16384 x 16384 RGBA PNG stored uncompressed is 1 GiB; no texture is). */
#define TEXTURE_MAX_FILE_BYTES ((size_t)256 << 20)

/* A texture reference as this file system has it (a model authored on Windows): backslashes as '/', and when the
 * file is not there as written, each component of the path matched without regard to letter case in its folder.
 * out: the path to read (dir + ref when ref is relative); true when it had to be adjusted to be found. */
static bool texture_path(const char *dir, const char *ref, char *out, size_t size)
{
    char fixed[FV_SCENE_PATH_MAX];
    size_t ref_len = strlen(ref);
    if (ref_len >= sizeof fixed) return false;
    memcpy(fixed, ref, ref_len + 1);
    bool slashes = false;
    for (char *p = fixed; *p; p++)
        if (*p == '\\') *p = '/', slashes = true;
    const char *rel = fixed;
    while (rel[0] == '.' && rel[1] == '/') rel += 2; /* ".\tex\a.png" */
    int n = fixed[0] == '/' ? snprintf(out, size, "%s", fixed) : snprintf(out, size, "%s%s", dir, rel);
    if (n < 0 || (size_t)n >= size) return false;
    if (access(out, F_OK) == 0) return slashes;
    /* component by component from the folder the model is in, each the one entry that matches ignoring case */
    char built[FV_SCENE_PATH_MAX];
    int b = fixed[0] == '/' ? snprintf(built, sizeof built, "/") : snprintf(built, sizeof built, "%s", dir[0] ? dir : "./");
    const char *p = fixed[0] == '/' ? fixed + 1 : rel;
    while (*p && b > 0 && (size_t)b < sizeof built) {
        size_t len = strcspn(p, "/");
        char part[256];
        if (len == 0 || len >= sizeof part) return slashes;
        memcpy(part, p, len);
        part[len] = '\0';
        DIR *d = opendir(built);
        const char *match = NULL;
        char name[256];
        for (struct dirent *e; d && (e = readdir(d));)
            if (strcasecmp(e->d_name, part) == 0) {
                snprintf(name, sizeof name, "%s", e->d_name);
                match = name;
                break;
            }
        if (d) closedir(d);
        if (!match) return slashes; /* not there in any case: the caller's warning names what was asked for */
        b += snprintf(built + b, sizeof built - (size_t)b, "%s%s", built[b - 1] == '/' ? "" : "/", match);
        p += len;
        while (*p == '/') p++;
    }
    if (b <= 0 || (size_t)b >= sizeof built || (size_t)b >= size) return slashes;
    snprintf(out, size, "%s", built);
    return true;
}

/* Load the base colour texture of an assimp material; -1 (after a warning) when it cannot be had. */
static int32_t load_texture(import_ctx *c, const char *ref, const char *mat_name)
{
    char source[FV_SCENE_PATH_MAX];
    int w = 0, h = 0, comp = 0;
    stbi_uc *px = NULL;
    if (ref[0] == '*') { /* embedded: "*N" */
        char *end = NULL;
        long k = strtol(ref + 1, &end, 10);
        if (end == ref + 1 || *end || k < 0 || (unsigned long)k >= c->ai->mNumTextures) {
            FV_WARN("scene", "%s: material '%s': embedded texture '%s' does not exist; using the base colour",
                    c->path, mat_name, ref);
            return -1;
        }
        snprintf(source, sizeof source, "embedded:%ld", k);
        int32_t have = find_texture(c->s, source);
        if (have >= 0) return have;
        const struct aiTexture *t = c->ai->mTextures[k];
        if (t->mHeight == 0) { /* compressed bytes (PNG/JPEG...) of mWidth bytes */
            if (t->mWidth > INT_MAX || !t->pcData) goto bad_embedded;
            if (!stbi_info_from_memory((const stbi_uc *)t->pcData, (int)t->mWidth, &w, &h, &comp)) goto bad_embedded;
            if ((uint32_t)w > FV_SCENE_MAX_TEXTURE_DIM || (uint32_t)h > FV_SCENE_MAX_TEXTURE_DIM) goto too_big;
            px = stbi_load_from_memory((const stbi_uc *)t->pcData, (int)t->mWidth, &w, &h, &comp, 4);
            if (!px) goto bad_embedded;
        } else { /* raw BGRA texels */
            if (!t->pcData || t->mWidth > FV_SCENE_MAX_TEXTURE_DIM || t->mHeight > FV_SCENE_MAX_TEXTURE_DIM) goto too_big;
            w = (int)t->mWidth;
            h = (int)t->mHeight;
            px = malloc((size_t)w * (size_t)h * 4u);
            if (!px) goto bad_embedded;
            for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
                px[i * 4 + 0] = t->pcData[i].r;
                px[i * 4 + 1] = t->pcData[i].g;
                px[i * 4 + 2] = t->pcData[i].b;
                px[i * 4 + 3] = t->pcData[i].a;
            }
        }
    } else {
        int n = ref[0] == '/' ? snprintf(source, sizeof source, "%s", ref)
                              : snprintf(source, sizeof source, "%s%s", c->dir, ref);
        if (n < 0 || (size_t)n >= sizeof source) {
            FV_WARN("scene", "%s: material '%s': texture path '%s' is too long; using the base colour", c->path,
                    mat_name, ref);
            return -1;
        }
        if (texture_path(c->dir, ref, source, sizeof source))
            FV_WARN("scene", "%s: material '%s': texture '%s' read as '%s' (Windows separators or letter case)",
                    c->path, mat_name, ref, source);
        int32_t have = find_texture(c->s, source);
        if (have >= 0) return have;
        /* read through fv_file: a FIFO or device would block or never end; a huge file is refused from its size */
        char why[FV_FILE_ERR_MAX], *bytes;
        size_t nbytes;
        fv_result rr = fv_file_read(source, NULL, TEXTURE_MAX_FILE_BYTES, &bytes, &nbytes, why, sizeof why);
        if (rr != FV_OK) {
            const char *kind = strstr(why, ": not a regular file: ");
            if (kind)
                FV_WARN("scene", "%s: material '%s': texture '%s' is not a regular file; using the base colour (%s)",
                        c->path, mat_name, source, kind + strlen(": not a regular file: "));
            else /* fv_file's reason, after the path it starts with */
                FV_WARN("scene", "%s: material '%s': texture '%s' cannot be read (%s); using the base colour", c->path,
                        mat_name, source, strncmp(why, source, strlen(source)) == 0 ? why + strlen(source) + 2 : why);
            return -1;
        }
        if (nbytes > INT_MAX || !stbi_info_from_memory((const stbi_uc *)bytes, (int)nbytes, &w, &h, &comp)) {
            FV_WARN("scene", "%s: material '%s': texture '%s' cannot be read (%s); using the base colour", c->path,
                    mat_name, source, stbi_failure_reason() ? stbi_failure_reason() : "unknown");
            free(bytes);
            return -1;
        }
        if ((uint32_t)w > FV_SCENE_MAX_TEXTURE_DIM || (uint32_t)h > FV_SCENE_MAX_TEXTURE_DIM) {
            free(bytes);
            goto too_big;
        }
        px = stbi_load_from_memory((const stbi_uc *)bytes, (int)nbytes, &w, &h, &comp, 4);
        free(bytes);
        if (!px) {
            FV_WARN("scene", "%s: material '%s': texture '%s' cannot be decoded (%s); using the base colour", c->path,
                    mat_name, source, stbi_failure_reason() ? stbi_failure_reason() : "unknown");
            return -1;
        }
    }
    {
        /* stb's buffer comes from malloc (STBI_MALLOC default), so the scene can own and free() it. */
        fv_texture tex;
        memset(&tex, 0, sizeof tex);
        fv_scene_copy_name(tex.source, sizeof tex.source, source);
        tex.width = (uint32_t)w;
        tex.height = (uint32_t)h;
        tex.rgba8 = px;
        uint32_t idx;
        if (fv_scene_add_texture(c->s, &tex, &idx) < 0) return -1;
        return (int32_t)idx;
    }
bad_embedded:
    FV_WARN("scene", "%s: material '%s': embedded texture '%s' cannot be decoded; using the base colour", c->path,
            mat_name, ref);
    return -1;
too_big:
    FV_WARN("scene", "%s: material '%s': texture '%s' is %dx%d, over the %u limit; using the base colour", c->path,
            mat_name, ref, w, h, FV_SCENE_MAX_TEXTURE_DIM);
    return -1;
}

static fv_result convert_materials(import_ctx *c)
{
    const struct aiScene *ai = c->ai;
    for (unsigned i = 0; i < ai->mNumMaterials; i++) {
        const struct aiMaterial *am = ai->mMaterials[i];
        fv_material m = fv_material_default();
        struct aiString name;
        if (aiGetMaterialString(am, AI_MATKEY_NAME, &name) == aiReturn_SUCCESS)
            fv_scene_copy_name(m.name, sizeof m.name, name.data);
        else
            snprintf(m.name, sizeof m.name, "material%u", i);
        struct aiColor4D col;
        if (aiGetMaterialColor(am, AI_MATKEY_BASE_COLOR, &col) == aiReturn_SUCCESS ||
            aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &col) == aiReturn_SUCCESS)
            m.base_color = fv_v3(sane_unit(col.r, 0.8f), sane_unit(col.g, 0.8f), sane_unit(col.b, 0.8f));
        if (aiGetMaterialColor(am, AI_MATKEY_COLOR_EMISSIVE, &col) == aiReturn_SUCCESS) {
            float k = 1.0f;
            ai_real ki;
            unsigned one = 1;
            if (aiGetMaterialFloatArray(am, AI_MATKEY_EMISSIVE_INTENSITY, &ki, &one) == aiReturn_SUCCESS &&
                isfinite(ki) && ki >= 0)
                k = (float)ki;
            fv_vec3 e = fv_v3(col.r * k, col.g * k, col.b * k);
            m.emissive = fv_v3_isfinite(e) ? fv_v3_max(e, fv_v3(0, 0, 0)) : fv_v3(0, 0, 0);
        }
        /* Embree-style OBJ lights carry their emission as an ambient colour above 1 (Ka 20 20 20). */
        if (!(m.emissive.x > 0 || m.emissive.y > 0 || m.emissive.z > 0) &&
            aiGetMaterialColor(am, AI_MATKEY_COLOR_AMBIENT, &col) == aiReturn_SUCCESS && isfinite(col.r) &&
            isfinite(col.g) && isfinite(col.b) && (col.r > 1.0f || col.g > 1.0f || col.b > 1.0f)) {
            m.emissive = fv_v3_max(fv_v3(col.r, col.g, col.b), fv_v3(0, 0, 0));
            FV_INFO("scene", "%s: material '%s': ambient colour above 1 taken as emission", c->path, m.name);
        }
        struct aiString tpath;
        enum aiTextureType types[2] = {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE};
        for (int t = 0; t < 2; t++) {
            if (aiGetMaterialTextureCount(am, types[t]) == 0) continue;
            if (aiGetMaterialTexture(am, types[t], 0, &tpath, NULL, NULL, NULL, NULL, NULL, NULL) != aiReturn_SUCCESS)
                continue;
            if (tpath.length == 0) continue;
            m.base_color_texture = load_texture(c, tpath.data, m.name);
            break;
        }
        FV_TRY(fv_scene_add_material(c->s, &m, &c->mat_map[i]));
    }
    if (ai->mNumMaterials == 0) { /* meshes still need one */
        fv_material m = fv_material_default();
        uint32_t idx;
        FV_TRY(fv_scene_add_material(c->s, &m, &idx));
    }
    return FV_OK;
}

static fv_result convert_meshes(import_ctx *c)
{
    const struct aiScene *ai = c->ai;
    for (unsigned i = 0; i < ai->mNumMeshes; i++) {
        const struct aiMesh *am = ai->mMeshes[i];
        c->mesh_map[i] = -1;
        const char *name = am->mName.length ? am->mName.data : "(unnamed)";
        if (am->mNumVertices > FV_SCENE_MAX_VERTICES) {
            FV_ERROR("scene", "%s: mesh %u '%s': %u vertices exceed the limit %u", c->path, i, name, am->mNumVertices,
                     FV_SCENE_MAX_VERTICES);
            return FV_ERR_RANGE;
        }
        uint64_t tris = 0;
        for (unsigned f = 0; f < am->mNumFaces; f++)
            if (am->mFaces[f].mNumIndices == 3) tris++;
        if (tris == 0) {
            FV_INFO("scene", "%s: mesh %u '%s' has no triangles (points or lines only); skipped", c->path, i, name);
            continue;
        }
        if (tris * 3u > FV_SCENE_MAX_INDICES) {
            FV_ERROR("scene", "%s: mesh %u '%s': %llu triangles exceed the limit %u", c->path, i, name,
                     (unsigned long long)tris, FV_SCENE_MAX_INDICES / 3u);
            return FV_ERR_RANGE;
        }
        fv_mesh m;
        memset(&m, 0, sizeof m);
        fv_scene_copy_name(m.name, sizeof m.name, name);
        m.vertex_count = am->mNumVertices;
        m.index_count = (uint32_t)(tris * 3u);
        m.material = am->mMaterialIndex < ai->mNumMaterials ? c->mat_map[am->mMaterialIndex] : 0;
        m.positions = malloc((size_t)m.vertex_count * sizeof *m.positions);
        m.indices = malloc((size_t)m.index_count * sizeof *m.indices);
        if (am->mNormals) m.normals = malloc((size_t)m.vertex_count * sizeof *m.normals);
        if (am->mTextureCoords[0]) m.texcoords = malloc((size_t)m.vertex_count * sizeof *m.texcoords);
        if (!m.positions || !m.indices || (am->mNormals && !m.normals) || (am->mTextureCoords[0] && !m.texcoords)) {
            free(m.positions);
            free(m.indices);
            free(m.normals);
            free(m.texcoords);
            FV_ERROR("scene", "%s: mesh %u '%s': out of memory", c->path, i, name);
            return FV_ERR_NO_MEMORY;
        }
        fv_result r = FV_OK;
        for (unsigned v = 0; v < am->mNumVertices; v++) {
            m.positions[v] = v3_of(am->mVertices[v]);
            if (!fv_v3_isfinite(m.positions[v]) && r == FV_OK) {
                FV_ERROR("scene", "%s: mesh %u '%s': vertex %u has a non-finite position (%g, %g, %g)", c->path, i,
                         name, v, (double)m.positions[v].x, (double)m.positions[v].y, (double)m.positions[v].z);
                r = FV_ERR_RANGE;
            }
            if (m.normals) m.normals[v] = fv_v3_normalize_or(v3_of(am->mNormals[v]), fv_v3(0, 1, 0));
            if (m.texcoords) {
                fv_vec2 uv = {am->mTextureCoords[0][v].x, am->mTextureCoords[0][v].y};
                m.texcoords[v] = (isfinite(uv.x) && isfinite(uv.y)) ? uv : (fv_vec2){0, 0};
            }
        }
        uint32_t k = 0;
        for (unsigned f = 0; f < am->mNumFaces && r == FV_OK; f++) {
            const struct aiFace *face = &am->mFaces[f];
            if (face->mNumIndices != 3) continue;
            for (int j = 0; j < 3; j++) {
                if (face->mIndices[j] >= am->mNumVertices) {
                    FV_ERROR("scene", "%s: mesh %u '%s': face %u index %u is past the vertex count %u", c->path, i,
                             name, f, face->mIndices[j], am->mNumVertices);
                    r = FV_ERR_PARSE;
                    break;
                }
                m.indices[k++] = face->mIndices[j];
            }
        }
        if (r < 0) {
            free(m.positions);
            free(m.indices);
            free(m.normals);
            free(m.texcoords);
            return r;
        }
        uint32_t idx;
        FV_TRY(fv_scene_add_mesh(c->s, &m, &idx));
        c->mesh_map[i] = (int32_t)idx;
    }
    return FV_OK;
}

/* Depth-first over the node tree; parents are added before children as fv_scene requires. */
static fv_result convert_node(import_ctx *c, const struct aiNode *an, int32_t parent, int depth)
{
    if (depth > MAX_NODE_DEPTH) {
        FV_ERROR("scene", "%s: node '%s': hierarchy deeper than %d levels", c->path, an->mName.data, MAX_NODE_DEPTH);
        return FV_ERR_RANGE;
    }
    struct aiVector3D sc, pos;
    struct aiQuaternion q;
    aiDecomposeMatrix(&an->mTransformation, &sc, &q, &pos);
    fv_node n = fv_node_default();
    fv_scene_copy_name(n.name, sizeof n.name, an->mName.data);
    n.parent = parent;
    n.translation_m = v3_of(pos);
    n.scale = v3_of(sc);
    n.rotation = fv_quat_normalize((fv_quat){q.x, q.y, q.z, q.w});
    if (!fv_v3_isfinite(n.translation_m) || !fv_v3_isfinite(n.scale) || !isfinite(n.rotation.x) ||
        !isfinite(n.rotation.y) || !isfinite(n.rotation.z) || !isfinite(n.rotation.w)) {
        FV_ERROR("scene", "%s: node '%s': non-finite transform", c->path, an->mName.data);
        return FV_ERR_RANGE;
    }
    /* The node itself carries its first drawable mesh; further meshes hang off it as identity children. */
    unsigned first = 0;
    while (first < an->mNumMeshes &&
           (an->mMeshes[first] >= c->ai->mNumMeshes || c->mesh_map[an->mMeshes[first]] < 0))
        first++;
    if (first < an->mNumMeshes) n.mesh = c->mesh_map[an->mMeshes[first]];
    uint32_t self;
    FV_TRY(fv_scene_add_node(c->s, &n, &self));
    for (unsigned k = first + 1; k < an->mNumMeshes; k++) {
        if (an->mMeshes[k] >= c->ai->mNumMeshes || c->mesh_map[an->mMeshes[k]] < 0) continue;
        fv_node extra = fv_node_default();
        char label[FV_SCENE_NAME_MAX + 16];
        snprintf(label, sizeof label, "%s#%u", n.name, k);
        fv_scene_copy_name(extra.name, sizeof extra.name, label);
        extra.parent = (int32_t)self;
        extra.mesh = c->mesh_map[an->mMeshes[k]];
        FV_TRY(fv_scene_add_node(c->s, &extra, NULL));
    }
    for (unsigned k = 0; k < an->mNumChildren; k++)
        if (an->mChildren[k]) FV_TRY(convert_node(c, an->mChildren[k], (int32_t)self, depth + 1));
    return FV_OK;
}

static int32_t node_by_name(const fv_scene *s, const char *name)
{
    char stored[FV_SCENE_NAME_MAX]; /* the name as a node keeps it (a long one cut with "...") */
    fv_scene_copy_name(stored, sizeof stored, name);
    for (uint32_t i = 0; i < s->node_count; i++)
        if (!strcmp(s->nodes[i].name, stored)) return (int32_t)i;
    return -1;
}

static fv_mat4 world_of_named(const fv_scene *s, const char *name)
{
    int32_t n = node_by_name(s, name);
    return n >= 0 ? fv_scene_node_world(s, (uint32_t)n, 0.0) : fv_mat4_identity();
}

/* An aiMetadata entry by key (the C API has no lookup), or NULL. */
static const struct aiMetadataEntry *meta_get(const struct aiMetadata *m, const char *key)
{
    if (!m || !m->mKeys || !m->mValues) return NULL;
    for (unsigned i = 0; i < m->mNumProperties; i++)
        if (!strcmp(m->mKeys[i].data, key)) return &m->mValues[i];
    return NULL;
}

/* The KHR_lights_punctual light index a glTF node refers to, as assimp 5.2 keeps it in the node's metadata
 * (extensions -> KHR_lights_punctual -> light), or -1. */
static int64_t gltf_node_light_index(const struct aiNode *n)
{
    const struct aiMetadataEntry *e = meta_get(n->mMetaData, "extensions");
    if (!e || e->mType != AI_AIMETADATA || !e->mData) return -1;
    e = meta_get(e->mData, "KHR_lights_punctual");
    if (!e || e->mType != AI_AIMETADATA || !e->mData) return -1;
    e = meta_get(e->mData, "light");
    if (!e || !e->mData) return -1;
    if (e->mType == AI_UINT64) {
        uint64_t v = *(const uint64_t *)e->mData;
        return v <= INT32_MAX ? (int64_t)v : -1;
    }
    if (e->mType == AI_INT32) {
        int32_t v = *(const int32_t *)e->mData;
        return v >= 0 ? v : -1;
    }
    return -1;
}

/* The first node named `name` that carries a glTF light (assimp names a glTF light after the last node that
 * refers to it). */
static const struct aiNode *gltf_light_node(const struct aiNode *n, const char *name, int depth)
{
    if (!n || depth > MAX_NODE_DEPTH) return NULL;
    if (!strcmp(n->mName.data, name) &&
        (gltf_node_light_index(n) >= 0 || meta_get(n->mMetaData, "PBR_LightRange")))
        return n;
    for (unsigned k = 0; k < n->mNumChildren; k++) {
        const struct aiNode *hit = gltf_light_node(n->mChildren[k], name, depth + 1);
        if (hit) return hit;
    }
    return NULL;
}

/* KHR_lights_punctual `range` (point and spot only): assimp 5.2 leaves it out of aiLight (whose attenuation is
 * always the plain inverse square) and puts it in the light node's metadata as "PBR_LightRange". In file units;
 * apply_unit_scale turns it into metres. A range that is not a finite number > 0 is ignored with a warning. */
static float gltf_light_range(const import_ctx *c, unsigned ai_index, const char *name)
{
    const struct aiNode *n = gltf_light_node(c->ai->mRootNode, name, 0);
    const struct aiMetadataEntry *e = n ? meta_get(n->mMetaData, "PBR_LightRange") : NULL;
    if (!e || !e->mData) return 0.0f;
    double range = NAN;
    if (e->mType == AI_FLOAT) range = *(const float *)e->mData;
    else if (e->mType == AI_DOUBLE) range = *(const double *)e->mData;
    if (isfinite(range) && range > 0 && range <= FLT_MAX) return (float)range;
    int64_t gi = gltf_node_light_index(n);
    if (gi >= 0)
        FV_WARN("scene", "%s: light '%s' (KHR_lights_punctual light %lld): range %g is not a finite number > 0; "
                "ignored (the light reaches infinitely)", c->path, name, (long long)gi, range);
    else
        FV_WARN("scene", "%s: light '%s' (light %u): range %g is not a finite number > 0; ignored (the light "
                "reaches infinitely)", c->path, name, ai_index, range);
    return 0.0f;
}

static fv_result convert_lights(import_ctx *c)
{
    for (unsigned i = 0; i < c->ai->mNumLights; i++) {
        const struct aiLight *al = c->ai->mLights[i];
        fv_light l;
        memset(&l, 0, sizeof l);
        fv_scene_copy_name(l.name, sizeof l.name, al->mName.data);
        switch (al->mType) {
        case aiLightSource_DIRECTIONAL: l.type = FV_LIGHT_DIRECTIONAL; break;
        case aiLightSource_POINT: l.type = FV_LIGHT_POINT; break;
        case aiLightSource_SPOT: l.type = FV_LIGHT_SPOT; break;
        default:
            FV_WARN("scene", "%s: light '%s': type %d is not supported (point, spot, directional); skipped", c->path,
                    al->mName.data, (int)al->mType);
            continue;
        }
        fv_mat4 w = world_of_named(c->s, al->mName.data);
        l.position_m = fv_mat4_mul_point(&w, v3_of(al->mPosition));
        l.direction = fv_v3_normalize_or(fv_mat4_mul_dir(&w, v3_of(al->mDirection)), fv_v3(0, 0, -1));
        /* assimp folds KHR_lights_punctual intensity into the colour: split it into a unit-peak colour and a
         * scale (only the product survives, so colour [0.5,0.5,0.5] x 10 comes back as [1,1,1] x 5). glTF gives
         * point/spot intensity in candela (lm/sr) and directional in lux (lm/m^2); fv_light wants W/sr and W/m^2,
         * so divide by the luminous efficacy FV_SCENE_LUMENS_PER_WATT (683 lm/W at 555 nm, the factor Blender's
         * glTF exporter applies to its watts). Other formats carry no units: their value is kept. */
        fv_vec3 col = fv_v3(al->mColorDiffuse.r, al->mColorDiffuse.g, al->mColorDiffuse.b);
        if (!fv_v3_isfinite(col)) col = fv_v3(1, 1, 1);
        col = fv_v3_max(col, fv_v3(0, 0, 0));
        float peak = fmaxf(col.x, fmaxf(col.y, col.z));
        l.intensity = peak > 0 ? (c->is_gltf ? peak / FV_SCENE_LUMENS_PER_WATT : peak) : 0.0f;
        l.color = peak > 0 ? fv_v3_scale(col, 1.0f / peak) : fv_v3(1, 1, 1);
        if (l.type == FV_LIGHT_SPOT) { /* glTF's innerConeAngle/outerConeAngle are half-angles, as fv_light's */
            float half = (float)(FV_PI / 2);
            float outer = isfinite(al->mAngleOuterCone) ? fv_clampf(al->mAngleOuterCone, 0.0f, half) : half;
            float inner = isfinite(al->mAngleInnerCone) ? fv_clampf(al->mAngleInnerCone, 0.0f, outer) : 0.0f;
            l.inner_cone_rad = inner;
            l.outer_cone_rad = outer;
        }
        if (c->is_gltf && l.type != FV_LIGHT_DIRECTIONAL) l.range_m = gltf_light_range(c, i, al->mName.data);
        if (!fv_v3_isfinite(l.position_m)) {
            FV_WARN("scene", "%s: light '%s': non-finite position; skipped", c->path, l.name);
            continue;
        }
        FV_TRY(fv_scene_add_light(c->s, &l, NULL));
    }
    return FV_OK;
}

static void convert_camera(import_ctx *c)
{
    if (c->ai->mNumCameras == 0) return;
    const struct aiCamera *ac = c->ai->mCameras[0];
    fv_mat4 w = world_of_named(c->s, ac->mName.data);
    /* assimp 5.2's glTF importer copies the camera node's translation into mPosition although the node transform
     * (w) already holds it, so adding it again would place the camera twice as far along its translation (and
     * rotated). For glTF the camera sits at its node's origin. */
    fv_vec3 pos = fv_mat4_mul_point(&w, c->is_gltf ? fv_v3(0, 0, 0) : v3_of(ac->mPosition));
    fv_vec3 look = fv_v3_normalize_or(fv_mat4_mul_dir(&w, v3_of(ac->mLookAt)), fv_v3(0, 0, -1));
    fv_vec3 up = fv_v3_normalize_or(fv_mat4_mul_dir(&w, v3_of(ac->mUp)), fv_v3(0, 1, 0));
    fv_vec3 right = fv_v3_normalize_or(fv_v3_cross(look, up), fv_v3(1, 0, 0));
    up = fv_v3_normalize_or(fv_v3_cross(right, look), fv_v3(0, 1, 0));
    if (!fv_v3_isfinite(pos)) {
        FV_WARN("scene", "%s: camera '%s': non-finite position; framing the scene instead", c->path, ac->mName.data);
        return;
    }
    fv_camera cam;
    memset(&cam, 0, sizeof cam);
    fv_scene_copy_name(cam.name, sizeof cam.name, ac->mName.data);
    cam.position_m = pos;
    cam.orientation = fv_quat_from_basis(right, up, fv_v3_scale(look, -1.0f));
    /* assimp 5.2's glTF importer stores yfov * aspect in mHorizontalFOV; other importers store the horizontal
     * half-angle. */
    float aspect = (isfinite(ac->mAspect) && ac->mAspect > 0) ? ac->mAspect : 1.0f;
    double yfov = c->is_gltf ? ac->mHorizontalFOV / aspect : 2.0 * atan(tan(ac->mHorizontalFOV) / aspect);
    cam.yfov_rad = (isfinite(yfov) && yfov > 0 && yfov < FV_PI) ? (float)yfov : 0.0f;
    cam.near_m = isfinite(ac->mClipPlaneNear) && ac->mClipPlaneNear > 0 ? ac->mClipPlaneNear : 0.0f;
    cam.far_m = isfinite(ac->mClipPlaneFar) && ac->mClipPlaneFar > cam.near_m ? ac->mClipPlaneFar : 0.0f;
    if (fv_scene_add_camera(c->s, &cam, NULL) < 0) return;
    c->s->head.position_m = cam.position_m;
    c->s->head.orientation = cam.orientation;
    c->s->head.from_file = true;
}

/* The file's camera framed the model for its own field of view; the HMD's is wider (FV_HMD_FOV_UP + DOWN, about
 * 93 degrees), so the model would come out small. Keep the camera's direction and move the head along it, towards
 * the model, until the HMD's vertical field shows at the model's centre what the camera's did. One warning line. */
static void honour_camera_fov(fv_scene *s, const char *path)
{
    if (!s->camera_count || !(s->cameras[0].yfov_rad > 0.0f)) return;
    fv_vec3 lo, hi;
    if (!fv_scene_world_bounds(s, 0.0, &lo, &hi)) return;
    fv_vec3 centre = fv_v3_scale(fv_v3_add(lo, hi), 0.5f);
    fv_vec3 look = fv_quat_rotate(s->head.orientation, fv_v3(0, 0, -1));
    double d = fv_v3_dot(fv_v3_sub(centre, s->head.position_m), look); /* the model's depth along the view */
    double hmd_half = fv_deg_to_rad(0.5 * (FV_HMD_FOV_UP_DEG + FV_HMD_FOV_DOWN_DEG));
    double cam_half = 0.5 * s->cameras[0].yfov_rad;
    double k = tan(cam_half) / tan(hmd_half); /* < 1: the HMD sees more at the same distance */
    if (!(d > 0) || !isfinite(k) || k >= 0.999 || k <= 0.0) return;
    double closer = d * (1.0 - k); /* at distance d k, the HMD's half-field spans what the camera's did at d */
    fv_vec3 moved = fv_v3_add(s->head.position_m, fv_v3_scale(look, (float)closer));
    if (!fv_v3_isfinite(moved)) return;
    s->head.position_m = moved;
    FV_WARN("scene", "%s: camera '%s' frames the model for a %.1f deg field of view; the HMD shows %.1f deg, so the "
            "head moved %.3g m closer along the camera's view to show what it framed", path, s->cameras[0].name,
            fv_rad_to_deg(2.0 * cam_half), fv_rad_to_deg(2.0 * hmd_half), closer);
}

/* Multiply every length in the scene by k (positions, translations, light positions, camera positions). Node
 * transforms are similarities, so scaling translations and vertices scales the whole world uniformly. */
static void apply_unit_scale(fv_scene *s, float k)
{
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        fv_mesh *m = &s->meshes[i];
        for (uint32_t v = 0; v < m->vertex_count; v++) m->positions[v] = fv_v3_scale(m->positions[v], k);
        m->bounds_min = fv_v3_scale(m->bounds_min, k);
        m->bounds_max = fv_v3_scale(m->bounds_max, k);
    }
    for (uint32_t i = 0; i < s->node_count; i++) s->nodes[i].translation_m = fv_v3_scale(s->nodes[i].translation_m, k);
    for (uint32_t i = 0; i < s->light_count; i++) {
        s->lights[i].position_m = fv_v3_scale(s->lights[i].position_m, k);
        s->lights[i].range_m *= k;
    }
    for (uint32_t i = 0; i < s->camera_count; i++) {
        s->cameras[i].position_m = fv_v3_scale(s->cameras[i].position_m, k);
        s->cameras[i].near_m *= k;
        s->cameras[i].far_m *= k;
    }
    s->head.position_m = fv_v3_scale(s->head.position_m, k);
}

/* No light in the file: one spot per emissive mesh (at its centre, along its mean normal, intensity = radiance x
 * area, as a Lambertian emitter seen head-on) or, when nothing glows, a point light above the viewer. */
fv_result fv_scene_add_default_lights(fv_scene *s, const char *origin)
{
    uint32_t added = 0;
    for (uint32_t i = 0; i < s->node_count && added < MAX_DEFAULT_EMITTER_LIGHTS; i++) {
        const fv_node *n = &s->nodes[i];
        if (n->mesh < 0) continue;
        const fv_mesh *m = &s->meshes[n->mesh];
        fv_vec3 e = s->materials[m->material].emissive;
        float peak = fmaxf(e.x, fmaxf(e.y, e.z));
        if (!(peak > 0)) continue;
        fv_mat4 w = fv_scene_node_world(s, i, 0.0);
        double area = 0;
        fv_vec3 centre = fv_v3(0, 0, 0), nsum = fv_v3(0, 0, 0);
        for (uint32_t t = 0; t + 2 < m->index_count; t += 3) {
            fv_vec3 a = fv_mat4_mul_point(&w, m->positions[m->indices[t]]);
            fv_vec3 b = fv_mat4_mul_point(&w, m->positions[m->indices[t + 1]]);
            fv_vec3 cc = fv_mat4_mul_point(&w, m->positions[m->indices[t + 2]]);
            fv_vec3 cr = fv_v3_cross(fv_v3_sub(b, a), fv_v3_sub(cc, a));
            float ta = 0.5f * fv_v3_len(cr);
            area += ta;
            nsum = fv_v3_add(nsum, cr);
            centre = fv_v3_add(centre, fv_v3_scale(fv_v3_add(a, fv_v3_add(b, cc)), ta / 3.0f));
        }
        if (!(area > 0)) continue;
        centre = fv_v3_scale(centre, (float)(1.0 / area));
        fv_vec3 dir = fv_v3_normalize_or(nsum, fv_v3(0, -1, 0));
        /* An emitter that is a closed box (a glowing block) has normals that cancel: aim it down, from just outside
         * its bottom (at its centre, the block's own faces would shadow everything). */
        bool closed = fv_v3_len(nsum) < 0.25f * 2.0f * (float)area;
        if (closed) {
            dir = fv_v3(0, -1, 0);
            fv_vec3 blo, bhi;
            if (fv_scene_node_bounds_grow(s, i, 0.0, &blo, &bhi, false))
                centre = fv_v3(centre.x, blo.y, centre.z);
        }
        fv_light l;
        memset(&l, 0, sizeof l);
        char label[FV_SCENE_NAME_MAX + 16];
        snprintf(label, sizeof label, "emitter:%s", n->name);
        fv_scene_copy_name(l.name, sizeof l.name, label);
        l.type = FV_LIGHT_SPOT;
        l.position_m = fv_v3_add(centre, fv_v3_scale(dir, 1e-3f));
        l.direction = dir;
        l.color = fv_v3_scale(e, 1.0f / peak);
        l.intensity = (float)(peak * area);
        l.inner_cone_rad = (float)fv_deg_to_rad(60.0);
        l.outer_cone_rad = (float)fv_deg_to_rad(89.0);
        if (!fv_v3_isfinite(l.position_m) || !isfinite(l.intensity)) continue;
        FV_TRY(fv_scene_add_light(s, &l, NULL));
        added++;
    }
    if (added) {
        FV_WARN("scene", "%s: no light in the file; added %u spot light(s) at the emissive surfaces", origin, added);
        return FV_OK;
    }
    fv_vec3 lo, hi;
    if (!fv_scene_world_bounds(s, 0.0, &lo, &hi)) return FV_OK;
    fv_vec3 centre = fv_v3_scale(fv_v3_add(lo, hi), 0.5f);
    float r = 0.5f * fv_v3_len(fv_v3_sub(hi, lo));
    fv_light l;
    memset(&l, 0, sizeof l);
    fv_scene_copy_name(l.name, sizeof l.name, "default_headlight");
    /* A spot light, not a point light: one-bounce GI needs a reflective shadow map, which spot and directional
     * lights have. Above the viewer, aimed at the scene's centre, its cone wide enough for the bounding sphere. */
    l.type = FV_LIGHT_SPOT;
    l.position_m = fv_v3_add(s->head.position_m, fv_v3(0, 0.5f * r, 0));
    fv_vec3 to = fv_v3_sub(centre, l.position_m);
    float d = fv_v3_len(to);
    l.direction = fv_v3_normalize_or(to, fv_v3(0, -1, 0));
    double half = d > r ? asin(fmin(1.0, (double)r / d)) : FV_PI / 2.0;
    l.outer_cone_rad = (float)fmin(half * 1.15, fv_deg_to_rad(85.0));
    l.inner_cone_rad = (float)(0.8 * l.outer_cone_rad);
    l.color = fv_v3(1, 1, 1);
    /* Irradiance pi at the scene centre, so a white Lambert surface facing the light has radiance about 1. */
    l.intensity = (float)(FV_PI * (double)d * (double)d);
    if (!isfinite(l.intensity) || !(l.intensity > 0)) l.intensity = 1.0f;
    FV_WARN("scene", "%s: no light in the file; added a spot light above the viewer aimed at the scene (cone %.0f "
            "deg; it casts shadows and indirect light)", origin, fv_rad_to_deg(2.0 * l.outer_cone_rad));
    return fv_scene_add_light(s, &l, NULL);
}

/* ---- entry ------------------------------------------------------------------------------------------------ */

fv_result fv_scene_import(const char *path, float unit_scale_m, fv_scene **out_scene)
{
    return fv_scene_import_ex(path, unit_scale_m, true, out_scene);
}

static fv_result import_file(const char *path, float unit_scale_m, bool default_lights, fv_scene **out_scene);

fv_result fv_scene_import_ex(const char *path, float unit_scale_m, bool default_lights, fv_scene **out_scene)
{
    fv_log_budget budget; /* a file that fails the same way a million times says so a few times */
    fv_log_budget_begin(&budget, path ? path : "", 0);
    fv_result r = import_file(path, unit_scale_m, default_lights, out_scene);
    fv_log_budget_end(&budget);
    return r;
}

static fv_result import_file(const char *path, float unit_scale_m, bool default_lights, fv_scene **out_scene)
{
    if (!out_scene) return FV_ERR_INVALID_ARG;
    *out_scene = NULL;
    if (!path || !*path) {
        FV_ERROR("scene", "no model path given");
        return FV_ERR_INVALID_ARG;
    }
    if (strlen(path) >= FV_SCENE_PATH_MAX) { /* the scene's source and the folder textures resolve from */
        FV_ERROR("scene", "%.60s...: the model path is %zu bytes, more than the %d-byte limit", path, strlen(path),
                 FV_SCENE_PATH_MAX - 1);
        return FV_ERR_RANGE;
    }
    /* the file as fv_file opens it: a FIFO, device or directory is refused without waiting or reading */
    int fd;
    uint64_t size;
    char why[FV_FILE_ERR_MAX];
    fv_result opened = fv_file_open(path, "model file", UINT64_MAX, &fd, &size, why, sizeof why);
    if (opened != FV_OK) {
        FV_ERROR("scene", "%s", why);
        return opened;
    }
    close(fd);
    if (!(isfinite(unit_scale_m) && unit_scale_m >= 0)) {
        FV_ERROR("scene", "%s: unit scale %g must be >= 0", path, (double)unit_scale_m);
        return FV_ERR_RANGE;
    }
    FV_TRY(fv_scene_precheck_file(path, size));
    bool is_gltf = has_ext(path, ".gltf") || has_ext(path, ".glb");
    if (is_gltf) gltf_precheck(path);

    import_ctx c;
    memset(&c, 0, sizeof c);
    c.path = path;
    c.is_gltf = is_gltf;
    const char *slash = strrchr(path, '/');
    if (slash && (size_t)(slash - path + 1) < sizeof c.dir) memcpy(c.dir, path, (size_t)(slash - path + 1));

    unsigned flags = aiProcess_Triangulate | aiProcess_GenSmoothNormals | aiProcess_JoinIdenticalVertices |
                     aiProcess_SortByPType | aiProcess_ValidateDataStructure | aiProcess_FlipUVs;
    c.ai = aiImportFile(path, flags);
    if (!c.ai) {
        const char *why = aiGetErrorString();
        FV_ERROR("scene", "%s: the importer rejected the file: %s", path, why && *why ? why : "unknown reason");
        return FV_ERR_PARSE;
    }
    fv_result r = FV_OK;
    if (!c.ai->mRootNode || (c.ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
        FV_ERROR("scene", "%s: the file has no complete scene (no root node or incomplete)", path);
        r = FV_ERR_PARSE;
        goto fail;
    }
    if (c.ai->mNumMeshes > FV_SCENE_MAX_ITEMS || c.ai->mNumMaterials > FV_SCENE_MAX_ITEMS ||
        c.ai->mNumLights > FV_SCENE_MAX_ITEMS || c.ai->mNumCameras > FV_SCENE_MAX_ITEMS) {
        FV_ERROR("scene", "%s: %u meshes / %u materials / %u lights / %u cameras exceed the limit %u", path,
                 c.ai->mNumMeshes, c.ai->mNumMaterials, c.ai->mNumLights, c.ai->mNumCameras, FV_SCENE_MAX_ITEMS);
        r = FV_ERR_RANGE;
        goto fail;
    }
    const char *base = slash ? slash + 1 : path;
    r = fv_scene_create(base, &c.s);
    if (r < 0) goto fail;
    fv_scene_copy_name(c.s->source, sizeof c.s->source, path);
    c.mesh_map = calloc(c.ai->mNumMeshes + 1u, sizeof *c.mesh_map);
    c.mat_map = calloc(c.ai->mNumMaterials + 1u, sizeof *c.mat_map);
    if (!c.mesh_map || !c.mat_map) {
        FV_ERROR("scene", "%s: out of memory", path);
        r = FV_ERR_NO_MEMORY;
        goto fail;
    }
    if ((r = convert_materials(&c)) < 0) goto fail;
    if ((r = convert_meshes(&c)) < 0) goto fail;
    if ((r = convert_node(&c, c.ai->mRootNode, -1, 0)) < 0) goto fail;
    if ((r = convert_lights(&c)) < 0) goto fail;
    convert_camera(&c);

    if (fv_scene_triangle_count(c.s) == 0) {
        FV_ERROR("scene", "%s: the file has no triangles to draw", path);
        r = FV_ERR_PARSE;
        goto fail;
    }
    float k = unit_scale_m;
    if (k == 0.0f) {
        fv_vec3 lo, hi;
        k = 1.0f;
        /* glTF's unit is the metre (glTF 2.0, 3.4 "Coordinate System and Units"): kept whatever the size. Formats
         * without units (OBJ, PLY, STL, ...) get the guess, said at warning level with its factor. */
        if (!is_gltf && fv_scene_world_bounds(c.s, 0.0, &lo, &hi)) {
            fv_vec3 ext = fv_v3_sub(hi, lo);
            float big = fmaxf(ext.x, fmaxf(ext.y, ext.z));
            if (big > MM_GUESS_EXTENT) {
                k = 0.001f;
                FV_WARN("scene", "%s: bounds span %.1f units (> %.0f) and the format has no unit: taking the file to "
                        "be in millimetres (scale 0.001; \"unit_scale_m\" in a scene file overrides)", path,
                        (double)big, (double)MM_GUESS_EXTENT);
            }
        }
    }
    c.s->unit_scale_m = k;
    if (k != 1.0f) apply_unit_scale(c.s, k);
    if (!c.s->head.from_file) fv_scene_frame_head(c.s);
    else honour_camera_fov(c.s, path);
    if (default_lights && c.s->light_count == 0 && (r = fv_scene_add_default_lights(c.s, path)) < 0) goto fail;
    if ((r = fv_scene_validate(c.s)) < 0) goto fail;
    aiReleaseImport(c.ai);
    free(c.mesh_map);
    free(c.mat_map);
    *out_scene = c.s;
    return FV_OK;
fail:
    aiReleaseImport(c.ai);
    free(c.mesh_map);
    free(c.mat_map);
    fv_scene_destroy(&c.s);
    return r;
}
