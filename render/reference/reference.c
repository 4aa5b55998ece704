/* @brief fv_reference_render: the desc and its defaults, the primary rays (the inverse of each eye's float
 * view-projection, in double), the per-sample random streams, and the worker threads that take 16 x 16 tiles of
 * both eyes from one shared counter (so uneven tiles spread over the threads; every pixel's value depends only on
 * (seed, eye, x, y, sample), never on which thread drew it). */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fv_log.h"
#include "reference_internal.h"

#define TILE 16u
#define MAX_THREADS 1024u
#define DEFAULT_PATH_SPP 16u

/* ---- names --------------------------------------------------------------------------------------------------- */

static const char *const g_mode_names[] = {"model", "path"};
static const char *const g_view_names[FV_REFERENCE_VIEW_COUNT] = {"color",  "direct", "shadow", "albedo",
                                                                  "normal", "depth",  "gi",     "sss"};

const char *fv_reference_mode_name(fv_reference_mode mode)
{
    return (unsigned)mode < 2 ? g_mode_names[mode] : "unknown";
}

const char *fv_reference_view_name(fv_reference_view view)
{
    return (unsigned)view < FV_REFERENCE_VIEW_COUNT ? g_view_names[view] : "unknown";
}

bool fv_reference_mode_parse(const char *name, fv_reference_mode *out_mode)
{
    for (int i = 0; name && i < 2; i++)
        if (strcmp(name, g_mode_names[i]) == 0) {
            *out_mode = (fv_reference_mode)i;
            return true;
        }
    return false;
}

bool fv_reference_view_parse(const char *name, fv_reference_view *out_view)
{
    for (int i = 0; name && i < FV_REFERENCE_VIEW_COUNT; i++)
        if (strcmp(name, g_view_names[i]) == 0) {
            *out_view = (fv_reference_view)i;
            return true;
        }
    return false;
}

/* ---- desc ---------------------------------------------------------------------------------------------------- */

fv_reference_desc fv_reference_desc_defaults(const fv_reference_desc *desc)
{
    fv_reference_desc d;
    if (desc) d = *desc;
    else memset(&d, 0, sizeof d);
    if (!d.spp) d.spp = d.mode == FV_REFERENCE_PATH ? DEFAULT_PATH_SPP : 1u;
    if (!d.eye_width) d.eye_width = 720;
    if (!d.eye_height) d.eye_height = 800;
    if (!d.threads) {
        long n = sysconf(_SC_NPROCESSORS_ONLN);
        d.threads = n > 0 ? (uint32_t)(n < (long)MAX_THREADS ? n : (long)MAX_THREADS) : 1u;
    }
    return d;
}

static bool desc_validate(const fv_reference_desc *d)
{
    bool ok = true;
#define RULE(cond, ...)                                                                                                \
    do {                                                                                                               \
        if (!(cond)) {                                                                                                 \
            FV_ERROR(REF_MOD, __VA_ARGS__);                                                                            \
            ok = false;                                                                                                \
        }                                                                                                              \
    } while (0)
    RULE((unsigned)d->mode <= FV_REFERENCE_PATH, "desc.mode %d is not model (0) or path (1)", (int)d->mode);
    RULE((unsigned)d->view < FV_REFERENCE_VIEW_COUNT, "desc.view %d is not a view (0..%d)", (int)d->view,
         FV_REFERENCE_VIEW_COUNT - 1);
    RULE(d->spp <= FV_REFERENCE_MAX_SPP, "desc.spp %u exceeds %u", d->spp, FV_REFERENCE_MAX_SPP);
    RULE(d->bounces <= FV_REFERENCE_MAX_BOUNCES, "desc.bounces %u exceeds %u", d->bounces, FV_REFERENCE_MAX_BOUNCES);
    RULE(d->eye_width <= FV_REFERENCE_MAX_DIM && d->eye_height <= FV_REFERENCE_MAX_DIM,
         "desc.eye_width x eye_height %ux%u exceeds %u per side", d->eye_width, d->eye_height, FV_REFERENCE_MAX_DIM);
    RULE(d->threads <= MAX_THREADS, "desc.threads %u exceeds %u", d->threads, MAX_THREADS);
#undef RULE
    return ok;
}

/* ---- primary rays -------------------------------------------------------------------------------------------- */

/* General 4x4 inverse in double (cofactors), column major m[col * 4 + row]. False when singular or not finite. */
static bool invert4(const double m[16], double out[16])
{
    double inv[16];
    inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] +
             m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] -
             m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] +
             m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] -
              m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] -
             m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] +
             m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] -
             m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] +
              m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] +
             m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] -
             m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] +
              m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] -
              m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] -
             m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] +
             m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] -
              m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] +
              m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
    double det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
    if (!isfinite(det) || det == 0.0) return false;
    for (int i = 0; i < 16; i++) out[i] = inv[i] / det;
    for (int i = 0; i < 16; i++)
        if (!isfinite(out[i])) return false;
    return true;
}

/* proj * view as the GPU's frame constants hold it (the float product), widened to double. */
static void view_proj(const fv_eye_view *v, double out[16])
{
    fv_mat4 vp = fv_mat4_mul(&v->proj, &v->view);
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) out[c * 4 + r] = vp.m[c][r];
}

static bool unproject(const double inv[16], double x, double y, double z, dvec3 *out)
{
    double p[4];
    for (int r = 0; r < 4; r++) p[r] = inv[r] * x + inv[4 + r] * y + inv[8 + r] * z + inv[12 + r];
    if (!(fabs(p[3]) > 1e-300)) return false;
    *out = dv(p[0] / p[3], p[1] / p[3], p[2] / p[3]);
    return dv_finite(*out);
}

static bool ray_from_inverse(const double inv[16], uint32_t width, uint32_t height, double px, double py, dvec3 *o,
                             dvec3 *d, double *t_max)
{
    double x = px / width * 2.0 - 1.0, y = py / height * 2.0 - 1.0;
    dvec3 p0, p1;
    if (!unproject(inv, x, y, 0.0, &p0) || !unproject(inv, x, y, 1.0, &p1)) return false;
    dvec3 dir = dv_sub(p1, p0);
    double len = sqrt(dv_dot(dir, dir));
    if (!(len > 0) || !isfinite(len)) return false;
    *o = p0;
    *d = dv_scale(dir, 1.0 / len);
    *t_max = len;
    return true;
}

bool ref_invert4(const double m[16], double out[16]) { return invert4(m, out); }

bool ref_ray_from_inverse(const double inv[16], uint32_t width, uint32_t height, double px, double py, dvec3 *o,
                          dvec3 *d, double *t_max)
{
    return ray_from_inverse(inv, width, height, px, py, o, d, t_max);
}

bool fv_reference_pixel_ray(const fv_eye_view *view, uint32_t width, uint32_t height, double px, double py,
                            double out_origin_world[3], double out_dir_world[3], double *out_t_max)
{
    double vp[16], inv[16];
    dvec3 o = dv(0, 0, 0), d = dv(0, 0, 0);
    double t = 0;
    bool ok = view && width && height;
    if (ok) {
        view_proj(view, vp);
        ok = invert4(vp, inv) && ray_from_inverse(inv, width, height, px, py, &o, &d, &t);
    }
    if (!ok) o = d = dv(0, 0, 0), t = 0;
    if (out_origin_world) out_origin_world[0] = o.x, out_origin_world[1] = o.y, out_origin_world[2] = o.z;
    if (out_dir_world) out_dir_world[0] = d.x, out_dir_world[1] = d.y, out_dir_world[2] = d.z;
    if (out_t_max) *out_t_max = t;
    return ok;
}

/* ---- random numbers: SplitMix64 (Steele et al. 2014) --------------------------------------------------------- */

static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

ref_rng ref_rng_seed(uint64_t seed, uint32_t eye, uint32_t x, uint32_t y, uint32_t sample)
{
    uint64_t s = mix64(seed + 0x9e3779b97f4a7c15ull);
    s = mix64(s ^ (0x632be59bd9b4e019ull + eye));
    s = mix64(s ^ (((uint64_t)x << 32) | y));
    s = mix64(s ^ (0x8cb92ba72f3d8dd7ull * ((uint64_t)sample + 1)));
    return (ref_rng){s};
}

double ref_rng_next(ref_rng *r)
{
    r->state += 0x9e3779b97f4a7c15ull;
    return (double)(mix64(r->state) >> 11) * 0x1.0p-53;
}

/* ---- the workers --------------------------------------------------------------------------------------------- */

typedef struct eye_job {
    float *out;       /* one of the two, or neither for an eye not asked for */
    double *out_f64;
    ref_pixel_ctx ctx;
    double inv_vp[16];
    bool valid; /* the view could be inverted */
} eye_job;

typedef struct render_job {
    const ref_world *w;
    fv_reference_desc desc;
    eye_job eyes[2];
    uint32_t eye_index[2]; /* active eyes */
    uint32_t eye_count;
    uint32_t tiles_x, tiles_y;
    uint64_t tiles_total;
    atomic_uint_fast64_t next_tile;
    atomic_bool stopped;  /* a worker saw desc.cancelled() */
    pthread_mutex_t lock; /* progress and the counters' sum */
    uint64_t tiles_done;
    ref_counts counts;
} render_job;

/* Whether the caller asked the render to stop (desc.cancelled), remembered for every worker. */
static bool stop_asked(render_job *job)
{
    if (atomic_load_explicit(&job->stopped, memory_order_relaxed)) return true;
    if (!job->desc.cancelled || !job->desc.cancelled()) return false;
    atomic_store(&job->stopped, true);
    return true;
}

static void render_pixel(render_job *job, uint32_t eye, uint32_t x, uint32_t y, ref_counts *counts)
{
    const eye_job *ej = &job->eyes[eye];
    const fv_reference_desc *d = &job->desc;
    size_t at = ((size_t)y * d->eye_width + x) * 3;
    double acc[3] = {0, 0, 0};
    if (!ej->valid) {
        double v = d->view == FV_REFERENCE_VIEW_DEPTH ? 1.0 : 0.0;
        acc[0] = acc[1] = acc[2] = v;
    }
    /* Model mode without jitter is deterministic: one sample gives the value of all of them. */
    uint32_t spp = !ej->valid ? 0u : d->mode == FV_REFERENCE_MODEL && !d->aa ? 1u : d->spp;
    for (uint32_t s = 0; s < spp; s++) {
        if ((s & 63u) == 63u && stop_asked(job)) return; /* many samples a pixel: a stop comes within 64 */
        ref_rng rng = ref_rng_seed(d->seed, eye, x, y, s);
        double jx = 0.5, jy = 0.5;
        if (d->aa) {
            jx = ref_rng_next(&rng);
            jy = ref_rng_next(&rng);
        }
        dvec3 o, dir;
        double t_max;
        dvec3 c = dv(0, 0, 0);
        if (ray_from_inverse(ej->inv_vp, d->eye_width, d->eye_height, x + jx, y + jy, &o, &dir, &t_max))
            c = d->mode == FV_REFERENCE_PATH ? ref_shade_path(&ej->ctx, o, dir, t_max, &rng, counts)
                                             : ref_shade_model(&ej->ctx, o, dir, t_max, counts);
        acc[0] += c.x, acc[1] += c.y, acc[2] += c.z;
    }
    for (int k = 0; k < 3; k++) {
        double v = spp ? acc[k] / spp : acc[k];
        v = isfinite(v) ? fmin(fmax(v, 0.0), 3e38) : 0.0; /* 3e38: still finite as a float */
        if (ej->out) ej->out[at + k] = (float)v;
        else ej->out_f64[at + k] = v;
    }
}

static void *worker(void *arg)
{
    render_job *job = arg;
    ref_counts counts = {0, 0, 0, 0};
    for (;;) {
        if (stop_asked(job)) break;
        uint64_t k = atomic_fetch_add(&job->next_tile, 1);
        if (k >= job->tiles_total) break;
        /* Interleave the eyes, then rows of tiles: neighbouring tile numbers are spread over the image. */
        uint32_t eye = job->eye_index[k % job->eye_count];
        uint64_t t = k / job->eye_count;
        uint32_t tx = (uint32_t)(t % job->tiles_x), ty = (uint32_t)(t / job->tiles_x);
        uint32_t x1 = (tx + 1) * TILE, y1 = (ty + 1) * TILE;
        if (x1 > job->desc.eye_width) x1 = job->desc.eye_width;
        if (y1 > job->desc.eye_height) y1 = job->desc.eye_height;
        for (uint32_t y = ty * TILE; y < y1 && !stop_asked(job); y++)
            for (uint32_t x = tx * TILE; x < x1; x++) render_pixel(job, eye, x, y, &counts);
        pthread_mutex_lock(&job->lock);
        job->tiles_done++;
        if (job->desc.progress) job->desc.progress(job->desc.progress_user, job->tiles_done, job->tiles_total);
        pthread_mutex_unlock(&job->lock);
    }
    pthread_mutex_lock(&job->lock);
    job->counts.primary += counts.primary;
    job->counts.shadow += counts.shadow;
    job->counts.bounce += counts.bounce;
    job->counts.nonfinite += counts.nonfinite;
    pthread_mutex_unlock(&job->lock);
    return NULL;
}

static fv_result render(const fv_scene *scene, const fv_frame_input *in, const fv_reference_desc *desc, float *out[2],
                        double *out_f64[2], fv_reference_stats *out_stats)
{
    if (out_stats) memset(out_stats, 0, sizeof *out_stats);
    if (!scene || !in) {
        FV_ERROR(REF_MOD, "fv_reference_render: %s is NULL", !scene ? "scene" : "frame input");
        return FV_ERR_INVALID_ARG;
    }
    fv_reference_desc d = fv_reference_desc_defaults(desc);
    if (!desc_validate(&d)) return FV_ERR_INVALID_ARG;
    if (!out[0] && !out[1] && !out_f64[0] && !out_f64[1]) return FV_OK;
    /* Limits before work: positions no renderer keeps (Embree aborts on rays from past 1.8e18 m) are refused. */
    bool far = false;
    for (int e = 0; e < 2; e++) {
        fv_vec3 p = in->eye[e].pos_world;
        if (fabs((double)p.x) <= FV_SCENE_MAX_COORD_M && fabs((double)p.y) <= FV_SCENE_MAX_COORD_M &&
            fabs((double)p.z) <= FV_SCENE_MAX_COORD_M)
            continue;
        FV_ERROR(REF_MOD, "%s: eye %d at (%g, %g, %g) m is not finite or beyond the +-%g m bound of a position",
                 scene->source[0] ? scene->source : scene->name, e, (double)p.x, (double)p.y, (double)p.z, FV_SCENE_MAX_COORD_M);
        far = true;
    }
    if (fv_scene_check_extent(scene) < 0) far = true; /* it said which items */
    if (far) {
        FV_ERROR(REF_MOD, "%s: not rendered: positions beyond the bound (see above)",
                 scene->source[0] ? scene->source : scene->name);
        return FV_ERR_INVALID_ARG;
    }
    fv_scene_warn_cost(scene, d.eye_width, d.eye_height,
                       d.mode == FV_REFERENCE_MODEL ? "the reference's model mode (a shadow ray per light)"
                                                    : "the reference's path mode (a shadow ray per light and bounce)");

    render_job *job = calloc(1, sizeof *job);
    pthread_t *threads = calloc(d.threads, sizeof *threads);
    if (!job || !threads) {
        free(job);
        free(threads);
        return FV_ERR_NO_MEMORY;
    }
    ref_world world;
    fv_result res = ref_world_init(&world, scene, isfinite(in->time_s) ? in->time_s : 0.0);
    if (res != FV_OK) {
        free(job);
        free(threads);
        return res;
    }
    job->w = &world;
    ref_gi gi; /* model mode's one-bounce GI: the exact VPL sum (path mode traces its bounces instead) */
    memset(&gi, 0, sizeof gi);
    res = d.mode == FV_REFERENCE_MODEL && d.gi ? ref_gi_init(&gi, &world, scene, in) : FV_OK;
    ref_sss sss; /* model mode's subsurface light: the exact dipole sum (path mode shades it as Lambert) */
    memset(&sss, 0, sizeof sss);
    if (res == FV_OK && d.mode == FV_REFERENCE_MODEL) res = ref_sss_init(&sss, &world, scene, in);
    if (res != FV_OK) {
        ref_sss_fini(&sss);
        ref_gi_fini(&gi);
        ref_world_fini(&world);
        free(job);
        free(threads);
        return res;
    }
    job->desc = d;
    for (uint32_t e = 0; e < 2; e++) {
        eye_job *ej = &job->eyes[e];
        ej->out = out[e];
        ej->out_f64 = out_f64[e];
        ej->ctx = (ref_pixel_ctx){.w = &world, .desc = &job->desc, .eye_pos = dv_from_f(in->eye[e].pos_world),
                                  .gi = gi.enabled ? &gi : NULL, .sss = sss.enabled ? &sss : NULL};
        view_proj(&in->eye[e], ej->ctx.vp);
        ej->valid = invert4(ej->ctx.vp, ej->inv_vp) && dv_finite(ej->ctx.eye_pos);
        if (out[e] || out_f64[e]) job->eye_index[job->eye_count++] = e;
    }
    job->tiles_x = (d.eye_width + TILE - 1) / TILE;
    job->tiles_y = (d.eye_height + TILE - 1) / TILE;
    job->tiles_total = (uint64_t)job->tiles_x * job->tiles_y * job->eye_count;
    atomic_init(&job->next_tile, 0);
    atomic_init(&job->stopped, false);
    pthread_mutex_init(&job->lock, NULL);

    uint32_t want = d.threads;
    if ((uint64_t)want > job->tiles_total) want = (uint32_t)(job->tiles_total ? job->tiles_total : 1);
    uint32_t started = 0;
    for (uint32_t i = 1; i < want; i++) { /* the calling thread is worker 0 */
        if (pthread_create(&threads[i], NULL, worker, job) != 0) {
            FV_WARN(REF_MOD, "could not start worker thread %u of %u; continuing with %u", i + 1, want, started + 1);
            break;
        }
        started++;
    }
    worker(job);
    for (uint32_t i = 1; i <= started; i++) pthread_join(threads[i], NULL);

    if (out_stats) {
        fv_reference_stats *st = out_stats;
        st->primary_rays = job->counts.primary;
        st->shadow_rays = job->counts.shadow;
        st->bounce_rays = job->counts.bounce;
        st->rays = st->primary_rays + st->shadow_rays + st->bounce_rays;
        uint32_t spp = d.mode == FV_REFERENCE_MODEL && !d.aa ? 1u : d.spp;
        st->samples = (uint64_t)d.eye_width * d.eye_height * job->eye_count * spp;
        st->nonfinite_samples = job->counts.nonfinite;
        st->threads = started + 1;
        st->eye_width = d.eye_width;
        st->eye_height = d.eye_height;
        st->triangles = world.triangles;
        st->skipped_triangles = world.skipped_triangles;
        st->emissive_triangles = world.emitter_count;
        st->emissive_area_m2 = world.emissive_area_m2;
    }
    if (job->counts.nonfinite)
        FV_WARN(REF_MOD, "%s: %llu samples were not finite and count as 0", scene->source,
                (unsigned long long)job->counts.nonfinite);
    pthread_mutex_destroy(&job->lock);
    ref_sss_fini(&sss);
    ref_gi_fini(&gi);
    ref_world_fini(&world);
    bool stopped = atomic_load(&job->stopped);
    free(job);
    free(threads);
    return stopped ? FV_ERR_CANCELLED : FV_OK;
}

fv_result fv_reference_render(const fv_scene *scene, const fv_frame_input *in, const fv_reference_desc *desc,
                              float *out_rgb_left, float *out_rgb_right, fv_reference_stats *out_stats)
{
    float *out[2] = {out_rgb_left, out_rgb_right};
    double *none[2] = {NULL, NULL};
    return render(scene, in, desc, out, none, out_stats);
}

fv_result fv_reference_render_f64(const fv_scene *scene, const fv_frame_input *in, const fv_reference_desc *desc,
                                  double *out_rgb_left, double *out_rgb_right, fv_reference_stats *out_stats)
{
    float *none[2] = {NULL, NULL};
    double *out[2] = {out_rgb_left, out_rgb_right};
    return render(scene, in, desc, none, out, out_stats);
}
